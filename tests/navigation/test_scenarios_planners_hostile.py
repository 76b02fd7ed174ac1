"""Hostile inputs to the Sec. 5.7 planners, the user's scenarios and the region sizing
(issue 41): a clear error naming the parameter, its value and what is allowed, before any
work; sizes (grid cells, obstacles, path samples, nesting, file size) bounded on one
declaration shared by Python and the study files."""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest

import designlab as dl
from designlab.errors import InvalidParameterError, StudyError
from designlab.navigation import scenario_io as io
from designlab.navigation.parameters import OBSTACLES
from designlab.navigation.planners import FieldDStarSettings, simulate_planner
from designlab.navigation.planners.parameters import GRID_CELLS
from designlab.navigation.scenarios import Disc, Rectangle, SampledPath, Scenario, Stationary

nav = dl.navigation


# ------------------------------------------------------------------------------ planners
@pytest.mark.parametrize("tol", [1e9, 1.5, math.nan, math.inf, -1.0, 0.0, "0.1", True, None])
@pytest.mark.parametrize("method", ["vo", "errt"])
def test_planner_arrival_tolerance_is_checked_by_its_declaration(tol, method):
    """arrival_tolerance=1e9 'arrived at 0.01 s'; NaN or -1 could never arrive: refused."""
    with pytest.raises(InvalidParameterError, match="arrival_tolerance"):
        simulate_planner(nav.configuration(1), method, arrival_tolerance=tol)
    with pytest.raises(InvalidParameterError, match="arrival_tolerance"):
        nav.simulate(nav.configuration(1), method=method, arrival_tolerance=tol)


def test_field_dstar_refuses_a_grid_too_fine_before_planning():
    """cell=0.0101 planned for 448 s on a 3 s scenario: the grid it would give is named."""
    sc = nav.configuration(1)
    with pytest.raises(InvalidParameterError, match=r"FieldDStarSettings\.cell") as exc:
        simulate_planner(sc, "field_dstar", FieldDStarSettings(cell=0.0101))
    assert "cells" in str(exc.value) and f"{GRID_CELLS.le:.0f}" in str(exc.value)
    with pytest.raises(InvalidParameterError, match=r"FieldDStarSettings\.cell"):
        simulate_planner(sc, "field_dstar", FieldDStarSettings(cell=0.02, margin=50.0))


def test_field_dstar_refuses_a_run_that_plans_too_many_cells():
    """A grid within its cap planned every period of a long horizon is refused as a whole."""
    sc = nav.configuration(1).replace(horizon=600.0)
    with pytest.raises(InvalidParameterError, match="plans"):
        simulate_planner(sc, "field_dstar", FieldDStarSettings(cell=0.05))


def test_check_grid_counts_the_grid_the_planner_builds():
    from designlab.navigation.planners.field_dstar import Grid, check_grid
    from designlab.navigation.planners.world import Snapshot

    sc = nav.configuration(3)
    s = FieldDStarSettings(cell=0.1)
    rects = [o.corners() for o in sc.obstacles if o.kind == "rectangle"]
    discs = [o.state([0.0])[0] for o in sc.obstacles if o.kind != "rectangle"]
    pts = np.vstack([[sc.start, sc.goal], *rects, *discs])
    g = Grid(Snapshot.of(sc, 0.0), np.asarray(sc.start), np.asarray(sc.goal), s)
    assert check_grid(pts, 1, s) == g.cost.size


# ----------------------------------------------------------------------------- scenarios
def _disc(i: int) -> Disc:
    return Disc(f"d{i}", 0.1, r2=0.5, r3=0.3, motion=Stationary((10.0 + i, 10.0)))


