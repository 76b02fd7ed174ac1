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

import math

import numpy as np

from designlab.impact.kernel_exp import cexp
from designlab.sx.jit import kernel

__all__ = [
    "ERR_COLUMNS", "MAX_TERMS", "NOISE", "ROUNDING", "UNDERFLOW", "cell_bound", "crossing_error",
    "curvature",
    "derivatives", "exponentials", "fastest_rate", "grid",
    "hermite_bound", "jerk", "mag", "newton", "noise", "pair", "real_product", "residue_errors",
    "separated", "shape", "stable", "term_errors", "triple", "value",
]  # fmt: skip

#: a value y(t) is provably negative when y < -NOISE * (sum of the magnitudes of its terms)
#: minus the error bounds of its residues and poles carried to t (:func:`noise`)
NOISE = 1e-12
#: relative rounding of the model's coefficients and of a Horner evaluation at a pole
#: (16 units of 1.1e-16: each coefficient is a sum of products of a few parameters, and
#: Horner's rule over degree 5 adds at most 10)
ROUNDING = 16 * 2.0**-53
#: most folded poles whose error bounds a polynomial part ``c`` (3, ERR_COLUMNS) carries
MAX_TERMS = 5
#: columns of ``c``: ``c0 t + c1``, the residues' error bounds, the poles' (times |r_k|)
ERR_COLUMNS = 2 + 2 * MAX_TERMS
#: Newton stops without a further exponential when the Halley step ``s`` has
#: ``|s| max|p_k|`` <= TAYLOR_STEP and the root of the local Taylor polynomial near it
#: (:func:`_taylor_root`) is provably within TAYLOR_ERROR / max|p_k| of the true root
#: (a stationary value is then exact to ~TAYLOR_ERROR^2 of its terms) or, for a zero,
#: within 1e-2 of the tolerance
TAYLOR_STEP = 5e-3
TAYLOR_ERROR = 1e-8
#: absolute error of one term ``Re r_k exp(p_k t)`` evaluated where its parts are subnormal
#: numbers (below 2.2e-308): each of its few roundings (exponential, cosine, product, sum)
#: loses up to half the smallest subnormal, 2^-1075, whatever the term's size
UNDERFLOW = 16 * 2.0**-1074
#: ``|z|^2`` at or above this: the squares' underflow is below 1e-20 of it (:func:`mag`)
_SQUARES_NORMAL = 1e-290
#: reciprocals of the Taylor coefficients' factorials (multiplications instead of divisions)
_I6 = 1.0 / 6.0
_I24 = 1.0 / 24.0
_I120 = 1.0 / 120.0
_I384 = 1.0 / 384.0


@kernel(inline=True)
def mag(z):  # type: ignore[no-untyped-def]
    """``|z|``: without hypot's care where the squares are normal numbers (the moduli here
    are far from overflow); by hypot where they underflow (``|z|`` below 1e-150: the
    exponentials of a slow tail, whose moduli enter the noise and derivative bounds; their
    squares flushed to zero made those bounds zero, issue 34)."""
    s = z.real * z.real + z.imag * z.imag
    if s >= _SQUARES_NORMAL:
        return math.sqrt(s)
    return math.hypot(z.real, z.imag)


@kernel(inline=True)
def value(p, r, c, o, nk, t):  # type: ignore[no-untyped-def]
    """Output ``o`` at ``t``."""
    s = c[o, 0] * t + c[o, 1]
    for k in range(nk):
        s += (r[o, k] * cexp(p[k] * t)).real
    return s


@kernel(inline=True)
def pair(p, r, c, o, nk, t, d):  # type: ignore[no-untyped-def]
    """Derivatives ``d`` and ``d + 1`` (d = 0 or 1) of output ``o`` at ``t``."""
    y = 0.0
    dy = 0.0
    for k in range(nk):
        e = r[o, k] * cexp(p[k] * t)
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
        e = r[o, k] * cexp(p[k] * t)
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
    """Rounding-noise level of ``y(t)``: NOISE times the sum of its terms' magnitudes plus
    the error bounds of the residues and poles (:func:`residue_errors`) carried to ``t``.

    A residue's rounding error is absolute: a pole next to a zero of the numerator
    (nearly repeated modes under a soft foam) has a residue smaller than that error, and
    its term, the slowest, decides the sign of a tail that in truth decays to zero from
    above (issue 34). Where ``c`` carries no bounds (``c.shape[1] == 2``: responses
    built elsewhere) every residue is counted at least as large as the largest one.
    Each term adds :data:`UNDERFLOW` (the absolute error of a term in subnormal numbers).
    """
    s = abs(c[o, 0] * t) + abs(c[o, 1])
    if c.shape[1] >= ERR_COLUMNS:
        extra = 0.0
        for k in range(nk):
            e = math.exp(p[k].real * t)
            s += mag(r[o, k]) * e
            extra += (c[o, 2 + k] + c[o, 2 + MAX_TERMS + k] * t) * e
        return NOISE * s + extra + nk * UNDERFLOW
    big = 0.0
    for k in range(nk):
        big = max(big, mag(r[o, k]))
    for k in range(nk):
        s += big * math.exp(p[k].real * t)
    return NOISE * s + nk * UNDERFLOW


