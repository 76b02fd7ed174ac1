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
>>> from designlab.following import FollowTheLeader, straight_line
>>> run = simulate(FollowTheLeader(), straight_line(10.0), speed=0.5, duration=15.0)
>>> round(float(run.tether_length[1000]), 6)         # l_d + v/K_V after the transient
1.5
"""

from __future__ import annotations

import math
from bisect import bisect_left, bisect_right
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError, check_nonnegative, check_positive
from designlab.following.paths import LeaderPath, make_path
from designlab.following.tether_controllers import TetherController
from designlab.following.tether_model import FollowerRobot, sensor_step, step_compiled, tip_step
from designlab.results import Result

__all__ = ["FollowerBatch", "FollowerRun", "simulate", "simulate_batch"]

_TWO_PI = 2.0 * math.pi


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
    status: str = "ok"
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
    member_status: tuple[str, ...]
    status: str = "ok"
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


def _record_shared(
    tips: NDArray[np.float64], min_step: float, prefill: NDArray[np.float64]
) -> tuple:
    """Record a tip sequence with the App. C ``point_tracker`` rule (shared buffer).

    Returns the recorded points (M, 2), their path distance (M,), and for
    each step the number of records made up to and including it.
    """
    rec = list(map(tuple, prefill))
    s_rec = [0.0]
    for i in range(1, len(rec)):
        s_rec.append(s_rec[-1] + math.dist(rec[i], rec[i - 1]))
    if not rec:
        s_rec = []
    counts = np.empty(len(tips), dtype=np.int64)
    ms2 = min_step
    lx, ly = rec[-1] if rec else (math.nan, math.nan)
    txs = tips[:, 0].tolist()
    tys = tips[:, 1].tolist()
    for k in range(len(txs)):
        tx, ty = txs[k], tys[k]
        if not rec:
            rec.append((tx, ty))
            s_rec.append(0.0)
            lx, ly = tx, ty
        else:
            d = math.hypot(tx - lx, ty - ly)
            if d >= ms2:
                rec.append((tx, ty))
                s_rec.append(s_rec[-1] + d)
                lx, ly = tx, ty
        counts[k] = len(rec)
    return np.array(rec, dtype=float), np.array(s_rec, dtype=float), counts


def _sensed(
    hist: dict[str, NDArray[np.float64]],
    leader: NDArray[np.float64],
    robot: FollowerRobot,
    noise: tuple[NDArray[np.float64], NDArray[np.float64]] | None,
) -> None:
    """Add the measured tether length and angle (one vectorised call over the run)."""
    lm, th = sensor_step(True)(
        hist["x"],
        hist["y"],
        hist["g"],
        leader[None, :, 0],
        leader[None, :, 1],
        robot.winch_offset_x,
        robot.winch_offset_y,
        robot.tip_height,
    )
    if noise is not None:
        lm = lm + noise[0]
        th = th + noise[1]
    hist["l"] = np.asarray(lm, dtype=float)
    hist["th"] = np.asarray(th, dtype=float)


def _loop_single(
    c: TetherController,
    leader: NDArray[np.float64],
    pose: tuple[float, float, float],
    robot: FollowerRobot,
    law_fn: Any,
    rec: NDArray[np.float64] | None,
    s_rec: NDArray[np.float64] | None,
    counts: NDArray[np.int64] | None,
    window: int,
) -> dict[str, NDArray[np.float64]]:
    """One noise-free run on Python floats (the fast path of :func:`simulate`)."""
    target = type(c).target
    limited = robot.max_wheel_speed < math.inf or robot.max_wheel_acceleration < math.inf
    offsets = robot.winch_offset_x != 0.0 or robot.winch_offset_y != 0.0
    step = step_compiled(law_fn, target != "tether", limited, offsets, False, False)
    b, r, dt = robot.wheel_track, robot.wheel_radius, robot.sample_time
    wmax, astep = robot.max_wheel_speed, robot.max_wheel_acceleration * dt
    ox, oy = robot.winch_offset_x, robot.winch_offset_y
    params = c.law_values()
    x, y, g = pose
    wl = wr = 0.0
    n = len(leader)
    out = np.empty((n, 5))
    txs, tys = leader[:, 0].tolist(), leader[:, 1].tolist()
    jx = jy = 0.0
    if target != "tether":
        assert rec is not None and s_rec is not None and counts is not None
        aug = np.column_stack([rec, -0.5 * np.einsum("ij,ij->i", rec, rec)])
        s_list = s_rec.tolist()
        rx, ry = rec[:, 0].tolist(), rec[:, 1].tolist()
        cnt = counts.tolist()
        p3 = np.ones(3)
        delta = getattr(c, "lookahead", 0.0) - 1e-12
        ld = c.desired_length
        ld2 = ld * ld
        last_hi = -1
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for k in range(n):
            if target == "lookahead":
                # App. C find_closest_point (nearest recorded point) + find_lookahead_point
                hi = cnt[k]
                lo = hi - window if hi > window else 0
                if hi - lo < 2:
                    j = hi - 1
                else:
                    p3[0] = x
                    p3[1] = y
                    i0 = int(np.argmax(aug[lo:hi] @ p3)) + lo
                    j = bisect_left(s_list, s_list[i0] + delta, i0, hi)
                    if j >= hi:
                        j = hi - 1
                jx, jy = rx[j], ry[j]
            elif target == "constant_distance":
                hi = cnt[k]
                if hi != last_hi:
                    # App. C find_const_dist_target: the newest point >= l_d (Euclidean) from the
                    # newest; a point closer than l_d along the path is closer in space too.
                    lo = hi - window if hi > window else 0
                    nx, ny = rx[hi - 1], ry[hi - 1]
                    j = bisect_right(s_list, s_list[hi - 1] - ld, lo, hi) - 1
                    while j >= lo and (rx[j] - nx) ** 2 + (ry[j] - ny) ** 2 < ld2:
                        j -= 1
                    if j < lo:
                        j = hi - 1
                    last_hi = hi
                    jx, jy = rx[j], ry[j]
            xn, yn, gn, v, om, wl, wr = step(
                x,
                y,
                g,
                txs[k],
                tys[k],
                jx,
                jy,
                wl,
                wr,
                0.0,
                0.0,
                b,
                r,
                dt,
                wmax,
                astep,
                ox,
                oy,
                0.0,
                *params,
            )
            out[k] = (x, y, g, v, om)
            x, y, g = xn, yn, gn
    hist = {k: out[:, i][None, :] for i, k in enumerate(("x", "y", "g", "v", "om"))}
    _sensed(hist, leader, robot, None)
    return hist


def _loop_batch(
    controllers: tuple[TetherController, ...],
    leader: NDArray[np.float64],
    pose: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    robot: FollowerRobot,
    law_fn: Any,
    rec: NDArray[np.float64] | None,
    s_rec: NDArray[np.float64] | None,
    counts: NDArray[np.int64] | None,
    window: int,
    min_step: float,
    prefill: NDArray[np.float64],
    rng: np.random.Generator,
) -> dict[str, NDArray[np.float64]]:
    """A batch of runs on numpy arrays (one member per gain set)."""
    cls = type(controllers[0])
    target = cls.target
    nb = len(controllers)
    n = len(leader)
    limited = robot.max_wheel_speed < math.inf or robot.max_wheel_acceleration < math.inf
    offsets = robot.winch_offset_x != 0.0 or robot.winch_offset_y != 0.0 or robot.tip_height != 0.0
    noisy = robot.noisy
    step = step_compiled(law_fn, target != "tether", limited, offsets, noisy, True)
    b, r, dt = robot.wheel_track, robot.wheel_radius, robot.sample_time
    wmax, astep = robot.max_wheel_speed, robot.max_wheel_acceleration * dt
    ox, oy, hh = robot.winch_offset_x, robot.winch_offset_y, robot.tip_height
    noise = None
    if noisy:
        noise = (
            rng.normal(0.0, 1.0, (nb, n)) * robot.length_noise_std,
            rng.normal(0.0, 1.0, (nb, n)) * robot.angle_noise_std,
        )
    params = [np.array(v) for v in zip(*(c.law_values() for c in controllers), strict=True)]
    x, y, g = (np.array(v, dtype=float) for v in pose)
    wl = np.zeros(nb)
    wr = np.zeros(nb)
    rows = np.arange(nb)
    jx = jy = np.zeros(nb)
    nl = nth = 0.0
    out = np.empty((n, 5, nb))
    shared = rec is not None
    if target == "lookahead":
        delta = np.array([c.lookahead for c in controllers]) - 1e-12  # type: ignore[attr-defined]
    ld2 = np.array([c.desired_length for c in controllers]) ** 2
    if target != "tether" and shared:
        assert rec is not None and s_rec is not None and counts is not None
        aug_t = np.ascontiguousarray(
            np.column_stack([rec, -0.5 * np.einsum("ij,ij->i", rec, rec)]).T
        )
        p3 = np.ones((nb, 3))
        last_hi = -1
    elif target != "tether":
        sense = sensor_step(True)
        tip = tip_step(True)
        cap = n + len(prefill) + 1
        bx = np.full((nb, cap), np.nan)
        by = np.full((nb, cap), np.nan)
        bs = np.zeros((nb, cap))
        cnt = np.zeros(nb, dtype=np.int64)
        if len(prefill):
            bx[:, : len(prefill)] = prefill[:, 0]
            by[:, : len(prefill)] = prefill[:, 1]
            bs[:, : len(prefill)] = np.concatenate(
                [[0.0], np.cumsum(np.hypot(*np.diff(prefill, axis=0).T))]
            )
            cnt[:] = len(prefill)
        ar = np.arange(window)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for k in range(n):
            tx, ty = leader[k]
            if noise is not None:
                nl, nth = noise[0][:, k], noise[1][:, k]
            if target != "tether" and shared:
                hi = counts[k]  # type: ignore[index]
                lo = max(0, hi - window)
                if target == "lookahead":
                    if hi - lo < 2:
                        j = np.full(nb, hi - 1)
                    else:
                        p3[:, 0] = x
                        p3[:, 1] = y
                        i0 = np.argmax(p3 @ aug_t[:, lo:hi], axis=1) + lo
                        j = np.searchsorted(s_rec[lo:hi], s_rec[i0] + delta) + lo  # type: ignore[index]
                        j = np.minimum(j, hi - 1)
                    jx, jy = rec[j, 0], rec[j, 1]  # type: ignore[index]
                elif hi != last_hi:
                    w = rec[lo:hi]  # type: ignore[index]
                    dd = ((w - w[-1]) ** 2).sum(axis=1)
                    ok = dd[None, :] >= ld2[:, None]
                    last = np.where(
                        ok.any(axis=1), (hi - lo - 1) - np.argmax(ok[:, ::-1], axis=1), hi - lo - 1
                    )
                    jx, jy = rec[last + lo, 0], rec[last + lo, 1]  # type: ignore[index]
                    last_hi = hi
            elif target != "tether":
                # per-member buffers of the estimated tip (noise, tip height)
                lm, th = sense(x, y, g, tx, ty, ox, oy, hh)
                tx_e, ty_e = tip(x, y, g, lm + nl, th + nth, ox, oy)
                has = cnt > 0
                last_i = np.maximum(cnt - 1, 0)
                dd = np.hypot(tx_e - bx[rows, last_i], ty_e - by[rows, last_i])
                recm = ~has | (dd >= min_step)
                ri, idx = rows[recm], cnt[recm]
                bx[ri, idx] = tx_e[recm]
                by[ri, idx] = ty_e[recm]
                bs[ri, idx] = np.where(has[recm], bs[ri, np.maximum(idx - 1, 0)] + dd[recm], 0.0)
                cnt = cnt + recm
                widx = cnt[:, None] - window + ar[None, :]
                valid = widx >= 0
                widx = np.maximum(widx, 0)
                wxs = bx[rows[:, None], widx]
                wys = by[rows[:, None], widx]
                if target == "lookahead":
                    d2 = np.where(valid, (wxs - x[:, None]) ** 2 + (wys - y[:, None]) ** 2, np.inf)
                    i0 = np.where(np.minimum(cnt, window) < 2, window - 1, np.argmin(d2, axis=1))
                    ws = bs[rows[:, None], widx]
                    ok = (
                        valid
                        & (ws - ws[rows, i0][:, None] >= delta[:, None])
                        & (ar[None, :] >= i0[:, None])
                    )
                    jj = np.where(ok.any(axis=1), np.argmax(ok, axis=1), window - 1)
                else:
                    nx, ny = wxs[:, -1], wys[:, -1]
                    ok = valid & (
                        (wxs - nx[:, None]) ** 2 + (wys - ny[:, None]) ** 2 >= ld2[:, None]
                    )
                    jj = np.where(
                        ok.any(axis=1), window - 1 - np.argmax(ok[:, ::-1], axis=1), window - 1
                    )
                jx, jy = wxs[rows, jj], wys[rows, jj]
            xn, yn, gn, v, om, wl, wr = step(
                x, y, g, tx, ty, jx, jy, wl, wr, nl, nth, b, r, dt, wmax, astep, ox, oy, hh, *params
            )
            o = out[k]
            o[0], o[1], o[2], o[3], o[4] = x, y, g, v, om
            x, y, g = xn, yn, gn
    hist = {k: out[:, i, :].T.copy() for i, k in enumerate(("x", "y", "g", "v", "om"))}
    _sensed(hist, leader, robot, noise)
    return hist


#: Fastest leader accepted (m/s): well above any walk (Allan 2015 uses 0.5 m/s).
MAX_LEADER_SPEED = 10.0


def simulate_batch(
    controllers: Sequence[TetherController],
    path: LeaderPath | str | dict[str, Any],
    speed: float = 0.5,
    robot: FollowerRobot | None = None,
    duration: float | None = None,
    settle_time: float = 5.0,
    lead_in: float = 0.0,
    initial_pose: tuple[float, float, float] | None = None,
    seed: int | None = 0,
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
        Leader speed in m/s (> 0; Allan 2015 uses 0.5 m/s).
    robot
        The robot (default :class:`FollowerRobot`, the App. C model with no
        wheel limits, 100 Hz).
    duration
        Simulated time in s (default: the leader's walk plus ``settle_time``).
    settle_time
        Time in s after the leader stops (>= 0).
    lead_in
        Straight approach in m along the initial tangent that the leader
        walked before t = 0 and that FTL/FTL-CD have already recorded (>= 0;
        0 as in the thesis: the buffer starts empty).
    initial_pose
        ``(x, y, heading)`` of the robot in m, m, rad (default: ``l_d`` behind
        the path start on its tangent, at rest).
    seed
        Seed of the sensor noise.

    Returns
    -------
    FollowerBatch
    """
    if isinstance(controllers, TetherController):
        controllers = [controllers]
    controllers = tuple(controllers)
    if not controllers:
        raise InvalidParameterError("controllers", controllers, "at least one controller")
    cls = type(controllers[0])
    for c in controllers:
        if type(c) is not cls or not isinstance(c, TetherController):
            raise InvalidParameterError(
                "controllers", type(c).__name__, f"all of one law ({cls.__name__})"
            )
    key = controllers[0].law_key()
    if any(c.law_key() != key for c in controllers):
        raise InvalidParameterError("controllers", "mixed law variants", "one variant per batch")
    path = make_path(path)
    speed = check_positive("speed", speed, "m/s")
    if speed > MAX_LEADER_SPEED:
        raise InvalidParameterError(
            "speed", speed, f"a walking leader's speed: at most {MAX_LEADER_SPEED:g} m/s", "m/s"
        )
    robot = robot or FollowerRobot()
    if not isinstance(robot, FollowerRobot):
        raise InvalidParameterError("robot", robot, "a FollowerRobot")
    settle_time = check_nonnegative("settle_time", settle_time, "s")
    lead_in = check_nonnegative("lead_in", lead_in, "m")
    for c in controllers:
        if c.desired_length <= 0.5 * robot.body_length:
            raise InvalidParameterError(
                f"{cls.__name__}.desired_length",
                c.desired_length,
                f"must exceed half the robot length ({0.5 * robot.body_length:g} m): "
                "the tether tip would be inside the robot",
                "m",
            )
    if cls.target != "tether":
        ms = {c.min_step for c in controllers}  # type: ignore[attr-defined]
        bs = {c.buffer_size for c in controllers}  # type: ignore[attr-defined]
        if len(ms) > 1 or len(bs) > 1:
            raise InvalidParameterError(
                "controllers", "different min_step/buffer_size", "one value per batch"
            )
    dt = robot.sample_time
    if duration is None:
        duration = path.length / speed + settle_time
    duration = check_positive("duration", duration, "s")
    leader = path.leader_positions(speed, dt, duration)
    n = len(leader)
    nb = len(controllers)

    g0 = path.start_heading
    u0 = np.array([math.cos(g0), math.sin(g0)])
    if initial_pose is None:
        ld = np.array([c.desired_length for c in controllers])
        x = path.points[0, 0] - ld * u0[0]
        y = path.points[0, 1] - ld * u0[1]
        g = np.full(nb, g0)
    else:
        x0, y0, h0 = (float(v) for v in initial_pose)
        if not all(math.isfinite(v) for v in (x0, y0, h0)):
            raise InvalidParameterError("initial_pose", initial_pose, "finite (x, y, heading)")
        x, y, g = np.full(nb, x0), np.full(nb, y0), np.full(nb, h0)

    b, r = robot.wheel_track, robot.wheel_radius
    wmax, hh = robot.max_wheel_speed, robot.tip_height
    law_fn = cls.law_function(key)
    buffered = cls.target != "tether"
    noisy = robot.noisy
    shared = not noisy and hh == 0.0

    prefill = np.zeros((0, 2))
    min_step = window = 0
    if buffered:
        min_step = controllers[0].min_step  # type: ignore[attr-defined]
        window = controllers[0].buffer_size - 1  # type: ignore[attr-defined]
        if lead_in > 0:
            m = math.floor(lead_in / min_step)
            prefill = path.points[0] - np.outer(np.arange(m, 0, -1) * min_step, u0)
    rec = s_rec = counts = None
    if buffered and shared:
        rec, s_rec, counts = _record_shared(leader, min_step, prefill)
    if nb == 1 and shared:
        hist = _loop_single(
            controllers[0],
            leader,
            (float(x[0]), float(y[0]), float(g[0])),
            robot,
            law_fn,
            rec,
            s_rec,
            counts,
            window,
        )
    else:
        hist = _loop_batch(
            controllers,
            leader,
            (x, y, g),
            robot,
            law_fn,
            rec,
            s_rec,
            counts,
            window,
            min_step,
            prefill,
            np.random.default_rng(seed),
        )

    t = dt * np.arange(n)
    robot_xy = np.stack([hist["x"], hist["y"]], axis=-1)
    finite = np.all(np.isfinite(robot_xy), axis=(1, 2)) & np.all(np.isfinite(hist["l"]), axis=1)
    member_status = []
    warns: list[str] = []
    for i in range(nb):
        if not finite[i]:
            member_status.append("failed")
            warns.append(f"member {i}: the state became non-finite")
            continue
        member_status.append("ok")
        if wmax < math.inf:
            wsat = np.abs(hist["v"][i]) / r + 0.5 * b * np.abs(hist["om"][i]) / r >= wmax * (
                1 - 1e-9
            )
            if wsat.mean() > 0.05:
                warns.append(
                    f"member {i}: a wheel is at its speed limit "
                    f"{100 * wsat.mean():.0f} % of the time"
                )
    status = (
        "ok"
        if all(s == "ok" for s in member_status)
        else ("failed" if not any(finite) else "partial")
    )
    return FollowerBatch(
        t=t,
        leader_xy=leader,
        robot_xy=robot_xy,
        heading=hist["g"],
        tether_length=hist["l"],
        tether_angle=hist["th"],
        speed=hist["v"],
        turn_rate=hist["om"],
        controllers=controllers,
        robot=robot,
        path=path,
        speed_leader=speed,
        member_status=tuple(member_status),
        status=status,
        warnings=tuple(warns),
    )


def simulate(
    controller: TetherController,
    path: LeaderPath | str | dict[str, Any],
    speed: float = 0.5,
    robot: FollowerRobot | None = None,
    duration: float | None = None,
    settle_time: float = 5.0,
    lead_in: float = 0.0,
    initial_pose: tuple[float, float, float] | None = None,
    seed: int | None = 0,
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
    >>> from designlab.following import FollowTheLeaderConstDistance, figure_eight
    >>> ctrl = FollowTheLeaderConstDistance(desired_length=1.0)
    >>> sim = simulate(ctrl, figure_eight(a=4.0), speed=0.5)
    >>> sim.robot_xy.shape == sim.leader_xy.shape, sim.status
    (True, 'ok')
    """
    if not isinstance(controller, TetherController):
        raise InvalidParameterError(
            "controller", controller, "a tether controller (e.g. FollowTheLeader())"
        )
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
