"""Closed-loop tether-follower simulation: engine behaviour, batches, buffers, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.results import check_result

fol = dl.following


def test_issue_example_api():
    sim = fol.simulate(
        fol.FollowTheLeaderConstDistance(desired_length=1.0), fol.figure_eight(a=4.0), speed=0.5
    )
    check_result(sim)
    n = len(sim.t)
    assert (
        sim.leader_xy.shape == (n, 2)
        and sim.robot_xy.shape == (n, 2)
        and sim.tether_length.shape == (n,)
    )
    # F4: the robot starts l_d behind the start point on the initial tangent (+y), at rest
    assert sim.robot_xy[0] == pytest.approx([4.0, -1.0])
    assert sim.tether_length[0] == pytest.approx(1.0)
    # the leader walks 20.98 m at 0.5 m/s, then stands for the settle time
    assert sim.t[-1] == pytest.approx(fol.figure_eight(a=4.0).length / 0.5 + 5.0, abs=0.011)
    # the tether stays taut and the robot stays behind: l in a sane band
    assert 0.9 < sim.tether_length.min() and sim.tether_length.max() < 1.6
    frame = sim.to_frame()
    assert {"t_s", "robot_x_m", "tether_length_m"} <= set(frame.columns)


@pytest.mark.parametrize(
    "ctrl",
    [fol.PseudoJoystick(), fol.FollowTheLeader(lookahead=0.3), fol.FollowTheLeaderConstDistance()],
)
def test_batch_members_equal_single_runs(ctrl):
    path = fol.square_s()
    other = ctrl.replace(desired_length=0.8)
    batch = fol.simulate_batch([ctrl, other], path, speed=0.5)
    check_result(batch)
    for i, c in enumerate((ctrl, other)):
        single = fol.simulate(c, path, speed=0.5)
        assert np.max(np.abs(batch.robot_xy[i] - single.robot_xy)) < 1e-9
        assert np.max(np.abs(batch.tether_length[i] - single.tether_length)) < 1e-9


def test_per_member_buffers_match_the_shared_buffer():
    """A tiny tip height forces per-member buffers of estimated tips; they must agree."""
    ctrl = [fol.FollowTheLeader(), fol.FollowTheLeaderConstDistance()]
    for c in ctrl:
        shared = fol.simulate(c, fol.slalom(), speed=0.5)
        own = fol.simulate_batch(
            [c, c], fol.slalom(), speed=0.5, robot=fol.FollowerRobot(tip_height=1e-7)
        )
        # the leader moves exactly ds_min every 2 steps, so the ds >= ds_min test sits on a tie
        # that rounding flips: buffers may differ by one 5 mm step, the paths by a few mm
        assert np.max(np.abs(own.robot_xy[1] - shared.robot_xy)) < 5e-3


def test_noise_is_seeded():
    robot = fol.FollowerRobot(length_noise_std=0.01, angle_noise_std=0.02)
    a = fol.simulate(fol.FollowTheLeader(), fol.slalom(), robot=robot, seed=3)
    b = fol.simulate(fol.FollowTheLeader(), fol.slalom(), robot=robot, seed=3)
    c = fol.simulate(fol.FollowTheLeader(), fol.slalom(), robot=robot, seed=4)
    assert np.array_equal(a.robot_xy, b.robot_xy)
    assert not np.array_equal(a.robot_xy, c.robot_xy)
    clean = fol.simulate(fol.FollowTheLeader(), fol.slalom())
    assert np.std(a.tether_length - clean.tether_length) > 0.005


def test_wheel_speed_and_acceleration_limits():
    robot = fol.FollowerRobot(max_wheel_speed=4.0, max_wheel_acceleration=20.0)
    run = fol.simulate(
        fol.PseudoJoystick(), fol.straight_line(20.0), speed=0.8, robot=robot, duration=20.0
    )
    wl = (run.speed - 0.5 * robot.wheel_track * run.turn_rate) / robot.wheel_radius
    wr = (run.speed + 0.5 * robot.wheel_track * run.turn_rate) / robot.wheel_radius
    assert np.max(np.abs(wl)) <= 4.0 + 1e-12 and np.max(np.abs(wr)) <= 4.0 + 1e-12
    assert np.max(np.abs(np.diff(wl))) <= 20.0 * 0.01 + 1e-12
    # 4 rad/s is 0.5 m/s < 0.8 m/s: the robot falls behind, the tether keeps growing
    assert run.tether_length[-1] > run.tether_length[len(run.t) // 2] > 2.0
    assert any("speed limit" in w for w in run.warnings)


def test_saturated_robot_keeps_turning_toward_its_leader():
    """Regression: stiff FTL gains at the OxyDog wheel limit on the out-and-back slalom.

    With each wheel clipped alone, a large speed demand saturated both wheels equally, the
    turn was lost at the turnaround and the robot drove on straight (tether 16 m). Scaling
    both wheels keeps the curvature, so the robot turns and the tether stays short.
    """
    ctrl = fol.FollowTheLeader(speed_gain=5.26, turn_gain=14.9, lookahead=0.284)
    run = fol.simulate(ctrl, fol.slalom(out_and_back=True), speed=0.5, robot=fol.OXYDOG)
    wl = (run.speed - 0.5 * fol.OXYDOG.wheel_track * run.turn_rate) / fol.OXYDOG.wheel_radius
    wr = (run.speed + 0.5 * fol.OXYDOG.wheel_track * run.turn_rate) / fol.OXYDOG.wheel_radius
    assert np.max(np.maximum(np.abs(wl), np.abs(wr))) == pytest.approx(8.0)  # it saturates
    assert run.tether_length.max() < 1.5
    assert fol.normal_path_deviation(run.leader_xy, run.robot_xy).mean < 0.3


def test_rotates_in_place_when_slack():
    """App. C PJ: V = 0 but Omega = k_O theta when l_m < l_d (Allan 2015 Sec. 4.4.2's creep)."""
    run = fol.simulate(
        fol.PseudoJoystick(),
        fol.straight_line(0.5),
        speed=0.5,
        duration=3.0,
        initial_pose=(0.0, -0.5, 0.0),  # leader 0.5 m to the left, tether slack, 90 deg off
    )
    assert np.max(np.abs(run.speed)) == 0.0  # the tether (<= 0.71 m) never exceeds l_d = 1 m
    assert np.max(np.abs(run.turn_rate)) > 10.0  # 12 * pi/2 at the start
    assert run.heading[-1] == pytest.approx(math.atan2(0.5, 0.5), abs=1e-3)  # facing the leader


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"speed": -0.5}, "speed"),
        ({"speed": float("nan")}, "speed"),
        ({"duration": 0.0}, "duration"),
        ({"settle_time": -1.0}, "settle_time"),
        ({"lead_in": float("inf")}, "lead_in"),
        ({"initial_pose": (0.0, float("nan"), 0.0)}, "initial_pose"),
        ({"robot": "oxydog"}, "robot"),
    ],
)
def test_bad_simulation_input(kwargs, name):
    args = {"speed": 0.5, **kwargs}
    with pytest.raises(InvalidParameterError, match=name):
        fol.simulate(fol.FollowTheLeader(), fol.straight_line(2.0), **args)


