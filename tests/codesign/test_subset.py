"""Subset simulation (Au and Beck 2001) against closed forms and crude Monte Carlo."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

import designlab as dl
from designlab.codesign.subset import subset_simulation
from designlab.errors import InvalidParameterError
from designlab.impact import FOAM_1, HEAD_MIN, MANIPULATOR_1, HeadAcceleration

G = 9.80665


@settings(max_examples=6, deadline=None)
@given(b=st.floats(1.0, 5.0), d=st.integers(1, 6), seed=st.integers(0, 2**16))
def test_linear_limit_state_has_the_normal_tail(b, d, seed) -> None:
    # g(u) = sum(u) / sqrt(d) - b is standard normal minus b: P(g > 0) = Phi(-b) exactly
    exact = stats.norm.sf(b)
    out = subset_simulation(lambda u: u.sum(axis=1) / math.sqrt(u.shape[1]) - b, d, 2000,
                            np.random.default_rng(seed))  # fmt: skip
    assert out.thresholds[-1] == 0.0 and len(out.thresholds) == out.levels
    assert all(np.diff(out.thresholds) > 0)
    # Au and Beck's c.o.v. is a lower bound; 5 of them cover the scatter
    assert abs(math.log(out.probability / exact)) < 5 * out.cov + 0.05
    lo, hi = out.interval(0.95)
    assert lo <= out.probability <= hi


def test_the_mean_over_seeds_is_unbiased_at_1e_minus_6() -> None:
    b = stats.norm.isf(1e-6)
    outs = [subset_simulation(lambda u: u[:, 0] + 0.0 * u[:, 1] - b, 2, 1000,
                              np.random.default_rng(s)) for s in range(40)]  # fmt: skip
    ps = np.array([o.probability for o in outs])
    # the mean of 40 independent runs within 4 standard errors of the exact value
    assert abs(ps.mean() - 1e-6) < 4 * ps.std(ddof=1) / math.sqrt(len(ps))
    # Au and Beck's c.o.v. is a lower bound (levels taken as uncorrelated): the scatter
    # over seeds is about twice the stated one here (docs/codesign.md), not more than 3x
    stated = np.mean([o.cov for o in outs])
    assert stated < ps.std(ddof=1) / 1e-6 < 3 * stated


def test_fixed_head_closed_form_at_a_tiny_probability() -> None:
    # one head, v_c Rayleigh(sigma): P = exp(-v*^2 / (2 sigma^2)) with v* = 10 g / a_h(1 m/s)
    m = dl.impact.impact_metrics(
        {"M_r": MANIPULATOR_1.mass, "C_r": MANIPULATOR_1.damping, "K_r": MANIPULATOR_1.stiffness,
         "K_c": FOAM_1.stiffness, "C_c": FOAM_1.damping, "M_h": HEAD_MIN.mass,
         "C_h": HEAD_MIN.damping, "K_h": HEAD_MIN.stiffness},
        1.0,
    )  # fmt: skip
    v_star = 10 * G / float(m.peak_head_acceleration[0])
    sigma = 0.3
    exact = math.exp(-(v_star**2) / (2 * sigma**2))
    assert 1e-12 < exact < 1e-8
    r = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, stats.rayleigh(scale=sigma),
                                       heads=HEAD_MIN, criterion=HeadAcceleration(10),
                                       samples=2000, method="subset", seed=1)  # fmt: skip
    assert r.method == "subset" and r.status == "ok"
    assert abs(math.log(r.probability / exact)) < 5 * r.standard_error / r.probability
    assert r.samples > 2000  # the chains' evaluations are counted


def test_agrees_with_crude_monte_carlo_over_the_thesis_range() -> None:
    speeds = stats.rayleigh(scale=1.0)
    crude = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, speeds, samples=200_000,
                                           method="crude", seed=3)  # fmt: skip
    sub = dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, speeds, samples=4000,
                                         method="subset", seed=4)  # fmt: skip
    se = math.hypot(crude.standard_error, 2 * sub.standard_error)  # c.o.v. is a lower bound
    assert abs(sub.probability - crude.probability) < 4 * se


def test_samples_per_level_must_give_chains() -> None:
    with pytest.raises(InvalidParameterError, match="samples"):
        dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, stats.rayleigh(), samples=50,
                                       method="subset")  # fmt: skip
    with pytest.raises(InvalidParameterError, match="level_probability"):
        subset_simulation(lambda u: u[:, 0], 1, 1000, np.random.default_rng(0),
                          level_probability=0.9)  # fmt: skip
    with pytest.raises(InvalidParameterError, match="method"):
        dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, stats.rayleigh(), method="ss")


def test_link_points_and_sampled_speeds_agree_with_importance_sampling() -> None:
    link = dl.impact.LinkImpact.from_contact(MANIPULATOR_1, joint_speed=1.0,
                                             lever_arm_min=0.02, lever_arm_max=0.078)  # fmt: skip
    speeds = np.random.default_rng(7).rayleigh(1.0, 5000)  # samples, not a distribution
    kw = {"closing_speed": speeds, "criterion": HeadAcceleration(10)}
    imp = dl.codesign.injury_probability(link, FOAM_1, samples=40_000, seed=8, **kw)
    sub = dl.codesign.injury_probability(link, FOAM_1, samples=4000, method="subset", seed=9,
                                         **kw)  # fmt: skip
    assert 0.01 < imp.probability < 0.5
    se = math.hypot(imp.standard_error, 2 * sub.standard_error)
    assert abs(sub.probability - imp.probability) < 4 * se
