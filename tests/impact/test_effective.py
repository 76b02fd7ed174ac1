"""Effective manipulator at the impact point (Zeng 2011, Sec. 3.4.3-3.4.4; DECISIONS I6)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from designlab.errors import InvalidParameterError
from designlab.impact.effective import (
    EffectiveContact,
    ImpactPointSweep,
    effective_contact,
    impact_point_sweep,
    scenario_single_joint,
    scenario_two_link,
    single_joint_from_contact,
    two_link_mass_matrix,
)
from designlab.impact.joint import reduced_joint
from designlab.impact.parameters import MANIPULATOR_1, ContactDynamics

# An arm of plausible size for scenario 3 (the thesis gives no link data).
ARM = {"m2": 8.0, "m3": 5.0, "a2": 0.43, "a3": 0.43}
JOINTS = {"k_j2": 9.0e3, "c_j2": 60.0, "k_j3": 4.0e3, "c_j3": 25.0}


# --- scenarios 1 and 2 -------------------------------------------------------------


def test_manipulator_1_mass_from_joint_inertia():
    """Table 3.1: m_11 = 0.059 kg m^2, l_1 = 0.078 m -> 9.70 kg (printed 9.6)."""
    e = scenario_single_joint(0.059, 0.0, 0.0, 0.078)
    assert e.mass == pytest.approx(0.059 / 0.078**2, rel=1e-14)
    assert e.mass == pytest.approx(9.6976, abs=1e-4)
    assert e.mass == pytest.approx(MANIPULATOR_1.mass, rel=0.02)  # +1.0 % vs the table


def test_single_joint_closed_forms():
    """(3.4.17) and (3.4.11)."""
    e = scenario_single_joint(0.059, 121.68, 1.521, 0.078, joint_speed=5.2)
    assert e.stiffness == pytest.approx(20e3, rel=1e-3)
    assert e.damping == pytest.approx(250.0, rel=1e-3)
    assert e.velocity == pytest.approx(5.2 * 0.078)  # Ch. 4: 0.4 m/s
    assert scenario_single_joint(0.059, 1.0, 1.0, 0.078).velocity is None


@pytest.mark.parametrize("arm", [0.05, 0.078, 0.3, 1.0])
def test_single_joint_equals_general_form(arm):
    single = scenario_single_joint(0.2, 500.0, 3.0, arm, joint_speed=-2.0)
    general = effective_contact([[0.2]], [500.0], [3.0], [arm], joint_velocity=[-2.0])
    for field in ("mass", "stiffness", "damping", "velocity"):
        assert getattr(general, field) == pytest.approx(getattr(single, field), rel=1e-14)
    # scalar and matrix forms of the joint parameters agree too
    matrix = effective_contact(np.array([[0.2]]), np.array([[500.0]]), 3.0, [[arm]])
    assert matrix.stiffness == pytest.approx(single.stiffness, rel=1e-14)


def test_single_joint_from_contact_round_trip():
    m11, k_j, c_j = single_joint_from_contact(MANIPULATOR_1)
    assert m11 == pytest.approx(9.6 * 0.078**2)
    e = scenario_single_joint(m11, k_j, c_j, MANIPULATOR_1.lever_arm)
    assert (e.mass, e.stiffness, e.damping) == pytest.approx((9.6, 20e3, 250.0), rel=1e-14)
    with pytest.raises(InvalidParameterError):
        single_joint_from_contact(ContactDynamics(9.6, 20e3, 250.0))


def test_locking_other_joints_raises_effective_mass():
    """Scenario 1/2 use m_ii (others locked) >= 1/(M^-1)_ii (others free)."""
    mass = two_link_mass_matrix(**ARM, theta3=0.3)
    locked = scenario_single_joint(mass[0, 0], 1.0, 1.0, 0.5).mass
    free = effective_contact(mass, [1.0, 1.0], [1.0, 1.0], [0.5, 0.0]).mass
    assert free == pytest.approx(1.0 / (np.linalg.inv(mass)[0, 0] * 0.25), rel=1e-12)
    assert free < locked


# --- scenario 3 ------------------------------------------------------------------


def test_two_link_mass_matrix_textbook_and_printed():
    m2, m3, a2, a3 = ARM.values()
    mass = two_link_mass_matrix(m2, m3, a2, a3, theta3=0.0)
    assert mass[0, 1] == mass[1, 0] == pytest.approx(m3 * a3**2 / 3 + m3 * a2 * a3 / 2)
    assert mass[1, 1] == pytest.approx(m3 * a3**2 / 3)
    assert mass[0, 0] == pytest.approx(m2 * a2**2 / 3 + m3 * a2**2 + m3 * a3**2 / 3 + m3 * a2 * a3)
    printed = two_link_mass_matrix(m2, m3, a2, a3, printed=True)
    assert printed[0, 1] == pytest.approx(m3 * a3**2 / 3 + m3 * a2 * a3)
    np.testing.assert_array_equal(np.diag(printed), np.diag(mass))


def test_textbook_mass_matrix_is_kinetic_energy_of_uniform_rods():
    """q_dot^T M q_dot / 2 equals the rods' kinetic energy by integration."""
    m2, m3, a2, a3 = 2.0, 1.5, 0.6, 0.4
    th2, th3, w2, w3 = 0.2, 0.9, 1.3, -0.7
    s = (np.arange(4000) + 0.5) / 4000  # midpoint rule along each rod
    # link 2: speed of a point at r = s a2 is w2 r
    ke2 = 0.5 * m2 * np.mean((w2 * s * a2) ** 2)
    # link 3: p = a2 e(th2) + r e(th2 + th3)
    vx = -a2 * w2 * np.sin(th2) - s * a3 * (w2 + w3) * np.sin(th2 + th3)
    vy = a2 * w2 * np.cos(th2) + s * a3 * (w2 + w3) * np.cos(th2 + th3)
    ke3 = 0.5 * m3 * np.mean(vx**2 + vy**2)
    qd = np.array([w2, w3])
    mass = two_link_mass_matrix(m2, m3, a2, a3, theta3=th3)
    assert 0.5 * qd @ mass @ qd == pytest.approx(ke2 + ke3, rel=1e-6)
    printed = two_link_mass_matrix(m2, m3, a2, a3, theta3=th3, printed=True)
    assert 0.5 * qd @ printed @ qd != pytest.approx(ke2 + ke3, rel=1e-3)


