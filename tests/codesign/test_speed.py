"""Speed limit from safety: exact answers from the linear scaling of the metrics.

Every peak metric of the linear impact model scales exactly with the closing
speed (acceleration, force, compression ~ v; HIC ~ v^2.5), so the closing speed a
criterion allows is ``(limit / metric(1 m/s)) ** (1/e)`` at the worst head. The
tests compute the metrics at 1 m/s here, head by head, with
``dl.impact.impact_metrics`` (and the HIC with the criterion itself), take the
worst head of the same grid, and compare.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.codesign import SafetyCase
from designlab.codesign.braking import contact_speed, max_robot_speed, stopping_distance
from designlab.impact import (
    FOAM_1,
    MANIPULATOR_1,
    THESIS_HEAD_RANGE,
    CompressionLimit,
    ContactDynamics,
    Foam,
    HeadAcceleration,
    HeadInjuryCriterion,
    HeadRange,
    ImpactForce,
    IsoTransientForce,
    LinkImpact,
)

G = 9.80665


def _grid_metric(robot, foam, head_range, levels, key):
    """The largest metric of ``key`` at v_c = 1 m/s over the head grid (independent path)."""
    heads = head_range.grid(levels)
    if isinstance(key, HeadInjuryCriterion):
        p = np.array(
            [
                [robot.mass, robot.damping, robot.stiffness, foam.stiffness, foam.damping,
                 h.mass, h.damping, h.stiffness]
                for h in heads
            ]
        )  # fmt: skip
        return float(np.max(key.values(p, np.ones(len(heads)))))
    m = dl.impact.impact_metrics(
        {
            "M_r": robot.mass, "C_r": robot.damping, "K_r": robot.stiffness,
            "K_c": foam.stiffness, "C_c": foam.damping,
            "M_h": np.array([h.mass for h in heads]),
            "C_h": np.array([h.damping for h in heads]),
            "K_h": np.array([h.stiffness for h in heads]),
        },
        1.0,
    )  # fmt: skip
    attr = {
        "head_acceleration": "peak_head_acceleration",
        "force": "peak_force",
        "compression": "max_compression",
    }[key.metric]
    return float(np.max(getattr(m, attr)))


def _expected(robot, foam, criteria, head_range, levels):
    keys = [*criteria, CompressionLimit(foam.linear_depth)]
    per = {
        k.name: (k.limit / _grid_metric(robot, foam, head_range, levels, k))
        ** (1 / k.velocity_exponent)
        for k in keys
    }
    return per


designs = st.fixed_dictionaries(
    {
        "m_r": st.floats(3.0, 60.0),
        "k_r": st.floats(5e3, 5e4),
        "c_r": st.floats(50.0, 400.0),
        "k_c": st.floats(5e3, 8e4),
        "xi": st.floats(0.05, 0.3),
        "v_h": st.floats(0.0, 1.0),
    }
)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(designs)
def test_limit_is_limit_over_unit_metric_at_worst_head(d):
    robot = ContactDynamics(mass=d["m_r"], stiffness=d["k_r"], damping=d["c_r"])
    foam = Foam.from_damping_ratio(d["k_c"], d["xi"])
    criteria = [HeadAcceleration(10), ImpactForce(660), HeadInjuryCriterion(650)]
    s = dl.codesign.speed_limit(
        robot, foam, SafetyCase(criteria, human_speed=d["v_h"]), refine=False
    )
    per = _expected(robot, foam, criteria, THESIS_HEAD_RANGE, 3)
    assert set(per) == set(s.per_criterion)
    for name, v in per.items():
        assert s.per_criterion[name] == pytest.approx(v, rel=1e-9)
    limiting = min(per, key=per.get)
    assert s.limiting_criterion == limiting
    assert s.closing_speed == pytest.approx(per[limiting], rel=1e-9)
    # the Sec. 3.4 split: v_c = v_r + v_h, and without braking the limit is v_r
    assert s.robot_speed + s.head_speed == pytest.approx(s.closing_speed, rel=1e-12)
    assert s.max_speed == pytest.approx(max(per[limiting] - d["v_h"], 0.0), rel=1e-9, abs=1e-12)


def test_metric_at_the_limit_equals_the_limit_at_the_worst_head():
    """At the limit the worst head's metric, simulated in the time domain, is the limit."""
    crit = [HeadAcceleration(10)]
    s = dl.codesign.speed_limit(MANIPULATOR_1, FOAM_1, SafetyCase(crit, human_speed=0.0))
    name = crit[0].name
    head = s.worst_heads[name]
    v = s.per_criterion[name]
    r = dl.impact.simulate(MANIPULATOR_1, FOAM_1, head, impact_velocity=v, samples=20001)
    assert r.peak_head_acceleration_g == pytest.approx(10.0, rel=2e-3)
    assert head.mass == THESIS_HEAD_RANGE.mass[0]  # the light head is the worst for a_h


