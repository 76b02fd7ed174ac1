"""The ``navigation_regions`` study kind: region sizes for a user's robot and obstacles.

For one robot (holonomic or nonholonomic, with its radius and limits) and a list of
obstacle classes (humans, stationary circles, other robots, rectangles) it sizes the
critical region r3 (the robot stops in time) and the active region r2 (it sidesteps
in time) with :func:`designlab.navigation.sizing.size_regions` (Zeng 2011, Sec. 5.3,
7.4, 7.5.5), and reports every intermediate quantity, the minimum and the adopted
radii, and the ``r2``/``r3`` to put in a scenario (``docs/navigation_scenarios.md``).

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: navigation_regions
... name: demo
... robot: {type: holonomic, max_speed: 0.7, max_accel: 10}
... obstacles:
...   - {name: human, type: human}
...   - {name: pillar, type: circle, radius: 0.1, critical_radius: 0.4}
... ''')
>>> r = run_study(study)
>>> r.status, [round(r2, 3) for r2, _ in r.plan.radii.values()]
('ok', [2.096, 0.467])
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import pandas as pd
from pydantic import Field, create_model, model_validator

from designlab.navigation.parameters import (
    SAMPLE_TIME,
    CircularObstacle,
    Human,
    ObstacleRobot,
    RectangularObstacle,
)
from designlab.navigation.sizing import MAX_OBSTACLES, RegionChoice, RegionPlan, size_regions
from designlab.params import params_of
from designlab.results import Result
from designlab.study.base import Model, StudyBase
from designlab.study.kinds.navigation_specs import RobotSpec
from designlab.study.registry import StudyKind
from designlab.study.reproduction import CLOSED_FORM
from designlab.study.runner import RunContext

__all__ = ["KIND", "NavigationRegionsResult", "NavigationRegionsStudy", "ObstacleClassSpec", "run"]

#: Obstacle ``type`` -> its class (Zeng 2011, Sec. 5.3.3-5.3.5, 7.5.5).
OBSTACLE_TYPES: dict[str, type] = {
    "human": Human,
    "circle": CircularObstacle,
    "robot": ObstacleRobot,
    "rectangle": RectangularObstacle,
}


def _optional_fields(*classes: type) -> dict[str, Any]:
    """Every field of the classes, optional (``None``: the class default)."""
    out: dict[str, Any] = {}
    for cls in classes:
        for n, d in params_of(cls).items():
            out.setdefault(n, (d.annotation(optional=True), None))
    return out


class _ObstacleClassBase(Model):
    def split(self) -> tuple[Any, RegionChoice]:
        """The obstacle class object and the adopted values."""
        data = self.model_dump(exclude_none=True)
        kind = data.pop("type")
        data.pop("name")
        cls = OBSTACLE_TYPES[kind]
        choice = {k: data.pop(k) for k in list(data) if k in params_of(RegionChoice)}
        unknown = sorted(set(data) - set(params_of(cls)))
        if unknown:
            raise ValueError(f"{unknown} do not apply to an obstacle of type {kind}")
        return cls(**data), RegionChoice(**choice)

    @model_validator(mode="after")
    def _builds(self) -> Any:
        self.split()
        return self


#: One obstacle class: ``name``, ``type`` (human, circle, robot, rectangle), the fields of
#: its class (radius, max_speed; length, width, offset) and the values adopted
#: (:class:`~designlab.navigation.sizing.RegionChoice`).
ObstacleClassSpec = create_model(
    "ObstacleClassSpec",
    __base__=_ObstacleClassBase,
    __doc__="One obstacle class with the values adopted for its regions.",
    name=(str, Field(min_length=1, max_length=60)),
    type=(Literal[tuple(OBSTACLE_TYPES)], ...),  # type: ignore[valid-type]
    **_optional_fields(*OBSTACLE_TYPES.values(), RegionChoice),
)


class NavigationRegionsStudy(StudyBase):
    """Critical and active region sizes for one robot among the user's obstacle classes."""

    kind: Literal["navigation_regions"]
    robot: RobotSpec = Field(default_factory=RobotSpec)  # type: ignore[valid-type]
    sample_time: SAMPLE_TIME.annotation() = 0.06  # type: ignore[valid-type]
    obstacles: list[ObstacleClassSpec] = Field(min_length=1, max_length=MAX_OBSTACLES)  # type: ignore[valid-type]

    PRODUCES: ClassVar[tuple[str, ...]] = ("summary.md", "regions.csv", "study.yaml")
    TYPICAL_DURATION: ClassVar[float] = 1  # s, the committed study, serial, this machine

    @model_validator(mode="after")
    def _unique(self) -> NavigationRegionsStudy:
        names = [o.name for o in self.obstacles]
        if len(set(names)) != len(names):
            raise ValueError("obstacle names must be unique")
        self.plan()
        return self

    def size(self) -> str:
        """The number of obstacle classes."""
        return f"{len(self.obstacles)} obstacle class(es)"

    def plan(self) -> RegionPlan:
        """The sizes (:func:`~designlab.navigation.sizing.size_regions`)."""
        parts = {o.name: o.split() for o in self.obstacles}
        return size_regions(
            self.robot.build(),
            {n: p[0] for n, p in parts.items()},
            self.sample_time,
            {n: p[1] for n, p in parts.items()},
        )


@dataclass(frozen=True)
class NavigationRegionsResult(Result):
    """Result of a ``navigation_regions`` study.

    Attributes
    ----------
    study
        The validated study.
    plan
        The sizes, with every intermediate quantity.
    """

    study: NavigationRegionsStudy
    plan: RegionPlan

    @property
    def status(self) -> str:  # type: ignore[override]
        """The plan's status."""
        return self.plan.status

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """The plan's warnings."""
        return self.plan.warnings

    def to_frame(self) -> pd.DataFrame:
        """One row per obstacle class with every quantity."""
        return self.plan.to_frame()


def run(study: NavigationRegionsStudy, context: RunContext) -> NavigationRegionsResult:
    """Size the regions (in this process; nothing is stored).

    Parameters
    ----------
    study
        The validated study.
    context
        How to run it (ignored: the sizing takes well under a second).
    """
    return NavigationRegionsResult(study, study.plan())


KIND = StudyKind(
    name="navigation_regions",
    schema=NavigationRegionsStudy,
    run=run,
    report="designlab.report.navigation_regions",
    reproduction=CLOSED_FORM,
)