def test_a_python_scenario_caps_its_obstacles_on_the_study_files_declaration():
    """2,000 discs ran 406 s then out of memory (the study files capped 100): one declaration."""
    from designlab.study.kinds import navigation_specs as specs

    cap = int(OBSTACLES.le)
    Scenario("ok", (0.0, 0.0), (1.0, 0.0), tuple(_disc(i) for i in range(cap)))
    with pytest.raises(InvalidParameterError, match=r"Scenario\.obstacles") as exc:
        Scenario("x", (0.0, 0.0), (1.0, 0.0), tuple(_disc(i) for i in range(2000)))
    assert "2000" in str(exc.value) and f"<= {cap}" in str(exc.value)
    items = [{"kind": "disc", "name": f"d{i}", "radius": 0.1, "r2": 0.5, "r3": 0.3,
              "position": [10 + i, 10]} for i in range(cap + 1)]  # fmt: skip
    with pytest.raises(InvalidParameterError, match="obstacles"):
        io.scenario_from_dict({"name": "x", "start": [0, 0], "goal": [1, 0], "obstacles": items})
    spec = specs.ScenarioSpec.model_json_schema()
    assert spec["properties"]["obstacles"]["maxItems"] == cap


@pytest.mark.parametrize(
    "corners",
    [
        [(0, 0), (1, 2), (3, 1), (2, 5)],  # any four points: was their bounding box
        [(0, 0), (2, 0), (2, 1), (0, 1.5)],  # one corner off
        [(0, 0), (2, 0), (2, 1), (2, 1)],  # a corner twice
        [(0, 0), (2, 0), (2, 1)],  # three
        [(0, 0), (2, 0), (2, 1), (0, 1), (1, 1)],  # five
        [(0, 0), (0, 0), (0, 0), (0, 0)],  # a point
        [(1, 0), (2, 1), (1, 2), (0, 1)],  # a rotated square: not axis-aligned
        [(0, 0), (2, 0), (2, math.nan), (0, 1)],
        "abcd",
    ],
)
def test_rectangle_from_corners_refuses_what_is_not_an_axis_aligned_rectangle(corners):
    with pytest.raises(InvalidParameterError, match=r"r\.corners"):
        Rectangle.from_corners("r", corners, r2=1.0, r3=0.5)


def test_rectangle_from_corners_takes_the_corners_in_any_order():
    a = Rectangle.from_corners("r", [(2, 1), (0, 0), (0, 1), (2, 0)], r2=1.0, r3=0.5)
    assert (a.center, a.length, a.width) == ((1.0, 0.5), 2.0, 1.0)


def _write(tmp_path: Path, text: str | bytes) -> Path:
    f = tmp_path / "room.yaml"
    if isinstance(text, bytes):
        f.write_bytes(text)
    else:
        f.write_text(text)
    return f


ROOM = "name: room\nstart: [3, 0]\ngoal: [0, 0]\n"


@pytest.mark.parametrize(
    ("text", "match"),
    [
        (ROOM + "name: hall\n", r"room\.yaml:4: name: key 'name' appears twice"),
        ("name: [room\n", r"room\.yaml:\d+: YAML syntax error"),
        ("name: " + "[" * 5000 + "]" * 5000 + "\n", r"room\.yaml:1: .*nests"),
        ("a: &a [1]\nb: *a\n" + ROOM, "is not a key here"),
    ],
)
def test_load_scenario_refuses_bad_yaml_with_the_file_and_line(tmp_path, text, match):
    """5,000 levels of nesting were a RecursionError, YAML errors raw, duplicate keys
    silently accepted; now the study files' loader refuses them with file and line."""
    with pytest.raises((StudyError, InvalidParameterError), match=match):
        io.load_scenario(_write(tmp_path, text))