def test_printed_mass_matrix_can_be_indefinite():
    """Equal links at th3 = 0: det of the printed M_23 is negative."""
    printed = two_link_mass_matrix(1.0, 1.0, 1.0, 1.0, printed=True)
    assert np.linalg.det(printed) < 0
    assert np.linalg.det(two_link_mass_matrix(1.0, 1.0, 1.0, 1.0)) > 0
    with pytest.raises(InvalidParameterError, match="positive definite"):
        scenario_two_link(1.0, 1.0, 1.0, 1.0, 0.5, 1.0, 1.0, 1.0, 1.0, printed=True)


@pytest.mark.parametrize("l3", [0.05, 0.2, 0.43])
def test_scenario_3_closed_forms(l3):
    """(3.4.28), (3.4.29), (3.4.33) and (3.4.23) at the worst case th3 = 0."""
    a2 = ARM["a2"]
    k2, c2, k3, c3 = JOINTS.values()
    e = scenario_two_link(**ARM, l3=l3, **JOINTS, joint_speeds=(0.8, -0.3))
    assert e.stiffness == pytest.approx(k2 * k3 / ((l3 + a2) ** 2 * k3 + l3**2 * k2), rel=1e-13)
    assert e.damping == pytest.approx(c2 * c3 / ((l3 + a2) ** 2 * c3 + l3**2 * c2), rel=1e-13)
    mass = two_link_mass_matrix(**ARM)
    j = np.array([a2 + l3, l3])
    x = np.linalg.solve(mass, j)
    assert e.mass == pytest.approx(1.0 / (j @ x), rel=1e-13)
    assert e.velocity == pytest.approx((a2 + l3) * 0.8 + l3 * (-0.3), rel=1e-14)


