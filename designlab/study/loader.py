"""Load and validate study files, with errors that point at the line.

Every problem with a study file - a missing file, a YAML syntax error, an
unknown or misspelt field, a wrong type or an out-of-range value - raises
:class:`designlab.errors.StudyError`. Its message starts with
``<file>:<line>: <field path>:`` and, for unknown fields and preset names,
suggests the closest valid name.

Examples
--------
>>> from designlab.study import parse_study
>>> text = '''
... designlab: 1
... kind: impact_cases
... name: demo
... cases:
...   - robot: {mass: 9.6, stifness: 20e3, damping: 250}
...     foam: FOAM_1
...     head: TEST_HEAD
...     impact_velocity: 1.25
... '''
>>> parse_study(text, file="demo.yaml")
Traceback (most recent call last):
...
designlab.errors.StudyError: demo.yaml:6: cases[0].robot.stifness: unknown field;
    did you mean 'stiffness'? (allowed: preset, mass, stiffness, damping)
"""

from __future__ import annotations

import difflib
import types
from collections.abc import Hashable
from os import PathLike
from typing import Annotated, Any, Union, get_args, get_origin

from pydantic import BaseModel, ValidationError

from designlab.errors import DesignlabError, StudyError
from designlab.study.base import FORMAT_VERSION, StudyBase, did_you_mean, format_path
from designlab.study.registry import kind_of, study_kinds
from designlab.yamlio import YamlError, YamlPath, load_yaml, read_text_file

__all__ = ["format_path", "load_study", "parse_study"]


def load_study(path: str | PathLike[str]) -> StudyBase:
    """Read and validate a study file.

    Parameters
    ----------
    path
        The YAML file.

    Returns
    -------
    StudyBase
        The validated study, an instance of the model for its ``kind``
        (e.g. :class:`~designlab.study.kinds.impact_cases.ImpactCasesStudy`).

    Raises
    ------
    StudyError
        If the file cannot be read or is not a valid study.

    Examples
    --------
    >>> load_study("no/such/study.yaml")
    Traceback (most recent call last):
    ...
    designlab.errors.StudyError: no/such/study.yaml: study file not found
    """
    try:
        text = read_text_file(path)
    except YamlError as exc:
        raise StudyError(_study_file(exc.message), file=str(path), line=exc.line) from None
    return parse_study(text, file=str(path))


def _study_file(message: str) -> str:
    """The reader's message about a study file ("file not found" -> "study file not found")."""
    return {"file not found": "study file not found"}.get(message, message)


def parse_study(text: str, file: str = "<string>") -> StudyBase:
    """Validate study YAML text; ``file`` is only used in error messages.

    See :func:`load_study`.

    Parameters
    ----------
    text
        The YAML text.
    file
        Name of the file, for error messages.

    Examples
    --------
    >>> parse_study("designlab: 1\\nkind: impact_case\\nname: x\\n", file="s.yaml")
    Traceback (most recent call last):
    ...
    designlab.errors.StudyError: s.yaml:2: kind: unknown study kind 'impact_case';
        did you mean 'impact_cases'? (known: impact_cases, ...)
    """
    try:
        data, lines = load_yaml(text)
    except YamlError as exc:
        raise StudyError(
            exc.message, file=file, line=exc.line, field=format_path(exc.path) or None
        ) from None
    _check_format(data, lines, file)
    kind = _kind_name(data, lines, file)
    data = {**data, "kind": kind}
    model = kind_of(kind).schema
    try:
        study = model.model_validate(data)
    except ValidationError as exc:
        raise _to_study_error(exc, data, lines, file, model) from None
    except RecursionError:  # pragma: no cover - the YAML depth limit comes first
        raise StudyError("the study is nested too deeply", file=file, line=1) from None
    _check(study, lines, file)
    return study


