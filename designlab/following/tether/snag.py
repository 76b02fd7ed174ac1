"""Tether snagging on a corridor corner (Allan 2015 Sec. 4.5, Table 4.1, eqs. 4.6-4.13).

The kinematic simulation of Sec. 4.5: a corridor of width ``w`` with one 90 degree
left turn; the leader walks the centre line at ``v_F`` and turns on an arc of
radius ``w/2`` about the inner corner vertex (Table 4.1). The follower records
the tether tip it estimates (robot + ``l_m`` along ``theta_m``, eq. 2.14) every
``step`` metres, and the robot drives along that recorded path, facing along it.
The default follower (``follower="constant_speed"``) is Table 4.1's: it starts
``gap`` metres (along the path) behind the newest point and advances at the target
following speed ``v_F``, never past the newest point. The project's gap-keeping
follower (``follower="gap"``, ours) keeps exactly ``gap`` behind the newest point;
the snag lengthens the recorded path, so it speeds up through the snag. The gap is
measured along the trajectory, as in the thesis.

**Snag point model.** The tether is a taut string from the winch (the robot
centre) to the leader. When the straight line between them would pass through
the wall block inside the corner, the string wraps the inner vertex (the snag
point): ``l_m`` is then the length of both segments and ``theta_m`` the
direction of the first. For one convex corner the taut string is the shortest
path, so it wraps exactly when the straight line is blocked. The estimated tip
is then off the leader's path: the tracked path is distorted (Fig. 4.17). By
geometry the first snag needs ``g_F > w (1 + pi/4) = 1.785 w`` (symmetric
positions; the thesis: "approximately 1.75 m").

**Limits (Sec. 4.5.4).** ``d_col`` is the least distance from the robot centre to
a wall over the run, normalised by ``w``; the thesis's fit (4.6) is
``g_F = -0.664 d_col^2 - 1.4 d_col + 2.565`` and a vehicle of bounding-circle
radius ``r_col`` (half its length, A18) does not collide while ``d_col >= r_col``
(4.7-4.8); no snagging while ``g_F < 1.75 w`` (4.9). :func:`snag_limits` fits
the same quadratic to simulated runs.

**Detection and compensation (Sec. 4.5.5).** The detection feature is the
change of ``beta_path``, the direction between neighbouring recorded points: a
change above ``beta_limit`` = 0.4 rad (4.13, read as an angle, A18) marks a snag
or an unsnag (they alternate). The rates per leader distance of
``theta_m``, ``l_m`` and ``beta_path`` (4.10-4.12) are returned for plotting.
The thesis gives no compensation law; the project's (stated in
``docs/tether_modes.md``): points recorded while snagged are not used; the robot
keeps to the path recorded before the snag (which already holds the leader's
turn: the snag starts only after the leader has left the arc), advancing at the
speed it had, and stops at its end if the tether has not come free; after the
unsnag the newest valid tip is joined by a straight segment. It works only when
the leader's own turns are gentler than the kink (a person who pivots on the
spot would trigger it), as the thesis notes.

Examples
--------
>>> run = simulate_snag(SnagScenario(gap=1.0))
>>> bool(run.snagged.any()), round(run.d_col, 3)
(False, 0.5)
>>> run = simulate_snag(SnagScenario(gap=2.5))
>>> bool(run.snagged.any()), run.d_col < 0.2
(True, True)
"""

from __future__ import annotations

import math
from bisect import bisect_left
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.params import Param, check_size, declared, param
from designlab.results import Result, Status
from designlab.validation import real_array

__all__ = [
    "SNAG_FIT",
    "SnagRun",
    "SnagScenario",
    "SnagStatus",
    "corridor_leader",
    "first_snag_gap",
    "simulate_snag",
    "snag_limits",
    "string",
    "thesis_gap_limits",
    "wall_distance",
]

