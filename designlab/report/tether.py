"""Reports of the tether-follower studies (Allan 2015): comparison and tuning.

``tether_comparison`` files:

``metrics.csv``
    One row per (path, l_d, law): normal path deviation (m and wheel tracks),
    tether-length error and range, smoothness, stops, path-length ratio.
``linear.csv``
    Per (law, l_d): the linearised lateral loop (python-control: poles as
    damping ratio and natural frequency, phase margin, crossover, tether-length
    pole, steady length, sampled stability) and the damping ratio and natural
    frequency fitted to a simulated lateral step.
``npd_heuristic.csv``
    Per case: the mean NPD by App. A and with the opt-in
    ``far_hit_fallback_ratio = 3`` heuristic, and the relative change.
``allan_tables.csv``
    Allan 2015 Tables 3.2 and 3.3 (measured, per subject).
``summary.md``
    The simulated mean deviation next to Tables 3.2/3.3, the PJ/FTL-CD
    factor, the other figures, the figures and the warnings.
``trajectories_<path>.png`` / ``npd_profiles_<path>.png``
    Leader and follower paths, and the per-segment deviation, per l_d.

``tether_tuning`` files: ``gains.csv`` (default vs tuned gains),
``scenarios.csv`` (cost parts per scenario), ``improvement.csv`` (per law: the
improvements with and without penalties, violations, wheel saturation), ``summary.md`` and
``tuning_<law>.png`` (deviation per scenario, default vs tuned, and the
optimiser's progress).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from designlab.following.tether import LAWS, allan_tables, measured_ratio, normal_path_deviation
from designlab.following.tether.reference import TABLES
from designlab.report import register_writer
from designlab.report.builder import ReportParts, claims, figure_section, slug
from designlab.report.figure_style import method_colour
from designlab.report.tether_errors import error_section
from designlab.report.writers import markdown_table
from designlab.study.kinds.tether_comparison import STEP_OFFSET, TetherComparisonResult
from designlab.study.kinds.tether_tuning import TetherTuningResult

__all__ = [
    "comparison_markdown",
    "comparison_report",
    "heuristic_claim",
    "heuristic_frame",
    "improvement_frame",
    "ranking_claims",
    "ranking_column",
    "tuning_claims",
    "tuning_report",
]

_DISCUSSION = """
Measured with people, the factor PJ / FTL-CD of the averages was {t32:.2f} (healthy leaders,
Table 3.2) and {t33:.2f} (patients, Table 3.3). The simulation has none of the error sources
Allan 2015 Sec. 3.4 lists for FTL-CD: wheel slip corrupts its dead reckoning and therefore its
recorded path, and the tether tip (hand or waist belt) is offset from the walking line measured
by the markers, while PJ needs neither. Human leaders also adapt (PJ subjects were told to look
back), and the patient paths were digitised at foot strikes only (about +-40 mm, Sec. 3.5),
which adds the same noise floor to both laws and pulls the ratio toward 1. The mechanisms
behind the trends listed above: PJ cuts corners by about the tether length (Sec. 2.5.2); FTL
follows the recorded path (Sec. 2.5.3) only while its 300-point buffer (3 m at 0.01 m) holds
the path behind the robot and the leader's path does not come back within about a tether
length of itself; where it does, the nearest recorded point jumps to the newer leg and FTL and
FTL-CD cut across like PJ: the buffer length (N x Delta s_min) must cover the tether length
plus the path's detours.
"""

_TUNING_INTRO = """
Status: **{status}**. Tuning paths: {paths}; validation paths (sharing no stretch with them):
{val}; leader
speeds {speeds} m/s. Seeded differential evolution (seed {s.seed}, population {s.popsize} x
gains, {s.maxiter} generations), the thesis defaults in the initial population; damping-ratio
floor {s.damping_floor:g} from the linear lateral loop at every speed; tether range
{lo:g}-{hi:g} m; at most {sat:g} % of a run with a wheel at its speed limit (a hard constraint
on the tuning paths); cost weights {w}
(`docs/following.md`).
"""


#: The law the others are compared with: the first that follows from behind (PJ).
_REFERENCE = LAWS.variants(placement="behind")[0]
#: The laws given as a ratio to it: those measured in Tables 3.2-3.3 first (FTL-CD), then the rest.
_RATIO_LAWS = sorted(
    (law for law in LAWS.variants(placement="behind") if law is not _REFERENCE),
    key=lambda law: not law.measured,
)


def _pivot(frame: pd.DataFrame, controllers: list[str]) -> pd.DataFrame:
    rows = []
    for (path, ld), grp in frame.groupby(["path", "desired_length_m"], sort=False):
        row: dict[str, Any] = {"path": path, "l_d [m]": ld}
        by = grp.set_index("controller")
        for c in controllers:
            if c in by.index:
                row[f"{c} mean/b"] = round(float(by.loc[c, "npd_mean_over_b"]), 3)
                row[f"{c} std/b"] = round(float(by.loc[c, "npd_std_over_b"]), 3)
        ref = _REFERENCE.short
        for other in _RATIO_LAWS:
            if ref in by.index and other.short in by.index:
                row[f"{ref} / {other.short}"] = round(
                    float(by.loc[ref, "npd_mean_m"] / by.loc[other.short, "npd_mean_m"]), 2
                )
        rows.append(row)
    out = pd.DataFrame(rows)
    if len(out):
        ranks = ranking_column(frame)
        out["ranking"] = [ranks[(p, ld)] for p, ld in zip(out["path"], out["l_d [m]"], strict=True)]
    return out


def _ratio_text(ratio: float) -> str:
    return f"{ratio:.2f}"


def ranking_column(frame: pd.DataFrame, metric: str = "npd_mean_m") -> pd.Series:
    """The order of the laws by ``metric`` for each (path, l_d), e.g. ``"FTL-CD < FTL < PJ"``.

    Parameters
    ----------
    frame
        One row per (path, desired_length_m, controller) with the ``metric`` column
        (``TetherComparisonResult.to_frame()``).
    metric
        The column ranked (lower is better).

    Examples
    --------
    >>> f = pd.DataFrame({"path": ["p"] * 2, "desired_length_m": [1.0] * 2,
    ...                   "controller": ["PJ", "FTL"], "npd_mean_m": [0.3, 0.1]})
    >>> ranking_column(f).tolist()
    ['FTL < PJ']
    """
    out = {}
    for key, grp in frame.groupby(["path", "desired_length_m"], sort=False):
        ordered = grp.sort_values(metric, kind="stable")
        out[key] = " < ".join(ordered["controller"])
    return pd.Series(out, name="ranking")


def _pairwise_claim(table: pd.DataFrame, law: str, reference: str) -> str:
    """How often ``law`` deviates less than ``reference``, with the factor and the exceptions."""
    ratio = (table[reference] / table[law]).dropna()
    if not len(ratio):
        return f"{law} and {reference} share no (path, l_d) case with a deviation."
    n, better = len(ratio), int((ratio > 1).sum())
    how = f"in all {n}" if better == n else f"in {better} of {n}"
    text = (
        f"{law} deviates less than {reference} {how} (path, l_d) cases; {reference} / {law} "
        f"ranges from {_ratio_text(ratio.min())} ({ratio.idxmin()[0]}, l_d = "
        f"{ratio.idxmin()[1]:g} m) to {_ratio_text(ratio.max())} ({ratio.idxmax()[0]}, "
        f"l_d = {ratio.idxmax()[1]:g} m)."
    )
    worse = ratio[ratio <= 1]
    if len(worse):
        cases = "; ".join(f"{p}, l_d = {ld:g} m ({_ratio_text(r)})" for (p, ld), r in worse.items())
        text += f" It does not on: {cases}."
    return text


def _length_trend_claim(table: pd.DataFrame, law: str) -> str:
    """Whether ``law``'s deviation grows with l_d, per path, and by how much."""
    grows, spread = [], []
    for path, col in table[law].unstack("desired_length_m").iterrows():
        vals = col.dropna().to_numpy()
        if len(vals) < 2:
            continue
        grows.append((path, bool(np.all(np.diff(vals) > 0))))
        spread.append((path, float(vals.max() / vals.min())))
    if not grows:
        return ""
    up = [p for p, g in grows if g]
    text = (
        f"{law}'s mean deviation grows with l_d on {len(up)} of {len(grows)} paths"
        + (f" ({', '.join(up)})" if 0 < len(up) < len(grows) else "")
        + "; its largest / smallest value over l_d is "
        + ", ".join(f"{_ratio_text(r)} ({p})" for p, r in spread)
        + "."
    )
    return text


