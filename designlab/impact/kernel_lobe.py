"""Compiled first-lobe search and certified maxima of one design (numba; see :mod:`.kernel`).

The algorithms of :mod:`designlab.impact.metrics` and :mod:`designlab.impact.modal`
for one design at a time: march a grid of step ``h`` to the first node where
a_h is *provably* <= 0 (below minus its rounding noise, :data:`.kernel_modal.NOISE`),
certify that no dip between nodes ends the lobe earlier, polish the lobe end by
safeguarded Newton, and take every maximum over the lobe by branch and bound.

Cells are certified by bounds on the second and third derivatives over the cell
(:func:`.kernel_modal.curvature`, :func:`.kernel_modal.jerk`): a cell where y'
keeps its sign, or where y'' does (y' monotone: at most one stationary point,
found by Newton when y' changes sign), holds its extremes at its ends or at that
point; any other cell whose curvature bound allows a better value is split in
16, depth first in time order (8 levels for maxima, 6 for the lobe end).

A lobe is closed only where the response provably returns to zero: a node
whose value is <= 0 but within the rounding noise of its terms does not end the
lobe (the overdamped pulses whose a_h decays to zero from above; issue 22).

Examples
--------
>>> import numpy as np
>>> p = np.array([-1.0 + 2.0j]); r = np.array([[-1.0j]]); c = np.zeros((1, 2))
>>> # y = Re(-i e^((-1+2i)t)) = e^-t sin 2t: first zero at pi/2, maximum at atan(2)/2
>>> found, lo, hi, guess, low = march(p, r, c, 0, 1, 0.1, 4096, False)
>>> bool(found and lo < np.pi / 2 <= hi)
True
>>> s = scratch()
>>> t, y = maximum(p, r, c, 0, 1, np.pi / 2, 0.3, s)
>>> round(t, 12) == round(np.arctan(2) / 2, 12)
True
"""

from __future__ import annotations

import cmath
import math

import numpy as np

from designlab.impact.kernel_modal import (
    cell_bound,
    curvature,
    grid,
    jerk,
    newton,
    noise,
    shape,
    triple,
    value,
)
from designlab.sx.jit import kernel

__all__ = ["crossing", "lobe_end", "march", "maximum", "scratch"]

LOW_FRACTION = 0.05
PARTS = 16
MAX_CELLS = 4096
_STACK = 200


@kernel
def scratch():  # type: ignore[no-untyped-def]
    """Work arrays of one block: node times, y, y', y'' and the cell stack."""
    n = MAX_CELLS + 2
    return np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty((_STACK, 9))