#: The arguments of :func:`thesis_gap_limits` (declared once, as the scenario's fields).
SNAG_WIDTH = Param("w", "m", "corridor width", gt=0, le=20, name="width")
SNAG_VEHICLE = Param("L_v", "m", "vehicle length", gt=0, le=10, name="vehicle_length")
#: The bounding-circle radius of :func:`snag_limits`, in corridor widths (the fit's range).
SNAG_RADIUS = Param("r_col/w", "", "bounding-circle radius over the width", ge=0, le=0.5,
                    name="r_col")  # fmt: skip

#: The thesis's fit (4.6), g_F = a d_col^2 + b d_col + c, normalised by w.
SNAG_FIT = (-0.664, -1.4, 2.565)


class SnagStatus(Status):
    """Status of a snagging run: ``OK`` (no wall reached), ``COLLISION`` (the vehicle's
    bounding circle reached a wall)."""

    OK = "ok"
    COLLISION = "collision"


@declared
@dataclass(frozen=True)
class SnagScenario:
    """The corridor-corner kinematic simulation of Allan 2015 Sec. 4.5 (Table 4.1).

    The straight lengths are not given in the thesis (A18); ``approach`` and
    ``exit`` are the project's.

    Examples
    --------
    >>> SnagScenario().gap, SnagScenario().width
    (2.0, 1.0)
    """

    width: float = param("w", "m", doc="corridor width (Table 4.1)", gt=0, le=20, default=1.0)
    gap: float = param(
        "g_F",
        "m",
        doc="following gap along the trajectory (Table 4.1: 2-5 m)",
        gt=0,
        le=50,
        default=2.0,
    )
    speed: float = param("v_F", "m/s", doc="leader speed (Table 4.1)", gt=0, le=5, default=0.4)
    approach: float = param(
        "L_1",
        "m",
        doc="leader's straight walk before the turn (not in the thesis)",
        ge=0,
        le=200,
        default=7.0,
    )
    exit: float = param(
        "L_2",
        "m",
        doc="leader's straight walk after the turn (not in the thesis)",
        gt=0,
        le=200,
        default=10.0,
    )
    step: float = param(
        "Delta s", "m", doc="follower algorithm step size (Table 4.1)", gt=0, le=1, default=0.005
    )
    sample_time: float = param(
        "dt", "s", doc="simulation time step (Table 4.1)", gt=0, le=1, default=0.005
    )
    vehicle_length: float = param(
        "L_v", "m", doc="vehicle length; r_col is half of it (Sec. 4.5.4)", gt=0, le=10, default=0.4
    )
    beta_limit: float = param(
        "beta_limit",
        "rad",
        doc="detection threshold on the change of beta_path (4.13)",
        gt=0,
        le=math.pi,
        default=0.4,
    )
    detect_points: int = param(
        None,
        "",
        doc="recorded steps per chord of the beta_path detector (1: neighbouring points)",
        kind="integer",
        ge=1,
        le=1000,
        default=4,
    )
    compensate: bool = param(
        kind="flag", doc="apply the snag compensation (Sec. 4.5.5)", default=False
    )
    follower: str = param(
        doc=(
            "the robot's advance along the recorded path: 'constant_speed' (Table 4.1's target "
            "following speed v_F, the thesis's follower) or 'gap' (ours: it keeps g_F behind the "
            "newest recorded point)"
        ),
        kind="choice",
        choices=("constant_speed", "gap"),
        default="constant_speed",
    )
    winch_offset: float = param(
        "e_w",
        "m",
        doc=(
            "the winch (the tether's robot end) along the robot's heading from its centre, "
            "negative behind it (A7: not given; zero in the thesis's code)"
        ),
        ge=-5,
        le=5,
        default=0.0,
    )
    tether_height: float = param(
        "h",
        "m",
        doc=(
            "height of the tether's leader end above the winch; the measured l_m is then the "
            "3-D string length (A7: the thesis ignores it; 0: planar). The estimate is then at "
            "least h from the robot, so near the stopped leader at the run's end it wanders: "
            "d_col may come from there at small gaps"
        ),
        ge=0,
        le=5,
        default=0.0,
    )
    max_speed: float | None = param(
        "v_max",
        "m/s",
        doc="fastest advance of the gap-keeping robot along the recorded path (None: no limit)",
        gt=0,
        le=50,
        optional=True,
        none="unlimited: the robot keeps the gap exactly",
        default=None,
    )

    @property
    def collision_radius(self) -> float:
        """r_col in m: half the vehicle length (A18)."""
        return 0.5 * self.vehicle_length


