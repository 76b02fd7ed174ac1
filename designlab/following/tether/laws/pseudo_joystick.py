"""Pseudo-Joystick: drive along the tether (Allan 2015 Sec. 2.3.1, App. C mode 10).

The default is the App. C code, ``V = k_V max(0, l_m - l_d)``,
``Omega = k_O theta``; ``law="printed"`` gives eqs. (2.1)-(2.2) with the
steering sign fixed to turn toward the tether, ``Omega = (2V/b) sin theta``.
Defaults are the App. C values (the thesis's only numerical gains); see
``docs/following.md``.

Examples
--------
>>> PseudoJoystick(turn_gain=-1.0)
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: PseudoJoystick.turn_gain = -1.0 1/s is not allowed: ...
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import Any, ClassVar

import casadi as ca

from designlab.following.tether.laws.base import TetherController, gain, symbols, tether_length
from designlab.params import declared, param

__all__ = ["PseudoJoystick"]


@declared
@dataclass(frozen=True)
class PseudoJoystick(TetherController):
    """Pseudo-Joystick: drive along the tether (Allan 2015 Sec. 2.3.1, App. C mode 10).

    ``law="coded"`` (default): ``V = k_V max(0, l_m - l_d)``, ``Omega = k_O theta``.
    ``law="printed"``: eqs. (2.1)-(2.2), ``V = k_V (l_m - l_d)``,
    ``Omega = (2V/b) sin theta`` (sign fixed to steer toward the tether). The
    defaults are App. C's: l_d 1.0 m, k_V 5.0, k_O 12.0.

    Examples
    --------
    >>> pj = PseudoJoystick()
    >>> pj.command(l_m=0.8, phi=0.5)       # tether slack: rotate in place
    (0.0, 6.0)
    >>> v, om = PseudoJoystick(law="printed").command(l_m=1.1, phi=0.5)
    >>> round(v, 3), round(om, 4)
    (0.5, 1.7122)
    """

    desired_length: float = tether_length(1.0)
    speed_gain: float = gain("k_V", "1/s", "speed gain", 5.0)
    turn_gain: float = gain("k_O", "1/s", "turn gain", 12.0)
    law: str = param(
        kind="choice",
        choices=("coded", "printed"),
        doc="the App. C code or the printed eqs. 2.1-2.2",
        default="coded",
    )

    label: ClassVar[str] = "Pseudo-Joystick"
    short: ClassVar[str] = "PJ"
    doc: ClassVar[str] = "drive along the tether (Sec. 2.3.1, App. C mode 10)"
    linear: ClassVar[bool] = True
    measured: ClassVar[bool] = True
    GAINS: ClassVar[tuple[str, ...]] = ("speed_gain", "turn_gain")
    BOUNDS: ClassVar[dict[str, tuple[float, float]]] = {
        "speed_gain": (0.1, 20.0),
        "turn_gain": (0.1, 20.0),
    }
    LAW_PARAMS: ClassVar[tuple[str, ...]] = ("desired_length", "speed_gain", "turn_gain")
    SWEEP_FIELDS: ClassVar[tuple[str, ...]] = ("desired_length", "speed_gain", "turn_gain")

    def law_key(self) -> str:
        """Which variant of the law this instance uses (``law``)."""
        return self.law

    @classmethod
    @cache
    def law_function(cls, variant: str = "coded") -> ca.Function:
        """CasADi function ``(l_m, phi, b, l_d, k_V, k_O) -> (V, Omega)`` of one variant.

        Parameters
        ----------
        variant
            ``"coded"`` or ``"printed"``.
        """
        lm, phi, b, ld, kv, ko = symbols("l_m", "phi", "b", "l_d", "k_V", "k_O")
        if variant == "printed":
            v = kv * (lm - ld)  # eq. 2.1
            om = 2.0 * v / b * ca.sin(phi)  # eq. 2.2 with phi = theta (2.3), sign fixed
        else:
            v = kv * ca.fmax(lm - ld, 0.0)  # App. C mode 10
            om = ko * phi
        return ca.Function(f"pj_{variant or 'coded'}", [lm, phi, b, ld, kv, ko], [v, om])

    def effective_loop(self, speed: Any, wheel_track: float) -> tuple[Any, Any, Any]:
        """K = k_O (printed: 2v/b), L = the steady tether length l_d + v/k_V (Sec. 2.5.2).

        Parameters
        ----------
        speed
            Leader speed in m/s.
        wheel_track
            Wheel track b in m (the printed law).
        """
        l_ss = self.desired_length + speed / self.speed_gain
        k = 2.0 * speed / wheel_track if self.law == "printed" else self.turn_gain
        return k, l_ss, l_ss
