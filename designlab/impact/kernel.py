"""The compiled impact kernel: first-lobe metrics of many designs on one core (numba).

:func:`reduced_metrics` computes, per design and without temporaries, what
:func:`designlab.impact.metrics.metrics_of_matrix` computes with numpy for the
reduced model: the exact modal solution (:mod:`.kernel_poles`; the quadratic
factors of :data:`~.kernel_poles.LANES` designs side by side), the lobe end and
the certified maxima (:mod:`.kernel_lobe`). :func:`modal_metrics` does the
second half for responses built elsewhere (the full joint's eigen-decomposition,
the constrained impact). Designs are processed in blocks, so memory stays
bounded whatever the batch (the arrays in and out only).

The compiled code is cached on disk (:mod:`designlab.sx.jit`); the first call of
a fresh installation compiles it (tens of seconds), later processes load it.
Without numba the callers keep the numpy path (:data:`AVAILABLE`).

Examples
--------
>>> import numpy as np
>>> p = np.array([[9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 0.0, 4e3]])
>>> out, status = reduced_metrics(p, (True, True, True), printed=False, stop_time=0.05,
...                               max_lobe_steps=4096, diagnostics=False)
>>> round(float(out[0, 0]) * 1.25 / 9.80665, 3), round(float(out[0, 3]) * 1e3, 2), int(status[0])
(6.568, 33.22, 0)
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from designlab.impact.kernel_exp import cexp
from designlab.impact.kernel_lobe import (
    EXACT_STEPS,
    STRIDE,
    lobe_end,
    maximum_on_nodes,
    node_count,
    scratch,
    tail_shift,
)
from designlab.impact.kernel_modal import (
    ERR_COLUMNS,
    NOISE,
    UNDERFLOW,
    crossing_error,
    exponentials,
    fastest_rate,
    mag,
    noise,
    real_product,
    residue_errors,
    term_errors,
)
from designlab.impact.kernel_poles import (
    LANES,
    bairstow_lanes,
    coefficients,
    factor_roots,
    modal_solution,
    quartic_roots,
    roots_certified,
    separate,
)
from designlab.sx.jit import AVAILABLE, kernel

__all__ = [
    "AUDIT_CELLS",
    "AVAILABLE",
    "COLUMNS",
    "LOBE_NOISE",
    "MAX_POLES",
    "OVERFLOW",
    "STATUS_CODES",
    "SUSPECT_LOBE",
    "SUSPECT_MAXIMUM",
    "SUSPECT_POLES",
    "SUSPECT_REASONS",
    "audit_metrics",
    "modal_metrics",
    "reduced_metrics",
    "time_scale_ratios",
]

#: columns of the kernel's output rows (unit v_c; outputs not asked for are NaN)
COLUMNS = ("a_max", "eps_max", "f_max", "t_imp", "t_a", "t_eps", "t_f", "t_low")
#: status codes of the kernel -> :class:`designlab.impact.metrics.ImpactStatus` values
STATUS_CODES = ("ok", "no_impact", "peak_at_contact", "lobe_not_closed")
#: status of a design whose model coefficients are not finite (overflow): the caller raises
OVERFLOW = 4
#: status of a design whose poles fail the a-posteriori check (residual, conjugate pairs)
SUSPECT_POLES = 5
#: status of a design whose first zero of a_h was not certified the first one
SUSPECT_LOBE = 6
#: status of a design whose maxima were not certified
SUSPECT_MAXIMUM = 7
#: status of a design whose lobe did not close within the horizon while a_h came within
#: :data:`.kernel_lobe.CLEAR` times its rounding noise (a zero may hide there): the caller
#: tries it in more digits, else it is ``lobe_not_closed`` (never left in a result)
LOBE_NOISE = 9
#: what each SUSPECT_* code means (the caller evaluates such a design elsewhere)
SUSPECT_REASONS = {
    SUSPECT_POLES: "poles not certified (residual or conjugate pairs)",
    SUSPECT_LOBE: "first zero of a_h not certified",
    SUSPECT_MAXIMUM: "a maximum not certified",
}
#: most folded poles of a response the kernel takes (the full joint has 5 states)
MAX_POLES = 5
#: largest share of a maximum the residues' and poles' error bounds may take
#: (:func:`.kernel_modal.term_errors`; the search's own tolerance is 1e-8)
TERM_ERROR = 1e-9
#: largest relative error of t_imp the rounding noise may cause (its noise level over the
#: slope of a_h there, :func:`.kernel_modal.crossing_error`; Newton's own is 1e-11)
TIMP_ERROR = 1e-10
#: column of each output's maximum and its time: force, head acceleration, compression
_COL = ((2, 6), (0, 4), (1, 5))


@kernel(borrows=True)
def _design(p, r, c, nk, h, outputs, lobe, window, max_steps, diag, row, work, check=True):  # type: ignore[no-untyped-def]
    """Metrics of one design from its folded modal solution; returns the status code
    (:data:`STATUS_CODES`, or :data:`SUSPECT_LOBE` / :data:`SUSPECT_MAXIMUM` where the
    search or its a-posteriori check (``check``, :func:`sampled_check`) could not
    certify them: ``row`` is then NaN)."""
    for k in range(8):
        row[k] = np.nan
    step = 0.0
    lp = p  # the poles of the lobe-end search: shifted by sigma in a slow tail
    sigma = tail_shift(p, c, 1, nk, h, max_steps, diag) if lobe else 0.0
    if sigma != 0.0:  # exp(-sigma t) a_h(t): the same zeros, no subnormal numbers
        lp = work[3][0]
        for k in range(nk):
            lp[k] = p[k] - sigma
    if lobe:
        t_imp, row[7], step, sure = lobe_end(lp, r, c, 1, nk, h, max_steps, diag, work)
        if sigma != 0.0:
            step = 0.0  # the grid's exponentials are the shifted poles'
        if not sure:
            return _suspect(row, SUSPECT_LOBE)
        if t_imp == -np.inf:
            return LOBE_NOISE
        if not np.isfinite(t_imp):
            return 3
    else:
        t_imp = window
        h = min(h, window / 64.0)
    row[3] = t_imp
    status = 0
    first = 0
    if step > 0:  # the march's nodes before t_imp and their exponentials, then t_imp
        count = max(int(math.ceil(t_imp / step)), 1)  # noqa: RUF046 (numba)
        for k in range(nk):
            work[2][count, k] = cexp(p[k] * t_imp)
        first = count  # the lobe end's grid of a_h holds the nodes before t_imp
    else:
        count = node_count(t_imp, STRIDE * h)
        step = t_imp / count
        exponentials(p, nk, t_imp, count, work[2])  # shared by the outputs
    for o in (1, 0, 2):  # a_h first, while the lobe end's grid of it is in work
        if outputs[o]:
            start = first if o == 1 else 0
            t, y, sure = maximum_on_nodes(p, r, c, o, nk, t_imp, count, step, work, start)
            if not sure:
                return _suspect(row, SUSPECT_MAXIMUM)
            row[_COL[o][0]], row[_COL[o][1]] = y, t
            if o == 1 and t <= 0.0:
                status = 2
    if not check:
        return status
    bad = sampled_check(p, r, c, nk, outputs, lobe, count, step, row, work, sigma)
    return status if bad == 0 else _suspect(row, bad)


@kernel(inline=True)
def _suspect(row, code):  # type: ignore[no-untyped-def]
    """NaN metrics and the status ``code`` of a design the kernel does not certify."""
    for k in range(8):
        row[k] = np.nan
    return code


@kernel(inline=True)
def sampled_check(p, r, c, nk, outputs, lobe, count, step, row, work, sigma=0.0):  # type: ignore[no-untyped-def]
    """The a-posteriori check of a design's metrics on samples the search did not use.

    At the midpoints ``(j + 1/2) step`` of the maxima's cells before ``t_imp``
    (the nodes' exponentials ``work[2][j]`` times ``r_k exp(p_k step / 2)``, one real
    product per pole) no output may exceed its maximum by more than its certified 1e-8
    (relative), a_h must be provably positive (above its rounding noise) before the lobe
    end, the noise may move the lobe end by at most :data:`TIMP_ERROR` (relative); the
    error bounds of the residues and poles (:func:`.kernel_modal.term_errors`) may take
    at most :data:`TERM_ERROR` of each maximum (the last three where ``c`` carries those
    bounds). With ``sigma`` (:func:`.kernel_lobe.tail_shift`) the tests of a_h's sign and
    of the lobe end are those of ``exp(-sigma t) a_h(t)`` (:func:`_tail_suspect`).
    Returns 0, :data:`SUSPECT_MAXIMUM` or :data:`SUSPECT_LOBE`.
    """
    bounds = c.shape[1] >= ERR_COLUMNS  # the terms' error bounds are known
    ex, half = work[2], work[1]  # exp(p_k t_j) (ex[count]: at t_imp); the stack is free
    if lobe and sigma != 0.0:
        if _tail_suspect(work[3], r, c, nk, count, step, row[3], bounds):
            return SUSPECT_LOBE
    elif lobe and bounds:
        if crossing_error(p, r, c, 1, nk, row[3], ex[count]) > TIMP_ERROR * row[3]:
            return SUSPECT_LOBE  # the noise may move the lobe end by more than its tolerance
    for k in range(nk):  # r_k exp(p_k step / 2) of the three outputs, side by side
        z = cexp(p[k] * (0.5 * step))
        for o in range(3):
            w = r[o, k] * z
            half[k, 2 * o], half[k, 2 * o + 1] = w.real, w.imag
    top0 = row[2] + 1e-8 * abs(row[2])  # force, head acceleration, compression (_COL)
    top1 = row[0] + 1e-8 * abs(row[0])
    top2 = row[1] + 1e-8 * abs(row[1])
    signed = lobe and outputs[1] and sigma == 0.0  # a_h's sign (else _tail_suspect's)
    low = _noise_ceiling(r, c, 1, nk, row[3]) if signed and bounds else -np.inf
    unbounded = signed and not bounds
    for j in range(count - 1):  # one pass over the midpoints for every output
        t = (j + 0.5) * step
        y0 = c[0, 0] * t + c[0, 1]
        y1 = c[1, 0] * t + c[1, 1]
        y2 = c[2, 0] * t + c[2, 1]
        for k in range(nk):
            er, ei = ex[j, k].real, ex[j, k].imag
            y0 += half[k, 0] * er - half[k, 1] * ei
            y1 += half[k, 2] * er - half[k, 3] * ei
            y2 += half[k, 4] * er - half[k, 5] * ei
        if (outputs[0] and y0 > top0) or (outputs[1] and y1 > top1) or (outputs[2] and y2 > top2):
            return SUSPECT_MAXIMUM
        if y1 <= low and y1 <= noise(p, r, c, 1, nk, t):
            return SUSPECT_LOBE  # a_h not provably positive before the lobe end
        if unbounded and y1 < 0.0 and y1 < -noise(p, r, c, 1, nk, t):
            return SUSPECT_LOBE  # without error bounds: a_h provably negative before it
    for o in range(3):
        if outputs[o] and term_errors(c, o, nk, row[3]) > TERM_ERROR * abs(row[_COL[o][0]]):
            return SUSPECT_MAXIMUM  # the residues' and poles' errors alone exceed the tolerance
    return 0


@kernel(inline=True)
def _tail_suspect(shifted, r, c, nk, count, step, t_imp, bounds):  # type: ignore[no-untyped-def]
    """:func:`sampled_check`'s a_h tests on ``exp(-sigma t) a_h(t)`` (its poles in
    ``shifted[0]``; ``shifted[1:3]`` scratch): whether the noise may move the lobe end
    ``t_imp`` by more than :data:`TIMP_ERROR`, or a_h is not provably positive (with error
    bounds; without them, provably negative) at a midpoint before it. The exponentials by
    recurrence, evaluated afresh every :data:`.kernel_lobe.EXACT_STEPS` midpoints (their
    error then below a tenth of :data:`.kernel_modal.NOISE`)."""
    lp, e, z = shifted[0], shifted[1], shifted[2]
    for k in range(nk):
        e[k] = cexp(lp[k] * t_imp)
        z[k] = cexp(lp[k] * step)
    if bounds and crossing_error(lp, r, c, 1, nk, t_imp, e) > TIMP_ERROR * t_imp:
        return True
    low = _noise_ceiling(r, c, 1, nk, t_imp) if bounds else -np.inf
    for j in range(count - 1):
        t = (j + 0.5) * step
        y = 0.0
        for k in range(nk):
            if j % EXACT_STEPS == 0:
                e[k] = cexp(lp[k] * t)
            y += real_product(r[1, k], e[k])
            e[k] = e[k] * z[k]
        if bounds and y <= low and y <= noise(lp, r, c, 1, nk, t):
            return True
        if not bounds and y < 0.0 and y < -noise(lp, r, c, 1, nk, t):
            return True
    return False


@kernel(inline=True)
def _noise_ceiling(r, c, o, nk, t):  # type: ignore[no-untyped-def]
    """An upper bound of :func:`.kernel_modal.noise` over ``[0, t]`` (stable poles) without
    exponentials: the sampled check evaluates the noise only below it."""
    s = abs(c[o, 0] * t) + abs(c[o, 1])
    big = 0.0
    for k in range(nk):
        s += mag(r[o, k])
        big = max(big, mag(r[o, k]))
    return NOISE * (s + nk * big) + term_errors(c, o, nk, t) + nk * UNDERFLOW


@kernel
def _reduced_block(params, outputs, printed, stop_time, max_steps, diag, out, status, check):  # type: ignore[no-untyped-def]
    work = scratch()
    den = np.empty((LANES, 5))
    num = np.zeros((LANES, 3, 6))
    guess = np.empty((2, LANES))
    state = np.empty(LANES, dtype=np.int8)
    roots = np.empty((LANES, 4), dtype=np.complex128)
    p = np.zeros(4, dtype=np.complex128)
    r = np.zeros((3, 4), dtype=np.complex128)
    c = np.zeros((3, ERR_COLUMNS))  # c0 t + c1 and the error bounds of the terms
    for i0 in range(0, params.shape[0], LANES):
        m = min(LANES, params.shape[0] - i0)
        _lane_roots(params, i0, m, printed, den, num, guess, state, roots)
        for k in range(m):  # Bairstow failed: as alone (numpy's eigenvalues where it fails again)
            if state[k] != 1 and _finite(den[k]):
                u, v = _head_mode(params[i0 + k])
                quartic_roots(den[k], u, v, roots[k])
        _lane_metrics(i0, m, outputs, stop_time, max_steps, diag, out, status,
                      work, den, num, roots, p, r, c, check)  # fmt: skip


@kernel(inline=True)
def _head_mode(q):  # type: ignore[no-untyped-def]
    """Bairstow's start for the design ``q``: the head's own mode
    ``s^2 + (C_c + C_h) s / M_h + (K_c + K_h) / M_h``."""
    return (q[4] + q[6]) / q[5], (q[3] + q[7]) / q[5]


@kernel(inline=True)
def _finite(den):  # type: ignore[no-untyped-def]
    """Whether the quartic's coefficients are finite (no overflow)."""
    return (
        np.isfinite(den[1]) and np.isfinite(den[2]) and np.isfinite(den[3]) and np.isfinite(den[4])
    )


