"""The exponential CBF safety filter on the attractive PD field (one QP per period).

The nominal force is the attractive field alone (5.4.2); the simulator's filter
(:class:`designlab.navigation.cbf_filter.CBFFilter`) corrects it each period so that
h'' + k1 h' + k0 h >= 0 for h = d - r3 of every obstacle (``docs/navigation.md``,
"Baselines"). Another method's force filtered the same way is a
:class:`~designlab.navigation.methods.base.Filtered` of it (``"vff_cbf"``).

Examples
--------
>>> from designlab.navigation.methods import METHODS
>>> m = METHODS.get("cbf")
>>> m.filtered, m.batched, m.sampled_margin, m.gains_dict(m.gain_row(None))
(True, False, False, {'k1': 3.0, 'b': 0.25, 'k3': 20.0, 'k5': 17.0})
"""

from __future__ import annotations

from typing import Any

import casadi as ca

from designlab.navigation.field_terms import Forces, Obs, Symbols, pd_attraction
from designlab.navigation.methods.base import NavigationMethod
from designlab.navigation.parameters import EXPERIMENT_GAINS

__all__ = ["CBF", "CBFMethod"]


def _cbf_forces(items: list[Obs], s: Symbols) -> Forces:
    """The CBF filter's nominal field: the PD attraction alone (filtered by the simulator)."""
    return Forces(pd_attraction(s), [ca.SX(0)] * len(items))


class CBFMethod(NavigationMethod):
    """The CBF filter on the PD attraction: default gains those of the experiments."""

    batched = False
    filtered = True

    def default_gains(self) -> Any:
        return EXPERIMENT_GAINS

    def forces(self, items: list[Obs], s: Symbols) -> Forces:
        return _cbf_forces(items, s)


#: The CBF filter on the attractive field (``method="cbf"``).
CBF = CBFMethod(
    "cbf", "CBF", "exponential control-barrier-function filter, d >= r3, on the PD attraction"
)
