"""The zeng_ch3_claims study kind: Zeng 2011 Ch. 3 statements recomputed and restated."""

from __future__ import annotations

from pathlib import Path

import pytest

from designlab.errors import StudyError
from designlab.report import write_report
from designlab.results import check_result
from designlab.study import load_study, parse_study, run_study

ROOT = Path(__file__).resolve().parents[2]

SMALL = """
designlab: 1
kind: zeng_ch3_claims
name: small
readings:
  - {name: b, impact_velocity: 0.25, feedforward: false}
speed_ratios: [0.62, 2.3]
"""


def test_run_and_report(tmp_path: Path) -> None:
    result = run_study(parse_study(SMALL))
    check_result(result)
    prof = result.profiles_frame()
    assert list(prof.reading) == ["b", "b"] and list(prof.thesis_d_f_c_pct) == [5.0, -4.0]
    # Sec. 3.8 reading (b) with standard gravity; the first peak, not the lobe maximum
    assert prof.d_f_c_first_peak_pct.tolist() == pytest.approx([4.95, -3.98], abs=0.01)
    assert prof.d_f_c_lobe_max_pct.iloc[0] > 80
    worst = result.worst_frame()
    assert worst.worst_l_m.tolist() == pytest.approx([0.0100, 0.0367], abs=2e-4)
    assert worst.d_a_h_max_l0_vs_ref_pct.tolist() == pytest.approx([-0.31, -1.95], abs=0.01)
    assert len(result.q2_frame()) == 4 * 4
    t31 = result.table_3_1_frame().set_index("quantity")
    assert t31.loc["mass", "recomputed"] == pytest.approx(0.059 / 0.078**2)
    assert t31.loc["mass", "printed"] == 9.6
    out = write_report(result, tmp_path, command="pytest", index=False)
    names = {p.name for p in out.iterdir()}
    assert names >= {"summary.md", "sec_3_8.csv", "fig_3_16.csv", "q2.csv", "table_3_1.csv",
                     "zeng_ch3_claims.png"}  # fmt: skip
    md = (out / "summary.md").read_text()
    assert 'cannot give +5 %" is wrong' in md and "| +4.95 " in md


@pytest.mark.parametrize(
    "old,new,field",
    [
        ("speed_ratios: [0.62, 2.3]", "speed_ratios: [-1]", "speed_ratios"),
        ("speed_ratios: [0.62, 2.3]", "speed_ratios: []", "speed_ratios"),
        ("impact_velocity: 0.25", "impact_velocity: 0", "impact_velocity"),
        ("impact_velocity: 0.25", "impact_velocity: .inf", "impact_velocity"),
        ("feedforward: false", "feedforward: maybe", "feedforward"),
        ("name: b,", "name: '',", "name"),
        ("speed_ratios:", "acceleration_g: -0.5\nspeed_ratios:", "acceleration_g"),
        ("speed_ratios:", "head: HEAD_MAX\nspeed_ratios:", "head"),
    ],
)
def test_schema_errors(refuses_edit, old: str, new: str, field: str) -> None:
    refuses_edit(SMALL, old, new, field)


def test_duplicate_reading_names() -> None:
    text = SMALL.replace(
        "  - {name: b,", "  - {name: b, impact_velocity: 1.25, feedforward: true}\n  - {name: b,"
    )
    with pytest.raises(StudyError, match="distinct"):
        parse_study(text)


def test_the_study_gives_the_fig_3_16_worst_points() -> None:
    """studies/zeng_ch3_claims.yaml's worst impact points (Fig. 3.16), computed here."""
    from designlab.impact import FOAM_1, HEAD_MIN, MANIPULATOR_1
    from designlab.impact.ch3_claims import worst_impact_point

    study = load_study(ROOT / "studies" / "zeng_ch3_claims.yaml")
    assert study.kind == "zeng_ch3_claims" and study.name == "zeng_ch3_claims"
    l1 = MANIPULATOR_1.lever_arm
    m, k, c = (MANIPULATOR_1.mass * l1**2, MANIPULATOR_1.stiffness * l1**2,
               MANIPULATOR_1.damping * l1**2)  # fmt: skip
    worst = [
        worst_impact_point(m, k, c, r, FOAM_1, HEAD_MIN, samples=40).lever_arm
        for r in study.speed_ratios
    ]
    assert worst == pytest.approx([0.008, 0.010, 0.016, 0.037], abs=6e-4)
