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

from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from designlab.analysis.sensitivity import tornado_figure
from designlab.report import register_writer
from designlab.report.atomic import atomic_write_text
from designlab.report.writers import markdown_table, write_csv, write_markdown, write_png
from designlab.study.sweep_runner import SweepStudyResult

__all__ = ["sweep_markdown", "write_sweep_report"]

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
#: Above this many points a scatter becomes a hexbin density plot.
DENSITY_FROM = 5_000
#: At most this many (evenly spread) points are binned into a density plot: at
#: 40 hexagons across, 50 000 points already fix every visible shade.
DENSITY_SAMPLE = 50_000
#: Rows per Parquet row group (and per Arrow conversion).
PARQUET_ROW_GROUP = 131_072


def _points_or_density(ax: Any, x: Any, y: Any) -> None:
    """A scatter for a few thousand points, a hexbin density (log counts) beyond."""
    x = pd.to_numeric(x, errors="coerce").to_numpy()
    y = pd.to_numeric(y, errors="coerce").to_numpy()
    keep = np.isfinite(x) & np.isfinite(y)
    if keep.sum() > DENSITY_FROM:
        idx = np.flatnonzero(keep)
        if len(idx) > DENSITY_SAMPLE:  # a fixed, evenly spread subset draws the same density
            idx = idx[:: len(idx) // DENSITY_SAMPLE + 1]
        ax.hexbin(x[idx], y[idx], gridsize=40, bins="log", mincnt=1, cmap="viridis",
                  linewidths=0)  # fmt: skip
    else:
        ax.plot(x[keep], y[keep], ".", ms=3, alpha=0.6)


def _summary_frame(frame: pd.DataFrame) -> pd.DataFrame:
    """Per numeric column: count, mean, std, min, quantiles, max; and the status counts."""
    numeric = frame.select_dtypes(include=["number"])
    table = numeric.describe(percentiles=[0.01, 0.05, 0.25, 0.5, 0.75, 0.95, 0.99]).T
    table.insert(0, "column", table.index)
    counts = frame["status"].value_counts() if "status" in frame else pd.Series(dtype=int)
    extra = pd.DataFrame({"column": [f"status={k}" for k in counts.index],
                          "count": counts.to_numpy(dtype=float)})  # fmt: skip
    return pd.concat([table.reset_index(drop=True), extra], ignore_index=True)


def _write_table(frame: pd.DataFrame, directory: Path) -> list[Path]:
    """``results.csv``; for a large sweep ``results.parquet`` and ``results_summary.csv``."""
    if len(frame) <= LARGE_SWEEP:
        return [write_csv(frame, directory / "results.csv")]
    import pyarrow as pa
    import pyarrow.parquet as pq

    # Written in row groups straight from the frame: the Arrow copy is one row
    # group at a time, not the whole table (the report directory itself is
    # swapped into place atomically, so no partial file is ever visible).
    path = directory / "results.parquet"
    text = [c for c in ("status", "error") if c in frame]
    fields = []
    for c in frame.columns:  # status and error always strings, even when all None
        if c in text:
            fields.append(pa.field(c, pa.string()))
        elif frame[c].dtype == object:  # e.g. booleans with None: infer from the whole column
            fields.append(pa.field(c, pa.array(frame[c], from_pandas=True).type))
        else:
            fields.append(pa.field(c, pa.from_numpy_dtype(frame[c].dtype)))
    schema = pa.schema(fields)
    with pq.ParquetWriter(path, schema, compression="snappy") as writer:
        for start in range(0, len(frame), PARQUET_ROW_GROUP):
            part = frame.iloc[start : start + PARQUET_ROW_GROUP]
            writer.write_table(pa.Table.from_pandas(part, schema=schema, preserve_index=False))
    return [
        path,
        write_csv(_summary_frame(frame), directory / "results_summary.csv"),
    ]


def _scatter_figure(result: Any) -> Figure | None:
    study = result.study
    sweep = getattr(study, "sweep", None)
    frame = result.frame
    if sweep is None or not len(frame):
        return None
    from designlab.study.sweep_runner import unit_slug

    params = [p for p, _ in sweep.parameters.items()][:6]
    metrics = [m for m in result.metrics if m in frame][:4]
    if not params or not metrics:
        return None
    fig = Figure(figsize=(2.6 * len(params) + 0.6, 2.2 * len(metrics) + 0.6))
    axes = fig.subplots(len(metrics), len(params), squeeze=False)
    ok = frame["status"] != "error"
    for r, m in enumerate(metrics):
        for c, p in enumerate(params):
            key, info = study.PARAMETERS[p]
            col = f"{key}_{unit_slug(info.unit)}"
            ax = axes[r][c]
            _points_or_density(ax, frame.loc[ok, col], frame.loc[ok, m])
            if r == len(metrics) - 1:
                ax.set_xlabel(f"{p} ({info.unit})", fontsize="small")
            if c == 0:
                ax.set_ylabel(m, fontsize="small")
            ax.tick_params(labelsize="x-small")
    fig.suptitle(f"{study.name}: {len(frame)} points ({sweep.method})")
    fig.tight_layout()
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
        out += [f"Sweep: {how}, {len(result.frame)} points.", ""]
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
        out += [f"Sensitivity of {', '.join(sens.metrics)}: {', '.join(parts)}.", ""]
    return out


def _results_md(result: Any) -> list[str]:
    frame = result.frame
    study = result.study
    out = ["## Results", ""]
    base = result.base
    brow = [{"metric": m, "description": study.METRICS.get(m, ""),
             "base design": _fmt(base.get(m))} for m in result.metrics]  # fmt: skip
    if len(frame):
        for row in brow:
            col = pd.to_numeric(frame[row["metric"]], errors="coerce")
            row |= {
                "min": _fmt(col.min()),
                "median": _fmt(col.median()),
                "max": _fmt(col.max()),
            }
    out += [markdown_table(pd.DataFrame(brow)), ""]
    if len(frame):
        n_ok = int((frame["status"] == "ok").sum())
        out += [
            f"{len(frame)} sweep points, {n_ok} with status `ok`. Every point, with full "
            "precision, is in "
            + (
                "`results.csv`."
                if len(frame) <= LARGE_SWEEP
                else "`results.parquet` (columnar; `pandas.read_parquet`), summarised in "
                "`results_summary.csv`."
            ),
            "",
        ]
    return out


def _fmt(x: Any) -> str:
    try:
        v = float(x)
    except (TypeError, ValueError):
        return "–"
    return "–" if not np.isfinite(v) else f"{v:.4g}"


def sweep_markdown(
    result: Any,
    *,
    figures: dict[str, str],
    command: str | None = None,
    version: str | None = None,
) -> str:
    """The Markdown summary of a sweep study.

    Parameters
    ----------
    result
        A :class:`~designlab.study.sweep_runner.SweepStudyResult`.
    figures
        Caption -> PNG file name of the figures to show.
    command
        The command line that produced the result.
    version
        The designlab version.
    """
    study = result.study
    out = [f"# {study.name}", ""]
    if study.description:
        out += [study.description.strip(), ""]
    produced = "Produced by " + (f"`{command}`" if command else "designlab")
    if version:
        produced += f" with designlab {version}"
    st = result.stats
    out += [
        f"{produced}. Generated file: edit the study, not this report, and regenerate "
        "it with the same command (`designlab report` rebuilds it from the cache).",
        "",
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
        out += ["## Figures", ""]
        for caption, name in figures.items():
            out += [f"![{caption}]({name})", ""]
    out += ["## Warnings", ""]
    warnings = result.warnings
    out += [f"- {w}" for w in warnings] if warnings else ["None: every point has status `ok`."]
    return "\n".join(out)


@register_writer(SweepStudyResult)
def write_sweep_report(
    result: Any,
    directory: Path,
    *,
    command: str | None = None,
    version: str | None = None,
    study_text: str | None = None,
) -> list[Path]:
    """Write every file of a sweep report into ``directory`` (which must exist).

    Parameters
    ----------
    result
        A :class:`~designlab.study.sweep_runner.SweepStudyResult`.
    directory
        The (new, empty) report directory.
    command
        The command line that produced the result.
    version
        The designlab version.
    study_text
        The study file's text, copied as ``study.yaml``.
    """
    written = []
    if len(result.frame):
        written += _write_table(result.frame, directory)
    figures: dict[str, str] = {}
    for kind, table in result.sensitivity.items():
        written.append(atomic_write_text(directory / f"sensitivity_{kind}.csv", table.to_csv()))
    rng = result.sensitivity.get("range")
    if rng is not None:
        for m in rng.metrics:
            name = f"tornado_{m}.png"
            written.append(write_png(tornado_figure(rng, m), directory / name))
            figures[f"tornado: {m}"] = name
    fig = _scatter_figure(result)
    if fig is not None:
        written.append(write_png(fig, directory / "sweep.png"))
        figures["sweep: metrics against the swept parameters"] = "sweep.png"
    text = sweep_markdown(result, figures=figures, command=command, version=version)
    written.append(write_markdown(text, directory / "summary.md"))
    if study_text is not None:
        written.append(atomic_write_text(directory / "study.yaml", study_text))
    return written
