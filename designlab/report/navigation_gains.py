"""Report of a ``navigation_gains`` study: summary.md, gains.csv, convergence and trajectory plots,
the Appendix-C sensitivity tables (Zeng 2011, App. C)."""

from __future__ import annotations

import math
from functools import partial
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from designlab.navigation import Disc, GainOptimum, NavigationResult
from designlab.navigation.methods import METHOD, METHODS
from designlab.navigation.tuning_results import (
    NEAR_OPTIMAL_H_MEAN,
    REPRO_H_FIXED,
    REPRO_H_OPTIMUM,
)
from designlab.report import register_writer
from designlab.report.builder import ReportParts
from designlab.report.figure_style import start_and_goal
from designlab.report.writers import markdown_table
from designlab.results import OK
from designlab.study.kinds.navigation_gains import TABLE_C1, WIDER, NavigationGainsResult

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "convergence_figure",
    "navigation_gains_markdown",
    "navigation_gains_report",
    "near_optimal_frame",
    "trajectory_figure",
]

_COLOURS = {"off": "tab:blue", "lyapunov": "tab:red", "robust": "tab:green", "wider": "tab:purple"}


def _box_change(result: NavigationGainsResult, key: str) -> str:
    """' (K5 <= 5000)': the bounds the bound check moved, against the study's box."""
    o = result.optima[key]
    box = result.study.bounds.as_dict()
    parts = []
    for n, (lo, hi) in o.bounds.items():
        if lo < box[n][0]:
            parts.append(f"{n.upper() if n != 'b' else n} >= {lo:.4g}")
        if hi > box[n][1]:
            parts.append(f"{n.upper() if n != 'b' else n} <= {hi:.4g}")
    return f" ({', '.join(parts)})" if parts else ""


def convergence_figure(result: NavigationGainsResult) -> Figure:
    """Best feasible H_mean against evaluations, one panel per stabilising mode, with references.

    Parameters
    ----------
    result
        The study result.
    """
    from matplotlib.figure import Figure  # matplotlib only when drawing

    comp = result.comparison
    panels = list(dict.fromkeys(o.stabilising for o in result.optima.values()))
    fig = Figure(figsize=(6.0 * len(panels), 4.6))
    axes = fig.subplots(1, len(panels), squeeze=False, sharex=True)
    for ax, stab in zip(axes.ravel(), panels, strict=True):
        for mode, opt in result.optima.items():
            if opt.stabilising != stab:
                continue
            h = opt.history
            wider = mode.endswith(WIDER)
            c = _COLOURS.get("wider" if wider else mode, "k")
            robust = mode == "robust"
            label = (
                f"robust ({opt.robust_mode} over {opt.walks} walks)"
                if robust
                else "wider box" + _box_change(result, mode)
                if wider
                else "nominal walk"
            )
            ax.plot(h["evaluations"], h["best_H_mean"], color=c, lw=2, label=f"designlab, {label}")
            block = comp[(comp["stabilising"] == stab) & ((comp["robust"] != "") == robust)]
            for lab, ls in () if wider else (("thesis_optimum", "--"), ("experimental", ":")):
                v = block.loc[block["gains"] == lab, "H_mean"]
                if len(v):
                    ax.axhline(
                        float(v.iloc[0]),
                        color=c,
                        ls=ls,
                        lw=1,
                        label=f"{lab.replace('_', ' ')} gains, {label}: {float(v.iloc[0]):.4f}",
                    )
            refine = h[h["phase"] == "refine"]
            if len(refine):
                ax.axvline(float(refine["evaluations"].iloc[0]), color=c, lw=0.6, alpha=0.4)
        ax.set_xlabel("gain sets evaluated")
        ax.set_ylabel("best feasible H_mean")
        ax.set_title(f"stabilising force {stab}")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="lower right")
    fig.suptitle(
        "CMA-ES, then compass refinement (thin vertical line: start of the refinement)", fontsize=10
    )
    fig.tight_layout()
    return fig


