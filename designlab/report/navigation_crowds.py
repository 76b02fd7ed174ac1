"""Report of a ``navigation_crowds`` study: methods among crowds, rates against density.

Files: ``summary.md`` (sizes, the rates with their Wilson intervals, findings written from the
tables, why the runs shown are slow, the gains for crowds and their validation), ``rates.csv``
(one row per layout, density and method), ``runs.csv`` (one row per run), ``stalls.csv`` (the
:func:`~designlab.navigation.crowds.diagnosis.stall_summary` of each run shown),
``rates_vs_density.png``, ``trajectories.png`` (the representative run of each method),
``animation_representative.gif`` and ``animation_worst_<method>.gif`` (GIFs through
matplotlib's PillowWriter), and with tuning ``tuning_history.csv``, ``gains_validation.csv``
(one row per validation step) and ``validation_runs.csv``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from designlab.navigation.crowds.animation import animate
from designlab.navigation.crowds.decide import decision_findings, holm, mcnemar, time_limit_curve
from designlab.navigation.crowds.diagnosis import force_breakdown, stall_summary
from designlab.navigation.crowds.metrics import wilson_interval
from designlab.navigation.crowds.scenario import crowd
from designlab.navigation.methods import METHODS
from designlab.report import register_writer
from designlab.report.builder import ReportParts, figure_section
from designlab.report.figure_style import method_colour, start_and_goal
from designlab.report.writers import markdown_table
from designlab.study.kinds.navigation_crowds import NavigationCrowdsResult

__all__ = [
    "navigation_crowds_markdown",
    "navigation_crowds_report",
    "rates_figure",
    "trajectories_figure",
    "validation_findings",
    "validation_table",
    "wall_polygons",
]

_RATES = (("success", "success rate"), ("collision", "collision rate"),
          ("critical", "critical-entry rate"))  # fmt: skip


def wall_polygons(crowd: Any) -> list[np.ndarray]:
    """The walls of a crowd's layout as closed rectangles ``(4, 2)`` (m).

    Parameters
    ----------
    crowd
        A :class:`~designlab.navigation.CrowdScenario`.
    """
    out = []
    for (x0, y0), (x1, y1) in crowd.geometry.walls:
        out.append(np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=float))
    return out


def rates_figure(summary: pd.DataFrame) -> Figure:
    """Success, collision and critical-entry rates against density, one column per layout,
    one line per method, with the Wilson intervals as error bars.

    Parameters
    ----------
    summary
        The study's summary (:meth:`~designlab.navigation.crowds.study.CrowdStudy.to_frame`).
    """
    model = summary["model"] if "model" in summary else pd.Series("", index=summary.index)
    cells = list(dict.fromkeys(zip(model, summary["scenario"], strict=True)))
    fig, axes = plt.subplots(len(_RATES), len(cells), figsize=(4.2 * len(cells), 7.5),
                             squeeze=False, sharex=True, sharey=True)  # fmt: skip
    for j, (ped, layout) in enumerate(cells):
        sub = summary[(model == ped) & (summary["scenario"] == layout)]
        for i, (rate, name) in enumerate(_RATES):
            ax = axes[i, j]
            for k, (method, g) in enumerate(sub.groupby("method", sort=False)):
                g = g.sort_values("density")
                x = g["density"].to_numpy() * (1 + 0.02 * k)  # offset so the bars do not hide
                y = g[f"{rate}_rate"].to_numpy()
                err = [y - g[f"{rate}_low"].to_numpy(), g[f"{rate}_high"].to_numpy() - y]
                ax.errorbar(x, y, yerr=err, marker="o", capsize=3, label=method,
                            color=method_colour(method))  # fmt: skip
            ax.set_ylim(-0.05, 1.05)
            ax.grid(alpha=0.3)
            if j == 0:
                ax.set_ylabel(name)
            if i == 0:
                ax.set_title(f"{layout}\n{ped}" if ped else layout, fontsize=9)
            if i == len(_RATES) - 1:
                ax.set_xlabel("density (persons/m^2)")
    axes[0, 0].legend(fontsize=8)
    fig.tight_layout()
    return fig


def trajectories_figure(result: NavigationCrowdsResult) -> Figure:
    """The representative run of each method: the robot's path over the pedestrians' paths.

    Parameters
    ----------
    result
        A ``navigation_crowds`` result.
    """
    runs = [(label, r) for (kind, label), r in result.tracks.items() if kind == "representative"]
    fig, axes = plt.subplots(len(runs), 1, figsize=(8.0, 2.6 * len(runs) + 0.6), squeeze=False)
    for ax, (label, r) in zip(axes[:, 0], runs, strict=True):
        for poly in wall_polygons(r.crowd):
            ax.fill(poly[:, 0], poly[:, 1], color="0.6")
        p = r.pedestrian_positions
        for i in range(p.shape[1]):
            ax.plot(p[:, i, 0], p[:, i, 1], color="0.55", lw=0.6, alpha=0.5,
                    label="pedestrians" if i == 0 else None)  # fmt: skip
        ax.plot(r.robot_positions[:, 0], r.robot_positions[:, 1], lw=2,
                color=method_colour(r.method), label=f"robot ({label})")  # fmt: skip
        start_and_goal(ax, r.crowd.robot_start, r.crowd.robot_goal)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
        ax.set_title(f"{label}: {r.crowd.layout}, {_density(r)}, seed {r.crowd.seed}, "
                     f"{_outcome(r)}", fontsize=9)  # fmt: skip
    fig.tight_layout()
    return fig


def _density(r: Any) -> str:
    return (
        f"{r.crowd.density:g}/m^2"
        if r.crowd.density is not None
        else f"{r.crowd.pedestrians} people"
    )


def _outcome(r: Any) -> str:
    return f"{r.outcome} at {r.outcome_time:.1f} s"


def _ci(row: pd.Series, rate: str) -> str:
    v, lo, hi = row[f"{rate}_rate"], row[f"{rate}_low"], row[f"{rate}_high"]
    return "n/a" if not math.isfinite(v) else f"{v:.2f} [{lo:.2f}, {hi:.2f}]"


def rates_table(summary: pd.DataFrame) -> pd.DataFrame:
    """The summary as shown: rates with their intervals, time to goal, clearance, delay.

    Parameters
    ----------
    summary
        The study's summary.
    """
    rows = []
    clear = ("clearance_min_m", "clearance_p05_m", "clearance_median_m")
    for _, r in summary.iterrows():
        row = {"pedestrians": r["model"]} if "model" in r else {}
        row |= {"layout": r["scenario"], "density (1/m^2)": f"{r['density']:g}",
               "method": r["method"], "runs": int(r["runs"])}  # fmt: skip
        for rate, name in (("success", "success"), ("collision", "collision"),
                           ("timeout", "timeout"), ("left_area", "left area"),
                           ("simulator_failed", "simulator failed"),
                           ("critical", "critical entry")):  # fmt: skip
            row[name] = _ci(r, rate) if f"{rate}_rate" in r else "n/a"
        row["time to goal (s)"] = _num(r["time_to_goal_mean_s"])
        row["clearance min / p5 / median (m)"] = " / ".join(_num(r[c]) for c in clear)
        row["personal space (s)"] = _num(r["personal_space_mean_s"])
        row["ped. delay (s)"] = _num(r["ped_delay_mean_s"])
        row["ped. deviation (m)"] = _num(r["ped_deviation_mean_m"])
        row.update(_field_cells(r))
        rows.append(row)
    return pd.DataFrame(rows)


def _field_cells(r: pd.Series) -> dict[str, str]:
    """The field's metrics of a summary row as shown (n/a where a store lacks them)."""
    g = r.get
    return {
        "SPL": _num(g("spl", math.nan)),
        "path (m)": _num(g("path_length_m_mean", math.nan)),
        "jerk (m/s^3)": _num(g("jerk_mean_mean", math.nan)),
        "discomfort share": _num(g("discomfort_share_mean", math.nan)),
        "personal-space share": _num(g("intrusion_share_mean", math.nan)),
        "min TTC (s)": _num(g("ttc_min_s_mean", math.nan)),
        "frozen": _num(g("frozen_mean", math.nan)),
        "collisions robot / ped. / wall": f"{_int(g('collisions_by_robot'))} / "
        f"{_int(g('collisions_by_pedestrian'))} / {_int(g('collisions_by_wall'))}",
        "density classic / Voronoi": f"{_num(g('measured_density_per_m2', math.nan))} / "
        f"{_num(g('voronoi_density_per_m2', math.nan))}",
    }


