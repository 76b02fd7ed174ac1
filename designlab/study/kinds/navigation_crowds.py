"""The ``navigation_crowds`` study kind: robots among crowds from a pedestrian simulator.

Every layout x density x seed x method is simulated
(:func:`designlab.navigation.crowds.study.crowd_study`, through the run's executor and result
store) and summarised with Wilson
intervals; optionally VFF's gains are optimised over a training set of crowds
(:func:`designlab.navigation.crowds.tuning.optimise_crowd_gains`: robust mean or CVaR of the
time to goal plus a continuous penalty on the amount of violation) and validated on held-out
crowds one factor at a time (new seeds; then a new density; then a new layout) against the
gains to compare (the thesis's, the Configurations 1-3 optimum). The representative and the
worst run of each method are simulated again (runs are deterministic) for the report's plots
and animations
(``docs/navigation_crowds.md``).

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: navigation_crowds
... name: demo
... scenarios: [corridor_counterflow]
... densities: [0.1]
... seeds: [0]
... methods: [{method: vff}]
... crowd: {length: 8.0, horizon: 1.0}
... ''')
>>> r = run_study(study)
>>> r.to_frame()[["scenario", "method", "runs", "timeout_rate"]].values.tolist()
[['corridor_counterflow', 'vff', 1.0, 1.0]]
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Annotated, Any, ClassVar, Literal

import pandas as pd
from pydantic import Field, model_validator

from designlab.errors import DesignlabError, StudyError
from designlab.navigation.crowds.layouts import LAYOUTS
from designlab.navigation.crowds.metrics import CONFIDENCE, CVAR_ALPHA, PERSONAL_SPACE
from designlab.navigation.crowds.scenario import DENSITY, CrowdScenario, crowd
from designlab.navigation.crowds.study import (
    MAX_RUNS,
    MODEL,
    CrowdStudy,
    crowd_study,
    simulate_run,
)
from designlab.navigation.crowds.study import SEED as CROWD_SEED
from designlab.navigation.crowds.tuning import (
    PENALTY,
    RATE,
    CrowdGainOptimum,
    CrowdSet,
    GainValidation,
    optimise_crowd_gains,
    validate_gains,
    validation_steps,
)
from designlab.navigation.methods import METHODS, STABILISING
from designlab.navigation.tuning import DEFAULT_BOUNDS
from designlab.progress import Progress
from designlab.results import Result
from designlab.study.base import Flag, Integer, Model, StudyBase
from designlab.study.kinds.navigation_specs import (
    GainsSpec,
    GeCuiGainsSpec,
    MasoudGainsSpec,
    _gains_spec,
    typed_gains,
)
from designlab.study.registry import StudyKind
from designlab.study.reproduction import CROWD_TUNING
from designlab.study.runner import RunContext
from designlab.study.specs import spec_model

__all__ = ["KIND", "CrowdMethodSpec", "NavigationCrowdsResult", "NavigationCrowdsStudy", "run"]

#: Fields of a crowd set by the study's grid (the rest are the ``crowd`` options).
_GRID = ("layout", "pedestrians", "seed", "density", "start", "goal", "origin", "paths")
_CrowdFields = spec_model(CrowdScenario, exclude=_GRID, name="CrowdFields", what="crowd")


class CrowdSpec(_CrowdFields):  # type: ignore[valid-type, misc]
    """Options of every crowd (the fields of ``CrowdScenario`` not set by the study's grid)."""

    def build(self) -> dict[str, Any]:
        """The keywords of :func:`~designlab.navigation.crowd` (the crowd itself is built per
        run; :meth:`NavigationCrowdsStudy.check` builds one per layout and density)."""
        return self.model_dump()


_Layout = Literal["corridor_counterflow", "crossing", "bottleneck", "open_plaza"]
_Seed = CROWD_SEED.annotation()
_Density = DENSITY.annotation()
_Method = METHODS.literal(crowds=True)
_Model = MODEL.annotation()


class CrowdMethodSpec(Model):
    """A method among the crowd, optionally tagged to compare gain sets (``vff:thesis``)."""

    method: _Method = "vff"
    tag: str = Field("", max_length=40, pattern=r"^[A-Za-z0-9_.-]*$",
                     description="names a gain set: the label is method:tag")  # fmt: skip
    gains: GainsSpec | MasoudGainsSpec | GeCuiGainsSpec | None = Field(  # type: ignore[valid-type]
        None, description="vff/cbf {k1, b, k3, k5}; the baselines default to Table C.1"
    )
    stabilising: STABILISING.annotation() | None = Field(  # type: ignore[valid-type]
        None, description="VFF's stabilising force for this method (default: the study's)"
    )

    @property
    def label(self) -> str:
        """``method`` or ``method:tag``."""
        return f"{self.method}:{self.tag}" if self.tag else self.method

    @model_validator(mode="before")
    @classmethod
    def _typed_gains(cls, data: Any) -> Any:
        """Read ``gains`` as the method's own kind ({direction: -1} is Masoud's, not VFF's)."""
        return typed_gains(data)

    @model_validator(mode="after")
    def _gains_of_the_method(self) -> CrowdMethodSpec:
        if self.gains is not None and not isinstance(self.gains, _gains_spec(self.method)):
            raise ValueError(f"method {self.label!r}: gains of the wrong kind for {self.method}")
        return self


class CrowdSetSpec(Model):
    """Crowds of a training or validation set (the study's ``crowd`` options apply)."""

    scenarios: list[_Layout] = Field(min_length=1, max_length=4)
    densities: list[_Density] = Field(min_length=1, max_length=10)  # type: ignore[valid-type]
    seeds: list[_Seed] = Field(min_length=1, max_length=200)


class ValidationSpec(Model):
    """Held-out crowds, one factor changed at a time
    (:func:`~designlab.navigation.crowds.tuning.validation_steps`): the training layouts and
    densities with ``seeds``; then at ``density``; then also in ``scenario``."""

    seeds: list[_Seed] = Field(min_length=2, max_length=200)
    density: _Density  # type: ignore[valid-type]
    scenario: _Layout


class TuningSpec(Model):
    """Optimise VFF's gains over ``training``; validate one factor at a time (seeds, then
    density, then layout) against the first gains of ``compare``."""

    training: CrowdSetSpec
    validation: ValidationSpec
    robust: Literal["mean", "cvar"] = "mean"
    alpha: CVAR_ALPHA.annotation() = 0.8  # type: ignore[valid-type]
    collision_rate: RATE.annotation() | None = Field(  # type: ignore[valid-type]
        None, description="largest collision rate over the training runs (default: CrowdSet's, 0)"
    )
    critical_rate: RATE.annotation() | None = Field(  # type: ignore[valid-type]
        None, description="largest critical-entry rate over the training runs (default: CrowdSet's)"
    )
    popsize: Annotated[Integer, Field(ge=4, le=64)] = 6
    generations: Annotated[Integer, Field(ge=1, le=100)] = 4
    seed: _Seed = CROWD_SEED.default
    penalty: PENALTY.annotation() | None = Field(  # type: ignore[valid-type]
        None, description="seconds of fitness per unit of mean violation (default: the time limit)"
    )
    stabilising: STABILISING.annotation() | None = Field(  # type: ignore[valid-type]
        None, description="VFF's stabilising force while tuning and validating (default: the "
        "study's)",
    )  # fmt: skip
    compare: dict[str, GainsSpec] = Field(  # type: ignore[valid-type]
        min_length=1, max_length=6,
        description="tag -> gains validated beside the optimum (the first is the reference)",
    )  # fmt: skip

    @model_validator(mode="after")
    def _disjoint(self) -> TuningSpec:
        v = self.validation
        validation_steps(crowd_set(self, self.training, {}), v.seeds, v.density, v.scenario)
        if {"crowd_optimum", "crowd_least_violating"} & set(self.compare):
            raise ValueError("compare: the tags crowd_optimum and crowd_least_violating are the "
                             "optimum's")  # fmt: skip
        return self


def crowd_set(tuning: TuningSpec, spec: CrowdSetSpec, crowd: dict[str, Any]) -> CrowdSet:
    """The :class:`CrowdSet` of ``spec`` with the study's crowd options and the rates of
    ``tuning`` (those not given keep CrowdSet's defaults).

    Parameters
    ----------
    tuning
        The study's tuning section (its rate bounds).
    spec
        Its training or validation set.
    crowd
        The study's crowd options.
    """
    rates = {k: getattr(tuning, k) for k in ("collision_rate", "critical_rate")}
    return CrowdSet(tuple(spec.scenarios), tuple(spec.densities), tuple(spec.seeds), crowd,
                    **{k: v for k, v in rates.items() if v is not None})  # fmt: skip


class NavigationCrowdsStudy(StudyBase):
    """Rates, clearances and pedestrian delays of navigation methods among crowds."""

    kind: Literal["navigation_crowds"]
    scenarios: list[_Layout] = Field(min_length=1, max_length=4)
    densities: list[_Density] = Field(min_length=1, max_length=10)  # type: ignore[valid-type]
    seeds: list[_Seed] = Field(min_length=1, max_length=1000)
    methods: list[CrowdMethodSpec] = Field(min_length=1, max_length=8)
    models: list[_Model] | None = Field(  # type: ignore[valid-type]
        None, min_length=1, max_length=4,
        description="JuPedSim models: every crowd of the grid under each (default: crowd.model)",
    )  # fmt: skip
    stabilising: STABILISING.annotation() = "lyapunov"  # type: ignore[valid-type]
    crowd: CrowdSpec = Field(default_factory=CrowdSpec)  # type: ignore[valid-type]
    personal_space: PERSONAL_SPACE.annotation() = 1.2  # type: ignore[valid-type]
    confidence: CONFIDENCE.annotation() = 0.95  # type: ignore[valid-type]
    tuning: TuningSpec | None = None
    animations: Flag = Field(True, description="GIFs of the representative and worst runs")

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md", "runs.csv", "rates.csv", "rates_vs_density.png", "trajectories.png",
        "study.yaml",
    )  # fmt: skip
    #: s, the committed study: ~270 s CPU measured (2 worker processes: 19.5 min of wall time
    #: at load 13-18 on two shared cores)
    TYPICAL_DURATION: ClassVar[float] = 300
    MAX_POINTS: ClassVar[int] = int(MAX_RUNS.le)  # type: ignore[arg-type]
    #: Its runs go through the sweep engine: finished crowds are kept in the result store
    #: (``--cache-dir``), so an interrupted ``designlab run --resume`` computes only the rest.
    KEEPS_STORE: ClassVar[bool] = True

    @model_validator(mode="after")
    def _grid(self) -> NavigationCrowdsStudy:
        for name in ("scenarios", "densities", "seeds", "models"):
            vals = getattr(self, name) or []
            if len(set(vals)) != len(vals):
                raise ValueError(f"{name} must not repeat a value (got {vals})")
        labels = [m.label for m in self.methods]
        if len(set(labels)) != len(labels):
            raise ValueError(f"methods must have distinct labels (method:tag), got {labels}")
        if self.runs() > self.MAX_POINTS:
            raise ValueError(f"{self.runs()} runs is above the cap of {self.MAX_POINTS}")
        return self

    def check(self) -> None:
        """The schema's checks, then one crowd per layout and density (a density the area
        cannot hold, a goal inside a wall, ... fail here, before any run)."""
        super().check()
        sets: list[tuple[Any, Any, tuple[str, ...]]] = [(self.scenarios, self.densities, ())]
        if self.tuning is not None:
            t = self.tuning
            v = t.validation
            sets += [(t.training.scenarios, t.training.densities, ("tuning", "training")),
                     ([v.scenario], [v.density], ("tuning", "validation"))]  # fmt: skip
        for layouts, densities, where in sets:
            for layout in layouts:
                for j, rho in enumerate(densities):
                    try:
                        crowd(layout, density=rho, seed=0, **self.crowd.build())
                    except (DesignlabError, ValueError) as exc:
                        # a density the area cannot hold is the density's fault, else the crowd's
                        name = str(getattr(exc, "name", ""))
                        path = (*where, "densities", j) if "density" in name else ("crowd",)
                        raise StudyError(f"{layout} at {rho}/m^2: {exc}", path=path) from None

    def runs(self) -> int:
        """Runs of the main grid."""
        grid = len(self.scenarios) * len(self.densities) * len(self.seeds) * len(self.methods)
        return grid * len(self.models or [None])

    def size(self) -> str:
        """Runs of the grid, and of the tuning if any."""
        text = f"{self.runs()} runs"
        if self.tuning is not None:
            t = self.tuning
            per = len(t.training.scenarios) * len(t.training.densities) * len(t.training.seeds)
            held = len(t.validation.seeds) * (1 + len(t.compare))
            text += (f" + {t.popsize * t.generations * per} tuning runs + "
                     f"{held * (len(t.training.scenarios) * len(t.training.densities) + 2)} "
                     "validation runs")  # fmt: skip
        return text


