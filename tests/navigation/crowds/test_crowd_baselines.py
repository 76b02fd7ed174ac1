"""Issue 35, item 5: the field's baselines (ORCA through RVO2, a social-force robot) run
through ``nav.simulate(crowd, method=...)``; a method a crowd cannot run is a clear error."""

from __future__ import annotations

import math

import numpy as np
import pytest

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.navigation.crowds import field_metrics as fm
from designlab.navigation.crowds.simulate import _track
from designlab.navigation.methods.orca import ORCASettings
from designlab.navigation.methods.social_force import SocialForceSettings, repulsion

nav = dl.navigation


def _empty():
    return nav.crowd("corridor_counterflow", 1, width=3.0, length=9.0, seed=0,
                     paths=(((8.0, 0.5), (8.0, 0.5)),), start=(1.5, 1.5), goal=(7.5, 1.5),
                     horizon=15.0)  # fmt: skip


@pytest.mark.parametrize("method", ["orca", "social_force"])
def test_a_free_corridor_is_driven_straight_at_the_limits(method):
    c = _empty()
    res = nav.simulate(c, method=method)
    assert res.outcome == "arrived" and res.method == method and res.gains == {}
    # nearly straight (a 6 m task; ORCA may swerve round the standing pedestrian)
    assert res.robot_positions[-1, 0] > 7.3
    assert np.hypot(*np.diff(res.robot_positions, axis=0).T).sum() < 1.2 * 6.0
    # never faster than V_mr, never accelerating beyond a_mr (differences of the records)
    speed = np.hypot(*res.robot_velocities.T)
    assert speed.max() <= c.robot.max_speed + 1e-12
    acc = np.hypot(*np.diff(res.robot_velocities, axis=0).T) / np.diff(res.times)
    assert acc.max() <= c.robot.max_accel * (1 + 1e-9)


def test_orca_freezes_before_a_person_standing_on_its_path():
    # ORCA's symmetric deadlock: a person standing on the straight path, the goal behind:
    # the robot stops short of the person (never touching: the safety space holds) and
    # never turns, exactly (every input is symmetric about y = 1.5)
    c = nav.crowd("corridor_counterflow", 1, width=3.0, length=9.0, seed=0,
                  paths=(((4.5, 1.5), (4.5, 1.5)),), start=(1.5, 1.5), goal=(7.5, 1.5),
                  horizon=12.0, react_to_robot=True)  # fmt: skip
    res = nav.simulate(c, method="orca")
    assert res.outcome == "timeout" and res.min_surface_distance > 0
    assert np.all(res.robot_positions[:, 1] == 1.5)
    assert np.hypot(*res.robot_velocities[-1]) < fm.FREEZE_SPEED  # creeping to a stop


def test_track_reaches_the_command_at_the_acceleration_limit():
    robot = nav.HolonomicRobot(max_speed=0.7, max_accel=1.0)
    X, power = _track(np.zeros(4), np.array([0.5, 0.0]), robot, 60, 1e-3)
    # 0.5 m/s at 1 m/s^2: 1 mm/s per step, 60 steps: v = 0.06, x = sum 0.001 k dt
    assert X[2, -1] == pytest.approx(0.06, abs=1e-15) and X[3].max() == 0.0
    assert X[0, -1] == pytest.approx(1e-3 * 1e-3 * 60 * 61 / 2, abs=1e-15)
    assert power.shape == (60,) and np.all(power > 0)
    X, _ = _track(np.zeros(4), np.array([3.0, 4.0]), robot, 1000, 1e-3)  # capped at V_mr
    assert math.hypot(X[2, -1], X[3, -1]) == pytest.approx(0.7, abs=1e-12)


def test_social_force_repulsion_is_the_exponential_law():
    f = repulsion(np.zeros(2), np.array([[0.0, 0.6], [0.0, -0.6]]), 0.4, 25.0, 0.08)
    assert np.abs(f).max() < 1e-12  # symmetric: cancels
    f = repulsion(np.zeros(2), np.array([[0.6, 0.0]]), 0.4, 25.0, 0.08)
    assert f[0] == pytest.approx(-25.0 * math.exp(-0.2 / 0.08), rel=1e-14) and f[1] == 0.0


def test_methods_a_crowd_cannot_run_are_clear_errors():
    c = _empty()
    for bad in ("vff_cbf", "vo", "bug"):
        with pytest.raises(InvalidParameterError, match="method"):
            nav.simulate(c, method=bad)
    with pytest.raises(InvalidParameterError, match="SocialForceSettings"):
        nav.simulate(c, ORCASettings(), method="social_force")
    nh = c.replace(robot=nav.NonholonomicRobot())
    with pytest.raises(InvalidParameterError, match="HolonomicRobot"):
        nav.simulate(nh, method="orca")
    assert nav.simulate(c, SocialForceSettings(reaction_time=0.3), method="social_force").arrived
