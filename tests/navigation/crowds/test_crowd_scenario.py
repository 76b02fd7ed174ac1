"""Crowd scenarios (issue 23, item 1): layouts, regions of pedestrians and walls, density,
the JuPedSim pedestrians (placement, desired speeds, streams that keep the crowd's size)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import Point, box

import designlab as dl
from designlab.navigation.crowds.layouts import LAYOUTS
from designlab.navigation.crowds.pedestrians import PedestrianSim

nav = dl.navigation
SIZES = {"open_plaza": (10.0, 10.0), "crossing": (4.0, 16.0)}


@pytest.mark.parametrize("layout", sorted(LAYOUTS))
def test_layouts_walls_outside_the_walkable_area_and_task_inside(layout):
    w, length = SIZES.get(layout, (4.0, 20.0))
    c = nav.crowd(layout, 10, width=w, length=length)
    area = c.geometry.area
    for (x0, y0), (x1, y1) in c.geometry.walls:
        assert area.intersection(box(x0, y0, x1, y1)).area < 1e-9  # walls bound the area
    for p in (c.robot_start, c.robot_goal):
        assert area.contains(Point(p))
    for s in c.geometry.streams:
        assert area.covers(s.spawn) and area.covers(s.exit)
    assert math.isclose(sum(s.share for s in c.geometry.streams), 1.0)


def test_wall_regions_are_the_rectangle_sizing_with_no_offset():
    c = nav.crowd("corridor_counterflow", 5)
    rb = c.robot
    v, a, ts = rb.max_speed, rb.max_accel, c.sample_time
    r3 = v * ts + 0.5 * a * (v / a) ** 2 + rb.radius  # stop before the wall (5.3.11b)
    dt2 = (r3 - 0.5 * a * (v / a) ** 2) / v + v / a  # sidestep with B = 0 (5.3.6b)
    r2, got3 = c.wall_regions()
    assert math.isclose(got3, r3) and math.isclose(r2, v * (dt2 + ts))


def test_pedestrian_regions_are_sized_for_the_fastest_pedestrian():
    c = nav.crowd("corridor_counterflow", 5, max_desired_speed=1.5, pedestrian_radius=0.25)
    rb = c.robot
    v, a, ts, vp = rb.max_speed, rb.max_accel, c.sample_time, 1.5
    r3 = vp * (v / a + ts) + v * ts + 0.5 * a * (v / a) ** 2 + 0.25 + rb.radius
    dt2 = (r3 - 0.5 * a * (v / a) ** 2) / v + v / a
    r2, got3 = c.pedestrian_regions()
    assert math.isclose(got3, r3) and math.isclose(r2, (v + vp) * (dt2 + ts))
    r2, r3 = c.replace(critical_radius=0.9, active_radius=2.5).pedestrian_regions()
    assert (r2, r3) == (2.5, 0.9)


def test_density_gives_the_number_on_the_walkable_area():
    c = nav.crowd("bottleneck", density=0.3, width=4.0, length=20.0)
    assert c.pedestrians == round(0.3 * c.area_m2) and c.density == 0.3


def test_placement_speeds_and_seeds():
    c = nav.crowd("corridor_counterflow", 30, seed=7)
    a, b = PedestrianSim(c), PedestrianSim(c)
    _ids, P = a.positions()
    assert np.array_equal(P, b.positions()[1])  # the seed fixes the crowd
    assert not np.array_equal(P, PedestrianSim(c.replace(seed=8)).positions()[1])
    d = np.hypot(*(P[:, None, :] - P[None, :, :]).transpose(2, 0, 1))
    assert d[np.triu_indices(30, 1)].min() >= 2 * c.pedestrian_radius + 0.1 - 1e-9
    assert np.hypot(*(P - c.robot_start).T).min() > c.pedestrian_regions()[1]
    v = np.array(a.speeds)
    assert v.min() >= 0.3 and v.max() <= c.max_desired_speed
    assert abs(v.mean() - c.desired_speed) < 3 * c.desired_speed_sd / math.sqrt(30) + 0.05


def test_streams_keep_the_crowd_size():
    c = nav.crowd("corridor_counterflow", 20, length=8.0, seed=1, horizon=12.0)
    run = nav.simulate_pedestrians(c)
    present = (~np.isnan(run.pedestrian_positions[:, :, 0])).sum(axis=1)
    assert run.pedestrian_positions.shape[1] > 20  # some left and were replaced
    assert present[-1] >= 17 and present.max() <= 20 + 2  # leaving ones stay one step


def test_records_and_wall_distance_of_a_run():
    c = nav.crowd("bottleneck", 6, width=4.0, length=10.0, seed=3, horizon=1.2)
    res = nav.simulate(c, nav.VFFGains(4.3, 0.68, 20.3, 240.7))
    n = res.times.size
    np.testing.assert_allclose(res.times, np.arange(n) * c.pedestrian_step, atol=1e-12)
    assert res.robot_positions.shape == res.robot_velocities.shape == (n, 2)
    walls = c.walls()
    at_records = min(float(w.contour_distance(res.robot_positions).min()) for w in walls)
    # the run's minimum is taken at every 1 ms step: at most the records' minimum
    assert res.min_wall_distance <= at_records + 1e-12
    assert res.min_wall_distance >= at_records - c.robot.max_speed * c.pedestrian_step
    finite = np.isfinite(res.nearest_distance)
    d = np.hypot(*(res.pedestrian_positions - res.robot_positions[:, None, :]).transpose(2, 0, 1))
    np.testing.assert_allclose(res.nearest_distance[finite], np.nanmin(d, axis=1)[finite])
    assert res.min_distance <= res.nearest_distance.min() + 1e-12


def test_fast_reads_equal_full_reads_while_pedestrians_come_and_go():
    sim = PedestrianSim(nav.crowd("corridor_counterflow", 25, length=8.0, seed=5,
                                  react_to_robot=True))  # fmt: skip
    changes = 0
    for _ in range(600):
        sim.step((1.5, 2.0))
        changes += sim._order is None  # someone left or entered: a full read comes
        fast = sim.positions()
        full = sim._read_all()
        assert np.array_equal(fast[0], full[0]) and np.array_equal(fast[1], full[1])
    assert changes > 0  # pedestrians left and entered


def test_results_honour_the_contract_and_pickle():
    import pickle

    from designlab.results import check_result

    c = nav.crowd("open_plaza", 6, width=8.0, length=8.0, seed=1, horizon=0.3)
    res = nav.simulate(c, nav.VFFGains(4.3, 0.68, 20.3, 240.7))
    peds = nav.simulate_pedestrians(c)
    for r in (res, peds, res.pedestrians()):
        check_result(r)
    back = pickle.loads(pickle.dumps(res))  # process executors send results between processes
    assert back.crowd == c and np.array_equal(back.robot_positions, res.robot_positions)
    frame = peds.to_frame()
    assert set(frame.columns) == {"t_s", "pedestrian", "x_m", "y_m"}
    assert len(frame) == int((~np.isnan(peds.pedestrian_positions[:, :, 0])).sum())


@pytest.mark.parametrize("y", [0.34, 1.2])  # near the south wall (inside r2 + V T_s), and away
def test_wall_distance_is_exact_where_it_matters(y):
    c = nav.crowd("corridor_counterflow", 2, length=10.0, start=(1.5, y), goal=(8.5, y),
                  horizon=1.2, seed=9)  # fmt: skip
    res = nav.simulate(c, nav.VFFGains(4.3, 0.68, 20.3, 240.7))
    at_records = min(float(w.contour_distance(res.robot_positions).min()) for w in c.walls())
    assert res.min_wall_distance <= at_records + 1e-12 or y > 1.0
    assert res.min_wall_distance >= at_records - c.robot.max_speed * c.sample_time
