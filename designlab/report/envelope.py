"""Report of a ``foam_design`` study: envelope.md, envelope.csv, verdicts.csv, envelope.png.

The figure follows Zeng 2011, Figs. 3.18/3.19: foam stiffness against foam
damping, the upper (safety) and lower (thickness) boundaries, the feasible
region shaded, and the foams (with their verdicts) and the optimal foam marked.
The writer only formats: every verdict, margin and check comes with the result
(:class:`~designlab.study.kinds.foam_design.FoamDesignResult`); nothing is
solved here.

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> result = run_study(parse_study(_EXAMPLE))
>>> text = envelope_markdown(result)
>>> "exceeds the upper (safety) boundary by 1.0 %" in text
True
"""

from __future__ import annotations

import math
from functools import partial

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from designlab.report import register_writer
from designlab.report.builder import ReportParts, figure_section
from designlab.report.writers import markdown_table
from designlab.study.kinds.foam_design import FoamDesignResult, RobotDesign

__all__ = ["envelope_figure", "envelope_markdown", "envelope_report"]

#: The small study of the examples.
_EXAMPLE = """
designlab: 1
kind: foam_design
name: demo
robots: [MANIPULATOR_1]
foams: [FOAM_3]
damping: {low: 20, high: 100, num: 5}
optimal: false
worst_case_check: false
"""

_MARKERS = ("o", "s", "^", "D", "v", "P", "X")
_VERDICT_FILL = {"feasible": "black", "on the boundary": "tab:orange", "not feasible": "white"}
#: head mass of the thesis's damping-ratio convention, C_c = 2 xi_c sqrt(M_h K_c)
_XI_HEAD_MASS = 4.4


def _kn_per_m(y: float, _pos: object = None) -> str:
    """Tick label of a stiffness axis in kN/m (plain numbers, no powers of ten)."""
    return f"{y:g}"


def _panel(ax: Axes, result: FoamDesignResult, d: RobotDesign) -> None:
    """One robot: region, boundaries, delicate points, foams (with verdicts), optimum."""
    env = d.envelope
    c = env.damping
    kmin, kmax = env._effective()
    lo_b, hi_b = env.stiffness_bounds
    ax.fill_between(
        c, np.clip(kmin, lo_b, hi_b) / 1e3, np.clip(kmax, lo_b, hi_b) / 1e3,
        where=kmin <= kmax, color="tab:green", alpha=0.18, label="feasible region",
    )  # fmt: skip
    ax.plot(c, env.stiffness_max / 1e3, color="tab:red", lw=2, label="upper boundary (safety)")
    if len(env.upper) > 1:
        for k in env.upper.values():
            ax.plot(c, k / 1e3, color="tab:red", lw=0.8, ls=":", alpha=0.8)
    ax.plot(c, env.stiffness_min / 1e3, color="tab:blue", lw=2, label="lower boundary (thickness)")
    if np.any(env.delicate):
        ax.plot(c[env.delicate], env.stiffness_min[env.delicate] / 1e3, "x", color="gray",
                ms=5, label="delicate first lobe")  # fmt: skip
    if d.check is not None:
        for name, ratio in d.check.ratio_by_point.items():
            bad = np.nan_to_num(ratio, nan=0.0) > 1 + d.check.tolerance
            if not np.any(bad):
                continue
            kb = env.stiffness_min if d.check.boundary[name] == "lower" else env.upper[name]
            ax.plot(c[bad], kb[bad] / 1e3, "o", ms=7, mfc="none", mec="tab:red",
                    label=f"worst case exceeds {name}")  # fmt: skip
    for j, (foam, fv) in enumerate(zip(result.foams, d.verdicts, strict=True)):
        ax.plot(
            foam.damping, foam.stiffness / 1e3, _MARKERS[j % len(_MARKERS)], ms=8,
            mfc=_VERDICT_FILL[fv.verdict], mec="black", label=f"{foam.name}: {fv.verdict}",
        )  # fmt: skip
    if d.optimal is not None and not d.optimal.status.startswith("solver_failed"):
        ax.plot(d.optimal.damping, d.optimal.stiffness / 1e3, "*", ms=14, color="gold",
                mec="black", label=f"optimal foam ({d.optimal.status})")  # fmt: skip
    ax.set_yscale("log")
    ax.yaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 3.0, 5.0)))
    ax.yaxis.set_major_formatter(FuncFormatter(_kn_per_m))
    ax.yaxis.set_minor_locator(LogLocator(base=10, subs=np.arange(1.0, 10.0)))
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("foam damping $C_c$ (N s/m)")
    ax.set_title(f"{d.label}, $v_c$ = {env.impact_velocity:g} m/s")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, -0.16), ncol=2, frameon=False)