def ranking_claims(
    frame: pd.DataFrame, metric: str = "npd_mean_m", reference: str = _REFERENCE.short
) -> list[str]:
    """Ranking and trend sentences computed from a comparison table (never hand-written).

    Parameters
    ----------
    frame
        One row per (path, desired_length_m, controller) with the ``metric`` column.
    metric
        The deviation compared (lower is better).
    reference
        The law the others are compared with.

    Returns
    -------
    list of str
        One sentence per other law (how often it deviates less than the
        reference, the factor's range and the exceptions), one per tether
        length (which law deviates least on how many paths), and one per law
        on the trend with l_d.

    Examples
    --------
    >>> f = pd.DataFrame({"path": ["a", "a", "b", "b"], "desired_length_m": [1.0] * 4,
    ...                   "controller": ["PJ", "FTL"] * 2, "npd_mean_m": [0.3, 0.1, 0.1, 0.2]})
    >>> print(ranking_claims(f)[0])  # doctest: +NORMALIZE_WHITESPACE
    FTL deviates less than PJ in 1 of 2 (path, l_d) cases; PJ / FTL ranges from 0.50
    (b, l_d = 1 m) to 3.00 (a, l_d = 1 m). It does not on: b, l_d = 1 m (0.50).
    """
    table = frame.pivot_table(
        index=["path", "desired_length_m"], columns="controller", values=metric, sort=False
    )
    laws = list(dict.fromkeys(frame["controller"]))
    out = [_pairwise_claim(table, law, reference) for law in laws if law != reference]
    for ld, grp in table.groupby(level="desired_length_m", sort=True):
        best = grp.idxmin(axis=1)
        parts = []
        for law in laws:
            paths = [p for p, _ in best[best == law].index]
            if paths:
                parts.append(f"{law} on {len(paths)} ({', '.join(paths)})")
        counts = ", ".join(parts)
        out.append(f"At l_d = {ld:g} m the least mean deviation is: {counts} of {len(grp)} paths.")
    out += [t for t in (_length_trend_claim(table, law) for law in laws) if t]
    return out


