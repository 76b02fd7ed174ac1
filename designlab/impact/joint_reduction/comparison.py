"""The full joint against its reductions on one arm, foam and head (Zeng 2011, (3.4.6)-(3.4.9)).

Examples
--------
>>> import designlab as dl
>>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
>>> cmp = compare_joint_reductions(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25)
>>> cmp.conservative("taylor", "a_h_max")
True
"""

from __future__ import annotations

from dataclasses import dataclass

import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.joint import JointFit
from designlab.impact.joint_reduction import evaluation as ev
from designlab.impact.joint_reduction.evaluation import (
    HARM_METRICS,
    JointReductionStatus,
    ReductionResult,
)
from designlab.impact.parameters import STOP_TIME, ContactDynamics, Foam, HeadNeck
from designlab.impact.series_joint import FullJointContact

__all__ = ["JointReductionComparison", "compare_joint_reductions"]


@dataclass(frozen=True, eq=False)
class JointReductionComparison(ReductionResult):
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
    band_omega_max
        Upper end of the band fit's band, rad/s.
    foam, head, impact_velocity, warnings
        As in :class:`~designlab.impact.joint_reduction.evaluation.ReductionResult`.
    status
        A :class:`JointReductionStatus`: ``"ok"``, ``"band_fit_failed"`` (the
        band-fit rows are missing), the full joint's first metric status that
        is not ``"ok"``, or ``"ev.bottoming"``.

    Notes
    -----
    :meth:`to_frame` has one row per (reduction, metric): columns ``reduction,
    metric, unit, full, reduced, relative_error, conservative``.
    ``relative_error = (reduced - full) / full`` (0 where both are 0);
    ``conservative`` is True when the reduction overestimates a harm metric
    (a_h_max, eps_max, the force peaks) and missing for t_imp.
    """

    robot: FullJointContact
    reduced: dict[str, ContactDynamics]
    band: JointFit
    band_omega_max: float

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
        ev.check_metric(metric, HARM_METRICS)
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
        ev.check_metric(metric)
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
    if ev.bottoming(eps, foam):
        warnings.append(
            f"the full joint's eps_max = {eps:.4g} m exceeds the foam's linear depth "
            f"lambda = {foam.linear_depth:.4g} m: {ev.BOTTOMING_NOTE}"
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
    stop_time: float = STOP_TIME.default,
) -> JointReductionComparison:
    """Error of the reduced joint on the safety metrics, against the full joint (3.4.6).

    Evaluates the full series joint, the Taylor reduction (3.4.9) and the band
    fit on the same arm, foam, head and v_c, and reports for each reduction
    and metric (a_h,max, eps_max, the lobe maximum and the first local maximum
    of the force, the impact period) the relative error and its sign. Where
    the full joint compresses the foam beyond its linear depth the status is
    ``"ev.bottoming"``, with a warning.

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
    v_c, stop, omega_max = ev.check_settings(
        robot, foam, head, impact_velocity, stop_time, omega_max
    )
    reduced, fits, omegas = ev.reduced_rows([robot], foam, head, omega_max)
    full, vals = ev.evaluate_all([robot], reduced, foam, head, v_c, stop)
    rows = ev.long_rows({}, full, {k: v for k, v in vals.items() if reduced[k][0]}, 0)
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
