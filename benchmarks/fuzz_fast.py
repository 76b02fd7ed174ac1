"""A fast independent evaluator of the impact metrics, written for the fuzz harness only.

It shares no code with ``designlab.impact`` (``kernel*.py``, ``modal.py``) and uses other
algorithms, so that a defect of one is seen as a disagreement with the other
(``benchmarks/fuzz_kernel.py``, issue 34):

* **Poles.** The roots of the characteristic polynomial, reduced model
  ``D = P_r P_h + z_c (P_r + P_h)`` (``P_r = M_r s^2 + C_r s + K_r``, likewise ``P_h``;
  ``z_c = C_c s + K_c``; constrained: ``D = P_r + z_c``), full joint ``D = Q_r P_h +
  z_c (P_h z_e + Q_r)`` (``Q_r = M_r s^2 z_e + z_m z_q``; constrained ``Q_r + z_c
  z_e``), by the Aberth-Ehrlich simultaneous iteration (from the bodies' own modes,
  or a circle), the full joint's polished by Newton on D's factors; never folded
  into conjugate pairs: every term of the response is summed and the real part taken.
* **Residues** by solving the linear system ``V c = x(0) - x_p(0)`` for the
  initial state (``V`` the eigenvectors, the particular solution ``x_p = alpha +
  beta t`` of the unit ramp), not by partial fractions. a_h is the second
  derivative of the head's displacement, whose particular part is affine, so a_h
  has no polynomial part at all.
* **Lobe end and maxima** by dense sampling: a uniform grid of 63 points per period of
  the fastest pole still significant at that time (a pole whose term has decayed
  below 1e-17 of the output's scale no longer sets the step), exponentials by
  recurrence, the first sample where a_h is below minus its rounding level, then
  the first sign change before it refined by safeguarded Newton on the closed
  form (a_h's sign taken on ``exp(-sigma t) a_h(t)``, ``sigma`` the slowest pole's real
  part: a lobe end deep in a slow tail is not sought among subnormal numbers); every
  sampled local maximum among the best three refined by safeguarded Newton on y'
  (golden section where y' does not change sign in its bracket).

Dense sampling can miss a needle (a dip of a_h narrower than the grid): that is
counted as "evaluator wrong" by the harness's mpmath referee. Status codes:
0 ok, 2 peak at contact, 3 lobe not closed within the kernel's documented horizon
``((max_steps // 12) 12 + 11) 0.4 / rate``, -1 the evaluator gave up (singular
eigenvectors, too many samples): always a disagreement, settled by mpmath.
"""

from __future__ import annotations

import cmath
import math

import numba
import numpy as np

_jit = numba.njit(cache=True, nogil=True)

#: samples per radian of the fastest significant pole (63 per period)
DENSITY = 10.0
#: a pole's term is insignificant once below this fraction of its output's scale
NEGLIGIBLE = 1e-17
#: the most samples per design before the evaluator gives up (status -1)
MAX_SAMPLES = 400_000
#: candidates (sampled local maxima) refined per output
CANDIDATES = 3
#: a_h provably negative: below minus this times its largest residue times sum e^(Re p t)
NOISE = 1e-12
GAVE_UP = -1
#: P_r(p) of a pole is taken from the identity of :func:`_head_residues` where evaluated
#: directly it is below this fraction of its terms (the bodies' common mode)
CANCELLED = 1e-6


@_jit
def _polymul(a, b):  # type: ignore[no-untyped-def]
    out = np.zeros(a.size + b.size - 1)
    for i in range(a.size):
        for j in range(b.size):
            out[i + j] += a[i] * b[j]
    return out


@_jit
def _horner(a, z):  # type: ignore[no-untyped-def]
    """Value and derivative of the polynomial ``a`` (descending) at ``z``."""
    p = a[0] + 0j
    dp = 0j
    for i in range(1, a.size):
        dp = dp * z + p
        p = p * z + a[i]
    return p, dp


