"""Normal path deviation (Allan 2015 App. A) on geometries with exact answers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.following.tether.path_deviation import resegment
from designlab.results import check_result

fol = dl.following
TOL = 1e-4  # m


def test_parallel_lines():
    x = np.linspace(0.0, 6.0, 301)
    # the robot starts 0.3 m behind the leader and ends 0.3 m behind it
    d = fol.normal_path_deviation(
        np.column_stack([x, 0 * x]), np.column_stack([x - 0.3, 0.25 + 0 * x])
    )
    check_result(d)
    assert d.mean == pytest.approx(0.25, abs=TOL)
    assert d.max == pytest.approx(0.25, abs=TOL)
    assert d.std < TOL
    assert d.mean_over_b == pytest.approx(0.25 / 0.28, abs=TOL / 0.28)
    # comparison range: from the leader's start to where the robot stopped
    assert d.distance[-1] == pytest.approx(6.0 - 0.3, abs=0.05)
    assert not d.fallback.any()


@pytest.mark.parametrize("order", ["inner_first", "outer_first"])
def test_concentric_arcs_both_orders(order):
    r1, r2 = 2.0, 2.3
    t = np.linspace(0.0, 1.5 * math.pi, 1201)  # chord sag r (1 - cos(dt/2)) < 2e-5 m
    inner = np.column_stack([r1 * np.cos(t), r1 * np.sin(t)])
    outer = np.column_stack([r2 * np.cos(t), r2 * np.sin(t)])
    a, b = (inner, outer) if order == "inner_first" else (outer, inner)
    d = fol.normal_path_deviation(a, b)
    assert d.status == "ok"
    assert np.all(np.abs(d.profile - 0.3) < TOL)
    assert len(d.profile) > 0.9 * (len(d.leader_nodes) - 1)


def _dist_to_offset_square_s(pts: np.ndarray, dd: float) -> np.ndarray:
    """Distance to the exact left offset (by dd) of the square S, written out piece by piece.

    Left turns at (4,0), (4,2): the offset lines meet at a mitre point; right turns at
    (2,2), (2,4): the offset has a circular arc of radius dd about the corner.
    """
    segs = [
        ((0.0, dd), (4 - dd, dd)),
        ((4 - dd, dd), (4 - dd, 2 - dd)),
        ((4 - dd, 2 - dd), (2.0, 2 - dd)),
        ((2 - dd, 2.0), (2 - dd, 4.0)),
        ((2.0, 4 + dd), (4.0, 4 + dd)),
    ]
    arcs = [((2.0, 2.0), -math.pi, -math.pi / 2), ((2.0, 4.0), math.pi / 2, math.pi)]
    out = np.full(len(pts), np.inf)
    for (ax, ay), (bx, by) in segs:
        v = np.array([bx - ax, by - ay])
        t = np.clip(((pts - [ax, ay]) @ v) / (v @ v), 0.0, 1.0)
        q = np.array([ax, ay]) + t[:, None] * v
        out = np.minimum(out, np.hypot(*(pts - q).T))
    for (cx, cy), lo, hi in arcs:
        ang = np.arctan2(pts[:, 1] - cy, pts[:, 0] - cx)
        inside = (ang >= lo) & (ang <= hi)
        radial = np.abs(np.hypot(pts[:, 0] - cx, pts[:, 1] - cy) - dd)
        ends = np.minimum(
            np.hypot(pts[:, 0] - cx - dd * math.cos(lo), pts[:, 1] - cy - dd * math.sin(lo)),
            np.hypot(pts[:, 0] - cx - dd * math.cos(hi), pts[:, 1] - cy - dd * math.sin(hi)),
        )
        out = np.minimum(out, np.where(inside, radial, ends))
    return out


def test_square_s_against_its_exact_offset_with_corner_fallback():
    dd = 0.3
    leader = fol.square_s().points
    arc1 = [
        (2 + dd * math.cos(a), 2 + dd * math.sin(a))
        for a in np.linspace(-math.pi / 2, -math.pi, 400)
    ]
    arc2 = [
        (2 + dd * math.cos(a), 4 + dd * math.sin(a)) for a in np.linspace(math.pi, math.pi / 2, 400)
    ]
    robot = np.array(
        [
            (0.0, dd),
            (4 - dd, dd),
            (4 - dd, 2 - dd),
            (2.0, 2 - dd),
            *arc1,
            (2 - dd, 4.0),
            *arc2,
            (4.0, 4 + dd),
        ]
    )
    d = fol.normal_path_deviation(leader, robot)
    expected = _dist_to_offset_square_s(d.midpoints, dd)
    assert np.max(np.abs(d.profile - expected)) < TOL
    # straight parts: exactly dd; inner corners: the fallback to the mitre point, sqrt(x^2 + dd^2)
    assert d.fallback.sum() >= 20
    assert np.all(d.profile[d.fallback] > dd)
    assert np.all(d.profile[d.fallback] <= math.sqrt(2) * dd + TOL)
    assert d.distance[0] < 0.05 and d.distance[-1] > 11.95  # the whole leader path compared


def test_smooth_curve_against_its_parallel_curve():
    x = np.linspace(0.0, 10.0, 701)
    y = 0.5 * np.sin(x)
    tang = np.column_stack([np.ones_like(x), 0.5 * np.cos(x)])
    tang /= np.hypot(*tang.T)[:, None]
    nrm = np.column_stack([-tang[:, 1], tang[:, 0]])
    curve = np.column_stack([x, y])
    for dd in (0.2, -0.35):  # both sides; |dd| < the least radius of curvature (2 m)
        d = fol.normal_path_deviation(curve, curve + dd * nrm)
        assert np.all(np.abs(d.profile - abs(dd)) < TOL)


def test_crossing_paths_intersections_are_nodes():
    x = np.linspace(0.0, 4.0, 201)
    a = np.column_stack([x, 0 * x])
    b = np.column_stack([x, 0.2 * (x - 2.0)])  # crosses path 1 at x = 2
    d = fol.normal_path_deviation(a, b)
    assert np.any(np.all(np.isclose(d.leader_nodes, [2.0, 0.0], atol=1e-12), axis=1))
    assert np.any(np.all(np.isclose(d.follower_nodes, [2.0, 0.0], atol=1e-12), axis=1))
    # deviation along the normal (vertical) of a line of slope 0.2: 0.2 |x - 2|
    assert np.max(np.abs(d.profile - 0.2 * np.abs(d.midpoints[:, 0] - 2.0))) < TOL


def test_ordered_and_literal_comparison_range_on_an_out_and_back_path():
    """The literal App. A rule can match the robot's end to the leader's start."""
    ang = np.linspace(-math.pi / 2, math.pi / 2, 30)
    leader = np.vstack(
        [
            [[0.0, 0.0], [5.0, 0.0]],
            np.column_stack([5 + 0.2 * np.cos(ang), 0.2 + 0.2 * np.sin(ang)]),
            [[0.0, 0.4]],
        ]
    )
    # the robot cuts the hairpin: out 0.05 m beside the leader, back 0.25 m inside;
    # it stops at x = 1
    robot = np.array([[-0.5, 0.05], [4.8, 0.05], [4.8, 0.15], [1.0, 0.15]])
    ordered = fol.normal_path_deviation(leader, robot)
    literal = fol.normal_path_deviation(leader, robot, comparison="literal")
    assert ordered.distance[-1] > 9.0  # compared far into the return leg
    assert literal.distance[-1] < 1.5  # the robot's end was matched to the leader's out leg
    assert len(literal.profile) < 0.2 * len(ordered.profile)
    assert any("comparison range" in w for w in literal.warnings)
    out_leg = ordered.midpoints[:, 1] == 0.0
    assert np.allclose(ordered.profile[out_leg & (ordered.midpoints[:, 0] < 4.7)], 0.05, atol=TOL)


def test_resegment_minimum_and_maximum_passes():
    nodes = resegment(
        [[0, 0], [0.003, 0], [0.006, 0], [0.011, 0], [0.2, 0], [0.205, 0]], 0.01, 0.05
    )
    seg = np.hypot(*np.diff(nodes, axis=0).T)
    assert np.all(seg >= 0.01 - 1e-12) and np.all(seg <= 0.05 + 1e-12)
    assert nodes[0].tolist() == [0, 0] and nodes[-1].tolist() == [0.205, 0]
    # a stationary robot's duplicate nodes vanish
    dup = resegment([[0, 0]] * 5 + [[1, 0]] * 5)
    assert len(dup) == 21


@settings(max_examples=25, deadline=None)
@given(
    angle=st.floats(-math.pi, math.pi),
    shift=st.tuples(st.floats(-50, 50), st.floats(-50, 50)),
    offset=st.floats(0.02, 0.6),
)
def test_rigid_motion_invariance(angle, shift, offset):
    t = np.linspace(0.0, math.pi, 300)
    a = np.column_stack([3 * np.cos(t), 3 * np.sin(t)])
    b = np.column_stack([(3 + offset) * np.cos(t), (3 + offset) * np.sin(t)])
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    d0 = fol.normal_path_deviation(a, b)
    d1 = fol.normal_path_deviation(a @ rot.T + shift, b @ rot.T + shift)
    assert d1.mean == pytest.approx(d0.mean, abs=1e-7)
    assert d0.mean == pytest.approx(offset, abs=TOL)


@pytest.mark.parametrize(
    ("kw", "name"),
    [
        ({"leader_xy": [[0, 0]]}, "leader_xy"),
        ({"robot_xy": [[0, 0], [float("nan"), 0]]}, "robot_xy"),
        ({"leader_xy": [[0, 0], [1, float("inf")]]}, "leader_xy"),
        ({"leader_xy": np.zeros((3, 3))}, "leader_xy"),
        ({"max_segment": -1.0}, "max_segment"),
        ({"min_segment": 0.1, "max_segment": 0.05}, "max_segment"),
        ({"comparison": "both"}, "comparison"),
        ({"max_hit_ratio": 0.0}, "max_hit_ratio"),
    ],
)
def test_bad_input(kw, name):
    args = {"leader_xy": [[0, 0], [1, 0]], "robot_xy": [[0, 0.1], [1, 0.1]], **kw}
    with pytest.raises(InvalidParameterError, match=name):
        fol.normal_path_deviation(**args)
