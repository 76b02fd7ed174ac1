"""The wrapping tether (snag points on obstacle corners, with history)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.errors import InvalidParameterError
from designlab.following.tether.snag import SnagScenario, simulate_snag
from designlab.following.tether.wrap import WrappedTether, convex_corners

SQUARE = [(-0.2, -0.2), (0.2, -0.2), (0.2, 0.2), (-0.2, 0.2)]


@pytest.mark.parametrize("gap", [2.0, 3.0])
def test_one_convex_corner_equals_the_shortest_string(gap):
    run = simulate_snag(SnagScenario(gap=gap))
    t = WrappedTether([(0.0, 0.0)], run.robot_xy[0], run.leader_xy[0])
    lengths, wrapped = [], []
    for p, q in zip(run.robot_xy, run.leader_xy, strict=True):
        lengths.append(t.update(p, q)[0])
        wrapped.append(bool(t.snag_points))
    np.testing.assert_allclose(lengths, run.tether_length, atol=1e-12)
    assert wrapped == run.snagged.tolist()


def _loop(t, robot, turns, n=4001):
    a = np.linspace(math.pi / 2, math.pi / 2 + 2 * math.pi * turns, n)
    for ang in a[1:]:
        t.update(robot, (math.cos(ang), math.sin(ang)))


def test_a_loop_round_a_pillar_stays_wrapped_and_unwinds_exactly():
    robot = (-2.0, 1.0)
    t = WrappedTether(convex_corners(SQUARE), robot, (0.0, 1.0))
    _loop(t, robot, 1.0)
    # robot -> (-0.2, -0.2) -> (0.2, -0.2) -> (0.2, 0.2) -> tip (0, 1)
    expect = math.hypot(1.8, 1.2) + 0.4 + 0.4 + math.hypot(0.2, 0.8)
    assert t.snag_points == [(-0.2, -0.2), (0.2, -0.2), (0.2, 0.2)]
    assert t.length == pytest.approx(expect, abs=1e-12)
    a = np.linspace(math.pi / 2 + 2 * math.pi, math.pi / 2, 4001)
    for ang in a[1:]:
        t.update(robot, (math.cos(ang), math.sin(ang)))
    assert t.snag_points == [] and t.length == pytest.approx(2.0)


@settings(max_examples=40, deadline=None)
@given(st.floats(-3.0, 3.0), st.floats(0.5, 3.0))
def test_wrapped_length_is_never_shorter_than_the_chord(x, y):
    t = WrappedTether(convex_corners(SQUARE), (-2.0, 1.0), (0.0, 1.0))
    _loop(t, (-2.0, 1.0), 0.75, n=800)
    length, _ = t.update((x, y), t.tip)
    assert length >= math.dist((x, y), t.tip) - 1e-12


def test_convex_corners_either_orientation():
    star = [(0, 0), (2, 0), (2, 2), (1, 1), (0, 2)]
    assert convex_corners(star) == convex_corners(star[::-1])[::-1]
    assert (1.0, 1.0) not in convex_corners(star)


@pytest.mark.parametrize(
    "polygon", [[(0, 0), (1, 1)], [(0, 0), (1, 1), (2, 2)], [(0, 0), (1, math.nan), (2, 0)], "abc"]
)
def test_convex_corners_refuses(polygon):
    with pytest.raises(InvalidParameterError, match="polygon"):
        convex_corners(polygon)


@pytest.mark.parametrize("bad", [(math.nan, 0.0), (0.0,), "xy", None, (math.inf, 1.0)])
def test_tether_refuses_bad_points(bad):
    with pytest.raises(InvalidParameterError):
        WrappedTether([(0.0, 0.0)], bad, (1.0, 1.0))
    t = WrappedTether([(0.0, 0.0)], (1.0, 0.0), (1.0, 1.0))
    with pytest.raises(InvalidParameterError):
        t.update((1.0, 0.0), bad)


@pytest.mark.parametrize("corners", ["abc", [(0.0, math.nan)], [[1.0, 2.0, 3.0]]])
def test_tether_refuses_bad_corners(corners):
    with pytest.raises(InvalidParameterError, match="corners"):
        WrappedTether(corners, (0.0, 0.0), (1.0, 1.0))
