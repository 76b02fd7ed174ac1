"""Compiled per-design building blocks of the impact kernel (numba; see :mod:`.kernel`).

One design's exact response of an output ``o`` is
``y(t) = c0 t + c1 + Re sum_k r[o, k] exp(p[k] t)`` (one pole per conjugate pair
with a doubled residue; :mod:`designlab.impact.modal`). These functions evaluate
it and its derivatives, bound its rounding noise and its second and third
derivatives over a cell, and run the safeguarded Newton iteration of
:mod:`designlab.impact.modal` on one design at a time.

Examples
--------
>>> import numpy as np
>>> p = np.array([-1.0 + 0j]); r = np.array([[-1.0 + 0j]]); c = np.array([[0.0, 1.0]])
>>> y, dy, ddy, _, _ = triple(p, r, c, 0, 1, 1.0)          # y = 1 - exp(-t)
>>> [round(float(x), 6) for x in (y, dy, ddy)]
[0.632121, 0.367879, -0.367879]
"""

from __future__ import annotations

import cmath
import math

import numpy as np

from designlab.sx.jit import kernel

__all__ = [
    "NOISE", "cell_bound", "curvature", "derivatives", "exponentials", "grid", "jerk", "mag",
    "newton", "noise", "pair", "real_product", "shape", "stable", "triple", "value",
]  # fmt: skip

#: a value y(t) is provably negative when y < -NOISE * (sum of the magnitudes of its terms)
NOISE = 1e-12


@kernel(inline=True)
def mag(z):  # type: ignore[no-untyped-def]
    """``|z|`` without hypot's overflow care (the moduli here are far from overflow)."""
    return math.sqrt(z.real * z.real + z.imag * z.imag)


@kernel(inline=True)
def value(p, r, c, o, nk, t):  # type: ignore[no-untyped-def]
    """Output ``o`` at ``t``."""
    s = c[o, 0] * t + c[o, 1]
    for k in range(nk):
        s += (r[o, k] * cmath.exp(p[k] * t)).real
    return s


@kernel(inline=True)
def pair(p, r, c, o, nk, t, d):  # type: ignore[no-untyped-def]
    """Derivatives ``d`` and ``d + 1`` (d = 0 or 1) of output ``o`` at ``t``."""
    y = 0.0
    dy = 0.0
    for k in range(nk):
        e = r[o, k] * cmath.exp(p[k] * t)
        if d == 1:
            e = e * p[k]
        y += e.real
        dy += (e * p[k]).real
    if d == 0:
        y += c[o, 0] * t + c[o, 1]
        dy += c[o, 0]
    else:
        y += c[o, 0]
    return y, dy


@kernel(inline=True)
def triple(p, r, c, o, nk, t):  # type: ignore[no-untyped-def]
    """Output ``o``, its first two derivatives and its curvature and jerk scales at ``t``.

    The scales ``sum_k |r_k| |p_k|^j exp(Re p_k t)`` (j = 2, 3) bound the second
    and third derivatives at ``t``, and over a cell starting at ``t`` when no pole
    is unstable.
    """
    y = c[o, 0] * t + c[o, 1]
    dy = c[o, 0]
    ddy = 0.0
    m2 = 0.0
    m3 = 0.0
    for k in range(nk):
        e = r[o, k] * cmath.exp(p[k] * t)
        a = mag(p[k])
        g = mag(e) * a * a
        m2 += g
        m3 += g * a
        y += e.real
        e = e * p[k]
        dy += e.real
        ddy += (e * p[k]).real
    return y, dy, ddy, m2, m3


@kernel(inline=True)
def noise(p, r, c, o, nk, t):  # type: ignore[no-untyped-def]
    """Rounding-noise level of ``y(t)``: NOISE times the sum of its terms' magnitudes."""
    s = abs(c[o, 0] * t) + abs(c[o, 1])
    for k in range(nk):
        s += mag(r[o, k]) * math.exp(p[k].real * t)
    return NOISE * s


@kernel(inline=True)
def curvature(p, r, o, nk, tl, tr):  # type: ignore[no-untyped-def]
    """Upper bound of ``|y''|`` over ``[tl, tr]`` (the polynomial part is at most linear)."""
    s = 0.0
    for k in range(nk):
        a = mag(p[k])
        s += mag(r[o, k]) * a * a * math.exp(max(p[k].real * tl, p[k].real * tr))
    return s


@kernel(inline=True)
def jerk(p, r, o, nk, tl, tr):  # type: ignore[no-untyped-def]
    """Upper bound of ``|y'''|`` over ``[tl, tr]``."""
    s = 0.0
    for k in range(nk):
        a = mag(p[k])
        s += mag(r[o, k]) * a * a * a * math.exp(max(p[k].real * tl, p[k].real * tr))
    return s


@kernel(inline=True)
def shape(ddl, ddr, m3, w):  # type: ignore[no-untyped-def]
    """-1 where y'' < 0 on the whole cell, +1 where y'' > 0, else 0 (``|y'''| <= m3``)."""
    if ddl + ddr + m3 * w < 0:
        return -1
    if ddl + ddr - m3 * w > 0:
        return 1
    return 0


@kernel(inline=True)
def real_product(a, b):  # type: ignore[no-untyped-def]
    """``Re(a b)`` without the imaginary part."""
    return a.real * b.real - a.imag * b.imag