@dataclass(frozen=True)
class NavigationCrowdsResult(Result):
    """Result of a ``navigation_crowds`` study.

    Attributes
    ----------
    study
        The validated study.
    crowds
        The :class:`~designlab.navigation.crowds.study.CrowdStudy` of the grid.
    tracks
        ``(kind, label) -> CrowdResult`` for ``kind`` ``"representative"`` and ``"worst"``.
    tuning, validation
        The crowd gain optimum and its validation
        (:class:`~designlab.navigation.crowds.tuning.GainValidation`) beside the gains to
        compare (``None`` without ``tuning``).
    """

    study: NavigationCrowdsStudy
    crowds: CrowdStudy
    tracks: dict[tuple[str, str], Any] = field(default_factory=dict, repr=False)
    tuning: CrowdGainOptimum | None = None
    validation: GainValidation | None = None

    @property
    def status(self) -> str:  # type: ignore[override]
        """The crowd study's status, else the tuning's."""
        if self.crowds.status != "ok" or self.tuning is None:
            return self.crowds.status
        return self.tuning.status

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """Warnings of the studies and the tuning."""
        parts = [self.crowds.warnings]
        parts += [x.warnings for x in (self.tuning, self.validation) if x is not None]
        return tuple(w for p in parts for w in p)

    def to_frame(self) -> pd.DataFrame:
        """The summary per scenario, density and method (rates with Wilson intervals)."""
        return self.crowds.to_frame()


