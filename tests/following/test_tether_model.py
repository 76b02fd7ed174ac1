"""Tether follower model: kinematics, sensor, controllers (Allan 2015 Sec. 2.2-2.3, App. C)."""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.following.tether.model import (
    STEP_INPUTS,
    kinematics_function,
    kinematics_step,
    sensor_step,
    step_function,
    tip_step,
)
from designlab.sx.pycode import compile_sx

fol = dl.following
B, R = 0.28, 0.125


def test_straight_and_spin_in_place():
    step = kinematics_step()
    x, y, g, ds = step(1.0, 2.0, math.pi / 2, 4.0, 4.0, B, R, 0.5)  # V = 0.5 m/s
    assert (x, y, g) == pytest.approx((1.0, 2.25, math.pi / 2), abs=1e-12)
    assert ds == pytest.approx(0.25)
    x, y, g, ds = step(0.0, 0.0, 0.0, -2.0, 2.0, B, R, 0.1)  # Omega = r*4/b
    assert (x, y, ds) == pytest.approx((0.0, 0.0, 0.0), abs=1e-15)
    assert g == pytest.approx(R * 4.0 / B * 0.1)


@settings(max_examples=60, deadline=None)
@given(
    wl=st.floats(-10, 10),
    wr=st.floats(-10, 10),
    g0=st.floats(-math.pi, math.pi),
    dt=st.floats(1e-3, 0.5),
)
def test_exact_arc_about_the_instantaneous_centre(wl, wr, g0, dt):
    """App. C dead_reckon: the pose moves on a circle of radius V/Omega about the ICR."""
    v = 0.5 * R * (wl + wr)
    om = R * (wr - wl) / B
    x, y, g, ds = kinematics_step()(0.0, 0.0, g0, wl, wr, B, R, dt)
    assert g == pytest.approx(g0 + om * dt, abs=1e-12)
    if abs(om) > 1e-3:
        rad = v / om
        cx, cy = -rad * math.sin(g0), rad * math.cos(g0)  # ICR, independent formula
        assert math.hypot(x - cx, y - cy) == pytest.approx(abs(rad), abs=1e-9)
        # App. C: dx = (V/Omega)(sin G - sin G0), dy = -(V/Omega)(cos G - cos G0)
        assert x == pytest.approx(rad * (math.sin(g) - math.sin(g0)), abs=1e-9)
        assert y == pytest.approx(-rad * (math.cos(g) - math.cos(g0)), abs=1e-9)
    else:
        assert math.hypot(x, y) == pytest.approx(abs(v) * dt, abs=1e-6 * (1 + abs(v)))
    assert ds == pytest.approx(math.hypot(x, y), abs=1e-12)


def test_sensor_convention_and_tip_roundtrip():
    # robot at origin heading +y, leader at (-1, 1): tether 45 deg to the left
    lm, th = sensor_step()(0.0, 0.0, math.pi / 2, -1.0, 1.0, 0.0, 0.0, 0.0)
    assert lm == pytest.approx(math.sqrt(2.0))
    assert th == pytest.approx(math.pi / 4)
    # 3-D length with a tip height (A7)
    lm3, _ = sensor_step()(0.0, 0.0, 0.0, 0.6, 0.0, 0.0, 0.0, 0.8)
    assert lm3 == pytest.approx(1.0)
    # winch offset: forward 0.2 m on a robot heading +y puts the winch at (0, 0.2)
    lm, th = sensor_step()(0.0, 0.0, math.pi / 2, 0.0, 1.2, 0.2, 0.0, 0.0)
    assert (lm, th) == pytest.approx((1.0, 0.0), abs=1e-12)
    tx, ty = tip_step()(0.3, -0.2, 2.0, 1.3, -2.5, 0.1, 0.05)
    lm, th = sensor_step()(0.3, -0.2, 2.0, tx, ty, 0.1, 0.05, 0.0)
    assert (lm, th) == pytest.approx((1.3, -2.5), abs=1e-12)


def test_angle_wraps_to_minus_pi_pi():
    _, th = sensor_step()(0.0, 0.0, 3.0, -1.0, -0.5, 0.0, 0.0, 0.0)
    assert -math.pi < th <= math.pi
    assert th == pytest.approx(math.atan2(-0.5, -1.0) - 3.0 + 2 * math.pi)


