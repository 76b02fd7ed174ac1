"""Impact safety of foam-covered manipulators (Zeng 2011, Ch. 3-4)."""

from __future__ import annotations

from designlab.impact.effective import (
    EffectiveContact,
    ImpactPointSweep,
    effective_contact,
    impact_point_sweep,
    scenario_single_joint,
    scenario_two_link,
    single_joint_from_contact,
    two_link_mass_matrix,
)
from designlab.impact.joint import (
    JointFit,
    fit_joint_band,
    full_joint_tf,
    joint_error_tf,
    joint_from_pd_gains,
    pd_gains_for,
    reduced_joint,
    reduced_joint_tf,
)
from designlab.impact.metrics import ImpactMetrics, impact_metrics
from designlab.impact.model import (
    PARAM_NAMES,
    constrained_model,
    transfer_functions,
    unconstrained_model,
)
from designlab.impact.parameters import (
    FOAM_1,
    FOAM_2,
    FOAM_2_MEASURED,
    FOAM_3,
    HEAD_MAX,
    HEAD_MIN,
    MANIPULATOR_1,
    MANIPULATOR_2,
    TABLE_3_2_HEADS,
    TEST_HEAD,
    ContactDynamics,
    Foam,
    HeadNeck,
)
from designlab.impact.simulate import ImpactResponse, VelocityProfile, hic, simulate

__all__ = [
    "FOAM_1",
    "FOAM_2",
    "FOAM_2_MEASURED",
    "FOAM_3",
    "HEAD_MAX",
    "HEAD_MIN",
    "MANIPULATOR_1",
    "MANIPULATOR_2",
    "PARAM_NAMES",
    "TABLE_3_2_HEADS",
    "TEST_HEAD",
    "ContactDynamics",
    "EffectiveContact",
    "Foam",
    "HeadNeck",
    "ImpactMetrics",
    "ImpactPointSweep",
    "ImpactResponse",
    "JointFit",
    "VelocityProfile",
    "constrained_model",
    "effective_contact",
    "fit_joint_band",
    "full_joint_tf",
    "hic",
    "impact_metrics",
    "impact_point_sweep",
    "joint_error_tf",
    "joint_from_pd_gains",
    "pd_gains_for",
    "reduced_joint",
    "reduced_joint_tf",
    "scenario_single_joint",
    "scenario_two_link",
    "simulate",
    "single_joint_from_contact",
    "transfer_functions",
    "two_link_mass_matrix",
    "unconstrained_model",
]
