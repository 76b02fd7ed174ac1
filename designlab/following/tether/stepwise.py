"""Follower modes with memory, run one control period at a time (Allan 2015 Ch. 4, App. C).

Most laws of :mod:`designlab.following.tether.laws` are pure functions of the
tether reading, compiled once. Side Tracking (mode 31), FrontVelJoystick (mode
42) and Brake mode (Sec. 4.4) keep state between periods (a short tip buffer,
sample buffers, the selected mode), so they are stepwise laws
(:class:`~designlab.following.tether.laws.base.StepwiseController`):
``start(robot)`` returns a fresh :class:`ModeState` whose ``command`` maps one
tether reading to ``(V, Omega)``. :func:`run_stepwise` is the control-period
loop the tether :func:`~designlab.following.tether.simulate` uses for them: the
same sensor (:func:`~designlab.following.tether.model.sensor_step`), wheel limits
(one common scale keeps the curvature, then an acceleration step) and exact-arc
motion as the compiled loop of the other laws.

:class:`TipRecorder` is App. C's ``point_tracker`` with ``find_closest_point``,
``find_lookahead_point`` and ``find_const_dist_target``, for one run.

Examples
--------
>>> rec = TipRecorder(limit=300, min_step=0.01)
>>> for i in range(51):
...     _ = rec.record(0.02 * i, 0.0)
>>> len(rec), rec.newest(), round(rec.lookahead_point(0.0, 0.0, 0.5)[0], 6)
(51, (1.0, 0.0), 0.5)
"""

from __future__ import annotations

import math
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from designlab.following.tether.laws.base import TetherController
from designlab.following.tether.model import sensor_step, wrap_angle
from designlab.following.tether.parameters import FollowerRobot

__all__ = [
    "LawState",
    "ModeState",
    "TipRecorder",
    "limited_command",
    "run_stepwise",
    "start_state",
]


class TipRecorder:
    """App. C ``point_tracker``: record a point when it is ``min_step`` from the newest one.

    At most ``limit - 1`` points are kept (as coded); the path distance of each
    point is the running sum of the recorded steps.

    Parameters
    ----------
    limit
        Buffer limit (App. C: 300 for FTL, 10 for the Side Tracking tip buffer).
    min_step
        Delta s_min in m.
    """

    def __init__(self, limit: int, min_step: float) -> None:
        self.keep = max(1, int(limit) - 1)
        self.min_step = float(min_step)
        self.xs: list[float] = []
        self.ys: list[float] = []
        self.s: list[float] = []

    def __len__(self) -> int:
        return len(self.xs)

    def record(self, x: float, y: float) -> bool:
        """Record ``(x, y)`` if it is at least ``min_step`` from the newest point (or the first)."""
        if self.xs:
            ds = math.hypot(x - self.xs[-1], y - self.ys[-1])
            if not ds >= self.min_step:
                return False
            s = self.s[-1] + ds
        else:
            s = 0.0
        self.xs.append(float(x))
        self.ys.append(float(y))
        self.s.append(s)
        if len(self.xs) > self.keep:
            del self.xs[0], self.ys[0], self.s[0]
        return True

    def newest(self, back: int = 0) -> tuple[float, float]:
        """The newest recorded point (``back`` records earlier)."""
        return self.xs[-1 - back], self.ys[-1 - back]

    def closest_index(self, x: float, y: float) -> int:
        """Index (oldest first) of the recorded point nearest to ``(x, y)`` (the newest if < 2)."""
        n = len(self.xs)
        if n < 2:
            return n - 1
        d2 = (np.asarray(self.xs) - x) ** 2 + (np.asarray(self.ys) - y) ** 2
        return int(np.argmin(d2))

    def lookahead_point(self, x: float, y: float, delta: float) -> tuple[float, float]:
        """FTL's target: ``delta`` along the recorded path beyond the point nearest ``(x, y)``."""
        i0 = self.closest_index(x, y)
        s0 = self.s[i0] + delta - 1e-12
        for j in range(i0, len(self.xs)):
            if self.s[j] >= s0:
                return self.xs[j], self.ys[j]
        return self.newest()

    def const_distance_point(self, distance: float) -> tuple[float, float]:
        """FTL-CD's target: the newest point at least ``distance`` (Euclidean) from the newest."""
        nx, ny = self.newest()
        for j in range(len(self.xs) - 1, -1, -1):
            if math.hypot(self.xs[j] - nx, self.ys[j] - ny) >= distance:
                return self.xs[j], self.ys[j]
        return nx, ny


class ModeState(Protocol):
    """One run of a mode: ``command`` maps one tether reading to ``(V, Omega)``."""

    def command(
        self, x: float, y: float, g: float, l_m: float, theta_m: float
    ) -> tuple[float, float]:
        """Commanded forward speed (m/s) and yaw rate (rad/s) for a robot at ``(x, y, g)``."""
        ...  # pragma: no cover - protocol


class LawState:
    """One run of a memoryless law (PJ, FTL, FTL-CD, the joystick modes) inside another mode.

    A law whose target finder records the path (FTL, FTL-CD) records the
    estimated tip (robot + ``l_m`` along ``theta_m``) in its own App. C buffer
    and steers to the finder's target on it.

    Parameters
    ----------
    law
        The controller.
    robot
        The robot (its wheel track feeds the printed Pseudo-Joystick law).
    """

    def __init__(self, law: TetherController, robot: FollowerRobot) -> None:
        self.law = law
        self.b = robot.wheel_track
        self.finder = law.target_finder
        self.rec = None
        if self.finder.records_path:
            self.rec = TipRecorder(law.buffer_size, law.min_step)  # type: ignore[attr-defined]

    def command(
        self, x: float, y: float, g: float, l_m: float, theta_m: float
    ) -> tuple[float, float]:
        """``(V, Omega)`` of the law for one reading."""
        if self.rec is None:
            return self.law.command(l_m, theta_m, self.b)
        self.rec.record(x + l_m * math.cos(g + theta_m), y + l_m * math.sin(g + theta_m))
        tx, ty = self.finder.point(self.rec, x, y, self.law.search_distance())
        phi = wrap_angle(math.atan2(ty - y, tx - x) - g)
        return self.law.command(l_m, phi, self.b)


