"""Robot motion over one navigation period, in CasADi (Zeng 2011, Sec. 5.2, 7.2, App. D/E).

The virtual force is computed every T_s and held; the robot is integrated with a
fine dynamics step inside the hold (``docs/navigation.md``, "Timing"). One
``casadi.Function`` integrates a whole hold interval, so a simulation makes one
call per navigation period.

* Holonomic robot: a = F/m_mr norm-clipped to a_mr, velocity norm-clipped to
  V_mr (semi-implicit Euler); in a critical region it brakes at a_mr to a stop.
* Nonholonomic robot: a virtual holonomic reference is re-initialised to the
  measured robot state at each sample and driven by the held force; a
  differential-drive unicycle tracks it with the Klancar-Skrjanc law (7.2.2) with
  robot-frame errors and gains xi_nh, k_nh (7.2.3); each wheel's rim speed limited to V
  (``NonholonomicRobot.wheel_speed_limit``; the commanded v and omega are scaled together),
  linear and angular accelerations to a and omega_bar.
* Energy: wheel feed-forward voltages (D.3.2 / E.3.2) with i = 1 A/V * u, so the
  output ``power`` is sum(i^2) (copper loss per ohm; R_a cancels in H_E).

Examples
--------
>>> import numpy as np
>>> from designlab.navigation import HolonomicRobot
>>> hold = build_hold(HolonomicRobot(), n_sub=60, dt=1e-3)
>>> out = hold(x0=[0, 0, 0, 0], F=[100.0, 0.0], brake=0)
>>> X = np.array(out["X"])
>>> float(round(X[2, -1], 3)), float(round(X[0, -1], 4))  # 10 m/s^2 for 60 ms
(0.6, 0.0183)
"""

from __future__ import annotations

import math
from functools import lru_cache

import casadi as ca

from designlab.errors import InvalidParameterError, check_positive
from designlab.navigation.parameters import HolonomicRobot, NonholonomicRobot

__all__ = [
    "HOLONOMIC_FEEDFORWARD",
    "NONHOLONOMIC_FEEDFORWARD",
    "attraction_loop_radius",
    "build_hold",
    "state_size",
]

#: (J/K, B/K, tau/K) in V s^2, V s, V of the three omni wheels, Table D.2 / (D.3.2).
HOLONOMIC_FEEDFORWARD = ((0.0073, 0.0019, 0.19), (0.0074, 0.0020, 0.22), (0.0065, 0.0024, 0.18))
#: (J/K, B/K, tau/K) of the two differential-drive wheels, Table E.2 / (E.3.2).
NONHOLONOMIC_FEEDFORWARD = ((0.0079, 0.0032, 0.18), (0.0057, 0.0030, 0.28))


def state_size(robot: HolonomicRobot | NonholonomicRobot) -> int:
    """4 (x, y, v_x, v_y) for a holonomic robot, 5 (x, y, phi, v, omega) for a nonholonomic one.

    Parameters
    ----------
    robot
        A holonomic or nonholonomic robot.
    """
    return 4 if isinstance(robot, HolonomicRobot) else 5


def attraction_loop_radius(
    k1: float, b: float, mass: float, period: float = 0.06, dt: float = 1e-3
) -> float:
    """Spectral radius of the sampled free-space loop: the PD attraction held for a period.

    In C1 the force F = K1 E - K2 V (K2 = b K1) is held for ``period`` while the point mass
    is integrated with :func:`build_hold`'s semi-implicit Euler step ``dt`` (``docs/navigation.md``,
    "Timing"). Per axis, away from the limits, (e, v) -> A (e, v) once per period with
    alpha = K1/m, beta = K2/m, T = period, c = T (T + dt)/2 and
    A = [[1 - alpha c, beta c - T], [alpha T, 1 - beta T]]. By Jury's test the loop is stable
    (radius < 1) iff b > (T - dt)/2 and K2 T/m + K1 T dt/(2 m) < 2; beyond that the robot
    chatters at its acceleration limit near the goal, which the continuous-time stability
    proof (Zeng 2011, Sec. 5.5) does not see.

    Parameters
    ----------
    k1, b
        Attraction gain K1 (N/m) and gain ratio b (s).
    mass
        Robot mass m_mr (kg).
    period
        Force update period (s): T_s, or ``dt`` when the force is recomputed every step.
    dt
        Integration step (s).

    Returns
    -------
    float
        The largest eigenvalue modulus of A (>= 1: the sampled loop is unstable).

    Examples
    --------
    >>> round(attraction_loop_radius(4.3, 0.68, 4.4), 4)  # the thesis's optimum
    0.9807
    >>> attraction_loop_radius(143, 1.10, 4.4) > 1  # K2 T_s/m = 2.145
    True
    """
    alpha, beta = k1 / mass, b * k1 / mass
    T, c = period, period * (period + dt) / 2.0
    tr = 2.0 - alpha * c - beta * T
    det = 1.0 - beta * T - alpha * c + alpha * T * T
    disc = tr * tr / 4.0 - det
    if disc >= 0:
        r = math.sqrt(disc)
        return max(abs(tr / 2.0 + r), abs(tr / 2.0 - r))
    return math.sqrt(det)


