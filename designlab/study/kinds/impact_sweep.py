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

from typing import Annotated, Any, ClassVar, Literal

from pydantic import Field

from designlab.impact.metric_names import LIMITS as IMPACT_LIMITS
from designlab.impact.sweep import (
    IMPACT_METRICS,
    impact_elasticities_chunk,
    impact_metrics_chunk,
)
from designlab.study.base import Model, Number
from designlab.study.kinds.impact_specs import FoamSpec, HeadSpec, RobotSpec
from designlab.study.registry import StudyKind
from designlab.study.sweep_runner import run_sweep_study
from designlab.study.sweeps import ParameterInfo, SweepStudyBase, parameter_model

__all__ = ["IMPACT_PARAMETERS", "KIND", "ImpactDesign", "ImpactSweepStudy"]

#: Parameters of the impact model a sweep can vary: dotted path -> (point key, info).
IMPACT_PARAMETERS: dict[str, tuple[str, ParameterInfo]] = {
    "robot.mass": ("M_r", ParameterInfo("effective manipulator mass M_r", "kg", gt=0)),
    "robot.stiffness": ("K_r", ParameterInfo("manipulator stiffness K_r", "N/m", ge=0)),
    "robot.damping": ("C_r", ParameterInfo("manipulator damping C_r", "N s/m", ge=0)),
    "foam.stiffness": ("K_c", ParameterInfo("foam stiffness K_c", "N/m", gt=0)),
    "foam.damping": ("C_c", ParameterInfo("foam damping C_c", "N s/m", ge=0)),
    "foam.linear_depth": ("lambda", ParameterInfo("foam linear depth lambda", "m", gt=0)),
    "head.mass": ("M_h", ParameterInfo("head mass M_h", "kg", gt=0)),
    "head.stiffness": ("K_h", ParameterInfo("neck stiffness K_h", "N/m", ge=0)),
    "head.damping": ("C_h", ParameterInfo("neck damping C_h", "N s/m", ge=0)),
    "impact_velocity": ("v_c", ParameterInfo("closing velocity v_c", "m/s", gt=0, le=20)),
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
    impact_velocity: Annotated[Number, Field(gt=0, le=20.0, allow_inf_nan=False)] = Field(
        description="closing velocity v_c, m/s"
    )


class ImpactSweepStudy(SweepStudyBase[ImpactSweepParameters, ImpactMetricName]):  # type: ignore[valid-type]
    """Impact metrics over a sweep of designs, with sensitivity tables."""

    kind: Literal["impact_sweep"]
    base: ImpactDesign = Field(description="nominal design; the sweep varies some of it")

    PARAMETERS: ClassVar[dict[str, tuple[str, ParameterInfo]]] = IMPACT_PARAMETERS
    METRICS: ClassVar[dict[str, str]] = IMPACT_METRICS
    #: The thesis's design limits (Zeng 2011, Sec. 3.9): 10 g and 20 mm, drawn in the plots.
    LIMITS: ClassVar[dict[str, float]] = dict(IMPACT_LIMITS)
    EVALUATOR: ClassVar[Any] = impact_metrics_chunk
    LOCAL_EVALUATOR: ClassVar[Any] = impact_elasticities_chunk
    NEEDS_SWEEP_OR_SENSITIVITY: ClassVar[bool] = True

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
)
