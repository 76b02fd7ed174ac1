"""User walking tasks for the accompanying robot (Wu et al. 2021, Sec. 3).

A :class:`WalkingTask` is a trajectory of the user's frame origin LCS_U (the
user-side encoder housing) and heading in the world, with the moments the
user starts and stops walking and the robot's target pose in LCS_U. The nine
tasks of the paper are synthesised by :func:`walking_task`; a recorded walk is
read by :func:`walking_task_from_csv`.

World frame: the user starts at the origin facing +Y (heading pi/2,
counter-clockwise from +X, as Table 1). Speed profiles, step timing and the
circle radius are not given in the paper; they are parameters here (defaults
in ``docs/following.md``). Each move has a cruise speed and raised-cosine
ramps; the user stands for ``stand_before`` before walking and
``settle_time`` (default 10 s) after the last move.

Default targets are the paper's: (X_T, Y_T) from Table 2 and, for the six
basic tasks, the robot's relative heading at the start from Table 1 (robot
start heading minus user start heading); 0 for the combined tasks, whose
robot headings the paper does not give.

Examples
--------
>>> task = walking_task("forward")
>>> round(task.distance, 2), task.target_position
(1.95, (0.095, 0.418))
>>> round(task.walk_stop - task.walk_start, 2)
4.93
>>> sorted(TASK_NAMES)[:3]
['backward', 'circle_ccw', 'circle_cw']
"""

from __future__ import annotations

import io
import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.following.accompanying.parameters import (
    DISTANCE,
    HOLD_AFTER,
    PAUSE,
    PIVOT_OFFSET,
    RADIUS,
    RAMP_TIME,
    RECTANGLE_SIDE,
    SETTLE_TIME,
    SPEED_THRESHOLD,
    STAND_BEFORE,
    START_HEADING,
    STEP_FREQUENCY,
    SWAY_LATERAL,
    SWAY_YAW,
    TURN_ANGLE,
    WALKING_SPEED,
    YAW_RATE,
    YAW_RATE_THRESHOLD,
)
from designlab.params import Param, check_size, declared, param

__all__ = [
    "PAPER_TEST_NAMES",
    "TARGET_COORDINATE",
    "TASK_NAMES",
    "WalkingTask",
    "paper_table1",
    "paper_table2",
    "walking_task",
    "walking_task_from_csv",
]

#: The nine tasks of Wu et al. 2021, Sec. 3.
TASK_NAMES = (
    "forward",
    "backward",
    "left_lateral",
    "right_lateral",
    "left_pivot",
    "right_pivot",
    "rectangle",
    "circle_cw",
    "circle_ccw",
)

#: The paper's test names (Tables 1-2) for each task.
PAPER_TEST_NAMES = {
    "forward": "Forward walking",
    "backward": "Backward walking",
    "left_lateral": "Left lateral walking",
    "right_lateral": "Right lateral walking",
    "left_pivot": "Left pivot turning",
    "right_pivot": "Right pivot turning",
    "rectangle": "Walking along a rectangle",
    "circle_cw": "Clockwise-curve walking",
    "circle_ccw": "Counterclockwise-curve walking",
}

_DENSE_RATE = 1000.0  # Hz, sampling of synthetic trajectories


def _table(name: str) -> pd.DataFrame:
    with resources.files("designlab.data").joinpath(name).open("r", encoding="utf-8") as fh:
        return pd.read_csv(fh)


@lru_cache(maxsize=1)
def _tables() -> tuple[pd.DataFrame, pd.DataFrame]:
    return _table("accompanying_table1.csv"), _table("accompanying_table2.csv")


def paper_table1() -> pd.DataFrame:
    """Wu et al. 2021, Table 1 (WCS start, stop, displacement; mm and degrees), as printed.

    The ``note`` column flags the printed cells that are inconsistent
    (forward walking: user stop/displacement Y printed 914, text says 1914;
    robot start Y printed 438, displacement implies 428).
    """
    return _tables()[0].copy()


def paper_table2() -> pd.DataFrame:
    """Wu et al. 2021, Table 2 (robot pose in LCS_U: target, stop, mean +- sd; mm, degrees)."""
    return _tables()[1].copy()


