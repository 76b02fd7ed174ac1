"""Simulator, scenarios, batch API and criteria (Zeng 2011, Sec. 5.2, 5.6, 6-7)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.navigation import engine
from designlab.navigation.dynamics import build_hold
from designlab.results import check_result
from designlab.sx import compiler_missing_reason

nav = dl.navigation
EXP = nav.EXPERIMENT_GAINS
OPT = nav.OPTIMAL_GAINS


def test_public_api_of_the_issue() -> None:
    sizes = nav.region_sizes(
        obstacle=nav.Human(radius=0.4, max_speed=1.0),
        robot=nav.HolonomicRobot(radius=0.2, max_speed=0.7, max_accel=10.0),
        sample_time=0.06,
    )
    assert sizes.r2 > sizes.r3 > 0
    sc = nav.configuration(1)
    res = nav.simulate(sc, nav.VFFGains(k1=4.3, b=0.68, k3=20.3, k5=240.7))
    assert set(res.min_distance) == {"circle"}
    assert isinstance(res.entered_critical, bool) and isinstance(res.collided, bool)
    assert {"H_T", "H_D", "H_E", "H"} <= set(res.criteria.to_frame().columns)
    check_result(res)
    check_result(res.criteria)
    check_result(res.stability)
    assert res.trajectory_frame().shape[0] == res.t.size
    assert {o.name for o in nav.configuration(4).obstacles} == {"circle", "rectangle", "human"}


def test_no_obstacles_free_space_run_matches_an_independent_loop() -> None:
    """A hand-written 1 ms loop of the same point-mass model (force held 60 ms, norm clipping)."""
    sc = nav.Scenario("free", (3.0, 0.0), (0.0, 0.0))
    res = nav.simulate(sc, EXP, stabilising="off")
    p, v, t = np.array([3.0, 0.0]), np.zeros(2), 0.0
    k1, k2, m = 3.0, 0.75, 4.4
    arrival = math.inf
    for k in range(20000):
        if k % 60 == 0:
            F = k1 * (np.array([0.0, 0.0]) - p) - k2 * v
            a = F / m
            na = np.linalg.norm(a)
            a = a * min(1.0, 10.0 / na) if na > 0 else a
        v = v + a * 1e-3
        nv = np.linalg.norm(v)
        v = v * min(1.0, 0.7 / nv) if nv > 0 else v
        p = p + v * 1e-3
        t = (k + 1) * 1e-3
        if np.linalg.norm(p) <= 0.15:
            arrival = t
            break
    assert res.arrival_time == pytest.approx(arrival, abs=1e-9)
    assert res.criteria.H_T == pytest.approx(1.0)
    assert res.criteria.H == pytest.approx(1.0)


def test_speed_and_acceleration_limits_hold_along_a_run() -> None:
    res = nav.simulate(nav.configuration(4), OPT, stabilising="lyapunov")
    speed = np.hypot(*res.velocity.T)
    assert speed.max() <= 0.7 + 1e-9
    acc = np.diff(res.velocity, axis=0) / np.diff(res.t)[:, None]
    assert np.hypot(*acc.T).max() <= 10.0 + 1e-6


def test_critical_region_braking_stops_the_robot() -> None:
    # a human walking straight at a robot that cannot escape in time (tiny active region)
    human = nav.Disc(
        "human", 0.4, r2=0.85, r3=0.8, motion=nav.ConstantVelocity((0.0, 0.0), (1.0, 0.0))
    )
    sc = nav.Scenario("trap", (2.0, 0.0), (-3.0, 0.0), (human,), horizon=3.0)
    res = nav.simulate(sc, EXP, stabilising="off")
    assert res.entered_critical
    assert res.critical_time > 0
    assert any("critical" in w or "collision" in w for w in res.warnings)


def test_force_every_step_option_changes_little_without_obstacles() -> None:
    sc = nav.configuration(1).without_obstacles()
    held = nav.simulate(sc, OPT, stabilising="off")
    every = nav.simulate(sc, OPT, stabilising="off", force_every_step=True)
    assert every.arrival_time == pytest.approx(held.arrival_time, abs=0.1)


def test_tie_side_mirrors_the_collinear_detour() -> None:
    sc = nav.configuration(1, chapter=7, robot=nav.HolonomicRobot())  # exactly collinear circle
    up = nav.simulate(sc, EXP, stabilising="off", tie_side="+y")
    down = nav.simulate(sc, EXP, stabilising="off", tie_side="-y")
    assert up.position[:, 1].max() > 0.7 and down.position[:, 1].min() < 0.5
    assert up.arrival_time == pytest.approx(down.arrival_time, abs=1e-6)
    np.testing.assert_allclose(up.position[:, 1] - 0.6, -(down.position[:, 1] - 0.6), atol=1e-9)


def test_user_built_scenario() -> None:
    walk = nav.Walk((0.0, 2.0), (4.0, 2.0), speed=0.8)
    sc = nav.Scenario(
        "corridor",
        (4.0, 0.5),
        (0.0, 0.5),
        (
            nav.Disc("visitor", 0.4, r2=2.1, r3=0.8, motion=walk),
            nav.Rectangle("table", (2.0, -0.6), 1.0, 0.5, r2=0.8, r3=0.4),
        ),
    )
    res = nav.simulate(sc, EXP, stabilising="lyapunov")
    assert set(res.min_distance) == {"visitor", "table"}
    assert res.arrived and not res.collided


@pytest.mark.parametrize(
    "make, name",
    [
        (
            lambda: nav.Scenario(
                "x",
                (0.0, 0.0),
                (3.0, 0.0),
                (nav.Disc("c", 0.1, 0.8, 0.4, nav.Stationary((3.1, 0.0))),),
            ),
            "Scenario.goal",
        ),
        (
            lambda: nav.Scenario(
                "x",
                (0.0, 0.0),
                (3.0, 0.0),
                (nav.Disc("c", 0.1, 0.8, 0.4, nav.Stationary((0.2, 0.0))),),
            ),
            "Scenario.obstacles",
        ),
        (lambda: nav.Disc("c", 0.1, r2=0.4, r3=0.8, motion=nav.Stationary((0, 0))), "c.r2"),
        (lambda: nav.Disc("c", -0.1, r2=0.8, r3=0.4, motion=nav.Stationary((0, 0))), "c.radius"),
        (lambda: nav.Scenario("x", (math.nan, 0.0), (3.0, 0.0)), "Scenario.start"),
        (lambda: nav.Scenario("x", (0.0, 0.0), (3.0, 0.0), horizon=0.0), "Scenario.horizon"),
        (
            lambda: nav.Scenario("x", (0.0, 0.0), (3.0, 0.0), sample_time=-0.06),
            "Scenario.sample_time",
        ),
        (lambda: nav.configuration(5), "configuration"),
        (lambda: nav.configuration(1, chapter=8), "chapter"),
        (lambda: nav.Walk((0, 0), (0.1, 0), speed=1.0, ramp_time=0.5), "Walk.ramp_time"),
        (lambda: nav.simulate(nav.configuration(1), EXP, method="potential"), "method"),
        (lambda: nav.simulate(nav.configuration(1), EXP, stabilising="on"), "stabilising"),
        (lambda: nav.simulate(nav.configuration(1), None), "gains"),
        (lambda: nav.simulate(nav.configuration(1), nav.MasoudGains(), method="vff"), "gains"),
        (
            lambda: nav.simulate(nav.configuration(1), EXP, arrival_tolerance=0.0),
            "arrival_tolerance",
        ),
        (lambda: nav.simulate(nav.configuration(1), EXP, dynamics_step=0.007), "dynamics_step"),
        (
            lambda: nav.simulate_batch([nav.configuration(1)], [[3, 0.25, 20, -17]]),
            r"gains\[0, 3\]",
        ),
        (lambda: nav.simulate_batch([nav.configuration(1)], [[3, 0.25, 20]]), "gains"),
        (lambda: nav.simulate_batch([nav.configuration(1)], [[3, math.nan, 20, 17]]), "gains"),
        (lambda: nav.simulate_batch([], [[3, 0.25, 20, 17]]), "scenarios"),
        (lambda: nav.simulate_batch(None, [[3, 0.25, 20, 17]]), "scenarios"),
        (lambda: nav.simulate_batch([nav.configuration(1)], [[True, 0.25, 20, 17]]), "gains"),
        (lambda: nav.simulate_batch([nav.configuration(1)], np.ones((1, 4), bool)), "gains"),
        (lambda: nav.simulate_batch([nav.configuration(1)], "abc"), "gains"),
        (lambda: nav.simulate_batch([nav.configuration(1)], [[3, 0.25, 20, 17]], jit=1), "jit"),
        (lambda: nav.simulate(nav.configuration(1), EXP, force_every_step="yes"), "force_every"),
        (
            lambda: nav.simulate(nav.configuration(1), method="cbf", cbf_gains=(-1.0, 4.0)),
            "cbf_gains",
        ),
        (
            lambda: nav.simulate(nav.configuration(1), method="cbf", cbf_gains=(math.nan, 4.0)),
            "cbf_gains",
        ),
    ],
)
def test_bad_inputs_name_the_parameter(make, name: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidParameterError, match=name):
        make()


def test_batch_equals_single_runs() -> None:
    scen = [nav.configuration(1), nav.configuration(4)]
    gains = np.array([[4.3, 0.68, 20.3, 240.7], [3.0, 0.25, 20.0, 17.0], [6.0, 0.4, 40.0, 100.0]])
    for mode in ("off", "lyapunov"):
        batch = nav.simulate_batch(scen, gains, stabilising=mode)
        check_result(batch)
        assert batch.arrival_time.shape == (2, 3)
        assert batch.min_distance.shape == (2, 3, 3)
        assert np.isnan(batch.min_distance[0, :, 1:]).all()
        for s, sc in enumerate(scen):
            for j, g in enumerate(gains):
                one = nav.simulate(sc, nav.VFFGains(*g), stabilising=mode)
                assert batch.arrival_time[s, j] == pytest.approx(one.arrival_time, abs=1e-9)
                np.testing.assert_allclose(
                    batch.min_distance[s, j, : len(sc.obstacles)],
                    list(one.min_distance.values()),
                    atol=1e-9,
                )
                assert batch.H[s, j] == pytest.approx(one.criteria.H, abs=1e-9)
                assert batch.entered_critical[s, j] == one.entered_critical
        assert batch.H_mean.shape == (3,)
        assert len(batch.to_frame()) == 6


@settings(max_examples=15, deadline=None)
@given(
    fx=st.floats(-200, 200),
    fy=st.floats(-200, 200),
    vx=st.floats(-0.5, 0.5),
    vy=st.floats(-0.5, 0.5),
    brake=st.booleans(),
)
def test_hold_respects_limits_and_braking(
    fx: float, fy: float, vx: float, vy: float, brake: bool
) -> None:
    assume(math.hypot(vx, vy) <= 0.7)
    hold = build_hold(nav.HolonomicRobot(), 60, 1e-3)
    out = hold(x0=[0, 0, vx, vy], F=[fx, fy], brake=float(brake))
    X = np.array(out["X"])
    v = np.concatenate([[[vx, vy]], X[2:4].T])
    assert np.hypot(*v.T).max() <= 0.7 + 1e-9
    assert np.hypot(*np.diff(v, axis=0).T).max() <= 10.0 * 1e-3 + 1e-12
    if brake:  # decelerates at a_mr along the velocity and stays stopped
        assert np.hypot(*v[-1]) == pytest.approx(max(0.0, math.hypot(vx, vy) - 0.6), abs=1e-9)


def test_nonholonomic_robot_turns_before_moving_sideways() -> None:
    sc = nav.Scenario(
        "side", (0.0, 0.0), (0.0, 3.0), robot=nav.NonholonomicRobot(), initial_heading=0.0
    )
    res = nav.simulate(sc, EXP, stabilising="off")
    assert res.arrived
    assert abs(res.heading[-1] - math.pi / 2) < 0.3
    ho = nav.simulate(sc.with_robot(nav.HolonomicRobot()), EXP, stabilising="off")
    assert res.arrival_time > ho.arrival_time


def test_criteria_formulas() -> None:
    c = nav.criteria(
        arrival_time=math.inf,
        nominal_arrival_time=5.0,
        energy=4.0,
        nominal_energy=2.0,
        surface_clearance={"a": 0.2, "b": -0.01},
        nominal_clearance={"a": 0.4, "b": 0.4},
    )
    assert c.H_T == 0 and c.k == 0 and c.H == 0
    assert c.H_D == pytest.approx((0.5 + 0.0) / 2)
    assert len(c.warnings) == 2
    c2 = nav.criteria(
        arrival_time=10.0,
        nominal_arrival_time=5.0,
        energy=4.0,
        nominal_energy=2.0,
        surface_clearance={"a": 2.0},
        nominal_clearance={"a": 0.4},
    )
    assert c2.H_D == 1.0 and c2.H == pytest.approx((0.5 + 1.0 + 0.5) / 3)


@pytest.mark.parametrize(
    "w", [(0.5, 0.5, 0.5), (1.0, 0.0), (math.nan, 0.5, 0.5), (-0.1, 0.6, 0.5), "abc", None]
)
def test_criteria_weights_are_checked(w: object) -> None:
    with pytest.raises(InvalidParameterError, match="weights"):
        nav.criteria(
            arrival_time=6.0,
            nominal_arrival_time=5.0,
            energy=1.0,
            nominal_energy=1.0,
            surface_clearance={},
            nominal_clearance={},
            weights=w,  # type: ignore[arg-type]
        )
    c = nav.criteria(
        arrival_time=6.0,
        nominal_arrival_time=3.0,
        energy=1.0,
        nominal_energy=1.0,
        surface_clearance={},
        nominal_clearance={},
        weights=(1.0, 0.0, 0.0),
    )
    assert c.H == pytest.approx(0.5)


def test_walk_is_smooth_and_ends_at_rest() -> None:
    w = nav.Walk((0.6, 0.6), (4.0, 0.6), speed=1.0, ramp_time=0.5)
    t = np.linspace(0, 6, 6001)
    p, v, _a = w.state(t)
    assert p[0, 0] == pytest.approx(0.6) and p[-1, 0] == pytest.approx(4.0)
    assert np.abs(np.diff(v[:, 0])).max() < 0.01  # continuous speed
    np.testing.assert_allclose(np.gradient(p[:, 0], t), v[:, 0], atol=2e-3)
    assert v[:, 0].max() == pytest.approx(1.0)


def test_unpredictable_human_follows_sec_5_7() -> None:
    h = nav.configuration("unpredictable").obstacles[0]
    p, _v, _ = h.state(np.array([0.0, 1.0, 2.0, 3.0, 5.0]))
    np.testing.assert_allclose(p[:, 0], [0.6, 1.6, 2.1, 2.1, 2.1], atol=1e-6)
    np.testing.assert_allclose(p[:, 1], [0.0, 0.0, 0.0, 0.5, 2.5], atol=1e-6)


def _spread_gains(n: int) -> np.ndarray:
    rng = np.random.default_rng(7)
    return nav.OPTIMAL_GAINS.as_array()[None, :] * rng.uniform(0.5, 1.5, size=(n, 4))


needs_cc = pytest.mark.skipif(
    compiler_missing_reason() is not None, reason=f"needs a C compiler: {compiler_missing_reason()}"
)


@pytest.mark.slow
@needs_cc
@pytest.mark.parametrize("mode", ["lyapunov", "off"])
def test_jit_compiled_batch_equals_the_virtual_machine(mode: str) -> None:
    # the gain optimiser's fast path: the same CasADi step compiled to four lanes per pass
    # (designlab.sx.lanes); 7 members (the last pass is partly empty) who arrive at different
    # times and leave the call
    gains = _spread_gains(7)
    sc = [nav.configuration(4)]
    vm = nav.simulate_batch(sc, gains, stabilising=mode)
    jit = nav.simulate_batch(sc, gains, stabilising=mode, jit=True)
    assert np.unique(vm.arrival_time[np.isfinite(vm.arrival_time)]).size > 5  # arrive apart
    np.testing.assert_array_equal(jit.arrival_time, vm.arrival_time)
    np.testing.assert_array_equal(jit.min_distance, vm.min_distance)
    np.testing.assert_array_equal(jit.H, vm.H)


@pytest.mark.slow
@needs_cc
def test_jit_compiled_nonholonomic_batch_equals_the_virtual_machine() -> None:
    # the differential drive's step: trigonometry lane by lane from the C library (Config 2:
    # with F_L on and the wheel-speed limit the robot of Config 1 stalls at the circle)
    sc = nav.configuration(2, chapter=7)
    gains = _spread_gains(6)
    vm = engine.run(sc, gains, stabilising=True)
    jit = engine.run(sc, gains, stabilising=True, jit=True)
    assert np.isfinite(vm.arrival_time).sum() >= 4
    for a, b in ((jit.arrival_time, vm.arrival_time), (jit.min_distance, vm.min_distance),
                 (jit.energy, vm.energy), (jit.critical_time, vm.critical_time)):  # fmt: skip
        np.testing.assert_array_equal(a, b)


def test_intersecting_critical_regions_are_found_and_warned_about() -> None:
    def disc(name: str, x: float, y: float) -> nav.Disc:
        return nav.Disc(name, 0.1, r2=0.8, r3=0.4, motion=nav.Stationary((x, y)))

    bar = nav.Rectangle("bar", center=(2.0, -1.5), length=2.0, width=0.4, r2=0.8, r3=0.4)
    cross = nav.Rectangle(
        "cross", center=(2.0, -1.5), length=2.0, width=0.4, r2=0.8, r3=0.3, angle=math.pi / 2
    )
    sc = nav.Scenario(
        "gates",
        start=(4.0, 0.0),
        goal=(0.0, 0.0),
        obstacles=(disc("a", 2.0, 1.0), disc("b", 2.7, 1.0), disc("c", 2.0, -0.6), bar, cross),
    )
    found = {(a, b): o for a, b, o in sc.intersecting_critical_regions()}
    # centres 0.7 m apart, r3 0.4 + 0.4: overlap 0.1 m
    assert found[("a", "b")] == pytest.approx(0.1)
    # disc 0.9 m above the bar's centre line, 0.7 m above its long edge (its corners are
    # 1.22 m away): overlap 0.8 - 0.7 = 0.1 m
    assert found[("c", "bar")] == pytest.approx(0.1)
    # the two bars cross: overlap r3 + r3
    assert found[("bar", "cross")] == pytest.approx(0.7)
    assert ("a", "c") not in found and ("b", "c") not in found
    for which, chapter in ((3, 6), (4, 6), (3, 7)):
        assert nav.configuration(which, chapter).intersecting_critical_regions() == ()
    res = nav.simulate(sc.replace(obstacles=sc.obstacles[:2]), EXP, stabilising="off")
    assert any("overlap by 0.100 m" in w for w in res.warnings)