def test_scenario_3_general_angle_uses_link_normal():
    """j = n^T J of (3.4.20) with n normal to link 3; independent of theta2."""
    a2, l3, th3 = ARM["a2"], 0.3, 0.7
    for th2 in (0.0, 0.4, -1.1):
        th23 = th2 + th3
        jac = np.array(
            [
                [-l3 * np.sin(th23) - a2 * np.sin(th2), -l3 * np.sin(th23)],
                [l3 * np.cos(th23) + a2 * np.cos(th2), l3 * np.cos(th23)],
            ]
        )
        n = np.array([-np.sin(th23), np.cos(th23)])
        j = n @ jac
        ref = effective_contact(
            two_link_mass_matrix(**ARM, theta3=th3),
            [JOINTS["k_j2"], JOINTS["k_j3"]],
            [JOINTS["c_j2"], JOINTS["c_j3"]],
            j,
        )
        e = scenario_two_link(**ARM, l3=l3, **JOINTS, theta3=th3)
        assert e.mass == pytest.approx(ref.mass, rel=1e-12)
        assert e.stiffness == pytest.approx(ref.stiffness, rel=1e-12)


@pytest.mark.parametrize("l3", [0.1, 0.3, 0.43])
def test_scenario_3_theta3_zero_maximises_m23_not_m_r(l3):
    """Sec. 3.4.4 takes th3 = 0 as the worst case because every element of M_23 is
    largest there. That holds for M_23, but with the link-normal row
    j = [a2 cos th3 + l3, l3] the reduced M_r, K_r and C_r all *grow* with |th3| on
    [0, pi/2] for this arm (e.g. l3 = 0.1 m: M_r 7.1 kg at 0, 30.6 kg at 1.5 rad)."""
    angles = np.linspace(0.0, 1.5, 7)
    mats = [two_link_mass_matrix(**ARM, theta3=th) for th in angles]
    for m in mats[1:]:
        assert np.all(m <= mats[0] + 1e-15)
    results = [scenario_two_link(**ARM, l3=l3, **JOINTS, theta3=th) for th in angles]
    for field in ("mass", "stiffness", "damping"):
        values = np.array([getattr(r, field) for r in results])
        assert np.all(np.diff(values) > 0), field


def test_scenario_3_with_joint_model():
    """Joint values from (3.4.9) feed (3.4.28) unchanged."""
    k2, c2 = reduced_joint(4e4, 20.0, 1.2e4, 80.0)
    k3, c3 = reduced_joint(2e4, 10.0, 5e3, 30.0)
    e = scenario_two_link(**ARM, l3=0.3, k_j2=k2, c_j2=c2, k_j3=k3, c_j3=c3)
    a2, l3 = ARM["a2"], 0.3
    assert e.stiffness == pytest.approx(k2 * k3 / ((l3 + a2) ** 2 * k3 + l3**2 * k2))


def test_scenario_3_rejects_point_off_link():
    with pytest.raises(InvalidParameterError) as info:
        scenario_two_link(**ARM, l3=0.5, **JOINTS)
    assert info.value.name == "l3"


# --- general form: edge cases and validation -------------------------------------------


def test_zero_jacobian_entries_do_not_contribute():
    mass = np.diag([1.0, 2.0, 3.0])
    e = effective_contact(mass, [100.0, 0.0, 50.0], [2.0, 0.0, 1.0], [0.5, 0.0, 0.25])
    assert e.stiffness == pytest.approx(1.0 / (0.25 / 100.0 + 0.0625 / 50.0))
    assert e.damping == pytest.approx(1.0 / (0.25 / 2.0 + 0.0625 / 1.0))
    assert e.mass == pytest.approx(1.0 / (0.25 / 1.0 + 0.0625 / 3.0))


def test_zero_damping_in_contributing_joint_gives_zero():
    e = effective_contact(np.eye(2), [100.0, 100.0], [5.0, 0.0], [1.0, 0.2])
    assert e.damping == 0.0
    assert e.contact.damping == 0.0
    e = effective_contact(np.eye(2), [100.0, 0.0], [5.0, 5.0], [1.0, 0.2])
    assert e.stiffness == 0.0


def test_full_stiffness_matrix():
    k = np.array([[300.0, 50.0], [50.0, 200.0]])
    j = np.array([0.4, 0.1])
    e = effective_contact(np.eye(2), k, np.diag([1.0, 2.0]), j)
    assert e.stiffness == pytest.approx(1.0 / (j @ np.linalg.solve(k, j)), rel=1e-13)
    assert e.damping == pytest.approx(1.0 / (0.16 / 1.0 + 0.01 / 2.0), rel=1e-13)


