"""Report of a sweep study: results CSV, sensitivity tables, tornado plots, Markdown.

Files written into the report directory:

``summary.md``
    Inputs (base design, swept parameters with units and ranges, sampling),
    a statistical summary of the results, the ranked sensitivity tables,
    the figures, warnings and failed points, and the command and designlab
    version that produced it.
``results.csv``
    One row per sweep point: inputs (units in the column names), metrics,
    ``status`` and ``error``.
``sensitivity_<kind>.csv``
    ``elasticity`` (local, CasADi AD), ``one_at_a_time`` (App. C form),
    ``sobol`` (SALib), ``range`` (the tornado data): long tables.
``tornado_<metric>.png``, ``sweep.png``
    Tornado plot per metric; scatter of each metric against each swept parameter.
"""

from __future__ import annotations

import textwrap
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from designlab.analysis.sensitivity import tornado_figure
from designlab.report import register_writer
from designlab.report.atomic import atomic_write_text
from designlab.report.builder import ReportParts, figure_section
from designlab.report.writers import markdown_table, write_csv
from designlab.study.points_table import FrameTable, PointsTable
from designlab.study.sweep_runner import SweepStudyResult, unit_slug

__all__ = ["sweep_markdown", "sweep_report"]

_TITLES = {
    "elasticity": "Local elasticities at the base design (CasADi automatic differentiation)",
    "one_at_a_time": "One-at-a-time perturbations (Zeng 2011 App. C form)",
    "sobol": "Global Sobol indices (SALib)",
    "range": "Parameter ranges (tornado data)",
}

_EXPLAIN = {
    "elasticity": "d ln(metric) / d ln(parameter): a 1 % larger parameter changes the metric "
    "by that many %. Exact derivatives of the model at the base design.",
    "one_at_a_time": "Each parameter alone changed by the listed percentages; "
    "S = (Δm/m0)/(Δp/p0) in %, as in Zeng 2011 eqs. C.3.1-C.3.4. Ranked by the largest "
    "|S|; the wide tables below give every perturbation.",
    "sobol": "Share of the output variance due to each parameter alone (S1) and with all its "
    "interactions (ST), parameters uniform over their ranges; `_conf` = 95 % bootstrap "
    "half-widths. Ranked by ST.",
    "range": "The metric with each swept parameter at the low and at the high end of its "
    "range, the others at the base design. Ranked by |swing|.",
}


#: Above this many points a sweep's tables go to Parquet and its figures show densities.
LARGE_SWEEP = 50_000
#: Above this many points a scatter becomes a density plot (a 2-D histogram).
DENSITY_FROM = 5_000
#: Bins of a density plot along each axis.
DENSITY_BINS = 40


def _points_or_density(ax: Any, x: Any, y: Any) -> None:
    """A scatter for a few thousand points, a density (log counts per bin) beyond.

    The density is a 2-D histogram drawn as one mesh (every point of the scan's evenly
    spread subset counted, empty bins blank): a single artist per panel, which draws far
    faster than a hexbin's thousands of polygons.
    """
    from matplotlib.colors import LogNorm

    x = pd.to_numeric(x, errors="coerce").to_numpy()
    y = pd.to_numeric(y, errors="coerce").to_numpy()
    keep = np.isfinite(x) & np.isfinite(y)
    if keep.sum() > DENSITY_FROM:
        counts, xe, ye = np.histogram2d(x[keep], y[keep], bins=DENSITY_BINS)
        shown = np.ma.masked_less(counts.T, 1)
        ax.pcolormesh(xe, ye, shown, norm=LogNorm(vmin=1), cmap="viridis", linewidth=0)
    else:
        ax.plot(x[keep], y[keep], ".", ms=3, alpha=0.6)


def _arrow_schema(table: PointsTable, head: pd.DataFrame) -> Any:
    """One Arrow schema for every row group, from the first block and the column kinds.

    ``status`` and ``error`` are strings; booleans (possibly missing) are
    boolean; any other object column is text.
    """
    import pyarrow as pa

    fields = []
    for c in table.columns:
        dtype = head[c].dtype
        if c in ("status", "error"):
            fields.append(pa.field(c, pa.string()))
        elif table.is_flag(c):
            fields.append(pa.field(c, pa.bool_()))
        elif dtype.kind == "O":
            fields.append(pa.field(c, pa.string()))
        else:
            fields.append(pa.field(c, pa.from_numpy_dtype(dtype)))
    return pa.schema(fields)


