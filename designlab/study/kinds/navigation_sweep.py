"""The ``navigation_sweep`` study kind: VFF criteria over a sweep of gains, limits or walk.

Every point simulates the listed thesis configurations with the new VFF
(:func:`designlab.navigation.simulate_batch`, Zeng 2011, Ch. 5-6) and reports H_mean,
the mean arrival time, the smallest clearance and the critical-region entries and
collisions. The shared sweep, sensitivity (App. C style one-at-a-time tables),
executor and result-store machinery does the rest.

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: navigation_sweep
... name: demo
... base: {gains: {k1: 4.3, b: 0.68, k3: 20.3, k5: 240.7}, scenarios: [[1, 6]], stabilising: "off"}
... sweep:
...   method: grid
...   parameters:
...     gains.k1: {values: [3.0, 4.3]}
... ''')
>>> r = run_study(study)
>>> r.status, r.to_frame()["T_mean_s"].round(2).tolist()
('ok', [6.08, 5.98])
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from pydantic import Field, field_validator, model_validator

from designlab.navigation.criteria import EQUAL_WEIGHTS
from designlab.navigation.evaluators import VFF_METRICS, vff_metrics_chunk
from designlab.navigation.parameters import ARRIVAL_TOLERANCE, HolonomicRobot, VFFGains
from designlab.navigation.scenarios import Walk
from designlab.params import Param, params_of, sweepable
from designlab.study.base import Flag, Integer, Model
from designlab.study.kinds.navigation_gains import Weights
from designlab.study.kinds.navigation_specs import GainsSpec, ScenarioSpec, Stabilising
from designlab.study.registry import StudyKind
from designlab.study.reproduction import SAME_ON_A_GENERIC_CPU
from designlab.study.sweep_runner import run_sweep_study
from designlab.study.sweeps import SensitivitySpec, SweepOf, SweepStudyBase, parameter_model

__all__ = ["KIND", "NAVIGATION_PARAMETERS", "NavigationDesign", "NavigationSweepStudy"]

_ROBOT, _WALK = params_of(HolonomicRobot), params_of(Walk)
#: The evaluator's point key of each swept path (the columns of the results table).
_KEYS = {
    "gains.k1": "k1", "gains.b": "b", "gains.k3": "k3", "gains.k5": "k5",
    "robot.max_speed": "v_max", "robot.max_accel": "a_max",
    "human_speed": "v_h", "human_ramp_time": "ramp", "arrival_tolerance": "tol",
}  # fmt: skip

#: Parameters a navigation sweep can vary: dotted path -> (point key, declaration). The
#: declarations are the domain's (gains of :class:`~designlab.navigation.VFFGains`, limits
#: of :class:`~designlab.navigation.HolonomicRobot`, the synthetic human
#: :class:`~designlab.navigation.Walk`, the arrival tolerance).
NAVIGATION_PARAMETERS: dict[str, tuple[str, Param]] = {
    path: (_KEYS[path], decl)
    for path, (_, decl) in {
        **sweepable(VFFGains, "gains"),
        **sweepable(HolonomicRobot, "robot", names=("max_speed", "max_accel")),
        "human_speed": ("", _WALK["speed"]),
        "human_ramp_time": ("", _WALK["ramp_time"]),
        "arrival_tolerance": ("", ARRIVAL_TOLERANCE),
    }.items()
}

NavigationSweepParameters = parameter_model(
    "NavigationSweepParameters", {path: info for path, (_, info) in NAVIGATION_PARAMETERS.items()}
)


def _home_here(model: Any) -> None:
    """Make the generated models picklable: each is found in this module by its name (the
    generic fix belongs in :func:`designlab.study.sweeps.parameter_model`)."""
    for cls in [model] + [
        a for f in model.model_fields.values() for a in getattr(f.annotation, "__args__", ())
    ]:
        if isinstance(cls, type) and cls.__module__ == "designlab.study.sweeps":
            cls.__module__ = __name__
            globals()[cls.__name__] = cls


_home_here(NavigationSweepParameters)
NavigationMetricName = Literal[
    "H_mean", "T_mean_s", "clearance_min_m", "critical_entries", "collisions"
]


def _field(decl: Param) -> Any:
    return (decl.annotation(), decl.default)


_MaxSpeed = _ROBOT["max_speed"].annotation()
_MaxAccel = _ROBOT["max_accel"].annotation()
_HumanSpeed = _WALK["speed"].annotation()
_RampTime = _WALK["ramp_time"].annotation()
_Tolerance = ARRIVAL_TOLERANCE.annotation()


class NavigationDesign(Model):
    """The nominal design of a navigation sweep (SI; bounds and defaults: the domain's)."""

    gains: GainsSpec  # type: ignore[valid-type]
    max_speed: _MaxSpeed = _ROBOT["max_speed"].default
    max_accel: _MaxAccel = _ROBOT["max_accel"].default
    human_speed: _HumanSpeed = _WALK["speed"].default
    human_ramp_time: _RampTime = _WALK["ramp_time"].default
    scenarios: list[
        tuple[Integer | Literal["parallel", "unpredictable"], Literal[6, 7]] | ScenarioSpec  # type: ignore[valid-type]
    ] = Field(
        default_factory=lambda: [(1, 6), (2, 6), (3, 6)],
        max_length=50,
        description="thesis configurations as [configuration, chapter] (App. C uses 1-3 of "
        "Ch. 6), or scenarios of the user's (docs/navigation_scenarios.md)",
    )
    stabilising: Stabilising = "off"  # type: ignore[valid-type]
    arrival_tolerance: _Tolerance = 0.15
    weights: Weights = Field(EQUAL_WEIGHTS, description="criterion weights (w_T, w_D, w_E) of H")
    jit: Flag = Field(
        False,
        description="simulate with the step compiled to four gain sets per pass (needs a C "
        "compiler; the same results to the bit, several times faster for large sweeps)",
    )

    @field_validator("scenarios")
    @classmethod
    def _configs(cls, v: list[Any]) -> list[Any]:
        if not v:
            raise ValueError(
                "scenarios = [] is empty: give at least one scenario (a configuration 1-4, "
                "'parallel', 'unpredictable' or a scenario of your own)"
            )
        for spec in v:
            if not isinstance(spec, tuple):
                continue  # a user's scenario, checked by its spec
            which, chapter = spec
            if isinstance(which, int) and not 1 <= which <= 4:
                raise ValueError(
                    f"configuration {which} must be 1-4, 'parallel' or 'unpredictable'"
                )
            if chapter == 7 and not isinstance(which, int):
                raise ValueError(f"configuration {which!r} exists only in chapter 6")
        return v

    @model_validator(mode="after")
    def _own_limits(self) -> NavigationDesign:
        """A user's scenario states the limits and walk speeds the sweep sets: they must agree."""
        for spec in self.scenarios:
            if isinstance(spec, tuple):
                continue
            sc = spec.build()
            base = {"max_speed": self.max_speed, "max_accel": self.max_accel}
            for key, value in base.items():
                if getattr(sc.robot, key) != value:
                    raise ValueError(
                        f"scenario {sc.name!r}: robot.{key} = {getattr(sc.robot, key):g} differs "
                        f"from base.{key} = {value:g}; a navigation sweep sets the robot limits "
                        f"of every scenario from base (set base.{key}: {getattr(sc.robot, key):g})"
                    )
            for o in sc.obstacles:
                walk = getattr(o, "motion", None)
                if isinstance(walk, Walk) and (
                    walk.speed != self.human_speed or walk.ramp_time != self.human_ramp_time
                ):
                    raise ValueError(
                        f"scenario {sc.name!r}: the walk of {o.name!r} (speed {walk.speed:g} m/s, "
                        f"ramp {walk.ramp_time:g} s) differs from base.human_speed = "
                        f"{self.human_speed:g} / base.human_ramp_time = {self.human_ramp_time:g}; "
                        "a navigation sweep sets every walk's from base"
                    )
        return self


class NavigationSweep(SweepOf[NavigationSweepParameters]):  # type: ignore[valid-type]
    """The ``sweep`` block of a navigation sweep (a named class: results pickle)."""


class NavigationSensitivity(SensitivitySpec[NavigationMetricName]):  # type: ignore[valid-type]
    """The ``sensitivity`` block of a navigation sweep (a named class: results pickle)."""


class NavigationSweepStudy(SweepStudyBase[NavigationSweepParameters, NavigationMetricName]):  # type: ignore[valid-type]
    """VFF criteria over a sweep of gains and robot limits, with sensitivity tables."""

    kind: Literal["navigation_sweep"]
    sweep: NavigationSweep | None = None
    sensitivity: NavigationSensitivity | None = None
    base: NavigationDesign = Field(
        description="nominal gains, limits and scenarios; the sweep varies some of them"
    )

    PARAMETERS: ClassVar[dict[str, tuple[str, Param]]] = NAVIGATION_PARAMETERS
    METRICS: ClassVar[dict[str, str]] = VFF_METRICS
    DEFAULT_METRICS: ClassVar[tuple[str, ...]] = ("H_mean", "T_mean_s", "clearance_min_m")
    EVALUATOR: ClassVar[Any] = vff_metrics_chunk
    NEEDS_SWEEP_OR_SENSITIVITY: ClassVar[bool] = True
    #: A point costs about 12 ms of CPU (three configurations with their nominal runs on
    #: the virtual machine, measured; 3-4 ms with ``jit``), so 100 000 points are about
    #: 20 minutes per core; more is refused (docs/navigation.md, "Limits").
    MAX_POINTS: ClassVar[int] = 100_000
    #: s: CPU time of studies/navigation_gain_sensitivity.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 7

    @model_validator(mode="after")
    def _capped(self) -> NavigationSweepStudy:
        # until the shared sweep machinery checks MAX_POINTS of every kind
        n = self.sweep.count() if self.sweep is not None else 0
        if n > self.MAX_POINTS:
            raise ValueError(
                f"sweep: {n:,} points; a navigation sweep may have at most {self.MAX_POINTS:,} "
                "(about 12 ms of CPU each; docs/navigation.md, 'Limits')"
            )
        return self

    def base_point(self) -> dict[str, float]:
        """The base design as ``{k1, b, k3, k5, v_max, a_max, v_h, ramp, tol}``."""
        g = self.base.gains
        return {
            "k1": g.k1,
            "b": g.b,
            "k3": g.k3,
            "k5": g.k5,
            "v_max": self.base.max_speed,
            "a_max": self.base.max_accel,
            "v_h": self.base.human_speed,
            "ramp": self.base.human_ramp_time,
            "tol": self.base.arrival_tolerance,
        }

    def evaluator_options(self) -> dict[str, Any]:
        """Scenarios, stabilising mode, arrival tolerance and ``jit`` (plain, picklable)."""
        options: dict[str, Any] = {
            "scenarios": [
                list(s) if isinstance(s, tuple) else s.as_dict() for s in self.base.scenarios
            ],
            "stabilising": self.base.stabilising,
            "arrival_tolerance": self.base.arrival_tolerance,
        }
        if self.base.jit:  # only when on: the stored results of other studies keep their keys
            options["jit"] = True
        if tuple(self.base.weights) != EQUAL_WEIGHTS:  # likewise
            options["weights"] = list(self.base.weights)
        return options


KIND = StudyKind(
    name="navigation_sweep",
    schema=NavigationSweepStudy,
    run=run_sweep_study,
    report="designlab.report.sweep",
    reproduction=SAME_ON_A_GENERIC_CPU,
)
