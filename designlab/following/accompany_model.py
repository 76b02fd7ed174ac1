"""Mecanum platform and string-pot sensor of the accompanying robot (Wu et al. 2021).

The paper reports no robot dynamics (Wu et al. 2021, Sec. 2.2-2.3); this
module holds the project's simulation model (see ``docs/following.md``,
"Accompanying robot"):

* :class:`MecanumPlatform` -- a 3-DOF mecanum base commanded at body-velocity
  level (V_x lateral-right, V_y forward, omega_z), each axis a first-order lag,
  with speed and acceleration saturation (on the norm of (V_x, V_y) or per
  axis) and an optional wheel-speed limit through the mecanum inverse
  kinematics of eq. (10);
* :class:`StringPotSensor` -- the string-pot (d, theta_U, theta_R) of eqs.
  (7)-(8), sampled at the raw rate, median-filtered and down-sampled to the
  50 Hz control rate, with optional noise, encoder quantisation and the
  SHARP GP2Y0A02YK0F distance sensor's 0.20-1.50 m validity range.

The dynamics themselves are written once in CasADi in
:mod:`designlab.following.accompany_simulate`; this module holds the
validated parameters and the eq. (10) wheel mapping.

Examples
--------
>>> p = MecanumPlatform()
>>> p.time_constant, p.max_speed, p.limit_mode
(0.15, 1.0, 'norm')
>>> import numpy as np
>>> w = p.wheel_speeds([0.0, 0.5, 0.0])      # straight ahead: all wheels at V/R
>>> np.round(w, 3)
array([10., 10., 10., 10.])
>>> s = StringPotSensor()
>>> s.sample_rate, s.min_range, s.max_range
(50.0, 0.2, 1.5)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError, check_nonnegative, check_positive
from designlab.validation import ParamsMixin

__all__ = ["LIMIT_MODES", "MecanumPlatform", "StringPotSensor", "mecanum_matrix"]

#: How the linear speed and acceleration limits act: on the norm of (V_x, V_y)
#: (direction kept) or on each axis separately.
LIMIT_MODES = ("norm", "per_axis")


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
    >>> mecanum_matrix(0.05, 0.4) @ [0.1, 0.0, 0.0]      # pure lateral right
    array([ 2., -2., -2.,  2.])
    """
    r = check_positive("wheel_radius", wheel_radius, "m")
    ll = check_positive("half_length_sum", half_length_sum, "m")
    return (
        np.array(
            [
                [1.0, 1.0, -ll],
                [-1.0, 1.0, ll],
                [-1.0, 1.0, -ll],
                [1.0, 1.0, ll],
            ]
        )
        / r
    )


@dataclass(frozen=True)
class MecanumPlatform(ParamsMixin):
    """Mecanum base at body-velocity level: first-order lag and saturation per axis.

    Parameters
    ----------
    time_constant
        Lag time constant tau of the linear axes in s (> 0); default 0.15 s.
    yaw_time_constant
        Lag of the yaw axis in s (> 0); ``None`` uses ``time_constant``.
    max_speed
        Linear speed limit in m/s (> 0); default 1.0.
    max_acceleration
        Linear acceleration limit in m/s^2 (> 0); default 2.0.
    max_yaw_rate
        Yaw-rate limit in rad/s (> 0); default 3.
    max_yaw_acceleration
        Yaw acceleration limit in rad/s^2 (> 0); default 6.
    limit_mode
        ``"norm"`` (default): the linear limits act on the norm of (V_x, V_y),
        keeping the direction of the command; ``"per_axis"``: each of V_x and
        V_y is limited separately (a diagonal command can then reach
        sqrt(2) times ``max_speed``).
    wheel_radius, half_length_sum
        Mecanum wheel radius R and L1 + L2 in m, used by the wheel-level model.
    max_wheel_speed
        Wheel angular speed limit in rad/s. ``None`` (default): no wheel-level
        limit. Otherwise the commanded body velocity is mapped to wheel speeds
        by eq. (10) and scaled down uniformly so that no wheel exceeds the limit
        (direction of motion kept), before the lag.

    Examples
    --------
    >>> MecanumPlatform(time_constant=0.2).yaw_tau
    0.2
    >>> MecanumPlatform(time_constant=-1.0)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: MecanumPlatform.time_constant = -1.0 s ...
    """

    time_constant: float = 0.15
    yaw_time_constant: float | None = None
    max_speed: float = 1.0
    max_acceleration: float = 2.0
    max_yaw_rate: float = 3.0
    max_yaw_acceleration: float = 6.0
    limit_mode: str = "norm"
    wheel_radius: float = 0.05
    half_length_sum: float = 0.40
    max_wheel_speed: float | None = None

    def __post_init__(self) -> None:
        c = "MecanumPlatform."
        for name, unit in (
            ("time_constant", "s"),
            ("max_speed", "m/s"),
            ("max_acceleration", "m/s^2"),
            ("max_yaw_rate", "rad/s"),
            ("max_yaw_acceleration", "rad/s^2"),
            ("wheel_radius", "m"),
            ("half_length_sum", "m"),
        ):
            object.__setattr__(self, name, check_positive(c + name, getattr(self, name), unit))
        for name, unit in (("yaw_time_constant", "s"), ("max_wheel_speed", "rad/s")):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, check_positive(c + name, getattr(self, name), unit))
        if self.limit_mode not in LIMIT_MODES:
            raise InvalidParameterError(c + "limit_mode", self.limit_mode, f"one of {LIMIT_MODES}")

    @property
    def yaw_tau(self) -> float:
        """Time constant of the yaw axis in s."""
        return self.time_constant if self.yaw_time_constant is None else self.yaw_time_constant

    def wheel_speeds(self, body_velocity: ArrayLike) -> NDArray[np.float64]:
        """Wheel angular speeds (rad/s; FL, FR, RL, RR) for a body velocity (eq. 10).

        Parameters
        ----------
        body_velocity
            (V_x, V_y, omega_z) in m/s, m/s, rad/s; shape (3,) or (3, n).
        """
        return mecanum_matrix(self.wheel_radius, self.half_length_sum) @ np.asarray(
            body_velocity, dtype=float
        )

    def body_velocity(self, wheel_speeds: ArrayLike) -> NDArray[np.float64]:
        """Body velocity (V_x, V_y, omega_z) from four wheel speeds (least squares of eq. 10).

        Parameters
        ----------
        wheel_speeds
            FL, FR, RL, RR in rad/s; shape (4,) or (4, n).

        Examples
        --------
        >>> p = MecanumPlatform()
        >>> np.round(p.body_velocity(p.wheel_speeds([0.1, -0.2, 0.3])), 12)
        array([ 0.1, -0.2,  0.3])
        """
        m = mecanum_matrix(self.wheel_radius, self.half_length_sum)
        return np.linalg.pinv(m) @ np.asarray(wheel_speeds, dtype=float)