@_jit
def aberth(a, z, start):  # type: ignore[no-untyped-def]
    """Roots of the real polynomial ``a`` (descending, a[0] != 0) into ``z`` (from ``z``'s
    values if ``start``, else from a circle); False if the iteration did not converge."""
    n = a.size - 1
    lead = a[0]
    r = abs(a[n] / lead) ** (1.0 / n)
    for k in range(n):
        ang = 2.0 * math.pi * k / n + 0.4
        if not start:
            z[k] = r * complex(math.cos(ang), math.sin(ang))
        else:  # a start off the real axis, apart from the others
            z[k] += 1e-3 * r * complex(math.cos(ang), math.sin(ang))
    last = np.full(n, np.inf)
    for _ in range(400):
        done = True
        for k in range(n):
            p, dp = _horner(a, z[k])
            if p == 0:
                last[k] = 0.0
                continue
            w = p / dp
            s = 0j
            for j in range(n):
                if j != k:
                    s += 1.0 / (z[k] - z[j])
            d = w / (1.0 - w * s)
            z[k] -= d
            size = abs(d)
            # converged: at rounding, or no longer shrinking once small (a cluster's noise)
            if size > 4e-16 * abs(z[k]) and not (size < 1e-9 * abs(z[k]) and size > 0.5 * last[k]):
                done = False
            last[k] = size
        if done:
            return True
    # a cluster (nearly repeated root) converges only linearly: accept if the
    # last corrections are at the cluster's resolution, sqrt(eps)
    for k in range(n):
        p, dp = _horner(a, z[k])
        if not abs(p / dp) <= 1e-7 * abs(z[k]):
            return False
    return True


@_jit
def _quadratic(a, b, c, z, at):  # type: ignore[no-untyped-def]
    """Both roots of ``a s^2 + b s + c`` into ``z[at], z[at + 1]`` (a start only)."""
    d = cmath.sqrt(b * b - 4.0 * a * c + 0j)
    q = -0.5 * (b + d)
    z[at] = q / a
    z[at + 1] = c / q if q != 0 else -b / a


@_jit
def _solve(m, b):  # type: ignore[no-untyped-def]
    """Gaussian elimination with partial pivoting of the complex system ``m x = b``
    (both overwritten); returns x (NaN if singular)."""
    n = b.size
    for col in range(n):
        piv = col
        for i in range(col + 1, n):
            if abs(m[i, col]) > abs(m[piv, col]):
                piv = i
        if m[piv, col] == 0:
            b[:] = np.nan
            return b
        if piv != col:
            for j in range(n):
                m[col, j], m[piv, j] = m[piv, j], m[col, j]
            b[col], b[piv] = b[piv], b[col]
        for i in range(col + 1, n):
            f = m[i, col] / m[col, col]
            for j in range(col, n):
                m[i, j] -= f * m[col, j]
            b[i] -= f * b[col]
    x = b
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= m[i, j] * x[j]
        x[i] = s / m[i, i]
    return x


@_jit
def _reduced_modes(q, lam, g, c):  # type: ignore[no-untyped-def]
    """Poles ``lam`` (4), residues ``g`` (3, 4: force, a_h, eps) and polynomial parts ``c``
    (3, 2: slope, constant) of a reduced unconstrained design; False on failure."""
    m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h = q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7]
    pr = np.array([m_r, c_r, k_r])
    ph = np.array([m_h, c_h, k_h])
    zc = np.array([0.0, c_c, k_c])
    den = _polymul(pr, ph) + _polymul(zc, pr + ph)
    # start from the two bodies' own modes on the foam (roots of P_r + z_c, P_h + z_c)
    _quadratic(m_r, c_r + c_c, k_r + k_c, lam, 0)
    _quadratic(m_h, c_h + c_c, k_h + k_c, lam, 2)
    if not aberth(den, lam, True):
        return False
    # the unit ramp's particular solution d = a + b t of both bodies
    det = k_r * k_h + k_c * (k_r + k_h)
    b_r, b_h = -k_c * k_h / det, k_c * k_r / det
    r1 = -c_c - (c_r + c_c) * b_r + c_c * b_h
    r2 = c_c - (c_h + c_c) * b_h + c_c * b_r
    a_r = ((k_h + k_c) * r1 + k_c * r2) / det
    a_h = (k_c * r1 + (k_r + k_c) * r2) / det
    v = np.empty((4, 4), dtype=np.complex128)
    for k in range(4):
        s = lam[k]
        dr = c_c * s + k_c
        dh = (m_r * s + c_r) * s + k_r + dr
        sc = 1.0 / max(abs(dr), abs(dh), abs(s * dr), abs(s * dh))
        v[0, k], v[1, k], v[2, k], v[3, k] = dr * sc, s * dr * sc, dh * sc, s * dh * sc
    v0 = v.copy()
    x0 = np.array([-a_r + 0j, -b_r, -a_h, -b_h])
    coef = _solve(v, x0)
    for k in range(4):
        e = coef[k] * (v0[0, k] - v0[2, k])
        g[2, k] = e
        g[0, k] = (k_c + c_c * lam[k]) * e
        g[1, k] = coef[k] * v0[2, k] * lam[k] * lam[k]
    _head_residues(q, lam, g)
    slope = b_r - b_h + 1.0
    c[2, 0], c[2, 1] = slope, a_r - a_h
    c[0, 0], c[0, 1] = k_c * slope, k_c * (a_r - a_h) + c_c * slope
    c[1, 0] = c[1, 1] = 0.0
    return np.all(np.isfinite(coef))


