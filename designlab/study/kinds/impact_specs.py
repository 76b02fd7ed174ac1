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

from pydantic import model_validator

from designlab.impact.parameters import (
    DAMPING_GRID,
    DAMPING_POINTS,
    FOAM_PRESETS,
    HEAD_PRESETS,
    ROBOT_PRESETS,
    ContactDynamics,
    Foam,
    HeadNeck,
)
from designlab.study.base import Model
from designlab.study.specs import spec_model

__all__ = ["DampingGrid", "FoamSpec", "HeadSpec", "RobotSpec"]

#: Effective manipulator at the impact point: ``MANIPULATOR_1`` (direct-drive arm),
#: ``MANIPULATOR_2`` (Puma 560) or explicit values.
RobotSpec = spec_model(
    ContactDynamics,
    name="RobotSpec",
    presets=ROBOT_PRESETS,
    required=("mass", "stiffness", "damping"),
    exclude=("lever_arm", "name"),
    what="robot",
)

#: Foam covering: ``FOAM_1``, ``FOAM_2`` (Zeng 2011, Table 3.3), ``FOAM_2_MEASURED``
#: (App. A.1, used for Ch. 4), ``FOAM_3`` or explicit values.
FoamSpec = spec_model(
    Foam,
    name="FoamSpec",
    presets=FOAM_PRESETS,
    required=("stiffness", "damping"),
    exclude=("name",),
    what="foam",
)

#: Head on a neck: ``HEAD_MIN``, ``HEAD_MAX`` (Zeng 2011, Sec. 3.6), ``TEST_HEAD`` (Ch. 4)
#: or explicit values.
HeadSpec = spec_model(
    HeadNeck,
    name="HeadSpec",
    presets=HEAD_PRESETS,
    required=("mass", "stiffness", "damping"),
    exclude=("name",),
    what="head",
)


class DampingGrid(Model):
    """The C_c grid of a foam envelope, N s/m: ``num`` values from ``low`` to ``high``.

    Each value and the number of values are the envelope's declarations
    (:data:`~designlab.impact.parameters.DAMPING_GRID`,
    :data:`~designlab.impact.parameters.DAMPING_POINTS`), so the study file and
    :func:`designlab.impact.foam_envelope` enforce the same limits.
    """

    low: DAMPING_GRID.annotation() = 0.0  # type: ignore[valid-type]
    high: DAMPING_GRID.annotation() = 200.0  # type: ignore[valid-type]
    num: DAMPING_POINTS.annotation() = 21  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _order(self) -> DampingGrid:
        if not self.low < self.high:
            raise ValueError(f"low = {self.low:g} N s/m must be < high = {self.high:g} N s/m")
        return self

    def values(self) -> list[float]:
        """The grid (``[low]`` for one value)."""
        step = (self.high - self.low) / max(self.num - 1, 1)
        return [round(self.low + i * step, 12) for i in range(self.num)]
