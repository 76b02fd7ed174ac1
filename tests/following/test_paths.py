"""Leader paths (Allan 2015 Sec. 2.4-2.5, 3.3-3.5; the project's fixed shapes)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import ellipk

import designlab as dl
from designlab.errors import InvalidParameterError

fol = dl.following


@pytest.mark.parametrize("a", [2.0, 4.0])
def test_lemniscate_length_and_start(a):
    # Bernoulli lemniscate perimeter: 4 a K(1/2) / sqrt(2) (complete elliptic integral, m = 1/2)
    exact = 4.0 * a * ellipk(0.5) / math.sqrt(2.0)
    p = fol.figure_eight(a=a, points=8001)
    assert p.length == pytest.approx(exact, rel=1e-5)
    assert p.points[0] == pytest.approx([a, 0.0])
    assert p.start_heading == math.pi / 2  # heading +y
    d = p.points[1] - p.points[0]
    assert math.atan2(d[1], d[0]) == pytest.approx(math.pi / 2, abs=2e-3)
    # right lobe first, counter-clockwise: the first quarter has x > 0 and y > 0
    q = p.points[1 : len(p.points) // 8]
    assert np.all(q[:, 0] > 0) and np.all(q[:, 1] > 0)
    # the thesis's "around 11 m" (a = 2) and "around 20 m" (a = 4)
    assert abs(p.length - {2.0: 11.0, 4.0: 20.0}[a]) < 1.0


def test_square_s():
    p = fol.square_s()
    assert p.points.tolist() == [[0, 0], [2, 0], [4, 0], [4, 2], [2, 2], [2, 4], [4, 4]]
    assert p.length == 12.0
    # one left, one left, one right, one right corner
    d = np.diff(p.points, axis=0)
    turn = np.sign(d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0])
    assert turn.tolist() == [0, 1, 1, -1, -1]


def test_slalom_passes_cones_on_alternate_sides():
    p = fol.slalom(spacing=1.5, amplitude=0.5)
    assert p.obstacles.tolist() == [[1.5, 0.0], [3.0, 0.0], [4.5, 0.0]]
    for k, (cx, _) in enumerate(p.obstacles):
        y = np.interp(cx, p.points[:, 0], p.points[:, 1])
        assert y == pytest.approx(0.5 * (-1) ** k, abs=1e-4)
    back = fol.slalom(out_and_back=True)
    # the return leg passes each cone on the other side, the turn is a half circle of radius A
    ret = back.points[back.points[:, 1] * 0 == 0][len(p.points) + 58 :]
    for k, (cx, _) in enumerate(p.obstacles):
        y = np.interp(cx, ret[::-1, 0], ret[::-1, 1])
        assert y == pytest.approx(-0.5 * (-1) ** k, abs=1e-4)
    assert back.length == pytest.approx(2 * p.length + math.pi * 0.5, rel=2e-3)


def test_corridor_circle_line():
    c = fol.corridor_corner(width=1.0, leg=3.0)
    assert c.length == pytest.approx(6.0 + math.pi * 0.5 / 2, rel=1e-4)
    assert c.points[-1] == pytest.approx([3.5, 3.5])
    circ = fol.circle(radius=2.0)
    assert np.allclose(np.hypot(*circ.points.T), 2.0)
    assert circ.start_heading == pytest.approx(math.pi / 2)
    assert fol.straight_line(3.0).position_at(1.5) == pytest.approx([1.5, 0.0])


def test_leader_walks_at_constant_speed_and_stops():
    p = fol.straight_line(2.0)
    xy = p.leader_positions(speed=0.5, sample_time=0.1, duration=6.0)
    assert len(xy) == 61
    assert xy[10] == pytest.approx([0.5, 0.0])
    assert xy[-1] == pytest.approx([2.0, 0.0])  # stopped at the end


def test_user_paths(tmp_path):
    p = fol.from_array([[0, 0], [0, 0], [3, 4]])  # duplicates are dropped
    assert len(p.points) == 2 and p.length == 5.0
    f = tmp_path / "walk.csv"
    f.write_text("t_s,x_m,y_m\n0,0,0\n1,1,0\n2,1,1\n")
    w = fol.from_csv(f)
    assert w.length == 2.0 and w.name == "walk"
    assert fol.make_path({"points": [[0, 0], [1, 1]]}).length == pytest.approx(math.sqrt(2))
    assert fol.make_path("square_s").length == 12.0


@pytest.mark.parametrize(
    "bad",
    [
        [[0.0, 0.0]],
        [[0.0, 0.0], [float("nan"), 1.0]],
        [[0.0, 0.0], [float("inf"), 1.0]],
        [[1.0, 1.0], [1.0, 1.0]],
        [0.0, 1.0, 2.0],
        "path",
    ],
)
def test_bad_paths(bad):
    with pytest.raises(InvalidParameterError, match=r"path\.points"):
        fol.from_array(bad)


def test_bad_shape_arguments(tmp_path):
    with pytest.raises(InvalidParameterError, match=r"figure_eight\.a"):
        fol.figure_eight(a=-2.0)
    with pytest.raises(InvalidParameterError, match=r"slalom\.cones"):
        fol.slalom(cones=0)
    with pytest.raises(InvalidParameterError, match=r"path\.type"):
        fol.make_path({"type": "spiral"})
    f = tmp_path / "w.csv"
    f.write_text("a,b\n0,0\n1,1\n")
    with pytest.raises(InvalidParameterError, match="x_m"):
        fol.from_csv(f)