@pytest.mark.parametrize(
    ("args", "name", "match"),
    [
        (([[1.0, 0.0], [0.0, 1.0]], [1, 1], [1, 1], [0.0, 0.0]), "jacobian_row", "non-zero"),
        (([[1.0, 0.5], [0.4, 1.0]], [1, 1], [1, 1], [1.0, 0.0]), "mass_matrix", "symmetric"),
        (([[1.0, 2.0], [2.0, 1.0]], [1, 1], [1, 1], [1.0, 0.0]), "mass_matrix", "positive"),
        (([[1.0, 0.0, 0.0]], [1], [1], [1.0]), "mass_matrix", "square"),
        ((np.eye(2), [1, 1], [1, 1], [1.0, 0.0, 0.0]), "jacobian_row", "length 2"),
        ((np.eye(2), [1, 1, 1], [1, 1], [1.0, 0.0]), "joint_stiffness", "length 2"),
        ((np.eye(2), [1, -1], [1, 1], [1.0, 0.0]), "joint_stiffness", ">= 0"),
        ((np.eye(2), [1, 1], [[1, 2], [2, 1]], [1.0, 0.0]), "joint_damping", "positive"),
        ((np.eye(2), [1, 1], [1, np.nan], [1.0, 0.0]), "joint_damping", "finite"),
    ],
)
def test_effective_contact_rejects_bad_input(args, name, match):
    with pytest.raises(InvalidParameterError, match=match) as info:
        effective_contact(*args)
    assert info.value.name == name


def test_joint_velocity_shape_is_checked():
    with pytest.raises(InvalidParameterError) as info:
        effective_contact(np.eye(2), [1, 1], [1, 1], [1.0, 0.5], joint_velocity=[1.0])
    assert info.value.name == "joint_velocity"


def test_effective_contact_result_object():
    e = effective_contact(np.eye(2), [100.0, 100.0], [1.0, 1.0], [1.0, 1.0], [2.0, 1.0])
    assert isinstance(e, EffectiveContact)
    assert e.velocity == 3.0
    frame = e.to_frame()
    assert frame.loc[0, "k_r_N_per_m"] == 50.0 and frame.loc[0, "v_r_m_per_s"] == 3.0
    c = e.contact
    assert isinstance(c, ContactDynamics) and (c.mass, c.stiffness, c.damping) == (0.5, 50.0, 0.5)
    with pytest.raises(AttributeError):
        e.mass = 1.0  # type: ignore[misc]
    assert math.isnan(EffectiveContact(1.0, 1.0, 1.0).to_frame().loc[0, "v_r_m_per_s"])


# --- Sec. 3.7.3 sweep ---------------------------------------------------------------


def test_impact_point_sweep_matches_single_joint():
    arms = np.linspace(0.05, 0.6, 12)
    sweep = impact_point_sweep(0.059, 121.68, 1.521, 5.2, arms)
    assert isinstance(sweep, ImpactPointSweep) and len(sweep) == 12
    for i, arm in enumerate(arms):
        e = scenario_single_joint(0.059, 121.68, 1.521, arm, joint_speed=5.2)
        assert sweep.mass[i] == pytest.approx(e.mass, rel=1e-14)
        assert sweep.stiffness[i] == pytest.approx(e.stiffness, rel=1e-14)
        assert sweep.damping[i] == pytest.approx(e.damping, rel=1e-14)
        assert sweep.velocity[i] == pytest.approx(e.velocity, rel=1e-14)
    # near the joint: heavy and stiff but slow (Sec. 2.2)
    assert np.all(np.diff(sweep.mass) < 0) and np.all(np.diff(sweep.velocity) > 0)
    # M_r v_r^2 (kinetic energy) grows only as ... it is constant: m_11 theta_dot^2
    np.testing.assert_allclose(sweep.mass * sweep.velocity**2, 0.059 * 5.2**2, rtol=1e-12)
    frame = sweep.to_frame()
    assert list(frame.columns) == [
        "l_m",
        "m_r_kg",
        "k_r_N_per_m",
        "c_r_N_s_per_m",
        "v_r_m_per_s",
    ]
    contacts = sweep.contacts()
    assert contacts[0].lever_arm == pytest.approx(0.05)
    with pytest.raises(ValueError):
        sweep.mass[0] = 1.0


