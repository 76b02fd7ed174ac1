"""Point sources: the points of a sweep as columns, produced a chunk at a time.

A sweep engine that asks a :class:`PointSource` for the points ``[start, stop)``
never needs the whole sample in memory: a grid, a Latin hypercube or a Sobol
sequence of a million points (:mod:`designlab.analysis.sampling`) is generated
chunk by chunk, and the same chunk comes back identical however the points are
split. Points held in memory are an :class:`ArrayPoints`; several point sets
evaluated in one pass are a :class:`ConcatPoints`.

Examples
--------
>>> import numpy as np
>>> a = ArrayPoints({"x": np.arange(3.0)})
>>> both = ConcatPoints([a, ArrayPoints({"x": np.array([10.0, 11.0])})])
>>> len(both), both.take(2, 4)["x"].tolist()
(5, [2.0, 10.0])
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

__all__ = ["ArrayPoints", "ConcatPoints", "PointSource"]

Columns = dict[str, NDArray[np.float64]]


class PointSource(ABC):
    """Points as named float columns, any range of them on demand.

    Subclasses define :attr:`names`, ``__len__`` and :meth:`_take`;
    :meth:`take` checks the range.
    """

    names: tuple[str, ...]

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