def _relative_change(value: float, reference: float) -> float:
    """``value / reference - 1``; 0 when both are 0 (a run on the path), inf above a 0."""
    if reference > 0:
        return value / reference - 1.0
    return 0.0 if value == 0 else math.inf


def heuristic_frame(result: TetherComparisonResult, ratio: float = 3.0) -> pd.DataFrame:
    """Mean NPD of every case by App. A and with the opt-in ``far_hit_fallback_ratio``.

    Parameters
    ----------
    result
        A comparison result (its runs are measured again with the heuristic).
    ratio
        The heuristic's ratio (3, the former default).
    """
    rows = []
    for c in result.cases:
        npd = c.metrics.npd
        alt = normal_path_deviation(
            c.run.leader_xy,
            c.run.robot_xy,
            far_hit_fallback_ratio=ratio,
            wheel_track=npd.wheel_track,
        )
        rows.append(
            {
                "path": c.path,
                "controller": c.controller,
                "desired_length_m": c.run.controller.desired_length,
                "npd_mean_m": npd.mean,
                "npd_mean_heuristic_m": alt.mean,
                "change": _relative_change(alt.mean, npd.mean),
            }
        )
    return pd.DataFrame(rows)


def heuristic_claim(table: pd.DataFrame, ratio: float = 3.0) -> str:
    """The measured effect of the opt-in heuristic on a table of :func:`heuristic_frame`.

    Parameters
    ----------
    table
        The table of :func:`heuristic_frame` (``npd_heuristic.csv``).
    ratio
        The heuristic's ratio the table was measured with.

    Examples
    --------
    >>> t = pd.DataFrame({"path": ["a", "b"], "controller": ["PJ", "FTL"],
    ...                   "desired_length_m": [1.0, 2.0], "npd_mean_m": [0.2, 0.1],
    ...                   "npd_mean_heuristic_m": [0.15, 0.1], "change": [-0.25, 0.0]})
    >>> print(heuristic_claim(t))  # doctest: +NORMALIZE_WHITESPACE
    far_hit_fallback_ratio = 3 (a heuristic, not App. A) changes the mean NPD by -25.0 % to
    +0.0 % over the 2 runs (unchanged, to 0.1 %, on 1); the largest change: a, PJ, l_d = 1 m,
    0.536 b instead of 0.714 b (b = 0.28 m).
    """
    ch = table["change"]
    i = int(np.argmax(np.abs(ch.to_numpy())))
    row = table.iloc[i]
    same = int((np.abs(ch) < 1e-3).sum())
    return (
        f"far_hit_fallback_ratio = {ratio:g} (a heuristic, not App. A) changes the mean NPD by "
        f"{100 * ch.min():+.1f} % to {100 * ch.max():+.1f} % over the {len(table)} runs "
        f"(unchanged, to 0.1 %, on {same}); the largest change: {row['path']}, "
        f"{row['controller']}, l_d = {row['desired_length_m']:g} m, "
        f"{row['npd_mean_heuristic_m'] / 0.28:.3f} b instead of {row['npd_mean_m'] / 0.28:.3f} b "
        "(b = 0.28 m)."
    )


