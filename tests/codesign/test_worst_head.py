"""Any head in the stated range: the off-grid worst head in the speed limit, the map, links.

The metrics are recomputed here head by head with ``dl.impact.impact_metrics`` on dense
grids and random heads (an independent path), and never exceed the worst case the
co-design layer found by more than 1e-9 relative.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.codesign import SafetyCase
from designlab.codesign.worst_head import compass_search, multi_start
from designlab.impact import (
    FOAM_1,
    MANIPULATOR_1,
    THESIS_HEAD_RANGE,
    ContactDynamics,
    Foam,
    HeadAcceleration,
    ImpactForce,
    LinkImpact,
)

CRITERIA = [HeadAcceleration(10), ImpactForce(660)]
ATTR = {"head_acceleration": "peak_head_acceleration", "force": "peak_force",
        "compression": "max_compression"}  # fmt: skip


def _dense_heads(n: int, extra: int, seed: int) -> np.ndarray:
    """An n^3 lattice over the thesis's head range plus ``extra`` random heads."""
    hr = THESIS_HEAD_RANGE
    axes = [np.linspace(*hr.mass, n), np.linspace(*hr.damping, n), np.linspace(*hr.stiffness, n)]
    lattice = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    return np.vstack([lattice, hr.sample(extra, np.random.default_rng(seed))])


def _metrics(robot: dict, foam: Foam, heads: np.ndarray, v: np.ndarray | float):
    return dl.impact.impact_metrics(
        {**robot, "K_c": foam.stiffness, "C_c": foam.damping,
         "M_h": heads[:, 0], "C_h": heads[:, 1], "K_h": heads[:, 2]},
        v,
    )  # fmt: skip


foams = st.tuples(st.floats(5e3, 8e4), st.floats(10.0, 450.0), st.floats(0.005, 0.03))


# 8 foams and 3 found by CI against a dense head lattice: 12 CPU s, the slow step; the README's
# command checks one of the three (below) and the map and search through the lighter tests
@pytest.mark.slow
@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(foam=foams, robot=st.sampled_from([MANIPULATOR_1,
                                          ContactDynamics(9.57, 30.7e3, 221.3)]))  # fmt: skip
@example(foam=(10175.0, 116.0, 0.015625), robot=MANIPULATOR_1)  # a 9.2e-6 miss, found by CI
# peak force: two local maxima; the search from the grid's worst head (a corner) missed the
# edge maximum by 1e-3 (h41) and 7e-2 relative, before it started from the lattice's maxima
@example(foam=(13720.0, 137.0, 0.015625), robot=ContactDynamics(9.57, 30.7e3, 221.3))
@example(foam=(36892.14686368067, 282.89391888676624, 0.0298774126308831),
         robot=ContactDynamics(9.57, 30.7e3, 221.3))  # fmt: skip
def test_no_head_of_a_dense_grid_is_worse_and_the_map_agrees(foam, robot) -> None:
    """The refined worst head is a multi-start local search (docs/codesign.md): a dense lattice
    plus random heads may beat it by a maximum narrower than its lattice's spacing; allowed
    1e-5 relative (9.2e-6 found for the first example: peak force)."""
    _no_head_of_a_dense_grid_is_worse(foam, robot)


def test_the_edge_maximum_found_by_ci_is_the_worst_head() -> None:
    """The README's command: the second example above (two local maxima of the peak force)."""
    _no_head_of_a_dense_grid_is_worse(
        (13720.0, 137.0, 0.015625), ContactDynamics(9.57, 30.7e3, 221.3)
    )


def _no_head_of_a_dense_grid_is_worse(foam, robot) -> None:
    k, c, lam = foam
    f = Foam(k, c, lam)
    s = dl.codesign.speed_limit(robot, f, SafetyCase(CRITERIA, human_speed=0.5))
    m = dl.codesign.speed_limit_map(robot, K_c=[k, 6e4], C_c=[c], linear_depth=lam,
                                    case=SafetyCase(CRITERIA, human_speed=0.5))  # fmt: skip
    assert m.max_speed[0, 0] == pytest.approx(s.max_speed, rel=1e-12, abs=1e-15)
    assert m.closing_speed[0, 0] == pytest.approx(s.closing_speed, rel=1e-12)
    for name, v in s.per_criterion.items():
        assert m.per_criterion[name][0, 0] == pytest.approx(v, rel=1e-12)
    heads = _dense_heads(15, 1000, seed=int(k))
    r = {"M_r": robot.mass, "C_r": robot.damping, "K_r": robot.stiffness}
    met = _metrics(r, f, heads, np.ones(len(heads)))
    for key in [*CRITERIA, dl.impact.CompressionLimit(lam)]:
        dense = float(np.nanmax(getattr(met, ATTR[key.metric])))
        assert dense <= s.unit_metric[key.name] * (1 + 1e-5), key.name
    # the worst head's metric at the allowed closing speed is the limit
    name = s.limiting_criterion
    h = s.worst_heads[name]
    one = _metrics(r, f, np.array([[h.mass, h.damping, h.stiffness]]), s.closing_speed)
    key = {k_.name: k_ for k_ in [*CRITERIA, dl.impact.CompressionLimit(lam)]}[name]
    assert float(getattr(one, ATTR[key.metric])[0]) == pytest.approx(key.limit, rel=1e-9)


def test_the_map_is_refined_off_the_grid() -> None:
    # the strongly damped robot and foam of the speed-limit tests: the worst compression
    # lies inside the range, so the refined map allows less than the grid's
    robot = ContactDynamics(mass=9.57, stiffness=30.7e3, damping=221.3)
    kw = {"K_c": [52.4e3], "C_c": [450.3], "case": SafetyCase(human_speed=0.0)}
    grid = dl.codesign.speed_limit_map(robot, refine=False, **kw)
    best = dl.codesign.speed_limit_map(robot, **kw)
    name = dl.impact.CompressionLimit(0.02).name
    assert best.per_criterion[name][0, 0] < grid.per_criterion[name][0, 0] * (1 - 1e-5)


