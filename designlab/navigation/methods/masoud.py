"""Masoud (2007), a Sec. 2.2.4 baseline: F_a = K1 E, repulsion K3 D, detour K5 |D| in a
fixed rotational sense, which is its gains' ``direction`` (the tie side elsewhere).

Examples
--------
>>> from designlab.navigation.methods import METHODS
>>> m = METHODS.get("masoud")
>>> m.gain_row(None).tolist(), m.gains_dict(m.gain_row(None))
([5.0, 0.0, 24.0, 36.0], {'k1': 5.0, 'k3': 24.0, 'k5': 36.0})
"""

from __future__ import annotations

from typing import Any

import casadi as ca

from designlab.navigation.field_terms import Forces, Obs, Symbols
from designlab.navigation.methods.base import NavigationMethod
from designlab.navigation.parameters import MasoudGains

__all__ = ["MASOUD", "MasoudMethod"]


def _masoud_forces(items: list[Obs], s: Symbols) -> Forces:
    """Masoud (2007): F_a = K1 E, repulsion K3 D, detour K5 |D| in a fixed sense (the tie)."""
    F = s.k1 * s.E
    for it in items:
        rot = s.tie * it.u_perp  # fixed rotational sense (+1 counter-clockwise)
        F = F + ca.if_else(it.c, s.k3 * it.D + s.k5 * it.d * rot, ca.SX.zeros(2))
    return Forces(F, [s.tie] * len(items))


class MasoudMethod(NavigationMethod):
    """Masoud (2007): no attractive damping (no b); its fixed detour sense is the tie side."""

    gains_type = MasoudGains
    used_gains = ("k1", "k3", "k5")
    baseline = True
    fixed_sense = True

    def gains_of_row(self, row: Any, tie_side: str = "+y") -> Any:
        k1, _, k3, k5 = (float(v) for v in row)
        return MasoudGains(k1=k1, k3=k3, k5=k5, direction=1 if tie_side == "+y" else -1)

    def tie(self, gains: Any, tie_side: str) -> int:
        return gains.direction if isinstance(gains, MasoudGains) else super().tie(gains, tie_side)

    def forces(self, items: list[Obs], s: Symbols) -> Forces:
        return _masoud_forces(items, s)


#: Masoud (2007) (``method="masoud"``).
MASOUD = MasoudMethod("masoud", "Masoud", "Masoud (2007), a baseline of Sec. 2.2.4")
