"""Point sources: the points of a sweep as columns, produced a chunk at a time.

A sweep engine that asks a :class:`PointSource` for the points ``[start, stop)``
never needs the whole sample in memory: a grid, a Latin hypercube or a Sobol
sequence of a million points (:mod:`designlab.analysis.sampling`) is generated
chunk by chunk, and the same chunk comes back identical however the points are
split. Points held in memory are an :class:`ArrayPoints`; several point sets
evaluated in one pass are a :class:`ConcatPoints`.

A source that knows what determines its points (a sampler's kind, bounds, sample
count, seed and code) says so in
:meth:`~designlab.analysis.points.PointSource.identity`: the sweep engine then keys
its stored chunks by index (chunk i covers points ``[i c, (i + 1) c)``), so that a
resumed run finds its finished chunks without drawing their points.

Examples
--------
>>> import numpy as np
>>> a = ArrayPoints({"x": np.arange(3.0)})
>>> both = ConcatPoints([a, ArrayPoints({"x": np.array([10.0, 11.0])})])
>>> len(both), both.take(2, 4)["x"].tolist()
(5, [2.0, 10.0])
>>> both.identity() == ConcatPoints([a, ArrayPoints({"x": [10.0, 11.0]})]).identity()
True
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import json
import sys
from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["ArrayPoints", "ConcatPoints", "PointSource", "source_identity"]

Columns = dict[str, NDArray[np.float64]]


class PointSource(ABC):
    """Points as named float columns, any range of them on demand.

    Subclasses define :attr:`names`, ``__len__`` and :meth:`_take`;
    :meth:`take` checks the range.
    """

    names: tuple[str, ...]
    #: Modules, besides those defining the class and its bases, whose code fixes the
    #: points (part of :meth:`~designlab.analysis.points.PointSource.identity`).
    code_modules: tuple[str, ...] = ()

    @abstractmethod
    def __len__(self) -> int:
        """The number of points."""

    @abstractmethod
    def _take(self, start: int, stop: int) -> Columns:
        """The columns of points ``start .. stop - 1`` (a valid, non-empty range)."""

    def take(self, start: int, stop: int) -> Columns:
        """The columns of points ``start .. stop - 1`` (float arrays, possibly read-only views).

        Parameters
        ----------
        start
            First point.
        stop
            One past the last point.
        """
        n = len(self)
        if not 0 <= start <= stop <= n:
            raise IndexError(f"points [{start}, {stop}) are not within [0, {n}]")
        if start == stop:
            return {k: np.empty(0) for k in self.names}
        return self._take(start, stop)

    def columns(self) -> Columns:
        """Every point at once (memory grows with the number of points)."""
        return self.take(0, len(self))

    def identity(self) -> str | None:
        """A hash of everything that determines the points, or ``None`` when unknown.

        Two sources with the same identity give the same points, bit for bit,
        for every range. The default, ``None``, says nothing is known: the sweep
        engine then keys stored chunks by a hash of their points.
        """
        return None


@cache
def _module_hash(name: str) -> str:
    """A hash of a module's source file (cached per process)."""
    module = sys.modules.get(name)
    if module is not None:
        path = getattr(module, "__file__", None)
    else:  # found, not imported (a compiled sampler's module would start numba)
        spec = importlib.util.find_spec(name)
        path = spec.origin if spec is not None and spec.has_location else None
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()[:16] if path else "no file"