@pytest.mark.parametrize(
    ("data", "match"),
    [
        (b"name: room\0\n", "NUL"),
        (b"name: \xff\xfe\n", "UTF-8"),
        (b"#" * (io.MAX_FILE_BYTES + 1), "bytes"),
    ],
)
def test_load_scenario_reads_only_bounded_text(tmp_path, data, match):
    """The core reader (designlab.yamlio): the file and the line are named."""
    with pytest.raises(StudyError, match=rf"room\.yaml:.*{match}"):
        io.load_scenario(_write(tmp_path, data))


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_load_scenario_refuses_a_fifo_a_device_and_a_directory_without_waiting(tmp_path):
    fifo = tmp_path / "pipe.yaml"
    os.mkfifo(fifo)
    for path in (fifo, Path("/dev/zero"), tmp_path):
        if path.exists():
            with pytest.raises(StudyError, match="not a regular file"):
                io.load_scenario(path)
    with pytest.raises(StudyError, match=r"missing\.yaml: file not found"):
        io.load_scenario(tmp_path / "missing.yaml")


def test_load_scenario_still_reads_a_scenario(tmp_path):
    sc = io.load_scenario(_write(tmp_path, ROOM))
    assert (sc.start, sc.goal, sc.obstacle_names) == ((3.0, 0.0), (0.0, 0.0), ())


def test_mirrored_checks_its_scenario_and_sampling_interval():
    with pytest.raises(InvalidParameterError, match="scenario"):
        io.mirrored("room")  # type: ignore[arg-type]
    sc = nav.configuration("unpredictable")
    for dt in (0.0, -0.02, math.nan, 2.0):
        with pytest.raises(InvalidParameterError, match="dt"):
            io.mirrored(sc, dt)
    with pytest.raises(InvalidParameterError, match="samples"):
        io.mirrored(sc.replace(horizon=600.0), 1e-3)
    rect = nav.configuration(3)
    twice = io.mirrored(io.mirrored(rect))  # an angle kept within its declaration
    assert [o.name for o in twice.obstacles] == [o.name for o in rect.obstacles]


@pytest.mark.parametrize(
    ("times", "positions", "match"),
    [
        ((0.0, 1.0, 2.0), ((0, 0), (1, 0), (1e308, 0)), "positions"),  # was accepted
        ((0.0, 1.0), ((0, 0), (math.nan, 0)), "positions"),
        ((-1.0, 1.0), ((0, 0), (1, 0)), "times"),
        ((0.0, 1e9), ((0, 0), (1, 0)), "times"),
        (("a", "b"), ((0, 0), (1, 0)), "SampledPath"),
    ],
)
def test_sampled_path_refuses_positions_and_times_outside_the_scene(times, positions, match):
    with pytest.raises(InvalidParameterError, match=match):
        SampledPath(times, positions)


# ------------------------------------------------------------------------ region sizing
@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"critical_radius": 1e300}, "critical_radius"),
        ({"sidestep_time": 1e300}, "sidestep_time"),
        ({"active_radius": 1e300}, "active_radius"),
        ({"active_radius": math.nan}, "active_radius"),
        ({"critical_radius": "1"}, "critical_radius"),
    ],
)
def test_region_sizes_check_adopted_values_on_their_declarations(kwargs, name):
    """An adopted r3 of 1e300 m gave r2 = 2.4e300 m: the adopted values have the bounds of
    RegionChoice's fields (one declaration)."""
    from designlab.navigation.regions import region_sizes
    from designlab.navigation.sizing import RegionChoice

    with pytest.raises(InvalidParameterError, match=name):
        region_sizes(nav.Human(), nav.HolonomicRobot(), 0.06, **kwargs)
    with pytest.raises(InvalidParameterError, match=name):
        RegionChoice(**kwargs)


def test_region_sizes_check_a_nonholonomic_turn_time():
    from designlab.navigation.regions import region_sizes

    with pytest.raises(InvalidParameterError, match="turn_time"):
        region_sizes(nav.Human(), nav.NonholonomicRobot(), 0.06, turn_time=1e300)


@pytest.mark.parametrize(
    ("args", "name"),
    [
        (({"h": None}, 0.06, None), "obstacles"),
        (({"h": dl.navigation.Human()}, 0.06, [1]), "choices"),
        (({1: dl.navigation.Human()}, 0.06, None), "obstacles"),
        (({"h": dl.navigation.Human()}, math.nan, None), "sample_time"),
    ],
)
def test_size_regions_names_what_is_wrong(args, name):
    from designlab.navigation.sizing import size_regions

    with pytest.raises(InvalidParameterError, match=name):
        size_regions(nav.HolonomicRobot(), *args)


