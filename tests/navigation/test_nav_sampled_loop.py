"""The sampled PD attraction loop (dynamics.attraction_loop_radius) and H above 1.

Finding (s37): an optimum at K1 = 143, b = 1.10 scored H_mean > 1. Its attraction loop,
held for T_s = 0.06 s, is unstable (K2 T_s/m = 2.145 > 2): the obstacle-free nominal run
chatters at the acceleration limit near the goal and L* doubles, so H_E = L*/L reaches 1.9.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from designlab.navigation import HolonomicRobot, VFFGains, configuration, evaluate_gains
from designlab.navigation.criteria import criteria
from designlab.navigation.dynamics import attraction_loop_radius, build_hold

M, T, DT = 4.4, 0.06, 1e-3


def test_jury_boundary_is_exact() -> None:
    # 1 + tr + det = 4 - 2 K2 T/m - K1 T dt/m = 0 at K1* = 2 m / (T (b + dt/2)): eigenvalue -1
    b = 1.0
    k1 = 2 * M / (T * (b + DT / 2))
    assert attraction_loop_radius(k1, b, M, T, DT) == pytest.approx(1.0, abs=1e-12)
    assert attraction_loop_radius(k1 * 0.999, b, M, T, DT) < 1.0
    assert attraction_loop_radius(k1 * 1.001, b, M, T, DT) > 1.0
    # det = 1 at b = (T - dt)/2 (complex pair on the unit circle for a small K1)
    assert attraction_loop_radius(1.0, (T - DT) / 2, M, T, DT) == pytest.approx(1.0, abs=1e-12)
    assert attraction_loop_radius(1.0, (T - DT) / 2 * 0.99, M, T, DT) > 1.0


def test_radius_of_the_finding_by_hand() -> None:
    k1, b = 143.0, 1.10
    a, be, c = k1 / M, b * k1 / M, T * (T + DT) / 2
    tr = 2 - a * c - be * T
    det = 1 - be * T - a * c + a * T * T
    hand = abs(tr / 2 - math.sqrt(tr * tr / 4 - det))  # real pair, the negative one dominates
    assert attraction_loop_radius(k1, b, M) == pytest.approx(hand, rel=1e-14)
    assert hand == pytest.approx(1.15006, abs=1e-5)


def test_the_matrix_is_the_simulator_hold() -> None:
    """One held period of build_hold (no limit reached) is A (e, v) to rounding."""
    k1, b = 2.0, 0.5
    hold = build_hold(HolonomicRobot(), n_sub=60, dt=DT)
    e, v = np.array([0.01, -0.02]), np.array([0.03, 0.01])  # goal at the origin, p = -e
    F = k1 * e - b * k1 * v
    X = np.array(hold(x0=[*(-e), *v], F=F, brake=0)["X"])[:, -1]
    a, be, c = k1 / M, b * k1 / M, T * (T + DT) / 2
    A = np.array([[1 - a * c, be * c - T], [a * T, 1 - be * T]])
    for ax in range(2):
        e1, v1 = A @ np.array([e[ax], v[ax]])
        assert -X[ax] == pytest.approx(e1, abs=1e-15)
        assert X[2 + ax] == pytest.approx(v1, abs=1e-15)


def test_criteria_warn_when_a_ratio_exceeds_one() -> None:
    c = criteria(arrival_time=8.0, nominal_arrival_time=6.0, energy=1.0, nominal_energy=2.0,
                 surface_clearance={"human": 0.5}, nominal_clearance={"human": 0.5})  # fmt: skip
    assert c.H_E == 2.0 and c.H == pytest.approx((0.75 + 1.0 + 2.0) / 3, rel=1e-15)
    assert any("H_E = 2.000 > 1" in w for w in c.warnings)


def test_the_finding_is_infeasible() -> None:
    g = VFFGains(k1=143.0, b=1.10, k3=25913.0, k5=49644.0)
    e = evaluate_gains([configuration(1)], g, stabilising="off")
    row = e.frame.iloc[0]
    assert bool(row["arrived_all"]) and bool(row["critical_free"])
    assert not bool(row["feasible"])
    assert "unstable sampled attraction loop" in e.warnings[0]


def test_simulate_warns_for_the_finding() -> None:
    from designlab.navigation import simulate

    g = VFFGains(k1=143.0, b=1.10, k3=25913.0, k5=49644.0)
    res = simulate(configuration(2), g, stabilising="off")
    assert any("spectral radius 1.150 >= 1" in w for w in res.warnings)
    assert res.criteria.H_E > 1 and any("H_E =" in w for w in res.criteria.warnings)
    ok = simulate(configuration(2), VFFGains(4.3, 0.68, 20.3, 240.7), stabilising="off")
    assert not any("spectral radius" in w for w in ok.warnings)


def test_simulate_and_batch_report_undefined_criteria_when_only_the_nominal_run_fails(
    monkeypatch,
):
    """The nominal (obstacle-free) run made to miss the goal, the obstacle run unchanged:
    simulate returns H NaN with status 'undefined' and the warning (it raised before: the
    navigation_gains study crashed in its settling check); the batch gives NaN and counts it."""
    import importlib
    from dataclasses import replace

    from designlab.navigation import simulate, simulate_batch

    engine = importlib.import_module("designlab.navigation.simulate").engine
    real = engine.run

    def nominal_never_arrives(scenario, gains, **kw):
        raw = real(scenario, gains, **kw)
        if not scenario.obstacles:
            raw = replace(raw, arrival_time=np.full_like(raw.arrival_time, np.inf))
        return raw

    monkeypatch.setattr(engine, "run", nominal_never_arrives)
    sc = configuration(1)
    res = simulate(sc, VFFGains(3, 0.25, 20, 17), stabilising="off")
    c = res.criteria
    assert math.isfinite(res.arrival_time) and c.status == "undefined"
    assert math.isnan(c.H) and math.isnan(c.H_T) and math.isnan(c.H_E) and 0 < c.H_D <= 1
    assert any("nominal run never arrived" in w for w in res.warnings)
    batch = simulate_batch([sc], np.array([[3, 0.25, 20, 17]]), stabilising="off")
    assert np.isnan(batch.H[0, 0]) and np.isnan(batch.H_T[0, 0]) and np.isnan(batch.H_E[0, 0])
    assert any("nominal run did not" in w for w in batch.warnings)