def test_compiled_functions_equal_casadi():
    f = kinematics_function()
    args = (0.3, -1.0, 0.7, 3.0, 5.5, B, R, 0.01)
    ref = [float(v) for v in f(*args)]
    assert kinematics_step()(*args) == pytest.approx(ref, abs=1e-14)
    batch = kinematics_step(True)(*(np.full(3, a) for a in args))
    assert [float(v[1]) for v in batch] == pytest.approx(ref, abs=1e-14)
    law = fol.FollowTheLeaderConstDistance.law_function("")
    for flags in [(True, False, False, False), (True, True, True, True)]:
        d = step_function(law, *flags)
        inp = (
            0.0,
            0.0,
            0.2,
            1.5,
            0.3,
            1.0,
            0.5,
            0.0,
            0.0,
            0.01,
            -0.02,
            B,
            R,
            0.01,
            8.0,
            0.5,
            0.1,
            0.0,
            0.1,
        )
        inp = (*inp, 1.2, 2.0, 0.5, 2.0)
        assert len(inp) == len(STEP_INPUTS) + 4
        assert compile_sx(d)(*inp) == pytest.approx([float(v) for v in d(*inp)], abs=1e-14)
    x = ca.SX.sym("x")
    with pytest.raises(TypeError):
        compile_sx(ca.Function("v", [ca.SX.sym("v", 2)], [x * 0 + 1]))


def test_wheel_limits_in_drive():
    law = fol.PseudoJoystick.law_function("coded")
    d = compile_sx(step_function(law, False, True))
    # leader 2 m ahead: l error 1 m -> V = 5 m/s demanded; wheels limited to 8 rad/s (1 m/s),
    # and to a change of 0.05 rad/s per period
    common = (0.0, 0.0, B, R, 0.01, 8.0)
    out = d(
        0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0, *common, 0.05, 0.0, 0.0, 0.0, 1.0, 5.0, 12.0
    )
    assert out[5] == pytest.approx(0.05) and out[6] == pytest.approx(0.05)
    assert out[3] == pytest.approx(0.05 * R)
    out = d(
        0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 7.99, 7.99, *common, 1.0, 0.0, 0.0, 0.0, 1.0, 5.0, 12.0
    )
    assert out[5] == pytest.approx(8.0) and out[3] == pytest.approx(1.0)
    assert out[0] == pytest.approx(0.01)  # 1 m/s for 0.01 s
    # a turning demand beyond the limit: both wheels scaled alike, so the curvature is kept
    lm, th = math.hypot(2.0, 0.5), math.atan2(0.5, 2.0)
    v, om = 5.0 * (lm - 1.0), 12.0 * th  # App. C mode 10, demanded
    out = d(
        0.0, 0.0, 0.0, 2.0, 0.5, 0.0, 0.0, 8.0, 8.0, *common, 1e9, 0.0, 0.0, 0.0, 1.0, 5.0, 12.0
    )
    assert out[6] == pytest.approx(8.0) and out[5] < 8.0
    assert out[4] / out[3] == pytest.approx(om / v, rel=1e-12)
    assert out[3] == pytest.approx(8.0 * R * v / (v + 0.5 * B * om), rel=1e-12)


def test_robot_validation():
    assert fol.OXYDOG.max_speed == pytest.approx(1.0)
    for kw in (
        {"wheel_track": 0.0},
        {"wheel_radius": float("nan")},
        {"sample_time": -0.01},
        {"max_wheel_speed": 0.0},
        {"max_wheel_speed": "fast"},
        {"length_noise_std": -1e-3},
        {"winch_offset_x": float("inf")},
    ):
        name = next(iter(kw))
        with pytest.raises(InvalidParameterError, match=f"FollowerRobot.{name}"):
            fol.FollowerRobot(**kw)


# --- control laws: App. C values ---------------------------------------------------------


def test_pseudo_joystick_coded_and_printed():
    pj = fol.PseudoJoystick()
    assert (pj.desired_length, pj.speed_gain, pj.turn_gain) == (1.0, 5.0, 12.0)
    assert pj.command(1.2, -0.1) == pytest.approx((1.0, -1.2))
    assert pj.command(0.7, 0.3) == pytest.approx((0.0, 3.6))  # forward only, rotates in place
    pr = fol.PseudoJoystick(law="printed")
    v, om = pr.command(1.2, 0.3, wheel_track=0.28)
    assert v == pytest.approx(1.0)
    assert om == pytest.approx(2.0 * 1.0 / 0.28 * math.sin(0.3))  # toward the tether (CCW +)
    assert om > 0