def _paper_target(name: str) -> tuple[tuple[float, float], float]:
    t1, t2 = _tables()
    test = PAPER_TEST_NAMES[name]
    row = t2[t2["test"] == test].iloc[0]
    pos = (float(row["target_X_C_mm"]) / 1000.0, float(row["target_Y_C_mm"]) / 1000.0)
    rows = t1[t1["test"] == test]
    if len(rows) == 2:
        user = rows[rows["subject"] == "user"].iloc[0]
        robot = rows[rows["subject"] == "robot"].iloc[0]
        heading = math.radians(float(robot["start_gamma_deg"]) - float(user["start_gamma_deg"]))
    else:
        heading = 0.0
    return pos, heading


#: A coordinate of the robot's target in the user's frame LCS_U.
TARGET_COORDINATE = Param(
    None, "m", "coordinate of the robot's target in LCS_U", ge=-10, le=10, name="target_position"
)
#: The most samples of a task's trajectory.
_MAX_SAMPLES = 10_000_000
#: Largest walk file read (bytes; a FIFO or a device is refused, never read whole).
_MAX_BYTES = 200_000_000


def _trajectory_array(label: str, value: Any) -> NDArray[np.float64]:
    """A finite 1-D trajectory array of 2 to 10**7 samples, or an error naming ``label``."""
    if isinstance(value, np.ndarray) and value.size > _MAX_SAMPLES:
        raise InvalidParameterError(label, f"{value.size} samples", f"at most {_MAX_SAMPLES}")
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameterError(label, value, "must be a 1-D array of numbers") from None
    if a.ndim != 1 or not 2 <= a.size <= _MAX_SAMPLES:
        raise InvalidParameterError(label, a.shape, "must be a 1-D array of 2 to 10**7 points")
    bad = ~np.isfinite(a)
    if bad.any():
        k = int(np.argmax(bad))
        raise InvalidParameterError(
            f"{label}[{k}]", float(a[k]), "every trajectory point must be finite"
        )
    return a


