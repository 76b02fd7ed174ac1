"""Models of the accompanying robot (Wu et al. 2021): frames, string-pot, platform, sensor."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.results import check_result

fol = dl.following

angles = st.floats(-math.pi, math.pi, allow_nan=False)
coords = st.floats(-3.0, 3.0, allow_nan=False)


def test_robot_in_user_frame_known_geometry():
    # user at (1, 2) facing -X (heading pi); robot 0.5 m in front of the user and
    # 0.1 m to the user's right (the user's right is +Y when facing -X)
    user = [1.0, 2.0, math.pi]
    robot = [0.5, 2.1, math.pi + 0.3]
    p_c, g = fol.robot_in_user_frame(user, robot)
    assert p_c == pytest.approx([0.1, 0.5], abs=1e-12)
    assert g == pytest.approx(0.3, abs=1e-12)


@settings(max_examples=60, deadline=None)
@given(coords, coords, angles, coords, coords, angles)
def test_string_pot_reconstructs_pose(xu, yu, pu, xr, yr, pr):
    """Eq. (7): p_C = d [cos theta_U, sin theta_U]; eq. (8): gamma_C = theta_U + theta_R."""
    if math.hypot(xr - xu, yr - yu) < 1e-3:
        return
    p_c, g = fol.robot_in_user_frame([xu, yu, pu], [xr, yr, pr])
    d, tu, tr = fol.string_pot_readings(p_c, g)
    assert d == pytest.approx(math.hypot(xr - xu, yr - yu), rel=1e-12)
    assert d * math.cos(tu) == pytest.approx(p_c[0], abs=1e-9)
    assert d * math.sin(tu) == pytest.approx(p_c[1], abs=1e-9)
    diff = (tu + tr - g + math.pi) % (2 * math.pi) - math.pi
    assert diff == pytest.approx(0.0, abs=1e-9)


@settings(max_examples=60, deadline=None)
@given(coords, coords, angles, st.floats(0.2, 1.5), angles, angles)
def test_robot_frame_error_is_the_rotated_user_frame_error(tx, ty, tg, d, tu, tr):
    """Eq. (8): e_R = R(gamma_C)^T (p_T - p_C); a rotation keeps the norm."""
    e = fol.robot_frame_error((tx, ty), tg, d, tu, tr)
    eu = np.array([tx - d * math.cos(tu), ty - d * math.sin(tu)])
    g = tu + tr
    # independent: express eu in the robot axes (X_R = (cos g, sin g), Y_R = (-sin g, cos g))
    ex = eu @ [math.cos(g), math.sin(g)]
    ey = eu @ [-math.sin(g), math.cos(g)]
    assert e[0] == pytest.approx(ex, abs=1e-9)
    assert e[1] == pytest.approx(ey, abs=1e-9)
    assert math.hypot(e[0], e[1]) == pytest.approx(np.linalg.norm(eu), abs=1e-9)
    dth = (tg - g + math.pi) % (2 * math.pi) - math.pi
    assert abs((e[2] - dth + math.pi) % (2 * math.pi) - math.pi) < 1e-9


def test_user_translation_and_rotation_eqs_2_to_4():
    """Eq. (4): user moves by dp (own frame), turns by alpha: p_C1 = R(alpha)^T (p_C0 - dp)."""
    p0 = np.array([0.1, 0.5])
    dp = np.array([0.2, 0.3])
    alpha = 0.4
    user0 = np.array([0.0, 0.0, math.pi / 2])
    robot = np.array([p0[0], p0[1], math.pi / 2])  # user faces +Y: LCS_U = WCS
    # the user's move in its own frame at time 0 is a world move here (aligned frames)
    user1 = np.array([dp[0], dp[1], math.pi / 2 + alpha])
    p_c1, g1 = fol.robot_in_user_frame(user1, robot)
    c, s = math.cos(alpha), math.sin(alpha)
    expected = np.array([[c, s], [-s, c]]) @ (p0 - dp)
    assert p_c1 == pytest.approx(expected, abs=1e-12)
    assert g1 == pytest.approx(-alpha, abs=1e-12)  # gamma_C1 = gamma_C0 - alpha_r
    _ = user0


def test_mecanum_matrix_eq10_patterns():
    m = fol.mecanum_matrix(0.05, 0.4)
    # forward: all wheels roll forward at V/R
    assert m @ [0.0, 1.0, 0.0] == pytest.approx([20.0] * 4)
    # counter-clockwise spin: left wheels backwards, right wheels forwards, (L1+L2) w / R
    assert m @ [0.0, 0.0, 1.0] == pytest.approx([-8.0, 8.0, -8.0, 8.0])
    # the printed eq. (10) pattern = physical speeds with the right motors negated (s = -1)
    printed = np.diag([1.0, -1.0, 1.0, -1.0]) @ m * 0.05
    assert printed[:, :2] == pytest.approx(np.array([[1, 1], [1, -1], [-1, 1], [-1, -1]]))
    assert printed[:, 2] == pytest.approx([-0.4] * 4)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"time_constant": -0.1}, "MecanumPlatform.time_constant"),
        ({"time_constant": float("nan")}, "MecanumPlatform.time_constant"),
        ({"max_speed": float("inf")}, "MecanumPlatform.max_speed"),
        ({"max_acceleration": 0.0}, "MecanumPlatform.max_acceleration"),
        ({"limit_mode": "box"}, "MecanumPlatform.limit_mode"),
        ({"max_wheel_speed": -1.0}, "MecanumPlatform.max_wheel_speed"),
        ({"time_constant": "fast"}, "MecanumPlatform.time_constant"),
    ],
)
def test_platform_bad_input(kwargs, name):
    with pytest.raises(InvalidParameterError) as exc:
        fol.MecanumPlatform(**kwargs)
    assert exc.value.name == name


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"min_range": 1.5, "max_range": 1.5}, "StringPotSensor.max_range"),
        ({"min_range": 0.8, "max_range": 0.3}, "StringPotSensor.max_range"),
        ({"min_range": -0.1}, "StringPotSensor.min_range"),
        ({"median_window": 4}, "StringPotSensor.median_window"),
        ({"median_window": 2.5}, "StringPotSensor.median_window"),
        ({"oversampling": 0}, "StringPotSensor.oversampling"),
        ({"distance_noise": float("nan")}, "StringPotSensor.distance_noise"),
        ({"sample_rate": -50.0}, "StringPotSensor.sample_rate"),
    ],
)
def test_sensor_bad_input(kwargs, name):
    with pytest.raises(InvalidParameterError) as exc:
        fol.StringPotSensor(**kwargs)
    assert exc.value.name == name


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"kp": -1.0}, "UserFramePID.kp"),
        ({"ki": float("inf")}, "UserFramePID.ki"),
        ({"derivative_filter_time": -0.01}, "UserFramePID.derivative_filter_time"),
        ({"kd_heading": float("nan")}, "UserFramePID.kd_heading"),
        ({"kp": 0.0, "ki": 0.0}, "UserFramePID.kp"),
    ],
)
def test_pid_bad_input(kwargs, name):
    with pytest.raises(InvalidParameterError) as exc:
        fol.UserFramePID(**kwargs)
    assert exc.value.name == name


def _still_task(duration=6.0, target=(0.0, 0.5)):
    t = np.linspace(0.0, duration, 601)
    z = np.zeros_like(t)
    return fol.WalkingTask("still", t, z, z, z + math.pi / 2, 0.0, 0.0, target)


def test_linear_closed_loop_matches_python_control():
    """Away from saturation the simulation is the sampled loop of the linear analysis."""
    import control as ct

    tau, ts, kp, ki = 0.15, 0.02, 2.0, 1.0
    pid = fol.UserFramePID(kp=kp, ki=ki, kd=0.0)
    off = 0.05
    res = fol.accompany(_still_task(), pid, initial_offset=(0.0, off))
    # independent discrete model: ZOH{1/(s(tau s+1))} with C(z) = kp + ki ts z/(z-1)
    plant = ct.c2d(ct.tf([1.0], [tau, 1.0, 0.0]), ts, "zoh")
    z = ct.tf([1.0, 0.0], [1.0], ts)
    loop = (kp + ki * ts * z / (z - 1)) * plant
    n = 150
    _, y = ct.step_response(ct.feedback(loop, 1), T=np.arange(n) * ts)
    # robot starts off + Y_T; the loop drives the offset to 0: offset(k) = off (1 - y_k)
    sim = res.robot_in_user[1, :n] - 0.5
    assert np.max(np.abs(sim - off * (1 - np.ravel(y)))) < 0.01 * off


def test_saturation_norm_and_per_axis():
    task = _still_task(4.0)
    big = (0.8, 0.8)  # 1.13 m diagonal offset: the command saturates
    pid = fol.UserFramePID(kp=4.0, ki=0.0, kd=0.0)
    r_norm = fol.accompany(task, pid, initial_offset=big)
    speed = np.hypot(r_norm.command[0], r_norm.command[1])
    assert speed.max() == pytest.approx(1.0, rel=1e-9)
    assert any("saturated" in w for w in r_norm.warnings)
    r_axis = fol.accompany(
        task, pid, platform=fol.MecanumPlatform(limit_mode="per_axis"), initial_offset=big
    )
    assert np.abs(r_axis.command[:2]).max() == pytest.approx(1.0, rel=1e-9)
    assert np.hypot(r_axis.command[0], r_axis.command[1]).max() > 1.3  # diagonal: sqrt(2)
    # acceleration limit: world speed of the robot changes by at most a_max per second
    for r in (r_norm,):
        v = np.hypot(*np.diff(r.robot_pose[:2], axis=1)) / 0.02
        assert np.max(np.abs(np.diff(v))) / 0.02 <= 2.0 * 1.02


def test_wheel_level_limit_slows_the_robot():
    task = fol.walking_task("forward", speed=0.8)
    pid = fol.UserFramePID(kp=4.0, ki=1.0)
    free = fol.accompany(task, pid)
    limited_platform = fol.MecanumPlatform(max_wheel_speed=10.0, wheel_radius=0.05)
    lim = fol.accompany(task, pid, platform=limited_platform)
    wheels = limited_platform.wheel_speeds(lim.command)
    # the command seen by the platform is scaled so no wheel exceeds 10 rad/s; the
    # controller's command may exceed it -- but the robot then lags more
    assert lim.rms_error > free.rms_error
    assert np.abs(wheels).max() > 0


def test_sensor_range_flags_and_holds():
    # a target closer than the distance sensor's 0.20 m minimum: every raw sample is flagged
    res = fol.accompany(_still_task(target=(0.0, 0.18)))
    assert int(res.flagged.sum()) == res.command.shape[1]  # window 1: one sample per period
    filtered = fol.accompany(
        _still_task(target=(0.0, 0.18)), sensor=fol.StringPotSensor(median_window=3)
    )
    assert int(filtered.flagged.sum()) == 4 * res.command.shape[1]  # every raw sample
    assert any("outside the sensor range" in w for w in res.warnings)
    # the held distance is the target's, so the robot does not move (and does not run away)
    assert np.ptp(res.robot_pose[1]) < 1e-9
    # walking towards a robot parked too close: flagged samples and a collision warning
    walk = fol.accompany(fol.walking_task("forward", target_position=(0.0, 0.18)))
    assert walk.flagged.sum() > 0
    assert any("collision" in w for w in walk.warnings)
    # inside the range nothing is flagged
    assert int(fol.accompany(fol.walking_task("forward")).flagged.sum()) == 0


def test_median_filter_reduces_noise():
    task = _still_task(6.0)
    pid = fol.UserFramePID(kp=1.0, ki=0.0, kd=0.0)
    noisy = fol.StringPotSensor(distance_noise=0.01, angle_noise=0.01)
    filtered = noisy.replace(median_window=7)
    r1 = fol.accompany(task, pid, sensor=noisy, seed=3)
    r7 = fol.accompany(task, pid, sensor=filtered, seed=3)
    assert np.std(r7.readings[0]) < 0.7 * np.std(r1.readings[0])
    # same seed, same run
    r1b = fol.accompany(task, pid, sensor=noisy, seed=3)
    assert np.array_equal(r1.robot_pose, r1b.robot_pose)


def test_result_contract():
    res = fol.accompany(fol.walking_task("left_pivot"))
    check_result(res)
    frame = res.to_frame()
    assert len(frame) == 1 and frame["task"][0] == "left_pivot"
    h = res.history()
    assert len(h) == res.time.size and "error_x_m" in h


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"initial_offset": (float("nan"), 0.0)}, "initial_offset"),
        ({"controller": "pid"}, "controller"),
        ({"platform": 3}, "platform"),
    ],
)
def test_accompany_bad_input(kwargs, name):
    with pytest.raises(InvalidParameterError) as exc:
        fol.accompany(fol.walking_task("forward"), **kwargs)
    assert exc.value.name == name
