"""Linear loop analysis and PID tuning of the accompanying robot."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.results import check_result

fol = dl.following


def _hand_loop(kp, ki, kd, tf, tau, ts, w):
    """L(e^{jwT}) written out independently: ZOH of 1/(s(tau s+1)) and the discrete PID."""
    z = np.exp(1j * w * ts)
    a = math.exp(-ts / tau)
    # ZOH: (1 - z^-1) Z{1/(s^2 (tau s + 1))}; partial fractions 1/s^2 - tau/s + tau/(s + 1/tau)
    zi = 1 / z
    ramp = ts * zi / (1 - zi) ** 2
    step = 1 / (1 - zi)
    expo = 1 / (1 - a * zi)
    plant = (1 - zi) * (ramp - tau * step + tau * expo)
    c = kp + ki * ts * z / (z - 1) + kd * (z - 1) / ((tf + ts) * z - tf)
    return c * plant


def test_loop_analysis_matches_hand_formula():
    pid = fol.UserFramePID(kp=3.0, ki=2.0, kd=0.3, derivative_filter_time=0.04)
    la = fol.loop_analysis(pid)
    check_result(la)
    lw = _hand_loop(3.0, 2.0, 0.3, 0.04, 0.15, 0.02, la.omega)
    assert np.allclose(la.loops["forward"], lw, rtol=1e-6)
    row = la.axis("lateral")
    # the peaks are refined between grid points: a dense hand grid gives the same
    dense = _hand_loop(3.0, 2.0, 0.3, 0.04, 0.15, 0.02, np.logspace(-3, np.log10(157.0), 200_000))
    assert row["Ms"] == pytest.approx(np.max(np.abs(1 / (1 + dense))), rel=1e-8)
    assert row["Mt"] == pytest.approx(np.max(np.abs(dense / (1 + dense))), rel=1e-8)
    assert row["Ms"] >= np.max(np.abs(1 / (1 + lw)))
    # gain crossover: |L| = 1 there, and the phase margin is 180 + arg L
    lc = _hand_loop(3.0, 2.0, 0.3, 0.04, 0.15, 0.02, np.array([row["crossover_rad_s"]]))[0]
    assert abs(lc) == pytest.approx(1.0, abs=2e-3)
    assert row["phase_margin_deg"] == pytest.approx(180 + math.degrees(np.angle(lc)), abs=0.2)


def test_p_only_gain_margin_is_the_critical_gain():
    """Jury/root locus: the P loop is stable exactly for K_p below K_p * gain margin."""
    la = fol.loop_analysis(fol.UserFramePID(kp=2.0, ki=0.0, kd=0.0))
    gm = la.axis("forward")["gain_margin"]
    kcrit = 2.0 * gm
    tau, ts = 0.15, 0.02
    a = math.exp(-ts / tau)
    b1 = ts - tau * (1 - a)
    b0 = tau * (1 - a) - a * ts

    def max_pole(k):
        # (z - 1)(z - a) + k (b1 z + b0) = 0
        return max(abs(np.roots([1.0, -(1 + a) + k * b1, a + k * b0])))

    assert max_pole(kcrit * 0.99) < 1.0 < max_pole(kcrit * 1.01)
    bad = fol.loop_analysis(fol.UserFramePID(kp=kcrit * 1.05, ki=0.0, kd=0.0))
    assert bad.status == "unstable" and bad.warnings


@settings(max_examples=10, deadline=None)
@given(
    st.floats(0.2, 20.0),
    st.floats(0.0, 20.0),
    st.floats(0.0, 1.0),
    st.floats(0.05, 0.5),
)
def test_sensitivity_peaks_invariants(kp, ki, kd, tau):
    la = fol.loop_analysis(
        fol.UserFramePID(kp=kp, ki=ki, kd=kd),
        fol.MecanumPlatform(time_constant=tau),
        n_frequencies=300,
    )
    for row in la.rows:
        assert row["Mt"] >= 1.0 - 1e-4  # integrating loop: T -> 1 at low frequency
        if row["stable"]:
            assert row["Ms"] >= 1.0 - 1e-4  # Bode's integral for a stable discrete loop
        # lateral and forward loops are the same loop (isotropic platform)
        assert la.rows[0]["Ms"] == la.rows[1]["Ms"]


def test_convex_concave_solution_satisfies_constraints_on_a_dense_grid():
    sol = fol.accompanying.tuning.convex_concave_pid(0.15, 0.02, 0.05, ms_max=1.4, mt_max=1.3)
    assert sol.converged and sol.solver_status == "optimal"
    w = np.logspace(-3, math.log10(math.pi / 0.02 * 0.9999), 20000)
    lw = _hand_loop(sol.kp, sol.ki, sol.kd, 0.05, 0.15, 0.02, w)
    assert np.max(np.abs(1 / (1 + lw))) <= 1.4 * 1.003
    assert np.max(np.abs(lw / (1 + lw))) <= 1.3 * 1.003
    # a looser Ms allows a larger integral gain (the objective of Hast et al. 2013)
    loose = fol.accompanying.tuning.convex_concave_pid(0.15, 0.02, 0.05, ms_max=1.8, mt_max=1.3)
    assert loose.ki > sol.ki
    # a slower platform allows a smaller one
    slow = fol.accompanying.tuning.convex_concave_pid(0.4, 0.02, 0.05, ms_max=1.4, mt_max=1.3)
    assert slow.ki < sol.ki


def test_noise_gain_limit():
    """Hast et al.'s noise-sensitivity constraint |C S| <= ks trades K_i for noise rejection."""
    free = fol.accompanying.tuning.convex_concave_pid(0.15, 0.02, 0.05)
    lim = fol.accompanying.tuning.convex_concave_pid(0.15, 0.02, 0.05, max_noise_gain=10.0)
    assert lim.converged and lim.ki < free.ki and lim.kd < free.kd
    w = np.logspace(-3, math.log10(math.pi / 0.02 * 0.9999), 20000)
    lw = _hand_loop(lim.kp, lim.ki, lim.kd, 0.05, 0.15, 0.02, w)
    z = np.exp(1j * w * 0.02)
    c = lim.kp + lim.ki * 0.02 * z / (z - 1) + lim.kd * (z - 1) / (0.07 * z - 0.05)
    assert np.max(np.abs(c / (1 + lw))) <= 10.0 * 1.003
    r = fol.tune_pid(tasks=[fol.walking_task("forward")], max_noise_gain=10.0)
    assert r.margins["noise_gain_1_s"].max() <= 10.0 * 1.003


