"""Validation of the crowd simulator (issue 23, item 7): one pedestrian on a straight line
reproduces Configuration 2, and the lock-step has no one-step lag."""

from __future__ import annotations

import numpy as np
import pytest

import designlab as dl

nav = dl.navigation
GAINS = nav.VFFGains(4.3, 0.68, 20.3, 240.7)


def _config2_crowd(**kw):
    """Configuration 2 (Sec. 6.4.2) as a crowd: one JuPedSim pedestrian walking from
    (0.6, 0.6) to (4.0, 0.6) at 1 m/s and stopping there, the human's regions, the plaza's
    walls far from the robot (farther than their active distance)."""
    return nav.crowd(
        "open_plaza", 1, width=12.0, length=15.0, origin=(-5.0, -5.0),
        start=(3.9, 0.6), goal=(0.0, 0.6), paths=(((0.6, 0.6), (4.0, 0.6)),),
        desired_speed=1.0, desired_speed_sd=0.0, max_desired_speed=1.0,
        pedestrian_radius=0.4, critical_radius=0.8, active_radius=2.1, horizon=30.0, **kw,
    )  # fmt: skip


@pytest.mark.parametrize("stabilising", ["lyapunov", "off"])
def test_one_pedestrian_reproduces_configuration_2(stabilising):
    # the collision-free speed model walks at its desired speed from the first step, so the
    # reference is Configuration 2's walk without its speed ramps (human_ramp_time = 0)
    ref = nav.simulate(nav.configuration(2, human_ramp_time=0.0), GAINS, stabilising=stabilising)
    res = nav.simulate(_config2_crowd(), GAINS, stabilising=stabilising)
    assert res.status == "ok" and ref.arrived
    assert abs(res.arrival_time - ref.arrival_time) <= 1e-9
    assert abs(res.min_distance - ref.min_distance["human"]) <= 1e-9
    assert res.entered_critical == ref.entered_critical and res.collided == ref.collided
    step = round(0.01 / 0.001)  # records at every pedestrian step, the reference at every 1 ms
    n = res.times.size
    ref_pos = ref.position[::step]
    m = min(n, ref_pos.shape[0])
    assert m >= int(ref.arrival_time / 0.01)  # the whole run
    np.testing.assert_allclose(res.robot_positions[:m], ref_pos[:m], rtol=0, atol=1e-9)
    np.testing.assert_allclose(res.times[:m], ref.t[::step][:m], rtol=0, atol=1e-12)
    # the pedestrian walked the thesis's walk (to rounding)
    walk = ref.obstacle_positions[0][::step][:m]
    np.testing.assert_allclose(res.pedestrian_positions[:m, 0], walk, rtol=0, atol=1e-9)


def _small(order: str, react: bool, model: str = "collision_free_speed"):
    c = nav.crowd("corridor_counterflow", 12, length=12.0, seed=4, horizon=2.4, model=model,
                  react_to_robot=react)  # fmt: skip
    return nav.crowds.simulate_crowd(c, GAINS, order=order)


def test_lock_step_has_no_one_step_lag():
    # the robot reads the pedestrians at t_k in both orders: swapping them changes nothing
    a, b = _small("robot_first", False), _small("pedestrians_first", False)
    np.testing.assert_array_equal(a.robot_positions, b.robot_positions)
    np.testing.assert_array_equal(a.pedestrian_positions, b.pedestrian_positions)
    assert a.min_distance == b.min_distance and a.arrival_time == b.arrival_time


def test_pedestrians_that_ignore_the_robot_are_the_pedestrians_alone():
    res = _small("robot_first", False)
    alone = nav.simulate_pedestrians(res.crowd)
    n = res.pedestrian_positions.shape[1]
    np.testing.assert_array_equal(
        alone.pedestrian_positions[: res.times.size, :n], res.pedestrian_positions
    )
    np.testing.assert_array_equal(alone.times[: res.times.size], res.times)


def test_lag_would_show_the_sensed_state_is_the_current_one():
    # the robot's field sees the pedestrians at t_k: a pedestrian dropped at the robot's side
    # at t = 0 changes the very first period (a lagged field would not see it before t_1)
    c = nav.crowd("open_plaza", 1, width=10.0, length=10.0, start=(3.0, 5.0), goal=(8.0, 5.0),
                  paths=(((4.5, 5.3), (4.5, 9.0)),), horizon=0.06)  # fmt: skip
    alone = c.replace(paths=(((4.5, 9.0), (4.6, 9.0)),))
    near, far = nav.simulate(c, GAINS), nav.simulate(alone, GAINS)
    assert not np.array_equal(near.robot_positions[1:], far.robot_positions[1:])


@pytest.mark.parametrize(
    "model",
    [
        "collision_free_speed",
        "social_force",
        "generalized_centrifugal_force",
        "anticipation_velocity",
    ],
)
def test_pedestrians_avoiding_the_robot_see_it_where_it_is(model):
    res = _small("robot_first", True, model)
    assert res.status in ("ok", "not_arrived")
    assert res.robot_agent_offset < 0.05  # JuPedSim's agent follows the robot
    ignore = _small("robot_first", False, model)
    assert (
        not np.array_equal(
            np.nan_to_num(res.pedestrian_positions[-1]),
            np.nan_to_num(ignore.pedestrian_positions[-1]),
        )
        or res.pedestrian_positions.shape != ignore.pedestrian_positions.shape
    )


def test_intersecting_critical_regions_are_counted():
    pair = (((4.0, 4.6), (4.0, 4.6)), ((4.0, 5.6), (4.0, 5.6)))  # standing 1 m apart
    c = nav.crowd("open_plaza", 2, width=10.0, length=10.0, start=(2.5, 5.1), goal=(8.0, 5.1),
                  paths=pair, horizon=0.3)  # fmt: skip
    assert 1.0 < 2 * c.pedestrian_regions()[1]
    res = nav.simulate(c, GAINS)
    assert res.critical_overlaps == 5  # every period: both are within r2 of the robot
    apart = c.replace(paths=(pair[0], ((4.0, 8.6), (4.0, 8.6))))
    assert nav.simulate(apart, GAINS).critical_overlaps == 0


def test_nonholonomic_robot_in_a_crowd():
    c = nav.crowd("open_plaza", 8, width=8.0, length=8.0, seed=2, horizon=0.6,
                  robot=nav.NonholonomicRobot())  # fmt: skip
    res = nav.simulate(c, GAINS)
    v = res.robot_velocities
    speed = np.hypot(v[:, 0], v[:, 1])
    assert speed.max() <= c.robot.max_speed + 1e-9 and speed[-1] > 0
    step = np.diff(res.robot_positions, axis=0)  # moves along its (mean) velocity
    mean_v = (v[1:] + v[:-1]) / 2
    vs = np.hypot(mean_v[:, 0], mean_v[:, 1])
    ds = np.hypot(step[:, 0], step[:, 1])
    moving = (ds > 1e-4) & (vs > 1e-3)
    cos = (step * mean_v).sum(axis=1)[moving] / (ds[moving] * vs[moving])
    assert moving.sum() > 20 and cos.min() > 0.99
