"""Schema pieces shared by the navigation kinds: scenarios, robots, gains, methods.

A scenario is either a thesis configuration (``configuration: 1`` ... ``4``,
``parallel``, ``unpredictable``, ``multi`` with ``chapter: 6`` or ``7``) or
built by hand (start, goal, obstacles with their regions and motions).
Every field, unit, bound and default is the domain's declaration
(:mod:`designlab.navigation.parameters`, :mod:`designlab.navigation.scenarios`,
derived with :func:`designlab.study.specs.spec_model`), and each spec builds its
domain object while it is validated, so ``designlab validate`` refuses what the
constructors refuse (a disc with r2 <= r3, a walk that ends where it starts) and
names the parameter. ``build()`` returns the :mod:`designlab.navigation` object.

A bare YAML ``off`` (read as ``false`` by YAML 1.1) is accepted as the stabilising
mode ``"off"`` (docs/navigation.md, "Study files").

Examples
--------
>>> ScenarioSpec.model_validate({"configuration": 3}).build().obstacle_names
('circle', 'rectangle')
>>> s = ScenarioSpec.model_validate({
...     "name": "corridor", "start": [4, 0.5], "goal": [0, 0.5],
...     "obstacles": [{"name": "visitor", "kind": "disc", "radius": 0.4, "r2": 2.1, "r3": 0.8,
...                    "walk": {"start": [0, 2], "end": [4, 2], "speed": 0.8}}]})
>>> s.build().obstacles[0].motion.speed
0.8
>>> from pydantic import ValidationError
>>> try:
...     WalkSpec.model_validate({"start": [1, 1], "end": [1, 1]})
... except ValidationError as exc:
...     print(exc.errors()[0]["msg"][:44])
Value error, Walk.end = (1.0, 1.0) m is not
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field, ValidationError, create_model, model_validator

from designlab.navigation.methods import METHOD, METHODS, PLANNER, STABILISING, TIE_SIDE
from designlab.navigation.parameters import (
    CBF_K0,
    CBF_K1,
    OBSTACLES,
    GeCuiGains,
    HolonomicRobot,
    MasoudGains,
    NonholonomicRobot,
    VFFGains,
)
from designlab.navigation.scenario_io import (
    OBSTACLE_KINDS,
    obstacle_from_dict,
    robot_from_dict,
    scenario_from_dict,
)
from designlab.navigation.scenarios import (
    MAX_PATH_SAMPLES,
    ConstantVelocity,
    Disc,
    Rectangle,
    SampledPath,
    Scenario,
    Stationary,
    Walk,
    configuration,
)
from designlab.params import params_of
from designlab.study.base import Finite, Integer, Model
from designlab.study.specs import spec_model

__all__ = [
    "GainsSpec",
    "GeCuiGainsSpec",
    "MasoudGainsSpec",
    "MethodSpec",
    "ObstacleSpec",
    "PathSpec",
    "RobotSpec",
    "RouteSpec",
    "ScenarioSpec",
    "Stabilising",
    "WalkSpec",
]

Point = Annotated[list[Finite], Field(min_length=2, max_length=2)]


def _yaml_off(value: object) -> object:
    # YAML 1.1 reads a bare ``off`` as false; in this field it can only mean the mode "off".
    return "off" if value is False else value


#: The stabilising mode of a study file (a bare ``off`` is the mode ``"off"``).
Stabilising = Annotated[STABILISING.annotation(), BeforeValidator(_yaml_off)]


def _optional(cls: type, names: tuple[str, ...] | None = None) -> dict[str, Any]:
    """Pydantic fields of a declared class, each optional (``None``: the class default)."""
    decls = params_of(cls)
    return {
        n: (d.annotation(optional=True), None)
        for n, d in decls.items()
        if d.kind != "object" and (names is None or n in names)
    }


class _Checked(Model):
    """Mixin: the domain object is built while validating (its constructor's errors become
    the spec's, naming the parameter)."""

    @model_validator(mode="after")
    def _builds(self) -> Any:
        self.build()  # type: ignore[attr-defined]
        return self


def _checked(base: type[Model], name: str, **fields: Any) -> type[Model]:
    """``base`` (a :func:`spec_model`) with :class:`_Checked` and extra fields."""
    model = create_model(name, __base__=(base, _Checked), __doc__=base.__doc__, **fields)
    model.BUILDS = base.BUILDS  # type: ignore[attr-defined]
    return model


# ------------------------------------------------------------------------ robots


class _RobotBase(_Checked):
    type: Literal["holonomic", "nonholonomic"] = "holonomic"

    def build(self) -> HolonomicRobot | NonholonomicRobot:
        """The robot object (:func:`designlab.navigation.scenario_io.robot_from_dict`)."""
        return robot_from_dict(self.model_dump(exclude_none=True))


#: ``holonomic`` (Ch. 6) or ``nonholonomic`` (Ch. 7), with optional limits (SI): the fields
#: of :class:`~designlab.navigation.HolonomicRobot` and
#: :class:`~designlab.navigation.NonholonomicRobot`.
RobotSpec = create_model(
    "RobotSpec",
    __base__=_RobotBase,
    __doc__="``holonomic`` (Ch. 6) or ``nonholonomic`` (Ch. 7), with optional limits (SI).",
    **{**_optional(HolonomicRobot), **_optional(NonholonomicRobot)},
)


# ------------------------------------------------------------------- motions


def _point_field(cls: type, name: str, optional: bool = True) -> tuple[Any, Any]:
    """A point (x, y) field of a declared class, described by its declaration."""
    doc = params_of(cls)[name].description
    unit = params_of(cls)[name].unit
    kind = Point | None if optional else Point
    return (kind, Field(None if optional else ..., description=f"{doc}, {unit}"))


#: A straight walk with smooth start and stop (:class:`~designlab.navigation.Walk`).
WalkSpec = _checked(
    spec_model(Walk), "WalkSpec", start=_point_field(Walk, "start", False),
    end=_point_field(Walk, "end", False),
)  # fmt: skip

_WALK = params_of(Walk)


class _RouteBase(_Checked):
    def build(self) -> SampledPath:
        """The :class:`~designlab.navigation.SampledPath` through the waypoints."""
        return SampledPath.through(**self.model_dump())


#: A walk through waypoints at a constant speed, turning on the spot at each
#: (:meth:`~designlab.navigation.SampledPath.through`).
RouteSpec = create_model(
    "RouteSpec",
    __base__=_RouteBase,
    __doc__="A walk through waypoints at a constant speed (SampledPath.through).",
    waypoints=(list[Point], Field(min_length=2, max_length=1000, description="waypoints, m")),
    speed=(_WALK["speed"].annotation(), _WALK["speed"].default),
    start_time=(_WALK["start_time"].annotation(), _WALK["start_time"].default),
)


class _PathBase(_Checked):
    def build(self) -> SampledPath:
        """The :class:`~designlab.navigation.SampledPath` of the samples."""
        return SampledPath(**self.model_dump())  # type: ignore[arg-type]


#: A sampled walk (e.g. measured), linearly interpolated
#: (:class:`~designlab.navigation.SampledPath`).
PathSpec = create_model(
    "PathSpec",
    __base__=_PathBase,
    __doc__="A sampled walk, linearly interpolated (SampledPath).",
    times=(list[Finite], Field(min_length=2, max_length=MAX_PATH_SAMPLES, description="s")),
    positions=(list[Point], Field(min_length=2, max_length=MAX_PATH_SAMPLES, description="m")),
)


class _ObstacleBase(_Checked):
    def build(self) -> Disc | Rectangle:
        """The obstacle object (:func:`designlab.navigation.scenario_io.obstacle_from_dict`)."""
        return obstacle_from_dict(self.model_dump(exclude_none=True), f"obstacle {self.name!r}")  # type: ignore[attr-defined]


_DISC, _RECT = params_of(Disc), params_of(Rectangle)

#: A disc or human (``radius``, ``r2``, ``r3`` and one motion: ``position`` (and
#: ``velocity``), ``walk``, ``route`` or ``path``), a rectangle (``center``, ``length``,
#: ``width``, ``angle``, or ``corners``) or a wall (``start``, ``end``, ``thickness``): the
#: fields of :class:`~designlab.navigation.Disc`, :class:`~designlab.navigation.Rectangle`
#: and their motions (docs/navigation_scenarios.md).
ObstacleSpec = create_model(
    "ObstacleSpec",
    __base__=_ObstacleBase,
    __doc__="A disc, human, rectangle or wall with its regions (docs/navigation_scenarios.md).",
    name=(_DISC["name"].annotation(), Field(min_length=1, max_length=60)),
    kind=(Literal[OBSTACLE_KINDS], ...),  # type: ignore[valid-type]
    r2=(_DISC["r2"].annotation(), ...),
    r3=(_DISC["r3"].annotation(), ...),
    radius=(_DISC["radius"].annotation(optional=True), None),
    position=_point_field(Stationary, "position"),
    velocity=_point_field(ConstantVelocity, "velocity"),
    walk=(WalkSpec | None, None),
    route=(RouteSpec | None, None),
    path=(PathSpec | None, None),
    center=_point_field(Rectangle, "center"),
    corners=(list[Point] | None, Field(None, min_length=4, max_length=4, description="m")),
    start=_point_field(Walk, "start"),
    end=_point_field(Walk, "end"),
    thickness=(_RECT["width"].annotation(optional=True), None),
    **_optional(Rectangle, ("length", "width", "angle")),
)


# ---------------------------------------------------------------------- scenario


class _ScenarioBase(Model):
    configuration: Integer | Literal["parallel", "unpredictable", "multi"] | None = None
    chapter: Literal[6, 7] = 6
    label: str | None = Field(None, min_length=1, max_length=60, description="name in the report")

    @model_validator(mode="after")
    def _one_way(self) -> Any:
        own = self.start is not None or self.goal is not None or self.obstacles  # type: ignore[attr-defined]
        if self.configuration is not None:
            if own:
                raise ValueError("give either configuration or start/goal/obstacles, not both")
            if isinstance(self.configuration, int) and not 1 <= self.configuration <= 4:
                raise ValueError(
                    f"configuration = {self.configuration!r} is not allowed: must be 1-4, "
                    "'parallel', 'unpredictable' or 'multi'"
                )
        elif self.start is None or self.goal is None or self.name is None:  # type: ignore[attr-defined]
            raise ValueError("give configuration, or name, start and goal (and obstacles)")
        self.build()
        return self

    @property
    def own(self) -> bool:
        """Whether this is a scenario of the user's (not a thesis configuration)."""
        return self.configuration is None

    @property
    def title(self) -> str:
        """The label used in reports."""
        if self.label:
            return self.label
        if self.configuration is not None:
            return (
                f"ch{self.chapter}_config{self.configuration}"
                if isinstance(self.configuration, int)
                else f"ch{self.chapter}_{self.configuration}"
            )
        return str(self.name)  # type: ignore[attr-defined]

    def as_dict(self) -> dict[str, Any]:
        """A scenario of the user's as plain data (:func:`scenario_from_dict`'s input)."""
        data = self.model_dump(
            mode="json",
            exclude_none=True,
            exclude={"configuration", "chapter", "label", "human_speed"},
        )
        return {**data, "name": self.title}

    def build(self) -> Scenario:
        """The :class:`~designlab.navigation.Scenario`."""
        if self.configuration is None:
            return scenario_from_dict(self.as_dict())
        robot = self.robot.build() if self.robot is not None else None  # type: ignore[attr-defined]
        timing = {"sample_time": self.sample_time} if self.sample_time is not None else {}  # type: ignore[attr-defined]
        sc = configuration(
            self.configuration,
            self.chapter,
            robot=robot,
            human_speed=self.human_speed,  # type: ignore[attr-defined]
            horizon=self.horizon,  # type: ignore[attr-defined]
        )
        return sc.replace(name=self.title, **timing)


_SCENARIO = params_of(Scenario)

#: A thesis configuration, or a scenario of the user's (docs/navigation_scenarios.md).
ScenarioSpec = create_model(
    "ScenarioSpec",
    __base__=_ScenarioBase,
    __doc__="A thesis configuration, or a scenario of the user's (docs/navigation_scenarios.md).",
    name=(_SCENARIO["name"].annotation(optional=True), Field(None, min_length=1, max_length=60)),
    start=_point_field(Scenario, "start"),
    goal=_point_field(Scenario, "goal"),
    obstacles=(list[ObstacleSpec], Field(default_factory=list, max_length=int(OBSTACLES.le))),  # type: ignore[valid-type]
    robot=(RobotSpec | None, None),  # type: ignore[valid-type]
    human_speed=(_WALK["speed"].annotation(), _WALK["speed"].default),
    horizon=(_SCENARIO["horizon"].annotation(), _SCENARIO["horizon"].default),
    sample_time=(_SCENARIO["sample_time"].annotation(optional=True), None),
    initial_heading=(_SCENARIO["initial_heading"].annotation(), None),
    description=(_SCENARIO["description"].annotation(optional=True), None),
)


# ------------------------------------------------------------------------- gains

#: New-VFF gains K1 (N/m), b (s), K3 (N/m), K5 (N/m^2); K2 = b K1, K4 = b K3, K6 = b K5.
GainsSpec = _checked(spec_model(VFFGains), "GainsSpec")
#: Masoud (2007) gains K_MM1, K_MM3 (N/m), K_MM5 (N/m) and the fixed detour sense.
MasoudGainsSpec = _checked(spec_model(MasoudGains), "MasoudGainsSpec")
#: Ge & Cui (2002) gains: attraction K1 (N/m) with ratio b (s), K3 and K5.
GeCuiGainsSpec = _checked(spec_model(GeCuiGains), "GeCuiGainsSpec")

#: The spec of each gains class (a method's ``gains_type`` picks its spec).
_SPEC_OF_GAINS: dict[type, type[Model]] = {
    VFFGains: GainsSpec,
    MasoudGains: MasoudGainsSpec,
    GeCuiGains: GeCuiGainsSpec,
}


def _gains_spec(method: str) -> type[Model] | None:
    """The gains spec of a force-field method (``None`` for a planner or an unknown name)."""
    if method not in METHODS or not METHODS.get(method).force_field:
        return None
    return _SPEC_OF_GAINS[METHODS.get(method).gains_type]


def typed_gains(data: Any) -> Any:
    """A method's mapping with its ``gains`` read as that method's kind of gains.

    ``{direction: -1}`` is Masoud's; given to ``vff`` it is refused here, naming what
    ``vff`` takes, rather than read as another method's gains and refused at run time.

    Examples
    --------
    >>> typed_gains({"method": "vff", "gains": {"direction": -1}})
    Traceback (most recent call last):
    ...
    ValueError: gains: {'direction': -1} are not vff gains (vff takes k1, b, k3, k5): ...
    """
    if not (isinstance(data, dict) and isinstance(data.get("gains"), dict)):
        return data
    method = str(data.get("method", METHOD.default))
    spec = _gains_spec(method)
    if spec is None:
        return data
    try:
        return {**data, "gains": spec.model_validate(data["gains"])}
    except ValidationError as exc:
        problems = "; ".join(
            f"{'.'.join(map(str, e['loc'])) or 'gains'}: "
            + {"extra_forbidden": "unknown field", "missing": "missing"}.get(e["type"], e["msg"])
            for e in exc.errors(include_url=False)
        )
        takes = ", ".join(spec.model_fields)
        raise ValueError(
            f"gains: {data['gains']!r} are not {method} gains ({method} takes {takes}): {problems}"
        ) from None


#: A force-field method (:data:`~designlab.navigation.methods.METHOD`) or a Sec. 5.7 planner
#: (:data:`~designlab.navigation.methods.PLANNER`, docs/navigation_planners.md).
_Method = Literal[METHOD.choices + PLANNER.choices]  # type: ignore[valid-type]
_TieSide = TIE_SIDE.annotation()
_CBFGains = tuple[CBF_K0.annotation(), CBF_K1.annotation()]  # type: ignore[misc]


class MethodSpec(Model):
    """A navigation method with its gains and settings.

    ``gains`` are read by the method: ``{k1, b, k3, k5}`` for ``vff`` and ``cbf`` (its
    attractive part), ``{k1, k3, k5, direction}`` for ``masoud`` and ``{k1, b, k3, k5}``
    for ``ge_cui`` (the baselines default to Zeng 2011, Table C.1).

    Examples
    --------
    >>> m = MethodSpec.model_validate({"label": "Masoud, clockwise", "method": "masoud",
    ...                                "gains": {"direction": -1}})
    >>> m.gains.build().direction, m.gains.build().k3
    (-1, 24.0)
    """

    label: str = Field(min_length=1, max_length=60)
    method: _Method = "vff"
    gains: GainsSpec | MasoudGainsSpec | GeCuiGainsSpec | None = Field(  # type: ignore[valid-type]
        None,
        description="gains of the method (vff and cbf: required / optional {k1, b, k3, k5}; "
        "masoud: {k1, k3, k5, direction}; ge_cui: {k1, b, k3, k5}; baselines default "
        "to Table C.1)",
    )
    stabilising: Stabilising = "lyapunov"
    tie_side: _TieSide = "+y"
    cbf_gains: _CBFGains = (4.0, 4.0)
    settings: dict[str, Any] | None = Field(
        None,
        description="a planner's settings (vo, errt, field_dstar; docs/navigation_planners.md)",
    )

    @property
    def planner(self) -> bool:
        """Whether the method is a Sec. 5.7 planner (simulated by ``simulate_planner``)."""
        return METHODS.get(self.method).planner

    def planner_settings(self) -> Any:
        """The planner's settings object (its defaults for keys not given)."""
        spec = spec_model(METHODS.get(self.method).settings_type)
        given = self.settings or {}
        unknown = sorted(set(given) - set(spec.model_fields))
        if unknown:
            raise ValueError(
                f"method {self.label!r}: settings {unknown} do not apply to {self.method} "
                f"(its settings: {', '.join(spec.model_fields)})"
            )
        return spec.model_validate(given).build()

    @model_validator(mode="before")
    @classmethod
    def _typed_gains(cls, data: Any) -> Any:
        return typed_gains(data)

    @model_validator(mode="after")
    def _gains(self) -> MethodSpec:
        if self.planner:
            if self.gains is not None:
                raise ValueError(f"method {self.label!r}: a planner takes settings, not gains")
            self.planner_settings()
            return self
        if self.settings is not None:
            raise ValueError(f"method {self.label!r}: settings apply to the planners only")
        method = METHODS.get(self.method)
        if method.gains_required and self.gains is None:
            takes = ", ".join(method.used_gains)
            raise ValueError(
                f"method {self.label!r}: the {self.method} method needs gains: {{{takes}}}"
            )
        if self.gains is not None and not isinstance(self.gains, _gains_spec(self.method)):
            raise ValueError(f"method {self.label!r}: gains of the wrong kind for {self.method}")
        if not method.filtered and "cbf_gains" in self.model_fields_set:
            filtered = " and ".join(METHODS.choices(filtered=True))
            raise ValueError(f"method {self.label!r}: cbf_gains apply to {filtered} only")
        return self
