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

__all__ = ["ModalResponse", "first_crossing", "poles_of", "refine_extremum"]

_SEPARATION = 1e-6


def poles_of(den: NDArray[np.float64]) -> NDArray[np.complex128]:
    """Roots of monic polynomials ``den`` ``(N, n+1)`` (descending), as ``(N, n)``.

    Roots closer than a relative 1e-6 are moved apart symmetrically so that
    partial fractions stay finite.
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


def _fold_plan(poles: NDArray[np.complex128]) -> tuple[NDArray, NDArray, NDArray, int]:
    """Order, weights and drop mask that fold conjugate pairs (see :func:`_fold`)."""
    drop = poles.imag < 0
    weight = np.where(poles.imag > 0, 2.0, 1.0)
    order = np.argsort(drop, axis=1, kind="stable")
    drop_sorted = np.take_along_axis(drop, order, axis=1)
    keep = int((~drop_sorted).sum(axis=1).max()) if poles.shape[1] else 0
    return order, weight, drop_sorted, keep


def _fold(
    poles: NDArray[np.complex128],
    residues: NDArray[np.complex128],
    plan: tuple[NDArray, NDArray, NDArray, int],
) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Keep one pole of each conjugate pair with a doubled residue.

    For a real response, ``r e^(pt) + conj(r) e^(conj(p) t) = Re(2 r e^(pt))``, so
    the real part of the folded sum is the response at half the cost. Real poles
    keep their residue. Dropped entries are moved to the end and the columns
    no design needs are cut off.
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
    """

    poles: NDArray[np.complex128]
    residues: NDArray[np.complex128]
    poly: NDArray[np.float64]

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
        plan = _fold_plan(poles)
        out = {}
        for name, num in nums.items():
            num = np.atleast_2d(np.asarray(num, dtype=float))
            if n:
                residues = _polyval(num, poles) * scale
            else:
                residues = np.zeros((num.shape[0], 0), dtype=complex)
            p_f, r_f = _fold(poles, residues, plan)
            # Taylor coefficients of N/D at s = 0 (ascending), first m of them
            na = num[:, ::-1]
            rho = np.zeros((num.shape[0], m))
            for lag in range(m):
                acc = na[:, lag].copy() if lag < na.shape[1] else np.zeros(num.shape[0])
                for k in range(1, lag + 1):
                    if k < da.shape[1]:
                        acc -= da[:, k] * rho[:, lag - k]
                rho[:, lag] = acc / da[:, 0]
            # rho_l s^l / s^m -> rho_l t^(m-1-l)/(m-1-l)!, descending powers of t
            poly = np.stack([rho[:, lag] / factorial(m - 1 - lag) for lag in range(m)], axis=1)
            out[name] = cls(p_f, r_f, poly)
        return out

    @property
    def batch_size(self) -> int:
        """Number of responses in the batch."""
        return self.poles.shape[0]

    def take(self, index: NDArray) -> ModalResponse:
        """Sub-batch."""
        return ModalResponse(self.poles[index], self.residues[index], self.poly[index])

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
    """Root of ``y`` in ``[lo, hi]`` with ``y(lo) > 0 >= y(hi)``, per response."""
    return _safeguarded_newton(resp, lo, hi, 0, iterations, rtol, guess)


def refine_extremum(
    resp: ModalResponse,
    lo: NDArray,
    hi: NDArray,
    iterations: int = 60,
    rtol: float = 1e-11,
    guess: NDArray | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Maximum of ``y`` on ``[lo, hi]``, per response.

    Where ``y'`` goes from + to - inside the bracket, Newton on ``y'`` finds the
    stationary point; otherwise the better end point is returned.
    """
    lo = np.asarray(lo, dtype=float)
    hi = np.asarray(hi, dtype=float)
    y_lo, d_lo = point_values(resp, lo, (0, 1))
    y_hi, d_hi = point_values(resp, hi, (0, 1))
    t_end = np.where(y_lo >= y_hi, lo, hi)
    y_end = np.maximum(y_lo, y_hi)
    bracketed = (d_lo > 0) & (d_hi <= 0)
    t = t_end.copy()
    y = y_end.copy()
    idx = np.flatnonzero(bracketed)
    if idx.size:
        sub = resp.take(idx)
        g = None if guess is None else np.asarray(guess, dtype=float)[idx]
        ts = _safeguarded_newton(sub, lo[idx], hi[idx], 1, iterations, rtol, g)
        (ys,) = point_values(sub, ts, (0,))
        better = ys >= y_end[idx]
        t[idx] = np.where(better, ts, t_end[idx])
        y[idx] = np.where(better, ys, y_end[idx])
    return t, y