def test_impact_point_sweep_rejects_bad_arms():
    with pytest.raises(InvalidParameterError) as info:
        impact_point_sweep(0.059, 1.0, 1.0, 5.2, [0.1, 0.0])
    assert (info.value.name, info.value.value) == ("lever_arms[1]", 0.0)
    with pytest.raises(InvalidParameterError):
        impact_point_sweep(0.059, 1.0, 1.0, 5.2, [])


# --- invariants (hypothesis) ---------------------------------------------------------


@st.composite
def _spd_and_row(draw):
    n = draw(st.integers(2, 3))
    elems = st.floats(-2.0, 2.0, allow_nan=False)
    a = draw(arrays(np.float64, (n, n), elements=elems))
    diag = draw(arrays(np.float64, (n,), elements=st.floats(0.05, 3.0)))
    mass = a @ a.T + np.diag(diag)
    j = draw(arrays(np.float64, (n,), elements=st.floats(-1.5, 1.5, allow_nan=False)))
    # keep at least one clearly contributing joint; allow exact zeros elsewhere
    k = draw(st.integers(0, n - 1))
    if abs(j[k]) < 1e-2:
        j[k] = 0.5
    j[np.abs(j) < 1e-3] = 0.0
    stiff = draw(arrays(np.float64, (n,), elements=st.floats(1.0, 1e5)))
    damp = draw(arrays(np.float64, (n,), elements=st.floats(0.01, 1e3)))
    return mass, j, stiff, damp


@settings(max_examples=150, deadline=None)
@given(_spd_and_row())
def test_effective_mass_bounds(case):
    """0 < M_r, Rayleigh bounds, and Cauchy-Schwarz M_r <= (j M j^T)/|j|^4."""
    mass, j, stiff, damp = case
    e = effective_contact(mass, stiff, damp, j)
    jj = j @ j
    lam = np.linalg.eigvalsh(mass)
    assert e.mass > 0
    assert lam[0] / jj * (1 - 1e-9) <= e.mass <= lam[-1] / jj * (1 + 1e-9)
    assert e.mass <= (j @ mass @ j) / jj**2 * (1 + 1e-9)


@settings(max_examples=150, deadline=None)
@given(_spd_and_row())
def test_series_combination(case):
    """K_r, C_r <= min_i K_i/j_i^2 over contributing joints, and >= that min / count."""
    mass, j, stiff, damp = case
    e = effective_contact(mass, stiff, damp, j)
    active = j != 0.0
    for value, diag in ((e.stiffness, stiff), (e.damping, damp)):
        per_joint = diag[active] / j[active] ** 2
        assert value <= per_joint.min() * (1 + 1e-12)
        assert value >= per_joint.min() / active.sum() * (1 - 1e-12)
        # a series chain: 1/K_r is the sum of the per-joint compliances
        assert 1.0 / value == pytest.approx(np.sum(1.0 / per_joint), rel=1e-12)


@settings(max_examples=100, deadline=None)
@given(_spd_and_row(), st.floats(0.1, 10.0))
def test_scaling_of_jacobian_row(case, factor):
    """Moving the impact point by scaling j divides M_r, K_r, C_r by factor^2."""
    mass, j, stiff, damp = case
    e1 = effective_contact(mass, stiff, damp, j)
    e2 = effective_contact(mass, stiff, damp, factor * j)
    assert e2.mass == pytest.approx(e1.mass / factor**2, rel=1e-9)
    assert e2.stiffness == pytest.approx(e1.stiffness / factor**2, rel=1e-9)
    assert e2.damping == pytest.approx(e1.damping / factor**2, rel=1e-9)


def test_single_joint_bound_does_not_hold_in_general():
    """M_r <= 1/(j_i^2 (M^-1)_ii) is *not* an invariant: inertial coupling can make
    the multi-joint M_r larger than any single-joint term (here 5x)."""
    inv = np.array([[1.0, 0.9], [0.9, 1.0]])
    e = effective_contact(np.linalg.inv(inv), [1.0, 1.0], [1.0, 1.0], [1.0, -1.0])
    assert e.mass == pytest.approx(5.0)
    assert e.mass > 1.0 / (1.0 * inv[0, 0])
