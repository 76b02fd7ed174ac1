"""Evaluate many design points through an executor, with an on-disk cache.

A *point* is a plain dictionary of floats (for the impact model
``{M_r, C_r, K_r, K_c, C_c, lambda, M_h, C_h, K_h, v_c}``). An *evaluator* is
a function registered in :data:`EVALUATORS` that takes a list of points and
the options shared by all of them and returns one result dictionary per
point; it runs inside the worker and builds its models there. Points are
sent in chunks (vectorised evaluation), each result is cached as soon as its
chunk finishes, and a point that fails is recorded with ``status: error``
and its error message while the sweep goes on.

Examples
--------
>>> from designlab.analysis.sweep import run_points
>>> point = {"M_r": 9.6, "C_r": 250.0, "K_r": 20e3, "K_c": 24.25e3, "C_c": 71.9,
...          "lambda": 0.02, "M_h": 4.4, "C_h": 0.0, "K_h": 4e3, "v_c": 1.25}
>>> bad = dict(point, M_r=0.0)
>>> run = run_points([point, bad], "impact_metrics")
>>> round(run.results[0]["a_h_max_g"], 2), run.results[0]["status"]
(6.57, 'ok')
>>> run.results[1]["status"], run.results[1]["error"]
('error', 'InvalidParameterError: M_r[0] = 0.0 kg is not allowed: must be a finite number > 0')
"""

from __future__ import annotations

import logging
import math
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from designlab.errors import DesignlabError

__all__ = [
    "EVALUATORS",
    "CacheIncompleteError",
    "SweepRun",
    "evaluate_task",
    "register_evaluator",
    "run_points",
]

logger = logging.getLogger(__name__)

Point = dict[str, float]
Evaluator = Callable[[list[Point], dict[str, Any]], list[dict[str, Any]]]

#: Evaluators by name. Each takes ``(points, options)`` and returns one result
#: dict per point (JSON-compatible values; include ``status``).
EVALUATORS: dict[str, Evaluator] = {}

STATUS_ERROR = "error"


class CacheIncompleteError(DesignlabError, LookupError):
    """Rebuilding from the cache only, but some points are not in it."""


def register_evaluator(name: str) -> Callable[[Evaluator], Evaluator]:
    """Decorator: register an evaluator under ``name``."""

    def deco(fn: Evaluator) -> Evaluator:
        EVALUATORS[name] = fn
        return fn

    return deco


_IMPACT_KEYS = ("M_r", "C_r", "K_r", "K_c", "C_c", "M_h", "C_h", "K_h")


def _f(x: Any) -> float:
    return float(x)


@register_evaluator("impact_metrics")
def _impact_metrics(points: list[Point], options: dict[str, Any]) -> list[dict[str, Any]]:
    """First-lobe impact metrics (:func:`designlab.impact.impact_metrics`)."""
    from designlab.impact.metrics import impact_metrics

    p = np.array([[pt[k] for k in _IMPACT_KEYS] for pt in points], dtype=float)
    v = np.array([pt["v_c"] for pt in points], dtype=float)
    m = impact_metrics(p, v)
    out = []
    for i, pt in enumerate(points):
        eps = _f(m.max_compression[i])
        out.append(
            {
                "a_h_max_g": _f(m.peak_head_acceleration_g[i]),
                "eps_max_m": eps,
                "f_c_max_N": _f(m.peak_force[i]),
                "t_imp_s": _f(m.impact_duration[i]),
                "bottoming": bool(eps > pt.get("lambda", math.inf)),
                "status": str(m.status[i]),
                "error": None,
            }
        )
    return out


@register_evaluator("impact_elasticities")
def _impact_elasticities(points: list[Point], options: dict[str, Any]) -> list[dict[str, Any]]:
    """Elasticities of the impact metrics by CasADi AD (:mod:`designlab.impact.derivatives`)."""
    from designlab.impact.derivatives import VARIABLE_NAMES, metric_gradients

    p = np.array([[pt[k] for k in _IMPACT_KEYS] for pt in points], dtype=float)
    v = np.array([pt["v_c"] for pt in points], dtype=float)
    g = metric_gradients(p, v)
    names = {
        "peak_head_acceleration": "a_h_max_g",
        "max_compression": "eps_max_m",
        "peak_force": "f_c_max_N",
        "impact_duration": "t_imp_s",
    }
    out: list[dict[str, Any]] = [{"status": str(s), "error": None} for s in g.metrics.status]
    for metric, column in names.items():
        el = g.elasticities(metric)
        for i in range(len(points)):
            out[i][column] = {k: _f(el[k][i]) for k in VARIABLE_NAMES}
    return out


