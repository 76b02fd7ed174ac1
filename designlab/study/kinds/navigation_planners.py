"""The ``navigation_planners`` study kind: the Sec. 5.7 planners beside the force fields.

Every scenario (by default the Sec. 5.7 human who stops and turns, and the same with the
turn to the other side) is run with velocity obstacles, ERRT and Field D*
(:func:`designlab.navigation.planners.simulate_planner`) and with the force-field
methods (:func:`designlab.navigation.simulate`), and the report says who collides,
when, and how far the robot kept from every obstacle (``docs/navigation_planners.md``).

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: navigation_planners
... name: demo
... scenarios: [{configuration: 1}]
... mirror: false
... planners: [{method: vo}]
... methods: []
... ''')
>>> r = run_study(study)
>>> r.to_frame()[["scenario", "method", "collided"]].values.tolist()
[['ch6_config1', 'vo', False]]
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Annotated, Any, ClassVar, Literal

import numpy as np
import pandas as pd
from pydantic import Field, model_validator

from designlab import navigation as nav
from designlab.navigation.methods import METHODS, PLANNER
from designlab.navigation.planners.simulate import PlannerResult, simulate_planner
from designlab.navigation.scenario_io import mirrored
from designlab.progress import Progress
from designlab.results import OK, Result
from designlab.study.base import Flag, Integer, Model, StudyBase
from designlab.study.kinds.navigation_specs import MethodSpec, ScenarioSpec
from designlab.study.registry import StudyKind
from designlab.study.reproduction import SAME_ON_A_GENERIC_CPU
from designlab.study.runner import RunContext
from designlab.study.specs import spec_model

__all__ = ["KIND", "NavigationPlannersResult", "NavigationPlannersStudy", "PlannerSpec", "run"]


@functools.cache
def _settings_spec(method: str) -> type[Model]:
    """The study spec of a planner's settings (built from its ``settings_type``)."""
    return spec_model(METHODS.get(method, planner=True).settings_type)


class PlannerSpec(Model):
    """A Sec. 5.7 planner and its settings (each defaults to the paper's usual value)."""

    method: PLANNER.annotation()  # type: ignore[valid-type]
    settings: dict[str, Any] = Field(default_factory=dict, description="the planner's settings")
    seeds: Annotated[Integer, Field(ge=1, le=50)] = Field(
        1, description="errt: runs with the seeds seed, seed + 1, ... (a randomised planner)"
    )

    @model_validator(mode="after")
    def _settings(self) -> PlannerSpec:
        spec = _settings_spec(self.method)
        unknown = sorted(set(self.settings) - set(spec.model_fields))
        if unknown:
            raise ValueError(
                f"settings {unknown} do not apply to {self.method} "
                f"(its settings: {', '.join(spec.model_fields)})"
            )
        if self.seeds > 1 and not METHODS.get(self.method).seeded:
            seeded = ", ".join(m.name for m in METHODS.variants(planner=True, seeded=True))
            raise ValueError(f"seeds apply to {seeded} only, not to {self.method}")
        self.build()
        return self

    def build(self) -> Any:
        """The settings object."""
        return _settings_spec(self.method).model_validate(self.settings).build()

    def runs(self) -> list[tuple[str, Any]]:
        """``(label, settings)`` of each run (one per seed for errt)."""
        base = self.build()
        if self.seeds == 1:
            return [(self.method, base)]
        seeds = [base.seed + k for k in range(self.seeds)]
        return [(f"{self.method} (seed {s})", base.replace(seed=s)) for s in seeds]


def _default_methods() -> list[MethodSpec]:
    gains = {"k1": 3.0, "b": 0.25, "k3": 20.0, "k5": 17.0}
    return [
        MethodSpec(label="New VFF", method="vff", gains=gains, stabilising="off"),
        MethodSpec(label="Masoud", method="masoud"),
        MethodSpec(label="Ge & Cui", method="ge_cui"),
    ]


class NavigationPlannersStudy(StudyBase):
    """The Sec. 5.7 planners and the force-field methods on the same scenarios."""

    kind: Literal["navigation_planners"]
    scenarios: list[ScenarioSpec] = Field(  # type: ignore[valid-type]
        default_factory=lambda: [ScenarioSpec(configuration="unpredictable", horizon=15.0)],
        min_length=1,
        max_length=10,
    )
    mirror: Flag = Field(
        True, description="also run every scenario reflected about the start-goal line"
    )
    planners: list[PlannerSpec] = Field(
        default_factory=lambda: [PlannerSpec(method=m) for m in ("vo", "errt", "field_dstar")],
        max_length=10,
    )
    methods: list[MethodSpec] = Field(default_factory=_default_methods, max_length=10)

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md", "planners.csv", "planners_paths.png", "study.yaml",
    )  # fmt: skip
    TYPICAL_DURATION: ClassVar[float] = 33  # s, the committed study, serial, this machine

    @model_validator(mode="after")
    def _something(self) -> NavigationPlannersStudy:
        if not self.planners and not self.methods:
            raise ValueError(
                "planners = [] and methods = []: give at least one planner or method (a "
                "planners entry such as {method: vo}, or a methods entry such as {method: vff})"
            )
        return self

    def size(self) -> str:
        """Scenarios x (planners + methods)."""
        n = len(self.scenarios) * (2 if self.mirror else 1)
        return f"{n * (sum(p.seeds for p in self.planners) + len(self.methods))} runs"


