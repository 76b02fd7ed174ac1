"""The band fit's errors on the impact metrics as its band changes, against the Taylor's.

Examples
--------
>>> import designlab as dl
>>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
>>> b = band_fit_sweep(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25, [89.6])
>>> b.status
'ok'
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.impact.full_joint_model import full_joint_params
from designlab.impact.joint import JointFit
from designlab.impact.joint_reduction.evaluation import (
    METRICS,
    JointReductionStatus,
    ReductionResult,
    check_metric,
    check_settings,
    metric_rows,
    relative_errors,
)
from designlab.impact.model import param_vector
from designlab.impact.parameters import (
    BAND_POINTS,
    OMEGA_MAX,
    STOP_TIME,
    Foam,
    HeadNeck,
    check_grid,
)
from designlab.impact.series_joint import FullJointContact

__all__ = ["BandFitSweep", "band_fit_sweep"]


@dataclass(frozen=True, eq=False)
class BandFitSweep(ReductionResult):
    """The band fit's errors as its band changes (:func:`band_fit_sweep`).

    Attributes
    ----------
    robot
        The full-joint manipulator.
    omega_max
        Upper ends of the bands, rad/s.
    rms_ratio
        Frequency-domain rms relative error of the fit divided by the Taylor
        truncation's, over each band (< 1: the fit is better *in frequency*).
    foam, head, impact_velocity, warnings
        As in :class:`~designlab.impact.joint_reduction.evaluation.ReductionResult`.
    status
        A :class:`JointReductionStatus`: ``"ok"`` or ``"band_fit_failed"``.

    Notes
    -----
    :meth:`to_frame` has one row per band: the fit, the rms ratio and the
    relative error of each metric (``err_<metric>``), with the Taylor
    reduction's (``taylor_err_<metric>``).
    """

    robot: FullJointContact
    omega_max: NDArray[np.float64]
    rms_ratio: NDArray[np.float64]

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
        check_metric(metric)
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
    stop_time: float = STOP_TIME.default,
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
    v_c, stop, _ = check_settings(robot, foam, head, impact_velocity, stop_time)
    w = check_grid(OMEGA_MAX, BAND_POINTS, omega_max, "omega_max")
    constrained = head is None
    full = metric_rows(full_joint_params(robot, foam, head)[None, :], v_c, constrained, stop)
    taylor = metric_rows(param_vector(robot.taylor(), foam, head)[None, :], v_c, constrained, stop)
    fits = [robot.band_fit(float(x)) for x in w]
    ok = [i for i, (c, _) in enumerate(fits) if c is not None]
    rows_p = np.array([param_vector(fits[i][0], foam, head) for i in ok]).reshape(len(ok), -1)
    band = metric_rows(rows_p, v_c, constrained, stop) if ok else {}
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
