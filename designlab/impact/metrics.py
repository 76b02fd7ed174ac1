"""Design metrics of the impact model for many designs at once.

The metrics follow Zeng 2011, Sec. 3.6 (docs/impact.md, "Metrics"): the impact
period runs from t = 0 to the first t > 0 at which the head acceleration is
<= 0, and a_h,max, eps_max and the peak force are the maxima over that first
lobe. For the constrained impact (head against a wall) there is no lobe end;
the window is ``[0, stop_time]``, the time within which the thesis recommends
stopping the manipulator (0.05 s).

Every response is exact: poles and residues of the model's transfer functions
(:mod:`designlab.impact.model`) evaluated by :mod:`designlab.impact.modal`, with
the lobe end and the maxima located by safeguarded Newton iterations on the
closed form. Every maximum is certified: a branch and bound on curvature bounds
(:func:`designlab.impact.modal.certified_maximum`) guarantees that no value
between the grid nodes is missed, the window ends included, and that the lobe
end is the first zero of a_h even when a_h dips below zero between two nodes.

Examples
--------
>>> import numpy as np
>>> from designlab.impact.metrics import impact_metrics
>>> m = impact_metrics({"M_r": 9.6, "C_r": 250, "K_r": 20e3, "K_c": 24.25e3,
...                     "C_c": 71.9, "M_h": 4.4, "C_h": 0.0, "K_h": 4e3},
...                    impact_velocity=np.array([0.4, 1.25]))
>>> np.round(m.peak_head_acceleration_g, 3)
array([2.102, 6.568])
>>> np.round(m.impact_duration * 1e3, 2)           # ms
array([33.22, 33.22])
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from functools import cache, partial
from typing import Any, ClassVar

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError, ModelError
from designlab.impact import kernel, kernel_full, kernel_modal, kernel_precise
from designlab.impact.conditioning import check_conditioning, check_eigen_route
from designlab.impact.full_joint_model import FULL_PARAM_NAMES, full_joint_model, grid_rate
from designlab.impact.kernel_modal import ERR_COLUMNS, MAX_TERMS
from designlab.impact.kernel_poles import LANES
from designlab.impact.metric_names import PARAMETERS
from designlab.impact.modal import (
    ModalResponse,
    certified_first_crossing,
    certified_maximum,
    first_crossing,
)
from designlab.impact.model import (
    PARAM_NAMES,
    LinearImpactModel,
    constrained_model,
    printed_q2_correction,
    unconstrained_model,
)
from designlab.impact.parameters import (
    HIC_SAMPLES,
    HIC_WINDOW,
    MAX_LOBE_STEPS,
    STOP_TIME,
    check_closing_velocity,
)
from designlab.impact.state_space import modal_families
from designlab.params import params_of
from designlab.results import OK, Result, Status
from designlab.sx.jit import say_no_jit
from designlab.units import STANDARD_GRAVITY
from designlab.validation import check_q2, named_columns, real_array
from designlab.workers import WORKERS, map_row_blocks

__all__ = [
    "STATUS_OK",
    "ImpactMetrics",
    "ImpactStatus",
    "hic_batch",
    "hic_of_velocity",
    "impact_metrics",
    "matrix_metrics",
    "metrics_from_responses",
    "metrics_of_matrix",
    "param_names",
    "ramp_responses",
    "response_model",
]


class ImpactStatus(Status):
    """Status of one impact (a design of :class:`ImpactMetrics`, an ``ImpactResponse``).

    Attributes
    ----------
    OK
        The first lobe closed and its maxima were found.
    NO_IMPACT
        v_c <= 0: the head and the manipulator do not close in; every metric is 0.
    PEAK_AT_CONTACT
        a_h peaks at t = 0+ (an overdamped pulse): the impact period is delicate.
    LOBE_NOT_CLOSED
        No end of the first lobe was found; the metrics are NaN.
    UNCERTIFIED
        Neither the compiled kernel nor the numpy path could certify the metrics
        (their a-posteriori checks failed; the warnings give the reason); the
        metrics are NaN, never a number presented as exact (docs/impact.md,
        "Self-check").
    BOTTOMING
        eps_max exceeds the foam's linear depth lambda: the linear model is not
        valid (docs/impact.md, "Foam bottoming"; single impacts only).
    """

    OK = "ok"
    NO_IMPACT = "no_impact"
    PEAK_AT_CONTACT = "peak_at_contact"
    LOBE_NOT_CLOSED = "lobe_not_closed"
    UNCERTIFIED = "uncertified"
    BOTTOMING = "bottoming"


# plain strings for the per-design status arrays (equal to the members; fast to convert)
STATUS_OK = ImpactStatus.OK.value
STATUS_NO_IMPACT = ImpactStatus.NO_IMPACT.value
STATUS_PEAK_AT_CONTACT = ImpactStatus.PEAK_AT_CONTACT.value
STATUS_LOBE_OPEN = ImpactStatus.LOBE_NOT_CLOSED.value
STATUS_UNCERTIFIED = ImpactStatus.UNCERTIFIED.value


#: fraction of the running a_h peak below which the lobe counts as "nearly over"
LOW_FRACTION = 0.05

_POSITIVE = ("M_r", "K_c", "M_h", "K_mech", "K_cont")
_FULL_UNITS = {"C_mech": "N s/m", "K_mech": "N/m", "C_cont": "N s/m", "K_cont": "N/m"}


def param_names(width: int | None = None, keys: object = None) -> tuple[str, ...]:
    """Names of the reduced (8) or full-joint (10) parameter rows.

    Parameters
    ----------
    width
        The number of columns of the rows.
    keys
        Or the names given (a full-joint row has ``K_mech``).

    Returns
    -------
    tuple of str
        :data:`~designlab.impact.model.PARAM_NAMES` or
        :data:`~designlab.impact.full_joint_model.FULL_PARAM_NAMES`.

    Examples
    --------
    >>> param_names(10)[-1], param_names(8)[-1]
    ('K_cont', 'K_h')
    """
    full = width == len(FULL_PARAM_NAMES) or (keys is not None and "K_mech" in keys)  # type: ignore[operator]
    return FULL_PARAM_NAMES if full else PARAM_NAMES


def response_model(p: NDArray, constrained: bool) -> LinearImpactModel:
    """The model of parameter rows ``p``: reduced for 8 columns, full joint for 10.

    Parameters
    ----------
    p
        ``(N, 8)`` rows ordered as :data:`PARAM_NAMES` or ``(N, 10)`` rows ordered as
        :data:`designlab.impact.full_joint.FULL_PARAM_NAMES`.
    constrained
        The constrained impact (head against a wall).

    Returns
    -------
    LinearImpactModel

    Examples
    --------
    >>> import numpy as np
    >>> response_model(np.zeros((1, 8)), False).name
    'unconstrained'
    >>> response_model(np.zeros((1, 10)), True).name.startswith("full_joint")
    True
    """
    if p.shape[-1] == len(PARAM_NAMES):
        return constrained_model() if constrained else unconstrained_model()
    return full_joint_model(constrained)


def _check_params(p: NDArray, constrained: bool = False) -> NDArray:
    """Range checks of an ``(N, 8)`` parameter matrix ordered as :data:`PARAM_NAMES` (or
    ``(N, 10)``, full joint), and the conditioning of every design
    (:func:`~designlab.impact.conditioning.check_conditioning`)."""
    if p.shape[0] == 0:
        raise InvalidParameterError("params", "0 designs", "needs at least one design")
    names = param_names(p.shape[-1])
    if p.shape[-1] != len(names):
        return p  # the caller reports the shape
    if len(names) != len(PARAM_NAMES) and np.any(p[:, 1] + p[:, 8] <= 0):
        j = int(np.flatnonzero(p[:, 1] + p[:, 8] <= 0)[0])
        raise InvalidParameterError(
            f"C_mech[{j}] + C_cont[{j}]", 0.0, "must be > 0 for the full joint", "N s/m"
        )
    positive = np.array([name in _POSITIVE for name in names])
    upper = np.array([_upper(name) for name in names])
    if (
        np.all(np.isfinite(p))
        and not np.any(np.where(positive, p <= 0, p < 0))
        and not np.any(p > upper)
    ):
        check_conditioning(p, names, constrained=constrained)
        return p  # one pass over the batch; the loop below names the first bad value
    for i, name in enumerate(names):
        col = p[:, i]
        bad = ~np.isfinite(col) | ((col <= 0) if name in _POSITIVE else (col < 0))
        bad |= col > upper[i]
        if np.any(bad):
            j = int(np.flatnonzero(bad)[0])
            allowed = "must be a finite number " + ("> 0" if name in _POSITIVE else ">= 0")
            if np.isfinite(upper[i]):
                allowed += f" and <= {upper[i]:g}"
            raise InvalidParameterError(
                f"{name}[{j}]",
                float(col[j]),
                allowed,
                (_FULL_UNITS.get(name) or PARAMETERS[name].unit),
            )
    check_conditioning(p, names, constrained=constrained)
    return p


@cache
def _upper(name: str) -> float:
    """The declared upper bound of a column (its model's declaration; inf where none)."""
    from designlab.impact.parameters import ContactDynamics, Foam, HeadNeck

    for cls in (HeadNeck, Foam, ContactDynamics):
        for decl in params_of(cls).values():
            if decl.symbol == name:
                return float(decl.le) if decl.le is not None else np.inf
    return np.inf


def ramp_responses(
    model: LinearImpactModel,
    params: NDArray,
    outputs: tuple[str, ...],
    *,
    q2: str = "correct",
    rows: NDArray[np.intp] | None = None,
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
        ``"correct"`` or ``"printed"`` (docs/impact.md, "q2"; unconstrained model only).
    rows
        The designs' rows in the caller's batch, for error messages (default: their
        rows in ``params``).

    Raises
    ------
    InvalidParameterError
        For the first design whose model leaves double precision (a mass of 1e-200 kg).
    """
    if model.name.startswith("full_joint"):
        if check_q2(q2) != "correct":
            raise InvalidParameterError(
                "q2", q2, "the printed q2 of (3.5.14) belongs to the reduced joint; use 'correct'"
            )
        return _eigen_ramp(model, params, outputs, rows)
    den, num = model.ramp_coefficients(params)
    if model.name == "unconstrained" and params.shape[1] == 8:
        den, num = _closed_form(params, check_q2(q2) == "printed", den, num)
    elif check_q2(q2) == "printed" and model.name == "unconstrained":
        den = den.copy()
        den[:, 2] -= printed_q2_correction(params)
    _check_finite(params, den, rows)
    if np.any(den[:, -1] <= 0):
        j = int(np.flatnonzero(den[:, -1] <= 0)[0])
        raise ModelError(
            f"design {j}: the model has a pole at s = 0 (no restoring stiffness): "
            "at least two of K_r, K_c, K_h must be positive"
        )
    return ModalResponse.family({name: num[name] for name in outputs}, den, 2)


def _closed_form(
    params: NDArray, printed: bool, den: NDArray, num: dict[str, NDArray]
) -> tuple[NDArray, dict[str, NDArray]]:
    """The reduced model's coefficients in closed form, as the kernel's
    (:func:`designlab.impact.kernel_poles.coefficients`, sums of products exact to a few
    ulps), for the outputs it has; the symbolic evaluation's carry rounding of 1e-11 and
    spurious terms where they cancel, which the residues' error bounds do not cover."""
    from designlab.impact import kernel_poles

    build = getattr(kernel_poles.coefficients, "py_func", kernel_poles.coefficients)
    d = np.empty((5, params.shape[0]))
    n = np.zeros((3, 6, params.shape[0]))
    build(*params.T, printed, d, n)
    num = dict(num)
    for o, name in enumerate(("force", "head_acceleration", "compression")):
        if name in num and num[name].shape[1] == 6:
            num[name] = n[o].T.copy()
    return d.T.copy(), num


@dataclass(frozen=True)
class ImpactMetrics(Result):
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
    design_status
        ``(N,)`` strings: ``"ok"``, ``"no_impact"`` (v_c <= 0), ``"peak_at_contact"``
        (a_h peaks at t = 0+: an overdamped pulse, the impact period is delicate),
        ``"lobe_not_closed"`` (no end of the first lobe found; metrics are NaN).
    status
        ``"ok"`` when every design's lobe closed, ``"lobe_not_closed"`` otherwise.
    warnings
        Counts of designs that did not close their lobe or peak at contact.
    constrained
        Whether the constrained model (head against a wall) was used.
    lobe_tail
        Fraction of the impact period during which a_h has already fallen below
        5 % of its peak (sampled on the search grid). See :attr:`delicate_lobe`.
    contact
        The registry name of the contact model whose general response path computed the
        batch (:mod:`designlab.impact.contact.integrated`; its rows are that model's
        columns); ``""`` for a linear kernel's batch.
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
    design_status: NDArray[np.str_]
    constrained: bool = False
    lobe_tail: NDArray[np.float64] | None = None
    status: str = OK
    warnings: tuple[str, ...] = ()
    contact: str = ""

    #: a lobe that lingers below LOW_FRACTION of its peak for more than this
    #: fraction of the impact period is "delicate"
    DELICATE_TAIL: ClassVar[float] = 0.2

    @property
    def delicate_lobe(self) -> NDArray[np.bool_]:
        """Designs whose a_h lingers near zero inside the first lobe (or peaks at contact).

        The lobe end, and eps_max with it, can then jump with a small change of
        the parameters (docs/impact.md, "Metrics"); such results deserve a flag.
        """
        tail = np.zeros(len(self)) if self.lobe_tail is None else self.lobe_tail
        return (np.nan_to_num(tail, nan=0.0) > self.DELICATE_TAIL) | (
            self.design_status == STATUS_PEAK_AT_CONTACT
        )

    @property
    def peak_head_acceleration_g(self) -> NDArray[np.float64]:
        """a_h,max in g (standard gravity, 9.80665 m/s^2)."""
        return self.peak_head_acceleration / STANDARD_GRAVITY

    def __len__(self) -> int:
        return self.params.shape[0]

    def to_frame(self) -> pd.DataFrame:
        """One row per design: parameters and metrics (columns of :mod:`.metric_names`)."""
        df = pd.DataFrame(self.params, columns=list(param_names(self.params.shape[1])))
        df["v_c_m_per_s"] = self.impact_velocity
        df["a_h_max_m_per_s2"] = self.peak_head_acceleration
        df["a_h_max_g"] = self.peak_head_acceleration_g
        df["eps_max_m"] = self.max_compression
        df["peak_force_N"] = self.peak_force
        df["t_imp_s"] = self.impact_duration
        df["status"] = self.design_status
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
            near = np.flatnonzero(stop.any(axis=1))
            if near.size:  # provably <= 0 only below the rounding noise (issue 34)
                level = resp[lobe].take(act[near]).noise(t[near])
                stop[near] &= vals[lobe][near] < -level
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
    params: Mapping[str, ArrayLike] | pd.DataFrame | ArrayLike,
    impact_velocity: ArrayLike,
    *,
    columns: Sequence[str] | None = None,
    constrained: bool = False,
    q2: str = "correct",
    stop_time: float = STOP_TIME.default,
    max_lobe_steps: int = MAX_LOBE_STEPS.default,
    with_force: bool = True,
    lobe_diagnostics: bool = False,
    with_compression: bool = True,
    workers: int | None = None,
) -> ImpactMetrics:
    """First-lobe metrics for a batch of designs (vectorised; the sweep engine).

    Parameters
    ----------
    params
        The model parameters by name: a mapping or a :class:`pandas.DataFrame`
        with exactly the keys :data:`PARAM_NAMES` (``M_r, C_r, K_r, K_c, C_c,
        M_h, C_h, K_h``; scalars and arrays broadcast together), or an ``(N, 8)``
        array together with ``columns``, the names of its columns. SI units:
        kg, N s/m, N/m.
    impact_velocity
        v_c in m/s, scalar or ``(N,)``. The response is linear in v_c and zero
        for v_c <= 0 (docs/impact.md, "Impact velocity").
    columns
        Names of the columns of an array ``params`` (any order); required for an
        array, so that a column order cannot be mistaken silently.
    constrained
        Use the constrained impact (head against a wall; head parameters ignored).
    q2
        ``"correct"`` (default) or ``"printed"``: the thesis's printed q2 of
        (3.5.14), which omits C_r C_h / (M_r M_h) (docs/impact.md, "q2").
    stop_time
        Window length for the constrained impact, s.
    max_lobe_steps
        Give up looking for the end of the first lobe after this many grid steps.
    with_force, with_compression
        Also compute the peak force / eps_max (``False`` leaves it NaN and saves
        work in large sweeps; the constrained model always computes eps_max).
    lobe_diagnostics
        Also measure how long a_h lingers near zero before the lobe ends
        (``lobe_tail``, :attr:`ImpactMetrics.delicate_lobe`).
    workers
        Threads sharing the batch (:data:`designlab.workers.WORKERS`; ``None``: every
        core). The results do not depend on it, to the bit (docs/sweeps.md, "Cores").

    Returns
    -------
    ImpactMetrics

    Examples
    --------
    >>> from designlab.impact.metrics import impact_metrics
    >>> from designlab.impact.model import PARAM_NAMES
    >>> m = impact_metrics([[9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 46.0, 3e3]], 1.25,
    ...                    columns=PARAM_NAMES)
    >>> round(float(m.peak_head_acceleration_g[0]), 2)
    6.12
    >>> impact_metrics([[9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 46.0, 3e3]], 1.25)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: params = 'array of shape (1, 8)' is not allowed:
    an array needs explicit column names (columns=...) ...
    """
    keys = columns if columns is not None else getattr(params, "keys", lambda: ())()
    from designlab.impact.contact import contact_for_columns  # its models call this module

    contact = contact_for_columns(keys)
    if contact is not None and not contact.linear:  # the general path (integrated)
        p = named_columns("params", params, contact.columns, columns=columns)
        return contact.metrics(p, impact_velocity, constrained=constrained, q2=q2,
                               stop_time=stop_time)  # fmt: skip
    p = named_columns("params", params, param_names(keys=list(keys)), columns=columns)
    return metrics_of_matrix(
        p,
        impact_velocity,
        constrained=_check_bool("constrained", constrained),
        q2=q2,
        stop_time=stop_time,
        max_lobe_steps=max_lobe_steps,
        with_force=_check_bool("with_force", with_force),
        lobe_diagnostics=_check_bool("lobe_diagnostics", lobe_diagnostics),
        with_compression=_check_bool("with_compression", with_compression),
        workers=workers,
    )


def _check_bool(name: str, value: object) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise InvalidParameterError(name, value, "must be True or False")
    return bool(value)


def metrics_of_matrix(
    p: NDArray[np.float64],
    impact_velocity: ArrayLike,
    *,
    constrained: bool = False,
    q2: str = "correct",
    stop_time: float = STOP_TIME.default,
    max_lobe_steps: int = MAX_LOBE_STEPS.default,
    with_force: bool = True,
    lobe_diagnostics: bool = False,
    with_compression: bool = True,
    workers: int | None = None,
) -> ImpactMetrics:
    """:func:`impact_metrics` of an ``(N, 8)`` matrix ordered as :data:`PARAM_NAMES`.

    For callers that build the matrix themselves in that order (the foam
    envelope, the criteria); ranges are checked, the column order cannot be.

    Parameters
    ----------
    p
        ``(N, 8)`` (or ``(N, 10)``, full joint) parameter rows.
    impact_velocity, constrained, q2, stop_time, max_lobe_steps, with_force
        As in :func:`impact_metrics`.
    lobe_diagnostics, with_compression, workers
        As in :func:`impact_metrics`.

    Returns
    -------
    ImpactMetrics
    """
    WORKERS.check(workers)
    p = np.atleast_2d(real_array("params", p))
    if p.ndim != 2 or p.shape[1] not in (len(PARAM_NAMES), 10):
        raise InvalidParameterError(
            "params", p.shape, f"must have shape (N, {len(PARAM_NAMES)}) (or (N, 10), full joint)"
        )
    p = _check_params(p, _check_bool("constrained", constrained))
    v = np.atleast_1d(check_closing_velocity(impact_velocity)).ravel()
    if v.size == 0:
        raise InvalidParameterError(
            "impact_velocity", v.tolist(), "needs at least one value", "m/s"
        )
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
    stop_time = STOP_TIME.check(stop_time)
    max_lobe_steps = MAX_LOBE_STEPS.check(max_lobe_steps)

    model = response_model(p, constrained)
    names: tuple[str, ...] = ("compression",) if constrained else ("head_acceleration",)
    if with_compression and not constrained:
        names = (*names, "compression")
    if with_force or constrained:
        names = ("force", *names)
    if kernel.AVAILABLE and model.name == "unconstrained":
        return _reduced_kernel(
            p, v, names, q2, stop_time, max_lobe_steps, lobe_diagnostics, workers
        )
    if model.name == "unconstrained":
        return _reduced_numpy(p, v, names, q2, stop_time, max_lobe_steps, lobe_diagnostics)
    closed = model.name.startswith("full_joint") or model.name == "constrained"
    if kernel.AVAILABLE and closed and check_q2(q2) == "correct":
        full = _full_kernel(
            p, v, names, constrained, stop_time, max_lobe_steps, lobe_diagnostics, workers
        )
        if full is not None:
            return full
    resp = ramp_responses(model, p, names, q2=q2)
    rate = None
    if model.name.startswith("full_joint"):
        rate = grid_rate(resp[names[0]].poles)
    return metrics_from_responses(
        resp,
        p,
        v,
        rate=rate,
        constrained=constrained,
        stop_time=stop_time,
        max_lobe_steps=max_lobe_steps,
        lobe_diagnostics=lobe_diagnostics,
    )


def matrix_metrics(params: ArrayLike, impact_velocity: ArrayLike, **options: Any) -> ImpactMetrics:
    """First-lobe metrics of a parameter matrix in the model's column order.

    ``(N, 8)`` rows ordered as :data:`~designlab.impact.model.PARAM_NAMES` use
    the reduced joint, ``(N, 10)`` rows ordered as
    :data:`~designlab.impact.full_joint_model.FULL_PARAM_NAMES` the full
    series joint (3.4.6). For callers that build the rows themselves (the
    joint comparisons, the benchmark); a mapping by name goes to
    :func:`impact_metrics`.

    Parameters
    ----------
    params
        ``(N, 8)`` or ``(N, 10)`` rows (SI units).
    impact_velocity
        v_c in m/s, scalar or ``(N,)``.
    **options
        Passed on to :func:`metrics_of_matrix` (``constrained``, ``stop_time``, ...).

    Returns
    -------
    ImpactMetrics

    Examples
    --------
    >>> from designlab.impact import FOAM_1, HEAD_MIN
    >>> from designlab.impact.full_joint_model import full_joint_params
    >>> from designlab.impact.series_joint import FullJointContact
    >>> arm = FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    >>> m = matrix_metrics(full_joint_params(arm, FOAM_1, HEAD_MIN)[None, :], 1.25)
    >>> round(float(m.peak_head_acceleration_g[0]), 3)
    4.079
    """
    return metrics_of_matrix(
        np.atleast_2d(np.asarray(params, dtype=float)), impact_velocity, **options
    )


def _reduced_kernel(
    p: NDArray,
    v: NDArray,
    names: tuple[str, ...],
    q2: str,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
    workers: int | None = None,
) -> ImpactMetrics:
    """:func:`metrics_of_matrix` of reduced unconstrained designs by the compiled kernel
    (in ``workers`` threads, :func:`designlab.workers.map_row_blocks`)."""
    q4 = p[:, 2] * p[:, 7] + p[:, 3] * p[:, 7] + p[:, 2] * p[:, 3]
    if np.any(q4 <= 0):
        j = int(np.flatnonzero(q4 <= 0)[0])
        raise ModelError(
            f"design {j}: the model has a pole at s = 0 (no restoring stiffness): "
            "at least two of K_r, K_c, K_h must be positive"
        )
    rows, codes = map_row_blocks(
        partial(
            kernel.reduced_metrics,
            outputs=tuple(k in names for k in _KERNEL_OUTPUTS),
            printed=check_q2(q2) == "printed",
            stop_time=stop_time,
            max_lobe_steps=max_lobe_steps,
            diagnostics=diagnostics,
        ),
        p,
        workers=workers,
        align=LANES,
    )
    if np.any(codes == kernel.OVERFLOW):
        _overflow(p, int(np.flatnonzero(codes == kernel.OVERFLOW)[0]))
    notes = settle_suspects(p, names, q2, rows, codes, stop_time, max_lobe_steps, diagnostics)
    m = _from_kernel(p, v, names, rows, codes, False, diagnostics)
    return replace(m, warnings=(*m.warnings, *notes)) if notes else m


def settle_suspects(
    p: NDArray,
    names: tuple[str, ...],
    q2: str,
    rows: NDArray,
    codes: NDArray,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
) -> tuple[str, ...]:
    """Settle in place the reduced designs whose kernel ``codes`` are ``SUSPECT_*`` (the
    self-check refused them): from 40-digit poles and residues (:func:`_settle_precise`),
    then those still refused by the numpy path (:func:`_settle`); a design neither
    certifies is :data:`UNCERTIFIED` with NaN ``rows``. Returns the warnings' notes.

    A design whose lobe end was not found while a_h came near its rounding noise
    (:data:`kernel.LOBE_NOISE`) is tried at 40 digits too, where the noise level is that
    of one rounding of each term: a lobe end certified there is taken, else the status is
    ``lobe_not_closed``."""
    open_ = np.flatnonzero(codes == kernel.LOBE_NOISE)
    codes[open_] = _LOBE_OPEN_CODE
    printed = check_q2(q2) == "printed"
    notes: tuple[str, ...] = ()
    if open_.size:
        got, again, _ = _settle_precise(
            p[open_], names, printed, codes[open_], stop_time, max_lobe_steps, diagnostics
        )
        done = (again == 0) | (again == _PEAK_CODE)
        rows[open_[done]], codes[open_[done]] = got[done], again[done]
        if np.any(done):
            notes = (
                f"{int(done.sum())} design(s): a_h's lobe end found from extended-precision "
                "poles and residues where double precision could not tell it from rounding noise",
            )
        # a zero of a_h found there but not certified: the lobe may close, so "not closed"
        # would be a claim; these are uncertified (issue 34: one closes at 61.5 s)
        refused = again >= kernel.SUSPECT_LOBE
        codes[open_[refused]] = UNCERTIFIED
        if np.any(refused):
            notes = (
                *notes,
                f"{int(refused.sum())} design(s) uncertified: a_h came within its rounding "
                "noise and a zero found in extended precision could not be certified",
            )
    sus = np.flatnonzero(codes >= kernel.SUSPECT_POLES)
    if not sus.size:
        return notes
    rows[sus], codes[sus], more = _settle_precise(
        p[sus], names, printed, codes[sus], stop_time, max_lobe_steps, diagnostics
    )
    notes = (*notes, *more)
    left = sus[codes[sus] >= kernel.SUSPECT_POLES]
    if left.size:
        resp = ramp_responses(response_model(p[left], False), p[left], names, q2=q2, rows=left)
        h = 0.4 / np.abs(resp[names[0]].poles).max(axis=1)
        rows[left], codes[left], more = _settle(
            resp, h, codes[left], False, stop_time, max_lobe_steps, diagnostics
        )
        notes = (*notes, *more)
    return notes


def _reduced_numpy(
    p: NDArray,
    v: NDArray,
    names: tuple[str, ...],
    q2: str,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
) -> ImpactMetrics:
    """:func:`metrics_of_matrix` of reduced unconstrained designs without numba: the numpy
    modal path checked as the kernel checks it (:func:`_settle`), the designs it does not
    certify again from their 40-digit modal solutions (:func:`_settle_precise`)."""
    say_no_jit("impact metrics")
    resp = ramp_responses(response_model(p, False), p, names, q2=q2)
    h = 0.4 / np.abs(resp[names[0]].poles).max(axis=1)
    zero = np.zeros(p.shape[0], dtype=np.int8)
    rows, codes, notes = _settle(resp, h, zero, False, stop_time, max_lobe_steps, diagnostics)
    bad = np.flatnonzero(codes >= kernel.SUSPECT_POLES)
    if bad.size:
        printed = check_q2(q2) == "printed"
        rows[bad], again, more = _settle_precise(
            p[bad], names, printed, codes[bad], stop_time, max_lobe_steps, diagnostics
        )
        codes[bad] = np.where(again >= kernel.SUSPECT_POLES, UNCERTIFIED, again)
        notes = more  # the numpy path's notes counted these designs uncertified
    m = _from_kernel(p, v, names, rows, codes, False, diagnostics)
    return replace(m, warnings=(*m.warnings, *notes)) if notes else m


def _settle_precise(
    p: NDArray,
    names: tuple[str, ...],
    printed: bool,
    codes: NDArray,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
) -> tuple[NDArray, NDArray, tuple[str, ...]]:
    """Rows and codes of reduced, unconstrained designs the kernel (or the numpy path) did not
    certify (``codes``), from their 40-digit modal solutions (:mod:`.kernel_precise`) with
    error bounds of about one rounding, searched and checked again by the kernel (by
    :func:`_settle` without numba). Designs still not certified keep a ``SUSPECT_*`` code
    (:data:`UNCERTIFIED` without numba). Also a note for the warnings."""
    rows, out = _precise_rows(p, names, printed, codes, stop_time, max_lobe_steps, diagnostics)
    again = np.flatnonzero(out >= kernel.SUSPECT_POLES)
    if kernel.AVAILABLE and again.size:  # refused from double-double: 40-digit decimal
        rows[again], out[again] = _precise_rows(
            p[again], names, printed, codes[again], stop_time, max_lobe_steps, diagnostics,
            compiled=False,
        )  # fmt: skip
    n = p.shape[0]
    done = int(np.sum(out < kernel.SUSPECT_POLES))
    note = (
        f"{n} design(s) not certified in double precision were evaluated from extended-precision "
        f'poles and residues (docs/impact.md, "Self-check"): {done} certified'
    )
    return rows, out, (note,)


def _precise_rows(
    p: NDArray,
    names: tuple[str, ...],
    printed: bool,
    codes: NDArray,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
    compiled: bool = True,
) -> tuple[NDArray, NDArray]:
    """:func:`_settle_precise`'s rows and codes from one extended-precision evaluation
    (``compiled``: double-double first, :func:`.kernel_precise.precise_responses`)."""
    resp, ok = kernel_precise.precise_responses(p, printed=printed, names=names, compiled=compiled)
    n = p.shape[0]
    rows = np.full((n, len(kernel.COLUMNS)), np.nan)
    out = np.where(ok, codes, kernel.SUSPECT_POLES).astype(np.int8)
    i = np.flatnonzero(ok)
    if i.size:
        sub = {k: r.take(i) for k, r in resp.items()}
        h = 0.4 / np.abs(sub[names[0]].poles).max(axis=1)
        if kernel.AVAILABLE:
            res, poly = _kernel_arrays(sub, bounded=True)
            rows[i], out[i] = kernel.modal_metrics(
                sub[names[0]].poles, res, poly, h, lobe=True, window=stop_time,
                max_lobe_steps=max_lobe_steps, diagnostics=diagnostics,
            )  # fmt: skip
            # the kernel found a provable zero of a_h it could not certify: "not closed"
            # contradicts it (a tail within the noise level at 40 digits too): not certified
            open_ = (codes[i] == kernel.SUSPECT_LOBE) & (out[i] == _LOBE_OPEN_CODE)
            out[i] = np.where(open_, kernel.SUSPECT_LOBE, out[i])
        else:
            rows[i], out[i], _ = _settle(
                sub, h, codes[i], False, stop_time, max_lobe_steps, diagnostics
            )
    return rows, out


def _kernel_arrays(resp: dict[str, ModalResponse], bounded: bool) -> tuple[NDArray, NDArray]:
    """The kernel's residues ``(N, 3, K)`` and polynomial parts ``(N, 3, 2)`` of ``resp``, or
    ``(N, 3, ERR_COLUMNS)`` with the residues' and poles' error bounds (``bounded``)."""
    names = tuple(k for k in _KERNEL_OUTPUTS if k in resp)
    n, nk = resp[names[0]].poles.shape
    res = np.zeros((n, 3, nk), dtype=complex)
    poly = np.zeros((n, 3, ERR_COLUMNS if bounded else 2))  # c0, c1, the error bounds
    for o, k in enumerate(_KERNEL_OUTPUTS):
        if k in resp:
            res[:, o] = resp[k].residues
            poly[:, o, 2 - resp[k].poly.shape[1] : 2] = resp[k].poly
            if bounded:
                poly[:, o, 2 : 2 + nk] = resp[k].errors[:, :, 0]
                poly[:, o, 2 + MAX_TERMS : 2 + MAX_TERMS + nk] = resp[k].errors[:, :, 1]
    return res, poly


def _eigen_ramp(
    model: LinearImpactModel, params: NDArray, outputs: tuple[str, ...], rows: NDArray | None
) -> dict[str, ModalResponse]:
    """:func:`ramp_responses` of the full joint by the eigen-decomposition; a design where it
    fails (a singular eigenvector matrix) or gives non-finite responses is
    :func:`_overflow`'s error."""
    try:
        with np.errstate(all="ignore"):
            resp = modal_families(model, params, outputs)["ramp"]
    except np.linalg.LinAlgError:
        for j in range(params.shape[0]):  # the first design that fails alone
            try:
                with np.errstate(all="ignore"):
                    modal_families(model, params[j : j + 1], outputs)
            except np.linalg.LinAlgError:
                _overflow(params, j, rows)
        raise
    for r in resp.values():
        parts = (r.poles, r.residues, r.poly)
        _check_finite(params, np.concatenate([np.abs(x) for x in parts], axis=1), rows)
    return resp


def _check_finite(p: NDArray, den: NDArray, rows: NDArray | None = None) -> None:
    """Raise :func:`_overflow`'s error for the first design whose denominator is not finite
    (``den`` of the designs ``p[rows]`` when ``rows`` is given)."""
    finite = np.all(np.isfinite(den), axis=1)
    if not np.all(finite):
        _overflow(p, int(np.flatnonzero(~finite)[0]), rows)


def _overflow(p: NDArray, j: int, rows: NDArray | None = None) -> None:
    """Raise the error of the design ``p[j]`` (row ``rows[j]`` of the caller's batch, if
    given) whose model coefficients overflow double precision."""
    raise InvalidParameterError(
        f"params[{j if rows is None else int(rows[j])}]",
        p[j].tolist(),
        "gives model coefficients beyond double precision (stiffness or damping over mass "
        "near 1e308): give the parameters in SI units of physical size",
    )


#: the kernel's outputs, in its order
_KERNEL_OUTPUTS = ("force", "head_acceleration", "compression")
#: the kernel's status codes by number: 4 (overflow) raises, 5-7 are settled by
#: :func:`_settle`, and :data:`UNCERTIFIED` is what it could not settle
UNCERTIFIED = 8
_KERNEL_STATUS = np.array(
    [*kernel.STATUS_CODES, "overflow", *[STATUS_UNCERTIFIED] * 4], dtype=str
)  # fixed width: fast compares
_NO_IMPACT_CODE = kernel.STATUS_CODES.index(STATUS_NO_IMPACT)
_LOBE_OPEN_CODE = kernel.STATUS_CODES.index(STATUS_LOBE_OPEN)
_PEAK_CODE = kernel.STATUS_CODES.index(STATUS_PEAK_AT_CONTACT)


def _from_kernel(
    p: NDArray,
    v: NDArray,
    names: tuple[str, ...],
    rows: NDArray,
    codes: NDArray,
    constrained: bool,
    diagnostics: bool,
) -> ImpactMetrics:
    """:class:`ImpactMetrics` from the kernel's unit-v_c rows (:data:`kernel.COLUMNS`)."""
    col = {k: i for i, k in enumerate(kernel.COLUMNS)}
    pairs = {"force": ("t_f", "f_max"), "head_acceleration": ("t_a", "a_max")}
    pairs["compression"] = ("t_eps", "eps_max")
    out = {k: (rows[:, col[pairs[k][0]]], rows[:, col[pairs[k][1]]]) for k in names}
    codes = np.where(v <= 0, _NO_IMPACT_CODE, codes)  # as _scaled marks them
    status = _KERNEL_STATUS[codes]
    counts: dict[str, int] = {}
    tally = np.bincount(codes, minlength=_KERNEL_STATUS.size)
    for name, count in zip(_KERNEL_STATUS, tally, strict=True):
        counts[str(name)] = counts.get(str(name), 0) + int(count)
    t_low = rows[:, col["t_low"]] if diagnostics else np.full(p.shape[0], np.nan)
    return _scaled(
        p, v, out, rows[:, col["t_imp"]], t_low, status, constrained, diagnostics, counts
    )


def _modal_kernel(
    resp: dict[str, ModalResponse],
    p: NDArray,
    v: NDArray,
    h: NDArray,
    constrained: bool,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
) -> ImpactMetrics | None:
    """:func:`metrics_from_responses` by the compiled kernel (None if it does not apply)."""
    part = _modal_rows(resp, h, constrained, stop_time, max_lobe_steps, diagnostics)
    if part is None:
        return None
    rows, codes = part
    sus = np.flatnonzero(codes >= kernel.SUSPECT_POLES)
    notes: tuple[str, ...] = ()
    if sus.size:
        sub = {k: r.take(sus) for k, r in resp.items()}
        rows[sus], codes[sus], notes = _settle(
            sub, h[sus], codes[sus], constrained, stop_time, max_lobe_steps, diagnostics
        )
    names = tuple(k for k in _KERNEL_OUTPUTS if k in resp)
    m = _from_kernel(p, v, names, rows, codes, constrained, diagnostics)
    return replace(m, warnings=(*m.warnings, *notes)) if notes else m


def _modal_rows(
    resp: dict[str, ModalResponse],
    h: NDArray,
    constrained: bool,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
) -> tuple[NDArray, NDArray] | None:
    """The kernel's rows and status codes of responses built elsewhere (None if it does not apply).

    The outputs must share their poles, at most :data:`kernel.MAX_POLES` of them.
    """
    names = tuple(k for k in _KERNEL_OUTPUTS if k in resp)
    poles = resp[names[0]].poles
    if any(not np.array_equal(resp[k].poles, poles) for k in names[1:]):
        return None
    n, width = poles.shape
    if width > kernel.MAX_POLES:
        return None
    res = np.zeros((n, 3, width), dtype=complex)
    poly = np.zeros((n, 3, 2))
    for o, k in enumerate(_KERNEL_OUTPUTS):
        if k in resp:
            res[:, o] = resp[k].residues
            poly[:, o, 2 - resp[k].poly.shape[1] :] = resp[k].poly
    return kernel.modal_metrics(
        poles,
        res,
        poly,
        h,
        lobe=not constrained,
        window=stop_time,
        max_lobe_steps=max_lobe_steps,
        diagnostics=diagnostics,
    )


def _full_kernel(
    p: NDArray,
    v: NDArray,
    names: tuple[str, ...],
    constrained: bool,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
    workers: int | None = None,
) -> ImpactMetrics | None:
    """:func:`metrics_of_matrix` of full-joint rows (or reduced, constrained) by the compiled
    kernel (:mod:`.kernel_full`).

    A design the kernel does not certify (nearly repeated or ill-conditioned
    poles) is evaluated from the responses of :func:`ramp_responses` (the
    eigen-decomposition for the full joint), and a warning counts them.
    """
    sel = tuple(k in names for k in _KERNEL_OUTPUTS)
    rows, codes = map_row_blocks(
        partial(kernel_full.full_metrics, outputs=sel, constrained=constrained,
                stop_time=stop_time, max_lobe_steps=max_lobe_steps, diagnostics=diagnostics),
        p, workers=workers,
    )  # fmt: skip
    back = np.flatnonzero((codes == kernel_full.FALLBACK) | (codes >= kernel.SUSPECT_POLES))
    if back.size and p.shape[1] == len(FULL_PARAM_NAMES):
        check_eigen_route(p[back], back, constrained)
    notes: tuple[str, ...] = ()
    if back.size:
        resp = ramp_responses(response_model(p, constrained), p[back], names, rows=back)
        poles = resp[names[0]].poles
        h = 0.4 / (grid_rate(poles) if p.shape[1] == 10 else np.abs(poles).max(axis=1))
        part = _modal_rows(resp, h, constrained, stop_time, max_lobe_steps, diagnostics)
        if part is None:
            return None
        rows[back], codes[back] = part
        sus = np.flatnonzero(codes[back] >= kernel.SUSPECT_POLES)
        if sus.size:
            sub = {k: r.take(sus) for k, r in resp.items()}
            rows[back[sus]], codes[back[sus]], notes = _settle(
                sub, h[sus], codes[back[sus]], constrained, stop_time, max_lobe_steps, diagnostics
            )
    m = _from_kernel(p, v, names, rows, codes, constrained, diagnostics)
    if notes:
        m = replace(m, warnings=(*m.warnings, *notes))
    if back.size:
        note = (
            f"{back.size} design(s): poles nearly repeated or ill-conditioned; evaluated "
            'by the numpy modal path (docs/impact_joint.md, "Compiled path")'
        )
        m = replace(m, warnings=(*m.warnings, note))
    return m


def _settle(
    resp: dict[str, ModalResponse],
    h: NDArray,
    codes: NDArray,
    constrained: bool,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
) -> tuple[NDArray, NDArray, tuple[str, ...]]:
    """Rows and codes of designs the kernel did not certify (its ``SUSPECT_*`` ``codes``),
    by the numpy modal path (:func:`_numpy_rows`), checked again by
    :func:`designlab.impact.kernel.audit_metrics`; a design that fails that too is
    :data:`UNCERTIFIED` (NaN rows). Also a note per reason for the warnings."""
    rows, again = _numpy_rows(resp, h, constrained, stop_time, max_lobe_steps, diagnostics)
    names = tuple(k for k in _KERNEL_OUTPUTS if k in resp)
    nk = resp[names[0]].poles.shape[1]
    bounded = nk <= MAX_TERMS and all(resp[k].errors is not None for k in names)
    res, poly = _kernel_arrays(resp, bounded)
    poles = resp[names[0]].poles
    if kernel.AVAILABLE:
        audit = kernel.audit_metrics(poles, res, poly, rows, again, lobe=not constrained)
    else:  # the same check, vectorised (the kernel's loops run slowly uncompiled)
        audit = audit_metrics_numpy(poles, res, poly, rows, again, lobe=not constrained)
    # the kernel found a provable zero of a_h it could not certify: "not closed" contradicts it
    bad = (audit >= kernel.SUSPECT_POLES) | (
        (codes == kernel.SUSPECT_LOBE) & (audit == kernel.STATUS_CODES.index(STATUS_LOBE_OPEN))
    )
    rows[bad] = np.nan
    notes = []
    for code, why in kernel.SUSPECT_REASONS.items():
        first = codes == code
        if np.any(first):
            lost = int(np.sum(first & bad))
            notes.append(
                f"{int(np.sum(first))} design(s): {why} by the compiled kernel; evaluated by "
                f"the numpy modal path"
                + (f", which could not certify {lost} either" if lost else "")
            )
    for code, why in kernel.SUSPECT_REASONS.items():
        lost = int(np.sum(audit == code))
        if lost:
            notes.append(f"{lost} design(s) uncertified (metrics NaN): {why} by the numpy path")
    return rows, np.where(bad, UNCERTIFIED, audit).astype(np.int8), tuple(notes)


#: designs per block of :func:`audit_metrics_numpy` (its samples take 2048 x 5 complex
#: values per design)
_AUDIT_BLOCK = 64


def audit_metrics_numpy(
    poles: NDArray[np.complex128],
    residues: NDArray[np.complex128],
    poly: NDArray[np.float64],
    rows: NDArray[np.float64],
    codes: NDArray[np.int8],
    *,
    lobe: bool,
) -> NDArray[np.int8]:
    """:func:`designlab.impact.kernel.audit_metrics` in numpy, for a process without numba.

    The same a-posteriori check (``kernel.sampled_check``): at the midpoints
    ``(j + 1/2) t_imp / n`` (``j < n - 1``) of ``n`` uniform cells over ``[0, t_imp]``,
    no output may exceed its maximum by more than 1e-8 relative, and (for a lobe) a_h
    may not be below minus its rounding-noise level (``kernel_modal.noise``); no output may
    exceed its maximum at ``t_imp`` either (the window's end counts). The cells are as
    wide as the numpy path's grid step ``0.4 / max|p_k|`` (the kernel's search samples
    every third: :data:`designlab.impact.kernel_lobe.STRIDE`), at least 16 and at most
    ``AUDIT_CELLS``. Only designs with code 0 (ok) or 2 (peak at contact) are checked.

    Parameters
    ----------
    poles, residues, poly, rows, codes, lobe
        As :func:`designlab.impact.kernel.audit_metrics`.

    Returns
    -------
    numpy.ndarray
        The codes, ``kernel.SUSPECT_MAXIMUM`` or ``kernel.SUSPECT_LOBE`` where a check fails.

    Examples
    --------
    >>> import numpy as np
    >>> poles = np.array([[-1.0 + 0j]]); poly = np.zeros((1, 3, 2))
    >>> res = np.zeros((1, 3, 1), dtype=complex); res[0, 1, 0] = 1.0  # a_h = exp(-t)
    >>> row = np.full((1, 8), np.nan); row[0, [0, 3, 4]] = 1.0, 2.0, 0.0
    >>> audit_metrics_numpy(poles, res, poly, row, np.zeros(1, np.int8), lobe=True)
    array([0], dtype=int8)
    >>> row[0, 0] = 0.9  # a maximum below what the samples show
    >>> audit_metrics_numpy(poles, res, poly, row, np.zeros(1, np.int8), lobe=True)
    array([7], dtype=int8)
    """
    out = np.array(codes, dtype=np.int8)
    todo = np.flatnonzero((out == 0) | (out == 2))
    t_imp = rows[todo, kernel.COLUMNS.index("t_imp")]
    with np.errstate(invalid="ignore", over="ignore"):
        cells = np.ceil(t_imp * np.abs(poles[todo]).max(axis=1) / 0.4)
    cells = np.clip(np.nan_to_num(cells, nan=kernel.AUDIT_CELLS), 16, kernel.AUDIT_CELLS)
    order = np.argsort(cells, kind="stable")  # blocks of similar sizes
    todo, cells = todo[order], cells[order].astype(np.int64)
    for start in range(0, todo.size, _AUDIT_BLOCK):
        i = todo[start : start + _AUDIT_BLOCK]
        n = cells[start : start + _AUDIT_BLOCK]
        block = _audit_block_numpy(poles[i], residues[i], poly[i], rows[i], lobe, n)
        out[i] = np.where(block == 0, out[i], block)  # a passed design keeps its code (0 or 2)
    return out


#: each kernel output's maximum and its time (columns of :data:`kernel.COLUMNS`)
_MAXIMA = (("f_max", "t_f"), ("a_max", "t_a"), ("eps_max", "t_eps"))


def _audit_block_numpy(
    poles: NDArray, res: NDArray, poly: NDArray, rows: NDArray, lobe: bool, n: NDArray
) -> NDArray[np.int8]:
    """:func:`audit_metrics_numpy` of one block of designs (all to be checked; ``n`` cells
    each)."""
    col = {k: i for i, k in enumerate(kernel.COLUMNS)}
    cells = int(n.max()) - 1
    t_imp = rows[:, col["t_imp"]]
    w = t_imp / n
    j = np.arange(cells)[None, :]
    t = (j + 0.5) * w[:, None]  # (n, cells): a design's samples beyond its own are left out
    mine = j < (n - 1)[:, None]
    ex = []  # exp(p_k t) per pole, (n, cells): by recurrence, as the kernel
    with np.errstate(over="ignore", invalid="ignore"):
        for k in range(poles.shape[1]):
            z = np.exp(poles[:, k] * w)
            e = np.cumprod(np.broadcast_to(z[:, None], t.shape), axis=1)
            ex.append(e * np.exp(-0.5 * poles[:, k] * w)[:, None])
    code = np.zeros(poles.shape[0], dtype=np.int8)
    for o, (top_col, t_col) in enumerate(
        (("f_max", "t_f"), ("a_max", "t_a"), ("eps_max", "t_eps"))
    ):
        if not (np.any(res[:, o]) or np.any(poly[:, o])):
            continue
        y = poly[:, o, :1] * t + poly[:, o, 1:2]  # c0 t + c1 (error bounds follow)
        for k, e in enumerate(ex):  # Re(r e) = Re r Re e - Im r Im e
            y += res[:, o, k].real[:, None] * e.real - res[:, o, k].imag[:, None] * e.imag
        top = rows[:, col[top_col]]
        end, size = _values_at(poles, res[:, o], poly[:, o], t_imp)  # the window's end counts
        at, size = _values_at(poles, res[:, o], poly[:, o], rows[:, col[t_col]])
        with np.errstate(invalid="ignore"):
            over = (y > (top + 1e-8 * np.abs(top))[:, None]) & mine
            high = np.any(over, axis=1) | (end > top + 1e-8 * np.abs(top))
            # the maximum is the value at its own time (to the search's 1e-8 and rounding)
            high |= np.abs(at - top) > 1e-8 * np.abs(top) + kernel_modal.NOISE * size
        if lobe and o == 1:
            big = np.abs(res[:, o]).max(axis=1)[:, None]
            noise = np.abs(poly[:, o, :1] * t) + np.abs(poly[:, o, 1:2])
            for e in ex:
                noise += big * np.abs(e)  # exp(Re p t) = |exp(p t)|
            with np.errstate(invalid="ignore"):
                under = (y < 0.0) & (y < -kernel_modal.NOISE * noise) & mine
            # the kernel stops at the first failing sample: a negative a_h before any high one
            first_high = np.where(high, np.argmax(over, axis=1), cells)
            lobe_bad = np.any(under, axis=1) & (np.argmax(under, axis=1) < first_high)
            code = np.where((code == 0) & lobe_bad, kernel.SUSPECT_LOBE, code)
        code = np.where((code == 0) & high, kernel.SUSPECT_MAXIMUM, code)
    if poly.shape[2] >= ERR_COLUMNS:  # the residues' and poles' error bounds are known
        code = np.where(code == 0, _bounds_check(poles, res, poly, rows, lobe), code)
    return code.astype(np.int8)


def _bounds_check(
    poles: NDArray, res: NDArray, poly: NDArray, rows: NDArray, lobe: bool
) -> NDArray[np.int8]:
    """The kernel's checks of the error bounds (``kernel.sampled_check``): the rounding noise
    (:func:`.kernel_modal.noise`) may move the lobe end by at most ``kernel.TIMP_ERROR``
    (relative), the residues' and poles' errors may take at most ``kernel.TERM_ERROR`` of
    each maximum; 0 or the ``SUSPECT_*`` code of each design."""
    nk = poles.shape[1]
    t_imp = rows[:, kernel.COLUMNS.index("t_imp")]
    code = np.zeros(poles.shape[0], dtype=np.int8)
    with np.errstate(over="ignore", invalid="ignore"):
        e = np.exp(poles * t_imp[:, None])
        for o, (top_col, _) in enumerate(_MAXIMA):
            if not (np.any(res[:, o]) or np.any(poly[:, o])):
                continue
            err0, err1 = poly[:, o, 2 : 2 + nk], poly[:, o, 2 + MAX_TERMS : 2 + MAX_TERMS + nk]
            if lobe and o == 1:
                c0, c1 = poly[:, o, 0], poly[:, o, 1]
                size = np.abs(c0 * t_imp) + np.abs(c1) + (np.abs(res[:, o]) * np.abs(e)).sum(1)
                extra = ((err0 + err1 * t_imp[:, None]) * np.abs(e)).sum(axis=1)
                slope = c0 + (res[:, o] * poles * e).real.sum(axis=1)
                moved = kernel_modal.NOISE * size + extra > kernel.TIMP_ERROR * t_imp * np.abs(
                    slope
                )
                code = np.where((code == 0) & moved, kernel.SUSPECT_LOBE, code)
            top = np.abs(rows[:, kernel.COLUMNS.index(top_col)])
            big = (err0 + err1 * t_imp[:, None]).sum(axis=1) > kernel.TERM_ERROR * top
            code = np.where((code == 0) & big, kernel.SUSPECT_MAXIMUM, code)
    return code


def _values_at(
    poles: NDArray, res: NDArray, poly: NDArray, t: NDArray
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``y(t)`` of one output of each design (``res`` ``(n, K)``, ``poly`` ``(n, >= 2)`` with
    ``c0, c1`` first) and the sum of its terms' magnitudes there."""
    e = np.exp(poles * t[:, None])
    y = poly[:, 0] * t + poly[:, 1] + (res * e).real.sum(axis=1)
    size = np.abs(poly[:, 0] * t) + np.abs(poly[:, 1]) + np.abs(res * e).sum(axis=1)
    return y, size


def _numpy_rows(
    resp: dict[str, ModalResponse],
    h: NDArray,
    constrained: bool,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
) -> tuple[NDArray, NDArray]:
    """The numpy path's unit-v_c rows (:data:`kernel.COLUMNS`) and status codes."""
    n = h.size
    names = tuple(k for k in _KERNEL_OUTPUTS if k in resp)
    status = np.full(n, STATUS_OK, dtype=object)
    out, t_imp, t_low = _window_maxima(
        resp, names, h, status, constrained, stop_time, max_lobe_steps, diagnostics
    )
    col = {k: i for i, k in enumerate(kernel.COLUMNS)}
    rows = np.full((n, len(kernel.COLUMNS)), np.nan)
    pairs = {"force": ("t_f", "f_max"), "head_acceleration": ("t_a", "a_max")}
    pairs["compression"] = ("t_eps", "eps_max")
    for k in names:
        rows[:, col[pairs[k][0]]], rows[:, col[pairs[k][1]]] = out[k]
    rows[:, col["t_imp"]] = t_imp
    rows[:, col["t_low"]] = t_low
    codes = np.array([kernel.STATUS_CODES.index(s) for s in status], dtype=np.int8)
    return rows, codes


def metrics_from_responses(
    resp: dict[str, ModalResponse],
    p: NDArray[np.float64],
    v: NDArray[np.float64],
    *,
    constrained: bool = False,
    stop_time: float = STOP_TIME.default,
    max_lobe_steps: int = MAX_LOBE_STEPS.default,
    lobe_diagnostics: bool = False,
    rate: NDArray[np.float64] | None = None,
) -> ImpactMetrics:
    """First-lobe metrics from unit-velocity responses already built (see :func:`impact_metrics`).

    ``resp`` maps output names (``head_acceleration`` unless constrained, and any of
    ``compression`` and ``force``) to the responses to v_c = 1 m/s of the designs
    ``p`` (``(N, 8)``); ``v`` is ``(N,)``. Inputs are not validated here.

    Parameters
    ----------
    resp
        Output name -> response to v_c = 1 m/s of every design.
    p
        ``(N, 8)`` model parameters of the designs.
    v
        ``(N,)`` impact velocities in m/s.
    constrained
        Whether the head is constrained (no head acceleration).
    stop_time
        Longest impact considered in s.
    max_lobe_steps
        Most grid steps of the march to the end of the first lobe.
    lobe_diagnostics
        Also return the lobe-search diagnostics.
    rate
        Fastest rate (1/s, ``(N,)``) the search grid must resolve; default the
        largest pole modulus. The full joint passes
        :func:`designlab.impact.full_joint.grid_rate` (its stiff motor node is
        not resolved).
    """
    n = p.shape[0]
    names = tuple(k for k in ("force", "head_acceleration", "compression") if k in resp)
    status = np.full(n, STATUS_OK, dtype=object)

    pol = resp[names[0]].poles
    # ``rate`` (1/s) replaces the largest pole modulus for the full joint, whose stiff
    # motor node need not be resolved (designlab.impact.full_joint_model.grid_rate)
    h = 0.4 / (
        np.abs(pol).max(axis=1) if rate is None else rate
    )  # <= 1/15 of the fastest mode's period
    if kernel.AVAILABLE and all(resp[k].poly.shape[1] <= 2 for k in names):
        fast = _modal_kernel(
            resp, p, v, h, constrained, stop_time, max_lobe_steps, lobe_diagnostics
        )
        if fast is not None:
            return fast
    if not kernel.AVAILABLE:
        say_no_jit("impact metrics")
        if all(resp[k].poly.shape[1] <= 2 for k in names):  # checked as the kernel checks
            zero = np.zeros(n, dtype=np.int8)
            rows, codes, notes = _settle(
                resp, h, zero, constrained, stop_time, max_lobe_steps, lobe_diagnostics
            )
            m = _from_kernel(p, v, names, rows, codes, constrained, lobe_diagnostics)
            return replace(m, warnings=(*m.warnings, *notes)) if notes else m
    out, t_imp, t_low = _window_maxima(
        resp, names, h, status, constrained, stop_time, max_lobe_steps, lobe_diagnostics
    )
    return _scaled(p, v, out, t_imp, t_low, status, constrained, lobe_diagnostics)


def _window_maxima(
    resp: dict[str, ModalResponse],
    names: tuple[str, ...],
    h: NDArray,
    status: NDArray,
    constrained: bool,
    stop_time: float,
    max_lobe_steps: int,
    diagnostics: bool,
) -> tuple[dict[str, tuple[NDArray, NDArray]], NDArray, NDArray]:
    """The numpy path's window (the lobe, or ``[0, stop_time]`` constrained) and its maxima.

    Marks ``status`` where the lobe does not close; returns the maxima of
    :func:`_lobe_maxima`, ``t_imp`` and ``t_low`` (NaN without diagnostics or constrained).
    """
    t_low = np.full(h.size, np.nan)
    if constrained:
        h = np.minimum(h, stop_time / 64.0)
        t_imp = np.full(h.size, float(stop_time))
    else:
        t_imp, found, t_low = _lobe_end(
            resp["head_acceleration"], h, stop_time, max_lobe_steps, diagnostics
        )
        status[~found] = STATUS_LOBE_OPEN
    return _lobe_maxima(resp, names, t_imp, h, status), t_imp, t_low


def _lobe_end(
    a_h: ModalResponse, h: NDArray, stop_time: float, max_lobe_steps: int, diagnose: bool
) -> tuple[NDArray, NDArray, NDArray]:
    """The end of the first lobe: march the grid, certify the crossing, polish it by Newton.

    Returns the impact period (NaN where no end was found), whether it was found,
    and the first time a_h fell below :data:`LOW_FRACTION` of its running peak.
    """
    n = h.size
    _lo, hi, found, _, guess, t_low = _march(
        {"head_acceleration": a_h},
        "head_acceleration",
        h,
        np.full(n, float(stop_time)),
        block=12,
        max_steps=max_lobe_steps,
        diagnose=diagnose,
    )
    t_imp = np.full(n, np.nan)
    if np.any(found):
        idx = np.flatnonzero(found)
        a_resp = a_h.take(idx)
        # a dip below zero between two grid nodes ends the lobe earlier
        lo_c, hi_c = certified_first_crossing(a_resp, hi[idx], h[idx])
        moved = hi_c < hi[idx]
        g = np.where(moved, 0.5 * (lo_c + hi_c), guess[idx])
        t_imp[idx] = first_crossing(a_resp, lo_c, hi_c, guess=g)
    return t_imp, found, t_low


def _lobe_maxima(
    resp: dict[str, ModalResponse],
    names: tuple[str, ...],
    t_imp: NDArray,
    h: NDArray,
    status: NDArray,
) -> dict[str, tuple[NDArray, NDArray]]:
    """Certified maxima ``(time, value)`` of each output over ``[0, t_imp]`` (unit v_c).

    Marks the designs whose a_h peaks at contact in ``status``.
    """
    n = t_imp.size
    idx = np.flatnonzero(np.isfinite(t_imp))
    out: dict[str, tuple[NDArray, NDArray]] = {}
    for name in names:
        tt = np.full(n, np.nan)
        yy = np.full(n, np.nan)
        if idx.size:
            # cells of <= 1.2 / |p|max (a fifth of the fastest period); the bounds refine them
            t_s, y_s = certified_maximum(
                resp[name].take(idx), np.zeros(idx.size), t_imp[idx], 3.0 * h[idx]
            )
            tt[idx], yy[idx] = t_s, y_s
            if name == "head_acceleration":
                status[idx[t_s <= 0.0]] = STATUS_PEAK_AT_CONTACT
        out[name] = (tt, yy)
    return out


def _scaled(
    p: NDArray,
    v: NDArray,
    out: dict[str, tuple[NDArray, NDArray]],
    t_imp: NDArray,
    t_low: NDArray,
    status: NDArray,
    constrained: bool,
    lobe_diagnostics: bool,
    counts: dict[str, int] | None = None,
) -> ImpactMetrics:
    """The metrics at the designs' v_c (the model is linear in v_c; no impact for v_c <= 0);
    ``counts``: the number of designs of each status, where the caller has them."""
    n = p.shape[0]
    if constrained:
        t_a = a_max = np.zeros(n)
    else:
        t_a, a_max = out["head_acceleration"]

    tail = None
    if lobe_diagnostics:
        with np.errstate(divide="ignore", invalid="ignore"):
            tail = np.where(np.isfinite(t_low), (t_imp - t_low) / t_imp, 0.0)

    # linearity in v_c; zero response for v_c <= 0
    scale = np.where(v > 0, v, 0.0)
    status[v <= 0] = STATUS_NO_IMPACT
    none = v <= 0
    some = bool(np.any(none))
    t_imp_out = np.where(none, 0.0, t_imp) if some else t_imp.copy()

    def _z(arr: NDArray) -> NDArray:
        return np.where(none, 0.0, arr) if some else arr.copy()

    nan = np.full(n, np.nan)
    if counts is None:
        counts = _status_counts(status)

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
        design_status=status if status.dtype.kind == "U" else status.astype(str),
        constrained=constrained,
        lobe_tail=None if tail is None else np.where(none | constrained, np.nan, tail),
        status=_batch_status(counts),
        warnings=_batch_warnings(counts),
    )


def _status_counts(status: NDArray) -> dict[str, int]:
    """The number of designs of each status that the batch's status and warnings name."""
    names = (STATUS_UNCERTIFIED, STATUS_LOBE_OPEN, STATUS_PEAK_AT_CONTACT)
    return {k: int(np.count_nonzero(status == k)) for k in names}


def _batch_status(counts: dict[str, int]) -> Status:
    """The batch's status: uncertified before lobe_not_closed before ok."""
    if counts.get(STATUS_UNCERTIFIED, 0):
        return ImpactStatus.UNCERTIFIED
    return ImpactStatus.LOBE_NOT_CLOSED if counts.get(STATUS_LOBE_OPEN, 0) else OK


def _batch_warnings(counts: dict[str, int]) -> tuple[str, ...]:
    out = []
    n_bad = counts.get(STATUS_UNCERTIFIED, 0)
    if n_bad:
        out.append(
            f"{n_bad} design(s) uncertified: the a-posteriori checks failed on both the "
            'compiled and the numpy path; metrics are NaN (docs/impact.md, "Self-check")'
        )
    n_open = counts.get(STATUS_LOBE_OPEN, 0)
    if n_open:
        out.append(f"{n_open} design(s): the first impact lobe did not close; metrics are NaN")
    n_pac = counts.get(STATUS_PEAK_AT_CONTACT, 0)
    if n_pac:
        out.append(
            f"{n_pac} design(s): a_h peaks at contact (overdamped pulse, xi_c far above "
            '0.05-0.2); the impact period is delicate (docs/impact.md, "Metrics")'
        )
    return tuple(out)


def hic_batch(
    metrics: ImpactMetrics, window: float = HIC_WINDOW.default, samples: int = 400
) -> NDArray:
    """HIC (standard definition; docs/impact.md, "HIC") over the first lobe of each design.

    The head's velocity relative to the torso is the exact integral of a_h, so
    the mean acceleration over ``[t1, t2]`` is ``(v(t2) - v(t1)) / (t2 - t1)``;
    it is evaluated exactly on ``samples`` points of ``[0, t_imp]``, the windows
    with ``t2 - t1 <= window`` are searched on that grid, and the best window is
    refined by zooming grids around it (never below the grid value).

    Parameters
    ----------
    metrics
        First-lobe metrics of the designs (:func:`impact_metrics`).
    window
        Longest HIC window in s.
    samples
        Grid points over the first lobe before the window search is refined.

    Examples
    --------
    >>> from designlab.impact.model import PARAM_NAMES
    >>> m = impact_metrics([9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 0.0, 4e3], 1.25,
    ...                    columns=PARAM_NAMES)
    >>> round(float(hic_batch(m, 0.015)[0]), 2)
    1.37
    """
    if not isinstance(metrics, ImpactMetrics):
        raise InvalidParameterError("metrics", metrics, "must be an ImpactMetrics")
    window = HIC_WINDOW.check(window)
    samples = HIC_SAMPLES.check(samples)
    if metrics.contact:  # a general-path batch: its model integrates the head velocity
        from designlab.impact.contact import CONTACTS  # its models call this module

        return CONTACTS.get(metrics.contact).hic(metrics, window, samples)
    n = len(metrics)
    out = np.zeros(n)
    t_imp = metrics.impact_duration
    idx = np.flatnonzero((metrics.impact_velocity > 0) & np.isfinite(t_imp) & (t_imp > 0))
    if metrics.constrained or idx.size == 0:
        return out
    resp = ramp_responses(
        response_model(metrics.params, False), metrics.params[idx], ("head_velocity",)
    )
    out[idx] = hic_of_velocity(
        resp["head_velocity"], metrics.impact_velocity[idx], t_imp[idx], window, samples
    )
    return out


def hic_of_velocity(
    vel: Any, scale: NDArray, t_end: NDArray, window: float, samples: int
) -> NDArray[np.float64]:
    """HIC of designs from their head velocity over ``[0, t_end]`` (:func:`hic_batch`'s search).

    The mean acceleration over ``[t1, t2]`` is ``(v(t2) - v(t1)) / (t2 - t1)``; the
    windows with ``t2 - t1 <= window`` are searched on ``samples`` points of each
    ``[0, t_end]``, and the best one is refined by zooming grids around it.

    Parameters
    ----------
    vel
        The head velocity: ``vel.evaluate(t)`` gives, for ``(n, k)`` times, the ``(n, k)``
        velocities (in m/s once multiplied by ``scale``): a linear model's exact response,
        or an integrated one's dense output.
    scale
        ``(n,)`` factors of the velocities (v_c for a unit-speed linear response).
    t_end
        ``(n,)`` ends of the first lobes, s (finite and positive).
    window, samples
        Longest HIC window (s) and grid points, as checked by :func:`hic_batch`.

    Returns
    -------
    numpy.ndarray
        ``(n,)`` HIC values.
    """
    t_end = np.asarray(t_end, dtype=float)
    n = t_end.size
    rel = np.linspace(0.0, 1.0, samples)
    t = t_end[:, None] * rel[None, :]
    v = vel.evaluate(t) * scale[:, None]
    dt = t_end / (samples - 1)
    best = np.zeros(n)
    arg = np.zeros((n, 2))
    max_lag = int(min(samples - 1, np.ceil(window / dt.min())))
    rows = np.arange(n)
    for lag in range(1, max_lag + 1):
        dur = lag * dt
        ok = dur <= window * (1 + 1e-12)
        if not np.any(ok):
            break
        dv = v[:, lag:] - v[:, :-lag]
        j = dv.argmax(axis=1)
        mean_g = dv[rows, j] / (dur * STANDARD_GRAVITY)
        val = np.where(ok & (mean_g > 0), dur * np.maximum(mean_g, 0.0) ** 2.5, 0.0)
        better = val > best
        best = np.where(better, val, best)
        arg[better, 0] = t[better, j[better]]
        arg[better, 1] = t[better, j[better] + lag]
    return _zoom_hic(vel, scale, t_end, window, best, arg, dt)


def _zoom_hic(
    vel: Any,
    scale: NDArray,
    t_end: NDArray,
    window: float,
    best: NDArray,
    arg: NDArray,
    step: NDArray,
    points: int = 21,
    rounds: int = 14,
) -> NDArray[np.float64]:
    """Refine the best HIC window ``arg`` (t1, t2) by zooming grids around it.

    Each round evaluates ``points x points`` windows in a box of half-width
    ``2 step`` centred on the best window (which is one of them), keeps the best
    feasible one (``0 <= t1 < t2 <= t_end``, ``t2 - t1 <= window``) and shrinks
    the box by ``points / 4``. The value never decreases.
    """
    n = best.size
    k = np.linspace(-1.0, 1.0, points)
    best = best.copy()
    arg = arg.copy()
    step = np.asarray(step, dtype=float).copy()
    rows = np.arange(n)
    for _ in range(rounds):
        t1 = np.clip(arg[:, :1] + 2.0 * step[:, None] * k[None, :], 0.0, t_end[:, None])
        t2 = np.clip(arg[:, 1:] + 2.0 * step[:, None] * k[None, :], 0.0, t_end[:, None])
        v1 = vel.evaluate(t1) * scale[:, None]
        v2 = vel.evaluate(t2) * scale[:, None]
        dur = t2[:, None, :] - t1[:, :, None]
        dv = v2[:, None, :] - v1[:, :, None]
        ok = (dur > 0) & (dur <= window) & (dv > 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            val = np.where(ok, np.abs(dur) ** -1.5 * np.abs(dv) ** 2.5 / STANDARD_GRAVITY**2.5, 0.0)
        flat = val.reshape(n, -1)
        j = flat.argmax(axis=1)
        cand = flat[rows, j]
        better = cand > best
        i1, i2 = np.unravel_index(j, (points, points))
        arg[better, 0] = t1[better, i1[better]]
        arg[better, 1] = t2[better, i2[better]]
        best = np.where(better, cand, best)
        step = step * 4.0 / points
    return best