def test_link_at_its_joint_speed_meets_every_limit_at_any_point_and_head() -> None:
    link = LinkImpact.from_contact(MANIPULATOR_1, joint_speed=1.0, lever_arm_min=0.02,
                                   lever_arm_max=0.078)  # fmt: skip
    crit = [HeadAcceleration(10)]
    s = dl.codesign.speed_limit(link, FOAM_1, SafetyCase(crit, human_speed=1.0))
    omega = s.joint_speed
    heads = _dense_heads(9, 300, seed=1)
    levers = np.linspace(0.02, 0.078, 25)
    L = np.repeat(levers, len(heads))
    H = np.tile(heads, (len(levers), 1))
    r = {"M_r": link.inertia / L**2, "C_r": link.joint_damping / L**2,
         "K_r": link.joint_stiffness / L**2}  # fmt: skip
    met = _metrics(r, FOAM_1, H, omega * L + 1.0)
    assert np.nanmax(met.max_compression) <= FOAM_1.linear_depth * (1 + 1e-9)
    assert np.nanmax(met.peak_head_acceleration) <= crit[0].limit * (1 + 1e-9)
    # and the limiting case sits on its limit (the joint speed is not needlessly low)
    name = s.limiting_criterion
    h, lev = s.worst_heads[name], s.worst_lever_arm[name]
    one = dl.impact.impact_metrics(
        {"M_r": link.inertia / lev**2, "C_r": link.joint_damping / lev**2,
         "K_r": link.joint_stiffness / lev**2, "K_c": FOAM_1.stiffness, "C_c": FOAM_1.damping,
         "M_h": h.mass, "C_h": h.damping, "K_h": h.stiffness},
        omega * lev + 1.0,
    )  # fmt: skip
    got = one.max_compression[0] if name.startswith("eps") else one.peak_head_acceleration[0]
    limit = FOAM_1.linear_depth if name.startswith("eps") else crit[0].limit
    assert float(got) == pytest.approx(limit, rel=1e-9)


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=3, max_size=3),
       st.lists(st.floats(0.0, 1.0), min_size=3, max_size=3))  # fmt: skip
def test_compass_search_finds_a_concave_maximum_inside_or_on_the_box(centre, start) -> None:
    # f = -|z - c'|^2 with c' possibly outside the box: the maximum is c' clipped to it
    c = np.array(centre) * 1.4 - 0.2
    x0 = np.array([start])
    f = lambda rows, z: -((z - c) ** 2).sum(axis=2)  # noqa: E731
    x, fx = compass_search(f, x0, f(None, x0[None])[0])
    assert np.abs(x[0] - np.clip(c, 0.0, 1.0)).max() < 1e-8
    assert fx[0] >= f(None, x0[None])[0][0]


@settings(max_examples=20, deadline=None)
@given(st.lists(st.floats(0.6, 0.95), min_size=4, max_size=4),
       st.lists(st.floats(0.0, 0.2), min_size=4, max_size=4))  # fmt: skip
def test_multi_start_finds_a_planted_worst_case_a_single_start_misses(peak, hill) -> None:
    # f = max(hill, cone): a broad hill of height 1 around the start and a narrow cone of
    # height 3 at ``b`` (|b - a| >= 0.8: no first step of the pattern, at most 0.5 long,
    # reaches where the cone beats the hill). The exact answer is (b, 3); a single start at
    # the hill's top a stays there
    b, a = np.array(peak), np.array(hill)

    def f(z: np.ndarray) -> np.ndarray:
        hill_z = 1.0 - ((z - a) ** 2).sum(axis=-1)
        cone = 3.0 - 10.0 * np.sqrt(((z - b) ** 2).sum(axis=-1))
        return np.maximum(hill_z, cone)

    _, f1 = compass_search(lambda _, z: f(z), a[None], np.array([1.0]))
    assert f1[0] == pytest.approx(1.0, abs=1e-12)  # one start stays on the hill
    x, fx, starts = multi_start(f, a, 1.0)
    assert starts > 1
    assert fx == pytest.approx(3.0, abs=1e-7)
    assert np.abs(x - b).max() < 1e-7


def test_a_link_struck_at_one_point_is_the_fixed_robot_there() -> None:
    # lever_arm_min = lever_arm_max: the link is the fixed robot at that lever arm, so its
    # refined limits are the fixed robot's (whose worst compression head is off the grid)
    robot = ContactDynamics(mass=9.57, stiffness=30.7e3, damping=221.3)
    link = LinkImpact.from_contact(robot, joint_speed=1.0, lever_arm=0.45, lever_arm_min=0.45,
                                   lever_arm_max=0.45)  # fmt: skip
    foam = Foam(52.4e3, 450.3, 0.02)
    crit = [HeadAcceleration(10)]
    fixed = dl.codesign.speed_limit(robot, foam, SafetyCase(crit, human_speed=0.0))
    grid = dl.codesign.speed_limit(link, foam, SafetyCase(crit, human_speed=0.0), refine=False)
    best = dl.codesign.speed_limit(link, foam, SafetyCase(crit, human_speed=0.0))
    for name, v in fixed.per_criterion.items():
        assert best.per_criterion[name] == pytest.approx(v, rel=1e-9)
    name = dl.impact.CompressionLimit(0.02).name
    assert best.per_criterion[name] < grid.per_criterion[name] * (1 - 1e-3)
