"""The error sources of Allan 2015 Sec. 3.4 in the tether_comparison study and report."""

from __future__ import annotations

import re
from pathlib import Path

import pandas as pd
import pytest

from designlab.errors import DesignlabError
from designlab.report import write_report
from designlab.report.tether_errors import error_claims
from designlab.study import parse_study, run_study

ROOT = Path(__file__).resolve().parents[2]

STUDY = """\
designlab: 1
kind: tether_comparison
name: cmp_errors
controllers:
  - {type: PseudoJoystick, label: PJ}
  - {type: FollowTheLeaderConstDistance, label: CD}
paths:
  - {type: points, name: walk, points: [[0, 0], [4, 0], [4, 3]]}
  - {type: slalom}
error_sources:
  paths: [walk]
  desired_length: 1.0
  slip: {left_slip: 0.03}
  marker: {left: 0.1}
"""


def test_error_sources_run_per_law_and_variant_and_the_report_states_them(tmp_path):
    result = run_study(parse_study(STUDY))
    table = result.errors
    assert list(table["variant"].unique()) == ["none", "slip", "marker", "both"]
    assert set(table["path"]) == {"walk"} and len(table) == 8
    rows = table.set_index(["controller", "variant"])
    # no slip: the odometry is the truth; with slip it drifts
    assert rows.loc[("CD", "none"), "odometry_drift_m"] == 0.0
    assert rows.loc[("CD", "slip"), "odometry_drift_m"] > 0.01
    # the tip 0.1 m left of the marker: CD, which tracks the tip's path, deviates more
    assert rows.loc[("CD", "marker"), "npd_mean_m"] > rows.loc[("CD", "none"), "npd_mean_m"] + 0.05
    out = write_report(result, tmp_path, index=False)
    assert (out / "error_sources.csv").exists()
    text = (out / "summary.md").read_text()
    assert "## Error sources of Sec. 3.4" in text
    for claim in error_claims(table, "PJ"):
        assert claim in text


def test_claims_follow_a_table_written_in_the_test():
    t = pd.DataFrame(
        {
            "path": ["a"] * 8,
            "controller": ["PJ"] * 4 + ["CD"] * 4,
            "variant": ["none", "slip", "marker", "both"] * 2,
            "npd_mean_m": [0.3, 0.3, 0.32, 0.33, 0.03, 0.06, 0.15, 0.22],
        }
    )
    assert error_claims(t, "PJ") == [
        "a: mean NPD PJ / CD 10.00 without errors, 5.00 with slip, 2.13 with the marker "
        "offset, 1.50 with both."
    ]


@pytest.mark.skipif(
    not (ROOT / "reports" / "tether_comparison" / "error_sources.csv").exists(),
    reason="the committed tether_comparison report is not in this checkout",
)
def test_docs_sentences_follow_from_the_committed_error_table():
    table = pd.read_csv(ROOT / "reports" / "tether_comparison" / "error_sources.csv")
    text = (ROOT / "docs" / "following.md").read_text()
    body = re.search(r"<!-- claims:tether_errors -->\n(.*?)<!-- /claims -->", text, re.S)
    assert body
    items = [" ".join(i.split()) for i in re.split(r"^\s*- ", body.group(1), flags=re.M)]
    assert [i for i in items if i] == error_claims(table, "PJ")


@pytest.mark.parametrize(
    ("body", "name"),
    [
        ("error_sources: {paths: [nowhere]}", "error_sources.paths"),
        ("error_sources: {slip: {left_slip: .nan}}", "left_slip"),
        ("error_sources: {slip: {noise_std: 2}}", "noise_std"),
        ("error_sources: {marker: {left: '0.1'}}", "left"),
        ("error_sources: {desired_length: 0.2}", "desired_length"),
        ("error_sources: {seed: -1}", "seed"),
        ("error_sources: {slips: {}}", "slips"),
    ],
)
def test_hostile_error_sources_yaml_is_refused_naming_the_field(body, name):
    text = (
        "designlab: 1\nkind: tether_comparison\nname: hostile\n"
        f"paths:\n  - {{type: slalom}}\n{body}\n"
    )
    with pytest.raises(DesignlabError) as exc:
        parse_study(text)
    assert name in str(exc.value)
