"""Validation of the accompanying robot: physics and Wu et al. 2021, Tables 1-2 (issue item 7)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl

fol = dl.following


@pytest.fixture(scope="module")
def default_runs():
    return {n: fol.accompany(fol.walking_task(n)) for n in fol.TASK_NAMES}


@pytest.mark.parametrize("kp", [1.5, 3.0])
def test_p_only_cruise_error_is_v_over_kp(kp):
    """A type-1 loop following a ramp: the cruise error tends to v / K_p (within 2 %)."""
    v = 0.3
    task = fol.walking_task("forward", speed=v, distance=3.0, target_heading=0.0)
    res = fol.accompany(task, fol.UserFramePID(kp=kp, ki=0.0, kd=0.0))
    # last sample of the cruise (before the ramp down)
    t_end_cruise = task.walk_stop - task.parameters["ramp_time_s"]
    k = int(np.searchsorted(res.time, t_end_cruise)) - 1
    err = res.position_error[:, k]
    assert math.hypot(*err) == pytest.approx(v / kp, rel=0.02)
    assert err[1] > 0  # the robot (in front) lags behind its target


def test_p_only_cruise_error_with_a_rotated_robot():
    """The robot-frame rotation of eq. (8) does not change the isotropic steady state."""
    v, kp = 0.3, 2.0
    task = fol.walking_task(
        "left_lateral", speed=v, distance=3.0, target_heading=math.radians(-30.0)
    )
    res = fol.accompany(task, fol.UserFramePID(kp=kp, ki=0.0, kd=0.0))
    k = int(np.searchsorted(res.time, task.walk_stop - task.parameters["ramp_time_s"])) - 1
    ex, ey = res.position_error[:, k]
    assert math.hypot(ex, ey) == pytest.approx(v / kp, rel=0.02)
    assert ex < 0 and abs(ey) < 0.01 * v / kp  # lags to the user's right


def test_every_task_settles_within_20_mm_in_10_s(default_runs):
    for name, res in default_runs.items():
        assert res.ok, name
        assert res.settled_error < 0.020, name
        assert res.metrics.target_x == pytest.approx(res.task.target_position[0], abs=1e-9)


# the component of the walking-average offset (mean - target) that the task drives
_SIGN_CHECKS = {
    "forward": ["y"],
    "backward": ["y"],
    "right_lateral": ["x"],
    "left_pivot": ["x"],
    "right_pivot": ["x"],
    "circle_cw": ["x", "y"],
    "circle_ccw": ["x", "y"],
}


@pytest.mark.parametrize("name", sorted(_SIGN_CHECKS))
def test_walking_offset_sign_matches_table2(default_runs, name):
    row = fol.paper_table2().set_index("test").loc[fol.accompanying.PAPER_TEST_NAMES[name]]
    m = default_runs[name].metrics
    for axis in _SIGN_CHECKS[name]:
        paper = row[f"avg_{axis.upper()}_C_mm"] - row[f"target_{axis.upper()}_C_mm"]
        sim = getattr(m, f"mean_{axis}") - getattr(m, f"target_{axis}")
        assert np.sign(sim) == np.sign(paper), (name, axis, sim, paper)


def test_left_lateral_is_the_papers_anomaly(default_runs):
    """Lagging a user who walks left puts the robot to the user's right (+X).

    Table 2 shows the opposite (mean X_C 259 mm < target 292 mm); the paper
    (Sec. 6) explains this test separately: at reset the distance sensor saw
    the user's forearm, so the target distance was shorter than the real one.
    The model reproduces the physics, not the anomaly.
    """
    m = default_runs["left_lateral"].metrics
    row = fol.paper_table2().set_index("test").loc["Left lateral walking"]
    assert m.mean_x - m.target_x > 0
    assert row["avg_X_C_mm"] - row["target_X_C_mm"] < 0


def test_table2_targets_and_bearings():
    """Table 2's gamma_C is the bearing -atan2(X_C, Y_C) of the robot from the user (to 0.6 deg)."""
    t2 = fol.paper_table2()
    for _, row in t2.iterrows():
        for col in ("target", "stop"):
            bearing = -math.degrees(math.atan2(row[f"{col}_X_C_mm"], row[f"{col}_Y_C_mm"]))
            assert bearing == pytest.approx(row[f"{col}_gamma_C_deg"], abs=0.6), row["test"]
    res = fol.accompany(fol.walking_task("backward"))
    assert res.metrics.target_bearing_deg == pytest.approx(-13.2, abs=0.6)


