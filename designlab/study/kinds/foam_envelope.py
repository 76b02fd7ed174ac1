"""The ``foam_envelope`` study kind: how the feasible foam region moves with the design.

Every point solves the foam envelope of Zeng 2011, Sec. 3.9
(:func:`designlab.impact.foam_envelope`) over the damping grid and checks the
base foam against it: the upper (safety) and lower (thickness) boundaries at
the foam's damping, its margin in decades of K_c and the feasible area.

Examples
--------
>>> from designlab.study import parse_study
>>> study = parse_study('''
... designlab: 1
... kind: foam_envelope
... name: demo
... base: {robot: MANIPULATOR_1, foam: FOAM_1}
... damping: {low: 0, high: 200, num: 5}
... ''')
>>> study.base_point()["max_g"], study.evaluator_options()["damping"]
(10.0, [0.0, 50.0, 100.0, 150.0, 200.0])
"""

from __future__ import annotations

from typing import Annotated, Any, ClassVar, Literal

from pydantic import Field, model_validator

from designlab.impact.sweep import (
    ENVELOPE_METRICS,
    envelope_elasticities_chunk,
    foam_envelope_chunk,
)
from designlab.study.base import Integer, Model, Number
from designlab.study.kinds.impact_specs import FoamSpec, RobotSpec
from designlab.study.registry import StudyKind
from designlab.study.sweep_runner import run_sweep_study
from designlab.study.sweeps import ParameterInfo, SweepStudyBase, parameter_model

__all__ = ["ENVELOPE_PARAMETERS", "KIND", "DampingGrid", "EnvelopeDesign", "FoamEnvelopeStudy"]

#: Parameters of a foam-envelope sweep: dotted path -> (point key, info).
ENVELOPE_PARAMETERS: dict[str, tuple[str, ParameterInfo]] = {
    "robot.mass": ("M_r", ParameterInfo("effective manipulator mass M_r", "kg", gt=0)),
    "robot.stiffness": ("K_r", ParameterInfo("manipulator stiffness K_r", "N/m", ge=0)),
    "robot.damping": ("C_r", ParameterInfo("manipulator damping C_r", "N s/m", ge=0)),
    "impact_velocity": ("v_c", ParameterInfo("worst closing velocity v_c", "m/s", gt=0, le=20)),
    "max_g": ("max_g", ParameterInfo("head acceleration limit a_h,max", "g", gt=0, le=1000)),
    "foam.linear_depth": (
        "lambda",
        ParameterInfo("foam linear depth lambda (compression limit)", "m", gt=0, le=1),
    ),
    "foam.stiffness": ("K_c", ParameterInfo("stiffness K_c of the checked foam", "N/m", gt=0)),
    "foam.damping": ("C_c", ParameterInfo("damping C_c of the checked foam", "N s/m", ge=0)),
}

EnvelopeSweepParameters = parameter_model(
    "EnvelopeSweepParameters", {path: info for path, (_, info) in ENVELOPE_PARAMETERS.items()}
)
EnvelopeMetricName = Literal["k_c_max_N_per_m", "k_c_min_N_per_m", "margin_decades", "area_log"]


class EnvelopeDesign(Model):
    """The nominal design question of a foam envelope (Zeng 2011, Sec. 3.9).

    The upper boundary uses the minimum head-neck set and a_h,max <= ``max_g``;
    the lower boundary the maximum head-neck set and eps_max <= the foam's
    ``linear_depth`` (both as in the thesis).
    """

    robot: RobotSpec
    foam: FoamSpec = Field(description="the foam checked against the envelope (margin)")
    impact_velocity: Annotated[Number, Field(gt=0, le=20.0, allow_inf_nan=False)] = Field(
        1.25, description="worst closing velocity v_c, m/s"
    )
    max_g: Annotated[Number, Field(gt=0, le=1000, allow_inf_nan=False)] = Field(
        10.0, description="head acceleration limit, g"
    )


class DampingGrid(Model):
    """The C_c grid of the envelope, N s/m."""

    low: Annotated[Number, Field(ge=0, allow_inf_nan=False)] = 0.0
    high: Annotated[Number, Field(gt=0, le=1e5, allow_inf_nan=False)] = 200.0
    num: Annotated[Integer, Field(ge=2, le=2001)] = 21

    @model_validator(mode="after")
    def _order(self) -> DampingGrid:
        if not self.low < self.high:
            raise ValueError(f"low = {self.low:g} N s/m must be < high = {self.high:g} N s/m")
        return self

    def values(self) -> list[float]:
        """The grid."""
        step = (self.high - self.low) / (self.num - 1)
        return [round(self.low + i * step, 12) for i in range(self.num)]


class FoamEnvelopeStudy(SweepStudyBase[EnvelopeSweepParameters, EnvelopeMetricName]):  # type: ignore[valid-type]
    """Feasible foam region (Zeng 2011, Sec. 3.9) and how it moves with the design."""

    kind: Literal["foam_envelope"]
    base: EnvelopeDesign
    damping: DampingGrid = Field(default_factory=DampingGrid)

    PARAMETERS: ClassVar[dict[str, tuple[str, ParameterInfo]]] = ENVELOPE_PARAMETERS
    METRICS: ClassVar[dict[str, str]] = ENVELOPE_METRICS
    DEFAULT_METRICS: ClassVar[tuple[str, ...]] = (
        "k_c_max_N_per_m",
        "k_c_min_N_per_m",
        "margin_decades",
    )
    EVALUATOR: ClassVar[Any] = foam_envelope_chunk
    LOCAL_EVALUATOR: ClassVar[Any] = envelope_elasticities_chunk

    def base_point(self) -> dict[str, float]:
        """``{M_r, C_r, K_r, v_c, max_g, lambda, K_c, C_c}``."""
        r, f = self.base.robot.build(), self.base.foam.build()
        return {
            "M_r": float(r.mass),
            "C_r": float(r.damping),
            "K_r": float(r.stiffness),
            "v_c": float(self.base.impact_velocity),
            "max_g": float(self.base.max_g),
            "lambda": float(f.linear_depth),
            "K_c": float(f.stiffness),
            "C_c": float(f.damping),
        }

    def evaluator_options(self) -> dict[str, Any]:
        """The damping grid."""
        return {"damping": self.damping.values()}


KIND = StudyKind(
    name="foam_envelope",
    schema=FoamEnvelopeStudy,
    run=run_sweep_study,
    report="designlab.report.sweep",
)
