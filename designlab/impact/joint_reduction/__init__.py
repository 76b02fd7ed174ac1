"""How wrong the reduced joint is: the full series joint (3.4.6) against its reductions.

The thesis replaces a position-controlled joint -- transmission (K_mech, C_mech)
in series with the PD controller (K_cont, C_cont) -- by one spring-damper
(K_J, C_J), the first two Taylor terms of (3.4.6) about s = 0, (3.4.9). The
impact model with the full joint (:mod:`designlab.impact.full_joint_model`)
shows how wrong a_h,max, eps_max, the peak force and the impact period are when
the reduced joint is used, and on which side (see ``docs/impact_joint.md``).

:func:`compare_joint_reductions` evaluates the full joint, the Taylor reduction
(3.4.9) and the frequency-band fit (:func:`~designlab.impact.joint.fit_joint_band`,
an extension of the thesis, which has only the Taylor truncation) on the same
arm, foam and head, and reports each metric's relative error and whether the
reduction is conservative (overestimates the harm). :func:`joint_reduction_sweep`
does the same over the transmission/controller stiffness ratio K_mech/K_cont,
:func:`band_fit_sweep` over the band of the fit.

The package holds, by what it does: :mod:`.evaluation` (the metrics compared,
their relative errors, the status, the base of the results), :mod:`.comparison`
(one arm), :mod:`.ratio_sweep` (over K_mech/K_cont) and :mod:`.band_sweep` (over
the band of the fit). Every name is importable from here, as before the split.

For the constrained impact (``head=None``, the head against a wall) a_h is 0
for every model: its relative error is 0 (both exactly zero), never NaN.

Examples
--------
>>> import designlab as dl
>>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
>>> cmp = dl.impact.compare_joint_reductions(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25)
>>> round(100 * cmp.relative_error("taylor", "a_h_max"), 1)
12.5
>>> cmp.conservative("taylor", "a_h_max")
True
"""

from designlab.impact.joint_reduction.band_sweep import BandFitSweep, band_fit_sweep
from designlab.impact.joint_reduction.comparison import (
    JointReductionComparison,
    compare_joint_reductions,
)
from designlab.impact.joint_reduction.evaluation import (
    EQUAL_TOLERANCE,
    HARM_METRICS,
    METRICS,
    REDUCTIONS,
    JointReductionStatus,
    ReductionResult,
    default_band,
    relative_errors,
)
from designlab.impact.joint_reduction.ratio_sweep import (
    JointReductionSweep,
    joint_reduction_sweep,
)

__all__ = [
    "EQUAL_TOLERANCE",
    "HARM_METRICS",
    "METRICS",
    "REDUCTIONS",
    "BandFitSweep",
    "JointReductionComparison",
    "JointReductionStatus",
    "JointReductionSweep",
    "ReductionResult",
    "band_fit_sweep",
    "compare_joint_reductions",
    "default_band",
    "joint_reduction_sweep",
    "relative_errors",
]
