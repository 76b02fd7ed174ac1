"""Report of an ``accompanying`` study: Tables 1-2 next to Wu et al. 2021, tuning, plots.

Files written into the report directory:

``summary.md``
    Settings, the simulated Table 2 (robot pose in the user's frame) and
    Table 1 (world displacements) next to the paper's, the sign check of the
    walking-average offsets, the tuned PIDs with margins and cost, warnings,
    figures.
``metrics.csv``
    One row per (controller, task): every metric of
    :class:`designlab.following.accompanying.AccompanyResult`.
``table1.csv``, ``table2.csv``
    Paper and simulation side by side (mm, degrees, as the paper).
``tuning.csv``, ``margins.csv``
    Gains, Ms, Mt, margins, improvement and cost of each controller.
``baseline_sensitivity.csv``
    The tuned PIDs' improvement against the default PID scaled by
    :data:`BASELINE_FACTORS` (the default is the project's choice).
``noise.csv``
    With the study's ``noise``: each PID (and one tuned with each limit on |C S|) without
    and with sensor noise: mean RMS error and command rate.
``trajectories_<controller>.png``
    User and robot paths in the world, one panel per task.
``errors.png``
    Position error in the user's frame against time, every controller.
``readings.png``
    String-pot readings d, theta_U, theta_R of the default PID (Fig. 7).
``bode.png``, ``nyquist.png``
    Loop transfer functions of the default and tuned PIDs (forward axis).
``study.yaml``
    The study file as it was run (when given).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from designlab.following.accompanying import (
    PAPER_TEST_NAMES,
    paper_table1,
    paper_table2,
    simulate,
)
from designlab.report import register_writer
from designlab.report.accompanying_extras import extras_frame, extras_section
from designlab.report.builder import ReportParts, claims, figure_section
from designlab.report.writers import markdown_table
from designlab.study.kinds.accompanying import AccompanyingResult

__all__ = [
    "BASELINE_FACTORS",
    "accompanying_report",
    "baseline_claim",
    "baseline_sensitivity",
    "bode_figure",
    "errors_figure",
    "nyquist_figure",
    "readings_figure",
    "sign_claim",
    "table1_frame",
    "table2_frame",
    "trajectory_figure",
    "tuning_claims",
]

_COLORS = {"default": "tab:red", "tuned": "tab:blue", "derivative_free": "tab:green"}


def table2_frame(result: AccompanyingResult) -> pd.DataFrame:
    """Table 2 (robot in LCS_U) of the paper and of each simulated controller, mm and deg.

    The simulated "gamma" columns are the bearing -atan2(X_C, Y_C), which is
    what the paper's gamma_C column holds numerically (``docs/following.md``).

    Parameters
    ----------
    result
        An accompanying study result.
    """
    paper = paper_table2().set_index("test")
    rows = []
    for name in result.study.tasks:
        test = PAPER_TEST_NAMES[name]
        p = paper.loc[test]
        rows.append(
            {
                "task": name,
                "source": "paper",
                "target_X_mm": p["target_X_C_mm"],
                "target_Y_mm": p["target_Y_C_mm"],
                "target_gamma_deg": p["target_gamma_C_deg"],
                "stop_X_mm": p["stop_X_C_mm"],
                "stop_Y_mm": p["stop_Y_C_mm"],
                "stop_gamma_deg": p["stop_gamma_C_deg"],
                "avg_X_mm": p["avg_X_C_mm"],
                "sd_X_mm": p["sd_X_C_mm"],
                "avg_Y_mm": p["avg_Y_C_mm"],
                "sd_Y_mm": p["sd_Y_C_mm"],
                "avg_gamma_deg": p["avg_gamma_C_deg"],
                "sd_gamma_deg": p["sd_gamma_C_deg"],
            }
        )
        for label, runs in result.runs.items():
            m = runs[name].metrics
            rows.append(
                {
                    "task": name,
                    "source": label,
                    "target_X_mm": 1e3 * m.target_x,
                    "target_Y_mm": 1e3 * m.target_y,
                    "target_gamma_deg": m.target_bearing_deg,
                    "stop_X_mm": 1e3 * m.stop_x,
                    "stop_Y_mm": 1e3 * m.stop_y,
                    "stop_gamma_deg": m.stop_bearing_deg,
                    "avg_X_mm": 1e3 * m.mean_x,
                    "sd_X_mm": 1e3 * m.sd_x,
                    "avg_Y_mm": 1e3 * m.mean_y,
                    "sd_Y_mm": 1e3 * m.sd_y,
                    "avg_gamma_deg": m.mean_bearing_deg,
                    "sd_gamma_deg": m.sd_bearing_deg,
                }
            )
    return pd.DataFrame(rows)


def table1_frame(result: AccompanyingResult) -> pd.DataFrame:
    """Table 1 displacements (stop - start) of user and robot, paper and simulation, mm and deg.

    The paper's forward-walking user Y displacement is printed 914 mm; its
    text gives 1914 mm (the value used here, flagged in ``note``).

    Parameters
    ----------
    result
        An accompanying study result.
    """
    paper = paper_table1()
    rows = []
    for name in result.study.tasks:
        test = PAPER_TEST_NAMES[name]
        sel = paper[paper["test"] == test]
        for _, p in sel.iterrows():
            dy = p["disp_Y_mm"]
            note = ""
            if test == "Forward walking" and p["subject"] == "user":
                dy, note = 1914.0, "printed 914; text 1914"
            rows.append(
                {
                    "task": name,
                    "source": "paper",
                    "subject": p["subject"],
                    "disp_X_mm": p["disp_X_mm"],
                    "disp_Y_mm": dy,
                    "disp_gamma_deg": p["disp_gamma_deg"],
                    "note": note,
                }
            )
        for label, runs in result.runs.items():
            m = runs[name].metrics
            for subject, a, b in (
                ("user", m.user_start, m.user_stop),
                ("robot", m.robot_start, m.robot_stop),
            ):
                rows.append(
                    {
                        "task": name,
                        "source": label,
                        "subject": subject,
                        "disp_X_mm": 1e3 * (b[0] - a[0]),
                        "disp_Y_mm": 1e3 * (b[1] - a[1]),
                        "disp_gamma_deg": b[2] - a[2],
                        "note": "",
                    }
                )
    return pd.DataFrame(rows)


def _sign_table(result: AccompanyingResult) -> pd.DataFrame:
    t2 = table2_frame(result)
    rows = []
    for name in result.study.tasks:
        sub = t2[t2["task"] == name].set_index("source")
        row: dict[str, Any] = {"task": name}
        for axis in ("X", "Y"):
            paper = sub.loc["paper", f"avg_{axis}_mm"] - sub.loc["paper", f"target_{axis}_mm"]
            sim = sub.loc["default", f"avg_{axis}_mm"] - sub.loc["default", f"target_{axis}_mm"]
            row[f"paper_d{axis}_mm"] = paper
            row[f"default_d{axis}_mm"] = sim
            # below 2 mm the model has no offset in this component (the paper's comes
            # from heading changes and pelvis motion the synthetic walk does not have)
            row[f"{axis}_sign_agrees"] = (
                "n/a" if abs(sim) < 2.0 else ("yes" if np.sign(paper) == np.sign(sim) else "no")
            )
        rows.append(row)
    return pd.DataFrame(rows)


def sign_claim(signs: pd.DataFrame) -> str:
    """How often the sign of the walking-average offset agrees with the paper (from the table).

    Parameters
    ----------
    signs
        One row per task with ``X_sign_agrees``/``Y_sign_agrees`` ("yes", "no", "n/a") and
        the offsets ``paper_dX_mm``, ``default_dX_mm`` (and Y).

    Examples
    --------
    >>> t = pd.DataFrame({"task": ["a", "b"], "paper_dX_mm": [5.0, -3.0],
    ...                   "default_dX_mm": [4.0, 9.0], "X_sign_agrees": ["yes", "no"],
    ...                   "paper_dY_mm": [1.0, 1.0], "default_dY_mm": [0.0, 0.0],
    ...                   "Y_sign_agrees": ["n/a", "n/a"]})
    >>> print(sign_claim(t))  # doctest: +NORMALIZE_WHITESPACE
    The sign agrees with the paper in 1 of the 2 components where the default PID has an
    offset of 2 mm or more; it does not in: b X (paper -3 mm, model +9 mm).
    """
    cells = [(r["task"], ax, r) for _, r in signs.iterrows() for ax in ("X", "Y")]
    judged = [(t, ax, r) for t, ax, r in cells if r[f"{ax}_sign_agrees"] != "n/a"]
    bad = [(t, ax, r) for t, ax, r in judged if r[f"{ax}_sign_agrees"] == "no"]
    text = (
        f"The sign agrees with the paper in {len(judged) - len(bad)} of the {len(judged)} "
        "components where the default PID has an offset of 2 mm or more"
    )
    if bad:
        text += "; it does not in: " + ", ".join(
            f"{t} {ax} (paper {r[f'paper_d{ax}_mm']:+.0f} mm, "
            f"model {r[f'default_d{ax}_mm']:+.0f} mm)"
            for t, ax, r in bad
        )
    return text + "."


def _change(value: float, reference: float) -> str:
    rel = 1.0 - value / reference
    return f"{100 * abs(rel):.0f} % {'lower' if rel >= 0 else 'higher'}"


def tuning_claims(tuning: pd.DataFrame, metrics: pd.DataFrame) -> list[str]:
    """The tuned controllers against the default, computed from the report's tables.

    Parameters
    ----------
    tuning
        ``tuning.csv``: one row per controller (``method``) with ``mean_rms_all_tasks_m``.
    metrics
        ``metrics.csv``: one row per (controller, task) with ``rms_error_m``.

    Examples
    --------
    >>> tu = pd.DataFrame({"method": ["default", "tuned"], "mean_rms_all_tasks_m": [0.1, 0.02]})
    >>> me = pd.DataFrame({"controller": ["default", "default", "tuned", "tuned"],
    ...                    "task": ["a", "b"] * 2, "rms_error_m": [0.1, 0.1, 0.01, 0.03]})
    >>> print(tuning_claims(tu, me)[0])  # doctest: +NORMALIZE_WHITESPACE
    tuned: mean RMS error over the 2 tasks 20.0 mm against 100.0 mm with the default PID
    (80 % lower); lower on 2 of 2 tasks.
    """
    rms = tuning.set_index("method")["mean_rms_all_tasks_m"]
    per_task = metrics.pivot_table(index="task", columns="controller", values="rms_error_m")
    if "default" not in rms.index:
        return []
    out = []
    for method in [m for m in rms.index if m != "default"]:
        lower = int((per_task[method] < per_task["default"]).sum())
        out.append(
            f"{method}: mean RMS error over the {len(per_task)} tasks "
            f"{1e3 * rms[method]:.1f} mm against {1e3 * rms['default']:.1f} mm with the default "
            f"PID ({_change(rms[method], rms['default'])}); lower on {lower} of "
            f"{len(per_task)} tasks."
        )
    others = [m for m in rms.index if m != "default"]
    if len(others) == 2:
        a, b = others
        best = a if rms[a] < rms[b] else b
        worse = b if best == a else a
        wins = int((per_task[best] < per_task[worse]).sum())
        out.append(
            f"{best} has the lower mean RMS error of the two tuned controllers "
            f"({1e3 * rms[best]:.1f} mm against {1e3 * rms[worse]:.1f} mm) and is lower on "
            f"{wins} of {len(per_task)} tasks."
        )
    return out


#: Scale factors of the baseline PID in the sensitivity table (all three gains scaled).
BASELINE_FACTORS = (0.25, 0.5, 1.0, 2.0, 4.0)


def baseline_sensitivity(
    result: AccompanyingResult, factors: tuple[float, ...] = BASELINE_FACTORS
) -> pd.DataFrame:
    """The tuned PIDs' improvement against baselines scaled from the study's default PID.

    The default PID is the project's choice (the paper reports no gains), so
    the improvement depends on it: each factor f scales K_p, K_i and K_d of the
    default, the tasks are simulated with it, and ``improvement_<label>`` is
    1 - mean RMS (tuned) / mean RMS (baseline) over the study's tasks.

    Parameters
    ----------
    result
        An accompanying study result.
    factors
        Scale factors of the baseline gains.
    """
    study = result.study
    platform, sensor = study.platform.build(), study.sensor.build()
    base = study.controller.build()
    tuned = {
        label: float(np.mean([r.rms_error for r in runs.values()]))
        for label, runs in result.runs.items()
        if label != "default"
    }
    rows = []
    for f in factors:
        c = base.replace(kp=f * base.kp, ki=f * base.ki, kd=f * base.kd)
        rms = float(
            np.mean(
                [
                    simulate(study.build_task(n), c, platform=platform, sensor=sensor).rms_error
                    for n in study.tasks
                ]
            )
        )
        row: dict[str, Any] = {
            "factor": f,
            "kp_1_s": c.kp,
            "ki_1_s2": c.ki,
            "kd": c.kd,
            "mean_rms_baseline_m": rms,
        }
        row.update({f"improvement_{k}": 1.0 - v / rms for k, v in tuned.items()})
        rows.append(row)
    return pd.DataFrame(rows)


def baseline_claim(table: pd.DataFrame) -> str:
    """How much the tuned PIDs' improvement depends on the baseline (from the table).

    Parameters
    ----------
    table
        The table of :func:`baseline_sensitivity` (``baseline_sensitivity.csv``).

    Examples
    --------
    >>> t = pd.DataFrame({"factor": [0.5, 1.0, 2.0], "mean_rms_baseline_m": [0.2, 0.1, 0.05],
    ...                   "improvement_tuned": [0.95, 0.9, 0.8]})
    >>> print(baseline_claim(t))  # doctest: +NORMALIZE_WHITESPACE
    With the baseline gains scaled by 0.5-2 (mean RMS error 200.0-50.0 mm), the improvement
    of tuned ranges from 80 % (factor 2) to 95 % (factor 0.5); at the study's default
    (factor 1) it is 90 %.
    """
    out = []
    for col in [c for c in table.columns if c.startswith("improvement_")]:
        label = col.removeprefix("improvement_")
        lo, hi = table[col].idxmin(), table[col].idxmax()
        at1 = table.loc[table["factor"] == 1.0, col]
        out.append(
            f"the improvement of {label} ranges from {100 * table.loc[lo, col]:.0f} % "
            f"(factor {table.loc[lo, 'factor']:g}) to {100 * table.loc[hi, col]:.0f} % "
            f"(factor {table.loc[hi, 'factor']:g})"
            + (
                f"; at the study's default (factor 1) it is {100 * at1.iloc[0]:.0f} %"
                if len(at1)
                else ""
            )
        )
    rms = table["mean_rms_baseline_m"]
    return (
        f"With the baseline gains scaled by {table['factor'].min():g}-{table['factor'].max():g} "
        f"(mean RMS error {1e3 * rms.iloc[0]:.1f}-{1e3 * rms.iloc[-1]:.1f} mm), "
        + "; ".join(out)
        + "."
    )


def _grid(n: int) -> tuple[int, int]:
    cols = min(3, n)
    return math.ceil(n / cols), cols


def trajectory_figure(result: AccompanyingResult, label: str) -> Figure:
    """World paths of the user's frame origin and the robot, one panel per task.

    Parameters
    ----------
    result
        An accompanying study result.
    label
        Which controller's runs: ``"default"`` or ``"tuned"``.
    """
    runs = result.runs[label]
    nr, nc = _grid(len(runs))
    fig = Figure(figsize=(4.0 * nc, 3.6 * nr), layout="constrained")
    axes = fig.subplots(nr, nc, squeeze=False)
    for ax, (name, r) in zip(axes.flat, runs.items(), strict=False):
        ax.plot(r.user_pose[0], r.user_pose[1], color="k", lw=1.2, label="user")
        ax.plot(
            r.robot_pose[0],
            r.robot_pose[1],
            color=_COLORS.get(label, "tab:blue"),
            lw=1.2,
            label="robot",
        )
        step = max(1, round(1.0 / (r.time[1] - r.time[0])))  # heading marks every 1 s
        for pose, col in ((r.user_pose, "k"), (r.robot_pose, _COLORS.get(label, "tab:blue"))):
            k = slice(0, None, step)
            ax.quiver(
                pose[0, k],
                pose[1, k],
                np.cos(pose[2, k]),
                np.sin(pose[2, k]),
                color=col,
                scale=25,
                width=0.004,
                alpha=0.6,
            )
        ax.set_title(name)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("X (m)")
        ax.set_ylabel("Y (m)")
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(runs) :]:
        ax.set_visible(False)
    axes.flat[0].legend(loc="best", fontsize=8)
    fig.suptitle(f"{result.study.name}: user and robot in the world ({label} PID)")
    return fig


def errors_figure(result: AccompanyingResult) -> Figure:
    """Position error |p_T - p_C| in the user's frame against time, every controller.

    Parameters
    ----------
    result
        An accompanying study result.
    """
    names = list(result.study.tasks)
    nr, nc = _grid(len(names))
    fig = Figure(figsize=(4.0 * nc, 2.8 * nr), layout="constrained")
    axes = fig.subplots(nr, nc, squeeze=False)
    for ax, name in zip(axes.flat, names, strict=False):
        first = next(iter(result.runs.values()))[name]
        ax.axvspan(first.task.walk_start, first.task.walk_stop, color="0.9")
        for label, runs in result.runs.items():
            r = runs[name]
            e = r.position_error
            ax.plot(
                r.time, 1e3 * np.hypot(e[0], e[1]), color=_COLORS.get(label), lw=1.0, label=label
            )
        ax.axhline(20.0, color="0.5", ls=":", lw=0.8)
        ax.set_title(name)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("error (mm)")
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(names) :]:
        ax.set_visible(False)
    axes.flat[0].legend(fontsize=8)
    fig.suptitle("Position error in the user's frame (grey: user walking; dotted: 20 mm)")
    return fig


def readings_figure(result: AccompanyingResult, label: str = "default") -> Figure:
    """String-pot readings d, theta_U, theta_R against time (as Wu et al. 2021, Fig. 7).

    Parameters
    ----------
    result
        An accompanying study result.
    label
        Which controller's runs: ``"default"`` or ``"tuned"``.
    """
    runs = result.runs[label]
    names = [n for n in result.study.tasks if n in runs][:6]
    fig = Figure(figsize=(11.0, 2.3 * len(names)), layout="constrained")
    axes = fig.subplots(len(names), 2, squeeze=False)
    for row, name in zip(axes, names, strict=True):
        r = runs[name]
        t = r.time[:-1]
        row[0].plot(t, 1e3 * r.readings[0], color="k")
        row[0].set_ylabel(f"{name}\nd (mm)")
        row[1].plot(t, np.degrees(r.readings[1]), label="theta_U")
        row[1].plot(t, np.degrees(r.readings[2]), label="theta_R")
        row[1].set_ylabel("deg")
        for ax in row:
            ax.axvspan(r.task.walk_start, r.task.walk_stop, color="0.92")
            ax.grid(alpha=0.3)
    axes[0, 1].legend(fontsize=8)
    axes[-1, 0].set_xlabel("time (s)")
    axes[-1, 1].set_xlabel("time (s)")
    fig.suptitle(f"String-pot readings, {label} PID (grey: user walking)")
    return fig


def bode_figure(result: AccompanyingResult) -> Figure:
    """|L|, arg L, |S| and |T| of the forward loop of each controller.

    Parameters
    ----------
    result
        An accompanying study result.
    """
    fig = Figure(figsize=(7.5, 7.0), layout="constrained")
    ax_m, ax_p, ax_s = fig.subplots(3, 1, sharex=True)
    for label, la in result.loops.items():
        w = la.omega
        lw = la.loops["forward"]
        col = _COLORS.get(label)
        ax_m.loglog(w, np.abs(lw), color=col, label=label)
        ax_p.semilogx(w, np.degrees(np.unwrap(np.angle(lw))), color=col)
        ax_s.loglog(w, np.abs(1 / (1 + lw)), color=col, label=f"|S| {label}")
        ax_s.loglog(w, np.abs(lw / (1 + lw)), color=col, ls="--", label=f"|T| {label}")
    ax_m.axhline(1.0, color="0.5", lw=0.8)
    ax_m.set_ylabel("|L|")
    ax_m.legend(fontsize=8)
    ax_p.axhline(-180.0, color="0.5", lw=0.8)
    ax_p.set_ylabel("arg L (deg)")
    ms = result.study.tuning.ms_max if result.study.tuning is not None else None
    if ms is not None:
        ax_s.axhline(ms, color="k", ls=":", lw=0.8)
    ax_s.set_ylabel("|S|, |T|")
    ax_s.set_xlabel("frequency (rad/s)")
    ax_s.legend(fontsize=7, ncol=2)
    for ax in (ax_m, ax_p, ax_s):
        ax.grid(alpha=0.3, which="both")
    fig.suptitle("Forward (and lateral) loop, sampled at 50 Hz")
    return fig


def nyquist_figure(result: AccompanyingResult) -> Figure:
    """Nyquist curves of the forward loops with the Ms circle around -1.

    Parameters
    ----------
    result
        An accompanying study result.
    """
    fig = Figure(figsize=(6.0, 6.0), layout="constrained")
    ax = fig.subplots()
    for label, la in result.loops.items():
        lw = la.loops["forward"]
        keep = np.abs(lw) < 5
        ax.plot(lw.real[keep], lw.imag[keep], color=_COLORS.get(label), label=label)
        ax.plot(lw.real[keep], -lw.imag[keep], color=_COLORS.get(label), ls=":", lw=0.7)
    th = np.linspace(0, 2 * np.pi, 200)
    if result.study.tuning is not None:
        r = 1 / result.study.tuning.ms_max
        ax.plot(
            -1 + r * np.cos(th),
            r * np.sin(th),
            "k--",
            lw=0.8,
            label=f"|S| = {result.study.tuning.ms_max}",
        )
    ax.plot([-1], [0], "k+", ms=10)
    ax.set_xlim(-2.5, 1.0)
    ax.set_ylim(-2.5, 1.0)
    ax.set_aspect("equal")
    ax.grid(alpha=0.3)
    ax.set_xlabel("Re L")
    ax.set_ylabel("Im L")
    ax.legend(fontsize=8)
    ax.set_title("Nyquist, forward loop")
    return fig


def _fmt_number(value: float, digits: int) -> str:
    if pd.isna(value):
        return ""
    text = f"{value:.{digits}f}"
    return f"{0.0:.{digits}f}" if float(text) == 0.0 else text  # no "-0"


def _fmt_frame(frame: pd.DataFrame, digits: int = 0) -> pd.DataFrame:
    out = frame.copy()
    for c in out.columns:
        if out[c].dtype.kind == "f":
            out[c] = out[c].map(lambda v, d=digits: _fmt_number(v, d))
    return out


_CONTROLLER_COLUMNS = (
    "method",
    "kp_1_s",
    "ki_1_s2",
    "kd",
    "Ms",
    "Mt",
    "phase_margin_deg",
    "mean_rms_all_tasks_m",
    "improvement_all_tasks",
    "iterations",
    "simulations",
    "status",
)
_TRACKING_COLUMNS = [
    "controller",
    "task",
    "rms_error_m",
    "max_error_m",
    "settled_error_m",
    "lag_s",
    "overshoot_m",
    "settling_time_s",
]
_TABLE2_TEXT = (
    "`paper` rows are Wu et al. 2021, Table 2; `gamma` is the bearing of the robot seen "
    "from the user, -atan2(X_C, Y_C), which the paper's gamma_C column matches. Stop: "
    "10 s after the user stops. Average: mean (sd) while the user walks."
)
_SIGN_TEXT = (
    "The tests check the components each task drives (forward and backward: Y; right "
    "lateral and the pivots: X; the circles: X and Y); the other offsets in the paper come "
    "from heading changes and pelvis motion that the synthetic walks do not have. "
    "Left lateral walking is the paper's own anomaly (Sec. 6: at reset the distance "
    "sensor saw the user's forearm, so the target distance was too short); a robot that "
    "lags a user walking left is to the user's right (+X) of its target."
)


def _model(result: AccompanyingResult) -> list[str]:
    s = result.study
    return [
        "Model (Wu et al. 2021; `docs/following.md`): mecanum platform with a first-order "
        f"lag (tau = {s.platform.time_constant} s) and speed/acceleration saturation "
        f"({s.platform.max_speed} m/s, {s.platform.max_acceleration} m/s^2, "
        f"{s.platform.limit_mode} limits), string-pot sensor at {s.sensor.sample_rate:g} Hz "
        "with zero-order hold, the eq. (8) error in the robot frame and one PID per axis "
        "(eq. 9). The user walks synthetic versions of the paper's tasks; the robot starts "
        "on the paper's target (Table 2). The paper's gains, speeds and timing are not "
        "reported, so compare orders of magnitude and signs, not digits.",
        "",
    ]


def _controllers_section(result: AccompanyingResult) -> list[str]:
    s = result.study
    tuning = result.tuning_frame()
    cols = [c for c in _CONTROLLER_COLUMNS if c in tuning.columns]
    untuned = {c: "not tuned" for c in ("status", "iterations", "simulations",
                                          "improvement_all_tasks") if c in cols}  # fmt: skip
    out = ["## Controllers", "", markdown_table(tuning[cols], floatfmt=".4g", missing=untuned), ""]
    found = tuning_claims(tuning, result.to_frame())
    if found:
        out += claims(found, lead="Computed from the tables:")
    out += [
        "`default` is the project's choice of baseline (K_p, K_i, K_d from the study file), "
        "not the paper's: Wu et al. 2021 report no gains. The improvements above are measured "
        "against it; `baseline_sensitivity.csv` shows how they depend on it.",
        "",
    ]
    if s.tuning is not None:
        out += [
            f"`tuned`: convex-concave optimisation (Hast, Astrom, Bernhardsson, Boyd 2013): "
            f"maximise K_i subject to |S| <= {s.tuning.ms_max} and |T| <= {s.tuning.mt_max} "
            f"on the sampled loop, a sequence of second-order cone programs (cvxpy/Clarabel); "
            f"checked with python-control margins. `derivative_free`: Nelder-Mead on the "
            f"simulated mean RMS error of the tuning tasks ({', '.join(s.tuning.tune_on)}) "
            "with the same Ms and Mt limits as penalties. `improvement_all_tasks` is "
            "1 - mean RMS / mean RMS of the default over every task of the study. The tuners' "
            "wall times are in the run record, kept outside the report (`designlab list` "
            "shows it).",
            "",
        ]
    return out


def _tables_section(result: AccompanyingResult) -> list[str]:
    m = result.to_frame()[_TRACKING_COLUMNS].copy()
    for c in ("rms_error_m", "max_error_m", "settled_error_m", "overshoot_m"):
        m[c.replace("_m", "_mm")] = 1e3 * m.pop(c)
    out = ["## Tracking", "", markdown_table(m, floatfmt=".3g"), ""]
    out += [
        "## Table 2: robot in the user's frame (mm, deg)",
        "",
        _TABLE2_TEXT,
        "",
        markdown_table(_fmt_frame(table2_frame(result), 0)),
        "",
        "### Sign of the walking-average offset (mean - target), default PID vs paper",
        "",
        markdown_table(_fmt_frame(_sign_table(result), 0)),
        "",
        sign_claim(_sign_table(result)) + " " + _SIGN_TEXT,
        "",
    ]
    t1 = table1_frame(result)
    if len(t1):
        out += [
            "## Table 1: displacements in the world (mm, deg)",
            "",
            markdown_table(_fmt_frame(t1, 1)),
            "",
        ]
    return out


def _markdown(
    result: AccompanyingResult,
    sensitivity: pd.DataFrame | None = None,
    extras: pd.DataFrame | None = None,
) -> str:
    out = _model(result) + _controllers_section(result)
    if sensitivity is not None and len(sensitivity):
        out += [
            "## Sensitivity of the improvement to the baseline PID",
            "",
            baseline_claim(sensitivity),
            "",
            markdown_table(sensitivity, floatfmt=".4g"),
            "",
        ]
    out += _tables_section(result)
    if extras is not None:
        out += extras_section(result, extras)
    out += _noise_section(result)
    return "\n".join(out)


def _noise_section(result: AccompanyingResult) -> list[str]:
    """The noise table: each PID without and with sensor noise (noise.csv)."""
    f = result.noise
    if f.empty:
        return []
    nz = result.study.noise
    shown = pd.DataFrame(
        {
            "PID": f["controller"],
            "K_p (1/s)": f["kp_1_s"].map(lambda v: f"{v:.3g}"),
            "K_i (1/s^2)": f["ki_1_s2"].map(lambda v: f"{v:.3g}"),
            "K_d": f["kd"].map(lambda v: f"{v:.2g}"),
            "max abs(C S) (1/s)": f["noise_gain_1_s"].map(lambda v: f"{v:.3g}"),
            "RMS error, clean (mm)": (1e3 * f["rms_clean_m"]).map(lambda v: f"{v:.1f}"),
            "RMS error, noisy (mm)": (1e3 * f["rms_noisy_m"]).map(lambda v: f"{v:.1f}"),
            "command rate, noisy (m/s^2)": f["command_rate_m_s2"].map(lambda v: f"{v:.2g}"),
        }
    )
    bad = f[~f.get("tuning_status", pd.Series("", index=f.index)).isin(["", "ok"])]
    failed = (
        "Tunings that did not end ok: "
        + "; ".join(f"{c} ({st})" for c, st in bad[["controller", "tuning_status"]].values)
        + "."
        if len(bad)
        else "Every tuning with a limit ended ok."
    )
    return [
        "## Sensor noise and the noise-gain limit",
        "",
        f"White noise of {1e3 * nz.distance_noise:g} mm on the raw distance and "
        f"{1e3 * nz.angle_noise:g} mrad on the raw angles (seed {result.study.seed}); each "
        "PID tuned again on the same tasks with the noise-sensitivity limit |C S| <= k_s "
        "(Hast et al. 2013, linearised as a cone constraint). Means over the tasks; the "
        "command rate is the RMS of |d(V_x, V_y)/dt| with noise, against the platform's "
        f"{result.study.platform.max_acceleration:g} m/s^2 acceleration limit (noise.csv).",
        "",
        markdown_table(shown, index=False),
        "",
        failed,
        "",
    ]


@register_writer(AccompanyingResult)
def accompanying_report(result: AccompanyingResult) -> ReportParts:
    """The report's parts: the tables and figures listed in the module notes, the summary's body.

    Parameters
    ----------
    result
        An ``accompanying`` result.
    """
    margins = pd.concat(
        [la.to_frame().assign(controller=label) for label, la in result.loops.items()],
        ignore_index=True,
    )
    tuning = result.tuning_frame()
    timings: dict[str, float] = {}
    if "elapsed_s" in tuning.columns:  # a wall time: to the run record, never the report
        elapsed = tuning.set_index("method")["elapsed_s"].dropna()
        timings = {f"tune {m}": float(v) for m, v in elapsed.items()}
        tuning = tuning.drop(columns="elapsed_s")
    tables = {
        "metrics.csv": result.to_frame(),
        "table1.csv": table1_frame(result),
        "table2.csv": table2_frame(result),
        "tuning.csv": tuning,
        "margins.csv": margins,
    }
    figures: dict[str, Callable[[], Figure]] = {
        f"trajectories_{label}.png": partial(trajectory_figure, result, label)
        for label in result.runs
    }
    for name, make in (
        ("errors.png", errors_figure),
        ("readings.png", readings_figure),
        ("bode.png", bode_figure),
        ("nyquist.png", nyquist_figure),
    ):
        figures[name] = partial(make, result)
    sensitivity = baseline_sensitivity(result) if len(result.runs) > 1 else None
    if sensitivity is not None:
        tables["baseline_sensitivity.csv"] = sensitivity
    extras = extras_frame(result) if result.extras else None
    if extras is not None:
        tables["extras.csv"] = extras
    if not result.noise.empty:
        tables["noise.csv"] = result.noise
    return ReportParts(
        body=[_markdown(result, sensitivity, extras)],
        tables=tables,
        figures=figures,
        timings=timings,
        no_warnings="None.",
        closing=figure_section([(f, f) for f in figures], spaced=False),
    )
