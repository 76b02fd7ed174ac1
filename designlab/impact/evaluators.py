"""Chunk evaluators of the impact domain: whole chunks of designs at once (the sweep engine).

Each evaluator is a plain module-level function
``(points: dict[str, ndarray], options: dict) -> dict[str, ndarray]`` that the
sweep engine (:mod:`designlab.analysis.engine`) sends to its workers by
reference. Points are columns keyed ``M_r, C_r, K_r, K_c, C_c, lambda, M_h,
C_h, K_h, v_c`` (SI units; ``max_g`` in g for the envelope).

Examples
--------
>>> import numpy as np
>>> pts = {"M_r": np.array([9.6, 9.6]), "C_r": np.array([250.0, 250.0]),
...        "K_r": np.array([20e3, 20e3]), "K_c": np.array([24.25e3, 24.25e3]),
...        "C_c": np.array([71.9, 71.9]), "lambda": np.array([0.02, 0.02]),
...        "M_h": np.array([4.4, 4.4]), "C_h": np.array([0.0, 0.0]),
...        "K_h": np.array([4e3, 4e3]), "v_c": np.array([1.25, 0.4])}
>>> out = impact_metrics_chunk(pts, {})
>>> np.round(out["a_h_max_g"], 2).tolist(), out["status"].tolist()
([6.57, 2.1], ['ok', 'ok'])
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from designlab.impact.metric_names import ENVELOPE_COLUMNS, METRICS
from designlab.impact.model import PARAM_NAMES
from designlab.impact.parameters import HEAD_MAX, HEAD_MIN, ContactDynamics, Foam

if TYPE_CHECKING:
    from designlab.impact.envelope import FoamEnvelope
    from designlab.impact.verdict import FoamVerdict

# The engines (the compiled kernel, CasADi, the envelope solver) are imported by the
# evaluators that use them, not here: a study kind that names an evaluator, a resumed run
# that reads every point from the store and a report rebuilt from it import none of them
# (numba and the kernel modules alone are about a second of a process's start).

__all__ = [
    "ENVELOPE_METRICS",
    "IMPACT_METRICS",
    "envelope_elasticities_chunk",
    "foam_envelope_chunk",
    "impact_elasticities_chunk",
    "impact_metrics_chunk",
]

#: The model quantity behind each impact metric column (names from
#: :mod:`designlab.impact.metric_names`).
_METRIC_ATTR = {
    "a_h_max_g": "peak_head_acceleration",
    "eps_max_m": "max_compression",
    "peak_force_N": "peak_force",
    "t_imp_s": "impact_duration",
}

#: Metrics of one impact (column -> description with unit), from the one table.
IMPACT_METRICS: dict[str, str] = {c: METRICS[c].label for c in _METRIC_ATTR}

#: Metrics of a foam envelope (column -> description with unit), from the one table.
ENVELOPE_METRICS: dict[str, str] = {c: info.label for c, info in ENVELOPE_COLUMNS.items()}


def _params(points: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The model's columns: the linear model's, or a non-linear contact model's whole row
    when the points carry it (its foam shape columns; docs/impact_contact.md)."""
    from designlab.impact.contact import CONTACTS

    wider = [m.columns for m in CONTACTS.variants(linear=False) if set(m.columns) <= set(points)]
    return {k: np.asarray(points[k], dtype=float) for k in (wider[0] if wider else PARAM_NAMES)}


def impact_metrics_chunk(points: dict[str, np.ndarray], options: dict[str, Any]) -> dict[str, Any]:
    """First-lobe impact metrics of every design (:func:`designlab.impact.impact_metrics`).

    Parameters
    ----------
    points
        Columns ``M_r, C_r, K_r, K_c, C_c, M_h, C_h, K_h, v_c`` and optionally
        ``lambda`` (the foam's linear depth, for the ``bottoming`` flag).
    options
        Unused (no shared settings).
    """
    from designlab.impact.metrics import impact_metrics

    m = impact_metrics(_params(points), np.asarray(points["v_c"], dtype=float))
    eps = np.asarray(m.max_compression, dtype=float)
    depth = np.asarray(points.get("lambda", np.full(len(eps), np.inf)), dtype=float)
    out: dict[str, Any] = {
        c: np.asarray(getattr(m, a), dtype=float) for c, a in _METRIC_ATTR.items()
    }
    out["a_h_max_g"] = np.asarray(m.peak_head_acceleration_g, dtype=float)
    out["bottoming"] = eps > depth
    out["status"] = np.asarray(m.design_status, dtype=object)
    return out


