"""Metrics of an accompanying run: Table 1 and Table 2 quantities, error, lag, overshoot.

Definitions (Wu et al. 2021, Sec. 4; ``docs/following.md``):

* Table 2: the robot's position (X_C, Y_C) in LCS_U and its bearing
  ``-atan2(X_C, Y_C)`` (the paper's "gamma_C" column behaves as this bearing)
  and relative orientation gamma_C at the target (t = 0), at the stop
  (``settle_window`` s after the user stops, the robot having settled) and
  their mean and standard deviation while the user walks;
* Table 1: world start/stop positions and headings of user and robot and their
  displacements (stop - start);
* tracking: the position error ``e = p_T - p_C`` in LCS_U, its RMS while the
  user walks, its maximum over the run and its norm ``settle_window`` s after
  the stop (the settled error);
* lag: the delay tau in [0, 3] s that best aligns the robot's world path with
  the target point's path delayed by tau (least squares over the walk);
* overshoot: after the stop, the largest travel of the robot beyond the
  (now fixed) target point along the direction the target was moving;
* settling time: time after the stop until the error stays within
  ``settle_band`` (default 20 mm) to the end of the run;
* path length (Wu et al. 2021, Sec. 6: "the robot takes a longer path than
  the user during pivots; on circles its path matches the user's when the
  target lies on the walking curve and is longer when it lies outside"): the
  length of the world path of the user's frame origin, of the robot and of
  the target point (where a robot exactly on target would go), over the run,
  and the ratio robot / user.

Examples
--------
>>> import numpy as np
>>> t = np.linspace(0.0, 4.0, 201)
>>> user = np.vstack([np.zeros_like(t), np.clip(t - 1, 0, 1), np.full_like(t, np.pi / 2)])
>>> robot = user + np.array([[0.0], [0.5], [0.0]])            # rigidly on target
>>> m = accompany_metrics(t, user, robot, (0.0, 0.5), 0.0, 1.0, 2.0, settle_window=2.0)
>>> round(m.rms_error, 12), round(m.settled_error, 12), round(m.lag, 3)
(0.0, 0.0, 0.0)
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.following.accompanying.parameters import SETTLE_BAND
from designlab.following.accompanying.user_frame import robot_in_user_frame
from designlab.params import Param
from designlab.validation import real_array

__all__ = [
    "MAX_LAG",
    "SETTLE_WINDOW",
    "AccompanyMetrics",
    "accompany_metrics",
    "command_rate",
    "path_length",
]

#: Time after the stop at which the Table 2 stop pose and the settled error are taken.
SETTLE_WINDOW = Param(
    None,
    "s",
    "time after the stop of the settled error",
    ge=0,
    le=600,
    default=10.0,
    name="settle_window",
)
#: Largest delay searched for the lag.
MAX_LAG = Param(
    None, "s", "largest delay searched for the lag", ge=0, le=60, default=3.0, name="max_lag"
)


@dataclass(frozen=True)
class AccompanyMetrics:
    """Scalar metrics of one accompanying run (SI; angles in degrees where named ``_deg``).

    Attributes
    ----------
    target_x, target_y, target_bearing_deg, target_gamma_deg
        Robot pose in LCS_U at t = 0 (Table 2 "Target").
    stop_x, stop_y, stop_bearing_deg, stop_gamma_deg
        Robot pose in LCS_U at the stop instant (Table 2 "Stop").
    mean_x, sd_x, mean_y, sd_y, mean_bearing_deg, sd_bearing_deg, mean_gamma_deg, sd_gamma_deg
        Mean and sd while walking (Table 2 "Average").
    user_start, user_stop, robot_start, robot_stop
        World (x m, y m, heading deg) (Table 1).
    rms_error, max_error, settled_error
        Position error norms in m.
    lag
        Delay in s; NaN if the user did not move.
    overshoot
        In m; NaN if the target did not move before the stop.
    settling_time
        In s after the stop; NaN if the error never stays within the band.
    stop_time
        The instant of the Table 2 stop values, s.
    user_path_length, robot_path_length, target_path_length
        Length in m of the world paths of the user's frame origin, the robot
        and the target point over the run.
    path_length_ratio
        ``robot_path_length / user_path_length`` (NaN if the user did not move).
    """

    target_x: float
    target_y: float
    target_bearing_deg: float
    target_gamma_deg: float
    stop_x: float
    stop_y: float
    stop_bearing_deg: float
    stop_gamma_deg: float
    mean_x: float
    sd_x: float
    mean_y: float
    sd_y: float
    mean_bearing_deg: float
    sd_bearing_deg: float
    mean_gamma_deg: float
    sd_gamma_deg: float
    user_start: tuple[float, float, float]
    user_stop: tuple[float, float, float]
    robot_start: tuple[float, float, float]
    robot_stop: tuple[float, float, float]
    rms_error: float
    max_error: float
    settled_error: float
    lag: float
    overshoot: float
    settling_time: float
    stop_time: float
    user_path_length: float = math.nan
    robot_path_length: float = math.nan
    target_path_length: float = math.nan
    path_length_ratio: float = math.nan

    def as_dict(self) -> dict[str, float]:
        """Flat dict with unit-carrying keys (tuples expanded)."""
        out: dict[str, float] = {}
        for k, v in asdict(self).items():
            if isinstance(v, tuple):
                for lab, val in zip(("x_m", "y_m", "heading_deg"), v, strict=True):
                    out[f"{k}_{lab}"] = val
            elif k.endswith("_deg"):
                out[k] = v
            elif k in ("lag", "settling_time", "stop_time"):
                out[f"{k}_s"] = v
            elif k == "path_length_ratio":
                out[k] = v
            else:
                out[f"{k}_m"] = v
        return out


def path_length(x: NDArray, y: NDArray) -> float:
    """Length in m of the polyline through the points (x, y).

    Parameters
    ----------
    x, y
        Coordinates in m, same length.

    Examples
    --------
    >>> path_length(np.array([0.0, 3.0, 3.0]), np.array([0.0, 0.0, 4.0]))
    7.0
    """
    return float(np.sum(np.hypot(np.diff(x), np.diff(y))))


def command_rate(time: NDArray, command: NDArray) -> float:
    """RMS over a run of the rate of change of the planar velocity command, m/s^2.

    ``|d(V_x, V_y)/dt|`` between consecutive control periods: what sensor noise passed to
    the command asks of the platform, to compare with its acceleration limit (a norm
    limit on the same vector).

    Parameters
    ----------
    time
        Control instants in s, (n + 1,) or (n,), evenly spaced.
    command
        (V_x, V_y, omega_z) commands per control period, (3, n), m/s and rad/s.

    Examples
    --------
    >>> t = np.arange(5) * 0.02
    >>> cmd = np.vstack([np.array([0.0, 0.02, 0.04, 0.06]), np.zeros(4), np.zeros(4)])
    >>> round(command_rate(t, cmd), 12)
    1.0
    """
    t = np.asarray(time, dtype=float)
    c = np.asarray(command, dtype=float)
    if c.ndim != 2 or c.shape[0] < 2 or c.shape[1] < 2 or t.ndim != 1 or len(t) < 2:
        raise InvalidParameterError("command", c.shape, "(3, n) commands with n >= 2 and times")
    dv = np.diff(c[:2], axis=1)
    return float(np.sqrt(np.mean(np.sum(dv * dv, axis=0))) / (t[1] - t[0]))


def _circ_mean_sd(a: NDArray) -> tuple[float, float]:
    if a.size == 0:
        return math.nan, math.nan
    m = math.atan2(float(np.mean(np.sin(a))), float(np.mean(np.cos(a))))
    dev = np.arctan2(np.sin(a - m), np.cos(a - m))
    return math.degrees(m), math.degrees(float(np.std(dev)))


def _lag(
    t: NDArray, robot: NDArray, target: tuple[NDArray, NDArray], idx: NDArray, max_lag: float
) -> float:
    """The delay in [0, max_lag] that best aligns the robot's path with the target point's."""
    twx, twy = target
    if not np.hypot(np.ptp(twx[idx]), np.ptp(twy[idx])) > 1e-3:
        return math.nan
    dt = float(t[1] - t[0])
    shifts = np.arange(0, round(max_lag / dt) + 1)
    k = np.clip(idx[None, :] - shifts[:, None], 0, None)
    costs = np.mean((robot[0, idx] - twx[k]) ** 2 + (robot[1, idx] - twy[k]) ** 2, axis=1)
    return float(shifts[int(np.argmin(costs))] * dt)


def _overshoot(
    t: NDArray, robot: NDArray, target: tuple[NDArray, NDArray], walk_stop: float
) -> float:
    """The largest travel beyond the stopped target along its last direction of motion."""
    twx, twy = target
    k_ws = min(int(np.searchsorted(t, walk_stop - 1e-9)), t.size - 1)
    k0 = int(np.searchsorted(t, walk_stop - 0.5))
    vx = twx[k_ws] - twx[max(k0 - 1, 0)]
    vy = twy[k_ws] - twy[max(k0 - 1, 0)]
    nv = math.hypot(vx, vy)
    if not nv > 1e-4:
        return math.nan
    after = slice(k_ws, t.size)
    proj = ((robot[0, after] - twx[after]) * vx + (robot[1, after] - twy[after]) * vy) / nv
    return max(0.0, float(np.max(proj)))


def _settling_time(t: NDArray, err: NDArray, walk_stop: float, band: float) -> float:
    """Time after the stop until the error stays within ``band``; NaN if it never does."""
    outside = np.flatnonzero((err > band) & (t >= walk_stop))
    if outside.size == 0:
        return 0.0
    if outside[-1] == t.size - 1:
        return math.nan
    return float(t[outside[-1] + 1] - walk_stop)


def _pose(a: NDArray, k: int) -> tuple[float, float, float]:
    return (float(a[0, k]), float(a[1, k]), math.degrees(float(a[2, k])))


def _check_walk(
    walk_start: Any, walk_stop: Any, target_heading: Any, target_position: Any
) -> tuple[float, float, float, float, float]:
    """The walk's span (start <= stop, s), the target heading (rad) and position (m)."""
    start, stop, heading = (
        float(real_array(n, v, "s" if n != "target_heading" else "rad"))
        for n, v in (("walk_start", walk_start), ("walk_stop", walk_stop),
                     ("target_heading", target_heading))
    )  # fmt: skip
    if not start <= stop:
        raise InvalidParameterError(
            "walk_stop", walk_stop, f"must not be before walk_start = {start:g} s", "s"
        )
    tp = real_array("target_position", target_position, "m")
    if tp.shape != (2,):
        raise InvalidParameterError("target_position", target_position, "must be (x, y)", "m")
    return start, stop, heading, float(tp[0]), float(tp[1])


