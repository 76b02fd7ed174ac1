"""What the joint-reduction comparisons share: the metrics compared, their errors, the status.

The full series joint (3.4.6) and its reductions (the Taylor truncation (3.4.9),
the band fit) are evaluated on the same arm, foam, head and v_c
(:func:`evaluate_all`); :func:`relative_errors` and :func:`long_rows` turn the
values into the long table of every result (:class:`ReductionResult`):
:mod:`~designlab.impact.joint_reduction.comparison` (one arm),
:mod:`~designlab.impact.joint_reduction.ratio_sweep` (over K_mech/K_cont) and
:mod:`~designlab.impact.joint_reduction.band_sweep` (over the band of the fit).

Examples
--------
>>> relative_errors([1.1, 0.0], [1.0, 0.0]).round(3).tolist()
[0.1, 0.0]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.full_joint_model import full_joint_params
from designlab.impact.joint import JointFit
from designlab.impact.metrics import matrix_metrics, ramp_responses, response_model
from designlab.impact.modal import poles_of
from designlab.impact.model import constrained_model, param_vector, unconstrained_model
from designlab.impact.parameters import (
    IMPACT_VELOCITY,
    OMEGA_MAX,
    STOP_TIME,
    ContactDynamics,
    Foam,
    HeadNeck,
)
from designlab.impact.peaks import first_local_maximum
from designlab.impact.series_joint import FullJointContact
from designlab.results import Result, Status
from designlab.units import STANDARD_GRAVITY

__all__ = [
    "EQUAL_TOLERANCE",
    "HARM_METRICS",
    "METRICS",
    "REDUCTIONS",
    "JointReductionStatus",
    "ReductionResult",
    "default_band",
    "relative_errors",
]

#: The reductions compared with the full joint.
REDUCTIONS: tuple[str, ...] = ("taylor", "band_fit")

#: Metrics compared: name -> unit. "f_c_first_peak" is the first local maximum of the
#: force (the thesis's "peak", Sec. 3.6), "f_c_max" the maximum over the first lobe
#: (docs/impact.md, "Metrics").
METRICS: dict[str, str] = {
    "a_h_max": "g",
    "eps_max": "m",
    "f_c_max": "N",
    "f_c_first_peak": "N",
    "t_imp": "s",
}
#: Relative difference below which a reduced metric counts as equal to the full one
#: (and so as conservative): rounding of two exact evaluations.
EQUAL_TOLERANCE = 1e-9

#: Metrics for which a larger value is the worse (harm) side.
HARM_METRICS: tuple[str, ...] = ("a_h_max", "eps_max", "f_c_max", "f_c_first_peak")

BOTTOMING_NOTE = (
    'the foam bottoms out and the linear model is not valid (docs/impact.md, "Foam bottoming")'
)


class JointReductionStatus(Status):
    """Status of a joint comparison or sweep (:func:`compare_joint_reductions`, ...).

    Attributes
    ----------
    OK
        Every model evaluated, the full joint's first lobe is regular and the
        foam does not bottom out.
    BAND_FIT_FAILED
        The band fit failed (at some point): its rows are missing.
    BOTTOMING
        The full joint compresses the foam beyond its linear depth lambda: the
        linear model, and the comparison with it, are not valid there.
    PEAK_AT_CONTACT
        The full joint's a_h peaks at contact (an overdamped pulse).
    LOBE_NOT_CLOSED
        The full joint's first lobe did not close; its metrics are NaN.
    """

    OK = "ok"
    BAND_FIT_FAILED = "band_fit_failed"
    BOTTOMING = "bottoming"
    PEAK_AT_CONTACT = "peak_at_contact"
    LOBE_NOT_CLOSED = "lobe_not_closed"


def relative_errors(reduced: ArrayLike, full: ArrayLike) -> NDArray[np.float64]:
    """``(reduced - full) / full``; 0 where both are exactly 0, NaN where only ``full`` is.

    The constrained impact has a_h = 0 in every model: no error, not an undefined one.

    Parameters
    ----------
    reduced, full
        The reduced and the full values.

    Returns
    -------
    numpy.ndarray

    Examples
    --------
    >>> relative_errors([1.1, 0.0, 1.0], [1.0, 0.0, 0.0]).round(3).tolist()
    [0.1, 0.0, nan]
    """
    r = np.asarray(reduced, dtype=float)
    f = np.asarray(full, dtype=float)
    ok = (f != 0) & np.isfinite(f)
    with np.errstate(divide="ignore", invalid="ignore"):
        err = np.where(ok, (r - f) / np.where(ok, f, 1.0), np.nan)
    return np.where((f == 0) & (r == 0), 0.0, err)


def default_band(robot: FullJointContact, foam: Foam, head: HeadNeck | None) -> float:
    """The fastest mode of the Taylor-reduced impact (largest pole modulus), rad/s.

    The default upper end of the band fit: the band then covers the impact's modes.

    Parameters
    ----------
    robot, foam, head
        The full-joint manipulator, the covering and the head (``None``: constrained).

    Returns
    -------
    float
        The largest pole modulus, rad/s.
    """
    model = constrained_model() if head is None else unconstrained_model()
    den = model.denominator(param_vector(robot.taylor(), foam, head))
    return float(np.abs(poles_of(den)).max())


def metric_rows(
    params: NDArray[np.float64], v_c: float, constrained: bool, stop_time: float
) -> dict[str, NDArray[np.float64]]:
    """The compared metrics for designs ``params`` (rows of 8 or 10 parameters)."""
    m = matrix_metrics(params, v_c, constrained=constrained, stop_time=stop_time)
    model = response_model(params, constrained)
    resp = ramp_responses(model, params, ("force",))["force"]
    t_end = m.impact_duration
    ok = np.isfinite(t_end) & (t_end > 0)
    _, f1 = first_local_maximum(resp.take(np.flatnonzero(ok)), t_end[ok])
    first = np.full(len(m), np.nan)
    first[ok] = f1 * max(v_c, 0.0)
    return {
        "a_h_max": m.peak_head_acceleration / STANDARD_GRAVITY,
        "eps_max": m.max_compression,
        "f_c_max": m.peak_force,
        "f_c_first_peak": first,
        "t_imp": m.impact_duration,
        "status": np.broadcast_to(m.design_status, (len(m),)),
    }


def long_rows(
    key: dict[str, Any],
    full: dict[str, NDArray],
    reduced: dict[str, dict[str, NDArray]],
    index: int,
) -> list[dict[str, Any]]:
    """One row per (reduction, metric) of design ``index``."""
    rows = []
    for red, vals in reduced.items():
        for metric, unit in METRICS.items():
            f = float(full[metric][index])
            r = float(vals[metric][index])
            err = float(relative_errors(r, f))
            cons: Any = pd.NA
            if metric in HARM_METRICS and np.isfinite(err):
                cons = bool(err >= -EQUAL_TOLERANCE)
            rows.append(
                {**key, "reduction": red, "metric": metric, "unit": unit, "full": f,
                 "reduced": r, "relative_error": err, "conservative": cons}
            )  # fmt: skip
    return rows


def _check_inputs(robot: Any, foam: Any, head: Any) -> None:
    if not isinstance(robot, FullJointContact):
        raise InvalidParameterError("robot", robot, "must be a FullJointContact")
    if not isinstance(foam, Foam):
        raise InvalidParameterError("foam", foam, "must be a Foam")
    if head is not None and not isinstance(head, HeadNeck):
        raise InvalidParameterError("head", head, "must be a HeadNeck or None")


def reduced_rows(
    robots: Sequence[FullJointContact],
    foam: Foam,
    head: HeadNeck | None,
    omega_max: float | None,
) -> tuple[dict[str, list[ContactDynamics | None]], list[JointFit], list[float]]:
    """Taylor and band-fit manipulators for each robot (``None`` where the fit failed)."""
    taylor, band, fits, omegas = [], [], [], []
    for r in robots:
        w = omega_max if omega_max is not None else default_band(r, foam, head)
        contact, fit = r.band_fit(w)
        taylor.append(r.taylor())
        band.append(contact)
        fits.append(fit)
        omegas.append(w)
    return {"taylor": taylor, "band_fit": band}, fits, omegas


def evaluate_all(
    robots: Sequence[FullJointContact],
    reduced: dict[str, list[ContactDynamics | None]],
    foam: Foam,
    head: HeadNeck | None,
    v_c: float,
    stop_time: float,
) -> tuple[dict[str, NDArray], dict[str, dict[str, NDArray]]]:
    """The metrics of the full joints and of every reduction (NaN where one is missing)."""
    constrained = head is None
    full = metric_rows(
        np.array([full_joint_params(r, foam, head) for r in robots]), v_c, constrained, stop_time
    )
    out: dict[str, dict[str, NDArray]] = {}
    for name, contacts in reduced.items():
        ok = [i for i, c in enumerate(contacts) if c is not None]
        vals = {k: np.full(len(robots), np.nan) for k in METRICS}
        if ok:
            rows = np.array([param_vector(contacts[i], foam, head) for i in ok])
            got = metric_rows(rows, v_c, constrained, stop_time)
            for k in METRICS:
                vals[k][ok] = got[k]
        out[name] = vals
    return full, out


def check_settings(
    robot: Any, foam: Any, head: Any, impact_velocity: Any, stop_time: Any, omega_max: Any = None
) -> tuple[float, float, float | None]:
    """Validate the common arguments; returns ``(v_c, stop_time, omega_max)``."""
    _check_inputs(robot, foam, head)
    return (
        IMPACT_VELOCITY.check(impact_velocity),
        STOP_TIME.check(stop_time),
        OMEGA_MAX.check(omega_max),
    )


def bottoming(eps: NDArray, foam: Foam) -> NDArray[np.bool_]:
    """Where the full joint's eps_max exceeds the foam's linear depth."""
    return np.asarray(eps, dtype=float) > foam.linear_depth


def check_metric(metric: str, allowed: Sequence[str] = tuple(METRICS)) -> str:
    """Refuse a metric name not among ``allowed`` (default: :data:`METRICS`).

    Parameters
    ----------
    metric
        The name asked for.
    allowed
        The names allowed (:data:`HARM_METRICS` where only harm metrics make sense).

    Returns
    -------
    str
        ``metric``.
    """
    if metric not in allowed:
        raise InvalidParameterError("metric", metric, f"must be one of {tuple(allowed)}")
    return metric


@dataclass(frozen=True, eq=False, kw_only=True)
class ReductionResult(Result):
    """What every joint-reduction result holds besides its own fields (keywords).

    Attributes
    ----------
    foam, head
        The foam and the head-neck set (``None``: constrained impact).
    impact_velocity
        v_c, m/s.
    status
        A :class:`JointReductionStatus`.
    warnings
        Notes on the result (failed fits, metric statuses, bottoming).
    """

    foam: Foam
    head: HeadNeck | None
    impact_velocity: float
    status: str
    warnings: tuple[str, ...]
    _frame: pd.DataFrame = field(repr=False)

    def to_frame(self) -> pd.DataFrame:
        """The result's table (its columns: the class's ``Notes``).

        Returns
        -------
        pandas.DataFrame
            A copy.
        """
        return self._frame.copy()