@dataclass(frozen=True)
class NavigationPlannersResult(Result):
    """Result of a ``navigation_planners`` study.

    Attributes
    ----------
    study
        The validated study.
    runs
        ``(scenario, label, result)`` for every run, scenario-major; a result is a
        :class:`~designlab.navigation.planners.PlannerResult` or a
        :class:`~designlab.navigation.NavigationResult`.
    """

    study: NavigationPlannersStudy
    runs: tuple[tuple[str, str, Any], ...]

    @property
    def status(self) -> str:  # type: ignore[override]
        """``"ok"``, or the first run's status that is not."""
        return next((r.status for _, _, r in self.runs if r.status != OK), OK)

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """Every run's warnings, prefixed with scenario and method."""
        return tuple(f"{s} / {m}: {w}" for s, m, r in self.runs for w in r.warnings)

    def to_frame(self) -> pd.DataFrame:
        """One row per run: arrival, minimum distances, critical entry, collision and its time."""
        rows = []
        for scen, label, r in self.runs:
            row: dict[str, Any] = {"scenario": scen, "method": label,
                                   "T_arrive_s": r.arrival_time}  # fmt: skip
            row |= {f"d_{n}_min_m": d for n, d in r.min_distance.items()}
            row["entered_critical"] = r.entered_critical if hasattr(r, "entered_critical") else (
                any(r.critical_entries.values()))  # fmt: skip
            row["collided"] = r.collided
            row["first_collision_s"] = _first_collision(r)
            row["passed_on"] = _side(r)
            row["H"] = r.criteria.H if r.criteria is not None else float("nan")
            rows.append(row)
        return pd.DataFrame(rows)


def _side(r: Any) -> str:
    """Which side of the start-goal line the robot was on when closest to the first moving
    obstacle (``left``/``right`` looking from start to goal; empty without one)."""
    sc = r.scenario
    moving = [i for i, o in enumerate(sc.obstacles) if getattr(o, "motion", None) is not None
              and o.motion.moving]  # fmt: skip
    if not moving:
        return ""
    obs = r.obstacle_positions[moving[0]]
    n = min(len(obs), len(r.position))
    k = int(np.argmin(np.hypot(*(r.position[:n] - obs[:n]).T)))
    a, b = np.asarray(sc.start), np.asarray(sc.goal)
    d, q = b - a, r.position[k] - a
    cross = float(d[0] * q[1] - d[1] * q[0])
    return "left" if cross > 0 else "right"


def _first_collision(r: Any) -> float:
    if isinstance(r, PlannerResult):
        return r.first_collision
    if not r.collided:
        return float("inf")
    d = r.distance  # n_obs x len(t), first column the start
    rho = r.scenario.robot.radius
    times = []
    for i, o in enumerate(r.scenario.obstacles):
        hit = (d[i, 1:] <= o.collision_distance(rho)).nonzero()[0]
        if hit.size:
            times.append(float(r.t[hit[0]]))
    return min(times, default=float("inf"))


def run(study: NavigationPlannersStudy, context: RunContext) -> NavigationPlannersResult:
    """Run every scenario (and its mirror image) with every planner and method.

    Parameters
    ----------
    study
        The validated study.
    context
        How to run it (its progress bar; these runs are never stored).
    """
    scenarios = []
    for spec in study.scenarios:
        sc = spec.build()
        scenarios += [sc, mirrored(sc)] if study.mirror else [sc]
    runs: list[tuple[str, str, Any]] = []
    total = len(scenarios) * (sum(p.seeds for p in study.planners) + len(study.methods))
    with context.bar("navigation_planners: runs", total) as hook:
        for sc in scenarios:
            for p in study.planners:
                for label, settings in p.runs():
                    runs.append((sc.name, label, simulate_planner(sc, p.method, settings)))
                    hook(Progress(len(runs), total, label=label))
            for m in study.methods:
                g = m.gains.build() if m.gains is not None else None
                res = nav.simulate(sc, g, method=m.method, stabilising=m.stabilising,
                                   tie_side=m.tie_side)  # fmt: skip
                runs.append((sc.name, m.label, res))
                hook(Progress(len(runs), total, label=m.label))
    return NavigationPlannersResult(study, tuple(runs))


KIND = StudyKind(
    name="navigation_planners",
    schema=NavigationPlannersStudy,
    run=run,
    report="designlab.report.navigation_planners",
    reproduction=SAME_ON_A_GENERIC_CPU,
)
