"""Schema pieces shared by the impact kinds: robot, foam and head-neck specs.

Each spec is a preset name, explicit values, or a preset with some values
replaced; ``build()`` returns the :mod:`designlab.impact` parameter object
(validated by its constructor). The fields, units, bounds and defaults are the
domain's declarations (:func:`designlab.study.specs.spec_model`).

Examples
--------
>>> RobotSpec.model_validate("MANIPULATOR_1").build().mass
9.6
>>> FoamSpec.model_validate({"preset": "FOAM_1", "linear_depth": 0.025}).build().linear_depth
0.025
"""

from __future__ import annotations

from designlab.impact.parameters import (
    FOAM_1,
    FOAM_2,
    FOAM_2_MEASURED,
    FOAM_3,
    HEAD_MAX,
    HEAD_MIN,
    MANIPULATOR_1,
    MANIPULATOR_2,
    TEST_HEAD,
    ContactDynamics,
    Foam,
    HeadNeck,
)
from designlab.study.specs import spec_model

__all__ = ["FoamSpec", "HeadSpec", "RobotSpec"]

#: Effective manipulator at the impact point: ``MANIPULATOR_1`` (direct-drive arm),
#: ``MANIPULATOR_2`` (Puma 560) or explicit values.
RobotSpec = spec_model(
    ContactDynamics,
    name="RobotSpec",
    presets={"MANIPULATOR_1": MANIPULATOR_1, "MANIPULATOR_2": MANIPULATOR_2},
    required=("mass", "stiffness", "damping"),
    exclude=("lever_arm", "name"),
    what="robot",
)

#: Foam covering: ``FOAM_1``, ``FOAM_2`` (Zeng 2011, Table 3.3), ``FOAM_2_MEASURED``
#: (App. A.1, used for Ch. 4), ``FOAM_3`` or explicit values.
FoamSpec = spec_model(
    Foam,
    name="FoamSpec",
    presets={
        "FOAM_1": FOAM_1,
        "FOAM_2": FOAM_2,
        "FOAM_2_MEASURED": FOAM_2_MEASURED,
        "FOAM_3": FOAM_3,
    },
    required=("stiffness", "damping"),
    exclude=("name",),
    what="foam",
)

#: Head on a neck: ``HEAD_MIN``, ``HEAD_MAX`` (Zeng 2011, Sec. 3.6), ``TEST_HEAD`` (Ch. 4)
#: or explicit values.
HeadSpec = spec_model(
    HeadNeck,
    name="HeadSpec",
    presets={"HEAD_MIN": HEAD_MIN, "HEAD_MAX": HEAD_MAX, "TEST_HEAD": TEST_HEAD},
    required=("mass", "stiffness", "damping"),
    exclude=("name",),
    what="head",
)
