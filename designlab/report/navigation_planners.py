"""Report of a ``navigation_planners`` study: the Sec. 5.7 planners beside the force fields.

Files: ``summary.md`` (the thesis's finding, one table of runs, who collided and when),
``planners.csv`` (one row per run) and ``planners_paths.png`` (the robot's path of every
method and the obstacles' paths, one panel per scenario).
"""

from __future__ import annotations

import math
from functools import partial

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from designlab.report import register_writer
from designlab.report.builder import ReportParts
from designlab.report.figure_style import method_colour, start_and_goal
from designlab.report.writers import markdown_table
from designlab.study.kinds.navigation_planners import NavigationPlannersResult

__all__ = [
    "navigation_planners_figure",
    "navigation_planners_markdown",
    "navigation_planners_report",
]

_THESIS = (
    "Zeng 2011, Sec. 5.7 (Figs. 5.11-5.12): on the human who walks towards the robot, "
    "stops and turns, velocity obstacles, RRT and Field D* all collide after the human "
    "changes direction; Masoud, Ge & Cui and the new VFF do not (Table 5.1: d_h,min 1.8, "
    "1.1 and 1.4 m)."
)


def navigation_planners_figure(result: NavigationPlannersResult) -> Figure:
    """The robot's path of every method, the obstacles' paths, one panel per scenario.

    Parameters
    ----------
    result
        A ``navigation_planners`` result.
    """
    scenarios = list(dict.fromkeys(s for s, _, _ in result.runs))
    fig, axes = plt.subplots(1, len(scenarios), figsize=(6.2 * len(scenarios), 5.2),
                             squeeze=False)  # fmt: skip
    for ax, name in zip(axes[0], scenarios, strict=True):
        runs = [(m, r) for s, m, r in result.runs if s == name]
        sc = runs[0][1].scenario
        t_end = max(float(r.t[-1]) for _, r in runs)
        ts = np.linspace(0.0, t_end, 200)
        for o in sc.obstacles:
            p = o.state(ts)[0]
            ax.plot(p[:, 0], p[:, 1], "k:", lw=1.2)
            ax.add_patch(plt.Circle(tuple(p[0]), getattr(o, "radius", 0.0), fill=False,
                                    color="gray"))  # fmt: skip
        for label, r in runs:  # the method's colour; dashed: the run collides
            ax.plot(r.position[:, 0], r.position[:, 1], "--" if r.collided else "-", lw=1.5,
                    color=method_colour(r.method),
                    label=f"{label}{' (collides)' if r.collided else ''}")  # fmt: skip
        paths = np.vstack([r.position for _, r in runs] + [np.array([sc.start, sc.goal])])
        lo, hi = paths.min(axis=0) - 1.0, paths.max(axis=0) + 1.0
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        start_and_goal(ax, sc.start, sc.goal)
        ax.set_aspect("equal")
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"{result.study.name}: robot paths (dotted: obstacles' paths)", fontsize=11)
    fig.tight_layout()
    return fig


def _fmt(x: float) -> str:
    return "never" if not math.isfinite(x) else f"{x:.2f}"


def _findings(result: NavigationPlannersResult) -> list[str]:
    frame = result.to_frame()
    out = []
    for name, grp in frame.groupby("scenario", sort=False):
        hit = grp[grp["collided"]]
        if hit.empty:
            out.append(f"* **{name}**: no method collides.")
        else:
            who = ", ".join(
                f"{m} (t = {_fmt(t)} s, passing on the {side})"
                for m, t, side in zip(
                    hit["method"], hit["first_collision_s"], hit["passed_on"], strict=True
                )
            )
            out.append(f"* **{name}**: {who} collide.")
        sides = grp.groupby("passed_on")["collided"].agg(["sum", "count"])
        if len(sides) > 1 or not hit.empty:
            share = "; ".join(
                f"passing on the {side}: {int(row['sum'])} of {int(row['count'])} collide"
                for side, row in sides.iterrows()
                if side
            )
            out.append(f"  ({share}; left/right looking from the start to the goal)")
    return [*out, ""]


def navigation_planners_markdown(result: NavigationPlannersResult) -> str:
    """The body of the Markdown summary (the framework adds header and warnings).

    Parameters
    ----------
    result
        A ``navigation_planners`` result.

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> r = run_study(parse_study('''
    ... designlab: 1
    ... kind: navigation_planners
    ... name: demo
    ... scenarios: [{configuration: 1}]
    ... mirror: false
    ... planners: [{method: vo}]
    ... methods: []
    ... '''))
    >>> "no method collides" in navigation_planners_markdown(r)
    True
    """
    frame = result.to_frame()
    shown = frame.copy()
    for c in shown.columns:
        if shown[c].dtype.kind == "f":
            shown[c] = [_fmt(x) if not math.isfinite(x) else f"{x:.3f}" for x in shown[c]]
    out = [
        "## The thesis",
        "",
        _THESIS,
        "",
        "## Runs",
        "",
        "Distances are centre distances (contour distance for rectangles), m; a collision is "
        "a distance at or below rho_r + rho_o (0.6 m for the human); `entered_critical`: "
        "d <= r3 (0.8 m). Planners: docs/navigation_planners.md.",
        "",
        markdown_table(shown, index=False, disable_numparse=True),
        "",
        "## Who collides",
        "",
    ]
    out += _findings(result)
    return "\n".join(out)


@register_writer(NavigationPlannersResult)
def navigation_planners_report(result: NavigationPlannersResult) -> ReportParts:
    """The report's parts: ``planners.csv``, ``planners_paths.png`` and the summary's body.

    Parameters
    ----------
    result
        A ``navigation_planners`` result.
    """
    return ReportParts(
        title=f"Sec. 5.7 planners and force fields: {result.study.name}",
        body=[navigation_planners_markdown(result)],
        tables={"planners.csv": result.to_frame()},
        figures={"planners_paths.png": partial(navigation_planners_figure, result)},
        no_warnings="None.",
        closing=["## Figure", "", "![robot paths](planners_paths.png)", ""],
    )
