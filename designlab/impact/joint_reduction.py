"""How wrong the reduced joint is: the full series joint (3.4.6) against its reductions.

The thesis replaces a position-controlled joint -- transmission (K_mech, C_mech)
in series with the PD controller (K_cont, C_cont) -- by one spring-damper
(K_J, C_J), the first two Taylor terms of (3.4.6) about s = 0, (3.4.9). The
impact model with the full joint (:mod:`designlab.impact.full_joint_model`)
shows how wrong a_h,max, eps_max, the peak force and the impact period are when
the reduced joint is used, and on which side (see ``docs/impact_joint.md``).

:func:`compare_joint_reductions` evaluates the full joint, the Taylor reduction
(3.4.9) and the frequency-band fit (:func:`~designlab.impact.joint.fit_joint_band`,
an extension of the thesis, which has only the Taylor truncation) on the same
arm, foam and head, and reports each metric's relative error and whether the
reduction is conservative (overestimates the harm). :func:`joint_reduction_sweep`
does the same over the transmission/controller stiffness ratio K_mech/K_cont,
:func:`band_fit_sweep` over the band of the fit.

For the constrained impact (``head=None``, the head against a wall) a_h is 0
for every model: its relative error is 0 (both exactly zero), never NaN.

Examples
--------
>>> import designlab as dl
>>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
>>> cmp = dl.impact.compare_joint_reductions(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25)
>>> round(100 * cmp.relative_error("taylor", "a_h_max"), 1)
12.5
>>> cmp.conservative("taylor", "a_h_max")
True
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
    BAND_POINTS,
    IMPACT_VELOCITY,
    OMEGA_MAX,
    RATIO_POINTS,
    STIFFNESS_RATIO,
    STOP_TIME,
    USABLE_TOLERANCE,
    ContactDynamics,
    Foam,
    HeadNeck,
    check_grid,
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
    "BandFitSweep",
    "JointReductionComparison",
    "JointReductionStatus",
    "JointReductionSweep",
    "band_fit_sweep",
    "compare_joint_reductions",
    "default_band",
    "joint_reduction_sweep",
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

_BOTTOMING_NOTE = (
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


def _metric_rows(
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


def _long_rows(
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


def _reduced_rows(
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


def _evaluate_all(
    robots: Sequence[FullJointContact],
    reduced: dict[str, list[ContactDynamics | None]],
    foam: Foam,
    head: HeadNeck | None,
    v_c: float,
    stop_time: float,
) -> tuple[dict[str, NDArray], dict[str, dict[str, NDArray]]]:
    """The metrics of the full joints and of every reduction (NaN where one is missing)."""
    constrained = head is None
    full = _metric_rows(
        np.array([full_joint_params(r, foam, head) for r in robots]), v_c, constrained, stop_time
    )
    out: dict[str, dict[str, NDArray]] = {}
    for name, contacts in reduced.items():
        ok = [i for i, c in enumerate(contacts) if c is not None]
        vals = {k: np.full(len(robots), np.nan) for k in METRICS}
        if ok:
            rows = np.array([param_vector(contacts[i], foam, head) for i in ok])
            got = _metric_rows(rows, v_c, constrained, stop_time)
            for k in METRICS:
                vals[k][ok] = got[k]
        out[name] = vals
    return full, out


def _settings(
    robot: Any, foam: Any, head: Any, impact_velocity: Any, stop_time: Any, omega_max: Any = None
) -> tuple[float, float, float | None]:
    """Validate the common arguments; returns ``(v_c, stop_time, omega_max)``."""
    _check_inputs(robot, foam, head)
    return (
        IMPACT_VELOCITY.check(impact_velocity),
        STOP_TIME.check(stop_time),
        OMEGA_MAX.check(omega_max),
    )


def _bottoming(eps: NDArray, foam: Foam) -> NDArray[np.bool_]:
    """Where the full joint's eps_max exceeds the foam's linear depth."""
    return np.asarray(eps, dtype=float) > foam.linear_depth


@dataclass(frozen=True, eq=False)
class JointReductionComparison(Result):
    """Full joint vs its reductions on one arm, foam and head (:func:`compare_joint_reductions`).

    Attributes
    ----------
    robot
        The full-joint manipulator.
    reduced
        The reduced manipulators by name (``"taylor"``, ``"band_fit"``).
    band
        The band fit (:class:`~designlab.impact.joint.JointFit`) and its
        ``omega_max`` in :attr:`band_omega_max`.
    foam, head
        The foam and the head-neck set (``None``: constrained impact).
    band_omega_max
        Upper end of the band fit's band, rad/s.
    impact_velocity
        v_c, m/s.
    status
        A :class:`JointReductionStatus`: ``"ok"``, ``"band_fit_failed"`` (the
        band-fit rows are missing), the full joint's first metric status that
        is not ``"ok"``, or ``"bottoming"``.
    warnings
        Notes on the result (a failed band fit, metric warnings, bottoming).
    """

    robot: FullJointContact
    foam: Foam
    head: HeadNeck | None
    impact_velocity: float
    reduced: dict[str, ContactDynamics]
    band: JointFit
    band_omega_max: float
    status: str
    warnings: tuple[str, ...]
    _frame: pd.DataFrame = field(repr=False)

    def to_frame(self) -> pd.DataFrame:
        """One row per (reduction, metric): full and reduced values, relative error, side.

        ``relative_error = (reduced - full) / full`` (0 where both are 0);
        ``conservative`` is True when the reduction overestimates a harm metric
        (a_h_max, eps_max, the force peaks) and missing for t_imp.

        Returns
        -------
        pandas.DataFrame
            Columns ``reduction, metric, unit, full, reduced, relative_error,
            conservative``.
        """
        return self._frame.copy()

    def relative_error(self, reduction: str, metric: str) -> float:
        """``(reduced - full) / full`` of ``metric`` for ``reduction``.

        Parameters
        ----------
        reduction
            ``"taylor"`` or ``"band_fit"``.
        metric
            A key of :data:`METRICS` (``a_h_max``, ``eps_max``, ``f_c_max``,
            ``f_c_first_peak``, ``t_imp``).

        Returns
        -------
        float
            The relative error (0 where both values are 0, NaN where only the full one is).
        """
        return float(self._row(reduction, metric)["relative_error"])

    def conservative(self, reduction: str, metric: str) -> bool:
        """Whether ``reduction`` overestimates the harm metric ``metric``.

        Parameters
        ----------
        reduction
            ``"taylor"`` or ``"band_fit"``.
        metric
            A harm metric: ``a_h_max``, ``eps_max``, ``f_c_max`` or ``f_c_first_peak``.

        Returns
        -------
        bool
            True when the reduced value is at least the full one (within a
            relative :data:`EQUAL_TOLERANCE`).
        """
        if metric not in HARM_METRICS:
            raise InvalidParameterError("metric", metric, f"must be one of {HARM_METRICS}")
        return bool(self._row(reduction, metric)["conservative"])

    def value(self, model: str, metric: str) -> float:
        """A metric of the full joint or of a reduction.

        Parameters
        ----------
        model
            ``"full"``, ``"taylor"`` or ``"band_fit"``.
        metric
            A key of :data:`METRICS`.

        Returns
        -------
        float
            The value in the unit of :data:`METRICS` (g, m, N, s).
        """
        row = self._row("taylor" if model == "full" else model, metric)
        return float(row["full" if model == "full" else "reduced"])

    def _row(self, reduction: str, metric: str) -> pd.Series:
        if metric not in METRICS:
            raise InvalidParameterError("metric", metric, f"must be one of {tuple(METRICS)}")
        sel = self._frame[(self._frame.reduction == reduction) & (self._frame.metric == metric)]
        if sel.empty:
            raise InvalidParameterError(
                "reduction", reduction, f"must be one of {sorted(self.reduced)}"
            )
        return sel.iloc[0]


def _comparison_status(
    fit: JointFit, band_ok: bool, full: dict[str, NDArray], foam: Foam
) -> tuple[JointReductionStatus, list[str]]:
    """Status and warnings of one comparison."""
    warnings: list[str] = []
    status = JointReductionStatus.OK
    if not band_ok:
        status = JointReductionStatus.BAND_FIT_FAILED
        warnings.append(f"the band fit failed ({fit.status}); only the Taylor rows are given")
    metric_status = str(full["status"][0])
    if metric_status != "ok":
        warnings.append(f"full-joint metrics status: {metric_status}")
        if status == JointReductionStatus.OK:
            status = JointReductionStatus(metric_status)
    eps = float(full["eps_max"][0])
    if _bottoming(eps, foam):
        warnings.append(
            f"the full joint's eps_max = {eps:.4g} m exceeds the foam's linear depth "
            f"lambda = {foam.linear_depth:.4g} m: {_BOTTOMING_NOTE}"
        )
        if status == JointReductionStatus.OK:
            status = JointReductionStatus.BOTTOMING
    return status, warnings


def compare_joint_reductions(
    robot: FullJointContact,
    foam: Foam,
    head: HeadNeck | None,
    impact_velocity: float,
    *,
    omega_max: float | None = None,
    stop_time: float = 0.05,
) -> JointReductionComparison:
    """Error of the reduced joint on the safety metrics, against the full joint (3.4.6).

    Evaluates the full series joint, the Taylor reduction (3.4.9) and the band
    fit on the same arm, foam, head and v_c, and reports for each reduction
    and metric (a_h,max, eps_max, the lobe maximum and the first local maximum
    of the force, the impact period) the relative error and its sign. Where
    the full joint compresses the foam beyond its linear depth the status is
    ``"bottoming"``, with a warning.

    Parameters
    ----------
    robot
        The manipulator with its full joint.
    foam, head
        The covering and the head (``None``: constrained impact, head against a wall).
    impact_velocity
        v_c, m/s (> 0 and <= 20).
    omega_max
        Upper end of the band fit, rad/s. Default: the fastest mode of the
        Taylor-reduced impact model, so the band covers the impact.
    stop_time
        Window of the constrained impact, s.

    Returns
    -------
    JointReductionComparison

    Examples
    --------
    >>> import designlab as dl
    >>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    >>> c = compare_joint_reductions(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25)
    >>> f = c.to_frame()
    >>> f[f.metric == "a_h_max"].relative_error.round(3).tolist()   # Taylor, band fit
    [0.125, 0.044]
    """
    v_c, stop, omega_max = _settings(robot, foam, head, impact_velocity, stop_time, omega_max)
    reduced, fits, omegas = _reduced_rows([robot], foam, head, omega_max)
    full, vals = _evaluate_all([robot], reduced, foam, head, v_c, stop)
    rows = _long_rows({}, full, {k: v for k, v in vals.items() if reduced[k][0]}, 0)
    status, warnings = _comparison_status(fits[0], reduced["band_fit"][0] is not None, full, foam)
    return JointReductionComparison(
        robot=robot,
        foam=foam,
        head=head,
        impact_velocity=v_c,
        reduced={k: v[0] for k, v in reduced.items() if v[0] is not None},
        band=fits[0],
        band_omega_max=omegas[0],
        status=status,
        warnings=tuple(warnings),
        _frame=pd.DataFrame(rows),
    )


# --- sweep over the stiffness ratio ----------------------------------------------------------


@dataclass(frozen=True, eq=False)
class JointReductionSweep(Result):
    """Errors of the reductions over K_mech/K_cont (:func:`joint_reduction_sweep`).

    Attributes
    ----------
    ratio
        K_mech / K_cont of each point.
    base
        The manipulator the sweep was built from (its controller, mass and
        transmission damping are kept; K_mech = ratio * K_cont).
    foam, head
        The foam and the head-neck set (``None``: constrained impact).
    impact_velocity
        v_c, m/s.
    status
        A :class:`JointReductionStatus`: ``"ok"``, ``"band_fit_failed"`` or
        ``"bottoming"`` (the full joint bottoms out the foam at some ratio).
    warnings
        Notes on the result (failed fits, metric statuses, bottoming).
    """

    base: FullJointContact
    foam: Foam
    head: HeadNeck | None
    impact_velocity: float
    ratio: NDArray[np.float64]
    status: str
    warnings: tuple[str, ...]
    _frame: pd.DataFrame = field(repr=False)

    def to_frame(self) -> pd.DataFrame:
        """One row per (ratio, reduction, metric).

        Returns
        -------
        pandas.DataFrame
            ``point, ratio, k_mech_N_per_m, band_omega_max_rad_per_s`` and the
            columns of :meth:`JointReductionComparison.to_frame`.
        """
        return self._frame.copy()

    def errors(self, reduction: str, metric: str) -> NDArray[np.float64]:
        """Relative errors of ``reduction`` on ``metric`` along :attr:`ratio`.

        Parameters
        ----------
        reduction
            ``"taylor"`` or ``"band_fit"``.
        metric
            A key of :data:`METRICS`.

        Returns
        -------
        numpy.ndarray
            One error per ratio (NaN where the reduction is missing).
        """
        f = self._frame
        sel = f[(f.reduction == reduction) & (f.metric == metric)]
        if sel.empty:
            raise InvalidParameterError("reduction/metric", (reduction, metric), "not in the sweep")
        by_point = sel.set_index("point").relative_error
        return by_point.reindex(range(self.ratio.size)).to_numpy(dtype=float)

    def conservative_region(self, reduction: str, metric: str) -> NDArray[np.bool_]:
        """Where ``reduction`` overestimates ``metric`` (a harm metric), along :attr:`ratio`.

        Parameters
        ----------
        reduction
            ``"taylor"`` or ``"band_fit"``.
        metric
            A harm metric: ``a_h_max``, ``eps_max``, ``f_c_max`` or ``f_c_first_peak``.

        Returns
        -------
        numpy.ndarray
            Booleans, one per ratio; False where the reduction is missing.
        """
        if metric not in HARM_METRICS:
            raise InvalidParameterError("metric", metric, f"must be one of {HARM_METRICS}")
        err = self.errors(reduction, metric)
        return np.isfinite(err) & (err >= -EQUAL_TOLERANCE)

    def conservative_intervals(
        self, reduction: str, metrics: Sequence[str] = ("a_h_max", "eps_max", "f_c_max")
    ) -> list[tuple[float, float]]:
        """Ratio intervals (of the sampled points) where ``reduction`` overestimates every metric.

        Parameters
        ----------
        reduction
            ``"taylor"`` or ``"band_fit"``.
        metrics
            Harm metrics that must all be overestimated.

        Returns
        -------
        list of tuple
            ``[(first ratio, last ratio), ...]`` of the runs of consecutive
            sampled ratios at which the reduction is conservative on all ``metrics``.

        Examples
        --------
        >>> import designlab as dl
        >>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0,
        ...                                              lever_arm=0.2)
        >>> s = dl.impact.joint_reduction_sweep(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN,
        ...                                     1.25, [0.03, 0.1, 1.0, 10.0])
        >>> s.conservative_intervals("taylor")
        [(0.03, 0.1)]
        >>> s.conservative_intervals("taylor", ["a_h_max"])
        [(0.03, 10.0)]
        """
        ok = np.ones(self.ratio.size, dtype=bool)
        for m in metrics:
            ok &= self.conservative_region(reduction, m)
        return self._runs(ok)

    def usable_intervals(
        self,
        reduction: str,
        tolerance: float = 0.01,
        metrics: Sequence[str] = ("a_h_max", "eps_max", "f_c_max"),
    ) -> list[tuple[float, float]]:
        """Ratio intervals where ``reduction`` may stand in for the full joint on ``metrics``.

        A reduction may be used where, on every metric, it either overestimates
        the harm (conservative) or underestimates it by at most ``tolerance``.

        Parameters
        ----------
        reduction
            ``"taylor"`` or ``"band_fit"``.
        tolerance
            Largest accepted underestimate, relative (0.01: 1 %), in ``[0, 1)``
            (:data:`~designlab.impact.parameters.USABLE_TOLERANCE`).
        metrics
            Harm metrics checked.

        Returns
        -------
        list of tuple
            ``[(first ratio, last ratio), ...]`` runs of consecutive sampled ratios.

        Examples
        --------
        >>> import designlab as dl
        >>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0,
        ...                                              lever_arm=0.2)
        >>> s = dl.impact.joint_reduction_sweep(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN,
        ...                                     1.25, [0.03, 0.1, 1.0, 10.0, 100.0])
        >>> s.usable_intervals("taylor")          # within 1 % from K_mech = 10 K_cont on
        [(0.03, 0.1), (10.0, 100.0)]
        >>> s.usable_intervals("taylor", tolerance=0.005)
        [(0.03, 0.1), (100.0, 100.0)]
        """
        tol = USABLE_TOLERANCE.check(tolerance)
        ok = np.ones(self.ratio.size, dtype=bool)
        for m in metrics:
            if m not in HARM_METRICS:
                raise InvalidParameterError("metric", m, f"must be one of {HARM_METRICS}")
            err = self.errors(reduction, m)
            ok &= np.isfinite(err) & (err >= -(tol + EQUAL_TOLERANCE))
        return self._runs(ok)

    def _runs(self, ok: NDArray[np.bool_]) -> list[tuple[float, float]]:
        """``(first, last)`` ratios of the runs of consecutive True entries of ``ok``."""
        out: list[tuple[float, float]] = []
        start = None
        for i, flag in enumerate(ok):
            if flag and start is None:
                start = i
            if start is not None and (not flag or i == ok.size - 1):
                end = i if flag else i - 1
                out.append((float(self.ratio[start]), float(self.ratio[end])))
                start = None
        return out


def _sweep_status(
    ratios: NDArray, failed: list[float], full: dict[str, NDArray], foam: Foam
) -> tuple[JointReductionStatus, list[str]]:
    """Status and warnings of a sweep over the stiffness ratio."""
    warnings = []
    if failed:
        warnings.append(f"the band fit failed at ratios {failed}; those rows are missing")
    bad = sorted({str(s) for s in full["status"] if str(s) != "ok"})
    if bad:
        warnings.append(f"full-joint metric statuses other than ok: {bad}")
    bottom = _bottoming(full["eps_max"], foam)
    if np.any(bottom):
        where = [float(x) for x in ratios[bottom]]
        warnings.append(
            f"the full joint's eps_max exceeds the foam's linear depth lambda = "
            f"{foam.linear_depth:.4g} m at {len(where)} of {ratios.size} ratios "
            f"({where[0]:.4g}-{where[-1]:.4g}): {_BOTTOMING_NOTE}"
        )
    if failed:
        return JointReductionStatus.BAND_FIT_FAILED, warnings
    if np.any(bottom):
        return JointReductionStatus.BOTTOMING, warnings
    return JointReductionStatus.OK, warnings


def joint_reduction_sweep(
    robot: FullJointContact,
    foam: Foam,
    head: HeadNeck | None,
    impact_velocity: float,
    ratios: ArrayLike,
    *,
    omega_max: float | None = None,
    stop_time: float = 0.05,
) -> JointReductionSweep:
    """Errors of the Taylor and band-fit reductions over K_mech/K_cont.

    The controller (K_cont, C_cont), the mass and the transmission damping of
    ``robot`` are kept; the transmission stiffness is ``ratio * K_cont``. A large
    ratio is a direct drive (the reduction tends to exact), a ratio near or
    below one a compliant transmission.

    Parameters
    ----------
    robot, foam, head, impact_velocity, omega_max, stop_time
        As in :func:`compare_joint_reductions` (``omega_max`` per point by default).
    ratios
        K_mech / K_cont values (each > 0), at most 1001 of them
        (:data:`~designlab.impact.parameters.RATIO_POINTS`, the cap of the study file too).

    Returns
    -------
    JointReductionSweep

    Examples
    --------
    >>> import designlab as dl
    >>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    >>> s = joint_reduction_sweep(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25, [0.5, 1e3])
    >>> err = s.errors("taylor", "a_h_max")
    >>> bool(abs(err[1]) < 1e-3 < abs(err[0]))
    True
    """
    v_c, stop, omega_max = _settings(robot, foam, head, impact_velocity, stop_time, omega_max)
    r = check_grid(STIFFNESS_RATIO, RATIO_POINTS, ratios, "ratios")
    robots = [robot.with_ratio(float(x)) for x in r]
    reduced, _, omegas = _reduced_rows(robots, foam, head, omega_max)
    full, vals = _evaluate_all(robots, reduced, foam, head, v_c, stop)
    rows: list[dict[str, Any]] = []
    for i, x in enumerate(r):
        key = {
            "point": i,
            "ratio": float(x),
            "k_mech_N_per_m": robots[i].transmission_stiffness,
            "band_omega_max_rad_per_s": omegas[i],
        }
        avail = {k: v for k, v in vals.items() if reduced[k][i] is not None}
        rows.extend(_long_rows(key, full, avail, i))
    failed = [float(x) for i, x in enumerate(r) if reduced["band_fit"][i] is None]
    status, warnings = _sweep_status(r, failed, full, foam)
    return JointReductionSweep(
        base=robot,
        foam=foam,
        head=head,
        impact_velocity=v_c,
        ratio=r,
        status=status,
        warnings=tuple(warnings),
        _frame=pd.DataFrame(rows),
    )


# --- sweep over the band of the fit ---------------------------------------------------------


@dataclass(frozen=True, eq=False)
class BandFitSweep(Result):
    """The band fit's errors as its band changes (:func:`band_fit_sweep`).

    Attributes
    ----------
    omega_max
        Upper ends of the bands, rad/s.
    rms_ratio
        Frequency-domain rms relative error of the fit divided by the Taylor
        truncation's, over each band (< 1: the fit is better *in frequency*).
    robot
        The full-joint manipulator.
    foam, head
        The foam and the head-neck set (``None``: constrained impact).
    impact_velocity
        v_c, m/s.
    status
        A :class:`JointReductionStatus`: ``"ok"`` or ``"band_fit_failed"``.
    warnings
        Notes on the result (failed fits).
    """

    robot: FullJointContact
    foam: Foam
    head: HeadNeck | None
    impact_velocity: float
    omega_max: NDArray[np.float64]
    rms_ratio: NDArray[np.float64]
    status: str
    warnings: tuple[str, ...]
    _frame: pd.DataFrame = field(repr=False)

    def to_frame(self) -> pd.DataFrame:
        """One row per band.

        Returns
        -------
        pandas.DataFrame
            The fit, the rms ratio and the relative error of each metric
            (``err_<metric>``), with the Taylor reduction's (``taylor_err_<metric>``).
        """
        return self._frame.copy()

    def errors(self, metric: str) -> NDArray[np.float64]:
        """The band fit's relative error on ``metric`` along :attr:`omega_max`.

        Parameters
        ----------
        metric
            A key of :data:`METRICS`.

        Returns
        -------
        numpy.ndarray
            One error per band (NaN where the fit failed).
        """
        if metric not in METRICS:
            raise InvalidParameterError("metric", metric, f"must be one of {tuple(METRICS)}")
        return self._frame[f"err_{metric}"].to_numpy(dtype=float)


def _band_frame(
    w: NDArray, fits: list[tuple[Any, JointFit]], full: dict, taylor: dict, band: dict
) -> dict[str, Any]:
    """The columns of a :class:`BandFitSweep` (errors against the full joint's metrics)."""
    ok = [i for i, (c, _) in enumerate(fits) if c is not None]
    frame: dict[str, Any] = {
        "omega_max_rad_per_s": w,
        "K_fit_N_per_m": [f.stiffness for _, f in fits],
        "C_fit_N_s_per_m": [f.damping for _, f in fits],
        "rms_ratio": [f.rms_error / f.taylor_rms_error for _, f in fits],
        "fit_status": [f.status for _, f in fits],
    }
    for metric in METRICS:
        ref = float(full[metric][0])
        err = np.full(w.size, np.nan)
        if ok:
            err[ok] = relative_errors(band[metric], ref)
        frame[f"err_{metric}"] = err
        frame[f"taylor_err_{metric}"] = float(relative_errors(taylor[metric][0], ref))
    return frame


def band_fit_sweep(
    robot: FullJointContact,
    foam: Foam,
    head: HeadNeck | None,
    impact_velocity: float,
    omega_max: ArrayLike,
    *,
    stop_time: float = 0.05,
) -> BandFitSweep:
    """How the band fit's errors on the impact metrics follow its band, against the Taylor's.

    A smaller frequency-domain error (``rms_ratio`` < 1) does not mean a smaller
    error on the safety metrics, nor one on the safe side: this puts the two
    side by side for each band ``[omega_max/1000, omega_max]``.

    Parameters
    ----------
    robot, foam, head, impact_velocity, stop_time
        As in :func:`compare_joint_reductions`.
    omega_max
        Upper ends of the bands, rad/s (each > 0; at most 1001).

    Returns
    -------
    BandFitSweep

    Examples
    --------
    >>> import designlab as dl
    >>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    >>> b = dl.impact.band_fit_sweep(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25, [89.6, 200])
    >>> b.rms_ratio.round(2).tolist(), b.errors("a_h_max").round(3).tolist()
    ([0.84, 0.67], [0.089, 0.037])
    """
    v_c, stop, _ = _settings(robot, foam, head, impact_velocity, stop_time)
    w = check_grid(OMEGA_MAX, BAND_POINTS, omega_max, "omega_max")
    constrained = head is None
    full = _metric_rows(full_joint_params(robot, foam, head)[None, :], v_c, constrained, stop)
    taylor = _metric_rows(param_vector(robot.taylor(), foam, head)[None, :], v_c, constrained, stop)
    fits = [robot.band_fit(float(x)) for x in w]
    ok = [i for i, (c, _) in enumerate(fits) if c is not None]
    rows_p = np.array([param_vector(fits[i][0], foam, head) for i in ok]).reshape(len(ok), -1)
    band = _metric_rows(rows_p, v_c, constrained, stop) if ok else {}
    frame = _band_frame(w, fits, full, taylor, band)
    failed = [float(w[i]) for i in range(w.size) if i not in ok]
    return BandFitSweep(
        robot=robot,
        foam=foam,
        head=head,
        impact_velocity=v_c,
        omega_max=w,
        rms_ratio=np.asarray(frame["rms_ratio"], dtype=float),
        status=JointReductionStatus.BAND_FIT_FAILED if failed else JointReductionStatus.OK,
        warnings=(f"the band fit failed for omega_max = {failed} rad/s",) if failed else (),
        _frame=pd.DataFrame(frame),
    )
