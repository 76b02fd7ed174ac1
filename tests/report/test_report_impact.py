"""Content of an impact_cases report: CSV columns and units, Markdown, PNG."""

from __future__ import annotations

import math

import pandas as pd
import pytest

import designlab
from designlab.report import write_report
from designlab.study import parse_study, run_study


@pytest.fixture(scope="module")
def report(tmp_path_factory, tiny_study_text):
    out_root = tmp_path_factory.mktemp("reports")
    result = run_study(parse_study(tiny_study_text))
    out = write_report(
        result, out_root, command="designlab run tiny.yaml", study_text=tiny_study_text
    )
    return out, result


def test_files(report):
    out, _ = report
    assert out.name == "tiny"
    assert sorted(p.name for p in out.iterdir()) == [
        "metrics.csv",
        "study.yaml",
        "summary.md",
        "time_histories.png",
    ]
    assert (out / "time_histories.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_metrics_csv(report):
    out, result = report
    frame = pd.read_csv(out / "metrics.csv")
    for col in [
        "a_h_max_g",
        "t_imp_s",
        "eps_max_m",
        "peak_force_N",
        "hic15",
        "ref_a_h_max_g",
        "err_a_h_max_pct",
        "err_t_imp_s",
        "err_eps_max_pct",
    ]:
        assert col in frame.columns
    assert list(frame.case) == ["slow", "fast"]
    slow = frame.iloc[0]
    r = result.cases[0].response
    assert slow.a_h_max_g == pytest.approx(r.peak_head_acceleration_g, rel=1e-6)
    # the CSV holds 7 significant digits: a_h to ~5e-7 relative, so the error to ~3e-5 %
    assert slow.err_a_h_max_pct == pytest.approx(100 * (slow.a_h_max_g / 2.10 - 1), abs=1e-4)
    assert slow.err_t_imp_s == pytest.approx(slow.t_imp_s - 0.033, abs=1e-7)
    assert bool(slow.within_tolerance)
    # no reference for the second case: errors are empty, not zero
    assert math.isnan(frame.iloc[1].err_a_h_max_pct)
    # the model is linear in v_c (thesis Sec. 4.3.2)
    ratio = frame.iloc[1].a_h_max_g / frame.iloc[0].a_h_max_g
    assert ratio == pytest.approx(1.25 / 0.4, rel=1e-6)


def test_summary_markdown(report):
    out, _ = report
    text = (out / "summary.md").read_text()
    assert text.startswith("# tiny\n")
    assert "`designlab run tiny.yaml`" in text
    assert f"designlab {designlab.__version__}" in text
    assert "![all cases](time_histories.png)" in text
    assert "## Model vs reference simulation" in text
    assert "| slow " in text and "| fast " in text
    assert "- slow: a_h,max within 2 %, t_imp within 3 ms, eps_max within 6 %" in text
