"""Closed-loop simulation of the tether follower (Allan 2015 Sec. 2.3-2.4, App. C).

Each control period: the leader (the tether tip) moves along its path; the
sensor returns ``l_m`` and ``theta_m`` (plus noise); the controller computes
``(V, Omega)`` (FTL and FTL-CD first record the estimated tip in their path
buffer and pick a target on it); ``(V, Omega)`` becomes wheel speeds by
eq. (2.4), limited in speed and acceleration; the pose advances on the exact
arc (App. C ``dead_reckon``). The robot starts ``l_d`` behind the path start,
aligned with the initial tangent, at rest (``docs/following.md``).

:func:`simulate_batch` runs many gain sets of one law at once (numpy arrays
over the batch); :func:`simulate` is one run. With a noise-free planar sensor
the estimated tip equals the leader position, so every member of a batch
records the same buffer, which is then kept once.

Examples
--------
>>> from designlab.following.tether import FollowTheLeader, straight_line
>>> run = simulate(FollowTheLeader(), straight_line(10.0), speed=0.5, duration=15.0)
>>> round(float(run.tether_length[1000]), 6)         # l_d + v/K_V after the transient
1.5
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.following.tether.buffer import record_shared
from designlab.following.tether.closed_loop import Buffering, run_batch, run_single
from designlab.following.tether.laws.base import TetherController, checked_law
from designlab.following.tether.parameters import (
    DURATION,
    LEAD_IN,
    LEADER_SPEED,
    SEED,
    SETTLE_TIME,
    FollowerRobot,
)
from designlab.following.tether.paths import LeaderPath, make_path
from designlab.following.tether.stepwise import run_stepwise
from designlab.params import check_size
from designlab.results import Result, Status

__all__ = [
    "MAX_LEADER_SPEED",
    "FollowerBatch",
    "FollowerRun",
    "FollowerStatus",
    "simulate",
    "simulate_batch",
]

#: Fastest leader accepted (m/s): well above any walk (Allan 2015 uses 0.5 m/s).
MAX_LEADER_SPEED = LEADER_SPEED.le

#: Targets of the laws that keep the FTL path buffer of the compiled loop.

#: Arrays of float64 values a run keeps per member and control period (for the size check).
_VALUES_PER_STEP = 16


class FollowerStatus(Status):
    """Status of a tether-follower run, batch or its figures of merit.

    ``OK``: the run finished with a finite state. ``FAILED``: the state became
    non-finite (every member of a batch). ``PARTIAL``: some members of a batch
    failed. ``EMPTY``: the run's normal path deviation has no comparison range
    (App. A.6).
    """

    OK = "ok"
    FAILED = "failed"
    PARTIAL = "partial"
    EMPTY = "empty"


@dataclass(frozen=True, eq=False)
class FollowerRun(Result):
    """One simulated run of a tether follower.

    Attributes
    ----------
    t
        Time in s, shape (N,).
    leader_xy, robot_xy
        Leader (tether tip) and robot-centre positions in m, shape (N, 2).
    heading
        Robot heading Gamma in rad, shape (N,).
    tether_length, tether_angle
        Measured l_m (m) and theta_m (rad), shape (N,).
    speed, turn_rate
        Commanded V (m/s) and Omega (rad/s) after the wheel limits, shape (N,).
    controller, robot, path
        What was simulated; ``speed_leader`` is the leader speed in m/s.
    speed_leader
        Leader speed in m/s.
    status
        ``"ok"``, or what went wrong (e.g. the leader was lost).
    warnings
        What a user should know about the run.
    """

    t: NDArray[np.float64]
    leader_xy: NDArray[np.float64]
    robot_xy: NDArray[np.float64]
    heading: NDArray[np.float64]
    tether_length: NDArray[np.float64]
    tether_angle: NDArray[np.float64]
    speed: NDArray[np.float64]
    turn_rate: NDArray[np.float64]
    controller: TetherController
    robot: FollowerRobot
    path: LeaderPath
    speed_leader: float
    status: FollowerStatus = FollowerStatus.OK
    warnings: tuple[str, ...] = ()

    @property
    def tether_length_error(self) -> NDArray[np.float64]:
        """``l_m - l_d`` in m."""
        return self.tether_length - self.controller.desired_length

    def to_frame(self) -> pd.DataFrame:
        """Time histories with unit-carrying columns."""
        return pd.DataFrame(
            {
                "t_s": self.t,
                "leader_x_m": self.leader_xy[:, 0],
                "leader_y_m": self.leader_xy[:, 1],
                "robot_x_m": self.robot_xy[:, 0],
                "robot_y_m": self.robot_xy[:, 1],
                "heading_rad": self.heading,
                "tether_length_m": self.tether_length,
                "tether_angle_rad": self.tether_angle,
                "speed_m_per_s": self.speed,
                "turn_rate_rad_per_s": self.turn_rate,
            }
        )


@dataclass(frozen=True, eq=False)
class FollowerBatch(Result):
    """Runs of one law with many gain sets on one path; arrays are (B, N[, 2]).

    ``run(i)`` returns member ``i`` as a :class:`FollowerRun`.

    Attributes
    ----------
    t
        Times in s, (N,).
    leader_xy
        Leader positions in m, (N, 2).
    robot_xy
        Robot positions in m, (B, N, 2).
    heading
        Robot headings in rad, (B, N).
    tether_length
        Tether lengths in m, (B, N).
    tether_angle
        Tether angles in rad, (B, N).
    speed
        Robot forward speeds in m/s, (B, N).
    turn_rate
        Robot turn rates in rad/s, (B, N).
    controllers
        The B controllers.
    robot
        The robot model.
    path
        The leader's path.
    speed_leader
        Leader speed in m/s.
    member_status
        Status of each member run.
    status
        ``"ok"`` when every member is ``ok``, else the first other status.
    warnings
        What a user should know about the runs (lost leader, wheel limits).
    """

    t: NDArray[np.float64]
    leader_xy: NDArray[np.float64]
    robot_xy: NDArray[np.float64]
    heading: NDArray[np.float64]
    tether_length: NDArray[np.float64]
    tether_angle: NDArray[np.float64]
    speed: NDArray[np.float64]
    turn_rate: NDArray[np.float64]
    controllers: tuple[TetherController, ...]
    robot: FollowerRobot
    path: LeaderPath
    speed_leader: float
    member_status: tuple[FollowerStatus, ...]
    status: FollowerStatus = FollowerStatus.OK
    warnings: tuple[str, ...] = ()

    def __len__(self) -> int:
        return len(self.controllers)

    def run(self, i: int) -> FollowerRun:
        """Member ``i`` as a single run."""
        return FollowerRun(
            t=self.t,
            leader_xy=self.leader_xy,
            robot_xy=self.robot_xy[i],
            heading=self.heading[i],
            tether_length=self.tether_length[i],
            tether_angle=self.tether_angle[i],
            speed=self.speed[i],
            turn_rate=self.turn_rate[i],
            controller=self.controllers[i],
            robot=self.robot,
            path=self.path,
            speed_leader=self.speed_leader,
            status=self.member_status[i],
            warnings=tuple(w for w in self.warnings if w.startswith(f"member {i}:")),
        )

    def to_frame(self) -> pd.DataFrame:
        """One row per member: its gains, status and final tether length."""
        rows = []
        for i, c in enumerate(self.controllers):
            rows.append(
                {
                    "member": i,
                    **{f"{k}": v for k, v in c.gains.items()},
                    "desired_length_m": c.desired_length,
                    "status": self.member_status[i],
                    "final_tether_length_m": float(self.tether_length[i, -1]),
                }
            )
        return pd.DataFrame(rows)


@dataclass(frozen=True)
class _Request:
    """A checked simulation request (see :func:`simulate_batch`)."""

    controllers: tuple[TetherController, ...]
    path: LeaderPath
    speed: float
    robot: FollowerRobot
    duration: float
    lead_in: float
    initial_pose: tuple[float, float, float] | None
    seed: int | None

    @property
    def law(self) -> type[TetherController]:
        return type(self.controllers[0])


def _checked_controllers(controllers: Any) -> tuple[TetherController, ...]:
    if isinstance(controllers, (str, bytes)):
        raise InvalidParameterError("controllers", controllers, "a list of tether controllers")
    if not isinstance(controllers, Sequence):  # one law given alone (checked below)
        controllers = [controllers]
    controllers = tuple(controllers)
    if not controllers:
        raise InvalidParameterError("controllers", controllers, "at least one controller")
    cls = type(checked_law(controllers[0], "controllers"))
    for c in controllers:
        if type(c) is not cls:
            raise InvalidParameterError(
                "controllers", type(c).__name__, f"all of one law ({cls.__name__})"
            )
    if len({c.law_key() for c in controllers}) > 1:
        raise InvalidParameterError("controllers", "mixed law variants", "one variant per batch")
    buffers = (
        {(c.min_step, c.buffer_size) for c in controllers} if cls.target_finder.records_path else ()
    )  # type: ignore[attr-defined]
    if len(buffers) > 1:
        raise InvalidParameterError(
            "controllers", "different min_step/buffer_size", "one value per batch"
        )
    return controllers


def _checked_pose(initial_pose: Any) -> tuple[float, float, float] | None:
    if initial_pose is None:
        return None
    try:
        x0, y0, h0 = (float(v) for v in initial_pose)
    except (TypeError, ValueError):
        raise InvalidParameterError("initial_pose", initial_pose, "(x, y, heading)") from None
    if not all(math.isfinite(v) and abs(v) <= 1e6 for v in (x0, y0, h0)):
        raise InvalidParameterError(
            "initial_pose", initial_pose, "finite (x, y, heading) of magnitude <= 1e6"
        )
    return x0, y0, h0


def _checked_request(
    controllers: Any,
    path: Any,
    speed: float,
    robot: FollowerRobot | None,
    duration: float | None,
    settle_time: float,
    lead_in: float,
    initial_pose: Any,
    seed: int | None,
) -> _Request:
    """Validate every argument of :func:`simulate_batch` before anything is allocated."""
    ctrls = _checked_controllers(controllers)
    path = make_path(path)
    speed = LEADER_SPEED.check(speed)
    robot = FollowerRobot() if robot is None else robot
    if not isinstance(robot, FollowerRobot):
        raise InvalidParameterError("robot", robot, "a FollowerRobot")
    settle_time = SETTLE_TIME.check(settle_time)
    for c in ctrls:
        if c.desired_length <= 0.5 * robot.body_length:
            raise InvalidParameterError(
                f"{type(c).__name__}.desired_length",
                c.desired_length,
                f"must exceed half the robot length (FollowerRobot.body_length = "
                f"{robot.body_length:g} m): the tether tip would be inside the robot",
                "m",
            )
    if duration is None:
        walk = path.length / speed + settle_time
        duration = DURATION.check(walk, "duration (path length / speed + settle_time)")
    duration = DURATION.check(duration)
    n = math.floor(duration / robot.sample_time + 1e-9) + 1
    check_size(
        "duration",
        duration,
        float(n) * len(ctrls) * _VALUES_PER_STEP,
        what=f"{n} control periods of {len(ctrls)} member(s)",
    )
    return _Request(
        ctrls,
        path,
        speed,
        robot,
        duration,
        LEAD_IN.check(lead_in),
        _checked_pose(initial_pose),
        SEED.check(seed),
    )


def _start(req: _Request) -> tuple[NDArray, NDArray, NDArray]:
    """Initial poses: ``l_d`` behind the path start on its tangent (or ``initial_pose``).

    A mode with a ``start_pose(point, heading)`` method (side and front modes,
    ``docs/tether_modes.md``) places itself.
    """
    nb = len(req.controllers)
    if req.initial_pose is not None:
        return tuple(np.full(nb, v) for v in req.initial_pose)  # type: ignore[return-value]
    g0 = req.path.start_heading
    placed = [
        getattr(c, "start_pose", lambda *_: None)(req.path.points[0], g0) for c in req.controllers
    ]
    if all(p is not None for p in placed):
        return tuple(np.array(v, dtype=float) for v in zip(*placed, strict=True))  # type: ignore[return-value]
    u0 = np.array([math.cos(g0), math.sin(g0)])
    ld = np.array([c.desired_length for c in req.controllers])
    return req.path.points[0, 0] - ld * u0[0], req.path.points[0, 1] - ld * u0[1], np.full(nb, g0)


def _buffering(req: _Request, leader: NDArray) -> Buffering | None:
    """The path buffer of FTL/FTL-CD (``None`` for the other modes)."""
    if not req.law.target_finder.records_path:
        return None
    c0 = req.controllers[0]
    min_step, window = c0.min_step, c0.buffer_size - 1  # type: ignore[attr-defined]
    prefill = np.zeros((0, 2))
    if req.lead_in > 0:
        g0 = req.path.start_heading
        u0 = np.array([math.cos(g0), math.sin(g0)])
        m = math.floor(req.lead_in / min_step)
        prefill = req.path.points[0] - np.outer(np.arange(m, 0, -1) * min_step, u0)
    shared = None
    if not req.robot.noisy and req.robot.tip_height == 0.0:
        shared = record_shared(leader, min_step, prefill)
    return Buffering(window, min_step, prefill, shared)


def _member_status(
    req: _Request, hist: dict[str, NDArray]
) -> tuple[list[FollowerStatus], list[str]]:
    """Each member's status, and warnings on non-finite states and saturated wheels."""
    robot = req.robot
    finite = np.all(np.isfinite(hist["x"]) & np.isfinite(hist["y"]), axis=1) & np.all(
        np.isfinite(hist["l"]), axis=1
    )
    status, warns = [], []
    for i in range(len(req.controllers)):
        if not finite[i]:
            status.append(FollowerStatus.FAILED)
            warns.append(f"member {i}: the state became non-finite")
            continue
        status.append(FollowerStatus.OK)
        if robot.max_wheel_speed < math.inf:
            b, r = robot.wheel_track, robot.wheel_radius
            wsat = np.abs(hist["v"][i]) / r + 0.5 * b * np.abs(hist["om"][i]) / r >= (
                robot.max_wheel_speed * (1 - 1e-9)
            )
            if wsat.mean() > 0.05:
                warns.append(
                    f"member {i}: a wheel is at its speed limit "
                    f"{100 * wsat.mean():.0f} % of the time"
                )
    return status, warns