def _stiffness_limits(result: FoamDesignResult) -> tuple[float, float]:
    """A stiffness range (N/m) that shows every boundary and every foam."""
    values = [f.stiffness for f in result.foams]
    for d in result.designs:
        for k in (d.envelope.stiffness_min, d.envelope.stiffness_max):
            if np.any(np.isfinite(k)):
                values += [float(np.nanmin(k)), float(np.nanmax(k))]
    return min(values) / 1.5, max(values) * 1.5


def envelope_figure(result: FoamDesignResult) -> Figure:
    """One panel per robot: boundaries, feasible region, foams and the optimum.

    The stiffness axis is logarithmic with ticks labelled in kN/m; the legend
    sits below each panel, outside the data. The thesis prints no boundary
    values for Figs. 3.18-3.19 (its curves exist only as figures), so no
    thesis points are overlaid; its statements are compared in the Markdown.

    Parameters
    ----------
    result
        The computed study.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> len(envelope_figure(run_study(parse_study(_EXAMPLE))).axes)
    1
    """
    n = len(result.designs)
    fig, axes = plt.subplots(1, n, figsize=(5.6 * n, 6.0), squeeze=False, sharey=True)
    for ax, d in zip(axes[0], result.designs, strict=True):
        _panel(ax, result, d)
    axes[0][0].set_ylabel("foam stiffness $K_c$ (kN/m)")
    lo, hi = _stiffness_limits(result)
    axes[0][0].set_ylim(lo / 1e3, hi / 1e3)
    fig.suptitle(f"{result.study.name}: feasible foam stiffness and damping (Zeng 2011, Sec. 3.9)")
    fig.tight_layout()
    return fig


def _fmt(x: float, spec: str = ".4g") -> str:
    if isinstance(x, float) and not math.isfinite(x):
        return "—" if math.isnan(x) else ("∞" if x > 0 else "−∞")
    return format(x, spec)


def _inputs_section(result: FoamDesignResult) -> list[str]:
    st = result.study
    out = ["## Inputs", ""]
    rows = pd.DataFrame(
        [
            {
                "robot": d.label,
                "M_r (kg)": d.robot.mass,
                "K_r (N/m)": d.robot.stiffness,
                "C_r (N s/m)": d.robot.damping,
            }
            for d in result.designs
        ]
    )
    out += [markdown_table(rows, index=False), ""]
    heads = (
        f"worst case over the head-neck ranges M_h {st.head_range.mass} kg, K_h "
        f"{st.head_range.stiffness} N/m, C_h {st.head_range.damping} N s/m (3-level grid)"
        if st.head_range
        else "each criterion's conservative head-neck set (Sec. 3.9): minimum set "
        "(4.4 kg, 3 kN/m, 46 N s/m) for head acceleration and HIC, maximum set "
        "(5.3 kg, 5 kN/m, 130.2 N s/m) for force and compression"
    )
    crit = result.designs[0].envelope.criteria
    out += [
        f"- impact velocity v_c = {st.impact_velocity:g} m/s (worst case: the response is "
        "linear in v_c)",
        "- upper boundary: " + "; ".join(c.describe() for c in crit),
        f"- lower boundary: eps_max <= lambda = {st.max_compression * 1e3:g} mm (3.9.3)",
        f"- head-neck parameters: {heads}",
        f"- damping grid: {st.damping.low:g}-{st.damping.high:g} N s/m, {st.damping.num} points",
        "- g is standard gravity, 9.80665 m/s^2",
        "",
    ]
    return out


def _verdicts_section(result: FoamDesignResult) -> list[str]:
    if not result.foams:
        return []
    st = result.study
    out = [
        "## Verdicts",
        "",
        "Each foam is judged at its own damping against both boundaries: **feasible**, "
        f"**on the boundary** (within {100 * st.verdict_tolerance:g} % of a boundary in K_c) "
        "or **not feasible**. v_c,max: largest impact velocity for which the foam meets every "
        f"constraint; v_r,max = v_c,max - {st.human_speed:g} m/s (head moving toward the "
        "robot). lambda needed: worst-case eps_max at the study's v_c.",
        "",
    ]
    v = result.verdicts()
    table = pd.DataFrame(
        {
            "robot": v["robot"],
            "foam": v["foam"],
            "K_c (kN/m)": (v["K_c_N_per_m"] / 1e3).map(lambda x: _fmt(x, ".2f")),
            "C_c (N s/m)": v["C_c_N_s_per_m"].map(lambda x: _fmt(x, ".1f")),
            "verdict": v["verdict"].map(lambda s: s if s == "feasible" else f"**{s}**"),
            "where": v["statement"],
            "v_c,max (m/s)": v["v_c_max_m_per_s"].map(lambda x: _fmt(x, ".2f")),
            "v_r,max (m/s)": v["v_r_max_m_per_s"].map(lambda x: _fmt(x, ".2f")),
            "limited by": v["limiting"],
            "lambda needed (mm)": (v["lambda_needed_m"] * 1e3).map(lambda x: _fmt(x, ".1f")),
        }
    )
    return [*out, markdown_table(table, index=False), ""]