def source_identity(source: PointSource, fields: Mapping[str, Any]) -> str:
    """The identity of ``source`` from the ``fields`` that determine its points.

    The hash covers the class, the source files of the modules that define it and
    its bases and of those it names in
    :attr:`~designlab.analysis.points.PointSource.code_modules` (an edited sampler
    may draw other points), numpy's version, then ``fields`` (JSON; arrays by their
    bytes).

    Parameters
    ----------
    source
        The point source.
    fields
        Its parameters: numbers, strings, lists, dicts, or float arrays.
    """
    cls = type(source)
    h = hashlib.sha256()
    modules = {c.__module__ for c in cls.__mro__ if c.__module__ not in ("builtins", "abc")}
    modules |= {m for c in cls.__mro__ for m in getattr(c, "code_modules", ())}
    head = {"class": f"{cls.__module__}.{cls.__qualname__}", "numpy": np.__version__,
            "code": {m: _module_hash(m) for m in sorted(modules)}}  # fmt: skip
    arrays: list[NDArray] = []

    def plain(v: Any) -> Any:
        if isinstance(v, np.ndarray):
            arrays.append(np.ascontiguousarray(v, dtype="<f8"))
            return ["array", v.shape]
        return v

    body = {k: plain(fields[k]) for k in sorted(fields)}  # arrays hashed in the order of names
    text = json.dumps({**head, **body}, sort_keys=True,
                      separators=(",", ":"), allow_nan=True, default=float)  # fmt: skip
    h.update(text.encode())
    for a in arrays:
        h.update(a.tobytes())
    return h.hexdigest()


class ArrayPoints(PointSource):
    """Points held in memory as equal-length columns.

    Parameters
    ----------
    columns
        Name -> 1-D array of values.
    """

    def __init__(self, columns: Mapping[str, NDArray | Sequence[float]]) -> None:
        self._cols = {k: np.asarray(v, dtype=float) for k, v in columns.items()}
        lengths = {k: v.shape for k, v in self._cols.items()}
        if len({s for s in lengths.values()}) > 1 or any(len(s) != 1 for s in lengths.values()):
            raise ValueError(f"point columns must be 1-D and of one length, got shapes {lengths}")
        self.names = tuple(self._cols)
        self._n = len(next(iter(self._cols.values()))) if self._cols else 0

    def __len__(self) -> int:
        return self._n

    def _take(self, start: int, stop: int) -> Columns:
        return {k: v[start:stop] for k, v in self._cols.items()}

    def columns(self) -> Columns:
        """The columns themselves (no copy)."""
        return dict(self._cols)

    def identity(self) -> str:
        """A hash of the names and values of the columns (in order)."""
        return source_identity(self, {f"column {k}": v for k, v in self._cols.items()})


class ConcatPoints(PointSource):
    """Several point sets with the same columns, one after the other.

    Parameters
    ----------
    parts
        The point sets, in order.
    """

    def __init__(self, parts: Sequence[PointSource]) -> None:
        self.parts = [p for p in parts if len(p)]
        names = {tuple(sorted(p.names)) for p in self.parts}
        if len(names) > 1:
            raise ValueError(f"point sets with different columns: {sorted(names)}")
        self.names = self.parts[0].names if self.parts else ()
        self.offsets = np.cumsum([0, *(len(p) for p in self.parts)])

    def __len__(self) -> int:
        return int(self.offsets[-1])

    def identity(self) -> str | None:
        """The parts' identities, in order (``None`` if a part's is unknown)."""
        parts = [p.identity() for p in self.parts]
        if any(p is None for p in parts):
            return None
        return source_identity(self, {"parts": parts})

    def _take(self, start: int, stop: int) -> Columns:
        pieces: list[Columns] = []
        for p, lo, hi in zip(self.parts, self.offsets[:-1], self.offsets[1:], strict=True):
            s, e = max(start, lo), min(stop, hi)
            if s < e:
                pieces.append(p.take(int(s - lo), int(e - lo)))
        if len(pieces) == 1:
            return pieces[0]
        return {k: _join([piece[k] for piece in pieces]) for k in self.names}


def _join(parts: list[NDArray]) -> NDArray:
    """Concatenate; a value constant over every part stays a broadcast view (no memory)."""
    first = float(parts[0][0])
    if all(p.strides == (0,) or len(p) <= 1 for p in parts) and all(
        float(p[0]) == first for p in parts
    ):
        return np.broadcast_to(np.float64(first), (sum(len(p) for p in parts),))
    return np.concatenate(parts)