def _draw_scenario(ax, res: NavigationResult) -> None:  # type: ignore[no-untyped-def]
    from matplotlib.patches import Circle
    from matplotlib.patches import Rectangle as RectPatch

    sc = res.scenario
    for i, o in enumerate(sc.obstacles):
        if isinstance(o, Disc):
            track = res.obstacle_positions[i]
            moving = np.ptp(track[:, 0]) + np.ptp(track[:, 1]) > 1e-9
            c = (
                track[0]
                if not moving
                else track[np.argmin(res.distance[i][1:])]
                if res.distance.shape[1] > 1
                else track[0]
            )
            ax.add_patch(Circle(c, o.radius, color="0.4", alpha=0.5))
            ax.add_patch(Circle(c, o.r3, fill=False, ls="--", color="0.3", lw=0.8))
            ax.add_patch(Circle(c, o.r2, fill=False, ls=":", color="0.5", lw=0.8))
            if moving:
                ax.plot(track[:, 0], track[:, 1], color="0.5", lw=1, ls="-.")
        else:
            x0, y0 = o.center[0] - o.length / 2, o.center[1] - o.width / 2
            ax.add_patch(RectPatch((x0, y0), o.length, o.width, color="0.4", alpha=0.5))
            ax.add_patch(
                RectPatch(
                    (x0 - o.r3, y0 - o.r3),
                    o.length + 2 * o.r3,
                    o.width + 2 * o.r3,
                    fill=False,
                    ls="--",
                    color="0.3",
                    lw=0.8,
                )
            )
    ax.plot(*sc.start, "ko", ms=4)
    ax.plot(*sc.goal, "k*", ms=9)


def trajectory_figure(result: NavigationGainsResult, mode: str) -> Figure:
    """One panel per configuration: the thesis's optimum and ours, stabilising ``mode``.

    Parameters
    ----------
    result
        The study result.
    mode
        ``"off"`` or ``"lyapunov"``: the stabilising mode whose runs to draw.
    """
    confs = sorted({k[2] for k in result.runs if k[0] == mode})
    n = len(confs)
    cols = 2 if n > 1 else 1
    rows = -(-n // cols)
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.2 * cols, 3.6 * rows))
    axes = fig.subplots(rows, cols, squeeze=False)
    pts = []
    for (m, _, _), res in result.runs.items():
        if m == mode:
            pts.append(res.position)
            for k, o in enumerate(res.scenario.obstacles):
                r = o.r3 if isinstance(o, Disc) else o.r3 + max(o.length, o.width) / 2
                pts.append(res.obstacle_positions[k][[0, -1]] + r)
                pts.append(res.obstacle_positions[k][[0, -1]] - r)
    allp = np.vstack(pts)
    lo, hi = allp.min(axis=0) - 0.2, allp.max(axis=0) + 0.2
    lims = ((float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1])))
    for ax, i in zip(axes.ravel(), confs, strict=False):
        first = True
        for label, colour in (("thesis_optimum", "tab:orange"), ("designlab_optimum", "tab:blue")):
            res = result.runs.get((mode, label, i))
            if res is None:
                continue
            if first:
                _draw_scenario(ax, res)
                start_and_goal(ax, res.scenario.start, res.scenario.goal)
                first = False
            g = res.gains
            ax.plot(
                res.position[:, 0],
                res.position[:, 1],
                color=colour,
                lw=1.8,
                label=f"{label.replace('_', ' ')} "
                f"({g['k1']:.3g}, {g['b']:.3g}, {g['k3']:.3g}, {g['k5']:.4g}): "
                f"T = {res.arrival_time:.2f} s, H = {res.criteria.H:.3f}",
            )
        ax.set_xlim(*lims[0])
        ax.set_ylim(*lims[1])
        ax.set_aspect("equal")
        ax.set_title(
            f"Configuration {i}"
            + (" (not optimised)" if i not in result.study.configurations else "")
        )
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6.5, loc="upper center", bbox_to_anchor=(0.5, -0.18))
    for ax in axes.ravel()[n:]:
        ax.set_visible(False)
    fig.suptitle(
        f"Paths with the thesis's optimum and designlab's optimum, stabilising force {mode} "
        "(grey: obstacle; dashed: r3; dotted: r2; dash-dot: human path, drawn at closest approach)",
        fontsize=9,
    )
    fig.tight_layout()
    return fig


def _fmt(x: object, spec: str = ".4f") -> str:
    if isinstance(x, float | np.floating):
        if math.isnan(x):
            return "—"
        if math.isinf(x):
            return "∞"
        return format(float(x), spec)
    return str(x)


def navigation_gains_markdown(result: NavigationGainsResult) -> str:
    """The body of the Markdown summary (the framework adds header and warnings).

    Parameters
    ----------
    result
        The study result.
    """
    st = result.study
    out = like_for_like_lines(result)
    out += _problem_section(result)
    out += _gains_section(result)
    for mode in st.modes:
        out += _mode_line(result, mode)
    out += _effort_section(result)
    out += _reproduction_section(result)
    out += _repeatability_section(result)
    out += _sensitivity_section(result)
    out += _appendix_c_section(result)
    out += _global_section(result)
    out += _baseline_section(result)
    return "\n".join(out)


