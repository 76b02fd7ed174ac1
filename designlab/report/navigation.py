"""Report of a ``navigation_scenarios`` study: CSVs, Markdown summary, paths and distances.

Files written into the report directory:

``results.csv``
    One row per (scenario, method): arrival time, minimum distances, flags, H_T, H_D,
    H_E, H, the Lyapunov share, and the source's values (``ref_*``).
``stability.csv``
    The Lyapunov audit of each new-VFF run (share of active-region samples where
    dV/dt <= -b |v_L|^2, time spent in each assumption break).
``summary.md``
    The tables next to the source's, the audit, the warnings and the figures.
``trajectories_<scenario>.png``
    The robot's path for each method, the obstacles with their active (dashed) and
    critical (solid) regions.
``distances_<scenario>.png``
    Distance to each obstacle against time, with its critical radius.
``energy_<scenario>.png``
    Cumulative energy of every method against time (Zeng 2011, Fig. 7.5).
``force_<scenario>.png``
    The static field of the first new-VFF method: the total force on a log scale (its
    near-zeros are the local minima of Fig. 5.10) and the repulsion + detour part (Fig. 6.12).
``study.yaml``
    The study file as it was run (when given).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial
from typing import TYPE_CHECKING, Any

from designlab.navigation.methods import METHODS
from designlab.navigation.parameters import VFFGains
from designlab.report import register_writer
from designlab.report.builder import ReportParts, figure_section, slug
from designlab.report.figure_style import MethodStyles, start_and_goal
from designlab.report.navigation_figures import energy_figure, force_figure
from designlab.report.writers import markdown_table
from designlab.study.kinds.navigation_scenarios import NavigationScenariosResult

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["distance_figure", "navigation_markdown", "navigation_report", "trajectory_figure"]


def _region_patch(o: Any, r: float, **kw: Any) -> Any:
    from matplotlib.patches import Circle, FancyBboxPatch  # matplotlib only when drawing

    if o.kind == "rectangle":
        x0, y0 = o.center[0] - o.length / 2, o.center[1] - o.width / 2
        return FancyBboxPatch(
            (x0, y0), o.length, o.width, boxstyle=f"round,pad={r}", fill=False, **kw
        )
    return Circle((0.0, 0.0), r, fill=False, **kw)


def trajectory_figure(runs: list[Any], title: str) -> Figure:
    """Paths of every method in one scenario, obstacles and regions at the start.

    Parameters
    ----------
    runs
        The runs of one scenario (one per method).
    title
        Figure title.
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle, Rectangle

    fig = Figure(figsize=(7.5, 5.0))
    ax = fig.add_subplot(1, 1, 1)
    sc = runs[0].result.scenario
    for i, o in enumerate(sc.obstacles):
        p0 = runs[0].result.obstacle_positions[i, 0]
        p1 = runs[0].result.obstacle_positions[i, -1]
        if o.kind == "rectangle":
            ax.add_patch(
                Rectangle(
                    (o.center[0] - o.length / 2, o.center[1] - o.width / 2),
                    o.length,
                    o.width,
                    color="0.4",
                    alpha=0.6,
                )
            )
            for r, ls in ((o.r3, "-"), (o.r2, "--")):
                ax.add_patch(_region_patch(o, r, ec="0.3", ls=ls, lw=0.8))
        else:
            ax.add_patch(Circle(tuple(p0), o.radius, color="0.4", alpha=0.6))
            for r, ls in ((o.r3, "-"), (o.r2, "--")):
                c = Circle(tuple(p0), r, fill=False, ec="0.3", ls=ls, lw=0.8)
                ax.add_patch(c)
            if o.motion.moving:
                track = runs[0].result.obstacle_positions[i]
                ax.plot(track[:, 0], track[:, 1], ":", color="0.3", lw=1)
                ax.annotate(o.name, tuple(p1), fontsize=8, color="0.3")
        ax.annotate(o.name, tuple(p0), fontsize=8, color="0.2", ha="center")
    style = MethodStyles()
    for run in runs:
        r = run.result
        ax.plot(r.position[:, 0], r.position[:, 1], lw=1.5, label=run.method, **style(run.method))
    start_and_goal(ax, sc.start, sc.goal)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"{title}: paths; regions at t = 0 (solid r3, dashed r2)", fontsize=9)
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    return fig


def distance_figure(runs: list[Any], title: str) -> Figure:
    """Distance to each obstacle against time for every method, with r3.

    Parameters
    ----------
    runs
        The runs of one scenario (one per method).
    title
        Figure title.
    """
    from matplotlib.figure import Figure

    sc = runs[0].result.scenario
    n = max(1, len(sc.obstacles))
    fig = Figure(figsize=(7.5, 2.2 * n + 0.6))
    for i in range(n):
        ax = fig.add_subplot(n, 1, i + 1)
        if not sc.obstacles:
            ax.text(0.5, 0.5, "no obstacles", ha="center", transform=ax.transAxes)
            continue
        o = sc.obstacles[i]
        style = MethodStyles()
        for run in runs:
            r = run.result
            ax.plot(r.t, r.distance[i], lw=1.2, label=run.method, **style(run.method))
        ax.axhline(o.r3, color="r", lw=0.8, label="r3")
        ax.axhline(
            o.collision_distance(sc.robot.radius), color="k", lw=0.8, ls=":", label="contact"
        )
        ax.set_ylabel(f"d {o.name} (m)")
        ax.grid(alpha=0.3)
        if i == 0:
            ax.set_title(f"{title}: distances", fontsize=9)
            ax.legend(fontsize=7, ncol=3)
    fig.axes[-1].set_xlabel("t (s)")
    fig.tight_layout()
    return fig


