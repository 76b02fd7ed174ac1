"""The ``codesign`` study kind and its report (issue 24, item 5): claims from the tables."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from designlab.report import write_report
from designlab.study import parse_study, run_study

# a whole study and its report (24 CPU s of one process at a load of 15): a long validation,
# run by .ci/run's second step (-m slow), not by the README's test command
pytestmark = pytest.mark.slow

SMALL = """
designlab: 1
kind: codesign
name: small
scenarios: [{configuration: 2}]
walks: {n: 2, seed: 1}
front:
  objectives: [arrival_time, closing_speed]
  space: {thickness_min: 0.03, thickness_max: 0.03}
  population: 4
  generations: 2
  seed: 3
  compare_seeds: [4]
  risk_bound: 0.5
speed_map: {stiffness: {low: 1.0e+4, high: 6.0e+4, num: 4}, damping: {num: 3}}
risk: {foams: [FOAM_1, FOAM_3], speeds: {low: 0.5, high: 3.5, num: 4}, samples: 2000}
sensitivity: {samples: 2, seed: 1}
"""


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    result = run_study(parse_study(SMALL))
    return write_report(result, tmp_path_factory.mktemp("codesign"))


def test_the_report_holds_its_tables_and_figures(report: Path) -> None:
    names = {p.name for p in report.iterdir()}
    assert {"summary.md", "contacts.csv", "front.csv", "designs.csv", "reference.csv",
            "speed_map.csv", "risk.csv", "speed_map.png", "risk.png", "contacts.png",
            "front.png", "sensitivity.csv", "sensitivity.png"} <= names  # fmt: skip
    assert len(pd.read_csv(report / "speed_map.csv")) == 12
    risk = pd.read_csv(report / "risk.csv")
    assert len(risk) == 8 and set(risk["foam"]) == {"Foam 1", "Foam 3"}
    for _, g in risk.groupby("foam"):  # the linear model: the risk never falls with speed
        assert g["probability"].is_monotonic_increasing
    designs = pd.read_csv(report / "designs.csv")
    assert len(designs) == 8 and (designs["T_u_m"] == 0.03).all()  # the fixed variable
    contacts = pd.read_csv(report / "contacts.csv")
    assert len(contacts) == 2  # one walking human, two random walks


def test_claims_are_computed_from_the_tables(report: Path) -> None:
    text = (report / "summary.md").read_text(encoding="utf-8")
    designs = pd.read_csv(report / "designs.csv")
    front = pd.read_csv(report / "front.csv")
    ref = pd.read_csv(report / "reference.csv").iloc[0]
    m = re.search(r"evaluated (\d+) designs .*?; (\d+) meet every hard constraint and (\d+)", text)
    assert m is not None
    assert [int(g) for g in m.groups()] == [
        len(designs), int(designs["feasible"].sum()), len(front)
    ]  # fmt: skip
    cols = ["arrival_time_s", "closing_speed_m_per_s"]
    F = front[cols].to_numpy()
    for i, f in enumerate(F):  # the front is non-dominated (brute force)
        others = np.delete(F, i, axis=0)
        assert not ((others <= f).all(axis=1) & (others < f).any(axis=1)).any()
    r = ref[cols].to_numpy(dtype=float)
    dominating = ((F <= r).all(axis=1) & (F < r).any(axis=1)).sum()
    assert int(ref["dominated_by"]) == dominating
    assert f"{dominating} front designs dominate it" in text
    contacts = pd.read_csv(report / "contacts.csv")
    assert f"to {contacts['v_rel_m_per_s'].max():.3f} m/s" in text
    smap = pd.read_csv(report / "speed_map.csv")
    lo, hi = smap["max_speed_m_per_s"].min(), smap["max_speed_m_per_s"].max()
    assert f"ranges from {lo:.3f} to {hi:.3f} m/s" in text
    assert f"{int((smap['max_speed_m_per_s'] <= 0).sum())} foams allow no robot speed" in text
    lower = 1 - smap["v_c_max_m_per_s"] / smap["v_c_max_grid_m_per_s"]
    assert (lower >= 0).all()  # off the grid, never a better head than the grid's
    assert f"for {int((lower > 1e-9).sum())} of the {len(smap)} foams" in text
    assert f"by up to {100 * lower.max():.2f} %" in text
    risk = pd.read_csv(report / "risk.csv")
    for name, g in risk.groupby("foam"):
        top = g.iloc[-1]
        assert f"- {name}: " in text and f"P = {top['probability']:.3g}" in text


def test_sensitivity_table_and_claims(report: Path) -> None:
    sens = pd.read_csv(report / "sensitivity.csv")
    # 7 free variables (T_u is fixed) x (2 objectives + infeasible)
    assert len(sens) == 21 and "T_u" not in set(sens["parameter"])
    assert set(sens["metric"]) == {"arrival_time", "closing_speed", "infeasible"}
    f = sens.set_index(["metric", "parameter"])
    for metric in ("arrival_time", "closing_speed"):  # the foam does not steer the robot
        for var in ("K_c", "C_c"):
            assert f.loc[(metric, var), "ST"] == 0.0
    text = (report / "summary.md").read_text(encoding="utf-8")
    assert "## Sensitivity of the front" in text and "18 designs (2 x (7 + 2)" in text
    rows = sens[sens["metric"] == "arrival_time"]
    if rows["ST"].notna().any():
        top = rows.loc[rows["ST"].abs().idxmax()]
        assert f"- arrival_time: most influential {top['parameter']} (S_T = {top['ST']:.3g}" in text
        zero = rows[(rows["ST"] == 0) & (rows["ST_conf"] == 0)]["parameter"]
        assert "K_c" in set(zero) and "C_c" in set(zero)
        assert "S_T = 0 exactly (changing it alone never changed the metric in the sample)" in text


def test_the_report_opens_with_the_designers_answer_from_its_tables(report: Path) -> None:
    text = (report / "summary.md").read_text()
    first = text.split("## Speed-limit map")[0]
    front = pd.read_csv(report / "front.csv")
    seeds = pd.read_csv(report / "seeds.csv")
    assert seeds["seed"].tolist() == [3, 4] and (seeds["designs"] == 8).all()
    assert len(pd.read_csv(report / "hypervolume.csv")) == 2
    if front.empty:
        assert "nothing can be signed" in first
        return
    # the pick under equal weights: the smallest sum of the objectives normalised over the front
    cols = ["arrival_time_s", "closing_speed_m_per_s"]
    z = (front[cols] - front[cols].min()) / (front[cols].max() - front[cols].min()).replace(0, 1)
    d = front.iloc[int(np.argmin(z.sum(axis=1).to_numpy()))]
    assert f"speed limit V_mr = {d['V_mr_m_per_s']:.3g} m/s" in first
    assert f"T_u = {1e3 * d['T_u_m']:.3g} mm" in first
    assert "**Risk:**" in first and "**Binding constraint:**" in first
    assert "Seed 4's search picks" in first or "Seed 4 found no feasible design" in first
    iso = pd.read_csv(report / "iso.csv")
    assert len(iso) == 12 and "## ISO/TS 15066 beside the Zeng model" in text
