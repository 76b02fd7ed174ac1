"""Study-file specifications shared by the tether-follower kinds (Allan 2015).

Every field, unit, bound and default is the domain's declaration
(:mod:`designlab.following.tether`), read through
:func:`designlab.study.specs.spec_model`; nothing is restated here.

* :data:`FollowerRobotSpec`: ``DEFAULT`` (the App. C model: no wheel limits,
  100 Hz) or ``OXYDOG`` (Table 3.1's 1.0 m/s), optionally with fields replaced;
* :data:`ControllerSpec`: a law that follows from behind (every one the
  law registry :data:`designlab.following.tether.LAWS` holds with
  ``placement="behind"``: PJ, FTL, FTL-CD) with optional gains (App. C
  defaults otherwise) and a ``label``;
* :data:`PathSpec`: a named leader path with its arguments, or points.

Each spec builds its domain object while it is validated, so that
``designlab validate`` refuses what the run would refuse.

Examples
--------
>>> from pydantic import TypeAdapter
>>> TypeAdapter(PathSpec).validate_python({"type": "figure_eight", "a": 4.0}).build().name
'figure_eight_a4'
>>> spec = TypeAdapter(ControllerSpec).validate_python(
...     {"type": "FollowTheLeader", "lookahead": 0.3})
>>> spec.build().lookahead, spec.title
(0.3, 'FTL')
>>> FollowerRobotSpec.model_validate("OXYDOG").build().max_speed
1.0
"""

from __future__ import annotations

from typing import Annotated, Any, Literal, Union

from pydantic import Field, TypeAdapter, create_model

from designlab.following.tether import (
    LAWS,
    OXYDOG,
    FollowerRobot,
    LeaderPath,
    TetherController,
    make_path,
)
from designlab.following.tether.paths import PATHS, SHAPE_PARAMETERS
from designlab.params import params_of
from designlab.study.base import Finite
from designlab.study.specs import Buildable, built, spec_model

__all__ = [
    "ControllerSpec",
    "FollowerRobotSpec",
    "PathSpec",
    "built",
    "controllers_field",
    "robot_field",
]

#: The laws a ``controllers`` list may hold: those that follow from behind.
BEHIND = {"placement": "behind"}


#: The differential-drive follower (:class:`designlab.following.tether.FollowerRobot`):
#: a preset (``DEFAULT``: App. C, no wheel limits, 100 Hz; ``OXYDOG``: 1.0 m/s) and/or fields.
FollowerRobotSpec = create_model(
    "FollowerRobotSpec",
    __base__=(
        spec_model(
            FollowerRobot,
            name="FollowerRobotFields",
            presets={"DEFAULT": FollowerRobot(), "OXYDOG": OXYDOG},
            what="follower robot",
        ),
        Buildable,
    ),
    __doc__="The differential-drive follower: a preset (DEFAULT, OXYDOG) and/or fields, SI units.",
)


class _LawSpec(Buildable):
    """What every law's spec adds to the law's declared fields: its type and a label."""

    label: str | None = Field(None, min_length=1, max_length=40, description="name in reports")

    def build(self, **changes: Any) -> TetherController:
        """The controller (``changes`` override fields, e.g. ``desired_length``).

        Parameters
        ----------
        **changes
            Field name -> value.
        """
        fields = self.model_dump(exclude={"type", "label"})
        fields.update(changes)
        return LAWS.get(self.type)(**fields)  # type: ignore[attr-defined,no-any-return]

    @property
    def title(self) -> str:
        """The label, or the law's short name."""
        return self.label or LAWS.get(self.type).short  # type: ignore[attr-defined]


def _law_spec(name: str, cls: type) -> Any:
    """The law's spec, bound in this module under its own name (so that it pickles)."""
    fields = spec_model(cls, name=f"{name}Fields")
    model = create_model(
        f"{name}Spec",
        __base__=(_LawSpec, fields),
        __doc__=f"The {name} law with its gains (App. C defaults), SI units.",
        __module__=__name__,
        type=(Literal[name], Field(description="the control law")),  # type: ignore[valid-type]
    )
    globals()[model.__name__] = model
    return model


