"""The sweep engine: evaluate many design points in vectorised chunks, through an executor
and a result store.

Points are *columns*: a mapping from point key (``"M_r"``, ``"K_c"``, ...) to a
1-D float array, one entry per point. An *evaluator* is a plain module-level
function of the domain that owns the physics,

``evaluator(points: dict[str, ndarray], options: dict) -> dict[str, ndarray]``

which computes a whole chunk at once and returns result columns of the same
length (numbers, booleans or strings; a ``status`` column says ``"ok"`` or what
happened). The engine hands evaluators to the workers *by reference* (pickled
by qualified name), so nothing is registered through import side effects and
the serial, process and Dask executors run exactly the same code.

The engine

* merges identical points (they are evaluated once; :attr:`SweepRun.duplicates`
  says how many were merged),
* cuts the distinct points into chunks of a fixed size (the evaluator's
  ``chunk_size`` attribute, default :data:`DEFAULT_CHUNK_SIZE`), so that the
  chunks, and their keys, do not depend on the executor or the worker count,
* keys each chunk by a hash of its points, the evaluator's qualified name, its
  options and the *source* of the package that holds the evaluator
  (:func:`~designlab.analysis.keys.code_version`): editing navigation code
  invalidates navigation points and nothing else; points streamed from a source
  that states its identity (a seeded sampler: kind, bounds, count, seed, code) are
  keyed by chunk index instead (:func:`~designlab.analysis.keys.indexed_chunk_keys`),
  and the store keeps a summary of each chunk, so a resumed run neither draws the
  points of its finished chunks nor unpacks them,
* reads finished chunks from the store (``resume``), and writes each chunk to
  the store as soon as it comes back (the client is the only writer); a
  damaged stored chunk is recomputed on ``resume`` and named, never recomputed,
  when only the store may be read (``cache_only``),
* records a point that fails on its own: when a chunk raises, it is split in
  halves until the failing points are isolated; they get ``status: error`` and
  the exception in ``error``, the rest of the chunk is kept.

The store is :class:`designlab.analysis.store.ChunkStore`; chunk keys come from
:mod:`designlab.analysis.keys`, the column helpers from
:mod:`designlab.analysis.columns`.

Examples
--------
>>> import numpy as np
>>> def square(points, options):
...     x = points["x"]
...     if np.any(x < 0):
...         raise ValueError("x must be >= 0")
...     return {"y": x**2 + options["c"], "status": np.full(len(x), "ok")}
>>> run = run_points({"x": np.array([1.0, -1.0, 2.0, 1.0])}, square, {"c": 0.5})
>>> run.frame[["y", "status"]].to_dict("list")
{'y': [1.5, nan, 4.5, 1.5], 'status': ['ok', 'error', 'ok', 'ok']}
>>> run.frame["error"][1]
'ValueError: x must be >= 0'
>>> run.computed, run.duplicates
(3, 1)
"""

from __future__ import annotations

import hashlib
import logging
import sys
from collections import Counter
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
import pandas as pd

from designlab.analysis.columns import (
    Assembler,
    Columns,
    as_columns,
    column_length,
    distinct_rows,
    take_rows,
)
from designlab.analysis.executors import SerialExecutor
from designlab.analysis.keys import chunk_key, code_version, evaluator_id, indexed_chunk_keys
from designlab.analysis.points import ArrayPoints, PointSource
from designlab.errors import DesignlabError

__all__ = [
    "DEFAULT_CHUNK_SIZE",
    "STATUS_ERROR",
    "CacheIncompleteError",
    "Columns",
    "Evaluator",
    "ResultStore",
    "StoredRows",
    "SweepRun",
    "as_columns",
    "chunk_key",
    "code_version",
    "evaluate_chunk",
    "evaluator_id",
    "run_points",
]

logger = logging.getLogger(__name__)

#: ``evaluator(points, options) -> results``, vectorised over the chunk.
Evaluator = Callable[[Columns, dict[str, Any]], Mapping[str, Any]]

#: Status of a point whose evaluation raised.
STATUS_ERROR = "error"
#: Points per chunk unless the evaluator sets ``chunk_size``.
DEFAULT_CHUNK_SIZE = 2048
#: Leading points of a chunk hashed into its stored summary: a resume draws these of one
#: finished chunk to check that the source still draws the points the chunk was computed from.
HEAD_POINTS = 16


