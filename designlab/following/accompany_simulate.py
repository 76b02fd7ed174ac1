"""Closed-loop simulation of the accompanying robot (Wu et al. 2021).

One control period is written once in CasADi: string-pot raw samples at the
oversampled rate (noise, quantisation, validity range, median filter), the
eq. (8) error at the control instant, three PIDs with anti-windup (eq. 9),
command saturation, the optional eq. (10) wheel-speed limit and the
first-order-lag, acceleration-limited mecanum platform integrated exactly per
raw sub-step. The whole run is the period function chained by CasADi's
``mapaccum`` and evaluated in one call.

Examples
--------
>>> import designlab as dl
>>> fol = dl.following
>>> res = fol.accompany(fol.walking_task("forward"))
>>> res.status, res.rms_error < 0.15, res.settled_error < 0.02
('ok', True, True)
>>> list(res.to_frame().columns[:4])
['task', 'target_x_m', 'target_y_m', 'target_bearing_deg']
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import casadi as ca
import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.following.accompany_metrics import AccompanyMetrics, accompany_metrics
from designlab.following.accompany_model import MecanumPlatform, StringPotSensor
from designlab.following.user_frame import (
    robot_frame_error,
    robot_in_user_frame,
    string_pot_readings,
    sx_robot_frame_error,
    sx_robot_in_user_frame,
    sx_string_pot,
)
from designlab.following.user_frame_pid import UserFramePID, sx_pid_axis
from designlab.following.walking_tasks import WalkingTask
from designlab.results import OK, Result

__all__ = ["AccompanyResult", "accompany", "period_function"]

_N_PARAM = 28
_N_OUT = 10


def _wrap(a):
    return ca.atan2(ca.sin(a), ca.cos(a))


def _median(values: list) -> ca.SX:
    """Median of an odd-length list by an odd-even transposition sorting network."""
    v = list(values)
    n = len(v)
    for p in range(n):
        for i in range(p % 2, n - 1, 2):
            lo, hi = ca.fmin(v[i], v[i + 1]), ca.fmax(v[i], v[i + 1])
            v[i], v[i + 1] = lo, hi
    return v[n // 2]


def _state_size(window: int) -> int:
    return 16 + 3 * (window - 1)


@lru_cache(maxsize=32)
def period_function(
    substeps: int, window: int, limit_mode: str, wheel_level: bool, quantize: bool = False
) -> ca.Function:
    """The CasADi function of one control period: ``(x, user, noise, p) -> (x_next, y)``.

    Parameters
    ----------
    substeps
        Raw sensor samples (and platform integration steps) per period.
    window
        Median-filter window in raw samples (odd).
    limit_mode
        ``"norm"`` or ``"per_axis"`` linear limits.
    wheel_level
        Apply the eq. (10) wheel-speed limit to the command.
    quantize
        Round the encoder angles to the resolution in ``p``.

    Notes
    -----
    State ``x`` (``16 + 3 (window - 1)``): robot world pose (3), body
    velocity (3), PID integrators (3), derivative states (3), previous errors
    (3), last valid distance (1), then the median buffers of d, theta_U,
    theta_R. Raw samples between control instants feed only the median filter;
    with ``window == 1`` only the sample at the control instant is taken (the
    others would be discarded by the down-sampling), and only it is checked
    against the range. Input ``user`` (3 substeps): user world pose at each raw instant;
    ``noise`` (3 substeps): additive noise on (d, theta_U, theta_R); ``p``
    (28): gains (K_p, K_i, K_d, T_f) x 3, tau, tau_yaw, v_max, a_max,
    omega_max, alpha_max, target (X_T, Y_T, gamma_T), range (min, max), wheel
    radius, L1 + L2, wheel-speed limit, angle resolution, T_s.
    Output ``y`` (10): measured errors (3), saturated command (3), filtered
    readings (3), number of flagged raw distance samples.
    """
    s_n = substeps
    nx = _state_size(window)
    x = ca.SX.sym("x", nx)
    user = ca.SX.sym("user", 3 * s_n)
    noise = ca.SX.sym("noise", 3 * s_n)
    p = ca.SX.sym("p", _N_PARAM)
    gains = [p[4 * i : 4 * i + 4] for i in range(3)]
    tau, tau_yaw, vmax, amax, wmax, alpmax = (p[12 + i] for i in range(6))
    tx, ty, tg = p[18], p[19], p[20]
    rmin, rmax = p[21], p[22]
    wheel_r, ll, wheel_max, res, ts = p[23], p[24], p[25], p[26], p[27]
    h = ts / s_n

    pose = [x[0], x[1], x[2]]
    vel = [x[3], x[4], x[5]]
    integ = [x[6], x[7], x[8]]
    deriv = [x[9], x[10], x[11]]
    e_prev = [x[12], x[13], x[14]]
    d_last = x[15]
    w1 = window - 1
    bufs = [[x[16 + c * w1 + k] for k in range(w1)] for c in range(3)]
    flags = 0
    cmd = None
    y_err = y_read = None
    for j in range(s_n):
        if window == 1 and j > 0:
            windows = [[], [], []]
        else:
            uj = user[3 * j : 3 * j + 3]
            xc, yc, gc = sx_robot_in_user_frame(uj, pose)
            d, tu, tr = sx_string_pot(xc, yc, gc)
            d = d + noise[3 * j]
            tu = tu + noise[3 * j + 1]
            tr = tr + noise[3 * j + 2]
            if quantize:
                tu = ca.floor(tu / res + 0.5) * res
                tr = ca.floor(tr / res + 0.5) * res
            valid = ca.logic_and(d >= rmin, d <= rmax)
            d_used = ca.if_else(valid, d, d_last)
            flags = flags + (1 - valid)
            d_last = d_used
            windows = [bufs[0] + [d_used], bufs[1] + [tu], bufs[2] + [tr]]
        if j == 0:
            d_f = _median(windows[0])
            filt = [d_f]
            for c in (1, 2):
                newest = windows[c][-1]
                rel = [_wrap(a - newest) for a in windows[c]]
                filt.append(newest + _median(rel))
            ex, ey, eth = sx_robot_frame_error(tx, ty, tg, *filt)
            err = [ex, ey, eth]
            raw_u, cand, dnew = [], [], []
            for i in range(3):
                kp, ki, kd, tf = gains[i][0], gains[i][1], gains[i][2], gains[i][3]
                ui, ii, di = sx_pid_axis(err[i], e_prev[i], integ[i], deriv[i], kp, ki, kd, tf, ts)
                raw_u.append(ui)
                cand.append(ii)
                dnew.append(di)
            if limit_mode == "norm":
                nrm = ca.sqrt(raw_u[0] ** 2 + raw_u[1] ** 2)
                sc = vmax / ca.fmax(nrm, vmax)
                ux, uy = sc * raw_u[0], sc * raw_u[1]
                sat = [nrm > vmax, nrm > vmax]
            else:
                ux = ca.fmin(ca.fmax(raw_u[0], -vmax), vmax)
                uy = ca.fmin(ca.fmax(raw_u[1], -vmax), vmax)
                sat = [ca.fabs(raw_u[0]) > vmax, ca.fabs(raw_u[1]) > vmax]
            uw = ca.fmin(ca.fmax(raw_u[2], -wmax), wmax)
            sat.append(ca.fabs(raw_u[2]) > wmax)
            integ = [
                ca.if_else(ca.logic_and(sat[i], err[i] * raw_u[i] > 0), integ[i], cand[i])
                for i in range(3)
            ]
            deriv = dnew
            e_prev = err
            cmd = [ux, uy, uw]
            if wheel_level:
                # eq. (10): body velocity -> wheel speeds; scale down uniformly
                wheels = [
                    (ux + uy - ll * uw) / wheel_r,
                    (-ux + uy + ll * uw) / wheel_r,
                    (-ux + uy - ll * uw) / wheel_r,
                    (ux + uy + ll * uw) / wheel_r,
                ]
                wm = ca.fmax(
                    ca.fmax(ca.fabs(wheels[0]), ca.fabs(wheels[1])),
                    ca.fmax(ca.fabs(wheels[2]), ca.fabs(wheels[3])),
                )
                sc_w = wheel_max / ca.fmax(wm, wheel_max)
                cmd = [sc_w * c for c in cmd]
            y_err = err
            y_read = filt
        if window > 1:
            bufs = [w[1:] for w in windows]
        # platform: exact first-order lag per axis over h, then acceleration limit
        a_lin = ca.exp(-h / tau)
        a_yaw = ca.exp(-h / tau_yaw)
        dv = [(cmd[i] - vel[i]) * (1 - (a_lin if i < 2 else a_yaw)) for i in range(3)]
        if limit_mode == "norm":
            nd = ca.sqrt(dv[0] ** 2 + dv[1] ** 2)
            sc = amax * h / ca.fmax(nd, amax * h)
            dv[0], dv[1] = sc * dv[0], sc * dv[1]
        else:
            dv[0] = ca.fmin(ca.fmax(dv[0], -amax * h), amax * h)
            dv[1] = ca.fmin(ca.fmax(dv[1], -amax * h), amax * h)
        dv[2] = ca.fmin(ca.fmax(dv[2], -alpmax * h), alpmax * h)
        new_vel = [vel[i] + dv[i] for i in range(3)]
        avg = [0.5 * (vel[i] + new_vel[i]) for i in range(3)]
        psi_mid = pose[2] + 0.5 * h * avg[2]
        # body (X right, Y forward) -> world
        vxw = avg[0] * ca.sin(psi_mid) + avg[1] * ca.cos(psi_mid)
        vyw = -avg[0] * ca.cos(psi_mid) + avg[1] * ca.sin(psi_mid)
        pose = [pose[0] + h * vxw, pose[1] + h * vyw, pose[2] + h * avg[2]]
        vel = new_vel
    x_next = ca.vertcat(
        *pose, *vel, *integ, *deriv, *e_prev, d_last, *[b for buf in bufs for b in buf]
    )
    y = ca.vertcat(*y_err, *cmd, *y_read, flags)
    return ca.Function("accompany_period", [x, user, noise, p], [x_next, y])


@lru_cache(maxsize=64)
def _run_function(
    substeps: int, window: int, limit_mode: str, wheel_level: bool, quantize: bool, n: int
) -> ca.Function:
    f = period_function(substeps, window, limit_mode, wheel_level, quantize)
    return f.mapaccum("accompany_run", n)


def _param_vector(
    controller: UserFramePID,
    platform: MecanumPlatform,
    sensor: StringPotSensor,
    task: WalkingTask,
) -> NDArray[np.float64]:
    p = np.zeros(_N_PARAM)
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
    return p


@dataclass(frozen=True, eq=False)
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
        World (x, y, psi) of user and robot at the control instants, (3, n + 1).
    robot_in_user
        (X_C, Y_C, gamma_C) of the robot in LCS_U (true, not measured), (3, n + 1).
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
        ``"ok"``, or what went wrong (e.g. the sensor left its valid range).
    warnings
        What a user should know about the run (flagged samples, saturation).
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
    status: str = OK
    warnings: tuple[str, ...] = field(default=())

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


def accompany(
    task: WalkingTask,
    controller: UserFramePID | None = None,
    *,
    platform: MecanumPlatform | None = None,
    sensor: StringPotSensor | None = None,
    initial_offset: tuple[float, float] = (0.0, 0.0),
    seed: int | None = 0,
    settle_band: float = 0.02,
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
        Mecanum platform model; default :class:`MecanumPlatform()` (F5 defaults).
    sensor
        String-pot model; default :class:`StringPotSensor()` (50 Hz, no noise).
    initial_offset
        Initial position offset of the robot from its target in LCS_U, m.
    seed
        Seed of the sensor noise (used only if the sensor is noisy).
    settle_band
        Error band of the settling time, m.

    Returns
    -------
    AccompanyResult
        ``status`` is ``"ok"``, or ``"unstable"`` if the error grew beyond
        10 m or became non-finite. ``warnings`` report flagged distance samples
        and saturation.

    Examples
    --------
    >>> from designlab.following import walking_task, UserFramePID
    >>> r = accompany(walking_task("right_lateral"), UserFramePID(kp=3.0, ki=1.0, kd=0.1))
    >>> r.metrics.mean_x < r.task.target_position[0]    # lags to the user's left
    True
    """
    if not isinstance(task, WalkingTask):
        raise InvalidParameterError("task", type(task).__name__, "must be a WalkingTask")
    controller = UserFramePID() if controller is None else controller
    platform = MecanumPlatform() if platform is None else platform
    sensor = StringPotSensor() if sensor is None else sensor
    for name, obj, cls in (
        ("controller", controller, UserFramePID),
        ("platform", platform, MecanumPlatform),
        ("sensor", sensor, StringPotSensor),
    ):
        if not isinstance(obj, cls):
            raise InvalidParameterError(name, type(obj).__name__, f"must be a {cls.__name__}")
    off = np.asarray(initial_offset, dtype=float)
    if off.shape != (2,) or not np.all(np.isfinite(off)):
        raise InvalidParameterError("initial_offset", initial_offset, "two finite numbers", "m")

    ts = sensor.period
    s_n = sensor.oversampling
    n = math.ceil(task.duration / ts - 1e-9)
    t_ctrl = np.arange(n + 1) * ts
    t_raw = (t_ctrl[:-1, None] + np.arange(s_n)[None, :] * (ts / s_n)).ravel()
    user_raw = task.pose(t_raw)  # (3, n*S)
    # rows of user_in: (x, y, psi) of substep 0, then of substep 1, ...
    user_in = np.stack([user_raw.reshape(3, n, s_n)[:, :, j] for j in range(s_n)]).reshape(
        3 * s_n, n
    )
    noise = np.zeros((3 * s_n, n))
    if sensor.noisy:
        rng = np.random.default_rng(seed)
        sd = np.tile([sensor.distance_noise, sensor.angle_noise, sensor.angle_noise], s_n)
        noise = rng.standard_normal((3 * s_n, n)) * sd[:, None]

    # initial state: on target (plus offset), at rest
    u0 = task.pose(0.0)
    tx, ty = task.target_position
    px, py = tx + off[0], ty + off[1]
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
    w1 = sensor.median_window - 1
    x0 = np.concatenate(
        [
            r0,
            np.zeros(6),
            np.zeros(3),
            e0,
            [d0],
            np.full(w1, d0),
            np.full(w1, tu0),
            np.full(w1, tr0),
        ]
    )
    p = _param_vector(controller, platform, sensor, task)
    run = _run_function(
        s_n,
        sensor.median_window,
        platform.limit_mode,
        platform.max_wheel_speed is not None,
        sensor.angle_resolution > 0,
        n,
    )
    xs, ys = run(x0, user_in, noise, p)
    xs = xs.full()
    ys = ys.full()
    robot = np.hstack([r0[:, None], xs[:3]])
    user = task.pose(t_ctrl)
    pc, gc = robot_in_user_frame(user, robot)
    rin = np.vstack([pc, gc])
    warnings: list[str] = []
    status = OK
    err = np.hypot(tx - rin[0], ty - rin[1])
    if not np.all(np.isfinite(robot)) or np.nanmax(err) > 10.0:
        status = "unstable"
        warnings.append("the closed loop diverged (error > 10 m or non-finite)")
    flagged = ys[9]
    nflag = int(flagged.sum())
    n_samples = n * (s_n if sensor.median_window > 1 else 1)
    if nflag:
        warnings.append(
            f"{nflag} of {n_samples} raw distance samples fell outside the sensor range "
            f"{sensor.min_range}-{sensor.max_range} m and were replaced by the last valid value"
        )
    cmd = ys[3:6]
    lin = np.hypot(cmd[0], cmd[1]) if platform.limit_mode == "norm" else np.max(np.abs(cmd[:2]), 0)
    sat_frac = float(np.mean(lin >= platform.max_speed * (1 - 1e-9)))
    if sat_frac > 0:
        warnings.append(f"the speed command saturated in {100 * sat_frac:.1f} % of the periods")
    d_true = np.hypot(rin[0], rin[1])
    if np.any(d_true < task.user_radius):
        warnings.append("the robot came within user_radius of the user's frame origin (collision)")
    metrics = accompany_metrics(
        t_ctrl,
        user,
        robot,
        task.target_position,
        task.target_heading,
        task.walk_start,
        task.walk_stop,
        settle_band=settle_band,
    )
    if task.duration < task.walk_stop + 10.0 - 1e-9:
        warnings.append(
            "the task ends less than 10 s after the user stops; "
            "the settled error is taken at the end"
        )
    return AccompanyResult(
        task=task,
        controller=controller,
        platform=platform,
        sensor=sensor,
        time=t_ctrl,
        user_pose=user,
        robot_pose=robot,
        robot_in_user=rin,
        measured_error=ys[0:3],
        command=cmd,
        readings=ys[6:9],
        flagged=flagged,
        metrics=metrics,
        status=status,
        warnings=tuple(warnings),
    )
