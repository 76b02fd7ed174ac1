"""Differential-drive follower with a tether sensor (Allan 2015, Sec. 2.2-2.3, App. C).

The robot is kinematic (Allan 2015 gives no masses, motor or friction data;
Sec. 2.4.1): two driven wheels of radius ``r`` on a track ``b``. Wheel speeds
map to body velocities by eq. (2.6)-(2.8), ``V = r(w_L + w_R)/2``,
``Omega = r(w_R - w_L)/b``, and the pose is integrated exactly over a control
period on the arc of constant curvature (App. C ``dead_reckon``).

The tether runs from a winch (optionally offset from the robot centre, at a
height below the leader's tether tip) to the leader. The sensor returns the
tether length ``l_m`` (3-D, as the V-REP sensor of App. C) and the angle
``theta_m`` between the tether and the robot heading, wrapped to (-pi, pi]
(eqs. 2.12-2.14). Gaussian noise on both and a control rate are parameters.

The physics is written once in CasADi symbols (:func:`kinematics_function`,
:func:`sensor_function`, :func:`tip_function`) and compiled to numpy/float
code for the closed-loop simulation (:func:`designlab.sx.pycode.compile_sx`).
The robot's parameters are :class:`designlab.following.tether.FollowerRobot`.

Examples
--------
>>> step = kinematics_step()
>>> x, y, g = step(0.0, 0.0, 0.0, 4.0, 4.0, 0.28, 0.125, 1.0)[:3]   # 0.5 m/s for 1 s
>>> round(x, 6), round(y, 6), g
(0.5, 0.0, 0.0)
"""

from __future__ import annotations

import math
from functools import cache
from typing import Any

import casadi as ca

from designlab.sx.pycode import compile_sx

__all__ = [
    "STEP_INPUTS",
    "kinematics_function",
    "kinematics_step",
    "sensor_function",
    "sensor_step",
    "step_compiled",
    "step_function",
    "tip_function",
    "tip_step",
    "wrap_angle",
]


def wrap_angle(a: Any) -> Any:
    """Wrap an angle (CasADi symbol or number) to (-pi, pi] as ``atan2(sin a, cos a)``.

    Parameters
    ----------
    a
        Angle in rad (number or CasADi symbol).
    """
    if isinstance(a, (ca.SX, ca.MX)):
        return ca.atan2(ca.sin(a), ca.cos(a))
    return math.atan2(math.sin(a), math.cos(a))


def _arc_step(x: ca.SX, y: ca.SX, g: ca.SX, v: ca.SX, om: ca.SX, dt: ca.SX) -> tuple[ca.SX, ...]:
    """Exact arc of constant (V, Omega) over dt, written without a branch on Omega.

    ``sin(G) - sin(G0) = 2 cos(G0 + h) sin(h)`` with h = Omega dt / 2, so the
    App. C formulas become a chord ``V dt sin(h)/h`` along ``G0 + h``;
    ``sin(h)/h`` is even and is evaluated at ``max(|h|, 1e-300)`` (exactly 1 at h = 0).
    """
    h = 0.5 * om * dt
    hs = ca.fmax(ca.fabs(h), 1e-300)
    chord = v * dt * (ca.sin(hs) / hs)
    return x + chord * ca.cos(g + h), y + chord * ca.sin(g + h), g + 2.0 * h, chord


@cache
def kinematics_function() -> ca.Function:
    """CasADi function of one control period of the differential drive.

    Inputs ``x, y, heading, omega_L, omega_R, b, r, dt``; outputs
    ``x, y, heading, ds`` (new pose and the chord travelled, App. C
    ``dead_reckon``; body velocities by eq. 2.6).
    """
    x, y, g, wl, wr, b, r, dt = (ca.SX.sym(n) for n in ("x", "y", "g", "wl", "wr", "b", "r", "dt"))
    v = 0.5 * r * (wl + wr)  # eq. 2.6
    om = r * (wr - wl) / b
    xn, yn, gn, chord = _arc_step(x, y, g, v, om, dt)
    return ca.Function(
        "follower_kinematics",
        [x, y, g, wl, wr, b, r, dt],
        [xn, yn, gn, ca.fabs(chord)],
        ["x", "y", "heading", "omega_L", "omega_R", "b", "r", "dt"],
        ["x_next", "y_next", "heading_next", "ds"],
    )


