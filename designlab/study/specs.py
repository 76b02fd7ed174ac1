"""Study models derived from the domain models' parameter declarations.

A study kind never restates a domain field: :func:`spec_model` builds the
pydantic model of a domain dataclass from its declarations
(:func:`designlab.params.param`), so the YAML schema, the JSON Schema, the
defaults and the allowed ranges are the domain's own. ``build()`` returns the
domain object (validated by its constructor).

With ``presets``, a spec is a preset name (``robot: MANIPULATOR_1``), explicit
values, or a preset with some values replaced; every field is then optional.

Examples
--------
>>> from designlab.impact import Foam, FOAM_1
>>> FoamSpec = spec_model(Foam, presets={"FOAM_1": FOAM_1}, required=("stiffness", "damping"))
>>> FoamSpec.model_validate("FOAM_1").build().stiffness
24250.0
>>> FoamSpec.model_validate({"preset": "FOAM_1", "linear_depth": 0.025}).build().linear_depth
0.025
>>> FoamSpec.model_json_schema()["anyOf"][1]["properties"]["stiffness"]["anyOf"][0]
{'exclusiveMinimum': 0.0, 'maximum': 1000000000000.0, 'type': 'number'}
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from typing import Any, ClassVar

from pydantic import Field, create_model, field_validator, model_validator

from designlab.errors import DesignlabError
from designlab.params import params_of
from designlab.study.base import Model, did_you_mean

__all__ = ["Buildable", "ComponentSpec", "built", "spec_model"]


def built(spec: Any) -> Any:
    """``spec.build()``, with a domain error turned into a validation error (for validators).

    Parameters
    ----------
    spec
        A spec with ``build()``.
    """
    try:
        return spec.build()
    except (DesignlabError, TypeError) as exc:
        raise ValueError(str(exc)) from None


class Buildable(Model):
    """A spec whose domain object is built (and so checked) while it is validated."""

    @model_validator(mode="after")
    def _buildable(self) -> Buildable:
        built(self)
        return self


class ComponentSpec(Model):
    """Base of the specs with presets: a preset name, explicit values, or both."""

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
    def _complete(self) -> ComponentSpec:
        if self.preset is None:
            missing = [f for f in self.REQUIRED if getattr(self, f) is None]
            if missing:
                raise ValueError(
                    f"give a preset ({', '.join(self.PRESETS)}) or all of "
                    f"{', '.join(self.REQUIRED)}; missing: {', '.join(missing)}"
                )
        return self

    def build(self) -> Any:
        """Return the domain object (validated by its constructor)."""
        overrides = {k: v for k, v in self.model_dump(exclude={"preset"}).items() if v is not None}
        if self.preset is None:
            return self.BUILDS(**overrides)
        base = self.PRESETS[self.preset]
        return base.replace(**overrides) if overrides else base


class _PlainSpec(Model):
    BUILDS: ClassVar[type] = object

    def build(self) -> Any:
        """Return the domain object (validated by its constructor)."""
        return self.BUILDS(**self.model_dump())


def spec_model(
    cls: type,
    *,
    presets: dict[str, Any] | None = None,
    required: Sequence[str] = (),
    exclude: Sequence[str] = (),
    name: str | None = None,
    what: str | None = None,
    doc: str | None = None,
) -> type[Model]:
    """The pydantic model of a :func:`~designlab.params.declared` dataclass.

    Parameters
    ----------
    cls
        The domain dataclass.
    presets
        Preset name -> instance. With presets every field is optional and the
        spec may be a bare preset name; without, the fields keep the
        dataclass's defaults (a field without a default is required).
    required
        With presets: the fields needed when no preset is given.
    exclude
        Fields left out of the study file (they keep the dataclass default).
    name
        The model's name (default ``<cls>Spec``).
    what
        The word for the thing in error messages (``"foam"``).
    doc
        The model's docstring (default: the class's summary line).

    Returns
    -------
    type
        A :class:`~designlab.study.base.Model` subclass with ``build()``.
    """
    decls = params_of(cls)
    fields: dict[str, Any] = {}
    for fname, decl in decls.items():
        if fname in exclude or decl.kind == "object":
            continue
        if presets is not None:
            fields[fname] = (decl.annotation(optional=True), None)
        elif decl.default is None and not decl.optional:
            fields[fname] = (decl.annotation(), ...)
        else:
            fields[fname] = (decl.annotation(), decl.default)
    summary = (cls.__doc__ or "").strip().splitlines()[0] if cls.__doc__ else ""
    model_doc = doc or f"{summary} (:class:`{cls.__module__}.{cls.__name__}`), SI units."
    base: type[Model] = ComponentSpec if presets is not None else _PlainSpec
    # The caller's module: a spec bound there under its own name pickles with its results.
    module = sys._getframe(1).f_globals.get("__name__", __name__)
    model = create_model(  # type: ignore[call-overload]
        name or f"{cls.__name__}Spec", __base__=base, __doc__=model_doc, __module__=module, **fields
    )
    model.BUILDS = cls
    if presets is not None:
        model.PRESETS = dict(presets)
        model.REQUIRED = tuple(required)
        model.WHAT = what or cls.__name__
        model.__doc__ += " Presets: " + ", ".join(f"``{p}``" for p in presets) + "."
    return model  # type: ignore[no-any-return]
