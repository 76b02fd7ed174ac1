"""The ``impact_sweep`` study kind: impact metrics over a sweep of designs.

Every point is one impact of the linear coupled model (Zeng 2011, Sec. 3.5;
:func:`designlab.impact.impact_metrics`): a_h,max, eps_max, the peak force,
the impact period, the status and ``bottoming`` (eps_max > lambda), evaluated
a chunk of thousands of designs at a time.

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: impact_sweep
... name: demo
... base: {robot: MANIPULATOR_1, foam: FOAM_1, head: HEAD_MIN, impact_velocity: 1.25}
... sweep:
...   method: grid
...   parameters:
...     foam.stiffness: {values: [2e4, 4e4]}
... ''')
>>> r = run_study(study)
>>> r.status, r.to_frame()["a_h_max_g"].round(2).tolist()
('ok', [5.45, 8.23])
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from pydantic import Field, model_validator

from designlab.impact.evaluators import (
    IMPACT_METRICS,
    impact_elasticities_chunk,
    impact_metrics_chunk,
)
from designlab.impact.metric_names import LIMITS as IMPACT_LIMITS
from designlab.impact.parameters import IMPACT_VELOCITY, ContactDynamics, Foam, HeadNeck
from designlab.params import Param, sweepable
from designlab.study.base import Model
from designlab.study.kinds.impact_specs import FoamSpec, HeadSpec, RobotSpec
from designlab.study.registry import StudyKind
from designlab.study.reproduction import CERTIFIED_IMPACT
from designlab.study.sweep_runner import run_sweep_study
from designlab.study.sweeps import SweepStudyBase, parameter_model

__all__ = ["IMPACT_PARAMETERS", "KIND", "ImpactDesign", "ImpactSweepStudy"]

#: Parameters of the impact model a sweep can vary: dotted path -> (point key, declaration).
#: The declarations are the domain's (:mod:`designlab.impact.parameters`).
IMPACT_PARAMETERS: dict[str, tuple[str, Param]] = {
    **sweepable(ContactDynamics, "robot", names=("mass", "stiffness", "damping")),
    **sweepable(Foam, "foam", names=("stiffness", "damping", "linear_depth")),
    **sweepable(HeadNeck, "head", names=("mass", "stiffness", "damping")),
    "impact_velocity": ("v_c", IMPACT_VELOCITY),
}

ImpactSweepParameters = parameter_model(
    "ImpactSweepParameters", {path: info for path, (_, info) in IMPACT_PARAMETERS.items()}
)
ImpactMetricName = Literal["a_h_max_g", "eps_max_m", "peak_force_N", "t_imp_s"]


class ImpactDesign(Model):
    """The nominal design of an impact sweep: manipulator, foam, head, closing speed."""

    robot: RobotSpec
    foam: FoamSpec
    head: HeadSpec
    impact_velocity: IMPACT_VELOCITY.annotation()  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _buildable(self) -> ImpactDesign:
        for spec in (self.robot, self.foam, self.head):  # the domain's own rules, at validate
            spec.build()
        return self


class ImpactSweepStudy(SweepStudyBase[ImpactSweepParameters, ImpactMetricName]):  # type: ignore[valid-type]
    """Impact metrics over a sweep of designs, with sensitivity tables."""

    kind: Literal["impact_sweep"]
    base: ImpactDesign = Field(description="nominal design; the sweep varies some of it")

    PARAMETERS: ClassVar[dict[str, tuple[str, Param]]] = IMPACT_PARAMETERS
    METRICS: ClassVar[dict[str, str]] = IMPACT_METRICS
    #: The thesis's design limits (Zeng 2011, Sec. 3.9): 10 g and 20 mm, drawn in the plots.
    LIMITS: ClassVar[dict[str, float]] = dict(IMPACT_LIMITS)
    EVALUATOR: ClassVar[Any] = impact_metrics_chunk
    LOCAL_EVALUATOR: ClassVar[Any] = impact_elasticities_chunk
    NEEDS_SWEEP_OR_SENSITIVITY: ClassVar[bool] = True
    #: A point costs about 20 us (a chunk of 4096 designs at once): 10 million points are
    #: some minutes, so the sweep engine's general cap stands.
    MAX_POINTS: ClassVar[int] = 10_000_000
    #: s: CPU time of studies/impact_sensitivity.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 7

    def base_point(self) -> dict[str, float]:
        """The base design as ``{M_r, C_r, K_r, K_c, C_c, lambda, M_h, C_h, K_h, v_c}``."""
        r, f, h = self.base.robot.build(), self.base.foam.build(), self.base.head.build()
        return {
            "M_r": float(r.mass),
            "C_r": float(r.damping),
            "K_r": float(r.stiffness),
            "K_c": float(f.stiffness),
            "C_c": float(f.damping),
            "lambda": float(f.linear_depth),
            "M_h": float(h.mass),
            "C_h": float(h.damping),
            "K_h": float(h.stiffness),
            "v_c": float(self.base.impact_velocity),
        }


KIND = StudyKind(
    name="impact_sweep",
    schema=ImpactSweepStudy,
    run=run_sweep_study,
    report="designlab.report.sweep",
    reproduction=CERTIFIED_IMPACT,
)