def _problem_section(result: NavigationGainsResult) -> list[str]:
    """The optimisation problem as the study poses it."""
    st = result.study
    out: list[str] = []
    b = st.bounds
    out += [
        "## Problem (Zeng 2011, Sec. 5.6 and App. C; docs/navigation_gains.md)",
        "",
        f"- maximise H_mean, the mean of H (5.6.6) over Ch. 6 Configurations {st.configurations}; "
        f"checked on {st.validation} (not optimised)",
        "- decision (K1, b, K3, K5) with K2 = b K1, K4 = b K3, K6 = b K5 (5.5.7); "
        f"bounds K1 {b.k1} N/m, "
        f"b {b.b} s, K3 {b.k3} N/m, K5 {b.k5} N/m^2",
        "- hard constraints: arrival (within 0.15 m of the goal, 30 s horizon) and no entry "
        "into any critical region"
        + (f" (clearance of {st.critical_margin:g} m or more)" if st.critical_margin else "")
        + " in every configuration; a violating candidate is infeasible (ranked below "
        "every feasible one), never scored",
        f"- CMA-ES (population {st.popsize}, budget {st.max_evaluations} gain sets, "
        f"seed {st.seed}), each "
        "generation simulated as one batch, then a batched compass search"
        + ("" if st.refine else " (off)"),
        "",
        "## Gains and H_mean",
        "",
    ]
    return out


def _gains_section(result: NavigationGainsResult) -> list[str]:
    """The gains table (and arrival times and margins)."""
    comp = result.comparison
    out: list[str] = []
    extra = [c for c in comp.columns if c.startswith(("T_arrive_s_", "critical_margin_m_"))]
    main = comp[[c for c in comp.columns if c not in extra]]
    out += [markdown_table(_ranged_gains(result, main), index=False), ""]
    if extra:
        key = ["gains", "stabilising", "robust"]
        out += [
            "Arrival times (s; mean over the walks in robust mode) and the smallest margin to a "
            "critical region (m: centre/contour distance minus r3, over obstacles and walks):",
            "",
            markdown_table(
                comp[key + extra]
                .rename(columns=lambda c: c.replace("_ch6_config", " C"))
                .map(lambda v: _fmt(v, ".3f") if isinstance(v, float) else v),
                index=False,
            ),
            "",
        ]
    return out


def _mode_line(result: NavigationGainsResult, mode: str) -> list[str]:
    """One stabilising mode: ours against the references, validation, bound check."""
    st = result.study
    comp = result.comparison
    out: list[str] = []
    block = comp[(comp["stabilising"] == mode) & (comp["robust"] == "")].set_index("gains")
    if "designlab_optimum" not in block.index:
        out.append(f"- stabilising {mode}: no feasible optimum found")
        return out
    ours = block.loc["designlab_optimum"]
    line = (
        f"- stabilising **{mode}**: H_mean {ours['H_mean']:.4f} against "
        f"{block.loc['experimental', 'H_mean']:.4f} "
        f"(experimental gains, {ours['vs_experimental_pct']:+.1f} %) and "
        f"{block.loc['thesis_optimum', 'H_mean']:.4f} "
        f"(thesis optimum, {ours['vs_thesis_optimum_pct']:+.1f} %)."
    )
    worse = [
        lab.replace("_", " ")
        for lab in ("experimental", "thesis_optimum")
        if ours["H_mean"] < block.loc[lab, "H_mean"]
    ]
    if worse:
        line += (
            f" **Ours is below the {' and the '.join(worse)} gains: the search missed a better "
            "point (raise max_evaluations or change the seed).**"
        )
    for n in [c for c in block.columns if c.startswith("H_ch6_config")]:
        i = int(n.rsplit("config", 1)[1])
        if i in st.validation and i not in st.configurations:
            vals = ", ".join(
                f"{lab.replace('_', ' ')} {block.loc[lab, n]:.4f}" for lab in block.index
            )
            best = block[n].idxmax()
            safe = ""
            if "validation_feasible" in block.columns:
                safe = (
                    "; ours arrives and stays out of every critical region there"
                    if bool(block.loc["designlab_optimum", "validation_feasible"])
                    else "; ours **enters a critical region or does not arrive** there"
                )
            ours_v = float(block.loc["designlab_optimum", n])
            rel = ", ".join(
                f"{100 * (ours_v / float(block.loc[lab, n]) - 1):+.1f} % vs {lab.replace('_', ' ')}"
                for lab in block.index
                if lab != "designlab_optimum"
            )
            line += f" Configuration {i} (not optimised): {vals} (ours {rel}){safe}; " + (
                "the optimum generalises."
                if best == "designlab_optimum"
                else f"the best set there is the {best.replace('_', ' ')} one."
            )
    if "designlab_optimum_wider_box" in block.index:
        w = block.loc["designlab_optimum_wider_box"]
        d = 100 * (w["H_mean"] / ours["H_mean"] - 1)
        line += (
            " Bound check: ours lies on the bound of "
            f"{sorted(result.optima[mode].on_bounds())}; "
            f"optimised again in a wider box{_box_change(result, mode + WIDER)}: "
            f"{_gains_text(result, mode + WIDER, w)}, "
            f"H_mean {w['H_mean']:.4f} ({d:+.2f} % against the optimum in the study's box)."
        )
    out.append(line)
    return out