@kernel(inline=True)
def crossing_error(p, r, c, o, nk, t, ex):  # type: ignore[no-untyped-def]
    """How far the rounding noise (:func:`noise`) can move a zero of ``y`` at ``t``: the
    noise level over ``|y'(t)|`` (inf where the slope is zero); ``ex[k]`` is
    ``exp(p_k t)`` (the grid's last node, :func:`exponentials`)."""
    bounds = c.shape[1] >= ERR_COLUMNS
    dy = c[o, 0]
    s = abs(c[o, 0] * t) + abs(c[o, 1])
    terms = extra = big = 0.0
    for k in range(nk):
        e = ex[k]
        g = mag(e)
        a = mag(r[o, k])
        dy += real_product(r[o, k] * p[k], e)
        terms += a * g
        big = max(big, a)
        extra += g * (c[o, 2 + k] + c[o, 2 + MAX_TERMS + k] * t if bounds else 1.0)
    if bounds:
        return (NOISE * (s + terms) + extra + nk * UNDERFLOW) / abs(dy)
    return (NOISE * (s + big * extra) + nk * UNDERFLOW) / abs(dy)


@kernel(inline=True)
def term_errors(c, o, nk, t):  # type: ignore[no-untyped-def]
    """Bound of the residues' and poles' error in ``y`` anywhere on ``[0, t]`` (stable poles;
    0 where ``c`` carries no bounds): ``sum_k c[o, 2 + k] + c[o, 2 + MAX_TERMS + k] t``."""
    if c.shape[1] < ERR_COLUMNS:
        return 0.0
    s = 0.0
    for k in range(nk):
        s += c[o, 2 + k] + c[o, 2 + MAX_TERMS + k] * t
    return s


@kernel(inline=True)
def _root_error(den, n, roots, j):  # type: ignore[no-untyped-def]
    """First-order bound of the distance of ``roots[j]`` to a root of the exact ``D``.

    Its residual ``|D(x)|`` plus ``ROUNDING`` times ``sum_k |d_k| |x|^k`` (the
    coefficients' own rounding and Horner's), over ``|D'(x)| = prod_k |x - x_k|``.
    """
    x = roots[j]
    ax = mag(x)
    f = complex(den[0], 0.0)
    size = abs(den[0])
    for k in range(1, n + 1):
        f = f * x + den[k]
        size = size * ax + abs(den[k])
    dp = 1.0 + 0j
    for k in range(n):
        if k != j:
            dp = dp * (x - roots[k])
    return (mag(f) + ROUNDING * size) / mag(dp)


@kernel(inline=True)
def _pick(j, d0, d1, d2, d3, d4):  # type: ignore[no-untyped-def]
    """The ``j``-th of five values."""
    if j == 0:
        return d0
    if j == 1:
        return d1
    if j == 2:
        return d2
    return d3 if j == 3 else d4


