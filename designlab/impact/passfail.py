"""Pass/fail of a head-acceleration limit without locating the maximum (issue 40.5).

A threshold question ("does this design's a_h,max exceed 10 g?", an envelope boundary,
a speed limit, a sample of an exceedance probability) needs the side of the limit the
first-lobe maximum is on, not the maximum itself. :func:`head_acceleration_exceeds`
decides it from certified bounds of a_h(t) and falls back to the full kernel
(:func:`~designlab.impact.metrics.metrics_of_matrix`) for every design the bounds cannot
decide, so its decisions are the full kernel's:

* the poles and residues are the kernel's own, with its a-posteriori checks
  (:func:`.kernel_poles.roots_certified`, :func:`.kernel_modal.residue_errors`); a design
  that fails them, has an unstable pole or non-finite numbers goes to the full kernel;
* a_h is marched over cells of ``0.8`` over the fastest pole's rate, its value and slope
  at each node by recurrence; over a cell it is bounded above and below by the cubic
  Hermite interpolant's extremum plus ``max|a_h''''| w^4 / 384``
  (:func:`.kernel_modal.hermite_bound`, the kernel's own certificate), widened by the
  rounding noise, the residues' and poles' error bounds and the recurrence's rounding;
* **exceeds**: a node value above the limit by the margin while a_h is provably positive
  from contact to that node (the node lies in the first lobe, whose maximum is then at
  least that value);
* **within**: a node provably below zero (the first lobe has ended before it, within the
  lobe search's horizon) while every cell up to it is bounded below the limit by the margin;
* anything else (the maximum within about 1e-4 of the limit, a lobe not provably closed
  within the horizon, ``v_c <= 0``) goes to the full kernel.

The margin, :data:`MARGIN` of the limit, is far above the kernel's certified tolerance
(1e-8 relative), so a design the bounds decide is on the same side of the limit in the
kernel's numbers: the decisions are the full kernel's wherever it gives a maximum. Where
it gives none (an ``uncertified`` design, NaN) a decision of the bounds is still a
certified one and stands; a design neither decides counts as exceeding
(:attr:`Decisions.unresolved`), as :func:`designlab.codesign.injury_probability` counts it.

Examples
--------
>>> import numpy as np
>>> p = np.array([[9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 0.0, 4e3]])    # a_h,max 6.568 g at 1.25
>>> d = head_acceleration_exceeds(p, 1.25, 6.5)
>>> bool(d.exceeds[0]), bool(d.by_bounds[0])
(True, True)
>>> bool(head_acceleration_exceeds(p, 1.25, 7.0).exceeds[0])
False
"""

from __future__ import annotations

import math
from functools import partial
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError, ModelError
from designlab.impact import kernel
from designlab.impact.kernel import _finite, _head_mode, _lane_roots
from designlab.impact.kernel_exp import cexp
from designlab.impact.kernel_modal import (
    ERR_COLUMNS,
    fastest_rate,
    hermite_bound,
    mag,
    noise,
    real_product,
    residue_errors,
    term_errors,
    value,
)
from designlab.impact.kernel_poles import (
    LANES,
    modal_solution,
    quartic_roots,
    roots_certified,
    separate,
)
from designlab.impact.model import PARAM_NAMES
from designlab.impact.parameters import MAX_LOBE_STEPS, check_closing_velocity
from designlab.sx.jit import kernel as compiled
from designlab.units import STANDARD_GRAVITY
from designlab.validation import real_array
from designlab.workers import WORKERS, map_row_blocks

__all__ = ["A_H_ONLY", "MARGIN", "Decisions", "decisions_of_metrics", "head_acceleration_exceeds"]

#: relative margin around the limit inside which the bounds leave the design to the full
#: kernel (100 times the kernel's certified tolerance of 1e-8)
MARGIN = 1e-6
#: cell width over the kernel's grid step 0.4 / fastest rate (wider cells: fewer nodes,
#: looser bounds; 2 measured fastest in benchmarks/passfail.py)
CELL = 2.0
#: the full kernel's options for a_h alone (what :meth:`.criteria.Criterion.values` asks of
#: it for a head-acceleration limit): the reference of the decisions
A_H_ONLY = {"with_force": False, "with_compression": False}
#: codes of the compiled decision
EXCEEDS, WITHIN, UNDECIDED = 1, 0, -1
#: relative rounding of one step of the exponentials' recurrence (a complex product)
_STEP_ROUNDING = 8.0 * 2.0**-52
#: steps of the recurrence between exponentials evaluated directly
_REFRESH = 32