class CacheIncompleteError(DesignlabError, LookupError):
    """Rebuilding from the store only, but some points are not in it."""


class ResultStore(Protocol):
    """What the engine needs of a result store (see :mod:`designlab.analysis.store`).

    A store may also keep a summary per chunk (points per status, column kinds,
    a hash of the chunk's points), as :class:`~designlab.analysis.store.ChunkStore`
    does: ``put_chunk(key, columns, summary)`` and ``summaries(keys) -> {key: (n,
    summary)}``. A resumed run whose chunks are keyed by index then reads no chunk
    at all (see :func:`run_points`).
    """

    def get_chunk(self, key: str) -> tuple[str, Any]:
        """``("ok", columns)``, ``("missing", None)`` or ``("corrupt", reason)``.

        Parameters
        ----------
        key
            The chunk key (:func:`chunk_key`).
        """

    def put_chunk(self, key: str, columns: Columns) -> None:
        """Store a finished chunk.

        Parameters
        ----------
        key
            The chunk key (:func:`chunk_key`).
        columns
            The chunk's result columns.
        """

    def discard(self, key: str) -> None:
        """Remove a chunk (e.g. a corrupt one).

        Parameters
        ----------
        key
            The chunk key.
        """


def _own(cols: Columns) -> Columns:
    """Writable, contiguous copies of (views of) point columns, for an evaluator to use."""
    return {k: np.array(v, dtype=float) for k, v in cols.items()}


def _normalise(out: Mapping[str, Any], n: int, where: str) -> Columns:
    cols: Columns = {}
    for k, v in out.items():
        arr = np.asarray(v)
        if arr.ndim == 0:
            arr = np.full(n, arr.item(), dtype=arr.dtype if arr.dtype != object else object)
        if arr.shape != (n,):
            raise ValueError(f"{where}: result column {k!r} has shape {arr.shape}, expected ({n},)")
        cols[str(k)] = arr
    if "status" not in cols:
        cols["status"] = np.full(n, "ok", dtype=object)
    cols["status"] = cols["status"].astype(object)
    if "error" not in cols:
        cols["error"] = np.full(n, None, dtype=object)
    return cols


def _error_columns(n: int, message: str) -> Columns:
    return {
        "status": np.full(n, STATUS_ERROR, dtype=object),
        "error": np.full(n, message, dtype=object),
    }


# --- the worker side ------------------------------------------------------------------


def evaluate_chunk(task: dict[str, Any]) -> Columns:
    """Evaluate one chunk in a worker: ``{"evaluator": fn, "options": {...}, "points": cols}``.

    If the vectorised evaluation raises, the chunk is split in halves until
    the failing points are isolated: they get ``status: error`` and the
    exception's type and message, every other point keeps its result.

    Parameters
    ----------
    task
        ``{"evaluator": fn, "options": {...}, "points": columns}``.
    """
    fn: Evaluator = task["evaluator"]
    options = task.get("options", {})
    points: Columns = task["points"]
    n = column_length(points)
    if n == 0:
        return {}
    try:
        return _normalise(fn(dict(points), dict(options)), n, evaluator_id(fn))
    except Exception as exc:
        if n == 1:
            return _error_columns(1, f"{type(exc).__name__}: {exc}")
    half = n // 2
    halves = Assembler(n)
    halves.put(0, evaluate_chunk({**task, "points": take_rows(points, slice(0, half))}))
    halves.put(half, evaluate_chunk({**task, "points": take_rows(points, slice(half, n))}))
    return halves.columns()


# --- the client side --------------------------------------------------------------------


