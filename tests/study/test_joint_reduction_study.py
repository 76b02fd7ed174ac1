"""The joint_reduction study kind: where the reduced joint (3.4.9) may be used."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

import designlab as dl
from designlab.report import write_report
from designlab.results import check_result
from designlab.study import load_study, parse_study, run_study

ROOT = Path(__file__).resolve().parents[2]

SMALL = """
designlab: 1
kind: joint_reduction
name: small
joints:
  - {name: geared, inertia: 0.059, k_mech: 2000, c_mech: 2.0, k_cont: 1500, c_cont: 30,
     lever_arm: 0.2}
  - {inertia: 0.059, k_mech: 1216.8, c_mech: 0.1, k_cont: 121.68, c_cont: 1.521,
     lever_arm: 0.078}
ratios: {low: 0.1, high: 1000, num: 5}
"""


def test_run_and_report(tmp_path: Path) -> None:
    result = run_study(parse_study(SMALL))
    check_result(result)
    assert [j.robot.name for j in result.joints] == ["geared", "joint 2"]
    frame = result.to_frame()
    assert len(frame) == 2 * 5 * 2 * 5  # joints x ratios x reductions x metrics
    # the study's numbers are the domain's
    arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    direct = dl.impact.compare_joint_reductions(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25)
    assert result.joints[0].nominal.relative_error("taylor", "eps_max") == pytest.approx(
        direct.relative_error("taylor", "eps_max"), rel=1e-12
    )
    out = write_report(result, tmp_path, command="pytest", index=False)
    names = {p.name for p in out.iterdir()}
    assert names >= {"summary.md", "joint_reduction.csv", "nominal.csv",
                     "joint_reduction.png"}  # fmt: skip
    md = (out / "summary.md").read_text()
    assert "## Where the reduction is conservative" in md and "**-10.15 %**" in md
    assert "usable (conservative or within 1 %)" in md
    nominal = pd.read_csv(out / "nominal.csv")
    assert set(nominal.reduction) == {"taylor", "band_fit"}


@pytest.mark.parametrize(
    "old,new,field",
    [
        ("c_mech: 2.0, k_cont: 1500, c_cont: 30", "c_mech: 0, k_cont: 1500, c_cont: 0", "c_mech"),
        ("{low: 0.1, high: 1000, num: 5}", "{low: 10, high: 1, num: 5}", "low"),
        ("{low: 0.1, high: 1000, num: 5}", "{low: 0.1, high: 1000, num: 2000}", "num"),
        ("k_mech: 2000", "k_mech: -2000", "k_mech"),
        ("lever_arm: 0.2", "lever_arm: .nan", "lever_arm"),
        ("name: geared, ", "name: joint 2, ", "distinct"),  # clashes with the unnamed 2nd joint
        ("lever_arm: 0.2}", "lever_arm: 0.2, gear: 3}", "gear"),
        ("ratios: {low", "usable_tolerance: 1.5\nratios: {low", "usable_tolerance"),
        ("ratios: {low", "usable_tolerance: .nan\nratios: {low", "usable_tolerance"),
    ],
)
def test_schema_errors(refuses_edit, old: str, new: str, field: str) -> None:
    refuses_edit(SMALL, old, new, field)


def test_the_study_gives_the_documented_errors() -> None:
    """studies/joint_reduction.yaml's geared joint, computed here: the Taylor reduction
    overestimates a_h,max by 12.5 % and underestimates eps_max by 10.2 %
    (docs/impact_joint.md)."""
    import designlab as dl

    study = load_study(ROOT / "studies" / "joint_reduction.yaml")
    assert study.kind == "joint_reduction" and study.name == "joint_reduction"
    geared = study.joints[0].build(0)
    assert geared.name == "geared joint (illustrative)"
    c = dl.impact.compare_joint_reductions(
        geared, study.foam.build(), study.head.build(), study.impact_velocity
    )
    assert c.relative_error("taylor", "a_h_max") == pytest.approx(0.1253, abs=5e-4)
    assert c.conservative("taylor", "a_h_max")
    assert c.relative_error("taylor", "eps_max") == pytest.approx(-0.1015, abs=5e-4)
    assert not c.conservative("taylor", "eps_max")
    assert study.ratios.num == 41 and len(study.joints) == 2
