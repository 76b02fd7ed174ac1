"""Wu et al. 2021, Sec. 5-6 extras: the sensor point offset from the rotation centre, the
target-distance adaptation and the motion filter, each against its equations
(docs/accompanying.md, "Sec. 6 options")."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import signal

from designlab.errors import InvalidParameterError
from designlab.following import accompanying as acc
from designlab.following.accompanying.extras import (
    adapted_target,
    approach_speed,
    centre_velocity,
    filter_step,
    sensor_point_velocity,
)

finite = st.floats(-2.0, 2.0)


def _world(psi: float, v: tuple[float, float]) -> np.ndarray:
    """Body (X right, Y forward) -> world for heading psi."""
    right = np.array([math.sin(psi), -math.cos(psi)])
    fwd = np.array([math.cos(psi), math.sin(psi)])
    return v[0] * right + v[1] * fwd


@settings(max_examples=30, deadline=None)
@given(vx=finite, vy=finite, w=finite, ax=finite, ay=finite, psi=st.floats(-4, 4))
def test_sensor_point_velocity_is_the_rigid_body_velocity(vx, vy, w, ax, ay, psi):
    """A point at body offset a on a body turning at omega: d/dt (p + R(psi) a)."""
    h = 1e-6

    def point(t):
        return _world(psi, (vx, vy)) * t + _world(psi + w * t, (ax, ay))

    fd = (point(h) - point(-h)) / (2 * h)
    vs = sensor_point_velocity((vx, vy), w, (ax, ay))
    np.testing.assert_allclose(_world(psi, vs), fd, atol=1e-6)
    back = centre_velocity(vs, w, (ax, ay))
    np.testing.assert_allclose(back, (vx, vy), atol=1e-12)


@settings(max_examples=30, deadline=None)
@given(
    xc=st.floats(-1.2, 1.2),
    yc=st.floats(0.2, 1.2),
    gamma=st.floats(-1.5, 1.5),
    vu=st.tuples(finite, finite),
    vs=st.tuples(finite, finite),
)
def test_approach_speed_is_the_user_s_speed_towards_the_robot(xc, yc, gamma, vu, vs):
    """With d_dot = u.(v_s - v_U) exact, u.v_s - d_dot returns u.v_U from theta_R alone."""
    d, tu, tr = acc.string_pot_readings(np.array([xc, yc]), gamma)
    u_user = np.array([xc, yc]) / d  # user -> robot in LCS_U
    # robot frame axes in LCS_U: rotated by gamma = theta_U + theta_R
    g = tu + tr
    rot = np.array([[math.cos(g), -math.sin(g)], [math.sin(g), math.cos(g)]])
    v_s_user = rot @ np.array(vs)  # the sensor point's velocity in LCS_U
    d_dot = u_user @ (v_s_user - np.array(vu))
    assert approach_speed(d_dot, tr, vs) == pytest.approx(u_user @ np.array(vu), abs=1e-12)


@settings(max_examples=30, deadline=None)
@given(
    tx=st.floats(-1, 1),
    ty=st.floats(0.2, 1),
    va=st.floats(-3, 3),
    k=st.floats(0, 2),
    cap=st.floats(0, 0.5),
)
def test_adapted_target_keeps_the_bearing_and_clips_the_change(tx, ty, va, k, cap):
    x, y = adapted_target((tx, ty), va, gain=k, max_change=cap)
    d_t = math.hypot(tx, ty)
    change = min(max(k * va, -cap), cap)
    assert math.hypot(x, y) == pytest.approx(max(d_t + change, 0.0), abs=1e-12)
    if d_t + change > 0:
        assert math.atan2(y, x) == pytest.approx(math.atan2(ty, tx), abs=1e-9)


def test_motion_filter_gain_is_that_of_the_discrete_first_order_filter():
    f = acc.MotionFilter(time_constant=0.2)
    b = f.pole(0.02)
    for hz in (0.0, 0.9, 1.8, 10.0):
        _, h = signal.freqz([1 - b], [1, -b], worN=[2 * math.pi * hz * 0.02])
        assert f.gain_at(hz, 0.02) == pytest.approx(abs(h[0]), rel=1e-12)
    steps = [1.0]
    for _ in range(5):
        steps.append(filter_step(steps[-1], 0.0, b))
    np.testing.assert_allclose(steps, b ** np.arange(6), rtol=1e-14)


def test_compensated_offset_tracks_like_a_sensor_at_the_centre():
    """With compensation the sensor point moves as the PID asks: the run equals the zero
    offset run (up to the acceleration limit acting on the centre, here never reached)."""
    task = acc.walking_task("left_pivot")
    base = acc.simulate(task)
    comp = acc.simulate(task, mount=acc.SensorMount(offset_y=0.25, compensate=True))
    np.testing.assert_allclose(comp.robot_in_user, base.robot_in_user, atol=1e-6)
    assert not np.allclose(comp.robot_pose[:2], base.robot_pose[:2], atol=0.05)
    # the sensor point starts on the target, the centre 0.25 m behind it
    np.testing.assert_allclose(comp.robot_in_user[:2, 0], task.target_position, atol=1e-12)
    d = np.hypot(*(comp.sensor_pose[:2] - comp.robot_pose[:2]))
    np.testing.assert_allclose(d, 0.25, atol=1e-12)


def test_uncompensated_turning_drags_the_sensor_point_by_omega_cross_a():
    """Turning left moves a sensor ahead of the centre to the left (-a_y omega in X) and one
    behind it to the right: on the left pivot (the robot must go left) ahead helps, behind hurts."""
    task = acc.walking_task("left_pivot")
    base = acc.simulate(task).rms_error
    ahead = acc.simulate(task, mount=acc.SensorMount(offset_y=0.25)).rms_error
    behind = acc.simulate(task, mount=acc.SensorMount(offset_y=-0.25)).rms_error
    assert ahead < base < behind


def test_adaptation_settles_on_k_times_the_walking_speed():
    """A long forward walk at constant speed with the robot ahead: the approach speed
    estimate converges to the radial part of the walking speed, v Y_C / d, and the target
    grows by k_a times it."""
    speed, k = 0.4, 0.5
    task = acc.walking_task("forward", speed=speed, distance=6.0)
    res = acc.simulate(task, adaptation=acc.TargetAdaptation(gain=k, max_change=1.0))
    mid = (res.time[:-1] > task.walk_start + 8.0) & (res.time[:-1] < task.walk_stop - 2.0)
    assert mid.sum() > 50
    rin = res.robot_in_user[:, :-1][:, mid]
    radial = speed * rin[1] / np.hypot(rin[0], rin[1])
    np.testing.assert_allclose(res.target_change[mid], k * radial, atol=2e-4)
    # backward: the user moves away, the target shortens, clipped at max_change
    back = acc.walking_task("backward", speed=speed, distance=6.0)
    res = acc.simulate(back, adaptation=acc.TargetAdaptation(gain=k, max_change=0.1))
    assert res.target_change.min() == pytest.approx(-0.1, abs=1e-12)
    assert res.target_change.max() <= 1e-9


def test_adaptation_off_changes_nothing_and_reports_zero():
    task = acc.walking_task("forward")
    res = acc.simulate(task)
    assert np.all(res.target_change == 0.0)
    assert res.adaptation is None and res.mount is None and res.motion_filter is None


def test_motion_filter_feeds_the_pid_the_filtered_error():
    """P-only loop below the limits: command = K_p * filtered(eq. 8 error), the filter
    started at the first error."""
    task = acc.walking_task("forward", sway=(0.02, math.radians(4)))
    pid = acc.UserFramePID(kp=1.5, ki=0.0, kd=0.0)
    mf = acc.MotionFilter(time_constant=0.15)
    res = acc.simulate(task, pid, motion_filter=mf)
    e = res.measured_error
    b = mf.pole(res.sensor.period)
    filt = np.empty_like(e)
    prev = e[:, 0]
    for k in range(e.shape[1]):
        prev = filter_step(prev, e[:, k], b)
        filt[:, k] = prev
    assert np.max(np.hypot(res.command[0], res.command[1])) < res.platform.max_speed
    np.testing.assert_allclose(res.command, pid.kp * filt, atol=1e-12)


def test_motion_filter_smooths_the_sway_in_the_yaw_command():
    task = acc.walking_task("forward", sway=(0.03, math.radians(5)))
    raw = acc.simulate(task).command[2]
    smooth = acc.simulate(task, motion_filter=acc.MotionFilter(0.4)).command[2]
    assert np.sqrt(np.mean(np.diff(smooth) ** 2)) < 0.5 * np.sqrt(np.mean(np.diff(raw) ** 2))


@pytest.mark.parametrize(
    ("make", "name"),
    [
        (lambda: acc.SensorMount(offset_x=float("nan")), "offset_x"),
        (lambda: acc.SensorMount(offset_y=1e9), "offset_y"),
        (lambda: acc.SensorMount(compensate="yes"), "compensate"),
        (lambda: acc.TargetAdaptation(gain=-1.0), "gain"),
        (lambda: acc.TargetAdaptation(max_change=float("inf")), "max_change"),
        (lambda: acc.TargetAdaptation(time_constant=0.0), "time_constant"),
        (lambda: acc.MotionFilter(time_constant=-0.1), "time_constant"),
        (lambda: acc.MotionFilter(time_constant="0.2"), "time_constant"),
        (lambda: acc.simulate(acc.walking_task("forward"), mount=(0.0, 0.2)), "mount"),
        (lambda: acc.simulate(acc.walking_task("forward"), adaptation=0.3), "adaptation"),
        (lambda: acc.simulate(acc.walking_task("forward"), motion_filter=0.2), "motion_filter"),
    ],
)
def test_bad_options_are_refused_naming_the_parameter(make, name):
    with pytest.raises(InvalidParameterError) as exc:
        make()
    assert name in str(exc.value)
