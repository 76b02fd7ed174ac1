"""The ``codesign`` study kind: foam, speed limit and VFF gains chosen together (issue 24).

Computes the speed-limit map over foam stiffness x damping
(:func:`designlab.codesign.speed_limit_map`) and the risk curves P(criterion exceeded |
contact) against the closing speed for a few foams
(:func:`designlab.codesign.fragility_curve`), then searches the Pareto front of foam
(K_c, C_c, T_u), speed limit and VFF gains
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
... speed_map: {stiffness: {low: 1.0e+4, high: 6.0e+4, num: 3}, damping: {num: 3}}
... risk: {foams: [FOAM_1], speeds: {low: 1.0, high: 3.0, num: 3}, samples: 2000}
... ''')
>>> r = run_study(study)
>>> r.front.status, len(r.front.X), r.contacts.obstacle, r.speed_map.max_speed.shape
('ok', 4, ('human',), (3, 3))
>>> len(r.risk)
3
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field
from typing import Any, ClassVar, Literal

import numpy as np
import pandas as pd
from pydantic import Field, model_validator

import designlab.navigation as nav
from designlab.analysis.sensitivity import SensitivityTable
from designlab.codesign import (
    OBJECTIVES,
    ContactSpeeds,
    CrowdEncounters,
    DesignSpace,
    ParetoFront,
    SpeedLimitMap,
    contact_speeds,
    fragility_curve,
    injury_probability,
    pareto,
    speed_limit_map,
)
from designlab.codesign.assessment import Exposure, exposure, iso_comparison
from designlab.codesign.contacts import MEASURES
from designlab.codesign.front import (
    GENERATIONS,
    MAX_EVALUATIONS,
    POPULATION,
    RISK_BOUND,
    SEED,
    Design,
    design_runs,
)
from designlab.codesign.injury import head_injury_risk, hic_curves
from designlab.codesign.parameters import MAP_POINTS, RISK_SAMPLES, SENSITIVITY_SAMPLES
from designlab.codesign.robot import BUMPER_BASE, THESIS_ROBOT, RobotDescription
from designlab.codesign.sensitivity import front_sensitivity
from designlab.codesign.speed import SafetyCase, speed_limit
from designlab.errors import StudyError
from designlab.impact import ContactDynamics, Foam, HeadInjuryCriterion
from designlab.impact.parameters import HUMAN_SPEED, IMPACT_VELOCITY
from designlab.params import params_of
from designlab.progress import Progress, ProgressHook, report
from designlab.results import Result, Status
from designlab.study.base import Model, StudyBase
from designlab.study.kinds.foam_design import CriterionSpec, HeadRangeSpec
from designlab.study.kinds.impact_specs import DampingGrid, FoamSpec, RobotSpec
from designlab.study.kinds.navigation_crowds import CrowdSpec
from designlab.study.kinds.navigation_specs import ScenarioSpec
from designlab.study.registry import StudyKind
from designlab.study.reproduction import CODESIGN
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
_Stiffness = params_of(Foam)["stiffness"].annotation()
_Speed = IMPACT_VELOCITY.annotation()
_Points = MAP_POINTS.annotation()
_Samples = RISK_SAMPLES.annotation()
_SobolN = SENSITIVITY_SAMPLES.annotation()
_CROWD = params_of(nav.CrowdScenario)
_Pedestrians = _CROWD["pedestrians"].annotation()
_CrowdSeed = _CROWD["seed"].annotation()
_HumanSpeed = HUMAN_SPEED.annotation()
_RiskBound = RISK_BOUND.annotation()

#: The robot descriptions a study can name (:mod:`designlab.codesign.robot`).
PLATFORMS = {"THESIS_ROBOT": THESIS_ROBOT, "BUMPER_BASE": BUMPER_BASE}

#: The design space of the front: the bounds are the domains' declarations.
DesignSpaceSpec = spec_model(DesignSpace, name="DesignSpaceSpec")


class WalksSpec(Model):
    """Randomised walks: every walking human replaced by ``n`` seeded walks."""

    n: _WalksN = _WALKS["n"].default  # type: ignore[valid-type]
    seed: _WalksSeed = _WALKS["seed"].default  # type: ignore[valid-type]

    def build(self) -> nav.RandomWalks:
        """The :class:`~designlab.navigation.RandomWalks`."""
        return nav.RandomWalks(n=self.n, seed=self.seed)


class StiffnessGrid(Model):
    """The K_c axis of the speed-limit map, N/m: ``num`` values from ``low`` to ``high``."""

    low: _Stiffness = 5.0e3  # type: ignore[valid-type]
    high: _Stiffness = 80.0e3  # type: ignore[valid-type]
    num: _Points = 9  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _order(self) -> StiffnessGrid:
        if not self.low < self.high:
            raise ValueError(f"low = {self.low:g} N/m must be < high = {self.high:g} N/m")
        return self

    def values(self) -> list[float]:
        """The grid."""
        return np.linspace(self.low, self.high, self.num).tolist()


class SpeedGrid(Model):
    """Closing speeds of the risk curves, m/s: ``num`` values from ``low`` to ``high``."""

    low: _Speed = 0.25  # type: ignore[valid-type]
    high: _Speed = 4.0  # type: ignore[valid-type]
    num: _Points = 12  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _order(self) -> SpeedGrid:
        if not self.low < self.high:
            raise ValueError(f"low = {self.low:g} m/s must be < high = {self.high:g} m/s")
        return self

    def values(self) -> list[float]:
        """The grid."""
        return np.linspace(self.low, self.high, self.num).tolist()


class SpeedMapSpec(Model):
    """The speed-limit map: the robot speed every contact allows, over K_c x C_c."""

    stiffness: StiffnessGrid = Field(default_factory=StiffnessGrid)
    damping: DampingGrid = Field(default_factory=lambda: DampingGrid(low=10.0, num=9))
    criteria: list[CriterionSpec] | None = Field(  # type: ignore[valid-type]
        None, min_length=1, description="default: a_h,max <= 10 g (and the thickness limit)"
    )


class CrowdEncountersSpec(Model):
    """Crowd runs whose encounters feed the risk.

    The thesis's design (experiment gains) runs them for the crowd risk table; with the
    front objective ``crowd_injury_probability`` every candidate design also runs them
    with its own gains and speed limit (cached per gains and speed limit).
    """

    layout: Literal["corridor_counterflow", "crossing", "bottleneck", "open_plaza"] = Field(
        description="crowd layout (:func:`designlab.navigation.crowd`)"
    )
    pedestrians: _Pedestrians = Field(20, description="pedestrians in each crowd")  # type: ignore[valid-type]
    seeds: list[_CrowdSeed] = Field(  # type: ignore[valid-type]
        default_factory=lambda: [0], min_length=1, max_length=64, description="one run per seed"
    )
    options: CrowdSpec = Field(  # type: ignore[valid-type]
        default_factory=CrowdSpec, description="the other crowd options"
    )

    def build(self) -> list[nav.CrowdScenario]:
        """The crowds, one per seed."""
        kw = self.options.build()
        return [nav.crowd(self.layout, self.pedestrians, seed=s, **kw) for s in self.seeds]


class RiskSpec(Model):
    """Risk curves: P(criterion exceeded | contact) against a fixed closing speed."""

    foams: list[FoamSpec] = Field(  # type: ignore[valid-type]
        default_factory=lambda: [
            FoamSpec.model_validate(n) for n in ("FOAM_1", "FOAM_2", "FOAM_3")
        ],
        min_length=1,
        max_length=8,
    )
    criterion: CriterionSpec | None = Field(  # type: ignore[valid-type]
        None, description="also the front's injury criterion; default: a_h,max <= 10 g"
    )
    speeds: SpeedGrid = Field(default_factory=SpeedGrid)
    samples: _Samples = 20_000  # type: ignore[valid-type]


class FrontSpec(Model):
    """The Pareto search: the space, the objectives, the constraints' statements and
    NSGA-II's budget (seeded with the thesis's designs; more seeds compared)."""

    space: DesignSpaceSpec = Field(default_factory=DesignSpaceSpec)  # type: ignore[valid-type]
    objectives: list[_Objective] = Field(  # type: ignore[valid-type]
        default_factory=lambda: ["arrival_time", "closing_speed", "foam_thickness"],
        min_length=2,
        description="objectives, all minimised (docs/codesign.md)",
    )
    population: _Population = 16  # type: ignore[valid-type]
    generations: _Generations = 8  # type: ignore[valid-type]
    seed: _Seed = SEED.default  # type: ignore[valid-type]
    compare_seeds: list[_Seed] = Field(  # type: ignore[valid-type]
        default_factory=list, max_length=4,
        description="further seeds whose fronts are compared with the first's",
    )  # fmt: skip
    human_speed: _HumanSpeed = Field(  # type: ignore[valid-type]
        1.0, description="the walker's speed of the speed-limit constraint and the regions"
    )
    risk_bound: _RiskBound = Field(  # type: ignore[valid-type]
        1.0, description="stated upper bound on P(criterion exceeded | contact) (1: none)"
    )
    preference: list[float] | None = Field(
        None, description="weights of the objectives (normalised over the front) of the pick; "
        "default: equal",
    )  # fmt: skip

    @model_validator(mode="after")
    def _weights(self) -> FrontSpec:
        w = self.preference
        if w is not None and (len(w) != len(self.objectives) or min(w) < 0 or not sum(w) > 0):
            raise ValueError(f"preference must be {len(self.objectives)} non-negative weights, "
                             "not all zero")  # fmt: skip
        return self


class SensitivitySpec(Model):
    """Sobol indices of the front's objectives (and feasibility) to the design variables.

    Over the front's space and objectives (docs/codesign.md): ``samples * (D + 2)``
    designs for D free variables, each a set of navigation runs.
    """

    samples: _SobolN = SENSITIVITY_SAMPLES.default  # type: ignore[valid-type]
    seed: _Seed = SEED.default  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _power_of_two(self) -> SensitivitySpec:
        if self.samples & (self.samples - 1):
            raise ValueError(f"samples = {self.samples} must be a power of two (Saltelli)")
        return self


class CodesignStudy(StudyBase):
    """Foam, speed limit and VFF gains chosen together: contact speeds and the Pareto front."""

    kind: Literal["codesign"]
    robot: RobotSpec = Field(  # type: ignore[valid-type]
        default_factory=lambda: RobotSpec.model_validate("MANIPULATOR_1"),
        description="the robot body at the contact point (impact model)",
    )
    platform: Literal["THESIS_ROBOT", "BUMPER_BASE"] = Field(
        "THESIS_ROBOT", description="the robot description navigation, impact and co-design "
        "read (its touching part's impact model is `robot`; docs/codesign.md)",
    )  # fmt: skip
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
    crowds: CrowdEncountersSpec | None = Field(
        None, description="crowd encounters as a closing-speed distribution of the risk"
    )
    front: FrontSpec = Field(default_factory=FrontSpec)
    sensitivity: SensitivitySpec | None = Field(
        None, description="Sobol indices of the front's objectives (none: not computed)"
    )
    speed_map: SpeedMapSpec = Field(default_factory=SpeedMapSpec)
    risk: RiskSpec = Field(default_factory=RiskSpec)

    TYPICAL_DURATION: ClassVar[float] = 608  # s, wall time measured at load 14 (108 s CPU)
    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "speed_map.csv",
        "risk.csv",
        "contacts.csv",
        "front.csv",
        "designs.csv",
        "reference.csv",
        "sensitivity.csv",
        "seeds.csv",
        "hypervolume.csv",
        "iso.csv",
        "*.png",
        "study.yaml",
    )

    def check(self) -> None:
        """The search budget within its cap, and every spec built."""
        super().check()
        f = self.front
        n = f.population * f.generations * (1 + len(f.compare_seeds))
        if n > MAX_EVALUATIONS:
            raise StudyError(
                f"front.population x front.generations x seeds = {n} designs is above the cap "
                f"{MAX_EVALUATIONS}",
                path=("front", "generations"),
            )
        if len(set(self.front.objectives)) != len(self.front.objectives):
            raise StudyError("objectives repeat", path=("front", "objectives"))
        if "crowd_injury_probability" in f.objectives and self.crowds is None:
            raise StudyError(
                "the objective crowd_injury_probability needs a crowds section",
                path=("front", "objectives"),
            )
        if self.sensitivity is not None:
            free = int(f.space.build().free.sum())
            m = self.sensitivity.samples * (free + 2)
            if free < 2 or m > MAX_EVALUATIONS:
                raise StudyError(
                    f"sensitivity: {m} designs ({free} free variables) must have at least two "
                    f"free variables and be at most {MAX_EVALUATIONS}",
                    path=("sensitivity", "samples"),
                )
        points = len(self.risk.foams) * self.risk.speeds.num * self.risk.samples
        if points > 10**8:
            raise StudyError(
                f"risk: {points} Monte Carlo samples in all is above the cap 1e8",
                path=("risk", "samples"),
            )

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
    speed_map
        The :class:`~designlab.codesign.SpeedLimitMap`.
    risk
        The risk curves: foam, closing speed, probability and its interval.
    crowd_risk
        With ``crowds``: per foam, the probability over the crowd encounters' closing speeds.
    sensitivity
        With ``sensitivity``: the Sobol indices of the front's objectives
        (:func:`designlab.codesign.front_sensitivity`).
    platform
        The robot description navigation, impact and co-design read.
    seed_fronts
        The fronts of ``front.compare_seeds``.
    iso
        ISO/TS 15066 beside the Zeng speed limit for the picked design's foam
        (:func:`designlab.codesign.assessment.iso_comparison`).
    exposure
        Contacts with people per hour of the picked design's runs
        (:func:`designlab.codesign.assessment.exposure`).
    head_risk
        The picked design's worst head contact (at V_mr + the walker's speed): its HIC15
        and the cited curves' risks (:func:`designlab.codesign.injury.head_injury_risk`).
    cpu_seconds
        CPU time of the searches (every seed), s.
    status, warnings
        The front's status; the warnings of the contacts and the front.
    """

    study: CodesignStudy
    contacts: ContactSpeeds = field(repr=False)
    front: ParetoFront = field(repr=False)
    speed_map: SpeedLimitMap = field(repr=False)
    risk: pd.DataFrame = field(repr=False)
    status: str = CodesignStatus.OK
    warnings: tuple[str, ...] = ()
    crowd_risk: pd.DataFrame | None = field(default=None, repr=False)
    sensitivity: SensitivityTable | None = field(default=None, repr=False)
    platform: RobotDescription | None = field(default=None, repr=False)
    seed_fronts: tuple[ParetoFront, ...] = field(default=(), repr=False)
    iso: pd.DataFrame | None = field(default=None, repr=False)
    exposure: Exposure | None = field(default=None, repr=False)
    head_risk: dict[str, float] = field(default_factory=dict, repr=False)
    cpu_seconds: float = math.nan

    def to_frame(self) -> pd.DataFrame:
        """The front's non-dominated designs."""
        return self.front.to_frame()


