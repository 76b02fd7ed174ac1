"""Report of a ``zeng_ch3_claims`` study: Zeng 2011 Ch. 3 statements, recomputed and restated.

Files: ``summary.md`` (each statement, what the model gives and what the text
supports), ``sec_3_8.csv``, ``fig_3_16.csv``, ``q2.csv``, ``table_3_1.csv`` and
``zeng_ch3_claims.png`` (left: a_h,max along the link for each speed ratio,
worst points marked; right: the force of each Sec. 3.8 reading at +g, first
local maximum and first-lobe maximum marked).
"""

from __future__ import annotations

from functools import partial

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import pandas as pd
from matplotlib.figure import Figure

from designlab.report import register_writer
from designlab.report.builder import ReportParts, figure_section
from designlab.report.writers import markdown_table
from designlab.study.kinds.zeng_ch3_claims import Ch3ClaimsResult

__all__ = ["ch3_claims_figure", "ch3_claims_markdown", "ch3_claims_report"]

#: The small study of the examples below.
_EXAMPLE = """
designlab: 1
kind: zeng_ch3_claims
name: demo
readings: [{name: b, impact_velocity: 0.25, feedforward: false}]
speed_ratios: [1.0]
"""


def ch3_claims_figure(result: Ch3ClaimsResult) -> Figure:
    """Fig. 3.16 curves and the Sec. 3.8 force histories.

    Parameters
    ----------
    result
        The study's result.

    Returns
    -------
    matplotlib.figure.Figure
        Two panels.

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> result = run_study(parse_study(_EXAMPLE))
    >>> len(ch3_claims_figure(result).axes)
    2
    """
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.6))
    for w in result.worst_points:
        rel = w.grid_a_h_max_g / w.a_h_max_g
        (line,) = ax1.plot(1e3 * w.grid, rel, label=f"ratio {w.speed_ratio:g} 1/m")
        ax1.plot(1e3 * w.lever_arm, 1.0, "o", color=line.get_color())
    ax1.axvline(1e3 * result.study.reference_lever_arm, color="k", ls=":", lw=1)
    ax1.set_xlabel("impact point l (mm)")
    ax1.set_ylabel("a_h,max / a_h,max at the worst point")
    ax1.set_title("Fig. 3.16: Manipulator 1, Foam 1, minimum head set")
    ax1.set_ylim(bottom=max(0.0, min(float(w.grid_a_h_max_g.min() / w.a_h_max_g)
                                     for w in result.worst_points) - 0.01))  # fmt: skip
    ax1.legend(fontsize=8)
    for p in result.profiles:
        if p.sign < 0:
            continue
        c = p.change
        for r, t1, f1, style, tag in (
            (c.base, c.force_first_peak_time[0], c.force_first_peak[0], "--", "constant"),
            (c.profiled, c.force_first_peak_time[1], c.force_first_peak[1], "-", "+g"),
        ):
            (line,) = ax2.plot(1e3 * r.t, r.force, style, lw=1.2,
                               label=f"{p.reading.name}, {tag}")  # fmt: skip
            ax2.plot(1e3 * t1, f1, "o", color=line.get_color())
            ax2.plot(1e3 * r.time_of_peak_force, r.peak_force, "s", mfc="none",
                     color=line.get_color())  # fmt: skip
    ax2.set_xlabel("t (ms)")
    ax2.set_ylabel("f_c (N)")
    ax2.set_title("Sec. 3.8: force; o first local maximum, □ first-lobe maximum")
    ax2.legend(fontsize=7)
    fig.tight_layout()
    return fig


def _fmt(df: pd.DataFrame, digits: dict[str, str]) -> pd.DataFrame:
    out = df.copy()
    for col, spec in digits.items():
        out[col] = [format(float(x), spec) for x in out[col]]
    return out


