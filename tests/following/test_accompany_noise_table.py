"""The accompanying study's noise table and the command rate it reports."""

from __future__ import annotations

import numpy as np
import pytest

from designlab.errors import InvalidParameterError, StudyError
from designlab.following.accompanying.metrics import command_rate
from designlab.study import parse_study, run_study


def test_command_rate_of_a_circle_at_constant_speed_is_v_omega() -> None:
    """A command of speed v turning at omega changes at |dV/dt| = 2 v sin(omega T / 2) / T."""
    v, omega, period = 0.5, 2.0, 0.02
    t = np.arange(201) * period
    phase = omega * t[:-1]
    cmd = np.vstack([v * np.cos(phase), v * np.sin(phase), np.zeros_like(phase)])
    assert command_rate(t, cmd) == pytest.approx(
        2 * v * np.sin(omega * period / 2) / period, rel=1e-12
    )


@pytest.mark.parametrize("cmd", [np.zeros(5), np.zeros((3, 1)), np.zeros((1, 5))])
def test_command_rate_refuses_a_command_that_is_not_three_rows(cmd: np.ndarray) -> None:
    with pytest.raises(InvalidParameterError, match="command"):
        command_rate(np.arange(6) * 0.02, cmd)


_STUDY = """
designlab: 1
kind: accompanying
name: demo
tasks: [forward]
tuning: {tune_on: [forward], derivative_free: false}
"""


def test_the_noise_table_limits_the_noise_gain_and_the_command_rate() -> None:
    r = run_study(parse_study(_STUDY + "noise: {max_noise_gains: [10], median_windows: [5]}\n"))
    f = r.noise.set_index("controller")
    assert list(f.index) == ["default", "tuned", "tuned, k_s = 10 1/s", "tuned, median of 5"]
    assert f.loc["tuned, k_s = 10 1/s", "noise_gain_1_s"] <= 10 * (1 + 1e-6)
    assert f.loc["tuned", "noise_gain_1_s"] > 10
    rate = f["command_rate_m_s2"]
    assert rate["tuned, k_s = 10 1/s"] < rate["tuned"]
    assert rate["tuned, median of 5"] < rate["tuned"]
    assert np.isnan(f.loc["tuned, median of 5", "rms_clean_m"])  # same gains as "tuned"
    assert f.loc["tuned", "rms_clean_m"] == r.runs["tuned"]["forward"].rms_error


def test_the_noise_table_needs_tuning() -> None:
    with pytest.raises(StudyError, match="noise needs tuning"):
        parse_study(_STUDY.replace("tuning: {tune_on: [forward], derivative_free: false}",
                                   "tuning: null") + "noise: {}\n")  # fmt: skip