@dataclass
class SweepRun:
    """Results of :func:`run_points`, one row per point in the order given.

    Attributes
    ----------
    frame
        Result columns (and ``status``, ``error``), one row per point.
    points
        How many points were asked for.
    distinct
        How many distinct points there were (identical points are merged).
    computed, cached
        Distinct points computed now / read from the store.
    corrupt
        Keys of store chunks found corrupt (and recomputed).
    chunks
        Chunks evaluated or read.
    digest
        A hash of what determines the results: the evaluator, its code
        version, its options and every point in order. Two runs with the
        same digest have the same results.
    status_counts
        Points per ``status`` value (every point, duplicates included).
    rows
        With ``collect=False``: the results, left in the store and read back
        block by block (:class:`StoredRows`); ``frame`` is then empty.
    """

    frame: pd.DataFrame
    points: int = 0
    distinct: int = 0
    computed: int = 0
    cached: int = 0
    corrupt: list[str] = field(default_factory=list)
    chunks: int = 0
    digest: str = ""
    status_counts: dict[str, int] = field(default_factory=dict)
    rows: StoredRows | None = None

    @property
    def duplicates(self) -> int:
        """Points merged with an identical earlier point."""
        return self.points - self.distinct

    @property
    def failed_count(self) -> int:
        """How many points failed (``status == "error"``)."""
        return int(self.status_counts.get(STATUS_ERROR, 0))

    @property
    def failed(self) -> list[int]:
        """Row positions of points whose evaluation raised (collected runs only)."""
        if "status" not in self.frame:
            return []
        return list(np.flatnonzero(self.frame["status"].to_numpy() == STATUS_ERROR))

    @property
    def results(self) -> list[dict[str, Any]]:
        """The rows as dicts (convenient for a handful of points)."""
        return self.frame.to_dict("records")


class _StatusCounter:
    """Points per status, chunk by chunk (weighted by how often each distinct point occurs)."""

    def __init__(self, multiplicity: np.ndarray | None) -> None:
        self.multiplicity = multiplicity
        self.counts: dict[str, int] = {}
        #: Every result column seen, with its dtype kind ("O" when chunks disagree).
        self.kinds: dict[str, str] = {}
        self.chunks = 0
        self.seen: dict[str, int] = {}

    def partial(self) -> set[str]:
        """Columns that some chunk lacks (NaN or ``None`` there)."""
        return {k for k in self.kinds if self.seen.get(k, 0) < self.chunks}

    @staticmethod
    def summarise(part: Columns) -> dict[str, Any]:
        """A chunk's column kinds and points per status (what a resume needs of it)."""
        kinds: dict[str, str] = {}
        for name, values in part.items():
            kind = np.asarray(values).dtype.kind
            kinds[name] = "f" if kind in "fiu" else kind if kind == "b" else "O"
        counts: dict[str, int] = {}
        status = np.asarray(part.get("status", ()), dtype=object).tolist()
        for value, times in Counter(status).items():
            counts[str(value)] = counts.get(str(value), 0) + times
        return {"kinds": kinds, "status": dict(sorted(counts.items()))}

    def add_summary(self, summary: Mapping[str, Any]) -> None:
        """Count a chunk from its :meth:`summarise` (unweighted: no merged duplicates)."""
        self.chunks += 1
        for name, kind in summary["kinds"].items():
            self.seen[name] = self.seen.get(name, 0) + 1
            if self.kinds.setdefault(name, kind) != kind:
                self.kinds[name] = "O"
        for value, total in summary["status"].items():
            self.counts[value] = self.counts.get(value, 0) + int(total)

    def add(self, start: int, part: Columns) -> dict[str, Any] | None:
        """Count a chunk starting at distinct point ``start``; its summary when unweighted."""
        summary = self.summarise(part)
        if self.multiplicity is None:
            self.add_summary(summary)
            return summary
        self.add_summary({"kinds": summary["kinds"], "status": {}})
        status = np.asarray(part.get("status", ()), dtype=object)
        if not len(status):
            return None
        values, inverse = np.unique(status.astype(str), return_inverse=True)
        weights = (
            None if self.multiplicity is None else self.multiplicity[start : start + len(status)]
        )
        totals = np.bincount(inverse.ravel(), weights=weights, minlength=len(values))
        for v, t in zip(values, totals, strict=True):
            self.counts[str(v)] = self.counts.get(str(v), 0) + round(float(t))
        return None


def _digest(
    evaluator: Evaluator,
    options: Mapping[str, Any],
    cols: Columns | None,
    keys: Sequence[str | None],
    inverse: np.ndarray | None,
) -> str:
    """A hash of the evaluator, its code, its options and every point in order.

    With a store, the chunk keys already hash every distinct point (and the
    evaluator, code and options): the digest combines them with the order of
    the points instead of hashing the points again.
    """
    if not keys or any(k is None for k in keys):
        return chunk_key(evaluator, options, cols or {})
    h = hashlib.sha256(b"chunks")
    for key in keys:
        h.update(key.encode())  # type: ignore[union-attr]
    if inverse is not None:
        h.update(np.ascontiguousarray(inverse, dtype="<i8").tobytes())
    return h.hexdigest()


