"""Front Joystick: the robot walks ahead of its leader (Allan 2015 Sec. 4.3.2, mode 40).

The tether points backwards (``theta_d = pi``); ``V = -k_V (l_m - l_d)`` (the
user closing in pushes the robot on, falling back pulls it back; the code's
forward-only clip is commented out) and ``Omega = k_O e_theta`` with
``e_theta = wrap(theta_m - theta_d)``, but ``Omega = 0`` when
``|e_theta| > pi/2``. The printed eq. 4.5 has the two cases the other way
round and uses phi for phi_f (A13); the code is followed: steer only while the
tether is within 90 degrees of straight behind. The robot starts ``l_d`` ahead
of the leader, facing the path's heading (``docs/tether_modes.md``).

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
from dataclasses import dataclass
from functools import cache
from typing import Any, ClassVar

import casadi as ca

from designlab.following.tether.laws.base import (
    TetherController,
    angle,
    cap,
    gain,
    side_pose,
    tether_length,
)
from designlab.following.tether.model import wrap_angle
from designlab.params import declared

__all__ = ["FrontJoystick"]


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

    desired_length: float = tether_length(
        1.0, doc="desired tether length (robot ahead)", typical=None
    )
    speed_gain: float = gain("k_V", "1/s", "speed per metre of tether length error", 1.0)
    turn_gain: float = gain("k_O", "1/s", "yaw rate per radian of tether angle error", 1.5)
    desired_angle: float = angle("theta_d", "tether angle held (pi: straight behind)", math.pi)
    max_speed: float = cap("V_max", "m/s", "upper clamp on V (App. C: 100)")
    max_turn_rate: float = cap("Omega_max", "rad/s", "upper clamp on Omega (App. C: 100)")

    label: ClassVar[str] = "Front Joystick"
    short: ClassVar[str] = "FJ"
    doc: ClassVar[str] = "walk ahead of the leader on the tether (Sec. 4.3.2, mode 40)"
    placement: ClassVar[str] = "front"
    brakeable: ClassVar[bool] = False
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
