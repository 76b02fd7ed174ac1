"""Numerical stability test: the convergence map of Allan 2015 Sec. 2.4.5 (Figs. 2.9-2.10).

The thesis checked stability numerically over tether inputs
``-pi < theta_m < pi`` and ``0 < l_m < 10`` (units not stated, A16), recorded
the convergence time and took convergence in finite time as evidence of
stability; Figs. 2.9 (PJ) and 2.10 (FTL) are plots only. Its grid, tolerance
and the leader's motion are not stated. The reconstruction here (stated in
``docs/tether_modes.md``): a **static** leader is placed at ``(l_0, theta_0)``
relative to a robot at rest; every grid point is one member of a batch run of the
compiled closed loop (:func:`designlab.following.tether.closed_loop.run_batch`);
the robot has **converged** once it stays at rest facing the leader with the
tether not longer than ``l_d``: ``|theta_m| < tol_angle``, ``|V| < tol_speed``,
``|Omega| < tol_turn`` and ``l_m - l_d < tol_length`` from then until the end
(at least ``hold`` seconds). A slack tether (``l_0 < l_d``) is converged for the
forward-only laws, which then only turn to face the leader. With a static leader
FTL and FTL-CD hold one recorded point and steer at the tip.

Examples
--------
>>> from designlab.following.tether import PseudoJoystick
>>> m = convergence_map(PseudoJoystick(), lengths=[0.5, 2.0], angles=[0.0, 3.0], max_time=10.0)
>>> m.converged.all(), m.time.shape
(np.True_, (2, 2))
>>> round(float(m.time[0, 0]), 2)     # slack and facing the leader: converged at once
0.0
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.following.tether.buffer import record_shared
from designlab.following.tether.closed_loop import Buffering, run_batch
from designlab.following.tether.laws.base import TetherController, checked_law
from designlab.following.tether.parameters import FollowerRobot
from designlab.params import Param, check_size
from designlab.results import Result, Status

__all__ = [
    "GRID_LENGTH",
    "GRID_POINTS",
    "HOLD",
    "MAX_GRID",
    "MAX_TIME",
    "TOL_ANGLE",
    "TOL_LENGTH",
    "TOL_SPEED",
    "ConvergenceMap",
    "ConvergenceStatus",
    "convergence_map",
]

#: Longest simulated time per grid point (s): the cap of "not converged".
MAX_TIME = Param(
    "T_max", "s", "time allowed to converge", gt=0, le=1000, default=30.0, name="max_time"
)
#: Time the convergence criterion must hold until the end (s).
HOLD = Param("T_hold", "s", "time the criterion must hold", ge=0, le=100, default=1.0, name="hold")
#: Tolerances of the convergence criterion.
TOL_ANGLE = Param(
    "eps_theta", "rad", "tolerance on theta_m", gt=0, le=1, default=0.01, name="tol_angle"
)
TOL_SPEED = Param(
    "eps_V", "m/s", "tolerance on V and on b Omega / 2", gt=0, le=1, default=0.01, name="tol_speed"
)
TOL_LENGTH = Param(
    "eps_l", "m", "tolerance on l_m - l_d", gt=0, le=1, default=0.01, name="tol_length"
)
#: Largest grid (points): a batch of this many members runs in one numpy loop.
MAX_GRID = 100_000
#: An initial tether length of the grid (m; the thesis's range is 0 < l_m < 10, unit unstated).
GRID_LENGTH = Param("l_0", "m", "initial tether length", gt=0, le=100, name="lengths")
#: Points along one axis of the grid.
GRID_POINTS = Param(
    None, "", "grid points along one axis", kind="integer", ge=2, le=1000, name="num"
)


class ConvergenceStatus(Status):
    """``OK``: every grid point converged; ``PARTIAL``: some did not within ``max_time``."""

    OK = "ok"
    PARTIAL = "partial"


@dataclass(frozen=True, eq=False)
class ConvergenceMap(Result):
    """Convergence time over a grid of initial tether readings (static leader).

    Attributes
    ----------
    controller
        The law.
    lengths, angles
        Initial tether length l_0 (m) and angle theta_0 (rad) of the grid, (L,) and (A,).
    time
        Convergence time in s, NaN where it did not converge, (L, A).
    final_length, final_angle
        l_m (m) and theta_m (rad) at the end, (L, A).
    at_rest
        True where the robot is at rest (speeds within tolerance) over the last ``hold``
        seconds, facing the leader or not, (L, A).
    max_time
        The cap in s.
    status
        ``ok`` when every point converged.
    warnings
        What did not converge.
    """

    controller: TetherController
    lengths: NDArray[np.float64]
    angles: NDArray[np.float64]
    time: NDArray[np.float64]
    final_length: NDArray[np.float64]
    final_angle: NDArray[np.float64]
    at_rest: NDArray[np.bool_]
    max_time: float
    status: ConvergenceStatus = ConvergenceStatus.OK
    warnings: tuple[str, ...] = ()

    @property
    def converged(self) -> NDArray[np.bool_]:
        """True where the robot converged, (L, A)."""
        return np.isfinite(self.time)

    def to_frame(self) -> pd.DataFrame:
        """One row per grid point."""
        ll, aa = np.meshgrid(self.lengths, self.angles, indexing="ij")
        return pd.DataFrame(
            {
                "initial_length_m": ll.ravel(),
                "initial_angle_rad": aa.ravel(),
                "converged": self.converged.ravel(),
                "time_s": self.time.ravel(),
                "final_length_m": self.final_length.ravel(),
                "final_angle_rad": self.final_angle.ravel(),
                "at_rest": self.at_rest.ravel(),
            }
        )


def _grid(values: Sequence[float], name: str, lo: float, hi: float) -> NDArray[np.float64]:
    try:
        arr = np.asarray(values, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InvalidParameterError(name, values, "a list of numbers") from None
    if arr.size == 0 or not np.all(np.isfinite(arr)) or arr.min() < lo or arr.max() > hi:
        raise InvalidParameterError(
            name, values, f"a non-empty list of numbers in [{lo:g}, {hi:g}]"
        )
    return arr


def _settled_time(ok: NDArray[np.bool_], dt: float, hold: float) -> NDArray[np.float64]:
    """First time from which ``ok`` holds to the end, if that leaves at least ``hold``; else NaN."""
    n = ok.shape[1]
    fails = ~ok
    last_fail = np.where(fails.any(axis=1), n - 1 - np.argmax(fails[:, ::-1], axis=1), -1)
    t = (last_fail + 1) * dt
    return np.where((n - 1 - last_fail) * dt >= hold - 1e-12, t, np.nan)


def convergence_map(
    controller: TetherController,
    lengths: Sequence[float],
    angles: Sequence[float],
    robot: FollowerRobot | None = None,
    max_time: float = MAX_TIME.default,
    hold: float = HOLD.default,
    tol_angle: float = TOL_ANGLE.default,
    tol_speed: float = TOL_SPEED.default,
    tol_length: float = TOL_LENGTH.default,
) -> ConvergenceMap:
    """Convergence time from every ``(l_0, theta_0)`` of a grid toward a static leader.

    Parameters
    ----------
    controller
        A memoryless law (PJ, FTL, FTL-CD; Ch. 2).
    lengths
        Initial tether lengths l_0 in m (0 < l_0 <= 100).
    angles
        Initial tether angles theta_0 in rad, within [-pi, pi].
    robot
        The robot (default :class:`FollowerRobot`; noise is ignored).
    max_time
        Time allowed in s (:data:`MAX_TIME`).
    hold
        Time in s the criterion must hold until the end (:data:`HOLD`).
    tol_angle, tol_speed, tol_length
        Tolerances on ``|theta_m|`` (rad), ``|V|`` and ``b |Omega| / 2`` (m/s), and
        ``l_m - l_d`` (m).

    Returns
    -------
    ConvergenceMap
    """
    memoryless = "a memoryless law (PJ, FTL, FTL-CD)"
    if checked_law(controller, allowed=memoryless).stepwise:
        raise InvalidParameterError("controller", controller, memoryless)
    ls = _grid(lengths, "lengths", 1e-6, 100.0)
    th = _grid(angles, "angles", -math.pi, math.pi)
    robot = FollowerRobot() if robot is None else robot
    if not isinstance(robot, FollowerRobot):
        raise InvalidParameterError("robot", robot, "a FollowerRobot")
    robot = robot.replace(length_noise_std=0.0, angle_noise_std=0.0)
    max_time, hold = MAX_TIME.check(max_time), HOLD.check(hold)
    if hold >= max_time:
        raise InvalidParameterError("hold", hold, f"less than max_time ({max_time:g} s)", "s")
    tols = (TOL_ANGLE.check(tol_angle), TOL_SPEED.check(tol_speed), TOL_LENGTH.check(tol_length))
    n = math.floor(max_time / robot.sample_time + 1e-9) + 1
    if ls.size * th.size > MAX_GRID:
        raise InvalidParameterError(
            "lengths x angles", ls.size * th.size, f"at most {MAX_GRID} grid points"
        )
    check_size(
        "max_time",
        max_time,
        8.0 * n * ls.size * th.size,
        what=f"{n} periods x {ls.size * th.size} points",
    )
    return _run(controller, ls, th, robot, n, hold, tols)


def _run(
    c: TetherController,
    ls: NDArray[np.float64],
    th: NDArray[np.float64],
    robot: FollowerRobot,
    n: int,
    hold: float,
    tols: tuple[float, float, float],
) -> ConvergenceMap:
    ll, aa = (v.ravel() for v in np.meshgrid(ls, th, indexing="ij"))
    nb = ll.size
    leader = np.zeros((n, 2))  # the leader at the origin; each robot l_0 away, heading 0
    pose = (-ll * np.cos(aa), -ll * np.sin(aa), np.zeros(nb))
    buf = None
    if c.target_finder.records_path:
        shared = record_shared(leader, c.min_step, np.zeros((0, 2)))  # type: ignore[attr-defined]
        buf = Buffering(c.buffer_size - 1, c.min_step, np.zeros((0, 2)), shared)  # type: ignore[attr-defined]
    hist = run_batch((c,) * nb, leader, pose, robot, buf, np.random.default_rng(0))
    ta, ts, tl = tols
    with np.errstate(invalid="ignore"):
        rest = (np.abs(hist["v"]) < ts) & (0.5 * robot.wheel_track * np.abs(hist["om"]) < ts)
        ok = rest & (np.abs(hist["th"]) < ta) & (hist["l"] - c.desired_length < tl)
    tail = max(1, round(hold / robot.sample_time))
    t = _settled_time(ok, robot.sample_time, hold).reshape(ls.size, th.size)
    bad = int((~np.isfinite(t)).sum())
    warns = (
        ()
        if bad == 0
        else (f"{bad} of {t.size} grid points did not converge in {n * robot.sample_time:g} s",)
    )
    return ConvergenceMap(
        controller=c,
        lengths=ls,
        angles=th,
        time=t,
        final_length=hist["l"][:, -1].reshape(t.shape),
        final_angle=hist["th"][:, -1].reshape(t.shape),
        at_rest=rest[:, -tail:].all(axis=1).reshape(t.shape),
        max_time=(n - 1) * robot.sample_time,
        status=ConvergenceStatus.OK if bad == 0 else ConvergenceStatus.PARTIAL,
        warnings=warns,
    )
