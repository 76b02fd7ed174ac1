"""Closed-loop simulation of the accompanying robot (Wu et al. 2021).

The control period is written once in CasADi
(:func:`designlab.following.accompanying.model.period_function`); the whole
run is the period function chained by CasADi's ``mapaccum`` and evaluated in
one call. :func:`simulate` (also called :func:`accompany`, its name in the
package's API) checks its inputs and the size of the run, builds the inputs
(user poses at the raw sampling instants, sensor noise), runs the chain and
summarises the run (:class:`AccompanyResult`).

Examples
--------
>>> from designlab.following import accompanying as acc
>>> res = acc.simulate(acc.walking_task("forward"))
>>> str(res.status), res.rms_error < 0.15, res.settled_error < 0.02
('ok', True, True)
>>> list(res.to_frame().columns[:4])
['task', 'target_x_m', 'target_y_m', 'target_bearing_deg']
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import casadi as ca
import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.following.accompanying.extras import MotionFilter, SensorMount, TargetAdaptation
from designlab.following.accompanying.metrics import AccompanyMetrics, accompany_metrics
from designlab.following.accompanying.model import N_PARAMETERS, period_function
from designlab.following.accompanying.parameters import (
    INITIAL_OFFSET,
    SEED,
    SETTLE_BAND,
    MecanumPlatform,
    StringPotSensor,
    UserFramePID,
    loop_parts,
)
from designlab.following.accompanying.tasks import WalkingTask
from designlab.following.accompanying.user_frame import (
    robot_frame_error,
    robot_in_user_frame,
    string_pot_readings,
)
from designlab.params import check_size
from designlab.results import Result, Status

__all__ = ["AccompanyResult", "AccompanyStatus", "accompany", "simulate"]

#: float64 values a run keeps per raw sample (inputs, noise, CasADi's work and outputs).
_VALUES_PER_SAMPLE = 64


class AccompanyStatus(Status):
    """Status of an accompanying run.

    ``OK``: the closed loop stayed bounded. ``UNSTABLE``: the error grew beyond
    10 m or became non-finite.
    """

    OK = "ok"
    UNSTABLE = "unstable"


@lru_cache(maxsize=64)
def _run_function(
    substeps: int,
    window: int,
    modes: tuple[str, bool, bool],
    extras: tuple[bool, bool, bool],
    n: int,
) -> ca.Function:
    limit_mode, wheel_level, quantize = modes
    f = period_function(substeps, window, limit_mode, wheel_level, quantize, extras)
    return f.mapaccum("accompany_run", n)


def _param_vector(run: _Run) -> NDArray[np.float64]:
    controller, platform, sensor, task = run.controller, run.platform, run.sensor, run.task
    p = np.zeros(N_PARAMETERS)
    p[:12] = controller.vector()
    p[12:18] = [
        platform.time_constant,
        platform.yaw_tau,
        platform.max_speed,
        platform.max_acceleration,
        platform.max_yaw_rate,
        platform.max_yaw_acceleration,
    ]
    p[18:21] = [*task.target_position, task.target_heading]
    p[21:23] = [sensor.min_range, sensor.max_range]
    p[23:26] = [
        platform.wheel_radius,
        platform.half_length_sum,
        platform.max_wheel_speed if platform.max_wheel_speed is not None else 1e9,
    ]
    p[26] = sensor.angle_resolution
    p[27] = sensor.period
    if run.mount is not None:
        p[28:31] = [*run.mount.offset, float(run.mount.compensate)]
    if run.adaptation is not None:
        a = run.adaptation
        p[31:34] = [a.gain, a.max_change, a.time_constant]
    if run.motion_filter is not None:
        p[34] = run.motion_filter.time_constant
    return p


@dataclass(frozen=True, eq=False, repr=False)  # Result's one-line repr, not 221 lines
class AccompanyResult(Result):
    """One accompanying run: time series, metrics and the Table 1/2 quantities.

    Attributes
    ----------
    task
        The :class:`WalkingTask`.
    controller, platform, sensor
        The models used.
    time
        Control instants in s, shape (n + 1,).
    user_pose, robot_pose
        World (x, y, psi) of user and robot (its rotation centre) at the control
        instants, (3, n + 1).
    robot_in_user
        (X_C, Y_C, gamma_C) of the sensor point (the origin of LCS_R) in LCS_U
        (true, not measured), (3, n + 1); the metrics are of this point.
    measured_error
        (e_x, e_y, e_theta) the controller saw (eq. 8), (3, n).
    command
        Saturated (V_x, V_y, omega_z) commands, (3, n).
    readings
        Filtered (d, theta_U, theta_R) used by the controller, (3, n).
    flagged
        Raw distance samples outside the sensor's range, per period, (n,).
    metrics
        :class:`AccompanyMetrics`.
    status
        ``"ok"`` or ``"unstable"`` (:class:`AccompanyStatus`).
    warnings
        What a user should know about the run (flagged samples, saturation).
    sensor_pose
        World (x, y, psi) of the sensor point, (3, n + 1); ``robot_pose``
        without a :class:`SensorMount` offset.
    target_change
        Change of the target distance by the :class:`TargetAdaptation`, m, (n,)
        (zeros without it).
    mount, adaptation, motion_filter
        The Sec. 6 options used (``None``: off).
    """

    task: WalkingTask
    controller: UserFramePID
    platform: MecanumPlatform
    sensor: StringPotSensor
    time: NDArray[np.float64]
    user_pose: NDArray[np.float64]
    robot_pose: NDArray[np.float64]
    robot_in_user: NDArray[np.float64]
    measured_error: NDArray[np.float64]
    command: NDArray[np.float64]
    readings: NDArray[np.float64]
    flagged: NDArray[np.float64]
    metrics: AccompanyMetrics
    status: AccompanyStatus = AccompanyStatus.OK
    warnings: tuple[str, ...] = field(default=())
    sensor_pose: NDArray[np.float64] | None = None
    target_change: NDArray[np.float64] | None = None
    mount: SensorMount | None = None
    adaptation: TargetAdaptation | None = None
    motion_filter: MotionFilter | None = None

    @property
    def rms_error(self) -> float:
        """RMS of the position error in the user's frame while the user walks, m."""
        return self.metrics.rms_error

    @property
    def settled_error(self) -> float:
        """Position error in the user's frame 10 s after the user stops, m."""
        return self.metrics.settled_error

    @property
    def max_error(self) -> float:
        """Largest position error in the user's frame over the run, m."""
        return self.metrics.max_error

    @property
    def position_error(self) -> NDArray[np.float64]:
        """Position error p_T - p_C in LCS_U at the control instants, (2, n + 1), m."""
        tx, ty = self.task.target_position
        return np.vstack([tx - self.robot_in_user[0], ty - self.robot_in_user[1]])

    def to_frame(self) -> pd.DataFrame:
        """One row: the Table 2 and Table 1 quantities and the tracking metrics (SI, deg)."""
        row: dict[str, object] = {"task": self.task.name}
        row.update(self.metrics.as_dict())
        row["flagged_samples"] = int(self.flagged.sum())
        row["status"] = self.status
        return pd.DataFrame([row])

    def history(self) -> pd.DataFrame:
        """Time series at the control rate (world poses, pose in LCS_U, errors, commands)."""
        n = self.command.shape[1]
        pad = np.full(1, np.nan)
        e = self.position_error
        return pd.DataFrame(
            {
                "time_s": self.time,
                "user_x_m": self.user_pose[0],
                "user_y_m": self.user_pose[1],
                "user_heading_rad": self.user_pose[2],
                "robot_x_m": self.robot_pose[0],
                "robot_y_m": self.robot_pose[1],
                "robot_heading_rad": self.robot_pose[2],
                "X_C_m": self.robot_in_user[0],
                "Y_C_m": self.robot_in_user[1],
                "gamma_C_rad": self.robot_in_user[2],
                "error_x_m": e[0],
                "error_y_m": e[1],
                "command_vx_m_s": np.concatenate([self.command[0], pad]),
                "command_vy_m_s": np.concatenate([self.command[1], pad]),
                "command_wz_rad_s": np.concatenate([self.command[2], pad]),
                "d_m": np.concatenate([self.readings[0], pad]),
                "theta_U_rad": np.concatenate([self.readings[1], pad]),
                "theta_R_rad": np.concatenate([self.readings[2], pad]),
            }
        ).iloc[: n + 1]


