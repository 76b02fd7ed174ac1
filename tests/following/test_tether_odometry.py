"""Allan 2015: odometry with wheel slip and the marker-to-tether-tip offset (Sec. 2.3, 3.4)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.errors import InvalidParameterError
from designlab.following import tether as T
from designlab.following.tether.metrics import follower_metrics
from designlab.following.tether.odometry import (
    MarkerOffset,
    WheelSlip,
    arc_step,
    ground_motion,
    marker_to_tip,
    simulate_with_errors,
)


@settings(max_examples=40, deadline=None)
@given(
    v=st.floats(-2, 2),
    om=st.floats(-5, 5),
    g=st.floats(-4, 4),
    dt=st.floats(1e-3, 0.5),
)
def test_arc_step_is_the_app_c_dead_reckon_arc(v, om, g, dt):
    """App. C dead_reckon: dx = (V/Om)(sin G1 - sin G0), dy = -(V/Om)(cos G1 - cos G0)."""
    x, y, g1 = arc_step((0.3, -0.2, g), v, om, dt)
    assert g1 == pytest.approx(g + om * dt, abs=1e-12)
    if abs(om) > 1e-3:
        dx = (v / om) * (math.sin(g + om * dt) - math.sin(g))
        dy = -(v / om) * (math.cos(g + om * dt) - math.cos(g))
    else:
        dx, dy = v * math.cos(g + 0.5 * om * dt) * dt, v * math.sin(g + 0.5 * om * dt) * dt
    assert x - 0.3 == pytest.approx(dx, abs=1e-9)
    assert y + 0.2 == pytest.approx(dy, abs=1e-9)


@settings(max_examples=40, deadline=None)
@given(
    wl=st.floats(-10, 10),
    wr=st.floats(-10, 10),
    sl=st.floats(-0.5, 0.5),
    sr=st.floats(-0.5, 0.5),
)
def test_ground_motion_is_eq_2_6_on_the_slipped_wheel_speeds(wl, wr, sl, sr):
    r, b = 0.125, 0.28
    v, om = 0.5 * r * (wl + wr), r * (wr - wl) / b  # eq. 2.6
    vg, omg = ground_motion(v, om, sl, sr, b)
    assert vg == pytest.approx(0.5 * r * (wl * (1 - sl) + wr * (1 - sr)), abs=1e-12)
    assert omg == pytest.approx(r * (wr * (1 - sr) - wl * (1 - sl)) / b, abs=1e-12)


@settings(max_examples=20, deadline=None)
@given(fwd=st.floats(-0.5, 0.5), left=st.floats(-0.5, 0.5), ang=st.floats(-3, 3))
def test_marker_to_tip_offsets_in_the_walker_frame(fwd, left, ang):
    s = np.linspace(0.0, 2.0, 21)
    marker = np.column_stack([s * math.cos(ang), s * math.sin(ang)])
    marker = np.vstack([marker, marker[-1:], marker[-1:]])  # the walker stops
    tip = marker_to_tip(marker, MarkerOffset(forward=fwd, left=left))
    want = np.array(
        [
            fwd * math.cos(ang) - left * math.sin(ang),
            fwd * math.sin(ang) + left * math.cos(ang),
        ]
    )
    np.testing.assert_allclose(tip - marker, np.tile(want, (len(marker), 1)), atol=1e-12)


@pytest.mark.parametrize("law", [T.FollowTheLeader, T.FollowTheLeaderConstDistance])
def test_without_errors_it_is_the_per_member_simulation(law):
    """No slip, no offset: the same loop as simulate's per-member buffers, bit for bit, and
    the true pose is the odometry."""
    robot = T.FollowerRobot(tip_height=1e-9)  # forces simulate's per-member buffers
    a = T.simulate(law(), "square_s", robot=robot)
    b = simulate_with_errors(law(), "square_s", robot=robot)
    np.testing.assert_array_equal(a.robot_xy, b.run.robot_xy)
    np.testing.assert_array_equal(b.odometry_xy, b.run.robot_xy)


def test_pseudo_joystick_without_errors_is_simulate():
    a = T.simulate(T.PseudoJoystick(), "square_s")
    b = simulate_with_errors(T.PseudoJoystick(), "square_s")
    np.testing.assert_allclose(a.robot_xy, b.run.robot_xy, atol=1e-9)


def test_slip_on_a_straight_line_turns_the_odometry_by_the_arc_of_the_lost_speed():
    """Pseudo-Joystick straight behind a walker: the true path stays straight (the tether
    corrects), the odometry believes the robot turned: odometry minus true heading is the
    running sum of (Omega commanded - Omega on the ground) dt, Omega on the ground by eq. 2.6
    on the slipped wheel speeds."""
    s_l = 0.05
    res = simulate_with_errors(T.PseudoJoystick(), T.straight_line(6.0), slip=WheelSlip(s_l))
    true_g = res.run.heading
    odo_g = res.odometry_heading
    # true heading ~ constant (the law steers the true robot at the tip)
    assert np.max(np.abs(true_g[200:])) < 0.02
    # odometry yaw drift = integral of the omega the robot commanded to cancel the slip
    v, om = res.run.speed, res.run.turn_rate
    _, omg = ground_motion(v, om, s_l, 0.0, res.run.robot.wheel_track)
    drift = np.cumsum((om - omg) * res.run.robot.sample_time)
    np.testing.assert_allclose(odo_g[1:] - true_g[1:], drift[:-1], atol=1e-9)
    assert res.odometry_drift[-1] > 0.1


def test_slip_moves_the_buffered_laws_more_than_pseudo_joystick():
    """PJ steers on the tether reading alone; FTL drives to points recorded in the
    odometry frame, so its deviation grows with slip, PJ's hardly."""
    slip = WheelSlip(left_slip=0.03)
    out = {}
    for law in (T.PseudoJoystick, T.FollowTheLeader):
        base = follower_metrics(simulate_with_errors(law(), "square_s").run).npd.mean
        slipped = follower_metrics(simulate_with_errors(law(), "square_s", slip=slip).run).npd
        out[law.__name__] = slipped.mean - base
    assert abs(out["PseudoJoystick"]) < 0.01
    assert out["FollowTheLeader"] > 0.02