def _batch_result(req: _Request, leader: NDArray, hist: dict[str, NDArray]) -> FollowerBatch:
    member_status, warns = _member_status(req, hist)
    if all(s == FollowerStatus.OK for s in member_status):
        status = FollowerStatus.OK
    elif all(s == FollowerStatus.FAILED for s in member_status):
        status = FollowerStatus.FAILED
    else:
        status = FollowerStatus.PARTIAL
    return FollowerBatch(
        t=req.robot.sample_time * np.arange(len(leader)),
        leader_xy=leader,
        robot_xy=np.stack([hist["x"], hist["y"]], axis=-1),
        heading=hist["g"],
        tether_length=hist["l"],
        tether_angle=hist["th"],
        speed=hist["v"],
        turn_rate=hist["om"],
        controllers=req.controllers,
        robot=req.robot,
        path=req.path,
        speed_leader=req.speed,
        member_status=tuple(member_status),
        status=status,
        warnings=tuple(warns),
    )


def simulate_batch(
    controllers: Sequence[TetherController],
    path: LeaderPath | str | dict[str, Any],
    speed: float = LEADER_SPEED.default,
    robot: FollowerRobot | None = None,
    duration: float | None = None,
    settle_time: float = SETTLE_TIME.default,
    lead_in: float = LEAD_IN.default,
    initial_pose: tuple[float, float, float] | None = None,
    seed: int | None = SEED.default,
) -> FollowerBatch:
    """Simulate several gain sets of one control law on one path at once.

    Parameters
    ----------
    controllers
        Controllers of one class (their gains, look-aheads and desired
        lengths may differ; FTL/FTL-CD members must share ``min_step`` and
        ``buffer_size``).
    path
        A :class:`LeaderPath` (or a name/dict for :func:`make_path`).
    speed
        Leader speed in m/s (Allan 2015 uses 0.5 m/s; :data:`LEADER_SPEED`).
    robot
        The robot (default :class:`FollowerRobot`, the App. C model with no
        wheel limits, 100 Hz).
    duration
        Simulated time in s (default: the leader's walk plus ``settle_time``;
        at most 10**4 s, :data:`DURATION`).
    settle_time
        Time in s after the leader stops.
    lead_in
        Straight approach in m along the initial tangent that the leader
        walked before t = 0 and that FTL/FTL-CD have already recorded (0 as
        in the thesis: the buffer starts empty).
    initial_pose
        ``(x, y, heading)`` of the robot in m, m, rad (default: ``l_d`` behind
        the path start on its tangent, at rest).
    seed
        Seed of the sensor noise.

    Returns
    -------
    FollowerBatch
    """
    req = _checked_request(
        controllers, path, speed, robot, duration, settle_time, lead_in, initial_pose, seed
    )
    leader = req.path.leader_positions(req.speed, req.robot.sample_time, req.duration)
    buf = _buffering(req, leader)
    x, y, g = _start(req)
    if req.law.stepwise:
        hist = run_stepwise(req.controllers, leader, (x, y, g), req.robot, _rng(req.seed))
    elif len(req.controllers) == 1 and not req.robot.noisy and req.robot.tip_height == 0.0:
        pose = (float(x[0]), float(y[0]), float(g[0]))
        hist = run_single(req.controllers[0], leader, pose, req.robot, buf)
    else:
        hist = run_batch(req.controllers, leader, (x, y, g), req.robot, buf, _rng(req.seed))
    return _batch_result(req, leader, hist)