def corridor_leader(sc: SnagScenario, s: NDArray[np.float64]) -> NDArray[np.float64]:
    """Leader positions at path distances ``s`` (inner vertex at the origin, leg 1 along +x).

    Parameters
    ----------
    sc
        The scenario.
    s
        Path distances from the leader's start in m (clipped to the path).

    Examples
    --------
    >>> corridor_leader(SnagScenario(), np.array([0.0, 7.0])).round(6).tolist()
    [[-7.0, -0.5], [0.0, -0.5]]
    """
    if not isinstance(sc, SnagScenario):
        raise InvalidParameterError("sc", sc, "must be a SnagScenario")
    s = np.atleast_1d(real_array("s", s, "m"))
    if s.ndim != 1 or (s < 0).any():
        raise InvalidParameterError("s", s, "must be path distances >= 0 (one axis)", "m")
    r, a = 0.5 * sc.width, sc.approach
    arc = 0.5 * math.pi * r
    s = np.clip(s, None, a + arc + sc.exit)
    out = np.empty((len(s), 2))
    leg1, on_arc, leg2 = s <= a, (s > a) & (s <= a + arc), s > a + arc
    out[leg1] = np.column_stack([s[leg1] - a, np.full(leg1.sum(), -r)])
    ang = -0.5 * math.pi + (s[on_arc] - a) / r
    out[on_arc] = np.column_stack([r * np.cos(ang), r * np.sin(ang)])
    out[leg2] = np.column_stack([np.full(leg2.sum(), r), s[leg2] - a - arc])
    return out


def string(px: float, py: float, lx: float, ly: float) -> tuple[float, float, bool]:
    """Taut tether from the robot to the leader around the inner vertex (the origin).

    The wall block inside the corner is ``x < 0, y > 0``. Returns the total
    length, the direction of the first segment (rad) and whether the string
    wraps the vertex.

    Parameters
    ----------
    px, py
        Winch (robot centre) in m.
    lx, ly
        Leader (tether tip) in m.

    Examples
    --------
    >>> [round(v, 6) for v in string(-1.0, -0.5, 0.5, 1.0)[:2]], string(-1.0, -0.5, 0.5, 1.0)[2]
    ([2.236068, 0.463648], True)
    """
    for name, v in (("px", px), ("py", py), ("lx", lx), ("ly", ly)):
        if (
            isinstance(v, (bool, np.bool_))
            or not isinstance(v, (int, float, np.number))
            or (not math.isfinite(v))
        ):
            raise InvalidParameterError(name, v, "must be a finite number", "m")
    return _string(px, py, lx, ly)


def _string(px: float, py: float, lx: float, ly: float) -> tuple[float, float, bool]:
    dx, dy = lx - px, ly - py
    lo, hi = 0.0, 1.0
    for p, d, sign in ((px, dx, -1.0), (py, dy, 1.0)):  # x(t) < 0 and y(t) > 0
        # sign * (p + t d) > 0
        if d == 0.0:
            if not sign * p > 0.0:
                lo, hi = 1.0, 0.0
        elif sign * d > 0.0:
            lo = max(lo, -p / d)
        else:
            hi = min(hi, -p / d)
    if hi - lo > 1e-12:
        return math.hypot(px, py) + math.hypot(lx, ly), math.atan2(-py, -px), True
    return math.hypot(dx, dy), math.atan2(dy, dx), False


