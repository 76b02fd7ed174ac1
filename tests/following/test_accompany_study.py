"""The ``accompanying`` study kind and its report."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from designlab.errors import StudyError
from designlab.report import write_report
from designlab.results import check_result
from designlab.study import parse_study, run_study, study_kinds

REPO = Path(__file__).resolve().parents[2]

SMALL = """\
designlab: 1
kind: accompanying
name: acc_small
tasks: [forward, right_pivot]
tuning: {tune_on: [forward], derivative_free: false}
"""


def test_kind_registered_and_shipped_study_validates():
    assert "accompanying" in study_kinds()
    study = parse_study((REPO / "studies" / "accompanying.yaml").read_text())
    assert len(study.tasks) == 9 and study.tuning.ms_max == 1.6


@pytest.mark.parametrize(
    ("extra", "field"),
    [
        ("tasks: [forward, sideways]\n", "tasks"),
        ("platform: {time_constant: -0.1}\n", "time_constant"),
        ("sensor: {min_range: 1.0, max_range: 0.5}\n", "max_range"),
        ("controller: {kp: .nan}\n", "kp"),
        ("walking: {speed: -1}\n", "speed"),
        ("walking: {radius: 0}\n", "radius"),
        ("tasks: [forward, forward]\n", "twice"),
    ],
)
def test_bad_studies(extra, field):
    text = SMALL.replace("tasks: [forward, right_pivot]\n", "") + extra
    with pytest.raises((StudyError, ValueError), match=field):
        study = parse_study(text)
        run_study(study)


@pytest.mark.slow
def test_run_and_report(tmp_path):
    result = run_study(parse_study(SMALL))
    check_result(result)
    assert result.status == "ok"
    frame = result.to_frame()
    assert set(frame["controller"]) == {"default", "tuned"}
    tuning = result.tuning_frame()
    assert tuning.set_index("method").loc["tuned", "improvement_all_tasks"] > 0.5
    out = write_report(result, tmp_path, index=False)
    files = {p.name for p in out.iterdir()}
    assert {
        "summary.md",
        "metrics.csv",
        "table1.csv",
        "table2.csv",
        "tuning.csv",
        "margins.csv",
        "errors.png",
        "bode.png",
        "nyquist.png",
        "trajectories_default.png",
        "trajectories_tuned.png",
    } <= files
    t2 = pd.read_csv(out / "table2.csv")
    paper = t2[(t2["task"] == "forward") & (t2["source"] == "paper")].iloc[0]
    assert (paper["target_X_mm"], paper["target_Y_mm"]) == (95, 418)
    sim = t2[(t2["task"] == "forward") & (t2["source"] == "default")].iloc[0]
    assert sim["target_X_mm"] == pytest.approx(95.0) and sim["avg_Y_mm"] < 418
    t1 = pd.read_csv(out / "table1.csv")
    fwd_user = t1[
        (t1["task"] == "forward") & (t1["source"] == "paper") & (t1["subject"] == "user")
    ].iloc[0]
    assert fwd_user["disp_Y_mm"] == 1914  # the text's value, not the printed 914
    text = (out / "summary.md").read_text()
    assert "Table 2" in text and "anomaly" in text
