"""The ``foam_envelope_sweep`` study kind: how the feasible foam region moves with the design.

Every point solves the foam envelope of Zeng 2011, Sec. 3.9
(:func:`designlab.impact.foam_envelope`) over the damping grid and checks the
base foam against it: the upper (safety) and lower (thickness) boundaries at
the foam's damping, its margin in decades of K_c and the feasible area. A
point costs about 14 ms (11 damping values), so a sweep has at most
:attr:`FoamEnvelopeStudy.MAX_POINTS` (100,000) points.

Examples
--------
>>> from designlab.study import parse_study
>>> study = parse_study('''
... designlab: 1
... kind: foam_envelope_sweep
... name: demo
... base: {robot: MANIPULATOR_1, foam: FOAM_1}
... damping: {low: 0, high: 200, num: 5}
... ''')
>>> study.base_point()["max_g"], study.evaluator_options()["damping"]
(10.0, [0.0, 50.0, 100.0, 150.0, 200.0])
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, ClassVar, Literal

from pydantic import Field, model_validator

from designlab.impact.criteria import HeadAcceleration
from designlab.impact.evaluators import (
    ENVELOPE_METRICS,
    envelope_elasticities_chunk,
    foam_envelope_chunk,
)
from designlab.impact.parameters import IMPACT_VELOCITY, ContactDynamics, Foam
from designlab.params import Param, params_of, sweepable
from designlab.study.base import Model
from designlab.study.kinds.impact_specs import DampingGrid, FoamSpec, RobotSpec
from designlab.study.registry import StudyKind
from designlab.study.reproduction import ENVELOPE
from designlab.study.sweep_runner import run_sweep_study
from designlab.study.sweeps import SweepStudyBase, parameter_model

__all__ = ["ENVELOPE_PARAMETERS", "KIND", "DampingGrid", "EnvelopeDesign", "FoamEnvelopeStudy"]

_FOAM = params_of(Foam)
#: v_c of the envelope: the worst (largest) closing velocity.
_WORST_VELOCITY = replace(IMPACT_VELOCITY, doc="worst closing velocity")
_MAX_G = params_of(HeadAcceleration)["max_g"]

#: Parameters of a foam-envelope sweep: dotted path -> (point key, declaration). The
#: declarations are the domain's; the checked foam's are relabelled for this context.
ENVELOPE_PARAMETERS: dict[str, tuple[str, Param]] = {
    **sweepable(ContactDynamics, "robot", names=("mass", "stiffness", "damping")),
    "impact_velocity": ("v_c", _WORST_VELOCITY),
    "max_g": ("max_g", _MAX_G),
    "foam.linear_depth": (
        "lambda",
        replace(_FOAM["linear_depth"], doc="foam linear depth lambda (compression limit)",
                symbol=None),
    ),
    "foam.stiffness": (
        "K_c", replace(_FOAM["stiffness"], doc="stiffness K_c of the checked foam", symbol=None)
    ),
    "foam.damping": (
        "C_c", replace(_FOAM["damping"], doc="damping C_c of the checked foam", symbol=None)
    ),
}  # fmt: skip

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
    impact_velocity: _WORST_VELOCITY.annotation() = 1.25  # type: ignore[valid-type]
    max_g: _MAX_G.annotation() = _MAX_G.default  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _buildable(self) -> EnvelopeDesign:
        self.robot.build()  # the domain's own rules, at validate
        self.foam.build()
        return self


class FoamEnvelopeStudy(SweepStudyBase[EnvelopeSweepParameters, EnvelopeMetricName]):  # type: ignore[valid-type]
    """Feasible foam region (Zeng 2011, Sec. 3.9) and how it moves with the design."""

    kind: Literal["foam_envelope_sweep"]
    base: EnvelopeDesign
    damping: DampingGrid = Field(default_factory=DampingGrid)

    PARAMETERS: ClassVar[dict[str, tuple[str, Param]]] = ENVELOPE_PARAMETERS
    METRICS: ClassVar[dict[str, str]] = ENVELOPE_METRICS
    DEFAULT_METRICS: ClassVar[tuple[str, ...]] = (
        "k_c_max_N_per_m",
        "k_c_min_N_per_m",
        "margin_decades",
    )
    EVALUATOR: ClassVar[Any] = foam_envelope_chunk
    LOCAL_EVALUATOR: ClassVar[Any] = envelope_elasticities_chunk
    #: About 14 ms a point (11 damping values): 100,000 points are some 25 min on one core.
    MAX_POINTS: ClassVar[int] = 100_000
    #: s: CPU time of studies/envelope_sensitivity.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 9

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
    name="foam_envelope_sweep",
    schema=FoamEnvelopeStudy,
    run=run_sweep_study,
    report="designlab.report.sweep",
    reproduction=ENVELOPE,
)