def ch3_claims_markdown(result: Ch3ClaimsResult) -> str:
    """The body of the summary page (the framework adds header and warnings).

    Parameters
    ----------
    result
        The study's result.

    Returns
    -------
    str
        Markdown.

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> result = run_study(parse_study(_EXAMPLE))
    >>> "## Fig. 3.16" in ch3_claims_markdown(result)
    True
    """
    out = [
        "Each section recomputes one statement of Zeng 2011 Ch. 3 with designlab's impact "
        "model and says what the model and the text support (`docs/impact_joint.md`, Sec. 5).",
        "",
        *_sec_3_8(result),
        *_fig_3_16(result),
        *_q2_section(result),
        *_table_3_1(result),
        "## Also restated",
        "",
        "- The band fit of the joint (`fit_joint_band`) is an extension of the thesis, which "
        "has only the Taylor truncation (3.4.9); it is not one of the thesis's scenarios.",
        "- The geared joint of the tests and of `reports/joint_reduction/` is illustrative, "
        "not a thesis joint.",
        "",
    ]
    return "\n".join(out)


def _sec_3_8(result: Ch3ClaimsResult) -> list[str]:
    """Sec. 3.8 (Fig. 3.17): the changes under the acceleration profile, per reading."""
    s = result.study
    prof = result.profiles_frame()
    prof_table = _fmt(
        prof[["reading", "v_c_m_per_s", "acceleration_g", "feedforward", "d_f_c_first_peak_pct",
              "d_a_h_max_pct", "d_f_c_lobe_max_pct", "thesis_d_f_c_pct",
              "thesis_d_a_h_max_pct"]],
        {"acceleration_g": "+.2f", "d_f_c_first_peak_pct": "+.2f", "d_a_h_max_pct": "+.2f",
         "d_f_c_lobe_max_pct": "+.2f", "thesis_d_f_c_pct": "+.0f", "thesis_d_a_h_max_pct": "+.0f"},
    ).rename(columns={
        "v_c_m_per_s": "v_c (m/s)", "acceleration_g": "acceleration (g)",
        "d_f_c_first_peak_pct": "force, first peak (%)", "d_a_h_max_pct": "a_h,max (%)",
        "d_f_c_lobe_max_pct": "force, lobe max (%)", "thesis_d_f_c_pct": "thesis force (%)",
        "thesis_d_a_h_max_pct": "thesis a_h,max (%)",
    })  # fmt: skip
    return [
        "## Sec. 3.8 (Fig. 3.17): accelerating and decelerating at "
        f"{s.acceleration_g:g} g for {1e3 * s.profile_duration:g} ms",
        "",
        "Manipulator 1, Foam 1, Table 3.2 head set 3. The thesis does not state the head "
        "speed or whether the controller has feed-forward; each reading is one choice. "
        "The force change is given at the force's first local maximum (the thesis's "
        '"peak", Sec. 3.6) and at its first-lobe maximum (docs/impact.md, "Metrics"). '
        "g is standard gravity, 9.80665 m/s^2 (with 9.81 m/s^2 reading (b) gives +4.96 % "
        "and -3.99 %).",
        "",
        markdown_table(prof_table, index=False, disable_numparse=True),
        "",
        "With the first local maximum, the head-still reading without feed-forward is as "
        "close to the thesis's +5/+4 and -4/-3 % as the moving-head reading with "
        'feed-forward: a statement that it "cannot give +5 %" is wrong. Only the '
        "first-lobe maximum of the force moves far, because the accelerating arm drives "
        "the force up its ramp after the peak, until the lobe closes.",
        "",
    ]


def _fig_3_16(result: Ch3ClaimsResult) -> list[str]:
    """Fig. 3.16: the worst impact point for each speed ratio."""
    s = result.study
    worst = _fmt(
        result.worst_frame()[["speed_ratio_per_m", "worst_l_m", "a_h_max_worst_g",
                              "a_h_max_ref_g", "a_h_max_l0_g", "d_a_h_max_l0_vs_ref_pct",
                              "status"]],
        {"worst_l_m": ".4f", "a_h_max_worst_g": ".4f", "a_h_max_ref_g": ".4f",
         "a_h_max_l0_g": ".4f", "d_a_h_max_l0_vs_ref_pct": "+.2f"},
    ).rename(columns={
        "speed_ratio_per_m": "joint speed / head speed (1/m)", "worst_l_m": "worst l (m)",
        "a_h_max_worst_g": "a_h,max worst (g)",
        "a_h_max_ref_g": f"a_h,max at {s.reference_lever_arm:g} m (g)",
        "a_h_max_l0_g": "a_h,max at l -> 0 (g)",
        "d_a_h_max_l0_vs_ref_pct": f"l -> 0 vs {s.reference_lever_arm:g} m (%)",
    })  # fmt: skip
    return [
        "## Fig. 3.16: the worst impact point along Manipulator 1's link",
        "",
        "Foam 1, minimum head-neck set. Since v_c = v_h (1 + (theta_dot / v_h) l) and the "
        "model is linear in v_c, the worst point and the change at l -> 0 depend only on "
        "the joint-speed/head-speed ratio (continuous search).",
        "",
        markdown_table(worst, index=False, disable_numparse=True),
        "",
        "The thesis states both that a_h,max is largest at l_1 = 0.01 m and that it is 2 % "
        "smaller at l_1 -> 0. The first needs a ratio near 0.62 1/m, where the l -> 0 change "
        "is only about -0.3 %; a 2 % change needs a ratio near 2.3 1/m, where the worst "
        "point is near 0.037 m. Both cannot hold for one pair of speeds, whatever the "
        "(unstated) speeds were.",
        "",
    ]