def _check_format(data: Any, lines: dict[YamlPath, int], file: str) -> None:
    """A mapping with ``designlab: 1`` (the format this designlab reads)."""
    if not isinstance(data, dict):
        raise StudyError(
            "a study must be a YAML mapping with the keys designlab, kind, name, ...",
            file=file,
            line=1,
        )
    if "designlab" not in data:
        raise StudyError(
            f"missing the format key; add 'designlab: {FORMAT_VERSION}' at the top",
            file=file,
            field="designlab",
            line=1,
        )
    version = data["designlab"]
    if version == FORMAT_VERSION and not isinstance(version, bool):
        return
    if isinstance(version, str) and version.strip() == str(FORMAT_VERSION):
        problem = (
            f"the format version is the number {FORMAT_VERSION}, not the text {version!r}; "
            f"write 'designlab: {FORMAT_VERSION}' without quotes"
        )
    elif isinstance(version, bool) or not isinstance(version, int | float):
        problem = (
            f"the format version must be the number {FORMAT_VERSION} (got {version!r}); "
            f"write 'designlab: {FORMAT_VERSION}'"
        )
    else:
        problem = (
            f"study format {version!r} is not supported; this designlab reads format "
            f"{FORMAT_VERSION} only (write 'designlab: {FORMAT_VERSION}', or use the designlab "
            "version that wrote the study)"
        )
    raise StudyError(problem, file=file, field="designlab", line=lines.get(("designlab",)))


def _kind_name(data: dict[str, Any], lines: dict[YamlPath, int], file: str) -> str:
    """The registered kind the study names."""
    kind = data.get("kind")
    if isinstance(kind, str) and _known(kind):
        return kind
    registry = study_kinds()
    known = ", ".join(registry)
    if kind is None:
        raise StudyError(
            f"missing required field (the study kind, one of: {known})",
            file=file,
            field="kind",
            line=1,
        )
    if not isinstance(kind, str) or kind not in registry:
        hint = did_you_mean(kind, list(registry)) if isinstance(kind, str) else ""
        raise StudyError(
            f"unknown study kind {kind!r}{hint} (known: {known})",
            file=file,
            field="kind",
            line=lines.get(("kind",)),
        )
    return kind


def _known(kind: str) -> bool:
    """Whether ``kind`` is registered (importing only its own module when it is shipped)."""
    try:
        kind_of(kind)
    except KeyError:
        return False
    return True


def _check(study: StudyBase, lines: dict[YamlPath, int], file: str) -> None:
    """Run the study's own checks (:meth:`StudyBase.check`) and place their errors in the file."""
    try:
        study.check()
    except StudyError as exc:
        if exc.file is not None:
            raise
        path = exc.path or ()
        line = _line_for(path, lines) if path else None
        raise StudyError(exc.message, file=file, field=exc.field, line=line) from None
    except (DesignlabError, ValueError, OverflowError) as exc:
        raise StudyError(str(exc), file=file) from None


# --- mapping pydantic errors back to the file ---------------------------------


def _data_path(loc: tuple[int | str, ...], data: Any) -> YamlPath:
    """Follow a pydantic error location through the data, dropping union tags."""
    path: list[Hashable] = []
    current = data
    for i, part in enumerate(loc):
        last = i == len(loc) - 1
        if isinstance(current, dict) and part in current:
            current = current[part]
        elif isinstance(current, list) and isinstance(part, int) and 0 <= part < len(current):
            current = current[part]
        elif last:
            # a missing field, or ``preset`` of the ``robot: NAME`` shorthand
            if not (part == "preset" and isinstance(current, str)):
                path.append(part)
            break
        else:
            continue  # a tag added by pydantic (union member, validator), not data
        path.append(part)
    return tuple(path)


def _line_for(path: YamlPath, lines: dict[YamlPath, int]) -> int:
    for n in range(len(path), 0, -1):
        if path[:n] in lines:
            return lines[path[:n]]
    return 1