# ------------------------------------------------------------ the planners' building blocks
def test_field_dstar_building_blocks_check_their_arguments():
    from designlab.navigation.planners.field_dstar import compute_cost, node_costs

    with pytest.raises(InvalidParameterError, match="c"):
        compute_cost(math.nan, 1.0, 1.0, 0.0)  # was nan
    with pytest.raises(InvalidParameterError, match="g1"):
        compute_cost(1.0, 1.0, -1.0, 0.0)
    assert compute_cost(1.0, math.inf, 1.0, 0.0) == math.sqrt(2)
    with pytest.raises(InvalidParameterError, match="goal"):
        node_costs(np.ones((3, 3)), (10, 10))  # was an IndexError
    with pytest.raises(InvalidParameterError, match=r"stop\[0\]"):
        node_costs(np.ones((3, 3)), (0, 0), ((4, 0),))
    with pytest.raises(InvalidParameterError, match="cell_cost"):
        node_costs(np.ones((10**3, 10**3)), (0, 0))  # over GRID_CELLS: was minutes
    with pytest.raises(InvalidParameterError, match="cell_cost"):
        node_costs(-np.ones((3, 3)), (0, 0))


def test_vo_candidates_and_wheel_energy_check_their_arguments():
    from designlab.navigation.planners import VOSettings
    from designlab.navigation.planners.simulate import wheel_energy
    from designlab.navigation.planners.velocity_obstacle import candidate_velocities

    for v in (math.nan, -1.0, 1e300):
        with pytest.raises(InvalidParameterError, match="max_speed"):
            candidate_velocities(v, VOSettings())  # NaN and -1 gave NaN or reversed candidates
    with pytest.raises(InvalidParameterError, match="settings"):
        candidate_velocities(0.7, "vo")
    robot = nav.HolonomicRobot()
    with pytest.raises(InvalidParameterError, match="dt"):
        wheel_energy(robot, np.zeros((3, 2)), dt=-1.0)  # was -0.0
    with pytest.raises(InvalidParameterError, match="velocity"):
        wheel_energy(robot, np.array([[math.nan, 0.0]]))
    with pytest.raises(InvalidParameterError, match="robot"):
        wheel_energy("robot", np.zeros((3, 2)))


def test_errt_settings_that_cannot_explore_are_refused():
    """goal_bias=1.0 (or with waypoint_bias summing to 1) and margin=0 ran 196 s on a 15 s
    scenario: the tree never explored, every plan spent max_nodes."""
    from designlab.navigation.planners import ERRTSettings

    for kw in (
        {"goal_bias": 1.0},
        {"waypoint_bias": 1.0},
        {"goal_bias": 0.4, "waypoint_bias": 0.6},
    ):
        with pytest.raises(InvalidParameterError, match=r"ERRTSettings\.goal_bias"):
            ERRTSettings(**kw)
    with pytest.raises(InvalidParameterError, match=r"ERRTSettings\.margin"):
        ERRTSettings(margin=0.0)
    ERRTSettings(goal_bias=0.3, waypoint_bias=0.6)


def test_field_dstar_on_a_scene_on_one_line_without_margin():
    """margin=0 on a scene whose start, goal and obstacle lie on one line gave a grid of no
    width (an error about cell_cost); the grid is one cell wide and the run says it did not
    get around the obstacle."""
    disc = Disc("c", 0.1, r2=0.8, r3=0.4, motion=Stationary((2.45, 0.6)))
    sc = Scenario("line", (3.9, 0.6), (0.0, 0.6), horizon=3.0, obstacles=(disc,))
    res = simulate_planner(sc, "field_dstar", FieldDStarSettings(margin=0.0))
    assert not res.collided


