"""The full series joint (3.4.6) with a linear Kelvin-Voigt foam.

The manipulator keeps its transmission (K_mech, C_mech) in series with the PD controller
(K_cont, C_cont), (3.4.6), instead of the reduced joint of (3.4.9): one more state, the
massless motor node (:mod:`designlab.impact.full_joint_model`). The foam is linear,
f_c = K_c eps + C_c eps_dot (3.5.1), so the metrics come from the exact kernel of the full
joint. It serves :class:`~designlab.impact.series_joint.FullJointContact` and a link
struck anywhere along it, :class:`~designlab.impact.series_joint.FullJointLink`.

Examples
--------
>>> from designlab.impact import FOAM_1, HEAD_MIN, FullJointContact
>>> arm = FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
>>> row = SERIES_JOINT.row(arm, FOAM_1, HEAD_MIN)
>>> round(float(SERIES_JOINT.column(row, "K_cont")[0]), 1)
37500.0
"""

from __future__ import annotations

from designlab.impact.contact.base import ContactModel
from designlab.impact.full_joint_model import FULL_PARAM_NAMES, full_joint_model
from designlab.impact.parameters import Foam
from designlab.impact.series_joint import FullJointContact, FullJointLink

__all__ = ["SERIES_JOINT"]

SERIES_JOINT = ContactModel(
    name="series_joint",
    label="Full series joint, linear foam",
    doc="transmission in series with the PD controller (3.4.6), Kelvin-Voigt foam; exact kernel",
    robots=(FullJointContact, FullJointLink),
    foam=Foam,
    columns=FULL_PARAM_NAMES,
    robot_attributes=(
        ("M_r", "mass", "inertia"),
        ("C_mech", "transmission_damping", "transmission_damping"),
        ("K_mech", "transmission_stiffness", "transmission_stiffness"),
        ("C_cont", "control_damping", "joint_damping"),
        ("K_cont", "control_stiffness", "joint_stiffness"),
    ),
    linear_model=full_joint_model,
    equations="f_c = K_c eps + C_c eps_dot; joint (3.4.6)",
    linear=True,
    batched=True,
    gradients=False,
    response_form="state_space",
)
