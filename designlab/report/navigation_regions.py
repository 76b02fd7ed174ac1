"""Report of a ``navigation_regions`` study: region sizes with every intermediate quantity.

Files: ``summary.md`` (the robot, one table per obstacle class with each quantity, its
equation and value, the radii to adopt and a scenario snippet) and ``regions.csv``
(one row per obstacle class, every quantity).
"""

from __future__ import annotations

import pandas as pd
import yaml

from designlab.navigation.regions import RegionSizes
from designlab.report import register_writer
from designlab.report.builder import ReportParts
from designlab.report.writers import markdown_table
from designlab.study.kinds.navigation_regions import NavigationRegionsResult

__all__ = ["navigation_regions_markdown", "navigation_regions_report"]

#: Quantity -> (symbol, equation in Zeng 2011, unit).
_ROWS = {
    "sample_time": ("T_s", "navigation period (reaction delay)", "s"),
    "stopping_time": ("Δt1", "V_mr / a_mr (5.3.2)", "s"),
    "accel_time": ("t_a", "V_mr / a_mr (5.3.6)", "s"),
    "robot_stopping_distance": ("δ_r1", "V_mr T_s + ½ a_mr Δt1² (5.3.1)", "m"),
    "obstacle_advance": ("δ_o1", "V_o (Δt1 + T_s) (5.3.1, 7.5.1)", "m"),
    "r3_hat": ("r̂3", "δ_o1 + δ_r1 (5.3.1, 5.3.11a)", "m"),
    "r3_min": ("r3,min", "r̂3 + ρ_o + ρ_r (5.3.3, 5.3.8a); r̂3 + ρ_r for a rectangle", "m"),
    "r3": ("r3", "adopted critical radius (≥ r3,min)", "m"),
    "offset": ("B", "rectangle offset (Fig. 5.4); 0 for a disc", "m"),
    "sidestep_time": ("Δt2", "(r3 + B − ½ a_mr t_a²) / V_mr + t_a (5.3.6b, 5.3.14)", "s"),
    "turn_time": ("t_turn", "√(π / ω̄) for a nonholonomic robot (7.4.2); 0 otherwise", "s"),
    "robot_sidestep_travel": ("δ_rx2", "V_mr (Δt2 + t_turn + T_s) (5.3.7)", "m"),
    "obstacle_sidestep_travel": ("δ_ox2", "V_o (Δt2 + t_turn + T_s) (5.3.7)", "m"),
    "r2": ("r2,min", "δ_ox2 + δ_rx2 (5.3.7, 5.3.8b, 5.3.12, 7.4.3-7.4.6, 7.5.3)", "m"),
}


def _quantities(s: RegionSizes, r2_used: float) -> pd.DataFrame:
    rows = [
        {"symbol": sym, "equation": eq, "value": f"{getattr(s, q):.4f}", "unit": u}
        for q, (sym, eq, u) in _ROWS.items()
    ]
    adopted = {"symbol": "r2", "equation": "adopted active radius"}
    rows.append({**adopted, "value": f"{r2_used:.4f}", "unit": "m"})
    return pd.DataFrame(rows)


def _inputs(result: NavigationRegionsResult) -> list[str]:
    plan = result.plan
    robot = plan.robot
    fields = ", ".join(f"{k} = {v:g}" for k, v in vars(robot).items() if isinstance(v, float))
    rows = []
    for name, o in plan.obstacles.items():
        values = ", ".join(f"{k} = {v:g}" for k, v in vars(o).items() if v is not None)
        rows.append({"obstacle": name, "class": type(o).__name__, "values (SI)": values})
    return [
        "## Inputs",
        "",
        f"Robot: {robot.kind} ({fields}); navigation period T_s = {plan.sample_time:g} s.",
        "",
        markdown_table(pd.DataFrame(rows), index=False, disable_numparse=True),
        "",
    ]


def navigation_regions_markdown(result: NavigationRegionsResult) -> str:
    """The body of the Markdown summary (the framework adds header and warnings).

    Parameters
    ----------
    result
        A ``navigation_regions`` result.

    Examples
    --------
    >>> from designlab.study import parse_study, run_study
    >>> r = run_study(parse_study('''
    ... designlab: 1
    ... kind: navigation_regions
    ... name: demo
    ... obstacles: [{name: human, type: human}]
    ... '''))
    >>> "δ_r1" in navigation_regions_markdown(r)
    True
    """
    plan = result.plan
    out = _inputs(result)
    out += [
        "## Radii",
        "",
        "Centre distances for discs, distances from the contour for rectangles (Zeng 2011, "
        "Sec. 5.3; docs/navigation_scenarios.md).",
        "",
        markdown_table(
            result.to_frame()[
                ["obstacle", "class", "r3_min_m", "r3_m", "r2_min_m", "r2_m", "r2_margin_m"]
            ].round(4),
            index=False,
        ),
        "",
    ]
    for name, s in plan.sizes.items():
        out += [
            f"## {name}: every quantity",
            "",
            markdown_table(_quantities(s, plan.radii[name][0]), index=False, disable_numparse=True),
            "",
        ]
    snippet = yaml.safe_dump(
        {"obstacles": [{"name": n, **v} for n, v in plan.scenario_regions().items()]},
        sort_keys=False,
    )
    out += [
        "## For a scenario file",
        "",
        "The r2 and r3 of each obstacle (add kind, radius and motion; "
        "docs/navigation_scenarios.md):",
        "",
        "```yaml",
        snippet.rstrip(),
        "```",
        "",
    ]
    return "\n".join(out)


@register_writer(NavigationRegionsResult)
def navigation_regions_report(result: NavigationRegionsResult) -> ReportParts:
    """The report's parts: ``regions.csv`` and the summary's body.

    Parameters
    ----------
    result
        A ``navigation_regions`` result.
    """
    return ReportParts(
        title=f"Region sizes: {result.study.name}",
        body=[navigation_regions_markdown(result)],
        tables={"regions.csv": result.to_frame()},
        warnings=result.plan.warnings,
        no_warnings="None.",
    )
