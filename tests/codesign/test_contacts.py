"""Contact speeds from navigation runs (issue 24, item 2): exact encounters and the distribution."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as hst

import designlab.navigation as nav
from designlab.codesign import ContactSpeeds, contact_speeds, navigation_contacts
from designlab.errors import DesignlabError

ROBOT_SPEED = nav.HolonomicRobot().max_speed  # the robot cruises at V_mr on a clear line


def _passing(offset: float, v_obs: float) -> nav.Scenario:
    """A robot driving straight along y = 0.6 towards -x and a disc walking along +x,
    ``offset`` m to the side (outside its active region, so the robot never swerves)."""
    t_cross = 3.0 / ROBOT_SPEED + 0.1  # the robot reaches x = 3 at about this time
    human = nav.Disc(
        "human", 0.3, r2=0.8, r3=0.6,
        motion=nav.ConstantVelocity((3.0 - v_obs * t_cross, 0.6 + offset), (v_obs, 0.0)),
    )  # fmt: skip
    return nav.Scenario("pass", start=(6.0, 0.6), goal=(0.0, 0.6), obstacles=(human,))


@pytest.mark.parametrize(("offset", "v_obs"), [(3.0, 0.3), (2.0, 0.0), (-2.5, 0.5)])
def test_closest_approach_of_a_straight_pass_is_exact(offset: float, v_obs: float) -> None:
    # Robot on a straight line at V_mr, obstacle at constant velocity on a parallel line:
    # closest approach at the lateral offset, relative speed V_mr + v_obs, normal speed 0.
    s = contact_speeds(nav.simulate(_passing(offset, v_obs), nav.EXPERIMENT_GAINS))
    assert s.status == "ok" and len(s) == 1 and not s.contact[0]
    assert s.distance[0] == pytest.approx(abs(offset), abs=1e-6)
    assert s.surface_distance[0] == pytest.approx(abs(offset) - 0.3 - 0.2, abs=1e-6)
    assert s.relative_speed[0] == pytest.approx(ROBOT_SPEED + v_obs, abs=1e-9)
    assert s.robot_speed[0] == pytest.approx(ROBOT_SPEED, abs=1e-9)
    assert s.obstacle_speed[0] == pytest.approx(v_obs, abs=1e-12)
    assert abs(s.normal_speed[0]) < 1e-3 * (ROBOT_SPEED + v_obs)
    assert s.angle[0] == pytest.approx(math.pi / 2, abs=1e-3)
    assert s.approach_speed[0] == 0.0  # never inside the active region
    assert float(np.asarray(s)[0]) == pytest.approx(ROBOT_SPEED + v_obs)


def test_contact_is_the_first_touch() -> None:
    # A disc running head-on at the robot faster than the robot can back away: a contact.
    # At the first touch the surface distance is within one dynamics step of zero and the
    # normal closing speed is the rate at which the gap closes there.
    runner = nav.Disc(
        "runner", 0.3, r2=0.9, r3=0.6, motion=nav.ConstantVelocity((-1.0, 0.6), (3.0, 0.0))
    )
    sc = nav.Scenario("hit", start=(4.0, 0.6), goal=(0.0, 0.6), obstacles=(runner,), horizon=5.0)
    run = nav.simulate(sc, nav.EXPERIMENT_GAINS)
    assert run.collided
    s = contact_speeds(run, measure="normal")
    assert s.contact[0] and s.n_contacts == 1
    step = float(run.t[1] - run.t[0])
    assert -s.relative_speed[0] * step <= s.surface_distance[0] <= 0.0
    assert 0.0 < s.normal_speed[0] <= s.relative_speed[0] + 1e-12
    assert s.samples[0] == s.normal_speed[0]
    assert s.approach_speed[0] >= s.normal_speed[0] - 1e-9
    i = int(np.searchsorted(run.t, s.time[0]))
    p, _, _ = runner.state(run.t[i - 1 : i + 1])
    gap = np.hypot(*(run.position[i - 1 : i + 1] - p).T) - 0.5
    assert gap[0] > 0.0 >= gap[1]  # the step before did not touch
    assert any("contact" in w for w in s.warnings)


def test_configurations_meet_their_discs_only() -> None:
    scenarios = [nav.configuration(i) for i in (3, 4)]
    s = navigation_contacts(scenarios, nav.EXPERIMENT_GAINS)
    assert s.obstacle == ("circle", "circle", "human")  # the rectangles are not people
    only = navigation_contacts(scenarios, nav.EXPERIMENT_GAINS, obstacles="human")
    assert only.obstacle == ("human",) and only.scenario == ("ch6_config4",)
    frame = s.to_frame()
    assert len(frame) == 3 and {"v_rel_m_per_s", "angle_rad", "contact"} <= set(frame.columns)
    np.testing.assert_allclose(frame["v_rel_m_per_s"], s.relative_speed)


def _speeds(samples: np.ndarray) -> ContactSpeeds:
    n = samples.size
    z = np.zeros(n)
    return ContactSpeeds(
        ("s",) * n, ("o",) * n, np.zeros(n, bool), z, z + 1, z + 0.5, samples, z, z, z, z, z
    )


@settings(max_examples=40, deadline=None)
@given(
    hst.lists(hst.floats(0, 5, allow_nan=False), min_size=1, max_size=30),
    hst.floats(-1, 6, allow_nan=False),
)
def test_empirical_distribution_against_brute_force(values: list[float], x: float) -> None:
    s = _speeds(np.array(values))
    v = np.array(values)
    assert s.cdf(x) == pytest.approx(np.mean(v <= x))
    assert s.sf(x) == pytest.approx(np.mean(v > x))
    assert s.mean() == pytest.approx(v.mean())
    assert s.support() == (v.min(), v.max())
    q = s.ppf(0.5)
    assert np.mean(v <= q) >= 0.5 and np.mean(v < q) < 0.5
    draws = s.rvs(size=50, random_state=1)
    assert set(np.round(draws, 12)) <= set(np.round(v, 12))
    h = s.histogram()
    assert h.cdf(v.min() - 1e-9) == 0.0 and h.cdf(v.max() + 1e-5) == pytest.approx(1.0)


def test_bad_input_names_the_parameter() -> None:
    run = nav.simulate(nav.configuration(1), nav.EXPERIMENT_GAINS)
    with pytest.raises(DesignlabError, match="measure"):
        contact_speeds(run, measure="fast")
    with pytest.raises(DesignlabError, match="runs"):
        contact_speeds("run")  # type: ignore[arg-type]
    with pytest.raises(DesignlabError, match="runs"):
        contact_speeds([run, 3])  # type: ignore[list-item]
    with pytest.raises(DesignlabError, match="obstacles"):
        contact_speeds(run, obstacles=[])
    with pytest.raises(DesignlabError, match="scenarios"):
        navigation_contacts([], nav.EXPERIMENT_GAINS)
    with pytest.raises(DesignlabError, match="measure"):
        ContactSpeeds((), (), *([np.zeros(0)] * 10), measure="speedy")  # type: ignore[arg-type]
    with pytest.raises(DesignlabError, match=r"obstacles = \['nobody'\].*\['circle'\]"):
        contact_speeds(run, obstacles="nobody")  # a name no run has: refused (issue 41)
    alone = nav.simulate(nav.configuration(1).without_obstacles(), nav.EXPERIMENT_GAINS)
    empty = contact_speeds(alone)
    assert empty.status == "empty" and len(empty) == 0
    with pytest.raises(DesignlabError, match="closing_speed"):
        empty.rvs(3)