def _int(x: Any) -> str:
    return "n/a" if x is None or not math.isfinite(float(x)) else str(int(x))


def decision_lines(result: NavigationCrowdsResult) -> list[str]:
    """The tests between methods on paired crowds and the success rate against the time limit,
    computed from the runs (:mod:`~designlab.navigation.crowds.decide`).

    Parameters
    ----------
    result
        A ``navigation_crowds`` result.
    """
    runs, st = result.crowds.runs, result.study
    if "success" not in runs or len(st.methods) < 2:
        return []
    out = ["## Decisions (exact McNemar tests on paired crowds, computed from the runs)", "",
           *decision_findings(mcnemar(runs), len(st.seeds)), "",
           "Every test, with its Holm-adjusted p-value: mcnemar.csv.", ""]  # fmt: skip
    keys = [k for k in ("model", "scenario", "density") if k in runs]
    if st.crowd.horizon is None and {"free_run_s", "time_limit_s"} <= set(runs):
        top = st.crowd.horizon_factor
        ks = [k for k in (1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 7.5, 10.0) if k < top] + [top]
        curve = time_limit_curve(runs, ks, st.confidence)
        curve["rate"] = [f"{a:.2f} [{lo:.2f}, {hi:.2f}]" for a, lo, hi in
                         zip(curve.success_rate, curve.success_low, curve.success_high,
                             strict=True)]  # fmt: skip
        wide = curve.pivot_table(index=[*keys, "method"], columns="factor",
                                 values="rate", aggfunc="first", sort=False)  # fmt: skip
        wide.columns = [f"{k:g} x T_free" for k in wide.columns]
        out += ["## Success against the time limit", "",
                "The success rate had the limit been k times the robot's free-run time (from "
                "the runs' arrival times: a run counts if it arrived within the limit).", "",
                markdown_table(wide.reset_index()), ""]  # fmt: skip
    return out


