"""Follow the Leader with Constant Distance (Allan 2015 Sec. 2.3.3, App. C mode 21).

Steer to the newest recorded point at least ``l_d`` (Euclidean) from the
leader, ``V = max(0, K_p (l_m - l_d)(1 - K_a |phi|))``, ``Omega = K_b phi``
with the effective positive gains of the code (K_p = 2, K_a = 0.5, K_b = 2;
the printed signs of eqs. 2.20-2.21 would drive the robot backwards;
``docs/following.md``).

Examples
--------
>>> v, om = FollowTheLeaderConstDistance().command(l_m=1.45, phi=0.2)
>>> round(v, 3), round(om, 3)
(0.45, 0.4)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache
from typing import Any, ClassVar

import casadi as ca

from designlab.following.tether.buffer import CONSTANT_DISTANCE, TargetFinder
from designlab.following.tether.laws.base import (
    TetherController,
    buffer_size,
    gain,
    min_step,
    symbols,
    tether_length,
)
from designlab.params import declared

__all__ = ["FollowTheLeaderConstDistance"]


@declared
@dataclass(frozen=True)
class FollowTheLeaderConstDistance(TetherController):
    """Follow the Leader with Constant Distance (Allan 2015 Sec. 2.3.3, App. C mode 21).

    ``V = max(0, K_p (l_m - l_d)(1 - K_a |phi|))``, ``Omega = K_b phi`` with phi
    the direction to the newest recorded point at least l_d (Euclidean) from the
    leader. The effective gains are the code's: App. C has K_p = -2 and K_b = -2
    with extra minus signs, i.e. 2.0 each; K_a 0.5; l_d 1.2 m.

    Examples
    --------
    >>> FollowTheLeaderConstDistance().short
    'FTL-CD'
    """

    desired_length: float = tether_length(1.2)
    speed_gain: float = gain("K_p", "1/s", "effective speed gain", 2.0)
    angle_gain: float = gain(
        "K_a", "1/rad", "angle gain: 1 - K_a |phi| slows a robot turned away", 0.5, ge=0
    )
    turn_gain: float = gain("K_b", "1/s", "effective turn gain", 2.0)
    min_step: float = min_step()
    buffer_size: int = buffer_size()

    label: ClassVar[str] = "Follow the Leader with Constant Distance"
    short: ClassVar[str] = "FTL-CD"
    doc: ClassVar[str] = "steer to the recorded point l_d from the leader (Sec. 2.3.3, mode 21)"
    target_finder: ClassVar[TargetFinder] = CONSTANT_DISTANCE
    linear: ClassVar[bool] = True
    measured: ClassVar[bool] = True
    GAINS: ClassVar[tuple[str, ...]] = ("speed_gain", "angle_gain", "turn_gain")
    BOUNDS: ClassVar[dict[str, tuple[float, float]]] = {
        "speed_gain": (0.1, 20.0),
        "angle_gain": (0.0, 1.0 / math.pi),
        "turn_gain": (0.1, 20.0),
    }
    LAW_PARAMS: ClassVar[tuple[str, ...]] = (
        "desired_length",
        "speed_gain",
        "angle_gain",
        "turn_gain",
    )
    SWEEP_FIELDS: ClassVar[tuple[str, ...]] = ("angle_gain",)

    @classmethod
    @cache
    def law_function(cls, variant: str = "") -> ca.Function:
        """CasADi function ``(l_m, phi, b, l_d, K_p, K_a, K_b) -> (V, Omega)``.

        Parameters
        ----------
        variant
            Unused (one variant).
        """
        lm, phi, b, ld, kp, ka, kb = symbols("l_m", "phi", "b", "l_d", "K_p", "K_a", "K_b")
        v = ca.fmax(kp * (lm - ld) * (1.0 - ka * ca.fabs(phi)), 0.0)  # eq. 2.20, effective
        return ca.Function("ftlcd", [lm, phi, b, ld, kp, ka, kb], [v, kb * phi + 0.0 * b])

    def effective_loop(self, speed: Any, wheel_track: float) -> tuple[Any, Any, Any]:
        """K = K_b, L = v/K_p (the target moves with the leader), steady length l_d + v/K_p.

        Parameters
        ----------
        speed
            Leader speed in m/s.
        wheel_track
            Wheel track b in m (unused).
        """
        return (
            self.turn_gain,
            speed / self.speed_gain,
            self.desired_length + speed / self.speed_gain,
        )
