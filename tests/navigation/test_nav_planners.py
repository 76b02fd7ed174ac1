"""The Sec. 5.7 planners against exact and independent answers."""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from designlab import navigation as nav
from designlab.errors import InvalidParameterError
from designlab.navigation.planners import (
    ERRTSettings,
    FieldDStarSettings,
    VOSettings,
    simulate_planner,
)
from designlab.navigation.planners import errt as errt_mod
from designlab.navigation.planners.field_dstar import compute_cost, node_costs
from designlab.navigation.planners.velocity_obstacle import (
    in_velocity_obstacle,
    time_to_collision,
)
from designlab.navigation.planners.world import Snapshot
from designlab.navigation.scenario_io import mirrored, scenario_from_dict

f = st.floats(-3, 3, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(f, f, f, f, f, f, st.floats(0.1, 1.0))
def test_the_untruncated_vo_is_the_collision_cone(
    px: float, py: float, vx: float, vy: float, wx: float, wy: float, radius: float
) -> None:
    p = np.array([px, py])
    if np.hypot(*p) <= radius * 1.01:
        return
    w = np.array([wx, wy])  # robot velocity; obstacle velocity v_o
    v_o = np.array([vx, vy])
    rel = w - v_o
    inside = in_velocity_obstacle(np.zeros(2), p[None], v_o[None], np.array([radius]),
                                  w[None], horizon=1e9)[0]  # fmt: skip
    if np.hypot(*rel) < 1e-9:
        assert not inside
        return
    # the cone: apex v_o, axis p, half-angle asin(R / |p|) (Fiorini & Shiller 1998)
    cos_angle = rel @ p / (np.hypot(*rel) * np.hypot(*p))
    half = math.asin(radius / np.hypot(*p))
    angle = math.acos(np.clip(cos_angle, -1, 1))
    if abs(angle - half) < 1e-7:
        return  # on the boundary
    assert inside == (angle < half)


@settings(max_examples=100, deadline=None)
@given(f, f, f, f, st.floats(0.1, 1.0))
@example(0.109375, 1e-9, 0.0, 0.0, 0.109375)  # |p| rounds to R, |p|^2 does not (found by CI)
def test_time_to_collision_is_the_first_contact(
    px: float, py: float, wx: float, wy: float, radius: float
) -> None:
    p, w = np.array([px, py]), np.array([wx, wy])
    t = time_to_collision(np.zeros(2), p[None], np.zeros((1, 2)), np.array([radius]), w[None])
    t = float(t[0, 0])
    d = float(np.hypot(*p))
    if d < radius - 1e-12:
        assert t == 0.0
    elif abs(d - radius) <= 1e-12 and t == 0.0:
        return  # touching at the start: inside or not by the last bit (|p|^2 against R^2)
    elif math.isfinite(t):
        assert np.hypot(*(p - w * t)) == pytest.approx(radius, abs=1e-9)
        ts = np.linspace(0, t, 50)[:-1]
        assert np.all(np.hypot(*(p[None] - w[None] * ts[:, None]).T) > radius - 1e-9)
    else:  # never closer than R
        ts = np.linspace(0, 100, 2001)
        assert np.all(np.hypot(*(p[None] - w[None] * ts[:, None]).T) >= radius - 1e-9)


def test_field_dstar_costs_on_a_free_grid() -> None:
    g = node_costs(np.ones((6, 6)), (0, 0))
    f_ = math.sqrt(2) - 1
    y = f_ / math.sqrt(1 - f_**2)
    interpolated = 1 + math.sqrt(1 + y**2) + f_ * (1 - y)  # Ferguson & Stentz 2006, Fig. 9
    assert g[2, 1] == pytest.approx(interpolated, rel=1e-12)
    assert g[1, 2] == pytest.approx(interpolated, rel=1e-12)
    for i in range(7):
        assert g[i, 0] == pytest.approx(i)
        assert g[i, i] == pytest.approx(i * math.sqrt(2))
    ii, jj = np.indices(g.shape)
    euclid = np.hypot(ii, jj)
    octile = np.maximum(ii, jj) + (math.sqrt(2) - 1) * np.minimum(ii, jj)
    assert np.all(g >= euclid - 1e-9)
    assert np.all(g <= octile + 1e-9)


def test_field_dstar_goes_around_a_wall() -> None:
    cost = np.ones((6, 6))
    cost[2, 0:5] = np.inf  # a wall of cells at x in [2, 3], open above y = 5
    g = node_costs(cost, (0, 0))
    assert math.isinf(compute_cost(math.inf, math.inf, 0.0, 0.0))
    # from (4, 0) round the wall's top corners (3, 5) and (2, 5): between the shortest
    # Euclidean path and the shortest 8-connected (octile) one
    euclid = math.hypot(1, 5) + 1 + math.hypot(2, 5)
    octile = (5 + (math.sqrt(2) - 1)) + 1 + (5 + 2 * (math.sqrt(2) - 1))
    assert euclid - 1e-9 <= g[4, 0] <= octile + 1e-9


def test_errt_reaches_the_goal_around_a_wall_with_a_seed() -> None:
    sc = scenario_from_dict({
        "name": "wall", "start": [4, 0], "goal": [0, 0],
        "obstacles": [{"kind": "wall", "name": "w", "start": [2, -1.5], "end": [2, 1.0],
                       "thickness": 0.1, "r2": 0.6, "r3": 0.3}]})  # fmt: skip
    world = Snapshot.of(sc, 0.0)
    path, _ = errt_mod.plan(world, np.array([4.0, 0.0]), np.zeros(2), ERRTSettings(seed=3),
                            np.random.default_rng(3), np.zeros((0, 2)))  # fmt: skip
    assert np.allclose(path[-1], [0, 0])
    assert all(world.segment_free(a, b) for a, b in itertools.pairwise(path))
    run = simulate_planner(sc, "errt", ERRTSettings(seed=3))
    assert run.arrived and not run.collided


@pytest.mark.parametrize("method", ["vo", "errt", "field_dstar"])
def test_free_space_arrival_is_the_straight_run(method: str) -> None:
    sc = nav.Scenario("free", (4.0, 0.0), (0.0, 0.0), horizon=8.0)
    coarse = {"field_dstar": FieldDStarSettings(cell=0.25, margin=0.5)}
    r = simulate_planner(sc, method, coarse.get(method))
    v, a = sc.robot.max_speed, sc.robot.max_accel
    # accelerate to V (V/a s, V^2/2a m), cruise to within 0.15 m of the goal
    expected = v / a + (4.0 - 0.15 - v**2 / (2 * a)) / v
    assert r.arrival_time == pytest.approx(expected, abs=0.06)
    assert np.all(np.abs(r.position[:, 1]) < 0.05)


def test_mirroring_twice_is_the_scenario() -> None:
    sc = nav.configuration(4)
    twice = mirrored(mirrored(sc))
    t = np.linspace(0, 10, 11)
    for a, b in zip(sc.obstacles, twice.obstacles, strict=True):
        np.testing.assert_allclose(a.state(t)[0], b.state(t)[0], atol=1e-9)


def test_unknown_planner_is_refused() -> None:
    with pytest.raises(InvalidParameterError, match="method"):
        simulate_planner(nav.configuration(1), "astar")


def test_planner_study_seeds_and_their_limits() -> None:
    from designlab.errors import StudyError
    from designlab.study import parse_study

    text = """
designlab: 1
kind: navigation_planners
name: s
scenarios: [{configuration: unpredictable}]
planners: [{method: %s, seeds: 3}]
methods: []
"""
    study = parse_study(text % "errt")
    assert study.size() == "6 runs"
    assert [lab for lab, _ in study.planners[0].runs()] == [
        "errt (seed 0)", "errt (seed 1)", "errt (seed 2)",
    ]  # fmt: skip
    with pytest.raises(StudyError, match="seeds"):
        parse_study(text % "vo")


def test_wheel_energy_of_a_steady_run() -> None:
    from designlab.navigation.planners.simulate import wheel_energy

    robot = nav.HolonomicRobot()
    v = np.tile([[0.5, 0.0]], (101, 1))  # 1 s at 0.5 m/s along x
    s3 = math.sqrt(3) / 2
    w = np.array([-s3 * 0.5, s3 * 0.5, 0.0]) / robot.wheel_radius  # (D.1.2), phi = 0
    bk, tk = np.array([0.0019, 0.0020, 0.0024]), np.array([0.19, 0.22, 0.18])  # (D.3.2)
    u = bk * w + tk * np.sign(w)
    assert wheel_energy(robot, v) == pytest.approx(float(np.sum(u**2)) * 1.0, rel=1e-12)


def test_planner_criteria_are_the_thesis_criteria() -> None:
    r = simulate_planner(nav.configuration(1), "vo")
    c = r.criteria
    assert c is not None and c.k == 1
    free = simulate_planner(nav.configuration(1).without_obstacles(), "vo")
    assert c.H_T == pytest.approx(free.arrival_time / r.arrival_time)
    assert c.H_E == pytest.approx(free.energy / r.energy)


def test_planners_are_methods_of_the_scenarios_kind() -> None:
    from designlab.errors import StudyError
    from designlab.study import parse_study, run_study

    text = """
designlab: 1
kind: navigation_scenarios
name: s
scenarios: [{configuration: 1}]
methods: [%s]
"""
    study = parse_study(text % "{label: VO, method: vo, settings: {horizon: 2.0}}")
    run = run_study(study).runs[0].result
    direct = simulate_planner(nav.configuration(1), "vo", VOSettings(horizon=2.0))
    assert run.arrival_time == direct.arrival_time
    assert run.min_distance == direct.min_distance
    assert run.criteria.H == direct.criteria.H
    with pytest.raises(StudyError, match="settings, not gains"):
        parse_study(text % "{label: VO, method: vo, gains: {k1: 3, b: 0.25, k3: 20, k5: 17}}")
    with pytest.raises(StudyError, match="planners only"):
        parse_study(text % "{label: C, method: cbf, settings: {horizon: 2}}")
    with pytest.raises(StudyError, match="do not apply"):
        parse_study(text % "{label: E, method: errt, settings: {horizon: 2}}")


def test_a_nonholonomic_robot_is_simulated_as_holonomic_and_the_result_says_so() -> None:
    free = nav.Scenario("free", (4.0, 0.0), (0.0, 0.0), horizon=8.0)
    holo = simulate_planner(free, "vo")
    assert not any("nonholonomic" in w for w in holo.warnings)
    robot = nav.NonholonomicRobot()
    car = simulate_planner(dataclasses.replace(free, robot=robot), "vo")
    assert any("simulated as holonomic" in w for w in car.warnings)


def test_simulate_dispatches_a_planner_name_to_simulate_planner() -> None:
    sc = nav.configuration(1)
    settings = VOSettings(horizon=2.0)
    via = nav.simulate(sc, settings, method="vo")
    direct = simulate_planner(sc, "vo", settings)
    assert via.arrival_time == direct.arrival_time
    assert via.min_distance == direct.min_distance
    assert via.criteria.H == direct.criteria.H
    assert nav.simulate(sc, method="vo", arrival_tolerance=0.3).arrival_time < direct.arrival_time
    for bad in ({"stabilising": "off"}, {"force_every_step": True},
                {"noise": nav.SensorNoise(seed=1)}):  # fmt: skip
        with pytest.raises(ValueError, match=r"does not apply to a Sec\. 5\.7 planner"):
            nav.simulate(sc, method="vo", **bad)
    with pytest.raises(ValueError, match="must be a VOSettings"):
        nav.simulate(sc, nav.EXPERIMENT_GAINS, method="vo")
    with pytest.raises(ValueError, match="nor batched"):
        nav.simulate_batch([sc], [[3.0, 0.25, 20.0, 17.0]], method="errt")


def test_nlvo_prediction_stops_a_braking_walker_and_follows_an_accelerating_one() -> None:
    from designlab.navigation.planners.velocity_obstacle import predicted_centres

    c, v = np.array([[0.6, 0.0], [2.1, 0.0]]), np.array([[1.0, 0.0], [0.0, 0.0]])
    a = np.array([[-1.0, 0.0], [0.0, 1.0]])
    t = np.array([0.0, 0.5, 1.0, 3.0])
    p = predicted_centres(c, v, a, t)
    # braking at 1 m/s^2 from 1 m/s stands after 1 s, 0.5 m on; the other accelerates on
    np.testing.assert_allclose(p[:, 0, 0], [0.6, 0.6 + 0.5 - 0.125, 1.1, 1.1])
    np.testing.assert_allclose(p[:, 1, 1], 0.5 * t**2)


def test_nlvo_without_accelerations_is_the_linear_vo_to_its_sampling_step() -> None:
    from designlab.navigation.planners.velocity_obstacle import (
        NLVO_STEP,
        time_to_collision_nonlinear,
    )

    rng = np.random.default_rng(5)
    centres, vel = rng.uniform(-3, 3, (4, 2)), rng.uniform(-1, 1, (4, 2))
    radii, cand = rng.uniform(0.3, 0.7, 4), rng.uniform(-0.7, 0.7, (200, 2))
    exact = time_to_collision(np.zeros(2), centres, vel, radii, cand)
    nl = time_to_collision_nonlinear(np.zeros(2), centres, vel, np.zeros((4, 2)), radii, cand, 5.0)
    finite = exact < 5.0 - NLVO_STEP
    assert finite.any() and (exact > 5.0).any()
    # sampled every NLVO_STEP: found no earlier than the exact time, at most one step later
    assert np.all(nl[finite] >= exact[finite] - 1e-12)
    assert np.all(nl[finite] <= exact[finite] + NLVO_STEP + 1e-12)
    assert np.all(np.isinf(nl[exact > 5.0]))


def test_nlvo_runs_through_simulate_on_the_unpredictable_human() -> None:
    sc = nav.configuration("unpredictable")
    nl = nav.simulate(sc, method="nlvo")
    assert nl.arrived and not nl.collided
    assert nl.min_distance["human"] >= 0.6  # skims it, as the linear VO does (docs)