def test_follow_the_leader_laws():
    ftl = fol.FollowTheLeader()
    assert (ftl.speed_gain, ftl.turn_gain, ftl.lookahead, ftl.min_step, ftl.buffer_size) == (
        1.0,
        3.0,
        0.5,
        0.01,
        300,
    )
    assert ftl.command(0.8, 0.2) == pytest.approx((-0.2, 0.6))  # no clip (App. C)
    cd = fol.FollowTheLeaderConstDistance()
    assert (cd.desired_length, cd.speed_gain, cd.angle_gain, cd.turn_gain) == (1.2, 2.0, 0.5, 2.0)
    assert cd.command(1.7, 0.4) == pytest.approx((2.0 * 0.5 * (1 - 0.5 * 0.4), 0.8))
    assert cd.command(1.7, 2.5) == pytest.approx((0.0, 5.0))  # 1 - K_a|phi| < 0 -> V = 0
    assert cd.command(1.0, 0.0)[0] == 0.0


@pytest.mark.parametrize(
    ("cls", "field", "value"),
    [
        (fol.PseudoJoystick, "speed_gain", -5.0),
        (fol.PseudoJoystick, "desired_length", float("nan")),
        (fol.FollowTheLeader, "lookahead", 0.0),
        (fol.FollowTheLeader, "turn_gain", float("inf")),
        (fol.FollowTheLeader, "min_step", "a"),
        (fol.FollowTheLeaderConstDistance, "angle_gain", -0.1),
        (fol.FollowTheLeaderConstDistance, "speed_gain", True),
    ],
)
def test_bad_gains_name_the_field(cls, field, value):
    with pytest.raises(InvalidParameterError, match=rf"{cls.__name__}\.{field}"):
        cls(**{field: value})


def test_bad_buffer_and_law():
    with pytest.raises(InvalidParameterError, match="buffer_size"):
        fol.FollowTheLeader(buffer_size=2)
    with pytest.raises(InvalidParameterError, match="law"):
        fol.PseudoJoystick(law="eq. 2.2")


def test_controller_roundtrip():
    c = fol.FollowTheLeader(lookahead=0.3, desired_length=0.6)
    assert fol.controller_from_dict(c.as_dict()) == c
    with pytest.raises(InvalidParameterError, match=r"controller\.type"):
        fol.controller_from_dict({"type": "Joystick"})


@settings(max_examples=40, deadline=None)
@given(
    lm=st.floats(0.0, 5.0),
    phi=st.floats(-math.pi, math.pi),
    kv=st.floats(0.1, 20.0),
    ko=st.floats(0.1, 20.0),
    ka=st.floats(0.0, 1.0 / math.pi),
)
def test_law_invariants(lm, phi, kv, ko, ka):
    """Forward-only laws never reverse; every law turns toward phi (counter-clockwise +)."""
    v, om = fol.PseudoJoystick(speed_gain=kv, turn_gain=ko).command(lm, phi)
    assert v >= 0.0 and om * phi >= 0.0
    v, om = fol.FollowTheLeaderConstDistance(speed_gain=kv, angle_gain=ka, turn_gain=ko).command(
        lm, phi
    )
    assert v >= 0.0 and om * phi >= 0.0
    assert v <= kv * max(lm - 1.2, 0.0) + 1e-12  # (1 - K_a |phi|) <= 1
    v, om = fol.PseudoJoystick(speed_gain=kv, law="printed").command(lm, phi)
    assert om * phi * v >= -1e-12  # toward the tether when driving forward


@settings(max_examples=6, deadline=None)
@given(angle=st.floats(-math.pi, math.pi), dx=st.floats(-20, 20), dy=st.floats(-20, 20))
def test_simulation_is_equivariant_under_rigid_motion(angle, dx, dy):
    """Rotating and shifting the leader path rotates and shifts the robot's path."""
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    base = fol.square_s()
    moved = fol.from_array(base.points @ rot.T + [dx, dy])
    for ctrl, tol in ((fol.PseudoJoystick(), 1e-8), (fol.FollowTheLeaderConstDistance(), 5e-3)):
        a = fol.simulate(ctrl, base, duration=12.0)
        b = fol.simulate(ctrl, moved, duration=12.0)
        assert np.max(np.abs(a.robot_xy @ rot.T + [dx, dy] - b.robot_xy)) < tol
        assert np.max(np.abs(a.tether_length - b.tether_length)) < tol
