"""The ``navigation_scenarios`` study kind: scenarios x methods, with the thesis's numbers.

Every (scenario, method) pair is simulated with :func:`designlab.navigation.simulate`
(Zeng 2011, Ch. 5-7). Optional ``references`` give the thesis's values for a pair, shown
next to the model in the report.

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: navigation_scenarios
... name: demo
... scenarios: [{configuration: 1}]
... methods:
...   - {label: "New VFF*", gains: {k1: 4.3, b: 0.68, k3: 20.3, k5: 240.7}, stabilising: "off"}
... references:
...   - {scenario: ch6_config1, method: "New VFF*", T_arrive_s: 6.3, d_circle_min_m: 0.55, H: 0.74}
... ''')
>>> r = run_study(study)
>>> r.to_frame()[["T_arrive_s", "ref_T_arrive_s"]].round(2).values.tolist()
[[5.98, 6.3]]
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import pandas as pd
from pydantic import Field, model_validator

from designlab.navigation import simulate
from designlab.navigation.criteria import EQUAL_WEIGHTS
from designlab.navigation.parameters import ARRIVAL_TOLERANCE
from designlab.navigation.planners import simulate_planner
from designlab.progress import Progress
from designlab.results import OK, Result
from designlab.study.base import Model, Number, Positive, StudyBase
from designlab.study.kinds.navigation_gains import Weights
from designlab.study.kinds.navigation_specs import MethodSpec, ScenarioSpec
from designlab.study.registry import StudyKind
from designlab.study.reproduction import SAME_ON_A_GENERIC_CPU
from designlab.study.runner import RunContext

__all__ = [
    "KIND",
    "NavigationReference",
    "NavigationRun",
    "NavigationScenariosResult",
    "NavigationScenariosStudy",
    "run",
]

logger = logging.getLogger(__name__)


class NavigationReference(Model):
    """The source's values for one (scenario, method) pair, e.g. a row of Table 6.2."""

    scenario: str = Field(min_length=1)
    method: str = Field(min_length=1)
    source: str | None = None
    T_arrive_s: Positive | None = None
    H: Number | None = Field(None, ge=0, le=1)
    d_circle_min_m: Positive | None = None
    d_rectangle_min_m: Positive | None = None
    d_human_min_m: Positive | None = None


_Tolerance = ARRIVAL_TOLERANCE.annotation()


class NavigationScenariosStudy(StudyBase):
    """Simulate every scenario with every method and compare with the source."""

    kind: Literal["navigation_scenarios"]
    scenarios: list[ScenarioSpec] = Field(min_length=1, max_length=50)
    methods: list[MethodSpec] = Field(min_length=1, max_length=20)
    arrival_tolerance: _Tolerance = 0.15
    weights: Weights = Field(EQUAL_WEIGHTS, description="criterion weights (w_T, w_D, w_E) of H")
    references: list[NavigationReference] = Field(default_factory=list)

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "results.csv",
        "stability.csv",
        "trajectories_*.png",
        "distances_*.png",
        "energy_*.png",
        "force_*.png",
        "study.yaml",
    )
    #: s: CPU time of studies/navigation_configurations.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 13

    def size(self) -> str:
        """The number of simulations."""
        return f"{len(self.scenarios) * len(self.methods)} runs"

    @model_validator(mode="after")
    def _unique(self) -> NavigationScenariosStudy:
        for what, names in (
            ("scenario", [s.title for s in self.scenarios]),
            ("method", [m.label for m in self.methods]),
        ):
            if len(set(names)) != len(names):
                raise ValueError(f"{what} labels must be unique, got {names}")
        sc = {s.title for s in self.scenarios}
        me = {m.label for m in self.methods}
        for r in self.references:
            if r.scenario not in sc:
                raise ValueError(f"reference scenario {r.scenario!r} is not one of {sorted(sc)}")
            if r.method not in me:
                raise ValueError(f"reference method {r.method!r} is not one of {sorted(me)}")
        return self


@dataclass(frozen=True)
class NavigationRun:
    """One simulated (scenario, method) pair.

    Attributes
    ----------
    scenario
        Scenario name.
    method
        Method and stabilising mode.
    result
        The simulation result.
    reference
        The thesis's published figures for this run, if any.
    """

    scenario: str
    method: str
    result: Any  # designlab.navigation.NavigationResult
    reference: NavigationReference | None

    def row(self) -> dict[str, Any]:
        """Model metrics and reference values, one row."""
        r = self.result
        row: dict[str, Any] = {
            "scenario": self.scenario,
            "method": self.method,
            "algorithm": r.method,
            "stabilising": r.stabilising,
            "status": r.status,
            "T_arrive_s": r.arrival_time,
        }
        for name, d in r.min_distance.items():
            row[f"d_{name}_min_m"] = d
        c = r.criteria
        row.update(
            {
                "entered_critical": r.entered_critical,
                "collided": r.collided,
                "H_T": c.H_T,
                "H_D": c.H_D,
                "H_E": c.H_E,
                "H": c.H,
                "L_energy_J_per_ohm": r.energy,
            }
        )
        a = r.stability
        row["lyapunov_share"] = a.share_satisfied if a is not None else math.nan
        ref = self.reference
        for key in ("T_arrive_s", "H", "d_circle_min_m", "d_rectangle_min_m", "d_human_min_m"):
            v = getattr(ref, key) if ref is not None else None
            row[f"ref_{key}"] = math.nan if v is None else float(v)
        return row


