"""Pass/fail from certified bounds: the full kernel's decisions, exactly (issue 40.5).

The full kernel is certified (its maxima within 1e-8), so the decisions of
:func:`head_acceleration_exceeds` must equal, design for design, those of
:func:`metrics_of_matrix` compared with the limit: an exact check. The long run
(1e6-1e7 designs) is ``benchmarks/passfail.py``; here a seeded slice.
"""

from __future__ import annotations

import numpy as np
import pytest

from designlab.errors import InvalidParameterError
from designlab.impact.metrics import metrics_of_matrix
from designlab.impact.passfail import (
    A_H_ONLY,
    Decisions,
    decisions_of_metrics,
    head_acceleration_exceeds,
)

BASE = [9.6, 250.0, 20e3, 24.25e3, 71.9, 4.4, 0.0, 4e3]


def _designs(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Wide random designs with their edges (no foam or head damping, no neck stiffness)."""
    rng = np.random.default_rng(seed)
    p = np.column_stack([
        rng.uniform(2, 40, n), rng.uniform(0, 500, n), 10 ** rng.uniform(3, 5, n),
        10 ** rng.uniform(3, 5.5, n), rng.uniform(0, 300, n), rng.uniform(2, 8, n),
        rng.uniform(0, 60, n), rng.uniform(1e3, 1e4, n),
    ])  # fmt: skip
    p[rng.random(n) < 0.05, 4] = 0.0  # C_c = 0: a_h starts at zero
    p[rng.random(n) < 0.1, 7] = 0.0  # K_h = 0
    v = rng.uniform(0.1, 3.0, n)
    return p, v


def _reference(p: np.ndarray, v: np.ndarray, limit: float) -> np.ndarray:
    return decisions_of_metrics(metrics_of_matrix(p, v, **A_H_ONLY).peak_head_acceleration_g, limit)


@pytest.mark.parametrize("limit", [3.0, 10.0, 40.0])
def test_decisions_equal_the_full_kernel(limit: float) -> None:
    p, v = _designs(6000, 405)
    d = head_acceleration_exceeds(p, v, limit)
    assert isinstance(d, Decisions)
    ref = _reference(p, v, limit)
    assert np.array_equal(d.exceeds, ref)
    assert d.by_bounds.mean() > 0.9  # the bounds decide nearly every design
    assert 0 < ref.sum() < ref.size


def test_limits_at_the_maxima_go_to_the_full_kernel() -> None:
    """A limit within 1e-9 .. 1e-3 of a design's maximum: the bounds cannot decide it, the
    full kernel does (and both sides of the limit are met)."""
    p, v = _designs(400, 406)
    peak = metrics_of_matrix(p, v, **A_H_ONLY).peak_head_acceleration_g
    ok = np.isfinite(peak)
    p, v, peak = p[ok], v[ok], peak[ok]
    rng = np.random.default_rng(7)
    for rel in (1e-9, 1e-6, 1e-4, 1e-3):
        sign = rng.choice([-1.0, 1.0], size=peak.size)
        for i in range(0, peak.size, 40):
            limit = float(peak[i] * (1 + sign[i] * rel))
            d = head_acceleration_exceeds(p[i : i + 1], v[i : i + 1], limit)
            assert bool(d.exceeds[0]) == bool(peak[i] > limit), (i, rel)
            if rel <= 1e-6:
                assert not d.by_bounds[0]


def test_threads_give_the_same_decisions() -> None:
    p, v = _designs(9000, 407)
    one = head_acceleration_exceeds(p, v, 10.0, workers=1)
    two = head_acceleration_exceeds(p, v, 10.0, workers=2)
    for a, b in zip(one, two, strict=True):
        assert np.array_equal(a, b)


def test_no_impact_and_one_velocity() -> None:
    p = np.array([BASE, BASE])
    d = head_acceleration_exceeds(p, np.array([0.0, 1.25]), 6.5)
    assert d.exceeds.tolist() == _reference(p, np.array([0.0, 1.25]), 6.5).tolist()
    assert d.exceeds.tolist() == [False, True]
    assert not d.by_bounds[0]  # v_c <= 0 goes to the full kernel
    assert head_acceleration_exceeds(BASE, 1.25, 7.0).exceeds.tolist() == [False]


@pytest.mark.parametrize(
    ("limit", "params", "v", "name"),
    [
        (float("nan"), BASE, 1.25, "limit_g"),
        (float("inf"), BASE, 1.25, "limit_g"),
        (-1.0, BASE, 1.25, "limit_g"),
        (0.0, BASE, 1.25, "limit_g"),
        (True, BASE, 1.25, "limit_g"),
        ("10", BASE, 1.25, "limit_g"),
        (10.0, [*BASE[:3], float("nan"), *BASE[4:]], 1.25, "params"),
        (10.0, [*BASE[:3], -1.0, *BASE[4:]], 1.25, "K_c"),
        (10.0, [*BASE[:5], 1e300, *BASE[6:]], 1.25, "M_h"),
        (10.0, BASE[:7], 1.25, "params"),
        (10.0, BASE, float("nan"), "impact_velocity"),
        (10.0, BASE, [1.0, 2.0, 3.0], "impact_velocity"),
    ],
)
def test_hostile_inputs_are_refused_by_name(
    limit: object, params: object, v: object, name: str
) -> None:
    with pytest.raises((InvalidParameterError, ValueError), match=name):
        head_acceleration_exceeds(params, v, limit)  # type: ignore[arg-type]


def test_a_design_the_kernel_leaves_uncertified_is_decided_by_the_bounds() -> None:
    """The full kernel could not certify this design's first zero of a_h (NaN, counted as
    exceeding); the bounds show its whole first lobe below 10 g, a certified decision that
    stands (the benchmark's one such design in a million wide ones)."""
    p = [2.4433630214122215, 11.39363367080744, 11186.555464777537, 28738.223834794924,
         162.18085838762366, 4.063392521443943, 33.75525528495021, 6273.642933677337]  # fmt: skip
    v = 0.30184936060074774
    d = head_acceleration_exceeds(p, v, 10.0)
    assert d.by_bounds.tolist() == [True] and d.exceeds.tolist() == [False]
    assert d.unresolved.tolist() == [False]
    peak = metrics_of_matrix([p], v, **A_H_ONLY).peak_head_acceleration_g[0]
    assert np.isnan(peak) or peak <= 10.0
