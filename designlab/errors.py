"""Exceptions raised by designlab.

Every error designlab raises on purpose derives from :class:`DesignlabError`.
Errors about bad input are also :class:`ValueError` so that generic callers
can catch them the usual way.

Examples
--------
>>> import designlab as dl
>>> try:
...     dl.impact.HeadNeck(mass=-1.0, stiffness=3e3, damping=46.0)
... except dl.errors.InvalidParameterError as exc:
...     print(exc)
HeadNeck.mass = -1.0 kg is not allowed: must be a finite number > 0 and <= 1000
"""

from __future__ import annotations

import math
from typing import Any

__all__ = [
    "DesignlabError",
    "InvalidParameterError",
    "MissingExtraError",
    "ModelError",
    "SolverError",
    "StudyError",
    "check_finite",
    "check_nonnegative",
    "check_positive",
]


class DesignlabError(Exception):
    """Base class of every error raised by designlab."""


class InvalidParameterError(DesignlabError, ValueError):
    """A parameter is outside its allowed range.

    Parameters
    ----------
    name
        Qualified parameter name, e.g. ``"Foam.stiffness"``.
    value
        The offending value.
    allowed
        Human-readable description of what is allowed.
    unit
        SI unit of the parameter (optional).
    """

    def __init__(self, name: str, value: Any, allowed: str, unit: str = "") -> None:
        self.name = name
        self.value = value
        self.allowed = allowed
        self.unit = unit
        shown = f"{value!r} {unit}".rstrip()
        super().__init__(f"{name} = {shown} is not allowed: {allowed}")


class MissingExtraError(DesignlabError, ImportError):
    """A call needs an optional dependency that is not installed; names the extra to install.

    Parameters
    ----------
    package
        The missing package, e.g. ``"jupedsim"``.
    extra
        The designlab extra that installs it, e.g. ``"crowds"``.
    needed_for
        What needs it, e.g. ``"crowd simulations"``.
    reason
        Why it could not be imported (the ``ImportError``'s message).
    """

    def __init__(self, package: str, extra: str, needed_for: str, reason: str = "") -> None:
        self.package = package
        self.extra = extra
        why = f" ({reason})" if reason else ""
        super().__init__(
            f"{needed_for} need {package}, which cannot be imported{why}: install designlab "
            f"with the {extra!r} extra, pip install 'designlab[{extra}]'"
        )


class ModelError(DesignlabError, ValueError):
    """A model cannot be evaluated for the given combination of parameters."""


class SolverError(DesignlabError, RuntimeError):
    """A solver failed in a way that cannot be reported in its result object."""


class StudyError(DesignlabError, ValueError):
    """A study file is missing, malformed or inconsistent.

    The message names the file, the field path and, where known, the line.

    Parameters
    ----------
    message
        What is wrong and what is allowed.
    file
        The study file, if known.
    field
        Dotted path of the offending field (``sweep.parameters.foam.stiffness``).
    line
        1-based line of the field in the file, if known.
    path
        The field as keys and list indices from the root of the study
        (``("cases", 0, "robot")``); the loader uses it to find the line. When
        ``field`` is not given it is written from ``path``.

    Examples
    --------
    >>> str(StudyError("must be > 0", file="s.yaml", line=4, path=("cases", 0, "mass")))
    's.yaml:4: cases[0].mass: must be > 0'
    """

    def __init__(
        self,
        message: str,
        *,
        file: str | None = None,
        field: str | None = None,
        line: int | None = None,
        path: tuple[Any, ...] | None = None,
    ) -> None:
        if field is None and path:
            field = "".join(
                f"[{p}]" if isinstance(p, int) else (f".{p}" if i else str(p))
                for i, p in enumerate(path)
            )
        self.message = message
        self.file = file
        self.field = field
        self.line = line
        self.path = tuple(path) if path else None
        where = ""
        if file is not None:
            where = str(file)
            if line is not None:
                where += f":{line}"
            where += ": "
        if field:
            where += f"{field}: "
        super().__init__(where + message)


def _as_float(name: str, value: Any, unit: str) -> float:
    from designlab.params import is_complex  # params imports this module

    if isinstance(value, bool) or is_complex(value):
        raise InvalidParameterError(name, value, "must be a real number", unit)
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise InvalidParameterError(name, value, "must be a real number", unit) from None
    return out


def check_finite(name: str, value: Any, unit: str = "") -> float:
    """Return ``value`` as float, or raise if it is not a finite real number.

    Parameters
    ----------
    name
        Qualified parameter name for the message.
    value
        The value to check.
    unit
        SI unit for the message.
    """
    out = _as_float(name, value, unit)
    if not math.isfinite(out):
        raise InvalidParameterError(name, value, "must be a finite number", unit)
    return out


def check_positive(name: str, value: Any, unit: str = "") -> float:
    """Return ``value`` as float, or raise unless it is finite and > 0.

    Parameters
    ----------
    name
        Qualified parameter name for the message.
    value
        The value to check.
    unit
        SI unit for the message.
    """
    out = _as_float(name, value, unit)
    if not (math.isfinite(out) and out > 0.0):
        raise InvalidParameterError(name, value, "must be a finite number > 0", unit)
    return out


def check_nonnegative(name: str, value: Any, unit: str = "") -> float:
    """Return ``value`` as float, or raise unless it is finite and >= 0.

    Parameters
    ----------
    name
        Qualified parameter name for the message.
    value
        The value to check.
    unit
        SI unit for the message.
    """
    out = _as_float(name, value, unit)
    if not (math.isfinite(out) and out >= 0.0):
        raise InvalidParameterError(name, value, "must be a finite number >= 0", unit)
    return out
