"""The compiled bookkeeping of crowd runs (issue 23, item 5): the same runs, bit for bit, as the
numpy path; the walkable-area test as shapely's; sums in numpy's order."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.affinity import translate
from shapely.geometry import Polygon, box

import designlab as dl
from designlab.navigation.crowds import simulate as crowd_sim
from designlab.navigation.crowds.bookkeeping import (
    area_edges,
    fill_candidates,
    inside_area,
    pairwise_sum,
)
from designlab.navigation.crowds.layouts import LAYOUTS, build_layout

nav = dl.navigation
GAINS = nav.VFFGains(4.3, 0.68, 20.3, 240.7)
FIELDS = (
    "arrival_time", "min_distance", "min_surface_distance", "min_wall_distance",
    "entered_critical", "collided", "critical_time", "energy", "slot_overflow",
    "robot_agent_offset", "critical_overlaps", "status", "warnings", "times",
    "robot_positions", "robot_velocities", "pedestrian_positions", "nearest_distance",
)  # fmt: skip


def _area_points(area, rng, n):
    """Random points around ``area``: inside, outside, on its edges and at its vertices."""
    x0, y0, x1, y1 = area.bounds
    free = np.column_stack([rng.uniform(x0 - 1, x1 + 1, n), rng.uniform(y0 - 1, y1 + 1, n)])
    edges = area_edges(area)
    t = rng.uniform(0, 1, n)
    e = edges[rng.integers(0, len(edges), n)]
    on = np.column_stack([e[:, 0] + t * (e[:, 2] - e[:, 0]), e[:, 1] + t * (e[:, 3] - e[:, 1])])
    # the vertices, and points an ulp off the edges' lines
    vert = edges[:, :2]
    off = np.concatenate([np.nextafter(on, on + 1), np.nextafter(on, on - 1)])
    grid = np.array(np.meshgrid(np.unique(edges[:, [0, 2]]), np.unique(edges[:, [1, 3]])))
    return np.concatenate([free, on, vert, off, grid.reshape(2, -1).T])


@settings(max_examples=25, deadline=None)
@given(
    name=st.sampled_from(sorted(LAYOUTS)),
    length=st.floats(6.0, 40.0),
    width=st.floats(2.0, 6.0),
    origin=st.tuples(st.floats(-50.0, 50.0), st.floats(-50.0, 50.0)),
    seed=st.integers(0, 2**32 - 1),
)
def test_inside_area_is_shapely_contains_on_every_layout(name, length, width, origin, seed):
    """Interior points only (an edge or a vertex is outside), as ``shapely.contains_xy``."""
    area = translate(build_layout(name, length=length, width=min(width, length / 2)).area, *origin)
    edges = area_edges(area)
    assert edges is not None
    pts = _area_points(area, np.random.default_rng(seed), 300)
    want = shapely.contains_xy(area, pts[:, 0], pts[:, 1])
    got = np.array([inside_area(edges, x, y) for x, y in pts])
    assert (got == want).all(), pts[got != want][:5]
    assert want.any() and (~want).any()


def test_inside_area_edges_holes_and_hostile_points():
    ring = box(0.0, 0.0, 4.0, 4.0).difference(box(1.0, 1.0, 2.0, 2.0))  # a hole
    edges = area_edges(ring)
    cases = {(0.5, 0.5): True, (1.5, 1.5): False, (1.0, 1.5): False, (0.0, 2.0): False,
             (4.0, 4.0): False, (3.0, 1.0): True, (math.nan, 1.0): False,
             (1.0, math.inf): False, (-math.inf, 2.0): False}  # fmt: skip
    for (x, y), want in cases.items():
        assert bool(inside_area(edges, x, y)) is want is bool(shapely.contains_xy(ring, x, y))
    assert area_edges(Polygon([(0, 0), (2, 0), (0, 1)])) is None  # a slanted edge


@settings(max_examples=60, deadline=None)
@given(
    n=st.integers(0, 700),
    lo=st.integers(0, 5),
    scale=st.floats(-12, 12),
    seed=st.integers(0, 2**32 - 1),
)
def test_pairwise_sum_is_numpys_sum_bit_for_bit(n, lo, scale, seed):
    rng = np.random.default_rng(seed)
    a = rng.standard_normal(n + lo) * 10.0 ** rng.uniform(scale - 4, scale + 4, n + lo)
    assert pairwise_sum(a, lo, n) == float(a[lo : lo + n].sum())


CASES = [  # (layout, pedestrians, seed, method, stabilising, react, order, length, horizon, K)
    ("corridor_counterflow", 25, 0, "vff", "lyapunov", False, "robot_first", 12.0, 4.0, 16),
    ("crossing", 25, 1, "cbf", "lyapunov", False, "robot_first", 12.0, 4.0, 16),
    ("bottleneck", 25, 2, "masoud", "lyapunov", True, "pedestrians_first", 12.0, 4.0, 16),
    ("open_plaza", 40, 0, "cbf", "lyapunov", False, "robot_first", 12.0, 4.0, 2),  # overflow
    ("open_plaza", 40, 3, "ge_cui", "lyapunov", True, "robot_first", 12.0, 4.0, 16),
    ("open_plaza", 2, 1, "cbf", "off", False, "robot_first", 8.0, 13.0, 16),  # arrives
]


@pytest.mark.parametrize("case", CASES, ids=[f"{c[0]}-{c[3]}" for c in CASES])
def test_compiled_runs_equal_the_numpy_path_bit_for_bit(case, monkeypatch):
    """Every metric and record of a run, compiled and numpy, on the same seeds."""
    name, n, seed, method, stab, react, order, length, horizon, k = case
    c = nav.crowd(name, n, length=length, width=4.0, seed=seed, horizon=horizon,
                  react_to_robot=react, neighbours=k)  # fmt: skip
    kw = dict(method=method, stabilising=stab, order=order)
    gains = GAINS if method == "vff" else None
    fast = nav.simulate(c, gains, **kw)
    monkeypatch.setattr(crowd_sim, "COMPILED", False)
    slow = nav.simulate(c, gains, **kw)
    for f in FIELDS:
        a, b = getattr(fast, f), getattr(slow, f)
        if isinstance(a, np.ndarray):
            assert a.shape == b.shape and np.array_equal(a, b, equal_nan=True), f
        else:
            assert a == b or (a != a and b != b), (f, a, b)
    if k == 2:
        assert fast.slot_overflow > 0  # the numpy fill of an overflowing period is covered
    if length == 8.0:
        assert fast.arrived


def test_closing_speed_regions_are_sized_on_the_compiled_path_too(monkeypatch):
    """With ``region_sizing="closing_speed"`` the compiled run sizes every pedestrian's active
    region from its closing speed exactly as the numpy path does, and the sizing takes effect
    (the run differs from the thesis's worst-case regions)."""
    kw = dict(length=12.0, width=4.0, seed=0, horizon=6.0, react_to_robot=False)
    sized = nav.crowd("corridor_counterflow", 25, region_sizing="closing_speed", **kw)
    thesis = nav.crowd("corridor_counterflow", 25, **kw)
    fast = nav.simulate(sized, GAINS, stabilising="off")
    worst = nav.simulate(thesis, GAINS, stabilising="off")
    monkeypatch.setattr(crowd_sim, "COMPILED", False)
    slow = nav.simulate(sized, GAINS, stabilising="off")
    assert np.array_equal(fast.robot_positions, slow.robot_positions)
    assert fast.min_distance == slow.min_distance
    assert not np.array_equal(fast.robot_positions, worst.robot_positions)


@settings(max_examples=60, deadline=None)
@given(
    n=st.integers(0, 30),
    k=st.integers(1, 8),
    absent=st.floats(0.0, 0.5),
    seed=st.integers(0, 2**32 - 1),
)
def test_fill_candidates_is_the_numpy_slots_with_ties_and_absent_pedestrians(n, k, absent, seed):
    """The slots (nearest first, a stable order on ties), the empty slots and the overlap flag
    as the numpy path writes them; NaN rows (not in the simulation) are never candidates."""
    rng = np.random.default_rng(seed)
    F = np.round(rng.uniform(-3.0, 3.0, (3, n, 2)), 1)  # a 0.1 m grid: equal distances occur
    F[:, rng.uniform(size=n) < absent] = np.nan
    F[0, rng.uniform(size=n) < absent] = np.nan  # entered a step ago: no acceleration yet
    x, y, r2, r3, dt = 0.05, -0.05, 2.0, 0.4, 0.01
    parked = np.tile(np.arange(6.0) + 100.0, (k, 1))
    obs = np.full((k, 6), -1.0)
    got_n, overlap = fill_candidates(
        F, np.arange(3, dtype=np.int64), n, x, y, r2 * r2, dt, obs, parked, 2 * r3,
        np.empty(n), np.empty(n, np.int64),
    )  # fmt: skip
    d2 = (F[2, :, 0] - x) ** 2 + (F[2, :, 1] - y) ** 2
    inside = np.flatnonzero(d2 < r2 * r2)
    assert got_n == inside.size
    if inside.size > k:
        assert (obs == -1.0).all() and not overlap  # left to the numpy fill
        return
    want = np.array(crowd_sim._slot_rows(F[:, inside], d2[inside].tolist(), dt)).reshape(-1, 6)
    assert (
        np.array_equal(obs[: inside.size], want)
        and (obs[inside.size :] == parked[inside.size :]).all()
    )
    Q = want[:, :2]
    pairs = [np.hypot(*(Q[i] - Q[j])) < 2 * r3 for i in range(len(Q)) for j in range(i + 1, len(Q))]
    assert overlap == any(pairs)
