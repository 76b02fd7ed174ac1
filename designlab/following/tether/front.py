"""Front following: the robot walks ahead of its leader (Allan 2015 Sec. 4.3, App. C modes 40, 42).

* :class:`FrontJoystick` (Sec. 4.3.2, eqs. 4.3-4.5, mode 40): the tether points
  backwards (``theta_d = pi``); ``V = -k_V (l_m - l_d)`` (the user closing in
  pushes the robot on, falling back pulls it back; the code's forward-only clip
  is commented out) and ``Omega = k_O e_theta`` with
  ``e_theta = wrap(theta_m - theta_d)``, but ``Omega = 0`` when
  ``|e_theta| > pi/2``. The printed eq. 4.5 has the two cases the other way
  round and uses phi for phi_f (A13); the code is followed: steer only while the
  tether is within 90 degrees of straight behind.
* :class:`FrontVelJoystick` (code only, mode 42): 5-sample buffers of ``l_m``
  and ``theta_m`` give the tip's velocity *relative to the robot*
  ``(l_new cos th_new - l_old cos th_old, ...)/(dt (size + 1))``;
  ``V = |v_tip|``, ``Omega = k_O atan2(v_y, v_x)``. As coded the time span is
  ``dt (size + 1)`` for ``size - 1`` sample intervals, and no tether length is
  held (``k_V`` and ``l_d`` are unused): a robot ahead of a leader walking
  straight at ``v`` settles where ``V = (4/6)(v - V)``, i.e. ``V = 0.4 v``
  (``docs/tether_modes.md``).

Both start ``l_d`` ahead of the leader, facing the path's heading.

Examples
--------
>>> fj = FrontJoystick()
>>> [round(u, 6) for u in fj.command(l_m=0.8, phi=3.0)]  # user 0.2 m close, 0.14 rad off
[0.2, -0.212389]
>>> fj.command(l_m=1.0, phi=1.0)      # tether more than 90 degrees off behind: no turn
(0.0, 0.0)
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from functools import cache
from typing import Any, ClassVar

import casadi as ca

from designlab.following.tether.controllers import TetherController
from designlab.following.tether.model import wrap_angle
from designlab.following.tether.parameters import FollowerRobot
from designlab.following.tether.side import side_pose
from designlab.following.tether.stepwise import StepwiseController
from designlab.params import declared, param

__all__ = ["FrontJoystick", "FrontVelJoystick"]


def _gain(symbol: str, unit: str, doc: str, default: float) -> Any:
    return param(symbol, unit, doc=doc, gt=0, le=1e3, default=default)


def _cap(symbol: str, unit: str, doc: str) -> Any:
    return param(symbol, unit, doc=doc, gt=0, le=1e6, default=100.0)


def _desired_length() -> Any:
    return param("l_d", "m", doc="desired tether length (robot ahead)", gt=0, le=10, default=1.0)


def _desired_angle() -> Any:
    return param(
        "theta_d",
        "rad",
        doc="tether angle held (pi: straight behind)",
        ge=-math.pi,
        le=math.pi,
        default=math.pi,
    )


@declared
@dataclass(frozen=True)
class FrontJoystick(TetherController):
    """Front Joystick: walk ahead of the leader (Allan 2015 Sec. 4.3.2, eqs. 4.3-4.5, mode 40).

    ``V = -k_V (l_m - l_d)``, ``e_theta = wrap(theta_m - theta_d)``,
    ``Omega = k_O e_theta`` if ``|e_theta| <= pi/2`` else 0, each clamped above at
    100 as coded. Defaults are App. C's: k_V 1.0, k_O 1.5, l_d 1.0 m, theta_d pi.

    Examples
    --------
    >>> v, om = FrontJoystick().command(l_m=1.3, phi=-3.0)
    >>> round(v, 6), round(om, 6)
    (-0.3, 0.212389)
    """

    desired_length: float = _desired_length()
    speed_gain: float = _gain("k_V", "1/s", "speed per metre of tether length error", 1.0)
    turn_gain: float = _gain("k_O", "1/s", "yaw rate per radian of tether angle error", 1.5)
    desired_angle: float = _desired_angle()
    max_speed: float = _cap("V_max", "m/s", "upper clamp on V (App. C: 100)")
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
        """CasADi law ``(l_m, theta_m, b, l_d, k_V, k_O, theta_d, V_max, Om_max) -> (V, Omega)``.

        Parameters
        ----------
        variant
            Unused (one variant).
        """
        names = ("l_m", "phi", "b", "l_d", "k_V", "k_O", "theta_d", "V_max", "Om_max")
        lm, phi, b, ld, kv, ko, thd, vmax, ommax = (ca.SX.sym(n) for n in names)
        v = -kv * (lm - ld)  # eq. 4.3
        e_th = wrap_angle(phi - thd)  # eq. 4.4
        om = ca.if_else(ca.fabs(e_th) > 0.5 * math.pi, 0.0, ko * e_th)  # eq. 4.5 as coded
        v, om = ca.fmin(v, vmax), ca.fmin(om, ommax)
        return ca.Function(
            "front_joystick", [lm, phi, b, ld, kv, ko, thd, vmax, ommax], [v, om + 0.0 * b]
        )

    def start_pose(self, point: Any, heading: float) -> tuple[float, float, float]:
        """``l_d`` ahead of the leader, facing the path's heading."""
        return side_pose(point, heading, self.desired_length, self.desired_angle)