def accompany_metrics(
    time: NDArray,
    user_pose: NDArray,
    robot_pose: NDArray,
    target_position: tuple[float, float],
    target_heading: float,
    walk_start: float,
    walk_stop: float,
    *,
    settle_window: float = SETTLE_WINDOW.default,
    settle_band: float = SETTLE_BAND.default,
    max_lag: float = MAX_LAG.default,
) -> AccompanyMetrics:
    """Compute :class:`AccompanyMetrics` from world poses of user and robot.

    Parameters
    ----------
    time
        Sample times in s, shape (n,), uniformly spaced, n >= 2.
    user_pose, robot_pose
        World (x, y, psi) in m, m, rad, shape (3, n).
    target_position, target_heading
        Robot target pose in LCS_U (m, rad).
    walk_start, walk_stop
        When the user walks, s.
    settle_window
        Time after the stop at which the stop pose and the settled error are
        taken, s (the end of the run if shorter; :data:`SETTLE_WINDOW`).
    settle_band
        Error band of the settling time, m (:data:`SETTLE_BAND`).
    max_lag
        Largest delay searched for the lag, s (:data:`MAX_LAG`).
    """
    settle_window, max_lag = SETTLE_WINDOW.check(settle_window), MAX_LAG.check(max_lag)
    settle_band = SETTLE_BAND.check(settle_band)
    t = real_array("time", time, "s")
    if t.ndim != 1 or t.size < 2 or (np.diff(t) <= 0).any():
        raise InvalidParameterError("time", t.shape, "at least 2 increasing samples", "s")
    u = real_array("user_pose", user_pose, "m")
    r = real_array("robot_pose", robot_pose, "m")
    if u.shape != (3, t.size) or r.shape != (3, t.size):
        raise InvalidParameterError(
            "user_pose, robot_pose", (u.shape, r.shape), f"3 rows (x, y, psi) of {t.size} samples"
        )
    walk_start, walk_stop, target_heading, tx, ty = _check_walk(
        walk_start, walk_stop, target_heading, target_position
    )
    p_c, g = robot_in_user_frame(u, r)
    xc, yc = p_c[0], p_c[1]
    err = np.hypot(tx - xc, ty - yc)
    bearing = -np.arctan2(xc, yc)
    walking = (t >= walk_start) & (t <= walk_stop)
    if not walking.any():
        walking = t <= walk_stop
    t_eval = min(walk_stop + settle_window, float(t[-1]))
    k_stop = min(int(np.searchsorted(t, t_eval - 1e-9)), t.size - 1)
    # the target point in the world
    ps = u[2]
    target = (u[0] + np.sin(ps) * tx + np.cos(ps) * ty, u[1] - np.cos(ps) * tx + np.sin(ps) * ty)
    gmean, gsd = _circ_mean_sd(g[walking])
    bmean, bsd = _circ_mean_sd(bearing[walking])
    return AccompanyMetrics(
        target_x=float(xc[0]),
        target_y=float(yc[0]),
        target_bearing_deg=math.degrees(float(bearing[0])),
        target_gamma_deg=math.degrees(float(g[0])),
        stop_x=float(xc[k_stop]),
        stop_y=float(yc[k_stop]),
        stop_bearing_deg=math.degrees(float(bearing[k_stop])),
        stop_gamma_deg=math.degrees(float(g[k_stop])),
        mean_x=float(np.mean(xc[walking])),
        sd_x=float(np.std(xc[walking])),
        mean_y=float(np.mean(yc[walking])),
        sd_y=float(np.std(yc[walking])),
        mean_bearing_deg=bmean,
        sd_bearing_deg=bsd,
        mean_gamma_deg=gmean,
        sd_gamma_deg=gsd,
        user_start=_pose(u, 0),
        user_stop=_pose(u, k_stop),
        robot_start=_pose(r, 0),
        robot_stop=_pose(r, k_stop),
        rms_error=float(np.sqrt(np.mean(err[walking] ** 2))),
        max_error=float(np.max(err)),
        settled_error=float(err[k_stop]),
        lag=_lag(t, r, target, np.flatnonzero(walking), max_lag),
        overshoot=_overshoot(t, r, target, walk_stop),
        settling_time=_settling_time(t, err, walk_stop, settle_band),
        stop_time=float(t[k_stop]),
        **_path_lengths(u, r, target),
    )


def _path_lengths(u: NDArray, r: NDArray, target: tuple[NDArray, NDArray]) -> dict[str, float]:
    user = path_length(u[0], u[1])
    robot = path_length(r[0], r[1])
    return {
        "user_path_length": user,
        "robot_path_length": robot,
        "target_path_length": path_length(*target),
        "path_length_ratio": robot / user if user > 1e-12 else math.nan,
    }
