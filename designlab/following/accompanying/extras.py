"""Wu et al. 2021, Sec. 5-6: the sensor offset, target-distance adaptation and motion filter.

The paper names three refinements without giving their equations; this
module states the project's models (``docs/accompanying.md``) and their
declared parameters. Each is an option of
:func:`designlab.following.accompanying.simulate`; without it the run is the
paper's eq. (7)-(9) loop unchanged.

* :class:`SensorMount`: the origin of LCS_R is the robot-side encoder housing,
  *not* the robot's centre (Sec. 2.1). The platform turns about its centre, so
  a sensor point at body offset ``a = (a_x, a_y)`` (X right, Y forward) moves
  at ``v_s = v_c + omega (-a_y, a_x)`` (:func:`sensor_point_velocity`). With
  ``compensate=True`` the PID output is taken as the wanted velocity of the
  sensor point and the centre is commanded ``v_c = v_s - omega (-a_y, a_x)``
  (:func:`centre_velocity`), so turning no longer drags the sensor point.
* :class:`TargetAdaptation`: Sec. 6 proposes lengthening the target distance
  while the user approaches the robot and shortening it while the user moves
  away. The robot estimates the user's approach speed from its own readings:
  ``v_a = u . v_s - d_dot`` (:func:`approach_speed`), with ``u`` the unit
  vector from the user to the sensor point in LCS_R (``(cos theta_R,
  -sin theta_R)``) and ``d_dot`` the backward difference of the filtered
  distance; ``v_a`` passes a first-order low-pass ``T_a`` and the target is
  moved along its own bearing by ``clip(k_a v_a, -Delta_max, Delta_max)``
  (:func:`adapted_target`).
* :class:`MotionFilter`: Sec. 6 prefers "a movement filter to smooth the
  motion" against pelvis sway: a first-order low-pass ``T_m`` on the eq. (8)
  error before the PIDs, ``e_f,k = b e_f,k-1 + (1 - b) e_k``,
  ``b = exp(-T_s / T_m)`` (:func:`filter_step`).

The functions work on numbers and on CasADi symbols alike (the simulation's
control period uses them).

Examples
--------
>>> import numpy as np
>>> v = sensor_point_velocity([0.0, 0.0], 1.0, (0.0, 0.2))   # turning, sensor 0.2 m ahead
>>> [float(x) for x in v]
[-0.2, 0.0]
>>> [float(x) for x in centre_velocity(v, 1.0, (0.0, 0.2))]
[0.0, 0.0]
>>> round(float(adapted_target((0.0, 0.5), 0.4, gain=0.5, max_change=0.3)[1]), 6)
0.7
>>> bool(np.isclose(MotionFilter(time_constant=0.2).pole(0.02), np.exp(-0.1), rtol=1e-15))
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import casadi as ca

from designlab.params import declared, param
from designlab.validation import ParamsMixin

__all__ = [
    "MotionFilter",
    "SensorMount",
    "TargetAdaptation",
    "adapted_target",
    "approach_speed",
    "centre_velocity",
    "filter_step",
    "sensor_point_velocity",
]


@declared
@dataclass(frozen=True)
class SensorMount(ParamsMixin):
    """Where the robot-side encoder (the origin of LCS_R) sits on the robot.

    ``offset_x`` (right) and ``offset_y`` (forward) are in the robot's body
    frame, from its centre of rotation. ``compensate`` converts the PID
    output, the wanted sensor-point velocity, to the centre velocity (see the
    module notes); without it the centre is commanded directly, as in a
    controller that ignores the offset.

    Examples
    --------
    >>> SensorMount(offset_y=0.25).offset
    (0.0, 0.25)
    >>> SensorMount(offset_y=float("nan"))
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: SensorMount.offset_y = nan m ...
    """

    offset_x: float = param(
        "a_x",
        "m",
        doc="lateral offset of the sensor from the rotation centre (right +)",
        ge=-5,
        le=5,
        typical=(-0.3, 0.3),
        default=0.0,
    )
    offset_y: float = param(
        "a_y",
        "m",
        doc="forward offset of the sensor from the rotation centre",
        ge=-5,
        le=5,
        typical=(-0.3, 0.3),
        default=0.0,
    )
    compensate: bool = param(
        kind="flag",
        doc="command the centre so that the sensor point moves as the PID asks",
        default=False,
    )

    @property
    def offset(self) -> tuple[float, float]:
        """(a_x, a_y) in m."""
        return (self.offset_x, self.offset_y)


class _LowPass:
    """A first-order low-pass of time constant ``time_constant`` (s), sampled."""

    time_constant: float

    def pole(self, period: float) -> float:
        """Pole ``exp(-T_s / time_constant)`` of the sampled low-pass for a control period.

        Parameters
        ----------
        period
            Control period T_s in s.
        """
        return math.exp(-period / self.time_constant)


@declared
@dataclass(frozen=True)
class TargetAdaptation(_LowPass, ParamsMixin):
    """Target-distance adaptation (Wu et al. 2021, Sec. 6).

    The target moves along its bearing by ``clip(gain * v_a, -max_change,
    max_change)``, ``v_a`` the user's estimated approach speed low-passed
    with ``time_constant`` (module notes).

    Examples
    --------
    >>> TargetAdaptation().gain
    0.3
    >>> TargetAdaptation(max_change=-0.1)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: TargetAdaptation.max_change = -0.1 m ...
    """

    gain: float = param(
        "k_a",
        "s",
        doc="target lengthening per m/s of approach speed",
        ge=0,
        le=10,
        typical=(0.1, 1.0),
        default=0.3,
    )
    max_change: float = param(
        "Delta_max",
        "m",
        doc="largest change of the target distance",
        ge=0,
        le=2,
        typical=(0.1, 0.5),
        default=0.3,
    )
    time_constant: float = param(
        "T_a",
        "s",
        doc="low-pass time constant of the approach-speed estimate",
        gt=0,
        le=10,
        typical=(0.1, 1.0),
        default=0.3,
    )


@declared
@dataclass(frozen=True)
class MotionFilter(_LowPass, ParamsMixin):
    """First-order low-pass on the eq. (8) error before the PIDs (Wu et al. 2021, Sec. 6).

    Examples
    --------
    >>> MotionFilter().time_constant
    0.2
    >>> MotionFilter(time_constant=0.0)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: MotionFilter.time_constant = 0.0 s ...
    """

    time_constant: float = param(
        "T_m",
        "s",
        doc="time constant of the low-pass on the error",
        gt=0,
        le=10,
        typical=(0.05, 0.5),
        default=0.2,
    )

    def gain_at(self, frequency: float, period: float) -> float:
        """Magnitude of the discrete filter ``(1 - b) / (1 - b z^-1)`` at a frequency.

        Parameters
        ----------
        frequency
            Frequency in Hz (e.g. the step frequency of the pelvis sway).
        period
            Control period T_s in s.

        Examples
        --------
        >>> round(MotionFilter(0.2).gain_at(0.0, 0.02), 12)
        1.0
        """
        b = self.pole(period)
        w = 2 * math.pi * frequency * period
        return (1 - b) / abs(complex(1 - b * math.cos(w), b * math.sin(w)))


def sensor_point_velocity(centre_velocity: Any, omega: Any, offset: Any) -> tuple[Any, Any]:
    """Body-frame velocity of the sensor point: ``v_c + omega (-a_y, a_x)``.

    Parameters
    ----------
    centre_velocity
        (V_x, V_y) of the rotation centre in the body frame, m/s.
    omega
        Yaw rate, rad/s (counter-clockwise +).
    offset
        (a_x, a_y) of the sensor from the centre in the body frame, m.
    """
    return (
        centre_velocity[0] - omega * offset[1],
        centre_velocity[1] + omega * offset[0],
    )


def centre_velocity(sensor_velocity: Any, omega: Any, offset: Any) -> tuple[Any, Any]:
    """Centre velocity that moves the sensor point at ``sensor_velocity`` (inverse of above).

    Parameters
    ----------
    sensor_velocity
        Wanted (V_x, V_y) of the sensor point in the body frame, m/s.
    omega
        Yaw rate, rad/s.
    offset
        (a_x, a_y) of the sensor from the centre in the body frame, m.
    """
    return (
        sensor_velocity[0] + omega * offset[1],
        sensor_velocity[1] - omega * offset[0],
    )


def approach_speed(d_dot: Any, theta_r: Any, sensor_velocity: Any) -> Any:
    """The user's speed towards the robot from on-board quantities: ``u . v_s - d_dot``.

    ``d = |p_s - p_U|`` gives ``d_dot = u . (v_s - v_U)``, so ``u . v_U = u . v_s - d_dot``
    with ``u = (cos theta_R, -sin theta_R)`` the direction from the user to the
    sensor point in LCS_R (eqs. 7-8: the robot sits at bearing theta_U in
    LCS_U and is turned by gamma_C = theta_U + theta_R).

    Parameters
    ----------
    d_dot
        Rate of change of the measured distance, m/s.
    theta_r
        Robot-side encoder reading theta_R, rad.
    sensor_velocity
        (V_x, V_y) of the sensor point in the body frame (odometry), m/s.
    """
    cos_r, sin_r = _cos(theta_r), _sin(theta_r)
    return cos_r * sensor_velocity[0] - sin_r * sensor_velocity[1] - d_dot


def adapted_target(target: Any, v_a: Any, *, gain: float | Any, max_change: float | Any) -> Any:
    """The target moved along its bearing by ``clip(gain * v_a, -max_change, max_change)``.

    The distance never drops below zero (the target then sits at the user's origin).

    Parameters
    ----------
    target
        (X_T, Y_T) in LCS_U, m (not both zero).
    v_a
        Approach speed of the user (towards the robot +), m/s.
    gain
        k_a in s.
    max_change
        Delta_max in m.
    """
    d_t = _sqrt(target[0] ** 2 + target[1] ** 2)
    change = _fmin(_fmax(gain * v_a, -max_change), max_change)
    scale = _fmax(d_t + change, 0.0) / d_t
    return (scale * target[0], scale * target[1])


def filter_step(previous: Any, value: Any, pole: Any) -> Any:
    """One step of the motion filter: ``b previous + (1 - b) value``.

    Parameters
    ----------
    previous
        Filtered value at the previous control instant.
    value
        New raw value.
    pole
        ``b = exp(-T_s / T_m)``.
    """
    return pole * previous + (1 - pole) * value


def _symbolic(x: Any) -> bool:
    return isinstance(x, (ca.SX, ca.MX, ca.DM))


def _cos(x: Any) -> Any:
    return ca.cos(x) if _symbolic(x) else math.cos(x)


def _sin(x: Any) -> Any:
    return ca.sin(x) if _symbolic(x) else math.sin(x)


def _sqrt(x: Any) -> Any:
    return ca.sqrt(x) if _symbolic(x) else math.sqrt(x)


def _fmin(a: Any, b: Any) -> Any:
    return ca.fmin(a, b) if _symbolic(a) or _symbolic(b) else min(a, b)


def _fmax(a: Any, b: Any) -> Any:
    return ca.fmax(a, b) if _symbolic(a) or _symbolic(b) else max(a, b)