def _optimisation_label(result: NavigationGainsResult, mode: str) -> str:
    """'off', 'lyapunov, wider box (b >= 0.005)', 'robust (mean, 8 walks, stabilising off)'."""
    o = result.optima[mode]
    if mode.endswith(WIDER):
        return f"{o.stabilising}, wider box{_box_change(result, mode)}"
    if mode == "robust":
        return f"robust ({o.robust_mode}, {o.walks} walks, stabilising {o.stabilising})"
    return mode


def _gains_text(result: NavigationGainsResult, mode: str, row: pd.Series) -> str:
    """'K1 = 8.69, b = 0.00956, ...', a flat gain as its near-optimal range (~)."""
    near = near_optimal_frame(result)
    near = near[near["optimisation"] == _optimisation_label(result, mode)].set_index("gain")
    parts = []
    for n in ("k1", "b", "k3", "k5"):
        shown = n.upper() if n != "b" else n
        if n in near.index and _flat(near.loc[n, "low"], near.loc[n, "high"]):
            parts.append(f"{shown} ~ {near.loc[n, 'low']:.4g}-{near.loc[n, 'high']:.4g}")
        else:
            parts.append(f"{shown} = {row[n]:.4g}")
    return ", ".join(parts)


def _effort_section(result: NavigationGainsResult) -> list[str]:
    """Search effort (no wall times: they go to the run record) and the figures."""
    st = result.study
    out: list[str] = []
    out += ["", "## Search effort", ""]
    eff = [
        {
            "optimisation": _optimisation_label(result, mode),
            "status": o.status,
            "gain sets": o.evaluations,
            "closed-loop runs": o.simulations,
        }
        for mode, o in result.optima.items()
    ]
    out += [
        markdown_table(pd.DataFrame(eff), index=False),
        "",
        "The thesis's grid search and fmincon took one week (App. C.2). How long each "
        "optimisation took here depends on the machine and its load: the times are kept with "
        "the run record, kept outside the report (`designlab list` shows it).",
        "",
        "![convergence](convergence.png)",
        "",
    ]
    for mode in st.modes:
        out += [f"![trajectories, stabilising {mode}](trajectories_{mode}.png)", ""]
    return out


def _all_optima(result: NavigationGainsResult) -> dict[str, GainOptimum]:
    """Every optimisation of the study by its label (the baselines' too)."""
    found = {_optimisation_label(result, m): o for m, o in result.optima.items()}
    found.update({like_for_like_label(m): o for m, o in result.baseline_optima.items()})
    return found


def like_for_like_label(method: str) -> str:
    """The label of a method's optimisation on the comparison configurations.

    Parameters
    ----------
    method
        A navigation method's registry name.

    Examples
    --------
    >>> like_for_like_label("masoud"), like_for_like_label("vff")
    ('baseline masoud', 'vff like for like')
    """
    own = method in METHODS.choices() and not METHODS.get(method).baseline
    return f"{method} like for like" if own else f"baseline {method}"


#: Table C.1's H_opt per method (App. C.2), for the ranking sentence (the kind's table).
TABLE_C1_H = {method: h for method, (_, h) in TABLE_C1.items()}


def _half_budget_best(opt: GainOptimum) -> float:
    """The best H_mean an optimisation had after half of its evaluations (nan: no history)."""
    h = opt.history
    if h is None or h.empty or "evaluations" not in h:
        return math.nan
    half = h[h["evaluations"] <= 0.5 * float(h["evaluations"].max())]
    return float(half["best_H_mean"].max()) if len(half) else math.nan


def _method_optimum(result: NavigationGainsResult, method: str) -> GainOptimum | None:
    """The optimisation behind a method's like-for-like optimum."""
    return result.baseline_optima.get(method) or result.optima.get("off")


def _ranked(scores: dict[str, float]) -> list[str]:
    return sorted(scores, key=lambda m: -scores[m] if math.isfinite(scores[m]) else math.inf)


def _thesis_sentence(order: list[str], name: dict[str, str]) -> str:
    """Table C.1's order, and whether the like-for-like order keeps it."""
    thesis = _ranked({m: TABLE_C1_H[m] for m in order if m in TABLE_C1_H})
    text = "Table C.1 (App. C.2): " + " > ".join(f"{name[m]} {TABLE_C1_H[m]:g}" for m in thesis)
    ours = [m for m in order if m in TABLE_C1_H]
    if ours == thesis:
        return text + ". The thesis's order holds here."
    swaps = [
        f"{name[a]} ranks above {name[b]}"
        for i, a in enumerate(ours)
        for b in ours[i + 1 :]
        if thesis.index(a) > thesis.index(b)
    ]
    return text + ". **The thesis's order is reversed here**: " + ", ".join(swaps) + "."


