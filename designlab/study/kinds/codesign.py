"""The ``codesign`` study kind: foam, speed limit and VFF gains chosen together (issue 24).

Searches the Pareto front of foam (K_c, C_c, T_u), speed limit and VFF gains
(:func:`designlab.codesign.pareto`) and places the thesis's design against it; the
closing speeds of the thesis design's encounters with people
(:func:`designlab.codesign.contact_speeds`) are reported with it. Every
bound of the design space is the domains' declaration
(:class:`designlab.codesign.DesignSpace`, derived with
:func:`designlab.study.specs.spec_model`).

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: codesign
... name: demo
... scenarios: [{configuration: 2}]
... front: {objectives: [arrival_time, foam_thickness], population: 4, generations: 1}
... ''')
>>> r = run_study(study)
>>> r.front.status, len(r.front.X), r.contacts.obstacle
('ok', 4, ('human',))
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar, Literal

import pandas as pd
from pydantic import Field

import designlab.navigation as nav
from designlab.codesign import (
    OBJECTIVES,
    ContactSpeeds,
    DesignSpace,
    ParetoFront,
    pareto,
)
from designlab.codesign.contacts import MEASURES
from designlab.codesign.front import GENERATIONS, MAX_EVALUATIONS, POPULATION, SEED
from designlab.errors import StudyError
from designlab.params import params_of
from designlab.results import Result, Status
from designlab.study.base import Model, StudyBase
from designlab.study.kinds.foam_design import HeadRangeSpec
from designlab.study.kinds.impact_specs import RobotSpec
from designlab.study.kinds.navigation_specs import ScenarioSpec
from designlab.study.registry import StudyKind
from designlab.study.runner import RunContext
from designlab.study.specs import spec_model

__all__ = ["KIND", "CodesignResult", "CodesignStudy", "run"]

_WALKS = params_of(nav.RandomWalks)
_Objective = Literal[tuple(OBJECTIVES)]  # type: ignore[valid-type]
_Measure = Literal[MEASURES]  # type: ignore[valid-type]
_WalksN = _WALKS["n"].annotation()
_WalksSeed = _WALKS["seed"].annotation()
_Population = POPULATION.annotation()
_Generations = GENERATIONS.annotation()
_Seed = SEED.annotation()

#: The design space of the front: the bounds are the domains' declarations.
DesignSpaceSpec = spec_model(DesignSpace, name="DesignSpaceSpec")


class WalksSpec(Model):
    """Randomised walks: every walking human replaced by ``n`` seeded walks."""

    n: _WalksN = _WALKS["n"].default  # type: ignore[valid-type]
    seed: _WalksSeed = _WALKS["seed"].default  # type: ignore[valid-type]

    def build(self) -> nav.RandomWalks:
        """The :class:`~designlab.navigation.RandomWalks`."""
        return nav.RandomWalks(n=self.n, seed=self.seed)


class FrontSpec(Model):
    """The Pareto search: the space, the objectives and NSGA-II's budget."""

    space: DesignSpaceSpec = Field(default_factory=DesignSpaceSpec)  # type: ignore[valid-type]
    objectives: list[_Objective] = Field(  # type: ignore[valid-type]
        default_factory=lambda: ["arrival_time", "closing_speed", "foam_thickness"],
        min_length=2,
        description="objectives, all minimised (docs/codesign.md)",
    )
    population: _Population = 16  # type: ignore[valid-type]
    generations: _Generations = 8  # type: ignore[valid-type]
    seed: _Seed = 0  # type: ignore[valid-type]


