"""Joint reduced-order model (Zeng 2011, Sec. 3.4.2, App. A.2.3)."""

from __future__ import annotations

import numpy as np
import pytest

from designlab.errors import InvalidParameterError
from designlab.impact.joint import (
    JointFit,
    fit_joint_band,
    full_joint_tf,
    joint_error_tf,
    joint_from_pd_gains,
    pd_gains_for,
    reduced_joint,
    reduced_joint_tf,
)

# An illustrative geared joint (not a joint of the thesis, whose arms are the
# direct-drive arm and the Puma 560) whose transmission and controller are comparable, so that the
# Taylor truncation is visibly imperfect below the corner frequency
# (K_mech + K_cont)/(C_mech + C_cont) = 3500/32 = 109 rad/s.
GEARED = (2.0e3, 2.0, 1.5e3, 30.0)

# Table 3.1 Manipulator 1 / App. A.2.3
L1 = 0.078  # m
KT_KAMP = 0.2807  # N m/V
B_DD = 0.0079  # N m s/rad


def _freq(sys, omega):
    return np.array([complex(sys(1j * w)) for w in omega])


# --- closed forms -------------------------------------------------------------


def test_reduced_joint_closed_form():
    km, cm, kc, cc = GEARED
    k_j, c_j = reduced_joint(*GEARED)
    assert k_j == pytest.approx(km * kc / (km + kc), rel=1e-14)
    assert c_j == pytest.approx((kc**2 * cm + km**2 * cc) / (km + kc) ** 2, rel=1e-14)
    assert isinstance(k_j, float) and isinstance(c_j, float)


def test_reduced_joint_is_taylor_expansion_of_full():
    """K_J = G(0) and C_J = dG/ds(0) of the full joint (3.4.6)."""
    g = full_joint_tf(*GEARED)
    k_j, c_j = reduced_joint(*GEARED)
    h = 1e-4
    assert complex(g(0.0)).real == pytest.approx(k_j, rel=1e-12)
    slope = (complex(g(h)).real - complex(g(-h)).real) / (2 * h)
    assert slope == pytest.approx(c_j, rel=1e-7)


def test_reduced_joint_vectorised():
    km = np.array([1e3, 2e3, 5e3])
    k_j, c_j = reduced_joint(km, 2.0, 1.5e3, 30.0)
    assert k_j.shape == c_j.shape == (3,)
    for i, k in enumerate(km):
        ks, cs = reduced_joint(float(k), 2.0, 1.5e3, 30.0)
        assert k_j[i] == pytest.approx(ks, rel=1e-14)
        assert c_j[i] == pytest.approx(cs, rel=1e-14)
    k_b, c_b = reduced_joint(km, np.array([1.0, 2.0, 3.0]), 1.5e3, 0.0)
    assert k_b.shape == c_b.shape == (3,)


@pytest.mark.parametrize(
    ("args", "name", "unit"),
    [
        ((0.0, 1.0, 1.0, 1.0), "k_mech", "N m/rad"),
        ((1.0, -1.0, 1.0, 1.0), "c_mech", "N m s/rad"),
        ((1.0, 1.0, -5.0, 1.0), "k_cont", "N m/rad"),
        ((1.0, 1.0, 1.0, float("nan")), "c_cont", "N m s/rad"),
        ((np.array([1.0, -2.0]), 1.0, 1.0, 1.0), "k_mech", "N m/rad"),
    ],
)
def test_reduced_joint_rejects_bad_input(args, name, unit):
    with pytest.raises(InvalidParameterError) as info:
        reduced_joint(*args)
    assert info.value.name == name
    assert info.value.unit == unit
    assert name in str(info.value) and unit in str(info.value)


def test_zero_dampings_are_allowed():
    k_j, c_j = reduced_joint(1e3, 0.0, 1e3, 0.0)
    assert (k_j, c_j) == (500.0, 0.0)
    # both dampings zero: the full joint is a pure spring, so no truncation error
    omega = np.logspace(-1, 3, 20)
    np.testing.assert_allclose(_freq(full_joint_tf(1e3, 0.0, 1e3, 0.0), omega), 500.0)


# --- limiting cases (Sec. 3.4.2) ---------------------------------------------------


def test_limit_stiff_transmission_gives_controller():
    """K_mech >> K_cont (direct drive): K_J -> K_cont, C_J -> C_cont."""
    k_cont, c_cont = 121.68, 1.52
    k_j, c_j = reduced_joint(1e9, 5.0, k_cont, c_cont)
    assert k_j == pytest.approx(k_cont, rel=1e-6)
    assert c_j == pytest.approx(c_cont, rel=1e-6)