@kernel(borrows=True)
def residue_errors(den, n, num, roots, r, c, outputs):  # type: ignore[no-untyped-def]
    """Bounds of the folded residues' errors into ``c[o, 2 + k]`` and of their poles' errors
    (times ``|r_k|``) into ``c[o, 2 + MAX_TERMS + k]``; False where the poles are too close
    for a first-order bound (the caller does not certify the design).

    ``r[o, k] = w N_o(p_k) / (p_k^2 prod_(j != k) (p_k - p_j))`` (:mod:`.kernel_poles`) with
    the ``n`` roots ``roots`` of the monic ``den`` and ``num[o]`` of degree ``n + 1``. With
    ``delta_j`` the roots' error bounds (:func:`_root_error`) and ``sep_k = sum_(j != k)
    (delta_k + delta_j) / |p_k - p_j|`` (at most 0.1: the poles' separation), the error of
    ``r[o, k]`` is at most twice ``w (ROUNDING S(|p_k|) + |N_o'(p_k)| delta_k) / |p_k^2
    D'(p_k)| + |r[o, k]| (sep_k + 2 delta_k / |p_k| + ROUNDING)``, ``S`` the sum of the
    numerator's terms' magnitudes; a residue next to a zero of its numerator (nearly repeated modes
    under a soft foam, issue 34) is then known to be no better than this absolute error.
    """
    d0 = _root_error(den, n, roots, 0)  # at most 5 roots: registers, not an array
    d1 = _root_error(den, n, roots, 1) if n > 1 else 0.0
    d2 = _root_error(den, n, roots, 2) if n > 2 else 0.0
    d3 = _root_error(den, n, roots, 3) if n > 3 else 0.0
    d4 = _root_error(den, n, roots, 4) if n > 4 else 0.0
    nk = 0
    for i in range(n):
        x = roots[i]
        if x.imag < 0:
            continue
        w = 2.0 if x.imag > 0 else 1.0
        ax = mag(x)
        di = _pick(i, d0, d1, d2, d3, d4)
        sep = 0.0
        dp = x * x
        for j in range(n):
            if j != i:
                dp = dp * (x - roots[j])
                sep += (di + _pick(j, d0, d1, d2, d3, d4)) / mag(x - roots[j])
        if not sep <= 0.1:
            return False
        scale = w / mag(dp)
        for o in range(3):
            c[o, 2 + nk] = c[o, 2 + MAX_TERMS + nk] = 0.0
            if outputs[o]:
                sn = abs(num[o, 0])
                f = complex(num[o, 0], 0.0)
                df = 0j
                for k in range(1, n + 2):
                    df = df * x + f
                    f = f * x + num[o, k]
                    sn = sn * ax + abs(num[o, k])
                a = mag(r[o, nk])
                slope = mag(df) + ROUNDING * sn / ax  # |N'(x)| and its own rounding
                err = scale * (ROUNDING * sn + slope * di) + a * (sep + 2.0 * di / ax)
                c[o, 2 + nk] = 2.0 * (err + a * ROUNDING)
                c[o, 2 + MAX_TERMS + nk] = 2.0 * a * di
        nk += 1
    return True


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
    """Output ``o``, its first five derivatives and the sum of its terms' magnitudes at ``t``
    (one exponential per pole)."""
    y = c[o, 0] * t + c[o, 1]
    d1 = c[o, 0]
    d2 = 0.0
    d3 = 0.0
    d4 = 0.0
    d5 = 0.0
    m = 0.0
    for k in range(nk):
        pk = p[k]
        p2 = pk * pk  # off the exponential's critical path: the products in parallel
        e = r[o, k] * cexp(pk * t)
        y += e.real
        d1 += real_product(e, pk)
        d2 += real_product(e, p2)
        d3 += real_product(e, p2 * pk)
        d4 += real_product(e, p2 * p2)
        d5 += real_product(e, p2 * p2 * pk)
        m += mag(e)
    return y, d1, d2, d3, d4, d5, m


@kernel(inline=True)
def _taylor_root(f, g, q, u, v, s, scale, z):  # type: ignore[no-untyped-def]
    """Root near the Halley step ``s`` of ``T(x) = f + g x + q x^2/2 + u x^3/6 + v x^4/24``
    and a bound of its distance to the true root.

    ``s`` is first corrected by Halley's error term ``C s^3`` (``C = (q/2g)^2 - u/6g``),
    then one Newton step on ``T``. The bound adds the step's quadratic error and
    the remainder of ``T`` over ``|x| <= 1.25 |s|`` (``scale (1.25 z)^5 / 120`` with
    ``scale = sum |terms| max|p_k|^order`` and ``z = |s| max|p_k|``) over the slope.
    """
    ig = 1.0 / g
    x = s + ((0.5 * q * ig) ** 2 - u * ig * _I6) * s * s * s
    fx = f + x * (g + x * (0.5 * q + x * (u * _I6 + x * v * _I24)))
    igx = 1.0 / (g + x * (q + x * (0.5 * u + x * v * _I6)))
    d = fx * igx
    w = 1.25 * z
    err = (abs(d) * abs(d) * abs(q) + scale * w * w * w * w * w * _I120) * abs(igx)
    if not abs(x - d) <= 1.25 * abs(s):  # outside the remainder's interval (also NaN)
        err = np.inf
    return x - d, err