@_jit
def _two_product(a, b):  # type: ignore[no-untyped-def]
    """``a b = hi + lo`` exactly (Dekker's splitting; no fused multiply-add needed)."""
    hi = a * b
    t = 134217729.0 * a
    ah = t - (t - a)
    al = a - ah
    t = 134217729.0 * b
    bh = t - (t - b)
    bl = b - bh
    return hi, ((ah * bh - hi) + ah * bl + al * bh) + al * bl


@_jit
def _minus_product(a, alpha, b):  # type: ignore[no-untyped-def]
    """``a - alpha b`` with one rounding of the result (the product kept exactly)."""
    hi, lo = _two_product(alpha, b)
    return (a - hi) - lo


@_jit
def _head_residues(q, lam, g):  # type: ignore[no-untyped-def]
    """a_h's residues ``z_c(p) P_r(p) / D'(p)`` into ``g[1]`` (the unit ramp's a_h is
    ``z_c P_r / D``), with ``P_r(p)`` free of cancellation, at the poles where P_r(p)
    evaluated directly loses more than :data:`CANCELLED` of its terms (elsewhere the
    residues of the initial state's linear system stay: consistent with the poles' own
    errors, they keep a nearly double pole's zero of a_h to 1e-12).

    Near the bodies' common mode (the arm's own mode equal to the head's, ``repeated``
    family) P_r(p) is a tiny difference of large terms; evaluated directly, or through
    the linear system of the initial state, its absolute error (1e-13 of a_h's scale)
    swamped the true residue (1e-15) and the evaluator found no lobe end (issue 34). With
    ``alpha = M_r / M_h``, ``eps(s) = P_r(s) - alpha P_h(s)`` (its coefficients exact
    differences) and ``u = P_h(p)``, ``D(p) = 0`` reads ``alpha u^2 + ((1 + alpha) z_c +
    eps) u + eps z_c = 0``: u is its root nearest the direct P_h(p), the small one by
    the stable formula, and ``P_r(p) = alpha u + eps(p)``. ``g[3, k]`` gets the residue's
    size times its first-order condition number (the weight of its term in a_h's noise
    level, :func:`_sweep`)."""
    m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h = q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7]
    alpha = m_r / m_h
    e2 = _minus_product(m_r, alpha, m_h)
    e1 = _minus_product(c_r, alpha, c_h)
    e0 = _minus_product(k_r, alpha, k_h)
    for k in range(4):
        s = lam[k]
        zc = c_c * s + k_c
        direct = (m_h * s + c_h) * s + k_h
        eps = (e2 * s + e1) * s + e0
        b = (1.0 + alpha) * zc + eps
        cc = eps * zc
        d = cmath.sqrt(b * b - 4.0 * alpha * cc)
        qq = -0.5 * (b + d) if (b.conjugate() * d).real >= 0 else -0.5 * (b - d)
        u = qq / alpha
        if qq != 0 and abs(cc / qq - direct) < abs(u - direct):
            u = cc / qq
        pr = alpha * u + eps
        size = abs(m_r * s * s) + abs(c_r * s) + k_r
        if abs((m_r * s + c_r) * s + k_r) >= CANCELLED * size:  # no cancellation
            g[3, k] = 0.0
            continue
        dpr, dph = 2.0 * m_r * s + c_r, 2.0 * m_h * s + c_h
        t1, t2, t3, t4 = dpr * u, pr * dph, c_c * (pr + u), zc * (dpr + dph)
        dd = t1 + t2 + t3 + t4
        g[1, k] = zc * pr / dd
        # first-order condition of the residue: each factor's terms over its value
        cond = (abs(c_c * s) + abs(k_c)) / abs(zc) + (abs(alpha * u) + abs(eps)) / abs(pr)
        cond += (abs(t1) + abs(t2) + abs(t3) + abs(t4)) / abs(dd)
        g[3, k] = abs(g[1, k]) * cond


