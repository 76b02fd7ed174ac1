"""Report of a ``tether_stability`` study: the convergence map of Allan 2015 Figs. 2.9-2.10.

Files: ``summary.md`` (the reconstruction and its criterion, per law the share
of the grid that converged, the convergence times, where it did not converge,
and the thesis's claim checked against the map), ``convergence.csv`` (every law
and grid point) and ``convergence_<law>.png`` (convergence time over the initial
tether angle and length; grid points that did not converge in black).
"""

from __future__ import annotations

import math
from functools import partial

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from designlab.following.tether.stability import ConvergenceMap
from designlab.report import register_writer
from designlab.report.builder import ReportParts, slug
from designlab.report.writers import markdown_table
from designlab.study.kinds.tether_stability import TetherStabilityResult

__all__ = ["convergence_figure", "stability_markdown", "stability_report"]


def convergence_figure(title: str, m: ConvergenceMap) -> Figure:
    """Convergence time (s) over theta_0 (deg) and l_0 (m); black: did not converge.

    Parameters
    ----------
    title
        The law's label.
    m
        Its map.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = plt.subplots(figsize=(7.5, 4.6))
    cmap = plt.get_cmap("viridis").with_extremes(bad="black")
    deg = np.degrees(m.angles)
    img = ax.pcolormesh(deg, m.lengths, np.ma.masked_invalid(m.time), cmap=cmap, shading="nearest")
    fig.colorbar(img, ax=ax, label="convergence time (s)")
    ax.set_xlabel(r"initial tether angle $\theta_0$ (deg)")
    ax.set_ylabel(r"initial tether length $l_0$ (m)")
    ax.axhline(m.controller.desired_length, color="white", ls="--", lw=0.8)
    ax.set_title(
        f"{title}: {100 * m.converged.mean():.1f} % of the grid converged within "
        f"{m.max_time:g} s (black: not)",
        fontsize=10,
    )
    fig.tight_layout()
    return fig


def _ranges(values: np.ndarray) -> str:
    return f"{values.min():.3g} to {values.max():.3g}"


def _law_row(title: str, m: ConvergenceMap) -> dict[str, str]:
    t = m.time[np.isfinite(m.time)]
    i, j = np.unravel_index(np.nanargmax(m.time), m.time.shape) if t.size else (0, 0)
    bad = ~m.converged
    ll, aa = np.meshgrid(m.lengths, m.angles, indexing="ij")
    return {
        "law": title,
        "l_d (m)": f"{m.controller.desired_length:g}",
        "grid points": str(m.time.size),
        "converged": f"{100 * m.converged.mean():.1f} %",
        "median time (s)": f"{np.median(t):.2f}" if t.size else "—",
        "slowest (s)": f"{t.max():.2f} at l_0 {m.lengths[i]:.3g} m, theta_0 "
        f"{math.degrees(m.angles[j]):.0f} deg"
        if t.size
        else "—",
        "not converged, at rest not facing the leader": str(int((bad & m.at_rest).sum())),
        "not converged, still moving": str(int((bad & ~m.at_rest).sum())),
        "not converged: l_0 (m)": _ranges(ll[bad]) if bad.any() else "—",
        "not converged: theta_0 (deg)": _ranges(np.degrees(aa[bad])) if bad.any() else "—",
    }


def _claim(result: TetherStabilityResult) -> list[str]:
    out = [
        "## Against the thesis",
        "",
        "Allan 2015 Sec. 2.4.5: the control converged for all inputs in the tested range "
        "(Figs. 2.9 PJ and 2.10 FTL, plots only) and is 'stable for all realistic steering "
        "inputs'. On this grid:",
        "",
    ]
    for title, m in zip(result.titles, result.maps, strict=True):
        if m.converged.all():
            out.append(f"- {title}: every grid point converged (reproduced).")
        else:
            n = int((~m.converged).sum())
            out.append(
                f"- {title}: {n} of {m.time.size} grid points did not converge within "
                f"{m.max_time:g} s (not reproduced for this law)."
            )
    return [*out, ""]


def stability_markdown(result: TetherStabilityResult) -> str:
    """The body of the summary (the framework adds header and warnings).

    Parameters
    ----------
    result
        The study's result.
    """
    st = result.study
    robot = st.robot.build()
    lines = [
        "## Set-up",
        "",
        "The thesis's grid, tolerance and leader motion are not stated (docs/tether_modes.md). "
        "Here the leader stands still at (l_0, theta_0) from a robot at rest; the robot has "
        "converged once, until the end of the run, |theta_m| < "
        f"{st.tol_angle:g} rad, |V| and b|Omega|/2 < {st.tol_speed:g} m/s and "
        f"l_m - l_d < {st.tol_length:g} m, for at least {st.hold:g} s "
        "(a slack tether counts: the forward-only laws then only turn to face the leader).",
        "",
        f"- grid: l_0 from {st.lengths.low:g} to {st.lengths.high:g} m ({st.lengths.num} "
        f"points; the thesis's 0 < l_m < 10, read in metres), theta_0 from -180 to 180 deg "
        f"({st.angles} points)",
        f"- robot: b {robot.wheel_track:g} m, r {robot.wheel_radius:g} m, dt "
        f"{robot.sample_time:g} s, wheel speed limit {robot.max_wheel_speed:g} rad/s",
        f"- time allowed: {st.max_time:g} s",
        "",
        "## Convergence per law",
        "",
        markdown_table(
            pd.DataFrame([_law_row(t, m) for t, m in zip(result.titles, result.maps, strict=True)]),
            disable_numparse=True,
        ),
        "",
        *_claim(result),
    ]
    return "\n".join(lines)


@register_writer(TetherStabilityResult)
def stability_report(result: TetherStabilityResult) -> ReportParts:
    """The report's parts: summary.md, convergence.csv, one PNG per law.

    Parameters
    ----------
    result
        The study's result.
    """
    figures = {
        f"convergence_{slug(title, 'law')}.png": partial(convergence_figure, title, m)
        for title, m in zip(result.titles, result.maps, strict=True)
    }
    return ReportParts(
        body=[stability_markdown(result)],
        no_warnings="Every grid point of every law converged.",
        tables={"convergence.csv": result.to_frame()},
        figures=figures,
    )