def test_hic_scales_as_power_two_and_a_half():
    key = HeadInjuryCriterion(650)
    s = dl.codesign.speed_limit(MANIPULATOR_1, FOAM_1, SafetyCase([key], human_speed=0.0))
    v = s.per_criterion[key.name]
    m1 = s.unit_metric[key.name]
    assert v == pytest.approx((650 / m1) ** 0.4, rel=1e-12)
    head = s.worst_heads[key.name]
    p = np.array([[9.6, 250, 20e3, FOAM_1.stiffness, FOAM_1.damping,
                   head.mass, head.damping, head.stiffness]])  # fmt: skip
    assert key.values(p, np.array([v]))[0] == pytest.approx(650.0, rel=1e-3)


def test_head_levels_and_a_narrow_range():
    one = HeadRange(mass=(4.4, 4.4), stiffness=(3e3, 3e3), damping=(46.0, 46.0))
    s = dl.codesign.speed_limit(MANIPULATOR_1, FOAM_1, SafetyCase(head_range=one, human_speed=0.0))
    assert s.worst_heads[HeadAcceleration(10).name].mass == 4.4
    expected = _expected(MANIPULATOR_1, FOAM_1, [HeadAcceleration(10)], one, 2)
    assert s.per_criterion == pytest.approx(expected, rel=1e-9)
    fine = dl.codesign.speed_limit(MANIPULATOR_1, FOAM_1, SafetyCase(head_levels=5), refine=False)
    coarse = dl.codesign.speed_limit(MANIPULATOR_1, FOAM_1, SafetyCase(head_levels=2), refine=False)
    # a finer grid contains the corners: it can only find a worse head
    assert fine.closing_speed <= coarse.closing_speed * (1 + 1e-12)


def test_iso_transient_factor_is_stated_and_limits():
    iso = IsoTransientForce("skull_forehead", transient_factor=2.0)
    s = dl.codesign.speed_limit(MANIPULATOR_1, FOAM_1, SafetyCase([iso], human_speed=0.0))
    assert s.limiting_criterion == iso.name and "260 N" in iso.name
    assert s.per_criterion[iso.name] == pytest.approx(260.0 / s.unit_metric[iso.name], rel=1e-12)
    frame = s.to_frame()
    assert list(frame["criterion"]) == list(s.per_criterion)
    assert frame["limiting"].sum() == 1


def test_unsafe_at_rest():
    iso = IsoTransientForce("skull_forehead", transient_factor=1.0)  # 130 N
    s = dl.codesign.speed_limit(MANIPULATOR_1, FOAM_1, SafetyCase([iso], human_speed=1.0))
    assert s.status == "unsafe_at_rest" and s.max_speed == 0.0 and s.warnings


def test_refined_worst_head_beats_the_grid_and_random_heads():
    """A strongly damped foam whose largest compression lies inside the head range."""
    robot = ContactDynamics(mass=9.57, stiffness=30.7e3, damping=221.3)
    foam = Foam(52.4e3, 450.3, 0.02)
    key = CompressionLimit(0.02)
    grid = dl.codesign.speed_limit(robot, foam, SafetyCase(human_speed=0.0), refine=False)
    best = dl.codesign.speed_limit(robot, foam, SafetyCase(human_speed=0.0))
    assert best.unit_metric[key.name] > grid.unit_metric[key.name] * (1 + 1e-4)
    assert best.per_criterion[key.name] < grid.per_criterion[key.name]
    heads = THESIS_HEAD_RANGE.sample(2000, np.random.default_rng(0))
    n = len(heads)
    m = dl.impact.impact_metrics(
        {"M_r": robot.mass, "C_r": robot.damping, "K_r": robot.stiffness, "K_c": foam.stiffness,
         "C_c": foam.damping, "M_h": heads[:, 0], "C_h": heads[:, 1], "K_h": heads[:, 2]},
        np.ones(n),
    )  # fmt: skip
    assert np.nanmax(m.max_compression) <= best.unit_metric[key.name] * (1 + 1e-9)
    h = best.worst_heads[key.name]
    one = dl.impact.impact_metrics(
        {"M_r": robot.mass, "C_r": robot.damping, "K_r": robot.stiffness, "K_c": foam.stiffness,
         "C_c": foam.damping, "M_h": h.mass, "C_h": h.damping, "K_h": h.stiffness},
        best.per_criterion[key.name],
    )  # fmt: skip
    assert float(one.max_compression[0]) == pytest.approx(0.02, rel=1e-9)


# --- braking (reaction time) --------------------------------------------------------


@settings(max_examples=60, deadline=None)
@given(
    u=st.floats(0.01, 3.0),
    v_h=st.floats(0.0, 1.5),
    t_r=st.floats(0.0, 0.5),
    a=st.floats(0.5, 20.0),
    d=st.floats(0.0, 3.0),
)
def test_max_robot_speed_inverts_contact_speed(u, v_h, t_r, a, d):
    v = max_robot_speed(u, human_speed=v_h, reaction_time=t_r, deceleration=a,
                        detection_distance=d)  # fmt: skip
    assert v >= u
    assert contact_speed(v, v_h, t_r, a, d) == pytest.approx(u, rel=1e-6, abs=1e-9) or v == u
    assert contact_speed(v * 1.001 + 1e-6, v_h, t_r, a, d) > u * (1 - 1e-9)