def wall_distance(
    x: NDArray[np.float64], y: NDArray[np.float64], width: float
) -> NDArray[np.float64]:
    """Signed distance (m) from points to the nearest corridor wall (negative: beyond a wall).

    Parameters
    ----------
    x, y
        Points in m (inner vertex at the origin, leg 1 along +x, leg 2 along +y).
    width
        Corridor width in m.

    Examples
    --------
    >>> wall_distance(np.array([-3.0, 0.5, 0.5]), np.array([-0.5, 3.0, -0.5]), 1.0).tolist()
    [0.5, 0.5, 0.5]
    """
    x, y, width = real_array("x", x, "m"), real_array("y", y, "m"), SNAG_WIDTH.check(width)
    # inner wall block x < 0, y > 0: distance to the quadrant (negative inside)
    outside = np.hypot(np.maximum(x, 0.0), np.minimum(y, 0.0))
    inner = np.where((x < 0) & (y > 0), -np.minimum(-x, y), outside)
    outer = np.minimum(y + width, width - x)  # the outer walls y = -w and x = w
    return np.minimum(inner, outer)


@dataclass(frozen=True, eq=False)
class SnagRun(Result):
    """One corridor-corner run (arrays per time step unless stated).

    Attributes
    ----------
    scenario
        What was simulated.
    t
        Time in s.
    leader_s
        Leader path distance s_L in m.
    leader_xy, robot_xy
        Positions in m, (N, 2).
    tether_length, tether_angle
        Measured l_m (m) and theta_m (rad, relative to the robot heading).
    snagged
        The string wraps the vertex.
    tracked_xy
        The recorded (estimated tip) path in m, (M, 2).
    tracked_s_leader : numpy.ndarray
        Leader path distance s_L in m when each point of ``tracked_xy`` was recorded, (M,).
    beta_change
        |change of beta_path| at each recorded point (rad), (M,); 0 for the first two.
    detections
        Leader distances s_L (m) where the detector flagged a snag or an unsnag.
    d_col
        Least robot-centre distance to a wall over the run, normalised by w.
    status
        ``collision`` if ``d_col`` < r_col / w.
    warnings
        What a user should know.
    """

    scenario: SnagScenario
    t: NDArray[np.float64]
    leader_s: NDArray[np.float64]
    leader_xy: NDArray[np.float64]
    robot_xy: NDArray[np.float64]
    tether_length: NDArray[np.float64]
    tether_angle: NDArray[np.float64]
    snagged: NDArray[np.bool_]
    tracked_xy: NDArray[np.float64]
    tracked_s_leader: NDArray[np.float64]
    beta_change: NDArray[np.float64]
    detections: tuple[float, ...]
    d_col: float
    status: SnagStatus = SnagStatus.OK
    warnings: tuple[str, ...] = ()

    @property
    def snag_span(self) -> tuple[float, float] | None:
        """Leader distances (m) where the string first wraps and last comes free (None: never)."""
        idx = np.flatnonzero(self.snagged)
        if len(idx) == 0:
            return None
        return float(self.leader_s[idx[0]]), float(self.leader_s[min(idx[-1] + 1, len(self.t) - 1)])

    @property
    def tracked_s(self) -> NDArray[np.float64]:
        """Distance (m) along the recorded (estimated) leader path at each recorded point.

        The follower knows the leader only through this path, and the features
        (4.10-4.12) are computed on it, so it is the natural axis of Figs. 4.19-4.21.
        It starts at the first point recorded at t = 0, which is the leader's start.
        """
        xy = self.tracked_xy
        return np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))])

    @property
    def snag_span_recorded(self) -> tuple[float, float] | None:
        """:attr:`snag_span` on the recorded-path axis (:attr:`tracked_s`), m (None: never)."""
        span = self.snag_span
        if span is None:
            return None
        start = float(np.interp(span[0], self.tracked_s_leader, self.tracked_s))
        # the release without the tip's jump back to the leader: the last point recorded
        # while the string was wrapped (the jump is one long segment, not path walked)
        before = np.flatnonzero(self.tracked_s_leader < span[1])
        end = float(self.tracked_s[before[-1]]) if len(before) else start
        return start, max(start, end)

    def feature_rates(self) -> pd.DataFrame:
        """Eqs. 4.10-4.12 per recorded point: d theta/ds_L, dL/ds_L, d beta_path/ds_L."""
        k = np.searchsorted(self.leader_s, self.tracked_s_leader).clip(0, len(self.t) - 1)
        ds = np.diff(self.tracked_s_leader, prepend=np.nan)
        with np.errstate(invalid="ignore", divide="ignore"):
            return pd.DataFrame(
                {
                    "s_leader_m": self.tracked_s_leader,
                    "dtheta_ds_rad_per_m": np.diff(self.tether_angle[k], prepend=np.nan) / ds,
                    "dl_ds": np.diff(self.tether_length[k], prepend=np.nan) / ds,
                    "dbeta_ds_rad_per_m": self.beta_change / ds,
                }
            )