#: A law that follows from behind, with optional gains and a label (``type`` selects the law).
ControllerSpec = Annotated[
    Union[tuple(_law_spec(law.name, law) for law in LAWS.variants(**BEHIND))],  # type: ignore[misc]  # noqa: UP007
    Field(discriminator="type"),
]


class _PathBuild(Buildable):
    """What every path spec does: build the path, renamed when the spec gives a name."""

    def build(self) -> LeaderPath:
        """The :class:`designlab.following.tether.LeaderPath`."""
        args = self.model_dump(exclude={"type", "name"})
        path = PATHS[self.type](**args)  # type: ignore[attr-defined]
        if not self.name:
            return path
        return LeaderPath(
            path.points,
            name=self.name,
            obstacles=path.obstacles,
            initial_heading=path.initial_heading,
        )


#: The base of every path spec: an optional ``name`` (the declaration of
#: :attr:`LeaderPath.name`; ``None``: the shape's own name).
_PathSpec = create_model(
    "_PathSpec",
    __base__=_PathBuild,
    __doc__="What every path spec adds: an optional name (the shape's own name otherwise).",
    name=(params_of(LeaderPath)["name"].annotation(optional=True), None),
)


def _shape_spec(shape: str) -> Any:
    """The spec of a named path shape, bound in this module under its name (so that it pickles)."""
    fields = {
        n: (d.annotation(), d.default) for n, d in SHAPE_PARAMETERS[shape].items()
    }  # every argument has a default (None for an optional one)
    camel = "".join(w.capitalize() for w in shape.split("_"))
    model = create_model(
        f"{camel}PathSpec",
        __base__=_PathSpec,
        __doc__=f"The {shape} leader path (:func:`designlab.following.tether.paths.{shape}`), SI"
        " units.",
        __module__=__name__,
        type=(Literal[shape], Field(description="the path shape")),  # type: ignore[valid-type]
        **fields,
    )
    globals()[model.__name__] = model  # bound under its own name, so that it pickles
    return model


class PointsPathSpec(_PathSpec):
    """A recorded leader path: its points in m, ``[[x, y], ...]`` (2 to 10**6 points)."""

    type: Literal["points"]
    points: list[tuple[Finite, Finite]] = Field(min_length=2, description="[[x, y], ...] in m")

    def build(self) -> LeaderPath:
        """The :class:`designlab.following.tether.LeaderPath`."""
        return make_path({"points": self.points, "name": self.name or "recorded"})


#: A leader path: a named shape with its arguments (m), or recorded points (m).
PathSpec = Annotated[
    Union[(*(_shape_spec(s) for s in SHAPE_PARAMETERS), PointsPathSpec)],  # type: ignore[misc]
    Field(discriminator="type"),
]


def robot_field(preset: str = "DEFAULT") -> Any:
    """The ``robot`` block of a tether study kind: a follower robot, by default a preset.

    Parameters
    ----------
    preset
        The preset the block defaults to (``DEFAULT`` or ``OXYDOG``).

    Examples
    --------
    >>> from designlab.study.base import Model
    >>> class Demo(Model):
    ...     robot: FollowerRobotSpec = robot_field("OXYDOG")
    >>> Demo().robot.build().max_speed
    1.0
    """
    return Field(default_factory=lambda: FollowerRobotSpec(preset=preset))


def controllers_field(*laws: Any, max_length: int) -> Any:
    """The ``controllers`` list of a tether study kind: by default the given laws, thesis gains.

    Parameters
    ----------
    *laws
        The law classes of the default list (default: every law that follows from behind,
        in the registry's order).
    max_length
        The most laws a study may list.

    Examples
    --------
    >>> from designlab.study.base import Model
    >>> class Demo(Model):
    ...     controllers: list[ControllerSpec] = controllers_field(max_length=3)
    >>> [c.title for c in Demo().controllers]
    ['PJ', 'FTL', 'FTL-CD']
    """

    def default() -> list[Any]:
        chosen = laws or LAWS.variants(**BEHIND)
        return TypeAdapter(list[ControllerSpec]).validate_python([{"type": t.name} for t in chosen])

    return Field(default_factory=default, min_length=1, max_length=max_length)