def like_for_like_lines(result: NavigationGainsResult) -> list[str]:
    """The ranking of the methods optimised by the same search on the same configurations,
    against Table C.1's, with the evidence on the search budget (the report's first lines).

    Parameters
    ----------
    result
        The study result (its ``baselines`` table and optimisations).
    """
    f = result.baselines
    if f.empty:
        return []
    opt = f[f["gains"] == "designlab_optimum"].set_index("method")
    methods = list(f["method"].unique())
    score = {
        m: float(opt.loc[m, "H_mean"])
        if m in opt.index and bool(opt.loc[m, "feasible"])
        else -math.inf
        for m in methods
    }
    order = _ranked(score)
    name = {m: METHODS.get(m).label for m in methods}
    shown = [
        f"{name[m]} {score[m]:.3f}" if math.isfinite(score[m]) else f"{name[m]} (none feasible)"
        for m in order
    ]
    configs = ", ".join(map(str, result.study.baseline_configurations))
    lines = [
        "**Ranking like for like** (every method's gains optimised by the same seeded search "
        f"on Configurations {configs}, stabilising force off; H_mean of each optimum): "
        + " > ".join(shown)
        + ".",
        "",
        _thesis_sentence(order, name),
        "",
    ]
    runs = {m: o for m in methods if (o := _method_optimum(result, m)) is not None}
    half = {m: _half_budget_best(o) for m, o in runs.items()}
    budget = "; ".join(
        f"{name[m]}: {o.evaluations} gain sets, {o.status}, "
        + (
            f"best H_mean {o.objective:.4f} (after half of them {half[m]:.4f})"
            if math.isfinite(o.objective)
            else "no feasible gain set"
        )
        for m, o in runs.items()
    )
    if runs:
        again = _ranked(half) == [m for m in order if m in half]
        lines += [
            f"Search budget: {budget}. After half of each budget the optima give "
            f"{'the same' if again else 'a different'} ranking.",
            "",
        ]
    return lines + _wider_box_line(result, score, name)


def _wider_box_line(
    result: NavigationGainsResult, score: dict[str, float], name: dict[str, str]
) -> list[str]:
    """The new VFF optimised again in the wider box (the bound check), if the study did."""
    wide = result.optima.get(f"off{WIDER}")
    if wide is None or METHOD.default not in score or not math.isfinite(wide.objective):
        return []
    st = result.study
    if st.scenarios or sorted(st.configurations) != sorted(st.baseline_configurations):
        return []  # the wider box's optimum is then not on the comparison configurations
    ranked = _ranked({**score, METHOD.default: wide.objective})
    on = sorted(result.optima["off"].on_bounds())
    return [
        f"Bound check: the new VFF's optimum lies on the bound of {on}; optimised again in "
        f"a box widened tenfold there{_box_change(result, 'off' + WIDER)} it reaches H_mean "
        f"{wide.objective:.4f}, and the ranking is then "
        + " > ".join(name[m] for m in ranked)
        + ".",
        "",
    ]


def near_optimal_frame(
    result: NavigationGainsResult, tolerance: float = NEAR_OPTIMAL_H_MEAN
) -> pd.DataFrame:
    """Per optimisation and gain: the range of the evaluated gain sets near the best H_mean.

    Parameters
    ----------
    result
        The study result.
    tolerance
        Absolute H_mean below the best that counts as near-optimal
        (:data:`~designlab.navigation.tuning_results.NEAR_OPTIMAL_H_MEAN`).

    Returns
    -------
    pandas.DataFrame
        ``optimisation``, ``gain``, ``low``, ``high``, ``optimum``, ``sets`` (gain sets
        within the tolerance), ``H_mean_best``, ``tolerance`` (``near_optimal.csv``).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> o = GainOptimum(None, 0.55054, ("c1",), np.array([0.55]), pd.DataFrame(), 3, 3, 0.0,
    ...                 "off", "", 0, {}, 0, feasible=pd.DataFrame(
    ...                     {"k1": [8.3, 7.8, 3.0], "b": [0.05] * 3, "k3": [16.0] * 3,
    ...                      "k5": [29.0] * 3, "H_mean": [0.55054, 0.55049, 0.4]}))
    >>> result = SimpleNamespace(optima={}, baseline_optima={"off": o})  # a study result
    >>> frame = near_optimal_frame(result, 1e-4)
    >>> print(frame[["optimisation", "gain", "low", "high", "sets"]].to_string(index=False))
    optimisation gain  low  high  sets
    baseline off   k1 7.80  8.30     2
    baseline off    b 0.05  0.05     2
    baseline off   k3 16.00 16.00     2
    baseline off   k5 29.00 29.00     2
    """
    rows = []
    for label, o in _all_optima(result).items():
        r = o.near_optimal(tolerance)
        for _, g in r.iterrows():
            rows.append(
                {"optimisation": label, **g.to_dict(), "sets": r.attrs["sets"],
                 "H_mean_best": o.objective, "tolerance": tolerance}
            )  # fmt: skip
    cols = ["optimisation", "gain", "low", "high", "optimum", "sets", "H_mean_best", "tolerance"]
    return pd.DataFrame(rows, columns=cols)


