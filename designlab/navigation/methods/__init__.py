"""The navigation methods, one module each, registered by their public name.

Each method (the new VFF of Zeng 2011, the baselines of Sec. 2.2.4: Masoud 2007 and
Ge & Cui 2002, and the CBF safety filter, alone or on the new VFF) is one object of
:class:`~designlab.navigation.methods.base.NavigationMethod` declared in its own module:
its gains and defaults, how they become a row of the simulator's gain array, its
capabilities (batched, stabilised, filtered, run among crowds) and its force, written in
the terms of :mod:`designlab.navigation.field_terms`. The Sec. 5.7 planners (velocity
obstacles, ERRT, Field D*) stand behind the same face
(:class:`~designlab.navigation.methods.base.Planner`): their settings and the velocity
they command each period. :data:`METHODS` is the registry;
engines, kinds and reports look a method up there and ask it, never its name. A new
method is one module and one line below.

Examples
--------
>>> from designlab.navigation.methods import METHODS, method_of
>>> METHODS.choices(force_field=True), METHODS.choices(planner=True)
(('vff', 'masoud', 'ge_cui', 'cbf', 'vff_cbf'), ('vo', 'nlvo', 'errt', 'field_dstar'))
>>> METHODS.choices(batched=True), METHODS.labels(filtered=True)
(('vff', 'masoud', 'ge_cui'), {'cbf': 'CBF', 'vff_cbf': 'New VFF + CBF'})
>>> m = method_of("masoud")
>>> m.gain_row(None).tolist(), m.gains_dict(m.gain_row(None))
([5.0, 0.0, 24.0, 36.0], {'k1': 5.0, 'k3': 24.0, 'k5': 36.0})
>>> method_of("bug")
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: method = 'bug' is not allowed: must be one of ...
"""

from __future__ import annotations

from typing import Any

from designlab.errors import InvalidParameterError
from designlab.navigation.methods.base import (
    STABILISING,
    TIE_SIDE,
    Filtered,
    NavigationMethod,
    Planner,
)
from designlab.navigation.methods.cbf import CBF
from designlab.navigation.methods.errt import ERRT
from designlab.navigation.methods.field_dstar import FIELD_DSTAR
from designlab.navigation.methods.ge_cui import GE_CUI
from designlab.navigation.methods.masoud import MASOUD
from designlab.navigation.methods.orca import ORCA
from designlab.navigation.methods.social_force import SOCIAL_FORCE
from designlab.navigation.methods.vff import VFF
from designlab.navigation.methods.vo import NLVO, VO
from designlab.registry import Registry

__all__ = [
    "CROWD_METHOD",
    "METHOD",
    "METHODS",
    "PLANNER",
    "STABILISING",
    "TIE_SIDE",
    "NavigationMethod",
    "Planner",
    "docs_table",
    "method_of",
]

#: The registry: public name -> method, in the order of the docs.
METHODS: Registry[NavigationMethod] = Registry(
    "method",
    "navigation methods",
    [
        VFF,
        MASOUD,
        GE_CUI,
        CBF,
        Filtered("vff_cbf", "New VFF + CBF", "the new VFF filtered by the CBF", nominal=VFF),
        VO,
        NLVO,
        ERRT,
        FIELD_DSTAR,
        ORCA,
        SOCIAL_FORCE,
    ],
)

#: The ``method`` argument of a force-field run: one of :data:`METHODS`.
METHOD = METHODS.param("navigation method", default=VFF.name, force_field=True)
#: The methods a robot can run among a crowd: the force fields, and the field's crowd
#: baselines commanding a velocity (ORCA, social force); the others are refused.
CROWD_METHOD = METHODS.param("navigation method among a crowd", default=VFF.name, crowds=True)

#: The Sec. 5.7 planners (velocity obstacles linear and non-linear, ERRT, Field D*): they
#: command a velocity, not a force, and are simulated by
#: :func:`designlab.navigation.planners.simulate_planner`.
PLANNER = METHODS.param("Sec. 5.7 planner", planner=True)


#: The capabilities the docs table lists, in its order.
_SHOWN = ("batched", "stabilised", "filtered", "crowds", "baseline", "planner", "seeded")


def _module_of(m: NavigationMethod) -> str:
    if isinstance(m, Filtered):
        return f"`Filtered(nominal={m.nominal.name})` in `methods`"
    return f"`{type(m).__module__.replace('designlab.navigation.', '')}`"


def docs_table() -> str:
    """The table of the methods in ``docs/navigation.md`` (a test keeps the page equal to it).

    Examples
    --------
    >>> print(docs_table().splitlines()[2])
    | `vff` | New VFF | the new virtual force field (Zeng 2011, Sec. 5.4-5.5) | `methods.vff` | ...
    """
    return METHODS.table(
        {
            "module": _module_of,
            "capabilities": lambda m: ", ".join(c for c in _SHOWN if getattr(m, c, False)),
        }
    )


def method_of(name: Any, **capabilities: Any) -> NavigationMethod:
    """The registered force-field method of a public name (or a clear error).

    Parameters
    ----------
    name
        A name of :data:`METHODS` (``"vff"``, ``"masoud"``, ``"ge_cui"``, ``"cbf"``,
        ``"vff_cbf"``). A Sec. 5.7 planner's name (:data:`PLANNER`) is refused with where
        to run it instead.
    **capabilities
        Only the methods with these capabilities are allowed (``batched=True``).
    """
    if name in METHODS and METHODS.get(name).planner:
        raise InvalidParameterError(
            "method", name, "a Sec. 5.7 planner is not a force-field method nor batched: run "
            f"it with designlab.navigation.simulate(scenario, method={name!r}) (which calls "
            "designlab.navigation.planners.simulate_planner; docs/navigation_planners.md)",
        )  # fmt: skip
    return METHODS.get(name, force_field=True, **capabilities)
