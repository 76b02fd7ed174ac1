"""Run a sweep study: expand its points, evaluate them in chunks, build the sensitivity tables.

The kind-specific parts come from the study model (``PARAMETERS``,
``METRICS``, ``EVALUATOR``, ``LOCAL_EVALUATOR``, :meth:`base_point`); the
rest - sampling, executors, the result store, the tables - is shared by every
sweep kind.

Point sets (all evaluated in one pass, through one store):

``base``
    The base design.
``sweep``
    The ``sweep`` block's points (the results table).
``one_at_a_time``
    Each listed parameter changed alone by each percentage.
``range``
    Each swept parameter at the low and high end of its range (tornado).
``sobol``
    SALib's Saltelli sample over the listed parameters' ranges.
"""

from __future__ import annotations

import hashlib
import logging
import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import pandas as pd

from designlab.analysis import sampling
from designlab.analysis.engine import STATUS_ERROR, SweepRun, run_points
from designlab.analysis.points import ArrayPoints, ConcatPoints, PointSource, source_identity
from designlab.analysis.sensitivity import (
    SensitivityTable,
    elasticity_table,
    one_at_a_time_table,
    range_table,
    sobol_table,
)
from designlab.results import OK, Result
from designlab.study.points_table import FrameTable, PointsTable, StoredTable
from designlab.study.runner import RunContext
from designlab.study.sweeps import SweepStudyBase

__all__ = ["STREAM_FROM", "SweepStudyResult", "count_points", "run_sweep_study", "unit_slug"]

#: A sweep of more than this many points, run with a result store, leaves its
#: results in the store and reads them back block by block (memory bounded by
#: the chunk and block sizes, not by the number of points).
STREAM_FROM = 50_000

logger = logging.getLogger(__name__)

_UNIT_SLUGS = {"N s/m": "N_s_per_m", "N/m": "N_per_m", "m/s": "m_per_s", "": ""}

Columns = dict[str, np.ndarray]


def unit_slug(unit: str) -> str:
    """A unit as a column-name suffix: ``"N s/m"`` -> ``"N_s_per_m"``.

    Parameters
    ----------
    unit
        An SI unit as written in the docs.

    Examples
    --------
    >>> unit_slug("N/m"), unit_slug("kg")
    ('N_per_m', 'kg')
    """
    return _UNIT_SLUGS.get(unit, unit.replace(" ", "_").replace("/", "_per_"))


@dataclass(frozen=True)
class SweepStudyResult(Result):
    """Results of a sweep study.

    Attributes
    ----------
    study
        The study.
    table
        The sweep points (:class:`~designlab.study.points_table.PointsTable`):
        one row per point, inputs (point keys with units, e.g.
        ``K_c_N_per_m``), metrics, ``status`` and ``error``. In memory, or, for
        a sweep of more than :data:`STREAM_FROM` points run with a result
        store, read back from the store block by block.
    base
        Metrics at the base design.
    sensitivity
        Tables by kind (``elasticity``, ``one_at_a_time``, ``sobol``, ``range``).
    stats
        Points asked for, distinct, computed now, read from the store, corrupt
        chunks recomputed, failed; chunks; the executor; and ``digest``, a
        hash of every evaluated point with the evaluator's code version (equal
        digests, equal results).

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> r = run_study(parse_study('''
    ... designlab: 1
    ... kind: impact_sweep
    ... name: demo
    ... base: {robot: MANIPULATOR_1, foam: FOAM_1, head: HEAD_MIN, impact_velocity: 1.25}
    ... sweep: {method: grid, parameters: {foam.stiffness: {low: 10e3, high: 60e3, num: 3}}}
    ... '''))
    >>> type(r).__name__, r.status, len(r.to_frame())
    ('SweepStudyResult', 'ok', 3)
    """

    study: SweepStudyBase
    table: PointsTable
    base: dict[str, Any]
    sensitivity: dict[str, SensitivityTable]
    stats: dict[str, Any] = field(default_factory=dict)

    @cached_property
    def frame(self) -> pd.DataFrame:
        """The sweep points as one data frame (for a stored table: read in full, once)."""
        return self.table.frame()

    @property
    def metrics(self) -> list[str]:
        """The metrics analysed (``sensitivity.metrics``, or the kind's defaults)."""
        return self.study.metrics

    @property
    def status(self) -> str:
        """``"ok"``; ``"partial"`` when some points failed; ``"failed"`` when the base did."""
        if self.base.get("status") == STATUS_ERROR:
            return "failed"
        if self.stats.get("failed"):
            return "partial"
        return OK

    def to_frame(self) -> pd.DataFrame:
        """The sweep points (a copy)."""
        return self.table.frame().copy()

    @property
    def fingerprint(self) -> str:
        """What the results depend on: a hash of every point and the evaluator's code.

        A report written from a result with the same fingerprint, the same
        study text and the same designlab holds the same numbers (see
        ``designlab run --resume``, which then leaves it as it is).
        """
        return str(self.stats.get("digest", ""))

    @cached_property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """Failed points, non-``ok`` statuses and recomputed store chunks."""
        out: list[str] = []
        n = len(self.table)
        if n:
            scan = self.table.scan()
            for i, error in scan.failed:
                out.append(f"point {i}: failed: {error}")
            failed = scan.status_counts.get(STATUS_ERROR, 0)
            if failed > len(scan.failed):
                out.append(f"... and {failed - len(scan.failed)} more failed points")
            for name in sorted(k for k in scan.status_counts if k not in (OK, STATUS_ERROR)):
                out.append(f"{scan.status_counts[name]} of {n} points have status {name}")
            if scan.flags.get("bottoming"):
                out.append(
                    f"{scan.flags['bottoming']} of {n} points bottom the foam (eps_max > lambda)"
                )
            notes, first = scan.notes
            if notes:
                out.append(f"{notes} of {n} points have solver warnings, e.g.: {first}")
        if self.stats.get("corrupt"):
            out.append(f"{self.stats['corrupt']} corrupt stored chunks were recomputed")
        if self.base.get("status") not in (None, OK):
            out.append(
                f"base design: status {self.base.get('status')} {self.base.get('error') or ''}"
            )
        return tuple(out)