def start_state(mode: TetherController, robot: FollowerRobot) -> ModeState:
    """A fresh run state of any mode (its own for a stepwise mode, :class:`LawState` otherwise).

    Parameters
    ----------
    mode
        The controller.
    robot
        The robot.
    """
    if mode.stepwise:
        return mode.start(robot)  # type: ignore[attr-defined,no-any-return]
    return LawState(mode, robot)


def limited_command(
    robot: FollowerRobot, v: float, om: float, wheels: tuple[float, float]
) -> tuple[float, float, float, float]:
    """Apply the wheel speed and acceleration limits to ``(V, Omega)``.

    Both wheels are scaled by one factor so that neither exceeds the speed limit
    (the curvature is kept), then each changes by at most one acceleration step
    from ``wheels`` (the previous wheel speeds), as in the compiled loop.

    Parameters
    ----------
    robot
        The robot and its limits.
    v, om
        Demanded forward speed (m/s) and yaw rate (rad/s).
    wheels
        Previous ``(omega_L, omega_R)`` in rad/s.

    Returns
    -------
    tuple
        ``(V, Omega, omega_L, omega_R)`` applied.
    """
    b, r = robot.wheel_track, robot.wheel_radius
    wl, wr = (v - 0.5 * b * om) / r, (v + 0.5 * b * om) / r
    if not robot.limited:
        return v, om, wl, wr
    wmax, astep = robot.max_wheel_speed, robot.max_wheel_acceleration * robot.sample_time
    scale = 1.0 / max(1.0, max(abs(wl), abs(wr)) / wmax)
    wl, wr = wl * scale, wr * scale
    wl = min(max(min(max(wl, wheels[0] - astep), wheels[0] + astep), -wmax), wmax)
    wr = min(max(min(max(wr, wheels[1] - astep), wheels[1] + astep), -wmax), wmax)
    return 0.5 * r * (wl + wr), r * (wr - wl) / b, wl, wr


def _arc(
    x: float, y: float, g: float, v: float, om: float, dt: float
) -> tuple[float, float, float]:
    """Exact arc of constant ``(V, Omega)`` over ``dt`` (App. C ``dead_reckon``)."""
    h = 0.5 * om * dt
    chord = v * dt * (math.sin(h) / h if abs(h) > 1e-300 else 1.0)
    return x + chord * math.cos(g + h), y + chord * math.sin(g + h), g + 2.0 * h


def _one_run(
    mode: TetherController,
    leader: NDArray[np.float64],
    pose: tuple[float, float, float],
    robot: FollowerRobot,
    noise: tuple[NDArray[np.float64], NDArray[np.float64]] | None,
) -> NDArray[np.float64]:
    """One member: rows ``x, y, g, V, Omega, l_m, theta_m`` per period, (N, 7)."""
    sense = sensor_step(False)
    state = start_state(mode, robot)
    x, y, g = pose
    wheels = (0.0, 0.0)
    ox, oy, hh, dt = robot.winch_offset_x, robot.winch_offset_y, robot.tip_height, robot.sample_time
    out = np.empty((len(leader), 7))
    for k, (tx, ty) in enumerate(leader.tolist()):
        lm, th = sense(x, y, g, tx, ty, ox, oy, hh)
        if noise is not None:
            lm, th = lm + noise[0][k], th + noise[1][k]
        v, om = state.command(x, y, g, lm, th)
        v, om, wl, wr = limited_command(robot, v, om, wheels)
        wheels = (wl, wr)
        out[k] = (x, y, g, v, om, lm, th)
        if not (math.isfinite(v) and math.isfinite(om)):
            out[k:] = math.nan
            break
        x, y, g = _arc(x, y, g, v, om, dt)
    return out


def run_stepwise(
    controllers: tuple[TetherController, ...],
    leader: NDArray[np.float64],
    pose: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    robot: FollowerRobot,
    rng: np.random.Generator,
) -> dict[str, NDArray[np.float64]]:
    """Runs of stepwise modes, one member after another; histories are (B, N).

    Parameters
    ----------
    controllers
        The members.
    leader
        Leader positions per period in m, (N, 2).
    pose
        Initial ``(x, y, heading)`` of each member, three (B,) arrays.
    robot
        The robot (its sensor noise is drawn from ``rng``).
    rng
        Random numbers of the sensor noise.

    Returns
    -------
    dict
        ``x, y, g, v, om, l, th`` as in the compiled loop.
    """
    n = len(leader)
    runs = []
    for i, c in enumerate(controllers):
        noise = None
        if robot.noisy:
            noise = (
                rng.normal(0.0, 1.0, n) * robot.length_noise_std,
                rng.normal(0.0, 1.0, n) * robot.angle_noise_std,
            )
        p0 = (float(pose[0][i]), float(pose[1][i]), float(pose[2][i]))
        runs.append(_one_run(c, leader, p0, robot, noise))
    stacked = np.stack(runs)  # (B, N, 7)
    names: Any = ("x", "y", "g", "v", "om", "l", "th")
    return {k: stacked[:, :, j].copy() for j, k in enumerate(names)}
