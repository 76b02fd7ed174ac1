"""Combined impact planes (Zeng 2011, Sec. 3.3-3.4, (3.4.13), (3.4.21))."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.impact import FOAM_1, HEAD_MIN, MANIPULATOR_1, MANIPULATOR_2
from designlab.impact.full_joint import FullJointContact
from designlab.impact.planes import ImpactPlane, closing_speed, combined_impact
from designlab.results import check_result

G0 = 9.80665


def test_closing_speed_equation_3_4_13() -> None:
    """Scenario 1: v_c = v_r(0) - v_h(0) cos(gamma_c), v_h signed along the normal (I5)."""
    v_r = 0.25
    for gamma_c in (0.0, 0.3, 1.0, math.pi / 2):
        speed = 1.0
        head = (-speed * math.cos(gamma_c), speed * math.sin(gamma_c))
        c = closing_speed((v_r, 0.0), head, (1.0, 0.0))
        assert c.closing_speed == pytest.approx(v_r - (-speed) * math.cos(gamma_c), abs=1e-15)
        assert c.gamma_c == pytest.approx(gamma_c, abs=1e-7)
        assert c.gamma_r == 0.0
    check_result(c)


def test_closing_speed_equation_3_4_21() -> None:
    """Scenario 3: v_c = v_r(0) cos(gamma_r) - v_h(0) cos(gamma_c)."""
    gamma_r, gamma_c = 0.6, 0.4
    v_r, v_h = 0.3, 0.8
    n = np.array([0.0, 0.0, 1.0])
    robot = v_r * np.array([math.sin(gamma_r), 0.0, math.cos(gamma_r)])
    head = -v_h * np.array([0.0, math.sin(gamma_c), math.cos(gamma_c)])  # towards the arm
    c = closing_speed(robot, head, 2.0 * n)  # the normal's length does not matter
    assert c.closing_speed == pytest.approx(v_r * math.cos(gamma_r) + v_h * math.cos(gamma_c))
    assert (c.gamma_r, c.gamma_c) == pytest.approx((gamma_r, gamma_c))
    assert c.impact
    assert not closing_speed((0.0, 0.1), (0.0, 0.5), (0.0, 1.0)).impact  # head moves away faster


vec = st.lists(st.floats(-2.0, 2.0), min_size=3, max_size=3)


@settings(max_examples=60, deadline=None)
@given(v_r=vec, v_h=vec, n=vec, angle=st.floats(0.0, 2 * math.pi))
def test_closing_speed_invariants(v_r, v_h, n, angle) -> None:
    if np.linalg.norm(n) < 1e-3:
        return
    c = closing_speed(v_r, v_h, n)
    # v_c = |v_r| cos(gamma_r) + |v_h| cos(gamma_c) (gamma_c measured from -n)
    expect = 0.0
    if c.robot_speed > 0:
        expect += c.robot_speed * math.cos(c.gamma_r)
    if c.head_speed > 0:
        expect += c.head_speed * math.cos(c.gamma_c)
    assert c.closing_speed == pytest.approx(expect, abs=1e-12)
    # a rigid rotation of everything changes nothing
    ca, sa = math.cos(angle), math.sin(angle)
    rot = np.array([[ca, -sa, 0.0], [sa, ca, 0.0], [0.0, 0.0, 1.0]])
    c2 = closing_speed(rot @ v_r, rot @ v_h, rot @ n)
    assert c2.closing_speed == pytest.approx(c.closing_speed, abs=1e-12)
    assert abs(c.closing_speed) <= np.linalg.norm(np.subtract(v_r, v_h)) + 1e-12


def test_single_plane_is_the_plane_impact() -> None:
    plane = ImpactPlane(MANIPULATOR_1, (1.0, 0.0), "horizontal")
    c = combined_impact([plane], FOAM_1, HEAD_MIN, (0.25, 0.0), (-1.0, 0.0))
    check_result(c)
    r = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25)
    assert c.a_h_max_sum == pytest.approx(r.peak_head_acceleration, rel=1e-12)
    assert c.a_h_max_vector == pytest.approx(r.peak_head_acceleration, rel=1e-12)
    assert c.a_h_max_sum_g == pytest.approx(r.peak_head_acceleration / G0)
    frame = c.to_frame()
    assert list(frame.plane) == ["horizontal", "combined"]


def test_two_planes_add_and_the_vector_is_smaller() -> None:
    """The thesis adds the planes' a_h,max; the vector magnitude is at most that sum."""
    h = ImpactPlane(MANIPULATOR_1, (1.0, 0.0, 0.0), "horizontal")
    v = ImpactPlane(MANIPULATOR_1, (0.0, 0.0, -1.0), "vertical")
    # the same arm and closing speed in both planes: the peaks coincide in time
    c = combined_impact([h, v], FOAM_1, HEAD_MIN, (0.5, 0.0, -0.5), (0.0, 0.0, 0.0))
    one = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 0.5).peak_head_acceleration
    assert c.a_h_max_sum == pytest.approx(2 * one, rel=1e-12)
    assert c.a_h_max_vector == pytest.approx(math.sqrt(2) * one, rel=1e-9)
    # different arms: the vector sum is below the thesis's sum
    v2 = ImpactPlane(MANIPULATOR_2, (0.0, 0.0, -1.0), "vertical")
    c2 = combined_impact([h, v2], FOAM_1, HEAD_MIN, (0.25, 0.0, -0.2), (-1.0, 0.0, 0.0))
    a1 = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25).peak_head_acceleration
    a2 = dl.impact.simulate(MANIPULATOR_2, FOAM_1, HEAD_MIN, 0.2).peak_head_acceleration
    assert c2.a_h_max_sum == pytest.approx(a1 + a2, rel=1e-12)
    assert max(a1, a2) <= c2.a_h_max_vector < c2.a_h_max_sum


