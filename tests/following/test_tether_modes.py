"""Allan 2015 Ch. 4 side, front and Brake modes: laws, steady states and the stepwise loop."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.following import tether as T
from designlab.following.tether.stepwise import TipRecorder, limited_command

angles = st.floats(-math.pi, math.pi)
lengths = st.floats(0.01, 5.0)


@settings(max_examples=60, deadline=None)
@given(lengths, angles)
def test_side_joystick_law_is_eqs_4_1_4_2_as_coded(l_m, theta):
    c = T.SideJoystick(desired_length=0.56)
    v, om = c.command(l_m, theta)
    e = theta - math.pi / 2
    v_exp = min(-1.25 * e, 100.0) if e < 0 else 0.0
    om_exp = 0.0 if v_exp == 0 else min(1.8 * (l_m - 0.56), 100.0)
    assert v == pytest.approx(v_exp, abs=1e-12)
    assert om == pytest.approx(om_exp, abs=1e-12)


@settings(max_examples=60, deadline=None)
@given(lengths, angles)
def test_front_joystick_law_is_eqs_4_3_4_5_as_coded(l_m, theta):
    v, om = T.FrontJoystick().command(l_m, theta)
    e = math.atan2(math.sin(theta - math.pi), math.cos(theta - math.pi))
    assert v == pytest.approx(-(l_m - 1.0), abs=1e-12)
    assert om == pytest.approx(0.0 if abs(e) > math.pi / 2 else 1.5 * e, abs=1e-12)


def test_side_joystick_straight_line_steady_state():
    # V = v needs theta = theta_d - v/k_V; Omega = 0 needs l_m = l_H
    lh, v = 0.56, 0.5
    run = T.simulate(T.SideJoystick(desired_length=lh), T.straight_line(30.0), speed=v)
    k = int(55.0 / run.robot.sample_time)  # leader still walking, transient gone
    assert run.tether_length[k] == pytest.approx(lh, abs=1e-4)
    assert run.tether_angle[k] == pytest.approx(math.pi / 2 - v / 1.25, abs=1e-4)
    assert run.speed[k] == pytest.approx(v, abs=1e-4)
    # the robot starts abreast on the leader's right
    assert run.robot_xy[0].tolist() == pytest.approx([0.0, -lh])


def test_front_joystick_straight_line_steady_state():
    # V = -k_V (l - l_d) = v gives l = l_d - v/k_V, robot ahead on the path
    run = T.simulate(T.FrontJoystick(), T.straight_line(20.0), speed=0.5)
    k = int(30.0 / run.robot.sample_time)
    assert run.tether_length[k] == pytest.approx(0.5, abs=1e-6)
    assert abs(run.tether_angle[k]) == pytest.approx(math.pi, abs=1e-6)
    assert run.robot_xy[k, 1] == pytest.approx(0.0, abs=1e-9)
    assert run.robot_xy[0].tolist() == pytest.approx([1.0, 0.0])


def test_front_vel_joystick_moves_at_two_fifths_of_the_leader():
    # V = |v_tip| over dt (size + 1) for size - 1 intervals: V = (4/6)(v - V), V = 0.4 v
    run = T.simulate(T.FrontVelJoystick(), T.straight_line(20.0), speed=0.5, duration=1.5)
    assert run.speed[100] == pytest.approx(0.2, abs=1e-3)
    assert run.tether_length[100] < 1.0  # no tether length is held: the user closes in


def test_side_tracking_straight_line_tracks_the_side_point():
    # K path is y = -l_H; the robot converges on it, |K - P| -> l_d + v/k_V
    lh, v = 0.56, 0.5
    run = T.simulate(T.SideTracking(offset_length=lh), T.straight_line(20.0), speed=v)
    k = int(30.0 / run.robot.sample_time)
    assert run.robot_xy[k, 1] == pytest.approx(-lh, abs=1e-3)
    behind = run.leader_xy[k, 0] - run.robot_xy[k, 0]
    assert behind == pytest.approx(0.1 + v / 1.0, abs=2e-2)


@pytest.mark.parametrize(
    "law", [T.PseudoJoystick(), T.FollowTheLeader(), T.FollowTheLeaderConstDistance()]
)
def test_brake_that_never_engages_reproduces_the_compiled_law(law):
    # an independent loop (Python buffer, Python arc) against the compiled loop of the law
    path = T.figure_eight(a=2.0)
    ref = T.simulate(law, path, speed=0.5)
    wrapped = T.simulate(T.BrakeMode(law, engage_margin=-10.0, release_margin=-9.0), path)
    np.testing.assert_allclose(wrapped.robot_xy, ref.robot_xy, atol=1e-9)
    np.testing.assert_allclose(wrapped.tether_length, ref.tether_length, atol=1e-9)


def test_brake_mode_holds_still_while_engaged():
    brake = T.BrakeMode(T.PseudoJoystick(), engage_margin=0.02, release_margin=0.05)
    run = T.simulate(brake, T.straight_line(3.0), speed=0.5, settle_time=5.0)
    on = T.brake_timeline(run.tether_length, 1.0, 0.02, 0.05)
    # at rest l_d behind the leader it starts braked, is released, and brakes after the stop
    assert on[0] and on[-1] and not on.all()
    assert np.all(run.speed[on] == 0.0) and np.all(run.turn_rate[on] == 0.0)
    first = len(on) - int(np.argmin(on[::-1]))  # the last engagement
    held = run.robot_xy[first + 1 :]
    np.testing.assert_array_equal(held, np.broadcast_to(held[0], held.shape))


def test_brake_stops_the_creep_of_a_noisy_sensor():
    robot = T.FollowerRobot(length_noise_std=0.01, angle_noise_std=0.05)
    path = T.straight_line(2.0)
    free = T.simulate(T.PseudoJoystick(), path, robot=robot, settle_time=20.0, seed=3)
    held = T.simulate(T.BrakeMode(T.PseudoJoystick()), path, robot=robot, settle_time=20.0, seed=3)
    stop = int(4.0 / robot.sample_time) + 200  # 2 s after the leader stopped
    turn_free = np.abs(np.diff(free.heading[stop:])).sum()
    turn_held = np.abs(np.diff(held.heading[stop:])).sum()
    assert turn_held < 0.2 * turn_free


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(0.5, 1.5), min_size=1, max_size=60))
def test_brake_timeline_has_hysteresis(lengths_):
    on = T.brake_timeline(lengths_, 1.0, 0.02, 0.05)
    prev = False
    for lm, now in zip(lengths_, on, strict=True):
        if now and not prev:
            assert lm < 1.02
        if prev and not now:
            assert lm > 1.05
        if lm < 1.02:
            assert now
        prev = now


def test_tip_recorder_is_point_tracker():
    rec = TipRecorder(limit=5, min_step=0.1)
    for x in (0.0, 0.05, 0.1, 0.3, 0.35, 0.5, 0.7, 0.9):
        rec.record(x, 0.0)
    assert rec.xs == pytest.approx([0.3, 0.5, 0.7, 0.9])  # limit - 1 points kept
    assert rec.const_distance_point(0.35) == pytest.approx((0.5, 0.0))
    assert rec.lookahead_point(0.31, 0.0, 0.4) == pytest.approx((0.7, 0.0))


@settings(max_examples=50, deadline=None)
@given(st.floats(-2, 2), st.floats(-5, 5))
def test_limited_command_keeps_curvature(v, om):
    robot = T.FollowerRobot(max_wheel_speed=4.0)
    va, oa, wl, wr = limited_command(robot, v, om, (0.0, 0.0))
    assert max(abs(wl), abs(wr)) <= 4.0 + 1e-12
    assert va * om == pytest.approx(oa * v, abs=1e-9)


def test_modes_study_report(tmp_path):
    from designlab.report import write_report
    from designlab.study import parse_study, run_study

    study = parse_study(
        "designlab: 1\nkind: tether_modes\nname: m\npaths: [{type: straight_line, length: 3.0}]\n"
        "modes: [SideJoystick, SideTracking, FrontJoystick]\nside_offsets: [0.5]\n"
        "brake_laws: [PseudoJoystick]\nbrake_walk: 2.0\nbrake_wait: 5.0"
    )
    result = run_study(study)
    frame = result.to_frame()
    assert frame["mode"].tolist() == ["SideJoystick", "SideTracking", "FrontJoystick"]
    assert not frame["lost"].any()
    brakes = result.brake_frame()
    assert brakes["brake"].tolist() == [False, True]
    assert brakes["turned_after_stop_rad"][1] < brakes["turned_after_stop_rad"][0]
    out = write_report(result, tmp_path, index=False)
    text = (out / "summary.md").read_text()
    assert "spread of the side offset" in text and (out / "brake.png").exists()


@pytest.mark.parametrize(
    "body",
    [
        "modes: [Sideways]",
        "side_offsets: [0.1]",
        "side_offsets: [.nan]",
        "engage_margin: 0.1\nrelease_margin: 0.05",
        "brake_laws: [SideJoystick]",
        "brake_length_noise: -1",
        "brake_walk: 1e9",
    ],
)
def test_modes_study_refuses(body):
    from designlab.errors import StudyError
    from designlab.study import parse_study

    with pytest.raises(StudyError, match=r"<string>:\d+: "):
        parse_study(f"designlab: 1\nkind: tether_modes\nname: m\n{body}")


def test_turn_errors_split_by_the_side_of_the_turn():
    from types import SimpleNamespace

    from designlab.study.kinds.tether_modes import turn_errors

    left = T.circle(radius=2.0)  # counter-clockwise: a left turn, the robot (on the right) outside
    mid = left.points[1:-1:10]
    npd = SimpleNamespace(midpoints=mid, profile=np.full(len(mid), 0.6))
    inside, outside = turn_errors(left, npd, 0.5)
    assert math.isnan(inside) and outside == pytest.approx(0.1)
    right = T.from_array(left.points * [1.0, -1.0])  # mirrored: clockwise, the robot inside
    mirrored = SimpleNamespace(midpoints=mid * [1.0, -1.0], profile=np.full(len(mid), 0.3))
    inside, outside = turn_errors(right, mirrored, 0.5)
    assert inside == pytest.approx(0.2) and math.isnan(outside)


@settings(max_examples=50, deadline=None)
@given(st.floats(-5, 5), st.floats(-5, 5), angles, st.floats(0.1, 3.0), angles)
def test_side_pose_sees_the_point_at_the_angle(px, py, heading, offset, angle):
    from designlab.following.tether.laws.base import side_pose
    from designlab.following.tether.metrics import lateral_offset

    x, y, g = side_pose((px, py), heading, offset, angle)
    assert math.hypot(px - x, py - y) == pytest.approx(offset)
    seen = math.atan2(py - y, px - x) - g
    assert math.cos(seen - angle) == pytest.approx(1.0)
    # the robot's signed offset left of the point's heading line
    lat = lateral_offset(np.array([[x, y]]), np.array([[px, py]]), np.array([heading]))[0]
    assert lat == pytest.approx(-offset * math.sin(angle), abs=1e-9)