@dataclass(frozen=True)
class _Run:
    """A checked request of :func:`simulate`."""

    task: WalkingTask
    controller: UserFramePID
    platform: MecanumPlatform
    sensor: StringPotSensor
    offset: tuple[float, float]
    seed: int | None
    settle_band: float
    periods: int
    mount: SensorMount | None = None
    adaptation: TargetAdaptation | None = None
    motion_filter: MotionFilter | None = None

    @property
    def extras(self) -> tuple[bool, bool, bool]:
        """Flags of the Sec. 6 options for the period function."""
        return (
            self.mount is not None,
            self.adaptation is not None,
            self.motion_filter is not None,
        )


def _checked(task: Any, controller: Any, platform: Any, sensor: Any, **args: Any) -> _Run:
    """Validate every argument of :func:`simulate` and the size of the run."""
    if not isinstance(task, WalkingTask):
        raise InvalidParameterError("task", type(task).__name__, "must be a WalkingTask")
    controller, platform, sensor = loop_parts(controller, platform, sensor)
    for name, obj, cls in (
        ("mount", args["mount"], (SensorMount, type(None))),
        ("adaptation", args["adaptation"], (TargetAdaptation, type(None))),
        ("motion_filter", args["motion_filter"], (MotionFilter, type(None))),
    ):
        if not isinstance(obj, cls):
            want = cls.__name__ if isinstance(cls, type) else f"{cls[0].__name__} or None"
            raise InvalidParameterError(name, type(obj).__name__, f"must be a {want}")
    off = args["initial_offset"]
    if isinstance(off, (str, bytes)) or np.shape(off) != (2,):
        raise InvalidParameterError("initial_offset", off, "two numbers (X, Y) in m", "m")
    offset = tuple(INITIAL_OFFSET.check(v, "initial_offset") for v in off)
    n = math.ceil(task.duration / sensor.period - 1e-9)
    check_size(
        "task.duration",
        task.duration,
        float(n) * sensor.oversampling * _VALUES_PER_SAMPLE,
        what=f"{n} control periods of {sensor.oversampling} raw samples",
    )
    return _Run(
        task,
        controller,
        platform,
        sensor,
        offset,  # type: ignore[arg-type]
        SEED.check(args["seed"]),
        SETTLE_BAND.check(args["settle_band"]),
        n,
        args["mount"],
        args["adaptation"],
        args["motion_filter"],
    )