def mcnemar_table(result: NavigationCrowdsResult) -> pd.DataFrame:
    """Every exact McNemar test of success between two methods on paired crowds, with its
    Holm-adjusted p-value over the whole table (empty with fewer than two methods).

    Parameters
    ----------
    result
        A ``navigation_crowds`` result.
    """
    runs = result.crowds.runs
    if "success" not in runs or len(result.study.methods) < 2:
        return pd.DataFrame()
    tests = mcnemar(runs)
    return tests.assign(p_holm=holm(tests["p_value"])) if not tests.empty else tests


def _num(x: float) -> str:
    return "n/a" if not math.isfinite(float(x)) else f"{float(x):.2f}"


def findings(summary: pd.DataFrame) -> list[str]:
    """Sentences computed from the summary: the best and worst method per rate over all runs.

    Parameters
    ----------
    summary
        The study's summary.
    """
    out = []
    per = summary.assign(s=summary["success_rate"] * summary["runs"],
                         c=summary["collision_rate"] * summary["runs"],
                         k=summary["critical_rate"] * summary["runs"])  # fmt: skip
    tot = per.groupby("method", sort=False)[["runs", "s", "c", "k"]].sum()
    for method, r in tot.iterrows():
        out.append(f"- {method}: {int(r.s)} of {int(r.runs)} runs arrived, {int(r.c)} collided, "
                   f"{int(r.k)} entered a critical region.")  # fmt: skip
    worst = summary.sort_values(["collision_rate", "success_rate"], ascending=[False, True]).iloc[0]
    among = f" among {worst['model']} pedestrians" if "model" in worst else ""
    out.append(f"- Hardest cell: {worst['method']}{among} in {worst['scenario']} at "
               f"{worst['density']:g}/m^2 (success {_ci(worst, 'success')}, collision "
               f"{_ci(worst, 'collision')}).")  # fmt: skip
    return out


