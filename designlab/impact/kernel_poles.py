"""Compiled exact modal solution of the reduced impact model, one design at a time (numba).

The transfer functions of Zeng 2011 (3.5.11), (3.5.14) and (3.9.2) in closed
form (docs/impact.md, "The model"): with ``z_r = s^2 + (C_r s + K_r)/M_r``,
``z_h = s^2 + (C_h s + K_h)/M_h`` and ``z_c = C_c s + K_c``, the monic
denominator is ``D = s^4 + q1 s^3 + q2 s^2 + q3 s + q4`` and the responses to the
unit ramp (v_c = 1) are ``N(s) / (s^2 D(s))`` with

* force ``N = z_c z_r z_h``, compression ``N = z_r z_h``,
* head acceleration ``N = s^2 z_c z_r / M_h``.

The poles are the roots of ``D``: a quadratic factor by Bairstow's iteration
started from the head's own mode (numpy's eigenvalues of the companion matrix
where it does not converge), each root polished by Newton on ``D``; nearly
coincident poles are separated as in :func:`designlab.impact.modal.poles_of`,
and residues and the polynomial part follow
:meth:`designlab.impact.modal.ModalResponse.family`.

Examples
--------
>>> import numpy as np
>>> roots = np.empty(4, dtype=np.complex128)
>>> quartic_roots(np.array([1.0, 10.0, 35.0, 50.0, 24.0]), 0.0, 0.0, roots)  # (s+1)(s+2)(s+3)(s+4)
>>> sorted(np.round(roots.real, 12).tolist())
[-4.0, -3.0, -2.0, -1.0]
"""

from __future__ import annotations

import math

import numpy as np

from designlab.sx.jit import kernel

__all__ = ["RESIDUAL", "coefficients", "modal_solution", "quartic_roots", "roots_certified"]

SEPARATION = 1e-6
#: largest relative residual (backward error) of a root the a-posteriori check accepts:
#: a root polished by Newton has a few ulps (2.2e-16 each); 1e-12 leaves 4,500 of them
RESIDUAL = 1e-12
#: designs whose quadratic factors are found side by side (:func:`bairstow_lanes`)
LANES = 16


@kernel(borrows=True)
def coefficients(m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h, printed, den, num):  # type: ignore[no-untyped-def]
    """Fill ``den`` (5,) and ``num`` (3, 6): force, head acceleration, compression (descending)."""
    mm = m_r * m_h
    den[0] = 1.0
    den[1] = (c_r + c_c) / m_r + (c_c + c_h) / m_h
    cc = c_c * c_r + c_c * c_h if printed else c_c * c_r + c_c * c_h + c_r * c_h
    den[2] = (k_r + k_c) / m_r + (k_h + k_c) / m_h + cc / mm
    den[3] = (k_r * (c_c + c_h) + k_c * (c_r + c_h) + k_h * (c_c + c_r)) / mm
    den[4] = (k_r * k_h + k_c * k_h + k_r * k_c) / mm
    zr1, zr2 = c_r / m_r, k_r / m_r
    zh1, zh2 = c_h / m_h, k_h / m_h
    # z_r z_h (descending, degree 4)
    e0, e1, e2 = 1.0, zr1 + zh1, zr2 + zr1 * zh1 + zh2
    e3, e4 = zr1 * zh2 + zr2 * zh1, zr2 * zh2
    num[2, 0], num[2, 1], num[2, 2], num[2, 3], num[2, 4], num[2, 5] = 0.0, e0, e1, e2, e3, e4
    # z_c z_r z_h
    num[0, 0] = c_c * e0
    num[0, 1] = c_c * e1 + k_c * e0
    num[0, 2] = c_c * e2 + k_c * e1
    num[0, 3] = c_c * e3 + k_c * e2
    num[0, 4] = c_c * e4 + k_c * e3
    num[0, 5] = k_c * e4
    # s^2 z_c z_r / M_h
    num[1, 0] = c_c / m_h
    num[1, 1] = (c_c * zr1 + k_c) / m_h
    num[1, 2] = (c_c * zr2 + k_c * zr1) / m_h
    num[1, 3] = k_c * zr2 / m_h
    num[1, 4] = 0.0
    num[1, 5] = 0.0


