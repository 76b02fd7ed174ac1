"""The ``codesign`` study kind and its report (issue 24, item 5): claims from the tables."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from designlab.report import write_report
from designlab.study import parse_study, run_study

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
"""


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    result = run_study(parse_study(SMALL))
    return write_report(result, tmp_path_factory.mktemp("codesign"))


def test_the_report_holds_its_tables_and_figures(report: Path) -> None:
    names = {p.name for p in report.iterdir()}
    assert {"summary.md", "contacts.csv", "front.csv", "designs.csv", "reference.csv",
            "contacts.png", "front.png"} <= names  # fmt: skip
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
