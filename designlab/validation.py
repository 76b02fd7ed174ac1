"""Input validation shared by every designlab layer.

Scalars go through :func:`designlab.errors.check_positive` and friends; this
module holds the rest: arrays, integers, choices, frozen (read-only) arrays,
named columns (mapping, DataFrame, or array with explicit names) and the
boolean guard for pydantic fields. Every failure is an
:class:`~designlab.errors.InvalidParameterError` naming the parameter, its value
and what is allowed.

Examples
--------
>>> check_int("samples", 3, minimum=0)
3
>>> check_int("samples", -3, minimum=0)
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: samples = -3 is not allowed: must be an integer >= 0
>>> check_choice("q2", "printed", ("correct", "printed"))
'printed'
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError, check_nonnegative, check_positive
from designlab.params import is_complex

__all__ = [
    "ParamsMixin",
    "check_array",
    "check_choice",
    "check_int",
    "check_q2",
    "frozen_array",
    "named_columns",
    "real_array",
    "reject_bool",
]


def reject_bool(value: Any) -> Any:
    """Refuse booleans where a number is expected (pydantic ``BeforeValidator``).

    YAML ``yes``/``true`` would otherwise be read as 1.0 by pydantic's lax mode.

    Parameters
    ----------
    value
        The value given.
    """
    if isinstance(value, (bool, np.bool_)):
        raise ValueError("must be a number, not a boolean")
    return value


def frozen_array(value: Any, dtype: Any = float) -> NDArray:
    """A read-only copy of ``value`` (for fields of frozen result dataclasses).

    Parameters
    ----------
    value
        Array-like values.
    dtype
        The dtype of the copy.
    """
    out = np.array(value, dtype=dtype, copy=True)
    out.setflags(write=False)
    return out


def check_int(name: str, value: Any, *, minimum: int | None = None, unit: str = "") -> int:
    """Return ``value`` as int, or raise unless it is an integer (not a bool) >= ``minimum``.

    Parameters
    ----------
    name
        Parameter name for the error message.
    value
        The value given.
    minimum
        Smallest allowed value, if any.
    unit
        Its unit, for the error message.
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        allowed = "must be an integer" + (f" >= {minimum}" if minimum is not None else "")
        raise InvalidParameterError(name, value, allowed, unit)
    out = int(value)
    if minimum is not None and out < minimum:
        raise InvalidParameterError(name, value, f"must be an integer >= {minimum}", unit)
    return out


def check_choice(name: str, value: Any, choices: Sequence[str]) -> str:
    """Return ``value`` if it is one of ``choices`` (strings), else raise.

    Parameters
    ----------
    name
        Parameter name for the error message.
    value
        The value given.
    choices
        The allowed strings.
    """
    if not isinstance(value, str) or value not in choices:
        raise InvalidParameterError(name, value, f"must be one of {list(choices)}")
    return value


def check_q2(q2: Any) -> str:
    """The q2 option of the impact model: ``"correct"`` or ``"printed"`` (docs/impact.md).

    Parameters
    ----------
    q2
        ``"correct"`` or ``"printed"``.
    """
    return check_choice("q2", q2, ("correct", "printed"))


_BOOLS = (bool, np.bool_)


def real_array(name: str, value: Any, unit: str = "") -> NDArray[np.float64]:
    """``value`` as a float array of finite real numbers (booleans refused).

    Parameters
    ----------
    name
        Parameter name for the error message.
    value
        Array-like values.
    unit
        Its SI unit, for the error message.
    """
    if (
        isinstance(value, (bool, np.bool_))
        or (isinstance(value, np.ndarray) and value.dtype == bool)
        or (isinstance(value, (list, tuple)) and any(isinstance(x, _BOOLS) for x in value))
    ):
        raise InvalidParameterError(name, value, "must be real numbers, not booleans", unit)
    if is_complex(value):
        raise InvalidParameterError(name, value, "must be real numbers, not complex", unit)
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameterError(name, value, "must be an array of real numbers", unit) from None
    if not np.all(np.isfinite(arr)):
        raise InvalidParameterError(name, value, "must contain only finite numbers", unit)
    return arr


