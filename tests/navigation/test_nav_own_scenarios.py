"""A user's own scenario (walls, routes, paths) and region sizing: against independent answers."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab import navigation as nav
from designlab.errors import InvalidParameterError
from designlab.navigation.scenario_io import scenario_from_dict, with_limits
from designlab.navigation.sizing import RegionChoice, size_regions
from designlab.study import parse_study, run_study
from designlab.study.kinds.navigation_specs import ScenarioSpec

coord = st.floats(-5, 5, allow_nan=False)


def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    t = np.clip(np.dot(p - a, b - a) / np.dot(b - a, b - a), 0.0, 1.0)
    return float(np.linalg.norm(p - (a + t * (b - a))))


@settings(max_examples=60, deadline=None)
@given(coord, coord, coord, coord, coord, coord, st.floats(0.01, 0.5))
def test_wall_contour_distance_is_the_segment_distance_minus_half_the_thickness(
    ax: float, ay: float, bx: float, by: float, px: float, py: float, thick: float
) -> None:
    a, b, p = np.array([ax, ay]), np.array([bx, by]), np.array([px, py])
    if np.linalg.norm(b - a) < 1e-3:
        return
    wall = nav.Rectangle.wall("w", (ax, ay), (bx, by), thick, r2=0.8, r3=0.4)
    expected = _segment_distance(p, a, b)
    # outside the slab the rectangle's distance is the capsule's only along the sides;
    # at the ends it is the box corner: compare with the exact box distance in wall axes
    u = (b - a) / np.linalg.norm(b - a)
    n = np.array([-u[1], u[0]])
    lx = np.dot(p - (a + b) / 2, u)
    ly = np.dot(p - (a + b) / 2, n)
    box = math.hypot(max(abs(lx) - np.linalg.norm(b - a) / 2, 0.0), max(abs(ly) - thick / 2, 0.0))
    got = float(wall.contour_distance(p[None, :])[0])
    assert got == pytest.approx(box, abs=1e-9)
    assert got <= expected + 1e-9  # never farther than the centre line


def test_route_positions_at_constant_speed() -> None:
    pts = [(0.0, 0.0), (3.0, 0.0), (3.0, 4.0)]
    path = nav.SampledPath.through(pts, speed=0.5, start_time=2.0)
    t = np.array([0.0, 2.0, 5.0, 8.0, 10.0, 16.0, 30.0])
    # independent: wait 2 s, 6 s along x, 8 s along y, then stay
    s = np.clip(t - 2.0, 0, None) * 0.5
    expected = np.where(
        (s <= 3)[:, None],
        np.stack([s, 0 * s], 1),
        np.stack([np.full_like(s, 3.0), np.minimum(s - 3, 4.0)], 1),
    )
    np.testing.assert_allclose(path.state(t)[0], expected, atol=1e-12)


def test_route_refuses_repeated_waypoints() -> None:
    with pytest.raises(InvalidParameterError, match="waypoints"):
        nav.SampledPath.through([(0, 0), (0, 0), (1, 0)])


def test_a_configuration_written_by_hand_is_the_configuration() -> None:
    own = scenario_from_dict(
        {
            "name": "ch6_config3",
            "start": [3.9, 0.6],
            "goal": [0.0, 0.6],
            "obstacles": [
                {"kind": "disc", "name": "circle", "radius": 0.1, "r2": 0.8, "r3": 0.4,
                 "position": [2.45, 1.4]},
                {"kind": "rectangle", "name": "rectangle", "r2": 0.8, "r3": 0.4,
                 "corners": [[1.6, -0.3], [3, -0.3], [3, 0.3], [1.6, 0.3]]},
            ],
        }
    )  # fmt: skip
    thesis = nav.configuration(3)
    assert own.obstacles == thesis.obstacles
    a = nav.simulate(own, nav.EXPERIMENT_GAINS, stabilising="off")
    b = nav.simulate(thesis, nav.EXPERIMENT_GAINS, stabilising="off")
    assert a.arrival_time == b.arrival_time
    assert a.min_distance == b.min_distance


def test_the_spec_builds_what_the_dict_builds() -> None:
    data = {
        "name": "room",
        "start": [4, 0.5],
        "goal": [0, 0.5],
        "robot": {"type": "nonholonomic", "max_speed": 0.5},
        "obstacles": [
            {"kind": "wall", "name": "w", "start": [0, 2], "end": [4, 2], "thickness": 0.1,
             "r2": 0.6, "r3": 0.3},
            {"kind": "human", "name": "h", "r2": 2.5, "r3": 0.8,
             "path": {"times": [0, 1, 2], "positions": [[0, -1], [1, -1], [1, 0]]}},
        ],
    }  # fmt: skip
    spec = ScenarioSpec.model_validate(data)
    assert spec.build() == scenario_from_dict(data)
    assert scenario_from_dict(spec.as_dict()) == spec.build()


def test_with_limits_changes_only_limits_and_walks() -> None:
    sc = nav.configuration(4)
    s2 = with_limits(sc, 0.5, 4.0, 1.2, 0.3)
    assert (s2.robot.max_speed, s2.robot.max_accel) == (0.5, 4.0)
    assert s2.obstacles[:2] == sc.obstacles[:2]
    assert (s2.obstacles[2].motion.speed, s2.obstacles[2].motion.ramp_time) == (1.2, 0.3)


robots = st.builds(
    nav.HolonomicRobot,
    radius=st.floats(0.05, 1.0),
    max_speed=st.floats(0.1, 3.0),
    max_accel=st.floats(0.5, 20.0),
)


@settings(max_examples=50, deadline=None)
@given(robots, st.floats(0.01, 0.3), st.floats(0.1, 0.6), st.floats(0.0, 2.0))
def test_sizes_follow_the_thesis_formulas(
    robot: nav.HolonomicRobot, ts: float, rho: float, v_o: float
) -> None:
    plan = size_regions(
        robot,
        {"h": nav.Human(radius=rho, max_speed=min(v_o, 12.0)), "box": nav.RectangularObstacle(
            length=1.4, width=0.6, offset=0.3)},
        ts,
    )  # fmt: skip
    v, a = robot.max_speed, robot.max_accel
    dt1 = v / a
    d_r1 = v * ts + 0.5 * a * dt1**2  # (5.3.1)
    r3 = v_o * (dt1 + ts) + d_r1 + rho + robot.radius  # (5.3.3)
    dt2 = (r3 - 0.5 * a * dt1**2) / v + dt1  # (5.3.6b)
    r2 = (v + v_o) * (dt2 + ts)  # (5.3.7)
    assert plan.radii["h"] == pytest.approx((r2, r3), rel=1e-12)
    r3r = d_r1 + robot.radius  # (5.3.11)
    dt2r = (r3r + 0.3 - 0.5 * a * dt1**2) / v + dt1  # (5.3.14)
    assert plan.radii["box"] == pytest.approx((v * (dt2r + ts), r3r), rel=1e-12)  # (5.3.12)


def test_an_adopted_r2_below_the_minimum_is_a_warning() -> None:
    plan = size_regions(
        nav.NonholonomicRobot(),
        {"rectangle": nav.RectangularObstacle(offset=0.3)},
        0.06,
        {"rectangle": RegionChoice(critical_radius=0.3, active_radius=0.55)},
    )
    assert plan.radii["rectangle"] == (0.55, 0.3)
    assert any("below the minimum" in w for w in plan.warnings)


def test_regions_study() -> None:
    text = """