def test_tune_pid_result():
    tasks = [fol.walking_task("right_lateral")]
    r = fol.tune_pid(tasks=tasks)
    check_result(r)
    assert r.status == "ok" and r.method == "convex"
    assert set(r.margins["axis"]) == {"lateral", "forward", "heading"}
    assert r.margins["Ms"].max() <= 1.6 * 1.002
    assert r.improvement > 0.5
    assert r.gains_frame()["improvement"][0] == r.improvement
    assert list(r.to_frame()["task"]) == ["right_lateral"]


def test_tune_pid_yaw_time_constant_gets_its_own_loop():
    r = fol.tune_pid(
        tasks=[fol.walking_task("left_pivot")],
        platform=fol.MecanumPlatform(yaw_time_constant=0.3),
    )
    assert r.controller.ki_heading < r.controller.ki
    assert r.margins["Ms"].max() <= 1.6 * 1.002


@pytest.mark.slow
def test_derivative_free_tuner_improves_but_is_costlier():
    tasks = [fol.walking_task("forward")]
    r = fol.tune_pid(tasks=tasks, method="simulation", max_evaluations=40)
    assert r.method == "simulation"
    assert r.simulations >= 30
    assert r.improvement > 0
    assert r.margins["Ms"].max() <= 1.6 * 1.01


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"method": "ziegler"}, "method"),
        ({"ms_max": 0.9}, "ms_max"),
        ({"mt_max": float("nan")}, "mt_max"),
        ({"derivative_filter_time": -1.0}, "derivative_filter_time"),
        ({"max_noise_gain": 0.0}, "max_noise_gain"),
    ],
)
def test_tune_pid_bad_input(kwargs, name):
    with pytest.raises(InvalidParameterError) as exc:
        fol.tune_pid(tasks=[fol.walking_task("forward")], **kwargs)
    assert exc.value.name == name


def test_tune_pid_needs_tasks():
    with pytest.raises(InvalidParameterError) as exc:
        fol.tune_pid(tasks=[])
    assert exc.value.name == "tasks"


def test_derivative_free_with_noise_limit_runs():
    r = fol.tune_pid(
        tasks=[fol.walking_task("left_pivot")],
        method="simulation",
        max_noise_gain=8.0,
        max_evaluations=12,
    )
    assert r.simulations >= 10 and np.isfinite(r.improvement)
    assert r.status in ("ok", "not_converged")