@kernel(inline=True)
def derivatives(p, r, c, o, nk, t):  # type: ignore[no-untyped-def]
    """Output ``o`` and its first three derivatives at ``t`` (one exponential per pole)."""
    y = c[o, 0] * t + c[o, 1]
    d1 = c[o, 0]
    d2 = 0.0
    d3 = 0.0
    for k in range(nk):
        pk = p[k]
        p2 = pk * pk  # off the exponential's critical path: the three products in parallel
        e = r[o, k] * cmath.exp(pk * t)
        y += e.real
        d1 += real_product(e, pk)
        d2 += real_product(e, p2)
        d3 += real_product(e, p2 * pk)
    return y, d1, d2, d3


@kernel(inline=True)
def newton(p, r, c, o, nk, lo, hi, order, sign, iterations, rtol, guess):  # type: ignore[no-untyped-def]
    """Root ``t`` of ``sign * y^(order)`` in ``[lo, hi]`` (``+`` at lo, ``-`` at hi) and ``y(t)``.

    The safeguarded iteration of :func:`designlab.impact.modal._safeguarded_newton`
    with Halley's step (the derivatives come with the same exponentials): steps
    that leave the bracket become bisections. It stops when a step is below
    ``rtol |t|``, or earlier when two successive Halley steps show cubic
    convergence and predict the next step below 1e-14 |t|. ``y(t)``
    is the third-order Taylor value from the last evaluation (its error is of
    the fourth order in the last step).
    """
    t = min(max(guess, lo), hi)
    width = hi - lo
    prev = np.inf
    for _ in range(iterations):
        y, d1, d2, d3 = derivatives(p, r, c, o, nk, t)
        if order == 0:
            f, g, q = sign * y, sign * d1, sign * d2
        else:
            f, g, q = sign * d1, sign * d2, sign * d3
        if f > 0:
            lo = t
        else:
            hi = t
        s = -2.0 * f * g / (2.0 * g * g - f * q)
        if not np.isfinite(s) or s * g * f > 0:
            s = -f / g
        tol = rtol * abs(t) + 1e-300
        a = abs(s)
        done = a <= tol or hi - lo <= tol or f == 0
        if not done and prev < np.inf and a <= 1e-3 * width and a <= 1e-2 * prev:
            done = a * (a / prev) ** 3 <= 1e-14 * abs(t)  # the next step, at cubic convergence
        if not np.isfinite(s):
            s = 0.0
        tn = t + s
        if done:
            return tn, y + s * (d1 + s * (0.5 * d2 + s * d3 / 6.0))
        if tn <= lo or tn >= hi:
            tn = 0.5 * (lo + hi)
            prev = np.inf
        else:
            prev = a
        t = tn
    return t, value(p, r, c, o, nk, t)


@kernel(inline=True)
def cell_bound(yl, yr, dl, dr, w, m):  # type: ignore[no-untyped-def]
    """Upper bound of y over a cell (:func:`designlab.impact.modal._cell_bound`)."""
    ends = max(min(yl, yr - dr * w + 0.5 * m * w * w), min(yl + dl * w + 0.5 * m * w * w, yr))
    slope = dl - dr + m * w
    x = -(yl - yr + dr * w - 0.5 * m * w * w) / slope
    taylor = ends
    if np.isfinite(x) and 0.0 < x < w:
        u = w - x
        cross = min(yl + dl * x + 0.5 * m * x * x, yr - dr * u + 0.5 * m * u * u)
        taylor = max(ends, cross)
    return min(taylor, max(yl, yr) + m * w * w / 8.0)


@kernel(inline=True)
def exponentials(p, nk, hi, count, ex):  # type: ignore[no-untyped-def]
    """``exp(p_k t_j)`` at the nodes ``t_j = hi j / count`` (j = 0..count) into ``ex[j, k]``.

    By recurrence from ``exp(p_k hi / count)``; the last node is evaluated directly.
    Shared by every output of a design (they have the same poles).
    """
    w = hi / count
    for k in range(nk):
        z = cmath.exp(p[k] * w)
        e = 1.0 + 0j
        for j in range(count):
            ex[j, k] = e
            e = e * z
        ex[count, k] = cmath.exp(p[k] * hi)


@kernel(inline=True)
def grid(p, r, c, o, nk, hi, count, ex, work):  # type: ignore[no-untyped-def]
    """Nodes ``hi j / count`` (j = 0..count) of output ``o`` into ``work``.

    Times, values, first and second derivatives and the scales of :func:`triple`
    from the exponentials ``ex`` (:func:`exponentials`); the last node is ``hi``.
    """
    ts, ys, ds, qs, m2s, m3s = work[0], work[1], work[2], work[3], work[4], work[5]
    for j in range(count + 1):
        ts[j] = hi * (j / count)
        ys[j] = c[o, 0] * ts[j] + c[o, 1]
        ds[j] = c[o, 0]
        qs[j] = 0.0
        m2s[j] = 0.0
        m3s[j] = 0.0
    for k in range(nk):
        pk = p[k]
        rk = r[o, k]
        rp, rp2 = rk * pk, rk * pk * pk
        a = mag(pk)
        g = mag(rk) * a * a
        for j in range(count + 1):
            x = ex[j, k]
            ys[j] += real_product(rk, x)
            ds[j] += real_product(rp, x)
            qs[j] += real_product(rp2, x)
            gj = g * mag(x)
            m2s[j] += gj
            m3s[j] += gj * a


@kernel(inline=True)
def stable(p, nk):  # type: ignore[no-untyped-def]
    """Whether no pole has a positive real part (the scales then peak at a cell's left end)."""
    for k in range(nk):
        if p[k].real > 0:
            return False
    return True