@declared
@dataclass(frozen=True, eq=False)
class WalkingTask:
    """A user trajectory and the robot's target pose in the user's frame.

    The trajectory is the world position of the user's frame origin and the
    user's world heading (counter-clockwise from +X; continuous, not wrapped)
    at strictly increasing times from 0. The target's distance from the user
    must exceed ``user_radius``.
    """

    name: str = param(kind="text", doc="label")
    time: NDArray[np.float64] = param(kind="object", doc="sample times in s, increasing from 0")  # noqa: RUF009
    x: NDArray[np.float64] = param(kind="object", doc="world x of the user's frame origin in m")  # noqa: RUF009
    y: NDArray[np.float64] = param(kind="object", doc="world y of the user's frame origin in m")  # noqa: RUF009
    heading: NDArray[np.float64] = param(kind="object", doc="world heading of the user in rad")  # noqa: RUF009
    walk_start: float = param(None, "s", doc="when the user starts walking", ge=0, le=1e6)
    walk_stop: float = param(None, "s", doc="when the user stops walking", ge=0, le=1e6)
    target_position: tuple[float, float] = param(
        kind="object", doc="robot target (X_T, Y_T) in LCS_U in m (X right, Y forward)"
    )
    target_heading: float = param(
        "gamma_T",
        "rad",
        doc="robot target orientation in LCS_U",
        ge=-2 * math.pi,
        le=2 * math.pi,
        default=0.0,
    )
    user_radius: float = param(
        None,
        "m",
        doc="radius of the user's body around the frame origin",
        gt=0,
        le=2,
        default=0.15,
    )
    source: str = param(kind="text", doc="'synthetic' or the CSV path", default="synthetic")
    parameters: dict[str, float] = param(  # noqa: RUF009
        kind="object", doc="the generator's parameters (for reports)", default_factory=dict
    )

    def __post_init__(self) -> None:
        c = f"WalkingTask({self.name!r})."
        arrays = {
            n: _trajectory_array(c + n, getattr(self, n)) for n in ("time", "x", "y", "heading")
        }
        n = arrays["time"].size
        for name in ("x", "y", "heading"):
            if arrays[name].size != n:
                raise InvalidParameterError(
                    c + name, arrays[name].size, f"must have as many points as time ({n})"
                )
        t = arrays["time"]
        if np.any(np.diff(t) <= 0):
            raise InvalidParameterError(c + "time", "not increasing", "must be strictly increasing")
        for name, a in arrays.items():
            a.setflags(write=False)
            object.__setattr__(self, name, a)
        if not (t[0] <= self.walk_start <= self.walk_stop <= t[-1]):
            raise InvalidParameterError(
                c + "walk_stop",
                self.walk_stop,
                f"need time[0] <= walk_start ({self.walk_start}) <= walk_stop <= time[-1] "
                f"({t[-1]})",
                "s",
            )
        self._check_target(c)

    def _check_target(self, c: str) -> None:
        pos = self.target_position
        if isinstance(pos, (str, bytes)) or np.shape(pos) != (2,):
            raise InvalidParameterError(
                c + "target_position", pos, "must be two numbers (X_T, Y_T)", "m"
            )
        tx, ty = (TARGET_COORDINATE.check(v, c + "target_position") for v in pos)
        r = self.user_radius
        if math.hypot(tx, ty) <= r:
            raise InvalidParameterError(
                c + "target_position",
                pos,
                f"is inside the user: its distance {math.hypot(tx, ty):.3f} m must exceed "
                f"user_radius = {r} m",
                "m",
            )
        object.__setattr__(self, "target_position", (tx, ty))

    @property
    def duration(self) -> float:
        """Length of the task in s."""
        return float(self.time[-1] - self.time[0])

    @property
    def distance(self) -> float:
        """Path length of the user's frame origin in m."""
        return float(np.sum(np.hypot(np.diff(self.x), np.diff(self.y))))

    def pose(self, t: ArrayLike) -> NDArray[np.float64]:
        """User pose (x, y, psi) at times ``t`` (linear interpolation), shape (3, n).

        Parameters
        ----------
        t
            Times in s; held at the ends outside the recorded span.
        """
        tt = np.asarray(t, dtype=float)
        return np.vstack(
            [np.interp(tt, self.time, a) for a in (self.x, self.y, self.heading)]
        ).reshape((3, *tt.shape))

    def with_target(
        self, target_position: tuple[float, float], target_heading: float | None = None
    ) -> WalkingTask:
        """Return a copy with another robot target pose in LCS_U."""
        return WalkingTask(
            self.name,
            self.time,
            self.x,
            self.y,
            self.heading,
            self.walk_start,
            self.walk_stop,
            target_position,
            self.target_heading if target_heading is None else target_heading,
            self.user_radius,
            self.source,
            dict(self.parameters),
        )


# --------------------------------------------------------------------------- synthesis


def _shape(t: NDArray, t0: float, duration: float, ramp: float) -> NDArray:
    """Raised-cosine trapezoid in [0, 1]: 0 before t0, ramps up, cruises, ramps down."""
    s = np.zeros_like(t)
    t1 = t - t0
    up = (t1 >= 0) & (t1 < ramp)
    s[up] = 0.5 * (1 - np.cos(np.pi * t1[up] / ramp))
    cruise = (t1 >= ramp) & (t1 <= duration - ramp)
    s[cruise] = 1.0
    down = (t1 > duration - ramp) & (t1 <= duration)
    s[down] = 0.5 * (1 - np.cos(np.pi * (duration - t1[down]) / ramp))
    return s


#: One move of a walk: (lateral speed m/s, forward speed m/s, yaw rate rad/s, duration of
#: cruise-equivalent motion s); the move lasts that duration plus one ramp.
Move = tuple[float, float, float, float]


@dataclass(frozen=True)
class _Walk:
    """The checked settings of :func:`walking_task` (SI units)."""

    speed: float
    yaw_rate: float
    distance: float
    turn_angle: float
    radius: float
    rectangle: tuple[float, float]
    ramp_time: float
    pause: float
    stand_before: float
    settle_time: float
    pivot_offset: float
    sway: tuple[float, float]
    step_frequency: float
    start_heading: float


def _straight(lateral: float, forward: float) -> Callable[[_Walk], list[Move]]:
    return lambda w: [(lateral * w.speed, forward * w.speed, 0.0, w.distance / w.speed)]


def _pivot(sign: float) -> Callable[[_Walk], list[Move]]:
    return lambda w: [(0.0, 0.0, sign * w.yaw_rate, w.turn_angle / w.yaw_rate)]