def _write_large_table(table: PointsTable, path: Path) -> list[Path]:
    """A large sweep's ``results.parquet`` at ``path`` and ``results_summary.csv`` beside it."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    # Written block by block in the same pass over the table (read from the result store
    # for a streamed sweep) as its scan: the report never holds the whole table, and the
    # report directory is swapped into place atomically, so no partial file shows.
    schema = _arrow_schema(table, next(iter(table.blocks(1))))
    text = {f.name for f in schema if f.type == pa.string()}

    def as_text(v: Any) -> Any:
        return None if v is None or v is pd.NA or v != v else str(v)

    def column(values: pd.Series, c: str) -> Any:
        if c not in text or values.dtype.kind != "O":
            return values
        # strings and missing values only (the usual status and error columns): arrow
        # converts them as they are, as the per-value ``as_text`` would, 50x faster
        if pd.api.types.infer_dtype(values, skipna=True) in ("string", "empty"):
            return values
        return values.map(as_text)

    # dictionary encoding for the text columns only: tried on every float column (arrow's
    # default) it costs about 7x the rest of the write and the file grows (distinct doubles)
    with pq.ParquetWriter(
        path, schema, compression="snappy", use_dictionary=sorted(text)
    ) as writer:

        def write(block: pd.DataFrame) -> None:
            arrays = [
                pa.array(column(block[c], c), type=schema.field(c).type, from_pandas=True)
                for c in table.columns
            ]
            writer.write_table(pa.Table.from_arrays(arrays, schema=schema))

        scan = table.scan(visit=write)
    exact = table.frame() if isinstance(table, FrameTable) else None
    return [
        path,
        write_csv(scan.summary_frame(quantiles=exact), path.parent / "results_summary.csv"),
    ]


def _readable_tornado(fig: Figure, study: Any, metric: str) -> Figure:
    """Name the metric and the parameters with their units, and draw the metric's limit."""
    ax = fig.axes[0]
    label = study.METRICS.get(metric, metric)
    ax.set_xlabel(label)
    ax.set_title(label, fontsize="medium")
    limit = dict(getattr(study, "LIMITS", {}) or {}).get(metric)
    if limit is not None:
        ax.axvline(limit, color="tab:red", lw=1, ls="--", label="design limit")
        ax.legend(fontsize="small", loc="lower right")
    names = []
    for tick in ax.get_yticklabels():
        text = tick.get_text()
        path, _, rest = text.partition("  ")
        entry = study.PARAMETERS.get(path)
        if entry is not None:
            _, info = entry
            text = f"{info.description} {rest} {info.unit}".strip()
        names.append(text)
    ax.set_yticks(ax.get_yticks(), names)
    fig.tight_layout()
    return fig


def _wrap(label: str, width: int) -> str:
    """A label broken into lines of at most ``width`` characters (it fits beside its axes)."""
    return textwrap.fill(label, width, break_long_words=False)


def _scatter_figure(result: Any) -> Figure | None:
    study = result.study
    sweep = getattr(study, "sweep", None)
    frame = result.table.scan().subset  # every row up to SUBSET_ROWS, else evenly spread
    if sweep is None or not len(frame):
        return None
    params = [p for p, _ in sweep.parameters.items()][:6]
    metrics = [m for m in result.metrics if m in frame][:4]
    if not params or not metrics:
        return None
    # a kind may declare design limits of its metrics (drawn as dashed red lines)
    limits: dict[str, float] = dict(getattr(study, "LIMITS", {}) or {})
    fig = _grid_figure(len(metrics), len(params))
    # a column is one parameter, a row one metric: shared axes draw each scale once
    axes = fig.subplots(len(metrics), len(params), squeeze=False, sharex="col", sharey="row")
    ok = frame["status"] != "error"
    for r, m in enumerate(metrics):
        for c, p in enumerate(params):
            key, info = study.PARAMETERS[p]
            col = f"{key}_{unit_slug(info.unit)}"
            ax = axes[r][c]
            _points_or_density(ax, frame.loc[ok, col], frame.loc[ok, m])
            limit = limits.get(m)
            if limit is not None:
                ax.axhline(limit, color="tab:red", lw=1, ls="--")
            if r == len(metrics) - 1:
                ax.set_xlabel(_wrap(f"{info.description} ({info.unit})", 34), fontsize="small")
            if c == 0:
                ax.set_ylabel(_wrap(study.METRICS.get(m, m), 26), fontsize="small")
            ax.tick_params(labelsize="x-small")
    fig.suptitle(f"{study.name}: {len(result.table)} points ({sweep.method})")
    return fig


