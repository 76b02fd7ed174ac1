"""Validation of the tether follower against analysis and Allan 2015 (Sec. 2.4-2.5, 3.3-3.5)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import designlab as dl

fol = dl.following
DATA = Path(dl.__file__).parent / "data"  # the package copy of the source tables


@pytest.mark.parametrize(
    ("ctrl", "gain"),
    [
        (fol.PseudoJoystick(), 5.0),
        (fol.PseudoJoystick(law="printed", speed_gain=3.0), 3.0),
        (fol.FollowTheLeader(), 1.0),
        (fol.FollowTheLeader(speed_gain=2.5, desired_length=0.6), 2.5),
        (fol.FollowTheLeaderConstDistance(), 2.0),
    ],
)
@pytest.mark.parametrize("speed", [0.4, 0.8])
def test_straight_line_steady_tether_length(ctrl, gain, speed):
    """l = l_d + v/K on a straight line (velocity loop l' = v - K (l - l_d)) to 1e-6 m."""
    duration = 25.0
    run = fol.simulate(
        ctrl, fol.straight_line(speed * duration + 5.0), speed=speed, duration=duration
    )
    expected = ctrl.desired_length + speed / gain
    assert run.tether_length[-1] == pytest.approx(expected, abs=1e-6)
    assert abs(run.robot_xy[-1, 1]) < 1e-9 and run.speed[-1] == pytest.approx(speed, abs=1e-6)


def test_pseudo_joystick_on_a_circle_settles_inside():
    """Tractrix limit: leader on radius R, tether l: PJ settles just outside sqrt(R^2 - l^2)."""
    big_r = 2.0
    run = fol.simulate(
        fol.PseudoJoystick(), fol.circle(big_r, turns=3.0), speed=0.5, settle_time=0.0
    )
    last = slice(-1500, None)  # the last 3/4 turn, long settled
    radius = np.hypot(*run.robot_xy[last].T)
    ell = np.mean(run.tether_length[last])
    assert np.ptp(radius) < 2e-3  # a constant radius
    # the robot's speed is v R_robot / R on the inner circle, so l = l_d + (v R_robot / R) / k_V
    assert ell == pytest.approx(1.0 + 0.5 * radius.mean() / big_r / 5.0, abs=1e-4)
    tractrix = math.sqrt(big_r**2 - ell**2)
    assert tractrix < radius.mean() < 1.03 * tractrix


PATHS = {
    "figure_eight_a4": fol.figure_eight(a=4.0),
    "figure_eight_a2": fol.figure_eight(a=2.0),
    "square_s": fol.square_s(),
    "slalom": fol.slalom(),
}


def _npd(ctrl, path):
    run = fol.simulate(ctrl, path, speed=0.5)
    return fol.normal_path_deviation(run.leader_xy, run.robot_xy).mean


@pytest.mark.slow
@pytest.mark.parametrize(
    ("path", "lengths"),
    [
        (
            "figure_eight_a4",
            (0.5, 0.6, 1.0, 2.0),
        ),  # Sec. 2.5's 4 m loops; 0.5 and 2.0 m are its l_d
        # On the 2 m loops a 2 m tether is longer than FTL's 3 m buffer can bridge (300 x 0.01 m
        # along a curved path): FTL/FTL-CD lose the path too (NPD ratio 1.4), see docs/following.md.
        ("figure_eight_a2", (0.5, 0.6, 1.0)),
        ("square_s", (0.6, 1.0, 2.0)),
        ("slalom", (0.6, 1.0, 2.0)),
    ],
)
def test_ranking_ftl_beats_pseudo_joystick(path, lengths):
    """Tables 3.2/3.3 ranking (FTL-CD more accurate than PJ); simulated factor >= 2."""
    p = PATHS[path]
    for ld in lengths:
        pj = _npd(fol.PseudoJoystick(desired_length=ld), p)
        ftl = _npd(fol.FollowTheLeader(desired_length=ld), p)
        cd = _npd(fol.FollowTheLeaderConstDistance(desired_length=ld), p)
        assert 2.0 * ftl < pj, (path, ld, pj, ftl)
        assert 2.0 * cd < pj, (path, ld, pj, cd)


@pytest.mark.slow
def test_deviation_grows_with_tether_length_for_pj_not_ftl():
    """Sec. 2.5.2-2.5.3: PJ deviation increases with l_d; FTL is unaffected."""
    p = PATHS["figure_eight_a4"]
    lengths = (0.5, 1.0, 2.0)
    pj = [_npd(fol.PseudoJoystick(desired_length=ld), p) for ld in lengths]
    ftl = [_npd(fol.FollowTheLeader(desired_length=ld), p) for ld in lengths]
    assert pj[0] < pj[1] < pj[2]
    assert pj[2] > 5 * pj[0]
    assert max(ftl) - min(ftl) < 0.01  # within 1 cm of each other
    assert max(ftl) < 0.5 * pj[0]


def test_small_lookahead_weaves():
    """Sec. 2.5.4: delta = 0.1 m (0.2 normalised) weaves; 0.5 m does not."""
    from designlab.following.tether.linear import lateral_step_response

    _, e_small = lateral_step_response(fol.FollowTheLeader(lookahead=0.1), offset=0.05)
    _, e_large = lateral_step_response(fol.FollowTheLeader(lookahead=0.5), offset=0.05)
    overshoot_small = -np.min(e_small) / 0.05
    overshoot_large = -np.min(e_large) / 0.05
    # linear overshoot exp(-pi zeta / sqrt(1 - zeta^2)) of the free response: 0.27 at zeta 0.387
    assert overshoot_small > 0.15
    assert overshoot_large < 0.02
    crossings = np.sum(np.diff(np.sign(e_small[np.abs(e_small) > 1e-4])) != 0)
    assert crossings >= 2


@pytest.mark.parametrize(
    "table", ["following_mocap_table3_2.csv", "following_patients_table3_3.csv"]
)
def test_source_tables_average_rows(table):
    """Tables 3.2/3.3: the 'Average' row is the arithmetic mean of the subjects (also for std)."""
    df = pd.read_csv(DATA / table)
    subjects = df[df["subject"] != "Average"].astype(float)
    avg = df[df["subject"] == "Average"].iloc[0]
    for col in subjects.columns[1:]:
        assert subjects[col].mean() == pytest.approx(float(avg[col]), abs=6e-4)
    # the measured ranking: FTL-CD below PJ on average by a factor 1.27-1.53
    ratio = float(avg["pj_mean_dev_over_b"]) / float(avg["ftlcd_mean_dev_over_b"])
    assert 1.25 < ratio < 1.55


def test_simulated_slalom_ranking_direction_matches_tables():
    """The simulation ranks the laws as the people did (FTL-CD < PJ), with a larger factor.

    Measured factors are 1.53 (Table 3.2) and 1.27 (Table 3.3). The simulation has no tether-tip
    offset from the walker, no wheel slip and a perfectly repeatable leader (Sec. 3.4's error
    sources), so the simulated factor is an upper bound; see the follower_comparison report.
    """
    p = fol.slalom(out_and_back=True)
    pj = _npd(fol.PseudoJoystick(desired_length=0.6), p)
    cd = _npd(fol.FollowTheLeaderConstDistance(desired_length=0.6), p)
    assert pj / cd > 1.53
