"""Stalls and collisions as results: the critical-region rule, the hold audit, the
per-step stall and the stabilising force's counterexample (docs/navigation.md)."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.navigation import engine
from designlab.navigation.field import ObstacleGeometry
from designlab.navigation.recovery import BACK_OUT_MARGIN, critical_response

nav = dl.navigation
EXP = nav.EXPERIMENT_GAINS
#: gains within the App. C box whose stabilising force drives the robot into the human
COUNTEREXAMPLE = nav.VFFGains(9.69, 0.744, 8.1, 302.3)


def _response(robot: object, geo: ObstacleGeometry) -> ca.Function:
    nx = 4 if isinstance(robot, nav.HolonomicRobot) else 5
    x0, obs, F = ca.SX.sym("x0", nx), ca.SX.sym("obs", 6), ca.SX.sym("F", 2)
    Fo, brake = critical_response((geo,), robot, x0, obs, F, period=0.06)
    return ca.Function("r", [x0, obs, F], [Fo, brake])


@settings(max_examples=30, deadline=None)
@given(
    depth=st.floats(1e-4, 0.3),
    angle=st.floats(-np.pi, np.pi),
    obstacle_speed=st.floats(0.05, 1.5),
)
def test_critical_rule_backs_out_of_a_static_region_and_waits_for_an_approaching_one(
    depth: float, angle: float, obstacle_speed: float
) -> None:
    robot = nav.HolonomicRobot()
    geo = ObstacleGeometry("disc", r2=1.2, r3=0.4, moving=True)
    f = _response(robot, geo)
    u = np.array([np.cos(angle), np.sin(angle)])
    p = (0.4 - depth) * u
    pulled_in = -50.0 * u  # the field's force, pointing into the obstacle
    # stopped next to a static obstacle: backs out along the outward normal, no braking
    F, brake = (np.array(v).ravel() for v in f([*p, 0, 0], [0] * 6, pulled_in))
    assert brake[0] == 0.0
    a = np.linalg.norm(F) / robot.mass
    assert F @ u == pytest.approx(np.linalg.norm(F), rel=1e-9)
    expected = min(robot.max_accel, 2 * (depth + BACK_OUT_MARGIN) / 0.06**2)
    assert a == pytest.approx(expected, rel=1e-9)
    # still moving: brakes
    assert float(f([*p, 0.1, 0.0], [0] * 6, pulled_in)[1]) == 1.0
    # stopped, the obstacle approaching: waits (brakes at rest)
    closing = [0, 0, *(obstacle_speed * u), 0, 0]
    assert float(f([*p, 0, 0], closing, pulled_in)[1]) == 1.0
    # stopped, the obstacle walking away: backs out
    leaving = [0, 0, *(-obstacle_speed * u), 0, 0]
    assert float(f([*p, 0, 0], leaving, pulled_in)[1]) == 0.0
    # outside every critical region: the method's force, no braking
    out = (0.5 * u).tolist()
    F_free, b_free = f([*out, 0.1, 0], [0] * 6, pulled_in)
    assert float(b_free) == 0.0 and np.allclose(np.array(F_free).ravel(), pulled_in)


def test_sec_7_5_5_force_off_no_longer_stalls_in_the_circles_critical_region() -> None:
    # The nonholonomic robot enters the circle's critical region by a few mm at 3.05 s.
    # Waiting "until the obstacle leaves" never ended for the static circle (arrival inf);
    # the robot now backs out and arrives, as the thesis's robot does (15 s).
    # The entry came with the robot whose outer wheel outran V in turns (wheel_speed_limit
    # off); with each wheel bounded (the default) the robot keeps out and arrives too.
    robot = nav.NonholonomicRobot(wheel_speed_limit=False)
    sc = nav.configuration("multi", chapter=7, robot=robot)
    res = nav.simulate(sc, EXP, stabilising="off")
    assert res.arrived and res.arrival_time < 20.0
    assert res.entered_critical and not res.collided
    assert res.min_distance["circle"] > 0.4 - 0.02  # a few mm inside at most
    assert res.critical_time < 2.0
    now = nav.simulate(nav.configuration("multi", chapter=7), EXP, stabilising="off")
    assert now.arrived and now.arrival_time < 15.0 and not now.entered_critical


def test_hold_audit_sees_v_rise_between_samples_that_the_sample_audit_cannot() -> None:
    res = nav.simulate(nav.configuration(1), EXP, stabilising="lyapunov")
    sample = res.stability
    held = res.hold_audit()
    assert sample is not None and sample.share_satisfied == 1.0  # true by construction
    assert held.periods > 50
    assert 0.1 < held.share_rose < 0.9 and held.max_rise > 0
    # the audit's V at the samples is the engine's V
    k = np.searchsorted(held.t, sample.t[:20])
    assert held.V[k] == pytest.approx(sample.V[:20], rel=1e-9, abs=1e-12)


def test_force_every_step_stall_is_a_sliding_mode_on_omega_zero() -> None:
    # Recomputed every 1 ms, F_L = max(Omega, 0)/|v_L| switches on and off: each time the
    # robot moves, Omega > 0 and F_L (growing as 1/|v_L|) cancels the pull; the robot
    # creeps at ~1 mm/s at 0.62 m from the circle, V falling by <1 in 30 s.
    sc = nav.configuration(1, horizon=5.0)
    raw = engine.run(sc, EXP.as_array()[None, :], force_every_step=True, record=True)
    rec = raw.record
    assert rec is not None and not np.isfinite(raw.arrival_time[0])
    t = rec["t_sample"]
    late = t >= 2.0
    speed = np.hypot(rec["x_sample"][late, 2], rec["x_sample"][late, 3])
    assert speed.max() < 5e-3
    on = np.hypot(rec["FL"][late, 0], rec["FL"][late, 1]) > 0
    assert 0.05 < on.mean() < 0.95  # chattering
    V = rec["V"][late, 0]
    assert V[-1] < V[0] and V[0] - V[-1] < 0.5
    # the same gains with the force held for 60 ms arrive
    assert nav.simulate(nav.configuration(1), EXP).arrived


def test_stabilising_force_counterexample_is_flagged_and_rejected_by_the_optimiser() -> None:
    sc = nav.configuration(2)
    on = nav.simulate(sc, COUNTEREXAMPLE, stabilising="lyapunov")
    off = nav.simulate(sc, COUNTEREXAMPLE, stabilising="off")
    assert on.collided and on.criteria.H == 0.0
    assert not off.entered_critical
    ev = nav.evaluate_gains([sc], [COUNTEREXAMPLE.as_array()], stabilising="lyapunov")
    assert not bool(ev.frame["feasible"].iloc[0])


def test_optimiser_flags_an_optimum_that_the_other_mode_makes_unsafe() -> None:
    from designlab.navigation.tuning import _Evaluator, _other_mode_warnings

    ev = _Evaluator([nav.configuration(2)], "off", None, "mean", 0.15, None, 1)
    (warning,) = _other_mode_warnings(ev, COUNTEREXAMPLE)
    assert "stabilising='lyapunov'" in warning and "ch6_config2" in warning
    assert _other_mode_warnings(ev, nav.OPTIMAL_GAINS) == []


def test_navigation_page_examples_run() -> None:
    import doctest
    from pathlib import Path

    page = Path(__file__).resolve().parents[2] / "docs" / "navigation.md"
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    assert doctest.testfile(str(page), module_relative=False, optionflags=flags).failed == 0


#: The App. C.2 search box (K1, b, K3, K5), sampled log-uniformly as the benchmark does.
_BOX = np.array([[0.5, 50.0], [0.05, 3.0], [0.5, 200.0], [0.5, 500.0]])


def _random_gains(n: int, seed: int) -> np.ndarray:
    lo, hi = np.log(_BOX[:, 0]), np.log(_BOX[:, 1])
    return np.exp(lo + (hi - lo) * np.random.default_rng(seed).random((n, 4)))


def test_the_cbf_layer_removes_the_stabilising_forces_counterexample() -> None:
    sc = nav.configuration(2)
    bare = nav.simulate(sc, COUNTEREXAMPLE)
    layer = nav.simulate(sc, COUNTEREXAMPLE, method="vff_cbf")
    assert bare.collided and bare.entered_critical
    assert not layer.collided and not layer.entered_critical
    # the layer works on the robot's own force: every recorded distance stays >= r3
    r3 = sc.obstacles[0].r3
    assert layer.trajectory_frame()["d_human_m"].min() >= r3
    with pytest.raises(ValueError, match="not batched"):
        nav.simulate_batch([sc], COUNTEREXAMPLE.as_array()[None, :], method="vff_cbf")


@pytest.mark.slow
@pytest.mark.parametrize("config", [1, 2, 3, 4])
def test_the_cbf_layer_keeps_random_gain_sets_out_of_the_critical_regions(config: int) -> None:
    # 50 gain sets per configuration (benchmarks/navigation_safety.py runs 1,000). The
    # guarantee's assumption (docs/navigation.md, "A safety layer"): every obstacle is static
    # or no faster than the robot can retreat. It holds for the circle and the rectangle, so
    # their critical regions are never entered; the walking human (1.0 m/s head-on against a
    # 0.7 m/s robot) breaks it, and there the layer can only do better than the bare field.
    sc = nav.configuration(config)
    gains = _random_gains(50, seed=config)
    bare = nav.simulate_batch([sc], gains)
    layer = [nav.simulate(sc, nav.VFFGains(*g), method="vff_cbf") for g in gains]
    for r, g in zip(layer, gains, strict=True):
        for o in sc.obstacles:
            if not o.motion.moving:
                assert r.min_distance[o.name] >= o.r3, (g, o.name)
        if not any(o.motion.moving for o in sc.obstacles):
            assert not r.entered_critical, g
    collided = np.array([r.collided for r in layer])
    assert collided.sum() <= bare.collided[0].sum()
    assert not (collided & ~bare.collided[0]).any()  # the layer adds no collision
