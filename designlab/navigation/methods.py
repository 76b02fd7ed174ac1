"""The navigation methods as small strategy objects, registered by their public name.

Each method (the new VFF of Zeng 2011, the baselines of Sec. 2.2.4: Masoud 2007 and
Ge & Cui 2002, and the CBF safety filter) says which gains it takes and their
defaults, how they become a row of the simulator's gain array, whether it has the
Lyapunov stabilising force (and so an audit) and whether it can be batched. The
simulator dispatches through :data:`METHODS`; the force itself is built by
:func:`designlab.navigation.field.build_field` for the same name.

Examples
--------
>>> from designlab.navigation.methods import method_of
>>> m = method_of("masoud")
>>> m.gain_row(None).tolist(), m.gains_dict(m.gain_row(None))
([5.0, 0.0, 24.0, 36.0], {'k1': 5.0, 'k3': 24.0, 'k5': 36.0})
>>> method_of("bug")
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: method = 'bug' is not allowed: must be one of ...
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from designlab.errors import InvalidParameterError
from designlab.navigation.parameters import (
    EXPERIMENT_GAINS,
    GeCuiGains,
    MasoudGains,
    VFFGains,
)
from designlab.params import Param

__all__ = ["METHOD", "METHODS", "STABILISING", "TIE_SIDE", "NavigationMethod", "method_of"]

#: The stabilising force F_L of (5.4.6): ``"lyapunov"`` (on) or ``"off"`` (how the thesis's
#: tables come back, docs/navigation.md).
STABILISING = Param(
    doc="stabilising force F_L of (5.4.6)",
    kind="choice",
    choices=("lyapunov", "off"),
    name="stabilising",
)
#: The detour side where the direction rules leave it open (``"+y"`` or ``"-y"``).
TIE_SIDE = Param(
    doc="detour side where the rules leave it open (docs/navigation.md, 'The force field')",
    kind="choice",
    choices=("+y", "-y"),
    name="tie_side",
)


@dataclass(frozen=True)
class NavigationMethod:
    """One navigation method: its gains and what the simulator does with it.

    Attributes
    ----------
    name
        The public name (``method="vff"``).
    """

    name: str
    GAINS: ClassVar[type] = VFFGains
    #: Whether the method has the Lyapunov stabilising force (and an audit).
    STABILISED: ClassVar[bool] = False
    #: Whether many gain sets can be simulated together.
    BATCHED: ClassVar[bool] = True

    def default_gains(self) -> Any:
        """The gains used when none are given (``None``: gains are required)."""
        return self.GAINS()

    def gains(self, gains: Any) -> Any:
        """The gains checked for this method (the default if ``None``)."""
        g = self.default_gains() if gains is None else gains
        if not isinstance(g, self.GAINS):
            raise InvalidParameterError(
                "gains", gains, f"must be a {self.GAINS.__name__} for method {self.name!r}"
            )
        return g

    def gain_row(self, gains: Any) -> np.ndarray:
        """The gains as one row (k1, b, k3, k5) of the simulator's gain array."""
        g = self.gains(gains)
        return np.array([g.k1, g.b, g.k3, g.k5])

    def gains_dict(self, row: np.ndarray) -> dict[str, float]:
        """The gains of a row, by name, as results report them."""
        return {k: float(v) for k, v in zip(("k1", "b", "k3", "k5"), row, strict=True)}

    def tie(self, gains: Any, tie_side: str) -> int:
        """The tie side +1 / -1 the field uses."""
        return 1 if tie_side == "+y" else -1


class _VFF(NavigationMethod):
    """The new VFF (Zeng 2011, Sec. 5.4-5.5): gains required, stabilising force, audit."""

    STABILISED = True

    def default_gains(self) -> Any:
        return None


class _Masoud(NavigationMethod):
    """Masoud (2007): no attractive damping; its fixed detour sense is the tie side."""

    GAINS = MasoudGains

    def gain_row(self, gains: Any) -> np.ndarray:
        g = self.gains(gains)
        return np.array([g.k1, 0.0, g.k3, g.k5])

    def gains_dict(self, row: np.ndarray) -> dict[str, float]:
        return {"k1": float(row[0]), "k3": float(row[2]), "k5": float(row[3])}

    def tie(self, gains: Any, tie_side: str) -> int:
        return gains.direction if isinstance(gains, MasoudGains) else super().tie(gains, tie_side)


class _GeCui(NavigationMethod):
    """Ge & Cui (2002)."""

    GAINS = GeCuiGains


class _CBF(NavigationMethod):
    """The exponential CBF safety filter on the attractive PD field (one QP per period)."""

    BATCHED = False

    def default_gains(self) -> Any:
        return EXPERIMENT_GAINS


class _VFFCBF(_VFF):
    """The new VFF (with its stabilising force) filtered by the CBF: one QP per period."""

    BATCHED = False


#: The registry: public name -> method.
METHODS: dict[str, NavigationMethod] = {
    m.name: m
    for m in (_VFF("vff"), _Masoud("masoud"), _GeCui("ge_cui"), _CBF("cbf"), _VFFCBF("vff_cbf"))
}

#: The ``method`` argument: one of :data:`METHODS`.
METHOD = Param(doc="navigation method", kind="choice", choices=tuple(METHODS), name="method")

#: The Sec. 5.7 planners (velocity obstacles linear and non-linear, ERRT, Field D*): they
#: command a velocity, not a force, and are simulated by
#: :func:`designlab.navigation.planners.simulate_planner`.
PLANNER = Param(
    doc="Sec. 5.7 planner",
    kind="choice",
    choices=("vo", "nlvo", "errt", "field_dstar"),
    name="method",
)


def method_of(name: Any) -> NavigationMethod:
    """The registered method of a public name (or a clear error).

    Parameters
    ----------
    name
        ``"vff"``, ``"masoud"``, ``"ge_cui"``, ``"cbf"`` or ``"vff_cbf"``. A Sec. 5.7
        planner's name
        (:data:`PLANNER`) is refused with where to run it instead.
    """
    if isinstance(name, str) and name in PLANNER.choices:
        raise InvalidParameterError(
            "method", name, "a Sec. 5.7 planner is not a force-field method nor batched: run "
            f"it with designlab.navigation.simulate(scenario, method={name!r}) (which calls "
            "designlab.navigation.planners.simulate_planner; docs/navigation_planners.md)",
        )  # fmt: skip
    return METHODS[METHOD.check(name)]