@_jit
def _constrained_modes(q, lam, g, c):  # type: ignore[no-untyped-def]
    """As :func:`_reduced_modes` for the head against a wall (2 poles; a_h 0)."""
    m_r, c_r, k_r, k_c, c_c = q[0], q[1], q[2], q[3], q[4]
    den = np.array([m_r, c_r + c_c, k_r + k_c])
    if not aberth(den, lam, False):
        return False
    b_r = -k_c / (k_r + k_c)
    a_r = (-c_c - (c_r + c_c) * b_r) / (k_r + k_c)
    v = np.empty((2, 2), dtype=np.complex128)
    for k in range(2):
        sc = 1.0 / max(1.0, abs(lam[k]))
        v[0, k], v[1, k] = sc, lam[k] * sc
    v0 = v.copy()
    coef = _solve(v, np.array([-a_r + 0j, -b_r]))
    for k in range(2):
        e = coef[k] * v0[0, k]
        g[2, k] = e
        g[0, k] = (k_c + c_c * lam[k]) * e
        g[1, k] = 0.0
    slope = b_r + 1.0
    c[2, 0], c[2, 1] = slope, a_r
    c[0, 0], c[0, 1] = k_c * slope, k_c * a_r + c_c * slope
    c[1, 0] = c[1, 1] = 0.0
    return np.all(np.isfinite(coef))


@_jit
def _padd(a, b):  # type: ignore[no-untyped-def]
    """Sum of two polynomials (descending coefficients) of any lengths."""
    out = np.zeros(max(a.size, b.size))
    out[out.size - a.size :] += a
    out[out.size - b.size :] += b
    return out


@_jit
def _full_d(q, constrained, s):  # type: ignore[no-untyped-def]
    """D and D' of the full joint at ``s`` from its factors (no expanded coefficients):
    ``D = Q_r P_h + z_c (P_h z_e + Q_r)``, ``Q_r = M_r s^2 z_e + z_m z_q``; constrained
    ``D = Q_r + z_c z_e``."""
    m_r, c_m, k_m, k_c, c_c, m_h, c_h, k_h, c_q, k_q = (
        q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7], q[8], q[9])  # fmt: skip
    zm, zq, zc = c_m * s + k_m, c_q * s + k_q, c_c * s + k_c
    ze = zm + zq
    dze = c_m + c_q
    qr = m_r * s * s * ze + zm * zq
    dqr = 2.0 * m_r * s * ze + m_r * s * s * dze + c_m * zq + zm * c_q
    if constrained:
        return qr + zc * ze, dqr + c_c * ze + zc * dze
    ph = (m_h * s + c_h) * s + k_h
    dph = 2.0 * m_h * s + c_h
    inner = ph * ze + qr
    d_inner = dph * ze + ph * dze + dqr
    return qr * ph + zc * inner, dqr * ph + qr * dph + c_c * inner + zc * d_inner