@kernel(borrows=True)
def _bairstow(a, u, v):  # type: ignore[no-untyped-def]
    """Quadratic factor ``s^2 + u s + v`` of the monic quartic ``a``; ``(u, v, converged)``.

    Newton on the remainder ``(b3, b4)`` of the division by the factor;
    ``d_k = d b_k / d u`` (and ``d b_k / d v = d_(k-1)``).
    """
    a1, a2, a3, a4 = a[1], a[2], a[3], a[4]
    scale = max(1.0, abs(a1), abs(a2), abs(a3), abs(a4))
    b3 = b4 = 0.0
    for _ in range(60):
        b1 = a1 - u
        b2 = a2 - u * b1 - v
        b3 = a3 - u * b2 - v * b1
        b4 = a4 - u * b3 - v * b2
        d1 = -1.0
        d2 = -b1 - u * d1
        d3 = -b2 - u * d2 - v * d1
        d4 = -b3 - u * d3 - v * d2
        det = d3 * d3 - d2 * d4
        if det == 0 or not np.isfinite(det):
            return u, v, False
        du = (-b3 * d3 + b4 * d2) / det
        dv = (-b4 * d3 + b3 * d4) / det
        u += du
        v += dv
        if abs(du) <= 1e-14 * abs(u) + 1e-300 and abs(dv) <= 1e-14 * abs(v):
            return u, v, True
    return u, v, abs(b3) + abs(b4) <= 1e-12 * scale


@kernel(inline=True)
def _quadratic(b1, b2, roots, i):  # type: ignore[no-untyped-def]
    """Roots of ``s^2 + b1 s + b2`` into ``roots[i], roots[i + 1]`` (conjugates exact)."""
    disc = 0.25 * b1 * b1 - b2
    if disc < 0:
        w = math.sqrt(-disc)
        roots[i] = complex(-0.5 * b1, w)
        roots[i + 1] = complex(-0.5 * b1, -w)
    else:
        big = -0.5 * b1 - math.copysign(math.sqrt(disc), b1)
        roots[i] = big
        roots[i + 1] = b2 / big if big != 0 else 0.0


@kernel(inline=True)
def _square(z):  # type: ignore[no-untyped-def]
    """``|z|^2`` of a real or complex number (no hypot: the moduli here are far from overflow)."""
    return z.real * z.real + z.imag * z.imag


@kernel(inline=True)
def _reciprocal(z):  # type: ignore[no-untyped-def]
    """``1 / z`` of a real or complex number with one real division (no overflow care)."""
    return z.conjugate() * (1.0 / _square(z))


@kernel(inline=True)
def _polish(a, x):  # type: ignore[no-untyped-def]
    """Two Newton steps of the root ``x`` of the monic quartic ``a`` (kept if they help)."""
    for _ in range(2):
        f = a[0] * x + a[1]
        df = a[0]
        for k in range(2, 5):
            df = df * x + f
            f = f * x + a[k]
        if df == 0:
            return x
        xn = x - f * _reciprocal(df)
        fn = (((xn + a[1]) * xn + a[2]) * xn + a[3]) * xn + a[4]
        if not _square(fn) < _square(f):  # |fn| < |f| without hypot
            return x
        x = xn
    return x


@kernel
def _companion_roots(a, roots):  # type: ignore[no-untyped-def]
    """The roots of the monic quartic ``a`` where Bairstow failed from the head's mode.

    numpy's eigenvalues of the companion matrix give approximations whose real
    roots carry imaginary parts of rounding size (either sign), so they are never
    folded by that sign: they are paired into the two real quadratic factors that
    fit them best (:func:`_partner`), Bairstow refines the first factor from there,
    and :func:`factor_roots` takes the roots of both factors. Each factor has two
    real roots or an exact conjugate pair, so the roots are always four, real ones
    real, whatever the rounding of the eigenvalues.
    """
    comp = np.zeros((4, 4), dtype=np.complex128)
    for k in range(4):
        comp[0, k] = -a[k + 1]
    for k in range(3):
        comp[k + 1, k] = 1.0
    ev = np.linalg.eigvals(comp)
    j = _partner(ev)
    u0 = -(ev[0] + ev[j]).real
    v0 = (ev[0] * ev[j]).real
    u, v, ok = _bairstow(a, u0, v0)
    if not ok:  # keep the eigenvalues' factor (polished root by root below)
        u, v = u0, v0
    factor_roots(a, u, v, roots)