def _tuning_lines(result: NavigationCrowdsResult) -> list[str]:
    opt, val = result.tuning, result.validation
    if opt is None or val is None:
        return []
    t = result.study.tuning
    g = opt.gains
    edges = ", ".join(opt.at_bounds) if opt.at_bounds else "none (every gain inside the box)"
    out = [
        "## Gains for crowds", "",
        f"CMA-ES over log-gains in the thesis's box, {t.popsize} candidates x {t.generations} "
        f"generations = {opt.evaluations} gain sets, each on the same {opt.runs} training "
        f"crowds ({t.training.scenarios}, densities {t.training.densities}, seeds "
        f"{t.training.seeds}). Fitness: the {opt.robust}"
        f"{f' (alpha {opt.alpha:g})' if opt.robust == 'cvar' else ''} of the runs' time costs "
        "(the arrival time; for a run that did not arrive, its time limit plus the distance "
        "left at the free-run speed) plus "
        f"{opt.penalty:.1f} s per unit of mean violation (a run's violation: the share of it "
        "spent inside critical regions plus the clearance deficit max(0, 0.2 m - s_min) / "
        "0.2 m, s_min its smallest surface distance to a pedestrian; 1 at touching, more with "
        "a collision's depth). Rates required of the optimum: collision <= "
        f"{opt.collision_bound:g}, critical entry <= {opt.critical_bound:g}. "
        f"Status: {opt.status}.", "",
        f"{'Optimum' if opt.status == 'ok' else 'Fittest gains (not keeping the rates)'}: "
        f"K1 = {g.k1:.3g}, b = {g.b:.3g}, K3 = {g.k3:.3g}, K5 = {g.k5:.3g} "
        f"(fitness {opt.fitness:.2f} s: time cost {opt.cost:.2f} s, mean violation "
        f"{opt.violation:.3f}; over its {opt.runs} training crowds success "
        f"{_count_ci(opt.success_rate, opt.runs)}, collision "
        f"{_count_ci(opt.collision_rate, opt.runs)}, critical entry "
        f"{_count_ci(opt.critical_rate, opt.runs)}). Gains on a bound of the box: {edges}.", "",
        *_feasibility(opt.history, opt.collision_bound, opt.critical_bound), "",
        "Validation on held-out crowds, one factor changed at a time (each step adds one change "
        f"to the one before; seeds {_seeds(t.validation.seeds)}, never a training seed), "
        f"{val.candidate} against {val.reference} on the same crowds. Cost: the penalised "
        "cost of a run (time cost + the penalty x its violation), in s; difference: "
        f"{val.candidate} minus {val.reference}, with its {result.study.confidence:.0%} t "
        "interval; p-values: exact McNemar (success) and Wilcoxon signed-rank (cost).", "",
        markdown_table(validation_table(val.to_frame())), "",
        *validation_findings(val.to_frame()), "",
    ]  # fmt: skip
    return out


def _feasibility(history: pd.DataFrame, coll: float, crit: float) -> list[str]:
    """How many candidates kept each rate and how far the fitness spread, from the history."""
    n = len(history)
    keep_c = int((history["collision_rate"] <= coll).sum())
    keep_k = int((history["critical_rate"] <= crit).sum())
    distinct = history["fitness"].round(9).nunique()
    gens = int(history["generation"].max())
    best = history.loc[history["fitness"].idxmin()]
    last = history[history["generation"] == gens]["fitness"].min()
    return [
        f"Of the {n} candidates, {keep_c} kept the collision rate, {keep_k} the critical-entry "
        f"rate and {int(history['feasible'].sum())} both; {distinct} of the {n} fitness values "
        f"are distinct (from {history['fitness'].min():.1f} to {history['fitness'].max():.1f} "
        f"s; time costs {history['cost_s'].min():.1f} to {history['cost_s'].max():.1f} s, mean "
        f"violations {history['violation'].min():.3f} to {history['violation'].max():.3f}). "
        f"The fittest candidate came in generation {int(best['generation'])} of {gens}; the "
        f"fittest of generation {gens} scored {last:.1f} s"
        + (" (the search had not converged: more generations may find better gains)."
           if gens > 1 and last > best["fitness"] else ".")
    ]  # fmt: skip