def _scenarios(study: CodesignStudy) -> list[nav.Scenario]:
    built = [s.build() for s in study.scenarios]
    if study.walks is None:
        return built
    walks = study.walks.build()
    return [w for sc in built for w in walks.expand(sc)]


def _foam_label(foam: Foam, k: int) -> str:
    return foam.name or f"foam {k + 1}"


def risk_curves(
    study: CodesignStudy, robot: Any, heads: Any, progress: ProgressHook | None = None
) -> pd.DataFrame:
    """P(criterion exceeded | contact) at each closing speed of the grid, for each foam.

    Parameters
    ----------
    study
        The study (its ``risk`` section).
    robot
        The impact robot.
    heads
        The head-neck range (``None``: the injury model's default).
    progress
        Called after each foam.
    """
    spec = study.risk
    crit = None if spec.criterion is None else spec.criterion.build()
    frames = []
    foams = [f.build() for f in spec.foams]
    for k, foam in enumerate(foams):
        curve = fragility_curve(
            robot, foam, spec.speeds.values(), heads=heads, criterion=crit,
            samples=spec.samples, seed=study.front.seed,
        )  # fmt: skip
        frames.append(pd.DataFrame({
            "foam": _foam_label(foam, k), "K_c_N_per_m": foam.stiffness,
            "C_c_N_s_per_m": foam.damping, "v_c_m_per_s": curve.speeds,
            "probability": curve.probability, "low": curve.low, "high": curve.high,
        }))  # fmt: skip
        report(progress, Progress(k + 1, len(foams), label="foam"))
    return pd.concat(frames, ignore_index=True)