@kernel(borrows=True)
def _lane_roots(params, i0, m, printed, den, num, guess, state, roots):  # type: ignore[no-untyped-def]
    """The poles of designs ``i0 .. i0 + m``: their quadratic factors side by side
    (:func:`.kernel_poles.bairstow_lanes`); ``state[k]`` 1 where the roots are in."""
    for k in range(m):
        m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h = params[i0 + k]
        coefficients(m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h, printed, den[k], num[k])
        guess[0, k], guess[1, k] = _head_mode(params[i0 + k])
    bairstow_lanes(den, guess[0], guess[1], state, m)
    for k in range(m):
        if state[k] == 1:
            factor_roots(den[k], guess[0, k], guess[1, k], roots[k])


@kernel(borrows=True)
def _lane_metrics(i0, m, outputs, stop_time, max_steps, diag, out, status,
                  work, den, num, roots, p, r, c, check):  # type: ignore[no-untyped-def]  # fmt: skip
    """The metrics of designs ``i0 .. i0 + m`` from their poles, one by one (``check``: with
    the a-posteriori checks of the poles and of the metrics)."""
    for k in range(m):
        i = i0 + k
        a = den[k]
        if not _finite(a):
            out[i, :] = np.nan
            status[i] = OVERFLOW
            continue
        certified = not check or roots_certified(a, roots[k])  # before separate moves them
        separate(roots[k], 4)
        nk = modal_solution(a, num[k], roots[k], p, r, c, outputs)
        if nk >= 0 and not residue_errors(a, 4, num[k], roots[k], r, c, outputs):
            certified = False  # poles too close for a bound of the residues' errors
        if nk < 0 or not certified:
            out[i, :] = np.nan
            status[i] = OVERFLOW if nk < 0 else SUSPECT_POLES
            continue
        h = 0.4 / fastest_rate(p, nk)
        status[i] = _design(
            p, r, c, nk, h, outputs, True, stop_time, max_steps, diag, out[i], work, check
        )