def _comparison_header(result: TetherComparisonResult, frame: pd.DataFrame) -> list[str]:
    study = result.study
    robot = result.cases[0].run.robot if result.cases else None
    controllers = [c.title for c in study.controllers]
    robot_text = (
        f"robot b = {robot.wheel_track:g} m, r = {robot.wheel_radius:g} m, control period "
        f"{robot.sample_time:g} s, wheel limit {robot.max_wheel_speed:g} rad/s. "
        if robot
        else ""
    )
    return [
        f"Status: **{result.status}**. Leader speed {study.speed:g} m/s; "
        + robot_text
        + "Normal path deviation (NPD) as Allan 2015 App. A with the project's settings "
        "(segments 0.01-0.05 m, unsigned, ordered comparison range, 2 m search, "
        "point-to-polyline fallback; `docs/following.md`), in wheel tracks b = 0.28 m as "
        "Tables 3.2/3.3.",
        "",
        "## Mean normal path deviation (simulation)",
        "",
        markdown_table(_pivot(frame, controllers)),
        "",
    ]


def _measured_tables() -> list[str]:
    lines = ["## Measured: Allan 2015 Tables 3.2 and 3.3", ""]
    tables = allan_tables()
    names = {
        "pj_mean_dev_over_b": "PJ mean/b",
        "pj_std_dev_over_b": "PJ std/b",
        "ftlcd_mean_dev_over_b": "FTL-CD mean/b",
        "ftlcd_std_dev_over_b": "FTL-CD std/b",
    }
    for key, (_, caption) in TABLES.items():
        lines += [
            f"{caption} (PJ / FTL-CD of the averages: {measured_ratio(key):.2f})",
            "",
            markdown_table(tables[key].rename(columns=names)),
            "",
        ]
    return lines


_OTHER_COLUMNS = [
    "path",
    "controller",
    "desired_length_m",
    "npd_max_over_b",
    "length_error_rms_m",
    "tether_max_m",
    "accel_rms_m_per_s2",
    "yaw_accel_rms_rad_per_s2",
    "stops",
    "path_length_ratio",
]
_OTHER_TEXT = (
    "Tether-length error (l_m - l_d), smoothness (RMS of dV/dt and dOmega/dt), stops while the "
    "leader walks, and robot over leader distance. The maximum NPD is dominated by "
    "end-of-range artefacts on simulated runs; compare means."
)


def comparison_markdown(
    result: TetherComparisonResult,
    *,
    figures: dict[str, tuple[str, str]],
    heuristic: pd.DataFrame | None = None,
) -> str:
    """The body of the summary of a ``tether_comparison`` study (Markdown; the report
    framework adds the header and the warnings).

    Parameters
    ----------
    result
        A follower comparison result.
    figures
        Caption -> (file name, description) of the figures to show.
    heuristic
        The table of :func:`heuristic_frame` (its effect is stated), or None.
    """
    study = result.study
    frame = result.to_frame()
    controllers = [c.title for c in study.controllers]
    lines = _comparison_header(result, frame) + _measured_tables()
    if len(frame) and frame["controller"].nunique() > 1:
        reference = controllers[0]
        lines += [
            "## Ranking (computed from the table above)",
            "",
            *[f"- {c}" for c in ranking_claims(frame, reference=reference)],
            "",
        ]
        text = _DISCUSSION.format(t32=measured_ratio("table_3_2"), t33=measured_ratio("table_3_3"))
        lines += ["## Discussion", "", " ".join(text.split()), ""]
    if heuristic is not None and len(heuristic):
        lines += [
            "## The opt-in far-hit heuristic (not App. A)",
            "",
            "The NPD above is App. A: every normal hit within 2 m counts. "
            + heuristic_claim(heuristic)
            + " Per run: `npd_heuristic.csv`.",
            "",
        ]
    lines += error_section(result.errors, study)
    if result.linear is not None and len(result.linear):
        lines += _linear_section(result.linear, study.speed)
    lines += ["## Other figures (Allan 2015 Sec. 2.5.1)", "", _OTHER_TEXT, ""]
    lines += [markdown_table(frame[_OTHER_COLUMNS].round(3)), ""]
    lines += figure_section(
        (caption, name)
        for path, (traj, prof) in figures.items()
        for caption, name in ((f"trajectories on {path}", traj), (f"NPD profiles on {path}", prof))
    )
    return "\n".join(lines)


_LINEAR_TEXT = """
The lateral-error loop of each law on a straight path at {v:g} m/s, linearised (e' = v psi,
psi' = Omega, Omega = K (psi + e/L); `docs/following.md`, Allan 2015 Sec. 2.3): K is the turn
gain, L the effective look-ahead (PJ: the tether length; FTL: delta; FTL-CD: v/K_p), zeta and
omega_n from the closed-loop poles, the phase margin of the loop broken at Omega. "sim" columns
come from the two poles identified in the full nonlinear simulation (buffers, saturations,
sampling) after a {off:g} m sideways start: a least-squares second-order autoregressive model
of the sampled offset, no curve fit and no assumed initial slope. Largest |zeta sim - zeta| per
law: {err}; largest relative difference of the slow pole: {slow}. A small look-ahead weaves
(zeta < 0.5, Sec. 2.5.4).
"""


