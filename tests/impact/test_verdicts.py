"""Three-way foam verdicts and the deterministic worst-case check (Zeng 2011, Sec. 3.9).

The boundaries are recomputed here by plain bisection on the model's metrics,
independently of the envelope's root finder.
"""

from __future__ import annotations

import itertools

import pytest
from scipy.optimize import brentq

import designlab as dl
from designlab.impact import (
    FOAM_1,
    FOAM_2,
    FOAM_3,
    HEAD_MAX,
    HEAD_MIN,
    MANIPULATOR_1,
    MANIPULATOR_2,
)

V = 1.25


def _metric(robot, k, c, head, attr):
    p = {"M_r": robot.mass, "C_r": robot.damping, "K_r": robot.stiffness, "K_c": k, "C_c": c,
         "M_h": head.mass, "C_h": head.damping, "K_h": head.stiffness}  # fmt: skip
    return float(getattr(dl.impact.impact_metrics(p, V), attr)[0])


def _upper(robot, c):  # a_h,max(K) = 10 g with the minimum head set
    f = lambda k: _metric(robot, k, c, HEAD_MIN, "peak_head_acceleration_g") - 10.0  # noqa: E731
    return brentq(f, 1e3, 1e6, xtol=1e-9, rtol=1e-12)


def _lower(robot, c):  # eps_max(K) = 20 mm with the maximum head set
    f = lambda k: _metric(robot, k, c, HEAD_MAX, "max_compression") - 0.02  # noqa: E731
    return brentq(f, 1e3, 1e6, xtol=1e-9, rtol=1e-12)


@pytest.fixture(scope="module")
def envs():
    return {
        r.name: dl.impact.foam_envelope(r, V, [0.0, 100.0]) for r in (MANIPULATOR_1, MANIPULATOR_2)
    }


def test_thesis_foams_three_way(envs) -> None:
    m1, m2 = envs["Manipulator 1"], envs["Manipulator 2"]
    # Sec. 3.9: Foam 1 feasible on both; Foam 2 "almost on the boundary" on Manipulator 1
    assert dl.impact.foam_verdict(m1, FOAM_1).verdict == "feasible"
    assert dl.impact.foam_verdict(m2, FOAM_1).verdict == "feasible"
    v = dl.impact.foam_verdict(m1, FOAM_2)
    assert v.verdict == "on the boundary" and v.nearest == "lower"
    kmin = _lower(MANIPULATOR_1, FOAM_2.damping)
    assert v.stiffness_min == pytest.approx(kmin, rel=1e-7)
    assert abs(FOAM_2.stiffness / kmin - 1) < 0.01
    # Foam 2 well below the thickness boundary on Manipulator 2
    v = dl.impact.foam_verdict(m2, FOAM_2)
    kmin = _lower(MANIPULATOR_2, FOAM_2.damping)
    assert v.verdict == "not feasible"
    assert v.lower_deficit == pytest.approx(1 - FOAM_2.stiffness / kmin, rel=1e-6)
    assert f"is {100 * v.lower_deficit:.1f} % below the lower (thickness) boundary" in v.statement
    # Foam 3: how far outside is K_c / K_c,max - 1, said as "exceeds ... by"
    for env, robot in ((m1, MANIPULATOR_1), (m2, MANIPULATOR_2)):
        v = dl.impact.foam_verdict(env, FOAM_3)
        excess = FOAM_3.stiffness / _upper(robot, FOAM_3.damping) - 1
        assert v.verdict == "not feasible" and v.upper_excess == pytest.approx(excess, rel=1e-6)
        assert f"exceeds the upper (safety) boundary by {100 * excess:.1f} %" in v.statement
    assert dl.impact.foam_verdict(m1, FOAM_3).upper_excess == pytest.approx(0.0100, abs=5e-4)
    assert dl.impact.foam_verdict(m2, FOAM_3).upper_excess == pytest.approx(0.276, abs=5e-3)


BAND = [(0.98, "feasible"), (0.995, "on the boundary"), (1.005, "on the boundary"),
        (1.02, "not feasible")]  # fmt: skip


@pytest.mark.parametrize(("factor", "expected"), BAND)
def test_tolerance_band_around_the_upper_boundary(envs, factor, expected) -> None:
    c = 60.0
    k = _upper(MANIPULATOR_1, c) * factor
    v = dl.impact.foam_verdict(envs["Manipulator 1"], dl.impact.Foam(k, c))
    assert v.verdict == expected
    assert (v.upper_excess > 0) == (factor > 1)


def test_worst_case_corners_are_exact_and_find_the_onset() -> None:
    """Manipulator 1's lower boundary: the maximum head set stops being the worst near
    C_c = 107 N s/m (xi_c ~ 0.24); each corner ratio is recomputed here."""
    c_grid = [100.0, 110.0, 120.0]
    env = dl.impact.foam_envelope(MANIPULATOR_1, V, c_grid)
    check = dl.impact.check_worst_case(env, samples=0)
    name = "eps_max <= 20 mm"
    box = dl.impact.THESIS_HEAD_RANGE
    for i, c in enumerate(c_grid):
        k = float(env.stiffness_min[i])
        ratios = [
            _metric(MANIPULATOR_1, k, c, dl.impact.HeadNeck(m, kh, ch), "max_compression") / 0.02
            for m, kh, ch in itertools.product(box.mass, box.stiffness, box.damping)
        ]
        assert check.corner_ratio_by_point[name][i] == pytest.approx(max(ratios), rel=1e-9)
    assert check.corner_ratio_by_point[name][0] <= 1 + 1e-6
    assert check.corner_ratio_by_point[name][1] > 1.0
    assert check.status == "violated" and not check.holds
    assert 100.0 < check.onset_damping[name] < 110.0
    assert 0.2 < check.onset_damping_ratio[name] < 0.26
    assert any("not the worst case on the lower boundary" in w for w in check.warnings)
