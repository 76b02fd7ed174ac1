"""Report of a ``tether_modes`` study: Allan 2015 Ch. 4 side, front and Brake modes.

Files: ``summary.md`` (the side and front runs, the thesis's statements checked
against them, the Brake runs), ``modes.csv``, ``brake.csv``,
``modes_<path>.png`` (leader and robot paths per mode, as Figs. 4.5-4.12) and
``brake.png`` (the robot's heading after the leader stops, without and with
Brake mode).
"""

from __future__ import annotations

import math
from functools import partial
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import pandas as pd
from matplotlib.figure import Figure

from designlab.following.tether import LAWS
from designlab.report import register_writer
from designlab.report.builder import ReportParts, slug
from designlab.report.figure_style import method_colour
from designlab.report.writers import markdown_table
from designlab.study.kinds.tether_modes import ModeCase, TetherModesResult

__all__ = ["brake_figure", "modes_figure", "modes_markdown", "modes_report"]


#: Why a cell of the side and front table can be empty.
_WHY_MISSING = {
    "side_offset_m": "not a side mode",
    "offset_error_mean_m": "not a side mode",
    "offset_error_inside_turns_m": "no turn, or not a side mode",
    "offset_error_outside_turns_m": "no turn, or not a side mode",
}


def modes_figure(cases: list[ModeCase]) -> Figure:
    """Leader and robot paths of one path, one panel per mode (offsets overlaid).

    Parameters
    ----------
    cases : list of ModeCase
        The side and front runs of one leader path (the first gives the leader's path
        and the title); one panel per mode, one line per run (labelled by its side offset
        l_H, or its desired length l_d for a front mode, in m).
    """
    modes = list(dict.fromkeys(c.mode for c in cases))
    fig, axes = plt.subplots(1, len(modes), figsize=(4.4 * len(modes), 4.4), squeeze=False)
    for ax, m in zip(axes[0], modes, strict=True):
        lead = cases[0].run.leader_xy
        ax.plot(lead[:, 0], lead[:, 1], "k-", lw=1.8, label="leader")
        for c in (c for c in cases if c.mode == m):
            lab = (
                f"l_H {c.offset:g} m"
                if math.isfinite(c.offset)
                else f"l_d {c.run.controller.desired_length:g} m"
            )
            ax.plot(c.run.robot_xy[:, 0], c.run.robot_xy[:, 1], lw=1.0, label=lab)
        x0, x1 = lead[:, 0].min() - 1.5, lead[:, 0].max() + 1.5
        y0, y1 = lead[:, 1].min() - 1.5, lead[:, 1].max() + 1.5
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_title(f"{cases[0].path}: {m}", fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def brake_figure(result: TetherModesResult) -> Figure:
    """Heading change after the leader stops, per law, without and with Brake mode.

    Parameters
    ----------
    result : TetherModesResult
        The study's result; its ``brakes`` runs are plotted, one panel per law, with
        the leader's stop time (s) dotted.
    """
    laws = list(dict.fromkeys(b.law for b in result.brakes))
    fig, axes = plt.subplots(1, len(laws), figsize=(4.4 * len(laws), 3.6), squeeze=False)
    for ax, law in zip(axes[0], laws, strict=True):
        for b in (b for b in result.brakes if b.law == law):
            r = b.run
            ax.plot(r.t, r.heading - r.heading[0], lw=0.9,
                    color=method_colour("BrakeMode") if b.brake else "0.45",
                    label="Brake mode" if b.brake else "without")  # fmt: skip
        ax.axvline(result.brakes[0].stop_time, color="gray", ls=":", lw=0.8)
        ax.set_title(law, fontsize=10)
        ax.set_xlabel("time (s); dotted: the leader stops")
        ax.set_ylabel("heading change (rad)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def _steadier_claim(path: str, lh: float, law: Any, row: Any, other: Any, ref: Any) -> str:
    """Whether ``law`` holds the side offset steadier than ``other``, as the thesis found."""
    a, b = law.short, other.short
    return (
        f"- {path}, l_H {lh:g} m: spread of the side offset {row['npd_std_m']:.3f} m ({a}) "
        f"against {ref['npd_std_m']:.3f} m ({b}), mean offset error "
        f"{row['offset_error_mean_m']:+.3f} against {ref['offset_error_mean_m']:+.3f} m: "
        + (
            f"{a} holds the offset more constant, as the thesis says (Fig. 4.7)."
            if row["npd_std_m"] < ref["npd_std_m"]
            else f"{a} does not hold it more constant here."
        )
    )


def _side_claims(frame: pd.DataFrame) -> list[str]:
    out = []
    side = frame[frame["mode"].isin(LAWS.choices(placement="side"))]
    pairs = [(law, LAWS.get(law.steadier_than)) for law in LAWS.variants() if law.steadier_than]
    for (path, lh), g in side.groupby(["path", "side_offset_m"], sort=False):
        by = g.set_index("mode")
        for law, other in pairs:
            if law.name in by.index and other.name in by.index:
                out.append(
                    _steadier_claim(path, lh, law, by.loc[law.name], other, by.loc[other.name])
                )
    turns = side[side["offset_error_inside_turns_m"].notna()]
    for _, row in turns.iterrows():
        ins, outs = row["offset_error_inside_turns_m"], row["offset_error_outside_turns_m"]
        out.append(
            f"- {row['path']}, {row['mode']}, l_H {row['side_offset_m']:g} m: mean |offset error| "
            f"{ins:.3f} m where the robot is inside the leader's turns, {outs:.3f} m outside: "
            + ("worse inside" if ins > outs else "not worse inside")
            + f" ({LAWS.get(row['mode']).turn_claim})."
        )
    for _, row in frame[frame["lost"]].iterrows():
        far = row["final_distance_m"]
        out.append(f"- {row['path']}, {row['mode']}: the robot lost the leader ({far:.2f} m away).")
    return out


def _brake_claims(frame: pd.DataFrame) -> list[str]:
    out = []
    for law, g in frame.groupby("law", sort=False):
        off, on = g[~g["brake"]].iloc[0], g[g["brake"]].iloc[0]
        cut = (
            1.0 - on["turned_after_stop_rad"] / off["turned_after_stop_rad"]
            if off["turned_after_stop_rad"] > 0
            else math.nan
        )
        out.append(
            f"- {law}: turning after the stop {off['turned_after_stop_rad']:.3f} -> "
            f"{on['turned_after_stop_rad']:.3f} rad ({100 * cut:.0f} % less), travel "
            f"{off['travel_after_stop_m']:.3f} -> {on['travel_after_stop_m']:.3f} m; braked "
            f"{on['braked_while_walking_pct']:.1f} % of the time while the leader walked "
            + ("(no false brake)." if on["braked_while_walking_pct"] == 0 else "(false brakes).")
        )
    return out


def modes_markdown(result: TetherModesResult) -> str:
    """The body of the summary (the framework adds header and warnings).

    Parameters
    ----------
    result
        The study's result.
    """
    st = result.study
    frame, brakes = result.to_frame(), result.brake_frame()
    cols = [
        *("path", "mode", "side_offset_m", "npd_mean_m", "npd_std_m", "offset_error_mean_m"),
        *("offset_error_inside_turns_m", "offset_error_outside_turns_m"),
        *("tether_min_m", "tether_max_m", "final_distance_m", "lost", "path_length_ratio"),
    ]
    lines = [
        "## Side and front following (Sec. 4.2-4.3)",
        "",
        f"Leader speed {st.speed:g} m/s; App. C gains; the side modes start abreast on the "
        "leader's right, the front modes l_d ahead (docs/tether_modes.md). For a side mode the "
        "normal deviation from the leader's path is the side offset (its target is l_H); the "
        "maximum is dominated by the ends of the comparison range.",
        "",
        markdown_table(frame[cols], floatfmt=".4g", missing=_WHY_MISSING),
        "",
        "Against the thesis (computed from the table):",
        "",
        *_side_claims(frame),
        "",
        "## Brake mode (Sec. 4.4)",
        "",
        f"The leader walks {st.brake_walk:g} m and stands still for {st.brake_wait:g} s; the "
        f"tether sensor has noise sigma_l {st.brake_length_noise:g} m and sigma_theta "
        f"{st.brake_angle_noise:g} rad. Brake mode engages below l_d + {st.engage_margin:g} m and "
        f"releases above l_d + {st.release_margin:g} m (the thesis gives no threshold, A14). "
        "Turning and travel are counted from 1 s after the stop.",
        "",
        markdown_table(brakes, floatfmt=".4g"),
        "",
        *_brake_claims(brakes),
        "",
        "The thesis's other Brake function, raising the motor gains to hold on slopes, is not "
        "modelled: a kinematic robot holds still at zero command.",
        "",
    ]
    return "\n".join(lines)


@register_writer(TetherModesResult)
def modes_report(result: TetherModesResult) -> ReportParts:
    """The report's parts: summary.md, modes.csv, brake.csv and the figures.

    Parameters
    ----------
    result
        The study's result.
    """
    by_path: dict[str, list[ModeCase]] = {}
    for c in result.cases:
        by_path.setdefault(c.path, []).append(c)
    figures = {f"modes_{slug(p)}.png": partial(modes_figure, cases) for p, cases in by_path.items()}
    if result.brakes:
        figures["brake.png"] = partial(brake_figure, result)
    return ReportParts(
        body=[modes_markdown(result)],
        no_warnings="No warnings.",
        tables={"modes.csv": result.to_frame(), "brake.csv": result.brake_frame()},
        figures=figures,
    )