@kernel
def _modal_block(poles, res, poly, h, outputs, lobe, window, max_steps, diag, out, status):  # type: ignore[no-untyped-def]
    work = scratch()
    for i in range(poles.shape[0]):
        code = _design(
            poles[i], res[i], poly[i], poles.shape[1], h[i], outputs, lobe, window,
            max_steps, diag, out[i], work,
        )  # fmt: skip
        status[i] = 3 if code == LOBE_NOISE else code  # these callers do not retry it


def reduced_metrics(
    params: NDArray[np.float64],
    outputs: tuple[bool, bool, bool],
    *,
    printed: bool,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
    self_check: bool = True,
) -> tuple[NDArray[np.float64], NDArray[np.int8]]:
    """Unit-v_c first-lobe metrics of ``(N, 8)`` reduced, unconstrained designs.

    Parameters
    ----------
    params
        ``(N, 8)`` rows ordered as :data:`~designlab.impact.model.PARAM_NAMES`
        (checked by the caller).
    outputs
        Whether to compute the force, the head acceleration (always needed for
        the lobe end) and the compression maxima.
    printed
        Use the thesis's printed q2 of (3.5.14).
    stop_time, max_lobe_steps, diagnostics
        As in :func:`designlab.impact.metrics.impact_metrics` (``lobe_diagnostics``).
    self_check
        Run the a-posteriori checks (:func:`.kernel_poles.roots_certified`,
        :func:`sampled_check`); off only to measure what they cost
        (benchmarks/impact.py).

    Returns
    -------
    tuple
        ``(N, 8)`` rows of :data:`COLUMNS` and ``(N,)`` status codes
        (:data:`STATUS_CODES`; :data:`OVERFLOW` where the model's coefficients are
        not finite; ``SUSPECT_*`` where the design is not certified: the caller
        evaluates it elsewhere, :data:`SUSPECT_REASONS`).
    """
    p = np.ascontiguousarray(params, dtype=np.float64)
    out = np.empty((p.shape[0], len(COLUMNS)))
    status = np.zeros(p.shape[0], dtype=np.int8)
    sel = np.array(outputs, dtype=np.bool_)
    _reduced_block(p, sel, bool(printed), float(stop_time), int(max_lobe_steps),
                   bool(diagnostics), out, status, bool(self_check))  # fmt: skip
    return out, status