class _Tracker:
    """The recorded tip path, its detector and the robot's place on it."""

    def __init__(self, sc: SnagScenario, prefill: NDArray[np.float64]) -> None:
        self.sc = sc
        self.xs, self.ys = prefill[:, 0].tolist(), prefill[:, 1].tolist()
        self.s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(prefill, axis=0).T))]).tolist()
        self.s_leader = [math.nan] * len(self.xs)
        self.beta = [0.0] * len(self.xs)
        self.raw = list(zip(self.xs, self.ys, strict=True))
        self.quiet = 0
        self.detections: list[float] = []
        self.snag_flag = False
        self.valid_end = len(self.xs)  # compensation: the valid path ends here while snagged

    def observe(self, ex: float, ey: float, s_leader: float) -> None:
        """Record an estimated tip (when ``step`` from the last) and run the detector."""
        rx, ry = self.raw[-1]
        if math.hypot(ex - rx, ey - ry) < self.sc.step:
            return
        self.raw.append((ex, ey))
        change = self._kink()
        self.quiet -= 1
        if abs(change) > self.sc.beta_limit and self.quiet <= 0:
            self.detections.append(s_leader)
            self.snag_flag = not self.snag_flag
            self.quiet = 2 * self.sc.detect_points
            if self.snag_flag:
                self.valid_end = len(self.xs) - self.sc.detect_points
        if self.sc.compensate and self.snag_flag:
            return
        self._append(ex, ey, s_leader, change)

    def _kink(self) -> float:
        """Change of beta_path at the newest point, between chords of ``detect_points`` steps."""
        n = self.sc.detect_points
        r = self.raw
        if len(r) < 2 * n + 1:
            return 0.0
        (ax, ay), (bx, by), (cx, cy) = r[-1 - 2 * n], r[-1 - n], r[-1]
        d = math.atan2(cy - by, cx - bx) - math.atan2(by - ay, bx - ax)
        return math.atan2(math.sin(d), math.cos(d))

    def _append(self, ex: float, ey: float, s_leader: float, change: float) -> None:
        self.s.append(self.s[-1] + math.hypot(ex - self.xs[-1], ey - self.ys[-1]))
        self.xs.append(ex)
        self.ys.append(ey)
        self.s_leader.append(s_leader)
        self.beta.append(abs(change))

    def point_at(self, s: float) -> tuple[float, float, float]:
        """Position and heading on the recorded path at distance ``s``."""
        j = min(max(bisect_left(self.s, s), 1), len(self.s) - 1)
        s0, s1 = self.s[j - 1], self.s[j]
        f = 0.0 if s1 <= s0 else min(max((s - s0) / (s1 - s0), 0.0), 1.0)
        x0, y0, x1, y1 = self.xs[j - 1], self.ys[j - 1], self.xs[j], self.ys[j]
        return x0 + f * (x1 - x0), y0 + f * (y1 - y0), math.atan2(y1 - y0, x1 - x0)


#: Weight of the newest step in the robot's speed estimate (about 1 s of steps at 5 ms).
_RATE_FILTER = 0.005


def _prefill(sc: SnagScenario) -> NDArray[np.float64]:
    """The straight lead-in the leader walked (and the follower recorded) before t = 0."""
    n = math.ceil((sc.gap + 1.0) / sc.step) + 1
    x = -sc.approach - sc.step * np.arange(n - 1, -1, -1)
    return np.column_stack([x, np.full(n, -0.5 * sc.width)])