def test_table1_start_is_table2_target():
    """Table 1 starts, in the user's start frame, give the Table 2 targets (source check)."""
    t1 = fol.paper_table1()
    t2 = fol.paper_table2().set_index("test")
    for test in t1["test"].unique():
        rows = t1[t1["test"] == test].set_index("subject")
        g = math.radians(rows.loc["user", "start_gamma_deg"])
        dx = rows.loc["robot", "start_X_mm"] - rows.loc["user", "start_X_mm"]
        dy = rows.loc["robot", "start_Y_mm"] - rows.loc["user", "start_Y_mm"]
        if test == "Forward walking":
            dy -= 10.0  # printed 438; the displacement and Table 2 imply 428
        x_c = math.sin(g) * dx - math.cos(g) * dy
        y_c = math.cos(g) * dx + math.sin(g) * dy
        assert x_c == pytest.approx(t2.loc[test, "target_X_C_mm"], abs=12.0), test
        assert y_c == pytest.approx(t2.loc[test, "target_Y_C_mm"], abs=12.0), test


def test_table1_displacements_follow_the_user(default_runs):
    """After settling, the robot's displacement is the user's plus the rotated target (geometry)."""
    for name, res in default_runs.items():
        m = res.metrics
        tx, ty = res.task.target_position
        u0, u1 = np.array(m.user_start), np.array(m.user_stop)
        p0, p1 = math.radians(u0[2]), math.radians(u1[2])

        def world(pu, psi, tx=tx, ty=ty):
            return pu + np.array(
                [math.sin(psi) * tx + math.cos(psi) * ty, -math.cos(psi) * tx + math.sin(psi) * ty]
            )

        expected = world(u1[:2], p1) - world(u0[:2], p0)
        got = np.array(m.robot_stop[:2]) - np.array(m.robot_start[:2])
        assert got == pytest.approx(expected, abs=0.02), name
        assert m.robot_stop[2] - m.robot_start[2] == pytest.approx(u1[2] - u0[2], abs=1.0), name


def test_lag_and_overshoot_of_the_default_pid(default_runs):
    """The paper's observations (Sec. 4.1): lag while walking, overshoot at the end."""
    fwd = default_runs["forward"].metrics
    assert 0.1 < fwd.lag < 1.0
    assert fwd.overshoot > 0.01
    assert fwd.mean_y < fwd.target_y  # distance shrinks while the user walks towards the robot
    assert default_runs["backward"].metrics.mean_y > fwd.target_y


@pytest.mark.slow
def test_tuned_pid_lowers_the_mean_rms_error_over_the_nine_tasks(default_runs):
    """Issue item 7: tuned on three tasks, better on all nine, with Ms <= 1.6."""
    pid = fol.tune_pid(
        tasks=[fol.walking_task(n) for n in ("forward", "left_lateral", "circle_cw")]
    )
    assert pid.status == "ok", pid.warnings
    assert pid.margins["Ms"].max() <= 1.6 * 1.002
    tuned = [fol.accompany(fol.walking_task(n), pid.controller) for n in fol.TASK_NAMES]
    mean_tuned = np.mean([r.rms_error for r in tuned])
    mean_default = np.mean([r.rms_error for r in default_runs.values()])
    assert mean_tuned < 0.5 * mean_default
    assert all(r.settled_error < 0.02 for r in tuned)


@settings(max_examples=6, deadline=None)
@given(
    st.floats(-math.pi, math.pi),
    st.floats(-5.0, 5.0),
    st.floats(-5.0, 5.0),
    st.sampled_from(["forward", "right_pivot", "circle_ccw"]),
)
def test_world_pose_does_not_matter(psi0, dx, dy, name):
    """The user-frame loop is invariant to where the user starts and which way they face."""
    ref = fol.accompany(fol.walking_task(name))
    task = fol.walking_task(name, start_heading=math.pi / 2 + psi0)
    moved = fol.WalkingTask(
        name, task.time, task.x + dx, task.y + dy, task.heading, task.walk_start,
        task.walk_stop, task.target_position, task.target_heading,
    )  # fmt: skip
    res = fol.accompany(moved)
    assert np.allclose(res.robot_in_user, ref.robot_in_user, atol=1e-7)
    assert res.rms_error == pytest.approx(ref.rms_error, abs=1e-8)


def test_mirror_symmetry_of_the_pivots():
    """Left and right pivots with a target straight ahead are mirror images (X -> -X)."""
    kw = {"target_position": (0.0, 0.5), "target_heading": 0.0}
    left = fol.accompany(fol.walking_task("left_pivot", **kw))
    right = fol.accompany(fol.walking_task("right_pivot", **kw))
    assert np.allclose(left.robot_in_user[0], -right.robot_in_user[0], atol=1e-9)
    assert np.allclose(left.robot_in_user[1], right.robot_in_user[1], atol=1e-9)
    assert left.metrics.mean_x > 0 > right.metrics.mean_x