def _linear_section(linear: pd.DataFrame, speed: float) -> list[str]:
    cols = {
        "controller": "law",
        "desired_length_m": "l_d [m]",
        "turn_gain_per_s": "K [1/s]",
        "lookahead_m": "L [m]",
        "damping_ratio": "zeta",
        "sim_damping_ratio": "zeta sim",
        "natural_frequency_rad_per_s": "omega_n [rad/s]",
        "sim_natural_frequency_rad_per_s": "omega_n sim",
        "slow_pole_per_s": "slow pole [1/s]",
        "sim_slow_pole_per_s": "slow pole sim",
        "phase_margin_deg": "PM [deg]",
        "steady_length_m": "l_ss [m]",
        "discrete_stable": "sampled stable",
    }
    table = linear[list(cols)].rename(columns=cols).round(3)
    err = ", ".join(
        f"{law} {float(np.max(np.abs(g['damping_ratio_error']))):.3f}"
        for law, g in linear.groupby("controller", sort=False)
    )
    rel = (linear["sim_slow_pole_per_s"] / linear["slow_pole_per_s"] - 1).abs()
    slow = ", ".join(
        f"{law} {100 * float(g.max()):.2f} %"
        for law, g in rel.groupby(linear["controller"], sort=False)
    )
    text = _LINEAR_TEXT.format(v=speed, off=STEP_OFFSET, err=err, slow=slow)
    return [
        "## Linear lateral loop (python-control) vs simulation",
        "",
        " ".join(text.split()),
        "",
        markdown_table(table),
        "",
    ]


def _comparison_figures(result: TetherComparisonResult, path: str) -> tuple[Figure, Figure]:
    cases = [c for c in result.cases if c.path == path]
    lengths = sorted({c.run.controller.desired_length for c in cases})
    ncol = len(lengths)
    traj = Figure(figsize=(4.2 * ncol, 4.2), layout="constrained")
    prof = Figure(figsize=(4.2 * ncol, 3.2), layout="constrained")
    axs_t = traj.subplots(1, ncol, squeeze=False)[0]
    axs_p = prof.subplots(1, ncol, squeeze=False)[0]
    for ax_t, ax_p, ld in zip(axs_t, axs_p, lengths, strict=True):
        sel = [c for c in cases if c.run.controller.desired_length == ld]
        if not sel:
            continue
        leader = sel[0].run.leader_xy
        ax_t.plot(leader[:, 0], leader[:, 1], "k-", lw=2.0, label="leader")
        obs = sel[0].run.path.obstacles
        if len(obs):
            ax_t.plot(obs[:, 0], obs[:, 1], "k^", ms=8, label="cones")
        for c in sel:
            col = method_colour(c.controller)
            ax_t.plot(
                c.run.robot_xy[:, 0], c.run.robot_xy[:, 1], color=col, lw=1.2, label=c.controller
            )
            npd = c.metrics.npd
            ax_p.plot(
                npd.distance, npd.profile / npd.wheel_track, color=col, lw=1.0, label=c.controller
            )
        ax_t.set_aspect("equal", adjustable="datalim")
        ax_t.set_title(f"{path}, l_d = {ld:g} m")
        ax_t.set_xlabel("x [m]")
        ax_t.set_ylabel("y [m]")
        ax_t.legend(fontsize=7)
        ax_p.set_title(f"{path}, l_d = {ld:g} m")
        ax_p.set_xlabel("distance along the leader path [m]")
        ax_p.set_ylabel("normal deviation / b")
        ax_p.legend(fontsize=7)
    return traj, prof


@register_writer(TetherComparisonResult)
def comparison_report(result: TetherComparisonResult) -> ReportParts:
    """The parts of the ``tether_comparison`` report (see the module notes).

    Parameters
    ----------
    result
        A follower comparison result.
    """
    tables = {"metrics.csv": result.to_frame()}
    if result.linear is not None:
        tables["linear.csv"] = result.linear
    allan = allan_tables()
    tables["allan_tables.csv"] = pd.concat(
        [t.assign(table=k) for k, t in allan.items()], ignore_index=True
    )
    makers: dict[str, Callable[[], Figure]] = {}
    figures: dict[str, tuple[str, str]] = {}
    for path in dict.fromkeys(c.path for c in result.cases):
        part = slug(path, "path")
        names = (f"trajectories_{part}.png", f"npd_profiles_{part}.png")
        made = partial(_comparison_figures, result, path)  # draws both; each maker keeps one
        makers[names[0]] = lambda made=made: made()[0]
        makers[names[1]] = lambda made=made: made()[1]
        figures[path] = names
    heuristic = heuristic_frame(result)
    tables["npd_heuristic.csv"] = heuristic
    if result.errors is not None:
        tables["error_sources.csv"] = result.errors
    text = comparison_markdown(result, figures=figures, heuristic=heuristic)
    return ReportParts(body=[text], tables=tables, figures=makers)