def _rng(seed: int | None) -> np.random.Generator:
    return np.random.default_rng(seed)


def simulate(
    controller: TetherController,
    path: LeaderPath | str | dict[str, Any],
    speed: float = LEADER_SPEED.default,
    robot: FollowerRobot | None = None,
    duration: float | None = None,
    settle_time: float = SETTLE_TIME.default,
    lead_in: float = LEAD_IN.default,
    initial_pose: tuple[float, float, float] | None = None,
    seed: int | None = SEED.default,
) -> FollowerRun:
    """Simulate one tether follower behind a leader walking ``path`` at ``speed``.

    Parameters are those of :func:`simulate_batch` with one controller.

    Parameters
    ----------
    controller
        The tether controller.
    path
        A :class:`LeaderPath` (or a name/dict for :func:`make_path`).
    speed
        Leader speed in m/s (> 0; Allan 2015 uses 0.5 m/s).
    robot
        The robot (default :class:`FollowerRobot`).
    duration
        Simulated time in s (default: the leader's walk plus ``settle_time``).
    settle_time
        Time in s after the leader stops (>= 0).
    lead_in
        Straight approach in m already walked (and recorded) before t = 0 (>= 0).
    initial_pose
        ``(x, y, heading)`` of the robot in m, m, rad (default: ``l_d`` behind the path start).
    seed
        Seed of the sensor noise (``None``: fresh randomness).

    Returns
    -------
    FollowerRun
        ``leader_xy``, ``robot_xy``, ``tether_length`` ... over time.

    Examples
    --------
    >>> from designlab.following.tether import FollowTheLeaderConstDistance, figure_eight
    >>> ctrl = FollowTheLeaderConstDistance(desired_length=1.0)
    >>> sim = simulate(ctrl, figure_eight(a=4.0), speed=0.5)
    >>> sim.robot_xy.shape == sim.leader_xy.shape, str(sim.status)
    (True, 'ok')
    """
    checked_law(controller)
    batch = simulate_batch(
        [controller],
        path,
        speed=speed,
        robot=robot,
        duration=duration,
        settle_time=settle_time,
        lead_in=lead_in,
        initial_pose=initial_pose,
        seed=seed,
    )
    return batch.run(0)