def _envelopes(pt: Point, damping: list[float]) -> tuple[Any, Any]:
    from designlab.impact import ContactDynamics, HeadAcceleration, foam_envelope

    robot = ContactDynamics(mass=pt["M_r"], stiffness=pt["K_r"], damping=pt["C_r"])
    kw = {
        "impact_velocity": pt["v_c"],
        "criteria": [HeadAcceleration(max_g=pt["max_g"])],
        "max_compression": pt["lambda"],
    }
    grid = foam_envelope(robot, damping=np.asarray(damping, dtype=float), **kw)
    at_foam = foam_envelope(robot, damping=np.array([pt["C_c"]]), **kw)
    return grid, at_foam


@register_evaluator("foam_envelope")
def _foam_envelope(points: list[Point], options: dict[str, Any]) -> list[dict[str, Any]]:
    """Foam envelope over the damping grid; boundaries and margin at the point's foam."""
    out = []
    for pt in points:
        grid, at = _envelopes(pt, options["damping"])
        kmax = _f(at.stiffness_max[0])
        kmin = _f(at.stiffness_min[0])
        with np.errstate(divide="ignore", invalid="ignore"):
            margin = min(math.log10(kmax / pt["K_c"]), math.log10(pt["K_c"] / kmin))
        out.append(
            {
                "k_c_max_N_per_m": kmax,
                "k_c_min_N_per_m": kmin,
                "margin_decades": margin if math.isfinite(margin) else math.nan,
                "area_log": _f(grid.area(log=True)),
                "feasible": bool(np.isfinite(margin) and margin > 0),
                "empty": bool(grid.is_empty),
                "status": "empty" if grid.is_empty else "ok",
                "error": None,
                "warnings": "; ".join(grid.warnings) or None,
            }
        )
    return out


@register_evaluator("envelope_elasticities")
def _envelope_elasticities(points: list[Point], options: dict[str, Any]) -> list[dict[str, Any]]:
    """Elasticities of the boundaries at the foam's damping (AD + implicit functions).

    On the upper boundary a_h,max(K*, p) = limit, so
    e(K*, p) = -e(a_h,max, p) / e(a_h,max, K_c) and e(K*, max_g) = 1 / e(a_h,max, K_c);
    likewise for the lower boundary with eps_max = lambda.
    """
    from designlab.impact import HEAD_MAX, HEAD_MIN
    from designlab.impact.derivatives import metric_gradients

    out = []
    for pt in points:
        _, at = _envelopes(pt, [pt["C_c"]])
        res: dict[str, Any] = {"status": "ok", "error": None}
        for column, k, head, metric, limit_key in (
            ("k_c_max_N_per_m", at.stiffness_max[0], HEAD_MIN, "peak_head_acceleration", "max_g"),
            ("k_c_min_N_per_m", at.stiffness_min[0], HEAD_MAX, "max_compression", "lambda"),
        ):
            if not np.isfinite(k):
                res[column] = {}
                continue
            p = [pt["M_r"], pt["C_r"], pt["K_r"], k, pt["C_c"],
                 head.mass, head.damping, head.stiffness]  # fmt: skip
            el = metric_gradients(p, pt["v_c"]).elasticities(metric)
            e_k = _f(el["K_c"][0])
            res[column] = {
                "M_r": -_f(el["M_r"][0]) / e_k,
                "C_r": -_f(el["C_r"][0]) / e_k,
                "K_r": -_f(el["K_r"][0]) / e_k,
                "C_c": -_f(el["C_c"][0]) / e_k,
                "v_c": -_f(el["v_c"][0]) / e_k,
                limit_key: 1.0 / e_k,
            }
        out.append(res)
    return out


def evaluate_task(task: dict[str, Any]) -> list[dict[str, Any]]:
    """Evaluate one chunk: ``{"evaluator": name, "options": {...}, "points": [...]}``.

    Runs in the worker. If the vectorised evaluation of the chunk fails, each
    point is evaluated on its own so that only the failing ones are marked
    ``status: error`` (with the exception's type and message).
    """
    fn = EVALUATORS[task["evaluator"]]
    points = task["points"]
    options = task.get("options", {})
    try:
        return fn(points, options)
    except Exception as exc:
        if len(points) == 1:
            return [{"status": STATUS_ERROR, "error": f"{type(exc).__name__}: {exc}"}]
    out = []
    for pt in points:
        out.extend(evaluate_task({**task, "points": [pt]}))
    return out