def _grid_options(study: NavigationCrowdsStudy) -> dict[str, Any]:
    stab = {m.label: m.stabilising or study.stabilising for m in study.methods}
    return {"crowd_options": study.crowd.model_dump(), "stabilising": stab,
            "personal_space": study.personal_space, "confidence": study.confidence}  # fmt: skip


def _gains(study: NavigationCrowdsStudy) -> dict[str, Any]:
    return {m.label: m.gains.build() for m in study.methods if m.gains is not None}


def _tracks(study: NavigationCrowdsStudy, crowds: CrowdStudy) -> dict[tuple[str, str], Any]:
    options = crowds.settings["options"]
    out = {}
    finished = set(crowds.runs.loc[crowds.runs["status"].astype(str) != "error", "method"])
    for m in (m for m in study.methods if m.label in finished):  # every run failed: none shown
        for kind, row in (("representative", crowds.representative(m.label)),
                          ("worst", crowds.worst(m.label))):  # fmt: skip
            where = (str(row["scenario"]), float(row["density"]), int(row["seed"]))
            model = str(row["model"]) if "models" in options else None
            out[(kind, m.label)] = simulate_run(options, *where, m.label, model)
    return out


def _tune(study: NavigationCrowdsStudy, context: RunContext) -> tuple[Any, Any]:
    t = study.tuning
    if t is None:
        return None, None
    training = crowd_set(t, t.training, study.crowd.model_dump())
    v = t.validation
    steps = validation_steps(training, v.seeds, v.density, v.scenario)
    stab = t.stabilising or study.stabilising
    with context.bar("navigation_crowds: tune", t.generations) as hook:
        opt = optimise_crowd_gains(training, bounds=DEFAULT_BOUNDS, robust=t.robust, alpha=t.alpha,
                                   popsize=t.popsize, generations=t.generations, seed=t.seed,
                                   penalty=t.penalty, stabilising=stab,
                                   executor=context.executor, store=context.store,
                                   resume=context.resume, cache_only=context.cache_only,
                                   progress=hook)  # fmt: skip
    tag = "crowd_optimum" if opt.status == "ok" else "crowd_least_violating"  # said as it is
    candidates = {tag: opt.gains, **{k: g.build() for k, g in t.compare.items()}}
    val = validate_gains(
        candidates, steps, training, reference=next(iter(t.compare)), penalty=opt.penalty,
        stabilising=stab, executor=context.executor, store=context.store, measures=False,
        resume=context.resume, cache_only=context.cache_only,
        personal_space=study.personal_space, confidence=study.confidence,
    )  # fmt: skip
    return opt, val


