"""Side following: the robot walks beside its leader (Allan 2015 Sec. 4.2, App. C modes 30, 31).

* :class:`SideJoystick` (Sec. 4.2.2, eqs. 4.1-4.2, mode 30): the tether angle
  drives and the tether length steers,
  ``V = -k_V (theta_m - theta_d)`` only while ``theta_m < theta_d`` (else 0),
  ``Omega = k_O (l_m - l_H)`` and ``Omega = 0`` whenever ``V = 0``; the code's
  upper clamps ``V <= 100``, ``Omega <= 100`` are kept (effectively none).
  The text attributes the gains the other way round (A11); the code is followed.
* :class:`SideTracking` (Sec. 4.2.4, mode 31): the newest 4 tips of a 10-point
  buffer give the leader's (backward-pointing) tangent; rotated by
  ``offset_angle`` (pi/2 as coded; the text says pi, A12) and scaled to
  ``offset_length`` it gives the side point K beside the newest tip; K is
  recorded in a 300-point path buffer and tracked with FTL's nearest point plus
  look-ahead, ``V = k_V (|K - P| - l_d)``, ``Omega = k_O phi`` (the code writes
  the wheel speeds ``(k_V e_l -+ k_O b phi/2)/r``, the same thing). Before K
  exists the code drives with ``phi = 0`` and ``e_l = 0.5``.

With ``theta_d = +pi/2`` and ``offset_angle = +pi/2`` the robot walks on the
leader's right (the leader is on the robot's left), as coded. Both modes start
abreast of the leader at the side offset (:meth:`SideJoystick.start_pose`).

Examples
--------
>>> sj = SideJoystick()
>>> sj.command(l_m=1.2, phi=1.0)        # tether ahead of abeam: drive, steer to close
(0.7134954084936207, 0.36)
>>> sj.command(l_m=1.2, phi=2.0)        # leader behind abeam: wait (and do not turn)
(0.0, 0.0)
>>> st = SideTracking()
>>> st.offset_length, st.side_gap, st.lookahead
(1.0, 0.1, 0.6)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache
from typing import Any, ClassVar

import casadi as ca
import numpy as np

from designlab.following.tether.controllers import TetherController
from designlab.following.tether.model import wrap_angle
from designlab.following.tether.parameters import FollowerRobot
from designlab.following.tether.stepwise import StepwiseController, TipRecorder
from designlab.params import declared, param

__all__ = ["SideJoystick", "SideTracking", "lateral_offset", "side_pose"]


def _gain(symbol: str, unit: str, doc: str, default: float) -> Any:
    return param(symbol, unit, doc=doc, gt=0, le=1e3, default=default)


def _length(symbol: str, doc: str, default: float, *, lower: float = 0.0) -> Any:
    return param(symbol, "m", doc=doc, gt=lower, le=10, default=default)


def _angle(symbol: str, doc: str, default: float) -> Any:
    return param(symbol, "rad", doc=doc, ge=-math.pi, le=math.pi, default=default)


def _cap(symbol: str, unit: str, doc: str) -> Any:
    return param(symbol, unit, doc=doc, gt=0, le=1e6, default=100.0)


def side_pose(
    point: Any, heading: float, offset: float, angle: float
) -> tuple[float, float, float]:
    """Pose ``offset`` from ``point`` at ``angle`` from ``heading`` *as seen from the robot*.

    The robot faces ``heading`` and sees the point at ``angle`` (``+pi/2``: on
    its left, so the robot is on the point's right).

    Parameters
    ----------
    point
        The leader's position ``(x, y)`` in m.
    heading
        The robot's heading in rad.
    offset
        Distance in m.
    angle
        Direction of the point relative to the robot's heading in rad.

    Examples
    --------
    >>> [round(v, 9) for v in side_pose((0.0, 0.0), 0.0, 1.0, math.pi / 2)]
    [0.0, -1.0, 0.0]
    """
    px, py = float(point[0]), float(point[1])
    d = heading + angle
    return px - offset * math.cos(d), py - offset * math.sin(d), float(heading)


@declared
@dataclass(frozen=True)
class SideJoystick(TetherController):
    """Side Joystick: walk beside the leader (Allan 2015 Sec. 4.2.2, eqs. 4.1-4.2, mode 30).

    ``V = -k_V (theta_m - theta_d)`` if ``theta_m < theta_d`` else 0,
    ``Omega = k_O (l_m - l_H)``, ``Omega = 0`` when ``V = 0``; defaults are App. C's
    (k_V 1.25, k_O 1.8, l_H 1.0 m, theta_d pi/2). ``desired_length`` is the side
    offset l_H (the tether length held while abreast).

    Examples
    --------
    >>> v, om = SideJoystick(desired_length=0.56).command(l_m=0.6, phi=1.2)
    >>> round(v, 4), round(om, 4)
    (0.4635, 0.072)
    """

    desired_length: float = _length("l_H", "side offset: the tether length held abreast", 1.0)
    speed_gain: float = _gain("k_V", "1/s", "speed per radian of tether angle error", 1.25)
    turn_gain: float = _gain("k_O", "1/s", "yaw rate per metre of tether length error", 1.8)
    desired_angle: float = _angle(
        "theta_d", "tether angle held (+pi/2: leader on the left)", math.pi / 2
    )
    max_speed: float = _cap("V_max", "m/s", "upper clamp on V (App. C: 100, effectively none)")
    max_turn_rate: float = _cap("Omega_max", "rad/s", "upper clamp on Omega (App. C: 100)")

    target: ClassVar[str] = "tether"
    GAINS: ClassVar[tuple[str, ...]] = ("speed_gain", "turn_gain")
    LAW_PARAMS: ClassVar[tuple[str, ...]] = (
        "desired_length",
        "speed_gain",
        "turn_gain",
        "desired_angle",
        "max_speed",
        "max_turn_rate",
    )

    @classmethod
    @cache
    def law_function(cls, variant: str = "") -> ca.Function:
        """CasADi law ``(l_m, theta_m, b, l_H, k_V, k_O, theta_d, V_max, Om_max) -> (V, Omega)``.

        Parameters
        ----------
        variant
            Unused (one variant).
        """
        names = ("l_m", "phi", "b", "l_H", "k_V", "k_O", "theta_d", "V_max", "Om_max")
        lm, phi, b, lh, kv, ko, thd, vmax, ommax = (ca.SX.sym(n) for n in names)
        e_th = phi - thd  # as coded: not wrapped
        v = ca.if_else(e_th < 0, -kv * e_th, 0.0)  # eq. 4.1, forward only
        om = ca.if_else(v == 0, 0.0, ko * (lm - lh))  # eq. 4.2
        v, om = ca.fmin(v, vmax), ca.fmin(om, ommax)
        return ca.Function(
            "side_joystick", [lm, phi, b, lh, kv, ko, thd, vmax, ommax], [v, om + 0.0 * b]
        )

    def start_pose(self, point: Any, heading: float) -> tuple[float, float, float]:
        """Abreast of the leader at the side offset, facing the path's heading."""
        return side_pose(point, heading, self.desired_length, self.desired_angle)


class _SideTrackingRun:
    """One run of Side Tracking (App. C mode 31)."""

    TANGENT_POINTS: ClassVar[int] = 4

    def __init__(self, c: SideTracking, robot: FollowerRobot) -> None:
        self.c = c
        self.b = robot.wheel_track
        self.tips = TipRecorder(c.tip_buffer_size, c.min_step)
        self.side = TipRecorder(c.buffer_size, c.min_step)
        self.rot = (math.cos(c.offset_angle), math.sin(c.offset_angle))

    def side_point(self) -> tuple[float, float] | None:
        """K: the newest tip plus the rotated, scaled backward tangent (None before 4 tips)."""
        n = self.TANGENT_POINTS
        if len(self.tips) < n:
            return None
        nx, ny = self.tips.newest()
        ox, oy = self.tips.newest(n - 1)
        tx, ty = (ox - nx) / (n - 1), (oy - ny) / (n - 1)  # mean difference, pointing backwards
        norm = math.hypot(tx, ty)
        if not norm > 0.0:
            return None
        c, s = self.rot
        scale = self.c.offset_length / norm
        return nx + scale * (c * tx - s * ty), ny + scale * (s * tx + c * ty)

    def command(
        self, x: float, y: float, g: float, l_m: float, theta_m: float
    ) -> tuple[float, float]:
        c = self.c
        self.tips.record(x + l_m * math.cos(g + theta_m), y + l_m * math.sin(g + theta_m))
        k = self.side_point()
        if k is None:
            phi, e_l = 0.0, 0.5  # as coded, before K exists
        else:
            self.side.record(*k)
            tx, ty = self.side.lookahead_point(x, y, c.lookahead)
            phi = wrap_angle(math.atan2(ty - y, tx - x) - g)
            e_l = math.hypot(k[0] - x, k[1] - y) - c.side_gap
        return c.speed_gain * e_l, c.turn_gain * phi


@declared
@dataclass(frozen=True)
class SideTracking(StepwiseController):
    """Side Tracking: track a point beside the leader's path (Allan 2015 Sec. 4.2.4, mode 31).

    K = newest tip + the backward tangent (mean over 4 tips) rotated by
    ``offset_angle`` and scaled to ``offset_length``; K is recorded and tracked
    with FTL's nearest point plus ``lookahead``; ``V = k_V (|K - P| - l_d)``,
    ``Omega = k_O phi``. Defaults are App. C's (k_V 1.0, k_O 3.0, delta 0.6 m,
    l_d 0.1 m, offset pi/2 and 1.0 m, tip buffer 10, side buffer 300, 0.01 m).
    ``desired_length`` is ``offset_length`` (the tether length while abreast).

    Examples
    --------
    >>> SideTracking(offset_length=0.56).desired_length
    0.56
    """

    offset_length: float = _length("l_H", "side offset of K from the newest tip", 1.0)
    side_gap: float = _length("l_d", "distance to K at which V = 0", 0.1)
    speed_gain: float = _gain("k_V", "1/s", "speed per metre of distance to K", 1.0)
    turn_gain: float = _gain("k_O", "1/s", "yaw rate per radian of target angle", 3.0)
    lookahead: float = _length("delta", "look-ahead along the recorded K path", 0.6)
    offset_angle: float = _angle(
        "offset_angle", "rotation of the backward tangent (+pi/2: right)", math.pi / 2
    )
    min_step: float = param(
        "ds_min", "m", doc="least step between recorded points", gt=0, le=1, default=0.01
    )
    tip_buffer_size: int = param(
        None,
        "",
        doc="tip buffer limit (tangent from its newest 4)",
        kind="integer",
        ge=5,
        le=1000,
        default=10,
    )
    buffer_size: int = param(
        None, "", doc="K path buffer limit", kind="integer", ge=3, le=100_000, default=300
    )

    GAINS: ClassVar[tuple[str, ...]] = ("speed_gain", "turn_gain", "lookahead")

    @property
    def desired_length(self) -> float:  # type: ignore[override]
        """The side offset in m (the tether length while abreast)."""
        return self.offset_length

    def start(self, robot: FollowerRobot) -> _SideTrackingRun:
        """A fresh run state."""
        return _SideTrackingRun(self, robot)

    def start_pose(self, point: Any, heading: float) -> tuple[float, float, float]:
        """Abreast of the leader, on the side ``offset_angle`` puts K."""
        return side_pose(point, heading, self.offset_length, self.offset_angle)


def lateral_offset(robot_xy: Any, leader_xy: Any, heading: Any) -> np.ndarray:
    """Signed distance of the robot left of the leader's heading line, per period (m).

    Parameters
    ----------
    robot_xy, leader_xy
        Positions (N, 2) in m.
    heading
        Leader heading per period in rad, (N,).
    """
    d = np.asarray(robot_xy, float) - np.asarray(leader_xy, float)
    h = np.asarray(heading, float)
    return -np.sin(h) * d[:, 0] + np.cos(h) * d[:, 1]
