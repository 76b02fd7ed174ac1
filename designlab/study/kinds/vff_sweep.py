"""The ``vff_sweep`` study kind: VFF criteria over a sweep of gains, robot limits or walk speed.

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
... kind: vff_sweep
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

from pydantic import Field, field_validator

from designlab.navigation.parameters import MAX_GAIN
from designlab.navigation.sweep import VFF_METRICS, vff_metrics_chunk
from designlab.study.base import Flag, Integer, Model, NonNegative, Positive
from designlab.study.kinds.vff_specs import GainsSpec
from designlab.study.registry import StudyKind
from designlab.study.sweep_runner import run_sweep_study
from designlab.study.sweeps import ParameterInfo, SweepStudyBase, parameter_model

__all__ = ["KIND", "VFF_PARAMETERS", "VffDesign", "VffSweepStudy"]

#: Parameters a VFF sweep can vary: dotted path -> (point key, info).
VFF_PARAMETERS: dict[str, tuple[str, ParameterInfo]] = {
    "gains.k1": ("k1", ParameterInfo("attractive gain K1", "N/m", gt=0, le=MAX_GAIN)),
    "gains.b": (
        "b",
        ParameterInfo("gain ratio b = K2/K1 = K4/K3 = K6/K5", "s", gt=0, le=MAX_GAIN),
    ),
    "gains.k3": ("k3", ParameterInfo("repulsive gain K3", "N/m", gt=0, le=MAX_GAIN)),
    "gains.k5": ("k5", ParameterInfo("detour gain K5", "N/m^2", gt=0, le=MAX_GAIN)),
    "robot.max_speed": ("v_max", ParameterInfo("robot speed limit", "m/s", gt=0, le=5)),
    "robot.max_accel": ("a_max", ParameterInfo("robot acceleration limit", "m/s^2", gt=0, le=100)),
    "human_speed": (
        "v_h",
        ParameterInfo("cruise speed of the synthetic human walk", "m/s", gt=0, le=3),
    ),
    "human_ramp_time": (
        "ramp",
        ParameterInfo("speed-ramp time of the synthetic human walk", "s", ge=0, le=5),
    ),
    "arrival_tolerance": (
        "tol",
        ParameterInfo("arrival radius around the goal (first passage)", "m", gt=0, le=1),
    ),
}

VffSweepParameters = parameter_model(
    "VffSweepParameters", {path: info for path, (_, info) in VFF_PARAMETERS.items()}
)
VffMetricName = Literal["H_mean", "T_mean_s", "clearance_min_m", "critical_entries", "collisions"]


class VffDesign(Model):
    """The nominal design of a VFF sweep."""

    gains: GainsSpec
    max_speed: Positive = Field(0.7, le=5, description="robot speed limit, m/s")
    max_accel: Positive = Field(10.0, le=100, description="robot acceleration limit, m/s^2")
    human_speed: Positive = Field(1.0, le=3, description="synthetic walk cruise speed, m/s")
    human_ramp_time: NonNegative = Field(0.5, le=5, description="walk speed-ramp time, s")
    scenarios: list[tuple[Integer | Literal["parallel", "unpredictable"], Literal[6, 7]]] = Field(
        default_factory=lambda: [(1, 6), (2, 6), (3, 6)],
        description="thesis configurations as [configuration, chapter] (App. C uses 1-3 of Ch. 6)",
    )
    stabilising: Literal["lyapunov", "off"] = "off"
    arrival_tolerance: Positive = Field(0.15, le=1.0, description="m")
    jit: Flag = Field(
        False,
        description="simulate with the step compiled to four gain sets per pass (needs a C "
        "compiler; the same results to the bit, several times faster for large sweeps)",
    )

    @field_validator("scenarios")
    @classmethod
    def _configs(cls, v: list[Any]) -> list[Any]:
        if not v:
            raise ValueError("give at least one scenario")
        for which, chapter in v:
            if isinstance(which, int) and not 1 <= which <= 4:
                raise ValueError(
                    f"configuration {which} must be 1-4, 'parallel' or 'unpredictable'"
                )
            if chapter == 7 and not isinstance(which, int):
                raise ValueError(f"configuration {which!r} exists only in chapter 6")
        return v


class VffSweepStudy(SweepStudyBase[VffSweepParameters, VffMetricName]):  # type: ignore[valid-type]
    """VFF criteria over a sweep of gains and robot limits, with sensitivity tables."""

    kind: Literal["vff_sweep"]
    base: VffDesign = Field(
        description="nominal gains, limits and scenarios; the sweep varies some of them"
    )

    PARAMETERS: ClassVar[dict[str, tuple[str, ParameterInfo]]] = VFF_PARAMETERS
    METRICS: ClassVar[dict[str, str]] = VFF_METRICS
    DEFAULT_METRICS: ClassVar[tuple[str, ...]] = ("H_mean", "T_mean_s", "clearance_min_m")
    EVALUATOR: ClassVar[Any] = vff_metrics_chunk
    NEEDS_SWEEP_OR_SENSITIVITY: ClassVar[bool] = True

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
            "scenarios": [list(s) for s in self.base.scenarios],
            "stabilising": self.base.stabilising,
            "arrival_tolerance": self.base.arrival_tolerance,
        }
        if self.base.jit:  # only when on: the stored results of other studies keep their keys
            options["jit"] = True
        return options


KIND = StudyKind(
    name="vff_sweep",
    schema=VffSweepStudy,
    run=run_sweep_study,
    report="designlab.report.sweep",
)
