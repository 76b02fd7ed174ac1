"""Schema pieces shared by the navigation kinds: scenarios, robots, gains, methods.

A scenario is either a thesis configuration (``configuration: 1`` ... ``4``,
``parallel``, ``unpredictable``, ``multi`` with ``chapter: 6`` or ``7``) or
built by hand (start, goal, obstacles with their regions and motions).
``build()`` returns the :mod:`designlab.navigation` object (validated by its
constructor).

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
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field, model_validator

from designlab.navigation.parameters import (
    MAX_GAIN,
    GeCuiGains,
    HolonomicRobot,
    MasoudGains,
    NonholonomicRobot,
    VFFGains,
)
from designlab.navigation.scenarios import (
    ConstantVelocity,
    Disc,
    Rectangle,
    Scenario,
    Stationary,
    Walk,
    configuration,
)
from designlab.study.base import Finite, Integer, Model, NonNegative, Number, Positive
from designlab.validation import reject_bool

__all__ = [
    "GainsSpec",
    "GeCuiGainsSpec",
    "MasoudGainsSpec",
    "MethodSpec",
    "ObstacleSpec",
    "RobotSpec",
    "ScenarioSpec",
]

Point = Annotated[list[Finite], Field(min_length=2, max_length=2)]


class RobotSpec(Model):
    """``holonomic`` (Ch. 6) or ``nonholonomic`` (Ch. 7), with optional limits (SI)."""

    type: Literal["holonomic", "nonholonomic"] = "holonomic"
    radius: Positive | None = None
    max_speed: Positive | None = None
    max_accel: Positive | None = None
    mass: Positive | None = None

    def build(self) -> HolonomicRobot | NonholonomicRobot:
        """The robot object."""
        cls = HolonomicRobot if self.type == "holonomic" else NonholonomicRobot
        kw = {
            k: getattr(self, k)
            for k in ("radius", "max_speed", "max_accel", "mass")
            if getattr(self, k) is not None
        }
        return cls(**kw)


class WalkSpec(Model):
    """A straight walk with smooth start and stop (m, m/s, s)."""

    start: Point
    end: Point
    speed: Positive = 1.0
    ramp_time: NonNegative = 0.5
    start_time: NonNegative = 0.0


class ObstacleSpec(Model):
    """A disc (``radius``, ``r2``, ``r3``, and ``position``, ``velocity`` or ``walk``) or a
    rectangle (``center``, ``length``, ``width``, ``r2``, ``r3``, ``angle``)."""

    name: str = Field(min_length=1, max_length=40)
    kind: Literal["disc", "rectangle"]
    r2: Positive = Field(
        description="active radius (disc: centre distance; rectangle: from the contour), m"
    )
    r3: Positive = Field(description="critical radius, m")
    radius: Positive | None = None
    position: Point | None = Field(None, description="disc: start (or fixed) position, m")
    velocity: Point | None = Field(None, description="disc: constant velocity, m/s")
    walk: WalkSpec | None = None
    center: Point | None = None
    length: Positive | None = None
    width: Positive | None = None
    angle: Finite = 0.0

    @model_validator(mode="after")
    def _complete(self) -> ObstacleSpec:
        if self.kind == "disc":
            if self.radius is None:
                raise ValueError(f"disc {self.name!r}: give radius (m)")
            if (self.walk is None) == (self.position is None):
                raise ValueError(
                    f"disc {self.name!r}: give either position (and optionally velocity) or walk"
                )
        elif self.center is None or self.length is None or self.width is None:
            raise ValueError(f"rectangle {self.name!r}: give center, length and width (m)")
        return self

    def build(self) -> Disc | Rectangle:
        """The obstacle object."""
        if self.kind == "rectangle":
            return Rectangle(
                self.name,
                tuple(self.center),
                self.length,
                self.width,
                self.r2,
                self.r3,  # type: ignore[arg-type]
                self.angle,
            )
        if self.walk is not None:
            w = self.walk
            motion: Walk | ConstantVelocity | Stationary = Walk(
                tuple(w.start),
                tuple(w.end),
                w.speed,  # type: ignore[arg-type]
                w.ramp_time,
                w.start_time,
            )
        elif self.velocity is not None:
            motion = ConstantVelocity(tuple(self.position), tuple(self.velocity))  # type: ignore[arg-type]
        else:
            motion = Stationary(tuple(self.position))  # type: ignore[arg-type]
        return Disc(self.name, self.radius, self.r2, self.r3, motion)  # type: ignore[arg-type]


class ScenarioSpec(Model):
    """A thesis configuration, or a scenario built by hand."""

    configuration: Integer | Literal["parallel", "unpredictable", "multi"] | None = None
    chapter: Literal[6, 7] = 6
    label: str | None = Field(None, min_length=1, max_length=60, description="name in the report")
    name: str | None = Field(None, min_length=1, max_length=60)
    start: Point | None = None
    goal: Point | None = None
    obstacles: list[ObstacleSpec] = Field(default_factory=list)
    robot: RobotSpec | None = None
    human_speed: Positive = Field(1.0, description="synthetic walk of Configs 2 and 4, m/s")
    horizon: Positive = Field(30.0, le=600.0, description="simulated time limit, s")

    @model_validator(mode="after")
    def _one_way(self) -> ScenarioSpec:
        if self.configuration is not None:
            if self.start is not None or self.goal is not None or self.obstacles:
                raise ValueError("give either configuration or start/goal/obstacles, not both")
            if isinstance(self.configuration, int) and not 1 <= self.configuration <= 4:
                raise ValueError(
                    "configuration must be 1-4, 'parallel', 'unpredictable' or 'multi'"
                )
        elif self.start is None or self.goal is None or self.name is None:
            raise ValueError("give configuration, or name, start and goal (and obstacles)")
        return self

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
        return str(self.name)

    def build(self) -> Scenario:
        """The :class:`~designlab.navigation.Scenario`."""
        robot = self.robot.build() if self.robot is not None else None
        if self.configuration is not None:
            sc = configuration(
                self.configuration,
                self.chapter,
                robot=robot,
                human_speed=self.human_speed,
                horizon=self.horizon,
            )
            return sc.replace(name=self.title)
        return Scenario(
            self.title,
            tuple(self.start),
            tuple(self.goal),  # type: ignore[arg-type]
            tuple(o.build() for o in self.obstacles),
            robot if robot is not None else HolonomicRobot(),
            self.horizon,
        )


#: A gain: a finite number > 0, at most :data:`designlab.navigation.parameters.MAX_GAIN`.
Gain = Annotated[Number, Field(gt=0, le=MAX_GAIN, allow_inf_nan=False)]


class GainsSpec(Model):
    """New-VFF gains K1 (N/m), b (s), K3 (N/m), K5 (N/m^2); K2 = b K1, K4 = b K3, K6 = b K5."""

    k1: Gain
    b: Gain
    k3: Gain
    k5: Gain

    def build(self) -> VFFGains:
        """The :class:`~designlab.navigation.VFFGains`."""
        return VFFGains(self.k1, self.b, self.k3, self.k5)


class MasoudGainsSpec(Model):
    """Masoud (2007) gains K_MM1, K_MM3 (N/m), K_MM5 (N/m) and the fixed detour sense."""

    k1: Gain = 5.0
    k3: Gain = 24.0
    k5: Gain = 36.0
    direction: Annotated[Literal[1, -1], BeforeValidator(reject_bool)] = Field(
        1, description="+1 counter-clockwise, -1 clockwise"
    )

    def build(self) -> MasoudGains:
        """The :class:`~designlab.navigation.MasoudGains`."""
        return MasoudGains(self.k1, self.k3, self.k5, self.direction)


class GeCuiGainsSpec(Model):
    """Ge & Cui (2002) gains: attraction K1 (N/m) with ratio b (s), K3 and K5."""

    k1: Gain = 1.0
    b: Gain = 0.75
    k3: Gain = 14.2
    k5: Gain = 14.2

    def build(self) -> GeCuiGains:
        """The :class:`~designlab.navigation.GeCuiGains`."""
        return GeCuiGains(self.k1, self.b, self.k3, self.k5)


_GAIN_SPECS: dict[str, type[Model]] = {
    "vff": GainsSpec,
    "cbf": GainsSpec,
    "masoud": MasoudGainsSpec,
    "ge_cui": GeCuiGainsSpec,
}


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
    method: Literal["vff", "masoud", "ge_cui", "cbf"] = "vff"
    gains: GainsSpec | MasoudGainsSpec | GeCuiGainsSpec | None = Field(
        None,
        description="gains of the method (vff and cbf: required / optional {k1, b, k3, k5}; "
        "masoud: {k1, k3, k5, direction}; ge_cui: {k1, b, k3, k5}; baselines default "
        "to Table C.1)",
    )
    stabilising: Literal["lyapunov", "off"] = "lyapunov"
    tie_side: Literal["+y", "-y"] = Field(
        "+y",
        description="detour side where the rules leave it open (docs/navigation.md, "
        "'The force field')",
    )
    cbf_gains: tuple[Positive, Positive] = Field(
        (4.0, 4.0), description="cbf only: (k_0, k_1) of h'' + k_1 h' + k_0 h >= 0"
    )

    @model_validator(mode="before")
    @classmethod
    def _typed_gains(cls, data: Any) -> Any:
        if isinstance(data, dict) and isinstance(data.get("gains"), dict):
            spec = _GAIN_SPECS.get(str(data.get("method", "vff")))
            if spec is not None:
                data = {**data, "gains": spec.model_validate(data["gains"])}
        return data

    @model_validator(mode="after")
    def _gains(self) -> MethodSpec:
        if self.method == "vff" and self.gains is None:
            raise ValueError(
                f"method {self.label!r}: the vff method needs gains: {{k1, b, k3, k5}}"
            )
        if self.gains is not None and not isinstance(self.gains, _GAIN_SPECS[self.method]):
            raise ValueError(f"method {self.label!r}: gains of the wrong kind for {self.method}")
        if self.method != "cbf" and "cbf_gains" in self.model_fields_set:
            raise ValueError(f"method {self.label!r}: cbf_gains apply to method cbf only")
        return self
