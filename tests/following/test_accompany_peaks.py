"""Ms and Mt of the tuned accompanying PID hold on any frequency grid (issue 20)."""

from __future__ import annotations

import numpy as np
import pytest

from designlab.following.accompanying import UserFramePID, loop_analysis
from designlab.following.accompanying.linear import (
    delay_periods,
    frequency_grid,
    pid_basis,
    plant_response,
    refined_peak,
)
from designlab.following.accompanying.parameters import StringPotSensor
from designlab.following.accompanying.tuning import PEAK_TOLERANCE, convex_concave_pid


def _dense_peaks(kp, ki, kd, tau=0.15, ts=0.02, tf=0.05, delay=0, n=400_000):
    """|S| and |T| maxima on a dense grid (independent of the tuner's refinement)."""
    return tuple(p for p, _ in _dense_peaks_and_gaps(kp, ki, kd, tau, ts, tf, delay, n))


def _dense_peaks_and_gaps(kp, ki, kd, tau=0.15, ts=0.02, tf=0.05, delay=0, n=400_000):
    """(grid maximum, bound on how far the true peak can lie above it) for |S| and |T|.

    Between samples h apart a smooth maximum exceeds the best sample by at most
    |f''| h^2 / 8 (the peak midway); f'' from the samples around the grid maximum, doubled
    for the higher-order terms.
    """
    w = frequency_grid(ts, n, 1e-3)
    c = pid_basis(tf, ts, w) @ np.array([kp, ki, kd])
    loop = c * plant_response(tau, ts, w, delay)
    s = 1.0 / (1.0 + loop)
    out = []
    for f in (np.abs(s), np.abs(loop * s)):
        i = int(np.clip(np.argmax(f), 1, f.size - 2))
        h1, h2 = w[i] - w[i - 1], w[i + 1] - w[i]
        curv = 2.0 * ((f[i + 1] - f[i]) / h2 - (f[i] - f[i - 1]) / h1) / (h1 + h2)
        out.append((float(f.max()), 2.0 * abs(curv) * max(h1, h2) ** 2 / 8.0))
    return out


def _assert_is_the_peak(refined: float, sampled: float, gap: float) -> None:
    """The refined peak is never below a sample and at most ``gap`` above the best one."""
    assert sampled * (1 - 8 * EPS) <= refined <= sampled + gap + 8 * EPS * sampled


EPS = float(np.finfo(float).eps)


@pytest.mark.parametrize(("ms_max", "mt_max"), [(1.6, 1.3)])
def test_convex_tuner_limits_hold_on_a_dense_grid(ms_max, mt_max):
    sol = convex_concave_pid(0.15, 0.02, 0.05, ms_max=ms_max, mt_max=mt_max)
    ms, mt = _dense_peaks(sol.kp, sol.ki, sol.kd)
    assert ms <= ms_max * (1 + PEAK_TOLERANCE)
    assert mt <= mt_max * (1 + PEAK_TOLERANCE)
    assert sol.ms == pytest.approx(ms, rel=1e-9, abs=0) or sol.ms >= ms
    # and python-control's loop (the polynomial L(z)) agrees at the peak frequency
    la = loop_analysis(UserFramePID(kp=sol.kp, ki=sol.ki, kd=sol.kd))
    assert la.ms == pytest.approx(ms, rel=1e-7)
    assert la.mt == pytest.approx(mt, rel=1e-7)
    w_peak = refined_peak(
        lambda w: np.abs(
            1.0
            / (
                1.0
                + (pid_basis(0.05, 0.02, w) @ np.array([sol.kp, sol.ki, sol.kd]))
                * plant_response(0.15, 0.02, w)
            )
        ),
        frequency_grid(0.02, 500, 1e-3),
    )[1]
    tf = la.transfer_functions["lateral"]
    z = np.exp(1j * w_peak * 0.02)
    assert abs(1.0 / (1.0 + complex(tf(z)))) == pytest.approx(la.ms, rel=1e-6)


def test_loop_analysis_peaks_do_not_depend_on_the_grid():
    pid = UserFramePID(kp=9.594162, ki=41.05242, kd=2.037089)  # the former tuned gains
    (ms, ms_gap), (mt, mt_gap) = _dense_peaks_and_gaps(9.594162, 41.05242, 2.037089)
    for n in (50, 300, 2000):
        la = loop_analysis(pid, n_frequencies=n)
        _assert_is_the_peak(la.ms, ms, ms_gap)
        _assert_is_the_peak(la.mt, mt, mt_gap)
    # the former tuning exceeded its limits between the 300 grid points (issue 20)
    assert ms > 1.6 and mt > 1.3


def test_refined_peak_finds_a_peak_between_grid_points():
    w = np.linspace(0.0, 1.0, 5)  # 0, 0.25, 0.5, ...: the narrow peak at 0.6 falls between
    value, at = refined_peak(lambda x: np.exp(-(((x - 0.6) / 0.05) ** 2)), w)
    assert value == pytest.approx(1.0, abs=1e-9) and at == pytest.approx(0.6, abs=1e-6)


def test_delay_of_the_median_window_is_in_the_peaks():
    sensor = StringPotSensor(median_window=9, oversampling=4)
    assert delay_periods(sensor) == 1
    la = loop_analysis(UserFramePID(kp=5.0, ki=5.0, kd=0.5), sensor=sensor)
    (ms, ms_gap), (mt, mt_gap) = _dense_peaks_and_gaps(5.0, 5.0, 0.5, delay=1)
    _assert_is_the_peak(la.ms, ms, ms_gap)
    _assert_is_the_peak(la.mt, mt, mt_gap)