@dataclass(frozen=True)
class StringPotSensor(ParamsMixin):
    """String-pot sensor (d, theta_U, theta_R) of Wu et al. 2021, eqs. (7)-(8).

    Raw samples are taken at ``sample_rate * oversampling`` Hz, the last
    ``median_window`` raw samples are median-filtered, and the filtered value
    at each control instant is held for one control period (zero-order hold,
    down-sampling to ``sample_rate``; the paper: 2000 samples/s, median filter,
    50 samples/s, window not stated).

    With ``median_window = 1`` the samples between control instants would be
    discarded by the down-sampling, so only the sample at each control
    instant is simulated.

    A raw distance outside ``[min_range, max_range]`` (SHARP GP2Y0A02YK0F,
    0.20-1.50 m) is flagged and *not* used: the last valid distance is held in
    its place and the simulation result counts the flagged samples.

    Parameters
    ----------
    sample_rate
        Control/down-sampled rate in Hz (> 0); default 50.
    oversampling
        Raw samples per control period (integer >= 1); default 4 (200 Hz raw).
    median_window
        Raw samples in the median filter (odd integer >= 1; 1 = no filter).
    distance_noise
        Standard deviation of white noise on raw d in m (>= 0).
    angle_noise
        Standard deviation of white noise on raw theta_U and theta_R in rad (>= 0).
    angle_resolution
        Encoder quantisation step in rad (>= 0; 0 = none). The P3015 12-bit
        encoder: 2 pi / 4096.
    min_range, max_range
        Validity range of the distance sensor in m (0 <= min < max).

    Examples
    --------
    >>> StringPotSensor(median_window=5, distance_noise=0.005).raw_rate
    200.0
    >>> StringPotSensor(min_range=1.0, max_range=0.5)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: StringPotSensor.max_range = 0.5 m ...> min_range ...
    """

    sample_rate: float = 50.0
    oversampling: int = 4
    median_window: int = 1
    distance_noise: float = 0.0
    angle_noise: float = 0.0
    angle_resolution: float = 0.0
    min_range: float = 0.20
    max_range: float = 1.50

    def __post_init__(self) -> None:
        c = "StringPotSensor."
        object.__setattr__(
            self, "sample_rate", check_positive(c + "sample_rate", self.sample_rate, "Hz")
        )
        for name in ("oversampling", "median_window"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
                raise InvalidParameterError(c + name, v, "must be an integer >= 1")
            object.__setattr__(self, name, int(v))
        if self.median_window % 2 == 0 or self.median_window > 15:
            raise InvalidParameterError(
                c + "median_window", self.median_window, "must be odd and <= 15"
            )
        for name, unit in (
            ("distance_noise", "m"),
            ("angle_noise", "rad"),
            ("angle_resolution", "rad"),
            ("min_range", "m"),
        ):
            object.__setattr__(self, name, check_nonnegative(c + name, getattr(self, name), unit))
        mx = check_positive(c + "max_range", self.max_range, "m")
        if mx <= self.min_range:
            raise InvalidParameterError(
                c + "max_range", self.max_range, f"must be > min_range = {self.min_range} m", "m"
            )
        object.__setattr__(self, "max_range", mx)

    @property
    def period(self) -> float:
        """Control period in s."""
        return 1.0 / self.sample_rate

    @property
    def raw_rate(self) -> float:
        """Raw sampling rate in Hz."""
        return self.sample_rate * self.oversampling

    @property
    def noisy(self) -> bool:
        """True if any noise is switched on."""
        return self.distance_noise > 0.0 or self.angle_noise > 0.0
