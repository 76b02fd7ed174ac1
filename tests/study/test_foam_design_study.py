"""The foam_design study kind (issue: foam covering design report)."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from designlab.errors import StudyError
from designlab.report import write_report
from designlab.study import load_study, parse_study, run_study

ROOT = Path(__file__).resolve().parents[2]


SMALL = """
designlab: 1
kind: foam_design
name: small
robots: [MANIPULATOR_1, MANIPULATOR_2]
foams: [FOAM_1, FOAM_2, {stiffness: 60.6e3, damping: 113.6}]
criteria:
  - {type: head_acceleration, max_g: 10}
  - {type: iso_ts_15066, body_region: skull_forehead}
damping: {low: 20, high: 100, num: 5}
optimal: true
worst_case_samples: 8
"""


def test_run_and_report(tmp_path: Path) -> None:
    result = run_study(parse_study(SMALL))
    v = result.verdicts()
    assert list(v["foam"]) == ["Foam 1", "Foam 2", "foam 3"] * 2
    foam1 = v[v.foam == "Foam 1"]
    # the ISO skull/forehead transient force limit (260 N) is much tighter than 10 g
    assert not foam1["feasible"].any()
    out = write_report(result, tmp_path, command="pytest", index=False)
    assert {p.name for p in out.iterdir()} >= {"envelope.md", "envelope.csv", "envelope.png"}
    md = (out / "envelope.md").read_text()
    assert "ISO/TS 15066" in md and "## Verdicts" in md and "## Optimal foam" in md
    env = pd.read_csv(out / "envelope.csv")
    assert set(env["robot"]) == {"Manipulator 1", "Manipulator 2"}
    assert len(env) == 10


def test_schema_errors_name_field_and_line(tmp_path: Path) -> None:
    f = tmp_path / "bad.yaml"
    f.write_text(SMALL.replace("body_region: skull_forehead", "body_region: elbow"))
    with pytest.raises(StudyError) as exc:
        load_study(f)
    msg = str(exc.value)
    assert "bad.yaml:" in msg and "body_region" in msg
    f.write_text(SMALL.replace("max_g: 10", "max_gee: 10"))
    with pytest.raises(StudyError, match="max_g"):
        load_study(f)


def test_committed_report_matches_the_study() -> None:
    """reports/foam_envelope is the output of studies/foam_envelope.yaml (thesis statements)."""
    v = pd.read_csv(ROOT / "reports" / "foam_envelope" / "verdicts.csv")
    row = {(r.robot, r.foam): r for r in v.itertuples()}
    assert row[("Manipulator 1", "Foam 1")].feasible and row[("Manipulator 2", "Foam 1")].feasible
    assert abs(row[("Manipulator 1", "Foam 2")].margin_percent) < 2.0
    assert row[("Manipulator 2", "Foam 2")].margin_percent < -20.0
    assert not row[("Manipulator 2", "Foam 3")].feasible
    study = load_study(ROOT / "studies" / "foam_envelope.yaml")
    assert study.kind == "foam_design" and study.name == "foam_envelope"