def _seeds(seeds: list[int]) -> str:
    s = sorted(seeds)
    if s == list(range(s[0], s[-1] + 1)):
        return f"{s[0]}-{s[-1]}"
    return ", ".join(str(x) for x in s)


def _count_ci(rate: float, n: int) -> str:
    k = round(rate * n)
    lo, hi = wilson_interval(k, n)
    return f"{k}/{n} [{lo:.2f}, {hi:.2f}]"


def validation_table(frame: pd.DataFrame) -> pd.DataFrame:
    """The validation steps for the report: counts with Wilson intervals, costs, differences.

    Parameters
    ----------
    frame
        :meth:`~designlab.navigation.crowds.tuning.GainValidation.to_frame`.
    """
    rows = []
    for _, r in frame.iterrows():
        n = int(r["pairs"])
        rows.append({
            "step": r["step"], "layouts": r["scenarios"], "density": r["densities"],
            "crowds": n,
            "success (tuned)": f"{int(r.a_success)}/{n} [{r.a_success_low:.2f}, "
                               f"{r.a_success_high:.2f}]",
            "success (reference)": f"{int(r.b_success)}/{n} [{r.b_success_low:.2f}, "
                                   f"{r.b_success_high:.2f}]",
            "McNemar p": f"{r.mcnemar_p:.3g}",
            "collisions": f"{int(r.a_collisions)} / {int(r.b_collisions)}",
            "cost (tuned) s": f"{r.a_cost_s:.1f}", "cost (reference) s": f"{r.b_cost_s:.1f}",
            "difference s": f"{r.difference_s:.1f} [{r.difference_low_s:.1f}, "
                            f"{r.difference_high_s:.1f}]",
            "Wilcoxon p": f"{r.wilcoxon_p:.3g}",
        })  # fmt: skip
    return pd.DataFrame(rows)


def validation_findings(frame: pd.DataFrame) -> list[str]:
    """One sentence per validation step, written from its row.

    Parameters
    ----------
    frame
        :meth:`~designlab.navigation.crowds.tuning.GainValidation.to_frame`.
    """
    what = {"seeds": "new seeds (training layouts and densities)",
            "density": "a new density as well", "layout": "a new layout as well"}  # fmt: skip
    out = []
    for _, r in frame.iterrows():
        d, lo, hi = r.difference_s, r.difference_low_s, r.difference_high_s
        head = f"- {r['step']} ({what.get(r['step'], r['step'])}, {int(r.pairs)} crowds): "
        if r.decided:
            better = r.candidate if d < 0 else r.reference
            cost = (f"{better} costs less by {abs(d):.1f} s (interval {lo:.1f} to {hi:.1f} s, "
                    f"narrower than the difference; Wilcoxon p = {r.wilcoxon_p:.2g})")  # fmt: skip
        else:
            cost = (f"no difference in cost is shown ({d:.1f} s, interval {lo:.1f} to {hi:.1f} s "
                    f"includes 0; Wilcoxon p = {r.wilcoxon_p:.2g})")  # fmt: skip
        shown = ", a difference" if r.mcnemar_p < 0.05 else ", no difference shown"
        succ = (f"; success {int(r.a_success)} vs {int(r.b_success)} of {int(r.pairs)} "
                f"(McNemar p = {r.mcnemar_p:.2g}{shown}).")  # fmt: skip
        out.append(head + cost + succ)
    return out