def _unwrap(tp: Any) -> Any:
    """Strip Annotated/Optional/list wrappers down to a model class (or give up)."""
    for _ in range(10):
        origin = get_origin(tp)
        if origin is Annotated:
            tp = get_args(tp)[0]
        elif origin in (Union, types.UnionType):
            args = [a for a in get_args(tp) if a is not type(None)]
            models = [a for a in args if isinstance(a, type) and issubclass(a, BaseModel)]
            if len(args) == 1:
                tp = args[0]
            elif len(models) == 1:
                tp = models[0]
            else:
                return None
        else:
            return tp
    return None  # pragma: no cover


def _fields_by_name(model: type[BaseModel]) -> dict[str, Any]:
    """A model's fields by the name used in the file (the alias, if any)."""
    return {(f.alias or name): f for name, f in model.model_fields.items()}


def _model_at(model: type[BaseModel], path: YamlPath) -> type[BaseModel] | None:
    """The model class that validates the mapping at ``path`` (None if unknown)."""
    current: Any = model
    for part in path:
        current = _unwrap(current)
        if isinstance(part, int):
            if get_origin(current) in (list, tuple):
                current = get_args(current)[0]
                continue
            return None
        if isinstance(current, type) and issubclass(current, BaseModel):
            fields = _fields_by_name(current)
            field = fields.get(str(part))
            if field is None:
                return None
            current = field.annotation
        else:
            return None
    current = _unwrap(current)
    return current if isinstance(current, type) and issubclass(current, BaseModel) else None


def _message(err: dict[str, Any], path: YamlPath, model: type[BaseModel]) -> str:
    kind = err["type"]
    if kind == "extra_forbidden":
        parent = _model_at(model, path[:-1])
        if parent is None:
            return "unknown field"
        allowed = list(_fields_by_name(parent))
        return (
            f"unknown field{did_you_mean(str(path[-1]), allowed)} (allowed: {', '.join(allowed)})"
        )
    if kind == "missing":
        return "missing required field"
    if kind == "literal_error" and isinstance(err.get("input"), str):
        expected = err.get("ctx", {}).get("expected", "")
        choices = [c.strip().strip("'") for c in expected.replace(" or ", ", ").split(",")]
        hint = did_you_mean(err["input"], [c for c in choices if c])
        return f"{err['msg']} (got {err['input']!r}{hint})"
    msg: str = err["msg"]
    if msg.startswith("Value error, "):
        return msg[len("Value error, ") :]
    return f"{msg} (got {_shown(err.get('input'))})"


def _shown(value: Any) -> str:
    """A value for an error message: its repr, a list or mapping named as such, cut short."""
    text = repr(value)
    if len(text) > 60:
        text = text[:57] + "..."
    if isinstance(value, list):
        return f"a list: {text}" if value else "an empty list []"
    if isinstance(value, dict):
        return f"a mapping: {text}" if value else "an empty mapping {}"
    return text


def _to_study_error(
    exc: ValidationError,
    data: Any,
    lines: dict[YamlPath, int],
    file: str,
    model: type[BaseModel],
) -> StudyError:
    errors = [(err, _data_path(tuple(err["loc"]), data)) for err in exc.errors(include_url=False)]
    # A misspelt field also shows up as a missing one; report only the misspelling.
    suggested = set()
    for err, path in errors:
        if err["type"] == "extra_forbidden":
            parent = _model_at(model, path[:-1])
            if parent is not None:
                names = list(_fields_by_name(parent))
                for name in difflib.get_close_matches(str(path[-1]), names, 1):
                    suggested.add((*path[:-1], name))
    found = [
        (_line_for(path, lines), format_path(path), _message(err, path, model))
        for err, path in errors
        if not (err["type"] == "missing" and path in suggested)
    ]
    found.sort(key=lambda item: item[0])
    line, field, message = found[0]
    if len(found) > 1:
        more = "\n".join(f"  {file}:{ln}: {fld}: {msg}" for ln, fld, msg in found[1:])
        message += f"\nand {len(found) - 1} more:\n{more}"
    return StudyError(message, file=file, field=field or None, line=line)
