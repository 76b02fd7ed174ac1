"""Report of a ``foam_design`` study: envelope.md, envelope.csv and envelope.png.

The figure follows Zeng 2011, Figs. 3.18/3.19: foam stiffness against foam
damping, the upper (safety) and lower (thickness) boundaries, the feasible
region shaded, and the foams and the optimal foam marked.
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.figure import Figure
from matplotlib.ticker import NullFormatter, ScalarFormatter

from designlab.report import register_writer
from designlab.report.writers import markdown_table, write_csv, write_markdown, write_png
from designlab.study.kinds.foam_design import FoamDesignResult

__all__ = ["envelope_figure", "envelope_markdown", "write_envelope_report"]

_MARKERS = ("o", "s", "^", "D", "v", "P", "X")


def envelope_figure(result: FoamDesignResult) -> Figure:
    """One panel per robot: boundaries, feasible region, foams and the optimum."""
    n = len(result.designs)
    fig, axes = plt.subplots(1, n, figsize=(5.6 * n, 4.6), squeeze=False, sharey=True)
    for ax, d in zip(axes[0], result.designs, strict=True):
        env = d.envelope
        c = env.damping
        kmin, kmax = env._effective()
        lo_b, hi_b = env.stiffness_bounds
        feasible = kmin <= kmax
        ax.fill_between(
            c, np.clip(kmin, lo_b, hi_b) / 1e3, np.clip(kmax, lo_b, hi_b) / 1e3,
            where=feasible, color="tab:green", alpha=0.18, label="feasible region",
        )  # fmt: skip
        ax.plot(c, env.stiffness_max / 1e3, color="tab:red", lw=2, label="upper (safety)")
        if len(env.upper) > 1:
            for k in env.upper.values():
                ax.plot(c, k / 1e3, color="tab:red", lw=0.8, ls=":", alpha=0.8)
        ax.plot(c, env.stiffness_min / 1e3, color="tab:blue", lw=2, label="lower (thickness)")
        if np.any(env.delicate):
            ax.plot(c[env.delicate], env.stiffness_min[env.delicate] / 1e3, "x", color="gray",
                    ms=5, label="delicate first lobe")  # fmt: skip
        for j, foam in enumerate(result.foams):
            ok = bool(env.is_feasible(foam.stiffness, foam.damping))
            ax.plot(
                foam.damping, foam.stiffness / 1e3, _MARKERS[j % len(_MARKERS)], ms=8,
                mfc="white" if not ok else "black", mec="black",
                label=f"{foam.name} ({'feasible' if ok else 'not feasible'})",
            )  # fmt: skip
        if d.optimal is not None and not d.optimal.status.startswith("solver_failed"):
            ax.plot(d.optimal.damping, d.optimal.stiffness / 1e3, "*", ms=14, color="gold",
                    mec="black", label=f"optimal foam ({d.optimal.status})")  # fmt: skip
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(ScalarFormatter())
        ax.yaxis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("foam damping $C_c$ (N s/m)")
        ax.set_title(f"{d.label}, $v_c$ = {env.impact_velocity:g} m/s")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
    axes[0][0].set_ylabel("foam stiffness $K_c$ (kN/m)")
    ymin = min(
        np.nanmin(d.envelope.stiffness_min)
        for d in result.designs
        if np.any(np.isfinite(d.envelope.stiffness_min))
    )
    ymax = max(
        np.nanmax(d.envelope.stiffness_max)
        for d in result.designs
        if np.any(np.isfinite(d.envelope.stiffness_max))
    )
    for foam in result.foams:
        ymin, ymax = min(ymin, foam.stiffness), max(ymax, foam.stiffness)
    axes[0][0].set_ylim(ymin / 1e3 / 1.5, ymax / 1e3 * 1.5)
    fig.suptitle(f"{result.study.name}: feasible foam stiffness and damping (Zeng 2011, Sec. 3.9)")
    fig.tight_layout()
    return fig


def _fmt(x: float, spec: str = ".4g") -> str:
    if isinstance(x, float) and not math.isfinite(x):
        return "—" if math.isnan(x) else ("∞" if x > 0 else "−∞")
    return format(x, spec)


def envelope_markdown(
    result: FoamDesignResult, *, command: str | None = None, version: str | None = None
) -> str:
    """The Markdown summary."""
    st = result.study
    crit = [c.build() for c in st.criteria]
    out = [f"# Foam covering design: {st.name}", ""]
    if st.description:
        out += [st.description.strip(), ""]
    out += ["## Inputs", ""]
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
    out += [
        f"- impact velocity v_c = {st.impact_velocity:g} m/s (worst case: the response is "
        "linear in v_c)",
        "- upper boundary: " + "; ".join(c.describe() for c in crit),
        f"- lower boundary: eps_max <= lambda = {st.max_compression * 1e3:g} mm",
        f"- head-neck parameters: {heads}",
        f"- damping grid: {st.damping.low:g}-{st.damping.high:g} N s/m, {st.damping.num} points",
        "",
        "## Verdicts",
        "",
        "Margin: signed distance to the nearest boundary in log10(K_c) (positive inside). "
        "v_c,max: largest impact velocity for which the foam meets every constraint; "
        f"v_r,max = v_c,max - {st.human_speed:g} m/s (head moving toward the robot). "
        "lambda needed: worst-case eps_max at the study's v_c.",
        "",
    ]
    v = result.verdicts()
    table = pd.DataFrame(
        {
            "robot": v["robot"],
            "foam": v["foam"],
            "K_c (kN/m)": (v["K_c_N_per_m"] / 1e3).map(lambda x: _fmt(x, ".2f")),
            "C_c (N s/m)": v["C_c_N_s_per_m"].map(lambda x: _fmt(x, ".1f")),
            "feasible": v["feasible"].map(lambda b: "yes" if b else "**no**"),
            "margin (decades)": v["margin_decades"].map(lambda x: _fmt(x, "+.4f")),
            "margin (% in K_c)": v["margin_percent"].map(lambda x: _fmt(x, "+.1f")),
            "v_c,max (m/s)": v["v_c_max_m_per_s"].map(lambda x: _fmt(x, ".2f")),
            "v_r,max (m/s)": v["v_r_max_m_per_s"].map(lambda x: _fmt(x, ".2f")),
            "limited by": v["limiting"],
            "lambda needed (mm)": (v["lambda_needed_m"] * 1e3).map(lambda x: _fmt(x, ".1f")),
        }
    )
    out += [markdown_table(table, index=False), ""]
    if any(d.optimal is not None for d in result.designs):
        out += [
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
                    "xi_c": _fmt(o.damping / (2 * math.sqrt(4.4 * o.stiffness)), ".3f"),
                    "headroom (%)": _fmt(100 * o.headroom, "+.1f"),
                    "binding": ", ".join(k for k, m in o.margins.items() if m - o.margin < 1e-4),
                    "reopens at v_c (m/s)": _fmt(o.reopen_velocity, ".2f")
                    if o.status == "empty"
                    else "—",
                }
            )
        out += [markdown_table(pd.DataFrame(rows), index=False), ""]
    out += [
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
        bt[f"{d.label} K_c,min"] = [
            _fmt(float(d.envelope.stiffness_min[i]) / 1e3, ".2f") for i in idx
        ]
        bt[f"{d.label} K_c,max"] = [
            _fmt(float(d.envelope.stiffness_max[i]) / 1e3, ".2f") for i in idx
        ]
    out += [markdown_table(bt, index=False), ""]
    out += [
        "Area of the feasible region over the grid (decades x N s/m): "
        + ", ".join(f"{d.label} {d.envelope.area(log=True):.1f}" for d in result.designs),
        "",
    ]
    checks = [(d, d.check) for d in result.designs if d.check is not None]
    if checks:
        out += [
            "## Worst-case check",
            "",
            "Heads sampled uniformly in the ranges (4.4-5.3 kg, 3-5 kN/m, 46-130.2 N s/m unless "
            "the study gives others) and velocities up to v_c, at every boundary point: the "
            "largest "
            "sampled metric divided by its limit (<= 1: the envelope's worst case is the worst), "
            "over the elastomeric foams of the thesis (xi_c = C_c / (2 sqrt(4.4 K_c)) <= 0.2) and "
            "over the whole grid. "
            "Samples whose first lobe is delicate (a_h lingers near zero before the lobe ends, so "
            "eps_max jumps) are listed apart.",
            "",
        ]
        rows = []
        for d, ch in checks:
            env = d.envelope
            for name in ch.max_ratio:
                kb = env.stiffness_min if name == "eps_max" else env.upper[name]
                with np.errstate(invalid="ignore", divide="ignore"):
                    xi = env.damping / (2 * np.sqrt(4.4 * kb))
                r = ch.ratio_by_point[name]
                phys = np.isfinite(r) & (xi <= 0.2)
                rows.append(
                    {
                        "robot": d.label,
                        "constraint": name,
                        "max ratio, xi_c <= 0.2": _fmt(float(r[phys].max()), ".4f")
                        if np.any(phys)
                        else "—",
                        "max ratio, regular lobes": _fmt(ch.max_ratio[name], ".4f"),
                        "max ratio, delicate lobes": _fmt(ch.max_ratio_delicate[name], ".4f"),
                        "points with a delicate sample above the limit (C_c)": ", ".join(
                            f"{x:g}" for x in ch.delicate_points[name]
                        )
                        or "none",
                    }
                )
        out += [markdown_table(pd.DataFrame(rows), index=False), ""]
    notes = [w for d in result.designs for w in (f"{d.label}: {x}" for x in d.envelope.warnings)]
    if notes:
        out += ["## Warnings", ""] + [f"- {w}" for w in notes] + [""]
    out += ["## Figure", "", "![feasible foam region](envelope.png)", ""]
    out += ["---", ""]
    if command:
        out.append(f"Produced by `{command}`")
    out.append(f"designlab {version or ''}".rstrip())
    out.append("")
    return "\n".join(out)


@register_writer(FoamDesignResult)
def write_envelope_report(
    result: FoamDesignResult,
    directory: Path,
    *,
    command: str | None = None,
    version: str | None = None,
    study_text: str | None = None,
) -> list[Path]:
    """Write envelope.csv, envelope.png, envelope.md (and study.yaml) into ``directory``."""
    frame = result.envelope_frame()
    written = [write_csv(frame, directory / "envelope.csv")]
    written.append(write_csv(result.verdicts(), directory / "verdicts.csv"))
    fig = envelope_figure(result)
    written.append(write_png(fig, directory / "envelope.png"))
    plt.close(fig)
    text = envelope_markdown(result, command=command, version=version)
    written.append(write_markdown(text, directory / "envelope.md"))
    if study_text is not None:
        from designlab.report.atomic import atomic_write_text

        written.append(atomic_write_text(directory / "study.yaml", study_text))
    return written