#: The density grid's panel size and margins, inches: room for the wrapped labels of the
#: outer axes (fixed margins, not a layout pass that draws every text to measure it)
_PANEL, _LEFT, _RIGHT, _BOTTOM, _TOP, _GAP = (2.3, 1.9), 1.05, 0.2, 0.95, 0.45, 0.12


def _grid_figure(rows: int, cols: int) -> Figure:
    """A figure for a ``rows`` x ``cols`` grid of panels with fixed margins."""
    width = _LEFT + _RIGHT + cols * _PANEL[0] + (cols - 1) * _GAP
    height = _BOTTOM + _TOP + rows * _PANEL[1] + (rows - 1) * _GAP
    fig = Figure(figsize=(width, height))
    fig.subplots_adjust(
        left=_LEFT / width, right=1 - _RIGHT / width, bottom=_BOTTOM / height,
        top=1 - _TOP / height, wspace=_GAP / _PANEL[0], hspace=_GAP / _PANEL[1],
    )  # fmt: skip
    return fig


def _inputs_md(result: Any) -> list[str]:
    study = result.study
    base = study.base_point()
    out = ["## Inputs", "", "Base design (SI units):", ""]
    key_info = {key: (path, info) for path, (key, info) in study.PARAMETERS.items()}
    rows = [
        {"parameter": path, "symbol": key, "value": f"{base[key]:.6g}", "unit": info.unit}
        for key, (path, info) in key_info.items()
        if key in base
    ]
    out += [markdown_table(pd.DataFrame(rows)), ""]
    sweep = getattr(study, "sweep", None)
    if sweep is not None:
        how = f"method `{sweep.method}`"
        if sweep.method in ("lhs", "sobol"):
            how += f", {sweep.samples} samples, seed {sweep.seed}"
        out += [f"Sweep: {how}, {len(result.table)} points.", ""]
        rows = []
        for path, rng in sweep.parameters.items():
            info = study.PARAMETERS[path][1]
            if rng.values is not None:
                spec = ", ".join(f"{v:.6g}" for v in rng.values)
            else:
                spec = f"{rng.low:.6g} … {rng.high:.6g}"
                if rng.num:
                    spec += f" ({rng.num} points)"
                if rng.scale == "log":
                    spec += " (log)"
            rows.append({"parameter": path, "values": spec, "unit": info.unit,
                         "description": info.description})  # fmt: skip
        out += [markdown_table(pd.DataFrame(rows)), ""]
    sens = getattr(study, "sensitivity", None)
    if sens is not None:
        parts = []
        if sens.local:
            parts.append("local elasticities")
        if sens.one_at_a_time is not None:
            d = ", ".join(f"{x:+g}" for x in sens.one_at_a_time.deltas_pct)
            parts.append(f"one-at-a-time ({d} %)")
        if sens.sobol is not None:
            parts.append(f"Sobol indices (N = {sens.sobol.samples}, seed {sens.sobol.seed})")
        if sens.tornado:
            parts.append("tornado")
        out += [f"Sensitivity of {', '.join(study.metrics)}: {', '.join(parts)}.", ""]
    return out


def _min_median_max(result: Any, metric: str) -> tuple[Any, Any, Any]:
    """Exact from a table in memory; from a stored table, exact extremes, median of the subset."""
    table = result.table
    if isinstance(table, FrameTable):
        frame = table.frame()
        if metric not in frame:
            return None, None, None
        col = pd.to_numeric(frame[metric], errors="coerce")
        return col.min(), col.median(), col.max()
    scan = table.scan()
    m = scan.moments.get(metric)
    if m is None:
        return None, None, None
    return m["min"], pd.to_numeric(scan.subset[metric], errors="coerce").median(), m["max"]