@_jit
def _full_modes(q, constrained, lam, g, c):  # type: ignore[no-untyped-def]
    """As :func:`_reduced_modes` for the full joint (5 poles; 3 when ``constrained``): the
    roots of D by Aberth from the node's, the arm's and the head's own modes, polished
    by Newton on D's factors; eigenvectors from the structure (massless node: ``z_e d_e
    = z_m d_r``; head ``(P_h + z_c) d_h = z_c d_r``); the particular solution of the unit
    ramp from the static equations of the three bodies."""
    m_r, c_m, k_m, k_c, c_c, m_h, c_h, k_h, c_q, k_q = (
        q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7], q[8], q[9])  # fmt: skip
    c_s, k_s = c_m + c_q, k_m + k_q
    zm, zq = np.array([c_m, k_m]), np.array([c_q, k_q])
    ze, zc = np.array([c_s, k_s]), np.array([c_c, k_c])
    qr = _padd(_polymul(np.array([m_r, 0.0, 0.0]), ze), _polymul(zm, zq))
    n = 3 if constrained else 5
    lam[0] = -k_s / c_s  # the node's own pole
    _quadratic(m_r, c_c, k_c + k_m * k_q / k_s, lam, 1)
    if constrained:
        den = _padd(qr, _polymul(zc, ze))
    else:
        ph = np.array([m_h, c_h, k_h])
        den = _padd(_polymul(qr, ph), _polymul(zc, _padd(_polymul(ph, ze), qr)))
        _quadratic(m_h, c_h + c_c, k_h + k_c, lam, 3)
    if not aberth(den, lam[:n], True):
        return False
    for k in range(n):  # polish on the factored D
        for _ in range(2):
            d, dd = _full_d(q, constrained, lam[k])
            if dd != 0:
                lam[k] -= d / dd
    # the unit ramp's particular solution: d = a + b t of the arm, the node, the head
    st = np.array([[k_m + k_c, -k_m, -k_c], [-k_m, k_s, 0.0], [-k_c, 0.0, k_h + k_c]])
    m = 2 if constrained else 3
    b = _solve(st[:m, :m].astype(np.complex128), np.array([-k_c + 0j, 0.0, k_c])[:m]).real
    b_h = 0.0 if constrained else b[2]
    rhs = np.array([-c_c - c_m * (b[0] - b[1]) - c_c * (b[0] - b_h) + 0j,
                    c_m * b[0] - c_s * b[1], c_c - c_h * b_h + c_c * (b[0] - b_h)])  # fmt: skip
    a = _solve(st[:m, :m].astype(np.complex128), rhs[:m]).real
    a_h = 0.0 if constrained else a[2]
    v = np.empty((n, n), dtype=np.complex128)
    for k in range(n):
        s = lam[k]
        e_s, m_s, c_s_ = c_s * s + k_s, c_m * s + k_m, c_c * s + k_c
        if constrained:
            dr, de, dh = e_s, m_s, 0j
        else:
            head = (m_h * s + c_h) * s + k_h + c_s_
            dr, de, dh = head * e_s, head * m_s, c_s_ * e_s
        sc = 1.0 / max(abs(dr), abs(s * dr), abs(de), abs(dh), abs(s * dh))
        v[0, k], v[1, k], v[2, k] = dr * sc, s * dr * sc, de * sc
        if not constrained:
            v[3, k], v[4, k] = dh * sc, s * dh * sc
    v0 = v.copy()
    x0 = np.array([-a[0] + 0j, -b[0], -a[1], -a_h, -b_h])[:n]
    coef = _solve(v, x0)
    for k in range(n):
        e = coef[k] * (v0[0, k] - (0.0 if constrained else v0[3, k]))
        g[2, k] = e
        g[0, k] = (k_c + c_c * lam[k]) * e
        g[1, k] = 0.0 if constrained else coef[k] * v0[3, k] * lam[k] * lam[k]
    slope = b[0] - b_h + 1.0
    c[2, 0], c[2, 1] = slope, a[0] - a_h
    c[0, 0], c[0, 1] = k_c * slope, k_c * (a[0] - a_h) + c_c * slope
    c[1, 0] = c[1, 1] = 0.0
    return np.all(np.isfinite(coef))


@_jit
def _value(lam, g, c, n, o, t, shift=0.0):  # type: ignore[no-untyped-def]
    """y, y', y'' of output ``o`` at ``t`` (closed form, direct exponentials); with
    ``shift`` those of ``exp(-shift t) y(t)`` (a_h, which has no polynomial part: the same
    zeros, and no subnormal numbers in a slow tail, :func:`_slowest`)."""
    y = c[o, 0] * t + c[o, 1]
    d1 = c[o, 0]
    d2 = 0.0
    for k in range(n):
        s = lam[k] - shift
        e = g[o, k] * cmath.exp(s * t)
        y += e.real
        e = e * s
        d1 += e.real
        d2 += (e * s).real
    return y, d1, d2


@_jit
def _slowest(lam, n):  # type: ignore[no-untyped-def]
    """The slowest pole's real part (<= 0 for a stable design, else 0). a_h is sampled and
    its zero solved as ``exp(-sigma t) a_h(t)``: in the ``repeated`` family the lobe ends
    at 40-70 s, where a_h's terms are about 1e-320 (subnormal, absolute rounding), and
    the evaluator found no lobe end (issue 34)."""
    sigma = -np.inf
    for k in range(n):
        sigma = max(sigma, lam[k].real)
    return min(sigma, 0.0)


@_jit
def _values(lam, g, c, n, t, out):  # type: ignore[no-untyped-def]
    """:func:`_value` of every output at ``t`` into ``out`` (3, 3)."""
    for o in range(3):
        out[o, 0] = c[o, 0] * t + c[o, 1]
        out[o, 1] = c[o, 0]
        out[o, 2] = 0.0
    for k in range(n):
        x = cmath.exp(lam[k] * t)
        for o in range(3):
            e = g[o, k] * x
            out[o, 0] += e.real
            e = e * lam[k]
            out[o, 1] += e.real
            out[o, 2] += (e * lam[k]).real


@_jit
def _root(lam, g, c, n, o, d, lo, hi, tol, shift=0.0):  # type: ignore[no-untyped-def]
    """Zero of derivative ``d`` (0: y, 1: y') of output ``o`` in ``[lo, hi]``, where it is
    > 0 at lo and <= 0 at hi: Newton safeguarded by bisection, to ``tol`` relative
    (``shift``: of ``exp(-shift t) y``, :func:`_value`)."""
    t = 0.5 * (lo + hi)
    for _ in range(200):
        v = _value(lam, g, c, n, o, t, shift)
        f, df = v[d], v[d + 1]
        if f > 0:
            lo = t
        else:
            hi = t
        step = f / df if df != 0 else np.inf
        tn = t - step
        if not (lo < tn < hi):
            tn = 0.5 * (lo + hi)
        if abs(tn - t) <= tol * abs(t) or hi - lo <= tol * hi:
            return tn
        t = tn
    return t


