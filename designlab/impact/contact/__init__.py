"""The impact contact models, one module each, registered by their public name.

Each model (:class:`~designlab.impact.contact.base.ContactModel`) is one way of writing
the manipulator-foam-head impact of Zeng 2011, Sec. 3.4-3.5, declared in its own module
with its parameter classes and row, its equations, how its metrics are computed and its
capabilities:

* :mod:`~designlab.impact.contact.kelvin_voigt`: the reduced joint (3.4.9) and the
  linear foam (3.5.1), the thesis's model; exact kernel;
* :mod:`~designlab.impact.contact.series_joint`: the full series joint (3.4.6) and the
  linear foam; exact kernel;
* :mod:`~designlab.impact.contact.hunt_crossley`: the reduced joint and a non-linear foam
  (Hunt-Crossley damping, densification spring); the general response path
  (:mod:`designlab.impact.general`);
* :mod:`~designlab.impact.contact.measured`: the reduced joint and a foam given by its
  measured stress-strain curve (PCHIP) and a linear damper; the general response path.

The integrated models share :mod:`~designlab.impact.contact.integrated` (metrics, HIC,
finite-difference gradients of the general path).

:data:`CONTACTS` is the registry; :func:`contact_of` finds the model of a (robot, foam)
pair. Engines ask the model, never the classes. A new contact model is one module and one
line below.

Examples
--------
>>> import designlab as dl
>>> CONTACTS.choices()
('kelvin_voigt', 'series_joint', 'hunt_crossley', 'stress_strain')
>>> CONTACTS.choices(linear=True)
('kelvin_voigt', 'series_joint')
>>> contact_of(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1).name
'kelvin_voigt'
>>> contact_of(dl.impact.MANIPULATOR_1, "foam")
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: foam = 'foam' is not allowed: ...
"""

from __future__ import annotations

from designlab.errors import InvalidParameterError
from designlab.impact.contact.base import HEAD_COLUMNS, ContactModel
from designlab.impact.contact.hunt_crossley import HUNT_CROSSLEY, HuntCrossleyFoam
from designlab.impact.contact.kelvin_voigt import KELVIN_VOIGT
from designlab.impact.contact.measured import STRESS_STRAIN, StressStrainFoam
from designlab.impact.contact.series_joint import SERIES_JOINT
from designlab.registry import Registry

__all__ = [
    "CONTACTS",
    "HEAD_COLUMNS",
    "ContactModel",
    "HuntCrossleyFoam",
    "StressStrainFoam",
    "contact_for_columns",
    "contact_of",
]

#: The contact models, by public name.
CONTACTS: Registry[ContactModel] = Registry(
    "contact",
    "impact contact models",
    [KELVIN_VOIGT, SERIES_JOINT, HUNT_CROSSLEY, STRESS_STRAIN],
)


#: ``contact_of(robot)``: the foam is not known yet (the robot's linear-foam model)
_UNKNOWN = object()


def contact_of(robot: object, foam: object = _UNKNOWN) -> ContactModel:
    """The contact model of a manipulator and a foam (omitted: the linear foam).

    Parameters
    ----------
    robot
        The manipulator (fixed, or struck along a link).
    foam
        The foam; omitted where only the manipulator is known yet (an envelope varies
        the foam's stiffness and damping), which gives the robot's linear-foam model.

    Returns
    -------
    ContactModel

    Raises
    ------
    InvalidParameterError
        No registered model serves the robot (naming the robot classes that are served),
        or none serves this foam with it.

    Examples
    --------
    >>> import designlab as dl
    >>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    >>> contact_of(arm).name, contact_of(dl.impact.MANIPULATOR_2).label
    ('series_joint', 'Reduced joint, linear foam')
    >>> contact_of(arm, None)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: foam = None is not allowed: must be one of ['Foam'] ...
    """
    robots = [m for m in CONTACTS if type(robot) in m.robots]
    if not robots:
        served = sorted({cls.__name__ for m in CONTACTS for cls in m.robots})
        raise InvalidParameterError("robot", robot, f"must be one of {served}")
    if foam is _UNKNOWN:
        return robots[0]
    for m in robots:
        if type(foam) is m.foam:
            return m
    foams = sorted({m.foam.__name__ for m in robots})
    raise InvalidParameterError(
        "foam", foam, f"must be one of {foams} with a {type(robot).__name__} robot"
    )


def contact_for_columns(columns: object) -> ContactModel | None:
    """The contact model whose parameter row has exactly these column names, if any.

    Parameters
    ----------
    columns
        Column names (a mapping's keys, a data frame's columns).

    Returns
    -------
    ContactModel or None

    Examples
    --------
    >>> contact_for_columns(["M_r", "C_r", "K_r", "K_c", "C_c", "M_h", "C_h", "K_h"]).name
    'kelvin_voigt'
    """
    names = set(columns)  # type: ignore[call-overload]
    return next((m for m in CONTACTS if set(m.columns) == names), None)
