"""The first local maximum of an impact response: the thesis's "peak" (Zeng 2011, Sec. 3.6).

The project (docs/impact.md, "Metrics") takes a_h,max, eps_max and the peak
force as maxima over the first impact lobe (t = 0 to the first zero of a_h).
The thesis's Sec. 3.6 and 3.8 comparisons of the force use its *first local maximum* after the step
f_c(0+) = C_c v_c. The two agree when the force falls after its first peak,
but where the force keeps rising into its ramp before the lobe closes -- a slow
closing speed, or a manipulator that keeps accelerating (Sec. 3.8) -- the lobe
maximum is later and much larger. Reports give both (``docs/impact_joint.md``).

Examples
--------
>>> import designlab as dl
>>> head = dl.impact.TABLE_3_2_HEADS[3][1]
>>> r = dl.impact.simulate(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, head, 1.25)
>>> round(first_peak(r)[1], 1), round(r.peak_force, 1)       # the same here
(305.4, 305.4)

Sec. 3.8, reading (b) (head still, v_c = 0.25 m/s, +0.51 g without feed-forward):
the force peaks at 16 ms, then rises again into the ramp until the lobe ends.

>>> prof = dl.impact.VelocityProfile(0.51 * 9.81, 0.05, feedforward=False)
>>> r = dl.impact.simulate(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, head, 0.25, profile=prof)
>>> t, f = first_peak(r)
>>> round(t, 4), round(f, 1), round(r.time_of_peak_force, 4), round(r.peak_force, 1)
(0.0164, 64.1, 0.0852, 115.9)
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.modal import ModalResponse, _safeguarded_newton, point_values

__all__ = ["first_local_maximum", "first_peak"]


def _refine_maximum(
    resp: ModalResponse, lo: NDArray, hi: NDArray, guess: NDArray | None = None
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Maximum of y on ``[lo, hi]`` per response: the stationary point if y' changes sign
    from + to - inside the bracket, else the better end."""
    y_lo, d_lo = point_values(resp, lo, (0, 1))
    y_hi, d_hi = point_values(resp, hi, (0, 1))
    t = np.where(y_lo >= y_hi, lo, hi)
    y = np.maximum(y_lo, y_hi)
    idx = np.flatnonzero((d_lo > 0) & (d_hi <= 0))
    if idx.size:
        sub = resp.take(idx)
        g = None if guess is None else np.asarray(guess, dtype=float)[idx]
        ts = _safeguarded_newton(sub, lo[idx], hi[idx], 1, 60, 1e-11, guess=g)  # root of y'
        (ys,) = point_values(sub, ts, (0,))
        better = ys >= y[idx]
        t[idx] = np.where(better, ts, t[idx])
        y[idx] = np.where(better, ys, y[idx])
    return t, y


def _first_peak_index(y: NDArray[np.float64]) -> NDArray[np.intp]:
    """Index of the first interior local maximum of each row (the last index if none)."""
    rise = np.diff(y, axis=1)
    peak = (rise[:, :-1] > 0) & (rise[:, 1:] <= 0)
    has = peak.any(axis=1)
    first = np.where(has, peak.argmax(axis=1) + 1, y.shape[1] - 1)
    # a response that falls from t = 0 has its first maximum at the start
    return np.where(~has & (rise[:, 0] <= 0), 0, first)


def first_local_maximum(
    resp: ModalResponse, t_end: ArrayLike, samples: int = 801
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """First local maximum of each response on ``[0, t_end]`` (exact, batch).

    The thesis's "peak" of the force (Sec. 3.6) is the first local maximum
    after the step f_c(0+) = C_c v_c; the first-lobe maximum (docs/impact.md, "Metrics")
    can be later and larger when the force keeps rising into its ramp. The
    responses are sampled on ``samples`` points and the first rise-fall
    bracket is polished by Newton iterations on the closed form. Where there
    is no interior maximum the larger end point is returned.

    Parameters
    ----------
    resp
        Batch of ``N`` responses (:mod:`designlab.impact.modal`).
    t_end
        ``(N,)`` or scalar end of the window, s (e.g. the impact period).
    samples
        Grid points of the bracketing search.

    Returns
    -------
    tuple of arrays
        Times (s) and values, ``(N,)`` each.

    Examples
    --------
    >>> import numpy as np
    >>> # y = L^-1[1/(s (s^2 + 1))] = 1 - cos t: first maximum at pi
    >>> r = ModalResponse.from_polynomials(np.array([[1.0]]), np.array([[1.0, 0.0, 1.0]]), 1)
    >>> t, y = first_local_maximum(r, 10.0)
    >>> round(float(t[0]), 9), round(float(y[0]), 12)
    (3.141592654, 2.0)
    """
    n = resp.batch_size
    t_end = np.broadcast_to(np.asarray(t_end, dtype=float), (n,)).copy()
    if int(samples) < 3:
        raise InvalidParameterError("samples", samples, "must be an integer >= 3")
    rel = np.linspace(0.0, 1.0, int(samples))
    t = t_end[:, None] * rel[None, :]
    y = resp.evaluate(t)
    j = _first_peak_index(y)
    step = t_end / (int(samples) - 1)
    t_j = t[np.arange(n), j]
    lo = np.maximum(t_j - step, 0.0)
    hi = np.minimum(t_j + step, t_end)
    return _refine_maximum(resp, lo, hi, guess=t_j)


def first_peak(response: Any, output: str = "force", samples: int = 4001) -> tuple[float, float]:
    """First local maximum of ``output`` of a simulated impact within its first lobe.

    Works for any :class:`~designlab.impact.simulate.ImpactResponse`, also with
    a manipulator velocity profile (Sec. 3.8): the exact response is sampled on
    ``samples`` points of ``[0, impact_duration]`` and the first rise-fall
    bracket is polished with Brent's method.

    Parameters
    ----------
    response
        An ``ImpactResponse`` from :func:`~designlab.impact.simulate.simulate`.
    output
        ``"force"`` (default), ``"head_acceleration"`` or ``"compression"``.
    samples
        Points of the bracketing grid (>= 3).

    Returns
    -------
    tuple of float
        ``(t, value)`` in s and the output's SI unit; ``(nan, nan)`` when the
        first lobe did not close, ``(0, 0)`` for no impact.

    Examples
    --------
    >>> import designlab as dl
    >>> r = dl.impact.simulate(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25)
    >>> t, f = first_peak(r)
    >>> bool(abs(f - r.peak_force) < 1e-6 * r.peak_force)   # the force falls after its peak
    True
    """
    from scipy.optimize import minimize_scalar

    if output not in ("force", "head_acceleration", "compression"):
        raise InvalidParameterError(
            "output", output, "must be 'force', 'head_acceleration' or 'compression'"
        )
    if int(samples) < 3:
        raise InvalidParameterError("samples", samples, "must be an integer >= 3")
    t_end = float(response.impact_duration)
    if not np.isfinite(t_end):
        return float("nan"), float("nan")
    if t_end <= 0.0:
        return 0.0, 0.0
    evaluate = response._lobe["evaluate"]
    t = np.linspace(0.0, t_end, int(samples))
    y = evaluate(t)[output]
    j = int(_first_peak_index(y[None, :])[0])
    if j in (0, t.size - 1):
        return float(t[j]), float(y[j])
    res = minimize_scalar(
        lambda x: -float(evaluate(np.array([x]))[output][0]),
        bounds=(t[j - 1], t[j + 1]),
        method="bounded",
        options={"xatol": 1e-13},
    )
    if -res.fun >= y[j]:
        return float(res.x), float(-res.fun)
    return float(t[j]), float(y[j])