class Decisions(NamedTuple):
    """Pass/fail of a batch of designs against a head-acceleration limit.

    Attributes
    ----------
    exceeds
        ``(N,)`` bool: a_h,max above the limit (or not computable, :attr:`unresolved`).
    by_bounds
        ``(N,)`` bool: decided from the bounds (else by the full kernel).
    unresolved
        ``(N,)`` bool: neither the bounds nor the full kernel decided (counted as exceeding).
    """

    exceeds: NDArray[np.bool_]
    by_bounds: NDArray[np.bool_]
    unresolved: NDArray[np.bool_]


@compiled(inline=True)
def _decide(p, r, c, nk, thr, horizon, ez):  # type: ignore[no-untyped-def]
    """:data:`EXCEEDS`, :data:`WITHIN` or :data:`UNDECIDED` for unit-v_c a_h (output 1) of
    one design's folded modal solution against ``thr`` (m/s^2 at unit v_c); ``ez`` (4, 4)
    complex scratch: per pole the node's exponential, one step's, and (real parts) the
    fourth-derivative scale at the node and its decay over one step."""
    top = a0 = a1 = 0.0
    for k in range(nk):
        if not p[k].real <= 0.0:
            return UNDECIDED  # unstable (or NaN): the scales do not peak at a cell's left end
        top = max(top, mag(p[k]))
        a0 += mag(r[1, k])
        a1 += mag(r[1, k]) * mag(p[k])
    if not (top > 0.0 and np.isfinite(a1) and np.isfinite(thr)):
        return UNDECIDED
    w = CELL * 0.4 / fastest_rate(p, nk)
    last = int(horizon / w)
    hi, lo = thr * (1.0 + MARGIN), thr * (1.0 - MARGIN)
    below, positive = True, True
    yl, dl = c[1, 1], c[1, 0]
    for k in range(nk):
        yl += r[1, k].real
        dl += real_product(r[1, k], p[k])
        ez[0, k] = 1.0
        ez[1, k] = cexp(p[k] * w)
        ez[2, k] = mag(r[1, k]) * mag(p[k]) ** 4 * (1.0 + 1e-12)  # the 4th derivative's scale
        ez[3, k] = math.exp(p[k].real * w)
    # rounding of the values and slopes at the nodes: the noise, the residues' and poles'
    # error bounds, and at most _REFRESH steps of the recurrence
    base = 2.0 * noise(p, r, c, 1, nk, 0.0) + _REFRESH * _STEP_ROUNDING * (a0 + w * a1)
    if yl - base > hi:
        return EXCEEDS  # a_h at contact, the first lobe's start, above the limit
    if abs(c[1, 0]) * horizon + abs(c[1, 1]) + a0 + base < lo:
        return _lobe_closes(p, r, c, nk, w, last, base, ez)  # below the limit for all t >= 0
    for j in range(1, last + 1):
        tr = j * w
        yr, dr = c[1, 0] * tr + c[1, 1], c[1, 0]
        m4 = 0.0
        for k in range(nk):
            m4 += ez[2, k].real  # over the cell: at its left end (stable poles)
            ez[2, k] = ez[2, k].real * ez[3, k].real
            e = cexp(p[k] * tr) if j % _REFRESH == 0 else ez[0, k] * ez[1, k]
            ez[0, k] = e
            q = r[1, k] * e
            yr += q.real
            dr += real_product(q, p[k])
        err = (base + 2.0 * term_errors(c, 1, nk, tr)) * (1.0 + top * w)
        if not (np.isfinite(yr) and np.isfinite(dr) and np.isfinite(m4)):
            return UNDECIDED
        if positive:
            positive = -hermite_bound(-yl, -yr, -dl, -dr, w, m4) - err > 0.0
            if positive and yr - err > hi:
                return EXCEEDS  # a node in the first lobe above the limit
            if positive and dl > 0.0 >= dr:  # the cell of a maximum: a_h at its secant guess
                ym = value(p, r, c, 1, nk, (j - 1) * w + w * dl / (dl - dr))
                if ym - err - _REFRESH * _STEP_ROUNDING * a0 > hi:
                    return EXCEEDS
        if below:
            below = hermite_bound(yl, yr, dl, dr, w, m4) + err < lo
        if yr + err < 0.0:  # the first lobe has ended within [0, tr]
            return WITHIN if below else UNDECIDED
        if not (below or positive):
            return UNDECIDED  # neither side can be shown any more
        yl, dl = yr, dr
    return UNDECIDED


