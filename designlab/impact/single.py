"""One design in microseconds: the first-lobe metrics without a batch around them.

An optimiser (``scipy.optimize``, another project's loop) asks for one design at a
time. :func:`impact_metrics_one` gives it the numbers of
:func:`designlab.impact.impact_metrics` for that design, to the bit, for the cost of
the compiled kernel and a few microseconds: the declared checks on plain floats, then
one compiled call that estimates the design's time-scale ratio (the conditioning
check) and computes its metrics. Anything off the plain path (a value outside its
declared range, an ill-conditioned design, v_c <= 0, a design the kernel did not
certify) goes through :func:`~designlab.impact.metrics.metrics_of_matrix` itself,
which raises its error or settles the design as the batch does (docs/sweeps.md,
"Single calls").

Examples
--------
>>> from designlab.impact.single import impact_metrics_one
>>> m = impact_metrics_one([9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 0.0, 4e3], 1.25)
>>> round(m.peak_head_acceleration_g, 3), round(m.impact_duration * 1e3, 2), m.status
(6.568, 33.22, 'ok')
>>> impact_metrics_one({"M_r": 9.6, "C_r": 250, "K_r": 20e3, "K_c": -1.0, "C_c": 71.9,
...                     "M_h": 4.4, "C_h": 0.0, "K_h": 4e3}, 1.25)
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: K_c[0] = -1.0 N/m is not allowed: ...
"""

from __future__ import annotations

import sys
from collections.abc import Mapping, Sequence

from designlab.impact.kernel import STATUS_CODES
from designlab.impact.kernel_single import one_design
from designlab.impact.metric_names import ImpactPoint
from designlab.impact.metrics import (
    _KERNEL_STATUS,
    _POSITIVE,
    _upper,
    impact_metrics,
    metrics_of_matrix,
)
from designlab.impact.model import PARAM_NAMES
from designlab.impact.parameters import IMPACT_VELOCITY, MAX_LOBE_STEPS, STOP_TIME, TIME_SCALE_RATIO

__all__ = ["ImpactPoint", "impact_metrics_one"]


#: each parameter's smallest and largest allowed value (> 0 is >= the smallest double; no
#: upper bound is the largest double: NaN and inf fail both)
_RANGES = tuple(
    (5e-324 if name in _POSITIVE else 0.0, min(_upper(name), sys.float_info.max))
    for name in PARAM_NAMES
)
#: the kernel's codes that are a design's final status as they come (the batch settles
#: every other: lobe_not_closed at 40 digits, the SUSPECT_* codes, :func:`.metrics.settle_suspects`)
_FAST_CODES = (STATUS_CODES.index("ok"), STATUS_CODES.index("peak_at_contact"))
_STATUS = tuple(str(s) for s in _KERNEL_STATUS)
_DEFAULTS = (STOP_TIME.default, MAX_LOBE_STEPS.default)


def _plain(values: Sequence[float]) -> bool:
    """Whether every parameter is finite and in its declared range (the batch's checks)."""
    for x, (lo, hi) in zip(values, _RANGES, strict=True):
        if not lo <= x <= hi:
            return False
    return True


def _options_plain(stop_time: object, max_lobe_steps: object) -> bool:
    """Whether the options are the defaults or plain values in their declared ranges."""
    if (stop_time, max_lobe_steps) == _DEFAULTS:
        return True
    return (
        type(stop_time) in (int, float)
        and STOP_TIME.within(stop_time)  # type: ignore[arg-type]
        and type(max_lobe_steps) is int
        and MAX_LOBE_STEPS.within(max_lobe_steps)
    )


def impact_metrics_one(
    params: Sequence[float] | Mapping[str, float],
    impact_velocity: float,
    *,
    stop_time: float = STOP_TIME.default,
    max_lobe_steps: int = MAX_LOBE_STEPS.default,
) -> ImpactPoint:
    """First-lobe metrics of one reduced, unconstrained design (the scalar fast path).

    Equal, to the bit, to row 0 of :func:`designlab.impact.impact_metrics` of that design
    (``q2="correct"``, every metric): the same checks, errors and kernel.

    Parameters
    ----------
    params
        ``M_r, C_r, K_r, K_c, C_c, M_h, C_h, K_h`` (:data:`~designlab.impact.model.PARAM_NAMES`)
        in that order, or a mapping by those names; SI units.
    impact_velocity
        v_c in m/s.
    stop_time, max_lobe_steps
        As in :func:`designlab.impact.impact_metrics`.

    Returns
    -------
    ImpactPoint

    Raises
    ------
    InvalidParameterError
        As :func:`designlab.impact.impact_metrics` does, with the same message.
    """
    if type(params) is dict or isinstance(params, Mapping):
        if len(params) != len(PARAM_NAMES) or any(k not in params for k in PARAM_NAMES):
            return _batch(params, impact_velocity, stop_time, max_lobe_steps)  # its error
        params = [params[k] for k in PARAM_NAMES]  # type: ignore[index]
    try:
        values = [float(x) for x in params]  # type: ignore[union-attr]
        v = float(impact_velocity)
    except (TypeError, ValueError):
        return _batch(params, impact_velocity, stop_time, max_lobe_steps)
    if not (
        len(values) == len(PARAM_NAMES)
        and _plain(values)
        and 0.0 < v <= IMPACT_VELOCITY.le
        and values[2] * values[7] + values[3] * values[7] + values[2] * values[3] > 0
        and _options_plain(stop_time, max_lobe_steps)
    ):
        return _batch(values, v, stop_time, max_lobe_steps)
    code, a, e, f, t_imp, t_a, t_e, t_f = one_design(
        *values, float(stop_time), int(max_lobe_steps), TIME_SCALE_RATIO.le
    )
    if code not in _FAST_CODES:  # settled (or refused) by the batch path
        return _batch(values, v, stop_time, max_lobe_steps)
    return ImpactPoint(a * v, e * v, f * v, t_imp, t_a, t_e, t_f, _STATUS[code])


def _batch(
    params: object, impact_velocity: object, stop_time: object, max_lobe_steps: object
) -> ImpactPoint:
    """The design through :func:`~designlab.impact.metrics.impact_metrics` (a mapping) or
    :func:`~designlab.impact.metrics.metrics_of_matrix`: their errors and their settling."""
    options = {"stop_time": stop_time, "max_lobe_steps": max_lobe_steps, "workers": 1}
    if isinstance(params, Mapping):
        m = impact_metrics(params, impact_velocity, **options)  # type: ignore[arg-type]
    else:
        rows = [list(params)] if isinstance(params, (list, tuple)) else params
        m = metrics_of_matrix(
            rows,  # type: ignore[arg-type]
            impact_velocity,  # type: ignore[arg-type]
            **options,  # type: ignore[arg-type]
        )
    if len(m) != 1:
        raise ValueError(f"impact_metrics_one takes one design, not {len(m)}")
    return ImpactPoint(
        float(m.peak_head_acceleration[0]),
        float(m.max_compression[0]),
        float(m.peak_force[0]),
        float(m.impact_duration[0]),
        float(m.time_of_peak_acceleration[0]),
        float(m.time_of_max_compression[0]),
        float(m.time_of_peak_force[0]),
        str(m.design_status[0]),
    )