def _circle(sign: float) -> Callable[[_Walk], list[Move]]:
    return lambda w: [(0.0, w.speed, sign * w.speed / w.radius, 2 * math.pi * w.radius / w.speed)]


def _rectangle(w: _Walk) -> list[Move]:
    a, b = w.rectangle
    v = w.speed
    return [
        (0.0, v, 0.0, a / v),
        (v, 0.0, 0.0, b / v),
        (0.0, -v, 0.0, a / v),
        (-v, 0.0, 0.0, b / v),
    ]


#: The moves of each task (a small registry, one entry per task of :data:`TASK_NAMES`).
_MOVES: dict[str, Callable[[_Walk], list[Move]]] = {
    "forward": _straight(0.0, 1.0),
    "backward": _straight(0.0, -1.0),
    "left_lateral": _straight(-1.0, 0.0),
    "right_lateral": _straight(1.0, 0.0),
    "left_pivot": _pivot(1.0),
    "right_pivot": _pivot(-1.0),
    "rectangle": _rectangle,
    "circle_cw": _circle(-1.0),
    "circle_ccw": _circle(1.0),
}

#: Default cruise speed (m/s) and straight distance (m) of each task (Sec. 4.1 distances).
_DEFAULT_SPEED = {"forward": 0.45, "backward": 0.4, "left_lateral": 0.4, "right_lateral": 0.4}
_DEFAULT_DISTANCE = {"forward": 1.95, "backward": 1.98, "left_lateral": 1.52, "right_lateral": 1.56}


def _plan(moves: list[Move], w: _Walk) -> tuple[list[tuple[float, ...]], float]:
    """Start, duration, ramp and speeds of each move, and when the walk stops."""
    plan = []
    t0 = w.stand_before
    for k, (vl, vf, om, cruise_equiv) in enumerate(moves):
        dur, r = cruise_equiv + w.ramp_time, w.ramp_time
        if cruise_equiv < w.ramp_time:  # short move: triangular-ish profile
            r = cruise_equiv
            dur = 2 * cruise_equiv
        plan.append((t0, dur, r, vl, vf, om))
        t0 += dur + (w.pause if k < len(moves) - 1 else 0.0)
    return plan, t0


def _velocities(t: NDArray, plan: list[tuple[float, ...]]) -> tuple[NDArray, ...]:
    """Body-frame lateral, forward and yaw velocities and the walking envelope in [0, 1]."""
    vl, vf, om, env = (np.zeros(t.size) for _ in range(4))
    for t0, dur, r, a, b, c in plan:
        s = _shape(t, t0, dur, r)
        vl += a * s
        vf += b * s
        om += c * s
        env = np.maximum(env, s)
    return vl, vf, om, env


def _integrate(
    moves: list[Move], w: _Walk, origin_offset: float
) -> tuple[NDArray, NDArray, NDArray, NDArray, float, float]:
    """Integrate body-frame moves into the trajectory of the user's frame origin."""
    plan, walk_stop = _plan(moves, w)
    t_end = walk_stop + w.settle_time
    n = round(t_end * _DENSE_RATE) + 1
    check_size(
        f"the walk's duration (speed = {w.speed:g} m/s, distance = {w.distance:g} m, "
        f"settle_time = {w.settle_time:g} s)", t_end, 16.0 * n,
        what=f"{n} samples at 1 kHz; a faster walk or a shorter one",
    )  # fmt: skip
    t = np.linspace(0.0, t_end, n)
    vl, vf, om, env = _velocities(t, plan)
    dt = np.diff(t)
    # heading of the body (turning centre), then world velocity of the centre
    psi = w.start_heading + np.concatenate([[0.0], np.cumsum(0.5 * (om[1:] + om[:-1]) * dt)])
    vx_w = vl * np.sin(psi) + vf * np.cos(psi)
    vy_w = -vl * np.cos(psi) + vf * np.sin(psi)
    cx = np.concatenate([[0.0], np.cumsum(0.5 * (vx_w[1:] + vx_w[:-1]) * dt)])
    cy = np.concatenate([[0.0], np.cumsum(0.5 * (vy_w[1:] + vy_w[:-1]) * dt)])
    # pelvis sway: lateral and yaw oscillation at the stride frequency while walking
    lat_amp, yaw_amp = w.sway
    phase = np.pi * w.step_frequency * np.maximum(t - w.stand_before, 0.0)  # stride = 2 steps
    lat = lat_amp * env * np.sin(phase)
    heading = psi + yaw_amp * env * np.sin(phase)
    # the frame origin sits origin_offset ahead of the turning centre, plus sway
    x = cx + origin_offset * np.cos(psi) + lat * np.sin(psi)
    y = cy + origin_offset * np.sin(psi) - lat * np.cos(psi)
    x -= x[0]
    y -= y[0]
    return t, x, y, heading, w.stand_before, walk_stop


