"""Ge & Cui (2002), a Sec. 2.2.4 baseline: (2.2.12)-(2.2.13) on the PD attraction.

Examples
--------
>>> from designlab.navigation.methods import METHODS
>>> m = METHODS.get("ge_cui")
>>> m.label, m.baseline, m.gains_dict(m.gain_row(None))
('Ge & Cui', True, {'k1': 1.0, 'b': 0.75, 'k3': 14.2, 'k5': 14.2})
"""

from __future__ import annotations

import casadi as ca

from designlab.navigation.field_terms import Forces, Obs, Symbols, pd_attraction
from designlab.navigation.methods.base import NavigationMethod
from designlab.navigation.parameters import GeCuiGains

__all__ = ["GE_CUI", "GeCuiMethod"]


def _ge_cui_forces(items: list[Obs], s: Symbols) -> Forces:
    """Ge & Cui (2002): (2.2.12)-(2.2.13) on the PD attraction."""
    F = pd_attraction(s)
    sigmas = []
    for it in items:
        r3 = it.geo.r3
        gap2 = (it.dd - r3) ** 2
        beta_rate = ca.dot(it.u_perp, s.v - it.vo) / it.dd
        rep = (s.k3 - it.d_rate / s.amax) / gap2
        det = ca.fabs(s.k5 * it.d_rate * beta_rate * it.dd) / gap2
        side = ca.sign(beta_rate)
        sigmas.append(side)
        F = F + ca.if_else(it.c, rep * it.u + det * side * it.u_perp, ca.SX.zeros(2))
    return Forces(F, sigmas)


class GeCuiMethod(NavigationMethod):
    """Ge & Cui (2002), with :class:`~designlab.navigation.parameters.GeCuiGains`."""

    gains_type = GeCuiGains
    baseline = True

    def forces(self, items: list[Obs], s: Symbols) -> Forces:
        return _ge_cui_forces(items, s)


#: Ge & Cui (2002) (``method="ge_cui"``).
GE_CUI = GeCuiMethod("ge_cui", "Ge & Cui", "Ge & Cui (2002), a baseline of Sec. 2.2.4")