def crowd_risk(study: CodesignStudy, robot: Any, heads: Any) -> pd.DataFrame | None:
    """P(criterion exceeded | contact) for each risk foam over the crowd encounters.

    The thesis's design (experiment gains) runs each crowd; the encounters
    (:func:`~designlab.codesign.contact_speeds` with the study's ``measure``) are the
    closing-speed distribution of :func:`~designlab.codesign.injury_probability`.

    Parameters
    ----------
    study
        The study (its ``crowds``, ``risk`` and ``measure``).
    robot
        The impact robot.
    heads
        The head-neck range (``None``: the injury model's default).
    """
    if study.crowds is None:
        return None
    runs = [nav.simulate(c, nav.EXPERIMENT_GAINS) for c in study.crowds.build()]
    speeds = contact_speeds(runs, measure=study.measure)
    if speeds.status != "ok":
        return None
    crit = None if study.risk.criterion is None else study.risk.criterion.build()
    rows = []
    for k, foam in enumerate(f.build() for f in study.risk.foams):
        r = injury_probability(
            robot, foam, speeds, heads=heads, criterion=crit, samples=study.risk.samples,
            seed=study.front.seed,
        )  # fmt: skip
        rows.append({
            "foam": _foam_label(foam, k), "encounters": len(speeds),
            "contacts": speeds.n_contacts, "v_mean_m_per_s": speeds.mean(),
            "probability": r.probability, "low": r.interval[0], "high": r.interval[1],
        })  # fmt: skip
    return pd.DataFrame(rows)


