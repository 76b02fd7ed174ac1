"""Compiled first-lobe search and certified maxima of one design (numba; see :mod:`.kernel`).

The algorithms of :mod:`designlab.impact.metrics` and :mod:`designlab.impact.modal`
for one design at a time: march a grid of step ``STRIDE h`` to the first node where
a_h is *provably* <= 0 (below minus its rounding noise, :data:`.kernel_modal.NOISE`),
certify that no dip between nodes ends the lobe earlier, polish the lobe end by
safeguarded Newton, and take every maximum over the lobe by branch and bound on
the same nodes (their exponentials are the march's).

Cells are certified by bounds on the second, third and fourth derivatives over
the cell (:func:`.kernel_modal.curvature`, :func:`.kernel_modal.jerk`; the
fourth at most ``max|p_k|`` times the third): a cell where y' keeps its sign, or
where y'' does (y' monotone: at most one stationary point, found by Newton when
y' changes sign), holds its extremes at its ends or at that point; a cell whose
bound (the lower of a quadratic bound and the cubic Hermite interpolant plus its
error ``|y''''| w^4 / 384``, :func:`.kernel_modal.cell_bound`) allows a better
value is split in 4, depth first in time order (16 levels for maxima, 13 for
the lobe end).

A lobe is closed only where the response provably returns to zero: a node
whose value is <= 0 but within the rounding noise of its terms does not end the
lobe (the overdamped pulses whose a_h decays to zero from above; issue 22).

Examples
--------
>>> import numpy as np
>>> p = np.array([-1.0 + 2.0j]); r = np.array([[-1.0j]]); c = np.zeros((1, 2))
>>> # y = Re(-i e^((-1+2i)t)) = e^-t sin 2t: first zero at pi/2, maximum at atan(2)/2
>>> s = scratch()
>>> found, lo, hi, guess, low = march(p, r, c, 0, 1, 0.1, 4091, False, s[2])
>>> bool(found and lo < np.pi / 2 <= hi)
True
>>> t, y, sure = maximum(p, r, c, 0, 1, np.pi / 2, 0.3, s)
>>> bool(sure and abs(t - np.arctan(2) / 2) < 1e-12)
True
"""

from __future__ import annotations

import math

import numpy as np

from designlab.impact.kernel_exp import cexp
from designlab.impact.kernel_modal import (
    ERR_COLUMNS,
    MAX_TERMS,
    NOISE,
    UNDERFLOW,
    cell_bound,
    curvature,
    exponentials,
    fastest_rate,
    grid,
    hermite_bound,
    jerk,
    mag,
    newton,
    noise,
    real_product,
    separated,
    shape,
    stable,
    triple,
)
from designlab.sx.jit import kernel

__all__ = [
    "crossing", "lobe_end", "march", "maximum", "maximum_on_nodes", "node_count", "scratch",
    "tail_shift",
]  # fmt: skip

LOW_FRACTION = 0.05
#: Newton on y' stops after a step below this (relative): the quadratic convergence leaves
#: an error of its square, and the value at a stationary point is second-order in it
STATIONARY_RTOL = 1e-7
PARTS = 4
#: the march's step (and the maxima's cell width) in grid steps h
STRIDE = 3
#: up to this many steps the march's exponentials by recurrence err by less than
#: EXACT_STEPS * 4.4e-16 of the terms (a tenth of :data:`.kernel_modal.NOISE`): the
#: node that ends the march is then not re-evaluated
EXACT_STEPS = 256
#: a cell ``w`` with ``max|p_k| w`` above this is also tried with the stiff poles' decaying
#: terms bounded by their size (:func:`.kernel_modal.separated`): no derivative bound
#: certifies a cell that a pole 1e16 times faster crosses
STIFF = 64.0
#: most levels of splitting in the lobe-end certification
LEVELS = 13
MAX_CELLS = 4096
_STACK = 200
#: an open lobe is final where a_h stays above this many times its rounding noise at every
#: node of the horizon; nearer, a zero may hide in the noise and the caller evaluates the
#: design in more digits (:func:`lobe_end`)
CLEAR = 256.0
#: the lobe end is searched on ``exp(-sigma t) y(t)`` (``sigma`` the slowest pole's real
#: part; the same zeros where y has no polynomial part, as a_h) where ``exp(sigma t)``
#: falls below ``exp(-TAIL)`` (1e-217) within the horizon (:func:`tail_shift`): a zero
#: deep in a slow tail is then not lost among subnormal numbers (issue 34)
TAIL = 500.0