def modal_metrics(
    poles: NDArray[np.complex128],
    residues: NDArray[np.complex128],
    poly: NDArray[np.float64],
    h: NDArray[np.float64],
    *,
    lobe: bool,
    window: float,
    max_lobe_steps: int,
    diagnostics: bool,
) -> tuple[NDArray[np.float64], NDArray[np.int8]]:
    """Unit-v_c first-lobe metrics from folded modal solutions built elsewhere.

    Parameters
    ----------
    poles
        ``(N, K)`` folded poles (shared by the outputs).
    residues
        ``(N, 3, K)`` residues of force, head acceleration, compression (zero rows
        for an output not computed).
    poly
        ``(N, 3, 2)`` polynomial parts ``c0 t + c1``.
    h
        ``(N,)`` grid steps (0.4 over the fastest rate resolved).
    lobe
        Search the first lobe's end on the head acceleration (else the window
        ``[0, window]``, the constrained impact).
    window
        Window length in s without a lobe.
    max_lobe_steps, diagnostics
        As in :func:`designlab.impact.metrics.impact_metrics`.

    Returns
    -------
    tuple
        As :func:`reduced_metrics`.
    """
    n = poles.shape[0]
    out = np.empty((n, len(COLUMNS)))
    status = np.zeros(n, dtype=np.int8)
    sel = np.array([np.any(residues[:, o]) or np.any(poly[:, o]) for o in range(3)])
    _modal_block(
        np.ascontiguousarray(poles, dtype=np.complex128),
        np.ascontiguousarray(residues, dtype=np.complex128),
        np.ascontiguousarray(poly, dtype=np.float64),
        np.ascontiguousarray(h, dtype=np.float64),
        sel, bool(lobe), float(window), int(max_lobe_steps), bool(diagnostics), out, status,
    )  # fmt: skip
    return out, status