impact_metrics_chunk.chunk_size = 4096  # type: ignore[attr-defined]


def impact_elasticities_chunk(
    points: dict[str, np.ndarray], options: dict[str, Any]
) -> dict[str, Any]:
    """Exact elasticities ``d ln m / d ln p`` of the impact metrics (CasADi AD).

    Returns one column ``"<metric>:<variable>"`` per metric and model variable
    (``M_r, ..., K_h, v_c``).

    Parameters
    ----------
    points
        As for :func:`impact_metrics_chunk`.
    options
        Unused.
    """
    from designlab.impact.derivatives import VARIABLE_NAMES, metric_gradients

    g = metric_gradients(_params(points), np.asarray(points["v_c"], dtype=float))
    out: dict[str, Any] = {"status": np.asarray(g.metrics.design_status, dtype=object)}
    for column, attr in _METRIC_ATTR.items():
        el = g.elasticities(attr)
        for var in VARIABLE_NAMES:
            out[f"{column}:{var}"] = np.asarray(el[var], dtype=float)
    return out


impact_elasticities_chunk.chunk_size = 256  # type: ignore[attr-defined]


def _envelopes(rows: list[dict[str, float]], damping: list[float]) -> list[FoamEnvelope]:
    """:func:`designlab.impact.foam_envelope` of every design, solved together."""
    from designlab.impact.criteria import HeadAcceleration
    from designlab.impact.envelope import foam_envelopes

    designs = [
        (
            ContactDynamics(mass=pt["M_r"], stiffness=pt["K_r"], damping=pt["C_r"]),
            pt["v_c"],
            [HeadAcceleration(max_g=pt["max_g"])],
            pt["lambda"],
        )
        for pt in rows
    ]
    return foam_envelopes(designs, np.asarray(damping, dtype=float))


def _verdicts(envs: list[FoamEnvelope], rows: list[dict[str, float]]) -> list[FoamVerdict]:
    """Each foam's verdict against its envelope, solved at the foam's own damping (together)."""
    from designlab.impact.verdict import foam_verdicts

    foams = [Foam(pt["K_c"], pt["C_c"], linear_depth=pt["lambda"]) for pt in rows]
    return foam_verdicts(envs, foams)


def _rows(points: dict[str, np.ndarray]) -> list[dict[str, float]]:
    n = len(next(iter(points.values())))
    return [{k: float(v[i]) for k, v in points.items()} for i in range(n)]


def _positive_or_nan(x: float) -> float:
    return x if math.isfinite(x) and x > 0 else math.nan


#: Designs solved together by :func:`foam_envelope_chunk` (its chunk size; see there).
_ENVELOPE_BLOCK = 128


def foam_envelope_chunk(points: dict[str, np.ndarray], options: dict[str, Any]) -> dict[str, Any]:
    """Foam envelope (Zeng 2011, Sec. 3.9) per design; boundaries and verdict at its foam.

    The boundaries and the margin are solved at the foam's own damping
    (:func:`designlab.impact.foam_verdict`); the area is over the damping grid.
    The designs are solved together, in blocks of 128: one root-finding per
    boundary over every design and damping value, with the results of
    :func:`designlab.impact.foam_envelope` and ``foam_verdict`` design by design.

    Parameters
    ----------
    points
        Columns ``M_r, C_r, K_r, v_c, max_g, lambda, K_c, C_c``.
    options
        ``{"damping": [...]}``, the C_c grid of the envelope, N s/m.
    """
    cols: dict[str, list[Any]] = {
        k: [] for k in (*ENVELOPE_METRICS, "verdict", "feasible", "empty", "status", "warnings")
    }
    rows = _rows(points)
    for start in range(0, len(rows), _ENVELOPE_BLOCK):  # bounded memory for any input:
        block = rows[start : start + _ENVELOPE_BLOCK]  # a block's envelopes go after it
        grids = _envelopes(block, options["damping"])
        for grid, fv in zip(grids, _verdicts(grids, block), strict=True):
            _append_envelope(cols, grid, fv)
    out: dict[str, Any] = {
        k: np.asarray(v, dtype=float) for k, v in cols.items() if k in ENVELOPE_METRICS
    }
    out["feasible"] = np.asarray(cols["feasible"], dtype=bool)
    out["empty"] = np.asarray(cols["empty"], dtype=bool)
    for k in ("verdict", "status", "warnings"):
        arr = np.empty(len(cols[k]), dtype=object)
        arr[:] = cols[k]
        out[k] = arr
    return out