class StoredRows:
    """Results of a run left in the store, read back in point order a block at a time.

    What :func:`run_points` returns (as :attr:`SweepRun.rows`) with
    ``collect=False``: memory stays at a block and one chunk, whatever the
    number of points. Reading a chunk that has gone from the store (or is
    damaged) raises :class:`CacheIncompleteError`.

    Parameters
    ----------
    store
        The store holding the chunks.
    keys
        Chunk keys, in order of the distinct points.
    size
        Points per chunk.
    distinct
        Number of distinct points.
    inverse
        For each point, its distinct index (``None``: the points are distinct).
    kinds
        Every result column of the run with its dtype kind (``f`` numbers,
        ``b`` booleans, ``O`` anything else): a block read back has all of
        them, typed alike in every block.
    partial
        Columns that some chunk lacks: NaN (numbers) or ``None`` there, and
        booleans among them are of object dtype in every block.
    """

    def __init__(
        self,
        store: ResultStore,
        keys: Sequence[str],
        size: int,
        distinct: int,
        inverse: np.ndarray | None,
        *,
        kinds: Mapping[str, str] | None = None,
        partial: set[str] | None = None,
    ) -> None:
        self.store, self.keys, self.size, self.distinct = store, list(keys), size, distinct
        self.inverse = inverse
        self.kinds = dict(kinds or {})
        self.partial = set(partial or ())
        self._last: tuple[int, Columns] | None = None

    def __len__(self) -> int:
        return self.distinct if self.inverse is None else len(self.inverse)

    def _chunk(self, c: int) -> Columns:
        if self._last is not None and self._last[0] == c:
            return self._last[1]
        state, value = self.store.get_chunk(self.keys[c])
        expected = min(self.size, self.distinct - c * self.size)
        if state != "ok" or column_length(value) != expected:
            raise CacheIncompleteError(
                f"stored chunk {self.keys[c][:12]}... is {state if state != 'ok' else 'damaged'}"
                " since it was written; run the study again with --resume"
            )
        self._last = (c, value)
        return value

    def _distinct_rows(self, index: np.ndarray) -> Columns:
        """Result columns of the distinct points ``index`` (any order)."""
        assembled = Assembler(len(index))
        chunk_of = index // self.size
        for c in np.unique(chunk_of):
            at = np.flatnonzero(chunk_of == c)
            part = self._chunk(int(c))
            offsets = index[at] - int(c) * self.size
            assembled.put_rows(at, {k: np.asarray(v)[offsets] for k, v in part.items()})
        return assembled.columns()

    def read(self, rows: slice, columns: Sequence[str] | None = None) -> pd.DataFrame:
        """The results of points ``rows`` (a slice in point order), optionally some columns.

        Parameters
        ----------
        rows
            Which points, e.g. ``slice(0, 1000)``.
        columns
            Only these result columns (missing ones are left out).
        """
        start, stop, _ = rows.indices(len(self))
        positions = np.arange(start, stop)
        index = positions if self.inverse is None else self.inverse[positions]
        got = self._distinct_rows(np.asarray(index, dtype=np.intp))
        n = len(positions)
        cols: Columns = {}
        for name, kind in (self.kinds or {k: "O" for k in got}).items():
            if columns is not None and name not in columns:
                continue
            v = got.get(name)
            if v is None:
                v = np.full(n, np.nan) if kind == "f" else np.full(n, None, dtype=object)
            elif (kind == "O" or (kind == "b" and name in self.partial)) and v.dtype != object:
                v = v.astype(object)
            cols[name] = v
        return pd.DataFrame(cols, copy=False)

    def blocks(self, rows: slice, block: int) -> Iterator[tuple[int, pd.DataFrame]]:
        """``(start, frame)`` for consecutive blocks of ``block`` points within ``rows``.

        Parameters
        ----------
        rows
            The range of points to read.
        block
            Points per block.
        """
        start, stop, _ = rows.indices(len(self))
        for s in range(start, stop, block):
            yield s, self.read(slice(s, min(s + block, stop)))