# --- the plan: which points, in which sets ------------------------------------------


def _sweep_source(study: SweepStudyBase) -> PointSource | None:
    """The sweep block's points, generated a chunk at a time (grid, LHS, Sobol) or listed."""
    sweep = study.sweep
    if sweep is None:
        return None
    items = sweep.parameters.items()
    if sweep.method == "list":
        return ArrayPoints(sampling.list_points({p: r.values for p, r in items}))
    if sweep.method == "grid":
        return sampling.GridPoints({p: r.grid() for p, r in items})
    bounds = {p: (float(r.low), float(r.high)) for p, r in items}
    log = {p: r.scale == "log" for p, r in items}
    sampler = sampling.LatinHypercubePoints if sweep.method == "lhs" else sampling.SobolPoints
    return sampler(bounds, sweep.samples, seed=sweep.seed, log=log)


class _Designs(PointSource):
    """Copies of the base point with the columns of ``values`` (by path) replaced.

    Unchanged parameters are read-only broadcast views of their base value:
    a million-point sweep over three parameters produces three columns, not ten.
    """

    def __init__(
        self, base: dict[str, float], key_of: dict[str, str], values: PointSource | None
    ) -> None:
        self.base, self.key_of, self.values = base, key_of, values
        self.names = tuple(base)

    def __len__(self) -> int:
        return 1 if self.values is None else len(self.values)

    def identity(self) -> str | None:
        """The base point, the column names and the identity of the values."""
        values = None if self.values is None else self.values.identity()
        if self.values is not None and values is None:
            return None
        return source_identity(self, {"base": self.base, "key_of": self.key_of, "values": values})

    def _take(self, start: int, stop: int) -> Columns:
        n = stop - start
        out = {k: np.broadcast_to(np.float64(v), (n,)) for k, v in self.base.items()}
        if self.values is not None:
            for path, v in self.values.take(start, stop).items():
                out[self.key_of[path]] = np.asarray(v, dtype=float)
        return out


@dataclass
class _Plan:
    base: dict[str, float]
    sets: dict[str, PointSource]
    oat_meta: list[tuple[str, float, float]]
    range_meta: list[tuple[str, float, float]]
    sobol_names: list[str]
    sobol_bounds: list[tuple[float, float]]
    path_of: dict[str, str]
    describe: dict[str, str]

    def count(self) -> int:
        return sum(len(c) for c in self.sets.values())


