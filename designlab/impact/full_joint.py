"""Impact with the full series joint (Zeng 2011, eq. 3.4.6) and the error of its reductions.

The full joint is held in four modules, by what they hold; this module gathers
their public names (``dl.impact.full_joint.FULL_PARAM_NAMES`` and the rest keep
working):

* :mod:`designlab.impact.series_joint` -- the parameter objects
  (:class:`SeriesJoint`, :class:`FullJointContact`, :class:`FullJointLink`);
* :mod:`designlab.impact.full_joint_model` -- the model written once in CasADi,
  its parameter vector and the search grid's rate;
* :mod:`designlab.impact.state_space` -- its exact responses from the state space;
* :mod:`designlab.impact.joint_reduction` -- the comparison of the full joint
  with the Taylor reduction (3.4.9) and the band fit, at one joint and over the
  stiffness ratio (see ``docs/impact_joint.md``).

:func:`~designlab.impact.simulate.simulate`,
:func:`~designlab.impact.metrics.impact_metrics` and
:func:`~designlab.impact.envelope.foam_envelope` accept a
:class:`FullJointContact` (or ``(N, 10)`` parameter rows) wherever they accept
the reduced manipulator.

Units: SI, effective (prismatic) values in N/m and N s/m; joint values in
N m/rad and N m s/rad.

Examples
--------
>>> import designlab as dl
>>> dl.impact.full_joint.FULL_PARAM_NAMES[-2:], dl.impact.full_joint.REDUCTIONS
(('C_cont', 'K_cont'), ('taylor', 'band_fit'))
"""

from __future__ import annotations

from designlab.impact.full_joint_model import (
    FULL_INPUT_NAMES,
    FULL_PARAM_NAMES,
    full_joint_model,
    full_joint_params,
    grid_rate,
)
from designlab.impact.joint_reduction import (
    EQUAL_TOLERANCE,
    HARM_METRICS,
    METRICS,
    REDUCTIONS,
    BandFitSweep,
    JointReductionComparison,
    JointReductionStatus,
    JointReductionSweep,
    band_fit_sweep,
    compare_joint_reductions,
    default_band,
    joint_reduction_sweep,
)
from designlab.impact.metrics import matrix_metrics
from designlab.impact.series_joint import FullJointContact, FullJointLink, SeriesJoint
from designlab.impact.state_space import FAMILIES, modal_families

__all__ = [
    "EQUAL_TOLERANCE",
    "FAMILIES",
    "FULL_INPUT_NAMES",
    "FULL_PARAM_NAMES",
    "HARM_METRICS",
    "METRICS",
    "REDUCTIONS",
    "BandFitSweep",
    "FullJointContact",
    "FullJointLink",
    "JointReductionComparison",
    "JointReductionStatus",
    "JointReductionSweep",
    "SeriesJoint",
    "band_fit_sweep",
    "compare_joint_reductions",
    "default_band",
    "full_joint_model",
    "full_joint_params",
    "grid_rate",
    "joint_reduction_sweep",
    "matrix_metrics",
    "modal_families",
]