def _inputs(run: _Run) -> tuple[NDArray, NDArray, NDArray]:
    """Control instants, the user pose at every raw instant (3 S, n) and the noise (3 S, n)."""
    ts, s_n, n = run.sensor.period, run.sensor.oversampling, run.periods
    t_ctrl = np.arange(n + 1) * ts
    t_raw = (t_ctrl[:-1, None] + np.arange(s_n)[None, :] * (ts / s_n)).ravel()
    user_raw = run.task.pose(t_raw)  # (3, n*S)
    # rows of user_in: (x, y, psi) of substep 0, then of substep 1, ...
    user_in = np.stack([user_raw.reshape(3, n, s_n)[:, :, j] for j in range(s_n)]).reshape(
        3 * s_n, n
    )
    noise = np.zeros((3 * s_n, n))
    if run.sensor.noisy:
        rng = np.random.default_rng(run.seed)
        sd = np.tile(
            [run.sensor.distance_noise, run.sensor.angle_noise, run.sensor.angle_noise], s_n
        )
        noise = rng.standard_normal((3 * s_n, n)) * sd[:, None]
    return t_ctrl, user_in, noise


def _sensor_to_centre(sensor: NDArray, offset: tuple[float, float]) -> NDArray:
    """World pose of the rotation centre from that of the sensor point at ``offset``."""
    ax, ay = offset
    psi = sensor[2]
    return np.array(
        [
            sensor[0] - ax * np.sin(psi) - ay * np.cos(psi),
            sensor[1] + ax * np.cos(psi) - ay * np.sin(psi),
            psi,
        ]
    )


