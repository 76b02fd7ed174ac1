"""The accompanying robot's control period in CasADi (Wu et al. 2021, eqs. 7-10).

One control period is written once: string-pot raw samples at the
oversampled rate (noise, quantisation, validity range, median filter), the
eq. (8) error at the control instant, three PIDs with anti-windup (eq. 9),
command saturation, the optional eq. (10) wheel-speed limit and the
first-order-lag, acceleration-limited mecanum platform integrated exactly per
raw sub-step (:func:`period_function`). The parts are small functions of
CasADi symbols: :func:`sx_pid_axis` (one PID update), the sampling, the
saturation, the wheel limit and the platform step. :func:`mecanum_matrix` is
eq. (10) on numbers.

The discrete PID (``docs/following.md``): backward-Euler integral
``I_k = I_{k-1} + K_i T_s e_k``; derivative on the error through a
first-order filter ``D_k = (T_f D_{k-1} + K_d (e_k - e_{k-1})) / (T_f + T_s)``;
anti-windup by conditional integration (while the command is saturated, the
integrator of an axis whose error pushes further into the saturation is
frozen). So ``C(z) = K_p + K_i T_s z/(z-1) + K_d (z-1)/((T_f+T_s) z - T_f)``,
which :mod:`designlab.following.accompanying.linear` uses.

Examples
--------
>>> f = period_function(4, 1, "norm", False)
>>> f.name(), f.size1_in(0), f.size1_out(1)
('accompany_period', 16, 11)
>>> mecanum_matrix(0.05, 0.4) @ [0.1, 0.0, 0.0]      # pure lateral right
array([ 2., -2., -2.,  2.])
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.following.accompanying.extras import (
    adapted_target,
    approach_speed,
    centre_velocity,
    filter_step,
    sensor_point_velocity,
)
from designlab.following.accompanying.user_frame import (
    sx_robot_frame_error,
    sx_robot_in_user_frame,
    sx_string_pot,
)

__all__ = [
    "N_OUTPUTS",
    "N_PARAMETERS",
    "mecanum_matrix",
    "period_function",
    "state_size",
    "sx_pid_axis",
]

#: Length of the parameter vector ``p`` of :func:`period_function`.
N_PARAMETERS = 35
#: Length of the output ``y`` of :func:`period_function`.
N_OUTPUTS = 11
#: The Sec. 6 options of :func:`period_function`, in the order of its ``extras`` flags.
EXTRAS = ("mount", "adaptation", "motion_filter")
#: Extra state entries of each option (previous distance and approach speed; filtered errors).
_EXTRA_STATES = {"mount": 0, "adaptation": 2, "motion_filter": 3}


def mecanum_matrix(wheel_radius: float, half_length_sum: float) -> NDArray[np.float64]:
    """Mecanum inverse kinematics, body velocity -> physical wheel speeds (eq. 10).

    Rows are the wheels front-left, front-right, rear-left, rear-right; a
    positive wheel speed rolls the wheel forward. Columns act on
    (V_x lateral-right, V_y forward, omega_z counter-clockwise). This is the
    consistent reading of the printed eq. (10) with the right-hand motors
    mounted mirrored (their pulse widths are the negated FR and RR rows).

    Parameters
    ----------
    wheel_radius
        Mecanum wheel radius R in m (> 0).
    half_length_sum
        L1 + L2, half wheelbase plus half track, in m (> 0).

    Examples
    --------
    >>> mecanum_matrix(0.05, 0.4) @ [0.0, 1.0, 0.0]
    array([20., 20., 20., 20.])
    """
    r, ll = float(wheel_radius), float(half_length_sum)
    for name, v in (("wheel_radius", r), ("half_length_sum", ll)):
        if not (np.isfinite(v) and v > 0):
            raise InvalidParameterError(name, v, "must be a finite number > 0", "m")
    return np.array([[1.0, 1.0, -ll], [-1.0, 1.0, ll], [-1.0, 1.0, -ll], [1.0, 1.0, ll]]) / r


def sx_pid_axis(e, e_prev, i_prev, d_prev, kp, ki, kd, tf, ts):  # type: ignore[no-untyped-def]
    """One PID update before saturation (symbolic): returns (u, I_candidate, D).

    ``u = K_p e + I + D`` with the backward-Euler integral and the filtered
    derivative described in the module notes. The caller saturates ``u``
    and decides (anti-windup) whether to keep ``I_candidate``.

    Parameters
    ----------
    e
        Error at this sample.
    e_prev
        Error at the previous sample.
    i_prev
        Integral state at the previous sample.
    d_prev
        Filtered derivative at the previous sample.
    kp
        Proportional gain K_p.
    ki
        Integral gain K_i (1/s).
    kd
        Derivative gain K_d (s).
    tf
        Derivative filter time constant T_f (s).
    ts
        Sample time T_s (s).
    """
    i_new = i_prev + ki * ts * e
    d_new = (tf * d_prev + kd * (e - e_prev)) / (tf + ts)
    return kp * e + i_new + d_new, i_new, d_new


def _wrap(a: Any) -> Any:
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


def state_size(window: int, extras: tuple[bool, bool, bool] = (False, False, False)) -> int:
    """Length of the state ``x`` of :func:`period_function` for a median window.

    Parameters
    ----------
    window
        Median-filter window in raw samples.
    extras
        Flags of the Sec. 6 options (:data:`EXTRAS`).
    """
    extra = sum(_EXTRA_STATES[name] for name, on in zip(EXTRAS, extras, strict=True) if on)
    return 16 + 3 * (window - 1) + extra


def _sensor_pose(pose: list, p: Any) -> list:
    """World pose of the sensor point (the origin of LCS_R) at body offset (p[28], p[29])."""
    ax, ay, psi = p[28], p[29], pose[2]
    return [
        pose[0] + ax * ca.sin(psi) + ay * ca.cos(psi),
        pose[1] - ax * ca.cos(psi) + ay * ca.sin(psi),
        psi,
    ]


def _sample(pose: list, user: Any, noise: Any, d_last: Any, p: Any, flags: tuple) -> tuple:
    """One raw string-pot sample: (d used, theta_U, theta_R, valid flag)."""
    quantize, mount = flags
    xc, yc, gc = sx_robot_in_user_frame(user, _sensor_pose(pose, p) if mount else pose)
    d, tu, tr = sx_string_pot(xc, yc, gc)
    d = d + noise[0]
    tu = tu + noise[1]
    tr = tr + noise[2]
    if quantize:
        res = p[26]
        tu = ca.floor(tu / res + 0.5) * res
        tr = ca.floor(tr / res + 0.5) * res
    valid = ca.logic_and(d >= p[21], d <= p[22])
    return ca.if_else(valid, d, d_last), tu, tr, valid


def _filtered(windows: list) -> list:
    """Median of the distance window; angles filtered relative to the newest sample."""
    filt = [_median(windows[0])]
    for c in (1, 2):
        newest = windows[c][-1]
        filt.append(newest + _median([_wrap(a - newest) for a in windows[c]]))
    return filt


def _saturated(raw_u: list, p: Any, limit_mode: str) -> tuple[list, list]:
    """The command after the speed limits, and which axes saturated."""
    vmax, wmax = p[14], p[16]
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
    return [ux, uy, uw], sat


def _wheel_limited(cmd: list, p: Any) -> list:
    """Eq. (10): body velocity -> wheel speeds; scale down uniformly to the wheel limit."""
    ux, uy, uw = cmd
    wheel_r, ll, wheel_max = p[23], p[24], p[25]
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
    return [sc_w * c for c in cmd]


def _target(filt: list, state: dict[str, Any], p: Any, extras: tuple) -> tuple[list, Any]:
    """The target (X_T, Y_T), adapted to the user's approach speed if asked (Sec. 6)."""
    if not extras[1]:
        return [p[18], p[19]], 0.0
    d_prev, va_prev = state["adapt"]
    vel = state["vel"]
    v_s = sensor_point_velocity(vel[:2], vel[2], (p[28], p[29])) if extras[0] else vel[:2]
    v_a = approach_speed((filt[0] - d_prev) / p[27], filt[2], v_s)
    va_f = filter_step(va_prev, v_a, ca.exp(-p[27] / p[33]))
    state["adapt"] = [filt[0], va_f]
    tx, ty = adapted_target((p[18], p[19]), va_f, gain=p[31], max_change=p[32])
    change = ca.sqrt(tx**2 + ty**2) - ca.sqrt(p[18] ** 2 + p[19] ** 2)
    return [tx, ty], change