@kernel
def march(p, r, c, o, nk, h, max_steps, diag):  # type: ignore[no-untyped-def]
    """March ``t_j = j h`` to the first node (t > 0) where output ``o`` is provably <= 0.

    Returns ``(found, lo, hi, guess, t_low)``: the bracket ``[hi - h, hi]``, a
    secant guess of the crossing and (``diag``) the first node where y fell below
    :data:`LOW_FRACTION` of its running peak.
    """
    last = (max_steps // 12) * 12 + 11
    peak = 0.0
    y_prev = 0.0
    t_low = np.nan
    zs = np.empty(nk, dtype=np.complex128)
    es = np.empty(nk, dtype=np.complex128)
    for k in range(nk):
        zs[k] = cmath.exp(p[k] * h)
        es[k] = r[o, k]
    for j in range(last + 1):
        t = j * h
        y = c[o, 0] * t + c[o, 1]
        for k in range(nk):
            y += es[k].real
            es[k] = es[k] * zs[k]
        if t > 0 and y <= 0:
            yd = value(p, r, c, o, nk, t)
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


@kernel
def _below(p, r, c, o, nk, t, y):  # type: ignore[no-untyped-def]
    """Whether ``y = y(t)`` is provably <= 0."""
    return y <= 0 and y < -noise(p, r, c, o, nk, t)


@kernel
def _push_grid(stack, ts, ys, ds, qs, j):  # type: ignore[no-untyped-def]
    stack[0, 0], stack[0, 1], stack[0, 2], stack[0, 3] = ts[j], ts[j + 1], ys[j], ys[j + 1]
    stack[0, 4], stack[0, 5], stack[0, 6], stack[0, 7] = ds[j], ds[j + 1], qs[j], qs[j + 1]
    stack[0, 8] = 0.0
    return 1


@kernel
def _split(p, r, c, o, nk, stack, n):  # type: ignore[no-untyped-def]
    """Replace the cell ``stack[n]`` by its PARTS sub-cells (earliest on top); new size."""
    tl, tr, level = stack[n, 0], stack[n, 1], stack[n, 8] + 1.0
    yl, dl, ql = stack[n, 2], stack[n, 4], stack[n, 6]
    yr, dr, qr = stack[n, 3], stack[n, 5], stack[n, 7]
    for i in range(PARTS):
        row = n + PARTS - 1 - i
        a = tl + (tr - tl) * (i / PARTS)
        if i == PARTS - 1:
            b, y, d, q = tr, yr, dr, qr
        else:
            b = tl + (tr - tl) * ((i + 1) / PARTS)
            y, d, q = triple(p, r, c, o, nk, b)
        stack[row, 0], stack[row, 1], stack[row, 8] = a, b, level
        stack[row, 2], stack[row, 4], stack[row, 6] = yl, dl, ql
        stack[row, 3], stack[row, 5], stack[row, 7] = y, d, q
        yl, dl, ql = y, d, q
    return n + PARTS


@kernel
def crossing(p, r, c, o, nk, hi, h, levels, work):  # type: ignore[no-untyped-def]
    """Bracket ``(lo, hi)`` of the first provable zero of output ``o`` in ``(0, hi]``.

    :func:`designlab.impact.modal.certified_first_crossing`, depth first over
    cells of width <= h in time order: a local minimum between positive nodes is
    solved by Newton on -y'; a cell that may dip to zero otherwise is split.
    """
    ts, ys, ds, qs, stack = work
    count = min(max(int(math.ceil(hi / h)), 1), MAX_CELLS)  # noqa: RUF046 (numba)
    grid(p, r, c, o, nk, 0.0, hi, count, ts, ys, ds, qs)
    lo_b = ts[count - 1]
    hi_b = hi
    for j in range(count):
        n = _push_grid(stack, ts, ys, ds, qs, j)
        while n > 0:
            n -= 1
            tl, tr, yl, yr = stack[n, 0], stack[n, 1], stack[n, 2], stack[n, 3]
            dl, dr = stack[n, 4], stack[n, 5]
            if tl >= hi_b:
                continue
            if yl > 0 and tr < hi_b and _below(p, r, c, o, nk, tr, yr):
                lo_b, hi_b = tl, tr
            if not (yl > 0 and yr > 0):
                continue
            if dl < 0 and dr >= 0:
                tm = newton(p, r, c, o, nk, tl, tr, 1, -1.0, 60, 1e-13, 0.5 * (tl + tr))
                if tm < hi_b and _below(p, r, c, o, nk, tm, value(p, r, c, o, nk, tm)):
                    lo_b, hi_b = tl, tm
            w = tr - tl
            if stack[n, 8] >= levels or (
                dl * dr > 0 and abs(dl + dr) > curvature(p, r, o, nk, tl, tr) * w
            ):
                continue  # y monotone between positive ends
            sh = shape(stack[n, 6], stack[n, 7], jerk(p, r, o, nk, tl, tr), w)
            if sh != 0:
                continue  # y' monotone: its one minimum, if any, was solved above
            if min(yl, yr) - curvature(p, r, o, nk, tl, tr) * w * w / 8.0 > 0:
                continue
            n = _split(p, r, c, o, nk, stack, n)
    return lo_b, hi_b


@kernel
def lobe_end(p, r, c, o, nk, h, max_steps, diag, work):  # type: ignore[no-untyped-def]
    """``(t_imp, t_low)`` of output ``o`` (a_h): NaN t_imp when no provable lobe end."""
    found, _lo, hi, guess, t_low = march(p, r, c, o, nk, h, max_steps, diag)
    if not found:
        return np.nan, t_low
    lo_c, hi_c = crossing(p, r, c, o, nk, hi, h, 6, work)
    g = 0.5 * (lo_c + hi_c) if hi_c < hi else guess
    return newton(p, r, c, o, nk, lo_c, hi_c, 0, 1.0, 60, 1e-11, g), t_low


@kernel
def maximum(p, r, c, o, nk, hi, w, work):  # type: ignore[no-untyped-def]
    """``(t, y)`` maximum of output ``o`` over ``[0, hi]``, certified to 1e-8 (relative).

    :func:`designlab.impact.modal.certified_maximum` depth first: cells of width
    <= w; every node and every stationary maximum (Newton on y') is a candidate.
    """
    ts, ys, ds, qs, stack = work
    count = min(max(int(math.ceil(hi / w)), 1), MAX_CELLS)  # noqa: RUF046 (numba)
    grid(p, r, c, o, nk, 0.0, hi, count, ts, ys, ds, qs)
    bt, by = 0.0, -np.inf
    for j in range(count + 1):
        if ys[j] > by:
            bt, by = ts[j], ys[j]
    for j in range(count):
        if ds[j] > 0 and ds[j + 1] <= 0:
            t = newton(
                p, r, c, o, nk, ts[j], ts[j + 1], 1, 1.0, 60, 1e-13, 0.5 * (ts[j] + ts[j + 1])
            )
            y = value(p, r, c, o, nk, t)
            if y > by:
                bt, by = t, y
    for j in range(count):
        if not (ds[j] > 0 and ds[j + 1] <= 0):
            _push_grid(stack, ts, ys, ds, qs, j)
            bt, by = _refine(p, r, c, o, nk, bt, by, stack)
    return bt, by


@kernel
def _refine(p, r, c, o, nk, bt, by, stack):  # type: ignore[no-untyped-def]
    """Branch and bound inside the cell ``stack[0]`` (no +/- sign change of y' at its ends)."""
    n = 1
    first = True
    while n > 0:
        n -= 1
        tl, tr, yl, yr = stack[n, 0], stack[n, 1], stack[n, 2], stack[n, 3]
        dl, dr = stack[n, 4], stack[n, 5]
        if not first:
            if yl > by:
                bt, by = tl, yl
            if dl > 0 and dr <= 0:
                t = newton(p, r, c, o, nk, tl, tr, 1, 1.0, 60, 1e-13, 0.5 * (tl + tr))
                y = value(p, r, c, o, nk, t)
                if y > by:
                    bt, by = t, y
                continue
        first = False
        w = tr - tl
        if stack[n, 8] >= 8 or w <= 0:
            continue
        m = curvature(p, r, o, nk, tl, tr)
        if dl * dr > 0 and abs(dl + dr) > m * w:
            continue  # y' keeps its sign: the maximum is at an end node
        if shape(stack[n, 6], stack[n, 7], jerk(p, r, o, nk, tl, tr), w) != 0:
            continue  # y' monotone without a +/- change: the maximum is at an end node
        if cell_bound(yl, yr, dl, dr, w, m) > by + 1e-8 * max(abs(by), 1e-300):
            n = _split(p, r, c, o, nk, stack, n)
    return bt, by