class _FrontVelRun:
    """One run of FrontVelJoystick (App. C mode 42)."""

    def __init__(self, c: FrontVelJoystick, robot: FollowerRobot) -> None:
        self.c = c
        self.dt = robot.sample_time
        self.ls: deque[float] = deque(maxlen=c.samples)
        self.ths: deque[float] = deque(maxlen=c.samples)

    def command(
        self, x: float, y: float, g: float, l_m: float, theta_m: float
    ) -> tuple[float, float]:
        self.ls.append(l_m)
        self.ths.append(theta_m)
        size = len(self.ls)
        span = self.dt * (size + 1)  # as coded
        vx = (self.ls[-1] * math.cos(self.ths[-1]) - self.ls[0] * math.cos(self.ths[0])) / span
        vy = (self.ls[-1] * math.sin(self.ths[-1]) - self.ls[0] * math.sin(self.ths[0])) / span
        v = min(math.hypot(vx, vy), self.c.max_speed)
        om = min(self.c.turn_gain * math.atan2(vy, vx), self.c.max_turn_rate) if v > 0 else 0.0
        return v, om


@declared
@dataclass(frozen=True)
class FrontVelJoystick(StepwiseController):
    """FrontVelJoystick: move with the tether tip's relative velocity (App. C mode 42, code only).

    ``V = |v_tip|``, ``Omega = k_O atan2(v_tip)`` with ``v_tip`` from the
    newest and oldest of ``samples`` readings over ``dt (samples + 1)`` (as
    coded); k_O 0.8. The code's k_V = 1.0 and l_d = 1.0 m are unused;
    ``desired_length`` only places the robot at the start.

    Examples
    --------
    >>> FrontVelJoystick().turn_gain, FrontVelJoystick().samples
    (0.8, 5)
    """

    desired_length: float = _desired_length()
    turn_gain: float = _gain("k_O", "1/s", "yaw rate per radian of tip velocity direction", 0.8)
    samples: int = param(
        None,
        "",
        doc="length of the l_m and theta_m buffers",
        kind="integer",
        ge=2,
        le=1000,
        default=5,
    )
    desired_angle: float = _desired_angle()
    max_speed: float = _cap("V_max", "m/s", "upper clamp on V (App. C: 100)")
    max_turn_rate: float = _cap("Omega_max", "rad/s", "upper clamp on Omega (App. C: 100)")

    GAINS: ClassVar[tuple[str, ...]] = ("turn_gain",)

    def start(self, robot: FollowerRobot) -> _FrontVelRun:
        """A fresh run state."""
        return _FrontVelRun(self, robot)

    def start_pose(self, point: Any, heading: float) -> tuple[float, float, float]:
        """``l_d`` ahead of the leader, facing the path's heading."""
        return side_pose(point, heading, self.desired_length, self.desired_angle)