def navigation_crowds_markdown(result: NavigationCrowdsResult,
                               stalls: pd.DataFrame | None = None) -> str:  # fmt: skip
    """The body of the report's text: sizes, rates with intervals, findings, gains.

    The report framework adds the header and the warnings; :func:`navigation_crowds_report`
    the figures.

    Parameters
    ----------
    result
        A ``navigation_crowds`` result.
    stalls
        :func:`stall_table` of the result if already computed.
    """
    st = result.study
    summary = result.to_frame()
    c = st.crowd
    out = [
        "## What was simulated", "",
        f"{st.size()}: layouts {st.scenarios}, densities {st.densities} persons/m^2, "
        f"seeds {st.seeds}, methods {[m.label for m in st.methods]} (VFF stabilising force: "
        f"{st.stabilising}). Pedestrians: JuPedSim's {' and '.join(st.models or [c.model])}, "
        f"{'avoiding' if c.react_to_robot else 'ignoring'} the robot, {c.width:g} m x "
        f"{c.length:g} m layouts, {_limits(st)}; pedestrians' regions sized "
        f"{_SIZING[c.region_sizing]}. Rates are counted over runs; "
        f"intervals are {st.confidence:.0%} Wilson intervals. Personal space: "
        f"{st.personal_space:g} m around a pedestrian's centre (Hall's personal distance). "
        "Outcomes are exclusive, each run's first event: success (arrived), collision, "
        "left area (the robot left the walkable area), simulator failed (JuPedSim stopped), "
        "else timeout; every run that left the area, failed or whose pedestrians did not "
        "see the robot where it was is listed under Warnings.", "",
        "## Rates, times and clearances", "",
        markdown_table(rates_table(summary)), "",
        "## Findings (computed from the table above)", "",
        *findings(summary), "",
    ]  # fmt: skip
    out += decision_lines(result)
    out += _stall_lines(stall_table(result) if stalls is None else stalls)
    out += _tuning_lines(result)
    return "\n".join(out)


def _figures_section(result: NavigationCrowdsResult) -> list[str]:
    """The figures and the animations written (:func:`_gifs`)."""
    figs = [("rates against density", "rates_vs_density.png"),
            ("representative runs", "trajectories.png")]  # fmt: skip
    if result.study.animations:
        shown = {f"animation_worst_{k[1].replace(':', '_')}.gif" for k in result.tracks}
        shown.add("animation_representative.gif")
        figs += [(f"animation: {n}", f) for n, f in _animations(result) if f in shown]
    return figure_section(figs, title="Figures and animations")


_SIZING = {
    "worst_case": "for the worst case (Zeng 2011, Sec. 5.3: every pedestrian at its top speed)",
    "closing_speed": "from each pedestrian's closing speed (the thesis's critical radius, the "
    "active radius at the measured speed towards the robot: docs/navigation_crowds.md)",
}


def _limits(study: Any) -> str:
    """The time limit of each layout, said as it was set."""
    c = study.crowd
    crowds = [crowd(name, density=study.densities[0], seed=0, **c.model_dump())
              for name in study.scenarios]  # fmt: skip
    if c.horizon is not None:
        return f"time limit {c.horizon:g} s"
    each = ", ".join(f"{x.layout} {x.time_limit:.1f} s (free run {x.free_run_time:.2f} s)"
                     for x in crowds)  # fmt: skip
    return f"time limit {c.horizon_factor:g} x the robot's free-run time: {each}"


def stall_table(result: NavigationCrowdsResult) -> pd.DataFrame:
    """Why the runs shown are slow: :func:`~designlab.navigation.crowds.diagnosis.stall_summary`
    of the representative and the worst run of each method (one row per run).

    Parameters
    ----------
    result
        A ``navigation_crowds`` result.
    """
    rows = []
    for (kind, label), r in result.tracks.items():
        if not METHODS.get(r.method).force_field:  # a velocity command: no field to split
            continue
        s = stall_summary(force_breakdown(r), r.crowd.robot.max_speed)
        rows.append({"run": kind, "method": label, "layout": r.crowd.layout,
                     "density": r.crowd.density, "seed": r.crowd.seed, "outcome": _outcome(r),
                     **s})  # fmt: skip
    return pd.DataFrame(rows)


