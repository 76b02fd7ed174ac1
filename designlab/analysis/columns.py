"""Points and results as columns: conversion, distinct rows, and assembly chunk by chunk.

The sweep engine (:mod:`designlab.analysis.engine`) moves points and results as
*columns*, a mapping from a name to a 1-D array with one entry per point.
This module holds what it needs of them:

* :func:`as_columns` - points from columns, a list of dicts or a DataFrame;
* :func:`distinct_rows` - which points are identical (evaluated once);
* :class:`Assembler` - result columns of many points filled chunk by chunk.

Examples
--------
>>> import numpy as np
>>> first, inverse = distinct_rows({"x": np.array([1.0, 2.0, 1.0])})
>>> first.tolist(), inverse.tolist()
([0, 1], [0, 1, 0])
>>> table = Assembler(3)
>>> table.put(0, {"y": np.array([1.0, 2.0])})
>>> table.put(2, {"y": np.array([3.0]), "note": np.array(["x"], dtype=object)})
>>> cols = table.columns()
>>> cols["y"].tolist(), cols["note"].tolist()
([1.0, 2.0, 3.0], [None, None, 'x'])
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

__all__ = ["Assembler", "Columns", "as_columns", "column_length", "distinct_rows", "take_rows"]

#: Point or result columns: key -> 1-D array (all of one length).
Columns = dict[str, np.ndarray]


def as_columns(points: Columns | Sequence[Mapping[str, float]] | pd.DataFrame) -> Columns:
    """Points as float columns, from columns, a list of dicts or a DataFrame.

    Parameters
    ----------
    points
        Columns (name -> array), a list of point dicts or a DataFrame.

    Examples
    --------
    >>> as_columns([{"a": 1, "b": 2.5}, {"a": 3, "b": 4}])
    {'a': array([1., 3.]), 'b': array([2.5, 4. ])}
    """
    if isinstance(points, pd.DataFrame):
        return {str(c): points[c].to_numpy(dtype=float) for c in points.columns}
    if isinstance(points, Mapping):
        cols = {str(k): np.atleast_1d(np.asarray(v, dtype=float)) for k, v in points.items()}
    else:
        rows = list(points)
        names = list(dict.fromkeys(k for r in rows for k in r))
        cols = {k: np.array([float(r[k]) for r in rows], dtype=float) for k in names}
    lengths = {len(v) for v in cols.values()}
    if len(lengths) > 1:
        raise ValueError(
            f"point columns differ in length: { {k: len(v) for k, v in cols.items()} }"
        )
    return cols


def column_length(cols: Mapping[str, Any]) -> int:
    """The number of rows of columns (0 without columns).

    Parameters
    ----------
    cols
        Columns of one length.
    """
    return len(next(iter(cols.values()))) if cols else 0


def take_rows(cols: Columns, idx: np.ndarray | slice) -> Columns:
    """The rows ``idx`` of every column (views for a slice).

    Parameters
    ----------
    cols
        The columns.
    idx
        A slice or an index array.
    """
    return {k: v[idx] for k, v in cols.items()}


def distinct_rows(cols: Columns) -> tuple[np.ndarray | None, np.ndarray | None]:
    """``(first, inverse)``: rows of the distinct points, and each point's distinct index.

    ``(None, None)`` when every point is distinct (the common case of a random
    sample), without building any per-point index. Rows are hashed column by
    column (pandas, 64 bit) and sorted by hash, which needs a few bytes per
    point and no hash table; when rows share a hash the grouping is verified
    value by value, so a hash collision can never merge two different points.
    Distinct points are numbered in order of first appearance (as ``pd.factorize``).

    Parameters
    ----------
    cols
        Point columns (NaN equals NaN).
    """
    n = column_length(cols)
    if n == 0:
        return None, None
    hashes = np.zeros(n, dtype=np.uint64)
    for name in sorted(cols):
        column = np.ascontiguousarray(cols[name], dtype=float)
        with np.errstate(over="ignore"):
            hashes *= np.uint64(0x100000001B3)
            hashes ^= pd.util.hash_array(column)
        del column
    order = np.argsort(hashes, kind="stable")
    ordered = hashes[order]
    del hashes
    same = ordered[1:] == ordered[:-1]
    if not same.any():  # no two rows hash alike: all distinct, nothing to verify
        return None, None
    first, inverse = _groups(order, np.flatnonzero(np.r_[True, ~same]))
    for name in cols:
        values = np.asarray(cols[name], dtype=float)
        rep = values[first[inverse]]
        if not bool(((rep == values) | (np.isnan(rep) & np.isnan(values))).all()):
            # a 64-bit hash collision merged different points: group by value instead
            frame = pd.DataFrame({k: cols[k] for k in sorted(cols)})
            codes = frame.groupby(list(frame.columns), sort=False, dropna=False).ngroup()
            codes = codes.to_numpy()
            first = np.flatnonzero(~pd.Series(codes).duplicated().to_numpy())
            return first, np.asarray(codes, dtype=np.intp)
    return first, inverse


def _groups(order: np.ndarray, starts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distinct rows and codes, numbered in order of first appearance (as ``pd.factorize``).

    ``order`` sorts the rows by hash (stably); ``starts`` are the positions in
    that order where a new hash begins.
    """
    n = len(order)
    sizes = np.diff(np.r_[starts, n])
    group_of_sorted = np.repeat(np.arange(len(starts)), sizes)
    earliest = order[starts]  # stable sort: the first row of each group
    rank = np.empty(len(starts), dtype=np.intp)
    rank[np.argsort(earliest, kind="stable")] = np.arange(len(starts))
    inverse = np.empty(n, dtype=np.intp)
    inverse[order] = rank[group_of_sorted]
    first = np.sort(earliest)
    return first, inverse