def _steps(sc: SnagScenario) -> int:
    total = sc.approach + 0.25 * math.pi * sc.width + sc.exit + sc.gap + 2.0
    if sc.follower == "constant_speed":  # the snag lengthens the path the robot drives at v_F
        total += 2.0 * sc.gap
    n = math.floor(total / sc.speed / sc.sample_time) + 1
    check_size("SnagScenario", sc, 12.0 * (n + total / sc.step), what=f"{n} steps")
    return n


def simulate_snag(scenario: SnagScenario) -> SnagRun:
    """Simulate the follower through the corridor corner (Allan 2015 Sec. 4.5).

    The leader walks until the robot, ``gap`` behind, has also covered the exit
    straight.

    Parameters
    ----------
    scenario
        The corridor, gap, speeds and detector (:class:`SnagScenario`).

    Returns
    -------
    SnagRun
    """
    sc = scenario
    if not isinstance(sc, SnagScenario):
        raise InvalidParameterError("scenario", sc, "a SnagScenario")
    n = _steps(sc)
    s_lead = sc.speed * sc.sample_time * np.arange(n)
    leader = corridor_leader(sc, s_lead)
    track = _Tracker(sc, _prefill(sc))
    out = np.empty((n, 5))
    snag = np.zeros(n, dtype=bool)
    s_robot = track.s[-1] - sc.gap
    rate = sc.speed * sc.sample_time
    for k in range(n):
        x, y, g = track.point_at(s_robot)
        wx, wy = x + sc.winch_offset * math.cos(g), y + sc.winch_offset * math.sin(g)
        lm, direction, snag[k] = _string(wx, wy, leader[k, 0], leader[k, 1])
        if sc.tether_height:
            lm = math.hypot(lm, sc.tether_height)  # a vertical edge: the unfolded 3-D length
        out[k] = (x, y, g, lm, math.atan2(math.sin(direction - g), math.cos(direction - g)))
        track.observe(
            wx + lm * math.cos(direction), wy + lm * math.sin(direction), float(s_lead[k])
        )
        if sc.compensate and track.snag_flag:
            s_robot = min(s_robot + rate, track.s[track.valid_end - 1])
        elif sc.follower == "constant_speed":  # v_F along the path, never past its newest point
            s_robot = min(s_robot + sc.speed * sc.sample_time, track.s[-1])
        else:
            new = max(track.s[-1] - sc.gap, s_robot)
            if sc.max_speed is not None:
                new = min(new, s_robot + sc.max_speed * sc.sample_time)
            rate += _RATE_FILTER * (new - s_robot - rate)  # the robot's recent speed x dt
            s_robot = new
    return _result(sc, s_lead, leader, out, snag, track)


def _result(
    sc: SnagScenario,
    s_lead: NDArray[np.float64],
    leader: NDArray[np.float64],
    out: NDArray[np.float64],
    snag: NDArray[np.bool_],
    track: _Tracker,
) -> SnagRun:
    d_col = float(wall_distance(out[:, 0], out[:, 1], sc.width).min() / sc.width)
    collided = d_col < sc.collision_radius / sc.width
    m = len(_prefill(sc))
    warns = []
    if collided:
        warns.append(
            f"the vehicle reaches a wall: d_col = {d_col:.3f} w "
            f"< r_col = {sc.collision_radius / sc.width:.3f} w"
        )
    return SnagRun(
        scenario=sc,
        t=sc.sample_time * np.arange(len(s_lead)),
        leader_s=s_lead,
        leader_xy=leader,
        robot_xy=out[:, :2].copy(),
        tether_length=out[:, 3].copy(),
        tether_angle=out[:, 4].copy(),
        snagged=snag,
        tracked_xy=np.column_stack([track.xs[m:], track.ys[m:]]),
        tracked_s_leader=np.array(track.s_leader[m:]),
        beta_change=np.array(track.beta[m:]),
        detections=tuple(track.detections),
        d_col=d_col,
        status=SnagStatus.COLLISION if collided else SnagStatus.OK,
        warnings=tuple(warns),
    )


