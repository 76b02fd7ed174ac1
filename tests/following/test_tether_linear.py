"""Linearised lateral loop (python-control) against hand-derived formulas and the simulation."""

from __future__ import annotations

import math

import numpy as np
import pytest

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.following.tether.linear import fit_damping, lateral_step_response
from designlab.results import check_result

fol = dl.following


@pytest.mark.parametrize(
    ("ctrl", "speed", "zeta", "wn"),
    [
        # FTL: s^2 + K s + K v / delta
        (
            fol.FollowTheLeader(lookahead=0.5),
            0.5,
            0.5 * math.sqrt(3 * 0.5 / 0.5),
            math.sqrt(3 * 0.5 / 0.5),
        ),
        (
            fol.FollowTheLeader(lookahead=0.1),
            0.8,
            0.5 * math.sqrt(3 * 0.1 / 0.8),
            math.sqrt(3 * 0.8 / 0.1),
        ),
        # PJ coded: L = l_d + v/k_V = 1.1 m, K = 12
        (fol.PseudoJoystick(), 0.5, 0.5 * math.sqrt(12 * 1.1 / 0.5), math.sqrt(12 * 0.5 / 1.1)),
        # PJ printed: K = 2v/b -> zeta = sqrt(2 l / b)/2 whatever the speed
        (
            fol.PseudoJoystick(law="printed"),
            0.5,
            0.5 * math.sqrt(2 * 1.1 / 0.28),
            math.sqrt((2 * 0.5 / 0.28) * 0.5 / 1.1),
        ),
        # FTL-CD: s^2 + K_b s + K_b K_p, independent of speed
        (fol.FollowTheLeaderConstDistance(), 0.8, 0.5, 2.0),
    ],
)
def test_damping_and_frequency_formulas(ctrl, speed, zeta, wn):
    lin = fol.linear_analysis(ctrl, speed=speed)
    check_result(lin)
    assert lin.damping_ratio == pytest.approx(zeta, rel=1e-9)
    assert lin.natural_frequency == pytest.approx(wn, rel=1e-9)
    assert lin.discrete_stable
    assert np.all(np.real(lin.poles) < 0)
    assert lin.steady_length == pytest.approx(ctrl.desired_length + speed / ctrl.speed_gain)


def test_phase_margin_of_ftl_loop():
    # L(j w) = K (j w + v/d) / (j w)^2; |L| = 1 at w_c; PM = atan(w_c d / v)
    # (an independent derivation)
    k, d, v = 3.0, 0.5, 0.5
    a = v / d
    wc = math.sqrt((k**2 + math.sqrt(k**4 + 4 * k**2 * a**2)) / 2)
    lin = fol.linear_analysis(fol.FollowTheLeader(lookahead=d, turn_gain=k), speed=v)
    assert lin.crossover_frequency == pytest.approx(wc, rel=1e-6)
    assert lin.phase_margin == pytest.approx(math.degrees(math.atan(wc / a)), abs=1e-6)


def test_sampled_loop_unstable_for_huge_gain():
    robot = fol.FollowerRobot(sample_time=0.05)
    lin = fol.linear_analysis(
        fol.FollowTheLeader(turn_gain=60.0, lookahead=0.5), speed=0.5, robot=robot
    )
    assert not lin.discrete_stable and lin.status == "unstable" and lin.warnings


@pytest.mark.slow
@pytest.mark.parametrize("lookahead", [0.1, 0.28, 0.5])
def test_ftl_damping_ratio_of_simulated_step_matches_linear(lookahead):
    """Issue item 5: zeta of a lateral step response within 0.05 of the linear prediction."""
    ctrl = fol.FollowTheLeader(lookahead=lookahead)
    t, e = lateral_step_response(ctrl, offset=0.05, speed=0.5, duration=12.0)
    zeta_fit, wn_fit = fit_damping(t[:1000], e[:1000])
    lin = fol.linear_analysis(ctrl, speed=0.5)
    assert zeta_fit == pytest.approx(lin.damping_ratio, abs=0.05)
    assert wn_fit == pytest.approx(lin.natural_frequency, rel=0.05)


def test_fit_damping_recovers_a_known_response():
    t = np.arange(0, 10, 0.01)
    z, w = 0.3, 2.0
    wd = w * math.sqrt(1 - z * z)
    e = np.exp(-z * w * t) * (np.cos(wd * t) + z * w / wd * np.sin(wd * t))  # e(0)=1, e'(0)=0
    assert fit_damping(t, e) == pytest.approx((z, w), rel=1e-4)


def test_bad_linear_input():
    with pytest.raises(InvalidParameterError, match="speed"):
        fol.linear_analysis(fol.FollowTheLeader(), speed=0.0)
    with pytest.raises(InvalidParameterError, match="controller"):
        fol.linear_analysis("FTL", speed=0.5)  # type: ignore[arg-type]


@pytest.mark.parametrize(("poles"), [(-0.5, -4.0), (-1.0 + 1.7j, -1.0 - 1.7j), (-0.243, -11.757)])
def test_identify_poles_recovers_the_poles_of_a_free_response(poles):
    from designlab.following.tether.linear import identify_poles

    t = np.arange(0.0, 10.0, 0.01)
    p1, p2 = (complex(p) for p in poles)
    e = (np.exp(p1 * t) * (1 + 0.3j) + np.exp(p2 * t) * (1 - 0.3j)).real
    got = identify_poles(t, e)
    assert sorted(got, key=abs) == pytest.approx(sorted([p1, p2], key=abs), rel=1e-8)
    zeta, wn = fit_damping(t, e)
    assert wn == pytest.approx(math.sqrt((p1 * p2).real), rel=1e-8)
    assert zeta == pytest.approx(-(p1 + p2).real / (2 * wn), rel=1e-8)


def test_pj_slow_pole_of_the_simulated_step_matches_the_linear_loop():
    """Issue 20: the damping ratio from the identified poles; PJ's slow pole to 0.2 %."""
    from designlab.following.tether.linear import identify_poles

    ctrl = fol.PseudoJoystick(desired_length=1.0)
    t, e = lateral_step_response(ctrl, offset=0.05, speed=0.5, duration=12.0)
    lin = fol.linear_analysis(ctrl, speed=0.5)
    z, w = lin.damping_ratio, lin.natural_frequency
    slow = -w * (z - math.sqrt(z * z - 1))
    assert identify_poles(t[:1000], e[:1000])[0].real == pytest.approx(slow, rel=2e-3)
