"""Report of an ``impact_cases`` study: metrics CSV, Markdown summary, PNG time histories.

Files written into the report directory:

``metrics.csv``
    One row per case: model metrics, reference and experimental values,
    errors (see :meth:`designlab.study.kinds.impact_cases.ImpactCasesResult.to_frame`).
``summary.md``
    Inputs, model vs reference and vs experiment tables, warnings, the figures
    (the report framework adds the header, provenance and reproduction).
``time_histories[_<group>].png``
    Force, head acceleration and foam compression against time, one figure
    per case group.
``study.yaml``
    The study file as it was run (when given).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import partial
from typing import Any

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from designlab.report import register_writer
from designlab.report.builder import ReportParts, figure_section, slug
from designlab.report.writers import markdown_table
from designlab.study.kinds.impact_cases import ImpactCaseResult, ImpactCasesResult
from designlab.units import STANDARD_GRAVITY

__all__ = ["impact_figure", "impact_markdown", "impact_report"]

#: A two-case study used by the examples below.
_EXAMPLE = """
designlab: 1
kind: impact_cases
name: demo
cases:
  - {label: slow, robot: MANIPULATOR_1, foam: FOAM_1, head: TEST_HEAD, impact_velocity: 0.4,
     reference: {source: Zeng 2011 Table 4.1, a_h_max_g: 2.1, t_imp_s: 0.033}}
  - {label: fast, robot: MANIPULATOR_1, foam: FOAM_1, head: TEST_HEAD, impact_velocity: 1.25}
"""

G = STANDARD_GRAVITY


def _groups(result: ImpactCasesResult) -> dict[str, list[ImpactCaseResult]]:
    groups: dict[str, list[ImpactCaseResult]] = {}
    for c in result.cases:
        groups.setdefault(c.group, []).append(c)
    return groups


def figure_names(result: ImpactCasesResult) -> dict[str, str]:
    """PNG file name of each case group."""
    groups = _groups(result)
    if len(groups) == 1:
        return {next(iter(groups)): "time_histories.png"}
    names: dict[str, str] = {}
    for g in groups:
        base = f"time_histories_{slug(g, 'all')}"
        name, n = f"{base}.png", 2
        while name in names.values():
            name, n = f"{base}_{n}.png", n + 1
        names[g] = name
    return names


_STYLES = ("-", "--", "-.", ":")


def _config_key(c: ImpactCaseResult) -> tuple[Any, ...]:
    return (c.robot.mass, c.robot.stiffness, c.robot.damping, c.foam, c.head)


def impact_figure(cases: Sequence[ImpactCaseResult], title: str = "") -> Figure:
    """Force, head acceleration and compression of several cases, stacked.

    Colour distinguishes the parameter set (robot, foam, head); line style the
    closing speed. Curves are drawn over the first impact lobe and a little
    beyond; a dot marks the end of each impact period (the first lobe,
    docs/impact.md, "Metrics").

    Parameters
    ----------
    cases
        Results of the cases to overlay.
    title
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        A figure not attached to pyplot (no global state); write it with
        :func:`designlab.report.writers.write_png`.

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> r = run_study(parse_study(_EXAMPLE))
    >>> len(impact_figure(r.cases).axes)
    3
    """
    configs: list[tuple[Any, ...]] = []
    speeds: list[float] = []
    for c in cases:
        if _config_key(c) not in configs:
            configs.append(_config_key(c))
        if c.closing_velocity not in speeds:
            speeds.append(c.closing_velocity)
    speeds.sort(reverse=True)

    durations = [float(c.response.impact_duration) for c in cases]
    finite = [d for d in durations if math.isfinite(d) and d > 0]
    t_end = 1.3 * max(finite) if finite else None

    fig = Figure(figsize=(10, 10), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    colours = [f"C{i % 10}" for i in range(len(configs))]
    for c in cases:
        colour = colours[configs.index(_config_key(c))]
        style = _STYLES[speeds.index(c.closing_velocity) % len(_STYLES)]
        _plot_case(axes, c, t_end, colour, style)
    _label_axes(axes, cases, t_end)
    fig.legend(loc="outside lower center", ncols=2, fontsize=8.5, frameon=False)
    suptitle = title or "Impact time histories"
    fig.suptitle(
        f"{suptitle}\n(colour: parameter set, line style: closing speed, "
        "dot: end of impact period)",
        fontsize=10,
    )
    return fig


def _plot_case(
    axes: Any, c: ImpactCaseResult, t_end: float | None, colour: str, style: Any
) -> None:
    """Force, a_h and compression of one case on the three axes, with the end-of-impact dot."""
    r = c.response
    t = np.asarray(r.t, dtype=float)
    keep = t <= t_end if t_end is not None else np.ones_like(t, dtype=bool)
    series = (
        np.asarray(r.force, dtype=float),
        np.asarray(r.head_acceleration, dtype=float) / G,
        np.asarray(r.compression, dtype=float) * 1e3,
    )
    t_imp = float(r.impact_duration)
    for ax, y in zip(axes, series, strict=True):
        ax.plot(
            t[keep] * 1e3,
            y[keep],
            color=colour,
            linestyle=style,
            linewidth=1.6,
            label=c.title if ax is axes[0] else None,
        )
        if math.isfinite(t_imp) and t.size:
            ax.plot(t_imp * 1e3, np.interp(t_imp, t, y), "o", color=colour, markersize=4)


def _label_axes(axes: Any, cases: Sequence[ImpactCaseResult], t_end: float | None) -> None:
    """Axis labels, grids, the time window and the foam's linear depth (one foam only)."""
    ylabels = ("contact force $f_c$ (N)", "head acceleration $a_h$ (g)", "compression (mm)")
    for ax, label in zip(axes, ylabels, strict=True):
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.35)
        ax.axhline(0.0, color="0.3", linewidth=0.8)
    axes[-1].set_xlabel("time since contact (ms)")
    if t_end is not None:
        axes[-1].set_xlim(0.0, t_end * 1e3)
    lambdas = {c.foam.linear_depth for c in cases}
    if len(lambdas) == 1:
        lam = lambdas.pop() * 1e3
        axes[2].axhline(lam, color="firebrick", linestyle=":", linewidth=1.2)
        axes[2].annotate(
            f"foam linear range $\\lambda$ = {lam:g} mm",
            (0.01, lam),
            xycoords=("axes fraction", "data"),
            va="bottom",
            fontsize=8,
            color="firebrick",
        )