def _pair(name: str, value: Any, decls: tuple[Param, Param]) -> tuple[float, float]:
    if isinstance(value, (str, bytes)) or np.shape(value) != (2,):
        raise InvalidParameterError(name, value, "two numbers")
    return decls[0].check(value[0], f"{name}[0]"), decls[1].check(value[1], f"{name}[1]")


def _checked_walk(name: str, given: dict[str, Any]) -> _Walk:
    """The settings of a task, each checked against its declaration (defaults per task)."""
    if name not in TASK_NAMES:
        raise InvalidParameterError("name", name, f"one of {TASK_NAMES}")
    speed = given["speed"] if given["speed"] is not None else _DEFAULT_SPEED.get(name, 0.5)
    dist = given["distance"] if given["distance"] is not None else _DEFAULT_DISTANCE.get(name, 1.0)
    return _Walk(
        speed=WALKING_SPEED.check(speed),
        yaw_rate=YAW_RATE.check(given["yaw_rate"]),
        distance=DISTANCE.check(dist),
        turn_angle=TURN_ANGLE.check(given["turn_angle"]),
        radius=RADIUS.check(given["radius"]),
        rectangle=_pair("rectangle", given["rectangle"], (RECTANGLE_SIDE, RECTANGLE_SIDE)),
        ramp_time=RAMP_TIME.check(given["ramp_time"]),
        pause=PAUSE.check(given["pause"]),
        stand_before=STAND_BEFORE.check(given["stand_before"]),
        settle_time=SETTLE_TIME.check(given["settle_time"]),
        pivot_offset=PIVOT_OFFSET.check(given["pivot_offset"]),
        sway=_pair("sway", given["sway"], (SWAY_LATERAL, SWAY_YAW)),
        step_frequency=STEP_FREQUENCY.check(given["step_frequency"]),
        start_heading=START_HEADING.check(given["start_heading"]),
    )