def _q2_section(result: Ch3ClaimsResult) -> list[str]:
    """The printed q2 of (3.5.14): the change of every metric."""
    s = result.study
    q2 = result.q2_frame().pivot(index="case", columns="metric", values="change_pct")
    q2 = q2[["a_h_max_g", "eps_max_m", "f_c_max_N", "t_imp_s"]].reset_index()
    q2 = _fmt(q2, {c: "+.2f" for c in ("a_h_max_g", "eps_max_m", "f_c_max_N", "t_imp_s")})
    q2.columns = ["case", "a_h,max (%)", "eps_max (%)", "f_c max (%)", "t_imp (%)"]
    return [
        '## The printed q2 of (3.5.14) (docs/impact.md, "q2")',
        "",
        f"Change of each metric with the printed q2 against the correct one, Foam 1, "
        f"v_c = {s.q2_impact_velocity:g} m/s. The printed q2 sits in the common denominator, "
        "so the force and the compression change as well as a_h. Fig. 3.10 cites the force "
        "of (3.5.11), which has no q2: that the thesis's force curves used the printed q2 is "
        "an inference from its Sec. 3.6 percentages, not a statement of the text.",
        "",
        markdown_table(q2, index=False, disable_numparse=True),
        "",
    ]


def _table_3_1(result: Ch3ClaimsResult) -> list[str]:
    """Table 3.1: Manipulator 1 recomputed from its joint data."""
    t31 = _fmt(result.table_3_1_frame(),
               {"printed": ".5g", "recomputed": ".5g", "difference_pct": "+.2f"})  # fmt: skip
    t31 = t31.rename(columns={"difference_pct": "difference (%)"})

    return [
        "## Table 3.1: Manipulator 1 recomputed from its joint data",
        "",
        "m_11 = 0.059 kg m^2 (A.2.5), l_1 = 0.078 m, K_p = 433.8 V/rad, K_d = 5.4 V s/rad, "
        "K_t K_amp = 0.2807 N m/V, B = 0.0079 N m s/rad (App. A.2, (A.2.20)). The printed "
        "M_r is 1 % low, an error in the thesis's own arithmetic; the preset "
        "`MANIPULATOR_1` keeps the printed values so that the thesis's tables are reproduced.",
        "",
        markdown_table(t31, index=False, disable_numparse=True),
        "",
    ]


@register_writer(Ch3ClaimsResult)
def ch3_claims_report(result: Ch3ClaimsResult) -> ReportParts:
    """The report's parts: summary.md, the four CSVs, the figure.

    Parameters
    ----------
    result
        The study's result.

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> result = run_study(parse_study(_EXAMPLE))
    >>> parts = ch3_claims_report(result)
    >>> len(parts.tables), len(parts.figures)
    (4, 1)
    """
    return ReportParts(
        body=[ch3_claims_markdown(result)],
        title=f"Zeng 2011 Ch. 3 statements, recomputed: {result.study.name}",
        closing=figure_section({"Fig. 3.16 and Sec. 3.8": "zeng_ch3_claims.png"}, title="Figure"),
        tables={
            "sec_3_8.csv": result.profiles_frame(),
            "fig_3_16.csv": result.worst_frame(),
            "q2.csv": result.q2_frame(),
            "table_3_1.csv": result.table_3_1_frame(),
        },
        figures={"zeng_ch3_claims.png": partial(ch3_claims_figure, result)},
    )