def _tuning_figure(r: Any) -> Figure:
    tab = r.scenarios
    keys = tab[tab["controller"] == "default"][["set", "path", "speed_m_per_s"]].reset_index(
        drop=True
    )
    # one horizontal bar pair per scenario, labelled on one line: readable for any number
    # of scenarios (the figure grows with them)
    fig = Figure(figsize=(11, max(3.8, 1.4 + 0.3 * len(keys))), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2, width_ratios=[3, 1])
    y = np.arange(len(keys))
    for j, who in enumerate(("default", "tuned")):
        vals = tab[tab["controller"] == who]["npd_mean_over_b"].to_numpy()
        ax1.barh(
            y + (j - 0.5) * 0.38, vals, height=0.38, label=who, color=("tab:gray", "tab:blue")[j]
        )
    ax1.set_yticks(
        y, [f"{p}, {v:g} m/s ({s})" for s, p, v in keys.itertuples(index=False)], fontsize=7
    )
    ax1.invert_yaxis()  # the scenarios in the order of the table, top down
    ax1.set_ylabel("leader path, leader speed (scenario set)")
    ax1.set_xlabel("mean normal deviation / b")
    ax1.set_title(f"{r.controller.name}: default vs tuned")
    ax1.legend()
    ax2.plot(np.arange(1, len(r.history) + 1), r.history, "o-")
    ax2.set_xlabel("generation")
    ax2.set_ylabel("best cost")
    ax2.set_title("differential evolution")
    return fig


def _tuned_text(r: Any, name: str, value: float) -> object:
    """A tuned gain to 3 decimals, or ``~low-high`` where the cost is flat around it."""
    near = r.near_optimal().set_index("gain") if hasattr(r, "near_optimal") else pd.DataFrame()
    if name in near.index:
        lo, hi = float(near.loc[name, "low"]), float(near.loc[name, "high"])
        if round(lo, 3) != round(hi, 3):
            return f"~{lo:.3f}-{hi:.3f}"
    return round(value, 3)


def _gains_table(result: TetherTuningResult) -> pd.DataFrame:
    rows = []
    for r in result.results:
        rows.append(
            {
                "law": r.controller.name,
                **{f"default {k}": round(v, 3) for k, v in r.default.gains.items()},
                **{f"tuned {k}": _tuned_text(r, k, v) for k, v in r.controller.gains.items()},
            }
        )
    return pd.DataFrame(rows)


def near_optimal_frame(result: TetherTuningResult) -> pd.DataFrame:
    """Per law and gain: the range of the evaluated gain sets near the best cost.

    Parameters
    ----------
    result
        A ``tether_tuning`` result.

    Returns
    -------
    pandas.DataFrame
        ``law``, ``gain``, ``low``, ``high``, ``tuned``, ``sets``, ``tolerance``
        (``near_optimal.csv``).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> import pandas as pd
    >>> from designlab.following.tether import FollowTheLeader
    >>> from designlab.following.tether.tuning import TuningResult
    >>> evaluated = pd.DataFrame({"speed_gain": [1.2, 1.1], "turn_gain": [2.9, 3.1],
    ...                           "lookahead": [0.45, 0.44], "cost": [0.50000, 0.50004]})
    >>> r = TuningResult(FollowTheLeader(speed_gain=1.2, turn_gain=2.9, lookahead=0.45),
    ...                  FollowTheLeader(), 0.5, 0.6, 0.17, 0.17, 0.1, {}, pd.DataFrame(), {},
    ...                  (0.5,), 2, 0.0, evaluated=evaluated)
    >>> frame = near_optimal_frame(SimpleNamespace(results=[r]))  # a tether_tuning result
    >>> print(frame.to_string(index=False))
                law       gain  low  high  tuned  sets  tolerance
    FollowTheLeader speed_gain 1.10  1.20   1.20     2     0.0001
    FollowTheLeader  turn_gain 2.90  3.10   2.90     2     0.0001
    FollowTheLeader  lookahead 0.44  0.45   0.45     2     0.0001
    """
    from designlab.following.tether.tuning import NEAR_OPTIMAL_COST

    frames = []
    for r in result.results:
        near = r.near_optimal()
        frames.append(
            near.assign(
                law=r.controller.name,
                sets=near.attrs["sets"],
                tolerance=NEAR_OPTIMAL_COST,
            )
        )
    cols = ["law", "gain", "low", "high", "tuned", "sets", "tolerance"]
    if not frames:
        return pd.DataFrame(columns=cols)
    return pd.concat(frames, ignore_index=True)[cols]