def test_field_dstar_grid_error_names_the_margin():
    with pytest.raises(InvalidParameterError, match=r"margin = 50 m"):
        s = FieldDStarSettings(cell=0.5, margin=50.0)
        simulate_planner(nav.configuration(1), "field_dstar", s)


@pytest.mark.parametrize("horizon", [1e-300, 0.05])
def test_a_scenario_horizon_shorter_than_a_period_is_refused(horizon):
    """horizon: 1e-300 in a navigation_scenarios study failed in its report writer."""
    with pytest.raises(InvalidParameterError, match=r"Scenario\.horizon"):
        Scenario("x", (0.0, 0.0), (1.0, 0.0), horizon=horizon)
    with pytest.raises(InvalidParameterError, match=r"Scenario\.horizon"):
        nav.configuration(1).replace(horizon=horizon)


# ------------------------------------------------------------------------------ criteria
BASE_RUN = {"arrival_time": 6.0, "nominal_arrival_time": 5.4, "energy": 2.0,
            "nominal_energy": 1.0, "surface_clearance": {"c": 0.25},
            "nominal_clearance": {"c": 0.5}}  # fmt: skip


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"arrival_time": 0.0}, "arrival_time"),  # was a ZeroDivisionError
        ({"arrival_time": None}, "arrival_time"),
        ({"arrival_time": "6"}, "arrival_time"),
        ({"arrival_time": math.nan}, "arrival_time"),
        ({"nominal_arrival_time": 0.0}, "nominal_arrival_time"),
        ({"nominal_arrival_time": math.nan}, "nominal_arrival_time"),
        ({"energy": math.inf}, "energy"),
        ({"nominal_energy": -1.0}, "nominal_energy"),
        ({"nominal_energy": None}, "nominal_energy"),
        ({"nominal_clearance": {"a": 0.5}}, "nominal_clearance"),  # was a KeyError
        ({"nominal_clearance": {"c": 0.0}}, "nominal_clearance"),  # was a ZeroDivisionError
        ({"surface_clearance": "c"}, "surface_clearance"),
    ],
)
def test_criteria_refuse_what_is_not_a_run(kwargs, name):
    from designlab.navigation.criteria import criteria

    with pytest.raises(InvalidParameterError, match=name):
        criteria(**{**BASE_RUN, **kwargs})


def test_criteria_name_both_clearance_mappings_when_their_obstacles_differ():
    """``surface_clearance={}`` was refused naming only ``nominal_clearance``'s keys."""
    from designlab.navigation.criteria import criteria

    with pytest.raises(InvalidParameterError) as err:
        criteria(**{**BASE_RUN, "surface_clearance": {}})
    assert err.value.name == "nominal_clearance" and err.value.value == {"c": 0.5}
    assert "surface_clearance = {}" in str(err.value)


def test_criteria_of_a_run_and_nominal_run_that_never_arrived():
    from designlab.navigation.criteria import criteria

    c = criteria(**{**BASE_RUN, "arrival_time": math.inf, "nominal_arrival_time": math.inf})
    assert c.H_T == 0.0 and any("never arrived" in w for w in c.warnings)
    c = criteria(**BASE_RUN)
    assert c.H_T == 5.4 / 6.0 and c.H_D == 0.5 and c.H_E == 0.5


def test_criteria_undefined_when_only_the_nominal_run_never_arrived():
    """T* = inf with T finite raised (a sensitivity run at arrival_tolerance 1e-9 crashed the
    navigation_gains study); H_T = inf was the value before that. Now H_T, H_E, H are NaN."""
    from designlab.navigation.criteria import UNDEFINED, criteria

    c = criteria(**{**BASE_RUN, "nominal_arrival_time": math.inf})
    assert c.status == UNDEFINED and not c.ok
    assert math.isnan(c.H_T) and math.isnan(c.H_E) and math.isnan(c.H) and c.H_D == 0.5
    assert any("nominal run never arrived" in w and "T = 6.000 s" in w for w in c.warnings)
