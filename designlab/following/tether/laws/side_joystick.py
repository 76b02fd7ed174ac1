"""Side Joystick: the robot walks beside its leader (Allan 2015 Sec. 4.2.2, eqs. 4.1-4.2, mode 30).

The tether angle drives and the tether length steers,
``V = -k_V (theta_m - theta_d)`` only while ``theta_m < theta_d`` (else 0),
``Omega = k_O (l_m - l_H)`` and ``Omega = 0`` whenever ``V = 0``; the code's
upper clamps ``V <= 100``, ``Omega <= 100`` are kept (effectively none).
The text attributes the gains the other way round (A11); the code is followed.
With ``theta_d = +pi/2`` the robot walks on the leader's right (the leader is
on the robot's left), as coded, and starts abreast of the leader at the side
offset (:meth:`SideJoystick.start_pose`; ``docs/tether_modes.md``).

Examples
--------
>>> sj = SideJoystick()
>>> sj.command(l_m=1.2, phi=1.0)        # tether ahead of abeam: drive, steer to close
(0.7134954084936207, 0.36)
>>> sj.command(l_m=1.2, phi=2.0)        # leader behind abeam: wait (and do not turn)
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
from designlab.params import declared

__all__ = ["SideJoystick"]


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

    desired_length: float = tether_length(
        1.0, "l_H", "side offset: the tether length held abreast", typical=None
    )
    speed_gain: float = gain("k_V", "1/s", "speed per radian of tether angle error", 1.25)
    turn_gain: float = gain("k_O", "1/s", "yaw rate per metre of tether length error", 1.8)
    desired_angle: float = angle(
        "theta_d", "tether angle held (+pi/2: leader on the left)", math.pi / 2
    )
    max_speed: float = cap("V_max", "m/s", "upper clamp on V (App. C: 100, effectively none)")
    max_turn_rate: float = cap("Omega_max", "rad/s", "upper clamp on Omega (App. C: 100)")

    label: ClassVar[str] = "Side Joystick"
    short: ClassVar[str] = "Joystick"
    doc: ClassVar[str] = "walk beside the leader on the tether angle (Sec. 4.2.2, mode 30)"
    placement: ClassVar[str] = "side"
    turn_claim: ClassVar[str] = "the thesis: Side Joystick distorted on the inside, Fig. 4.5"
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
