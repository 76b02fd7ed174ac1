"""Crowd metrics against closed forms and independent computations."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.errors import DesignlabError
from designlab.navigation.crowds.metrics import (
    clearance,
    cvar,
    exit_times,
    path_deviation,
    pedestrian_delay,
    personal_space_time,
    point_to_path,
    wilson_interval,
)

Z95 = 1.959963984540054  # the 97.5 % normal quantile


def wilson_formula(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson (1927): (p + z^2/2n -+ z sqrt(p(1-p)/n + z^2/4n^2)) / (1 + z^2/n)."""
    p = k / n
    centre = p + z * z / (2 * n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return (centre - half) / (1 + z * z / n), (centre + half) / (1 + z * z / n)


@given(st.integers(1, 500), st.data())
@settings(max_examples=60, deadline=None)
def test_wilson_matches_the_closed_form(n: int, data: st.DataObject) -> None:
    k = data.draw(st.integers(0, n))
    lo, hi = wilson_interval(k, n)
    want = wilson_formula(k, n)
    assert lo == pytest.approx(want[0], abs=1e-9)
    assert hi == pytest.approx(want[1], abs=1e-9)
    assert 0.0 <= lo <= k / n <= hi <= 1.0


def test_wilson_known_values() -> None:
    # 0 of n: upper bound z^2 / (n + z^2) (the "rule of three" neighbour)
    assert wilson_interval(0, 10)[1] == pytest.approx(Z95**2 / (10 + Z95**2), abs=1e-12)
    assert wilson_interval(0, 10)[0] == 0.0
    assert wilson_interval(10, 10)[0] == pytest.approx(10 / (10 + Z95**2), abs=1e-12)
    assert all(math.isnan(v) for v in wilson_interval(0, 0))
    lo90, hi90 = wilson_interval(3, 20, confidence=0.9)
    lo95, hi95 = wilson_interval(3, 20)
    assert lo95 < lo90 < 0.15 < hi90 < hi95


@pytest.mark.parametrize(
    ("k", "n", "conf"),
    [(-1, 3, 0.95), (4, 3, 0.95), (1, 2.5, 0.95), (True, 3, 0.95), (1, 3, 1.0), (1, 3, math.nan)],
)
def test_wilson_bad_input(k: object, n: object, conf: float) -> None:
    with pytest.raises(DesignlabError):
        wilson_interval(k, n, conf)  # type: ignore[arg-type]


def cvar_rockafellar_uryasev(x: np.ndarray, alpha: float) -> float:
    """min over t of t + mean((x - t)+) / (1 - alpha): the minimum lies at a sample."""
    return min(t + np.mean(np.maximum(x - t, 0.0)) / (1 - alpha) for t in x)


@given(
    st.lists(st.floats(-1e3, 1e3, allow_nan=False), min_size=1, max_size=40),
    st.floats(0.0, 0.97),
)
@settings(max_examples=80, deadline=None)
def test_cvar_equals_the_rockafellar_uryasev_minimum(xs: list[float], alpha: float) -> None:
    x = np.asarray(xs)
    assert cvar(x, alpha) == pytest.approx(cvar_rockafellar_uryasev(x, alpha), rel=1e-9, abs=1e-7)
    assert x.mean() - 1e-9 <= cvar(x, alpha) <= x.max() + 1e-9


def test_cvar_edges() -> None:
    assert cvar([1.0, 2.0, 3.0, 4.0], 0.0) == pytest.approx(2.5)
    assert cvar([1.0, 2.0, 3.0, 4.0], 0.75) == 4.0
    assert cvar([1.0, math.inf], 0.5) == math.inf
    assert math.isnan(cvar([], 0.5))
    for bad in ({"costs": [1.0, math.nan], "alpha": 0.5}, {"costs": [1.0], "alpha": 1.0},
                {"costs": [1.0], "alpha": -0.1}):  # fmt: skip
        with pytest.raises(DesignlabError):
            cvar(**bad)  # type: ignore[arg-type]


def test_clearance_and_personal_space() -> None:
    t = np.arange(5) * 0.1
    robot = np.zeros((5, 2))
    peds = np.full((5, 2, 2), np.nan)
    peds[:, 0] = [[3, 0], [1, 0], [0.6, 0.8], [2, 0], [0.5, 0]]
    peds[1:3, 1] = [[0, -0.5], [0, 5]]
    assert clearance(robot, peds).tolist() == [3.0, 0.5, 1.0, 2.0, 0.5]
    # inside 1.2 m at samples 1, 2 and 4 (the last lasts as long as the step before it)
    assert personal_space_time(t, robot, peds) == pytest.approx(0.3)
    # a 0.9 m robot reaches 2.1 m: sample 3 (2.0 m) counts too
    assert personal_space_time(t, robot, peds, robot_radius=0.9) == pytest.approx(0.4)
    assert personal_space_time(t, robot, peds, radius=0.4) == 0.0
    assert clearance(robot, np.full((5, 0, 2), 0.0)).tolist() == [math.inf] * 5


@pytest.mark.parametrize(
    "kwargs",
    [
        {"radius": 0.0},
        {"radius": math.nan},
        {"robot_radius": -1.0},
        {"times": [0.0, 0.2, 0.1, 0.3, 0.4]},
        {"times": [0.0, 0.1]},
    ],
)
def test_personal_space_bad_input(kwargs: dict) -> None:
    args = {
        "times": np.arange(5) * 0.1,
        "robot": np.zeros((5, 2)),
        "pedestrians": np.ones((5, 1, 2)),
    }
    args.update(kwargs)
    with pytest.raises(DesignlabError):
        personal_space_time(**args)


def test_exit_times_delay_and_deviation() -> None:
    t = np.arange(6) * 0.5
    without = np.full((6, 3, 2), np.nan)
    without[:2, 0] = 0.0  # leaves at 1.0 s
    without[:4, 1] = 0.0  # leaves at 2.0 s
    without[:3, 2] = 0.0  # leaves at 1.5 s
    with_r = np.full((6, 3, 2), np.nan)
    with_r[:3, 0] = 0.0  # leaves at 1.5 s: +0.5 s
    with_r[:, 1] = 0.0  # never leaves: beyond the window
    with_r[:5, 2] = 0.0  # leaves at 2.5 s: +1.0 s
    assert exit_times(t, without).tolist() == [1.0, 2.0, 1.5]
    assert exit_times(t, with_r).tolist() == [1.5, math.inf, 2.5]
    d = pedestrian_delay(t, with_r, without)
    assert d == {"mean_s": 0.75, "max_s": 1.0, "compared": 2.0, "beyond_window": 1.0}
    dev = path_deviation(t, with_r, without)
    assert dev == {"mean_m": 0.0, "max_m": 0.0, "compared": 3.0}


def test_deviation_is_geometric_not_timed() -> None:
    """A pedestrian slowed on the same line deviates 0 m; one pushed sideways its offset."""
    t = np.arange(5.0)
    line = np.stack([t, np.zeros(5)], axis=1)[:, None, :]
    slowed = np.stack([t / 2, np.zeros(5)], axis=1)[:, None, :]
    pushed = line.copy()
    pushed[2, 0, 1] = 0.3
    assert path_deviation(t, slowed, line)["max_m"] == 0.0
    assert path_deviation(t, pushed, line)["max_m"] == pytest.approx(0.3)


@given(
    st.lists(st.tuples(st.floats(-50, 50), st.floats(-50, 50)), min_size=1, max_size=8),
    st.lists(st.tuples(st.floats(-50, 50), st.floats(-50, 50)), min_size=2, max_size=6),
)
@settings(max_examples=60, deadline=None)
def test_point_to_path_against_dense_sampling(points: list, path: list) -> None:
    v = np.asarray(path)
    s = np.linspace(0.0, 1.0, 2001)
    dense = np.concatenate([a + s[:, None] * (b - a) for a, b in itertools.pairwise(v)])
    exact = point_to_path(points, v)
    brute = np.linalg.norm(np.asarray(points)[:, None] - dense[None], axis=2).min(axis=1)
    seg = np.linalg.norm(np.diff(v, axis=0), axis=1).max()
    assert np.all(exact <= brute + 1e-9)
    assert np.all(brute - exact <= seg / 2000 + 1e-9)


def test_delay_bad_shapes() -> None:
    with pytest.raises(DesignlabError):
        pedestrian_delay([0.0, 1.0], np.zeros((2, 2, 2)), np.zeros((2, 3, 2)))
    with pytest.raises(DesignlabError):
        path_deviation([0.0, 1.0, 2.0], np.zeros((2, 1, 2)), np.zeros((3, 1, 2)))
