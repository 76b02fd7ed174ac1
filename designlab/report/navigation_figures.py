"""Figures of the navigation reports beyond paths and distances (Zeng 2011, Figs. 5.10, 6.12, 7.5).

* :func:`energy_figure`: the cumulative energy of every method against time (Fig. 7.5,
  where the nonholonomic robot's turn shows as a step);
* :func:`force_figure`: the static field of the new VFF over the plane: the total force
  (log scale; its near-zeros are the local minima of Fig. 5.10) and the obstacles' part
  (the net repulsive and detour surface of Fig. 6.12).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from designlab.navigation.force_map import force_map
from designlab.report.figure_style import MethodStyles, start_and_goal

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["energy_figure", "force_figure"]


def energy_figure(runs: list[Any], title: str) -> Figure:
    """Cumulative L_energy per ohm against time for every method of one scenario.

    Parameters
    ----------
    runs
        The runs of one scenario (objects with ``method`` and ``result``).
    title
        Figure title.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 3.4))
    ax = fig.add_subplot(1, 1, 1)
    style = MethodStyles()
    for run in runs:
        r = run.result
        (line,) = ax.plot(r.t, r.energy_trace(), lw=1.2, label=run.method, **style(run.method))
        if math.isfinite(r.arrival_time):
            k = min(int(np.searchsorted(r.t, r.arrival_time)), r.t.size - 1)
            ax.plot(r.t[k], r.energy_trace()[k], "o", color=line.get_color(), ms=4)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("L_energy per ohm (A^2 s)")
    ax.set_title(f"{title}: cumulative energy (dot: arrival; Zeng 2011 Fig. 7.5)", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=3)
    fig.tight_layout()
    return fig


def _regions(ax: Any, scenario: Any, t: float) -> None:
    from matplotlib.patches import Circle, Rectangle

    from designlab.navigation.engine import obstacle_tracks

    P, _, _ = obstacle_tracks(scenario, np.array([t]))
    for i, o in enumerate(scenario.obstacles):
        if o.kind == "rectangle":
            ax.add_patch(Rectangle((o.center[0] - o.length / 2, o.center[1] - o.width / 2),
                                   o.length, o.width, color="0.4", alpha=0.7))  # fmt: skip
            continue
        for r, ls in ((o.r3, "-"), (o.r2, "--")):
            ax.add_patch(Circle(tuple(P[i, 0]), r, fill=False, ec="w", ls=ls, lw=0.8))


def force_figure(scenario: Any, gains: Any, title: str, *, t: float = 0.0) -> Figure:
    """The new VFF's static field over the scenario (robot at rest, obstacles at ``t``).

    Parameters
    ----------
    scenario
        The scenario.
    gains
        :class:`~designlab.navigation.VFFGains`.
    title
        Figure title.
    t
        Time of the obstacles' positions (s).
    """
    from matplotlib.figure import Figure

    from designlab.navigation.engine import obstacle_tracks

    P, _, _ = obstacle_tracks(scenario, np.array([t]))
    pts = np.array([scenario.start, scenario.goal, *P[:, 0]])
    lo, hi = pts.min(axis=0) - 1.0, pts.max(axis=0) + 1.0
    x, y = np.linspace(lo[0], hi[0], 161), np.linspace(lo[1], hi[1], 101)
    total = force_map(scenario, gains, x, y, t=t)
    obstacles = force_map(scenario, gains, x, y, t=t, part="obstacles")
    fig = Figure(figsize=(11.0, 4.2))
    axes = fig.subplots(1, 2)
    for ax, m, label in (
        (axes[0], total, "log10 |F| total, N (Fig. 5.10: near-zeros = local minima)"),
        (axes[1], obstacles, "log10 |F| repulsion + detour, N (Fig. 6.12)"),
    ):
        z = np.log10(np.clip(m.norm, 1e-2, 1e3))
        im = ax.pcolormesh(m.x, m.y, z, shading="auto", cmap="viridis", vmin=-1, vmax=2.5)
        fig.colorbar(im, ax=ax, shrink=0.85)
        _regions(ax, scenario, t)
        start_and_goal(ax, scenario.start, scenario.goal, colour="w")
        ax.set_aspect("equal")
        ax.set_title(label, fontsize=8)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.legend(fontsize=7, loc="upper left")
    mx, my, mf = total.minimum
    if math.isfinite(mf):
        axes[0].plot(mx, my, "rx", ms=8)
        axes[0].annotate(f" smallest |F| in an active region: {mf:.2g} N", (mx, my), color="r",
                         fontsize=7)  # fmt: skip
    axes[0].set_ylabel("y (m)")
    fig.suptitle(f"{title}: static field, robot at rest, obstacles at t = {t:g} s", fontsize=9)
    fig.tight_layout()
    return fig