@compiled(inline=True)
def _lobe_closes(p, r, c, nk, w, last, base, ez):  # type: ignore[no-untyped-def]
    """:data:`WITHIN` if a node ``j w`` (j <= last) is provably below zero (the first lobe
    ends before it, within the lobe search's horizon), else :data:`UNDECIDED`; ``ez`` as
    :func:`_decide` left it."""
    for j in range(1, last + 1):
        tr = j * w
        yr = c[1, 0] * tr + c[1, 1]
        for k in range(nk):
            e = cexp(p[k] * tr) if j % _REFRESH == 0 else ez[0, k] * ez[1, k]
            ez[0, k] = e
            yr += real_product(r[1, k], e)
        if yr + base + 2.0 * term_errors(c, 1, nk, tr) < 0.0:
            return WITHIN
    return UNDECIDED


@compiled
def _decide_block(params, thr, horizon_steps, out):  # type: ignore[no-untyped-def]
    """:func:`_decide` of ``(N, 8)`` designs against their thresholds ``thr`` on unit-v_c
    a_h into ``out`` (N,) int8: the poles of :data:`~.kernel_poles.LANES` designs side by
    side, as the kernel's."""
    den = np.empty((LANES, 5))
    num = np.zeros((LANES, 3, 6))
    guess = np.empty((2, LANES))
    state = np.empty(LANES, dtype=np.int8)
    roots = np.empty((LANES, 4), dtype=np.complex128)
    p = np.zeros(4, dtype=np.complex128)
    r = np.zeros((3, 4), dtype=np.complex128)
    c = np.zeros((3, ERR_COLUMNS))
    ez = np.zeros((4, 4), dtype=np.complex128)
    outputs = np.array([False, True, False])
    for i0 in range(0, params.shape[0], LANES):
        m = min(LANES, params.shape[0] - i0)
        _lane_roots(params, i0, m, False, den, num, guess, state, roots)
        for k in range(m):
            i = i0 + k
            out[i] = UNDECIDED
            if state[k] != 1:
                if not _finite(den[k]):
                    continue
                u, v = _head_mode(params[i])
                quartic_roots(den[k], u, v, roots[k])
            if not _finite(den[k]) or not roots_certified(den[k], roots[k]):
                continue
            separate(roots[k], 4)
            nk = modal_solution(den[k], num[k], roots[k], p, r, c, outputs)
            if nk < 0 or not residue_errors(den[k], 4, num[k], roots[k], r, c, outputs):
                continue
            horizon = horizon_steps * 0.4 / fastest_rate(p, nk)
            out[i] = _decide(p, r, c, nk, thr[i], horizon, ez)


def _bounds(
    index: NDArray[np.intp], params: NDArray[np.float64], thr: NDArray[np.float64], horizon: float
) -> tuple[NDArray[np.int8]]:
    """The compiled decisions of the contiguous rows ``index`` (:func:`_decide_block`)."""
    rows = slice(int(index[0]), int(index[-1]) + 1) if index.size else slice(0, 0)
    out = np.empty(index.size, dtype=np.int8)
    _decide_block(params[rows], thr[rows], horizon, out)
    return (out,)


def decisions_of_metrics(peak_g: ArrayLike, limit_g: float) -> NDArray[np.bool_]:
    """The full kernel's decisions: ``a_h,max > limit``, a NaN maximum counted as exceeding.

    Parameters
    ----------
    peak_g
        a_h,max in g (:attr:`~designlab.impact.metrics.ImpactMetrics.peak_head_acceleration_g`).
    limit_g
        The limit in g.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` bool.

    Examples
    --------
    >>> decisions_of_metrics([9.0, 11.0, float("nan")], 10.0).tolist()
    [False, True, True]
    """
    return ~(np.asarray(peak_g, dtype=float) <= limit_g)


