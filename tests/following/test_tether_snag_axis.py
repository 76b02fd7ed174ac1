"""Snagging on the recorded-path axis and the follower's speed limit (Allan 2015 Sec. 4.5.5)."""

from __future__ import annotations

import numpy as np
import pytest

from designlab.errors import InvalidParameterError
from designlab.following.tether.snag import SnagScenario, simulate_snag


def test_without_a_snag_the_recorded_path_axis_is_the_leader_distance():
    """Gap 1 m never snags: the recorded path is the leader's, point for point."""
    run = simulate_snag(SnagScenario(gap=1.0))
    assert run.snag_span_recorded is None
    moving = run.tracked_s_leader < run.leader_s[-1] - 1e-9
    np.testing.assert_allclose(
        run.tracked_s[moving], run.tracked_s_leader[moving] - run.tracked_s_leader[0], atol=0.02
    )


@pytest.mark.parametrize("gap", [2.5, 5.0])
def test_the_snag_lengthens_the_recorded_path(gap):
    run = simulate_snag(SnagScenario(gap=gap))
    a, b = run.snag_span
    ra, rb = run.snag_span_recorded
    assert ra == pytest.approx(a, abs=0.02)  # before the snag the two axes agree
    assert rb - ra > b - a + 0.3
    assert np.all(np.diff(run.tracked_s) >= 0)


def test_on_the_recorded_path_the_thesis_span_at_5_m_is_bracketed():
    """Allan 2015 at g_F = 5 m: snag at 7.91 m, unsnag at 14.95 m (7.04 m apart). A follower
    that keeps its gap and one limited to the leader's speed bracket it on the recorded axis."""
    keeps = simulate_snag(SnagScenario(gap=5.0)).snag_span_recorded
    slow = simulate_snag(SnagScenario(gap=5.0, max_speed=0.4)).snag_span_recorded
    assert keeps[1] - keeps[0] < 7.04 < slow[1] - slow[0]
    assert keeps[0] == pytest.approx(7.91, abs=0.1)


def test_max_speed_limits_the_advance_and_none_keeps_the_gap():
    base = simulate_snag(SnagScenario(gap=2.0))
    same = simulate_snag(SnagScenario(gap=2.0, max_speed=None))
    np.testing.assert_array_equal(base.robot_xy, same.robot_xy)
    capped = simulate_snag(SnagScenario(gap=2.0, max_speed=0.3))
    step = np.hypot(*np.diff(capped.robot_xy, axis=0).T)
    assert step.max() <= 0.3 * capped.scenario.sample_time + 1e-9


@pytest.mark.parametrize("value", [0.0, -1.0, float("nan"), 1e9, "fast"])
def test_bad_max_speed_is_refused_naming_it(value):
    with pytest.raises(InvalidParameterError, match="max_speed"):
        SnagScenario(max_speed=value)