class Assembler:
    """Result columns of ``n`` distinct points, filled chunk by chunk in place.

    Numbers become float (NaN where a chunk lacks the column); booleans stay
    boolean unless some chunk lacks them; anything else is object (``None``
    where missing). The chunks are not held: memory is the result table
    itself plus one chunk.

    Parameters
    ----------
    n
        The number of rows.
    """

    def __init__(self, n: int) -> None:
        self.n = n
        self.cols: dict[str, np.ndarray] = {}
        self.present: dict[str, np.ndarray] = {}

    def _allocate(self, name: str, kind: str) -> None:
        if kind in "fiu":
            self.cols[name] = np.full(self.n, np.nan)
        elif kind == "b":
            self.cols[name] = np.zeros(self.n, dtype=bool)
        else:
            self.cols[name] = np.full(self.n, None, dtype=object)
        self.present[name] = np.zeros(self.n, dtype=bool)

    def _widen(self, name: str) -> None:
        """A column seen with two incompatible types becomes object (``None`` where absent)."""
        old, mask = self.cols[name], self.present[name]
        new = np.full(self.n, None, dtype=object)
        new[mask] = old[mask].astype(object)
        self.cols[name] = new

    def put(self, start: int, part: Columns) -> None:
        """Write a chunk's columns at rows ``start:start + len(chunk)``."""
        self.put_rows(slice(start, start + column_length(part)), part)

    def put_rows(self, rows: slice | np.ndarray, part: Columns) -> None:
        """Write columns at ``rows`` (a slice or an index array)."""
        for name, values in part.items():
            a = np.asarray(values)
            if name not in self.cols:
                self._allocate(name, a.dtype.kind)
            have = self.cols[name].dtype.kind
            if have == "f" and a.dtype.kind not in "fiu":
                self._widen(name)
            elif have == "b" and a.dtype.kind != "b":
                self._widen(name)
            target = self.cols[name]
            target[rows] = a.astype(float) if target.dtype.kind == "f" else a
            self.present[name][rows] = True

    def columns(self) -> Columns:
        """The assembled columns (booleans missing somewhere become object with ``None``)."""
        for name, col in list(self.cols.items()):
            if col.dtype.kind == "b" and not self.present[name].all():
                self._widen(name)
        out, self.cols, self.present = self.cols, {}, {}
        return out

    def frame(self, inverse: np.ndarray | None) -> pd.DataFrame:
        """The table, one row per point (``inverse`` maps points to distinct rows)."""
        if self.n == 0:
            return pd.DataFrame()
        cols = self.columns()
        out = cols if inverse is None else {k: v[inverse] for k, v in cols.items()}
        return pd.DataFrame(out, copy=False)
