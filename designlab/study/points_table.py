"""The points of a sweep with their results: in memory, or read from the result store.

A sweep of a few thousand points keeps its table in memory
(:class:`FrameTable`). A large sweep run with a result store leaves its results
there (:class:`StoredTable`) and reads them back a block at a time, so that
running it and writing its report take memory for a block, a chunk and an
evenly spread subset of rows, not for the whole table. Both answer the same
questions:

``len(table)``, ``table.columns``
    Rows and column names.
``table.blocks(rows)``
    The table as consecutive data frames of at most ``rows`` rows.
``table.frame()``
    The whole table as one data frame (memory grows with the points).
``table.scan()``
    One pass over the table: statuses, the first failures, flag counts,
    per-column count / mean / std / min / max (exact) and an evenly spread
    subset of rows (:class:`TableScan`).

Examples
--------
>>> import pandas as pd
>>> t = FrameTable(pd.DataFrame({"x": [1.0, 2.0, 4.0], "status": ["ok", "ok", "error"],
...                              "error": [None, None, "ValueError: x"]}))
>>> scan = t.scan()
>>> sorted(scan.status_counts.items()), scan.failed
([('error', 1), ('ok', 2)], [(2, 'ValueError: x')])
>>> round(scan.moments["x"]["mean"], 4), scan.moments["x"]["max"]
(2.3333, 4.0)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from designlab.analysis.engine import STATUS_ERROR, StoredRows
from designlab.analysis.points import PointSource

__all__ = ["SUBSET_ROWS", "FrameTable", "PointsTable", "StoredTable", "TableScan"]

#: Rows of the evenly spread subset kept by a scan (figures, quantiles of large tables).
SUBSET_ROWS = 200_000
#: Rows per block when a table is read back from the store.
BLOCK_ROWS = 65_536
#: Failed points listed by name in warnings.
FAILED_SHOWN = 10


@dataclass
class TableScan:
    """What one pass over a points table learns.

    Attributes
    ----------
    rows
        Rows scanned.
    status_counts
        Rows per ``status``.
    failed
        ``(row, error)`` of the first failed rows (at most ``FAILED_SHOWN``).
    flags
        Boolean columns -> rows where true (e.g. ``bottoming``).
    notes
        ``warnings`` column: ``(rows with a warning, the first one)``.
    moments
        Numeric column -> ``count``, ``mean``, ``std`` (sample), ``min``, ``max``
        over every row (NaN ignored), exact.
    subset
        Every ``step``-th row (at most :data:`SUBSET_ROWS` rows).
    step
        Row step of the subset (1: the subset is the whole table).
    """

    rows: int = 0
    status_counts: dict[str, int] = field(default_factory=dict)
    failed: list[tuple[int, str]] = field(default_factory=list)
    flags: dict[str, int] = field(default_factory=dict)
    notes: tuple[int, str | None] = (0, None)
    moments: dict[str, dict[str, float]] = field(default_factory=dict)
    subset: pd.DataFrame = field(default_factory=pd.DataFrame)
    step: int = 1

    def summary_frame(self, quantiles: pd.DataFrame | None = None) -> pd.DataFrame:
        """Per numeric column: count, mean, std, min, quantiles, max; then the status counts.

        Quantiles (1, 5, 25, 50, 75, 95, 99 %) come from ``quantiles`` when
        given (the whole column), else from the subset; ``quantiles_of`` says
        from how many rows.

        Parameters
        ----------
        quantiles
            The whole table, when it is in memory (exact quantiles).
        """
        levels = [0.01, 0.05, 0.25, 0.5, 0.75, 0.95, 0.99]
        source = quantiles if quantiles is not None else self.subset
        rows = []
        for name, m in self.moments.items():
            values = pd.to_numeric(source[name], errors="coerce") if name in source else None
            q = (
                values.quantile(levels).to_numpy()
                if values is not None and values.notna().any()
                else np.full(len(levels), np.nan)
            )
            rows.append(
                {"column": name, "count": m["count"], "mean": m["mean"], "std": m["std"],
                 "min": m["min"], **{f"{round(p * 100)}%": v for p, v in zip(levels, q,
                 strict=True)}, "max": m["max"],
                 "quantiles_of": float(values.notna().sum()) if values is not None else 0.0}
            )  # fmt: skip
        table = pd.DataFrame(rows)
        extra = pd.DataFrame(
            {
                "column": [f"status={k}" for k in self.status_counts],
                "count": [float(v) for v in self.status_counts.values()],
            }
        )
        return pd.concat([table, extra], ignore_index=True)


def _is_flag(col: pd.Series) -> bool:
    """A boolean column (possibly with missing values, then of object dtype)."""
    if col.dtype == bool:
        return True
    if col.dtype != object:
        return False
    values = col.dropna()
    return bool(len(values)) and bool(values.map(lambda v: isinstance(v, (bool, np.bool_))).all())


class _Moments:
    """Count, mean, M2 (Chan et al.'s parallel update), min and max of a column, by blocks."""

    def __init__(self) -> None:
        self.n, self.mean, self.m2 = 0, 0.0, 0.0
        self.lo, self.hi = math.inf, -math.inf

    def add(self, values: np.ndarray) -> None:
        x = values[~np.isnan(values)]
        if not len(x):
            return
        nb, mb = len(x), float(x.mean())
        with np.errstate(invalid="ignore"):  # inf - inf: the spread of an infinite column is nan
            m2b = float(((x - mb) ** 2).sum())
        n = self.n + nb
        delta = mb - self.mean
        self.mean += delta * nb / n
        self.m2 += m2b + delta * delta * self.n * nb / n
        self.n = n
        self.lo, self.hi = min(self.lo, float(x.min())), max(self.hi, float(x.max()))

    def result(self) -> dict[str, float]:
        nan = math.nan
        return {
            "count": float(self.n),
            "mean": self.mean if self.n else nan,
            "std": math.sqrt(self.m2 / (self.n - 1)) if self.n > 1 else nan,
            "min": self.lo if self.n else nan,
            "max": self.hi if self.n else nan,
        }


class PointsTable:
    """Base class: a table of sweep points read in blocks (see the module docstring)."""

    columns: list[str]

    def __len__(self) -> int:  # pragma: no cover - abstract
        raise NotImplementedError

    def blocks(self, rows: int | None = None) -> Iterator[pd.DataFrame]:  # pragma: no cover
        """Consecutive data frames of at most ``rows`` rows (index = row number).

        Parameters
        ----------
        rows
            Rows per block.
        """
        raise NotImplementedError

    def frame(self) -> pd.DataFrame:  # pragma: no cover - abstract
        """The whole table as one data frame."""
        raise NotImplementedError

    def is_flag(self, column: str) -> bool:  # pragma: no cover - abstract
        """Whether ``column`` holds booleans (possibly with missing values).

        Parameters
        ----------
        column
            A column name.
        """
        raise NotImplementedError

    def scan(self, visit: Callable[[pd.DataFrame], None] | None = None) -> TableScan:
        """One pass over the table (cached): statuses, failures, flags, moments, subset.

        Parameters
        ----------
        visit
            Also called with every block of the pass (e.g. to write it out), so
            that one read of the table serves both. With a cached scan, the
            blocks are read again for ``visit`` alone.
        """
        cached = getattr(self, "_scan", None)
        if cached is not None:
            if visit is not None:
                for block in self.blocks():
                    visit(block)
            return cached
        n = len(self)
        step = max(1, math.ceil(n / SUBSET_ROWS)) if n else 1
        scan = TableScan(rows=n, step=step)
        moments: dict[str, _Moments] = {}
        subset: list[pd.DataFrame] = []
        notes, first_note = 0, None
        flags = {c for c in self.columns if c not in ("status", "error") and self.is_flag(c)}
        for block in self.blocks():
            if visit is not None:
                visit(block)
            start = int(block.index[0]) if len(block) else 0
            status = block["status"].astype(object) if "status" in block else None
            if status is not None:
                for k, v in status.value_counts().items():
                    scan.status_counts[str(k)] = scan.status_counts.get(str(k), 0) + int(v)
                if len(scan.failed) < FAILED_SHOWN:
                    bad = block[(status == STATUS_ERROR).to_numpy()]
                    for i, err in bad["error"].head(FAILED_SHOWN - len(scan.failed)).items():
                        scan.failed.append((int(i), str(err)))
            for name in block.columns:
                col = block[name]
                if name in ("status", "error"):
                    continue
                if name == "warnings":
                    present = col.notna()
                    notes += int(present.sum())
                    if first_note is None and present.any():
                        first_note = str(col[present].iloc[0])
                elif name in flags:
                    hits = int(col.fillna(False).astype(bool).sum())
                    scan.flags[name] = scan.flags.get(name, 0) + hits
                elif pd.api.types.is_numeric_dtype(col.dtype):
                    moments.setdefault(name, _Moments()).add(col.to_numpy(dtype=float))
            first = (-start) % step
            # a copy: a strided slice would be a view keeping the whole block alive
            subset.append(block.iloc[first::step].copy())
        scan.notes = (notes, first_note)
        scan.moments = {k: m.result() for k, m in moments.items()}
        scan.subset = pd.concat(subset) if subset else pd.DataFrame(columns=self.columns)
        self._scan = scan
        return scan


class FrameTable(PointsTable):
    """A points table held in memory.

    Parameters
    ----------
    frame
        The table.
    """

    def __init__(self, frame: pd.DataFrame) -> None:
        self._frame = frame.reset_index(drop=True)
        self.columns = list(frame.columns)

    def __len__(self) -> int:
        return len(self._frame)

    def blocks(self, rows: int | None = None) -> Iterator[pd.DataFrame]:
        """Consecutive slices of at most ``rows`` rows.

        Parameters
        ----------
        rows
            Rows per block (default :data:`BLOCK_ROWS`).
        """
        rows = rows or BLOCK_ROWS
        for s in range(0, len(self._frame), rows):
            yield self._frame.iloc[s : s + rows]

    def frame(self) -> pd.DataFrame:
        """The table itself."""
        return self._frame

    def is_flag(self, column: str) -> bool:
        """Whether ``column`` holds booleans (possibly with missing values).

        Parameters
        ----------
        column
            A column name.
        """
        return column in self._frame and _is_flag(self._frame[column])


class StoredTable(PointsTable):
    """A points table whose results stay in the result store.

    Parameters
    ----------
    points
        The sweep's points (drawn a block at a time), in row order.
    rows
        The stored results of the run that holds these points.
    offset
        Position of the first sweep point in that run.
    build
        ``build(points, results) -> frame``: the table of a block from its
        point columns and its results.
    """

    def __init__(
        self,
        points: PointSource,
        rows: StoredRows,
        offset: int,
        build: Callable[[dict[str, np.ndarray], pd.DataFrame], pd.DataFrame],
    ) -> None:
        self.points, self.rows, self.offset, self.build = points, rows, offset, build
        self.n = len(points)
        head = self._block(0, min(1, self.n)) if self.n else pd.DataFrame()
        self.columns = list(head.columns)

    def __len__(self) -> int:
        return self.n

    def _block(self, start: int, stop: int) -> pd.DataFrame:
        results = self.rows.read(slice(self.offset + start, self.offset + stop))
        frame = self.build(self.points.take(start, stop), results)
        frame.index = pd.RangeIndex(start, stop)
        return frame

    def blocks(self, rows: int | None = None) -> Iterator[pd.DataFrame]:
        """Consecutive blocks of at most ``rows`` rows, read from the store.

        Parameters
        ----------
        rows
            Rows per block (default :data:`BLOCK_ROWS`).
        """
        rows = rows or BLOCK_ROWS
        for s in range(0, self.n, rows):
            yield self._block(s, min(s + rows, self.n))

    def is_flag(self, column: str) -> bool:
        """Whether ``column`` holds booleans (a result column the store types as boolean).

        Parameters
        ----------
        column
            A column name.
        """
        return self.rows.kinds.get(column) == "b"

    def frame(self) -> pd.DataFrame:
        """The whole table (read from the store; memory grows with the points)."""
        if not self.n:
            return pd.DataFrame()
        return pd.concat(list(self.blocks()), ignore_index=True)
