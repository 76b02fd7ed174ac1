"""The follower_comparison and follower_tuning study kinds and their reports."""

from __future__ import annotations

import pandas as pd
import pytest

from designlab.errors import StudyError
from designlab.report import write_report
from designlab.results import check_result
from designlab.study import parse_study, run_study

COMPARISON = """\
designlab: 1
kind: tether_comparison
name: cmp
controllers:
  - {type: PseudoJoystick}
  - {type: FollowTheLeader, lookahead: 0.3}
  - {type: FollowTheLeaderConstDistance}
desired_lengths: [0.6, 1.0]
paths:
  - {type: slalom}
  - {type: points, name: walk, points: [[0, 0], [3, 0], [3, 3]]}
"""


def test_comparison_runs_and_reports(tmp_path):
    result = run_study(parse_study(COMPARISON))
    check_result(result)
    frame = result.to_frame()
    assert len(frame) == 2 * 2 * 3
    assert set(frame["path"]) == {"slalom", "walk"}
    assert set(frame["desired_length_m"]) == {0.6, 1.0}
    ftl = frame[(frame["controller"] == "FTL")]
    assert (ftl["npd_mean_over_b"] * 0.28).to_numpy() == pytest.approx(ftl["npd_mean_m"].to_numpy())
    # the Tables 3.2/3.3 ranking on the slalom
    sl = frame[frame["path"] == "slalom"].set_index(["desired_length_m", "controller"])
    for ld in (0.6, 1.0):
        assert sl.loc[(ld, "FTL-CD"), "npd_mean_m"] < 0.5 * sl.loc[(ld, "PJ"), "npd_mean_m"]
    out = write_report(result, tmp_path)
    names = {p.name for p in out.iterdir()}
    assert {"summary.md", "metrics.csv", "allan_tables.csv", "trajectories_slalom.png",
            "npd_profiles_walk.png"} <= names  # fmt: skip
    text = (out / "summary.md").read_text()
    assert "Table 3.2" in text and "1.53" in text and "PJ / FTL-CD" in text
    tables = pd.read_csv(out / "allan_tables.csv")
    assert len(tables) == 12
    # linear lateral loop per (law, l_d), against the closed forms of the characteristic
    # equations (PJ: zeta = sqrt(k_O l / v)/2 with l = l_d + v/k_V; FTL: sqrt(K delta / v)/2;
    # FTL-CD: sqrt(K_b / K_p)/2) and against the simulated step
    lin = pd.read_csv(out / "linear.csv").set_index(["desired_length_m", "controller"])
    assert len(lin) == 2 * 3 and "Linear lateral loop" in text
    v = 0.5
    for ld in (0.6, 1.0):
        l_pj = ld + v / 5.0
        assert lin.loc[(ld, "PJ"), "damping_ratio"] == pytest.approx(0.5 * (12 * l_pj / v) ** 0.5)
        assert lin.loc[(ld, "FTL"), "damping_ratio"] == pytest.approx(0.5 * (3 * 0.3 / v) ** 0.5)
        assert lin.loc[(ld, "FTL-CD"), "damping_ratio"] == pytest.approx(0.5)
    assert (lin["sim_damping_ratio"] - lin["damping_ratio"]).abs().max() < 0.1
    assert lin["discrete_stable"].all()


@pytest.mark.parametrize(
    ("patch", "field"),
    [
        ("  - {type: FollowTheLeader, lookahead: -0.3}", "lookahead"),
        ("  - {type: FollowTheLeader, lookahed: 0.3}", "lookahed"),
        ("  - {type: Joystick}", "type"),
        ("  - {type: FollowTheLeader, turn_gain: .nan}", "turn_gain"),
    ],
)
def test_comparison_bad_controllers(patch, field):
    text = COMPARISON.replace("  - {type: FollowTheLeader, lookahead: 0.3}", patch)
    with pytest.raises(StudyError, match=field):
        parse_study(text)


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        ("  - {type: slalom}", "  - {type: slalom, a: 2.0}", "a"),
        ("[[0, 0], [3, 0], [3, 3]]", "[[0, 0]]", "at least 2"),
        ("[[0, 0], [3, 0], [3, 3]]", "[[0, 0], [.nan, 1]]", "finite"),
        ("desired_lengths: [0.6, 1.0]", "desired_lengths: [0.2]", "half the robot length"),
    ],
)
def test_comparison_bad_paths(old, new, match):
    with pytest.raises((StudyError, ValueError), match=match):
        run_study(parse_study(COMPARISON.replace(old, new)))


TUNING = """\
designlab: 1
kind: tether_tuning
name: tun
laws: [FollowTheLeaderConstDistance]
paths: [{type: figure_eight, a: 2.0}]
speeds: [0.5]
validation_paths: [{type: slalom}]
popsize: 2
maxiter: 1
"""


def test_tuning_runs_and_reports(tmp_path):
    result = run_study(parse_study(TUNING))
    check_result(result)
    (r,) = result.results
    assert r.cost <= r.default_cost + 1e-12
    out = write_report(result, tmp_path)
    names = {p.name for p in out.iterdir()}
    assert {
        "summary.md",
        "gains.csv",
        "scenarios.csv",
        "tuning_followtheleaderconstdistance.png",
    } <= names
    gains = pd.read_csv(out / "gains.csv")
    assert set(gains["gain"]) == {"speed_gain", "angle_gain", "turn_gain"}


def test_tuning_schema_errors():
    with pytest.raises(StudyError, match="validation paths must differ"):
        parse_study(
            TUNING.replace(
                "validation_paths: [{type: slalom}]",
                "validation_paths: [{type: figure_eight, a: 2.0}]",
            )
        )
    with pytest.raises(StudyError, match="tether_range"):
        parse_study(TUNING + "tether_range: [1.0, 0.5]\n")
    with pytest.raises(StudyError, match="laws"):
        parse_study(TUNING.replace("[FollowTheLeaderConstDistance]", "[Joystick]"))


SWEEP = """\
designlab: 1
kind: tether_sweep
name: sw
base: {controller: {type: FollowTheLeader}, path: {type: slalom}, speed: 0.5}
sweep:
  method: grid
  parameters:
    controller.lookahead: {values: [0.1, 0.28, 0.5]}
    speed: {values: [0.4, 0.8]}
"""


def test_follower_sweep_grid_matches_single_runs():
    import math

    from designlab.following import FollowTheLeader, simulate, slalom
    from designlab.following.tether.linear import damping_ratio

    frame = run_study(parse_study(SWEEP)).to_frame()
    assert len(frame) == 6 and (frame["status"] == "ok").all()
    for _, row in frame.iterrows():
        delta, v = row["delta_m"], row["v_m_per_s"]
        zeta = damping_ratio(FollowTheLeader(lookahead=delta), v)
        assert row["damping_ratio"] == pytest.approx(zeta)
        assert row["damping_ratio"] == pytest.approx(0.5 * math.sqrt(3.0 * delta / v))
    run = simulate(FollowTheLeader(lookahead=0.28), slalom(), speed=0.8)
    one = frame[(frame["delta_m"] == 0.28) & (frame["v_m_per_s"] == 0.8)].iloc[0]
    assert one["tether_max_m"] == pytest.approx(run.tether_length.max(), abs=1e-9)


def test_follower_sweep_rejects_parameters_of_other_laws():
    text = SWEEP.replace("{type: FollowTheLeader}", "{type: PseudoJoystick}")
    with pytest.raises(StudyError, match=r"PseudoJoystick has no controller\.lookahead"):
        parse_study(text)
