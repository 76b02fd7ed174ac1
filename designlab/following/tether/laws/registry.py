"""Every tether follower law by name: the one table of them (Allan 2015 Sec. 2.3, Ch. 4).

:data:`LAWS` is a :class:`designlab.registry.Registry` of the law classes, in
the thesis's order. The study files' ``type``, the default law lists, the
short names of the reports and the docs tables derive from it; ask it for the
laws with a capability, e.g. ``LAWS.variants(placement="behind")`` (the laws
that follow from behind: PJ, FTL, FTL-CD).

Examples
--------
>>> LAWS.choices(placement="behind")
('PseudoJoystick', 'FollowTheLeader', 'FollowTheLeaderConstDistance')
>>> LAWS.get("FollowTheLeader").short
'FTL'
>>> controller_from_dict({"type": "FollowTheLeader", "lookahead": 0.3}).lookahead
0.3
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import fields
from typing import Any

from designlab.errors import InvalidParameterError
from designlab.following.tether.laws.base import TetherController
from designlab.following.tether.laws.brake import BrakeMode
from designlab.following.tether.laws.constant_distance import FollowTheLeaderConstDistance
from designlab.following.tether.laws.follow_the_leader import FollowTheLeader
from designlab.following.tether.laws.front_joystick import FrontJoystick
from designlab.following.tether.laws.front_vel_joystick import FrontVelJoystick
from designlab.following.tether.laws.pseudo_joystick import PseudoJoystick
from designlab.following.tether.laws.side_joystick import SideJoystick
from designlab.following.tether.laws.side_tracking import SideTracking
from designlab.registry import Registry

__all__ = ["LAWS", "TABLE_COLUMNS", "controller_from_dict"]

#: The tether follower laws by name (their class names, the ``type`` of a study file).
LAWS: Registry[type[TetherController]] = Registry(  # type: ignore[type-var]
    "controller.type",
    "tether laws",
    [
        PseudoJoystick,
        FollowTheLeader,
        FollowTheLeaderConstDistance,
        SideJoystick,
        SideTracking,
        FrontJoystick,
        FrontVelJoystick,
        BrakeMode,
    ],
)


#: The columns of the laws' table in ``docs/following.md`` (``LAWS.table(TABLE_COLUMNS)``).
TABLE_COLUMNS: dict[str, Callable[[Any], Any]] = {
    "short": lambda law: law.short,
    "module": lambda law: f"`laws.{law.__module__.rsplit('.', 1)[1]}`",
    "placement": lambda law: law.placement,
    "steering target": lambda law: "its own" if law.stepwise else law.target_finder.name,
    "stepwise": lambda law: law.stepwise,
    "linear": lambda law: law.linear,
}


def controller_from_dict(spec: dict[str, Any]) -> TetherController:
    """A law that follows from behind, from ``{"type": name, **fields}`` (``as_dict``'s inverse).

    Parameters
    ----------
    spec
        ``{"type": law name, **fields}``, e.g. ``{"type": "FollowTheLeader", "lookahead": 0.3}``.

    Examples
    --------
    >>> controller_from_dict({"type": "PseudoJoystick", "law": "printed"}).law
    'printed'
    """
    if not isinstance(spec, Mapping):
        raise InvalidParameterError("controller", spec, "a mapping {type: ..., field: value}")
    spec = dict(spec)
    law = LAWS.get(spec.pop("type", None), placement="behind")
    allowed = [f.name for f in fields(law)]  # type: ignore[arg-type]
    for key in spec:
        if key not in allowed:
            raise InvalidParameterError(f"controller.{key}", spec[key], f"a field of {law.name}: "
                                        f"one of {allowed}")  # fmt: skip
    return law(**spec)
