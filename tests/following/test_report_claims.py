"""Every ranking and claim sentence of the tether reports and docs is computed from its table."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from designlab.report.tether import (
    comparison_markdown,
    heuristic_claim,
    ranking_claims,
    ranking_column,
)
from designlab.study import parse_study, run_study

ROOT = Path(__file__).resolve().parents[2]


def _frame(values: dict[tuple[str, float], tuple[float, float, float]]) -> pd.DataFrame:
    rows = [
        {"path": p, "desired_length_m": ld, "controller": law, "npd_mean_m": v}
        for (p, ld), vals in values.items()
        for law, v in zip(("PJ", "FTL", "FTL-CD"), vals, strict=True)
    ]
    return pd.DataFrame(rows)


TABLE = {
    ("a", 0.6): (0.30, 0.10, 0.05),
    ("a", 2.0): (0.90, 0.11, 0.06),
    ("b", 0.6): (0.20, 0.04, 0.08),
    ("b", 2.0): (0.40, 0.50, 0.20),
}


def test_ranking_sentences_from_a_table_written_in_the_test():
    claims = ranking_claims(_frame(TABLE))
    assert claims[0] == (
        "FTL deviates less than PJ in 3 of 4 (path, l_d) cases; PJ / FTL ranges from 0.80 "
        "(b, l_d = 2 m) to 8.18 (a, l_d = 2 m). It does not on: b, l_d = 2 m (0.80)."
    )
    assert claims[1] == (
        "FTL-CD deviates less than PJ in all 4 (path, l_d) cases; PJ / FTL-CD ranges from "
        "2.00 (b, l_d = 2 m) to 15.00 (a, l_d = 2 m)."
    )
    assert claims[2] == (
        "At l_d = 0.6 m the least mean deviation is: FTL on 1 (b), FTL-CD on 1 (a) of 2 paths."
    )
    assert claims[3] == "At l_d = 2 m the least mean deviation is: FTL-CD on 2 (a, b) of 2 paths."
    assert claims[4].startswith("PJ's mean deviation grows with l_d on 2 of 2 paths;")
    assert "3.00 (a), 2.00 (b)" in claims[4]
    assert ranking_column(_frame(TABLE)).tolist() == [
        "FTL-CD < FTL < PJ",
        "FTL-CD < FTL < PJ",
        "FTL < FTL-CD < PJ",
        "FTL-CD < PJ < FTL",
    ]


def test_perturbing_the_table_changes_the_sentences():
    base = ranking_claims(_frame(TABLE))
    worse = dict(TABLE)
    worse[("a", 0.6)] = (0.30, 0.10, 0.31)  # FTL-CD now deviates more than PJ once
    changed = ranking_claims(_frame(worse))
    assert changed[1].startswith("FTL-CD deviates less than PJ in 3 of 4 (path, l_d) cases")
    assert changed[1].endswith("It does not on: a, l_d = 0.6 m (0.97).")
    assert changed[1] != base[1]
    assert changed[2] == ("At l_d = 0.6 m the least mean deviation is: FTL on 2 (a, b) of 2 paths.")


def test_heuristic_sentence_follows_its_table():
    t = pd.DataFrame(
        {
            "path": ["a", "b", "c"],
            "controller": ["PJ", "FTL", "FTL-CD"],
            "desired_length_m": [1.0, 2.0, 0.6],
            "npd_mean_m": [0.28, 0.14, 0.28],
            "npd_mean_heuristic_m": [0.28, 0.07, 0.2996],
        }
    )
    t["change"] = t["npd_mean_heuristic_m"] / t["npd_mean_m"] - 1
    text = heuristic_claim(t)
    assert "by -50.0 % to +7.0 % over the 3 runs (unchanged, to 0.1 %, on 1)" in text
    assert "b, FTL, l_d = 2 m, 0.250 b instead of 0.500 b" in text


STUDY = """\
designlab: 1
kind: tether_comparison
name: cmp
controllers:
  - {type: PseudoJoystick, label: PJ}
  - {type: FollowTheLeaderConstDistance, label: FTL-CD}
desired_lengths: [0.6, 1.0]
paths:
  - {type: slalom}
