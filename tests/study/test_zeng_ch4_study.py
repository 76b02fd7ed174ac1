"""The default study reproduces Zeng 2011 Tables 4.1 and 4.2 (simulated values).

Tolerances of the issue, model vs the thesis's simulated values: a_h,max within
2 % (Table 4.1) or 5 % (Table 4.2), impact period within 3 ms, eps_max within
6 %. The committed report must be what the current model produces.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from designlab.study import load_study, run_study

TOL_A = {"Table 4.1": 2.0, "Table 4.2": 5.0}  # percent
TOL_T = 0.003  # s
TOL_EPS = 6.0  # percent

# Finding: the thesis's Foam 2, C_r = 500 N s/m row of Table 4.1 is not reproduced.
# The thesis prints a shorter impact period for C_r = 500 than for C_r = 250
# (41 vs 42 ms); the linear model (and every nearby parameter variant) gives a
# longer one (44.9 vs 43.7 ms), and an a_h,max 2.06 % above the thesis at 0.4 m/s.
KNOWN_DEVIATIONS = {
    "Foam 2, K_r 20 kN/m, C_r 500, v_c 0.4",
    "Foam 2, K_r 20 kN/m, C_r 500, v_c 1.25",
}


@pytest.fixture(scope="module")
def frame() -> pd.DataFrame:
    return run_study(load_study(STUDY)).to_frame()


STUDY = Path(__file__).resolve().parents[2] / "studies" / "zeng_ch4_validation.yaml"


def _cases():
    study = load_study(STUDY)
    return [
        pytest.param(
            c.title(i),
            marks=pytest.mark.xfail(strict=True, reason="thesis C_r = 500 row, see module")
            if c.title(i) in KNOWN_DEVIATIONS
            else (),
        )
        for i, c in enumerate(study.cases)
    ]


@pytest.mark.parametrize("case", _cases())
def test_case_within_issue_tolerances(frame, case):
    row = frame.set_index("case").loc[case]
    assert row.status == "ok" and not row.bottoming
    assert abs(row.err_a_h_max_pct) <= TOL_A[row.group], row.err_a_h_max_pct
    assert abs(row.err_t_imp_s) <= TOL_T, row.err_t_imp_s
    assert abs(row.err_eps_max_pct) <= TOL_EPS, row.err_eps_max_pct


def test_thesis_claims(frame):
    """Sec. 4.3.2/4.4.2: proportional to v_c, K_r barely matters, model is conservative."""
    f = frame.set_index("case")
    a = f.a_h_max_g
    # a_h,max and eps_max are proportional to v_c
    slow, fast = "Foam 1, K_r 20 kN/m, C_r 250, v_c 0.4", "Foam 1, K_r 20 kN/m, C_r 250, v_c 1.25"
    assert a[fast] / a[slow] == pytest.approx(1.25 / 0.4, rel=1e-6)
    # halving K_r (20 -> 10 kN/m) reduces a_h,max by only about 0.5 %
    soft = "Foam 1, K_r 10 kN/m, C_r 250, v_c 0.4"
    assert 0.0 < 1 - a[soft] / a[slow] < 0.01
    # the Puma (heavier) gives a larger a_h,max than the direct-drive arm
    assert a["Puma 560, Foam 1, v_c 0.4"] > a[slow]
    # the model predicts more than the experiments (conservative), within 9 %
    for _, row in frame.iterrows():
        assert 0 < row.err_exp_a_h_max_pct < 9.0


def test_committed_report_is_current(frame, repo_root):
    committed = repo_root / "reports" / "zeng_ch4_validation" / "metrics.csv"
    assert committed.exists(), "run: designlab run studies/zeng_ch4_validation.yaml"
    old = pd.read_csv(committed)
    cols = ["a_h_max_g", "t_imp_s", "eps_max_m", "peak_force_N"]
    assert list(old.case) == list(frame.case)
    pd.testing.assert_frame_equal(
        old[cols],
        frame[cols],
        rtol=1e-5,
        obj="committed report vs model; regenerate with "
        "`designlab run studies/zeng_ch4_validation.yaml`",
    )
