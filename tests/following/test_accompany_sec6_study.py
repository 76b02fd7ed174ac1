"""The Sec. 6 options in the ``accompanying`` study: YAML, report section, claims."""

from __future__ import annotations

import re
from pathlib import Path

import pandas as pd
import pytest
import yaml

from designlab.errors import DesignlabError
from designlab.report import write_report
from designlab.report.accompanying_extras import extras_claims, extras_frame
from designlab.study import parse_study, run_study

ROOT = Path(__file__).resolve().parents[2]

STUDY = """\
designlab: 1
kind: accompanying
name: acc_extras
tasks: [forward]
tuning: null
extras:
  tasks: [forward, left_pivot]
  sway_lateral: 0.02
  sway_yaw: 0.05
  mount: {offset_y: 0.2}
  adaptation: {gain: 0.4}
  motion_filter: {time_constant: 0.3}
"""


def test_extras_block_runs_each_option_and_the_report_shows_it(tmp_path):
    result = run_study(parse_study(STUDY))
    assert set(result.extras) == {
        "none",
        "mount",
        "mount_compensated",
        "adaptation",
        "motion_filter",
    }
    run = result.extras["mount_compensated"]["left_pivot"]
    assert run.mount.compensate and run.mount.offset == (0.0, 0.2)
    assert result.extras["adaptation"]["forward"].adaptation.gain == 0.4
    params = result.extras["none"]["forward"].task.parameters
    assert (params["sway_lateral_m"], params["sway_yaw_rad"]) == (0.02, 0.05)
    table = extras_frame(result)
    assert len(table) == 10
    out = write_report(result, tmp_path, index=False)
    assert (out / "extras.csv").exists()
    text = (out / "summary.md").read_text()
    assert "## Sec. 6 options" in text
    for claim in extras_claims(table, (0.0, 0.2)):
        assert claim in text


def test_without_extras_the_study_and_report_are_as_before(tmp_path):
    body = STUDY.split("extras:")[0]
    result = run_study(parse_study(body))
    assert result.extras == {}
    out = write_report(result, tmp_path, index=False)
    assert not (out / "extras.csv").exists()
    assert "Sec. 6 options" not in (out / "summary.md").read_text()


def _table(rms: dict[str, tuple[float, float]]) -> pd.DataFrame:
    rows = []
    for option, (a, b) in rms.items():
        for task, v in (("a", a), ("b", b)):
            rows.append(
                {
                    "task": task,
                    "option": option,
                    "rms_error_mm": v,
                    "yaw_command_roughness_rad_s2": v / 10,
                    "max_target_change_mm": 5.0 if option == "adaptation" else 0.0,
                }
            )
    return pd.DataFrame(rows)


def test_claims_follow_a_table_written_in_the_test():
    table = _table(
        {
            "none": (100.0, 200.0),
            "mount": (50.0, 300.0),
            "mount_compensated": (100.0, 200.0),
            "adaptation": (90.0, 180.0),
            "motion_filter": (110.0, 220.0),
        }
    )
    claims = extras_claims(table, (0.0, 0.25))
    assert "-50.0 % on a, +50.0 % on b (lower on 1 of 2 tasks)" in claims[0]
    assert "at most 0.0 %" in claims[1]
    assert "-10.0 % on a, -10.0 % on b (lower on 2 of 2 tasks)" in claims[2]
    assert claims[3] == "Largest target-distance change: 5 mm on a, 5 mm on b."
    assert "(lower on 0 of 2 tasks)" in claims[4]
    assert claims[5].endswith("+10.0 % on a, +10.0 % on b.")
    table.loc[(table.option == "mount_compensated") & (table.task == "b"), "rms_error_mm"] = 220.0
    assert "at most 10.0 %" in extras_claims(table, (0.0, 0.25))[1]


@pytest.mark.skipif(
    not (ROOT / "reports" / "accompanying" / "extras.csv").exists(),
    reason="the committed accompanying report is not in this checkout",
)
def test_docs_sentences_follow_from_the_committed_extras_table():
    folder = ROOT / "reports" / "accompanying"
    table = pd.read_csv(folder / "extras.csv")
    mount = yaml.safe_load((folder / "study.yaml").read_text())["extras"]["mount"]
    text = (ROOT / "docs" / "accompanying.md").read_text()
    body = re.search(r"<!-- claims:accompanying_extras -->\n(.*?)<!-- /claims -->", text, re.S)
    assert body
    items = [" ".join(i.split()) for i in re.split(r"^\s*- ", body.group(1), flags=re.M)]
    items = [i for i in items if i]
    assert items == extras_claims(table, (mount["offset_x"], mount["offset_y"]))


@pytest.mark.parametrize(
    ("body", "name"),
    [
        ("extras: {mount: {offset_y: .nan}}", "offset_y"),
        ("extras: {mount: {offset_y: 0.2, compensate: true}}", "compensate"),
        ("extras: {adaptation: {gain: -1}}", "gain"),
        ("extras: {adaptation: {max_change: '0.2'}}", "max_change"),
        ("extras: {motion_filter: {time_constant: 0}}", "time_constant"),
        ("extras: {tasks: [jogging]}", "tasks"),
        ("extras: {tasks: []}", "tasks"),
        ("extras: {sway_yaw: 1.0e9}", "sway_yaw"),
        ("extras: {filter: {time_constant: 0.2}}", "filter"),
    ],
)
def test_hostile_extras_yaml_is_refused_naming_the_field(body, name):
    text = f"designlab: 1\nkind: accompanying\nname: hostile\ntuning: null\n{body}\n"
    with pytest.raises(DesignlabError) as exc:
        parse_study(text)
    assert name in str(exc.value)