def _initial_state(run: _Run) -> NDArray[np.float64]:
    """On target (plus the offset), at rest, the filters full of the first reading.

    The sensor point is placed on the target; the Sec. 6 options start from
    the first reading (approach speed zero, motion filter at the first error).
    """
    task = run.task
    u0 = task.pose(0.0)
    tx, ty = task.target_position
    px, py = tx + run.offset[0], ty + run.offset[1]
    psu = u0[2]
    r0 = np.array(
        [
            u0[0] + math.sin(psu) * px + math.cos(psu) * py,
            u0[1] - math.cos(psu) * px + math.sin(psu) * py,
            psu + task.target_heading,
        ]
    )
    p_c, g_c = robot_in_user_frame(u0, r0)
    d0, tu0, tr0 = string_pot_readings(p_c, g_c)
    e0 = robot_frame_error(task.target_position, task.target_heading, d0, tu0, tr0)
    if run.mount is not None:
        r0 = _sensor_to_centre(r0, run.mount.offset)
    w1 = run.sensor.median_window - 1
    extra = [[d0, 0.0]] if run.adaptation is not None else []
    if run.motion_filter is not None:
        extra.append(list(e0))
    return np.concatenate(
        [
            r0,
            np.zeros(6),
            np.zeros(3),
            e0,
            [d0],
            np.full(w1, d0),
            np.full(w1, tu0),
            np.full(w1, tr0),
            *extra,
        ]
    )


def _warnings(run: _Run, rin: NDArray, robot: NDArray, flagged: NDArray, cmd: NDArray) -> tuple:
    """The status and what a user should know about the run."""
    task, sensor, platform = run.task, run.sensor, run.platform
    warnings: list[str] = []
    status = AccompanyStatus.OK
    tx, ty = task.target_position
    err = np.hypot(tx - rin[0], ty - rin[1])
    if not np.all(np.isfinite(robot)) or np.nanmax(err) > 10.0:
        status = AccompanyStatus.UNSTABLE
        warnings.append("the closed loop diverged (error > 10 m or non-finite)")
    nflag = int(flagged.sum())
    n_samples = run.periods * (sensor.oversampling if sensor.median_window > 1 else 1)
    if nflag:
        warnings.append(
            f"{nflag} of {n_samples} raw distance samples fell outside the sensor range "
            f"{sensor.min_range}-{sensor.max_range} m and were replaced by the last valid value"
        )
    lin = np.hypot(cmd[0], cmd[1]) if platform.limit_mode == "norm" else np.max(np.abs(cmd[:2]), 0)
    sat_frac = float(np.mean(lin >= platform.max_speed * (1 - 1e-9)))
    if sat_frac > 0:
        warnings.append(f"the speed command saturated in {100 * sat_frac:.1f} % of the periods")
    if np.any(np.hypot(rin[0], rin[1]) < task.user_radius):
        warnings.append("the robot came within user_radius of the user's frame origin (collision)")
    if task.duration < task.walk_stop + 10.0 - 1e-9:
        warnings.append(
            "the task ends less than 10 s after the user stops; "
            "the settled error is taken at the end"
        )
    return status, tuple(warnings)


