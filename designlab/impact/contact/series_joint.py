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

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.impact.contact.base import ContactModel
from designlab.impact.full_joint_model import FULL_PARAM_NAMES, full_joint_model
from designlab.impact.metrics import ImpactMetrics, metrics_of_matrix
from designlab.impact.model import LinearImpactModel
from designlab.impact.parameters import Foam
from designlab.impact.series_joint import FullJointContact, FullJointLink

__all__ = ["SERIES_JOINT", "SeriesJointContact"]


@dataclass(frozen=True)
class SeriesJointContact(ContactModel):
    """The full series joint with a linear foam (see the module text).

    Attributes
    ----------
    name, label, doc, robots, foam, columns, robot_columns, foam_columns, equations
        As in :class:`~designlab.impact.contact.base.ContactModel`.
    linear, batched, gradients, profiles, printed_q2, response_form
        Its capabilities, as in :class:`~designlab.impact.contact.base.ContactModel`.
    """

    def _robot_values(self, robot: Any, levers: NDArray | None) -> Mapping[str, Any]:
        if robot.along_link:
            l2 = np.asarray(levers, dtype=float) ** 2
            return {
                "M_r": robot.inertia / l2,
                "C_mech": robot.transmission_damping / l2,
                "K_mech": robot.transmission_stiffness / l2,
                "C_cont": robot.joint_damping / l2,
                "K_cont": robot.joint_stiffness / l2,
            }
        return {"M_r": robot.mass, "C_mech": robot.transmission_damping,
                "K_mech": robot.transmission_stiffness, "C_cont": robot.control_damping,
                "K_cont": robot.control_stiffness}  # fmt: skip

    def _labels(self, along_link: bool) -> Mapping[str, str]:
        control = ("joint_damping", "joint_stiffness") if along_link else (
            "control_damping", "control_stiffness")  # fmt: skip
        return {"M_r": "robot.inertia" if along_link else "robot.mass",
                "C_mech": "robot.transmission_damping", "K_mech": "robot.transmission_stiffness",
                "K_c": "foam.stiffness", "C_c": "foam.damping",
                "C_cont": f"robot.{control[0]}", "K_cont": f"robot.{control[1]}"}  # fmt: skip

    def model(self, constrained: bool) -> LinearImpactModel:
        """The full-joint model (:mod:`designlab.impact.full_joint_model`)."""
        return full_joint_model(constrained)

    def metrics(self, rows: NDArray, impact_velocity: Any, **options: Any) -> ImpactMetrics:
        """The exact full-joint kernel's metrics (:func:`.metrics.metrics_of_matrix`)."""
        return metrics_of_matrix(rows, impact_velocity, **options)


SERIES_JOINT = SeriesJointContact(
    name="series_joint",
    label="Full series joint, linear foam",
    doc="transmission in series with the PD controller (3.4.6), Kelvin-Voigt foam; exact kernel",
    robots=(FullJointContact, FullJointLink),
    foam=Foam,
    columns=FULL_PARAM_NAMES,
    robot_columns=("M_r", "C_mech", "K_mech", "C_cont", "K_cont"),
    equations="f_c = K_c eps + C_c eps_dot; joint (3.4.6)",
    linear=True,
    batched=True,
    gradients=False,
    response_form="state_space",
)