#: What the thesis says about its foams on its manipulators, with the section that says it.
_THESIS_STATEMENTS: tuple[tuple[str, str, str, tuple[str, ...], str], ...] = (
    ("Manipulator 1", "Foam 1", "Sec. 3.9", ("feasible",),
     "Foam 1 is below the upper curve and satisfies the thickness constraint"),
    ("Manipulator 2", "Foam 1", "Sec. 3.9", ("feasible",),
     "Foam 1 is below the upper curve and satisfies the thickness constraint"),
    ("Manipulator 1", "Foam 2", "Sec. 3.9", ("on the boundary",),
     "Foam 2 does not satisfy the thickness constraint but is almost on the lower boundary"),
    ("Manipulator 2", "Foam 2", "Sec. 3.9", ("not feasible",),
     "Foam 2 is well below the lower (thickness) boundary"),
    ("Manipulator 2", "Foam 3", "Sec. 3.7, Fig. 3.13 discussion", ("not feasible",),
     "Foam 3 could make safety unattainable with a heavy manipulator"),
)  # fmt: skip


def _thesis_section(result: FoamDesignResult) -> list[str]:
    """The thesis's statements about its foams, where the study holds them."""
    by_key = {(d.label, fv.foam.name): fv for d in result.designs for fv in d.verdicts}
    rows = []
    for robot, foam, source, expected, text in _THESIS_STATEMENTS:
        fv = by_key.get((robot, foam))
        if fv is None:
            continue
        rows.append(
            {
                "robot": robot,
                "foam": foam,
                "thesis": text,
                "source": f"Zeng 2011, {source}",
                "here": f"{fv.verdict}: {fv.statement}",
                "agrees": "yes" if fv.verdict in expected else "**no**",
            }
        )
    if not rows:
        return []
    return [
        "## Thesis statements",
        "",
        "Sec. 3.9 names only Foams 1 and 2; that Foam 3 is unsafe on a heavy manipulator "
        "comes from the Fig. 3.13 discussion (Sec. 3.7). The thesis prints no boundary "
        "values for Figs. 3.18-3.19, so the curves are compared through these statements.",
        "",
        markdown_table(pd.DataFrame(rows), index=False),
        "",
    ]


def _optimal_section(result: FoamDesignResult) -> list[str]:
    if not any(d.optimal is not None for d in result.designs):
        return []
    out = [
        "## Optimal foam",
        "",
        "Largest worst-case margin min_i ln(limit_i / metric_i) over K_c and C_c within the "
        "damping grid and elastomeric damping ratios xi_c = 0.05-0.2 (CasADi/IPOPT, exact "
        "gradients; started from a grid search).",
        "",
    ]
    rows = []
    for d in result.designs:
        o = d.optimal
        if o is None:
            continue
        rows.append(
            {
                "robot": d.label,
                "status": o.status,
                "K_c (kN/m)": _fmt(o.stiffness / 1e3, ".2f"),
                "C_c (N s/m)": _fmt(o.damping, ".1f"),
                "xi_c": _fmt(o.damping / (2 * math.sqrt(_XI_HEAD_MASS * o.stiffness)), ".3f"),
                "headroom (%)": _fmt(100 * o.headroom, "+.1f"),
                "binding": ", ".join(k for k, m in o.margins.items() if m - o.margin < 1e-4),
                "reopens at v_c (m/s)": _fmt(o.reopen_velocity, ".2f")
                if o.status == "empty"
                else "—",
            }
        )
    return [*out, markdown_table(pd.DataFrame(rows), index=False), ""]


def _boundaries_section(result: FoamDesignResult) -> list[str]:
    out = [
        "## Boundaries",
        "",
        "Every fourth damping value; `envelope.csv` holds all of them with their status "
        "(bounded, unbounded, no_solution) and flags. Stiffness in kN/m.",
        "",
    ]
    env0 = result.designs[0].envelope
    idx = list(range(0, env0.damping.size, 4))
    if idx[-1] != env0.damping.size - 1:
        idx.append(env0.damping.size - 1)
    bt = pd.DataFrame({"C_c (N s/m)": [_fmt(float(env0.damping[i]), ".0f") for i in idx]})
    for d in result.designs:
        for col, k in (
            ("K_c,min", d.envelope.stiffness_min),
            ("K_c,max", d.envelope.stiffness_max),
        ):
            bt[f"{d.label} {col}"] = [_fmt(float(k[i]) / 1e3, ".2f") for i in idx]
    out += [markdown_table(bt, index=False), ""]
    out += [
        "Area of the feasible region over the grid (decades x N s/m): "
        + ", ".join(f"{d.label} {d.envelope.area(log=True):.1f}" for d in result.designs),
        "",
    ]
    return out