@_jit
def _golden(lam, g, c, n, o, lo, hi):  # type: ignore[no-untyped-def]
    """Largest y of output ``o`` on ``[lo, hi]`` by golden section (a bracket where y' has
    no single sign change)."""
    r = 0.5 * (math.sqrt(5.0) - 1.0)
    a, b = lo, hi
    best = max(_value(lam, g, c, n, o, lo)[0], _value(lam, g, c, n, o, hi)[0])
    x1, x2 = b - r * (b - a), a + r * (b - a)
    f1, f2 = _value(lam, g, c, n, o, x1)[0], _value(lam, g, c, n, o, x2)[0]
    for _ in range(80):
        if f1 >= f2:
            b, x2, f2 = x2, x1, f1
            x1 = b - r * (b - a)
            f1 = _value(lam, g, c, n, o, x1)[0]
        else:
            a, x1, f1 = x1, x2, f2
            x2 = a + r * (b - a)
            f2 = _value(lam, g, c, n, o, x2)[0]
        best = max(best, f1, f2)
    return best


@_jit
def _refine_max(lam, g, c, n, o, cand):  # type: ignore[no-untyped-def]
    """The maximum of output ``o`` near a sampled maximum ``cand`` = (y, lo, mid, hi, y_lo,
    y_hi): Newton on y' from the vertex of the samples' parabola, kept in ``[lo, hi]`` by
    the sign of y' (golden section if it does not settle). Every value evaluated is a
    value of y, so the result never exceeds the true maximum."""
    best, lo, mid, hi, f_lo, f_hi = cand[0], cand[1], cand[2], cand[3], cand[4], cand[5]
    den = (mid - lo) * (best - f_hi) - (mid - hi) * (best - f_lo)
    t = mid
    if den != 0 and lo < mid < hi:
        t = mid - 0.5 * ((mid - lo) ** 2 * (best - f_hi) - (mid - hi) ** 2 * (best - f_lo)) / den
    if not lo <= t <= hi:
        t = mid
    for _ in range(30):
        y, d1, d2 = _value(lam, g, c, n, o, t)
        best = max(best, y)
        if d1 > 0:
            lo = t
        else:
            hi = t
        tn = t - d1 / d2 if d2 < 0 else 0.5 * (lo + hi)
        if not lo <= tn <= hi:
            tn = 0.5 * (lo + hi)
        if abs(tn - t) <= 1e-10 * abs(t) + 1e-300 or hi - lo <= 1e-10 * hi:
            return max(best, _value(lam, g, c, n, o, tn)[0])
        t = tn
    return max(best, _golden(lam, g, c, n, o, cand[1], cand[3]))


@_jit
def _deactivation(lam, g, c, n, used):  # type: ignore[no-untyped-def]
    """Time after which each pole's term is below :data:`NEGLIGIBLE` of every output's
    scale (inf for a pole that does not decay)."""
    out = np.empty(n)
    for k in range(n):
        out[k] = 0.0
        for o in range(3):
            if not used[o]:
                continue
            scale = abs(c[o, 1])
            for j in range(n):
                scale = max(scale, abs(g[o, j]))
            mag = abs(g[o, k])
            if mag == 0 or scale == 0:
                continue
            if lam[k].real >= 0:
                out[k] = np.inf
            else:
                ratio = mag / (NEGLIGIBLE * scale)
                if ratio > 1:
                    out[k] = max(out[k], math.log(ratio) / -lam[k].real)
    return out


@_jit
def _push(cand, o, y, lo, mid, hi, y_lo, y_hi):  # type: ignore[no-untyped-def]
    """Keep the :data:`CANDIDATES` best sampled maxima of output ``o``: rows (y, lo, mid,
    hi, y_lo, y_hi), the sample ``(mid, y)`` and its neighbours."""
    worst = 0
    for m in range(1, CANDIDATES):
        if cand[o, m, 0] < cand[o, worst, 0]:
            worst = m
    if y > cand[o, worst, 0]:
        cand[o, worst, 0], cand[o, worst, 1] = y, lo
        cand[o, worst, 2], cand[o, worst, 3] = mid, hi
        cand[o, worst, 4], cand[o, worst, 5] = y_lo, y_hi