designlab: 1
kind: {kind}
name: demo
robot: {{type: nonholonomic}}
obstacles: [{{name: human, type: human}}]
"""
    r = run_study(parse_study(text.format(kind="navigation_regions")))
    s = r.plan.sizes["human"]
    assert s.turn_time == pytest.approx(math.sqrt(math.pi / 70))  # (7.4.2)


def test_a_sweep_of_an_own_scenario_is_the_batch_of_that_scenario() -> None:
    room = {
        "name": "room", "start": [4.0, 0.5], "goal": [0.0, 0.5],
        "obstacles": [{"kind": "wall", "name": "w", "start": [1.5, -1.0], "end": [2.5, 0.3],
                       "thickness": 0.1, "r2": 0.8, "r3": 0.4}],
    }  # fmt: skip
    study = parse_study(
        yaml.safe_dump(
            {
                "designlab": 1,
                "kind": "navigation_sweep",
                "name": "own",
                "base": {
                    "gains": {"k1": 3, "b": 0.25, "k3": 20, "k5": 17},
                    "stabilising": "off",
                    "scenarios": [room],
                },
                "sweep": {"method": "grid", "parameters": {"gains.k1": {"values": [3.0, 4.3]}}},
            }
        )
    )
    frame = run_study(study).to_frame()
    batch = nav.simulate_batch(
        [scenario_from_dict(room)], [[3.0, 0.25, 20, 17], [4.3, 0.25, 20, 17]], stabilising="off"
    )
    np.testing.assert_allclose(frame["H_mean"].to_numpy(), batch.H_mean, rtol=1e-12)


def test_a_scenario_refuses_an_obstacle_that_is_not_one() -> None:
    with pytest.raises(InvalidParameterError, match="Disc or Rectangle"):
        nav.Scenario("x", (4.0, 0.0), (0.0, 0.0), obstacles=(1.0,))  # type: ignore[arg-type]
