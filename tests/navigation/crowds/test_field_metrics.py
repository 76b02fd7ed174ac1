"""Issue 35, item 4: the field's metrics, each against a hand-built trajectory (exact)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import box

from designlab.errors import InvalidParameterError
from designlab.navigation.crowds import field_metrics as fm
from designlab.navigation.crowds.faced import faced_crowd, voronoi_density


def test_path_length_and_spl():
    p = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]])
    assert fm.path_length(p) == 7.0
    # success 1 with a 7 m path for a 5 m task, a failure, a success on the shortest path
    assert fm.spl([1, 0, 1], [5.0, 5.0, 5.0], [7.0, 5.0, 5.0]) == pytest.approx(
        (5 / 7 + 0 + 1) / 3, rel=0, abs=1e-15
    )
    with pytest.raises(InvalidParameterError):
        fm.spl([1], [0.0], [1.0])


def test_jerk_and_acceleration_of_known_motions():
    t = np.arange(0.0, 2.00001, 0.01)
    still = fm.motion_smoothness(t, np.ones((t.size, 2)), 0.1)
    assert still["accel_max"] == 0.0 and still["jerk_max"] == 0.0
    # v = (t^3 / 3, 0): a = t^2 -> second differences of a cubic, period h: jerk 2t + O(h)
    # exactly a_k = ((t+h)^3 - t^3) / (3h); j = (a_{k+1} - a_k)/h = 2 t_{k+1} + h (k-th)
    v = np.stack([t**3 / 3, np.zeros_like(t)], axis=1)
    out = fm.motion_smoothness(t, v, 0.1)
    grid = np.arange(0.0, 2.00001, 0.1)
    vs = grid**3 / 3
    j = np.diff(vs, 2) / 0.01
    assert out["jerk_max"] == pytest.approx(j.max(), rel=1e-9)
    assert out["jerk_mean"] == pytest.approx(j.mean(), rel=1e-9)


def test_discomfort_and_intrusion_shares():
    t = np.array([0.0, 1.0, 2.0, 4.0])
    robot = np.zeros((4, 2))
    # surface distances (contact 0.5): 1.5, 0.1, 0.15, NaN (gone): below 0.2 for 1 s + 2 s
    P = np.array([[[2.0, 0.0]], [[0.6, 0.0]], [[0.0, 0.65]], [[np.nan, np.nan]]])
    assert fm.discomfort_share(t, robot, P, 0.5) == 3.0 / 4.0
    # personal space 1.2 m + robot 0.3 m: inside at the samples 2 and 3 (1.5 m is not)
    assert fm.intrusion_share(t, robot, P, 1.2, 0.3) == 3.0 / 4.0


def test_time_to_collision_closed_form():
    # head-on, closing at 2 m/s from 5 m apart, contact at 1 m: 2 s
    assert fm.time_to_collision([0, 0], [1, 0], [[5, 0]], [[-1, 0]], 1.0) == 2.0
    # offset 0.6 m, contact 1 m: |dp + dv t| = 1 -> (5 - 2t)^2 + 0.36 = 1 -> t = 2.1
    assert fm.time_to_collision([0, 0], [1, 0], [[5, 0.6]], [[-1, 0]], 1.0) == pytest.approx(2.1)
    # moving apart: never; touching now: 0
    assert fm.time_to_collision([0, 0], [-1, 0], [[5, 0]], [[1, 0]], 1.0) == math.inf
    assert fm.time_to_collision([0, 0], [0, 0], [[0.5, 0]], [[0, 0]], 1.0) == 0.0


def test_freezing_needs_the_whole_duration_away_from_the_goal():
    t = np.arange(6.0)
    v = np.array([[1, 0], [0, 0], [0, 0], [1, 0], [0, 0], [1, 0]], float)
    assert not fm.freezing(t, v, np.zeros((6, 2)), [9.0, 0.0], 0.1, duration=2.0)
    v[3] = 0.0
    assert fm.freezing(t, v, np.zeros((6, 2)), [9.0, 0.0], 0.1, duration=2.0)
    # standing at the goal is arriving, not freezing
    assert not fm.freezing(t, np.zeros((6, 2)), np.zeros((6, 2)), [0.05, 0.0], 0.1)


def test_contacts_are_attributed_by_the_robots_velocity_towards_the_person():
    P = np.array([[[3.0, 0.0]], [[1.0, 0.0]], [[0.4, 0.0]]])
    robot = np.zeros((3, 2))
    moving_in = np.tile([0.5, 0.0], (3, 1))
    moving_away = np.tile([-0.5, 0.0], (3, 1))
    sideways = np.tile([0.0, 0.5], (3, 1))
    t = [0.0, 1.0, 2.0]
    assert fm.first_entry(t, robot, moving_in, P, 0.5) == (2.0, "robot")
    assert fm.first_entry(t, robot, moving_away, P, 0.5) == (2.0, "pedestrian")
    assert fm.first_entry(t, robot, sideways, P, 1.0) == (1.0, "pedestrian")
    assert fm.first_entry(t, robot, sideways, P, 0.1) == (math.inf, "none")


def test_classic_and_voronoi_density_of_a_hand_built_crowd():
    # two pedestrians standing at (1, 1) and (3.5, 1) in a 4 m x 2 m area; the band
    # [0, 2] x [0, 2] holds one (classic 1/4) and 4/4.5 of the first's cell (Voronoi)
    P = np.array([[[1.0, 1.0], [3.5, 1.0]]] * 11)
    t = np.arange(11) * 0.1
    band = box(0, 0, 2, 2)
    assert faced_crowd(t, P, band).measured_density_per_m2 == pytest.approx(0.25, abs=1e-12)
    assert voronoi_density(t, P, band, box(0, 0, 4, 2), frame_rate=10.0) == pytest.approx(
        (4 / 4.5) / 4, abs=1e-12
    )


def test_a_wall_contact_is_the_walls_and_a_tie_goes_to_the_person():
    wall = [[0.0, -1.2, 1.0, 0.0, 5.0, 0.1]]  # its face at y = -1.1
    robot = np.array([[0.0, 0.0], [0.0, -0.5], [0.0, -0.9]])
    P = np.full((3, 1, 2), np.nan)
    t, v = [0.0, 1.0, 2.0], np.tile([0.0, -0.4], (3, 1))
    # the robot's disc (0.3 m) touches the wall's face at the last sample, 0.2 m away
    assert fm.first_entry(t, robot, v, P, 0.5, wall, 0.3) == (2.0, "wall")
    assert fm.first_entry(t, robot, v, P, 0.5, wall, 0.1) == (math.inf, "none")
    P[2, 0] = [0.0, -1.2]  # a person there at the same sample: the person's
    assert fm.first_entry(t, robot, v, P, 0.5, wall, 0.3) == (2.0, "robot")
    assert fm.wall_distances(wall, robot).tolist() == pytest.approx([1.1, 0.6, 0.2], abs=1e-15)


def _grazing_period(robot_velocity):
    """One navigation period (20 dynamics steps of 1 ms, 2 pedestrian steps of 10 ms) in
    which a person passes the robot's disc (contact 0.5 m) at 0.4999 m, touching it only
    for about 10 ms between two pedestrian steps: no recorded sample shows the contact."""
    from types import SimpleNamespace

    from designlab.navigation.crowds.simulate import _contact, _Frames
    from designlab.navigation.parameters import HolonomicRobot

    x = np.array([-0.0105 - 0.021, -0.0105, 0.0105])  # frames 10 ms apart at 2.1 m/s
    frames = _Frames(1, 3)
    for xi in x:
        frames.push(np.array([0]), np.array([[xi, 0.4999]]), 1)
    robot = HolonomicRobot(radius=0.3)
    X = np.zeros((4, 20))
    X[2:4] = np.asarray(robot_velocity, dtype=float)[:, None]  # held at 0 (hand-built)
    run = SimpleNamespace(
        s=SimpleNamespace(crowd=SimpleNamespace(robot=robot, pedestrian_radius=0.2), per_ped=2,
                          n_sub=20, dt=1e-3),
        frames=frames, frac=(np.arange(1, 11) / 10)[None, :, None, None], dmin=0.4999,
        wmin=math.inf, r3=0.45, w3=0.1, collision_by="none", critical_by="none",
        collision_time=math.inf, wall_frames=np.zeros((0, 6)),
    )  # fmt: skip
    return run, X, frames, _contact


@pytest.mark.parametrize(("velocity", "who"), [((0.0, 0.3), "robot"), ((0.0, -0.3), "pedestrian")])
def test_a_contact_between_two_recorded_samples_is_attributed_at_its_own_step(velocity, who):
    run, X, frames, contact = _grazing_period(velocity)
    F = frames.last(3)
    d = np.hypot(F[:, 0, 0], F[:, 0, 1])
    assert (d > 0.5).all()  # the pedestrian steps (the records) never show it
    recorded = fm.first_entry([0.0, 0.01, 0.02], np.zeros((3, 2)), X[2:4, [0, 9, 19]].T, F, 0.5)
    assert recorded == (math.inf, "none")
    contact(run, 0, X)
    assert run.collision_by == who and run.critical_by == "none"
    # the first dynamics step with the interpolated centre within 0.5 m: x = -0.0105 +
    # 2.1 (t - 0.01) crosses -sqrt(0.5^2 - 0.4999^2) = -0.0099995 at t = 0.01024 s, step 11
    assert run.collision_time == pytest.approx(0.011, abs=1e-15)
