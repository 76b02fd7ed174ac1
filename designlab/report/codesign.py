"""Report of a ``codesign`` study: contact speeds, the Pareto front and the thesis's design.

Files written into the report directory:

``speed_map.csv``
    The speed-limit map: per foam (K_c, C_c) of the grid, the robot's speed limit, the
    closing speed at contact and the limiting criterion.
``risk.csv``
    The risk curves: per foam and closing speed, P(criterion exceeded | contact) and its
    Wilson confidence interval (:func:`designlab.codesign.fragility_curve`).
``contacts.csv``
    The thesis design's encounters: scenario, obstacle, contact, time, distances,
    relative / normal / approach speed, angle, robot and obstacle speed.
``front.csv``
    The non-dominated feasible designs: K_c, C_c, T_u, V_mr, the gains, the objectives.
``designs.csv``
    Every design the search evaluated, with its constraints and flags.
``reference.csv``
    The thesis's design: its objectives, constraints, distance from the front.
``sensitivity.csv``
    With a ``sensitivity`` section: the Sobol indices (S1, ST and their 95 % half-widths)
    of each objective and of ``infeasible`` per design variable
    (:func:`designlab.codesign.front_sensitivity`).
``speed_map.png``, ``risk.png``, ``contacts.png``, ``front.png``
    The speed-limit map (with Foam 1 and the front's foams); the risk curves; the closing
    speeds of the encounters; the front in pairs of objectives with every feasible design
    and the thesis's design; ``sensitivity.png`` (with a ``sensitivity`` section) the
    Sobol indices.
``summary.md``
    What the tables say (every sentence computed from them) and the figures.
``study.yaml``
    The study file as it was run (when given).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from designlab.analysis.sensitivity import SensitivityTable
from designlab.codesign import OBJECTIVES, ContactSpeeds, ParetoFront, SpeedLimitMap
from designlab.report import register_writer
from designlab.report.builder import ReportParts, figure_section
from designlab.report.codesign_answer import answer_lines, convergence_lines, iso_lines
from designlab.report.writers import markdown_table
from designlab.study.kinds.codesign import CodesignResult

__all__ = [
    "codesign_markdown",
    "codesign_report",
    "contacts_figure",
    "crowd_risk_section",
    "front_claims",
    "front_figure",
    "risk_figure",
    "sensitivity_figure",
    "sensitivity_section",
    "speed_map_figure",
]

_LABELS = {
    "arrival_time": "mean arrival time (s)",
    "foam_thickness": "foam thickness T_u (m)",
    "closing_speed": "largest closing speed (m/s)",
    "injury_probability": "P(criterion exceeded | contact)",
}


def speed_map_figure(smap: SpeedLimitMap, front: ParetoFront) -> Figure:
    """The robot speed limit over K_c x C_c, with Foam 1 and the front's foams.

    Parameters
    ----------
    smap
        The speed-limit map.
    front
        The Pareto front (its foams are marked).
    """
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    mesh = ax.pcolormesh(smap.stiffness / 1e3, smap.damping, smap.max_speed.T, shading="auto")
    fig.colorbar(mesh, ax=ax, label="robot speed limit (m/s)")
    table = front.to_frame()
    if len(table):
        ax.scatter(table["K_c_N_per_m"] / 1e3, table["C_c_N_s_per_m"], s=22, c="white",
                   edgecolors="k", label="front designs' foams")  # fmt: skip
    if front.reference is not None:
        f = front.reference.design.foam
        ax.scatter([f.stiffness / 1e3], [f.damping], marker="*", s=180, c="C3", label="Foam 1")
    ax.set_xlabel("foam stiffness K_c (kN/m)")
    ax.set_ylabel("foam damping C_c (N s/m)")
    ax.set_title(f"Speed limit (head moving at {smap.head_speed:g} m/s towards the robot)")
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    return fig


def risk_figure(risk: pd.DataFrame) -> Figure:
    """P(criterion exceeded | contact) against the closing speed, one curve per foam.

    Parameters
    ----------
    risk
        The risk curves (``risk.csv``).
    """
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for name, g in risk.groupby("foam", sort=False):
        ax.plot(g["v_c_m_per_s"], g["probability"], marker="o", label=str(name))
        ax.fill_between(g["v_c_m_per_s"], g["low"], g["high"], alpha=0.2)
    ax.set_xlabel("closing speed v_c (m/s)")
    ax.set_ylabel("P(criterion exceeded | contact)")
    ax.set_ylim(-0.02, 1.02)
    ax.set_title("Risk curves over the head-neck range")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def _speed_map_claims(frame: pd.DataFrame) -> list[str]:
    """Sentences computed from speed_map.csv."""
    best = frame.loc[frame["max_speed_m_per_s"].idxmax()]
    none = int((frame["max_speed_m_per_s"] <= 0.0).sum())
    limiting = frame["limiting"].value_counts()
    v, grid = frame["v_c_max_m_per_s"], frame["v_c_max_grid_m_per_s"]
    lower = (grid - v) / grid
    off = int((lower > 1e-9).sum())
    return [
        f"Over the {len(frame)} foams of the grid the robot's speed limit ranges from "
        f"{frame['max_speed_m_per_s'].min():.3f} to {frame['max_speed_m_per_s'].max():.3f} "
        f"m/s, highest at K_c = {best['K_c_N_per_m']:.4g} N/m, C_c = "
        f"{best['C_c_N_s_per_m']:.4g} N s/m; {none} foams allow no robot speed. Limiting: "
        + ", ".join(f"{k} ({n} foams)" for k, n in limiting.items())
        + ".",
        "",
        f"Each foam's worst head is sought off the head grid as well (docs/codesign.md): for "
        f"{off} of the {len(frame)} foams a head between the grid's points is worse, and the "
        f"allowed closing speed is lower than the grid's alone by up to "
        f"{100 * max(float(lower.max()), 0.0):.2f} % (`v_c_max_grid_m_per_s`).",
        "",
    ]


def _risk_claims(frame: pd.DataFrame) -> list[str]:
    """Sentences computed from risk.csv."""
    out = []
    for name, g in frame.groupby("foam", sort=False):
        hit = g[g["probability"] > 0.0]
        top = g.iloc[-1]
        first = (
            f"P > 0 from v_c = {hit['v_c_m_per_s'].iloc[0]:.3g} m/s"
            if len(hit)
            else "P = 0 over the whole grid"
        )
        out.append(
            f"- {name}: {first}; at {top['v_c_m_per_s']:.3g} m/s, P = {top['probability']:.3g} "
            f"[{top['low']:.3g}, {top['high']:.3g}]."
        )
    return [*out, ""]


def contacts_figure(contacts: ContactSpeeds) -> Figure:
    """Closing speeds of the encounters: relative, normal and approach speed per encounter.

    Parameters
    ----------
    contacts
        The encounters.
    """
    fig, ax = plt.subplots(figsize=(7.0, 3.8))
    x = np.arange(len(contacts))
    for k, (label, values) in enumerate(
        [
            ("|v_rel| at the encounter", contacts.relative_speed),
            ("normal speed at the encounter", contacts.normal_speed),
            ("largest approach speed inside r2", contacts.approach_speed),
        ]
    ):
        ax.bar(x + (k - 1) * 0.27, values, width=0.27, label=label)
    names = [f"{s}\n{o}" for s, o in zip(contacts.scenario, contacts.obstacle, strict=True)]
    ax.set_xticks(x, names, fontsize=7)
    ax.set_xlabel("encounter (scenario, obstacle)")
    ax.set_ylabel("speed (m/s)")
    ax.set_title("Closing speeds of the thesis design's encounters")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def front_figure(front: ParetoFront) -> Figure:
    """The first objective against each other one: feasible designs, the front, the thesis's.

    Parameters
    ----------
    front
        The Pareto front.
    """
    names = front.objectives
    fig, axes = plt.subplots(1, len(names) - 1, figsize=(4.6 * (len(names) - 1), 4.0),
                             squeeze=False)  # fmt: skip
    for j, ax in enumerate(axes[0], start=1):
        ok = front.feasible & ~front.front
        ax.scatter(front.F[ok, 0], front.F[ok, j], s=12, c="0.7", label="feasible design")
        ax.scatter(front.F[front.front, 0], front.F[front.front, j], s=28, c="C0",
                   label="non-dominated")  # fmt: skip
        for k, ref in enumerate(front.references):
            f = ref.objectives
            ax.scatter([f[0]], [f[j]], marker="*^sD"[k % 4], s=150 if k == 0 else 70,
                       c=f"C{3 + k}", label=ref.label)  # fmt: skip
        ax.set_xlabel(_LABELS.get(names[0], names[0]))
        ax.set_ylabel(_LABELS.get(names[j], names[j]))
        ax.legend(fontsize=8)
    fig.suptitle("Pareto front (all objectives minimised)")
    fig.tight_layout()
    return fig


def _contacts_claims(frame: pd.DataFrame) -> list[str]:
    """Sentences computed from contacts.csv."""
    if frame.empty:
        return ["The scenarios have no disc obstacle: no closing speed was met."]
    worst = frame.loc[frame["v_rel_m_per_s"].idxmax()]
    return [
        f"{len(frame)} encounters, {int(frame['contact'].sum())} of them contacts. The "
        f"relative speed at the encounter ranges from {frame['v_rel_m_per_s'].min():.3f} to "
        f"{frame['v_rel_m_per_s'].max():.3f} m/s (largest: {worst['obstacle']} in "
        f"{worst['scenario']}, at {worst['d_surface_m']:.3f} m surface distance); the "
        f"largest approach speed inside an active region is "
        f"{frame['v_approach_m_per_s'].max():.3f} m/s.",
        "",
    ]


def front_claims(front: ParetoFront) -> list[str]:
    """Sentences computed from the front's tables (designs.csv, front.csv, reference.csv).

    Parameters
    ----------
    front
        The Pareto front.
    """
    designs, table, ref = front.designs_frame(), front.to_frame(), front.reference_frame()
    out = [
        f"The search evaluated {len(designs)} designs (seed {front.seed}); "
        f"{int(designs['feasible'].sum())} meet every hard constraint and "
        f"{len(table)} of those are non-dominated.",
    ]
    for col in front.columns:
        if len(table):
            out[-1] += (
                f" On the front, {col} ranges from {table[col].min():.4g} to "
                f"{table[col].max():.4g}."
            )
    for _, r in ref.iterrows():
        verdict = "feasible" if bool(r["feasible"]) else "infeasible"
        out += [
            "",
            f"The design '{r['label']}' (K_c = {r['K_c_N_per_m']:.4g} N/m, T_u = "
            f"{r['T_u_m']:.4g} m, V_mr = {r['V_mr_m_per_s']:.3g} m/s, k1 = {r['k1']:.3g}, "
            f"b = {r['b']:.3g}, k3 = {r['k3']:.3g}, k5 = {r['k5']:.4g}) is {verdict}; "
            f"{int(r['dominated_by'])} front designs dominate it"
            + (
                ": feasible and dominated by no design found, it is on the front."
                if bool(r["feasible"]) and int(r["dominated_by"]) == 0
                else f", and its normalised distance from the front is "
                f"{r['distance_to_front']:.3f}."
            ),
        ]
    return [*out, ""]


def crowd_risk_section(result: CodesignResult) -> list[str]:
    """The Markdown section of the crowd encounters' risk (empty without ``crowds``).

    Parameters
    ----------
    result
        A ``codesign`` result.
    """
    frame = result.crowd_risk
    if frame is None:
        return []
    c = result.study.crowds
    assert c is not None  # crowd_risk is only computed with a crowds section
    return [
        "## Risk over crowd encounters",
        "",
        f"The thesis's design (experiment gains) driven through `{c.layout}` crowds of "
        f"{c.pedestrians} pedestrians (seeds {', '.join(map(str, c.seeds))}); the closing "
        f"speeds (`{result.study.measure}`) at each pedestrian's closest approach or first "
        "contact are the distribution of P(criterion exceeded | contact) (docs/codesign.md).",
        "",
        markdown_table(frame, floatfmt=".4g", index=False),
        "",
    ]


def sensitivity_figure(table: SensitivityTable) -> Figure:
    """Total (bars) and first-order (dots) Sobol indices with 95 % half-widths, per metric.

    Parameters
    ----------
    table
        The Sobol table (:func:`designlab.codesign.front_sensitivity`).
    """
    metrics = table.metrics
    fig, axes = plt.subplots(1, len(metrics), figsize=(3.4 * len(metrics), 3.8), sharey=True,
                             squeeze=False)  # fmt: skip
    for ax, m in zip(axes[0], metrics, strict=True):
        rows = table.frame[table.frame["metric"] == m]
        y = np.arange(len(rows))
        ax.barh(y, rows["ST"].fillna(0.0), xerr=rows["ST_conf"].fillna(0.0), color="C0",
                alpha=0.7, label="total S_T")  # fmt: skip
        ax.errorbar(rows["S1"].fillna(0.0), y, xerr=rows["S1_conf"].fillna(0.0), fmt="o",
                    color="C3", ms=4, label="first-order S_1")  # fmt: skip
        ax.set_yticks(y, rows["parameter"])
        ax.axvline(0.0, color="k", lw=0.6)
        ax.set_title(_LABELS.get(m, m), fontsize=9)
        ax.set_xlabel("Sobol index")
    axes[0][0].legend(fontsize=7)
    fig.suptitle("Sensitivity of the front's objectives to the design variables")
    fig.tight_layout()
    return fig


def _sensitivity_claims(table: SensitivityTable) -> list[str]:
    """One sentence per metric, computed from sensitivity.csv."""
    out = []
    for m in table.metrics:
        rows = table.ranked(m)
        if rows["ST"].isna().all():
            out.append(f"- {m}: constant over the sample (no index).")
            continue
        top = rows.iloc[0]
        exact = (rows["ST"] == 0.0) & (rows["ST_conf"] == 0.0)
        vague = ~exact & (rows["ST"] - rows["ST_conf"] <= 0.0)
        out.append(
            f"- {m}: most influential {top['parameter']} (S_T = {top['ST']:.3g} +- "
            f"{top['ST_conf']:.2g}); S_T = 0 exactly (changing it alone never changed the metric "
            "in the sample) for "
            + (", ".join(rows.loc[exact, "parameter"]) or "no variable")
            + "; the 95 % interval of S_T includes 0 for "
            + (", ".join(rows.loc[vague, "parameter"]) or "no other variable")
            + "."
        )
    return [*out, ""]


def sensitivity_section(result: CodesignResult) -> list[str]:
    """The Markdown section of the front's Sobol indices (empty without ``sensitivity``).

    Parameters
    ----------
    result
        A ``codesign`` result.
    """
    table = result.sensitivity
    if table is None:
        return []
    spec = result.study.sensitivity
    assert spec is not None  # the table is only computed with a sensitivity section
    n_vars = len(set(table.frame["parameter"]))
    return [
        "## Sensitivity of the front",
        "",
        f"First-order (S1) and total (ST) Sobol indices with 95 % bootstrap half-widths "
        f"(`sensitivity.csv`; SALib through designlab.analysis.sensitivity): "
        f"{spec.samples * (n_vars + 2)} designs ({spec.samples} x ({n_vars} + 2), seed "
        f"{spec.seed}) scored as the front scores them; `arrival_time` counts a run that "
        "did not arrive at its horizon, `infeasible` is 1 for a design breaking a hard "
        "constraint (docs/codesign.md). With few samples the half-widths are wide: read the "
        "ranking, not the digits.",
        "",
        *_sensitivity_claims(table),
        table.to_markdown(floatfmt=".3g"),
        "",
    ]


def seeds_frame(result: CodesignResult) -> pd.DataFrame:
    """Per seed: designs evaluated, feasible, on the front, final hypervolume and its change.

    Parameters
    ----------
    result
        A ``codesign`` result.
    """
    rows = []
    for fr in (result.front, *result.seed_fronts):
        hv = fr.hypervolume
        rows.append({"seed": fr.seed, "designs": len(fr.X), "feasible": int(fr.feasible.sum()),
                     "on_front": int(fr.front.sum()),
                     "hypervolume": float(hv[-1]) if len(hv) else float("nan"),
                     "hv_change_last_generations": fr.hypervolume_change})  # fmt: skip
    return pd.DataFrame(rows)


def hypervolume_frame(result: CodesignResult) -> pd.DataFrame:
    """The hypervolume trace of each seed, one row per generation.

    Parameters
    ----------
    result
        A ``codesign`` result.
    """
    frame = pd.DataFrame({"generation": np.arange(1, len(result.front.hypervolume) + 1)})
    for fr in (result.front, *result.seed_fronts):
        frame[f"seed_{fr.seed}"] = pd.Series(fr.hypervolume)
    return frame


#: The search's time goal (issue 36.5): wall minutes on a quiet 2-core machine.
WALL_GOAL_MIN = 20.0


def search_frame(result: CodesignResult) -> pd.DataFrame:
    """One row: designs evaluated (every seed), seeds, and the largest hypervolume change over
    the last generations. The search's CPU time and rate are machine-dependent: they are
    stated in the summary's prose and the run record, never in a table (docs/developers.md,
    "Reproduction on another machine").

    Parameters
    ----------
    result
        A ``codesign`` result.
    """
    seeds = seeds_frame(result)
    return pd.DataFrame([{
        "designs": int(seeds["designs"].sum()), "seeds": len(seeds),
        "max_hv_change_last_generations": float(seeds["hv_change_last_generations"].max()),
    }])  # fmt: skip


def exposure_frame(result: CodesignResult) -> pd.DataFrame | None:
    """One row: the picked design's contacts with people per hour and per km, and harms.

    Parameters
    ----------
    result
        A ``codesign`` result.
    """
    e = result.exposure
    if e is None:
        return None
    row = {k: v for k, v in dataclasses.asdict(e).items() if k != "closing_speeds"}
    row["largest_closing_speed_m_per_s"] = max(e.closing_speeds, default=float("nan"))
    return pd.DataFrame([row])


def _convergence_section(result: CodesignResult) -> list[str]:
    seeds = seeds_frame(result)
    n, cpu = int(search_frame(result).iloc[0]["designs"]), float(result.cpu_seconds)
    rate, wall = (n / cpu if cpu > 0 else float("nan")), cpu / 2.0 / 60.0
    met = "meets" if wall <= WALL_GOAL_MIN else "misses"
    return [
        "## Convergence",
        "",
        *convergence_lines(result.front),
        f"{n} designs evaluated over {len(seeds)} seeds in {result.cpu_seconds:.4g} CPU s "
        f"({rate:.3g} designs per CPU second; on a quiet 2-core machine with both cores "
        f"scoring, `-e processes`, about {wall:.3g} min of wall time, which {met} the "
        f"{WALL_GOAL_MIN:g}-minute goal). Hypervolume of the feasible designs "
        "found up to each generation, objectives normalised over them, reference point 1.1 "
        "(`hypervolume.csv`, `seeds.csv`):",
        "",
        markdown_table(seeds, floatfmt=".4g", index=False),
        "",
    ]


def codesign_markdown(result: CodesignResult) -> str:
    """The body of the Markdown summary (the framework adds header and warnings).

    Parameters
    ----------
    result
        A ``codesign`` result.
    """
    study, front = result.study, result.front
    contacts = result.contacts.to_frame()
    objectives = ", ".join(f"{o} ({OBJECTIVES[o].doc})" for o in front.objectives)
    out = [
        *answer_lines(result),
        "## Speed-limit map",
        "",
        "The largest robot speed at which a contact with any head of the range meets every "
        f"criterion ({', '.join(result.speed_map.criteria)}), for each foam of the grid "
        "(`speed_map.csv`; docs/codesign.md).",
        "",
        *_speed_map_claims(result.speed_map.to_frame()),
        "## Risk curves",
        "",
        f"P(criterion exceeded | contact) at a fixed closing speed, heads uniform over the "
        f"range ({int(result.risk['probability'].size)} points, `risk.csv`):",
        "",
        *_risk_claims(result.risk),
        "## Contact speeds",
        "",
        f"The thesis's design driven through the scenarios (closing speed: `{study.measure}`;"
        " docs/codesign.md).",
        "",
        *_contacts_claims(contacts),
        markdown_table(contacts.drop(columns=["t_s"]), floatfmt=".3f", index=False),
        "",
        *crowd_risk_section(result),
        "## Pareto front",
        "",
        f"Objectives, all minimised: {objectives}. Hard constraints: no collision, no "
        "critical-region entry (every region at least the minimum for the design's speed, "
        "Sec. 5.3), arrival in every scenario, no foam bottoming at the larger of the closing "
        "speed met and V_mr + the walker's speed (worst head found off the grid), V_mr at most "
        f"the speed limit of the design's foam for a walker at {study.front.human_speed:g} m/s, "
        f"and P(criterion exceeded | contact) <= {study.front.risk_bound:g}. NSGA-II (pymoo), "
        "the thesis's designs in the first population.",
        "",
        *front_claims(front),
        markdown_table(front.to_frame(), floatfmt=".4g", index=False),
        "",
        "The thesis's designs (Foam 1, V_mr = 0.7 m/s; experiment and Table C.1 gains):",
        "",
        markdown_table(front.reference_frame(), floatfmt=".4g", index=False),
        "",
        *sensitivity_section(result),
        *iso_lines(result),
        *_convergence_section(result),
    ]
    figures = {
        "speed-limit map": "speed_map.png",
        "risk curves": "risk.png",
        "closing speeds": "contacts.png",
        "Pareto front": "front.png",
    }
    if result.sensitivity is not None:
        figures["Sobol indices"] = "sensitivity.png"
    out += figure_section(figures)
    return "\n".join(out)


@register_writer(CodesignResult)
def codesign_report(result: CodesignResult) -> ReportParts:
    """The report's parts: the CSV tables, the figures and summary.md's body.

    Parameters
    ----------
    result
        A ``codesign`` result.
    """
    front = result.front
    tables = {
        "speed_map.csv": result.speed_map.to_frame(),
        "risk.csv": result.risk,
        "contacts.csv": result.contacts.to_frame(),
        "front.csv": front.to_frame(),
        "designs.csv": front.designs_frame(),
        "reference.csv": front.reference_frame(),
        "seeds.csv": seeds_frame(result),
        "hypervolume.csv": hypervolume_frame(result),
        "search.csv": search_frame(result),
    }
    expo = exposure_frame(result)
    if expo is not None:
        tables["exposure.csv"] = expo
    if result.iso is not None:
        tables["iso.csv"] = result.iso.reset_index()
    figures: dict[str, Callable[[], Figure]] = {
        "speed_map.png": lambda: speed_map_figure(result.speed_map, front),
        "risk.png": lambda: risk_figure(result.risk),
        "contacts.png": lambda: contacts_figure(result.contacts),
        "front.png": lambda: front_figure(front),
    }
    sens = result.sensitivity
    if sens is not None:
        tables["sensitivity.csv"] = sens.to_frame()
        figures["sensitivity.png"] = lambda: sensitivity_figure(sens)
    return ReportParts(body=[codesign_markdown(result)], tables=tables, figures=figures)
