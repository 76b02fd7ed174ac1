"""Injury probability: closed-form cases and the two estimators against each other.

With one head the threshold speed v* of a criterion is exact (the metrics scale with
v_c), so P(exceeded | contact) = P(v_c > v*) / P(v_c > 0) from the speed
distribution's survival function. Tolerances are several standard errors and the
seeds are fixed: the tests cannot flake.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy import stats

import designlab as dl
from designlab.codesign import SafetyCase
from designlab.impact import (
    FOAM_1,
    HEAD_MIN,
    MANIPULATOR_1,
    THESIS_HEAD_RANGE,
    HeadAcceleration,
    HeadInjuryCriterion,
    HeadRange,
    ImpactForce,
    LinkImpact,
)


def _threshold(head, key):
    one = HeadRange(mass=(head.mass,) * 2, stiffness=(head.stiffness,) * 2,
                    damping=(head.damping,) * 2)  # fmt: skip
    s = dl.codesign.speed_limit(
        MANIPULATOR_1, FOAM_1, SafetyCase([key], head_range=one, human_speed=0.0)
    )
    return s.per_criterion[key.name]


@pytest.mark.parametrize("key", [HeadAcceleration(10), ImpactForce(660), HeadInjuryCriterion(650)])
def test_fixed_head_closed_form(key):
    dist = stats.lognorm(s=0.5, scale=1.0)
    v_star = _threshold(HEAD_MIN, key)
    exact = float(dist.sf(v_star))  # all the mass is at v_c > 0
    imp = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, dist, heads=HEAD_MIN,
                                         criterion=key, samples=1000, seed=1)  # fmt: skip
    assert imp.probability == pytest.approx(exact, rel=1e-9)
    assert imp.standard_error == pytest.approx(0.0, abs=1e-15)
    crude = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, dist, heads=HEAD_MIN,
                                           criterion=key, samples=20_000, method="crude",
                                           seed=2)  # fmt: skip
    se = np.sqrt(exact * (1 - exact) / 20_000)
    assert abs(crude.probability - exact) < 5 * se + 1e-12
    assert crude.interval[0] <= crude.probability <= crude.interval[1]


def test_contact_conditioning_and_samples_input():
    """Samples at v_c <= 0 are no contact: left out, and the share reported."""
    key = HeadAcceleration(10)
    v_star = _threshold(HEAD_MIN, key)
    speeds = np.array([-0.5, 0.0, 0.3, 0.5 * v_star, 1.1 * v_star, 2 * v_star])
    imp = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, speeds, heads=HEAD_MIN,
                                         samples=100)  # fmt: skip
    assert imp.probability == pytest.approx(2 / 4)
    assert imp.contact_fraction == pytest.approx(4 / 6)
    assert any("conditional on a contact" in w for w in imp.warnings)
    dist = stats.norm(0.5, 1.0)
    imp = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, dist, heads=HEAD_MIN,
                                         samples=100)  # fmt: skip
    assert imp.probability == pytest.approx(dist.sf(v_star) / dist.sf(0.0), rel=1e-9)


def test_crude_and_importance_agree_over_the_thesis_range():
    dist = stats.rayleigh(scale=1.0)
    kw = dict(closing_speed=dist, heads=THESIS_HEAD_RANGE, samples=40_000)
    imp = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, **kw, seed=3)
    crude = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, **kw, method="crude", seed=4)
    se = np.hypot(imp.standard_error, crude.standard_error)
    assert abs(imp.probability - crude.probability) < 5 * se
    assert imp.standard_error < crude.standard_error / 3  # the point of importance sampling
    # bounded by the best and the worst head of the range (uniform heads)
    lo = dist.sf(dl.codesign.speed_limit(MANIPULATOR_1, FOAM_1, SafetyCase(
        criteria=[HeadAcceleration(10)], human_speed=0.0)).per_criterion[
        HeadAcceleration(10).name])  # fmt: skip
    assert imp.probability <= lo + 1e-12
    assert list(imp.to_frame().columns)[:3] == ["criterion", "method", "probability"]


def test_small_probability_importance_resolves_it():
    dist = stats.truncnorm(-4.0, np.inf, loc=0.6, scale=0.1)  # contacts mostly slow
    imp = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, dist, samples=5000, seed=5)
    crude = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, dist, samples=5000,
                                           method="crude", seed=5)  # fmt: skip
    assert 0 < imp.probability < 1e-15
    assert imp.interval[1] < 1e-14
    assert crude.failed_samples == 0 and crude.status == "unresolved"
    assert crude.interval[1] > imp.interval[1]


def test_seeded_and_reproducible():
    dist = stats.rayleigh(scale=1.2)
    a = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, dist, samples=3000, seed=7)
    b = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, dist, samples=3000, seed=7)
    assert a.probability == b.probability


def test_population_with_scipy_distributions():
    pop = dl.codesign.HeadPopulation(
        mass=stats.truncnorm(-2, 2, loc=4.85, scale=0.2),
        stiffness=stats.uniform(3e3, 2e3),
        damping=80.0,
    )
    x = pop.sample(1000, np.random.default_rng(0))
    assert x.shape == (1000, 3) and np.all(x[:, 1] == 80.0)
    assert np.all((x[:, 0] > 4.4) & (x[:, 0] < 5.3))
    risk = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, stats.rayleigh(scale=1.0),
                                          heads=pop, samples=2000)  # fmt: skip
    assert 0 < risk.probability < 1


def test_link_with_impact_points():
    link = LinkImpact.from_contact(MANIPULATOR_1, joint_speed=1.0, lever_arm_min=0.078,
                                   lever_arm_max=0.078)  # fmt: skip
    dist = stats.rayleigh(scale=1.0)
    at_one = dl.codesign.injury_probability(link, FOAM_1, dist, heads=HEAD_MIN, samples=200)
    fixed = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, dist, heads=HEAD_MIN,
                                           samples=200)  # fmt: skip
    assert at_one.probability == pytest.approx(fixed.probability, rel=1e-9)
    wide = LinkImpact.from_contact(MANIPULATOR_1, joint_speed=1.0, lever_arm_min=0.02,
                                   lever_arm_max=0.078)  # fmt: skip
    r = dl.codesign.injury_probability(wide, FOAM_1, dist, heads=HEAD_MIN, samples=4000,
                                       points=stats.uniform(0.05, 0.028))  # fmt: skip
    assert 0 < r.probability < 1


def test_progress_is_reported():
    seen = []
    dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, stats.rayleigh(), samples=100,
                                   progress=seen.append)  # fmt: skip
    assert seen and seen[-1].step == seen[-1].total


# --- fragility curve -----------------------------------------------------------------


def test_fragility_is_the_threshold_cdf_and_matches_injury_probability():
    """P(exceeded | v) from the curve equals injury_probability at a one-value speed input."""
    speeds = [1.9, 2.1, 2.3, 2.5]
    curve = dl.codesign.fragility_curve(MANIPULATOR_1, FOAM_1, speeds, samples=3000, seed=9)
    for v, p in zip(speeds, curve.probability, strict=True):
        r = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, np.array([v]), samples=3000,
                                           seed=9)  # fmt: skip
        assert p == pytest.approx(r.probability, abs=1e-12)
    assert np.all(np.diff(curve.probability) >= 0)
    assert np.all(curve.low <= curve.probability) and np.all(curve.probability <= curve.high)
    # below the worst head's threshold no head exceeds: the speed limit's answer
    s = dl.codesign.speed_limit(
        MANIPULATOR_1, FOAM_1, SafetyCase([HeadAcceleration(10)], human_speed=0.0)
    )
    assert curve.thresholds.min() >= s.per_criterion[HeadAcceleration(10).name] * (1 - 1e-9)
    assert len(curve.to_frame()) == 4


def test_fragility_of_one_head_is_a_step():
    key = HeadAcceleration(10)
    v_star = _threshold(HEAD_MIN, key)
    curve = dl.codesign.fragility_curve(MANIPULATOR_1, FOAM_1, [0.99 * v_star, 1.01 * v_star],
                                        heads=HEAD_MIN, samples=100)  # fmt: skip
    assert list(curve.probability) == [0.0, 1.0]
    assert curve.speed_at(0.5) == pytest.approx(v_star, rel=1e-9)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    m_r=st.floats(3.0, 60.0),
    k_c=st.floats(5e3, 8e4),
    xi=st.floats(0.05, 0.3),
    m_h=st.floats(4.4, 5.3),
    k_h=st.floats(3e3, 5e3),
    c_h=st.floats(46.0, 130.2),
    sigma=st.floats(0.2, 1.0),
    scale=st.floats(0.3, 3.0),
)
def test_closed_form_over_random_designs(m_r, k_c, xi, m_h, k_h, c_h, sigma, scale):
    """One head: P = P(v_c > v*) with v* = limit / a_h,max(1 m/s) computed here."""
    robot = dl.impact.ContactDynamics(mass=m_r, stiffness=20e3, damping=250.0)
    foam = dl.impact.Foam.from_damping_ratio(k_c, xi)
    head = dl.impact.HeadNeck(m_h, k_h, c_h)
    m = dl.impact.impact_metrics(
        {"M_r": m_r, "C_r": 250.0, "K_r": 20e3, "K_c": foam.stiffness, "C_c": foam.damping,
         "M_h": m_h, "C_h": c_h, "K_h": k_h},
        1.0,
        with_force=False,
    )  # fmt: skip
    v_star = HeadAcceleration(10).limit / float(m.peak_head_acceleration[0])
    dist = stats.lognorm(s=sigma, scale=scale)
    r = dl.codesign.injury_probability(robot, foam, dist, heads=head, samples=50)
    assert r.probability == pytest.approx(float(dist.sf(v_star)), rel=1e-9, abs=1e-300)


@settings(max_examples=40, deadline=None)
@given(w=st.floats(1e-12, 1.0), n=st.integers(2, 3000), seed=st.integers(0, 2**31))
def test_importance_standard_error_is_stable(w, n, seed):
    """Equal weights have a standard error of exactly 0 (no cancellation in the one-pass
    variance); random weights give numpy's ``std(ddof=1) / sqrt(n)``, over several blocks."""
    from designlab.codesign.risk import ImportanceEstimator, _Tally

    class Fixed:
        def __init__(self, values):
            self.values = values

        def sf(self, thresholds):
            return self.values[: thresholds.size]

    est = ImportanceEstimator()
    tally = _Tally()
    est.add(tally, np.zeros(n), Fixed(np.full(n, w)), np.random.default_rng(0))
    p, _, se = est.finish(tally, 0.95)
    assert se == 0.0 and p == pytest.approx(w, rel=1e-12)
    ws = np.random.default_rng(seed).uniform(0.0, w, n)
    tally = _Tally()
    for block in np.array_split(ws, 3):
        est.add(tally, np.zeros(block.size), Fixed(block), np.random.default_rng(0))
    p, _, se = est.finish(tally, 0.95)
    assert p == pytest.approx(ws.mean(), rel=1e-9)
    assert se == pytest.approx(ws.std(ddof=1) / np.sqrt(n), rel=1e-6, abs=1e-15 * w)