def _flat(low: float, high: float) -> bool:
    """True if the range changes the optimum's 4 significant digits."""
    return f"{low:.4g}" != f"{high:.4g}"


def _reproduction_section(result: NavigationGainsResult) -> list[str]:
    """How far the tables reproduce on another CPU, and the near-optimal ranges."""
    near = near_optimal_frame(result)
    out = [
        "## Reproduction on another machine",
        "",
        "The search is seeded: the same machine and build give these numbers to the bit. "
        "Another CPU (or libm, compiler, numba build) changes the last bits of each closed-loop "
        "run; the tables then reproduce within: H and H_mean of fixed gain sets "
        f"{REPRO_H_FIXED:g}; the best H_mean of an optimisation {REPRO_H_OPTIMUM:g}; arrival "
        "times one dynamics step (1 ms). The optimum's gains do not reproduce digit for digit: "
        "H_mean is flat around them and the seeded search may end elsewhere in the flat region "
        "(docs/navigation_gains.md, 'Reproduction'). For each optimum the gains table shows "
        f"the range of the gain sets this run evaluated within {NEAR_OPTIMAL_H_MEAN:g} of its "
        "best H_mean (marked ~; every range in near_optimal.csv, full digits of this run's "
        "optimum in gains.csv); a run on another machine may end outside it, at an H_mean "
        "within the tolerance above. Wall times are not in the report (run record).",
        "",
    ]
    if near.empty:
        return out
    table = []
    for label, grp in near.groupby("optimisation", sort=False):
        row: dict[str, object] = {
            "optimisation": label,
            "best H_mean": f"{grp['H_mean_best'].iloc[0]:.4f}",
            "sets within tolerance": int(grp["sets"].iloc[0]),
        }
        flat = False
        for _, g in grp.iterrows():
            name = g["gain"].upper() if g["gain"] != "b" else "b"
            wide = _flat(g["low"], g["high"])
            row[name] = f"{g['low']:.4g} - {g['high']:.4g}" if wide else f"{g['optimum']:.4g}"
            flat = flat or wide
        row["flat"] = "yes" if flat else "no"
        table.append(row)
    out += [markdown_table(pd.DataFrame(table).fillna("—"), index=False), ""]
    return out


def _repeatability_section(result: NavigationGainsResult) -> list[str]:
    """Each mode's optimum over the seeds of ``repeat_seeds`` (repeatability.csv)."""
    rep = result.repeatability
    if rep.empty:
        return []
    out = [
        "## Repeatability over seeds",
        "",
        "Each mode optimised again with other seeds, the same budget and box "
        "(repeatability.csv; the first seed is the optimum above). The spread of the gains "
        "against that of H_mean shows how flat the optimum is.",
        "",
    ]
    table = []
    for mode, grp in rep.groupby("stabilising", sort=False):
        row: dict[str, object] = {
            "stabilising": mode,
            "seeds": ", ".join(str(int(s)) for s in grp["seed"]),
        }
        for g in ("k1", "b", "k3", "k5", "H_mean"):
            lo, hi = grp[g].min(), grp[g].max()
            name = g.upper() if g.startswith("k") else g
            row[name] = f"{lo:.4g} - {hi:.4g}" if f"{lo:.4g}" != f"{hi:.4g}" else f"{lo:.4g}"
        row["not ok"] = int((grp["status"] != OK).sum())
        table.append(row)
    return [*out, markdown_table(pd.DataFrame(table), index=False), ""]


def _ranged_gains(result: NavigationGainsResult, main: pd.DataFrame) -> pd.DataFrame:
    """The gains table for Markdown, an optimum's flat gains shown as their range (~)."""
    near = near_optimal_frame(result)
    shown = main.map(lambda v: _fmt(v, ".4g") if isinstance(v, float) else v)
    for i, row in main.iterrows():
        label = _row_optimisation(result, row)
        if label is None:
            continue
        for _, g in near[near["optimisation"] == label].iterrows():
            if g["gain"] in shown.columns and _flat(g["low"], g["high"]):
                shown.loc[i, g["gain"]] = f"~{g['low']:.4g}-{g['high']:.4g}"
    return shown


