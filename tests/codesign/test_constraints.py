"""Issue 36.2 and 36.1: no front design breaks a limit another part of designlab reports;
one robot; regions sized for each design's speed (closed forms of Zeng 2011, Sec. 5.3)."""

from __future__ import annotations

import numpy as np
import pytest

import designlab as dl
import designlab.navigation as nav
from designlab.codesign import (
    THESIS_ROBOT,
    Design,
    DesignSpace,
    SafetyCase,
    foam_limits,
    knee_point,
    nsga2,
    pareto,
    preference_pick,
    sized_scenario,
    speed_limit,
)
from designlab.codesign.front import hypervolume_change, hypervolume_trace
from designlab.errors import DesignlabError

ROBOT = dl.impact.MANIPULATOR_1


def test_foam_limits_are_the_speed_limit_of_each_foam() -> None:
    k, c, t = [9.0e3, 24250.0, 61.0e3], [160.0, 71.9, 20.0], [0.03, 0.0254, 0.012]
    lam = [x * 0.02 / 0.0254 for x in t]
    lim = foam_limits(ROBOT, k, c, lam, t, SafetyCase(human_speed=1.0))
    for i in range(3):
        foam = dl.impact.Foam(k[i], c[i], linear_depth=lam[i], thickness=t[i])
        s = speed_limit(ROBOT, foam, SafetyCase(human_speed=1.0))
        assert lim.max_speed[i] == pytest.approx(s.max_speed, rel=1e-12, abs=1e-15)
        assert lim.closing_speed[i] == pytest.approx(s.closing_speed, rel=1e-12)
        eps1 = s.unit_metric[f"eps_max <= {lam[i] * 1e3:g} mm"]
        # the thickness needed is linear in v_c: eps_1 v T_u / lambda
        assert lim.required_thickness(1.3)[i] == pytest.approx(eps1 * 1.3 * t[i] / lam[i],
                                                               rel=1e-12)  # fmt: skip


def test_required_thickness_of_a_fixed_head_is_the_impact_packages() -> None:
    head = dl.impact.HEAD_MAX  # a one-point range: no search, the same linear model
    one = dl.impact.HeadRange(mass=(head.mass,) * 2, stiffness=(head.stiffness,) * 2,
                              damping=(head.damping,) * 2)  # fmt: skip
    foam = dl.impact.FOAM_1
    lim = foam_limits(ROBOT, [foam.stiffness], [foam.damping], [foam.linear_depth],
                      [foam.thickness], SafetyCase(head_range=one))  # fmt: skip
    want = dl.impact.min_foam_thickness(ROBOT, foam, 1.7, head_range=one).thickness
    assert lim.required_thickness(1.7)[0] == pytest.approx(want, rel=1e-9)


@pytest.mark.parametrize(("v", "r3"), [(1.0, 0.870), (1.25, 0.938), (1.43, 0.991), (1.48, 1.006)])
def test_regions_grow_with_the_design_speed(v: float, r3: float) -> None:
    # (5.3.x): r3 = V_h (V/a + T_s) + V T_s + V^2 / (2 a) + rho_r + rho_h, a = 10, T_s = 0.06
    closed = 1.0 * (v / 10 + 0.06) + v * 0.06 + v**2 / 20 + 0.2 + 0.4
    sc = sized_scenario(nav.configuration(2), THESIS_ROBOT.navigation_robot(v), 1.0)
    (human,) = [o for o in sc.obstacles if o.name == "human"]
    assert human.r3 == pytest.approx(closed, rel=1e-12) and round(human.r3, 3) == r3
    assert human.r2 >= 2.1 and sc.robot.max_speed == v  # never below the scenario's


def test_a_pole_is_not_a_person_and_keeps_its_regions() -> None:
    sc = nav.configuration(4)
    out = sized_scenario(sc, THESIS_ROBOT.navigation_robot(0.7), 1.0)
    assert dl.codesign.people_names(out) == ("human",)
    circle = {o.name: o for o in out.obstacles}["circle"]
    assert (circle.r2, circle.r3) == (0.8, 0.4)  # the thesis's adopted values exceed the minima


def test_the_robot_description_refuses_a_heavier_contact() -> None:
    with pytest.raises(DesignlabError, match=r"RobotDescription\.contact"):
        dl.codesign.RobotDescription("x", mass=5.0, contact=ROBOT)