def test_a_lateral_marker_offset_shows_in_the_deviation_of_a_tracking_law():
    """FTL tracks the tip's path closely: a 0.15 m lateral tip offset appears as about
    0.15 m of deviation from the marker's path on a straight line."""
    res = simulate_with_errors(
        T.FollowTheLeader(), T.straight_line(8.0), marker=MarkerOffset(left=0.15)
    )
    np.testing.assert_allclose(res.tip_xy[:, 1], 0.15, atol=1e-12)
    late = res.run.t > 8.0
    np.testing.assert_allclose(res.run.robot_xy[late, 1], 0.15, atol=2e-3)


@pytest.mark.parametrize(
    ("make", "name"),
    [
        (lambda: WheelSlip(left_slip=float("nan")), "left_slip"),
        (lambda: WheelSlip(right_slip=0.9), "right_slip"),
        (lambda: WheelSlip(noise_std=-0.1), "noise_std"),
        (lambda: MarkerOffset(forward=float("inf")), "forward"),
        (lambda: MarkerOffset(left="0.1"), "left"),
        (lambda: simulate_with_errors("PJ", "square_s"), "controller"),
        (lambda: simulate_with_errors(T.PseudoJoystick(), "square_s", slip=0.02), "slip"),
        (lambda: simulate_with_errors(T.PseudoJoystick(), "square_s", marker=(0, 1)), "marker"),
        (lambda: simulate_with_errors(T.PseudoJoystick(), "square_s", speed=-1), "speed"),
        (lambda: simulate_with_errors(T.PseudoJoystick(), "square_s", settle_time=1e9), "settle"),
        (
            lambda: simulate_with_errors(T.BrakeMode(mode=T.FollowTheLeader()), "square_s"),
            "controller",
        ),
    ],
)
def test_bad_input_is_refused_naming_the_parameter(make, name):
    with pytest.raises(InvalidParameterError) as exc:
        make()
    assert name in str(exc.value)
