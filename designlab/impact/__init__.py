"""Impact safety of foam-covered manipulators (Zeng 2011, Ch. 3-4)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from designlab._lazy import attach as _attach

if TYPE_CHECKING:  # the public names, imported on first use (designlab._lazy)
    from designlab.impact.contact import CONTACTS, HuntCrossleyFoam, StressStrainFoam, contact_of
    from designlab.impact.criteria import (
        ISO_TS_15066_QUASI_STATIC_FORCE,
        ISO_TS_15066_TRANSIENT_FACTOR,
        CompressionLimit,
        Criterion,
        HeadAcceleration,
        HeadInjuryCriterion,
        ImpactForce,
        IsoQuasiStaticForce,
        IsoTransientForce,
    )
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
    from designlab.impact.envelope import FoamEnvelope, foam_envelope
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
    from designlab.impact.joint_reduction import (
        BandFitSweep,
        JointReductionComparison,
        JointReductionSweep,
        band_fit_sweep,
        compare_joint_reductions,
        joint_reduction_sweep,
    )
    from designlab.impact.metrics import ImpactMetrics, impact_metrics
    from designlab.impact.model import (
        PARAM_NAMES,
        constrained_model,
        transfer_functions,
        unconstrained_model,
    )
    from designlab.impact.optimal import OptimalFoam, optimal_foam
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
        THESIS_HEAD_RANGE,
        ContactDynamics,
        Foam,
        HeadNeck,
        HeadRange,
        LinkImpact,
    )
    from designlab.impact.peaks import first_peak
    from designlab.impact.planes import (
        ClosingSpeed,
        CombinedImpact,
        ImpactPlane,
        closing_speed,
        combined_impact,
    )
    from designlab.impact.series_joint import FullJointContact, FullJointLink, SeriesJoint
    from designlab.impact.simulate import ImpactResponse, VelocityProfile, hic, simulate
    from designlab.impact.verdict import (
        FoamThickness,
        FoamVerdict,
        SafeVelocity,
        foam_verdict,
        max_safe_velocity,
        min_foam_thickness,
    )
    from designlab.impact.worst_case import WorstCaseCheck, check_worst_case

__all__ = [
    "CONTACTS",
    "FOAM_1",
    "FOAM_2",
    "FOAM_2_MEASURED",
    "FOAM_3",
    "HEAD_MAX",
    "HEAD_MIN",
    "ISO_TS_15066_QUASI_STATIC_FORCE",
    "ISO_TS_15066_TRANSIENT_FACTOR",
    "MANIPULATOR_1",
    "MANIPULATOR_2",
    "PARAM_NAMES",
    "TABLE_3_2_HEADS",
    "TEST_HEAD",
    "THESIS_HEAD_RANGE",
    "BandFitSweep",
    "ClosingSpeed",
    "CombinedImpact",
    "CompressionLimit",
    "ContactDynamics",
    "Criterion",
    "EffectiveContact",
    "Foam",
    "FoamEnvelope",
    "FoamThickness",
    "FoamVerdict",
    "FullJointContact",
    "FullJointLink",
    "HeadAcceleration",
    "HeadInjuryCriterion",
    "HeadNeck",
    "HeadRange",
    "HuntCrossleyFoam",
    "ImpactForce",
    "ImpactMetrics",
    "ImpactPlane",
    "ImpactPointSweep",
    "ImpactResponse",
    "IsoQuasiStaticForce",
    "IsoTransientForce",
    "JointFit",
    "JointReductionComparison",
    "JointReductionSweep",
    "LinkImpact",
    "OptimalFoam",
    "SafeVelocity",
    "SeriesJoint",
    "StressStrainFoam",
    "VelocityProfile",
    "WorstCaseCheck",
    "band_fit_sweep",
    "check_worst_case",
    "closing_speed",
    "combined_impact",
    "compare_joint_reductions",
    "constrained_model",
    "contact_of",
    "effective_contact",
    "first_peak",
    "fit_joint_band",
    "foam_envelope",
    "foam_verdict",
    "full_joint_tf",
    "hic",
    "impact_metrics",
    "impact_point_sweep",
    "joint_error_tf",
    "joint_from_pd_gains",
    "joint_reduction_sweep",
    "max_safe_velocity",
    "min_foam_thickness",
    "optimal_foam",
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

_attach(__name__)
