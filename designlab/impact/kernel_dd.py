"""The reduced impact model's modal solution in double-double arithmetic, compiled: the fast
first try of :mod:`.kernel_precise` (issue 34; docs/impact.md, "Self-check").

The same algorithm as :mod:`.kernel_precise`'s 40-digit decimal evaluation, operation for
operation: the closed-form coefficients (:func:`.kernel_poles.coefficients`, Zeng 2011
(3.5.11), (3.5.14), (3.9.2)), the poles refined by the Weierstrass (Durand-Kerner)
iteration from given starts and enclosed in the disks ``|z - z_j| <= 4 |W_j|``
(Carstensen 1991), a pole real where its disk is the only one meeting its mirror image,
the residues, the polynomial part and the error bounds. Each number is a pair of doubles
whose sum carries about 32 significant digits (Dekker 1971; the error-free ``two_sum``
and ``two_prod``); the evaluation's rounding is bounded by :data:`EPS` relative to the
magnitudes of the terms, as the decimal version bounds its own. A design whose disks do
not isolate its poles here, or whose coefficients are too large for the error-free
products (above :data:`BIG`), is left to the decimal evaluation. About 200 times faster
than it: the nearly repeated modes of the fuzz family ``repeated``
(``benchmarks/fuzz_kernel.py``), 70 % of which the double-precision self-check refuses,
no longer cost a millisecond each.

Examples
--------
>>> import numpy as np
>>> q = np.array([[9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 46, 3e3]])
>>> poles, res, poly, err, ok = dd_responses(q, False)
>>> bool(ok[0]), poles.shape, bool(err.max() < 1e-10)
(True, (1, 4), True)
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from designlab.sx.jit import kernel

__all__ = ["BIG", "EPS", "dd_responses", "starts"]

#: a generous bound of the double-double evaluation's relative rounding (1e5 units of its
#: last digit, 2^-104), as :data:`.kernel_precise._EPS` bounds the decimal one's
EPS = 1e5 * 2.0**-104
#: the Weierstrass iteration stops once every root's disk is this small (relative)
_CONVERGED = 1e-28
_ITERATIONS = 60
_UNIT = 2.0**-53
_SPLIT = 134217729.0  # 2^27 + 1 (Dekker's splitting)
#: largest coefficient or product handled (the splitting overflows near 1e300)
BIG = 1e290


@kernel(inline=True)
def _two_sum(a, b):  # type: ignore[no-untyped-def]
    s = a + b
    v = s - a
    return s, (a - (s - v)) + (b - v)


@kernel(inline=True)
def _quick(a, b):  # type: ignore[no-untyped-def]
    s = a + b
    return s, b - (s - a)


@kernel(inline=True)
def _two_prod(a, b):  # type: ignore[no-untyped-def]
    p = a * b
    t = _SPLIT * a
    ah = t - (t - a)
    al = a - ah
    t = _SPLIT * b
    bh = t - (t - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


@kernel(inline=True)
def _add(x, y):  # type: ignore[no-untyped-def]
    """Sum of two double-doubles ``(hi, lo)``."""
    s, e = _two_sum(x[0], y[0])
    t, f = _two_sum(x[1], y[1])
    s, e = _quick(s, e + t)
    return _quick(s, e + f)


@kernel(inline=True)
def _neg(x):  # type: ignore[no-untyped-def]
    return -x[0], -x[1]


@kernel(inline=True)
def _mul(x, y):  # type: ignore[no-untyped-def]
    p, e = _two_prod(x[0], y[0])
    return _quick(p, e + (x[0] * y[1] + x[1] * y[0]))


@kernel(inline=True)
def _div(x, y):  # type: ignore[no-untyped-def]
    q1 = x[0] / y[0]
    r = _add(x, _neg(_mul((q1, 0.0), y)))
    q2 = r[0] / y[0]
    r = _add(r, _neg(_mul((q2, 0.0), y)))
    q3 = r[0] / y[0]
    return _add(_quick(q1, q2), (q3, 0.0))


@kernel(inline=True)
def _d(a):  # type: ignore[no-untyped-def]
    return a, 0.0


@kernel(inline=True)
def _cmul(x, y):  # type: ignore[no-untyped-def]
    """Product of two double-double complex numbers ``((re_h, re_l), (im_h, im_l))``."""
    re = _add(_mul(x[0], y[0]), _neg(_mul(x[1], y[1])))
    im = _add(_mul(x[0], y[1]), _mul(x[1], y[0]))
    return re, im


@kernel(inline=True)
def _cadd(x, y):  # type: ignore[no-untyped-def]
    return _add(x[0], y[0]), _add(x[1], y[1])


@kernel(inline=True)
def _csub(x, y):  # type: ignore[no-untyped-def]
    return _add(x[0], _neg(y[0])), _add(x[1], _neg(y[1]))


@kernel(inline=True)
def _cdiv(x, y):  # type: ignore[no-untyped-def]
    n = _cmul(x, (y[0], _neg(y[1])))
    d = _add(_mul(y[0], y[0]), _mul(y[1], y[1]))
    return _div(n[0], d), _div(n[1], d)


@kernel(inline=True)
def _cabs(x):  # type: ignore[no-untyped-def]
    """``|x|`` as a double (to about one rounding: only bounds use it)."""
    return math.hypot(x[0][0] + x[0][1], x[1][0] + x[1][1])


@kernel(inline=True)
def _get(a, i):  # type: ignore[no-untyped-def]
    return a[i, 0], a[i, 1]


@kernel(inline=True)
def _set(out, i, v):  # type: ignore[no-untyped-def]
    out[i, 0], out[i, 1] = v[0], v[1]


@kernel(inline=True)
def _horner(coef, n, x):  # type: ignore[no-untyped-def]
    """``P(x)`` and ``P'(x)`` of the real double-double coefficients ``coef[:n]``
    (``(n, 2)``, descending) at the complex ``x``."""
    f = (_get(coef, 0), (0.0, 0.0))
    df = ((0.0, 0.0), (0.0, 0.0))
    for k in range(1, n):
        df = _cadd(_cmul(df, x), f)
        f = _cmul(f, x)
        f = (_add(f[0], _get(coef, k)), f[1])
    return f, df


@kernel(borrows=True)
def _coefficients(q, printed, den, nums, e):  # type: ignore[no-untyped-def]
    """The monic denominator ``den`` (5, 2) and numerators ``nums`` (3, 6, 2) of
    :func:`.kernel_poles.coefficients` in double-double from the design ``q`` (``e``
    (5, 2) scratch)."""
    m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h = q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7]
    mm = _two_prod(m_r, m_h)
    cc = _add(_two_prod(c_c, c_r), _two_prod(c_c, c_h))
    if not printed:
        cc = _add(cc, _two_prod(c_r, c_h))
    _set(den, 0, (1.0, 0.0))
    _set(den, 1, _add(_div(_two_sum(c_r, c_c), _d(m_r)), _div(_two_sum(c_c, c_h), _d(m_h))))
    x = _add(_div(_two_sum(k_r, k_c), _d(m_r)), _div(_two_sum(k_h, k_c), _d(m_h)))
    _set(den, 2, _add(x, _div(cc, mm)))
    a = _mul(_d(k_r), _two_sum(c_c, c_h))
    b = _mul(_d(k_c), _two_sum(c_r, c_h))
    c = _mul(_d(k_h), _two_sum(c_c, c_r))
    _set(den, 3, _div(_add(_add(a, b), c), mm))
    a = _add(_add(_two_prod(k_r, k_h), _two_prod(k_c, k_h)), _two_prod(k_r, k_c))
    _set(den, 4, _div(a, mm))
    zr1, zr2 = _div(_d(c_r), _d(m_r)), _div(_d(k_r), _d(m_r))
    zh1, zh2 = _div(_d(c_h), _d(m_h)), _div(_d(k_h), _d(m_h))
    _set(e, 0, (1.0, 0.0))
    _set(e, 1, _add(zr1, zh1))
    _set(e, 2, _add(_add(zr2, _mul(zr1, zh1)), zh2))
    _set(e, 3, _add(_mul(zr1, zh2), _mul(zr2, zh1)))
    _set(e, 4, _mul(zr2, zh2))
    nums[:] = 0.0
    _set(nums[0], 0, _mul(_d(c_c), _get(e, 0)))
    for k in range(1, 5):
        _set(nums[0], k, _add(_mul(_d(c_c), _get(e, k)), _mul(_d(k_c), _get(e, k - 1))))
    _set(nums[0], 5, _mul(_d(k_c), _get(e, 4)))
    _set(nums[1], 0, _div(_d(c_c), _d(m_h)))
    _set(nums[1], 1, _div(_add(_mul(_d(c_c), zr1), _d(k_c)), _d(m_h)))
    _set(nums[1], 2, _div(_add(_mul(_d(c_c), zr2), _mul(_d(k_c), zr1)), _d(m_h)))
    _set(nums[1], 3, _div(_mul(_d(k_c), zr2), _d(m_h)))
    for k in range(5):
        _set(nums[2], k + 1, _get(e, k))


@kernel(inline=True)
def _z(z, j):  # type: ignore[no-untyped-def]
    return (z[j, 0], z[j, 1]), (z[j, 2], z[j, 3])


@kernel(inline=True)
def _put(z, j, v):  # type: ignore[no-untyped-def]
    z[j, 0], z[j, 1], z[j, 2], z[j, 3] = v[0][0], v[0][1], v[1][0], v[1][1]


@kernel(inline=True)
def _complex(v):  # type: ignore[no-untyped-def]
    return complex(v[0][0] + v[0][1], v[1][0] + v[1][1])


@kernel(borrows=True)
def _roots(den, size, z, w, radius):  # type: ignore[no-untyped-def]
    """The four roots of ``den`` refined in ``z`` (4, 4) from its values and the radii of
    disks around them that hold one root each; False where two disks overlap (as
    :func:`.kernel_precise._roots`: the last corrections ``W_j`` are those at the
    previous points, whose disks lie within five times theirs around the new points)."""
    for _ in range(_ITERATIONS):
        idle = True
        for j in range(4):
            x = _z(z, j)
            prod = ((1.0, 0.0), (0.0, 0.0))
            for k in range(4):
                if k != j:
                    prod = _cmul(prod, _csub(x, _z(z, k)))
            if prod[0][0] == 0.0 and prod[1][0] == 0.0:
                return False
            f = _horner(den, 5, x)[0]
            _put(w, j, _cdiv(f, prod))
            ax = _cabs(x)
            s = 0.0
            for k in range(5):
                s += size[k] * ax ** (4 - k)
            noise = EPS * s / _cabs(prod)
            wj = _cabs(_z(w, j))
            radius[j] = 5.0 * (4.0 * wj + noise)
            idle = idle and 4.0 * wj <= noise  # no correction above the rounding left
        big = 0.0
        for j in range(4):
            _put(z, j, _csub(_z(z, j), _z(w, j)))
            big = max(big, _cabs(_z(z, j)))
        if idle or max(radius[0], radius[1], radius[2], radius[3]) <= _CONVERGED * big:
            break
    for j in range(4):
        for k in range(j + 1, 4):
            if not _cabs(_csub(_z(z, j), _z(z, k))) > radius[j] + radius[k]:
                return False
    return True


@kernel(borrows=True)
def _fold(z, radius, keep):  # type: ignore[no-untyped-def]
    """The roots kept by the fold (one per conjugate pair) into ``keep`` (index, weight 2 for a
    pair, 1 for a real root); their number, or -1 where a disk meets the real axis and
    another disk (:func:`.kernel_precise._fold`)."""
    n = 0
    for j in range(4):
        x = _z(z, j)
        if abs(x[1][0] + x[1][1]) > radius[j]:  # the disk lies off the axis: complex
            if x[1][0] > 0:
                keep[n, 0], keep[n, 1] = j, 2.0
                n += 1
            continue
        mirror = (x[0], _neg(x[1]))
        for k in range(4):  # the mirror disk may meet this disk only: the root is real
            if k != j and _cabs(_csub(mirror, _z(z, k))) <= radius[j] + radius[k]:
                return -1
        z[j, 2] = z[j, 3] = 0.0  # moved by at most the radius
        radius[j] *= 2.0
        keep[n, 0], keep[n, 1] = j, 1.0
        n += 1
    return n


@kernel(borrows=True)
def _residues(z, radius, j, wt, nums, poles, res, err, slot):  # type: ignore[no-untyped-def]
    """Pole ``j`` (weight ``wt``) into ``poles[slot]``, its residues and their error bounds (as
    :func:`.kernel_precise._design`)."""
    x = _z(z, j)
    ax = _cabs(x)
    poles[slot] = _complex(x)
    dp = _cmul(x, x)
    sep = 0.0
    for k in range(4):
        if k != j:
            d = _csub(x, _z(z, k))
            dp = _cmul(dp, d)
            sep += (radius[j] + radius[k]) / _cabs(d)
    delta = radius[j] + ax * _UNIT  # the pole's error once rounded
    adp = _cabs(dp)
    for o in range(3):
        f, df = _horner(nums[o], 6, x)
        r = _cdiv(_cmul(f, ((wt, 0.0), (0.0, 0.0))), dp)
        res[o, slot] = _complex(r)
        a = _cabs(r)
        size = 0.0
        for k in range(6):
            size += abs(nums[o, 5 - k, 0]) * ax**k
        slope = _cabs(df) * wt / adp
        # the evaluation's rounding, the root's enclosure, then one rounding of r
        e = EPS * size * wt / adp + slope * radius[j] + a * (sep + 2.0 * radius[j] / ax)
        err[o, slot, 0] = 2.0 * (e + 2.0 * a * _UNIT)
        err[o, slot, 1] = 2.0 * a * delta


@kernel
def _dd_block(params, printed, starts, poles, res, poly, err, ok):  # type: ignore[no-untyped-def]
    den = np.empty((5, 2))
    nums = np.empty((3, 6, 2))
    e = np.empty((5, 2))
    size = np.empty(5)
    z = np.empty((4, 4))
    w = np.empty((4, 4))
    radius = np.empty(4)
    keep = np.empty((4, 2))
    for i in range(params.shape[0]):
        ok[i] = False
        q = params[i]
        fine = True
        for k in range(8):
            fine = fine and (q[k] == 0.0 or 1e-100 <= abs(q[k]) <= 1e100)
        if not fine:
            continue
        _coefficients(q, printed, den, nums, e)
        for k in range(5):
            size[k] = abs(den[k, 0])
            fine = fine and size[k] < BIG
        for k in range(4):
            s = starts[i, k]
            fine = fine and np.isfinite(s.real) and np.isfinite(s.imag)
            z[k, 0], z[k, 1], z[k, 2], z[k, 3] = s.real, 0.0, s.imag, 0.0
        if not fine or not _roots(den, size, z, w, radius):
            continue
        n = _fold(z, radius, keep)
        weight = 0.0
        for k in range(max(n, 0)):
            weight += keep[k, 1]
        if n < 0 or weight != 4.0:
            continue
        for slot in range(n):
            _residues(z, radius, int(keep[slot, 0]), keep[slot, 1], nums, poles[i], res[i],
                      err[i], slot)  # fmt: skip
        for slot in range(n, 4):  # unused slots: the first pole with a zero residue
            poles[i, slot] = poles[i, 0]
        for o in range(3):
            rho0 = _div(_get(nums[o], 5), _get(den, 4))
            rho1 = _div(_add(_get(nums[o], 4), _neg(_mul(_get(den, 3), rho0))), _get(den, 4))
            poly[i, o, 0], poly[i, o, 1] = rho0[0] + rho0[1], rho1[0] + rho1[1]
        ok[i] = True


def starts(params: NDArray[np.float64], printed: bool) -> NDArray[np.complex128]:
    """Double-precision roots ``(N, 4)`` of the designs' characteristic quartics (the
    eigenvalues of their companion matrices; NaN where the coefficients are not finite):
    the Weierstrass iteration's starts.

    Parameters
    ----------
    params : ndarray, shape (N, 8)
        Reduced unconstrained designs, columns M_r, C_r, K_r, K_c, C_c, M_h, C_h, K_h (SI).
    printed : bool
        Use the thesis's printed q2 of (3.5.14) (no C_r C_h term) instead of the derived one.

    Returns
    -------
    ndarray, shape (N, 4), complex
        The roots, NaN for designs whose coefficients are not finite.
    """
    m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h = np.asarray(params, dtype=np.float64).T
    cc = c_c * c_r + c_c * c_h + (0.0 if printed else c_r * c_h)
    mm = m_r * m_h
    with np.errstate(all="ignore"):
        a = np.stack([(c_r + c_c) / m_r + (c_c + c_h) / m_h,
                      (k_r + k_c) / m_r + (k_h + k_c) / m_h + cc / mm,
                      (k_r * (c_c + c_h) + k_c * (c_r + c_h) + k_h * (c_c + c_r)) / mm,
                      (k_r * k_h + k_c * k_h + k_r * k_c) / mm], axis=1)  # fmt: skip
    fine = np.all(np.isfinite(a), axis=1)
    comp = np.zeros((a.shape[0], 4, 4))
    comp[:, 0, :] = -np.where(fine[:, None], a, 0.0)
    comp[:, 1, 0] = comp[:, 2, 1] = comp[:, 3, 2] = 1.0
    z = np.linalg.eigvals(comp).astype(np.complex128) if a.shape[0] else np.zeros((0, 4), complex)
    z[~fine] = np.nan
    return z


def dd_responses(
    params: NDArray[np.float64], printed: bool, start: NDArray[np.complex128] | None = None
) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray[np.bool_]]:
    """Folded poles ``(N, 4)``, residues ``(N, 3, 4)`` (force, head acceleration,
    compression), polynomial parts ``(N, 3, 2)``, error bounds ``(N, 3, 4, 2)`` and a mask
    of the designs certified here, of reduced unconstrained designs ``params`` ``(N, 8)``
    (the thesis's printed q2 of (3.5.14) where ``printed``) from the starts ``(N, 4)`` of
    the Weierstrass iteration (by default :func:`starts`).

    Parameters
    ----------
    params : ndarray, shape (N, 8)
        Reduced unconstrained designs, columns M_r, C_r, K_r, K_c, C_c, M_h, C_h, K_h (SI).
    printed : bool
        Use the thesis's printed q2 of (3.5.14) instead of the derived one.
    start : ndarray, shape (N, 4), complex, optional
        Starting roots of the Weierstrass iteration; by default :func:`starts`.

    Returns
    -------
    tuple
        Poles, residues, polynomial parts, error bounds and the certified mask, as above.
    """
    p = np.ascontiguousarray(params, dtype=np.float64)
    n = p.shape[0]
    start = starts(p, printed) if start is None else start
    poles = np.zeros((n, 4), dtype=np.complex128)
    res = np.zeros((n, 3, 4), dtype=np.complex128)
    poly = np.zeros((n, 3, 2))
    err = np.zeros((n, 3, 4, 2))
    ok = np.zeros(n, dtype=np.bool_)
    _dd_block(p, bool(printed), np.ascontiguousarray(start, dtype=np.complex128), poles, res,
              poly, err, ok)  # fmt: skip
    return poles, res, poly, err, ok