def _bar(total: int, desc: str, progress: bool) -> Any:
    from tqdm.auto import tqdm

    return tqdm(
        total=total, desc=desc, unit="pt", file=sys.stderr, disable=not progress, leave=False
    )


def run_points(
    points: Columns | Sequence[Mapping[str, float]] | pd.DataFrame | PointSource,
    evaluator: Evaluator,
    options: Mapping[str, Any] | None = None,
    *,
    executor: Any = None,
    store: ResultStore | None = None,
    resume: bool = False,
    cache_only: bool = False,
    progress: bool = False,
    chunk_size: int | None = None,
    desc: str = "points",
    collect: bool = True,
) -> SweepRun:
    """Evaluate ``points`` with ``evaluator`` in chunks.

    Parameters
    ----------
    points
        Point columns (key -> array), a list of point dicts, a DataFrame or a
        :class:`~designlab.analysis.points.PointSource` (a sample generated a
        chunk at a time).
    evaluator
        A module-level function ``(points, options) -> result columns``.
    options
        Evaluator settings shared by all points (part of the chunk key).
    executor
        An :class:`~designlab.analysis.executors.Executor` (default: serial).
    store
        Where finished chunks are kept (see :mod:`designlab.analysis.store`);
        each chunk is written as soon as it comes back.
    resume
        Reuse chunks found in the store; compute only the missing ones.
    cache_only
        Compute nothing; raise :class:`CacheIncompleteError` if a chunk is
        not in the store.
    progress
        Show a tqdm bar on stderr.
    chunk_size
        Points per chunk (default: ``evaluator.chunk_size`` or
        :data:`DEFAULT_CHUNK_SIZE`). Keep it fixed between a run and its
        resume: chunk keys depend on it.
    desc
        Label of the progress bar and of messages.
    collect
        Assemble the results in memory (:attr:`SweepRun.frame`). With
        ``False`` (needs a ``store``) they stay in the store and
        :attr:`SweepRun.rows` reads them back block by block; points given as a
        ``PointSource`` are then drawn from it a chunk at a time and not merged
        when identical, so memory is bounded by the chunks in flight, not by
        the number of points. Otherwise identical points are evaluated once.
        A streamed source with an
        :meth:`~designlab.analysis.points.PointSource.identity` has its chunks
        keyed by index: a resume finds the finished ones (from the store's
        chunk summaries, checksums verified) without drawing their points.

    Returns
    -------
    SweepRun
        One result row per point, and the counts.
    """
    evaluator_id(evaluator)  # a clear error for lambdas and closures
    options = dict(options or {})
    size = int(chunk_size or getattr(evaluator, "chunk_size", DEFAULT_CHUNK_SIZE))
    if size < 1:
        raise ValueError(f"chunk_size = {size} is not allowed: must be >= 1")
    if not collect and store is None:
        raise ValueError("collect=False keeps the results in the store: give a store")
    cols: Columns | None = None
    if isinstance(points, PointSource) and not collect:  # streamed: never held whole
        distinct, inverse = points, None
    else:
        cols = points.columns() if isinstance(points, PointSource) else as_columns(points)
        first, inverse = distinct_rows(cols)
        distinct = ArrayPoints(cols if first is None else take_rows(cols, first))
    n = len(points) if cols is None else column_length(cols)
    m = len(distinct)
    state = _Pass(
        evaluator, options, distinct, size, store, collect,
        _StatusCounter(None if inverse is None else np.bincount(inverse, minlength=m)),
    )  # fmt: skip
    identity = distinct.identity() if cols is None and store is not None else None
    if identity is not None:  # streamed from a known sampler: chunks keyed by index
        state.keys = list(indexed_chunk_keys(evaluator, options, identity, m, size))
        state.indexed = True
    run = SweepRun(pd.DataFrame(), points=n, distinct=m, chunks=len(state.bounds))
    todo = state.read_store(run, reuse=resume or cache_only, repair=not cache_only)
    if cache_only and todo:
        raise state.incomplete(todo, desc)
    logger.info(
        "%s: %d points (%d distinct, %d merged duplicates) in %d chunks of <= %d; "
        "%d points from the store, %d to compute",
        desc, n, m, n - m, len(state.bounds), size, run.cached, m - run.cached,
    )  # fmt: skip
    if todo:
        state.compute(run, todo, executor or SerialExecutor(), _bar(m - run.cached, desc, progress))
    run.digest = _digest(evaluator, options, cols, state.keys, inverse)
    run.status_counts = state.counter.counts
    _finish(run, state, inverse, desc)
    return run


