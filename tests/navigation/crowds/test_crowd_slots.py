"""Many obstacles through K slots (issue 23, item 2): the nearest K within r2 fill the slots,
an empty slot adds exactly nothing, for every method."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.navigation import HolonomicRobot
from designlab.navigation.cbf_filter import CBFFilter
from designlab.navigation.crowds.slots import PARKED, crowd_step, fill_slots
from designlab.navigation.field import ObstacleGeometry, build_field

PED = ObstacleGeometry("disc", 2.1, 0.8, moving=True)
WALL = ObstacleGeometry("rectangle", 0.333, 0.2665, half_length=5.0, half_width=0.1)
WALL_OBS = [5.0, -0.1, 0, 0, 0, 0]

coords = st.floats(-4.0, 4.0, allow_nan=False)


@settings(max_examples=40, deadline=None)
@given(
    pts=st.lists(st.tuples(coords, coords), min_size=0, max_size=30),
    k=st.integers(1, 8),
    r2=st.floats(0.5, 3.0),
)
def test_slots_hold_the_nearest_within_r2(pts, k, r2):
    P = np.array(pts, dtype=float).reshape(-1, 2)
    V = np.ones_like(P)
    A = 2 * np.ones_like(P)
    robot = np.array([0.3, -0.2])
    obs, n_active, overflow = fill_slots(robot, P, V, A, r2=r2, slots=k)
    obs = obs.reshape(k, 6)
    d = np.hypot(P[:, 0] - robot[0], P[:, 1] - robot[1])
    inside = np.sort(d[d < r2])
    assert n_active == inside.size and overflow == (inside.size > k)
    m = min(k, inside.size)
    got = np.hypot(obs[:m, 0] - robot[0], obs[:m, 1] - robot[1])
    np.testing.assert_allclose(got, inside[:m], rtol=0, atol=1e-12)  # nearest first
    assert np.all(obs[m:, 0:2] == PARKED) and np.all(obs[m:, 2:] == 0)
    assert np.all(obs[:m, 2:4] == 1) and np.all(obs[:m, 4:6] == 2)


def test_slots_skip_pedestrians_not_in_the_simulation():
    P = np.array([[np.nan, np.nan], [1.0, 0.0]])
    obs, n, _ = fill_slots(np.zeros(2), P, np.zeros((2, 2)), np.zeros((2, 2)), r2=2.0, slots=2)
    assert n == 1 and obs[0] == 1.0 and obs[6] == PARKED


CASES = [("vff", 1.0), ("vff", 0.0), ("masoud", 0.0), ("ge_cui", 0.0), ("cbf", 0.0)]


@pytest.mark.parametrize(("method", "stab"), CASES)
@settings(max_examples=25, deadline=None)
@given(
    x=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-0.7, 0.7), st.floats(-0.7, 0.7)),
    ped=st.tuples(st.floats(-2, 2), st.floats(-2, 2), st.floats(-1.5, 1.5), st.floats(-1.5, 1.5)),
)
def test_an_empty_slot_adds_exactly_nothing(method, stab, x, ped):
    """The field with the wall, one pedestrian and K - 1 parked slots equals the field with
    the wall and that pedestrian alone (the force, V, dV/dt and the flags)."""
    gains = [4.3, 0.68, 20.3, 240.7]
    params = [4.4, 1.0, stab, 10.0]
    one = [*ped[:2], *ped[2:], 0.3, -0.1]
    alone = build_field((WALL, PED), method)
    slotted = build_field((WALL,) + (PED,) * 4, method)
    parked = [PARKED, PARKED, 0, 0, 0, 0] * 3
    a = alone(x=list(x), goal=[3.0, 0.5], obs=WALL_OBS + one, gains=gains, params=params)
    b = slotted(x=list(x), goal=[3.0, 0.5], obs=WALL_OBS + one + parked, gains=gains, params=params)
    for key in ("F", "critical", "V", "Vdot0", "Omega", "FL"):
        np.testing.assert_allclose(np.array(b[key]), np.array(a[key]), rtol=1e-12, atol=1e-12)


def test_cbf_filter_with_empty_slots_gives_the_same_force():
    robot = HolonomicRobot()
    gains = np.array([4.3, 0.68, 20.3, 240.7])
    x = np.array([0.0, 0.0, 0.5, 0.0])
    ped = [1.2, 0.1, -1.0, 0.0, 0.0, 0.0]
    alone = CBFFilter((WALL, PED), robot, (4.0, 4.0)).force(
        x, np.array([3.0, 0.0]), gains, np.array(WALL_OBS + ped), robot, None
    )
    slotted = CBFFilter((WALL,) + (PED,) * 3, robot, (4.0, 4.0)).force(
        x, np.array([3.0, 0.0]), gains, np.array(WALL_OBS + ped + [PARKED, PARKED, 0, 0, 0, 0] * 2),
        robot, None,
    )  # fmt: skip
    np.testing.assert_allclose(slotted, alone, rtol=0, atol=1e-5)  # OSQP's tolerance


def test_one_compiled_step_serves_any_crowd():
    geos = (WALL,) + (PED,) * 4
    f = crowd_step(geos, HolonomicRobot(), "vff", 60, 1e-3)
    assert crowd_step(geos, HolonomicRobot(), "vff", 60, 1e-3) is f  # built once
    assert f.size1_in(2) == 6 * 5 and f.size2_out(0) == 60