def _worst_case_section(result: FoamDesignResult) -> list[str]:
    checks = [(d, d.check) for d in result.designs if d.check is not None]
    if not checks:
        return []
    samples = checks[0][1].samples
    out = [
        "## Worst-case check",
        "",
        "At every boundary point the 8 corners of the head-neck box (4.4-5.3 kg, 3-5 kN/m, "
        "46-130.2 N s/m unless the study gives others) are evaluated at the largest impact "
        f"velocity (the metrics rise linearly with v_c), then {samples} random cases "
        "(uniform heads and velocities up to v_c). Ratio: the largest metric over its limit "
        "(<= 1: the envelope's head set is the worst case). A case whose first lobe is "
        "delicate (a_h lingers near zero before the lobe ends, so eps_max jumps) counts like "
        "any other: the foam really compresses that far; such points are listed. Onset: the "
        "damping (and xi_c = C_c / (2 sqrt(4.4 kg K_c))) from which the envelope's head set "
        "stops being the worst, located by bisection on the corners.",
        "",
    ]
    rows = []
    for d, ch in checks:
        frame = ch.to_frame().set_index("constraint")
        for name in ch.ratio_by_point:
            r = frame.loc[name]
            delicate = ch.damping[ch.delicate_by_point[name]]
            rows.append(
                {
                    "robot": d.label,
                    "constraint": name,
                    "boundary": r["boundary"],
                    "max ratio": _fmt(float(r["max_ratio"]), ".4f"),
                    "max corner ratio": _fmt(float(r["max_corner_ratio"]), ".4f"),
                    "points violated": int(r["n_points_violated"]),
                    "onset C_c (N s/m)": _fmt(float(r["onset_C_c_N_s_per_m"]), ".1f"),
                    "onset xi_c": _fmt(float(r["onset_xi_c"]), ".3f"),
                    "delicate lobes above the limit (C_c)": ", ".join(f"{x:g}" for x in delicate)
                    or "none",
                    "verdict": "holds" if int(r["n_points_violated"]) == 0 else "**violated**",
                }
            )
    out += [markdown_table(pd.DataFrame(rows), index=False), ""]
    for d, ch in checks:
        out += [f"- **{d.label}: the worst case is not the envelope's.** {w}" for w in ch.warnings]
    if any(ch.warnings for _, ch in checks):
        out.append("")
    return out


def _warnings(result: FoamDesignResult) -> list[str]:
    """The envelopes' and optimal designs' warnings, each prefixed with its design."""
    return [
        f"{d.label}: {x}"
        for d in result.designs
        for part in (d.envelope, d.optimal)
        if part is not None
        for x in part.warnings
    ]


def envelope_markdown(result: FoamDesignResult) -> str:
    """The body of the Markdown summary of a ``foam_design`` study.

    Parameters
    ----------
    result
        The computed study (verdicts, envelopes and checks included).

    Returns
    -------
    str

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> envelope_markdown(run_study(parse_study(_EXAMPLE))).splitlines()[0]
    '## Inputs'
    """
    out = _inputs_section(result)
    out += _verdicts_section(result)
    out += _thesis_section(result)
    out += _optimal_section(result)
    out += _boundaries_section(result)
    out += _worst_case_section(result)
    return "\n".join(out)


@register_writer(FoamDesignResult)
def envelope_report(result: FoamDesignResult) -> ReportParts:
    """The report's parts: envelope.csv, verdicts.csv, envelope.png and envelope.md's body.

    Parameters
    ----------
    result
        The computed study.

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> parts = envelope_report(run_study(parse_study(_EXAMPLE)))
    >>> sorted([*parts.tables, *parts.figures, parts.page])
    ['envelope.csv', 'envelope.md', 'envelope.png', 'verdicts.csv']
    """
    return ReportParts(
        title=f"Foam covering design: {result.study.name}",
        page="envelope.md",
        body=[envelope_markdown(result)],
        tables={"envelope.csv": result.envelope_frame(), "verdicts.csv": result.verdicts()},
        figures={"envelope.png": partial(envelope_figure, result)},
        warnings=_warnings(result),
        closing=figure_section({"feasible foam region": "envelope.png"}, title="Figure"),
    )
