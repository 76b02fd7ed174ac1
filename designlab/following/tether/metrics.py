"""Figures of merit of a tether-follower run (Allan 2015 Sec. 2.5.1).

* normal path deviation (App. A; :mod:`designlab.following.tether.path_deviation`);
* tether-length error ``l_m - l_d`` (the tether-length profile of Sec. 2.5.1:
  the cannula length must be respected), RMS and maximum, and the range of l_m;
* velocity smoothness: RMS of dV/dt and dOmega/dt (the thesis shows velocity
  profiles and calls bursts "jerky" but defines no number; this is the
  project's measure), and robot stops while the leader walks;
* path-length ratio: robot distance over leader distance (Sec. 2.5.2: PJ with a
  long tether drives about half the leader's distance).

Examples
--------
>>> from designlab.following.tether import FollowTheLeader, figure_eight, simulate
>>> m = follower_metrics(simulate(FollowTheLeader(), figure_eight(a=4.0), speed=0.5))
>>> round(m.path_length_ratio, 2), str(m.npd.status)
(0.99, 'ok')
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from designlab.errors import InvalidParameterError
from designlab.following.tether.path_deviation import PathDeviation, normal_path_deviation
from designlab.following.tether.simulate import FollowerRun, FollowerStatus
from designlab.results import Result

__all__ = ["FollowerMetrics", "follower_metrics", "lateral_offset"]


@dataclass(frozen=True, eq=False)
class FollowerMetrics(Result):
    """Scalar figures of one run (SI units; ``*_over_b`` in wheel tracks).

    Attributes
    ----------
    npd
        The normal path deviation (profile and statistics).
    length_error_rms, length_error_max
        RMS and maximum of ``|l_m - l_d|`` in m.
    tether_min, tether_max
        Range of the measured tether length in m.
    accel_rms, yaw_accel_rms
        RMS of dV/dt (m/s^2) and dOmega/dt (rad/s^2).
    stops
        Number of times the robot stopped (V < 1 % of the leader speed for at
        least 0.2 s) while the leader was walking.
    path_length_ratio
        Robot distance over leader distance.
    wheel_track
        Wheel track b in m (the unit of the ``*_over_b`` figures).
    status
        ``"ok"``, or the run's status.
    warnings
        What a user should know about the figures.
    """

    npd: PathDeviation
    length_error_rms: float
    length_error_max: float
    tether_min: float
    tether_max: float
    accel_rms: float
    yaw_accel_rms: float
    stops: int
    path_length_ratio: float
    wheel_track: float
    status: FollowerStatus = FollowerStatus.OK
    warnings: tuple[str, ...] = ()

    def as_dict(self) -> dict[str, float]:
        """The figures as a flat dict with unit-carrying keys."""
        return {
            **self.npd.statistics(),
            "length_error_rms_m": self.length_error_rms,
            "length_error_max_m": self.length_error_max,
            "tether_min_m": self.tether_min,
            "tether_max_m": self.tether_max,
            "accel_rms_m_per_s2": self.accel_rms,
            "yaw_accel_rms_rad_per_s2": self.yaw_accel_rms,
            "stops": float(self.stops),
            "path_length_ratio": self.path_length_ratio,
        }

    def to_frame(self) -> pd.DataFrame:
        """One row of :meth:`as_dict`."""
        return pd.DataFrame([self.as_dict()])


def _stops(speed: np.ndarray, moving: np.ndarray, v_ref: float, dt: float) -> int:
    slow = (np.abs(speed) < 0.01 * v_ref) & moving
    if not slow.any():
        return 0
    edges = np.diff(np.concatenate([[0], slow.astype(int), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return int(np.sum((ends - starts) * dt >= 0.2))


def follower_metrics(run: FollowerRun, **npd_options: Any) -> FollowerMetrics:
    """Figures of merit of a simulated run (see the module notes).

    Parameters
    ----------
    run
        A :class:`FollowerRun` from :func:`designlab.following.simulate`.
    **npd_options
        Passed to :func:`normal_path_deviation` (``wheel_track`` defaults to
        the robot's).
    """
    if not isinstance(run, FollowerRun):
        raise InvalidParameterError("run", run, "must be a FollowerRun (tether.simulate())")
    npd_options.setdefault("wheel_track", run.robot.wheel_track)
    npd = normal_path_deviation(run.leader_xy, run.robot_xy, **npd_options)
    dt = run.robot.sample_time
    err = run.tether_length - run.controller.desired_length
    leader_step = np.hypot(*np.diff(run.leader_xy, axis=0).T)
    robot_step = np.hypot(*np.diff(run.robot_xy, axis=0).T)
    leader_dist = float(leader_step.sum())
    moving = np.concatenate([leader_step > 0.5 * run.speed_leader * dt, [False]])
    warns = list(npd.warnings)
    ratio = float(robot_step.sum()) / leader_dist if leader_dist > 0 else math.nan
    return FollowerMetrics(
        npd=npd,
        length_error_rms=float(np.sqrt(np.mean(err**2))),
        length_error_max=float(np.max(np.abs(err))),
        tether_min=float(np.min(run.tether_length)),
        tether_max=float(np.max(run.tether_length)),
        accel_rms=float(np.sqrt(np.mean((np.diff(run.speed) / dt) ** 2))),
        yaw_accel_rms=float(np.sqrt(np.mean((np.diff(run.turn_rate) / dt) ** 2))),
        stops=_stops(run.speed, moving, run.speed_leader, dt),
        path_length_ratio=ratio,
        wheel_track=npd.wheel_track,
        status=FollowerStatus(str(npd.status)) if run.status == "ok" else run.status,
        warnings=tuple(warns) + run.warnings,
    )


def lateral_offset(robot_xy: Any, leader_xy: Any, heading: Any) -> np.ndarray:
    """Signed distance of the robot left of the leader's heading line, per period (m).

    Parameters
    ----------
    robot_xy, leader_xy
        Positions (N, 2) in m.
    heading
        Leader heading per period in rad, (N,).
    """
    d = np.asarray(robot_xy, float) - np.asarray(leader_xy, float)
    h = np.asarray(heading, float)
    return -np.sin(h) * d[:, 0] + np.cos(h) * d[:, 1]