def head_acceleration_exceeds(
    params: ArrayLike,
    impact_velocity: ArrayLike,
    limit_g: float,
    *,
    max_lobe_steps: int = MAX_LOBE_STEPS.default,
    workers: int | None = None,
) -> Decisions:
    """Whether each design's first-lobe a_h,max exceeds ``limit_g``, without its maximum.

    The decisions of :func:`~designlab.impact.metrics.metrics_of_matrix` (reduced,
    unconstrained model, the thesis's correct q2, a_h alone: :data:`A_H_ONLY`) compared
    with the limit
    (:func:`decisions_of_metrics`), at a fraction of its cost where the bounds decide
    (module text).

    Parameters
    ----------
    params
        ``(N, 8)`` rows ordered as :data:`~designlab.impact.model.PARAM_NAMES` (SI units),
        checked as :func:`~designlab.impact.metrics.metrics_of_matrix` checks them.
    impact_velocity
        v_c in m/s, scalar or ``(N,)``.
    limit_g
        The limit of a_h,max in g: a finite number > 0.
    max_lobe_steps, workers
        As in :func:`designlab.impact.impact_metrics`.

    Returns
    -------
    Decisions

    Raises
    ------
    InvalidParameterError
        A parameter, v_c or the limit out of its range (the batch's messages).
    """
    from designlab.impact.metrics import _check_params, metrics_of_matrix

    limit = float(limit_g) if isinstance(limit_g, (int, float)) else math.nan
    if not (math.isfinite(limit) and limit > 0.0) or isinstance(limit_g, bool):
        raise InvalidParameterError("limit_g", limit_g, "must be a finite number > 0", "g")
    p = np.atleast_2d(real_array("params", params))
    if p.ndim != 2 or p.shape[1] != len(PARAM_NAMES):
        raise InvalidParameterError("params", p.shape, f"must have shape (N, {len(PARAM_NAMES)})")
    p = _check_params(p)
    v = np.atleast_1d(check_closing_velocity(impact_velocity)).ravel().astype(float)
    if v.size not in (1, p.shape[0]):
        raise InvalidParameterError(
            "impact_velocity", v.shape, f"must be a scalar or have the batch length {len(p)}", "m/s"
        )
    v = np.broadcast_to(v, (p.shape[0],))
    steps = MAX_LOBE_STEPS.check(max_lobe_steps)
    WORKERS.check(workers)
    q4 = p[:, 2] * p[:, 7] + p[:, 3] * p[:, 7] + p[:, 2] * p[:, 3]
    if np.any(q4 <= 0):
        raise ModelError(
            f"design {int(np.flatnonzero(q4 <= 0)[0])}: the model has a pole at s = 0 (no "
            "restoring stiffness): at least two of K_r, K_c, K_h must be positive"
        )
    codes = np.full(p.shape[0], UNDECIDED, dtype=np.int8)
    if kernel.AVAILABLE:
        with np.errstate(divide="ignore", invalid="ignore"):
            thr = np.where(v > 0, limit * STANDARD_GRAVITY / v, np.nan)
        horizon = float((steps // 12) * 12 + 11)  # the lobe search's (kernel_lobe.lobe_end)
        (codes,) = map_row_blocks(
            partial(_bounds, params=np.ascontiguousarray(p), thr=thr, horizon=horizon),
            np.arange(p.shape[0]),
            workers=workers,
            align=LANES,
        )
    exceeds = codes == EXCEEDS
    unresolved = np.zeros(p.shape[0], dtype=bool)
    rest = np.flatnonzero(codes == UNDECIDED)
    if rest.size:
        m = metrics_of_matrix(p[rest], v[rest], max_lobe_steps=steps, workers=workers, **A_H_ONLY)
        peak = m.peak_head_acceleration_g
        exceeds[rest] = decisions_of_metrics(peak, limit)
        unresolved[rest] = ~np.isfinite(peak)
    return Decisions(exceeds, codes != UNDECIDED, unresolved)