#: columns of a cell on the stack: times, values, slopes, second derivatives at both
#: ends, level, curvature and jerk scales at both ends
_TL, _TR, _YL, _YR, _DL, _DR, _QL, _QR, _LEVEL, _M2L, _M3L, _M2R, _M3R = range(13)


@kernel
def scratch():  # type: ignore[no-untyped-def]
    """Work arrays of one block: six node arrays (:func:`.kernel_modal.grid`), the stack,
    the nodes' exponentials (:func:`.kernel_modal.exponentials`, at most 5 poles) and the
    shifted poles of a slow tail's lobe end and their exponentials (:func:`tail_shift`)."""
    n = MAX_CELLS + 2
    nodes = (np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n))
    shifted = np.empty((3, 5), dtype=np.complex128)
    return nodes, np.empty((_STACK, 13)), np.empty((n, 5), dtype=np.complex128), shifted


@kernel(inline=True)
def tail_shift(p, c, o, nk, h, max_steps, diag):  # type: ignore[no-untyped-def]
    """``sigma``, the slowest pole's real part, where the lobe end of output ``o`` is to be
    searched on ``exp(-sigma t) y(t)`` (poles ``p_k - sigma``), else 0.

    Where y has no polynomial part (a_h) the two have the same zeros, and the scaled
    one's slowest term keeps its size: without it a zero deep in a slow tail (nearly
    repeated modes, 61.5 s, terms of 1e-320) is sought among subnormal numbers, whose
    rounding is absolute (:data:`.kernel_modal.UNDERFLOW`). Shifted where
    ``exp(sigma horizon) < exp(-TAIL)``, never with ``diag`` (whose low-fraction time is
    the unscaled response's). The shift's rounding, at most 2^-53 ``|p_k - sigma|`` per
    pole, moves a term by at most 2^-53 ``|p_k - sigma| t`` of itself: with the grid step
    ``h = 0.4 / max|p_k|`` and ``t`` within the horizon of about 4,100 steps, at most
    2^-53 * 2 * 1,640 = 3.6e-13, below :data:`.kernel_modal.NOISE`.
    """
    if diag or c[o, 0] != 0.0 or c[o, 1] != 0.0:
        return 0.0
    sigma = -np.inf
    for k in range(nk):
        sigma = max(sigma, p[k].real)
    horizon = ((max_steps // 12) * 12 + 11) * h
    if sigma < 0.0 and sigma * horizon < -TAIL:
        return sigma
    return 0.0


@kernel(borrows=True)
def march(p, r, c, o, nk, h, last, diag, ex):  # type: ignore[no-untyped-def]
    """March ``t_j = j h`` to the first node (t > 0) where output ``o`` is provably <= 0.

    Returns ``(found, lo, hi, guess, t_low)``: the bracket ``[hi - h, hi]``, a
    secant guess of the crossing and (``diag``) the first node where y fell below
    :data:`LOW_FRACTION` of its running peak. The nodes' exponentials
    ``exp(p_k t_j)`` (by recurrence; the last one evaluated directly after more than
    :data:`EXACT_STEPS` steps) are left in
    ``ex[j, k]`` for ``j <= MAX_CELLS``: :func:`crossing` takes them over. The last
    node is ``t = last h``.
    """
    peak = 0.0
    y_prev = 0.0
    t_low = np.nan
    z0 = z1 = z2 = z3 = z4 = 0j
    r0 = r1 = r2 = r3 = r4 = 0j
    for k in range(nk):  # at most 5 poles (full joint): registers, not arrays
        z, q = cexp(p[k] * h), r[o, k] + 0j
        if k == 0:
            z0, r0 = z, q
        elif k == 1:
            z1, r1 = z, q
        elif k == 2:
            z2, r2 = z, q
        elif k == 3:
            z3, r3 = z, q
        else:
            z4, r4 = z, q
    e0 = e1 = e2 = e3 = e4 = 1.0 + 0j
    for j in range(last + 1):
        t = j * h
        y = c[o, 0] * t + c[o, 1]
        y += real_product(r0, e0) + real_product(r1, e1) + real_product(r2, e2)
        y += real_product(r3, e3) + real_product(r4, e4)
        if j <= MAX_CELLS:
            _store(ex, j, nk, e0, e1, e2, e3, e4)
        e0, e1, e2, e3, e4 = e0 * z0, e1 * z1, e2 * z2, e3 * z3, e4 * z4
        if t > 0 and y <= 0:
            yd = y
            if j > EXACT_STEPS:  # the recurrence's rounding may near the noise level
                yd = c[o, 0] * t + c[o, 1]
                for k in range(nk):
                    x = cexp(p[k] * t)
                    yd += real_product(r[o, k], x)
                    if j <= MAX_CELLS:
                        ex[j, k] = x
            if yd < -noise(p, r, c, o, nk, t):
                lo = max(t - h, 0.0)
                frac = y_prev / (y_prev - yd)
                if not np.isfinite(frac):
                    frac = 0.5
                return True, lo, t, lo + frac * (t - lo), t_low
        if diag:
            peak = max(peak, y)
            if np.isnan(t_low) and peak > 0 and t > 0 and y < LOW_FRACTION * peak:
                t_low = t
        y_prev = y
    return False, np.nan, np.nan, np.nan, t_low


@kernel(inline=True)
def _store(ex, j, nk, e0, e1, e2, e3, e4):  # type: ignore[no-untyped-def]
    """``ex[j, :nk] = e0 .. e4``."""
    ex[j, 0] = e0
    if nk > 1:
        ex[j, 1] = e1
    if nk > 2:
        ex[j, 2] = e2
    if nk > 3:
        ex[j, 3] = e3
    if nk > 4:
        ex[j, 4] = e4


@kernel(inline=True)
def _below(p, r, c, o, nk, t, y):  # type: ignore[no-untyped-def]
    """Whether ``y = y(t)`` is provably <= 0."""
    return y <= 0 and y < -noise(p, r, c, o, nk, t)


@kernel(inline=True)
def _push_grid(stack, nodes, j):  # type: ignore[no-untyped-def]
    """Put the grid cell ``[t_j, t_j+1]`` on the empty stack; new size."""
    ts, ys, ds, qs, m2s, m3s = nodes
    stack[0, _TL], stack[0, _TR], stack[0, _YL], stack[0, _YR] = ts[j], ts[j + 1], ys[j], ys[j + 1]
    stack[0, _DL], stack[0, _DR], stack[0, _QL], stack[0, _QR] = ds[j], ds[j + 1], qs[j], qs[j + 1]
    stack[0, _M2L], stack[0, _M3L], stack[0, _M2R], stack[0, _M3R] = (
        m2s[j], m3s[j], m2s[j + 1], m3s[j + 1]
    )  # fmt: skip
    stack[0, _LEVEL] = 0.0
    return 1


@kernel(inline=True)
def _split(p, r, c, o, nk, stack, n):  # type: ignore[no-untyped-def]
    """Replace the cell ``stack[n]`` by its PARTS sub-cells (earliest on top); new size.

    The sub-nodes come by recurrence from ``exp(p_k tl)`` and ``exp(p_k w / PARTS)``
    (two exponentials per pole); the right end keeps its values.
    """
    tl, tr, level = stack[n, _TL], stack[n, _TR], stack[n, _LEVEL] + 1.0
    yl, dl, ql, al, bl = stack[n, _YL], stack[n, _DL], stack[n, _QL], stack[n, _M2L], stack[n, _M3L]
    yr, dr, qr, ar, br = stack[n, _YR], stack[n, _DR], stack[n, _QR], stack[n, _M2R], stack[n, _M3R]
    for i in range(PARTS - 1):  # the interior nodes' values, into the rows they end
        b = tl + (tr - tl) * ((i + 1) / PARTS)
        row = n + PARTS - 1 - i
        stack[row, _TR], stack[row, _LEVEL] = b, level
        stack[row, _YR] = c[o, 0] * b + c[o, 1]
        stack[row, _DR] = c[o, 0]
        stack[row, _QR], stack[row, _M2R], stack[row, _M3R] = 0.0, 0.0, 0.0
    dt = (tr - tl) / PARTS
    for k in range(nk):
        pk = p[k]
        p2 = pk * pk
        a = mag(pk)
        z = cexp(pk * dt)
        e = r[o, k] * cexp(pk * tl)
        for i in range(PARTS - 1):
            e = e * z
            row = n + PARTS - 1 - i
            g = mag(e) * a * a
            stack[row, _YR] += e.real
            stack[row, _DR] += real_product(e, pk)
            stack[row, _QR] += real_product(e, p2)
            stack[row, _M2R] += g
            stack[row, _M3R] += g * a
    for i in range(PARTS):
        row = n + PARTS - 1 - i
        if i == PARTS - 1:
            stack[row, _TR], stack[row, _LEVEL] = tr, level
            stack[row, _YR], stack[row, _DR], stack[row, _QR] = yr, dr, qr
            stack[row, _M2R], stack[row, _M3R] = ar, br
        stack[row, _TL] = tl + (tr - tl) * (i / PARTS)
        stack[row, _YL], stack[row, _DL], stack[row, _QL] = yl, dl, ql
        stack[row, _M2L], stack[row, _M3L] = al, bl
        yl, dl, ql = stack[row, _YR], stack[row, _DR], stack[row, _QR]
        al, bl = stack[row, _M2R], stack[row, _M3R]
    return n + PARTS


@kernel(inline=True)
def _scales(p, r, o, nk, stack, n, steady):  # type: ignore[no-untyped-def]
    """Bounds of ``|y''|`` and ``|y'''|`` over the cell ``stack[n]``."""
    if steady:
        return stack[n, _M2L], stack[n, _M3L]
    tl, tr = stack[n, _TL], stack[n, _TR]
    return curvature(p, r, o, nk, tl, tr), jerk(p, r, o, nk, tl, tr)


@kernel(borrows=True)
def crossing(p, r, c, o, nk, hi, h, levels, work, marched):  # type: ignore[no-untyped-def]
    """Bracket ``(lo, hi, count, sure)`` of the first provable zero of output ``o`` in ``(0, hi]``.

    :func:`designlab.impact.modal.certified_first_crossing`, depth first over
    cells of width <= h in time order: a local minimum between positive nodes is
    solved by Newton on -y' (the cell up to a minimum that is provably below zero
    then holds the first zero); a cell that may dip to zero otherwise is split; a
    cell from a positive to a provably negative end is the bracket once it holds
    one zero only (y or y' monotone over it, :func:`_one_root`), else it is split
    and its parts searched in time order. ``sure`` is False where a cell was not
    settled within ``levels`` splits (the zero is then not certified the first).
    ``marched`` (> 0) is the number of steps of :func:`march` that ended at ``hi``:
    the nodes' exponentials are then already in ``work[2]``. ``count`` is the number of
    grid cells over ``[0, hi]`` (the grid stays in ``work[0]``).
    """
    nodes, stack, ex = work[0], work[1], work[2]
    steady = stable(p, nk)
    fastest = fastest_rate(p, nk)
    if 0 < marched <= MAX_CELLS:
        count = marched
        w = h
    else:
        count = min(max(int(math.ceil(hi / h)), 1), MAX_CELLS)  # noqa: RUF046 (numba)
        w = hi / count
        exponentials(p, nk, hi, count, ex)
    grid(p, r, c, o, nk, hi, count, w, ex, nodes)
    lo_b = nodes[0][count - 1]
    hi_b = hi
    sure = True
    for j in range(count):
        if steady and _positive_cell(nodes, j, hi_b, fastest):
            continue  # what the stack would conclude at once, without pushing the cell
        n = _push_grid(stack, nodes, j)
        while n > 0:
            n -= 1
            tl, tr, yl, yr = stack[n, _TL], stack[n, _TR], stack[n, _YL], stack[n, _YR]
            dl, dr = stack[n, _DL], stack[n, _DR]
            if tl >= hi_b:
                continue
            w = tr - tl
            deep = stack[n, _LEVEL] >= levels
            if yl > 0 and _below(p, r, c, o, nk, tr, yr):  # a sign change (tr <= hi_b)
                lo_b, hi_b = tl, tr
                m2, m3 = _scales(p, r, o, nk, stack, n, steady)
                if not _one_root(dl, dr, stack[n, _QL], stack[n, _QR], w, m2, m3):
                    if deep:
                        sure = False
                    else:
                        n = _split(p, r, c, o, nk, stack, n)
                continue
            if not (yl > 0 and yr > 0):
                if stack[n, _LEVEL] > 0:  # an end within the rounding noise inside a cell
                    sure = False
                continue
            if dl < 0 and dr >= 0 and _dip(p, r, c, o, nk, stack, n, hi_b):
                hi_b = stack[n, _TR]  # the cell now ends at a provably negative minimum
                n += 1
                continue
            m2, m3 = _scales(p, r, o, nk, stack, n, steady)
            if dl * dr > 0 and abs(dl + dr) > m2 * w:
                continue  # y monotone between positive ends
            if shape(stack[n, _QL], stack[n, _QR], m3, w) != 0:
                continue  # y' monotone: its one minimum, if any, was solved above
            if _positive(yl, yr, dl, dr, w, m2, fastest * m3):
                continue
            if fastest * w > STIFF and _positive_separated(p, r, c, o, nk, tl, tr):
                continue  # positive once a stiff pole's decaying term is bounded by its size
            if deep:
                sure = False
            else:
                n = _split(p, r, c, o, nk, stack, n)
    return lo_b, hi_b, count, sure


@kernel(inline=True)
def _positive_separated(p, r, c, o, nk, tl, tr):  # type: ignore[no-untyped-def]
    """:func:`_positive` of the slow part of y minus the bound of its stiff terms
    (:func:`.kernel_modal.separated`)."""
    yl, yr, dl, dr, m2, m4, fast = separated(p, r, c, o, nk, tl, tr)
    if not (yl - fast > 0 and yr - fast > 0):
        return False
    return _positive(yl - fast, yr - fast, dl, dr, tr - tl, m2, m4)


@kernel(inline=True)
def _dip(p, r, c, o, nk, stack, n, hi_b):  # type: ignore[no-untyped-def]
    """Newton on -y' in the cell ``stack[n]`` (y' from - to +); where the minimum ``tm``
    is provably below zero, the cell is cut at ``tm`` (it then holds the first zero).
    Whether it was."""
    tl, tr, dl, dr = stack[n, _TL], stack[n, _TR], stack[n, _DL], stack[n, _DR]
    g = tl + (tr - tl) * dl / (dl - dr)
    tm, _ = newton(p, r, c, o, nk, tl, tr, 1, -1.0, 60, STATIONARY_RTOL, g)
    if not (tl < tm < hi_b):
        return False
    ym, dm, qm, am, bm = triple(p, r, c, o, nk, tm)
    if not _below(p, r, c, o, nk, tm, ym):
        return False
    stack[n, _TR], stack[n, _YR], stack[n, _DR], stack[n, _QR] = tm, ym, dm, qm
    stack[n, _M2R], stack[n, _M3R] = am, bm
    stack[n, _LEVEL] += 1.0
    return True


@kernel(inline=True)
def _one_root(dl, dr, ql, qr, w, m2, m3):  # type: ignore[no-untyped-def]
    """Whether a cell from a positive to a negative end holds one zero only: y' keeps its
    sign (``|y''| <= m2``) or y'' does (``|y'''| <= m3``: y' is monotone, so y rises
    then falls, or falls then rises, and crosses zero once)."""
    if dl * dr > 0 and abs(dl + dr) > m2 * w:
        return True
    return shape(ql, qr, m3, w) != 0


@kernel(borrows=True)
def lobe_end(p, r, c, o, nk, h, max_steps, diag, work):  # type: ignore[no-untyped-def]
    """``(t_imp, t_low, step, sure)`` of output ``o`` (a_h): NaN t_imp when no provable lobe
    end; ``sure`` False where :func:`crossing` could not certify that it is the first zero.

    The march takes steps of ``STRIDE h`` (of ``h`` with ``diag``, so that the
    diagnostic's nodes are the numpy path's) up to the numpy path's horizon
    ``((max_steps // 12) 12 + 11) h``; a lobe end beyond it is not accepted.
    ``step`` > 0 when ``work[2]`` holds ``exp(p_k j step)`` for the nodes before
    ``t_imp`` (the maxima's grid reuses them).
    """
    horizon = ((max_steps // 12) * 12 + 11) * h
    step = h if diag else STRIDE * h
    last = int(math.ceil(horizon / step))  # noqa: RUF046 (numba)
    found, _lo, hi, guess, t_low = march(p, r, c, o, nk, step, last, diag, work[2])
    if not found:
        # no node provably <= 0: a dip between the nodes may still end the lobe (a narrow
        # undershoot of a very overdamped design, issue 34): the same certification over
        # the whole horizon; where it cannot tell, the design is not certified
        end = last * step
        lo_c, hi_c, count, sure = crossing(p, r, c, o, nk, end, step, LEVELS, work, 0)
        if not hi_c < end:  # open; -inf: a_h came near its noise level (a zero may hide there)
            clear = sure and _clear(p, r, c, o, nk, count, work)
            return (np.nan if clear else -np.inf), t_low, 0.0, sure
        t = newton(p, r, c, o, nk, lo_c, hi_c, 0, 1.0, 60, 1e-11, 0.5 * (lo_c + hi_c))[0]
        return t, t_low, 0.0, sure
    marched = round(hi / step)
    lo_c, hi_c, count, sure = crossing(p, r, c, o, nk, hi, step, LEVELS, work, marched)
    if hi_c < hi or lo_c > work[0][0][count - 1]:
        g = 0.5 * (lo_c + hi_c)
    else:  # the last grid cell: Newton from its cubic Hermite root (values and slopes known)
        ts, ys, ds = work[0][0], work[0][1], work[0][2]
        j = count - 1
        g = _hermite_root(ts[j], ts[j + 1], ys[j], ys[j + 1], ds[j], ds[j + 1])
        if not np.isfinite(g):
            g = guess
    t = newton(p, r, c, o, nk, lo_c, hi_c, 0, 1.0, 60, 1e-11, g)[0]
    if t > horizon:
        return np.nan, t_low, 0.0, True
    return t, t_low, (0.0 if diag or marched > MAX_CELLS else step), sure


@kernel(inline=True)
def _clear(p, r, c, o, nk, count, work):  # type: ignore[no-untyped-def]
    """Whether output ``o`` is above :data:`CLEAR` times its rounding noise
    (:func:`.kernel_modal.noise`) at every node after 0 of the grid :func:`crossing` left in
    ``work`` (``count`` cells; the moduli of its exponentials give ``exp(Re p_k t)``): an
    open lobe that no evaluation in more digits can close (issue 34)."""
    ts, ys, ex = work[0][0], work[0][1], work[2]
    bounds = c.shape[1] >= ERR_COLUMNS
    big = 0.0
    for k in range(nk):
        big = max(big, mag(r[o, k]))
    for j in range(1, count + 1):
        t = ts[j]
        s = abs(c[o, 0] * t) + abs(c[o, 1])
        extra = 0.0
        for k in range(nk):
            e = mag(ex[j, k])
            s += (mag(r[o, k]) if bounds else big) * e
            if bounds:
                extra += (c[o, 2 + k] + c[o, 2 + MAX_TERMS + k] * t) * e
        if not ys[j] > CLEAR * (NOISE * s + extra + nk * UNDERFLOW):
            return False
    return True


@kernel(inline=True)
def _stationary(p, r, c, o, nk, tl, tr, dl, dr, ql, qr):  # type: ignore[no-untyped-def]
    """``(t, y)`` of the maximum where y' goes from + at tl to - at tr.

    Newton starts from the root of the cubic Hermite interpolant of y' (slopes
    ``dl, dr`` and second derivatives ``ql, qr`` at the ends; no exponential): an
    error of the fourth order in the cell width instead of the secant's second.
    """
    return newton(
        p, r, c, o, nk, tl, tr, 1, 1.0, 60, STATIONARY_RTOL, _hermite_root(tl, tr, dl, dr, ql, qr)
    )


@kernel(inline=True)
def _hermite_root(tl, tr, dl, dr, ql, qr):  # type: ignore[no-untyped-def]
    """Root in ``[tl, tr]`` of the cubic Hermite interpolant of values ``dl > 0 >= dr`` and
    slopes ``ql, qr``: two Newton steps from the secant root (the secant root if they
    leave the cell)."""
    w = tr - tl
    iw = 1.0 / w
    x = w * dl / (dl - dr)
    m = (dr - dl) * iw
    a2 = (3.0 * m - 2.0 * ql - qr) * iw
    a3 = (ql + qr - 2.0 * m) * (iw * iw)
    g = x
    for _ in range(2):
        f = dl + g * (ql + g * (a2 + g * a3))
        df = ql + g * (2.0 * a2 + g * 3.0 * a3)
        g = g - f / df
    if not (0.0 <= g <= w):  # also NaN
        g = x
    return tl + g


@kernel(borrows=True)
def maximum(p, r, c, o, nk, hi, w, work):  # type: ignore[no-untyped-def]
    """``(t, y, sure)`` maximum of output ``o`` over ``[0, hi]``, certified to 1e-8 (relative)
    where ``sure``.

    :func:`designlab.impact.modal.certified_maximum` depth first: cells of width
    <= w; every node and every stationary maximum (Newton on y') is a candidate.
    """
    count = node_count(hi, w)
    exponentials(p, nk, hi, count, work[2])
    return maximum_on_nodes(p, r, c, o, nk, hi, count, hi / count, work)


@kernel(inline=True)
def node_count(hi, w):  # type: ignore[no-untyped-def]
    """Cells of width <= w over ``[0, hi]`` (at most :data:`MAX_CELLS`)."""
    return min(max(int(math.ceil(hi / w)), 1), MAX_CELLS)  # noqa: RUF046 (numba)


@kernel(inline=True)  # three calls per design: inlined, the kernel is 4-7 % faster
def maximum_on_nodes(p, r, c, o, nk, hi, count, w, work, first=0):  # type: ignore[no-untyped-def]
    """:func:`maximum` once the nodes' exponentials are in ``work`` (shared by the outputs):
    nodes ``j w`` (j < count) and ``hi``; ``(t, y, sure)``. ``first`` = ``count`` where the
    nodes before ``count`` are already in ``work`` (:func:`crossing`'s grid of the same
    output, :func:`.kernel_modal.grid`).

    A cell where y' goes from + to - gets one Newton solve; it is settled by it only
    where y' is monotone over the cell (one stationary point), else it goes through
    the branch and bound like every other cell. ``sure`` is False where a cell was not
    settled within 16 levels of splitting.
    """
    nodes, stack, ex = work[0], work[1], work[2]
    ts, ys, ds, qs, m3s = nodes[0], nodes[1], nodes[2], nodes[3], nodes[5]
    steady = stable(p, nk)
    fastest = fastest_rate(p, nk)
    grid(p, r, c, o, nk, hi, count, w, ex, nodes, first)
    bt, by = 0.0, -np.inf
    for j in range(count + 1):
        if ys[j] > by:
            bt, by = ts[j], ys[j]
    for j in range(count):
        if ds[j] > 0 and ds[j + 1] <= 0:
            t, y = _stationary(p, r, c, o, nk, ts[j], ts[j + 1], ds[j], ds[j + 1], qs[j], qs[j + 1])
            if y > by:
                bt, by = t, y
    sure = True
    for j in range(count):
        cw = ts[j + 1] - ts[j]
        if ds[j] > 0 and ds[j + 1] <= 0:
            m3 = m3s[j] if steady else jerk(p, r, o, nk, ts[j], ts[j + 1])
            if shape(qs[j], qs[j + 1], m3, cw) != 0:
                continue  # y' monotone: its one zero is the maximum solved above
        elif steady and _bounded_cell(nodes, j, by, fastest):
            continue  # what _refine would conclude at once, without pushing the cell
        _push_grid(stack, nodes, j)
        bt, by, ok = _refine(p, r, c, o, nk, bt, by, stack, steady, fastest)
        sure = sure and ok
    return bt, by, sure


@kernel(inline=True)
def _bounded_cell(nodes, j, by, fastest):  # type: ignore[no-untyped-def]
    """Whether the grid cell ``j`` (no +/- change of y' at its ends, no unstable pole)
    cannot hold a maximum above ``by``: :func:`_refine`'s tests on its first cell."""
    ts, ys, ds, qs, m2s, m3s = nodes
    w = ts[j + 1] - ts[j]
    dl, dr, m2 = ds[j], ds[j + 1], m2s[j]
    if w <= 0 or (dl * dr > 0 and abs(dl + dr) > m2 * w):
        return True
    if shape(qs[j], qs[j + 1], m3s[j], w) != 0:
        return True
    top = by + 1e-8 * max(abs(by), 1e-300)
    if _below_top(ys[j], ys[j + 1], w, m2, top):
        return True
    return not cell_bound(ys[j], ys[j + 1], dl, dr, w, m2, fastest * m3s[j]) > top


@kernel(inline=True)
def _below_top(yl, yr, w, m2, top):  # type: ignore[no-untyped-def]
    """Whether the cheapest of :func:`.kernel_modal.cell_bound`'s terms,
    ``max(yl, yr) + m2 w^2 / 8`` (cell_bound is never above it), is <= ``top``: the
    cell is then settled without the full bound, with the same answer."""
    return max(yl, yr) + m2 * w * w / 8.0 <= top


@kernel(inline=True)
def _positive_cell(nodes, j, hi_b, fastest):  # type: ignore[no-untyped-def]
    """Whether the grid cell ``j`` (no unstable pole) provably stays positive, or lies
    past ``hi_b``: :func:`crossing`'s tests on a cell that is neither split nor solved."""
    ts, ys, ds, qs, m2s, m3s = nodes
    tl, tr, yl, yr, dl, dr = ts[j], ts[j + 1], ys[j], ys[j + 1], ds[j], ds[j + 1]
    if tl >= hi_b:
        return True
    if not (yl > 0 and yr > 0) or (dl < 0 and dr >= 0):
        return False
    w, m2 = tr - tl, m2s[j]
    if dl * dr > 0 and abs(dl + dr) > m2 * w:
        return True
    if shape(qs[j], qs[j + 1], m3s[j], w) != 0:
        return True
    return _positive(yl, yr, dl, dr, w, m2, fastest * m3s[j])


@kernel(inline=True)
def _positive(yl, yr, dl, dr, w, m2, m4):  # type: ignore[no-untyped-def]
    """Whether y > 0 over a cell with positive ends (``|y''| <= m2``, ``|y''''| <= m4``)."""
    if min(yl, yr) - m2 * w * w / 8.0 > 0:
        return True
    return hermite_bound(-yl, -yr, -dl, -dr, w, m4) < 0


@kernel(inline=True)
def _holds(t, tl, w):  # type: ignore[no-untyped-def]
    """Whether ``t`` lies inside the cell ``[tl, tl + w]``, farther than ``w / 1000`` from
    its ends (far beyond the error of a stationary point from :func:`_stationary`)."""
    return tl + 1e-3 * w < t < tl + (1.0 - 1e-3) * w


@kernel(inline=True)
def _refine(p, r, c, o, nk, bt, by, stack, steady, fastest):  # type: ignore[no-untyped-def]
    """Branch and bound inside the grid cell ``stack[0]`` (its ends and its stationary
    point, if y' goes from + to - over it, are already candidates); ``(t, y, sure)``."""
    n = 1
    first = True
    sure = True
    while n > 0:
        n -= 1
        tl, tr, yl, yr = stack[n, _TL], stack[n, _TR], stack[n, _YL], stack[n, _YR]
        dl, dr = stack[n, _DL], stack[n, _DR]
        w = tr - tl
        if not first:
            if yl > by:
                bt, by = tl, yl
            if dl > 0 and dr <= 0:  # a candidate; the cell may hold more than one
                ql, qr = stack[n, _QL], stack[n, _QR]
                if _holds(bt, tl, w):  # a stationary point solved in the cell it was split from
                    m3 = _scales(p, r, o, nk, stack, n, steady)[1]
                    if shape(ql, qr, m3, w) != 0:
                        continue  # y' monotone: its one zero is that point, bt
                t, y = _stationary(p, r, c, o, nk, tl, tr, dl, dr, ql, qr)
                if y > by:
                    bt, by = t, y
        first = False
        if w <= 0:
            continue
        m2, m3 = _scales(p, r, o, nk, stack, n, steady)
        if dl * dr > 0 and abs(dl + dr) > m2 * w:
            continue  # y' keeps its sign: the maximum is at an end node
        if shape(stack[n, _QL], stack[n, _QR], m3, w) != 0:
            continue  # y' monotone: the maximum is at an end node or its one stationary point
        top = by + 1e-8 * max(abs(by), 1e-300)
        if _below_top(yl, yr, w, m2, top):
            continue
        if cell_bound(yl, yr, dl, dr, w, m2, fastest * m3) > top:
            if fastest * w > STIFF:  # a stiff pole's decaying term bounded by its size
                sl, sr, s1, s2, s3, s4, fast = separated(p, r, c, o, nk, tl, tr)
                if cell_bound(sl, sr, s1, s2, w, s3, s4) + fast <= top:
                    continue
            if stack[n, _LEVEL] >= 16:
                sure = False
            else:
                n = _split(p, r, c, o, nk, stack, n)
    return bt, by, sure
