"""The errors of the joint reductions over the stiffness ratio K_mech/K_cont.

Examples
--------
>>> import designlab as dl
>>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
>>> s = joint_reduction_sweep(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25, [0.5, 1e3])
>>> s.ratio.tolist()
[0.5, 1000.0]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.joint_reduction import evaluation as ev
from designlab.impact.joint_reduction.evaluation import (
    HARM_METRICS,
    JointReductionStatus,
    ReductionResult,
)
from designlab.impact.parameters import (
    RATIO_POINTS,
    STIFFNESS_RATIO,
    STOP_TIME,
    USABLE_TOLERANCE,
    Foam,
    HeadNeck,
    check_grid,
)
from designlab.impact.series_joint import FullJointContact

__all__ = ["JointReductionSweep", "joint_reduction_sweep"]


@dataclass(frozen=True, eq=False)
class JointReductionSweep(ReductionResult):
    """Errors of the reductions over K_mech/K_cont (:func:`joint_reduction_sweep`).

    Attributes
    ----------
    base
        The manipulator the sweep was built from (its controller, mass and
        transmission damping are kept; K_mech = ratio * K_cont).
    ratio
        K_mech / K_cont of each point.
    foam, head, impact_velocity, warnings
        As in :class:`~designlab.impact.joint_reduction.evaluation.ReductionResult`.
    status
        A :class:`JointReductionStatus`: ``"ok"``, ``"band_fit_failed"`` or
        ``"ev.bottoming"`` (the full joint bottoms out the foam at some ratio).

    Notes
    -----
    :meth:`to_frame` has one row per (ratio, reduction, metric): columns
    ``point, ratio, k_mech_N_per_m, band_omega_max_rad_per_s`` and those of
    :class:`~designlab.impact.joint_reduction.comparison.JointReductionComparison`.
    """

    base: FullJointContact
    ratio: NDArray[np.float64]

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
        ev.check_metric(metric, HARM_METRICS)
        err = self.errors(reduction, metric)
        return np.isfinite(err) & (err >= -ev.EQUAL_TOLERANCE)

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
        tolerance: float = USABLE_TOLERANCE.default,
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
            ev.check_metric(m, HARM_METRICS)
            err = self.errors(reduction, m)
            ok &= np.isfinite(err) & (err >= -(tol + ev.EQUAL_TOLERANCE))
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
    bottom = ev.bottoming(full["eps_max"], foam)
    if np.any(bottom):
        where = [float(x) for x in ratios[bottom]]
        warnings.append(
            f"the full joint's eps_max exceeds the foam's linear depth lambda = "
            f"{foam.linear_depth:.4g} m at {len(where)} of {ratios.size} ratios "
            f"({where[0]:.4g}-{where[-1]:.4g}): {ev.BOTTOMING_NOTE}"
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
    stop_time: float = STOP_TIME.default,
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
    v_c, stop, omega_max = ev.check_settings(
        robot, foam, head, impact_velocity, stop_time, omega_max
    )
    r = check_grid(STIFFNESS_RATIO, RATIO_POINTS, ratios, "ratios")
    robots = [robot.with_ratio(float(x)) for x in r]
    reduced, _, omegas = ev.reduced_rows(robots, foam, head, omega_max)
    full, vals = ev.evaluate_all(robots, reduced, foam, head, v_c, stop)
    rows: list[dict[str, Any]] = []
    for i, x in enumerate(r):
        key = {
            "point": i,
            "ratio": float(x),
            "k_mech_N_per_m": robots[i].transmission_stiffness,
            "band_omega_max_rad_per_s": omegas[i],
        }
        avail = {k: v for k, v in vals.items() if reduced[k][i] is not None}
        rows.extend(ev.long_rows(key, full, avail, i))
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
