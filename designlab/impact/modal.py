"""Exact, vectorised time responses of rational transfer functions.

A response ``Y(s) = N(s) / (s^m D(s))`` (``D`` monic of degree ``n``, ``D(0) != 0``,
``deg N < m + n``) has the exact inverse Laplace transform::

    y(t) = sum_{l<m} rho_l t^(m-1-l) / (m-1-l)!  +  sum_i r_i exp(p_i t)
    r_i  = N(p_i) / (p_i^m D'(p_i)),     N(s)/D(s) = sum_l rho_l s^l  (Taylor at 0)

This module evaluates such responses for ``N`` designs at once (numpy
broadcasting over a leading batch axis) and locates first zero crossings and
maxima by safeguarded Newton iterations on the closed form. It contains no
physics: the polynomials come from :mod:`designlab.impact.model`.

Nearly repeated poles (critical damping coincidences) are separated by a
relative ``1e-6`` before the residues are formed, which changes the response by
about that relative amount instead of dividing by zero.

Examples
--------
>>> import numpy as np
>>> # y(t) = L^-1[ 1 / (s (s + 1)) ] = 1 - exp(-t)
>>> r = ModalResponse.from_polynomials(np.array([[1.0]]), np.array([[1.0, 1.0]]), 1)
>>> np.round(r.evaluate(np.array([0.0, 1.0])), 6)
array([[0.      , 0.632121]])
"""

from __future__ import annotations

from dataclasses import dataclass
from math import factorial

import numpy as np
from numpy.typing import NDArray

from designlab.impact.kernel_modal import NOISE, ROUNDING

__all__ = [
    "ModalResponse",
    "certified_first_crossing",
    "certified_maximum",
    "first_crossing",
    "fold_conjugates",
    "fold_plan",
    "poles_of",
    "residue_error_bounds",
]

_SEPARATION = 1e-6


def poles_of(den: NDArray[np.float64]) -> NDArray[np.complex128]:
    """Roots of monic polynomials ``den`` ``(N, n+1)`` (descending), as ``(N, n)``.

    Roots closer than a relative 1e-6 are moved apart symmetrically so that
    partial fractions stay finite.

    Parameters
    ----------
    den
        ``(N, n+1)`` monic polynomial coefficients, highest power first.
    """
    den = np.atleast_2d(den)
    n = den.shape[1] - 1
    if n == 0:
        return np.zeros((den.shape[0], 0), dtype=complex)
    comp = np.zeros((den.shape[0], n, n))
    comp[:, 0, :] = -den[:, 1:] / den[:, :1]
    if n > 1:
        idx = np.arange(n - 1)
        comp[:, idx + 1, idx] = 1.0
    poles = np.linalg.eigvals(comp).astype(complex)
    # separate nearly coincident roots
    scale = np.maximum(np.abs(poles).max(axis=1, keepdims=True), 1e-300)
    for i in range(n):
        for j in range(i + 1, n):
            gap = np.abs(poles[:, i] - poles[:, j])
            close = gap < _SEPARATION * scale[:, 0]
            if np.any(close):
                mid = 0.5 * (poles[close, i] + poles[close, j])
                d = _SEPARATION * scale[close, 0]
                poles[close, i] = mid - d
                poles[close, j] = mid + d
    return poles


def residue_error_bounds(
    den: NDArray[np.float64],
    num: NDArray[np.float64],
    poles: NDArray[np.complex128],
    residues: NDArray[np.complex128],
    m: int,
) -> NDArray[np.float64]:
    """Bounds of the residues' errors and of their poles' errors, ``(N, n, 2)``.

    The bound of :func:`designlab.impact.kernel_modal.residue_errors`, vectorised
    over designs and poles (residues ``N(p_i) / (p_i^m D'(p_i))`` of ``N / (s^m D)``):
    column 0 the error of ``r_i``, column 1 ``|r_i|`` times the error of ``p_i``
    (how far its term drifts per unit time); inf where the poles are too close for a
    first-order bound.

    Parameters
    ----------
    den
        ``(N, n+1)`` monic denominators, descending.
    num
        ``(N, k)`` numerators, descending.
    poles
        ``(N, n)`` roots of ``den`` (unfolded).
    residues
        ``(N, n)`` their residues.
    m
        Order of the pole at the origin.
    """
    n = poles.shape[1]
    ax = np.abs(poles)
    diff = poles[:, :, None] - poles[:, None, :]
    idx = np.arange(n)
    diff[:, idx, idx] = 1.0
    dprime = np.abs(diff.prod(axis=2))
    size_d = _polyval(np.abs(den), ax)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        delta = (np.abs(_polyval(den, poles)) + ROUNDING * size_d) / dprime
        gap = np.abs(diff)
        gap[:, idx, idx] = np.inf
        sep = ((delta[:, :, None] + delta[:, None, :]) / gap).sum(axis=2)
        size_n = _polyval(np.abs(num), ax)
        dnum = num[:, :-1] * np.arange(num.shape[1] - 1, 0, -1)[None, :]
        slope = np.abs(_polyval(dnum, poles)) + ROUNDING * size_n / ax
        a = np.abs(residues)
        scale = 1.0 / (ax**m * dprime)
        err = scale * (ROUNDING * size_n + slope * delta) + a * (sep + m * delta / ax)
        out = np.stack([2.0 * (err + a * ROUNDING), 2.0 * a * delta], axis=2)
    out[~(sep <= 0.1)] = np.inf
    return out