def _plan(study: SweepStudyBase) -> _Plan:
    params = study.PARAMETERS
    key_of = {path: key for path, (key, _) in params.items()}
    path_of = {key: path for path, key in key_of.items()}
    describe = {path: f"{info.description}, {info.unit}" for path, (_, info) in params.items()}
    base = study.base_point()
    sens = study.sensitivity
    sweep = study.sweep
    swept = dict(sweep.parameters.items()) if sweep is not None else {}

    sets: dict[str, PointSource] = {"base": _Designs(base, key_of, None)}
    values = _sweep_source(study)
    sets["sweep"] = _Designs(base, key_of, values) if values is not None else ArrayPoints({})
    oat_meta: list[tuple[str, float, float]] = []
    range_meta: list[tuple[str, float, float]] = []
    sobol_names: list[str] = []
    sobol_bounds: list[tuple[float, float]] = []
    if sens is not None and sens.one_at_a_time is not None:
        oat = sens.one_at_a_time
        for path in oat.parameters or list(swept):
            x0 = base[key_of[path]]
            oat_meta += [(path, float(d), x0 * (1.0 + d / 100.0)) for d in oat.deltas_pct]
        sets["one_at_a_time"] = _one_each(base, key_of, oat_meta)
    if sens is not None and sens.tornado and swept:
        for path, rng in swept.items():
            lo, hi = rng.span()
            range_meta.append((path, lo, hi))
        ends = [(p, 0.0, x) for p, lo, hi in range_meta for x in (lo, hi)]
        sets["range"] = _one_each(base, key_of, ends)
    if sens is not None and sens.sobol is not None:
        sobol_names = list(sens.sobol.parameters or list(swept))
        sobol_bounds = [swept[p].span() for p in sobol_names]
        sample = sampling.saltelli(
            dict(zip(sobol_names, sobol_bounds, strict=True)),
            sens.sobol.samples,
            seed=sens.sobol.seed,
        )
        sets["sobol"] = _Designs(base, key_of, ArrayPoints(sample))
    return _Plan(base, sets, oat_meta, range_meta, sobol_names, sobol_bounds, path_of, describe)


def _one_each(base: dict[str, float], key_of: dict[str, str], changes: list[Any]) -> ArrayPoints:
    """One point per change ``(path, _, value)``: the base with that one value replaced."""
    n = len(changes)
    out = {k: np.full(n, v, dtype=float) for k, v in base.items()}
    for i, (path, _, x) in enumerate(changes):
        out[key_of[path]][i] = x
    return ArrayPoints(out)


def count_points(study: SweepStudyBase) -> int:
    """How many points a sweep study evaluates (all sets, plus the local derivatives).

    Parameters
    ----------
    study
        A sweep study.
    """
    return sum(study.point_counts().values())


# --- running -----------------------------------------------------------------------------


def _metric_values(frame: pd.DataFrame, metrics: list[str]) -> list[dict[str, float]]:
    cols = {m: frame[m].to_numpy(dtype=float) if m in frame else None for m in metrics}
    return [
        {m: (float(c[i]) if c is not None else math.nan) for m, c in cols.items()}
        for i in range(len(frame))
    ]


def _stats(run: SweepRun, context: RunContext) -> dict[str, Any]:
    ex = context.executor
    return {
        "points": run.points,
        "distinct": run.distinct,
        "computed": run.computed,
        "cached": run.cached,
        "corrupt": len(run.corrupt),
        "failed": run.failed_count,
        "chunks": run.chunks,
        "executor": ex.describe() if ex is not None else "serial",
        "digest": run.digest,
    }


def _elasticities(
    study: SweepStudyBase, plan: _Plan, context: RunContext, stats: dict[str, Any]
) -> SensitivityTable | None:
    common = dict(
        executor=context.executor, store=context.store, resume=context.resume,
        cache_only=context.cache_only, progress=context.progress,
    )  # fmt: skip
    local = run_points(
        plan.sets["base"].columns(), type(study).LOCAL_EVALUATOR, study.evaluator_options(),  # type: ignore[arg-type]
        desc=f"{study.name}: elasticities", **common,
    )  # fmt: skip
    for k, v in _stats(local, context).items():
        if k == "digest":
            stats[k] = hashlib.sha256(f"{stats[k]}+{v}".encode()).hexdigest()
        elif k != "executor":
            stats[k] += v
    row = local.frame.iloc[0].to_dict()
    if row.get("status") == STATUS_ERROR:
        logger.warning("local elasticities failed: %s", row.get("error"))
        return None
    el: dict[str, dict[str, float]] = {}
    for col, value in row.items():
        if ":" not in str(col):
            continue
        metric, key = str(col).split(":", 1)
        if metric in study.metrics and key in plan.path_of:
            el.setdefault(metric, {})[plan.path_of[key]] = float(value)
    return elasticity_table(el, plan.describe)