def test_no_front_design_breaks_a_limit_another_part_reports() -> None:
    space = DesignSpace(speed_min=0.3, speed_max=1.5)
    front = pareto([nav.configuration(2)], space=space, robot=THESIS_ROBOT,
                   objectives=("arrival_time", "exceedance_probability", "foam_thickness"),
                   population=8, generations=2, seed=1, risk_samples=500, risk_bound=0.05,
                   human_speed=1.0)  # fmt: skip
    assert front.front.any()
    G = front.G[~front.feasible]
    assert (G.max(axis=1) > 0).all()  # every infeasible design names a broken limit
    for d in front.designs():
        s = speed_limit(THESIS_ROBOT.contact, d.foam, SafetyCase(human_speed=1.0))
        assert d.speed <= s.max_speed  # the project's own speed limit
        eps1 = s.unit_metric[f"eps_max <= {d.foam.linear_depth * 1e3:g} mm"]
        need = eps1 * (d.speed + 1.0) * d.foam.thickness / d.foam.linear_depth
        assert need <= d.foam.thickness * (1 + 1e-12)  # no bottoming at the worst contact
    table = front.to_frame()
    assert (table["exceedance_probability"] <= 0.05).all()


def test_reference_designs_seed_the_first_population() -> None:
    seen = []

    def f(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        seen.append(x.copy())
        return np.array([x[0], 1.0 - x[0]]), np.zeros(0)

    nsga2(f, [0.0, 0.0], [1.0, 1.0], n_obj=2, population=5, generations=1,
          initial=[[0.25, 0.75]])  # fmt: skip
    assert seen[0].tolist() == [0.25, 0.75]
    with pytest.raises(DesignlabError, match=r"initial\[0\]\[1\]"):
        nsga2(f, [0.0, 0.0], [1.0, 1.0], n_obj=2, population=5, generations=1,
              initial=[[0.25, 2.0]])  # fmt: skip


def test_hypervolume_knee_and_pick_against_closed_forms() -> None:
    # three points of the segment f1 + f2 = 1 and a knee below it; reference 1.1
    F = np.array([[0.0, 1.0], [1.0, 0.0], [0.5, 0.5], [0.2, 0.2]])
    trace = hypervolume_trace(F, np.ones(4, bool), np.array([1, 1, 2, 3]))
    # gen 1: 2 x 1.1 x 0.1 - 0.01; gen 2: + 0.6^2 - 2 x 0.06 + 0.01; gen 3: (0.2,0.2) dominates
    # (0.5,0.5): the staircase 1.1^2 - 0.8 x 0.2 x ... computed by inclusion-exclusion
    g3 = 0.21 + 0.9 * 0.9 - (0.9 * 0.1 * 2 - 0.01)
    np.testing.assert_allclose(trace, [0.21, 0.46, g3], rtol=1e-12)
    assert hypervolume_change(trace, window=1) == pytest.approx((g3 - 0.46) / g3)
    assert knee_point(F) == 3 and preference_pick(F, [1.0, 0.0]) == 0
    with pytest.raises(DesignlabError, match="weights"):
        preference_pick(F, [0.0, 0.0])


def test_the_thesis_design_is_on_the_front_when_nothing_dominates_it() -> None:
    d = Design(dl.impact.FOAM_1, 0.7, nav.EXPERIMENT_GAINS)
    front = pareto([nav.configuration(2)], objectives=("arrival_time", "foam_thickness"),
                   population=4, generations=1, seed=0, reference={"thesis": d},
                   space=DesignSpace(thickness_min=0.03, thickness_max=0.06))  # fmt: skip
    # every searched foam is thicker than the thesis's 25.4 mm: nothing can dominate it
    assert front.reference_dominated_by == 0 and front.reference_distance == 0.0


@pytest.mark.parametrize("name", ["processes", "dask"])
def test_an_executor_gives_the_serial_front(name: str) -> None:
    from designlab.analysis.executors import make_executor

    kw = dict(objectives=("arrival_time", "foam_thickness"), population=4, generations=2,
              seed=5, robot=THESIS_ROBOT)  # fmt: skip
    serial = pareto([nav.configuration(2)], **kw)
    opts = {"processes": False} if name == "dask" else {}
    with make_executor(name, workers=2, **opts) as ex:
        other = pareto([nav.configuration(2)], executor=ex, **kw)
    np.testing.assert_array_equal(other.X, serial.X)
    np.testing.assert_array_equal(other.F, serial.F)
    np.testing.assert_array_equal(other.G, serial.G)
    assert other.to_frame().equals(serial.to_frame())