_REPRODUCTION_TEXT = (
    "Reproduction on another machine: the search is seeded, so the same machine and build "
    "give these tables to the bit. Another CPU (or libm, compiler, numba build) changes the "
    "last bits of each simulation; the rows of the default gains then reproduce to the digits "
    "shown (costs to 1e-3 relative), but differential evolution may take another path and end "
    "at another gain set: the tuned gains, costs and improvements are the result of this run, "
    "not digits to reproduce. Where the evaluated gain sets within {tol:g} (relative) of the "
    "best cost spread beyond the digits shown, the gains table gives their range (~low-high; "
    "every range in near_optimal.csv). Wall times are in the run record, "
    "kept outside the report (`designlab list` shows it)."
)


def improvement_frame(result: TetherTuningResult) -> pd.DataFrame:
    """One row per law: the improvements, violations and wheel saturation (numbers).

    Parameters
    ----------
    result
        A ``tether_tuning`` result.
    """
    rows = []
    for r in result.results:
        sat = r.saturation or {}
        rows.append(
            {
                "law": r.controller.name,
                "improvement_validation": r.improvement,
                "improvement_validation_unpenalised": r.improvement_unpenalised,
                "npd_improvement_validation": r.npd_improvement,
                "improvement_tuning": r.training_improvement,
                "violations_tuning_default": r.violations["tuning"]["default"],
                "violations_tuning_tuned": r.violations["tuning"]["tuned"],
                "violations_validation_default": r.violations["validation"]["default"],
                "violations_validation_tuned": r.violations["validation"]["tuned"],
                "max_saturation_validation_default": sat.get("validation", {}).get(
                    "default", math.nan
                ),
                "max_saturation_validation_tuned": sat.get("validation", {}).get("tuned", math.nan),
                "saturation_bound": r.max_saturation,
                "min_damping_ratio": min(r.damping_ratios.values()),
                "gain_sets": r.evaluations,
                "status": str(r.status),
            }
        )
    return pd.DataFrame(rows)


def _improvement_table(frame: pd.DataFrame) -> pd.DataFrame:
    def pct(col: str) -> list[str]:
        return [f"{100 * v:.1f} %" for v in frame[col]]

    def pair(col: str, show: Callable[[Any, Any], str] = "{}/{}".format) -> list[str]:
        """``default/tuned`` of ``col``'s two columns (``col_default``, ``col_tuned``)."""
        both = zip(frame[f"{col}_default"], frame[f"{col}_tuned"], strict=True)
        return [show(a, b) for a, b in both]

    return pd.DataFrame(
        {
            "law": frame["law"],
            "cost improvement, unseen paths (with penalties)": pct("improvement_validation"),
            "without penalties": pct("improvement_validation_unpenalised"),
            "NPD improvement, unseen paths": pct("npd_improvement_validation"),
            "cost improvement, tuning paths": pct("improvement_tuning"),
            "violations default/tuned (tuning)": pair("violations_tuning"),
            "violations default/tuned (unseen)": pair("violations_validation"),
            "max time at wheel limit default/tuned (unseen)": pair(
                "max_saturation_validation", lambda a, b: f"{100 * a:.1f} % / {100 * b:.1f} %"
            ),
            "min damping ratio (tuned)": frame["min_damping_ratio"].round(3),
            "gain sets": frame["gain_sets"],
            "status": frame["status"],
        }
    )


def tuning_claims(frame: pd.DataFrame) -> list[str]:
    """One sentence per law, computed from :func:`improvement_frame` (never hand-written).

    Parameters
    ----------
    frame
        The table of :func:`improvement_frame` (``improvement.csv``).

    Examples
    --------
    >>> f = pd.DataFrame({"law": ["FTL"], "improvement_validation": [-0.1],
    ...     "improvement_validation_unpenalised": [0.2], "npd_improvement_validation": [0.05],
    ...     "violations_validation_default": [1], "violations_validation_tuned": [3],
    ...     "max_saturation_validation_default": [0.0],
    ...     "max_saturation_validation_tuned": [0.08], "saturation_bound": [0.05]})
    >>> print(tuning_claims(f)[0])  # doctest: +NORMALIZE_WHITESPACE
    FTL: on the unseen paths the tuned gains are worse than the defaults by 10.0 % of the
    full cost with the penalties and better by 20.0 % without them (+5.0 % in mean NPD); the
    two disagree: the penalties decide the sign, charged to the tuned gains;
    constraint-violating scenarios 1 -> 3; the largest time at the wheel limit 0.0 % -> 8.0 %
    of a run (bound 5 %).
    """
    out = []
    for _, r in frame.iterrows():
        full, bare = r["improvement_validation"], r["improvement_validation_unpenalised"]
        text = (
            f"{r['law']}: on the unseen paths the tuned gains are {_verdict(full)} than the "
            f"defaults by {100 * abs(full):.1f} % of the full cost with the penalties and "
            f"{_verdict(bare)} by {100 * abs(bare):.1f} % without them "
            f"({100 * r['npd_improvement_validation']:+.1f} % in mean NPD)"
        )
        if (full > 0) != (bare > 0):
            text += "; the two disagree: the penalties decide the sign, " + (
                "charged to the default gains" if full > 0 else "charged to the tuned gains"
            )
        out.append(
            f"{text}; constraint-violating scenarios "
            f"{r['violations_validation_default']} -> {r['violations_validation_tuned']}; the "
            "largest time at the wheel limit "
            f"{100 * r['max_saturation_validation_default']:.1f} % -> "
            f"{100 * r['max_saturation_validation_tuned']:.1f} % of a run "
            f"(bound {100 * r['saturation_bound']:g} %)."
        )
    return out