def _control(windows: list, state: dict[str, Any], p: Any, modes: tuple) -> tuple:
    """The control instant: filter, eq. (8) error, three PIDs, saturation, anti-windup.

    With the Sec. 6 options: the adapted target, the motion filter on the
    error and the sensor-offset compensation of the command (before saturation).
    """
    limit_mode, wheel_level, extras = modes
    filt = _filtered(windows)
    target, change = _target(filt, state, p, extras)
    err = list(sx_robot_frame_error(target[0], target[1], p[20], *filt))
    seen = err
    if extras[2]:
        b = ca.exp(-p[27] / p[34])
        seen = [filter_step(state["mfilt"][i], err[i], b) for i in range(3)]
        state["mfilt"] = seen
    raw_u, cand, dnew = [], [], []
    for i in range(3):
        g = p[4 * i : 4 * i + 4]
        ui, ii, di = sx_pid_axis(
            seen[i],
            state["e_prev"][i],
            state["integ"][i],
            state["deriv"][i],
            g[0],
            g[1],
            g[2],
            g[3],
            p[27],
        )
        raw_u.append(ui)
        cand.append(ii)
        dnew.append(di)
    wanted = raw_u
    if extras[0]:
        vc = centre_velocity(raw_u[:2], raw_u[2], (p[28], p[29]))
        wanted = [raw_u[i] + p[30] * (vc[i] - raw_u[i]) for i in range(2)] + [raw_u[2]]
    cmd, sat = _saturated(wanted, p, limit_mode)
    state["integ"] = [
        ca.if_else(ca.logic_and(sat[i], seen[i] * raw_u[i] > 0), state["integ"][i], cand[i])
        for i in range(3)
    ]
    state["deriv"], state["e_prev"] = dnew, seen
    if wheel_level:
        cmd = _wheel_limited(cmd, p)
    return cmd, err, filt, change