def _finish(run: SweepRun, state: _Pass, inverse: np.ndarray | None, desc: str) -> None:
    """Fill ``run.frame`` (collected) or ``run.rows`` (left in the store); warn of failures."""
    counter, n = state.counter, run.points
    if state.assembled is None:
        run.rows = StoredRows(
            state.store,  # type: ignore[arg-type]
            state.keys,  # type: ignore[arg-type]
            state.size,
            run.distinct,
            inverse,
            kinds=counter.kinds,
            partial=counter.partial(),
        )
        if run.failed_count:
            logger.warning("%s: %d of %d points failed", desc, run.failed_count, n)
        return
    frame = state.assembled.frame(inverse)
    if len(frame):
        for c in ("status", "error"):
            if c not in frame:
                frame[c] = None
    run.frame = frame
    failed = run.failed
    if failed:
        logger.warning(
            "%s: %d of %d points failed, e.g. point %d: %s",
            desc, len(failed), n, failed[0], frame["error"].iloc[failed[0]],
        )  # fmt: skip


def _plural(n: int, word: str) -> str:
    return f"{n} {word}{'s' if n != 1 else ''}"


class _Pass:
    """One pass of :func:`run_points` over the chunks of the distinct points."""

    def __init__(
        self,
        evaluator: Evaluator,
        options: dict[str, Any],
        distinct: PointSource,
        size: int,
        store: ResultStore | None,
        collect: bool,
        counter: _StatusCounter,
    ) -> None:
        m = len(distinct)
        self.evaluator, self.options, self.distinct, self.store = (
            evaluator,
            options,
            distinct,
            store,
        )
        self.bounds = [(s, min(s + size, m)) for s in range(0, m, size)]
        self.keys: list[str | None] = [None] * len(self.bounds)
        #: Whether :attr:`keys` come by index from the source's identity (no points drawn).
        self.indexed = False
        #: A hash of each chunk's points, drawn for computing (kept in indexed summaries).
        self.point_hashes: dict[int, str] = {}
        self.size = size
        self.assembled = Assembler(m) if collect else None
        self.counter = counter
        #: ``(chunk, reason)`` of every damaged chunk found in the store.
        self.damaged: list[tuple[int, str]] = []
        #: Whether the stored chunks of these keys hold other points (never reused).
        self.stale = False

    def _keep(self, c: int, columns: Columns) -> dict[str, Any] | None:
        start = self.bounds[c][0]
        if self.assembled is not None:
            self.assembled.put(start, columns)
        return self.counter.add(start, columns)

    def _summaries(self, todo: list[int]) -> dict[str, tuple[int, dict[str, Any]]]:
        """Summaries of the stored chunks among ``todo`` (indexed keys and a store with them).

        The first :data:`HEAD_POINTS` points of one chunk are drawn and compared
        with the hash kept in its summary: a source whose identity does not fix
        its points (which would be a defect) reuses nothing.
        """
        if not self.indexed or not _summarises(self.store):
            return {}
        keys = [self.keys[c] for c in todo]
        found: dict[str, tuple[int, dict[str, Any]]] = self.store.summaries(keys)  # type: ignore[union-attr]
        for c in todo:
            kept = found.get(self.keys[c])  # type: ignore[arg-type]
            if kept is None or "points" not in kept[1]:
                continue
            start, stop = self.bounds[c]
            head = self.distinct.take(start, min(stop, start + HEAD_POINTS))
            if kept[1]["points"] != _points_hash(head, HEAD_POINTS):
                logger.warning(
                    "stored chunk %d was computed from other points than this run draws "
                    "for it (same sampler, seed and code): recomputing every chunk", c,
                )  # fmt: skip
                self.stale = True
                return {}
            break
        return found

    def read_store(self, run: SweepRun, *, reuse: bool, repair: bool = True) -> list[int]:
        """Key every chunk; with ``reuse``, take finished ones from the store. The rest to do.

        A damaged stored chunk is discarded and recomputed with ``repair``;
        without (rebuilding from the store only), it is left as it is and
        listed in :attr:`damaged`.
        """
        if self.store is None:
            return list(range(len(self.bounds)))
        todo: list[int] = []
        summaries = self._summaries(list(range(len(self.bounds)))) if reuse else {}
        reuse = reuse and not self.stale
        for c, (s, e) in enumerate(self.bounds):
            if not self.indexed:
                self.keys[c] = chunk_key(self.evaluator, self.options, self.distinct.take(s, e))
            key: str = self.keys[c]  # type: ignore[assignment]
            if key in summaries and summaries[key][0] == e - s:
                self.counter.add_summary(summaries[key][1])
                run.cached += e - s
                continue
            if reuse:
                state, value = self.store.get_chunk(key)
                if state == "ok" and column_length(value) == e - s:
                    self._keep(c, value)
                    run.cached += e - s
                    continue
                if state in ("corrupt", "ok"):
                    reason = value if state == "corrupt" else "wrong length"
                    self.damaged.append((c, str(reason)))
                    if repair:
                        logger.warning(
                            "corrupt stored chunk %s (%s): recomputing its %s",
                            key, reason, _plural(e - s, "point"),
                        )  # fmt: skip
                        run.corrupt.append(key)
                        self.store.discard(key)
            todo.append(c)
        return todo

    def incomplete(self, todo: list[int], desc: str) -> CacheIncompleteError:
        """The error of a rebuild from the store that lacks the chunks ``todo``."""
        npoints = {c: self.bounds[c][1] - self.bounds[c][0] for c in todo}
        missing = sum(npoints.values())
        damaged = dict(self.damaged)
        parts = []
        if damaged:
            reasons = ", ".join(sorted(set(damaged.values())))
            hurt = sum(npoints[c] for c in damaged)
            parts.append(f"{hurt} in {_plural(len(damaged), 'damaged chunk')} ({reasons})")
        if missing > sum(npoints[c] for c in damaged):
            parts.append(f"{missing - sum(npoints[c] for c in damaged)} never stored or lost")
        return CacheIncompleteError(
            f"{_plural(missing, 'point')} of {desc} {'are' if missing != 1 else 'is'} not in "
            f"the store ({'; '.join(parts)}); rebuilding a report from the store computes "
            "nothing: run the study with --resume (designlab run STUDY.yaml --resume) to "
            "compute them"
        )

    def compute(self, run: SweepRun, todo: list[int], executor: Any, bar: Any) -> None:
        """Evaluate the chunks ``todo``; store and keep each as it comes back."""
        tasks = (  # a generator: only the chunks in flight exist as tasks
            {"evaluator": self.evaluator, "options": self.options, "points": self._draw(c)}
            for c in todo
        )  # fmt: skip
        try:
            for t, out in _as_completed(executor, tasks):
                c = todo[t]
                summary = self._keep(c, out)
                drawn = self.point_hashes.pop(c, None)
                if drawn is not None and summary is not None and _summarises(self.store):
                    summary["points"] = drawn
                    self.store.put_chunk(self.keys[c], out, summary)  # type: ignore[call-arg, union-attr]
                elif self.store is not None:
                    self.store.put_chunk(self.keys[c], out)  # type: ignore[arg-type]
                k = self.bounds[c][1] - self.bounds[c][0]
                run.computed += k
                bar.update(k)
        finally:
            bar.close()

    def _draw(self, c: int) -> Columns:
        """Chunk ``c``'s points, as the evaluator's own arrays (hashed when keyed by index)."""
        points = _own(self.distinct.take(*self.bounds[c]))
        if self.indexed:
            self.point_hashes[c] = _points_hash(points, HEAD_POINTS)
        return points


def _summarises(store: ResultStore | None) -> bool:
    """Whether ``store`` keeps chunk summaries (``summaries``, ``put_chunk(..., summary)``)."""
    return callable(getattr(store, "summaries", None))


def _points_hash(points: Columns, head: int) -> str:
    """A hash of the first ``head`` points of some columns (names and values, bit for bit)."""
    h = hashlib.sha256()
    for name in sorted(points):
        h.update(name.encode() + b"\0")
        h.update(np.ascontiguousarray(points[name][:head], dtype="<f8").tobytes())
    return h.hexdigest()


def _as_completed(ex: Any, tasks: Iterable[dict[str, Any]]) -> Iterator[tuple[int, Columns]]:
    yield from ex.map_unordered(evaluate_chunk, tasks)