def run_sweep_study(study: SweepStudyBase, context: RunContext) -> SweepStudyResult:
    """Evaluate every point of a sweep study and build its tables.

    Parameters
    ----------
    study
        A sweep study (a :class:`~designlab.study.sweeps.SweepStudyBase`).
    context
        How to run it (executor, store, resume; see
        :class:`~designlab.study.runner.RunContext`).
    """
    plan = _plan(study)
    metrics = study.metrics
    names = [name for name, points in plan.sets.items() if len(points)]
    logger.info("%s: %s", study.name, ", ".join(f"{s} {len(plan.sets[s])}" for s in names))
    stream = context.store is not None and len(plan.sets["sweep"]) > STREAM_FROM
    points = ConcatPoints([plan.sets[s] for s in names])
    run = run_points(
        points, type(study).EVALUATOR, study.evaluator_options(),  # type: ignore[arg-type]
        executor=context.executor, store=context.store, resume=context.resume,
        cache_only=context.cache_only, progress=context.progress, desc=study.name,
        collect=not stream,
    )  # fmt: skip
    results, offsets = _set_results(run, plan, names, metrics)
    base_result = {
        k: (v.item() if isinstance(v, np.generic) else v)
        for k, v in results["base"].iloc[0].to_dict().items()
    }
    base_metrics = _metric_values(results["base"], metrics)[0]
    stats = _stats(run, context)

    tables = _sensitivity_tables(study, plan, context, stats, results, base_metrics)
    if run.rows is None:
        sweep_frame = _points_frame(study, plan.sets["sweep"].columns(), results.get("sweep"))
        table: PointsTable = FrameTable(sweep_frame)
    else:
        table = StoredTable(
            plan.sets["sweep"], run.rows, offsets["sweep"],
            lambda points, res: _points_frame(study, points, res),
        )  # fmt: skip
    logger.info(
        "%s: %d points (%d distinct), %d computed, %d from the store, %d failed",
        study.name, stats["points"], stats["distinct"], stats["computed"], stats["cached"],
        stats["failed"],
    )  # fmt: skip
    return SweepStudyResult(study, table, base_result, tables, stats)


def _set_results(
    run: SweepRun, plan: _Plan, names: list[str], metrics: list[str]
) -> tuple[dict[str, pd.DataFrame], dict[str, int]]:
    """The results of each point set (the sweep's own stays in the store when streamed)
    and where each set starts in the run."""
    results: dict[str, pd.DataFrame] = {}
    offsets: dict[str, int] = {}
    i = 0
    for s in names:
        n = len(plan.sets[s])
        offsets[s] = i
        if run.rows is None:
            results[s] = run.frame.iloc[i : i + n].reset_index(drop=True)
        elif s != "sweep":  # small sets (and the Sobol outputs) are read back now
            wanted = None if s == "base" else [*metrics, "status"]
            results[s] = run.rows.read(slice(i, i + n), columns=wanted)
        i += n
    return results, offsets


def _sensitivity_tables(
    study: SweepStudyBase,
    plan: _Plan,
    context: RunContext,
    stats: dict[str, Any],
    results: dict[str, pd.DataFrame],
    base_metrics: Any,
) -> dict[str, SensitivityTable]:
    """The sensitivity tables the study asks for, from the results of their point sets."""
    metrics = study.metrics
    tables: dict[str, SensitivityTable] = {}
    sens = study.sensitivity
    if sens is not None and sens.local and study.LOCAL_EVALUATOR is not None:
        table = _elasticities(study, plan, context, stats)
        if table is not None:
            tables["elasticity"] = table
    if plan.oat_meta:
        rows = [
            (path, d, x, m)
            for (path, d, x), m in zip(
                plan.oat_meta, _metric_values(results["one_at_a_time"], metrics), strict=True
            )
        ]
        tables["one_at_a_time"] = one_at_a_time_table(base_metrics, rows, plan.describe)
    if plan.range_meta:
        rr = _metric_values(results["range"], metrics)
        rows = [
            (path, lo, hi, rr[2 * k], rr[2 * k + 1])
            for k, (path, lo, hi) in enumerate(plan.range_meta)
        ]
        tables["range"] = range_table(base_metrics, rows, plan.describe)
    if plan.sobol_names:
        frame = results["sobol"]
        outputs = {
            m: frame[m].to_numpy(dtype=float) if m in frame else np.full(len(frame), np.nan)
            for m in metrics
        }
        tables["sobol"] = sobol_table(
            plan.sobol_names, plan.sobol_bounds, outputs, seed=sens.sobol.seed,  # type: ignore[union-attr]
            descriptions=plan.describe,
        )  # fmt: skip
    return tables


def _points_frame(
    study: SweepStudyBase, points: Columns, results: pd.DataFrame | None
) -> pd.DataFrame:
    """Inputs (with units in the names), metrics, other columns, ``status``, ``error``.

    Built once, in its final column order, from the arrays as they are (no
    copy of a million-row table).
    """
    if not points or results is None:
        return pd.DataFrame()
    names = {key: f"{key}_{unit_slug(info.unit)}" for _, (key, info) in study.PARAMETERS.items()}
    columns: dict[str, Any] = {names.get(k, k): np.array(v) for k, v in points.items()}
    n = len(results)
    out = {c: columns[c] for c in names.values() if c in columns}
    out |= {m: results[m].to_numpy() for m in study.METRICS if m in results}
    rest = sorted((set(columns) | set(results.columns)) - set(out) - {"status", "error"})
    out |= {c: columns[c] if c in columns else results[c].to_numpy() for c in rest}
    for c in ("status", "error"):
        out[c] = results[c].to_numpy() if c in results else np.full(n, None, dtype=object)
    return pd.DataFrame(out, copy=False)