@cache
def sensor_function() -> ca.Function:
    """CasADi function of the tether sensor (Allan 2015 eqs. 2.12-2.14, App. C).

    Inputs ``x, y, heading, tip_x, tip_y, off_x, off_y, h``; outputs the
    measured length ``l_m`` (3-D, winch to tip) and angle ``theta_m`` (tether
    direction minus heading, wrapped).
    """
    x, y, g, tx, ty, ox, oy, hh = (
        ca.SX.sym(n) for n in ("x", "y", "g", "tx", "ty", "ox", "oy", "h")
    )
    wx = x + ox * ca.cos(g) - oy * ca.sin(g)
    wy = y + ox * ca.sin(g) + oy * ca.cos(g)
    dx, dy = tx - wx, ty - wy
    length = ca.sqrt(dx * dx + dy * dy + hh * hh)
    theta = wrap_angle(ca.atan2(dy, dx) - g)
    return ca.Function(
        "tether_sensor",
        [x, y, g, tx, ty, ox, oy, hh],
        [length, theta],
        ["x", "y", "heading", "tip_x", "tip_y", "off_x", "off_y", "h"],
        ["l_m", "theta_m"],
    )


@cache
def tip_function() -> ca.Function:
    """CasADi function of the robot's estimate of the tether tip (eq. 2.14, App. C).

    Inputs ``x, y, heading, l_m, theta_m, off_x, off_y``; outputs ``T_x, T_y``
    (the measured length taken as planar, as the thesis does).
    """
    x, y, g, lm, th, ox, oy = (ca.SX.sym(n) for n in ("x", "y", "g", "l", "th", "ox", "oy"))
    tx = x + ox * ca.cos(g) - oy * ca.sin(g) + lm * ca.cos(g + th)
    ty = y + ox * ca.sin(g) + oy * ca.cos(g) + lm * ca.sin(g + th)
    return ca.Function(
        "tether_tip",
        [x, y, g, lm, th, ox, oy],
        [tx, ty],
        ["x", "y", "heading", "l_m", "theta_m", "off_x", "off_y"],
        ["tip_x", "tip_y"],
    )


@cache
def kinematics_step(batch: bool = False) -> Any:
    """Compiled :func:`kinematics_function` (floats, or numpy arrays if ``batch``)."""
    return compile_sx(kinematics_function(), batch=batch)


@cache
def sensor_step(batch: bool = False) -> Any:
    """Compiled :func:`sensor_function` (floats, or numpy arrays if ``batch``)."""
    return compile_sx(sensor_function(), batch=batch)


@cache
def tip_step(batch: bool = False) -> Any:
    """Compiled :func:`tip_function` (floats, or numpy arrays if ``batch``)."""
    return compile_sx(tip_function(), batch=batch)


#: Inputs of :func:`step_function` before the law's own parameters.
STEP_INPUTS = (
    "x",
    "y",
    "heading",
    "tip_x",
    "tip_y",
    "target_x",
    "target_y",
    "omega_L_prev",
    "omega_R_prev",
    "length_noise",
    "angle_noise",
    "b",
    "r",
    "dt",
    "max_wheel_speed",
    "max_wheel_step",
    "off_x",
    "off_y",
    "h",
)


def _sensed_tether(
    syms: dict[str, ca.SX], steer_to_target: bool, offsets: bool, noisy: bool
) -> tuple[Any, Any]:
    """The measured tether length and angle (``None`` when the law does not need it)."""
    x, y, g = syms["x"], syms["y"], syms["heading"]
    if offsets:
        lm, th = sensor_function()(
            x, y, g, syms["tip_x"], syms["tip_y"], syms["off_x"], syms["off_y"], syms["h"]
        )
    else:
        dx, dy = syms["tip_x"] - x, syms["tip_y"] - y
        lm = ca.sqrt(dx * dx + dy * dy)
        th = wrap_angle(ca.atan2(dy, dx) - g) if not steer_to_target else None
    if noisy:
        lm = lm + syms["length_noise"]
        if th is None:
            th = sensor_function()(x, y, g, syms["tip_x"], syms["tip_y"], 0.0, 0.0, 0.0)[1]
        th = th + syms["angle_noise"]
    return lm, th


