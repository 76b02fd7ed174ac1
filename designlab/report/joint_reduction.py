"""Report of a ``joint_reduction`` study: where the reduced joint (3.4.9) may be used.

Files: ``summary.md`` (inputs, each joint as given, the errors over the
stiffness ratio with the conservative region, the intervals), ``joint_reduction.csv``
(every ratio, reduction and metric), ``nominal.csv`` (each joint as given) and
``joint_reduction.png`` (relative error against K_mech/K_cont, one panel per
joint and reduction, the ratios where the reduction is conservative on every
harm metric shaded).
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

from designlab.impact.joint_reduction import default_band
from designlab.report import register_writer
from designlab.report.builder import ReportParts, figure_section
from designlab.report.writers import markdown_table
from designlab.study.kinds.joint_reduction import JointReductionResult

__all__ = ["joint_reduction_figure", "joint_reduction_markdown", "joint_reduction_report"]

#: The small study of the examples below.
_EXAMPLE = """
designlab: 1
kind: joint_reduction
name: demo
joints: [{name: g, inertia: 0.059, k_mech: 2000, c_mech: 2.0, k_cont: 1500,
          c_cont: 30, lever_arm: 0.2}]
ratios: {low: 0.1, high: 10, num: 3}
"""

#: Metric labels, in report order.
_LABELS = {
    "a_h_max": "a_h,max",
    "eps_max": "eps_max",
    "f_c_max": "f_c (lobe max)",
    "f_c_first_peak": "f_c (first peak)",
    "t_imp": "t_imp",
}
_HARM = ("a_h_max", "eps_max", "f_c_max")
_REDUCTIONS = {"taylor": "Taylor (3.4.9)", "band_fit": "band fit (extension)"}
_COLORS = {
    "a_h_max": "tab:red",
    "eps_max": "tab:blue",
    "f_c_max": "tab:green",
    "f_c_first_peak": "tab:olive",
    "t_imp": "tab:gray",
}


def _pct(x: float) -> str:
    return "—" if not math.isfinite(x) else f"{100 * x:+.2f}"


def _mark(err: float, metric: str, unit: str = "") -> str:
    """Error in % (bold when the reduction underestimates a harm metric)."""
    text = _pct(err) + unit
    if metric in (*_HARM, "f_c_first_peak") and math.isfinite(err) and err < 0:
        return f"**{text}**"
    return text


def _intervals(pairs: list[tuple[float, float]]) -> str:
    if not pairs:
        return "nowhere in the range"
    return ", ".join(f"{lo:.3g}-{hi:.3g}" if lo != hi else f"{lo:.3g}" for lo, hi in pairs)


def joint_reduction_figure(result: JointReductionResult) -> Figure:
    """Relative error (%) against K_mech/K_cont: rows joints, columns reductions.

    Parameters
    ----------
    result
        The study's result.

    Returns
    -------
    matplotlib.figure.Figure
        Conservative ratios (on a_h,max, eps_max and force) shaded.

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> result = run_study(parse_study(_EXAMPLE))
    >>> fig = joint_reduction_figure(result)
    >>> len(fig.axes)
    2
    """
    n = len(result.joints)
    fig, axes = plt.subplots(n, 2, figsize=(11.5, 3.9 * n), squeeze=False, sharex=True)
    for row, j in zip(axes, result.joints, strict=True):
        s = j.sweep
        for ax, (red, title) in zip(row, _REDUCTIONS.items(), strict=True):
            safe = np.ones(s.ratio.size, dtype=bool)
            for m in _HARM:
                safe &= s.conservative_region(red, m)
            for lo, hi in s.conservative_intervals(red):
                ax.axvspan(lo, hi, color="tab:green", alpha=0.12, lw=0)
            for m, label in _LABELS.items():
                ls = "--" if m in ("f_c_first_peak", "t_imp") else "-"
                ax.plot(s.ratio, 100 * s.errors(red, m), ls, color=_COLORS[m], lw=1.6,
                        label=label)  # fmt: skip
            ax.axhline(0.0, color="black", lw=0.8)
            ax.axvline(j.robot.stiffness_ratio, color="black", ls=":", lw=1.0,
                       label="the joint as given")  # fmt: skip
            ax.set_xscale("log")
            ax.set_title(f"{j.robot.name}: {title}", fontsize=10)
            ax.grid(True, which="both", alpha=0.25)
            ax.set_ylabel("(reduced - full) / full (%)")
            if not np.any(safe):
                ax.text(0.02, 0.04, "conservative on all harm metrics: nowhere",
                        transform=ax.transAxes, fontsize=8)  # fmt: skip
        row[0].legend(fontsize=7, loc="upper right")
    for ax in axes[-1]:
        ax.set_xlabel("transmission/controller stiffness ratio $K_{mech}/K_{cont}$")
    fig.suptitle(
        f"{result.study.name}: error of the reduced joint on the impact metrics "
        "(shaded: conservative on a_h,max, eps_max and force)",
        fontsize=11,
    )
    fig.tight_layout()
    return fig


def _nominal_table(result: JointReductionResult) -> pd.DataFrame:
    rows = []
    for j in result.joints:
        c = j.nominal
        full = {m: c.value("full", m) for m in _LABELS}
        rows.append({"joint": j.robot.name, "model": "full (3.4.6)",
                     "K_r (N/m)": "—", "C_r (N s/m)": "—",
                     **{_LABELS[m]: f"{full[m]:.4g}" for m in _LABELS}})  # fmt: skip
        for red, contact in c.reduced.items():
            rows.append(
                {
                    "joint": "",
                    "model": _REDUCTIONS[red],
                    "K_r (N/m)": f"{contact.stiffness:.5g}",
                    "C_r (N s/m)": f"{contact.damping:.4g}",
                    **{_LABELS[m]: _mark(c.relative_error(red, m), m, " %") for m in _LABELS},
                }
            )
    return pd.DataFrame(rows)


def _sweep_table(result: JointReductionResult, j_index: int, every: int = 4) -> pd.DataFrame:
    s = result.joints[j_index].sweep
    idx = list(range(0, s.ratio.size, every))
    if idx[-1] != s.ratio.size - 1:
        idx.append(s.ratio.size - 1)
    frame = s.to_frame().drop_duplicates("point").set_index("point")
    robot = result.joints[j_index].robot
    corner = [
        (s.ratio[i] * robot.control_stiffness + robot.control_stiffness)
        / (robot.transmission_damping + robot.control_damping)
        / frame.loc[i, "band_omega_max_rad_per_s"]
        for i in idx
    ]
    table = pd.DataFrame(
        {
            "K_mech/K_cont": [f"{s.ratio[i]:.3g}" for i in idx],
            "corner / impact mode": [f"{x:.3g}" for x in corner],
        }
    )
    for red in _REDUCTIONS:
        for m in ("a_h_max", "eps_max", "f_c_max", "f_c_first_peak"):
            err = s.errors(red, m)
            table[f"{red} {_LABELS[m]}"] = [_mark(float(err[i]), m) for i in idx]
    return table


def _fastest_mode(j) -> float:  # type: ignore[no-untyped-def]
    return default_band(j.robot, j.nominal.foam, j.nominal.head)


def joint_reduction_markdown(result: JointReductionResult) -> str:
    """The body of the Markdown summary (the framework adds header and warnings).

    Parameters
    ----------
    result
        The study's result.

    Returns
    -------
    str
        The body of ``summary.md``.

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> result = run_study(parse_study(_EXAMPLE))
    >>> "## Where the reduction is conservative" in joint_reduction_markdown(result)
    True
    """
    out = _inputs_section(result)
    out += [
        "## Each joint as given",
        "",
        "Full-joint values (a_h,max in g, eps_max in m, forces in N, t_imp in s), then each "
        "reduction's relative error in %.",
        "",
        markdown_table(_nominal_table(result), index=False, disable_numparse=True),
        "",
    ]
    out += _conservative_section(result)
    for i, j in enumerate(result.joints):
        out += [
            f"## Errors over the stiffness ratio: {j.robot.name}",
            "",
            "Every fourth ratio; `joint_reduction.csv` has all of them. Relative errors in %.",
            "",
            markdown_table(_sweep_table(result, i), index=False, disable_numparse=True),
            "",
        ]
    return "\n".join(out)


def _joints_table(result: JointReductionResult) -> pd.DataFrame:
    """The joints as given, at joint level and at the impact point."""
    return pd.DataFrame(
        [
            {
                "joint": j.robot.name,
                "m_ii (kg m^2)": f"{sp.inertia:g}",
                "K_mech (N m/rad)": f"{sp.k_mech:g}",
                "C_mech (N m s/rad)": f"{sp.c_mech:g}",
                "K_cont (N m/rad)": f"{sp.k_cont:g}",
                "C_cont (N m s/rad)": f"{sp.c_cont:g}",
                "l (m)": f"{sp.lever_arm:g}",
                "M_r (kg)": f"{j.robot.mass:.4g}",
                "K_mech/K_cont": f"{j.robot.stiffness_ratio:.3g}",
                "corner (rad/s)": f"{j.robot.corner_frequency:.4g}",
                "fastest impact mode (rad/s)": f"{_fastest_mode(j):.4g}",
            }
            for j, sp in zip(result.joints, result.study.joints, strict=True)
        ]
    )


def _inputs_section(result: JointReductionResult) -> list[str]:
    """The introduction and the ``Inputs`` section."""
    st = result.study
    foam = st.foam.build()
    head = st.head.build() if st.head is not None else None
    out = [
        "The impact model with the full series joint of Zeng 2011 (3.4.6) (transmission in "
        "series with the PD controller, one more internal state) against the spring-damper "
        "reductions: the thesis's Taylor truncation (3.4.9) and a least-squares band fit (an "
        "extension of the thesis). Errors are `(reduced - full) / full`; a reduction is "
        "**conservative** on a harm metric (a_h,max, eps_max, the force) when it overestimates "
        "it. Negative (non-conservative) errors on harm metrics are in **bold**. See "
        "`docs/impact_joint.md`.",
        "",
        "## Inputs",
        "",
        markdown_table(_joints_table(result), index=False, disable_numparse=True),
        "",
        "The corner frequency (K_mech + K_cont)/(C_mech + C_cont) is the pole of (3.4.6): "
        "below it the joint is close to its Taylor reduction. The fastest impact mode is the "
        "largest pole modulus of the Taylor-reduced impact model. The reduction is close to "
        "exact when one of K_mech, K_cont is much larger than the other, or when the corner "
        "lies well above the impact's modes.",
        "",
    ]
    head_text = (
        "constrained impact (head against a wall)"
        if head is None
        else f"{head.name or 'head'}: M_h {head.mass:g} kg, K_h {head.stiffness:g} N/m, "
        f"C_h {head.damping:g} N s/m"
    )
    band = (
        f"omega_max = {st.omega_max:g} rad/s"
        if st.omega_max
        else "up to the fastest mode of the Taylor-reduced impact, at every point"
    )
    return [
        *out,
        f"- foam: {foam.name or 'foam'}, K_c {foam.stiffness:g} N/m, C_c {foam.damping:g} N s/m",
        f"- head: {head_text}",
        f"- closing velocity v_c = {st.impact_velocity:g} m/s",
        "- band fit: " + band,
        f"- stiffness ratios K_mech/K_cont: {st.ratios.low:g}-{st.ratios.high:g}, "
        f"{st.ratios.num} log-spaced points (controller, mass and C_mech kept)",
        "",
    ]


def _conservative_section(result: JointReductionResult) -> list[str]:
    """``Where the reduction is conservative``: the intervals of each joint and reduction."""
    rows = []
    tol = result.study.usable_tolerance
    for j in result.joints:
        for red, title in _REDUCTIONS.items():
            s = j.sweep
            worst = max(float(np.nanmax(np.abs(s.errors(red, m)))) for m in _HARM)
            rows.append(
                {
                    "joint": j.robot.name,
                    "reduction": title,
                    "conservative on a_h,max, eps_max and force": _intervals(
                        s.conservative_intervals(red)
                    ),
                    "on a_h,max": _intervals(s.conservative_intervals(red, ["a_h_max"])),
                    "on eps_max": _intervals(s.conservative_intervals(red, ["eps_max"])),
                    f"usable (conservative or within {100 * tol:g} %)": _intervals(
                        s.usable_intervals(red, tol)
                    ),
                    "largest |error| on harm metrics": f"{100 * worst:.2f} %",
                }
            )
    return [
        "## Where the reduction is conservative",
        "",
        "Intervals of K_mech/K_cont (sampled points) in which the reduction overestimates "
        "the metrics. **Usable**: on each of a_h,max, eps_max and the force (lobe maximum) "
        "the reduction either overestimates the harm or underestimates it by at most "
        f"{100 * tol:g} %: there (3.4.9) may stand in for the full joint.",
        "",
        markdown_table(pd.DataFrame(rows), index=False, disable_numparse=True),
        "",
    ]


@register_writer(JointReductionResult)
def joint_reduction_report(result: JointReductionResult) -> ReportParts:
    """The report's parts: joint_reduction.csv/.png, nominal.csv and the summary's body.

    Parameters
    ----------
    result
        The study's result.

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> parts = joint_reduction_report(run_study(parse_study(_EXAMPLE)))
    >>> sorted([*parts.tables, *parts.figures])
    ['joint_reduction.csv', 'joint_reduction.png', 'nominal.csv']
    """
    return ReportParts(
        title=f"Reduced joint vs full series joint: {result.study.name}",
        body=[joint_reduction_markdown(result)],
        tables={"joint_reduction.csv": result.to_frame(), "nominal.csv": result.nominal_frame()},
        figures={"joint_reduction.png": partial(joint_reduction_figure, result)},
        closing=figure_section(
            {"error of the reduced joint": "joint_reduction.png"}, title="Figure"
        ),
    )