def test_plane_without_impact_contributes_nothing() -> None:
    h = ImpactPlane(MANIPULATOR_1, (1.0, 0.0), "horizontal")
    v = ImpactPlane(MANIPULATOR_1, (0.0, 1.0), "vertical")
    c = combined_impact([h, v], FOAM_1, HEAD_MIN, (0.25, -0.3), (-1.0, 0.0))  # moving away in v
    assert c.responses[1] is None
    r = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25)
    assert c.a_h_max_sum == pytest.approx(r.peak_head_acceleration, rel=1e-12)
    none = combined_impact([v], FOAM_1, HEAD_MIN, (0.0, -0.3), (0.0, 0.0))
    assert none.status == "no_impact" and none.a_h_max_sum == 0.0 == none.a_h_max_vector


def test_full_joint_plane() -> None:
    arm = FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    c = combined_impact([ImpactPlane(arm, (1.0, 0.0))], FOAM_1, HEAD_MIN, (0.25, 0.0), (-1.0, 0.0))
    r = dl.impact.simulate(arm, FOAM_1, HEAD_MIN, 1.25)
    assert c.a_h_max_sum == pytest.approx(r.peak_head_acceleration, rel=1e-12)


def test_bad_input() -> None:
    with pytest.raises(InvalidParameterError, match="normal"):
        closing_speed((1.0, 0.0), (0.0, 0.0), (0.0, 0.0))
    with pytest.raises(InvalidParameterError, match="head_velocity"):
        closing_speed((1.0, 0.0), (0.0, 0.0, 0.0), (1.0, 0.0))
    with pytest.raises(InvalidParameterError, match="robot_velocity"):
        closing_speed((math.nan, 0.0), (0.0, 0.0), (1.0, 0.0))
    with pytest.raises(InvalidParameterError, match="robot_velocity"):
        closing_speed("fast", (0.0, 0.0), (1.0, 0.0))
    with pytest.raises(InvalidParameterError, match="robot"):
        ImpactPlane("arm", (1.0, 0.0))  # type: ignore[arg-type]
    with pytest.raises(InvalidParameterError, match="normal"):
        ImpactPlane(MANIPULATOR_1, (0.0, 0.0))
    with pytest.raises(InvalidParameterError, match="planes"):
        combined_impact([], FOAM_1, HEAD_MIN, (1.0, 0.0), (0.0, 0.0))
    with pytest.raises(InvalidParameterError, match="planes"):
        combined_impact(
            [ImpactPlane(MANIPULATOR_1, (1.0, 0.0, 0.0))], FOAM_1, HEAD_MIN, (1.0, 0.0), (0.0, 0.0)
        )
    with pytest.raises(InvalidParameterError, match="head"):
        combined_impact([ImpactPlane(MANIPULATOR_1, (1.0, 0.0))], FOAM_1, None, (1, 0), (0, 0))