def _clip_norm(v: ca.SX, limit: float) -> ca.SX:
    n = ca.sqrt(ca.sumsqr(v) + 1e-30)
    return v * ca.fmin(1.0, limit / n)


def _brake(v: ca.SX, amax: float, dt: float) -> ca.SX:
    n = ca.sqrt(ca.sumsqr(v) + 1e-30)
    return -v / n * ca.fmin(amax, n / dt)


def _ff_power(ff: tuple[tuple[float, float, float], ...], rate: list, acc: list) -> ca.SX:
    pw = ca.SX(0)
    for (jk, bk, tk), w, wd in zip(ff, rate, acc, strict=True):
        u = jk * wd + bk * w + tk * ca.sign(w)
        pw = pw + u * u
    return pw


@lru_cache(maxsize=32)
def build_hold(
    robot: HolonomicRobot | NonholonomicRobot, n_sub: int = 60, dt: float = 1e-3
) -> ca.Function:
    """Integrate one hold interval of ``n_sub`` dynamics steps of ``dt`` seconds.

    Parameters
    ----------
    robot
        The robot (its limits, mass, wheels and tracking gains are baked in).
    n_sub
        Dynamics steps per navigation period (60 for T_s = 0.06 s at 1 ms).
    dt
        Dynamics step in s.

    Returns
    -------
    casadi.Function
        Inputs ``x0`` (state, :func:`state_size`), ``F`` (held virtual force, N),
        ``brake`` (1: critical-region braking). Outputs ``X`` (state after each
        step, ``state_size x n_sub``) and ``power`` (sum of squared wheel
        feed-forward currents after each step, A^2, ``1 x n_sub``).
    """
    if not isinstance(n_sub, int) or n_sub < 1:
        raise InvalidParameterError("n_sub", n_sub, "must be an integer >= 1")
    dt = check_positive("dt", dt, "s")
    nx = state_size(robot)
    x0 = ca.SX.sym("x0", nx)
    F = ca.SX.sym("F", 2)
    brake = ca.SX.sym("brake")
    a_cmd = _clip_norm(F / robot.mass, robot.max_accel)
    if isinstance(robot, HolonomicRobot):
        cols, pows = _holonomic_steps(robot, x0, a_cmd, brake, n_sub, dt)
    else:
        cols, pows = _nonholonomic_steps(robot, x0, a_cmd, brake, n_sub, dt)
    return ca.Function(
        f"hold_{robot.kind}_{n_sub}",
        [x0, F, brake],
        [ca.horzcat(*cols), ca.horzcat(*pows)],
        ["x0", "F", "brake"],
        ["X", "power"],
    )


def _holonomic_steps(
    robot: HolonomicRobot, x0: ca.SX, a_cmd: ca.SX, brake: ca.SX, n_sub: int, dt: float
) -> tuple[list[ca.SX], list[ca.SX]]:
    """States and wheel powers of the omni-wheel robot over one hold (D.1.2, D.3.2)."""
    vmax, amax = robot.max_speed, robot.max_accel
    cols: list[ca.SX] = []
    pows: list[ca.SX] = []
    s3 = math.sqrt(3.0) / 2.0
    rw, lw = robot.wheel_radius, robot.wheel_offset
    rows = ((-s3, -0.5), (s3, -0.5), (0.0, 1.0))  # (D.1.2) with phi = 0, phi' = 0
    del lw  # no rotation is commanded: the l_w column multiplies phi' = 0
    p, v = x0[0:2], x0[2:4]
    # braking keeps the direction of the velocity: speed(t) = max(0, s0 - a t)
    s0 = ca.sqrt(ca.sumsqr(v) + 1e-30)
    v_hat = v / s0
    # wheel speeds w_i = R_i . v (D.1.2); feed-forward u_i = J/K w_i' + B/K w_i + tau/K sgn(w_i)
    R = [(r[0] / rw, r[1] / rw) for r in rows]
    w_prev = [Ri[0] * v[0] + Ri[1] * v[1] for Ri in R]
    for j in range(n_sub):
        v_brake = v_hat * ca.fmax(0.0, s0 - amax * dt * (j + 1))
        v_new = ca.if_else(brake, v_brake, _clip_norm(v + a_cmd * dt, vmax))
        p = p + v_new * dt
        pw = ca.SX(0)
        w_now = []
        for Ri, w_old, (jk, bk, tk) in zip(R, w_prev, HOLONOMIC_FEEDFORWARD, strict=True):
            w = Ri[0] * v_new[0] + Ri[1] * v_new[1]
            u = (jk / dt + bk) * w - (jk / dt) * w_old + tk * ca.sign(w)
            pw = pw + u * u
            w_now.append(w)
        w_prev = w_now
        pows.append(pw)
        v = v_new
        cols.append(ca.vertcat(p, v))
    return cols, pows