def fold_plan(poles: NDArray[np.complex128]) -> tuple[NDArray, NDArray, NDArray, int]:
    """Order, weights and drop mask that fold conjugate pairs (see :func:`fold_conjugates`).

    Parameters
    ----------
    poles
        ``(N, n)`` poles of each design.

    Returns
    -------
    tuple
        ``(order, weight, drop, keep)``: the column order putting dropped poles
        last, the residue weights (2 for a pole with a conjugate), the dropped
        entries in that order and the number of columns kept.
    """
    drop = poles.imag < 0
    weight = np.where(poles.imag > 0, 2.0, 1.0)
    order = np.argsort(drop, axis=1, kind="stable")
    drop_sorted = np.take_along_axis(drop, order, axis=1)
    keep = int((~drop_sorted).sum(axis=1).max()) if poles.shape[1] else 0
    return order, weight, drop_sorted, keep


def fold_conjugates(
    poles: NDArray[np.complex128],
    residues: NDArray[np.complex128],
    plan: tuple[NDArray, NDArray, NDArray, int],
) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Keep one pole of each conjugate pair with a doubled residue.

    For a real response, ``r e^(pt) + conj(r) e^(conj(p) t) = Re(2 r e^(pt))``, so
    the real part of the folded sum is the response at half the cost. Real poles
    keep their residue. Dropped entries are moved to the end and the columns
    no design needs are cut off.

    Parameters
    ----------
    poles, residues
        ``(N, n)`` poles and their residues.
    plan
        :func:`fold_plan` of ``poles``.

    Returns
    -------
    tuple
        The kept poles and their (doubled) residues.
    """
    order, weight, drop, keep = plan
    p = np.take_along_axis(poles, order, axis=1)[:, :keep]
    r = np.take_along_axis(residues * weight, order, axis=1)
    r = np.where(drop, 0.0, r)[:, :keep]
    return p, r


def _polyval(coeffs: NDArray, x: NDArray) -> NDArray:
    """Horner evaluation, ``coeffs`` ``(N, k)`` descending, ``x`` ``(N, ...)``."""
    out = np.zeros(x.shape, dtype=np.result_type(coeffs, x))
    extra = (slice(None),) + (None,) * (x.ndim - 1)
    for k in range(coeffs.shape[1]):
        out = out * x + coeffs[:, k][extra]
    return out


@dataclass(frozen=True)
class ModalResponse:
    """``y(t) = poly(t) + Re sum_i r_i exp(p_i t)`` for a batch of ``N`` responses.

    Attributes
    ----------
    poles, residues
        ``(N, n)`` complex; one pole per conjugate pair, with a doubled residue
        (unused slots have a zero residue).
    poly
        ``(N, m)`` real coefficients of the polynomial part in descending powers of t.
    errors
        ``(N, n, 2)`` bounds of each residue's error and of its pole's error times
        ``|r_i|`` (:func:`residue_error_bounds`; inf where the poles are too close for
        them), or None where unknown (responses built elsewhere).
    """

    poles: NDArray[np.complex128]
    residues: NDArray[np.complex128]
    poly: NDArray[np.float64]
    errors: NDArray[np.float64] | None = None

    @classmethod
    def from_polynomials(
        cls,
        num: NDArray[np.float64],
        den: NDArray[np.float64],
        m: int,
        poles: NDArray[np.complex128] | None = None,
    ) -> ModalResponse:
        """Build the response of ``N(s) / (s^m D(s))``.

        Parameters
        ----------
        num
            ``(N, k)`` numerator coefficients, descending powers.
        den
            ``(N, n+1)`` monic denominator, descending powers, ``D(0) != 0``.
        m
            Order of the pole at the origin contributed by the input (2 for a ramp).
        poles
            Roots of ``den`` if already known (from :func:`poles_of`).
        """
        return cls.family({"y": num}, den, m, poles)["y"]

    @classmethod
    def family(
        cls,
        nums: dict[str, NDArray[np.float64]],
        den: NDArray[np.float64],
        m: int,
        poles: NDArray[np.complex128] | None = None,
    ) -> dict[str, ModalResponse]:
        """Responses of several numerators over one denominator (shared poles)."""
        den = np.atleast_2d(np.asarray(den, dtype=float))
        if poles is None:
            poles = poles_of(den)
        n = poles.shape[1]
        if n:
            # D'(p_i) from the (separated) roots, consistent with them
            diff = poles[:, :, None] - poles[:, None, :]
            diff[:, np.arange(n), np.arange(n)] = 1.0
            scale = 1.0 / (poles**m * diff.prod(axis=2))
        da = den[:, ::-1]
        plan = fold_plan(poles)
        out = {}
        for name, num in nums.items():
            num = np.atleast_2d(np.asarray(num, dtype=float))
            if n:
                residues = _polyval(num, poles) * scale
                err = residue_error_bounds(den, num, poles, residues, m)
                with np.errstate(invalid="ignore"):  # an unbounded error (inf) times 0
                    _, e0 = fold_conjugates(poles, err[..., 0].astype(complex), plan)
                    _, e1 = fold_conjugates(poles, err[..., 1].astype(complex), plan)
                errors = np.stack([e0.real, e1.real], axis=2)
                errors[np.isnan(errors)] = np.inf  # unbounded stays unbounded, never NaN
            else:
                residues = np.zeros((num.shape[0], 0), dtype=complex)
                errors = np.zeros((num.shape[0], 0, 2))
            p_f, r_f = fold_conjugates(poles, residues, plan)
            # Taylor coefficients of N/D at s = 0 (ascending), first m of them
            na = num[:, ::-1]
            rho = np.zeros((num.shape[0], m))
            for lag in range(m):
                acc = na[:, lag].copy() if lag < na.shape[1] else np.zeros(num.shape[0])
                for k in range(1, lag + 1):
                    if k < da.shape[1]:
                        acc -= da[:, k] * rho[:, lag - k]
                with np.errstate(divide="ignore", invalid="ignore"):  # D(0) = 0: no restoring
                    rho[:, lag] = acc / da[:, 0]  # stiffness, refused by the caller (ModelError)
            # rho_l s^l / s^m -> rho_l t^(m-1-l)/(m-1-l)!, descending powers of t
            poly = np.stack([rho[:, lag] / factorial(m - 1 - lag) for lag in range(m)], axis=1)
            out[name] = cls(p_f, r_f, poly, errors)
        return out

    @property
    def batch_size(self) -> int:
        """Number of responses in the batch."""
        return self.poles.shape[0]

    def take(self, index: NDArray) -> ModalResponse:
        """Sub-batch."""
        errors = None if self.errors is None else self.errors[index]
        return ModalResponse(self.poles[index], self.residues[index], self.poly[index], errors)

    def noise(self, t: NDArray) -> NDArray[np.float64]:
        """Rounding-noise level of ``y`` at ``t`` (``(N,)`` or ``(N, T)``): as the kernel's
        (:func:`designlab.impact.kernel_modal.noise`), ``NOISE`` times the sum of the
        terms' magnitudes plus the residues' and poles' error bounds carried to ``t``
        (without bounds, every residue counted as large as the largest)."""
        t = np.asarray(t, dtype=float)
        flat = t.ndim == 1
        tt = t[:, None] if flat else t
        g = np.exp(self.poles.real[:, :, None] * tt[:, None, :])
        a = np.abs(self.residues)
        if self.errors is None:
            a = np.broadcast_to(a.max(axis=1, initial=0.0)[:, None], a.shape)
            extra = 0.0
        else:
            e = self.errors
            extra = ((e[:, :, 0, None] + e[:, :, 1, None] * tt[:, None, :]) * g).sum(axis=1)
        out = NOISE * ((a[:, :, None] * g).sum(axis=1) + np.abs(_poly_part(self.poly, tt, 0)))
        out = out + extra
        return out[:, 0] if flat else out

    @staticmethod
    def evaluate_family(
        family: dict[str, ModalResponse], t: NDArray, derivative: int = 0
    ) -> dict[str, NDArray[np.float64]]:
        """Evaluate responses that share their poles (one :meth:`family`) at once.

        The exponentials are computed once for all of them. ``t`` as in :meth:`evaluate`.
        """
        first = next(iter(family.values()))
        t = np.asarray(t, dtype=float)
        if t.ndim == 1:
            t = np.broadcast_to(t, (first.batch_size, t.shape[0]))
        out = {}
        e = None
        for name, r in family.items():
            if r.poles.shape != first.poles.shape or not np.array_equal(r.poles, first.poles):
                out.update(ModalResponse.evaluate_family({name: r}, t, derivative))
                continue
            if e is None:
                e = np.exp(first.poles[:, :, None] * t[:, None, :])
            coef = r.residues * r.poles**derivative if derivative else r.residues
            out[name] = np.real(np.einsum("nk,nkt->nt", coef, e)) + _poly_part(
                r.poly, t, derivative
            )
        return out

    def evaluate(self, t: NDArray, derivative: int = 0) -> NDArray[np.float64]:
        """Evaluate ``d^k y / dt^k`` at times ``t``.

        ``t`` is ``(T,)`` (same times for every response) or ``(N, T)``.
        Returns ``(N, T)``.
        """
        t = np.asarray(t, dtype=float)
        if t.ndim == 1:
            t = np.broadcast_to(t, (self.batch_size, t.shape[0]))
        return ModalResponse.evaluate_family({"y": self}, t, derivative)["y"]


def _poly_part(poly: NDArray, t: NDArray, derivative: int) -> NDArray:
    m = poly.shape[1]
    out = np.zeros(t.shape)
    for idx in range(m):
        power = m - 1 - idx
        if power - derivative < 0:
            continue
        fac = factorial(power) / factorial(power - derivative)
        out = out + (poly[:, idx] * fac)[:, None] * t ** (power - derivative)
    return out


def point_values(
    resp: ModalResponse, t: NDArray, derivatives: tuple[int, ...] = (0,)
) -> list[NDArray[np.float64]]:
    """Values of ``resp`` (batch ``N``) at one time per response ``t`` ``(N,)``.

    Returns one ``(N,)`` array per requested derivative order.
    """
    # hot path of the Newton iterations: 1-D arrays, no temporaries beyond need
    e = np.exp(resp.poles * t[:, None])
    m = resp.poly.shape[1]
    out = []
    for d in derivatives:
        coef = resp.residues * resp.poles**d if d else resp.residues
        val = np.real((coef * e).sum(axis=1))
        for idx in range(m - d):
            power = m - 1 - idx
            val = val + resp.poly[:, idx] * (factorial(power) / factorial(power - d)) * t ** (
                power - d
            )
        out.append(val)
    return out


def _safeguarded_newton(
    resp: ModalResponse,
    lo: NDArray,
    hi: NDArray,
    order: int,
    iterations: int,
    rtol: float,
    guess: NDArray | None = None,
) -> NDArray[np.float64]:
    """Root of the ``order``-th derivative of ``resp`` with ``+`` at ``lo`` and ``-`` at ``hi``.

    Newton steps that leave the bracket become bisections; converged responses
    leave the active set, so the cost follows the slowest few only.
    """
    lo = np.asarray(lo, dtype=float).copy()
    hi = np.asarray(hi, dtype=float).copy()
    t = 0.5 * (lo + hi) if guess is None else np.clip(guess, lo, hi)
    act = np.arange(t.shape[0])
    sub = resp
    for _ in range(iterations):
        if act.size == 0:
            break
        ta, la, ha = t[act], lo[act], hi[act]
        y, dy = point_values(sub, ta, (order, order + 1))
        pos = y > 0
        la = np.where(pos, ta, la)
        ha = np.where(pos, ha, ta)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            tn = ta - y / dy
        tol = rtol * np.abs(ta) + 1e-300
        done = (np.abs(tn - ta) <= tol) | (ha - la <= tol) | (y == 0)
        bad = ~done & (~np.isfinite(tn) | (tn <= la) | (tn >= ha))
        tn = np.where(bad, 0.5 * (la + ha), tn)
        tn = np.where(done & ~np.isfinite(tn), ta, tn)
        t[act], lo[act], hi[act] = tn, la, ha
        keep = ~done
        act = act[keep]
        sub = sub.take(keep)
    return t


def first_crossing(
    resp: ModalResponse,
    lo: NDArray,
    hi: NDArray,
    iterations: int = 60,
    rtol: float = 1e-11,
    guess: NDArray | None = None,
) -> NDArray[np.float64]:
    """Root of ``y`` in ``[lo, hi]`` with ``y(lo) > 0 >= y(hi)``, per response.

    Parameters
    ----------
    resp
        Responses of N designs.
    lo
        ``(N,)`` bracket starts in s (``y > 0``).
    hi
        ``(N,)`` bracket ends in s (``y <= 0``).
    iterations
        Most safeguarded Newton / bisection steps.
    rtol
        Relative tolerance on the root.
    guess
        Optional ``(N,)`` starting points inside the brackets.
    """
    return _safeguarded_newton(resp, lo, hi, 0, iterations, rtol, guess)


def _curvature_bound(resp: ModalResponse, tl: NDArray, tr: NDArray) -> NDArray[np.float64]:
    """Upper bound of ``|y''(t)|`` over ``[tl, tr]`` per response (triangle inequality).

    ``|Re sum r_i p_i^2 e^(p_i t)| <= sum |r_i| |p_i|^2 e^(Re p_i t)`` and each
    exponential is largest at one end of the cell; the polynomial part's second
    derivative is at most linear (``m <= 4``), so it is largest at an end too.
    """
    w = np.abs(resp.residues) * np.abs(resp.poles) ** 2
    re = resp.poles.real
    grow = np.maximum(re * tl[:, None], re * tr[:, None])
    with np.errstate(over="ignore"):
        bound = (w * np.exp(grow)).sum(axis=1)
    m = resp.poly.shape[1]
    if m >= 3:
        if m > 4:  # pragma: no cover - the impact responses have m <= 3
            raise ValueError("curvature bound needs a polynomial part of degree <= 3")
        ends = [np.zeros(tl.shape), np.zeros(tl.shape)]
        for j, t in enumerate((tl, tr)):
            for idx in range(m - 2):
                power = m - 1 - idx
                ends[j] = ends[j] + resp.poly[:, idx] * (power * (power - 1)) * t ** (power - 2)
        bound = bound + np.maximum(np.abs(ends[0]), np.abs(ends[1]))
    return bound


def _grid_values(
    resp: ModalResponse, t: NDArray
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``y`` and ``y'`` of each response (batch ``N``) at its own times ``t`` ``(N, T)``."""
    e = np.exp(resp.poles[:, :, None] * t[:, None, :])
    y = np.real(np.einsum("nk,nkt->nt", resp.residues, e))
    dy = np.real(np.einsum("nk,nkt->nt", resp.residues * resp.poles, e))
    m = resp.poly.shape[1]
    for idx in range(m):
        power = m - 1 - idx
        c = resp.poly[:, idx][:, None]
        y = y + c * t**power
        if power >= 1:
            dy = dy + c * power * t ** (power - 1)
    return y, dy