def walking_task(
    name: str,
    *,
    speed: float | None = None,
    yaw_rate: float = math.radians(45.0),
    distance: float | None = None,
    turn_angle: float = math.radians(90.0),
    radius: float = RADIUS.default,
    rectangle: tuple[float, float] = (2.5, 1.8),
    ramp_time: float = RAMP_TIME.default,
    pause: float = PAUSE.default,
    stand_before: float = STAND_BEFORE.default,
    settle_time: float = SETTLE_TIME.default,
    pivot_offset: float = PIVOT_OFFSET.default,
    sway: tuple[float, float] = (0.0, 0.0),
    step_frequency: float = STEP_FREQUENCY.default,
    target_position: tuple[float, float] | None = None,
    target_heading: float | None = None,
    start_heading: float = math.pi / 2,
) -> WalkingTask:
    """One of the nine walking tasks of Wu et al. 2021, Sec. 3, as a synthetic trajectory.

    Parameters
    ----------
    name
        One of :data:`TASK_NAMES`: ``forward``, ``backward``, ``left_lateral``,
        ``right_lateral``, ``left_pivot``, ``right_pivot``, ``rectangle``
        (forward, right, backward, left while facing forward), ``circle_cw``,
        ``circle_ccw`` (one full circle walking forward).
    speed, yaw_rate, distance, turn_angle, radius
        Cruise speed (m/s; default per task, :data:`WALKING_SPEED`), pivot rate (rad/s),
        straight distance (m; default the paper's, Sec. 4.1), pivot angle (rad), circle
        radius (m): the declarations in :mod:`~designlab.following.accompanying.parameters`.
    rectangle
        Forward and lateral side lengths in m; default (2.5, 1.8).
    ramp_time, pause, stand_before, settle_time
        Raised-cosine ramp of each move, pause between the rectangle's legs, standing
        time before and after the walk, in s.
    pivot_offset
        Frame origin ahead of the turning centre in pivots, m (0.25 m reproduces the
        left pivot's user displacement of Table 1).
    sway, step_frequency
        Pelvis sway amplitudes (lateral m, yaw rad) while walking; steps per second.
    target_position, target_heading
        Robot target pose in LCS_U (m, rad); default the paper's (Tables 1-2).
    start_heading
        User's initial world heading in rad; default pi/2 (facing +Y).

    Examples
    --------
    >>> t = walking_task("left_pivot")
    >>> round(float(np.degrees(t.heading[-1] - t.heading[0])), 1)
    90.0
    >>> walking_task("sideways")
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: name = 'sideways' is not allowed: ...
    """
    w = _checked_walk(name, {k: v for k, v in locals().items() if k != "name"})
    offset = w.pivot_offset if name in ("left_pivot", "right_pivot") else 0.0
    t, x, y, psi, ws, we = _integrate(_MOVES[name](w), w, offset)
    pos, hdg = _paper_target(name)
    params = {
        "speed_m_s": w.speed,
        "yaw_rate_rad_s": w.yaw_rate,
        "distance_m": w.distance,
        "turn_angle_rad": w.turn_angle,
        "radius_m": w.radius,
        "ramp_time_s": w.ramp_time,
        "settle_time_s": w.settle_time,
        "sway_lateral_m": w.sway[0],
        "sway_yaw_rad": w.sway[1],
    }
    return WalkingTask(
        name,
        t,
        x,
        y,
        psi,
        ws,
        we,
        pos if target_position is None else target_position,
        hdg if target_heading is None else target_heading,
        parameters=params,
    )