@dataclass(frozen=True)
class NavigationScenariosResult(Result):
    """Results of a ``navigation_scenarios`` study, scenario-major.

    Attributes
    ----------
    study
        The study.
    runs
        One run per (scenario, method), scenario-major.
    """

    study: NavigationScenariosStudy
    runs: tuple[NavigationRun, ...]

    @property
    def status(self) -> str:
        """``"ok"``, or the first run status that is not (e.g. ``"not_arrived"``)."""
        for r in self.runs:
            if r.result.status != OK:
                return str(r.result.status)
        return OK

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """Every run's warnings, prefixed with scenario and method."""
        return tuple(
            f"{r.scenario} / {r.method}: {w}" for r in self.runs for w in r.result.warnings
        )

    def to_frame(self) -> pd.DataFrame:
        """One row per run (``ref_*`` columns: the source's values, nan if none)."""
        return pd.DataFrame([r.row() for r in self.runs])

    def stability_frame(self) -> pd.DataFrame:
        """The Lyapunov audit of each new-VFF run: share satisfied at the samples, V over the
        held periods (:meth:`NavigationResult.hold_audit`) and the assumption breaks."""
        rows = []
        for r in self.runs:
            a = r.result.stability
            if a is None:
                continue
            held = r.result.hold_audit()
            reasons: dict[str, float] = {}
            for reason, t0, t1 in a.intervals:
                reasons[reason] = reasons.get(reason, 0.0) + (t1 - t0)
            rows.append(
                {
                    "scenario": r.scenario,
                    "method": r.method,
                    "stabilising": r.result.stabilising,
                    "share_satisfied": a.share_satisfied,
                    "share_satisfied_hold": a.share_satisfied_hold,
                    "active_samples": int(a.active.sum()),
                    "held_periods": held.periods,
                    "share_V_rose_over_hold": held.share_rose,
                    "max_V_rise_over_hold": held.max_rise,
                    **{f"time_{k.replace(' ', '_')}_s": v for k, v in sorted(reasons.items())},
                }
            )
        return pd.DataFrame(rows)


def run(study: NavigationScenariosStudy, context: RunContext) -> NavigationScenariosResult:
    """Simulate every (scenario, method) pair in this process.

    Parameters
    ----------
    study
        The validated study.
    context
        How to run it (these runs are never stored).
    """
    refs = {(r.scenario, r.method): r for r in study.references}
    pairs = [(s, m) for s in study.scenarios for m in study.methods]
    runs = []
    with context.bar(f"{study.kind}: {study.name}", len(pairs)) as hook:
        for i, (spec, method) in enumerate(pairs):
            runs.append(_run_pair(study, spec, method, refs))
            hook(Progress(i + 1, len(pairs), label="run", note=f"{spec.title} / {method.label}"))
    return NavigationScenariosResult(study, tuple(runs))


def _run_pair(
    study: NavigationScenariosStudy,
    spec: Any,
    method: MethodSpec,
    refs: dict[tuple[str, str], NavigationReference],
) -> NavigationRun:
    """Simulate one (scenario, method) pair."""
    if method.planner:  # a Sec. 5.7 planner (docs/navigation_planners.md)
        res = simulate_planner(
            spec.build(),
            method.method,
            method.planner_settings(),
            arrival_tolerance=study.arrival_tolerance,
        )
        return NavigationRun(spec.title, method.label, res, refs.get((spec.title, method.label)))
    res = simulate(
        spec.build(),
        method.gains.build() if method.gains is not None else None,
        method=method.method,
        stabilising=method.stabilising,
        arrival_tolerance=study.arrival_tolerance,
        tie_side=method.tie_side,
        cbf_gains=method.cbf_gains,
        weights=study.weights,
    )
    for w in res.warnings:
        logger.info("%s / %s: %s", spec.title, method.label, w)
    return NavigationRun(spec.title, method.label, res, refs.get((spec.title, method.label)))


KIND = StudyKind(
    name="navigation_scenarios",
    schema=NavigationScenariosStudy,
    run=run,
    report="designlab.report.navigation",
    reproduction=SAME_ON_A_GENERIC_CPU,
)