@kernel
def _ratio_block(params, out):  # type: ignore[no-untyped-def]
    den = np.empty(5)
    num = np.empty((3, 6))
    for i in range(params.shape[0]):
        q = params[i]
        coefficients(q[0], q[1], q[2], q[3], q[4], q[5], q[6], q[7], False, den, num)
        out[i] = _spread(den)


@kernel(inline=True)
def _spread(a):  # type: ignore[no-untyped-def]
    """:func:`~designlab.impact.conditioning.time_scale_ratio` of the monic quartic ``a``
    (descending): ``max_k a_k^(1/k) / min_k (a_4 / a_(4-k))^(1/k)``, in logarithms."""
    if not _finite(a):
        return np.inf
    if not a[4] > 0:
        return 1.0  # a pole at s = 0: refused elsewhere, by name
    logs = (0.0, _log(a[1]), _log(a[2]), _log(a[3]), math.log(a[4]))  # -inf for a zero
    top = -np.inf
    low = np.inf
    for k in range(1, 5):
        top = max(top, logs[k] / k)
        low = min(low, (logs[4] - logs[4 - k]) / k)  # +inf for a zero a_(4-k)
    return max(math.exp(top - low), 1.0)


@kernel(inline=True)
def _log(x):  # type: ignore[no-untyped-def]
    """``log x`` of ``x >= 0`` (``-inf`` for 0)."""
    return math.log(x) if x > 0 else -np.inf