def first_snag_gap(width: float = 1.0) -> float:
    """The least gap (m) at which the tether can touch the inner vertex: ``w (1 + pi/4)``.

    With the robot and the leader symmetric about the corner's bisector, the
    chord between them touches the vertex when each is ``w/2`` from the arc.

    Parameters
    ----------
    width
        Corridor width in m.

    Examples
    --------
    >>> round(first_snag_gap(1.0), 4)
    1.7854
    >>> first_snag_gap(-1)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: width = -1 m is not allowed: must be a finite ...
    """
    return SNAG_WIDTH.check(width) * (1.0 + 0.25 * math.pi)


def thesis_gap_limits(width: float, vehicle_length: float) -> dict[str, float]:
    """The thesis's design limits on the following gap for a corridor and a vehicle (m).

    ``no_snag`` is eq. 4.9 (``g_F < 1.75 w``); ``no_collision`` is eq. 4.8 with
    ``r_col`` half the vehicle length (A18): ``g_F <= w (-0.664 r^2 - 1.4 r + 2.565)``
    with ``r = r_col / w``. Valid only inside the fit's range (``r_col / w`` in 0 to 0.5).

    Parameters
    ----------
    width
        Corridor width w in m (> 0).
    vehicle_length
        Vehicle length in m (> 0, at most the width).

    Examples
    --------
    >>> {k: round(v, 4) for k, v in thesis_gap_limits(1.0, 0.4).items()}
    {'no_snag': 1.75, 'no_collision': 2.2584}
    """
    w = SNAG_WIDTH.check(width)
    length = SNAG_VEHICLE.check(vehicle_length)
    r = 0.5 * length / w
    if r > 0.5:
        raise InvalidParameterError(
            "vehicle_length", vehicle_length, f"at most the corridor width ({w:g} m)", "m"
        )
    a, b, c = SNAG_FIT
    return {"no_snag": 1.75 * w, "no_collision": w * (a * r * r + b * r + c)}


def snag_limits(
    d_col: NDArray[np.float64], gaps: NDArray[np.float64], r_col: float
) -> dict[str, float]:
    """Fit (4.6) ``g_F = a d_col^2 + b d_col + c`` and evaluate the collision limit (4.8).

    All in units of ``w``. Least squares (numpy) over the runs given (use the
    runs that snagged and stayed inside the corridor).

    Parameters
    ----------
    d_col
        Least wall distance of each run (/w).
    gaps
        The runs' gaps (/w).
    r_col
        Bounding-circle radius (/w).

    Returns
    -------
    dict
        ``a, b, c``, ``gap_limit`` (4.8: the largest collision-free gap) and
        ``rms`` of the fit (/w).

    Examples
    --------
    >>> d = np.linspace(0.0, 0.5, 6)
    >>> fit = snag_limits(d, -0.664 * d**2 - 1.4 * d + 2.565, 0.2)
    >>> round(fit["a"], 6), round(fit["gap_limit"], 4)
    (-0.664, 2.2584)
    """
    d_col, gaps = real_array("d_col", d_col), real_array("gaps", gaps)
    if d_col.ndim != 1 or d_col.shape != gaps.shape or d_col.size < 3:
        raise InvalidParameterError(
            "d_col", d_col, f"must be one value per gap ({np.shape(gaps)}), at least 3 runs"
        )
    if np.unique(d_col).size < 3:
        raise InvalidParameterError(
            "d_col", d_col, "must hold at least 3 distinct wall distances to fit a quadratic"
        )
    r_col = SNAG_RADIUS.check(r_col)
    a, b, c = np.polyfit(d_col, gaps, 2)
    resid = np.polyval([a, b, c], d_col) - gaps
    return {
        "a": float(a),
        "b": float(b),
        "c": float(c),
        "gap_limit": float(a * r_col**2 + b * r_col + c),
        "rms": float(np.sqrt(np.mean(resid**2))),
    }