def check_array(name: str, value: Any, unit: str = "", *, positive: bool = False) -> Any:
    """Validate a scalar (returned as float) or an array (returned as ndarray).

    Every element must be finite and ``> 0`` (``positive``) or ``>= 0``.

    Parameters
    ----------
    name
        Parameter name for the error message.
    value
        A number or an array.
    unit
        Its SI unit, for the error message.
    positive
        Also require every value > 0.
    """
    if np.ndim(value) == 0:
        check = check_positive if positive else check_nonnegative
        return check(name, value, unit)
    arr = real_array(name, value, unit)
    bad = (arr <= 0.0) if positive else (arr < 0.0)
    if np.any(bad):
        first = arr[bad].flat[0]
        allowed = "every element must be a finite number " + ("> 0" if positive else ">= 0")
        raise InvalidParameterError(name, float(first), allowed, unit)
    return arr


def named_columns(
    name: str,
    value: Any,
    names: Sequence[str],
    *,
    columns: Sequence[str] | None = None,
) -> NDArray[np.float64]:
    """Stack named columns into an ``(N, len(names))`` float array ordered as ``names``.

    Parameters
    ----------
    name
        Parameter name for error messages.
    value
        A mapping (dict) or :class:`pandas.DataFrame` whose keys/columns are
        exactly ``names`` (scalars and arrays broadcast together), or a 2-D
        array whose column order is given by ``columns``.
    names
        The column names wanted, in the order of the result.
    columns
        Required for an array: the names of its columns (any order). An array
        without them is refused, so a column order cannot be mistaken silently.

    Examples
    --------
    >>> named_columns("p", {"b": [1.0, 2.0], "a": 0.5}, ("a", "b"))
    array([[0.5, 1. ],
           [0.5, 2. ]])
    >>> named_columns("p", [[2.0, 1.0]], ("a", "b"), columns=("b", "a"))
    array([[1., 2.]])
    """
    names = tuple(names)
    if hasattr(value, "columns") and hasattr(value, "to_numpy"):  # a DataFrame
        value = {str(k): value[k].to_numpy() for k in value.columns}
    if isinstance(value, Mapping):
        keys = [str(k) for k in value]
        missing = [k for k in names if k not in keys]
        unknown = [k for k in keys if k not in names]
        if missing or unknown:
            raise InvalidParameterError(
                name,
                sorted(keys),
                f"needs exactly the keys {list(names)}"
                + (f"; missing {missing}" if missing else "")
                + (f"; unknown {unknown}" if unknown else ""),
            )
        cols = [real_array(f"{name}[{k!r}]", value[k]) for k in names]
        try:
            cols = np.broadcast_arrays(*cols)
        except ValueError:
            raise InvalidParameterError(
                name, {k: np.shape(c) for k, c in zip(names, cols, strict=True)},
                "columns must have broadcastable shapes",
            ) from None  # fmt: skip
        return np.stack([np.ravel(c) for c in cols], axis=1)
    if columns is None:
        raise InvalidParameterError(
            name,
            f"array of shape {np.shape(value)}",
            f"an array needs explicit column names (columns=...) for {list(names)}; "
            "or pass a mapping or a DataFrame",
        )
    columns = tuple(str(c) for c in columns)
    if sorted(columns) != sorted(names):
        raise InvalidParameterError(
            "columns", list(columns), f"must name each of {list(names)} exactly once"
        )
    arr = real_array(name, value)
    arr = np.atleast_2d(arr)
    if arr.ndim != 2 or arr.shape[1] != len(names):
        raise InvalidParameterError(
            name, f"array of shape {arr.shape}", f"must have shape (N, {len(names)})"
        )
    order = [columns.index(k) for k in names]
    return arr[:, order]


class ParamsMixin:
    """``as_dict`` and ``replace`` for the frozen parameter dataclasses of every domain.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class Spring(ParamsMixin):
    ...     stiffness: float = 1.0
    >>> Spring().replace(stiffness=2.0).as_dict()
    {'stiffness': 2.0}
    """

    def as_dict(self) -> dict[str, Any]:
        """Return the fields as a plain ``dict`` (picklable, YAML-friendly)."""
        from dataclasses import asdict

        return asdict(self)  # type: ignore[call-overload]

    def replace(self, **changes: Any) -> Any:
        """Return a copy with some fields changed (validated again).

        Parameters
        ----------
        **changes
            Field name -> new value.
        """
        from dataclasses import replace

        return replace(self, **changes)  # type: ignore[type-var]