def _fmt(value: Any, spec: str) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "–"
    return format(value, spec)


def _inputs_table(result: ImpactCasesResult) -> str:
    rows = []
    for c in result.cases:
        rows.append(
            {
                "case": c.title,
                "M_r (kg)": _fmt(c.robot.mass, "g"),
                "K_r (kN/m)": _fmt(c.robot.stiffness / 1e3, "g"),
                "C_r (N s/m)": _fmt(c.robot.damping, "g"),
                "K_c (kN/m)": _fmt(c.foam.stiffness / 1e3, "g"),
                "C_c (N s/m)": _fmt(c.foam.damping, "g"),
                "λ (mm)": _fmt(c.foam.linear_depth * 1e3, "g"),
                "M_h (kg)": _fmt(c.head.mass, "g"),
                "K_h (kN/m)": _fmt(c.head.stiffness / 1e3, "g"),
                "C_h (N s/m)": _fmt(c.head.damping, "g"),
                "v_r, v_h (m/s)": (
                    f"{c.case.v_r:g}, {c.case.v_h:g}" if c.case.v_r is not None else "–"
                ),
                "v_c (m/s)": _fmt(c.closing_velocity, "g"),
            }
        )
    return _text_table(rows)


def _text_table(rows: list[dict[str, str]]) -> str:
    """Markdown table of preformatted cells: first column left, the others right."""
    frame = pd.DataFrame(rows)
    align = ("left",) + ("right",) * (frame.shape[1] - 1)
    return markdown_table(frame, disable_numparse=True, colalign=align)


def _notes(result: ImpactCasesResult) -> dict[str, int]:
    """Number of each distinct reference note (1, 2, ...), by note text."""
    notes: dict[str, int] = {}
    for c in result.cases:
        ref = c.case.reference
        if ref is not None and ref.note and ref.note not in notes:
            notes[ref.note] = len(notes) + 1
    return notes


def _comparison_table(
    frame: pd.DataFrame, prefix: str, marks: list[str] | None = None
) -> str | None:
    """Model vs ``ref_`` (prefix "ref") or ``exp_`` (prefix "exp") values."""
    err = "err" if prefix == "ref" else "err_exp"
    cols = [f"{prefix}_a_h_max_g", f"{prefix}_t_imp_s", f"{prefix}_eps_max_m"]
    if frame[cols].isna().all().all():
        return None
    rows = []
    for i, (_, row) in enumerate(frame.iterrows()):
        mark = marks[i] if marks else ""
        out = {
            "case": row["case"] + mark,
            "a_h,max model (g)": _fmt(row["a_h_max_g"], ".2f"),
            f"a_h,max {prefix} (g)": _fmt(row[f"{prefix}_a_h_max_g"], ".2f"),
            "a_h,max err (%)": _fmt(row[f"{err}_a_h_max_pct"], "+.1f"),
            "t_imp model (ms)": _fmt(row["t_imp_s"] * 1e3, ".1f"),
            f"t_imp {prefix} (ms)": _fmt(row[f"{prefix}_t_imp_s"] * 1e3, ".1f"),
            "Δt_imp (ms)": _fmt(row[f"{err}_t_imp_s"] * 1e3, "+.1f"),
            "eps_max model (mm)": _fmt(row["eps_max_m"] * 1e3, ".2f"),
            f"eps_max {prefix} (mm)": _fmt(row[f"{prefix}_eps_max_m"] * 1e3, ".2f"),
            "eps_max err (%)": _fmt(row[f"{err}_eps_max_pct"], "+.1f"),
        }
        if prefix == "ref":
            out["F_peak (N)"] = _fmt(row["peak_force_N"], ".1f")
            out["HIC15"] = _fmt(row["hic15"], ".3g")
            within = row["within_tolerance"]
            out["within tolerance"] = (
                "–" if within is None or within is pd.NA else ("yes" if within else "**NO**" + mark)
            )
        rows.append(out)
    return _text_table(rows)