@dataclass
class SweepRun:
    """Results of :func:`run_points`, in the order of the points.

    Attributes
    ----------
    points, results
        Equal-length lists of plain dicts.
    computed, cached
        How many distinct points were computed now / read from the cache.
    corrupt
        Keys of cache entries found corrupt (and recomputed).
    """

    points: list[Point]
    results: list[dict[str, Any]]
    computed: int = 0
    cached: int = 0
    corrupt: list[str] = field(default_factory=list)

    @property
    def failed(self) -> list[int]:
        """Indices of points whose evaluation raised."""
        return [i for i, r in enumerate(self.results) if r.get("status") == STATUS_ERROR]


def _chunks(items: list[Any], size: int) -> list[list[Any]]:
    return [items[i : i + size] for i in range(0, len(items), size)]


def run_points(
    points: Sequence[Point],
    evaluator: str,
    options: dict[str, Any] | None = None,
    *,
    executor: Any = None,
    cache: Any = None,
    resume: bool = False,
    cache_only: bool = False,
    progress: bool = False,
    chunk_size: int | None = None,
    desc: str = "points",
) -> SweepRun:
    """Evaluate ``points`` with a registered evaluator.

    Parameters
    ----------
    points
        Plain point dictionaries.
    evaluator
        Name in :data:`EVALUATORS`.
    options
        Evaluator settings shared by all points (part of the cache key).
    executor
        An :class:`~designlab.analysis.executors.Executor` (default: serial).
    cache
        A :class:`~designlab.report.cache.PointCache`; every finished point
        is stored in it.
    resume
        Reuse cached points (only the missing ones are computed).
    cache_only
        Do not compute anything; raise :class:`CacheIncompleteError` if a
        point is not cached.
    progress
        Show a tqdm bar on stderr.
    chunk_size
        Points per task (default: about 8 tasks per worker, at most 64).
    """
    from tqdm.auto import tqdm

    from designlab.analysis.executors import SerialExecutor

    if evaluator not in EVALUATORS:
        raise KeyError(f"unknown evaluator {evaluator!r} (known: {', '.join(EVALUATORS)})")
    options = dict(options or {})
    points = [dict(p) for p in points]
    keys = [cache.key(evaluator, options, p) if cache is not None else None for p in points]
    results: list[dict[str, Any] | None] = [None] * len(points)
    run = SweepRun(points, [])

    # distinct points still to compute (identical points share one evaluation)
    todo: dict[Any, list[int]] = {}
    done: dict[Any, dict[str, Any]] = {}
    for i, (_p, key) in enumerate(zip(points, keys, strict=True)):
        ident = key if key is not None else i
        if ident in todo:
            todo[ident].append(i)
            continue
        if ident in done:
            results[i] = done[ident]
            continue
        if cache is not None and (resume or cache_only):
            state, value = cache.get(key)
            if state == "ok":
                results[i] = done[ident] = value
                run.cached += 1
                continue
            if state == "corrupt":
                logger.warning("corrupt cache entry %s (%s): recomputing", cache.path(key), value)
                run.corrupt.append(key)
                cache.discard(key)
        todo[ident] = [i]
    if cache_only and todo:
        raise CacheIncompleteError(
            f"{len(todo)} point{'s' if len(todo) != 1 else ''} of {desc} "
            f"{'are' if len(todo) != 1 else 'is'} not in the cache "
            f"{cache.root if cache is not None else '(none given)'}; run the study "
            "(designlab run ... --resume) to compute them"
        )

    order = list(todo)
    if order:
        ex = executor if executor is not None else SerialExecutor()
        workers = max(1, getattr(ex, "workers", 1))
        size = chunk_size or max(1, min(64, math.ceil(len(order) / (8 * workers))))
        groups = _chunks(order, size)
        tasks = [
            {"evaluator": evaluator, "options": options, "points": [points[todo[k][0]] for k in g]}
            for g in groups
        ]
        bar = tqdm(
            total=len(order), desc=desc, unit="pt", file=sys.stderr, disable=not progress,
            leave=False,
        )  # fmt: skip
        try:
            for t, out in ex.map_unordered(evaluate_task, tasks):
                for ident, res in zip(groups[t], out, strict=True):
                    idx = todo[ident]
                    if cache is not None:
                        cache.put(keys[idx[0]], points[idx[0]], res)
                    for i in idx:
                        results[i] = res
                run.computed += len(out)
                bar.update(len(out))
        finally:
            bar.close()
    run.results = [r if r is not None else {} for r in results]
    for i in run.failed:
        logger.warning("point %d failed: %s", i, run.results[i].get("error"))
    return run