def platform_of(study: CodesignStudy) -> RobotDescription:
    """The study's robot description with its touching part's impact model.

    Parameters
    ----------
    study
        The study (``platform`` and ``robot``).
    """
    contact = study.robot.build()
    if not isinstance(contact, ContactDynamics):
        raise StudyError("robot: a co-design robot's touching part must be a fixed contact "
                         "(ContactDynamics)", path=("robot",))  # fmt: skip
    return dataclasses.replace(PLATFORMS[study.platform], contact=contact)


def pick_of(front: ParetoFront, preference: list[float] | None) -> int | None:
    """The row of ``front.to_frame()`` the stated preference picks (equal weights by default).

    Parameters
    ----------
    front
        The front.
    preference
        Weights per objective.
    """
    if not front.front.any():
        return None
    w = preference if preference is not None else [1.0] * len(front.objectives)
    return front.pick(w)


def head_risk_of(robot: RobotDescription, design: Design, walker: float) -> dict[str, float]:
    """The worst head contact of a design (v_c = V_mr + walker): HIC15 and the cited risks.

    Parameters
    ----------
    robot, design, walker
        The robot, the design and the walker's speed (m/s).
    """
    crit = HeadInjuryCriterion(650.0)
    s = speed_limit(robot.contact, design.foam, SafetyCase(criteria=[crit], human_speed=walker))
    v = design.speed + walker
    hic = s.unit_metric[crit.name] * v**crit.velocity_exponent
    out = {"closing_speed_m_per_s": v, "hic15": hic}
    out.update({name: head_injury_risk(hic, name) for name in hic_curves()})
    return out