def _nonholonomic_steps(
    robot: NonholonomicRobot, x0: ca.SX, a_cmd: ca.SX, brake: ca.SX, n_sub: int, dt: float
) -> tuple[list[ca.SX], list[ca.SX]]:
    """States and wheel powers of the differential drive tracking its reference (7.2, E.3.2)."""
    vmax, amax = robot.max_speed, robot.max_accel
    cols: list[ca.SX] = []
    pows: list[ca.SX] = []
    rb = robot
    p, phi, vs, om = x0[0:2], x0[2], x0[3], x0[4]
    # the reference holonomic robot starts from the measured state (Sec. 7.2)
    pr = p
    vr = vs * ca.vertcat(ca.cos(phi), ca.sin(phi))
    for _ in range(n_sub):
        ar = ca.if_else(brake, _brake(vr, amax, dt), a_cmd)
        vr_new = _clip_norm(vr + ar * dt, vmax)
        ar_eff = (vr_new - vr) / dt
        pr = pr + vr_new * dt
        vr = vr_new
        vd = ca.sqrt(ca.sumsqr(vr) + 1e-30)
        has_dir = vd > 1e-3
        phid = ca.if_else(has_dir, ca.atan2(vr[1], vr[0]), phi)
        omd = ca.if_else(has_dir, (vr[0] * ar_eff[1] - vr[1] * ar_eff[0]) / (vd * vd), 0)
        c, s = ca.cos(phi), ca.sin(phi)
        ex = c * (pr[0] - p[0]) + s * (pr[1] - p[1])
        ey = -s * (pr[0] - p[0]) + c * (pr[1] - p[1])
        ephi = ca.atan2(ca.sin(phid - phi), ca.cos(phid - phi))
        wn = ca.sqrt(omd * omd + rb.k * vd * vd)
        kx = 2 * rb.xi * wn
        v_cmd = vd * ca.cos(ephi) + kx * ex
        w_cmd = omd + rb.k * vd * ey + kx * ephi
        v_cmd = ca.fmin(ca.fmax(v_cmd, -vmax), vmax)
        if rb.wheel_speed_limit:  # each wheel's rim speed |v +- omega l/2| <= V (same curvature)
            rim = ca.fabs(v_cmd) + ca.fabs(w_cmd) * (0.5 * rb.track)
            scale = ca.fmin(1.0, vmax / ca.fmax(rim, 1e-12))
            v_cmd, w_cmd = v_cmd * scale, w_cmd * scale
        dv = ca.fmin(ca.fmax(v_cmd - vs, -amax * dt), amax * dt)
        dw = ca.fmin(ca.fmax(w_cmd - om, -rb.max_angular_accel * dt), rb.max_angular_accel * dt)
        vs_new, om_new = vs + dv, om + dw
        phi = phi + om_new * dt
        p = p + vs_new * ca.vertcat(ca.cos(phi), ca.sin(phi)) * dt
        half = 0.5 * rb.track
        rate = [
            (vs_new + half * om_new) / rb.wheel_radius,
            (vs_new - half * om_new) / rb.wheel_radius,
        ]
        wacc = [
            (dv / dt + half * dw / dt) / rb.wheel_radius,
            (dv / dt - half * dw / dt) / rb.wheel_radius,
        ]
        pows.append(_ff_power(NONHOLONOMIC_FEEDFORWARD, rate, wacc))
        vs, om = vs_new, om_new
        cols.append(ca.vertcat(p, phi, vs, om))
    return cols, pows
