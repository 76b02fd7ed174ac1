"""Run a sweep study: expand its points, evaluate them, build the sensitivity tables.

The kind-specific parts come from the study model (``PARAMETERS``,
``METRICS``, ``EVALUATOR``, ``LOCAL_EVALUATOR``, :meth:`base_point`); the
rest - sampling, executors, the cache, the tables - is shared by every sweep
kind.

Point sets (all evaluated in one pass, through one cache):

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

import logging
import math
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from designlab.analysis import sampling
from designlab.analysis.sensitivity import (
    SensitivityTable,
    elasticity_table,
    one_at_a_time_table,
    range_table,
    sobol_table,
)
from designlab.analysis.sweep import STATUS_ERROR, SweepRun, run_points
from designlab.study.schema import SweepStudyBase

__all__ = ["SweepStudyResult", "count_points", "run_sweep_study", "unit_slug"]

logger = logging.getLogger(__name__)

_UNIT_SLUGS = {"N s/m": "N_s_per_m", "N/m": "N_per_m", "m/s": "m_per_s", "": ""}


def unit_slug(unit: str) -> str:
    """A unit as a column-name suffix: ``"N s/m"`` -> ``"N_s_per_m"``.

    Examples
    --------
    >>> unit_slug("N/m"), unit_slug("kg")
    ('N_per_m', 'kg')
    """
    return _UNIT_SLUGS.get(unit, unit.replace(" ", "_").replace("/", "_per_"))


@dataclass(frozen=True)
class SweepStudyResult:
    """Results of a sweep study.

    Attributes
    ----------
    study
        The study.
    frame
        The sweep points: one row per point, inputs (point keys with units,
        e.g. ``K_c_N_per_m``), metrics, ``status`` and ``error``.
    base
        Metrics at the base design.
    sensitivity
        Tables by kind (``elasticity``, ``one_at_a_time``, ``sobol``, ``range``).
    stats
        Points in total, computed now, read from the cache, corrupt entries
        recomputed, failed; and the executor.
    """

    study: SweepStudyBase
    frame: pd.DataFrame
    base: dict[str, Any]
    sensitivity: dict[str, SensitivityTable]
    stats: dict[str, Any] = field(default_factory=dict)

    @property
    def metrics(self) -> list[str]:
        """The metrics analysed (``sensitivity.metrics``, or all of the kind's)."""
        sens = getattr(self.study, "sensitivity", None)
        return list(sens.metrics) if sens is not None else list(self.study.METRICS)

    def to_frame(self) -> pd.DataFrame:
        """The sweep points (a copy)."""
        return self.frame.copy()

    @property
    def warnings(self) -> list[str]:
        """Failed points, non-``ok`` statuses and recomputed cache entries."""
        out = []
        if len(self.frame):
            failed = self.frame[self.frame["status"] == STATUS_ERROR]
            for i, row in failed.head(10).iterrows():
                out.append(f"point {i}: failed: {row['error']}")
            if len(failed) > 10:
                out.append(f"... and {len(failed) - 10} more failed points")
            counts = Counter(s for s in self.frame["status"] if s not in ("ok", STATUS_ERROR))
            for status, n in sorted(counts.items()):
                out.append(f"{n} of {len(self.frame)} points have status {status}")
            if "bottoming" in self.frame and self.frame["bottoming"].fillna(False).any():
                n = int(self.frame["bottoming"].fillna(False).sum())
                out.append(f"{n} of {len(self.frame)} points bottom the foam (eps_max > lambda)")
            if "warnings" in self.frame:
                n = int(self.frame["warnings"].notna().sum())
                if n:
                    first = self.frame["warnings"].dropna().iloc[0]
                    out.append(
                        f"{n} of {len(self.frame)} points have solver warnings, e.g.: {first}"
                    )
        if self.stats.get("corrupt"):
            out.append(f"{self.stats['corrupt']} corrupt cache entries were recomputed")
        if self.base.get("status") not in (None, "ok"):
            out.append(
                f"base design: status {self.base.get('status')} {self.base.get('error') or ''}"
            )
        return out


def _sweep_points(study: SweepStudyBase) -> list[dict[str, float]]:
    sweep = getattr(study, "sweep", None)
    if sweep is None:
        return []
    items = sweep.parameters.items()
    if sweep.method == "list":
        return sampling.list_points({p: r.values for p, r in items})
    if sweep.method == "grid":
        return sampling.grid({p: r.grid() for p, r in items})
    bounds = {p: (float(r.low), float(r.high)) for p, r in items}
    log = {p: r.scale == "log" for p, r in items}
    if sweep.method == "lhs":
        return sampling.latin_hypercube(bounds, sweep.samples, seed=sweep.seed, log=log)
    return sampling.sobol_sequence(bounds, sweep.samples, seed=sweep.seed, log=log)


def _metrics_of(result: dict[str, Any], metrics: list[str]) -> dict[str, float]:
    return {
        m: float(result.get(m, math.nan)) if result.get(m) is not None else math.nan
        for m in metrics
    }


@dataclass
class _Plan:
    base: dict[str, float]
    metrics: list[str]
    sets: dict[str, list[dict[str, float]]]
    oat_meta: list[tuple[str, float, float]]
    range_meta: list[tuple[str, float, float]]
    sobol_names: list[str]
    sobol_bounds: list[tuple[float, float]]
    path_of: dict[str, str]
    describe: dict[str, str]


def _plan(study: SweepStudyBase) -> _Plan:
    params = study.PARAMETERS
    key_of = {path: key for path, (key, _) in params.items()}
    path_of = {key: path for path, key in key_of.items()}
    describe = {path: f"{info.description}, {info.unit}" for path, (_, info) in params.items()}
    base = study.base_point()
    sens = getattr(study, "sensitivity", None)
    metrics = list(sens.metrics) if sens is not None else list(study.METRICS)

    def design(values: dict[str, float]) -> dict[str, float]:
        p = dict(base)
        for path, v in values.items():
            p[key_of[path]] = float(v)
        return p

    sets: dict[str, list[dict[str, float]]] = {"base": [base]}
    sweep_values = _sweep_points(study)
    sets["sweep"] = [design(v) for v in sweep_values]
    oat_meta: list[tuple[str, float, float]] = []
    range_meta: list[tuple[str, float, float]] = []
    sobol_names: list[str] = []
    sobol_bounds: list[tuple[float, float]] = []
    sweep = getattr(study, "sweep", None)
    swept = dict(sweep.parameters.items()) if sweep is not None else {}
    if sens is not None and sens.one_at_a_time is not None:
        oat = sens.one_at_a_time
        pts = []
        for path in oat.parameters or list(swept):
            x0 = base[key_of[path]]
            for d in oat.deltas_pct:
                x = x0 * (1.0 + d / 100.0)
                oat_meta.append((path, float(d), x))
                pts.append(design({path: x}))
        sets["one_at_a_time"] = pts
    if sens is not None and sens.tornado and swept:
        pts = []
        for path, rng in swept.items():
            lo, hi = rng.span()
            range_meta.append((path, lo, hi))
            pts += [design({path: lo}), design({path: hi})]
        sets["range"] = pts
    if sens is not None and sens.sobol is not None:
        sobol_names = list(sens.sobol.parameters or [p for p, r in swept.items()])
        sobol_bounds = [swept[p].span() for p in sobol_names]
        sample = sampling.saltelli(
            dict(zip(sobol_names, sobol_bounds, strict=True)),
            sens.sobol.samples,
            seed=sens.sobol.seed,
        )
        sets["sobol"] = [design(v) for v in sample]

    return _Plan(
        base, metrics, sets, oat_meta, range_meta, sobol_names, sobol_bounds, path_of, describe
    )


def count_points(study: SweepStudyBase) -> int:
    """How many points a sweep study evaluates (all sets, plus the local derivatives)."""
    plan = _plan(study)
    sens = getattr(study, "sensitivity", None)
    local = int(bool(sens is not None and sens.local and getattr(study, "LOCAL_EVALUATOR", None)))
    return sum(len(v) for v in plan.sets.values()) + local


def run_sweep_study(
    study: SweepStudyBase,
    *,
    progress: bool = False,
    executor: Any = None,
    cache_dir: str | Path | None = None,
    resume: bool = False,
    cache_only: bool = False,
) -> SweepStudyResult:
    """Evaluate every point of a sweep study and build its tables.

    See :func:`designlab.study.run_study` for the parameters.
    """
    from designlab.report.cache import PointCache

    plan = _plan(study)
    base, metrics, sets = plan.base, plan.metrics, plan.sets
    oat_meta, range_meta = plan.oat_meta, plan.range_meta
    sobol_names, sobol_bounds = plan.sobol_names, plan.sobol_bounds
    path_of, describe = plan.path_of, plan.describe
    sens = getattr(study, "sensitivity", None)
    all_points = [p for pts in sets.values() for p in pts]
    cache = PointCache(Path(cache_dir) / study.name) if cache_dir is not None else None
    common = dict(
        executor=executor, cache=cache, resume=resume, cache_only=cache_only, progress=progress
    )
    run: SweepRun = run_points(
        all_points, study.EVALUATOR, study.evaluator_options(), desc=study.name, **common
    )
    results: dict[str, list[dict[str, Any]]] = {}
    i = 0
    for name, pts in sets.items():
        results[name] = run.results[i : i + len(pts)]
        i += len(pts)
    base_result = results["base"][0]
    base_metrics = _metrics_of(base_result, metrics)

    tables: dict[str, SensitivityTable] = {}
    stats = {
        "points": len(all_points),
        "computed": run.computed,
        "cached": run.cached,
        "corrupt": len(run.corrupt),
        "failed": len(run.failed),
        "executor": executor.describe() if executor is not None else "serial",
    }
    if sens is not None and sens.local and getattr(study, "LOCAL_EVALUATOR", None):
        local = run_points(
            [base], study.LOCAL_EVALUATOR, study.evaluator_options(), desc="elasticities", **common
        )
        stats["points"] += 1
        stats["computed"] += local.computed
        stats["cached"] += local.cached
        stats["corrupt"] += len(local.corrupt)
        stats["failed"] += len(local.failed)
        res = local.results[0]
        if res.get("status") == STATUS_ERROR:
            logger.warning("local elasticities failed: %s", res.get("error"))
        else:
            el = {
                m: {path_of.get(k, k): v for k, v in res[m].items() if k in path_of}
                for m in metrics
                if m in res
            }
            tables["elasticity"] = elasticity_table(el, describe)
    if oat_meta:
        rows = [
            (path, d, x, _metrics_of(r, metrics))
            for (path, d, x), r in zip(oat_meta, results["one_at_a_time"], strict=True)
        ]
        tables["one_at_a_time"] = one_at_a_time_table(base_metrics, rows, describe)
    if range_meta:
        rr = results["range"]
        rows = [
            (path, lo, hi, _metrics_of(rr[2 * k], metrics), _metrics_of(rr[2 * k + 1], metrics))
            for k, (path, lo, hi) in enumerate(range_meta)
        ]
        tables["range"] = range_table(base_metrics, rows, describe)
    if sobol_names:
        outputs = {m: np.array([_metrics_of(r, [m])[m] for r in results["sobol"]]) for m in metrics}
        tables["sobol"] = sobol_table(
            sobol_names, sobol_bounds, outputs, seed=sens.sobol.seed, descriptions=describe
        )

    frame = _points_frame(study, sets["sweep"], results["sweep"])
    return SweepStudyResult(study, frame, base_result, tables, stats)


def _points_frame(
    study: SweepStudyBase, points: list[dict[str, float]], results: list[dict[str, Any]]
) -> pd.DataFrame:
    cols = {key: f"{key}_{unit_slug(info.unit)}" for _, (key, info) in study.PARAMETERS.items()}
    rows = []
    for p, r in zip(points, results, strict=True):
        row: dict[str, Any] = {cols.get(k, k): v for k, v in p.items()}
        row.update({k: v for k, v in r.items() if not isinstance(v, dict)})
        rows.append(row)
    frame = pd.DataFrame(rows)
    if len(frame):
        for c in ("status", "error"):
            if c not in frame:
                frame[c] = None
        inputs = [c for c in cols.values() if c in frame]
        metrics = [m for m in study.METRICS if m in frame]
        rest = sorted(set(frame.columns) - {*inputs, *metrics, "status", "error"})
        frame = frame[[*inputs, *metrics, *rest, "status", "error"]]
    return frame
