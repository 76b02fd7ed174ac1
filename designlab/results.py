"""The result contract shared by every solver in designlab.

Every public result object (impact, navigation, following, studies) has

* ``status`` -- a short string; ``"ok"`` when the solver did what was asked,
  otherwise a word saying what happened (``"empty"``, ``"infeasible"``,
  ``"not_converged"``, ``"failed"``, ...);
* ``warnings`` -- a tuple of human-readable strings (model used outside its
  valid range, solver fallbacks, ...), empty when there is nothing to say;
* ``to_frame()`` -- the numbers as a :class:`pandas.DataFrame` with unit-carrying
  column names;
* ``summary()`` -- a few lines of text for a terminal or a log.

This is the manner of python-control's ``TimeResponseData`` and scipy's
``OptimizeResult``. Results are frozen dataclasses that inherit
:class:`Result`; the mixin declares no fields, so each result keeps its own
field order.

Examples
--------
>>> from dataclasses import dataclass
>>> import pandas as pd
>>> @dataclass(frozen=True)
... class Demo(Result):
...     value: float
...     status: str = "ok"
...     warnings: tuple[str, ...] = ()
...     def to_frame(self) -> pd.DataFrame:
...         return pd.DataFrame({"value_m": [self.value]})
>>> d = Demo(1.5)
>>> d.ok, d.summary().splitlines()[0]
(True, 'Demo: status ok, no warnings')
>>> check_result(d)
"""

from __future__ import annotations

import dataclasses
import numbers
from enum import Enum
from typing import Any

import numpy as np
import pandas as pd

__all__ = ["OK", "Result", "Status", "check_result"]

#: The status of a result whose solver did what was asked.
OK = "ok"


class Status(str, Enum):
    """Base of the status enums, one per result family (documented with its members).

    A member is a ``str`` equal to its value, so ``result.status == "ok"`` holds,
    and it prints, shows (``repr``), formats and writes to CSV as its value. Convert with ``str()``
    before writing YAML with a safe dumper.

    Examples
    --------
    >>> class DemoStatus(Status):
    ...     "Status of a demo solver."
    ...     OK = "ok"
    ...     NOT_CONVERGED = "not_converged"
    >>> DemoStatus.OK == "ok", f"{DemoStatus.NOT_CONVERGED}", str(DemoStatus("ok"))
    (True, 'not_converged', 'ok')
    """

    def __str__(self) -> str:
        return str(self.value)

    def __repr__(self) -> str:
        return repr(self.value)

    def __format__(self, spec: str) -> str:
        return format(str(self.value), spec)


class Result:
    """Mixin of every designlab result: ``status``, ``warnings``, ``to_frame``, ``summary``.

    Subclasses are frozen dataclasses declaring ``status: str`` and
    ``warnings: tuple[str, ...]`` (fields or properties) and implementing
    :meth:`to_frame`.
    """

    status: str
    warnings: tuple[str, ...]

    @property
    def ok(self) -> bool:
        """True when ``status`` is ``"ok"``."""
        return self.status == OK

    def __repr__(self) -> str:
        """One line: the class, status, number of warnings, each field in short.

        Used by a result declared ``@dataclass(repr=False)`` (a dataclass's own repr prints
        every array in full): numbers to 6 digits, arrays and tables by their shape, other
        objects by their type unless their repr is short.
        """
        parts = [f"status={str(self.status)!r}"]
        if self.warnings:
            parts.append(f"warnings=<{len(self.warnings)}>")
        fields = dataclasses.fields(self) if dataclasses.is_dataclass(self) else ()  # type: ignore[arg-type]
        for f in fields:
            if f.repr and f.name not in ("status", "warnings"):
                parts.append(f"{f.name}={_short(getattr(self, f.name))}")
        return f"{type(self).__name__}({', '.join(parts)})"

    def to_frame(self) -> pd.DataFrame:  # pragma: no cover - every subclass overrides it
        """The result's numbers as a DataFrame (column names carry units)."""
        raise NotImplementedError

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Draw the result on ``ax`` (a new figure's axes if ``None``); return the axes.

        The main results draw themselves (:mod:`designlab.plots` lists them and what each
        draws); another raises :class:`NotImplementedError`.

        Parameters
        ----------
        ax
            A :class:`matplotlib.axes.Axes`.
        **kwargs
            Options of the drawing and line properties (:func:`designlab.plots.plot`).
        """
        from designlab.plots import plot

        return plot(self, ax=ax, **kwargs)

    def summary(self, max_rows: int = 10) -> str:
        """A short text: the status, the warnings and the first rows of :meth:`to_frame`.

        Parameters
        ----------
        max_rows
            Rows of the frame shown (the rest are counted).
        """
        n_warn = len(self.warnings)
        head = f"{type(self).__name__}: status {self.status}, " + (
            "no warnings" if n_warn == 0 else f"{n_warn} warning{'s' if n_warn > 1 else ''}"
        )
        lines = [head]
        lines.extend(f"  warning: {w}" for w in self.warnings[:5])
        if n_warn > 5:
            lines.append(f"  ... and {n_warn - 5} more warnings")
        frame = self.to_frame()
        if len(frame):
            with pd.option_context("display.width", 120, "display.max_columns", 12):
                lines.append(frame.head(max_rows).to_string())
            if len(frame) > max_rows:
                lines.append(f"... {len(frame) - max_rows} more rows")
        return "\n".join(lines)


def _short(value: Any) -> str:
    """``value`` for :meth:`Result.__repr__`: at most about 60 characters."""
    if isinstance(value, bool | None | Enum):
        return repr(value.value if isinstance(value, Enum) else value)
    if isinstance(value, numbers.Real):
        return f"{float(value):.6g}"
    if isinstance(value, np.ndarray):
        return f"<array {'x'.join(map(str, value.shape)) or 'scalar'}>"
    if isinstance(value, pd.DataFrame | pd.Series):
        return f"<{type(value).__name__} {len(value)} rows>"
    if isinstance(value, tuple | list | dict) and len(value) > 3:
        return f"<{type(value).__name__} of {len(value)}>"
    text = repr(value)
    return text if len(text) <= 60 and "\n" not in text else f"<{type(value).__name__}>"


def check_result(obj: Any) -> None:
    """Raise ``AssertionError`` unless ``obj`` honours the result contract.

    Used by the tests of every domain: ``status`` is a non-empty string,
    ``warnings`` a tuple of strings, ``to_frame()`` a DataFrame and
    ``summary()`` a string.

    Parameters
    ----------
    obj
        The result to check.
    """
    name = type(obj).__name__
    assert isinstance(obj, Result), f"{name} does not inherit designlab.results.Result"
    assert isinstance(obj.status, str) and obj.status, f"bad status {obj.status!r}"
    assert isinstance(obj.warnings, tuple), f"warnings must be a tuple, got {type(obj.warnings)}"
    assert all(isinstance(w, str) for w in obj.warnings), "every warning must be a string"
    assert isinstance(obj.to_frame(), pd.DataFrame), "to_frame() must return a DataFrame"
    assert isinstance(obj.summary(), str), "summary() must return a string"