def _tolerance_text(result: ImpactCasesResult) -> str:
    tols = {}
    for c in result.cases:
        ref = c.case.reference
        if ref is not None and ref.tolerance is not None:
            t = ref.tolerance
            parts = []
            if t.a_h_max_rel is not None:
                parts.append(f"a_h,max within {100 * t.a_h_max_rel:g} %")
            if t.t_imp_abs_s is not None:
                parts.append(f"t_imp within {1e3 * t.t_imp_abs_s:g} ms")
            if t.eps_max_rel is not None:
                parts.append(f"eps_max within {100 * t.eps_max_rel:g} %")
            tols.setdefault(", ".join(parts), []).append(c.group or c.title)
    if not tols:
        return ""
    lines = ["Tolerances of the model against the reference simulation:", ""]
    for text, names in tols.items():
        where = "; ".join(dict.fromkeys(names))  # unique, in order
        lines.append(f"- {where}: {text}")
    return "\n".join(lines)


def impact_markdown(result: ImpactCasesResult) -> str:
    """The body of the Markdown summary of an ``impact_cases`` study.

    Parameters
    ----------
    result
        The study result.

    Returns
    -------
    str
        Markdown (the report framework adds the header and the warnings).

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> r = run_study(parse_study(_EXAMPLE))
    >>> "## Model vs reference simulation" in impact_markdown(r)
    True
    """
    frame = result.to_frame()
    out = [
        "Model: linear coupled manipulator-foam-head impact (Zeng 2011, Sec. 3.5); "
        'metrics over the first impact lobe (docs/impact.md, "Metrics"); g is standard '
        "gravity, 9.80665 m/s^2. "
        "`ref` = reference simulation, `exp` = experimental mean; errors are "
        "(model − reference) / reference. Full precision in `metrics.csv`.",
        "",
        "## Inputs",
        "",
        _inputs_table(result),
        "",
    ]
    sources = sorted(
        {c.case.reference.source for c in result.cases if c.case.reference is not None} - {None}  # type: ignore[arg-type]
    )
    notes = _notes(result)
    marks = [
        f" [{notes[c.case.reference.note]}]"
        if c.case.reference is not None and c.case.reference.note
        else ""
        for c in result.cases
    ]
    ref_table = _comparison_table(frame, "ref", marks)
    if ref_table is not None:
        out += ["## Model vs reference simulation", ""]
        if sources:
            out += ["Reference: " + "; ".join(str(s) for s in sources) + ".", ""]
        out += [ref_table, ""]
        out += [f"[{n}] {text.strip()}" for text, n in notes.items()]
        if notes:
            out.append("")
        tol = _tolerance_text(result)
        if tol:
            out += [tol, ""]
    exp_table = _comparison_table(frame, "exp")
    if exp_table is not None:
        out += ["## Model vs experiment (means of the trials)", "", exp_table, ""]
    if ref_table is None and exp_table is None:
        cols = ["case", "v_c_m_per_s", "a_h_max_g", "t_imp_s", "eps_max_m", "peak_force_N", "hic15"]
        out += ["## Results", "", markdown_table(frame[cols], floatfmt=".4g"), ""]
    return "\n".join(out)


@register_writer(ImpactCasesResult)
def impact_report(result: ImpactCasesResult) -> ReportParts:
    """The report's parts: ``metrics.csv``, the summary's body, the time histories.

    Parameters
    ----------
    result
        The study result.

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> parts = impact_report(run_study(parse_study(_EXAMPLE)))
    >>> list(parts.tables), list(parts.figures)
    (['metrics.csv'], ['time_histories.png'])
    """
    names = figure_names(result)
    groups = _groups(result)
    figures = {
        name: partial(
            impact_figure, groups[group], title=f"{result.study.name}: {group or 'all cases'}"
        )
        for group, name in names.items()
    }
    shown = [(group or "all cases", name) for group, name in names.items()]
    return ReportParts(
        body=[impact_markdown(result)],
        tables={"metrics.csv": result.to_frame()},
        figures=figures,
        no_warnings="None: every case has status `ok`.",
        closing=figure_section(shown, title="Time histories"),
    )