def _assess(study: CodesignStudy, platform: RobotDescription, front: ParetoFront,
            scenarios: list[nav.Scenario]) -> tuple[Any, Any, dict[str, float]]:  # fmt: skip
    """ISO/TS 15066 table, exposure and head risk of the picked design (else the thesis's).

    The exposure counts the design's contacts with people in the scenarios and in the
    study's crowds (driven with the design's gains and speed limit), each at its closing
    speed after braking, and weighs them with the AIS3+ risk of a head contact at that
    speed (Prasad and Mertz 1985, HIC15 of the worst head).
    """
    row = pick_of(front, study.front.preference)
    design = front.designs()[row] if row is not None else front.references[0].score.design
    walker = study.front.human_speed
    runs: list[Any] = design_runs(design, scenarios, platform, walker)
    if study.crowds is not None:
        runs += [nav.simulate(dataclasses.replace(
            c, robot=dataclasses.replace(c.robot, max_speed=design.speed)), design.gains)
            for c in study.crowds.build()]  # fmt: skip
    head = head_risk_of(platform, design, walker)
    worst = head["closing_speed_m_per_s"]
    e = HeadInjuryCriterion(650.0).velocity_exponent  # HIC scales as v_c ** 2.5
    per_unit = head["hic15"] / worst**e

    def harm(v: float) -> float:
        return head_injury_risk(per_unit * v**e, "prasad_mertz_ais3")

    expo = exposure(runs, harm=harm, worst_speed=worst, human_speed=walker)
    return iso_comparison(platform, design.foam, walker), expo, head


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
    platform = platform_of(study)
    robot = platform.contact
    heads = None if study.head_range is None else study.head_range.build()
    kw: dict[str, Any] = {"measure": study.measure, "risk_samples": study.risk.samples}
    if study.risk.criterion is not None:
        kw["criterion"] = study.risk.criterion.build()
    if heads is not None:
        kw["heads"] = heads
    if study.crowds is not None and "crowd_injury_probability" in study.front.objectives:
        kw["crowds"] = CrowdEncounters(study.crowds.build(), study.measure)
    sm = study.speed_map
    smap = speed_limit_map(
        robot, K_c=sm.stiffness.values(), C_c=sm.damping.values(),
        case=SafetyCase(
            criteria=None if sm.criteria is None else [c.build() for c in sm.criteria],
            head_range=heads,
        ),
    )  # fmt: skip
    with context.bar(f"{study.kind}: risk curves", len(study.risk.foams)) as hook:
        risk = risk_curves(study, robot, heads, hook)
    f = study.front
    kw.update(human_speed=f.human_speed, risk_bound=f.risk_bound)
    cpu = time.process_time()
    fronts = []
    for seed in (f.seed, *f.compare_seeds):
        with context.bar(f"{study.kind}: Pareto front (seed {seed})", f.generations) as hook:
            fronts.append(pareto(
                scenarios, space=f.space.build(), objectives=tuple(f.objectives),
                robot=platform, population=f.population, generations=f.generations, seed=seed,
                progress=hook, executor=context.executor, **kw,
            ))  # fmt: skip
    # this process's CPU time and the executor's workers' (0 when serial)
    cpu = time.process_time() - cpu + sum(fr.worker_cpu_seconds for fr in fronts)
    front = fronts[0]
    assert front.reference is not None  # the thesis's design is always placed
    sens = None
    if study.sensitivity is not None:
        s = study.sensitivity
        with context.bar(f"{study.kind}: sensitivity", None) as hook:
            sens = front_sensitivity(
                scenarios, space=f.space.build(), objectives=tuple(f.objectives), robot=robot,
                samples=s.samples, seed=s.seed, progress=hook, **_sobol_kw(kw),
            )  # fmt: skip
    contacts = front.reference.contacts
    iso, expo, head = _assess(study, platform, front, scenarios)
    return CodesignResult(
        study,
        contacts,
        front,
        smap,
        risk,
        status=CodesignStatus(str(front.status)),
        warnings=(*smap.warnings, *contacts.warnings, *front.warnings),
        crowd_risk=crowd_risk(study, robot, heads),
        sensitivity=sens,
        platform=platform,
        seed_fronts=tuple(fronts[1:]),
        iso=iso,
        exposure=expo,
        head_risk=head,
        cpu_seconds=cpu,
    )


def _sobol_kw(kw: dict[str, Any]) -> dict[str, Any]:
    """The front's keywords that :func:`~designlab.codesign.front_sensitivity` takes."""
    return {k: v for k, v in kw.items() if k not in ("human_speed", "risk_bound")}


KIND = StudyKind(
    name="codesign",
    schema=CodesignStudy,
    run=run,
    report="designlab.report.codesign",
    reproduction=CODESIGN,
)
