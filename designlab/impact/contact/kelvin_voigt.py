"""The thesis's contact: the reduced joint (3.4.9) and a linear Kelvin-Voigt foam (3.5.1).

The manipulator is one mass on the reduced joint's spring and damper (M_r, K_r, C_r of
Sec. 3.4), the foam a spring and damper in parallel, f_c = K_c eps + C_c eps_dot (3.5.1),
the head a mass on the neck (3.5.3). Linear: its metrics come from the exact compiled
kernel (:mod:`designlab.impact.metrics`), its gradients from
:mod:`designlab.impact.derivatives`. It serves a fixed manipulator
(:class:`~designlab.impact.parameters.ContactDynamics`) and a link struck anywhere along
it (:class:`~designlab.impact.parameters.LinkImpact`, (3.4.17)).

Examples
--------
>>> from designlab.impact import FOAM_1, HEAD_MIN, MANIPULATOR_1
>>> KELVIN_VOIGT.row(MANIPULATOR_1, FOAM_1, HEAD_MIN).tolist()
[9.6, 250.0, 20000.0, 24250.0, 71.9, 4.4, 46.0, 3000.0]
"""

from __future__ import annotations

from designlab.impact.contact.base import REDUCED_JOINT, ContactModel
from designlab.impact.model import (
    PARAM_NAMES,
    LinearImpactModel,
    constrained_model,
    unconstrained_model,
)
from designlab.impact.parameters import ContactDynamics, Foam, LinkImpact

__all__ = ["KELVIN_VOIGT"]


def reduced_joint_model(constrained: bool) -> LinearImpactModel:
    """The model of Sec. 3.5 (3.5.11), or the constrained one (3.6.1)/(3.9.4).

    Examples
    --------
    >>> reduced_joint_model(False).n_states, reduced_joint_model(True).n_states
    (4, 2)
    """
    return constrained_model() if constrained else unconstrained_model()


KELVIN_VOIGT = ContactModel(
    name="kelvin_voigt",
    label="Reduced joint, linear foam",
    doc="the thesis's model: reduced joint (3.4.9), Kelvin-Voigt foam (3.5.1); exact kernel",
    robots=(ContactDynamics, LinkImpact),
    foam=Foam,
    columns=PARAM_NAMES,
    robot_attributes=REDUCED_JOINT,
    linear_model=reduced_joint_model,
    equations="f_c = K_c eps + C_c eps_dot",
    linear=True,
    batched=True,
    gradients=True,
    printed_q2=True,
)
