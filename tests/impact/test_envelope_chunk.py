"""The batched envelope evaluator of sweeps equals the public API applied design by design.

:func:`designlab.impact.evaluators.foam_envelope_chunk` solves every design of a chunk
in one root-finding; the reference here is a plain loop of the public
:func:`~designlab.impact.foam_envelope` and :func:`~designlab.impact.foam_verdict`.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from designlab.analysis.engine import evaluate_chunk
from designlab.impact import ContactDynamics, Foam, HeadAcceleration, foam_envelope, foam_verdict
from designlab.impact.evaluators import foam_envelope_chunk

DAMPING = [0.0, 75.0, 150.0, 225.0, 300.0]
COLUMNS = ("M_r", "C_r", "K_r", "v_c", "max_g", "lambda", "K_c", "C_c")


def _reference(pt: dict[str, float]) -> dict[str, object]:
    """One design through the public API: the columns the chunk must report."""
    env = foam_envelope(
        ContactDynamics(mass=pt["M_r"], stiffness=pt["K_r"], damping=pt["C_r"]),
        pt["v_c"],
        DAMPING,
        [HeadAcceleration(max_g=pt["max_g"])],
        pt["lambda"],
    )
    fv = foam_verdict(env, Foam(pt["K_c"], pt["C_c"], linear_depth=pt["lambda"]))

    def positive(x: float) -> float:
        return x if math.isfinite(x) and x > 0 else math.nan

    return {
        "k_c_max_N_per_m": positive(fv.stiffness_max),
        "k_c_min_N_per_m": positive(fv.stiffness_min),
        "margin_decades": fv.margin_decades if math.isfinite(fv.margin_decades) else math.nan,
        "area_log": env.area(log=True),
        "verdict": fv.verdict,
        "feasible": fv.feasible,
        "empty": env.is_empty,
        "status": "empty" if env.is_empty else "ok",
        "warnings": "; ".join((*env.warnings, *fv.warnings)) or None,
    }


def _design(m, k_r, c_r, v, g, lam, k_c, c_c) -> dict[str, float]:
    return dict(zip(COLUMNS, (m, c_r, k_r, v, g, lam, k_c, c_c), strict=True))


@pytest.fixture(scope="module")
def designs() -> list[dict[str, float]]:
    rng = np.random.default_rng(14)
    out = [
        _design(
            rng.uniform(5, 50),
            rng.uniform(10e3, 30e3),
            rng.uniform(50, 500),
            rng.uniform(0.5, 1.5),
            rng.uniform(8, 12),
            rng.uniform(0.01, 0.03),
            10 ** rng.uniform(3.5, 5.5),
            rng.uniform(0, 300),
        )
        for _ in range(8)
    ]
    base = _design(10, 20e3, 250, 1.25, 10, 0.02, 24e3, 70.0)
    out += [
        {**base, "v_c": 4.0, "max_g": 3.0},  # empty everywhere; upper no_solution at C_c
        {**base, "max_g": 1000.0, "lambda": 1.0},  # both boundaries unbounded
        {**base, "max_g": 1.0, "lambda": 1e-4},  # both hold nowhere at C_c
        {**base, "K_c": 50.0},  # outside the stiffness range: a verdict warning
        {**base, "C_c": 0.0},  # on the grid's first damping value
    ]
    ref = _reference(base)  # the foam just inside each boundary: "on the boundary"
    out += [
        {**base, "K_c": 0.996 * float(ref["k_c_max_N_per_m"])},
        {**base, "K_c": 1.004 * float(ref["k_c_min_N_per_m"])},
    ]
    return out


def test_chunk_equals_the_public_api_per_design(designs) -> None:
    points = {c: np.array([d[c] for d in designs]) for c in COLUMNS}
    out = foam_envelope_chunk(points, {"damping": DAMPING})
    refs = [_reference(d) for d in designs]
    # the edge cases are really there
    verdicts = [r["verdict"] for r in refs]
    assert verdicts.count("on the boundary") >= 2 and "feasible" in verdicts
    assert any(r["empty"] for r in refs) and any(r["warnings"] for r in refs)
    assert any(np.isnan(r["k_c_max_N_per_m"]) for r in refs)  # unbounded or held nowhere
    assert any(np.isnan(r["k_c_min_N_per_m"]) for r in refs)
    for col in ("k_c_max_N_per_m", "k_c_min_N_per_m"):
        expected = np.array([r[col] for r in refs], dtype=float)
        np.testing.assert_allclose(out[col], expected, rtol=1e-6, equal_nan=True, err_msg=col)
    for col, atol in (("margin_decades", 1e-6), ("area_log", 1e-6 * DAMPING[-1])):
        expected = np.array([r[col] for r in refs], dtype=float)
        np.testing.assert_allclose(out[col], expected, rtol=1e-6, atol=atol, equal_nan=True)
    for col in ("verdict", "feasible", "empty", "status", "warnings"):
        assert list(out[col]) == [r[col] for r in refs], col


def test_a_failing_design_is_isolated_by_the_sweep_engine(designs) -> None:
    rows = [designs[0], {**designs[1], "max_g": -1.0}, designs[2]]
    points = {c: np.array([d[c] for d in rows]) for c in COLUMNS}
    task = {"evaluator": foam_envelope_chunk, "options": {"damping": DAMPING}, "points": points}
    out = evaluate_chunk(task)
    assert list(out["status"]) == ["ok", "error", "ok"]
    assert "HeadAcceleration.max_g" in out["error"][1]
    refs = [_reference(rows[0]), _reference(rows[2])]
    got = out["k_c_max_N_per_m"][[0, 2]]
    np.testing.assert_allclose(got, [r["k_c_max_N_per_m"] for r in refs], rtol=1e-6)
    assert [out["verdict"][i] for i in (0, 2)] == [r["verdict"] for r in refs]


def test_envelopes_solved_together_keep_each_designs_criteria() -> None:
    from designlab.impact import MANIPULATOR_1, MANIPULATOR_2
    from designlab.impact.envelope import foam_envelopes

    designs = [(MANIPULATOR_1, 1.25, [HeadAcceleration(10)], 0.02),
               (MANIPULATOR_2, 1.0, [HeadAcceleration(8)], 0.015)]  # fmt: skip
    together = foam_envelopes(designs, [0.0, 100.0])
    for design, env in zip(designs, together, strict=True):
        alone = foam_envelope(*design[:2], [0.0, 100.0], *design[2:])
        assert list(env.upper) == list(alone.upper) == [design[2][0].name]
        np.testing.assert_allclose(env.stiffness_max, alone.stiffness_max, rtol=1e-6)
        np.testing.assert_allclose(env.stiffness_min, alone.stiffness_min, rtol=1e-6)
        assert env.is_feasible(24e3, 70.0) == alone.is_feasible(24e3, 70.0)


def test_only_problems_differing_in_robot_and_limits_are_solved_together() -> None:
    from designlab.errors import InvalidParameterError
    from designlab.impact import MANIPULATOR_1, ImpactForce, LinkImpact
    from designlab.impact.envelope import foam_envelopes

    one = (MANIPULATOR_1, 1.25, [HeadAcceleration(10)], 0.02)
    force = (MANIPULATOR_1, 1.25, [ImpactForce(660.0)], 0.02)
    link = (LinkImpact(0.059, 121.68, 1.521, 3.0, 0.01, 0.3), None, [HeadAcceleration(10)], 0.02)
    for other in (force, link):
        with pytest.raises(InvalidParameterError, match="problems"):
            foam_envelopes([one, other], [0.0])