@kernel(inline=True)
def _partner(ev):  # type: ignore[no-untyped-def]
    """Index ``j`` of the root that pairs with ``ev[0]`` among the four roots ``ev``: the
    pairing whose two quadratic factors are closest to real (imaginary parts of their
    sums and products, relative to the roots' size). Conjugates pair up, real roots
    with real roots."""
    big = 1e-300
    for k in range(4):
        big = max(big, _square(ev[k]))
    scale = math.sqrt(big)
    best, bj = np.inf, 1
    for j in range(1, 4):
        k = 2 if j == 1 else 1  # the other two
        m = 2 if j == 3 else 3
        off = abs((ev[0] + ev[j]).imag) / scale + abs((ev[0] * ev[j]).imag) / big
        off += abs((ev[k] + ev[m]).imag) / scale + abs((ev[k] * ev[m]).imag) / big
        if off < best:
            best, bj = off, j
    return bj


@kernel(inline=True)
def quartic_roots(a, u0, v0, roots):  # type: ignore[no-untyped-def]
    """The four roots of the monic quartic ``a`` (descending) into ``roots``.

    Bairstow from the factor guess ``s^2 + u0 s + v0`` (from the eigenvalues of the
    companion matrix if it fails, :func:`_companion_roots`); real roots stay real,
    complex ones come in exact conjugate pairs.
    """
    if not _factor_roots(a, u0, v0, roots):
        _companion_roots(a, roots)


@kernel(borrows=True)
def _factor_roots(a, u0, v0, roots):  # type: ignore[no-untyped-def]
    """:func:`quartic_roots` by Bairstow; False (``roots`` untouched) where it fails."""
    u, v, ok = _bairstow(a, u0, v0)
    if ok:
        factor_roots(a, u, v, roots)
    return ok


@kernel(borrows=True)
def factor_roots(a, u, v, roots):  # type: ignore[no-untyped-def]
    """The roots of the monic quartic ``a`` from its quadratic factor ``s^2 + u s + v``,
    each polished by Newton on ``a`` (real roots stay real, complex ones conjugate)."""
    g1 = a[1] - u
    g2 = a[2] - u * g1 - v
    _quadratic(u, v, roots, 0)
    _quadratic(g1, g2, roots, 2)
    for i in (0, 2):
        if roots[i].imag == 0:
            roots[i] = _polish(a, roots[i].real)
            roots[i + 1] = _polish(a, roots[i + 1].real)
        else:
            x = _polish(a, roots[i])
            roots[i] = complex(x.real, abs(x.imag))
            roots[i + 1] = complex(x.real, -abs(x.imag))


@kernel(borrows=True)
def bairstow_lanes(den, u, v, state, m):  # type: ignore[no-untyped-def]
    """:func:`_bairstow` on the quartics ``den[l]`` (l < m) at once, in lockstep.

    Independent designs side by side keep the processor's arithmetic units busy
    (one design's iteration is a chain of dependent operations). Each lane stops
    where :func:`_bairstow` stops, so ``u[l], v[l]`` are its values bit for bit;
    ``state[l]`` ends 1 where it converged, 0 where it failed and 2 where it ran
    out of steps (:func:`quartic_roots` then decides, as it would alone).
    """
    for k in range(m):
        state[k] = 2
    for _ in range(60):
        live = 0
        for k in range(m):
            uk, vk = u[k], v[k]
            b1 = den[k, 1] - uk
            b2 = den[k, 2] - uk * b1 - vk
            b3 = den[k, 3] - uk * b2 - vk * b1
            b4 = den[k, 4] - uk * b3 - vk * b2
            d2 = -b1 + uk
            d3 = -b2 - uk * d2 + vk
            d4 = -b3 - uk * d3 - vk * d2
            det = d3 * d3 - d2 * d4
            du = (-b3 * d3 + b4 * d2) / det
            dv = (-b4 * d3 + b3 * d4) / det
            un, vn = uk + du, vk + dv
            going = state[k] == 2
            bad = (det == 0.0) | (not np.isfinite(det))
            done = (abs(du) <= 1e-14 * abs(un) + 1e-300) & (abs(dv) <= 1e-14 * abs(vn))
            step = going & (not bad)
            u[k] = un if step else uk
            v[k] = vn if step else vk
            state[k] = (0 if bad else (1 if done else 2)) if going else state[k]
            live += state[k] == 2
        if live == 0:
            return