def test_braking_without_warning_is_the_contact_limit():
    assert max_robot_speed(0.7, human_speed=1.0, reaction_time=0.2, deceleration=3.0,
                           detection_distance=0.0) == 0.7  # fmt: skip
    assert stopping_distance(1.0, 0.1, 5.0) == pytest.approx(0.1 + 0.1)


def test_speed_limit_with_detection_distance():
    s0 = dl.codesign.speed_limit(MANIPULATOR_1, FOAM_1)
    s = dl.codesign.speed_limit(MANIPULATOR_1, FOAM_1, SafetyCase(
        reaction_time=0.06, deceleration=5.0, detection_distance=0.5))  # fmt: skip
    assert s.robot_speed == pytest.approx(s0.robot_speed)
    assert s.max_speed > s0.max_speed
    cs = contact_speed(s.max_speed, 1.0, 0.06, 5.0, 0.5)
    assert cs == pytest.approx(s0.robot_speed, rel=1e-9)
    assert s.stopping_distance == pytest.approx(s.max_speed * 0.06 + s.max_speed**2 / 10.0)


# --- a link struck anywhere ----------------------------------------------------------


def _link_metric(link, lever, head, v_c, attr):
    m = dl.impact.impact_metrics(
        {"M_r": link.inertia / lever**2, "C_r": link.joint_damping / lever**2,
         "K_r": link.joint_stiffness / lever**2, "K_c": FOAM_1.stiffness, "C_c": FOAM_1.damping,
         "M_h": head.mass, "C_h": head.damping, "K_h": head.stiffness},
        v_c,
    )  # fmt: skip
    return float(getattr(m, attr)[0])


def test_link_limit_meets_the_limit_at_the_worst_point():
    link = LinkImpact.from_contact(MANIPULATOR_1, joint_speed=1.0, lever_arm_min=0.02,
                                   lever_arm_max=0.078)  # fmt: skip
    s = dl.codesign.speed_limit(link, FOAM_1, SafetyCase([HeadAcceleration(10)], human_speed=1.0))
    name = s.limiting_criterion
    assert name == "eps_max <= 20 mm"
    omega, lever = s.joint_speed, s.worst_lever_arm[name]
    assert s.max_speed == pytest.approx(omega * 0.078)
    head = s.worst_heads[name]
    v_c = omega * lever + 1.0
    assert s.per_criterion[name] == pytest.approx(v_c)
    assert _link_metric(link, lever, head, v_c, "max_compression") == pytest.approx(0.02, rel=1e-6)
    # any other point of the link, at that joint speed, stays within every limit
    a_name = HeadAcceleration(10).name
    for lev in np.linspace(0.02, 0.078, 7):
        v = omega * lev + 1.0
        eps = _link_metric(link, lev, head, v, "max_compression")
        acc = _link_metric(link, lev, s.worst_heads[a_name], v, "peak_head_acceleration")
        assert eps <= 0.02 * (1 + 1e-6) and acc <= HeadAcceleration(10).limit


# --- the map ---------------------------------------------------------------------------


def test_map_equals_speed_limit_per_foam():
    ks, cs = np.array([12e3, 30e3, 70e3]), np.array([20.0, 90.0])
    crit = [HeadAcceleration(10), ImpactForce(660)]
    m = dl.codesign.speed_limit_map(MANIPULATOR_1, K_c=ks, C_c=cs, linear_depth=0.02,
                                    case=SafetyCase(crit, human_speed=0.5))  # fmt: skip
    assert m.max_speed.shape == (3, 2)
    frame = m.to_frame()
    assert len(frame) == 6
    for i, k in enumerate(ks):
        for j, c in enumerate(cs):
            s = dl.codesign.speed_limit(
                MANIPULATOR_1, Foam(k, c, 0.02), SafetyCase(crit, human_speed=0.5)
            )
            assert m.max_speed[i, j] == pytest.approx(s.max_speed, rel=1e-9, abs=1e-12)
            assert m.criteria[m.limiting[i, j]] == s.limiting_criterion
    # a stiffer foam at the same damping is never faster-safe for the head acceleration
    a = m.per_criterion[crit[0].name]
    assert np.all(np.diff(a, axis=0) <= 1e-9)
    assert math.isclose(frame["K_c_N_per_m"].iloc[0], 12e3)


def test_reaction_time_without_detection_distance_is_stated():
    s = dl.codesign.speed_limit(MANIPULATOR_1, FOAM_1, SafetyCase(reaction_time=0.1))
    assert s.max_speed == pytest.approx(s.robot_speed)
    assert any("reaction_time has no effect" in w for w in s.warnings)
    m = dl.codesign.speed_limit_map(
        MANIPULATOR_1, K_c=[2e4], C_c=[50.0], case=SafetyCase(reaction_time=0.1)
    )
    assert any("reaction_time has no effect" in w for w in m.warnings)
