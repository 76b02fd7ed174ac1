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

import math
from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError, check_nonnegative, check_positive

__all__ = [
    "PAPER_TEST_NAMES",
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


@dataclass(frozen=True, eq=False)
class WalkingTask:
    """A user trajectory and the robot's target pose in the user's frame.

    Parameters
    ----------
    name
        Label.
    time
        Sample times in s, strictly increasing, starting at 0.
    x, y
        World position of the user's frame origin in m (same length as ``time``).
    heading
        World heading of the user in rad (counter-clockwise from +X; continuous,
        not wrapped).
    walk_start, walk_stop
        When the user starts and stops walking, in s.
    target_position
        Robot target (X_T, Y_T) in LCS_U in m (X to the user's right, Y forward).
        Its distance from the user must exceed ``user_radius``.
    target_heading
        Robot target orientation gamma_T in LCS_U in rad.
    user_radius
        Radius of the user's body around the frame origin in m (> 0); a target
        inside it is rejected.
    source
        ``"synthetic"`` or the CSV path.
    parameters
        The generator's parameters (for reports).
    """

    name: str
    time: NDArray[np.float64]
    x: NDArray[np.float64]
    y: NDArray[np.float64]
    heading: NDArray[np.float64]
    walk_start: float
    walk_stop: float
    target_position: tuple[float, float]
    target_heading: float = 0.0
    user_radius: float = 0.15
    source: str = "synthetic"
    parameters: dict[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        c = f"WalkingTask({self.name!r})."
        arrays = {}
        for name in ("time", "x", "y", "heading"):
            a = np.asarray(getattr(self, name), dtype=float)
            if a.ndim != 1 or a.size < 2:
                raise InvalidParameterError(c + name, a.shape, "must be a 1-D array of >= 2 points")
            bad = ~np.isfinite(a)
            if bad.any():
                k = int(np.argmax(bad))
                raise InvalidParameterError(
                    f"{c}{name}[{k}]", float(a[k]), "every trajectory point must be finite"
                )
            arrays[name] = a
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
        ws = check_nonnegative(c + "walk_start", self.walk_start, "s")
        we = check_nonnegative(c + "walk_stop", self.walk_stop, "s")
        if not (t[0] <= ws <= we <= t[-1]):
            raise InvalidParameterError(
                c + "walk_stop",
                self.walk_stop,
                f"need time[0] <= walk_start ({ws}) <= walk_stop <= time[-1] ({t[-1]})",
                "s",
            )
        object.__setattr__(self, "walk_start", ws)
        object.__setattr__(self, "walk_stop", we)
        r = check_positive(c + "user_radius", self.user_radius, "m")
        object.__setattr__(self, "user_radius", r)
        try:
            tx, ty = (float(v) for v in self.target_position)
        except (TypeError, ValueError):
            raise InvalidParameterError(
                c + "target_position", self.target_position, "must be two numbers (X_T, Y_T)", "m"
            ) from None
        if not (math.isfinite(tx) and math.isfinite(ty)):
            raise InvalidParameterError(
                c + "target_position", self.target_position, "must be finite", "m"
            )
        if math.hypot(tx, ty) <= r:
            raise InvalidParameterError(
                c + "target_position",
                self.target_position,
                f"is inside the user: its distance {math.hypot(tx, ty):.3f} m must exceed "
                f"user_radius = {r} m",
                "m",
            )
        object.__setattr__(self, "target_position", (tx, ty))
        g = float(self.target_heading)
        if not math.isfinite(g):
            raise InvalidParameterError(
                c + "target_heading", self.target_heading, "must be finite", "rad"
            )
        object.__setattr__(self, "target_heading", g)

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


def _move_duration(amount: float, rate: float, ramp: float) -> tuple[float, float]:
    """Duration and (possibly shortened) ramp of a move covering ``amount`` at ``rate``."""
    ramp_eff = min(ramp, amount / rate)
    return amount / rate + ramp_eff, ramp_eff


def _integrate(
    name: str,
    moves: list[tuple[float, float, float, float]],
    *,
    ramp: float,
    pause: float,
    stand_before: float,
    settle_time: float,
    start_heading: float,
    origin_offset: float,
    sway: tuple[float, float],
    step_frequency: float,
) -> tuple[NDArray, NDArray, NDArray, NDArray, float, float]:
    """Integrate body-frame moves (v_lat, v_fwd, omega, amount_of_motion) into a trajectory.

    Each move is (lateral speed, forward speed, yaw rate, duration at cruise
    equivalent), i.e. the move lasts ``amount`` s of cruise plus one ramp.
    """
    plan = []
    t0 = stand_before
    for k, (vl, vf, om, cruise_equiv) in enumerate(moves):
        dur, r = cruise_equiv + ramp, ramp
        if cruise_equiv < ramp:  # short move: triangular-ish profile
            r = cruise_equiv
            dur = 2 * cruise_equiv
        plan.append((t0, dur, r, vl, vf, om))
        t0 += dur + (pause if k < len(moves) - 1 else 0.0)
    walk_stop = t0
    t_end = walk_stop + settle_time
    n = round(t_end * _DENSE_RATE) + 1
    t = np.linspace(0.0, t_end, n)
    vl = np.zeros(n)
    vf = np.zeros(n)
    om = np.zeros(n)
    env = np.zeros(n)
    for t0, dur, r, a, b, c in plan:
        s = _shape(t, t0, dur, r)
        vl += a * s
        vf += b * s
        om += c * s
        env = np.maximum(env, s)
    dt = np.diff(t)
    # heading of the body (turning centre), then world velocity of the centre
    psi = start_heading + np.concatenate([[0.0], np.cumsum(0.5 * (om[1:] + om[:-1]) * dt)])
    vx_w = vl * np.sin(psi) + vf * np.cos(psi)
    vy_w = -vl * np.cos(psi) + vf * np.sin(psi)
    cx = np.concatenate([[0.0], np.cumsum(0.5 * (vx_w[1:] + vx_w[:-1]) * dt)])
    cy = np.concatenate([[0.0], np.cumsum(0.5 * (vy_w[1:] + vy_w[:-1]) * dt)])
    # pelvis sway: lateral and yaw oscillation at the stride frequency while walking
    lat_amp, yaw_amp = sway
    phase = np.pi * step_frequency * np.maximum(t - stand_before, 0.0)  # stride = 2 steps
    lat = lat_amp * env * np.sin(phase)
    heading = psi + yaw_amp * env * np.sin(phase)
    # the frame origin sits origin_offset ahead of the turning centre, plus sway
    x = cx + origin_offset * np.cos(psi) + lat * np.sin(psi)
    y = cy + origin_offset * np.sin(psi) - lat * np.cos(psi)
    x -= x[0]
    y -= y[0]
    return t, x, y, heading, stand_before, walk_stop


#: Fastest user accepted (m/s): well above any walk (Wu et al. 2021 walk at about 0.5 m/s).
MAX_WALKING_SPEED = 10.0


def walking_task(
    name: str,
    *,
    speed: float | None = None,
    yaw_rate: float = math.radians(45.0),
    distance: float | None = None,
    turn_angle: float = math.radians(90.0),
    radius: float = 0.9,
    rectangle: tuple[float, float] = (2.5, 1.8),
    ramp_time: float = 0.6,
    pause: float = 0.5,
    stand_before: float = 1.0,
    settle_time: float = 10.0,
    pivot_offset: float = 0.25,
    sway: tuple[float, float] = (0.0, 0.0),
    step_frequency: float = 1.8,
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
    speed
        Cruise walking speed in m/s (> 0). Default 0.45 m/s for forward, 0.4 m/s
        for backward and lateral walking, 0.5 m/s on the rectangle and circles.
    yaw_rate
        Cruise turning rate of the pivots in rad/s (> 0); default 45 deg/s.
    distance
        Walked distance in m for the straight tasks (> 0). Default as the paper
        (Sec. 4.1): 1.95 m forward, 1.98 m backward, 1.52 m left and 1.56 m right.
    turn_angle
        Pivot angle in rad (> 0); default 90 deg.
    radius
        Circle radius in m (> 0); default 0.9 m (inside the 2.5 m x 1.8 m plate).
    rectangle
        Forward and lateral side lengths in m; default (2.5, 1.8).
    ramp_time
        Raised-cosine acceleration time of each move in s (> 0).
    pause
        Standing time between the legs of the rectangle in s (>= 0).
    stand_before, settle_time
        Standing time before the walk and after it in s (>= 0).
    pivot_offset
        Distance of the frame origin (the user-side encoder housing) ahead of
        the turning centre in pivots, m (>= 0). The default 0.25 m reproduces the
        user displacement of about (-0.27, -0.22) m of the left pivot of Table 1.
    sway
        Pelvis sway amplitudes (lateral in m, yaw in rad) at the stride
        frequency, while walking (>= 0); default none.
    step_frequency
        Steps per second (> 0); the sway has half this frequency.
    target_position, target_heading
        Robot target pose in LCS_U (m, rad); default the paper's (Tables 1-2).
    start_heading
        User's initial world heading in rad; default pi/2 (facing +Y).

    Raises
    ------
    InvalidParameterError
        For an unknown name or a bad parameter.

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
    if name not in TASK_NAMES:
        raise InvalidParameterError("name", name, f"one of {TASK_NAMES}")
    default_speed = {
        "forward": 0.45,
        "backward": 0.4,
        "left_lateral": 0.4,
        "right_lateral": 0.4,
    }.get(name, 0.5)
    v = check_positive("speed", default_speed if speed is None else speed, "m/s")
    if v > MAX_WALKING_SPEED:
        raise InvalidParameterError(
            "speed", v, f"a walking speed: at most {MAX_WALKING_SPEED:g} m/s", "m/s"
        )
    w = check_positive("yaw_rate", yaw_rate, "rad/s")
    ramp = check_positive("ramp_time", ramp_time, "s")
    turn = check_positive("turn_angle", turn_angle, "rad")
    rad = check_positive("radius", radius, "m")
    pause = check_nonnegative("pause", pause, "s")
    stand_before = check_nonnegative("stand_before", stand_before, "s")
    settle_time = check_nonnegative("settle_time", settle_time, "s")
    pivot_offset = check_nonnegative("pivot_offset", pivot_offset, "m")
    f_step = check_positive("step_frequency", step_frequency, "Hz")
    sway_lat = check_nonnegative("sway[0]", sway[0], "m")
    sway_yaw = check_nonnegative("sway[1]", sway[1], "rad")
    rect = (
        check_positive("rectangle[0]", rectangle[0], "m"),
        check_positive("rectangle[1]", rectangle[1], "m"),
    )
    default_dist = {"forward": 1.95, "backward": 1.98, "left_lateral": 1.52, "right_lateral": 1.56}
    if distance is not None:
        dist = check_positive("distance", distance, "m")
    else:
        dist = default_dist.get(name, 1.0)

    offset = 0.0
    if name == "forward":
        moves = [(0.0, v, 0.0, dist / v)]
    elif name == "backward":
        moves = [(0.0, -v, 0.0, dist / v)]
    elif name == "left_lateral":
        moves = [(-v, 0.0, 0.0, dist / v)]
    elif name == "right_lateral":
        moves = [(v, 0.0, 0.0, dist / v)]
    elif name in ("left_pivot", "right_pivot"):
        sign = 1.0 if name == "left_pivot" else -1.0
        moves = [(0.0, 0.0, sign * w, turn / w)]
        offset = pivot_offset
    elif name == "rectangle":
        a, b = rect
        moves = [
            (0.0, v, 0.0, a / v),
            (v, 0.0, 0.0, b / v),
            (0.0, -v, 0.0, a / v),
            (-v, 0.0, 0.0, b / v),
        ]
    else:
        sign = -1.0 if name == "circle_cw" else 1.0
        moves = [(0.0, v, sign * v / rad, 2 * math.pi * rad / v)]
    t, x, y, psi, ws, we = _integrate(
        name,
        moves,
        ramp=ramp,
        pause=pause,
        stand_before=stand_before,
        settle_time=settle_time,
        start_heading=float(start_heading),
        origin_offset=offset,
        sway=(sway_lat, sway_yaw),
        step_frequency=f_step,
    )
    pos, hdg = _paper_target(name)
    params = {
        "speed_m_s": v,
        "yaw_rate_rad_s": w,
        "distance_m": dist,
        "turn_angle_rad": turn,
        "radius_m": rad,
        "ramp_time_s": ramp,
        "settle_time_s": settle_time,
        "sway_lateral_m": sway_lat,
        "sway_yaw_rad": sway_yaw,
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


def walking_task_from_csv(
    path: str | Path,
    *,
    target_position: tuple[float, float],
    target_heading: float = 0.0,
    name: str | None = None,
    walk_start: float | None = None,
    walk_stop: float | None = None,
    hold_after: float = 10.0,
    speed_threshold: float = 0.05,
    yaw_rate_threshold: float = 0.15,
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
        Standing time appended after the last sample in s (>= 0), so that the
        settled error 10 s after the stop is defined.
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
    frame = pd.read_csv(p)
    need = {"time_s", "x_m", "y_m"}
    missing = need - set(frame.columns)
    if missing or not ({"heading_rad", "heading_deg"} & set(frame.columns)):
        raise InvalidParameterError(
            "path", str(p), "CSV needs columns time_s, x_m, y_m and heading_rad or heading_deg"
        )
    t = frame["time_s"].to_numpy(float)
    x = frame["x_m"].to_numpy(float)
    y = frame["y_m"].to_numpy(float)
    psi = (
        frame["heading_rad"].to_numpy(float)
        if "heading_rad" in frame
        else np.radians(frame["heading_deg"].to_numpy(float))
    )
    for label, a in (("time_s", t), ("x_m", x), ("y_m", y), ("heading", psi)):
        bad = ~np.isfinite(a)
        if bad.any():
            k = int(np.argmax(bad))
            raise InvalidParameterError(
                f"{p.name}:{label}[{k}]", float(a[k]), "every trajectory point must be finite"
            )
    if t.size < 2:
        raise InvalidParameterError("path", str(p), "needs at least 2 samples")
    t = t - t[0]
    psi = np.unwrap(psi)
    hold = check_nonnegative("hold_after", hold_after, "s")
    if hold > 0:
        dt = float(np.median(np.diff(t)))
        extra = np.arange(dt, hold + 0.5 * dt, dt)
        t = np.concatenate([t, t[-1] + extra])
        x = np.concatenate([x, np.full(extra.size, x[-1])])
        y = np.concatenate([y, np.full(extra.size, y[-1])])
        psi = np.concatenate([psi, np.full(extra.size, psi[-1])])
    if walk_start is None or walk_stop is None:
        speed = np.hypot(np.gradient(x, t), np.gradient(y, t))
        yaw = np.abs(np.gradient(psi, t))
        moving = (speed > speed_threshold) | (yaw > yaw_rate_threshold)
        if not moving.any():
            raise InvalidParameterError("path", str(p), "the user never moves in this recording")
        idx = np.flatnonzero(moving)
        ws = float(t[max(idx[0] - 1, 0)]) if walk_start is None else walk_start
        we = float(t[min(idx[-1] + 1, t.size - 1)]) if walk_stop is None else walk_stop
    else:
        ws, we = walk_start, walk_stop
    return WalkingTask(
        name or p.stem,
        t,
        x,
        y,
        psi,
        ws,
        we,
        target_position,
        target_heading,
        source=str(p),
    )