@kernel(inline=True)
def fastest_rate(p, nk):  # type: ignore[no-untyped-def]
    """``max_k |p_k|``."""
    fastest = 0.0
    for k in range(nk):
        fastest = max(fastest, mag(p[k]))
    return fastest


@kernel(inline=True)
def newton(p, r, c, o, nk, lo, hi, order, sign, iterations, rtol, guess):  # type: ignore[no-untyped-def]
    """Root ``t`` of ``sign * y^(order)`` in ``[lo, hi]`` (``+`` at lo, ``-`` at hi) and ``y(t)``.

    The safeguarded iteration of :func:`designlab.impact.modal._safeguarded_newton`
    with Halley's step (the derivatives come with the same exponentials): steps
    that leave the bracket become bisections. It stops when a step is below
    ``rtol |t|``, or earlier when two successive Halley steps show cubic
    convergence and predict the next step below 1e-14 |t|, or at once when the
    step is short (:data:`TAYLOR_STEP`) and the root of the Taylor polynomial at
    ``t`` is provably close enough (:func:`_taylor_root`, :data:`TAYLOR_ERROR`):
    one evaluation from a good start (the cubic Hermite root of the grid cell)
    is then enough. ``y(t)`` is the fifth-order Taylor value from the last
    evaluation (its error is of the sixth order in the last step).
    """
    t = min(max(guess, lo), hi)
    width = hi - lo
    prev = np.inf
    fastest = fastest_rate(p, nk)
    for _ in range(iterations):
        y, d1, d2, d3, d4, d5, m = derivatives(p, r, c, o, nk, t)
        if order == 0:
            f, g, q, u, v = sign * y, sign * d1, sign * d2, sign * d3, sign * d4
        else:
            f, g, q, u, v = sign * d1, sign * d2, sign * d3, sign * d4, sign * d5
        if f > 0:
            lo = t
        else:
            hi = t
        # Halley's step -2 f g / (2 g^2 - f q) over g^2: no product of two values of y's
        # size, whose squares underflow in a slow tail (|y| < 1e-154; issue 34: a zero at
        # 32.3 s solved 7.7e-8 late from subnormal products)
        ratio = f / g
        s = -2.0 * ratio / (2.0 - ratio * (q / g))
        if not np.isfinite(s) or s * ratio > 0:
            s = -ratio
        tol = rtol * abs(t) + 1e-300
        a = abs(s)
        done = a <= tol or hi - lo <= tol or f == 0
        if not done and a * fastest <= TAYLOR_STEP:
            x, err = _taylor_root(f, g, q, u, v, s, m * fastest**order, a * fastest)
            if err <= (1e-2 * tol if order == 0 else TAYLOR_ERROR / fastest) and lo < t + x < hi:
                s, done = x, True
        if not done and prev < np.inf and a <= 1e-3 * width and a <= 1e-2 * prev:
            done = a * (a / prev) ** 3 <= 1e-14 * abs(t)  # the next step, at cubic convergence
        if not np.isfinite(s):
            s = 0.0
        tn = t + s
        if done:
            taylor = d3 * _I6 + s * (d4 * _I24 + s * d5 * _I120)
            return tn, y + s * (d1 + s * (0.5 * d2 + s * taylor))
        if tn <= lo or tn >= hi:
            tn = 0.5 * (lo + hi)
            prev = np.inf
        else:
            prev = a
        t = tn
    return t, value(p, r, c, o, nk, t)


@kernel(inline=True)
def cell_bound(yl, yr, dl, dr, w, m, m4):  # type: ignore[no-untyped-def]
    """Upper bound of y over a cell: the lower of :func:`designlab.impact.modal._cell_bound`
    (``|y''| <= m``) and :func:`hermite_bound` (``|y''''| <= m4``)."""
    return min(_quadratic_bound(yl, yr, dl, dr, w, m), hermite_bound(yl, yr, dl, dr, w, m4))