def _draws_vff_field(method: str) -> bool:
    """Whether a run gets a force figure: the new VFF's own (stabilised, unfiltered) field."""
    m = METHODS.variants(force_field=True, stabilised=True, filtered=False)
    return method in {v.name for v in m}


def _fmt(v: Any) -> Any:
    if isinstance(v, float) and math.isinf(v):
        return "never"
    return v


def navigation_markdown(result: NavigationScenariosResult) -> str:
    """The body of the Markdown summary (the framework adds header and warnings).

    Parameters
    ----------
    result
        A ``navigation_scenarios`` result.
    """
    study = result.study
    frame = result.to_frame()
    out = [
        "Model: VFF navigation among humans (Zeng 2011, Ch. 5-7; `docs/navigation.md`): "
        "force recomputed every T_s = 0.06 s and held, 1 ms dynamics, speed 0.7 m/s and "
        "acceleration 10 m/s^2 norm-clipped, arrival at the first passage within "
        f"{study.arrival_tolerance} m of the goal. Distances are centre distances (contour "
        "distance for rectangles). `ref_*` = the thesis's simulation. Energy is the "
        "feed-forward copper loss per ohm, so only H_E is comparable with the thesis. "
        "Full precision in `results.csv`.",
        "",
        "## Results next to the thesis",
        "",
    ]
    dist_cols = [c for c in frame.columns if c.startswith("d_") and c.endswith("_min_m")]
    for scen, sub in frame.groupby("scenario", sort=False):
        out += [f"### {scen}", ""]
        cols = ["method", "T_arrive_s", "ref_T_arrive_s"]
        for c in dist_cols:
            if sub[c].notna().any():
                cols += [c] + (
                    [f"ref_{c}"] if f"ref_{c}" in sub and sub[f"ref_{c}"].notna().any() else []
                )
        cols += ["entered_critical", "collided", "H_T", "H_D", "H_E", "H"]
        if sub["ref_H"].notna().any():
            cols.append("ref_H")
        table = sub[cols].copy()
        table = table.drop(columns=[c for c in ("ref_T_arrive_s",) if table[c].isna().all()])
        table = table.map(_fmt)
        ref = {c: "not in the thesis" for c in table.columns if c.startswith("ref_")}
        out += [markdown_table(table, floatfmt=".3g", missing=ref), ""]
    stab = result.stability_frame()
    out += [
        "## Lyapunov audit of the new-VFF runs",
        "",
        "Share of the samples in an active region (no critical region) where the realised "
        "dV/dt <= -b |v_L|^2 holds (Zeng 2011, (5.5.12)), and the time the run spent where "
        "the proof's assumptions break (force or speed saturation, critical-region braking, "
        "a detour-side switch). With the stabilising force on, every violation lies in such "
        "an interval; with it off, the thesis's own field violates the bound in free "
        "active-region motion too. The sample check holds by construction; "
        "`share_V_rose_over_hold` is the share of the held 60 ms active-region periods in "
        "which V, evaluated at every 1 ms step, ended higher than it began "
        '(`docs/navigation.md`, "Audit over the held periods").',
        "",
    ]
    never = {c: "did not occur" for c in stab.columns if c.startswith("time_")}
    out += [
        markdown_table(stab, floatfmt=".3g", missing=never) if len(stab) else "No new-VFF runs.",
        "",
    ]
    return "\n".join(out)


def _figures_section(figures: dict[str, tuple[str, str]], extra: dict[str, list[str]]) -> list[str]:
    """The figures of each scenario: paths, distances, then ``extra`` (energy, field)."""
    out = ["## Figures", ""]
    for scen, (traj, dist) in figures.items():
        shown = [(f"{scen} paths", traj), (f"{scen} distances", dist)]
        shown += [(f"{scen} {name.split('_')[0]}", name) for name in extra.get(scen, [])]
        out += figure_section(shown, title=scen, level=3)
    return out


@register_writer(NavigationScenariosResult)
def navigation_report(result: NavigationScenariosResult) -> ReportParts:
    """The report's parts: results.csv, stability.csv, the figures and the summary's body.

    Parameters
    ----------
    result
        A ``navigation_scenarios`` result.
    """
    by_scen: dict[str, list[Any]] = {}
    for r in result.runs:
        by_scen.setdefault(r.scenario, []).append(r)
    makers: dict[str, Callable[[], Figure]] = {}
    figures: dict[str, tuple[str, str]] = {}
    extra: dict[str, list[str]] = {}
    for scen, runs in by_scen.items():
        part = slug(scen, "scenario")
        traj, dist = f"trajectories_{part}.png", f"distances_{part}.png"
        makers[traj] = partial(trajectory_figure, runs, scen)
        makers[dist] = partial(distance_figure, runs, scen)
        figures[scen] = (traj, dist)
        energy = f"energy_{part}.png"
        makers[energy] = partial(energy_figure, runs, scen)
        extra[scen] = [energy]
        vff = [r for r in runs if _draws_vff_field(r.result.method)]
        if vff:
            force = f"force_{part}.png"
            g = VFFGains(**vff[0].result.gains)
            makers[force] = partial(
                force_figure, vff[0].result.scenario, g, f"{scen}, {vff[0].method}"
            )
            extra[scen].append(force)
    return ReportParts(
        body=[navigation_markdown(result)],
        tables={"results.csv": result.to_frame(), "stability.csv": result.stability_frame()},
        figures=makers,
        no_warnings="None.",
        closing=_figures_section(figures, extra),
    )
