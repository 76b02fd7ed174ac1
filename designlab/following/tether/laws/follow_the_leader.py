"""Follow the Leader: track the recorded leader path (Allan 2015 Sec. 2.3.2, App. C mode 20).

Record the tether tip in a path buffer, take the recorded point nearest to
the robot, look ahead ``delta`` along the recorded path,
``V = k_V (l_m - l_d)`` (no clip), ``Omega = k_O phi``. Defaults are App. C's
(``docs/following.md``).

Examples
--------
>>> ftl = FollowTheLeader(lookahead=0.4)
>>> ftl.gains
{'speed_gain': 1.0, 'turn_gain': 3.0, 'lookahead': 0.4}
>>> v, om = ftl.command(l_m=1.5, phi=0.1, wheel_track=0.28)
>>> round(v, 3), round(om, 3)
(0.5, 0.3)
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import Any, ClassVar

import casadi as ca

from designlab.following.tether.buffer import LOOKAHEAD, TargetFinder
from designlab.following.tether.laws.base import (
    TetherController,
    buffer_size,
    gain,
    length,
    min_step,
    symbols,
    tether_length,
)
from designlab.params import declared

__all__ = ["FollowTheLeader"]


@declared
@dataclass(frozen=True)
class FollowTheLeader(TetherController):
    """Follow the Leader: track the recorded leader path (Allan 2015 Sec. 2.3.2, App. C mode 20).

    ``V = K_V (l_m - l_d)`` (eq. 2.17), ``Omega = K_Omega phi`` (eq. 2.18) with
    phi the direction to the point ``lookahead`` along the recorded path beyond
    the nearest recorded point (the thesis's rule is b < delta < 2b). The
    defaults are App. C's: l_d 1.0 m, K_V 1.0, K_Omega 3.0, delta 0.5 m.

    Examples
    --------
    >>> FollowTheLeader().lookahead, FollowTheLeader().buffer_size
    (0.5, 300)
    """

    desired_length: float = tether_length(1.0)
    speed_gain: float = gain("K_V", "1/s", "speed gain", 1.0)
    turn_gain: float = gain("K_Omega", "1/s", "turn gain", 3.0)
    lookahead: float = length("delta", "FTL look-ahead", 0.5, typical=(0.28, 0.56))
    min_step: float = min_step()
    buffer_size: int = buffer_size()

    label: ClassVar[str] = "Follow the Leader"
    short: ClassVar[str] = "FTL"
    doc: ClassVar[str] = "track the recorded leader path with a look-ahead (Sec. 2.3.2, mode 20)"
    target_finder: ClassVar[TargetFinder] = LOOKAHEAD
    linear: ClassVar[bool] = True
    GAINS: ClassVar[tuple[str, ...]] = ("speed_gain", "turn_gain", "lookahead")
    BOUNDS: ClassVar[dict[str, tuple[float, float]]] = {
        "speed_gain": (0.1, 20.0),
        "turn_gain": (0.1, 20.0),
        "lookahead": (0.05, 1.0),
    }
    LAW_PARAMS: ClassVar[tuple[str, ...]] = ("desired_length", "speed_gain", "turn_gain")
    SWEEP_FIELDS: ClassVar[tuple[str, ...]] = ("lookahead",)

    @classmethod
    @cache
    def law_function(cls, variant: str = "") -> ca.Function:
        """CasADi function ``(l_m, phi, b, l_d, K_V, K_Omega) -> (V, Omega)``.

        Parameters
        ----------
        variant
            Unused (one variant).
        """
        lm, phi, b, ld, kv, ko = symbols("l_m", "phi", "b", "l_d", "k_V", "k_O")
        return ca.Function("ftl", [lm, phi, b, ld, kv, ko], [kv * (lm - ld), ko * phi + 0.0 * b])

    def effective_loop(self, speed: Any, wheel_track: float) -> tuple[Any, Any, Any]:
        """K = K_Omega, L = delta, steady tether length l_d + v/K_V.

        Parameters
        ----------
        speed
            Leader speed in m/s.
        wheel_track
            Wheel track b in m (unused).
        """
        return self.turn_gain, self.lookahead, self.desired_length + speed / self.speed_gain