@pytest.mark.parametrize("robot", ["manipulator", "link"])
def test_crude_pass_fail_counts_the_threshold_speeds_exceedances(robot):
    """Crude sampling against a head-acceleration limit decides each sample by pass/fail
    (designlab.impact.passfail): the same count as drawing the same samples' threshold
    speeds v* from the full kernel and comparing (issue 40.5; the kernel is certified,
    so the counts must be equal)."""
    from designlab.codesign.population import ClosingSpeeds, HeadPopulation
    from designlab.codesign.risk import ThresholdModel

    arm = MANIPULATOR_1
    if robot == "link":
        arm = LinkImpact.from_contact(MANIPULATOR_1, joint_speed=1.0, lever_arm_min=0.02,
                                      lever_arm_max=0.078)  # fmt: skip
    dist = stats.uniform(1.0, 21.0)  # 1-22 m/s: beyond the model's 20 m/s, v* as before
    got = dl.codesign.injury_probability(arm, FOAM_1, dist, heads=THESIS_HEAD_RANGE,
                                         criterion=HeadAcceleration(10), samples=30_000,
                                         method="crude", seed=11)  # fmt: skip
    rng = np.random.default_rng(11)
    design = ThresholdModel.of(arm, FOAM_1, HeadAcceleration(10), None)
    heads = HeadPopulation.of(THESIS_HEAD_RANGE).sample(30_000, rng)
    v_star = design.thresholds(heads, rng)
    hits = int(np.count_nonzero(ClosingSpeeds.of(dist).sample(30_000, rng) > v_star))
    assert got.failed_samples == hits
    assert 0 < hits < 30_000
    assert got.probability == hits / 30_000