def test_tether_shorter_than_the_robot():
    with pytest.raises(InvalidParameterError, match=r"desired_length.*half the robot length"):
        fol.simulate(fol.FollowTheLeader(desired_length=0.3), fol.straight_line(2.0))


def test_bad_paths_and_controllers():
    with pytest.raises(InvalidParameterError, match=r"path\.points"):
        fol.simulate(fol.FollowTheLeader(), [[0.0, 0.0]])
    with pytest.raises(InvalidParameterError, match="path"):
        fol.simulate(fol.FollowTheLeader(), {"points": [[0.0, 0.0], [float("nan"), 1.0]]})
    with pytest.raises(InvalidParameterError, match="controller"):
        fol.simulate("FTL", fol.straight_line(2.0))  # type: ignore[arg-type]
    with pytest.raises(InvalidParameterError, match="one law"):
        fol.simulate_batch([fol.FollowTheLeader(), fol.PseudoJoystick()], fol.straight_line(2.0))
    with pytest.raises(InvalidParameterError, match="min_step"):
        fol.simulate_batch(
            [fol.FollowTheLeader(), fol.FollowTheLeader(min_step=0.02)], fol.straight_line(2.0)
        )


def test_metrics_of_a_run():
    run = fol.simulate(fol.FollowTheLeader(), fol.figure_eight(a=4.0), speed=0.5)
    m = fol.follower_metrics(run)
    check_result(m)
    assert m.npd.mean == pytest.approx(fol.normal_path_deviation(run.leader_xy, run.robot_xy).mean)
    # FTL walks the leader's path: the same distance, minus the l_d it starts behind and ends behind
    assert m.path_length_ratio == pytest.approx(1.0, abs=0.02)
    assert m.tether_max == pytest.approx(1.5, abs=0.05)  # l_d + v/K_V
    assert m.stops == 0
    pj = fol.follower_metrics(
        fol.simulate(fol.PseudoJoystick(desired_length=2.0), fol.figure_eight(a=4.0))
    )
    assert pj.path_length_ratio < 0.9  # Sec. 2.5.2: PJ with a long tether drives a shorter path


def test_an_absurd_leader_speed_is_refused():
    import pytest

    from designlab.errors import InvalidParameterError
    from designlab.following import FollowTheLeader, figure_eight, simulate

    with pytest.raises(InvalidParameterError, match=r"speed = 1e\+300 m/s is not allowed"):
        simulate(FollowTheLeader(), figure_eight(a=4.0), speed=1e300)


def test_an_absurd_walking_speed_is_refused():
    import pytest

    import designlab as dl
    from designlab.errors import InvalidParameterError

    with pytest.raises(InvalidParameterError, match=r"speed = 1e\+300 m/s is not allowed"):
        dl.following.walking_task("forward", speed=1e300)