def test_limit_stiff_controller_gives_transmission():
    """K_cont >> K_mech: K_J -> K_mech, C_J -> C_mech."""
    k_mech, c_mech = 2.0e3, 3.0
    k_j, c_j = reduced_joint(k_mech, c_mech, 1e10, 50.0)
    assert k_j == pytest.approx(k_mech, rel=1e-6)
    assert c_j == pytest.approx(c_mech, rel=1e-6)


def test_limits_are_approached_at_rate_k_ratio():
    """The relative deviation from the limit falls like K_cont/K_mech."""
    devs = []
    for ratio in (1e-2, 1e-3, 1e-4):
        k_j, _ = reduced_joint(1.0 / ratio, 0.0, 1.0, 0.0)
        devs.append(1.0 - k_j)
    np.testing.assert_allclose(devs, [1e-2 / 1.01, 1e-3 / 1.001, 1e-4 / 1.0001], rtol=1e-9)


# --- transfer functions and E_m (3.4.10) ---------------------------------------


@pytest.mark.parametrize(
    "params",
    [GEARED, (1e9, 5.0, 121.68, 1.52), (300.0, 0.0, 900.0, 12.0), (1e4, 40.0, 2e3, 0.0)],
)
def test_full_minus_reduced_equals_error_model(params):
    omega = np.logspace(-2, 4, 400)
    full = _freq(full_joint_tf(*params), omega)
    red = _freq(reduced_joint_tf(*params), omega)
    err = _freq(joint_error_tf(*params), omega)
    np.testing.assert_allclose(full - red, err, rtol=1e-10, atol=1e-12 * np.abs(full).max())
    # and symbolically, via python-control algebra
    diff = _freq(full_joint_tf(*params) - reduced_joint_tf(*params), omega)
    np.testing.assert_allclose(diff, err, rtol=1e-9, atol=1e-12 * np.abs(full).max())


def test_reduced_tf_is_improper_first_order():
    r = reduced_joint_tf(*GEARED)
    k_j, c_j = reduced_joint(*GEARED)
    np.testing.assert_allclose(np.ravel(r.num[0][0]), [c_j, k_j])
    np.testing.assert_allclose(np.ravel(r.den[0][0]), [1.0])


def test_error_model_is_second_order_small_at_low_frequency():
    """E_m(i w) = O(w^2): halving w divides |E_m| by ~4 at low frequency."""
    e = joint_error_tf(*GEARED)
    w = 0.1
    ratio = abs(complex(e(1j * w))) / abs(complex(e(0.5j * w)))
    assert ratio == pytest.approx(4.0, rel=1e-3)


# --- frequency-band fit ----------------------------------------------------------


def test_band_fit_beats_taylor_over_the_band():
    """Measured: band [10, 100] rad/s, rms relative error 0.107 (fit) vs 0.160 (Taylor)."""
    fit = fit_joint_band(*GEARED, omega_max=100.0, omega_min=10.0)
    assert isinstance(fit, JointFit)
    assert fit.status == "optimal" and fit.success
    assert fit.rms_error == pytest.approx(0.1074, abs=2e-3)
    assert fit.taylor_rms_error == pytest.approx(0.1596, abs=2e-3)
    assert fit.rms_error / fit.taylor_rms_error < 0.70
    assert fit.improvement > 1.4
    # worst point of the band also improves (0.260 vs 0.393)
    assert fit.relative_error.max() < 0.70 * fit.taylor_relative_error.max()
    # the fit is stiffer and less damped than the Taylor values
    assert fit.stiffness > fit.taylor_stiffness
    assert fit.damping < fit.taylor_damping


def test_band_fit_default_band_improves_less():
    """Default band [omega_max/1000, omega_max]: 0.0768 vs 0.0936 (ratio 0.82)."""
    fit = fit_joint_band(*GEARED, omega_max=100.0)
    assert fit.omega[0] == pytest.approx(0.1) and fit.omega[-1] == pytest.approx(100.0)
    assert fit.omega.size == 200
    assert fit.rms_error / fit.taylor_rms_error < 0.85


def test_band_fit_matches_weighted_least_squares_closed_form():
    """The problem decouples: K fits Re G, C fits Im G / w (weights 1/|G|^2)."""
    rng = np.random.default_rng(1)
    weights = rng.uniform(0.5, 2.0, 50)
    fit = fit_joint_band(*GEARED, omega_max=80.0, n=50, omega_min=1.0, weights=weights)
    g, w = fit.response, fit.omega
    a = weights / np.abs(g) ** 2
    k_ls = np.sum(a * g.real) / np.sum(a)
    c_ls = np.sum(a * w * g.imag) / np.sum(a * w**2)
    assert fit.stiffness == pytest.approx(k_ls, rel=1e-5)
    assert fit.damping == pytest.approx(c_ls, rel=1e-5)


