"""Issue 35, items 1-3: a sealed arena and exclusive outcomes, a coupling validated to a
bound (the pedestrians see the robot where it is) and pedestrians paired by identity."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from shapely.geometry import box
from shapely.ops import unary_union

import designlab as dl
from designlab.navigation.crowds.layouts import LAYOUTS, WALL_THICKNESS, build_layout
from designlab.navigation.crowds.simulate import AGENT_OFFSET_BOUND, OUTCOMES, _event

nav = dl.navigation


@pytest.mark.parametrize("name", sorted(LAYOUTS))
def test_every_layout_is_sealed(name):
    # the band of half a wall's thickness around the walkable area lies in the walls: the
    # robot cannot leave through an end (exact polygon arithmetic)
    lay = build_layout(name, length=12.0, width=4.0)
    walls = unary_union([box(a[0], a[1], b[0], b[1]) for a, b in lay.walls])
    band = lay.area.buffer(WALL_THICKNESS / 2, join_style="mitre").difference(lay.area)
    assert band.difference(walls).area <= 1e-12


def _fake(**kw):
    base = dict(
        collision_time=math.inf,
        left_area=0.0,
        failure="",
        failure_time=math.inf,
        arrival=math.inf,
        s=SimpleNamespace(crowd=SimpleNamespace(time_limit=30.0)),
    )
    return SimpleNamespace(**{**base, **kw})


@pytest.mark.parametrize(
    ("events", "expected"),
    [
        ({}, ("timeout", 30.0)),
        ({"arrival": 12.0}, ("arrived", 12.0)),
        ({"arrival": 12.0, "collision_time": 3.0}, ("collision", 3.0)),
        ({"arrival": 12.0, "collision_time": 13.0}, ("arrived", 12.0)),
        ({"left_area": 4.5, "failure": "x", "failure_time": 4.6}, ("left_area", 4.5)),
        (
            {"failure": "JuPedSim", "failure_time": 2.0, "collision_time": 2.4},
            ("simulator_failed", 2.0),
        ),
        ({"collision_time": 5.0, "left_area": 5.0}, ("collision", 5.0)),
    ],
)
def test_the_outcome_is_the_first_event(events, expected):
    assert _event(_fake(**events)) == expected
    assert expected[0] in OUTCOMES


def test_outcome_columns_are_in_the_frame():
    c = nav.crowd("corridor_counterflow", 6, length=8.0, seed=1, horizon=1.2)
    res = nav.simulate(c, nav.OPTIMAL_GAINS)
    row = res.to_frame().iloc[0]
    assert res.outcome == "timeout" and res.outcome_time == c.time_limit
    assert row["outcome"] == "timeout" and not row["coupling_exceeded"]
    assert any("outcome timeout" in w for w in res.warnings)


def _head_on(model: str, method: str):
    """A pedestrian walking straight at the robot along the corridor's axis; the
    pedestrians avoid the robot."""
    return nav.crowd(
        "corridor_counterflow", 1, width=3.0, length=9.0, seed=0, model=model,
        react_to_robot=True, paths=(((7.0, 1.5), (0.6, 1.5)),), start=(1.5, 1.5),
        goal=(7.5, 1.5), desired_speed=1.2, desired_speed_sd=0.0, horizon=9.0,
    )  # fmt: skip


@pytest.mark.parametrize("model", ["collision_free_speed", "social_force"])
@pytest.mark.parametrize("method", ["cbf", "vff"])
def test_pedestrians_see_the_robot_where_it_is(model, method):
    c = _head_on(model, method)
    res = nav.simulate(c, nav.OPTIMAL_GAINS if method == "vff" else None, method=method)
    assert res.robot_agent_offset <= AGENT_OFFSET_BOUND and not res.coupling_exceeded
    P, R = res.pedestrian_positions[:, 0], res.robot_positions
    d = np.hypot(P[:, 0] - R[:, 0], P[:, 1] - R[:, 1])
    # while the offset holds, the pedestrian's centre is never inside the robot's disc
    assert np.nanmin(d) > c.robot.radius


def test_replacements_are_the_same_persons_with_and_without_the_robot():
    # in this crowd the robot changes who leaves first: the entry orders differ, yet every
    # identity present in both runs is the same person (desired speed, stream)
    c = nav.crowd("corridor_counterflow", density=0.6, width=3.0, length=6.0, seed=0,
                  react_to_robot=True, horizon=12.0)  # fmt: skip
    res, alone = nav.simulate(c, nav.OPTIMAL_GAINS), nav.simulate_pedestrians(c)
    ia, ib = res.pedestrian_ids, alone.pedestrian_ids
    n = min(ia.size, ib.size)
    assert (ia[:n] != ib[:n]).any()  # paired by entry order, different persons
    va = dict(zip(ia.tolist(), res.desired_speeds.tolist(), strict=True))
    vb = dict(zip(ib.tolist(), alone.desired_speeds.tolist(), strict=True))
    common = sorted(set(va) & set(vb))
    assert len(common) >= n - 2 and len(common) > c.pedestrians
    assert all(va[k] == vb[k] for k in common)
    # replacements carry identities N + k S + s: stream s of the person
    assert all(k < c.pedestrians or (k - c.pedestrians) % 2 in (0, 1) for k in common)