"""


def test_the_report_prints_the_sentences_of_its_table_and_follows_a_perturbed_table(
    monkeypatch,
):
    result = run_study(parse_study(STUDY))
    frame = result.to_frame()
    text = comparison_markdown(result, figures={})
    for claim in ranking_claims(frame):
        assert claim in text
    assert "ranking" in text and "FTL-CD < PJ" in text
    perturbed = frame.copy()
    pj = perturbed["controller"] == "PJ"
    perturbed.loc[pj, "npd_mean_m"] = 1e-6  # PJ now best everywhere
    perturbed.loc[pj, "npd_mean_over_b"] = 1e-6 / 0.28
    monkeypatch.setattr(type(result), "to_frame", lambda self: perturbed)
    new = comparison_markdown(result, figures={})
    assert "FTL-CD deviates less than PJ in 0 of 2 (path, l_d) cases" in new
    assert "FTL-CD deviates less than PJ in all 2" in text
    assert "PJ < FTL-CD" in new


def _docs_block(name: str) -> list[str]:
    text = (ROOT / "docs" / "following.md").read_text()
    body = re.search(rf"<!-- claims:{name} -->\n(.*?)<!-- /claims -->", text, re.S)
    assert body, name
    items = re.split(r"^\s*- ", body.group(1), flags=re.M)
    return [" ".join(i.split()) for i in items if i.strip()]


@pytest.mark.skipif(
    not (ROOT / "reports" / "tether_comparison" / "npd_heuristic.csv").exists(),
    reason="the committed tether_comparison report is not in this checkout",
)
def test_docs_sentences_follow_from_the_committed_report_tables():
    """docs/following.md states what the generators give on the committed report tables."""
    folder = ROOT / "reports" / "tether_comparison"
    metrics = pd.read_csv(folder / "metrics.csv")
    heur = pd.read_csv(folder / "npd_heuristic.csv")
    assert _docs_block("tether_comparison") == ranking_claims(metrics)
    assert _docs_block("tether_heuristic") == [heuristic_claim(heur)]
    assert np.isfinite(metrics["npd_mean_m"]).all()


@pytest.mark.skipif(
    not (ROOT / "reports" / "accompanying" / "baseline_sensitivity.csv").exists(),
    reason="the committed accompanying report is not in this checkout",
)
def test_docs_accompanying_sentences_follow_from_the_committed_report_tables():
    from designlab.report.accompanying import baseline_claim, tuning_claims

    folder = ROOT / "reports" / "accompanying"
    tuning = pd.read_csv(folder / "tuning.csv")
    metrics = pd.read_csv(folder / "metrics.csv")
    base = pd.read_csv(folder / "baseline_sensitivity.csv")
    assert _docs_block("accompanying_tuning") == tuning_claims(tuning, metrics)
    assert _docs_block("accompanying_baseline") == [baseline_claim(base)]


def test_accompanying_sentences_follow_a_perturbed_table():
    from designlab.report.accompanying import sign_claim, tuning_claims

    tu = pd.DataFrame({"method": ["default", "tuned"], "mean_rms_all_tasks_m": [0.1, 0.02]})
    me = pd.DataFrame(
        {
            "controller": ["default"] * 2 + ["tuned"] * 2,
            "task": ["a", "b"] * 2,
            "rms_error_m": [0.1, 0.1, 0.01, 0.03],
        }
    )
    assert tuning_claims(tu, me)[0].endswith("(80 % lower); lower on 2 of 2 tasks.")
    me.loc[3, "rms_error_m"] = 0.2
    tu.loc[1, "mean_rms_all_tasks_m"] = 0.105
    assert tuning_claims(tu, me)[0].endswith("(5 % higher); lower on 1 of 2 tasks.")
    signs = pd.DataFrame(
        {
            "task": ["a"],
            "paper_dX_mm": [5.0],
            "default_dX_mm": [4.0],
            "X_sign_agrees": ["yes"],
            "paper_dY_mm": [0.0],
            "default_dY_mm": [0.0],
            "Y_sign_agrees": ["n/a"],
        }
    )
    assert sign_claim(signs).startswith("The sign agrees with the paper in 1 of the 1 ")
    signs.loc[0, "X_sign_agrees"] = "no"
    assert "it does not in: a X" in sign_claim(signs)


@pytest.mark.skipif(
    not (ROOT / "reports" / "tether_tuning" / "improvement.csv").exists(),
    reason="the committed tether_tuning report is not in this checkout",
)
def test_docs_tuning_sentences_follow_from_the_committed_report_table():
    from designlab.report.tether import tuning_claims

    imp = pd.read_csv(ROOT / "reports" / "tether_tuning" / "improvement.csv")
    assert _docs_block("tether_tuning") == tuning_claims(imp)
    worse = imp.copy()
    worse.loc[0, "improvement_validation"] = -0.2
    assert tuning_claims(worse)[0] != tuning_claims(imp)[0]
    assert "are worse than the defaults by 20.0 %" in tuning_claims(worse)[0]