def _platform_step(pose: list, vel: list, cmd: list, p: Any, h: Any, limit_mode: str) -> tuple:
    """Exact first-order lag per axis over ``h``, the acceleration limit, then the pose."""
    tau, tau_yaw, amax, alpmax = p[12], p[13], p[15], p[17]
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
    return [pose[0] + h * vxw, pose[1] + h * vyw, pose[2] + h * avg[2]], new_vel


def _extra_state(x: Any, start: int, extras: tuple) -> dict[str, list]:
    """The Sec. 6 options' state entries from ``x[start:]`` (see :func:`period_function`)."""
    out: dict[str, list] = {}
    k = start
    if extras[1]:
        out["adapt"] = [x[k], x[k + 1]]
        k += 2
    if extras[2]:
        out["mfilt"] = [x[k], x[k + 1], x[k + 2]]
    return out


@lru_cache(maxsize=32)
def period_function(
    substeps: int,
    window: int,
    limit_mode: str,
    wheel_level: bool,
    quantize: bool = False,
    extras: tuple[bool, bool, bool] = (False, False, False),
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
    extras
        Flags of the Sec. 6 options (:data:`EXTRAS`): sensor mount offset,
        target-distance adaptation, motion filter
        (:mod:`designlab.following.accompanying.extras`).

    Notes
    -----
    State ``x`` (:func:`state_size`): robot world pose (3, the rotation
    centre), body velocity (3), PID integrators (3), derivative states (3),
    previous errors (3), last valid distance (1), the median buffers of d,
    theta_U, theta_R, then the adaptation's previous distance and approach
    speed (2) and the motion filter's errors (3) when on. Raw samples between
    control instants feed only the median filter; with ``window == 1`` only
    the sample at the control instant is taken (the others would be discarded
    by the down-sampling), and only it is checked against the range. Input
    ``user`` (3 substeps): user world pose at each raw instant; ``noise``
    (3 substeps): additive noise on (d, theta_U, theta_R); ``p`` (35): gains
    (K_p, K_i, K_d, T_f) x 3, tau, tau_yaw, v_max, a_max, omega_max,
    alpha_max, target (X_T, Y_T, gamma_T), range (min, max), wheel radius,
    L1 + L2, wheel-speed limit, angle resolution, T_s, sensor offset (a_x,
    a_y), compensate (0/1), k_a, Delta_max, T_a, T_m. Output ``y`` (11):
    measured errors (3), saturated command (3), filtered readings (3), number
    of flagged raw distance samples, change of the target distance.
    """
    x = ca.SX.sym("x", state_size(window, extras))
    user = ca.SX.sym("user", 3 * substeps)
    noise = ca.SX.sym("noise", 3 * substeps)
    p = ca.SX.sym("p", N_PARAMETERS)
    h = p[27] / substeps
    pose, vel = [x[0], x[1], x[2]], [x[3], x[4], x[5]]
    state: dict[str, Any] = {"integ": [x[6], x[7], x[8]], "deriv": [x[9], x[10], x[11]]}
    state["e_prev"] = [x[12], x[13], x[14]]
    d_last = x[15]
    w1 = window - 1
    bufs = [[x[16 + c * w1 + k] for k in range(w1)] for c in range(3)]
    state.update(_extra_state(x, 16 + 3 * w1, extras))
    flags: Any = 0
    for j in range(substeps):
        windows: list = [[], [], []]
        if window > 1 or j == 0:
            d_used, tu, tr, valid = _sample(
                pose,
                user[3 * j : 3 * j + 3],
                noise[3 * j : 3 * j + 3],
                d_last,
                p,
                (quantize, extras[0]),
            )
            flags = flags + (1 - valid)
            d_last = d_used
            windows = [bufs[0] + [d_used], bufs[1] + [tu], bufs[2] + [tr]]
        if j == 0:
            state["vel"] = vel
            cmd, y_err, y_read, change = _control(
                windows, state, p, (limit_mode, wheel_level, extras)
            )
        if window > 1:
            bufs = [w[1:] for w in windows]
        pose, vel = _platform_step(pose, vel, cmd, p, h, limit_mode)
    x_next = ca.vertcat(
        *pose,
        *vel,
        *state["integ"],
        *state["deriv"],
        *state["e_prev"],
        d_last,
        *[b for buf in bufs for b in buf],
        *state.get("adapt", []),
        *state.get("mfilt", []),
    )
    y = ca.vertcat(*y_err, *cmd, *y_read, flags, change)
    return ca.Function("accompany_period", [x, user, noise, p], [x_next, y])
