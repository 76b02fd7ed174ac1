"""Schema pieces shared by the impact kinds: robot, foam and head-neck specs.

Each spec is a preset name, explicit values, or a preset with some values
replaced; ``build()`` returns the :mod:`designlab.impact` parameter object
(validated by its constructor).

Examples
--------
>>> RobotSpec.model_validate("MANIPULATOR_1").build().mass
9.6
>>> FoamSpec.model_validate({"preset": "FOAM_1", "linear_depth": 0.025}).build().linear_depth
0.025
"""

from __future__ import annotations

from typing import Any, ClassVar

from pydantic import Field, field_validator, model_validator

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
from designlab.study.base import Model, NonNegative, Positive, did_you_mean

__all__ = ["FoamSpec", "HeadSpec", "RobotSpec"]


class _ComponentSpec(Model):
    """A preset name, or explicit values, or a preset with some values replaced."""

    PRESETS: ClassVar[dict[str, Any]] = {}
    REQUIRED: ClassVar[tuple[str, ...]] = ()
    WHAT: ClassVar[str] = "component"
    BUILDS: ClassVar[type] = object

    preset: str | None = Field(None, description="name of a preset to start from")

    @classmethod
    def __get_pydantic_json_schema__(cls, core_schema: Any, handler: Any) -> dict[str, Any]:
        # a bare preset name is also allowed (``robot: MANIPULATOR_1``)
        schema = handler(core_schema)
        schema = handler.resolve_ref_schema(schema)
        schema["properties"]["preset"] = {
            "anyOf": [{"enum": list(cls.PRESETS)}, {"type": "null"}],
            "default": None,
            "description": "name of a preset to start from",
        }
        names = {"enum": list(cls.PRESETS), "description": f"a {cls.WHAT} preset"}
        return {"anyOf": [names, dict(schema)], "title": schema.get("title", cls.__name__)}

    @model_validator(mode="before")
    @classmethod
    def _preset_shorthand(cls, data: Any) -> Any:
        return {"preset": data} if isinstance(data, str) else data

    @field_validator("preset")
    @classmethod
    def _known_preset(cls, value: str | None) -> str | None:
        if value is not None and value not in cls.PRESETS:
            known = ", ".join(cls.PRESETS)
            raise ValueError(
                f"unknown {cls.WHAT} preset {value!r}{did_you_mean(value, list(cls.PRESETS))} "
                f"(known: {known})"
            )
        return value

    @model_validator(mode="after")
    def _complete(self) -> _ComponentSpec:
        if self.preset is None:
            missing = [f for f in self.REQUIRED if getattr(self, f) is None]
            if missing:
                raise ValueError(
                    f"give a preset ({', '.join(self.PRESETS)}) or all of "
                    f"{', '.join(self.REQUIRED)}; missing: {', '.join(missing)}"
                )
        return self

    def build(self) -> Any:
        """Return the designlab parameter object (validated by its constructor)."""
        overrides = {k: v for k, v in self.model_dump(exclude={"preset"}).items() if v is not None}
        if self.preset is None:
            return self.BUILDS(**overrides)
        base = self.PRESETS[self.preset]
        return base.replace(**overrides) if overrides else base


class RobotSpec(_ComponentSpec):
    """Effective manipulator at the impact point (:class:`~designlab.impact.ContactDynamics`).

    Presets: ``MANIPULATOR_1`` (direct-drive arm), ``MANIPULATOR_2`` (Puma 560).
    """

    PRESETS: ClassVar[dict[str, Any]] = {
        "MANIPULATOR_1": MANIPULATOR_1,
        "MANIPULATOR_2": MANIPULATOR_2,
    }
    REQUIRED: ClassVar[tuple[str, ...]] = ("mass", "stiffness", "damping")
    WHAT: ClassVar[str] = "robot"
    BUILDS: ClassVar[type] = ContactDynamics

    mass: Positive | None = Field(None, description="effective mass M_r, kg")
    stiffness: NonNegative | None = Field(None, description="stiffness K_r, N/m")
    damping: NonNegative | None = Field(None, description="damping C_r, N s/m")


class FoamSpec(_ComponentSpec):
    """Foam covering (:class:`~designlab.impact.Foam`).

    Presets: ``FOAM_1``, ``FOAM_2`` (Zeng 2011, Table 3.3), ``FOAM_2_MEASURED``
    (App. A.1, used for Ch. 4), ``FOAM_3``.
    """

    PRESETS: ClassVar[dict[str, Any]] = {
        "FOAM_1": FOAM_1,
        "FOAM_2": FOAM_2,
        "FOAM_2_MEASURED": FOAM_2_MEASURED,
        "FOAM_3": FOAM_3,
    }
    REQUIRED: ClassVar[tuple[str, ...]] = ("stiffness", "damping")
    WHAT: ClassVar[str] = "foam"
    BUILDS: ClassVar[type] = Foam

    stiffness: Positive | None = Field(None, description="stiffness K_c, N/m")
    damping: NonNegative | None = Field(None, description="damping C_c, N s/m")
    linear_depth: Positive | None = Field(
        None, description="lambda, end of the linear range, m (default 0.02)"
    )
    thickness: Positive | None = Field(None, description="uncompressed thickness T_u, m")


class HeadSpec(_ComponentSpec):
    """Head on a neck (:class:`~designlab.impact.HeadNeck`).

    Presets: ``HEAD_MIN``, ``HEAD_MAX`` (Zeng 2011, Sec. 3.6), ``TEST_HEAD`` (Ch. 4).
    """

    PRESETS: ClassVar[dict[str, Any]] = {
        "HEAD_MIN": HEAD_MIN,
        "HEAD_MAX": HEAD_MAX,
        "TEST_HEAD": TEST_HEAD,
    }
    REQUIRED: ClassVar[tuple[str, ...]] = ("mass", "stiffness", "damping")
    WHAT: ClassVar[str] = "head"
    BUILDS: ClassVar[type] = HeadNeck

    mass: Positive | None = Field(None, description="head mass M_h, kg")
    stiffness: NonNegative | None = Field(None, description="neck stiffness K_h, N/m")
    damping: NonNegative | None = Field(None, description="neck damping C_h, N s/m")
