"""Odometry with wheel slip, and the marker-to-tether-tip offset (Allan 2015 Sec. 2.3, 3.4).

Allan's robot knows its pose only by dead reckoning from the measured wheel
speeds (eqs. 2.8-2.11, App. C ``dead_reckon``), and FTL and FTL-CD record the
tether tip in that odometry frame. The thesis names two error sources of its
motion-capture results (Sec. 3.4): wheel slip on the floor and the offset
between the tether tip and the waist marker. :func:`simulate_with_errors`
adds both to the closed loop:

* :class:`WheelSlip`: each wheel's ground speed is ``r omega_i (1 - s_i -
  n_i)``, a constant slip ratio ``s_i`` plus white noise ``n_i`` per control
  period. The true pose moves on the exact arc of the ground speeds; the
  odometry moves on the exact arc of the wheel speeds (as coded,
  ``dead_reckon``). The tether sensor measures the true geometry; the law,
  its path buffer and its targets live in the odometry frame (the leader is
  handed to the compiled step transformed into that frame, which keeps every
  relative quantity exact).
* :class:`MarkerOffset`: the walker's measured point (the waist marker)
  walks the path; the tether tip sits at ``(forward, left)`` from it in the
  walker's frame (heading = the path tangent). The robot follows the tip;
  the deviation is measured against the marker, as the motion capture did.

Pseudo-Joystick uses only the tether reading, so slip moves its path but not
its law; FTL and FTL-CD drive to recorded points, so an odometry drift
shifts where they go (``docs/following.md``, "Odometry, slip and the marker").

Examples
--------
>>> from designlab.following.tether import FollowTheLeader, straight_line
>>> res = simulate_with_errors(FollowTheLeader(), straight_line(6.0),
...                            slip=WheelSlip(left_slip=0.02))
>>> bool(res.odometry_drift[-1] > 0.01)   # dead reckoning drifts from the true pose
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.following.tether.buffer import MemberBuffers, NoTarget
from designlab.following.tether.laws.base import TetherController, checked_law
from designlab.following.tether.model import sensor_step, step_compiled, tip_step
from designlab.following.tether.parameters import (
    LEADER_SPEED,
    SEED,
    SETTLE_TIME,
    FollowerRobot,
)
from designlab.following.tether.paths import LeaderPath, make_path
from designlab.following.tether.simulate import FollowerRun, FollowerStatus
from designlab.params import check_size, declared, param
from designlab.validation import ParamsMixin

__all__ = [
    "ErrorRun",
    "MarkerOffset",
    "WheelSlip",
    "arc_step",
    "ground_motion",
    "marker_to_tip",
    "simulate_with_errors",
]

#: float64 values a run keeps per control period (for the size check).
_VALUES_PER_STEP = 24


@declared
@dataclass(frozen=True)
class WheelSlip(ParamsMixin):
    """Longitudinal wheel slip: ground speed ``r omega (1 - s - n)`` per wheel.

    ``left_slip``/``right_slip`` are constant slip ratios (0.02: the wheel
    covers 2 % less ground than it turns); ``noise_std`` is the standard
    deviation of white slip noise per control period, drawn independently
    for both wheels.

    Examples
    --------
    >>> WheelSlip(left_slip=0.02).left_slip
    0.02
    >>> WheelSlip(left_slip=1.5)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: WheelSlip.left_slip = 1.5 is not allowed: ...
    """

    left_slip: float = param(
        "s_L",
        "",
        doc="slip ratio of the left wheel",
        ge=-0.5,
        le=0.5,
        typical=(0, 0.05),
        default=0.0,
    )
    right_slip: float = param(
        "s_R",
        "",
        doc="slip ratio of the right wheel",
        ge=-0.5,
        le=0.5,
        typical=(0, 0.05),
        default=0.0,
    )
    noise_std: float = param(
        "sigma_s",
        "",
        doc="standard deviation of white slip noise per period and wheel",
        ge=0,
        le=0.5,
        typical=(0, 0.05),
        default=0.0,
    )


@declared
@dataclass(frozen=True)
class MarkerOffset(ParamsMixin):
    """Where the tether tip sits relative to the walker's measured point (the waist marker).

    In the walker's frame: ``forward`` along the path tangent, ``left`` to
    its left (a tether clipped at the side of a belt: ``left`` about the
    waist half-width).

    Examples
    --------
    >>> MarkerOffset(left=0.15).left
    0.15
    """

    forward: float = param(
        "m_f", "m", doc="tip ahead of the marker", ge=-2, le=2, typical=(-0.2, 0.2), default=0.0
    )
    left: float = param(
        "m_l", "m", doc="tip left of the marker", ge=-2, le=2, typical=(-0.2, 0.2), default=0.0
    )


@dataclass(frozen=True, eq=False)
class ErrorRun:
    """A run with odometry, slip and the marker offset.

    Attributes
    ----------
    run
        The :class:`FollowerRun`: ``leader_xy`` is the **marker** path (what
        the deviation is measured against), ``robot_xy`` the true robot centre.
    tip_xy
        The tether tip, (N, 2) m.
    odometry_xy, odometry_heading
        The robot's dead-reckoned pose, (N, 2) m and (N,) rad.
    slip, marker
        The error models used (``None``: off).
    """

    run: FollowerRun
    tip_xy: NDArray[np.float64]
    odometry_xy: NDArray[np.float64]
    odometry_heading: NDArray[np.float64]
    slip: WheelSlip | None
    marker: MarkerOffset | None

    @property
    def odometry_drift(self) -> NDArray[np.float64]:
        """Distance between the true and the dead-reckoned robot position, (N,) m."""
        return np.hypot(*(self.run.robot_xy - self.odometry_xy).T)


def arc_step(pose: tuple[Any, Any, Any], v: Any, om: Any, dt: float) -> tuple[Any, Any, Any]:
    """Exact arc of constant (V, Omega) over ``dt`` (App. C ``dead_reckon``).

    Written as the chord ``V dt sin(h)/h`` along ``Gamma + h``, ``h = Omega dt / 2``
    (the form of the compiled step, so a run without slip follows it to rounding).

    Parameters
    ----------
    pose
        ``(x, y, Gamma)`` in m, m, rad (floats or arrays).
    v, om
        Forward speed V (m/s) and turn rate Omega (rad/s).
    dt
        Period in s.

    Examples
    --------
    >>> [round(float(v), 12) for v in arc_step((0.0, 0.0, 0.0), 1.0, 0.0, 0.5)]
    [0.5, 0.0, 0.0]
    """
    x, y, g = pose
    h = 0.5 * om * dt
    hs = np.maximum(np.abs(h), 1e-300)
    chord = v * dt * (np.sin(hs) / hs)
    return x + chord * np.cos(g + h), y + chord * np.sin(g + h), g + 2.0 * h


def ground_motion(v: Any, om: Any, slip_left: Any, slip_right: Any, track: float) -> tuple:
    """(V, Omega) on the ground when the wheels slip by ``s_L``, ``s_R`` (eq. 2.6).

    The rims move at ``V -+ b Omega / 2``; the ground under each wheel at the
    rim speed times ``1 - s``.

    Parameters
    ----------
    v, om
        Commanded (and odometry) V in m/s and Omega in rad/s.
    slip_left, slip_right
        Slip ratios of the wheels (this period's, noise included).
    track
        Wheel track b in m.

    Examples
    --------
    >>> [round(float(x), 12) for x in ground_motion(1.0, 0.0, 0.1, 0.0, 0.5)]
    [0.95, 0.2]
    """
    rim_l, rim_r = v - 0.5 * track * om, v + 0.5 * track * om
    lost_l, lost_r = rim_l * slip_left, rim_r * slip_right
    return v - 0.5 * (lost_l + lost_r), om - (lost_r - lost_l) / track


def marker_to_tip(marker_xy: NDArray[np.float64], offset: MarkerOffset) -> NDArray[np.float64]:
    """Tether-tip positions from marker positions: ``marker + R(psi) (forward, left)``.

    ``psi`` is the direction of motion (the last one is held while the walker
    stands).

    Parameters
    ----------
    marker_xy
        Marker positions, (N, 2) m.
    offset
        The :class:`MarkerOffset`.
    """
    d = np.diff(marker_xy, axis=0)
    moving = np.hypot(d[:, 0], d[:, 1]) > 1e-12
    psi = np.arctan2(d[:, 1], d[:, 0])
    idx = np.maximum.accumulate(np.where(moving, np.arange(len(d)), 0))
    psi = psi[idx]
    psi = np.concatenate([psi[:1], psi])
    c, s = np.cos(psi), np.sin(psi)
    return marker_xy + np.column_stack(
        [c * offset.forward - s * offset.left, s * offset.forward + c * offset.left]
    )


def _to_frame(point: NDArray, true_pose: tuple, odo_pose: tuple) -> tuple[NDArray, NDArray]:
    """A world point as the robot sees it in its odometry frame (same relative geometry)."""
    xt, yt, gt = true_pose
    xo, yo, go = odo_pose
    if xt[0] == xo[0] and yt[0] == yo[0] and gt[0] == go[0]:
        return np.array([point[0]]), np.array([point[1]])
    dx, dy = point[0] - xt, point[1] - yt
    c, s = np.cos(gt), np.sin(gt)
    fx, fy = c * dx + s * dy, -s * dx + c * dy  # in the robot frame
    c, s = np.cos(go), np.sin(go)
    return xo + c * fx - s * fy, yo + s * fx + c * fy


@dataclass(frozen=True)
class _Setup:
    controller: TetherController
    path: LeaderPath
    speed: float
    robot: FollowerRobot
    slip: WheelSlip
    marker: MarkerOffset | None
    n: int
    seed: int | None


def _checked(controller: Any, path: Any, args: dict[str, Any]) -> _Setup:
    if checked_law(controller).stepwise:
        raise InvalidParameterError(
            "controller", controller.name, "a continuous law (not a stepwise mode)"
        )
    robot = FollowerRobot() if args["robot"] is None else args["robot"]
    for name, obj, cls in (
        ("robot", robot, (FollowerRobot,)),
        ("slip", args["slip"], (WheelSlip, type(None))),
        ("marker", args["marker"], (MarkerOffset, type(None))),
    ):
        if not isinstance(obj, cls):
            raise InvalidParameterError(name, type(obj).__name__, f"must be a {cls[0].__name__}")
    path = make_path(path)
    speed = LEADER_SPEED.check(args["speed"])
    duration = path.length / speed + SETTLE_TIME.check(args["settle_time"])
    n = math.floor(duration / robot.sample_time + 1e-9) + 1
    check_size("settle_time", duration, float(n) * _VALUES_PER_STEP, what=f"{n} periods")
    slip = args["slip"] if args["slip"] is not None else WheelSlip()
    return _Setup(controller, path, speed, robot, slip, args["marker"], n, SEED.check(args["seed"]))


def _finder(s: _Setup) -> Any:
    c = s.controller
    if not c.target_finder.records_path:
        return NoTarget(np.zeros(1))
    per = np.array([c.search_distance()])
    r = s.robot
    return MemberBuffers(
        c.target_finder,
        1,
        s.n,
        c.buffer_size - 1,  # type: ignore[attr-defined]
        c.min_step,  # type: ignore[attr-defined]
        np.zeros((0, 2)),
        per,
        sensor_step(True),
        tip_step(True),
        (r.winch_offset_x, r.winch_offset_y, r.tip_height),
    )


def _loop(s: _Setup, tip: NDArray, rng: np.random.Generator) -> dict[str, NDArray]:
    """The control periods: law in the odometry frame, true and odometry poses on arcs."""
    c, r = s.controller, s.robot
    law = type(c).law_function(c.law_key())
    step = step_compiled(law, c.target_finder.records_path, r.limited, not r.planar, r.noisy, True)
    dt = r.sample_time
    consts = (r.wheel_track, r.wheel_radius, dt, r.max_wheel_speed)
    consts += (r.max_wheel_acceleration * dt, r.winch_offset_x, r.winch_offset_y, r.tip_height)
    params = [np.array([v]) for v in c.law_values()]
    g0 = s.path.start_heading
    true = (
        np.array([tip[0, 0] - c.desired_length * math.cos(g0)]),
        np.array([tip[0, 1] - c.desired_length * math.sin(g0)]),
        np.array([g0]),
    )
    odo = true
    wl, wr = np.zeros(1), np.zeros(1)
    noise = rng.normal(0.0, 1.0, (4, s.n)) * [
        [r.length_noise_std],
        [r.angle_noise_std],
        [s.slip.noise_std],
        [s.slip.noise_std],
    ]
    find = _finder(s)
    out = np.zeros((s.n, 8))
    for k in range(s.n):
        tx, ty = _to_frame(tip[k], true, odo)
        nl, nth = noise[0, k : k + 1], noise[1, k : k + 1]
        jx, jy = find(k, *odo, tx, ty, nl, nth)
        _, _, _, v, om, wl, wr = step(*odo, tx, ty, jx, jy, wl, wr, nl, nth, *consts, *params)
        out[k] = [true[0][0], true[1][0], true[2][0], v[0], om[0], odo[0][0], odo[1][0], odo[2][0]]
        vt, omt = ground_motion(
            v, om, s.slip.left_slip + noise[2, k], s.slip.right_slip + noise[3, k], r.wheel_track
        )
        true = arc_step(true, vt, omt, dt)
        odo = arc_step(odo, v, om, dt)
    return {k: out[:, i] for i, k in enumerate(("x", "y", "g", "v", "om", "ox", "oy", "og"))}


def simulate_with_errors(
    controller: TetherController,
    path: LeaderPath | str | dict[str, Any],
    speed: float = LEADER_SPEED.default,
    robot: FollowerRobot | None = None,
    *,
    slip: WheelSlip | None = None,
    marker: MarkerOffset | None = None,
    settle_time: float = SETTLE_TIME.default,
    seed: int | None = SEED.default,
) -> ErrorRun:
    """Simulate a tether follower with dead reckoning, wheel slip and a marker offset.

    Without ``slip`` and ``marker`` the run is that of
    :func:`~designlab.following.tether.simulate` (to rounding: a test checks it).

    Parameters
    ----------
    controller
        A continuous tether law (PJ, FTL, FTL-CD, the side and front modes).
    path
        The marker's path (:class:`LeaderPath`, or a name/dict for :func:`make_path`).
    speed
        Walking speed in m/s.
    robot
        The robot (default :class:`FollowerRobot`).
    slip
        Wheel slip (:class:`WheelSlip`; ``None``: none).
    marker
        Tip offset from the measured marker (:class:`MarkerOffset`; ``None``: the same point).
    settle_time
        Time in s after the walker stops.
    seed
        Seed of the sensor and slip noise.

    Returns
    -------
    ErrorRun
    """
    s = _checked(
        controller,
        path,
        {
            "robot": robot,
            "slip": slip,
            "marker": marker,
            "speed": speed,
            "settle_time": settle_time,
            "seed": seed,
        },
    )
    marker_xy = s.path.position_at(s.speed * s.robot.sample_time * np.arange(s.n))
    tip = marker_xy if s.marker is None else marker_to_tip(marker_xy, s.marker)
    hist = _loop(s, tip, np.random.default_rng(s.seed))
    robot_xy = np.column_stack([hist["x"], hist["y"]])
    lm, th = sensor_step(True)(
        hist["x"],
        hist["y"],
        hist["g"],
        tip[:, 0],
        tip[:, 1],
        s.robot.winch_offset_x,
        s.robot.winch_offset_y,
        s.robot.tip_height,
    )
    finite = bool(np.all(np.isfinite(robot_xy)))
    run = FollowerRun(
        t=s.robot.sample_time * np.arange(s.n),
        leader_xy=marker_xy,
        robot_xy=robot_xy,
        heading=hist["g"],
        tether_length=np.asarray(lm, dtype=float).ravel(),
        tether_angle=np.asarray(th, dtype=float).ravel(),
        speed=hist["v"],
        turn_rate=hist["om"],
        controller=s.controller,
        robot=s.robot,
        path=s.path,
        speed_leader=s.speed,
        status=FollowerStatus.OK if finite else FollowerStatus.FAILED,
        warnings=() if finite else ("the state became non-finite",),
    )
    return ErrorRun(
        run,
        tip,
        np.column_stack([hist["ox"], hist["oy"]]),
        hist["og"],
        slip,
        marker,
    )