def test_band_fit_at_low_frequency_recovers_taylor():
    fit = fit_joint_band(*GEARED, omega_max=0.01)
    assert fit.stiffness == pytest.approx(fit.taylor_stiffness, rel=1e-5)
    assert fit.damping == pytest.approx(fit.taylor_damping, rel=1e-3)
    assert fit.taylor_rms_error < 1e-6


def test_band_fit_result_is_frozen_and_tabular():
    fit = fit_joint_band(*GEARED, omega_max=50.0, n=30)
    frame = fit.to_frame()
    assert len(frame) == 30
    np.testing.assert_allclose(frame["fit_rel_error"], fit.relative_error)
    with pytest.raises(AttributeError):
        fit.stiffness = 1.0  # type: ignore[misc]
    with pytest.raises(ValueError):
        fit.omega[0] = 1.0


def test_band_fit_reports_solver_failure(monkeypatch):
    import cvxpy as cp

    def boom(self, *args, **kwargs):
        raise cp.error.SolverError("forced failure")

    monkeypatch.setattr(cp.Problem, "solve", boom)
    fit = fit_joint_band(*GEARED, omega_max=50.0)
    assert fit.status.startswith("solver_error") and "forced failure" in fit.status
    assert not fit.success
    assert np.isnan(fit.stiffness) and np.isnan(fit.rms_error)
    assert fit.taylor_rms_error > 0  # the Taylor comparison is still there


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"omega_max": -1.0}, "omega_max"),
        ({"omega_max": 10.0, "omega_min": 20.0}, "omega_min"),
        ({"omega_max": 10.0, "n": 1}, "n"),
        ({"omega_max": 10.0, "n": 3, "weights": [1.0, 1.0]}, "weights"),
        ({"omega_max": 10.0, "n": 2, "weights": [1.0, -1.0]}, "weights"),
    ],
)
def test_band_fit_rejects_bad_band(kwargs, name):
    with pytest.raises(InvalidParameterError) as info:
        fit_joint_band(*GEARED, **kwargs)
    assert info.value.name == name


# --- PD gains of the direct-drive arm (App. A.2.3, Sec. 4.3.1) ------------------------


def test_pd_gains_worked_example():
    """K_r = 20 kN/m, C_r = 250 N s/m, l_1 = 0.078 m, K_t K_amp = 0.2807 N m/V."""
    k_p, k_d = pd_gains_for(20e3, 250.0, L1, KT_KAMP, viscous_friction=B_DD)
    assert 433.4 <= k_p <= 433.8  # thesis: 433.8 (Sec. 4.3.1) and 433.4 (App. A.2.3)
    assert k_p == pytest.approx(433.49, abs=0.01)
    assert round(k_d, 1) == 5.4
    assert k_d == pytest.approx(5.390, abs=1e-3)
    # without the viscous friction (as in (4.3.3)) it still rounds to 5.4
    _, k_d0 = pd_gains_for(20e3, 250.0, L1, KT_KAMP)
    assert round(k_d0, 1) == 5.4
    assert k_d0 == pytest.approx(5.419, abs=1e-3)


def test_pd_gains_round_trip():
    k_p, k_d = pd_gains_for(20e3, 250.0, L1, KT_KAMP, viscous_friction=B_DD)
    k_j, c_j = joint_from_pd_gains(k_p, k_d, KT_KAMP, viscous_friction=B_DD)
    assert k_j / L1**2 == pytest.approx(20e3, rel=1e-12)  # (4.3.2)
    assert c_j / L1**2 == pytest.approx(250.0, rel=1e-12)
    # direct drive: the controller is the joint, (A.2.20) agrees with (3.4.9) as K_mech -> inf
    k_mech = 1e12
    k_j2, c_j2 = reduced_joint(k_mech, 0.0, KT_KAMP * k_p, KT_KAMP * k_d + B_DD)
    # (3.4.9) at finite K_mech: k_j2 = k_j/(1 + k_j/K_mech), c_j2 = c_j/(1 + k_j/K_mech)^2, so
    # the limit is approached to first order in k_j/K_mech (2.4e-10 here), not to rounding
    first_order = k_j / k_mech
    assert k_j2 == pytest.approx(k_j, rel=first_order * (1 + 1e-3) + 1e-15)
    assert c_j2 == pytest.approx(c_j, rel=2 * first_order * (1 + 1e-3) + 1e-15)


def test_pd_gains_reject_negative_d_gain():
    with pytest.raises(InvalidParameterError) as info:
        pd_gains_for(20e3, 1.0, L1, KT_KAMP, viscous_friction=B_DD)
    assert info.value.name == "damping"
    with pytest.raises(InvalidParameterError) as info:
        pd_gains_for(20e3, 250.0, L1, 0.0)
    assert info.value.name == "torque_constant"