def _read_walk(p: Path) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Time, x, y and heading (rad) of a recorded walk; errors name the file, line and column."""
    from designlab.yamlio import YamlError, read_text_file

    try:  # a regular file, read in bounded chunks, UTF-8 without NUL bytes
        text = read_text_file(p, max_bytes=_MAX_BYTES)
    except YamlError as exc:
        where = "" if exc.line is None else f" (line {exc.line})"
        raise InvalidParameterError("path", str(p), f"{exc.message}{where}") from None
    try:
        frame = pd.read_csv(io.StringIO(text))
    except pd.errors.EmptyDataError:
        raise InvalidParameterError("path", str(p), "a CSV file with a header row") from None
    except (pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise InvalidParameterError("path", str(p), f"a readable CSV file ({exc})") from None
    heading = "heading_rad" if "heading_rad" in frame else "heading_deg"
    if not {"time_s", "x_m", "y_m", heading} <= set(frame.columns):
        raise InvalidParameterError(
            "path", str(p), "CSV needs columns time_s, x_m, y_m and heading_rad or heading_deg"
        )
    if len(frame) < 2:
        raise InvalidParameterError("path", str(p), "needs at least 2 samples")
    if len(frame) > _MAX_SAMPLES:
        raise InvalidParameterError("path", str(p), f"at most {_MAX_SAMPLES} samples")
    cols = []
    for col in ("time_s", "x_m", "y_m", heading):
        values = pd.to_numeric(frame[col], errors="coerce").to_numpy(float)
        bad = np.flatnonzero(~np.isfinite(values))
        if len(bad):
            i = int(bad[0])
            raise InvalidParameterError(
                f"{p.name} line {i + 2} (data row {i + 1}), column {col!r}",
                frame[col].iloc[i],
                "every trajectory point must be a finite number",
            )
        cols.append(values)
    t, x, y, psi = cols
    return t, x, y, (psi if heading == "heading_rad" else np.radians(psi))


def _held(arrays: tuple[NDArray, ...], hold: float) -> tuple[NDArray, ...]:
    """Append ``hold`` s of standing (the last sample repeated at the median step)."""
    t, x, y, psi = arrays
    if hold <= 0:
        return arrays
    dt = float(np.median(np.diff(t)))
    if not dt > 0:
        raise InvalidParameterError("time_s", "not increasing", "must be strictly increasing", "s")
    check_size("hold_after", hold, 4.0 * (t.size + hold / dt), what="the standing samples")
    extra = np.arange(dt, hold + 0.5 * dt, dt)
    return (
        np.concatenate([t, t[-1] + extra]),
        np.concatenate([x, np.full(extra.size, x[-1])]),
        np.concatenate([y, np.full(extra.size, y[-1])]),
        np.concatenate([psi, np.full(extra.size, psi[-1])]),
    )


def _walk_span(arrays: tuple[NDArray, ...], p: Path, thresholds: tuple[float, float]) -> tuple:
    """First and last samples where the origin moves faster or turns faster than the thresholds."""
    t, x, y, psi = arrays
    speed = np.hypot(np.gradient(x, t), np.gradient(y, t))
    yaw = np.abs(np.gradient(psi, t))
    moving = (speed > thresholds[0]) | (yaw > thresholds[1])
    if not moving.any():
        raise InvalidParameterError("path", str(p), "the user never moves in this recording")
    idx = np.flatnonzero(moving)
    return float(t[max(idx[0] - 1, 0)]), float(t[min(idx[-1] + 1, t.size - 1)])


def walking_task_from_csv(
    path: str | Path,
    *,
    target_position: tuple[float, float],
    target_heading: float = 0.0,
    name: str | None = None,
    walk_start: float | None = None,
    walk_stop: float | None = None,
    hold_after: float = HOLD_AFTER.default,
    speed_threshold: float = SPEED_THRESHOLD.default,
    yaw_rate_threshold: float = YAW_RATE_THRESHOLD.default,
) -> WalkingTask:
    """A walking task from a recorded walk (CSV).

    The CSV has columns ``time_s``, ``x_m``, ``y_m`` and ``heading_rad`` or
    ``heading_deg`` (world heading of the user's frame origin, counter-clockwise
    from +X; unwrapped here). Times are shifted to start at 0.

    Parameters
    ----------
    path
        CSV file.
    target_position, target_heading
        Robot target pose in LCS_U (m, rad).
    name
        Label; default the file stem.
    walk_start, walk_stop
        When the user walks, in s after the first sample. Default: the first and
        last samples where the origin speed exceeds ``speed_threshold`` (m/s)
        or the yaw rate exceeds ``yaw_rate_threshold`` (rad/s).
    hold_after
        Standing time appended after the last sample in s (:data:`HOLD_AFTER`),
        so that the settled error 10 s after the stop is defined.
    speed_threshold
        The walk ends at the last sample faster than this (m/s).
    yaw_rate_threshold
        ... or turning faster than this (rad/s).

    Examples
    --------
    >>> import tempfile, os
    >>> t = np.linspace(0, 6, 61)
    >>> x = np.zeros_like(t); y = np.clip(0.5 * (t - 1), 0, 2.0)
    >>> p = os.path.join(tempfile.mkdtemp(), "walk.csv")
    >>> pd.DataFrame({"time_s": t, "x_m": x, "y_m": y, "heading_deg": 90.0}).to_csv(p, index=False)
    >>> task = walking_task_from_csv(p, target_position=(0.0, 0.45))
    >>> round(task.walk_start, 1), round(task.walk_stop, 1), task.duration
    (1.0, 5.0, 16.0)
    >>> import shutil; shutil.rmtree(os.path.dirname(p))
    """
    p = Path(path)
    hold = HOLD_AFTER.check(hold_after)
    thresholds = (
        SPEED_THRESHOLD.check(speed_threshold),
        YAW_RATE_THRESHOLD.check(yaw_rate_threshold),
    )
    t, x, y, psi = _read_walk(p)
    if np.any(np.diff(t) <= 0):
        raise InvalidParameterError(
            f"{p.name}:time_s", "not increasing", "must be strictly increasing", "s"
        )
    arrays = _held((t - t[0], x, y, np.unwrap(psi)), hold)
    if walk_start is None or walk_stop is None:
        ws, we = _walk_span(arrays, p, thresholds)
        ws = ws if walk_start is None else walk_start
        we = we if walk_stop is None else walk_stop
    else:
        ws, we = walk_start, walk_stop
    return WalkingTask(
        name or p.stem, *arrays, ws, we, target_position, target_heading, source=str(p)
    )
