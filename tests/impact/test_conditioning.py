"""The time-scale ratio of reduced designs against a 40-digit evaluation of its definition.

:func:`designlab.impact.conditioning.time_scale_ratio` estimates the ratio of the fastest to
the slowest pole modulus from the characteristic polynomial's coefficients (docs/impact.md,
"Limits"); reduced unconstrained designs take a compiled pass where numba is present. Both
paths are checked here against mpmath. The coefficients are sums of products of
non-negative parameters (a few rounding errors each); the estimate is an exponential of
differences of their logarithms (at most about 100 in size here), so its relative error is
at most a few hundred ulps: the tolerance is 1e-12.
"""

from __future__ import annotations

import mpmath
import numpy as np
import pytest

from designlab.impact import conditioning, kernel

mpmath.mp.dps = 40
RTOL = 1e-12


def _exact(row: np.ndarray) -> float:
    """The estimate of ``row`` (PARAM_NAMES order) from the polynomial of Zeng 2011,
    Sec. 3.5, ``(M_r s^2 + C_r s + K_r)(M_h s^2 + C_h s + K_h) + (K_c + C_c s)((M_r + M_h) s^2
    + (C_r + C_h) s + K_r + K_h)``, at 40 digits."""
    m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h = (mpmath.mpf(float(x)) for x in row)
    c = [
        k_r * k_h + k_c * (k_r + k_h),
        c_r * k_h + k_r * c_h + k_c * (c_r + c_h) + c_c * (k_r + k_h),
        m_r * k_h + c_r * c_h + k_r * m_h + k_c * (m_r + m_h) + c_c * (c_r + c_h),
        m_r * c_h + c_r * m_h + c_c * (m_r + m_h),
        m_r * m_h,
    ]  # ascending powers
    a = [c[4 - k] / c[4] for k in range(5)]  # monic, descending: a_0 = 1
    top = max(a[k] ** (mpmath.mpf(1) / k) for k in range(1, 5) if a[k] > 0)
    low = min((a[4] / a[4 - k]) ** (mpmath.mpf(1) / k) for k in range(1, 5) if a[4 - k] > 0)
    return float(max(top / low, 1))


def _designs() -> np.ndarray:
    """Typical, wide and extreme designs (parameters 1e-6-1e6 times the typical ones, some
    dampings and neck stiffnesses zero)."""
    rng = np.random.default_rng(34)
    typical = np.array([9.6, 250.0, 2e4, 2.4e4, 72.0, 4.4, 46.0, 3e3])
    p = typical * 10.0 ** rng.uniform(-6.0, 6.0, (300, 8))
    zero = rng.uniform(size=p.shape) < 0.1
    zero[:, [0, 2, 3, 5]] = False  # C_r, C_c, C_h and K_h may be 0
    p[zero] = 0.0
    return np.vstack([typical, p])


@pytest.mark.parametrize("compiled", [True, False])
def test_time_scale_ratio_is_its_definition(compiled: bool, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    if compiled and not kernel.AVAILABLE:
        pytest.skip("no compiled kernels here")
    monkeypatch.setattr(kernel, "AVAILABLE", compiled)
    p = _designs()
    got = conditioning.time_scale_ratio(p)
    want = np.array([_exact(row) for row in p])
    np.testing.assert_allclose(got, want, rtol=RTOL)
    assert got.max() > 1e6 and got.min() < 10  # both sides of the bound are covered