def _verdict(improvement: float) -> str:
    return "better" if improvement > 0 else "worse"


_IMPROVEMENT_TEXT = (
    "Cost improvement: 1 - J_tuned/J_default on the validation paths, which share no stretch "
    "with the tuning paths (checked geometrically: in place, after normalising position, "
    "heading, size and mirroring, and window by window anywhere along both paths), with J "
    "the full cost: the weighted deviation, tether-length and smoothness cost plus the "
    "constraint penalties; the figure without the penalties is beside it, and the headline "
    "above gives both. NPD improvement: 1 - mean NPD tuned/default. A violation is a "
    "scenario whose penalty exceeds 0.001: the tether left its range (10 x the excess / l_d) "
    "or a wheel ran at its speed limit for more than the bound of the run (10 x the excess "
    "fraction); the penalty and wheel_saturation columns below give the sizes. Status "
    "`not_converged` means that differential evolution used all its generations; the tuned "
    "cost on the tuning paths is still never above the defaults' when the defaults keep the "
    "wheel-limit bound (they are in the initial population). The wheel-limit bound is a hard "
    "constraint of the search on the tuning paths (a set beyond it ranks below every set "
    "within it; `infeasible` if none was found) and is measured, not imposed, on the unseen "
    "paths."
)
_SCENARIO_COLUMNS = [
    "law",
    "set",
    "path",
    "speed_m_per_s",
    "controller",
    "npd_mean_over_b",
    "length_error_rms_over_ld",
    "smoothness",
    "wheel_saturation",
    "penalty",
    "cost",
    "cost_unpenalised",
]


def _tuning_intro(result: TetherTuningResult) -> list[str]:
    study = result.study
    text = _TUNING_INTRO.format(
        status=result.status,
        paths=", ".join(p.build().name for p in study.paths),
        val=", ".join(p.build().name for p in study.validation_paths),
        speeds=", ".join(f"{v:g}" for v in study.speeds),
        s=study,
        lo=study.tether_range[0],
        hi=study.tether_range[1],
        w=study.weights.model_dump(),
        sat=100 * (result.results[0].max_saturation if result.results else math.nan),
    )
    return [" ".join(text.split()), ""]


@register_writer(TetherTuningResult)
def tuning_report(result: TetherTuningResult) -> ReportParts:
    """The parts of the ``tether_tuning`` report (see the module notes).

    Parameters
    ----------
    result
        A tether tuning result.
    """
    scen = pd.concat(
        [r.scenarios.assign(law=r.controller.name) for r in result.results],
        ignore_index=True,
    )
    lines = _tuning_intro(result)
    from designlab.following.tether.tuning import NEAR_OPTIMAL_COST

    improvement = improvement_frame(result)
    lead = "Headline, on the unseen paths (with and without the penalties; the table below):"
    lines += claims(tuning_claims(improvement), lead=lead)
    gains = _gains_table(result)
    not_its = {c: "not a gain of this law" for c in gains.columns if c != "law"}
    lines += ["## Gains", "", markdown_table(gains, missing=not_its), ""]
    lines += [_REPRODUCTION_TEXT.format(tol=NEAR_OPTIMAL_COST), ""]
    lines += ["## Improvement over the thesis defaults", ""]
    lines += [markdown_table(_improvement_table(improvement)), "", _IMPROVEMENT_TEXT, ""]
    lines += ["## Per scenario", "", markdown_table(scen[_SCENARIO_COLUMNS].round(3)), ""]
    makers: dict[str, Callable[[], Figure]] = {}
    figures = {}
    for r in result.results:
        name = f"tuning_{slug(r.controller.name)}.png"
        makers[name] = partial(_tuning_figure, r)
        figures[r.controller.name] = name
    lines += figure_section(figures)
    return ReportParts(
        body=lines,
        timings={f"tune {r.controller.name}": r.wall_time for r in result.results},
        tables={
            "gains.csv": result.to_frame(),
            "scenarios.csv": scen,
            "improvement.csv": improvement,
            "near_optimal.csv": near_optimal_frame(result),
        },
        figures=makers,
    )