@_jit
def _level(lam, g, n, big, sigma, t):  # type: ignore[no-untyped-def]
    """a_h's rounding level (over :data:`NOISE`) at ``t``, scaled by ``exp(-sigma t)``: each
    term's weight ``g[3, k]`` (reduced model, :func:`_head_residues`) or, without weights,
    the largest residue, times ``exp((Re p_k - sigma) t)``."""
    lvl = 0.0
    for k in range(n):
        w = g[3, k].real if g[3, k].real > 0 else big
        lvl += w * math.exp((lam[k].real - sigma) * t)
    return lvl


@_jit
def _sweep(lam, g, c, n, used, lobe, t_end, cand):  # type: ignore[no-untyped-def]
    """Sample the outputs from 0 to ``t_end`` (to the first provably negative a_h when
    ``lobe``); returns ``(t_lo, t_hi, samples, t_last)``: the bracket of a_h's first sign
    change before that sample (NaN when none), the number of samples (-1: too many) and
    the last sample but one before ``t_end`` (or before the bracket)."""
    off = _deactivation(lam, g, c, n, used)
    big = 0.0
    for k in range(n):
        big = max(big, abs(g[1, k]))
    prev = np.empty(3)
    prev2 = np.empty(3)
    tprev = tprev2 = 0.0
    first_lo = first_hi = np.nan
    before = 0.0
    t0 = 0.0
    count = 0
    ex = np.empty(n, dtype=np.complex128)
    z = np.empty(n, dtype=np.complex128)
    ex1 = np.empty(n, dtype=np.complex128)  # exp((p_k - sigma) t): a_h scaled (_slowest)
    z1 = np.empty(n, dtype=np.complex128)
    sigma = _slowest(lam, n)
    while t0 < t_end:
        rate = 0.0
        for k in range(n):
            if off[k] > t0:
                rate = max(rate, abs(lam[k]))
        seg = t_end
        if rate == 0.0:
            h = t_end / 64.0
        else:
            h = 1.0 / (DENSITY * rate)
            for k in range(n):
                if off[k] > t0 and abs(lam[k]) >= 0.999 * rate:
                    seg = min(seg, off[k])
        steps = max(int(math.ceil((seg - t0) / h)), 1)  # noqa: RUF046 (numba)
        if count + steps > MAX_SAMPLES:
            return np.nan, np.nan, -1, 0.0
        h = (seg - t0) / steps
        for k in range(n):
            ex[k] = cmath.exp(lam[k] * t0)
            z[k] = cmath.exp(lam[k] * h)
            ex1[k] = cmath.exp((lam[k] - sigma) * t0)
            z1[k] = cmath.exp((lam[k] - sigma) * h)
        for j in range(steps + (1 if seg >= t_end else 0)):
            t = t0 + j * h
            for o in range(3):
                if not used[o]:
                    continue
                y = c[o, 0] * t + c[o, 1]
                for k in range(n):
                    y += (g[o, k] * ex[k]).real
                if count >= 2 and prev[o] >= prev2[o] and prev[o] >= y:
                    _push(cand, o, prev[o], tprev2, tprev, t, prev2[o], y)
                elif count == 1 and prev[o] >= y and _value(lam, g, c, n, o, 0.0)[1] > 0:
                    _push(cand, o, prev[o], 0.0, 0.0, t, prev[o], y)
                prev2[o], prev[o] = prev[o], y
            if lobe and count > 0:
                a = 0.0  # a_h scaled by exp(-sigma t): its sign
                for k in range(n):
                    a += (g[1, k] * ex1[k]).real
                if a <= 0:
                    if np.isnan(first_lo):
                        first_lo, first_hi, before = tprev, t, tprev2
                    if a < -NOISE * _level(lam, g, n, big, sigma, t):
                        return first_lo, first_hi, count + 1, before
                else:
                    first_lo = first_hi = np.nan
            for k in range(n):
                ex[k] *= z[k]
                ex1[k] *= z1[k]
            tprev2, tprev = tprev, t
            count += 1
        t0 = seg
    return np.nan, np.nan, count, tprev2


