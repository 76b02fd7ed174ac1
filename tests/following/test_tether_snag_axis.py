"""Snagging on the recorded-path axis and the followers (Allan 2015 Sec. 4.5.5, Table 4.1)."""

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


def test_the_constant_speed_robot_drives_v_f_along_the_recorded_path():
    """Table 4.1's follower: v_F dt of recorded path per step, whatever the snag does."""
    sc = SnagScenario(gap=2.5)
    assert sc.follower == "constant_speed"
    run = simulate_snag(sc)
    step = np.hypot(*np.diff(run.robot_xy, axis=0).T)
    # on a straight stretch of the recorded path the chord is the arc: exactly v_F dt
    assert step.max() == pytest.approx(sc.speed * sc.sample_time, rel=1e-9)
    assert step.max() <= sc.speed * sc.sample_time * (1 + 1e-12)
    # while the string is wrapped the gap-keeping robot drives faster than v_F
    ours = simulate_snag(SnagScenario(gap=2.5, follower="gap"))
    fast = np.hypot(*np.diff(ours.robot_xy, axis=0).T).max()
    assert fast > 1.5 * sc.speed * sc.sample_time


def test_the_release_is_measured_without_the_tips_jump():
    """At the release the estimated tip jumps back to the leader: one long recorded segment,
    not path; the recorded span ends at the last point recorded while wrapped."""
    run = simulate_snag(SnagScenario(gap=5.0, follower="gap"))
    seg = np.diff(run.tracked_s)
    jump = int(np.argmax(seg))
    assert seg[jump] > 1.0  # about 2.2 m at 5 m
    assert run.tracked_s_leader[jump + 1] >= run.snag_span[1] - 1e-9
    assert run.snag_span_recorded[1] == pytest.approx(run.tracked_s[jump])


def test_max_speed_limits_the_advance_and_none_keeps_the_gap():
    base = simulate_snag(SnagScenario(gap=2.0, follower="gap"))
    same = simulate_snag(SnagScenario(gap=2.0, follower="gap", max_speed=None))
    np.testing.assert_array_equal(base.robot_xy, same.robot_xy)
    capped = simulate_snag(SnagScenario(gap=2.0, follower="gap", max_speed=0.3))
    step = np.hypot(*np.diff(capped.robot_xy, axis=0).T)
    assert step.max() <= 0.3 * capped.scenario.sample_time + 1e-9


@pytest.mark.parametrize("value", [0.0, -1.0, float("nan"), 1e9, "fast"])
def test_bad_max_speed_is_refused_naming_it(value):
    with pytest.raises(InvalidParameterError, match="max_speed"):
        SnagScenario(max_speed=value)