def _row_optimisation(result: NavigationGainsResult, row: pd.Series) -> str | None:
    """The optimisation a gains-table row shows (None for fixed gains)."""
    gains, stab = row["gains"], row["stabilising"]
    key = {"designlab_optimum": stab, "designlab_optimum_wider_box": f"{stab}{WIDER}",
           "designlab_robust_optimum": "robust"}.get(gains)  # fmt: skip
    return _optimisation_label(result, key) if key in result.optima else None


def _sensitivity_section(result: NavigationGainsResult) -> list[str]:
    """The App. C.3 tables around each base."""
    out: list[str] = []
    if result.sensitivities:
        out += [
            "## Sensitivity tables (Zeng 2011, App. C.3)",
            "",
            "S_K = (1 - H_mean/H_opt)/(1 - K/K_opt) in %. "
            "Distances are centre distances (contour for the "
            "rectangle), L_energy is per ohm of winding resistance (the thesis's R_a is unknown). "
            "-100 % rows: the gain at zero, classified from the run "
            "(no arrival, oscillation, critical "
            "region, collision). Long tables: sensitivity_<base>.csv.",
            "",
        ]
        for label, s in result.sensitivities.items():
            g = s.base
            out += [
                f"### Around {label.replace('_', ' ')}: K1 = {g.k1:.4g}, b = {g.b:.4g}, "
                f"K3 = {g.k3:.4g}, "
                f"K5 = {g.k5:.4g} (stabilising {s.stabilising})",
                "",
                markdown_table(
                    s.s_summary().map(lambda v: _fmt(v, ".2f") if isinstance(v, float) else v),
                    index=False,
                ),
                "",
            ]
            for p in ("k1", "b", "k3", "k5"):
                perf, crit = s.appendix_c(p)
                out += [
                    f"**{p}**",
                    "",
                    markdown_table(
                        perf.map(lambda v: _fmt(v, ".3f") if isinstance(v, float) else v),
                        index=False,
                    ),
                    "",
                    markdown_table(
                        crit.map(lambda v: _fmt(v, ".4f") if isinstance(v, float) else v),
                        index=False,
                    ),
                    "",
                ]
    return out


_QUANTITY = {
    "T_arrive": "T_arrive (s)",
    "d_s_min_cir": "d_min circle column (m)",
    "d_s_min_h": "d_min human (m)",
    "d_s_min_rect": "d_min rectangle column (m)",
    "H": "H",
    "H_mean": "H_mean",
    "S_relative_sensitivity": "|S_K| (%)",
}


def _appendix_c_section(result: NavigationGainsResult) -> list[str]:
    a = result.appendix_c
    if a.empty:
        return []
    g = a.assign(abs_error=a["error"].abs()).groupby(["quantity", "configuration"], sort=False)
    summ = pd.DataFrame(
        {
            "entries": g.size(),
            "thesis range": g["thesis"].agg(lambda v: f"{v.min():.4g} - {v.max():.4g}"),
            "designlab range": g["designlab"].agg(lambda v: f"{v.min():.4g} - {v.max():.4g}"),
            "mean error": g["error"].mean(),
            "max |error|": g["abs_error"].max(),
        }
    ).reset_index()
    summ["quantity"] = summ["quantity"].map(lambda q: _QUANTITY.get(q, q))
    out = [
        "## Against the thesis's Appendix C (Tables C.2-C.9)",
        "",
        "Our sensitivity table around the thesis's optimum, stabilising force off, entry by entry "
        "against Zeng 2011, Tables C.2-C.9 (-50 ... +100 %; error = designlab - thesis; "
        "every entry "
        "in appendix_c_comparison.csv). The thesis's Configuration 3 'cir'/'rect' columns are "
        "matched swapped (its 'cir' values are the rectangle's, as its Table 6.4 shows). "
        "Configuration 2 replays a synthetic human walk (the measured walk is not published), so "
        "its distances, times and H are not expected to match; L_energy depends on the unknown "
        "winding resistance and is left out. The thesis's H values are loosely consistent among "
        "its own tables (baseline H_mean 0.665 here, H_opt 0.69 in Table C.1).",
        "",
        markdown_table(
            summ.map(lambda v: _fmt(v, ".4f") if isinstance(v, float) else v), index=False
        ),
        "",
    ]
    if not result.appendix_c_outcomes.empty:
        out += [
            "The -100 % rows (a gain at zero):",
            "",
            markdown_table(result.appendix_c_outcomes, index=False),
            "",
        ]
    return out


