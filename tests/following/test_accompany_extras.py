"""Wu et al. 2021 extras: the path-length metric against the paper's Sec. 6 statements."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.following.accompanying.metrics import accompany_metrics, path_length

fol = dl.following


def _rigid_circle(radius: float, target: tuple[float, float], turn: float = 2 * math.pi):
    """A user walking a CCW circle about the origin and a robot exactly on its target."""
    t = np.linspace(0.0, 20.0, 4001)
    phi = turn * t / t[-1]
    psi = phi + math.pi / 2
    user = np.vstack([radius * np.cos(phi), radius * np.sin(phi), psi])
    tx, ty = target
    robot = np.vstack(
        [
            user[0] + np.sin(psi) * tx + np.cos(psi) * ty,
            user[1] - np.cos(psi) * tx + np.sin(psi) * ty,
            psi,
        ]
    )
    return t, user, robot


@settings(max_examples=6, deadline=None)
@given(
    radius=st.floats(0.5, 3.0),
    target=st.tuples(st.floats(-0.8, 0.8), st.floats(0.2, 0.8)),
)
def test_on_a_circle_the_path_length_ratio_is_the_distance_to_the_centre_over_the_radius(
    radius, target
):
    """Sec. 6: on a circle the robot's path equals the user's when the target lies on the
    walking curve and is longer outside it: a point rho from the centre travels rho * angle.
    The centre is at X = -R (the user's left, X to the right) in the user frame."""
    t, user, robot = _rigid_circle(radius, target)
    m = accompany_metrics(t, user, robot, target, 0.0, 0.0, 20.0, settle_window=0.0)
    rho = math.hypot(target[0] + radius, target[1])
    assert m.user_path_length == pytest.approx(2 * math.pi * radius, rel=1e-6)
    assert m.robot_path_length == pytest.approx(2 * math.pi * rho, rel=1e-6)
    assert m.path_length_ratio == pytest.approx(rho / radius, rel=1e-6)
    assert m.target_path_length == pytest.approx(m.robot_path_length, rel=1e-9)


def test_target_on_the_walking_curve_gives_the_user_s_path_length():
    radius = 1.2
    ang = 0.4  # a point of the walking circle, ahead of the user
    target = (radius * math.cos(ang) - radius, radius * math.sin(ang))
    t, user, robot = _rigid_circle(radius, target)
    m = accompany_metrics(t, user, robot, target, 0.0, 0.0, 20.0, settle_window=0.0)
    assert m.path_length_ratio == pytest.approx(1.0, rel=1e-6)
    outside = (target[0] + 0.3, target[1])  # 0.3 m further right: outside the circle
    t, user, robot = _rigid_circle(radius, outside)
    m2 = accompany_metrics(t, user, robot, outside, 0.0, 0.0, 20.0, settle_window=0.0)
    assert m2.path_length_ratio > 1.0


def test_pivot_the_robot_travels_further_than_the_user():
    """Sec. 6: during pivots the robot takes a longer path than the user. Turning 90 deg
    about a point c behind the frame origin, each point travels (its distance to c) * pi/2."""
    t = np.linspace(0.0, 2.0, 2001)
    psi = math.pi / 2 + (math.pi / 2) * t / t[-1]
    back = 0.25
    user = np.vstack([back * np.cos(psi), back * np.sin(psi), psi])  # c at the world origin
    target = (0.1, 0.45)
    robot = np.vstack(
        [
            user[0] + np.sin(psi) * target[0] + np.cos(psi) * target[1],
            user[1] - np.cos(psi) * target[0] + np.sin(psi) * target[1],
            psi,
        ]
    )
    m = accompany_metrics(t, user, robot, target, 0.0, 0.0, 2.0, settle_window=0.0)
    assert m.user_path_length == pytest.approx(back * math.pi / 2, rel=1e-6)
    rho = math.hypot(target[0], target[1] + back)
    assert m.robot_path_length == pytest.approx(rho * math.pi / 2, rel=1e-6)
    assert m.path_length_ratio > 1


def test_path_length_of_simulated_runs():
    """A tuned robot's path is close to its target point's; on a pivot it is longer than the
    user's (Sec. 6)."""
    pid = fol.UserFramePID(kp=9.67, ki=41.0, kd=2.01)
    res = fol.accompany(fol.walking_task("left_pivot"), controller=pid)
    m = res.metrics
    assert m.robot_path_length > 1.5 * m.user_path_length
    assert m.robot_path_length == pytest.approx(m.target_path_length, rel=0.1)
    frame = res.to_frame()
    assert {"user_path_length_m", "robot_path_length_m", "path_length_ratio"} <= set(frame)
    assert path_length(np.array([0.0, 1.0]), np.array([0.0, 0.0])) == 1.0
