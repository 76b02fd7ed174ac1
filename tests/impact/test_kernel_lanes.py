"""The kernel's own complex exponential and its side-by-side pole search (issue 22).

* :func:`designlab.impact.kernel_exp.cexp` against a 30-digit exponential over
  random arguments, at the quadrant boundaries and beyond its reduction range
  (where ``cmath.exp`` answers).
* :func:`designlab.impact.kernel_poles.bairstow_lanes` gives every lane the
  values of the one-design Bairstow iteration bit for bit, whatever the lane count.
* Blocks of designs give each design what it gets alone, bit for bit, with an
  overflowing design inside a block.
"""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.impact import kernel
from designlab.impact.kernel_exp import REDUCE_LIMIT, cexp
from designlab.impact.kernel_poles import LANES, _bairstow, bairstow_lanes, coefficients

mpmath = pytest.importorskip("mpmath")

RANGES = [(2, 20), (0, 800), (5e3, 5e4), (5e3, 8e4), (0, 300), (3, 6), (0, 150), (1e3, 1e4)]
KW = dict(printed=False, stop_time=0.05, max_lobe_steps=4096, diagnostics=False)


def _exp_mp(z: complex) -> complex:
    mpmath.mp.dps = 30
    return complex(mpmath.exp(mpmath.mpc(z.real, z.imag)))


@settings(max_examples=300, deadline=None)
@given(st.floats(-60.0, 5.0), st.floats(-REDUCE_LIMIT, REDUCE_LIMIT))
def test_cexp_is_exact_to_a_few_ulps(x: float, y: float) -> None:
    z = complex(x, y)
    exact = _exp_mp(z)
    assert abs(cexp(z) - exact) <= 4e-16 * abs(exact)


@pytest.mark.parametrize("k", range(-9, 10))
@pytest.mark.parametrize("offset", [-1e-9, 0.0, 1e-9, 0.3, 0.78])
def test_cexp_signs_at_every_quadrant(k: int, offset: float) -> None:
    z = complex(-0.25, k * math.pi / 2 + offset)
    exact = _exp_mp(z)
    assert abs(cexp(z) - exact) <= 4e-16 * abs(exact)


@pytest.mark.parametrize(
    "z",
    [complex(0.1, 2e5), complex(-1.0, -3e7), complex(-math.inf, 1.0), complex(math.nan, 1.0),
     complex(0.0, math.inf), complex(1.0, math.nan), complex(800.0, 0.5)],
)  # fmt: skip
def test_cexp_beyond_its_range_is_cmath(z: complex) -> None:
    """Compiled, ``cmath.exp`` answers with numba's IEEE values (Python's raises here)."""
    numba = pytest.importorskip("numba")
    if not kernel.AVAILABLE:
        pytest.skip("compiled kernels unavailable")
    a, b = cexp(z), numba.njit(lambda w: cmath.exp(w))(z)
    for u, v in ((a.real, b.real), (a.imag, b.imag)):
        assert u == v or (math.isnan(u) and math.isnan(v))


def _quartics(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    den, num = np.empty((n, 5)), np.zeros((n, 3, 6))
    for i in range(n):
        q = [rng.uniform(*b) for b in RANGES]
        coefficients(*q, bool(i % 2), den[i], num[i])
    return den


@pytest.mark.parametrize("m", [2, 5, LANES])
def test_lanes_give_each_quartic_its_own_bairstow_bit_for_bit(m: int) -> None:
    den = _quartics(m, 30 + m)
    den[0] = [1.0, math.nan, 0.0, 0.0, 0.0]  # fails at once (a NaN determinant)
    den[1] = [1.0, 0.0, 0.0, 0.0, 0.0]  # s^4: no convergence in 60 steps
    rng = np.random.default_rng(m)
    u0, v0 = rng.uniform(0.0, 100.0, m), rng.uniform(1e3, 1e5, m)
    u, v, state = u0.copy(), v0.copy(), np.empty(m, dtype=np.int8)
    bairstow_lanes(den, u, v, state, m)
    assert state[0] == 0 and state[1] == 2
    for k in range(m):
        ua, va, ok = _bairstow(den[k], u0[k], v0[k])
        if state[k] == 2:  # out of steps: the one-design call decides on its residual
            assert (u[k], v[k]) == (ua, va)
        else:
            assert bool(state[k]) == ok
        if state[k] == 1:
            assert (u[k], v[k]) == (ua, va)
    assert (state[2:] == 1).all()


@pytest.mark.skipif(not kernel.AVAILABLE, reason="compiled kernels unavailable")
def test_blocks_give_each_design_what_it_gets_alone() -> None:
    rng = np.random.default_rng(2011)
    n = 2 * LANES + 5
    p = np.column_stack([rng.uniform(*b, n) for b in RANGES])
    p[LANES + 3, 0] = 1e-160  # overflows the model, inside the second block
    out, status = kernel.reduced_metrics(p, (True, True, True), **KW)
    assert status[LANES + 3] == kernel.OVERFLOW
    for i in range(n):
        one, st1 = kernel.reduced_metrics(p[i : i + 1], (True, True, True), **KW)
        assert st1[0] == status[i]
        np.testing.assert_array_equal(one[0], out[i])
