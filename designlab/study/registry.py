"""The registry of study kinds: one :class:`StudyKind` per kind module.

Everything that lists kinds - the loader, the discriminated union, the JSON
Schema, ``designlab list`` / ``validate`` and the runner - is built from this
registry. The kinds shipped with designlab are the modules named in
:data:`designlab.study.kinds.MODULES`; a program (or a test) can add its own
with :func:`register_kind`.

Examples
--------
>>> from designlab.study.registry import study_kinds
>>> "impact_cases" in study_kinds(), kind_of("impact_sweep").report
(True, 'designlab.report.sweep')
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Annotated, Any, Union

from pydantic import Field, TypeAdapter

from designlab.study.base import FORMAT_VERSION, StudyBase
from designlab.study.reproduction import UNCHECKED, Reproduction

__all__ = [
    "StudyKind",
    "kind_of",
    "register_kind",
    "study_adapter",
    "study_json_schema",
    "study_kinds",
    "unregister_kind",
]


@dataclass(frozen=True)
class StudyKind:
    """One study kind.

    Attributes
    ----------
    name
        The ``kind:`` value in study files.
    schema
        The pydantic model of the study (a :class:`StudyBase` subclass whose
        ``kind`` is ``Literal[name]``).
    run
        ``run(study, context) -> result``: computes, writes nothing (see
        :class:`designlab.study.runner.RunContext`).
    report
        Module (dotted name) that registers the report writer of the result
        type with :func:`designlab.report.register_writer`; imported only when
        a report is written.
    reproduction
        How far the report's tables may move on another machine (stated in the
        report; :mod:`designlab.study.reproduction`). The default,
        ``UNCHECKED``, claims no tolerance and says so.
    """

    name: str
    schema: type[StudyBase]
    run: Callable[..., Any]
    report: str
    reproduction: Reproduction = UNCHECKED

    def __post_init__(self) -> None:
        annotation = self.schema.model_fields["kind"].annotation
        if getattr(annotation, "__args__", None) != (self.name,):
            raise TypeError(
                f"{self.schema.__name__}.kind must be Literal[{self.name!r}] to be registered "
                f"as kind {self.name!r}"
            )


_KINDS: dict[str, StudyKind] = {}
_LOADED = False
_ADAPTER: TypeAdapter[Any] | None = None


def register_kind(kind: StudyKind) -> StudyKind:
    """Add a kind (replacing one of the same name); returns it.

    Parameters
    ----------
    kind
        The kind to add.
    """
    global _ADAPTER
    _KINDS[kind.name] = kind
    _ADAPTER = None
    return kind


def unregister_kind(name: str) -> None:
    """Remove a kind added with :func:`register_kind` (for tests).

    Parameters
    ----------
    name
        The kind's name.
    """
    global _ADAPTER
    _KINDS.pop(name, None)
    _ADAPTER = None


def _load() -> None:
    global _LOADED
    if _LOADED:
        return
    from designlab.study.kinds import MODULES

    for module in MODULES:
        kind = importlib.import_module(f"designlab.study.kinds.{module}").KIND
        _KINDS.setdefault(kind.name, kind)
    _LOADED = True


def study_kinds() -> dict[str, StudyKind]:
    """Every registered kind, by name (shipped kinds first, in registry order)."""
    _load()
    return dict(_KINDS)


def _shipped(name: str) -> StudyKind | None:
    """The shipped kind whose module is called ``name``, imported alone (no other kind)."""
    from designlab.study.kinds import MODULES

    if name not in MODULES:
        return None
    kind: StudyKind = importlib.import_module(f"designlab.study.kinds.{name}").KIND
    return kind if kind.name == name else None


def kind_of(name: str) -> StudyKind:
    """The kind called ``name`` (``KeyError`` if there is none).

    A shipped kind whose module bears its name is imported on its own, so that
    running one study does not import every domain (navigation, crowds, ...).

    Parameters
    ----------
    name
        The ``kind:`` value.
    """
    if name in _KINDS:
        return _KINDS[name]
    if not _LOADED and (kind := _shipped(name)) is not None:
        return kind
    _load()
    return _KINDS[name]


def study_adapter() -> TypeAdapter[Any]:
    """A pydantic adapter validating a study of any kind (discriminated on ``kind``)."""
    global _ADAPTER
    _load()
    if _ADAPTER is None:
        schemas = tuple(k.schema for k in _KINDS.values())
        union: Any = schemas[0] if len(schemas) == 1 else Union[schemas]  # noqa: UP007
        _ADAPTER = TypeAdapter(Annotated[union, Field(discriminator="kind")])
    return _ADAPTER


_KEYWORDS = {"gt": "exclusiveMinimum", "ge": "minimum", "lt": "exclusiveMaximum", "le": "maximum"}


def _standard_keywords(node: Any) -> Any:
    """Replace pydantic's ``gt/ge/lt/le`` (left on wrapped numbers) by JSON Schema keywords."""
    if isinstance(node, dict):
        is_number = node.get("type") in ("number", "integer")
        return {
            (_KEYWORDS[k] if is_number and k in _KEYWORDS else k): _standard_keywords(v)
            for k, v in node.items()
        }
    if isinstance(node, list):
        return [_standard_keywords(v) for v in node]
    return node


def study_json_schema() -> dict[str, Any]:
    """The JSON Schema (draft 2020-12) of a study file of any kind, for editors and CI.

    Examples
    --------
    >>> schema = study_json_schema()
    >>> "impact_cases" in schema["discriminator"]["mapping"]
    True
    """
    schema = _standard_keywords(study_adapter().json_schema(by_alias=True))
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["title"] = f"designlab study (format {FORMAT_VERSION})"
    return schema
