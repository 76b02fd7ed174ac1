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


@pytest.mark.slow
def test_run_and_report(tmp_path: Path) -> None:
    result = run_study(parse_study(SMALL))
    v = result.verdicts()
    assert list(v["foam"]) == ["Foam 1", "Foam 2", "foam 3"] * 2
    foam1 = v[v.foam == "Foam 1"]
    # the ISO/TS 15066 Table A.2 skull/forehead force (130 N) is much tighter than 10 g
    assert set(foam1["verdict"]) == {"not feasible"}
    assert all(
        "exceeds the upper (safety) boundary by" in s or "no stiffness is feasible" in s
        for s in foam1["statement"]
    )
    out = write_report(result, tmp_path, command="pytest", index=False)
    assert {p.name for p in out.iterdir()} >= {"envelope.md", "envelope.csv", "envelope.png"}
    md = (out / "envelope.md").read_text()
    assert "ISO/TS 15066" in md and "## Verdicts" in md and "## Optimal foam" in md
    assert "Table A.2" in md and "## Worst-case check" in md
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


def test_the_study_reproduces_the_thesis_statements() -> None:
    """studies/foam_design.yaml's verdicts (Sec. 3.9), computed here from its robots and foams."""
    import designlab as dl

    study = load_study(ROOT / "studies" / "foam_design.yaml")
    assert study.kind == "foam_design" and study.name == "foam_design"
    foams = {f.build().name: f.build() for f in study.foams}
    row = {}
    for spec in study.robots:
        robot = spec.build()
        env = dl.impact.foam_envelope(robot, study.impact_velocity, study.damping.values())
        for name, foam in foams.items():
            row[(robot.name, name)] = dl.impact.foam_verdict(env, foam)
    assert row[("Manipulator 1", "Foam 1")].verdict == "feasible"
    assert row[("Manipulator 2", "Foam 1")].verdict == "feasible"
    # Sec. 3.9: Foam 2 "almost on the boundary" for Manipulator 1, well below for Manipulator 2
    assert row[("Manipulator 1", "Foam 2")].verdict == "on the boundary"
    assert 100 * row[("Manipulator 2", "Foam 2")].lower_deficit > 20.0
    # Foam 3 on Manipulator 1: 1.0 % over the upper boundary (K_c / K_c,max - 1, standard
    # gravity); not feasible on Manipulator 2
    assert 100 * row[("Manipulator 1", "Foam 3")].upper_excess == pytest.approx(1.0, abs=0.05)
    assert row[("Manipulator 2", "Foam 3")].verdict == "not feasible"


def test_iso_spec_contacts() -> None:
    base = SMALL.replace("optimal: true", "optimal: false").replace(
        "worst_case_samples: 8", "worst_case_check: false"
    )
    with pytest.raises(StudyError, match="no transient-contact multiplier"):
        (parse_study(base.replace("skull_forehead}", "skull_forehead, contact: transient}")))
    with pytest.raises(StudyError, match="transient_factor"):
        parse_study(base.replace("skull_forehead}", "skull_forehead, transient_factor: 2}"))
    study = parse_study(
        base.replace(
            "skull_forehead}", "skull_forehead, contact: transient, transient_factor: 1.5}"
        )
    )
    assert study.criteria[1].build().limit == pytest.approx(195.0)


def test_failed_worst_case_check_is_a_status_and_a_warning() -> None:
    """Manipulator 1's lower boundary: the maximum head set stops being the worst (C_c ~ 108)."""
    text = """
designlab: 1
kind: foam_design
name: wc
robots: [MANIPULATOR_1]
damping: {low: 100, high: 120, num: 3}
optimal: false
worst_case_samples: 0
"""
    result = run_study(parse_study(text))
    assert result.status == "worst_case_violated"
    assert any("not the worst case on the lower boundary" in w for w in result.warnings)
    check = result.designs[0].check
    onset = check.onset_damping["eps_max <= 20 mm"]
    assert 100.0 < onset < 112.0