def _global_section(result: NavigationGainsResult) -> list[str]:
    if not result.global_sensitivities:
        return []
    out = [
        "## Which gains matter when all move together",
        "",
        "Local elasticities d ln m / d ln K at the base (central differences of 2 %) and Sobol "
        "indices (first order S1, total ST, with 95 % half-widths) with every gain uniform within "
        "the box around the base, from the shared generators of designlab.analysis.sensitivity. "
        "critical_margin_min_m is the smallest centre/contour distance minus r3 over all obstacles "
        "and configurations (m). Long tables: global_sensitivity_<base>.csv.",
        "",
    ]
    for label, gs in result.global_sensitivities.items():
        f = gs.to_frame()
        out += [
            f"### Around {label.replace('_', ' ')} (stabilising {gs.stabilising}; box "
            f"+-{gs.spread_pct:g} %, N = {gs.samples}, {6 * gs.samples} gain sets; "
            f"{100 * gs.infeasible_share:.0f} % of them infeasible)",
            "",
        ]
        for m in ("H_mean", "critical_margin_min_m"):
            t = f[f["metric"] == m].drop(columns="metric")
            if t.empty:
                continue
            t = t.iloc[np.argsort(-t["ST"].fillna(-1).to_numpy(), kind="stable")]
            out += [
                f"**{m}**",
                "",
                markdown_table(
                    t.map(lambda v: _fmt(v, ".3f") if isinstance(v, float) else v), index=False
                ),
                "",
            ]
    return out


def _baseline_section(result: NavigationGainsResult) -> list[str]:
    """Table C.1 like for like: every method's gains optimised on the same configurations."""
    f = result.baselines
    if f.empty:
        return []
    st = result.study
    w = ", ".join(f"{x:.3g}" for x in st.weights)
    return [
        "",
        "## Table C.1 like for like: the baselines optimised too",
        "",
        f"Every method's gains optimised by the same search (stabilising force off, weights "
        f"({w})) and scored with the thesis's gains on Configurations "
        f"{', '.join(map(str, st.baseline_configurations))} (App. C.2 optimises the "
        "baselines on 1, 2 and 4). `H_opt_table_C1` is the thesis's H_opt (its own "
        "configurations and walk). Masoud has no b. `baseline_gains.csv` has full precision.",
        "",
        markdown_table(_ranged_baselines(result, f), index=False),
    ]


def _ranged_baselines(result: NavigationGainsResult, f: pd.DataFrame) -> pd.DataFrame:
    """The baselines table for Markdown, each optimum's flat gains shown as their range (~)."""
    near = near_optimal_frame(result)
    shown = f.map(lambda v: _fmt(v, ".4g") if isinstance(v, float) else v)
    for i, row in f.iterrows():
        if row["gains"] != "designlab_optimum":
            continue
        method = row["method"]
        label = like_for_like_label(method) if method in result.baseline_optima else "off"
        for _, g in near[near["optimisation"] == label].iterrows():
            if g["gain"] in shown.columns and _flat(g["low"], g["high"]):
                shown.loc[i, g["gain"]] = f"~{g['low']:.4g}-{g['high']:.4g}"
    return shown


@register_writer(NavigationGainsResult)
def navigation_gains_report(result: NavigationGainsResult) -> ReportParts:
    """The report's parts: gains.csv, history.csv, the figures, the sensitivity CSVs and
    the summary's body.

    Parameters
    ----------
    result
        The study result.
    """
    tables = {
        "gains.csv": result.comparison,
        "history.csv": pd.concat(
            [o.history.assign(optimisation=m) for m, o in result.optima.items()],
            ignore_index=True,
        ),
    }
    for label, s in result.sensitivities.items():
        tables[f"sensitivity_{label}.csv"] = s.to_frame()
        tables[f"sensitivity_{label}_outcomes.csv"] = s.outcomes
    for label, gs in result.global_sensitivities.items():
        tables[f"global_sensitivity_{label}.csv"] = gs.to_frame()
    if not result.baselines.empty:
        tables["baseline_gains.csv"] = result.baselines
    tables["near_optimal.csv"] = near_optimal_frame(result)
    if not result.repeatability.empty:
        tables["repeatability.csv"] = result.repeatability
    if not result.appendix_c.empty:
        tables["appendix_c_comparison.csv"] = result.appendix_c
        tables["appendix_c_outcomes.csv"] = result.appendix_c_outcomes
    figures = {"convergence.png": partial(convergence_figure, result)}
    for mode in result.study.modes:
        figures[f"trajectories_{mode}.png"] = partial(trajectory_figure, result, mode)
    return ReportParts(
        title=f"Optimal VFF gains: {result.study.name}",
        body=[navigation_gains_markdown(result)],
        tables=tables,
        figures=figures,
        timings={f"optimise {k}": o.wall_time for k, o in _all_optima(result).items()},
    )