def _limited_wheels(syms: dict[str, ca.SX], v: Any, om: Any) -> tuple[Any, ...]:
    """Wheel speeds under the speed and acceleration limits, and the ``V, Omega`` they give.

    Speed limit: both wheels scaled by the same factor, which keeps the demanded
    curvature Omega/V (clipping each wheel alone would drop the turn when V
    saturates, and a robot far behind its leader would then drive straight on and
    lose it); then each wheel changes by at most ``max_wheel_step`` per period.
    """
    b, r = syms["b"], syms["r"]
    wlp, wrp = syms["omega_L_prev"], syms["omega_R_prev"]
    wmax, astep = syms["max_wheel_speed"], syms["max_wheel_step"]
    wl = (v - 0.5 * b * om) / r
    wr = (v + 0.5 * b * om) / r
    scale = 1.0 / ca.fmax(1.0, ca.fmax(ca.fabs(wl), ca.fabs(wr)) / wmax)  # wmax may be inf
    wl, wr = wl * scale, wr * scale
    wl = ca.fmin(ca.fmax(ca.fmin(ca.fmax(wl, wlp - astep), wlp + astep), -wmax), wmax)
    wr = ca.fmin(ca.fmax(ca.fmin(ca.fmax(wr, wrp - astep), wrp + astep), -wmax), wmax)
    return wl, wr, 0.5 * r * (wl + wr), r * (wr - wl) / b  # eq. 2.6


@cache
def step_function(
    law: ca.Function,
    steer_to_target: bool,
    limits: bool = False,
    offsets: bool = False,
    noisy: bool = False,
) -> ca.Function:
    """CasADi function of one closed-loop control period: sense, law, wheels, motion.

    Inputs: :data:`STEP_INPUTS` followed by the law's own parameters
    (``l_d`` and the gains). Outputs: ``x, y, heading`` after the period, the
    applied ``V, Omega`` and wheel speeds ``omega_L, omega_R``.

    The tether sensor (:func:`sensor_function`) gives ``l_m, theta_m``, plus the
    noise inputs; the steering angle is ``theta_m`` (Pseudo-Joystick, eq. 2.3)
    or, with ``steer_to_target``, ``phi = wrap(atan2(target - P) - Gamma)``
    (eqs. 2.16, 2.19); the law gives ``(V, Omega)``; with ``limits`` the
    wheel speeds ``(V -+ b Omega/2)/r`` (eq. 2.4) are scaled by one common
    factor so that neither exceeds ``max_wheel_speed`` (the demanded
    curvature is kept), then change by at most ``max_wheel_step`` per period;
    the pose moves on the exact arc (App. C ``dead_reckon``).

    The flags leave out operations whose inputs are zero or infinite (no
    limits, no winch offset or tip height, no noise), so that the compiled
    step does only the work the model needs; the inputs are then ignored.

    Parameters
    ----------
    law
        The law's CasADi function ``(l_m, phi, b, *params) -> (V, Omega)``.
    steer_to_target
        Steer to the target point (FTL, FTL-CD) rather than along the tether.
    limits, offsets, noisy
        Include the wheel limits, the winch offset and tip height, the noise.
    """
    syms = {n: ca.SX.sym(n) for n in STEP_INPUTS}
    x, y, g = syms["x"], syms["y"], syms["heading"]
    extra = [ca.SX.sym(law.name_in(i)) for i in range(3, law.n_in())]
    lm, th = _sensed_tether(syms, steer_to_target, offsets, noisy)
    if steer_to_target:
        phi = wrap_angle(ca.atan2(syms["target_y"] - y, syms["target_x"] - x) - g)
    else:
        phi = th
    v, om = law(lm, phi, syms["b"], *extra)
    if limits:
        wl, wr, v, om = _limited_wheels(syms, v, om)
    else:
        wl = wr = ca.SX(0.0)
    xn, yn, gn, _ = _arc_step(x, y, g, v, om, syms["dt"])
    return ca.Function(
        f"step_{law.name()}",
        [*syms.values(), *extra],
        [xn, yn, gn, v, om, wl, wr],
        [*STEP_INPUTS, *(e.name() for e in extra)],
        ["x_next", "y_next", "heading_next", "V", "Omega", "omega_L", "omega_R"],
    )


@cache
def step_compiled(
    law: ca.Function,
    steer_to_target: bool,
    limits: bool = False,
    offsets: bool = False,
    noisy: bool = False,
    batch: bool = False,
) -> Any:
    """Compiled :func:`step_function` (floats, or numpy arrays if ``batch``)."""
    return compile_sx(step_function(law, steer_to_target, limits, offsets, noisy), batch=batch)
