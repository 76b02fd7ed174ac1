"""Design metrics of the impact model for many designs at once.

The metrics follow DECISIONS I2: the impact period runs from t = 0 to the first
t > 0 at which the head acceleration is <= 0, and a_h,max, eps_max and the peak
force are the maxima over that first lobe. For the constrained impact (head
against a wall) there is no lobe end; the window is ``[0, stop_time]``, the
time within which the thesis recommends stopping the manipulator (0.05 s).

Every response is exact: poles and residues of the model's transfer functions
(:mod:`designlab.impact.model`) evaluated by :mod:`designlab.impact.modal`, with
the lobe end and the maxima located by safeguarded Newton iterations on the
closed form (machine precision, not a grid).

Examples
--------
>>> import numpy as np
>>> from designlab.impact.metrics import impact_metrics
>>> m = impact_metrics({"M_r": 9.6, "C_r": 250, "K_r": 20e3, "K_c": 24.25e3,
...                     "C_c": 71.9, "M_h": 4.4, "C_h": 0.0, "K_h": 4e3},
...                    impact_velocity=np.array([0.4, 1.25]))
>>> np.round(m.peak_head_acceleration_g, 3)
array([2.101, 6.566])
>>> np.round(m.impact_duration * 1e3, 2)           # ms
array([33.22, 33.22])
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError, ModelError
from designlab.impact.modal import (
    ModalResponse,
    first_crossing,
    refine_extremum,
)
from designlab.impact.model import (
    PARAM_NAMES,
    LinearImpactModel,
    constrained_model,
    printed_q2_correction,
    unconstrained_model,
)

__all__ = [
    "STATUS_OK",
    "G",
    "ImpactMetrics",
    "hic_batch",
    "impact_metrics",
    "metrics_from_responses",
    "ramp_responses",
    "response_model",
]

#: Standard gravity used to express accelerations in g (the project convention).
G = 9.81

STATUS_OK = "ok"
STATUS_NO_IMPACT = "no_impact"
STATUS_PEAK_AT_CONTACT = "peak_at_contact"
STATUS_LOBE_OPEN = "lobe_not_closed"

#: fraction of the running a_h peak below which the lobe counts as "nearly over"
LOW_FRACTION = 0.05

_UNITS = {
    "M_r": "kg",
    "C_r": "N s/m",
    "K_r": "N/m",
    "K_c": "N/m",
    "C_c": "N s/m",
    "M_h": "kg",
    "C_h": "N s/m",
    "K_h": "N/m",
    "C_mech": "N s/m",
    "K_mech": "N/m",
    "C_cont": "N s/m",
    "K_cont": "N/m",
}


def _param_names(width: int | None = None, keys: object = None) -> tuple[str, ...]:
    """Names of the reduced (8) or full-joint (10, :mod:`designlab.impact.full_joint`) rows."""
    from designlab.impact.full_joint import FULL_PARAM_NAMES

    if width == len(FULL_PARAM_NAMES) or (keys is not None and "K_mech" in keys):  # type: ignore[operator]
        return FULL_PARAM_NAMES
    return PARAM_NAMES


def response_model(p: NDArray, constrained: bool) -> LinearImpactModel:
    """The model of parameter rows ``p``: reduced for 8 columns, full joint for 10."""
    if p.shape[-1] == len(PARAM_NAMES):
        return constrained_model() if constrained else unconstrained_model()
    from designlab.impact.full_joint import full_joint_model

    return full_joint_model(constrained)


def _param_matrix(params: Mapping[str, ArrayLike] | ArrayLike, n: int | None = None) -> NDArray:
    """Validate and stack parameters into an ``(N, 8)`` (or full-joint ``(N, 10)``) array."""
    if isinstance(params, Mapping):
        names = _param_names(keys=params)
        missing = [k for k in names if k not in params]
        unknown = [k for k in params if k not in names]
        if missing or unknown:
            raise InvalidParameterError(
                "params",
                sorted(params),
                f"needs exactly the keys {list(names)}"
                + (f"; missing {missing}" if missing else "")
                + (f"; unknown {unknown}" if unknown else ""),
            )
        cols = np.broadcast_arrays(*[np.asarray(params[k], dtype=float) for k in names])
        p = np.stack([c.ravel() for c in cols], axis=1)
    else:
        p = np.atleast_2d(np.asarray(params, dtype=float))
        names = _param_names(p.shape[-1])
        if p.shape[-1] != len(names):
            raise InvalidParameterError(
                "params",
                p.shape,
                f"needs shape (N, {len(PARAM_NAMES)}) ordered {PARAM_NAMES} "
                f"(or (N, {len(names)}) ordered {names} for the full joint)",
            )
    if n is not None and p.shape[0] == 1 and n > 1:
        p = np.repeat(p, n, axis=0)
    positive = {"M_r", "K_c", "M_h", "K_mech", "K_cont"}
    for i, name in enumerate(names):
        col = p[:, i]
        bad = ~np.isfinite(col) | ((col <= 0) if name in positive else (col < 0))
        if np.any(bad):
            j = int(np.flatnonzero(bad)[0])
            allowed = "must be a finite number " + ("> 0" if name in positive else ">= 0")
            raise InvalidParameterError(f"{name}[{j}]", float(col[j]), allowed, _UNITS.get(name))
    if len(names) != len(PARAM_NAMES) and np.any(p[:, 1] + p[:, 8] <= 0):
        j = int(np.flatnonzero(p[:, 1] + p[:, 8] <= 0)[0])
        raise InvalidParameterError(
            f"C_mech[{j}] + C_cont[{j}]", 0.0, "must be > 0 for the full joint", "N s/m"
        )
    return p


def ramp_responses(
    model: LinearImpactModel,
    params: NDArray,
    outputs: tuple[str, ...],
    *,
    q2: str = "correct",
) -> dict[str, ModalResponse]:
    """Exact responses of ``outputs`` to the unit constant-velocity impact (v_c = 1 m/s).

    Parameters
    ----------
    model
        :func:`unconstrained_model` or :func:`constrained_model`.
    params
        ``(N, 8)`` parameters ordered as :data:`PARAM_NAMES`.
    outputs
        Output names of ``model``.
    q2
        ``"correct"`` or ``"printed"`` (DECISIONS I1; unconstrained model only).
    """
    if model.name.startswith("full_joint"):
        if q2 != "correct":
            raise InvalidParameterError(
                "q2", q2, "the printed q2 of (3.5.14) belongs to the reduced joint; use 'correct'"
            )
        from designlab.impact.full_joint import modal_families

        return modal_families(model, params, outputs)["ramp"]
    den, num = model.ramp_coefficients(params)
    if q2 == "printed" and model.name == "unconstrained":
        den = den.copy()
        den[:, 2] -= printed_q2_correction(params)
    elif q2 not in ("correct", "printed"):
        raise InvalidParameterError("q2", q2, "must be 'correct' or 'printed'")
    if np.any(den[:, -1] <= 0):
        j = int(np.flatnonzero(den[:, -1] <= 0)[0])
        raise ModelError(
            f"design {j}: the model has a pole at s = 0 (no restoring stiffness): "
            "at least two of K_r, K_c, K_h must be positive"
        )
    return ModalResponse.family({name: num[name] for name in outputs}, den, 2)


@dataclass(frozen=True)
class ImpactMetrics:
    """First-lobe metrics of ``N`` impact designs (SI units).

    Attributes
    ----------
    params
        ``(N, 8)`` model parameters, ordered as :data:`PARAM_NAMES`.
    impact_velocity
        ``(N,)`` v_c in m/s.
    peak_head_acceleration, max_compression, peak_force, impact_duration
        ``(N,)`` arrays in m/s^2, m, N and s.
    time_of_peak_acceleration, time_of_max_compression, time_of_peak_force
        ``(N,)`` arrays in s.
    status
        ``(N,)`` strings: ``"ok"``, ``"no_impact"`` (v_c <= 0), ``"peak_at_contact"``
        (a_h peaks at t = 0+: an overdamped pulse, the impact period is delicate),
        ``"lobe_not_closed"`` (no end of the first lobe found; metrics are NaN).
    constrained
        Whether the constrained model (head against a wall) was used.
    lobe_tail
        Fraction of the impact period during which a_h has already fallen below
        5 % of its peak (sampled on the search grid). See :attr:`delicate_lobe`.
    """

    params: NDArray[np.float64]
    impact_velocity: NDArray[np.float64]
    peak_head_acceleration: NDArray[np.float64]
    max_compression: NDArray[np.float64]
    peak_force: NDArray[np.float64]
    impact_duration: NDArray[np.float64]
    time_of_peak_acceleration: NDArray[np.float64]
    time_of_max_compression: NDArray[np.float64]
    time_of_peak_force: NDArray[np.float64]
    status: NDArray[np.str_]
    constrained: bool = False
    lobe_tail: NDArray[np.float64] | None = None

    #: a lobe that lingers below LOW_FRACTION of its peak for more than this
    #: fraction of the impact period is "delicate"
    DELICATE_TAIL: ClassVar[float] = 0.2

    @property
    def delicate_lobe(self) -> NDArray[np.bool_]:
        """Designs whose a_h lingers near zero inside the first lobe (or peaks at contact).

        The lobe end, and eps_max with it, can then jump with a small change of
        the parameters (impact.md Sec. 2.10); such results deserve a flag.
        """
        tail = np.zeros(len(self)) if self.lobe_tail is None else self.lobe_tail
        return (np.nan_to_num(tail, nan=0.0) > self.DELICATE_TAIL) | (
            self.status == STATUS_PEAK_AT_CONTACT
        )

    @property
    def peak_head_acceleration_g(self) -> NDArray[np.float64]:
        """a_h,max in g (9.81 m/s^2)."""
        return self.peak_head_acceleration / G

    def __len__(self) -> int:
        return self.params.shape[0]

    def to_frame(self) -> pd.DataFrame:
        """One row per design, columns with units."""
        df = pd.DataFrame(self.params, columns=list(_param_names(self.params.shape[1])))
        df["v_c_m_per_s"] = self.impact_velocity
        df["a_h_max_m_per_s2"] = self.peak_head_acceleration
        df["a_h_max_g"] = self.peak_head_acceleration_g
        df["eps_max_m"] = self.max_compression
        df["f_c_max_N"] = self.peak_force
        df["t_imp_s"] = self.impact_duration
        df["status"] = self.status
        return df


def _march(
    resp: dict[str, ModalResponse],
    lobe: str | None,
    h: NDArray,
    horizon: NDArray,
    block: int,
    max_steps: int,
    diagnose: bool = False,
) -> tuple[NDArray, NDArray, NDArray, dict[str, tuple[NDArray, NDArray]], NDArray, NDArray]:
    """March a uniform grid ``t_k = k h`` (per design) over all outputs at once.

    Stops each design at the first ``t_k > 0`` where output ``lobe`` is <= 0 (or
    at ``horizon`` when ``lobe`` is None). The exponentials of the shared poles are
    advanced by complex multiplication, so every output costs one small product
    per step. Returns the lobe bracket ``(lo, hi, found)`` and, per output, the
    running grid maximum ``(t_best, y_best)`` before the lobe end, and a
    secant estimate of the lobe end, and the first grid time at which the lobe
    output fell below ``LOW_FRACTION`` of its running peak.
    """
    names = list(resp)
    first = resp[names[0]]
    n, n_modes = first.poles.shape
    z = np.exp(first.poles * h[:, None])
    e_start = np.ones((n, n_modes), dtype=complex)
    lo = np.zeros(n)
    hi = np.full(n, np.nan)
    found = np.zeros(n, dtype=bool)
    guess = np.full(n, np.nan)
    y_prev = np.zeros(n)
    # first time the lobe output falls below LOW_FRACTION of its running peak
    t_low = np.full(n, np.nan)
    prev_peak = np.zeros(n)
    best = {k: (np.zeros(n), np.full(n, -np.inf)) for k in names}
    act = np.arange(n)
    k0 = 0
    while act.size and k0 <= max_steps:
        steps = np.arange(k0, k0 + block, dtype=float)
        t = h[act, None] * steps[None, :]
        powers = np.empty((act.size, n_modes, block), dtype=complex)
        powers[:, :, 0] = 1.0
        powers[:, :, 1:] = z[act, :, None]
        np.cumprod(powers, axis=2, out=powers)
        e = e_start[act, :, None] * powers
        vals = {}
        for k in names:
            r = resp[k]
            v = np.real(np.einsum("nk,nkb->nb", r.residues[act], e))
            v += r.poly[act, 0, None] * t + r.poly[act, 1, None]
            vals[k] = v
        if lobe is not None:
            stop = (vals[lobe] <= 0) & (t > 0)
        else:
            stop = t >= horizon[act, None]
        hit = stop.any(axis=1)
        j = np.where(hit, stop.argmax(axis=1), block)
        valid = np.arange(block)[None, :] < j[:, None]
        for k in names:
            v = np.where(valid, vals[k], -np.inf)
            jb = v.argmax(axis=1)
            vb = v[np.arange(act.size), jb]
            tb, yb = best[k]
            upd = vb > yb[act]
            tb[act[upd]] = t[upd, jb[upd]]
            yb[act[upd]] = vb[upd]
        if np.any(hit):
            ah = act[hit]
            jh = j[hit]
            hi[ah] = t[hit, jh]
            lo[ah] = np.maximum(hi[ah] - h[ah], 0.0)
            found[ah] = True
            if lobe is not None:
                lv = vals[lobe]
                y_hi = lv[hit, jh]
                y_lo = np.where(jh > 0, lv[hit, np.maximum(jh - 1, 0)], y_prev[ah])
                with np.errstate(divide="ignore", invalid="ignore"):
                    frac = y_lo / (y_lo - y_hi)
                guess[ah] = lo[ah] + np.where(np.isfinite(frac), frac, 0.5) * (hi[ah] - lo[ah])
        if lobe is not None:
            lv = vals[lobe]
            y_prev[act] = lv[:, -1]
        if lobe is not None and diagnose:
            peak = np.maximum.accumulate(
                np.concatenate([prev_peak[act, None], lv], axis=1),
                axis=1,
            )[:, 1:]
            low = (lv < LOW_FRACTION * peak) & (peak > 0) & valid & (t > 0)
            first_low = low.any(axis=1) & np.isnan(t_low[act])
            t_low[act[first_low]] = t[first_low, low[first_low].argmax(axis=1)]
            prev_peak[act] = peak[:, -1]
        e_start[act] = e[:, :, -1] * z[act]
        act = act[~hit]
        k0 += block
    return lo, hi, found, best, guess, t_low


def impact_metrics(
    params: Mapping[str, ArrayLike] | ArrayLike,
    impact_velocity: ArrayLike,
    *,
    constrained: bool = False,
    q2: str = "correct",
    stop_time: float = 0.05,
    max_lobe_steps: int = 4096,
    with_force: bool = True,
    lobe_diagnostics: bool = False,
    with_compression: bool = True,
) -> ImpactMetrics:
    """First-lobe metrics for a batch of designs (vectorised; the sweep engine).

    Parameters
    ----------
    params
        Mapping of :data:`PARAM_NAMES` to scalars or arrays (broadcast together),
        or an ``(N, 8)`` array in that order. SI units: kg, N s/m, N/m. With the
        keys or ``(N, 10)`` columns of
        :data:`~designlab.impact.full_joint.FULL_PARAM_NAMES` the full series
        joint (3.4.6) is used (``docs/impact_joint.md``).
    impact_velocity
        v_c in m/s, scalar or ``(N,)``. The response is linear in v_c and zero
        for v_c <= 0 (DECISIONS I5).
    constrained
        Use the constrained impact (head against a wall; head parameters ignored).
    q2
        ``"correct"`` (default) or ``"printed"`` (thesis's q2, DECISIONS I1).
    stop_time
        Window length for the constrained impact, s.
    max_lobe_steps
        Give up looking for the end of the first lobe after this many grid steps.
    with_compression
        Also compute eps_max (``False`` leaves it NaN; the constrained model
        always computes it).
    lobe_diagnostics
        Also measure how long a_h lingers near zero before the lobe ends
        (``lobe_tail``, :attr:`ImpactMetrics.delicate_lobe`); costs ~15 %.
    with_force
        Also compute the peak force (``False`` leaves it NaN and saves a quarter
        of the work in large sweeps that do not need it).

    Returns
    -------
    ImpactMetrics

    Examples
    --------
    >>> from designlab.impact.metrics import impact_metrics
    >>> m = impact_metrics([9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 46.0, 3e3], 1.25)
    >>> float(m.peak_head_acceleration_g[0]) > 6.0
    True
    """
    p = _param_matrix(params)
    v = np.atleast_1d(np.asarray(impact_velocity, dtype=float)).ravel()
    if not np.all(np.isfinite(v)):
        raise InvalidParameterError("impact_velocity", v.tolist(), "must be finite", "m/s")
    n = max(p.shape[0], v.shape[0])
    if p.shape[0] not in (1, n) or v.shape[0] not in (1, n):
        raise InvalidParameterError(
            "impact_velocity",
            v.shape,
            f"must be a scalar or have the batch length {p.shape[0]}",
            "m/s",
        )
    p = np.repeat(p, n, axis=0) if p.shape[0] == 1 and n > 1 else p
    v = np.repeat(v, n) if v.shape[0] == 1 and n > 1 else v
    if stop_time <= 0 or not np.isfinite(stop_time):
        raise InvalidParameterError("stop_time", stop_time, "must be a finite number > 0", "s")

    model = response_model(p, constrained)
    names: tuple[str, ...] = ("compression",) if constrained else ("head_acceleration",)
    if with_compression and not constrained:
        names = (*names, "compression")
    if with_force or constrained:
        names = ("force", *names)
    resp = ramp_responses(model, p, names, q2=q2)
    rate = None
    if model.name.startswith("full_joint"):
        from designlab.impact.full_joint import grid_rate

        rate = grid_rate(resp[names[0]].poles)
    return metrics_from_responses(
        resp,
        p,
        v,
        constrained=constrained,
        stop_time=stop_time,
        max_lobe_steps=max_lobe_steps,
        lobe_diagnostics=lobe_diagnostics,
        rate=rate,
    )


def metrics_from_responses(
    resp: dict[str, ModalResponse],
    p: NDArray[np.float64],
    v: NDArray[np.float64],
    *,
    constrained: bool = False,
    stop_time: float = 0.05,
    max_lobe_steps: int = 4096,
    lobe_diagnostics: bool = False,
    rate: NDArray[np.float64] | None = None,
) -> ImpactMetrics:
    """First-lobe metrics from unit-velocity responses already built (see :func:`impact_metrics`).

    ``resp`` maps output names (``head_acceleration`` unless constrained, and any of
    ``compression`` and ``force``) to the responses to v_c = 1 m/s of the designs
    ``p`` (``(N, 8)``); ``v`` is ``(N,)``. Inputs are not validated here. ``rate``
    (1/s, ``(N,)``) is the fastest rate the search grid resolves; default the
    largest pole modulus (see :func:`designlab.impact.full_joint.grid_rate`).
    """
    n = p.shape[0]
    names = tuple(k for k in ("force", "head_acceleration", "compression") if k in resp)
    status = np.full(n, STATUS_OK, dtype=object)

    pol = resp[names[0]].poles
    h = 0.4 / (np.abs(pol).max(axis=1) if rate is None else rate)  # <= 1/15 of the fastest period
    horizon = np.full(n, float(stop_time))
    if constrained:
        h = np.minimum(h, stop_time / 64.0)
    lo, hi, found, best, guess, t_low = _march(
        resp,
        None if constrained else "head_acceleration",
        h,
        horizon,
        block=12,
        max_steps=max_lobe_steps,
        diagnose=lobe_diagnostics,
    )
    if constrained:
        t_imp = horizon.copy()
    else:
        t_imp = np.full(n, np.nan)
        if np.any(found):
            idx = np.flatnonzero(found)
            t_imp[idx] = first_crossing(
                resp["head_acceleration"].take(idx), lo[idx], hi[idx], guess=guess[idx]
            )
        status[~found] = STATUS_LOBE_OPEN

    idx = np.flatnonzero(np.isfinite(t_imp))
    out: dict[str, tuple[NDArray, NDArray]] = {}
    for name in names:
        tt = np.full(n, np.nan)
        yy = np.full(n, np.nan)
        if idx.size:
            tb = best[name][0][idx]
            lo_b = np.maximum(tb - h[idx], 0.0)
            hi_b = np.minimum(tb + h[idx], t_imp[idx])
            t_s, y_s = refine_extremum(resp[name].take(idx), lo_b, hi_b, guess=tb)
            tt[idx], yy[idx] = t_s, y_s
            if name == "head_acceleration":
                status[idx[t_s <= 0.0]] = STATUS_PEAK_AT_CONTACT
        out[name] = (tt, yy)
    if constrained:
        t_a = a_max = np.zeros(n)
    else:
        t_a, a_max = out["head_acceleration"]

    with np.errstate(divide="ignore", invalid="ignore"):
        tail = np.where(np.isfinite(t_low), (t_imp - t_low) / t_imp, 0.0)

    # linearity in v_c; zero response for v_c <= 0
    scale = np.where(v > 0, v, 0.0)
    status[v <= 0] = STATUS_NO_IMPACT
    none = v <= 0
    t_imp_out = np.where(none, 0.0, t_imp)

    def _z(arr: NDArray) -> NDArray:
        return np.where(none, 0.0, arr)

    nan = np.full(n, np.nan)

    return ImpactMetrics(
        params=p,
        impact_velocity=v,
        peak_head_acceleration=_z(a_max * scale),
        max_compression=_z(out["compression"][1] * scale) if "compression" in out else nan,
        peak_force=_z(out["force"][1] * scale) if "force" in out else nan,
        impact_duration=t_imp_out,
        time_of_peak_acceleration=_z(t_a),
        time_of_max_compression=_z(out["compression"][0]) if "compression" in out else nan,
        time_of_peak_force=_z(out["force"][0]) if "force" in out else nan,
        status=status.astype(str),
        constrained=constrained,
        lobe_tail=np.where(none | constrained, np.nan, tail) if lobe_diagnostics else None,
    )


def hic_batch(metrics: ImpactMetrics, window: float = 0.015, samples: int = 400) -> NDArray:
    """HIC (standard definition, DECISIONS I4) over the first lobe of each design.

    The head's velocity relative to the torso is the exact integral of a_h, so
    the mean acceleration over ``[t1, t2]`` is ``(v(t2) - v(t1)) / (t2 - t1)``;
    it is evaluated exactly on ``samples`` points of ``[0, t_imp]`` and the
    windows with ``t2 - t1 <= window`` are searched on that grid.

    Examples
    --------
    >>> m = impact_metrics([9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 0.0, 4e3], 1.25)
    >>> round(float(hic_batch(m, 0.015)[0]), 2)
    1.37
    """
    if not window > 0:
        raise InvalidParameterError("window", window, "must be > 0", "s")
    n = len(metrics)
    out = np.zeros(n)
    t_imp = metrics.impact_duration
    idx = np.flatnonzero((metrics.impact_velocity > 0) & np.isfinite(t_imp) & (t_imp > 0))
    if metrics.constrained or idx.size == 0:
        return out
    resp = ramp_responses(
        response_model(metrics.params, False), metrics.params[idx], ("head_velocity",)
    )
    rel = np.linspace(0.0, 1.0, samples)
    t = t_imp[idx, None] * rel[None, :]
    v = resp["head_velocity"].evaluate(t) * metrics.impact_velocity[idx, None]
    dt = t_imp[idx] / (samples - 1)
    best = np.zeros(idx.size)
    max_lag = int(min(samples - 1, np.ceil(window / dt.min())))
    for lag in range(1, max_lag + 1):
        dur = lag * dt
        ok = dur <= window * (1 + 1e-12)
        if not np.any(ok):
            break
        mean_g = (v[:, lag:] - v[:, :-lag]).max(axis=1) / (dur * G)
        val = np.where(ok & (mean_g > 0), dur * np.maximum(mean_g, 0.0) ** 2.5, 0.0)
        best = np.maximum(best, val)
    out[idx] = best
    return out