def run(study: NavigationCrowdsStudy, context: RunContext) -> NavigationCrowdsResult:
    """Run the grid, the tuning and its validation, and re-simulate the runs to show.

    Parameters
    ----------
    study
        The validated study.
    context
        How to run it (executor, result store, progress bars).
    """
    with context.bar("navigation_crowds: runs", study.runs()) as hook:
        crowds = crowd_study(study.scenarios, study.densities, study.seeds,
                             [m.label for m in study.methods], gains=_gains(study),
                             executor=context.executor, store=context.store, resume=context.resume,
                             cache_only=context.cache_only, progress=hook, models=study.models,
                             **_grid_options(study))  # fmt: skip
    opt, val = _tune(study, context)
    with context.bar("navigation_crowds: runs shown", 2 * len(study.methods)) as hook:
        tracks = _tracks(study, crowds)  # for the trajectory plot and the animations
        hook(Progress(len(tracks), 2 * len(study.methods), label="runs shown"))
    return NavigationCrowdsResult(study, crowds, tracks, opt, val)


KIND = StudyKind(
    name="navigation_crowds",
    schema=NavigationCrowdsStudy,
    run=run,
    report="designlab.report.navigation_crowds",
    reproduction=CROWD_TUNING,
)

__all__ += ["LAYOUTS", "CrowdSetSpec", "CrowdSpec", "TuningSpec", "ValidationSpec"]