def simulate(
    task: WalkingTask,
    controller: UserFramePID | None = None,
    *,
    platform: MecanumPlatform | None = None,
    sensor: StringPotSensor | None = None,
    initial_offset: tuple[float, float] = (0.0, 0.0),
    seed: int | None = SEED.default,
    settle_band: float = SETTLE_BAND.default,
    mount: SensorMount | None = None,
    adaptation: TargetAdaptation | None = None,
    motion_filter: MotionFilter | None = None,
) -> AccompanyResult:
    """Simulate the accompanying robot keeping its pose in the user's frame during ``task``.

    The robot starts at rest on its target pose (plus ``initial_offset``);
    the run lasts the task's duration at the sensor's control rate.

    Parameters
    ----------
    task
        The user's walk and the robot's target (:func:`walking_task`).
    controller
        PID gains; default :class:`UserFramePID()`.
    platform
        Mecanum platform model; default :class:`MecanumPlatform()`.
    sensor
        String-pot model; default :class:`StringPotSensor()` (50 Hz, no noise).
    initial_offset
        Initial position offset of the robot from its target in LCS_U, m.
    seed
        Seed of the sensor noise (used only if the sensor is noisy).
    settle_band
        Error band of the settling time, m (:data:`SETTLE_BAND`).
    mount
        The sensor's offset from the rotation centre, with or without
        compensation (:class:`SensorMount`; ``None``: at the centre).
    adaptation
        Target-distance adaptation of Sec. 6 (:class:`TargetAdaptation`; ``None``: off).
    motion_filter
        Low-pass on the error of Sec. 6 (:class:`MotionFilter`; ``None``: off).

    Returns
    -------
    AccompanyResult
        ``status`` ``"ok"`` or ``"unstable"``; ``warnings`` on flagged samples, saturation.

    Examples
    --------
    >>> from designlab.following.accompanying import walking_task, UserFramePID
    >>> r = simulate(walking_task("right_lateral"), UserFramePID(kp=3.0, ki=1.0, kd=0.1))
    >>> r.metrics.mean_x < r.task.target_position[0]    # lags to the user's left
    True
    >>> from designlab.following.accompanying import TargetAdaptation
    >>> a = simulate(walking_task("forward"), adaptation=TargetAdaptation(gain=0.3))
    >>> float(a.target_change.max()) > 0.0                  # the user approaches: longer
    True
    """
    run = _checked(
        task,
        controller,
        platform,
        sensor,
        initial_offset=initial_offset,
        seed=seed,
        settle_band=settle_band,
        mount=mount,
        adaptation=adaptation,
        motion_filter=motion_filter,
    )
    t_ctrl, user_in, noise = _inputs(run)
    s, p = run.sensor, run.platform
    chain = _run_function(
        s.oversampling,
        s.median_window,
        (p.limit_mode, p.max_wheel_speed is not None, s.angle_resolution > 0),
        run.extras,
        run.periods,
    )
    x0 = _initial_state(run)
    xs, ys = chain(x0, user_in, noise, _param_vector(run))
    return _result(run, t_ctrl, np.hstack([x0[:3, None], xs.full()[:3]]), ys.full())


def _result(run: _Run, t_ctrl: NDArray, robot: NDArray, ys: NDArray) -> AccompanyResult:
    """Summarise a run: poses in the user's frame, metrics, status and warnings."""
    user = run.task.pose(t_ctrl)
    sensor_pose = robot
    if run.mount is not None:
        sensor_pose = np.vstack([*_sensor_pose_np(robot, run.mount.offset), robot[2]])
    pc, gc = robot_in_user_frame(user, sensor_pose)
    rin = np.vstack([pc, gc])
    status, warnings = _warnings(run, rin, robot, ys[9], ys[3:6])
    t = run.task
    metrics = accompany_metrics(
        t_ctrl,
        user,
        sensor_pose,
        t.target_position,
        t.target_heading,
        t.walk_start,
        t.walk_stop,
        settle_band=run.settle_band,
    )
    if math.isnan(metrics.settling_time):
        warnings = (*warnings, f"the error never stays within settle_band = {run.settle_band:g} m "
                    "after the stop: settling_time is undefined (nan)")  # fmt: skip
    return AccompanyResult(
        task=t,
        controller=run.controller,
        platform=run.platform,
        sensor=run.sensor,
        time=t_ctrl,
        user_pose=user,
        robot_pose=robot,
        robot_in_user=rin,
        measured_error=ys[0:3],
        command=ys[3:6],
        readings=ys[6:9],
        flagged=ys[9],
        metrics=metrics,
        status=status,
        warnings=warnings,
        sensor_pose=sensor_pose,
        target_change=ys[10],
        mount=run.mount,
        adaptation=run.adaptation,
        motion_filter=run.motion_filter,
    )


def _sensor_pose_np(robot: NDArray, offset: tuple[float, float]) -> list[NDArray]:
    """World (x, y) of the sensor point for rotation-centre poses (3, n)."""
    ax, ay = offset
    psi = robot[2]
    return [
        robot[0] + ax * np.sin(psi) + ay * np.cos(psi),
        robot[1] - ax * np.cos(psi) + ay * np.sin(psi),
    ]


accompany = simulate
"""The name of :func:`simulate` in the package's API: ``designlab.following.accompany``."""