class CodesignStudy(StudyBase):
    """Foam, speed limit and VFF gains chosen together: contact speeds and the Pareto front."""

    kind: Literal["codesign"]
    robot: RobotSpec = Field(  # type: ignore[valid-type]
        default_factory=lambda: RobotSpec.model_validate("MANIPULATOR_1"),
        description="the robot body at the contact point (impact model)",
    )
    head_range: HeadRangeSpec | None = Field(  # type: ignore[valid-type]
        None, description="head-neck ranges (default: the thesis's, Sec. 3.6)"
    )
    scenarios: list[ScenarioSpec] = Field(  # type: ignore[valid-type]
        min_length=1, max_length=16, description="navigation scenarios every design runs"
    )
    walks: WalksSpec | None = Field(
        None, description="randomised human walks for the contact speeds (none: as given)"
    )
    measure: _Measure = Field("relative", description="which closing speed counts")
    front: FrontSpec = Field(default_factory=FrontSpec)

    TYPICAL_DURATION: ClassVar[float] = 66  # s, the committed study, serial, loaded machine
    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "contacts.csv",
        "front.csv",
        "designs.csv",
        "reference.csv",
        "*.png",
        "study.yaml",
    )

    def check(self) -> None:
        """The search budget within its cap, and every spec built."""
        super().check()
        n = self.front.population * self.front.generations
        if n > MAX_EVALUATIONS:
            raise StudyError(
                f"front.population x front.generations = {n} designs is above the cap "
                f"{MAX_EVALUATIONS}",
                path=("front", "generations"),
            )
        if len(set(self.front.objectives)) != len(self.front.objectives):
            raise StudyError("objectives repeat", path=("front", "objectives"))

    def size(self) -> str:
        """What the study runs."""
        f = self.front
        return (
            f"{len(self.scenarios)} scenarios x {f.population * f.generations} designs "
            f"({f.population} x {f.generations} generations)"
        )


class CodesignStatus(Status):
    """Status of a :class:`CodesignResult`: that of its front (``ok`` or ``no_feasible``)."""

    OK = "ok"
    NO_FEASIBLE = "no_feasible"


@dataclass(frozen=True)
class CodesignResult(Result):
    """The contact speeds and the Pareto front of a ``codesign`` study.

    Attributes
    ----------
    study
        The study.
    contacts
        The thesis design's encounters in the scenarios
        (:class:`~designlab.codesign.ContactSpeeds`).
    front
        The :class:`~designlab.codesign.ParetoFront`.
    status, warnings
        The front's status; the warnings of the contacts and the front.
    """

    study: CodesignStudy
    contacts: ContactSpeeds = field(repr=False)
    front: ParetoFront = field(repr=False)
    status: str = CodesignStatus.OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """The front's non-dominated designs."""
        return self.front.to_frame()


def _scenarios(study: CodesignStudy) -> list[nav.Scenario]:
    built = [s.build() for s in study.scenarios]
    if study.walks is None:
        return built
    walks = study.walks.build()
    return [w for sc in built for w in walks.expand(sc)]


def run(study: CodesignStudy, context: RunContext) -> CodesignResult:
    """Collect the contact speeds and search the front, with progress bars.

    Parameters
    ----------
    study
        The validated study.
    context
        How to run it (progress bars).
    """
    scenarios = _scenarios(study)
    robot = study.robot.build()
    kw: dict[str, Any] = {"measure": study.measure}
    if study.head_range is not None:
        kw["heads"] = study.head_range.build()
    f = study.front
    with context.bar(f"{study.kind}: Pareto front", f.generations) as hook:
        front = pareto(
            scenarios, space=f.space.build(), objectives=tuple(f.objectives), robot=robot,
            population=f.population, generations=f.generations, seed=f.seed, progress=hook, **kw,
        )  # fmt: skip
    assert front.reference is not None  # the thesis's design is always placed
    contacts = front.reference.contacts
    return CodesignResult(
        study,
        contacts,
        front,
        status=CodesignStatus(str(front.status)),
        warnings=(*contacts.warnings, *front.warnings),
    )


KIND = StudyKind(
    name="codesign",
    schema=CodesignStudy,
    run=run,
    report="designlab.report.codesign",
)
