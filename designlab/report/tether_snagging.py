"""Report of a ``tether_snagging`` study: the corridor corner of Allan 2015 Sec. 4.5.

Files: ``summary.md`` (the thesis's numbers beside the simulated ones: first
snagging gap, collision limits, the fit (4.6), detection points; the
compensation), ``snagging.csv`` (one row per gap), ``limits.csv`` (the limits and
the fit per follower), ``features.csv`` (the prominence of each detection feature),
``causes.csv`` (the constant-speed follower's limits under each candidate cause of the
difference to the thesis), ``fits.csv`` (the fit (4.6) per follower and set of fitted gaps),
``snagging_paths.png`` (the
distorted tracked path of Fig. 4.17 and the robot's path at the detail gaps),
``snagging_limits.png`` (d_col against the gap with the thesis's fit) and
``snagging_detection.png`` (the change of beta_path against the leader's
distance, with the threshold of (4.13)).
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

from designlab.following.tether.snag import SNAG_FIT, snag_limits
from designlab.report import register_writer
from designlab.report.builder import ReportParts
from designlab.report.writers import markdown_table
from designlab.study.kinds.tether_snagging import NEAR, TetherSnaggingResult

__all__ = ["causes_section", "fit_by_gaps", "snagging_markdown", "snagging_report"]

#: The thesis's numbers (Allan 2015 Sec. 4.5.3-4.5.5), in units of w = 1 m.
THESIS = {
    "first_snag": 1.75,
    "collision": 2.25,
    "always_collides": 2.75,
    "snag_at_5m": 7.91,
    "unsnag_at_5m": 14.95,
}


def _walls(ax: plt.Axes, w: float, lo: float, hi: float) -> None:
    ax.plot([lo, 0.0, 0.0], [0.0, 0.0, hi], "k-", lw=1.5)
    ax.plot([lo, w, w], [-w, -w, hi], "k-", lw=1.5)


def paths_figure(result: TetherSnaggingResult) -> Figure:
    """Leader path, tracked (estimated tip) path and robot path at each detail gap."""
    runs = list(zip(result.detail, result.detail_compensated, strict=True))
    fig, axes = plt.subplots(1, len(runs), figsize=(4.6 * len(runs), 4.8), squeeze=False)
    for ax, (r, c) in zip(axes[0], runs, strict=True):
        w = r.scenario.width
        _walls(ax, w, -3.0, 3.0)
        ax.plot(r.leader_xy[:, 0], r.leader_xy[:, 1], "k--", lw=1.0, label="leader")
        ax.plot(
            r.tracked_xy[:, 0],
            r.tracked_xy[:, 1],
            color="tab:red",
            lw=1.0,
            label="tracked (estimated tip)",
        )
        ax.plot(r.robot_xy[:, 0], r.robot_xy[:, 1], color="tab:blue", lw=1.0, label="robot")
        ax.plot(
            c.robot_xy[:, 0],
            c.robot_xy[:, 1],
            color="tab:green",
            lw=1.0,
            ls=":",
            label="robot, compensated",
        )
        ax.set_xlim(-3.0, 2.0)
        ax.set_ylim(-2.0, 3.0)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_title(f"gap {r.scenario.gap:g} m: d_col {r.d_col:.2f} w", fontsize=10)
        ax.grid(True, alpha=0.3)
    axes[0][0].legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    return fig


def limits_figure(result: TetherSnaggingResult) -> Figure:
    """d_col (/w) against the gap (/w): the simulation, its fit and the thesis's (4.6)."""
    f = result.to_frame()
    lim = result.limits()
    fig, ax = plt.subplots(figsize=(6.5, 4.4))
    ax.plot(f["gap_over_w"], f["d_col_over_w"], "o", ms=3, label="simulated")
    ax.plot(
        f["gap_over_w"], f["compensated_d_col_over_w"], "s", ms=3, label="simulated, compensated"
    )
    d = np.linspace(0.0, 0.5, 50)
    ax.plot(np.polyval(SNAG_FIT, d), d, "k-", lw=1.0, label="thesis fit (4.6)")
    if "fit_a" in lim:
        ax.plot(
            np.polyval([lim["fit_a"], lim["fit_b"], lim["fit_c"]], d),
            d,
            "r--",
            lw=1.0,
            label="fit to the simulation",
        )
    ax.axhline(lim["r_col_over_w"], color="gray", ls=":", label="r_col (collision below)")
    ax.set_xlabel("following gap g_F / w")
    ax.set_ylabel("least wall distance d_col / w")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def detection_figure(result: TetherSnaggingResult) -> Figure:
    """|change of beta_path| against the leader's distance at the detail gaps."""
    fig, ax = plt.subplots(figsize=(7.5, 4.0))
    for r in result.detail:
        ax.plot(r.tracked_s_leader, r.beta_change, lw=0.8, label=f"gap {r.scenario.gap:g} m")
    ax.axhline(
        result.study.scenario.beta_limit, color="k", ls="--", lw=0.8, label="beta_limit (4.13)"
    )
    ax.set_xlabel("leader distance s_L (m)")
    ax.set_ylabel("|change of beta_path| (rad)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def _f(x: float) -> str:
    return "—" if not math.isfinite(x) else f"{x:.3f}"


#: How the report names each follower (``SnagScenario.follower``).
FOLLOWER_LABELS = {
    "constant_speed": "constant v_F (Table 4.1; the thesis's follower)",
    "gap": "gap-keeping (ours)",
}
#: The gaps (/w) the thesis's text names for the collision study (Sec. 4.5.4).
THESIS_GAPS = (1.75, 2.0, 2.25, 2.5, 2.75)


def _column(result: TetherSnaggingResult, follower: str) -> list[str]:
    lim = result.limits(follower)
    grid, _ = result.runs_of(follower)
    by_gap = {round(r.scenario.gap / r.scenario.width, 6): r for r in grid}
    at_1, at_275 = by_gap.get(1.0), by_gap.get(2.75)
    geo = _f(lim["geometric_snag_gap_over_w"])
    fit = "—"
    if "fit_a" in lim:
        fit = (
            f"{lim['fit_a']:.3f}, {lim['fit_b']:.3f}, {lim['fit_c']:.3f} (rms {lim['fit_rms']:.4f})"
        )
    span = "—"
    if "span_recorded_m" in lim:
        span = f"{lim['span_recorded_m']:.2f} (at {lim['span_gap_m']:g} m)"
    return [
        "not on the grid" if at_1 is None else ("snagged" if at_1.snagged.any() else "none"),
        f"{_f(lim['first_snag_gap_over_w'])} on the grid; {geo} = 1 + pi/4 by geometry",
        _f(lim["collision_gap_over_w"]),
        _f(lim["wall_gap_over_w"]),
        "not on the grid" if at_275 is None else str(at_275.status),
        fit,
        span,
    ]


def _comparison(result: TetherSnaggingResult) -> pd.DataFrame:
    rcol = result.limits()["r_col_over_w"]
    table = pd.DataFrame(
        {
            "quantity": [
                "no snagging at 1 w",
                "first snagging gap (/w)",
                "collisions start above (/w), r_col = half the vehicle length",
                "robot centre reaches the wall, d_col = 0 (/w)",
                "collision at 2.75 w",
                "fit (4.6) a, b, c",
                "string wrapped along the recorded path, without the release jump (m)",
            ],
            "Allan 2015": [
                "none",
                f"about {THESIS['first_snag']:g} (4.9)",
                f"{THESIS['collision']:g} (4.8: {np.polyval(SNAG_FIT, rcol):.3f})",
                f"{SNAG_FIT[2]:g} (4.6)",
                "in every case",
                "-0.664, -1.4, 2.565",
                f"{THESIS['unsnag_at_5m'] - THESIS['snag_at_5m']:.2f} (at 5 m)",
            ],
        }
    )
    for follower in result.followers:
        table[FOLLOWER_LABELS[follower]] = _column(result, follower)
    return table


def _gap_sets(g: np.ndarray, d: np.ndarray, snag: np.ndarray) -> dict[str, np.ndarray]:
    """The sets of fitted gaps (masks over the grid): ours and the thesis's."""
    named = np.isin(np.round(g, 6), THESIS_GAPS)
    return {
        "snagged, inside the corridor (the fit above)": snag & (d >= 0.0),
        "every snagged run": snag,
        "the gaps the thesis names, 1.75-2.75 w by 0.25 w": named,
        "the gaps the thesis names, snagged and inside": named & snag & (d >= 0.0),
    }


def fit_by_gaps(result: TetherSnaggingResult) -> pd.DataFrame:
    """The fit (4.6) over different sets of fitted gaps, per follower (``fits.csv``).

    The thesis does not say which gaps it fitted; its text names 1.75-2.75 w in steps of
    0.25 w. The curvature ``a`` depends on that choice, the slope and the constant little.
    Fitted: the main follower's grid runs, then the constant-speed follower's grid runs
    under each cause of the study's ``fit_causes``.

    Parameters
    ----------
    result
        The study's result.
    """
    grids = {FOLLOWER_LABELS[result.follower]: result.runs_of(result.follower)[0]}
    grids.update({f"constant v_F, {k}": v for k, v in result.cause_grids.items()})
    rcol = result.limits()["r_col_over_w"]
    rows = []
    for follower, grid in grids.items():
        g = np.array([r.scenario.gap / r.scenario.width for r in grid])
        d = np.array([r.d_col for r in grid])
        snag = np.array([bool(r.snagged.any()) for r in grid])
        for label, mask in _gap_sets(g, d, snag).items():
            if mask.sum() < 3 or np.unique(d[mask]).size < 3:
                continue
            fit = snag_limits(d[mask], g[mask], rcol)
            abc = {k: fit[k] for k in "abc"}
            worst = max(abs(fit[k] - t) for k, t in zip("abc", SNAG_FIT, strict=True))
            rows.append({"follower": follower, "fitted gaps": label, "runs": int(mask.sum()),
                         **abc, "gap_limit (4.8)": fit["gap_limit"],
                         "largest difference to (4.6)": worst})  # fmt: skip
    return pd.DataFrame(rows)


def _fit_claim(fits: pd.DataFrame) -> str:
    """Which follower and gap set come closest to the thesis's fit (4.6), from the table."""
    if fits.empty:
        return ""
    best = fits.loc[fits["largest difference to (4.6)"].idxmin()]
    ta, tb, tc = SNAG_FIT
    parts = [
        f"Allan 2015 (4.6): a, b, c = {ta:g}, {tb:g}, {tc:g}. Closest: {best['follower']}, "
        f"{best['fitted gaps']} ({best['runs']} runs): "
        + ", ".join(f"{best[k]:.3f}" for k in "abc")
        + f" (largest difference {best['largest difference to (4.6)']:.3f})."
    ]
    for follower, f in fits.groupby("follower", sort=False):
        lo, hi = f["a"].min(), f["a"].max()
        inside = "inside" if lo <= ta <= hi else "outside"
        parts.append(
            f"{follower}: over the {len(f)} gap sets a runs from {lo:.3f} to {hi:.3f} "
            f"(the thesis's {ta:g} {inside} that range), b from {f['b'].min():.3f} to "
            f"{f['b'].max():.3f}, c from {f['c'].min():.3f} to {f['c'].max():.3f} "
            f"(|c - {tc:g}| at most {(f['c'] - tc).abs().max():.3f})."
        )
    parts.append(
        "The distorted path's d_col(g_F) is not a parabola (its closed form is in "
        "`designlab.following.tether.snag_geometry`), so the quadratic's curvature a is set by "
        "the gaps fitted, which the thesis does not list, while c follows the follower's limits "
        "(the winch offset moves it by the offset). A follower whose a range leaves out the "
        "thesis's a is not explained by the gap sets tried here."
    )
    return " ".join(parts)


def _span_text(span: tuple[float, float] | None) -> str:
    if span is None:
        return "never"
    return f"{span[0]:.3f} to {span[1]:.3f} ({span[1] - span[0]:.2f} apart)"


def _axis_claim(result: TetherSnaggingResult) -> str:
    """The snag's length on both axes at the largest detail gap, computed from the runs."""
    runs = [r for r in result.detail if r.snag_span is not None]
    if not runs:
        return ""
    r = max(runs, key=lambda run: run.scenario.gap)
    (a, b), (ra, rb) = r.snag_span, r.snag_span_recorded  # type: ignore[misc]
    return (
        f"At g_F = {r.scenario.gap:g} m the string stays wrapped for {rb - ra:.2f} m along the "
        f"recorded path ({ra:.2f} to {rb:.2f} m, up to the last point recorded while wrapped: "
        "the estimated tip's jump back to the leader at the release is not path) and "
        f"{b - a:.2f} m along the leader's true path "
        f"(thesis: {THESIS['unsnag_at_5m'] - THESIS['snag_at_5m']:.2f} m at 5 m)."
    )


def _detection_table(result: TetherSnaggingResult) -> pd.DataFrame:
    rows = []
    for r, c in zip(result.detail, result.detail_compensated, strict=True):
        span = r.snag_span
        rows.append(
            {
                "gap (m)": f"{r.scenario.gap:g}",
                "string wraps (s_L, m)": f"{span[0]:.3f} to {span[1]:.3f}" if span else "never",
                "along the recorded path (m)": _span_text(r.snag_span_recorded),
                "detected (s_L, m)": ", ".join(f"{d:.3f}" for d in r.detections) or "—",
                "d_col (/w)": f"{r.d_col:.3f}",
                "compensated: wraps (s_L, m)": (
                    f"{c.snag_span[0]:.3f} to {c.snag_span[1]:.3f}" if c.snag_span else "never"
                ),
                "compensated: detected": ", ".join(f"{d:.3f}" for d in c.detections) or "—",
                "compensated: d_col (/w)": f"{c.d_col:.3f}",
            }
        )
    return pd.DataFrame(rows)


def _thesis_limits(r_col: float) -> dict[str, float]:
    """The thesis's first snag (4.9), collision limit (4.8 at ``r_col``, over w) and wall (4.6)."""
    return {
        "first_snag": THESIS["first_snag"],
        "collision": float(np.polyval(SNAG_FIT, r_col)),
        "wall": SNAG_FIT[2],
    }


def causes_section(result: TetherSnaggingResult) -> list[str]:
    """The constant-speed follower's limits under each candidate cause, against the thesis.

    Parameters
    ----------
    result
        The study's result.
    """
    f = result.causes
    if f.empty:
        return []
    sc = result.study.scenario.build()
    th = _thesis_limits(sc.collision_radius / sc.width)
    shown = pd.DataFrame({"cause": f["cause"]})
    worst = []
    for q, col in (("first_snag", None), ("collision", "collision_gap_over_w"),
                   ("wall", "wall_gap_over_w")):  # fmt: skip
        exact = f[f"{q}_closed_form"]
        run = exact if col is None else f[col]
        shown[f"{q.replace('_', ' ')} (/w)"] = [
            f"{r:.4f}" if col is None else f"{r:.4f} ({e:.4f})"
            for r, e in zip(run, exact, strict=True)
        ]
        worst.append((run - th[q]).abs())
    if "span_recorded_m" in f:
        thesis_span = THESIS["unsnag_at_5m"] - THESIS["snag_at_5m"]
        shown[f"span at {f['span_gap_m'].iloc[0]:g} m (m; thesis {thesis_span:.2f} at 5 m)"] = f[
            "span_recorded_m"
        ].map(lambda v: f"{v:.2f}")
    shown["largest difference to the thesis (/w)"] = (
        pd.concat(worst, axis=1).max(axis=1).map(lambda v: f"{v:.3f}")
    )
    base = f.iloc[0]
    largest = pd.concat(worst, axis=1).max(axis=1)
    best, best_diff, worst_base = f.loc[largest.idxmin()], largest.min(), largest.iloc[0]
    gap_runs = (f["collision_gap_over_w"] - f["collision_closed_form"]).abs()
    gap_runs = pd.concat([gap_runs, (f["wall_gap_over_w"] - f["wall_closed_form"]).abs()])
    return [
        "## Why the limits differ from the thesis's (causes.csv)",
        "",
        "With the thesis's follower the robot is still on the straight before the corner, "
        "exactly g_F behind the leader, while the string is wrapped; the distorted path, and "
        "so the limits, are geometry alone, with a closed form "
        "(`designlab.following.tether.snag_geometry`). Each run below changes one setting "
        "of the first row and finds the collision (d_col = r_col) and wall (d_col = 0) gaps "
        "by bisection of the simulation; the closed form is in brackets. Largest difference "
        f"between a run and its closed form: {gap_runs.max():.4f} w, so the time step, the "
        "follower's step, the straight lengths and the release cannot move the limits. The "
        f"thesis: first snag about {th['first_snag']:g} w (4.9), collision "
        f"{th['collision']:.3f} w (4.8), wall {th['wall']:.3f} w (4.6); the first row "
        f"differs by {abs(base['first_snag_closed_form'] - th['first_snag']):.3f}, "
        f"{abs(base['collision_gap_over_w'] - th['collision']):.3f} and "
        f"{abs(base['wall_gap_over_w'] - th['wall']):.3f} w, all three the same way: the "
        "thesis's robot meets each limit at a shorter gap. Two settings the thesis does not "
        "give (A7) move the limits its way: the tether's robot end behind the robot centre "
        "(a longer effective gap: all three limits move by the offset) and a height "
        "difference between the tether's ends (the measured l_m is then the 3-D length, "
        "which lengthens the estimated tip; the first snag stays where it is):",
        "",
        markdown_table(shown, index=False, disable_numparse=True),
        "",
        f"Closest: {best['cause']} (largest difference {best_diff:.3f} w, against "
        f"{worst_base:.3f} w as run). The thesis gives neither setting, so this names a "
        "cause consistent with its numbers, not the one it had.",
        "",
    ]


def snagging_markdown(result: TetherSnaggingResult) -> str:
    """The body of the summary (the framework adds header and warnings).

    Parameters
    ----------
    result
        The study's result.
    """
    st = result.study
    sc = st.scenario.build()
    comp = result.to_frame()
    fits = fit_by_gaps(result)
    lines = [
        "## Set-up (Table 4.1)",
        "",
        f"- corridor width w {sc.width:g} m, one left turn on an arc of radius w/2 about the inner "
        f"vertex; leader speed {sc.speed:g} m/s; straight {sc.approach:g} m before and "
        f"{sc.exit:g} m after the turn (not given in the thesis)",
        f"- follower step {sc.step:g} m, time step {sc.sample_time:g} s, vehicle length "
        f"{sc.vehicle_length:g} m (r_col = {sc.collision_radius:g} m)",
        f"- follower: {FOLLOWER_LABELS[sc.follower]}: "
        + (
            f"the robot drives along the recorded path at v_F = {sc.speed:g} m/s, starting "
            "g_F behind its newest point, never past it"
            if sc.follower == "constant_speed"
            else "the robot keeps g_F behind the newest recorded point"
        )
        + "; the tether wraps the inner vertex when the straight line is blocked "
        "(docs/tether_modes.md)",
        f"- gaps {st.gaps.low:g} to {st.gaps.high:g} m ({st.gaps.num} runs), each without and "
        "with the compensation",
        "",
        "## Against the thesis (Sec. 4.5.3-4.5.4)",
        "",
        markdown_table(_comparison(result), disable_numparse=True),
        "",
        "The fit's curvature depends on which gaps are fitted, which the thesis does not say "
        "(its slope and constant little); each row fits the runs of one follower over one set "
        "of gaps (fits.csv):",
        "",
        markdown_table(fits, floatfmt=".3f"),
        "",
        _fit_claim(fits),
        "",
        *causes_section(result),
        "## Detection (Sec. 4.5.5)",
        "",
        f"A change of beta_path above {sc.beta_limit:g} rad between chords of "
        f"{sc.detect_points} recorded steps flags a snag or an unsnag. Allan 2015 at g_F = 5 m: "
        f"snag at s_L = {THESIS['snag_at_5m']:g} m and unsnag at {THESIS['unsnag_at_5m']:g} m "
        f"({THESIS['unsnag_at_5m'] - THESIS['snag_at_5m']:.2f} m apart; the thesis's straight "
        "lengths are unknown, so the start point depends on them, the distance between the two "
        "on the follower). s_L is the leader's distance along its true path; the follower sees "
        "the leader only through the path it records, which the snag distorts and lengthens, "
        "and the features (4.10-4.12) are computed on that path (`docs/tether_modes.md`). "
        + _axis_claim(result),
        "",
        markdown_table(_detection_table(result), disable_numparse=True),
        "",
        "Largest |rate| of each feature near the wrap and release points (within "
        f"{NEAR:g} m of leader distance) against its largest |rate| elsewhere; the thesis finds "
        "the length and angle gradients not clearly defined and clear maxima of beta_path. A "
        "ratio above 1 is a maximum that stands out:",
        "",
        markdown_table(result.feature_prominence(), floatfmt=".3g"),
        "",
        "## Compensation",
        "",
        f"Without it {int((comp['status'] == 'collision').sum())} of {len(comp)} grid gaps end "
        f"in a collision; with it {int((comp['compensated_status'] == 'collision').sum())}, "
        "and the least wall distance over the grid is "
        f"{comp['compensated_d_col_over_w'].min():.3f} w "
        f"(without: {comp['d_col_over_w'].min():.3f} w).",
        "",
    ]
    return "\n".join(lines)


@register_writer(TetherSnaggingResult)
def snagging_report(result: TetherSnaggingResult) -> ReportParts:
    """The report's parts: summary.md, snagging.csv, limits.csv, features.csv, three PNGs.

    Parameters
    ----------
    result
        The study's result.
    """
    makers = {"paths": paths_figure, "limits": limits_figure, "detection": detection_figure}
    figures = {
        f"snagging_{name}.png": partial(make, result)
        for name, make in makers.items()
        if name == "limits" or result.detail
    }
    return ReportParts(
        body=[snagging_markdown(result)],
        no_warnings="No compensated run collides.",
        tables={
            "snagging.csv": result.to_frame(),
            "limits.csv": result.limits_frame(),
            "features.csv": result.feature_prominence(),
            **({"causes.csv": result.causes} if not result.causes.empty else {}),
            "fits.csv": fit_by_gaps(result),
        },
        figures=figures,
    )