def time_scale_ratios(params: NDArray[np.float64]) -> NDArray[np.float64]:
    """:func:`~designlab.impact.conditioning.time_scale_ratio` of ``(N, 8)`` reduced,
    unconstrained designs, compiled (one pass, no temporaries).

    From the monic characteristic polynomial of :func:`.kernel_poles.coefficients`
    (the thesis's correct q2), the same estimate as the numpy function, to a few
    rounding errors.

    Parameters
    ----------
    params
        ``(N, 8)`` rows ordered as :data:`~designlab.impact.model.PARAM_NAMES`.

    Returns
    -------
    NDArray
        ``(N,)`` ratios (>= 1; ``inf`` where the coefficients are not finite).

    Examples
    --------
    >>> import numpy as np
    >>> p = np.array([[9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 46, 3e3]])
    >>> f"{time_scale_ratios(p)[0]:.3g}"
    '3.03'
    """
    p = np.ascontiguousarray(params, dtype=np.float64)
    out = np.empty(p.shape[0])
    _ratio_block(p, out)
    return out


#: cells of the uniform grid over ``[0, t_imp]`` on which :func:`audit_metrics` samples
AUDIT_CELLS = 2048


@kernel
def _audit_block(poles, res, poly, outputs, lobe, rows, codes):  # type: ignore[no-untyped-def]
    work = scratch()
    for i in range(poles.shape[0]):
        if codes[i] != 0 and codes[i] != 2:
            continue
        t_imp = rows[i, 3]
        nk = poles.shape[1]
        exponentials(poles[i], nk, t_imp, AUDIT_CELLS, work[2])
        check = sampled_check(poles[i], res[i], poly[i], nk, outputs, lobe, AUDIT_CELLS,
                              t_imp / AUDIT_CELLS, rows[i], work)  # fmt: skip
        if check != 0:
            codes[i] = check


def audit_metrics(
    poles: NDArray[np.complex128],
    residues: NDArray[np.complex128],
    poly: NDArray[np.float64],
    rows: NDArray[np.float64],
    codes: NDArray[np.int8],
    *,
    lobe: bool,
) -> NDArray[np.int8]:
    """The a-posteriori check (:func:`sampled_check`) of metrics found by another path.

    The folded modal solutions (as :func:`modal_metrics`) are sampled at the
    midpoints of :data:`AUDIT_CELLS` cells over ``[0, t_imp]``: no output above its
    maximum (beyond 1e-8 relative), a_h not provably negative before ``t_imp``.

    Parameters
    ----------
    poles
        ``(N, K)`` folded poles (as :func:`modal_metrics`).
    residues
        ``(N, 3, K)`` residues of force, head acceleration, compression.
    poly
        ``(N, 3, 2)`` polynomial parts ``c0 t + c1``.
    rows
        ``(N, width)`` the metrics found by the other path (the kernel's row layout).
    codes
        ``(N,)`` their status codes (copied; the input is not changed).
    lobe
        Whether the metrics end at the first lobe's end (else a fixed window).

    Returns
    -------
    NDArray
        The codes, :data:`SUSPECT_MAXIMUM` or :data:`SUSPECT_LOBE` where a check fails.
    """
    out = np.array(codes, dtype=np.int8)
    sel = np.array([np.any(residues[:, o]) or np.any(poly[:, o]) for o in range(3)])
    _audit_block(
        np.ascontiguousarray(poles, dtype=np.complex128),
        np.ascontiguousarray(residues, dtype=np.complex128),
        np.ascontiguousarray(poly, dtype=np.float64),
        sel, bool(lobe), np.ascontiguousarray(rows, dtype=np.float64), out,
    )  # fmt: skip
    return out