def _append_envelope(cols: dict[str, list[Any]], grid: Any, fv: Any) -> None:
    """One design's row: the boundaries and margin at its foam, the area, the verdict."""
    margin = fv.margin_decades
    cols["k_c_max_N_per_m"].append(_positive_or_nan(fv.stiffness_max))
    cols["k_c_min_N_per_m"].append(_positive_or_nan(fv.stiffness_min))
    cols["margin_decades"].append(margin if math.isfinite(margin) else math.nan)
    cols["area_log"].append(float(grid.area(log=True)))
    cols["verdict"].append(fv.verdict)
    cols["feasible"].append(fv.feasible)
    cols["empty"].append(bool(grid.is_empty))
    cols["status"].append("empty" if grid.is_empty else "ok")
    cols["warnings"].append("; ".join((*grid.warnings, *fv.warnings)) or None)


#: The designs of a chunk are solved together (one root-finding per boundary over
#: every design and damping value), which costs ~14 ms per design (11 damping values)
#: from ~64 designs on, against ~60 ms design by design; the scan's arrays take
#: ~1.5 MB per design. 128 designs are ~2 s of work: a kill loses little and the
#: executors balance; the chunk is near the cheapest per design, and its results
#: pack to ~40 bytes per point (~52 at 32 designs).
foam_envelope_chunk.chunk_size = _ENVELOPE_BLOCK  # type: ignore[attr-defined]


def envelope_elasticities_chunk(
    points: dict[str, np.ndarray], options: dict[str, Any]
) -> dict[str, Any]:
    """Elasticities of the boundaries at the foam's damping (AD + implicit functions).

    On the upper boundary a_h,max(K*, p) = limit, so
    e(K*, p) = -e(a_h,max, p) / e(a_h,max, K_c) and e(K*, max_g) = 1 / e(a_h,max, K_c);
    likewise for the lower boundary with eps_max = lambda. Columns
    ``"<boundary>:<variable>"``.

    Parameters
    ----------
    points
        As for :func:`foam_envelope_chunk`.
    options
        Unused (the boundaries are solved at the point's own damping).
    """
    from designlab.impact.derivatives import metric_gradients

    rows = _rows(points)
    out: dict[str, Any] = {}
    for i, pt in enumerate(rows):
        (at,) = _envelopes([pt], [pt["C_c"]])
        for column, k, head, metric, limit_key in (
            ("k_c_max_N_per_m", at.stiffness_max[0], HEAD_MIN, "peak_head_acceleration", "max_g"),
            ("k_c_min_N_per_m", at.stiffness_min[0], HEAD_MAX, "max_compression", "lambda"),
        ):
            values = dict.fromkeys(("M_r", "C_r", "K_r", "C_c", "v_c", limit_key), math.nan)
            if np.isfinite(k):
                p = [pt["M_r"], pt["C_r"], pt["K_r"], k, pt["C_c"],
                     head.mass, head.damping, head.stiffness]  # fmt: skip
                el = metric_gradients([p], pt["v_c"], columns=PARAM_NAMES).elasticities(metric)
                e_k = float(el["K_c"][0])
                for var in ("M_r", "C_r", "K_r", "C_c", "v_c"):
                    values[var] = -float(el[var][0]) / e_k
                values[limit_key] = 1.0 / e_k
            for var, v in values.items():
                out.setdefault(f"{column}:{var}", np.full(len(rows), math.nan))[i] = v
    out["status"] = np.full(len(rows), "ok", dtype=object)
    return out


envelope_elasticities_chunk.chunk_size = 4  # type: ignore[attr-defined]
