"""Compiled exact modal solution of the full-joint impact model, one design at a time (numba).

The full series joint (Zeng 2011, eq. 3.4.6; :mod:`designlab.impact.full_joint_model`)
in closed form. With the Laplace variable ``s``, ``C = C_mech + C_cont`` and
``K = K_mech + K_cont``, the transmission ``z_m = C_mech s + K_mech``, the
controller ``z_q = C_cont s + K_cont``, the motor node ``z_e = C s + K``, the foam
``z_c = C_c s + K_c`` and the head ``P_h = M_h s^2 + C_h s + K_h``, the arm's
impedance times the node's is ``Q_r = M_r s^2 z_e + z_m z_q`` (the joint's force is
``z_m z_q / z_e`` times the arm's deflection, eq. 3.4.6 over l^2). The responses
to the unit ramp (v_c = 1 m/s) are ``N(s) / (s^2 D(s))`` with

* unconstrained (5 poles): ``D = Q_r P_h + z_c (P_h z_e + Q_r)``; force
  ``N = z_c Q_r P_h``, compression ``N = Q_r P_h``, head acceleration
  ``N = s^2 z_c Q_r``;
* constrained, the head against a wall (3 poles): ``D = Q_r + z_c z_e``; force
  ``N = z_c Q_r``, compression ``N = Q_r``;
* the reduced model's constrained impact (2 poles, Zeng 2011, (3.9.2)) has the same
  form with ``z_r = M_r s^2 + C_r s + K_r`` for ``Q_r`` and 1 for ``z_e``
  (:func:`reduced_coefficients`).

Every coefficient is a sum of products of non-negative parameters (no
cancellation), and ``D(0) > 0`` because K_mech, K_cont and K_c are positive: the
model has no pole at ``s = 0``.

**Poles.** The full joint's ``D`` has odd degree, so it has a real root: a safeguarded Newton
iteration on a bracket (from the motor node's own pole ``-K/C``, which a stiff
transmission puts decades above the impact modes) finds one, it is divided out
(forwards or backwards, whichever is stable for its size), the rest is the
quartic of :func:`designlab.impact.kernel_poles.quartic_roots` or a quadratic,
and every root is polished by Newton on ``D`` itself. A design is **certified**
when its roots are distinct (relative gap above :data:`MIN_GAP`), each is well
conditioned (relative condition number below :data:`MAX_CONDITION`) and they
sum to ``-D``'s second coefficient (the reduced constrained quadratic is solved
directly and certified alike); a design that is not (nearly repeated poles, a
near-critically damped mode) gets the status :data:`FALLBACK` and its caller
evaluates it by the numpy modal path instead (for the full joint, the
eigen-decomposition of :mod:`designlab.impact.state_space`).

Residues and the polynomial part follow as in :mod:`.kernel_poles`; the lobe end
and the certified maxima are those of the reduced model (:mod:`.kernel`,
:mod:`.kernel_lobe`) on a grid that does not resolve the stiff motor node
(:func:`designlab.impact.full_joint_model.grid_rate`).

Examples
--------
>>> import numpy as np
>>> p = np.array([[1.475, 50.0, 5e4, 24250.0, 71.9, 4.4, 46.0, 3e3, 750.0, 37500.0]])
>>> out, status = full_metrics(p, (True, True, True), constrained=False, stop_time=0.05,
...                            max_lobe_steps=4096, diagnostics=False)
>>> int(status[0]), round(float(out[0, 0]) * 1.25 / 9.80665, 3)   # ok, a_h,max in g
(0, 4.079)
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from designlab.impact.kernel import LOBE_NOISE, _design
from designlab.impact.kernel_lobe import scratch
from designlab.impact.kernel_poles import quartic_roots
from designlab.sx.jit import kernel

__all__ = [
    "FALLBACK",
    "MAX_CONDITION",
    "MIN_GAP",
    "RESIDUAL",
    "certify",
    "full_coefficients",
    "full_metrics",
    "full_roots",
    "grid_step",
    "modal_solution",
    "reduced_coefficients",
]

#: status code of a design the compiled path does not certify (evaluated elsewhere)
FALLBACK = 4
#: smallest relative gap ``|p_i - p_j| / max(|p_i|, |p_j|)`` between two certified poles
MIN_GAP = 1e-3
#: largest relative condition number of a certified pole,
#: ``sum_k |d_k| |p|^(n-k) / (|p| |D'(p)|)``
MAX_CONDITION = 1e4
#: largest backward error of a certified pole, ``|D(p)|`` over ``sum_k |d_k| |p|^(n-k)``
RESIDUAL = 1e-13
_EPS = 2.220446049250313e-16


@kernel(inline=True)
def _conv(a, na, b, nb, out):  # type: ignore[no-untyped-def]
    """``out[:na + nb - 1] = a[:na] * b[:nb]`` (ascending polynomial product)."""
    for k in range(na + nb - 1):
        out[k] = 0.0
    for i in range(na):
        for j in range(nb):
            out[i + j] += a[i] * b[j]


@kernel
def full_coefficients(q, constrained, den, num):  # type: ignore[no-untyped-def]
    """Monic ``den`` (n+1) and numerators ``num`` (3, n+2) of one design (descending); n.

    ``q`` is a row of :data:`~designlab.impact.full_joint_model.FULL_PARAM_NAMES`;
    the numerators are those of force, head acceleration and compression (zero
    for the head when ``constrained``), and ``n`` is 5 (3 when ``constrained``).
    """
    return _coefficients(q, constrained, den, num, np.zeros((8, 7)))


@kernel
def _coefficients(q, constrained, den, num, work):  # type: ignore[no-untyped-def]
    """:func:`full_coefficients` with the scratch ``work`` (8, 7) (ascending polynomials)."""
    m_r, c_m, k_m, k_c, c_c, m_h, c_h, k_h, c_q, k_q = q
    zc, ze, ph, qr = work[0], work[1], work[2], work[3]
    d, nf, na, ne = work[4], work[5], work[6], work[7]
    for k in range(7):
        d[k] = nf[k] = na[k] = ne[k] = 0.0
    zc[0], zc[1] = k_c, c_c
    ze[0], ze[1] = k_m + k_q, c_m + c_q
    ph[0], ph[1], ph[2] = k_h, c_h, m_h
    qr[0], qr[1] = k_m * k_q, k_m * c_q + c_m * k_q
    qr[2], qr[3] = c_m * c_q + m_r * ze[0], m_r * ze[1]
    if constrained:
        n = 3
        _conv(zc, 2, ze, 2, d)
        for k in range(4):
            d[k] += qr[k]
            ne[k] = qr[k]
        _conv(zc, 2, qr, 4, nf)
    else:
        n = 5
        _conv(ph, 3, ze, 2, na)  # P_h z_e + Q_r, held in na for now
        for k in range(4):
            na[k] += qr[k]
        _conv(zc, 2, na, 4, d)
        _conv(qr, 4, ph, 3, ne)
        for k in range(6):
            d[k] += ne[k]
        _conv(zc, 2, ne, 6, nf)
        na[0] = na[1] = 0.0
        _conv(zc, 2, qr, 4, na[2:])
    lead = d[n]
    for k in range(n + 1):
        den[k] = d[n - k] / lead
    for k in range(n + 2):
        num[0, k] = nf[n + 1 - k] / lead
        num[1, k] = na[n + 1 - k] / lead
        num[2, k] = ne[n + 1 - k] / lead
    return n


@kernel
def reduced_coefficients(q, den, num):  # type: ignore[no-untyped-def]
    """:func:`full_coefficients` of the reduced model's constrained impact (n = 2).

    ``q`` is a row of :data:`~designlab.impact.model.PARAM_NAMES`; with
    ``z_r = M_r s^2 + C_r s + K_r``, ``D = z_r + z_c``, force ``N = z_c z_r`` and
    compression ``N = z_r`` (Zeng 2011, (3.9.2)).
    """
    m_r, c_r, k_r, k_c, c_c = q[0], q[1], q[2], q[3], q[4]
    den[0], den[1], den[2] = 1.0, (c_r + c_c) / m_r, (k_r + k_c) / m_r
    num[0, 0], num[0, 1] = c_c, (c_c * c_r + k_c * m_r) / m_r
    num[0, 2], num[0, 3] = (c_c * k_r + k_c * c_r) / m_r, k_c * k_r / m_r
    num[1, 0] = num[1, 1] = num[1, 2] = num[1, 3] = 0.0
    num[2, 0], num[2, 1], num[2, 2], num[2, 3] = 0.0, 1.0, c_r / m_r, k_r / m_r
    return 2


@kernel(inline=True)
def _horner(a, n, x):  # type: ignore[no-untyped-def]
    """``D(x)``, ``D'(x)`` of the monic ``a`` (descending, degree ``n``) and the rounding
    scale ``sum_k |a_k| |x|^(n-k)`` of ``D(x)``."""
    f = x + a[1]
    df = 1.0 + 0.0 * x
    m = abs(x)
    mags = m + abs(a[1])
    for k in range(2, n + 1):
        df = df * x + f
        f = f * x + a[k]
        mags = mags * m + abs(a[k])
    return f, df, mags


@kernel
def _real_root(a, n, guess):  # type: ignore[no-untyped-def]
    """A real root of the monic ``a`` of odd degree with positive coefficients (a negative one).

    Newton's iteration inside a shrinking bracket ``D(lo) < 0 < D(hi)``, started
    from Fujiwara's bounds on the roots' moduli; a step that leaves the bracket
    or does not halve the previous one is replaced by the bracket's geometric
    midpoint. Stops where ``D(x)`` is within its rounding noise.
    """
    big = abs(a[1])  # Fujiwara: every root has |x| <= 2 big and |x| >= 1 / (2 small)
    small = abs(a[n - 1] / a[n])
    for k in range(2, n + 1):
        big = max(big, abs(a[k]) ** (1.0 / k))
        small = max(small, abs(a[n - k] / a[n]) ** (1.0 / k))
    lo, hi = -2.0 * big, -0.5 / small
    x = guess if lo < guess < hi else -math.sqrt(lo * hi)
    step = old = hi - lo
    for _ in range(200):
        f, df, mags = _horner(a, n, x)
        if abs(f) <= 8.0 * _EPS * mags or not np.isfinite(f):
            return x
        if f < 0:
            lo = x
        else:
            hi = x
        xn = x - f / df if df != 0 else lo
        if not lo < xn < hi or abs(2.0 * f) > abs(old * df):
            xn = -math.sqrt(lo * hi)
        old = step
        step = xn - x
        if abs(step) <= 2.0 * _EPS * abs(xn):
            return xn
        x = xn
    return x


@kernel(inline=True)
def _deflate(a, n, r, b):  # type: ignore[no-untyped-def]
    """``b`` (degree n-1, monic) = ``a / (s - r)``: forwards for a small root, else backwards."""
    b[0] = 1.0
    if abs(r) ** n <= a[n]:  # |r| below the geometric mean of the roots' moduli
        for k in range(1, n):
            b[k] = a[k] + r * b[k - 1]
    else:
        b[n - 1] = -a[n] / r
        for k in range(n - 1, 1, -1):
            b[k - 1] = (b[k] - a[k]) / r


@kernel(inline=True)
def _polish(a, n, x):  # type: ignore[no-untyped-def]
    """Newton on ``D`` itself from ``x`` (real stays real), until ``D(x)`` is rounding noise
    (at most 4 steps)."""
    for _ in range(4):
        f, df, mags = _horner(a, n, x)
        if abs(f) <= 8.0 * _EPS * mags or df == 0:
            return x
        x = x - f / df
    return x


@kernel
def full_roots(a, n, guess, u0, v0, roots):  # type: ignore[no-untyped-def]
    """The ``n`` (3 or 5) roots of the monic ``a`` into ``roots`` (conjugates exact).

    A real root from ``guess`` (:func:`_real_root`), the deflated quartic by
    :func:`~designlab.impact.kernel_poles.quartic_roots` from the factor guess
    ``s^2 + u0 s + v0`` (or the deflated quadratic), each root polished on ``a``.
    """
    _roots(a, n, guess, u0, v0, roots, np.empty(5), np.empty(5, dtype=np.complex128),
           np.empty(4, dtype=np.complex128))  # fmt: skip


@kernel(inline=True)
def _quadratic(b1, b2, roots, i):  # type: ignore[no-untyped-def]
    """Roots of ``s^2 + b1 s + b2`` into ``roots[i], roots[i + 1]`` (conjugates exact)."""
    disc = 0.25 * b1 * b1 - b2
    if disc < 0:
        roots[i] = complex(-0.5 * b1, math.sqrt(-disc))
        roots[i + 1] = complex(-0.5 * b1, -math.sqrt(-disc))
    else:
        big = -0.5 * b1 - math.copysign(math.sqrt(disc), b1)
        roots[i] = big
        roots[i + 1] = b2 / big if big != 0 else 0.0


@kernel
def _polish_from(a, n, roots, start, found):  # type: ignore[no-untyped-def]
    """Polish ``roots[start:n]`` on ``a``; real roots stay real, conjugates exact (else NaN)."""
    m = start
    for k in range(start, n):
        z = roots[k]
        if z.imag == 0:
            found[m] = _polish(a, n, z.real)
            m += 1
        elif z.imag > 0 and m + 1 < n:
            x = _polish(a, n, z)
            found[m] = complex(x.real, abs(x.imag))
            found[m + 1] = complex(x.real, -abs(x.imag))
            m += 2
    for k in range(start, n):
        roots[k] = found[k] if m == n else complex(np.nan, 0.0)


@kernel
def _roots(a, n, guess, u0, v0, roots, b, found, four):  # type: ignore[no-untyped-def]
    """:func:`full_roots` with the scratch ``b`` (5), ``found`` (5) and ``four`` (4);
    ``n = 2`` (the reduced constrained impact) is solved directly."""
    if n == 2:
        _quadratic(a[1], a[2], roots, 0)
        _polish_from(a, n, roots, 0, found)
        return
    r = _real_root(a, n, guess)
    roots[0] = _polish(a, n, r)
    _deflate(a, n, roots[0].real, b)
    for k in range(n):
        if not np.isfinite(b[k]):
            for j in range(n):
                roots[j] = complex(np.nan, 0.0)
            return
    if n == 5:
        quartic_roots(b, u0, v0, four)
        for k in range(4):
            roots[k + 1] = four[k]
    else:
        _quadratic(b[1], b[2], roots, 1)
    _polish_from(a, n, roots, 1, found)


@kernel
def certify(a, n, roots):  # type: ignore[no-untyped-def]
    """Whether the ``n`` roots are distinct, well conditioned and complete (see module)."""
    total = 0.0
    size = 0.0
    for i in range(n):
        z = roots[i]
        m = abs(z)
        if not (np.isfinite(z.real) and np.isfinite(z.imag)) or z.real > 0:
            return False
        f, df, mags = _horner(a, n, z)
        if not (abs(f) <= RESIDUAL * mags and mags <= MAX_CONDITION * m * abs(df)):
            return False
        for j in range(i + 1, n):
            w = roots[j]
            dz = z - w
            gap = dz.real * dz.real + dz.imag * dz.imag
            size2 = max(m * m, w.real * w.real + w.imag * w.imag)
            if not gap >= MIN_GAP * MIN_GAP * size2:
                return False
        total -= z.real
        size += m
    return abs(total - a[1]) <= 1e-10 * size


@kernel
def modal_solution(den, num, roots, n, p, r, c, outputs):  # type: ignore[no-untyped-def]
    """Folded poles ``p``, residues ``r`` (3, 5), polynomial parts ``c`` (3, 2); pole count.

    One pole per conjugate pair with a doubled residue
    (:func:`designlab.impact.modal.fold_conjugates`); residues of ``N / (s^2 D)``
    at the simple roots ``roots`` of ``den``.
    """
    nk = 0
    for i in range(n):
        pi = roots[i]
        if pi.imag < 0:
            continue
        w = 2.0 if pi.imag > 0 else 1.0
        prod = pi * pi
        for j in range(n):
            if j != i:
                prod = prod * (pi - roots[j])
        p[nk] = pi
        for o in range(3):
            r[o, nk] = 0.0
            if outputs[o]:
                acc = complex(num[o, 0], 0.0)
                for k in range(1, n + 2):
                    acc = acc * pi + num[o, k]
                r[o, nk] = acc / prod * w
        nk += 1
    for o in range(3):
        c[o, 0] = c[o, 1] = 0.0
        if outputs[o]:
            c[o, 0] = num[o, n + 1] / den[n]
            c[o, 1] = (num[o, n] - den[n - 1] * c[o, 0]) / den[n]
    return nk


@kernel
def grid_step(p, nk):  # type: ignore[no-untyped-def]
    """``0.4`` over :func:`designlab.impact.full_joint_model.grid_rate` of the folded poles.

    Real poles faster than ten times the fastest oscillatory pole (or, without
    one, the slowest pole) are not resolved.
    """
    base = 0.0
    slow = np.inf
    any_osc = False
    for k in range(nk):
        m = abs(p[k])
        if abs(p[k].imag) > 1e-9 * max(m, 1e-300):
            any_osc = True
            base = max(base, m)
        slow = min(slow, m)
    if not any_osc:
        base = slow
    rate = 0.0
    for k in range(nk):
        m = abs(p[k])
        if abs(p[k].imag) > 1e-9 * max(m, 1e-300) or m <= 10.0 * base:
            rate = max(rate, m)
    return 0.4 / rate


@kernel
def _full_block(params, constrained, outputs, stop_time, max_steps, diag, out, status):  # type: ignore[no-untyped-def]
    work = scratch()
    den = np.empty(6)
    num = np.zeros((3, 7))
    poly = np.zeros((8, 7))
    roots = np.zeros(5, dtype=np.complex128)
    b = np.empty(5)
    found = np.empty(5, dtype=np.complex128)
    four = np.empty(4, dtype=np.complex128)
    p = np.zeros(5, dtype=np.complex128)
    r = np.zeros((3, 5), dtype=np.complex128)
    c = np.zeros((3, 2))
    reduced = params.shape[1] == 8
    for i in range(params.shape[0]):
        q = params[i]
        guess = u0 = v0 = 0.0
        if reduced:
            n = reduced_coefficients(q, den, num)
        else:
            n = _coefficients(q, constrained, den, num, poly)
            guess = -(q[2] + q[9]) / (q[1] + q[8])  # the motor node's own pole
            u0, v0 = (q[4] + q[6]) / q[5], (q[3] + q[7]) / q[5]  # the head's mode
        _roots(den, n, guess, u0, v0, roots, b, found, four)
        if not certify(den, n, roots):
            for k in range(out.shape[1]):
                out[i, k] = np.nan
            status[i] = FALLBACK
            continue
        nk = modal_solution(den, num, roots, n, p, r, c, outputs)
        h = grid_step(p, nk)
        if reduced:  # every pole resolved, as in metrics_from_responses
            fast = 0.0
            for k in range(nk):
                fast = max(fast, abs(p[k]))
            h = 0.4 / fast
        code = _design(
            p, r, c, nk, h, outputs, not constrained, stop_time, max_steps, diag, out[i], work
        )
        status[i] = 3 if code == LOBE_NOISE else code  # not retried in more digits here


def full_metrics(
    params: NDArray[np.float64],
    outputs: tuple[bool, bool, bool],
    *,
    constrained: bool,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
) -> tuple[NDArray[np.float64], NDArray[np.int8]]:
    """Unit-v_c first-lobe metrics of ``(N, 10)`` full-joint designs (or reduced, constrained).

    Parameters
    ----------
    params
        ``(N, 10)`` rows ordered as
        :data:`~designlab.impact.full_joint_model.FULL_PARAM_NAMES` (checked by
        the caller: K_mech, K_cont, K_c, M_r, M_h > 0, C_mech + C_cont > 0), or
        ``(N, 8)`` reduced rows (:data:`~designlab.impact.model.PARAM_NAMES`)
        with ``constrained``.
    outputs
        Whether to compute the force, the head acceleration and the compression
        maxima (the head acceleration is needed for the lobe end unless constrained).
    constrained
        The head against a wall: no lobe end, the window ``[0, stop_time]``.
    stop_time, max_lobe_steps, diagnostics
        As in :func:`designlab.impact.metrics.impact_metrics` (``lobe_diagnostics``).

    Returns
    -------
    tuple
        ``(N, 8)`` rows of :data:`designlab.impact.kernel.COLUMNS` and ``(N,)``
        status codes: those of :data:`designlab.impact.kernel.STATUS_CODES`, or
        :data:`FALLBACK` where the design was not certified (rows NaN).
    """
    p = np.ascontiguousarray(params, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] not in (8, 10) or (p.shape[1] == 8 and not constrained):
        raise ValueError(f"full_metrics takes (N, 10) rows, or (N, 8) constrained: {p.shape}")
    out = np.empty((p.shape[0], 8))
    status = np.zeros(p.shape[0], dtype=np.int8)
    sel = np.array(outputs, dtype=np.bool_)
    _full_block(p, bool(constrained), sel, float(stop_time), int(max_lobe_steps),
                bool(diagnostics), out, status)  # fmt: skip
    return out, status