def _evaluate_nodes(
    resp: ModalResponse, rows: NDArray, t: NDArray, chunk: int = 65536
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``y`` and ``y'`` of responses ``rows`` at times ``t`` (flat, paired), in chunks."""
    y = np.empty(t.shape)
    dy = np.empty(t.shape)
    for s in range(0, t.size, chunk):
        sl = slice(s, s + chunk)
        y[sl], dy[sl] = point_values(resp.take(rows[sl]), t[sl], (0, 1))
    return y, dy


@dataclass(frozen=True)
class _Cells:
    """Flat list of cells ``[tl, tr]`` of responses ``row`` with end values and slopes."""

    row: NDArray[np.intp]
    tl: NDArray[np.float64]
    tr: NDArray[np.float64]
    yl: NDArray[np.float64]
    yr: NDArray[np.float64]
    dl: NDArray[np.float64]
    dr: NDArray[np.float64]

    def take(self, keep: NDArray) -> _Cells:
        return _Cells(
            *(getattr(self, f)[keep] for f in ("row", "tl", "tr", "yl", "yr", "dl", "dr"))
        )

    def split(self, resp: ModalResponse, parts: int) -> tuple[_Cells, NDArray, NDArray, NDArray]:
        """Split every cell into ``parts`` equal cells; also return the new interior nodes."""
        n = self.row.size
        frac = np.arange(parts + 1) / parts
        t = self.tl[:, None] + (self.tr - self.tl)[:, None] * frac[None, :]
        t[:, -1] = self.tr
        rows = np.repeat(self.row, parts - 1)
        y = np.empty((n, parts + 1))
        d = np.empty((n, parts + 1))
        y[:, 0], y[:, -1], d[:, 0], d[:, -1] = self.yl, self.yr, self.dl, self.dr
        chunk = max(1, 65536 // max(parts - 1, 1))
        for s0 in range(0, n, chunk):
            sl = slice(s0, s0 + chunk)
            y[sl, 1:-1], d[sl, 1:-1] = _grid_values(resp.take(self.row[sl]), t[sl, 1:-1])
        ti = t[:, 1:-1].ravel()
        yi = y[:, 1:-1].ravel()
        cells = _Cells(
            np.repeat(self.row, parts),
            t[:, :-1].ravel(),
            t[:, 1:].ravel(),
            y[:, :-1].ravel(),
            y[:, 1:].ravel(),
            d[:, :-1].ravel(),
            d[:, 1:].ravel(),
        )
        return cells, rows, ti, yi


def _grid_cells(
    resp: ModalResponse, lo: NDArray, hi: NDArray, h: NDArray, max_cells: int
) -> _Cells:
    """Uniform cells of width <= ``h`` over ``[lo, hi]`` per response (at least one)."""
    n = lo.size
    with np.errstate(invalid="ignore", divide="ignore"):
        count = np.ceil((hi - lo) / h)
    count = np.clip(np.nan_to_num(count, nan=1.0), 1, max_cells).astype(int)
    width = int(count.max()) + 1 if n else 1
    if n * width > 4 * int(np.sum(count + 1)) + 1024:
        return _grid_cells_flat(resp, lo, hi, count)
    j = np.arange(width)[None, :]
    t = lo[:, None] + (hi - lo)[:, None] * (np.minimum(j, count[:, None]) / count[:, None])
    t[np.arange(n), count] = hi  # the last node exactly at the window end
    y = np.empty((n, width))
    dy = np.empty((n, width))
    chunk = max(1, 65536 // width)
    for s0 in range(0, n, chunk):
        sl = slice(s0, s0 + chunk)
        y[sl], dy[sl] = _grid_values(resp.take(np.arange(s0, min(s0 + chunk, n))), t[sl])
    valid = j[:, :-1] < count[:, None]  # cells [j, j + 1] with j < count
    rows = np.broadcast_to(np.arange(n)[:, None], valid.shape)[valid]
    return _Cells(
        rows,
        t[:, :-1][valid],
        t[:, 1:][valid],
        y[:, :-1][valid],
        y[:, 1:][valid],
        dy[:, :-1][valid],
        dy[:, 1:][valid],
    )


def _grid_cells_flat(resp: ModalResponse, lo: NDArray, hi: NDArray, count: NDArray) -> _Cells:
    """:func:`_grid_cells` for very uneven cell counts (no padding to the largest)."""
    rows = np.repeat(np.arange(lo.size), count + 1)
    start = np.repeat(np.cumsum(count + 1) - (count + 1), count + 1)
    j = np.arange(rows.size) - start
    t = lo[rows] + (hi - lo)[rows] * (j / count[rows])
    last = j == count[rows]
    t[last] = hi[rows[last]]
    y, dy = _evaluate_nodes(resp, rows, t)
    left = ~last
    right = np.roll(left, 1)  # the node after each left node
    return _Cells(rows[left], t[left], t[right], y[left], y[right], dy[left], dy[right])


def _cell_bound(cells: _Cells, curvature: NDArray) -> NDArray[np.float64]:
    """Upper bound of ``y`` over each cell from its end values, end slopes and ``|y''| <= M``.

    ``y(tl + s) <= L(s) = yl + dl s + M s^2 / 2`` and
    ``y(tr - u) <= R(u) = yr - dr u + M u^2 / 2``; the maximum over the cell of
    ``min(L, R)`` is at an end or where ``L = R`` (``L - R`` is linear in s).
    Never above the interpolation bound ``max(yl, yr) + M w^2 / 8``.
    """
    w = cells.tr - cells.tl
    m = curvature
    yl, yr, dl, dr = cells.yl, cells.yr, cells.dl, cells.dr

    def left(x: NDArray) -> NDArray:
        return yl + dl * x + 0.5 * m * x * x

    def right(x: NDArray) -> NDArray:
        u = w - x
        return yr - dr * u + 0.5 * m * u * u

    zero = np.zeros_like(w)
    ends = np.maximum(np.minimum(yl, right(zero)), np.minimum(left(w), yr))
    slope = dl - dr + m * w
    with np.errstate(divide="ignore", invalid="ignore"):
        x = -(yl - yr + dr * w - 0.5 * m * w * w) / slope
    inside = np.isfinite(x) & (x > 0) & (x < w)
    xs = np.where(inside, x, 0.0)
    cross = np.where(inside, np.minimum(left(xs), right(xs)), -np.inf)
    taylor = np.maximum(ends, cross)
    interp = np.maximum(yl, yr) + m * w * w / 8.0
    return np.minimum(taylor, interp)


def _keep_worst(cells: _Cells, score: NDArray, n_rows: int, cap: int) -> NDArray[np.intp]:
    """Indices of the ``cap`` highest-scoring cells of each response."""
    order = np.lexsort((-score, cells.row))
    rows = cells.row[order]
    first = np.searchsorted(rows, rows, side="left")
    rank = np.arange(rows.size) - first
    return np.sort(order[rank < cap])


def certified_maximum(
    resp: ModalResponse,
    lo: NDArray,
    hi: NDArray,
    h: NDArray,
    *,
    rtol: float = 1e-8,
    parts: int = 16,
    levels: int = 8,
    cap: int = 64,
    max_cells: int = 4096,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Maximum of ``y`` over ``[lo, hi]`` per response, and where it is.

    Branch and bound on cells of width ``h``: every cell whose values, slopes
    and curvature bound (:func:`_curvature_bound`) allow a value above the best
    one found by more than ``rtol`` (relative) is split into ``parts`` cells,
    ``levels`` times at most; every cell where ``y'`` changes from + to - is
    also solved by safeguarded Newton on ``y'`` (and split like the others while
    its bound allows a better value: it may hold three stationary points). The
    window ends count. The result is never below the best sampled value; it is
    within ``rtol`` of the exact maximum unless more than ``cap`` cells of a
    response stay open at a level (a loose bound: only the ``cap`` most promising
    are kept).

    Parameters
    ----------
    resp
        Responses of N designs.
    lo
        ``(N,)`` window starts in s.
    hi
        ``(N,)`` window ends in s.
    h
        ``(N,)`` initial cell widths in s.
    rtol
        Relative tolerance of the maximum.
    parts
        Cells a cell is split into.
    levels
        Most splitting levels.
    cap
        Most open cells per response and level.
    max_cells
        Most open cells over all responses at a level.
    """
    lo = np.asarray(lo, dtype=float)
    hi = np.asarray(hi, dtype=float)
    n = lo.size
    best_y = np.full(n, -np.inf)
    best_t = lo.copy()
    cells = _grid_cells(resp, lo, hi, np.asarray(h, dtype=float), max_cells)

    def offer(rows: NDArray, t: NDArray, y: NDArray) -> None:
        if rows.size == 0:
            return
        y = np.where(np.isnan(y), -np.inf, y)
        if rows.size > 1 and np.any(rows[1:] < rows[:-1]):  # pragma: no cover - defensive
            order = np.argsort(rows, kind="stable")
            rows, t, y = rows[order], t[order], y[order]
        start = np.flatnonzero(np.r_[True, rows[1:] != rows[:-1]])
        r = rows[start]
        cand_y = np.maximum.reduceat(y, start)
        at_max = y == np.repeat(cand_y, np.diff(np.r_[start, rows.size]))
        pos = np.arange(rows.size)
        first = np.minimum.reduceat(np.where(at_max, pos, rows.size), start)
        cand_t = t[np.minimum(first, rows.size - 1)]
        better = cand_y > best_y[r]
        best_y[r[better]] = cand_y[better]
        best_t[r[better]] = cand_t[better]

    offer(cells.row, cells.tl, cells.yl)
    offer(cells.row, cells.tr, cells.yr)
    for level in range(levels + 1):
        # stationary maxima inside cells
        sign = np.flatnonzero((cells.dl > 0) & (cells.dr <= 0))
        concave = np.zeros(cells.row.size, dtype=bool)
        if sign.size:
            s = cells.take(sign)
            sub = resp.take(s.row)
            ts = _safeguarded_newton(sub, s.tl, s.tr, 1, 60, 1e-13)
            (ys,) = point_values(sub, ts, (0,))
            offer(s.row, ts, ys)
            concave[sign] = _concave(sub, s.tl, s.tr)
        if level == levels or cells.row.size == 0:
            break
        width = cells.tr - cells.tl
        bound = _cell_bound(cells, _curvature_bound(resp.take(cells.row), cells.tl, cells.tr))
        tol = rtol * np.maximum(np.abs(best_y[cells.row]), 1e-300)
        # a cell with y' from + to - stays in the search too unless y'' < 0 all over it: its
        # Newton solve found one stationary point, and it may hold three (issue 34)
        open_ = np.flatnonzero((bound > best_y[cells.row] + tol) & (width > 0) & ~concave)
        if open_.size == 0:
            break
        cells = cells.take(open_)
        keep = _keep_worst(cells, bound[open_], n, cap)
        cells = cells.take(keep)
        cells, rows, ti, yi = cells.split(resp, parts)
        offer(rows, ti, yi)
    return best_t, best_y


def _concave(resp: ModalResponse, tl: NDArray, tr: NDArray) -> NDArray[np.bool_]:
    """Whether ``y'' < 0`` all over each cell ``[tl, tr]`` (then ``y'`` has one zero there).

    ``y''`` is below both ``y''(tl) + m3 (t - tl)`` and ``y''(tr) + m3 (tr - t)`` with
    ``m3`` a bound of ``|y'''|`` (a polynomial part of degree <= 2 adds none), so it is
    at most ``(y''(tl) + y''(tr) + m3 w) / 2``; that sum must be below minus the rounding
    of the two values (1e-12 of the curvature scale, twice).
    """
    if resp.poly.shape[1] > 3:  # pragma: no cover - the impact responses have m <= 3
        return np.zeros(tl.shape, dtype=bool)
    ddl, ddr = point_values(resp, tl, (2,))[0], point_values(resp, tr, (2,))[0]
    mag = np.abs(resp.residues) * np.abs(resp.poles) ** 2
    re = resp.poles.real
    with np.errstate(over="ignore", invalid="ignore"):
        grow = np.exp(np.maximum(re * tl[:, None], re * tr[:, None]))
        m2 = (mag * grow).sum(axis=1)
        m3 = (mag * np.abs(resp.poles) * grow).sum(axis=1)
        return ddl + ddr + m3 * (tr - tl) + 2e-12 * m2 < 0


def certified_first_crossing(
    resp: ModalResponse,
    hi: NDArray,
    h: NDArray,
    *,
    parts: int = 16,
    levels: int = 6,
    cap: int = 64,
    max_cells: int = 4096,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Bracket of the first ``t > 0`` with ``y(t) <= 0``, given ``y(hi) <= 0``.

    ``y`` is positive on the grid nodes before ``hi`` (the march found no
    earlier crossing) but may dip below zero between two nodes. Cells whose
    curvature bound allows a value <= 0 are split (``levels`` times at most, the
    ``cap`` lowest bounds per response and level), and a cell where ``y'`` goes
    from - to + is checked at its local minimum (Newton on ``y'``). Returns
    ``(lo, hi)`` with ``y(lo) > 0 >= y(hi)`` and no crossing resolved before ``lo``.

    Parameters
    ----------
    resp
        Responses of N designs.
    hi
        ``(N,)`` times in s where ``y <= 0``.
    h
        ``(N,)`` grid steps in s of the march that found ``hi``.
    parts
        Cells a cell is split into.
    levels
        Most splitting levels.
    cap
        Most open cells per response and level.
    max_cells
        Most open cells over all responses at a level.
    """
    hi = np.asarray(hi, dtype=float).copy()
    n = hi.size
    cells = _grid_cells(resp, np.zeros(n), hi, np.asarray(h, dtype=float), max_cells)
    lo_out = np.maximum(hi - np.asarray(h, dtype=float), 0.0)
    # the last cell of each response ends at hi; its left node is the bracket start
    last = np.r_[cells.row[1:] != cells.row[:-1], True]
    lo_out[cells.row[last]] = cells.tl[last]

    def found(rows: NDArray, tl: NDArray, tr: NDArray) -> None:
        """Cells ``[tl, tr]`` with y(tl) > 0 >= y(tr): keep the earliest per response."""
        if rows.size == 0:
            return
        order = np.lexsort((tr, rows))
        r, first = np.unique(rows[order], return_index=True)
        a, b = tl[order][first], tr[order][first]
        earlier = b < hi[r]
        hi[r[earlier]] = b[earlier]
        lo_out[r[earlier]] = a[earlier]

    for level in range(levels + 1):
        live = cells.tl < hi[cells.row]
        cells = cells.take(np.flatnonzero(live))
        if cells.row.size == 0:
            break
        # a crossing between nodes already sampled (after a split): provably <= 0 only
        # below the rounding noise (issue 34)
        cross = (cells.yl > 0) & (cells.yr <= 0)
        if np.any(cross):
            k = np.flatnonzero(cross)
            cross[k] = cells.yr[k] < -resp.take(cells.row[k]).noise(cells.tr[k])
        found(cells.row[cross], cells.tl[cross], cells.tr[cross])
        # local minima between nodes
        dip = (cells.dl < 0) & (cells.dr >= 0) & (cells.yl > 0) & (cells.yr > 0)
        if np.any(dip):
            s = cells.take(np.flatnonzero(dip))
            sub = resp.take(s.row)
            # Newton on -y' (which goes from + to -)
            neg = ModalResponse(sub.poles, -sub.residues, -sub.poly)
            tm = _safeguarded_newton(neg, s.tl, s.tr, 1, 60, 1e-13)
            (ym,) = point_values(sub, tm, (0,))
            below = (ym <= 0) & (ym < -sub.noise(tm))
            if np.any(below):
                # the crossing is in [tl, tm]: y(tl) > 0 >= y(tm)
                rows_b = s.row[below]
                found(rows_b, s.tl[below], tm[below])
        if level == levels:
            break
        width = cells.tr - cells.tl
        bound = (
            np.minimum(cells.yl, cells.yr)
            - _curvature_bound(resp.take(cells.row), cells.tl, cells.tr) * width**2 / 8.0
        )
        open_ = np.flatnonzero(
            (bound <= 0) & (cells.yl > 0) & (cells.yr > 0) & (cells.tl < hi[cells.row])
        )
        if open_.size == 0:
            break
        cells = cells.take(open_)
        cells = cells.take(_keep_worst(cells, -bound[open_], n, cap))
        cells, _, _, _ = cells.split(resp, parts)
    return lo_out, hi
