"""The first lines of a ``codesign`` report: the designer's answer, generated from the data.

For this robot and these people: which foam, speed limit and gains (the front's design
picked under the stated preference), how much risk per hour (contacts with people per
hour of the design's runs, 95 % Poisson bound, times the cited head-injury curve at the
worst contact), which constraint binds (the smallest relative slack), how ISO/TS 15066
compares, and how sensitive the answer is (the other seeds' picks and the hypervolume's
last change). Every number is read from the result's tables (docs/codesign.md).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from designlab.codesign.front import CONSTRAINTS, HV_TOLERANCE, HV_WINDOW, ParetoFront
from designlab.codesign.injury import CURVE_FLOOR, hic_curves
from designlab.study.kinds.codesign import CodesignResult, pick_of

__all__ = ["answer_lines", "binding_constraint", "convergence_lines", "iso_lines"]

#: The scale of each slack (a constraint's margin as a share of what it bounds).
_SCALE = {"thickness_shortfall_m": "T_u_m", "speed_over_limit_m_per_s": "V_mr_m_per_s"}


def binding_constraint(front: ParetoFront, row: int, bound: float = 1.0) -> tuple[str, float]:
    """The hard constraint with the smallest relative slack at front row ``row``.

    Parameters
    ----------
    front
        The front.
    row
        A row of ``front.to_frame()``.
    bound
        The stated bound on P(criterion exceeded | contact) (1: none stated).

    Returns
    -------
    tuple
        ``(name, slack)``: the slack as a share of the bounded quantity (0: active).
    """
    designs = front.designs_frame()
    on = designs[designs["on_front"]].sort_values(front.columns[0], kind="stable")
    r = on.iloc[row]
    slack = {name: -float(r[name]) / float(r[scale]) for name, scale in _SCALE.items()}
    if bound < 1.0:  # a bound was stated
        slack["risk_over_bound"] = -float(r["risk_over_bound"]) / bound
    name = min(slack, key=slack.__getitem__)
    return name, slack[name]


def _risk_text(p: float) -> str:
    return "below the curve's data" if p < CURVE_FLOOR else f"{p:.3g}"


def _design_text(d: pd.Series) -> str:
    return (
        f"foam K_c = {d['K_c_N_per_m']:.4g} N/m, C_c = {d['C_c_N_s_per_m']:.3g} N s/m, "
        f"T_u = {1e3 * d['T_u_m']:.3g} mm; speed limit V_mr = {d['V_mr_m_per_s']:.3g} m/s; "
        f"VFF gains k1 = {d['k1']:.3g}, b = {d['b']:.3g}, k3 = {d['k3']:.3g}, "
        f"k5 = {d['k5']:.4g}"
    )


def answer_lines(result: CodesignResult) -> list[str]:
    """The report's first paragraph: the design to sign and why (from the result's data).

    Parameters
    ----------
    result
        A ``codesign`` result.
    """
    study, front, robot = result.study, result.front, result.platform
    f = study.front
    who = (
        f"**For {robot.name}** (touching part: {robot.part.replace('_', ' ')} at "
        f"{robot.contact_low:g}-{robot.contact_high:g} m, effective mass "
        f"{robot.contact.mass:g} kg) **among people walking at up to {f.human_speed:g} m/s**"
        if robot is not None
        else "**For this robot**"
    )
    row = pick_of(front, f.preference)
    if row is None:
        return [f"{who}: no design of the search meets every hard constraint "
                f"({', '.join(CONSTRAINTS)}); nothing can be signed.", ""]  # fmt: skip
    table = front.to_frame()
    d = table.iloc[row]
    weights = f.preference or [1.0] * len(front.objectives)
    pref = ", ".join(f"{w:g} x {o}" for w, o in zip(weights, front.objectives, strict=True))
    knee = front.knee()
    lines = [
        f"{who}: {_design_text(d)}. Mean arrival time "
        f"{d['arrival_time_s']:.3g} s. Picked from the {len(table)} front designs by the "
        f"stated preference (minimum of {pref}, objectives normalised over the front); "
        + (
            "it is also the knee point."
            if knee == row
            else f"the knee point is {_design_text(table.iloc[knee])}."
        )
    ]
    lines += [" ".join(_risk_sentences(result, d)), " ".join(_binding_sentences(result, row))]
    lines += [" ".join(_sensitivity_sentences(result, d)), ""]
    return [x for line in lines for x in (line, "")][:-1]


def _risk_sentences(result: CodesignResult, d: pd.Series) -> list[str]:
    e, head = result.exposure, result.head_risk
    out = []
    if e is not None:
        crowd = (f", {60 * e.crowd_hours:.3g} min of them in crowds" if e.crowd_hours > 0
                 else "")  # fmt: skip
        out.append(
            f"**Risk:** {e.contacts} contacts with people in {e.runs} simulated runs of the "
            f"design ({60 * e.hours:.3g} min, {1e3 * e.km:.3g} m{crowd}): {e.per_hour:.3g} "
            f"contacts per hour ({e.per_hour_lower:.3g} to {e.per_hour_upper:.3g}) and "
            f"{e.per_km:.3g} per km ({e.per_km_lower:.3g} to {e.per_km_upper:.3g}; one-sided "
            "95 % Poisson bounds), each at its closing speed after braking."
        )
    if head:
        pm = head["prasad_mertz_ais3"]
        per_hour = e.risk_per_hour_upper if e is not None else math.nan
        out.append(
            f"A head contact at the worst closing speed ({head['closing_speed_m_per_s']:.3g} "
            f"m/s = V_mr + the walker) has HIC15 = {head['hic15']:.3g}: AIS3+ risk "
            f"{_risk_text(pm)} (Prasad and Mertz 1985), AIS2+ "
            f"{_risk_text(head['nhtsa_ais2'])} (NHTSA 1995 logistic curve, coefficients from "
            "secondary sources; both fitted to adult heads in vehicle crashes), so "
            + (
                "the AIS3+ risk per hour of operation is below the curves' data too."
                if pm < CURVE_FLOOR
                else f"at most {per_hour:.3g} AIS3+ head injuries per hour of operation."
            )
        )
    return out


def _binding_sentences(result: CodesignResult, row: int) -> list[str]:
    name, slack = binding_constraint(result.front, row, result.study.front.risk_bound)
    words = {"thickness_shortfall_m": "the foam thickness against the worst head's "
             "compression at V_mr + the walker",
             "speed_over_limit_m_per_s": "the speed limit its foam allows "
             "(10 g and the linear depth over the head-neck range)",
             "risk_over_bound": "the stated bound on P(criterion exceeded | contact)"}  # fmt: skip
    out = [f"**Binding constraint:** {words[name]}, with {100 * slack:.2g} % to spare."]
    iso = result.iso
    if iso is not None:
        met = iso[iso["share"] > 0.01]
        worst = met["iso_robot_speed_m_per_s"].idxmin() if len(met) else None
        if worst is not None:
            v_iso = float(met.loc[worst, "iso_robot_speed_m_per_s"])
            v = float(result.front.to_frame().iloc[row]["V_mr_m_per_s"])
            out.append(
                f"ISO/TS 15066 (Annex A, transient contact, v = F_T / sqrt(mu k)): of the body "
                f"regions this robot meets ({', '.join(met.index)}), {worst} allows the "
                f"lowest robot speed, {v_iso:.3g} m/s; the design's {v:.3g} m/s "
                + (
                    "exceeds it: under ISO/TS 15066 the standard binds, not the Zeng model."
                    if v > v_iso
                    else "meets it."
                )
            )
    return out


def _sensitivity_sentences(result: CodesignResult, d: pd.Series) -> list[str]:
    front = result.front
    out = [f"**Sensitivity:** {' '.join(convergence_lines(front))}"]
    for other in result.seed_fronts:
        row = pick_of(other, result.study.front.preference)
        if row is None:
            out.append(f"Seed {other.seed} found no feasible design.")
            continue
        o = other.to_frame().iloc[row]
        out.append(
            f"Seed {other.seed}'s search picks V_mr = {o['V_mr_m_per_s']:.3g} m/s (here "
            f"{d['V_mr_m_per_s']:.3g}), T_u = {1e3 * o['T_u_m']:.3g} mm (here "
            f"{1e3 * d['T_u_m']:.3g}), arrival {o['arrival_time_s']:.3g} s (here "
            f"{d['arrival_time_s']:.3g})."
        )
    return out


def convergence_lines(front: ParetoFront) -> list[str]:
    """One sentence on the hypervolume's last change (converged or not).

    Parameters
    ----------
    front
        The front.
    """
    hv = front.hypervolume
    change = front.hypervolume_change
    if not np.isfinite(change):
        return [f"The search ran {len(hv)} generations: too few to measure convergence "
                f"(over {HV_WINDOW})."]  # fmt: skip
    verdict = "converged" if change < HV_TOLERANCE else "not converged"
    return [f"The front's hypervolume changed {100 * change:.2g} % over the last {HV_WINDOW} "
            f"generations ({verdict}; the criterion is < {100 * HV_TOLERANCE:g} %)."]  # fmt: skip


def iso_lines(result: CodesignResult) -> list[str]:
    """The section ISO/TS 15066 beside the Zeng model (empty without it).

    Parameters
    ----------
    result
        A ``codesign`` result.
    """
    if result.iso is None:
        return []
    from designlab.report.writers import markdown_table

    curves = "; ".join(f"{c.name}: {c.source}" for c in hic_curves().values())
    return [
        "## ISO/TS 15066 beside the Zeng model",
        "",
        "Per body region (ISO/TS 15066:2016, Annex A: force and spring constant from Table "
        "A.2, effective mass from Table A.3; `designlab/data/iso_ts_15066_body_regions.csv`): "
        "the share of contacts of the robot's touching part that meet it (its height band and "
        "adult statures: Drillis and Contini 1966 landmark heights, Pheasant and Haslegrave "
        "2006 statures), the standard's permissible relative speed of a transient contact "
        "v = F_T / sqrt(mu k) with mu = (1/m_H + 1/m_R)^-1, the robot speed it leaves against "
        "the walker, and for the head regions the Zeng model's speed limit for the picked "
        "foam (`iso.csv`). The standard gives no transient factor for the head: its "
        "quasi-static force is used, and contact there is to be avoided.",
        "",
        markdown_table(result.iso.reset_index(), floatfmt=".4g", index=False),
        "",
        f"Head-injury curves used (`designlab/data/hic_injury_risk_curves.csv`): {curves}.",
        "",
    ]