@_jit
def _metrics(lam, g, c, n, used, lobe, window, horizon, row):  # type: ignore[no-untyped-def]
    """Row ``(a_max, eps_max, f_max, t_imp)`` of one design from its modes; the status."""
    for k in range(4):
        row[k] = np.nan
    cand = np.full((3, CANDIDATES, 6), -np.inf)
    t_end = horizon if lobe else window
    lo, hi, count, last = _sweep(lam, g, c, n, used, lobe, t_end, cand)
    if count < 0:
        return GAVE_UP
    if lobe:
        if np.isnan(lo):
            return 3
        t_imp = _root(lam, g, c, n, 1, 0, lo, hi, 1e-13, _slowest(lam, n)) if lo < hi else hi
        if t_imp > horizon:
            return 3
    else:
        t_imp = window
    row[3] = t_imp
    status = 0
    end = np.empty((3, 3))  # y, y', y'' of each output at t_imp, one set of exponentials
    _values(lam, g, c, n, t_imp, end)
    for o, col in ((0, 2), (1, 0), (2, 1)):
        if not used[o]:
            continue
        y0 = c[o, 1]
        for k in range(n):
            y0 += g[o, k].real
        best = max(y0, end[o, 0])
        for m in range(CANDIDATES):
            if cand[o, m, 0] > -np.inf and cand[o, m, 2] <= t_imp:
                cand[o, m, 3] = min(cand[o, m, 3], t_imp)
                best = max(best, _refine_max(lam, g, c, n, o, cand[o, m]))
        # the last two cells: a maximum between the last sample but one and t_imp (the
        # samples after t_imp do not count)
        if end[o, 1] < 0 < _value(lam, g, c, n, o, last)[1] and last < t_imp:
            t = _root(lam, g, c, n, o, 1, last, t_imp, 1e-10)
            best = max(best, _value(lam, g, c, n, o, t)[0])
        row[col] = best
        if o == 1 and best <= y0:
            status = 2
    return status


@_jit
def _rate(lam, n):  # type: ignore[no-untyped-def]
    r = 0.0
    for k in range(n):
        r = max(r, abs(lam[k]))
    return r


@_jit
def _grid_rate(lam, n, full):  # type: ignore[no-untyped-def]
    """The rate of the kernel's documented horizon: every pole (reduced); for the full
    joint, real poles above ten times the fastest oscillatory one (or the slowest) left
    out (docs/impact_joint.md)."""
    if not full:
        return _rate(lam, n)
    base = 0.0
    slow = np.inf
    osc = False
    for k in range(n):
        m = abs(lam[k])
        if abs(lam[k].imag) > 1e-9 * max(m, 1e-300):
            osc = True
            base = max(base, m)
        slow = min(slow, m)
    if not osc:
        base = slow
    r = 0.0
    for k in range(n):
        m = abs(lam[k])
        if abs(lam[k].imag) > 1e-9 * max(m, 1e-300) or m <= 10.0 * base:
            r = max(r, m)
    return r


@_jit
def _evaluate(params, kind, window, max_steps, rows, status):  # type: ignore[no-untyped-def]
    """kind 0: reduced, 1: reduced constrained, 2: full joint, 3: full constrained."""
    lam = np.zeros(5, dtype=np.complex128)
    g = np.zeros((4, 5), dtype=np.complex128)  # row 3: a_h's noise weights (reduced)
    c = np.zeros((3, 2))
    lobe = kind == 0 or kind == 2
    used = np.array([True, lobe, True])
    span = ((max_steps // 12) * 12 + 11) * 0.4
    for i in range(params.shape[0]):
        q = params[i]
        if kind == 0:
            n, ok = 4, _reduced_modes(q, lam, g, c)
        elif kind == 1:
            n, ok = 2, _constrained_modes(q, lam, g, c)
        else:
            n = 3 if kind == 3 else 5
            ok = _full_modes(q, kind == 3, lam, g, c)
        if not ok:
            rows[i, :] = np.nan
            status[i] = GAVE_UP
            continue
        horizon = span / _grid_rate(lam, n, kind >= 2)
        status[i] = _metrics(lam, g, c, n, used, lobe, window, horizon, rows[i])
        if status[i] == 3:
            rows[i, :] = np.nan


def evaluate(
    params: np.ndarray, kind: str, window: float = 0.05, max_steps: int = 4096
) -> tuple[np.ndarray, np.ndarray]:
    """Unit-v_c rows ``(a_max, eps_max, f_max, t_imp)`` and status codes of ``params``.

    ``kind``: ``"reduced"`` (N, 8), ``"constrained"`` (N, 8; head against a wall, the
    window ``[0, window]``), ``"full"`` or ``"full_constrained"`` (N, 10).
    """
    code = ("reduced", "constrained", "full", "full_constrained").index(kind)
    p = np.ascontiguousarray(params, dtype=np.float64)
    rows = np.empty((p.shape[0], 4))
    status = np.zeros(p.shape[0], dtype=np.int8)
    _evaluate(p, code, float(window), int(max_steps), rows, status)
    return rows, status