def _stall_lines(table: pd.DataFrame) -> list[str]:
    """The stall table as shown, and one sentence per method computed from it."""
    if table.empty:
        return []
    shown = table.copy()
    causes = [c for c in shown.columns if c.startswith("slow_by_")]
    for c in ("stopped", "slow", "receding", *causes):
        shown[c] = (100 * shown[c]).round(0).astype(int).astype(str) + " %"
    shown["progress_mps"] = shown["progress_mps"].map(lambda v: f"{v:.2f}")
    shown = shown.rename(columns={c: c.replace("slow_by_", "held by ") for c in causes})
    out = ["## Why the robot is slow (the runs shown)", "",
           "The field's force at every navigation sample of the runs shown, split into "
           "attraction, walls, pedestrians and the stabilising force F_L "
           "(`designlab.navigation.crowds.diagnosis`). Slow: progress towards the goal below "
           "half the speed limit; receding: moving away from the goal; held by: among the "
           "slow samples, braking in a critical region, else the part pulling away from the "
           "goal the most (for CBF, whose nominal force is the attraction alone, the "
           "filter's correction shows as none).", "", markdown_table(shown), ""]  # fmt: skip
    for method, g in table.groupby("method", sort=False):
        top = g[causes].mean().idxmax()
        out.append(f"- {method}: slow {g['slow'].mean():.0%} and receding "
                   f"{g['receding'].mean():.0%} of the time on average over its runs shown; "
                   f"the main hold: {top.replace('slow_by_', '')} "
                   f"({g[top].mean():.0%} of the slow samples).")  # fmt: skip
    return [*out, ""]


def _animations(result: NavigationCrowdsResult) -> list[tuple[str, str]]:
    """(caption, file) of each GIF: the representative run of the first method, the worst run
    of every method."""
    labels = [m.label for m in result.study.methods]
    out = [(f"representative run of {labels[0]}", "animation_representative.gif")]
    out += [(f"worst run of {m}", f"animation_worst_{m.replace(':', '_')}.gif") for m in labels]
    return out


def _gifs(result: NavigationCrowdsResult) -> dict[str, Callable[[Path], Path]]:
    """File name -> function writing the animation there, for each run tracked."""
    makers: dict[str, Callable[[Path], Path]] = {}
    if not result.study.animations:
        return makers
    labels = [m.label for m in result.study.methods]
    keys = [("representative", labels[0])] + [("worst", m) for m in labels]
    for (caption, name), key in zip(_animations(result), keys, strict=True):
        r = result.tracks.get(key)
        if r is None:  # every run of the method failed (said in the warnings)
            continue
        makers[name] = partial(animate, r.times, r.robot_positions, r.pedestrian_positions,
                               goal=r.crowd.robot_goal, walls=wall_polygons(r.crowd),
                               robot_radius=r.crowd.robot.radius,
                               person_radius=r.crowd.pedestrian_radius,
                               title=f"{caption}: {_outcome(r)}", max_frames=80)  # fmt: skip
    return makers


@register_writer(NavigationCrowdsResult)
def navigation_crowds_report(result: NavigationCrowdsResult) -> ReportParts:
    """The report's parts: the files listed in the module text and the summary's body.

    Parameters
    ----------
    result
        A ``navigation_crowds`` result.
    """
    summary = result.to_frame()
    stalls = stall_table(result)
    tables = {"rates.csv": summary, "runs.csv": result.crowds.runs, "stalls.csv": stalls}
    tests = mcnemar_table(result)
    if not tests.empty:
        tables["mcnemar.csv"] = tests
    if result.tuning is not None and result.validation is not None:
        tables["tuning_history.csv"] = result.tuning.to_frame()
        tables["gains_validation.csv"] = result.validation.to_frame()
        tables["validation_runs.csv"] = result.validation.runs
    return ReportParts(
        title=f"Navigation among crowds: {result.study.name}",
        body=[navigation_crowds_markdown(result, stalls=stalls)],
        tables=tables,
        figures={"rates_vs_density.png": lambda: rates_figure(summary),
                 "trajectories.png": lambda: trajectories_figure(result)},
        files=_gifs(result),
        no_warnings="None.",
        closing=_figures_section(result),
    )  # fmt: skip