@kernel(inline=True)
def separate(poles, n):  # type: ignore[no-untyped-def]
    """Move roots closer than a relative 1e-6 apart (:func:`designlab.impact.modal.poles_of`)."""
    big = 0.0
    for i in range(n):
        big = max(big, _square(poles[i]))
    scale = max(math.sqrt(big), 1e-300)
    for i in range(n):
        for j in range(i + 1, n):
            if _square(poles[i] - poles[j]) < (SEPARATION * scale) ** 2:
                mid = 0.5 * (poles[i] + poles[j])
                d = SEPARATION * scale
                poles[i] = mid - d
                poles[j] = mid + d


@kernel(borrows=True)
def modal_solution(den, num, roots, p, r, c, outputs):  # type: ignore[no-untyped-def]
    """Folded poles ``p``, residues ``r`` (3, 4) and polynomial parts ``c`` (3, 2); pole count
    (-1 where the poles are not representable: coefficients beyond double precision).

    ``roots`` (4,) are the roots of ``den``; ``outputs[o]`` selects the outputs built.
    """
    n = 4
    nk = 0
    for i in range(n):
        if roots[i].imag < 0:
            continue
        w = 2.0 if roots[i].imag > 0 else 1.0
        pi = roots[i]
        prod = pi * pi
        for j in range(n):
            if j != i:
                prod = prod * (pi - roots[j])
        if not (prod.real != 0.0 or prod.imag != 0.0) or not np.isfinite(prod):
            return -1  # coefficients beyond double precision (poles underflow or overflow)
        p[nk] = pi
        scale = w / prod  # one complex division per pole, shared by the outputs
        for o in range(3):
            if outputs[o]:
                acc = complex(num[o, 0], 0.0)
                for k in range(1, 6):
                    acc = acc * pi + num[o, k]
                r[o, nk] = acc * scale
        nk += 1
    for o in range(3):
        if outputs[o]:
            rho0 = num[o, 5] / den[4]
            rho1 = (num[o, 4] - den[3] * rho0) / den[4]
            c[o, 0], c[o, 1] = rho0, rho1
    return nk


@kernel(inline=True)
def roots_certified(a, roots):  # type: ignore[no-untyped-def]
    """The a-posteriori check of the four roots of the monic quartic ``a``: each has a
    relative residual ``|a(x)| / sum_k |a_k| |x|^k`` (its backward error) below
    :data:`RESIDUAL`, and the complex ones come in exact conjugate pairs (so that the
    fold of :func:`modal_solution` counts every root once: four with the degree)."""
    for i in range(4):
        x = roots[i]
        if not (np.isfinite(x.real) and np.isfinite(x.imag)):
            return False
        f = a[0] * x + a[1]
        size = abs(a[0])
        ax = math.sqrt(_square(x))
        size = size * ax + abs(a[1])
        for k in range(2, 5):
            f = f * x + a[k]
            size = size * ax + abs(a[k])
        if not _square(f) <= (RESIDUAL * size) ** 2:
            return False
        if x.imag != 0:
            partners = 0
            for j in range(4):
                if roots[j].real == x.real and roots[j].imag == -x.imag:
                    partners += 1
            if partners != 1:
                return False
    return True