@kernel(inline=True)
def hermite_bound(yl, yr, dl, dr, w, m4):  # type: ignore[no-untyped-def]
    """Upper bound of y over a cell of width ``w``: the maximum of the cubic Hermite
    interpolant of the end values and slopes plus its error bound ``m4 w^4 / 384``."""
    iw = 1.0 / w
    m = (yr - yl) * iw
    a2 = (3.0 * m - 2.0 * dl - dr) * iw
    a3 = (dl + dr - 2.0 * m) * (iw * iw)
    best = max(yl, yr)
    disc = a2 * a2 - 3.0 * a3 * dl  # stationary points: dl + 2 a2 x + 3 a3 x^2 = 0
    if disc >= 0.0 and a3 != 0.0:
        q = -(a2 + math.copysign(math.sqrt(disc), a2))
        for x in (q / (3.0 * a3), dl / q if q != 0.0 else -1.0):
            if 0.0 < x < w:
                best = max(best, yl + x * (dl + x * (a2 + x * a3)))
    elif a3 == 0.0 and a2 != 0.0:
        x = -dl / (2.0 * a2)
        if 0.0 < x < w:
            best = max(best, yl + x * (dl + x * a2))
    return best + m4 * w * w * w * w * _I384


@kernel(inline=True)
def _quadratic_bound(yl, yr, dl, dr, w, m):  # type: ignore[no-untyped-def]
    """Upper bound of y over a cell from ``|y''| <= m``."""
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
        z = cexp(p[k] * w)
        e = 1.0 + 0j
        for j in range(count):
            ex[j, k] = e
            e = e * z
        ex[count, k] = cexp(p[k] * hi)


@kernel(inline=True)
def grid(p, r, c, o, nk, hi, count, w, ex, work, first=0):  # type: ignore[no-untyped-def]
    """Nodes ``j w`` (j < count) and ``hi`` of output ``o`` into ``work``.

    Times, values, first and second derivatives and the scales of :func:`triple`
    from the exponentials ``ex`` (:func:`exponentials`); the last node is ``hi``.
    ``first`` is 0, or ``count`` where ``work`` already holds the nodes before it (a
    grid of the same output, step and exponentials up to there): the last node only.
    """
    ts, ys, ds, qs, m2s, m3s = work[0], work[1], work[2], work[3], work[4], work[5]
    for j in range(first, count + 1):
        ts[j] = j * w if j < count else hi
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
        rho = mag(ex[1, k]) if count > 1 else 0.0  # |exp(p_k w)|: the nodes' moduli by recurrence
        for j in range(first, count + 1):
            x = ex[j, k]
            ys[j] += real_product(rk, x)
            ds[j] += real_product(rp, x)
            qs[j] += real_product(rp2, x)
            if j == count:  # evaluated directly
                g = mag(rk) * a * a * mag(x)
            m2s[j] += g
            m3s[j] += g * a
            g *= rho


@kernel(inline=True)
def stable(p, nk):  # type: ignore[no-untyped-def]
    """Whether no pole has a positive real part (the scales then peak at a cell's left end)."""
    for k in range(nk):
        if p[k].real > 0:
            return False
    return True


@kernel(inline=True)
def separated(p, r, c, o, nk, tl, tr):  # type: ignore[no-untyped-def]
    """Output ``o`` over ``[tl, tr]`` split into its slow part and a bound of the rest.

    A stable pole with ``|p_k| (tr - tl) > 1`` decays within the cell: its term is
    bounded by ``F = sum |r_k| exp(Re p_k tl)`` instead of by its derivatives (which a
    stiff pole makes astronomically large). Returns the slow part's values and slopes
    at both ends, bounds of its second and fourth derivatives over the cell, and ``F``:
    ``y = y_slow + y_fast`` with ``|y_fast| <= F``.
    """
    w = tr - tl
    yl = c[o, 0] * tl + c[o, 1]
    yr = c[o, 0] * tr + c[o, 1]
    dl = dr = c[o, 0]
    m2 = m3 = fast = top = 0.0
    for k in range(nk):
        a = mag(p[k])
        if p[k].real < 0 and a * w > 1.0:
            fast += mag(r[o, k]) * math.exp(p[k].real * tl)
            continue
        el = r[o, k] * cexp(p[k] * tl)
        er = r[o, k] * cexp(p[k] * tr)
        yl += el.real
        yr += er.real
        dl += real_product(el, p[k])
        dr += real_product(er, p[k])
        g = mag(r[o, k]) * a * a * math.exp(max(p[k].real * tl, p[k].real * tr))
        m2 += g
        m3 += g * a
        top = max(top, a)
    return yl, yr, dl, dr, m2, top * m3, fast