def _results_md(result: Any) -> list[str]:
    table = result.table
    study = result.study
    out = ["## Results", ""]
    base = result.base
    brow = [{"metric": m, "description": study.METRICS.get(m, ""),
             "base design": _fmt(base.get(m))} for m in result.metrics]  # fmt: skip
    n = len(table)
    if n:
        for row in brow:
            lo, mid, hi = _min_median_max(result, row["metric"])
            row |= {"min": _fmt(lo), "median": _fmt(mid), "max": _fmt(hi)}
    out += [markdown_table(pd.DataFrame(brow)), ""]
    if n:
        scan = table.scan()
        n_ok = scan.status_counts.get("ok", 0)
        where = (
            "`results.csv`."
            if n <= LARGE_SWEEP
            else "`results.parquet` (columnar; `pandas.read_parquet`), summarised in "
            "`results_summary.csv`."
        )
        out += [f"{n} sweep points, {n_ok} with status `ok`. Every point, with full "
                f"precision, is in {where}", ""]  # fmt: skip
        if scan.step > 1:
            out += [
                f"Medians, quantiles and figures use every {scan.step}th point "
                f"({len(scan.subset)} points, evenly spread); counts, means, standard "
                "deviations, minima and maxima use every point.",
                "",
            ]
    return out


def _fmt(x: Any) -> str:
    try:
        v = float(x)
    except (TypeError, ValueError):
        return "–"
    return "–" if not np.isfinite(v) else f"{v:.4g}"


def sweep_markdown(result: Any, *, figures: dict[str, str]) -> str:
    """The body of the Markdown summary of a sweep study (the framework adds header and
    warnings).

    Parameters
    ----------
    result
        A :class:`~designlab.study.sweep_runner.SweepStudyResult`.
    figures
        Caption -> PNG file name of the figures to show.
    """
    st = result.stats
    out = [
        f"Points: {st.get('points', 0)} evaluated ({st.get('computed', 0)} computed, "
        f"{st.get('cached', 0)} from the cache; {st.get('failed', 0)} failed).",
        "",
    ]
    out += _inputs_md(result)
    out += _results_md(result)
    if result.sensitivity:
        out += ["## Sensitivity", ""]
        for kind, table in result.sensitivity.items():
            out += [f"### {_TITLES.get(kind, kind)}", "", _EXPLAIN.get(kind, ""), ""]
            out += [table.to_markdown(), "", f"Full table: `sensitivity_{kind}.csv`.", ""]
            if kind == "one_at_a_time":
                for m in table.metrics:
                    wide = table.percentage_table(m)
                    out += [f"**{m}: every perturbation**", "",
                            markdown_table(wide, floatfmt=".4g"), ""]  # fmt: skip
    if figures:
        out += figure_section(figures)
    return "\n".join(out)


@register_writer(SweepStudyResult)
def sweep_report(result: Any) -> ReportParts:
    """The parts of a sweep report: its points table, sensitivity tables, figures and body.

    ``results.csv``; for a large sweep ``results.parquet`` and ``results_summary.csv``.

    Parameters
    ----------
    result
        A :class:`~designlab.study.sweep_runner.SweepStudyResult`.
    """
    table: PointsTable = result.table
    tables: dict[str, pd.DataFrame] = {}
    files: dict[str, Callable[[Path], Any]] = {}
    if 0 < len(table) <= LARGE_SWEEP:
        tables["results.csv"] = table.frame()
    elif len(table):
        files["results.parquet"] = partial(_write_large_table, table)
    # indexed by parameter, unlike write_csv's tables: written as pandas prints them
    for kind, sens in result.sensitivity.items():
        files[f"sensitivity_{kind}.csv"] = partial(_write_text, sens.to_csv())
    makers: dict[str, Callable[[], Figure]] = {}
    figures: dict[str, str] = {}
    rng = result.sensitivity.get("range")
    if rng is not None:
        for m in rng.metrics:
            makers[f"tornado_{m}.png"] = partial(_tornado, rng, result.study, m)
            figures[f"tornado: {m}"] = f"tornado_{m}.png"
    scatter = _scatter_figure(result)
    if scatter is not None:
        makers["sweep.png"] = lambda: scatter
        figures["sweep: metrics against the swept parameters"] = "sweep.png"
    return ReportParts(
        body=[sweep_markdown(result, figures=figures)],
        tables=tables,
        figures=makers,
        files=files,
        no_warnings="None: every point has status `ok`.",
        cached=True,
    )


def _write_text(text: str, path: Path) -> Path:
    return atomic_write_text(path, text)


def _tornado(rng: Any, study: Any, metric: str) -> Figure:
    return _readable_tornado(tornado_figure(rng, metric), study, metric)
