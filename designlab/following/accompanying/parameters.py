"""Parameters of the accompanying robot (Wu et al. 2021), declared once.

The paper reports no robot dynamics (Wu et al. 2021, Sec. 2.2-2.3); these are
the project's simulation model (``docs/following.md``, "Accompanying robot"):

* :class:`MecanumPlatform`: a 3-DOF mecanum base commanded at body-velocity
  level (V_x lateral-right, V_y forward, omega_z), each axis a first-order lag,
  with speed and acceleration saturation (on the norm of (V_x, V_y) or per
  axis) and an optional wheel-speed limit through the mecanum inverse
  kinematics of eq. (10);
* :class:`StringPotSensor`: the string-pot (d, theta_U, theta_R) of eqs.
  (7)-(8), sampled at the raw rate, median-filtered and down-sampled to the
  50 Hz control rate, with optional noise, encoder quantisation and the
  SHARP GP2Y0A02YK0F distance sensor's 0.20-1.50 m validity range;
* :class:`UserFramePID`: the gains of the three PIDs of eq. (9);
* the arguments of the walking tasks, the simulation, the loop analysis and
  the tuners that are not fields of a model (:data:`WALKING_SPEED`,
  :data:`SETTLE_BAND`, :data:`N_FREQUENCIES`, :data:`MS_MAX`, ...), each a
  :class:`~designlab.params.Param` checked with ``.check``.

The caps in the declarations keep a run within memory and time (stated in
``docs/following.md``, "Limits").

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
>>> pid = UserFramePID()
>>> pid.kp, pid.ki, pid.kd, pid.gains("heading")
(2.0, 0.5, 0.1, (2.0, 0.5, 0.1, 0.05))
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.following.accompanying.model import mecanum_matrix
from designlab.params import ARG, Param, declared, param
from designlab.validation import ParamsMixin

__all__ = [
    "AXES",
    "DISTANCE",
    "HOLD_AFTER",
    "INITIAL_OFFSET",
    "KD_MAX",
    "LIMIT_MODES",
    "MAX_EVALUATIONS",
    "MAX_ITERATIONS",
    "MAX_NOISE_GAIN",
    "MAX_WALKING_SPEED",
    "MS_MAX",
    "MT_MAX",
    "N_FREQUENCIES",
    "PAUSE",
    "PIVOT_OFFSET",
    "RADIUS",
    "RAMP_TIME",
    "RECTANGLE_SIDE",
    "SEED",
    "SETTLE_BAND",
    "SETTLE_TIME",
    "SPEED_THRESHOLD",
    "STAND_BEFORE",
    "START_HEADING",
    "STEP_FREQUENCY",
    "SWAY_LATERAL",
    "SWAY_YAW",
    "TOLERANCE",
    "TURN_ANGLE",
    "WALKING_SPEED",
    "YAW_RATE",
    "YAW_RATE_THRESHOLD",
    "MecanumPlatform",
    "StringPotSensor",
    "UserFramePID",
    "loop_parts",
]

#: How the linear speed and acceleration limits act: on the norm of (V_x, V_y)
#: (direction kept) or on each axis separately.
LIMIT_MODES = ("norm", "per_axis")

#: The controlled axes: lateral (X_R), forward (Y_R) and heading.
AXES = ("lateral", "forward", "heading")


@declared
@dataclass(frozen=True)
class MecanumPlatform(ParamsMixin):
    """Mecanum base at body-velocity level: first-order lag and saturation per axis.

    ``limit_mode="norm"`` (default) limits the norm of (V_x, V_y), keeping the
    direction of the command; ``"per_axis"`` limits each of V_x and V_y (a
    diagonal command can then reach sqrt(2) times ``max_speed``). With
    ``max_wheel_speed`` the commanded body velocity is mapped to wheel speeds by
    eq. (10) and scaled down uniformly so that no wheel exceeds the limit
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

    time_constant: float = param(
        "tau",
        "s",
        doc="lag time constant of the linear axes",
        gt=0,
        le=100,
        typical=(0.05, 0.5),
        default=0.15,
    )
    yaw_time_constant: float | None = param(
        "tau_yaw",
        "s",
        doc="lag time constant of the yaw axis",
        gt=0,
        le=100,
        optional=True,
        none="time_constant",
        default=None,
    )
    max_speed: float = param(
        "v_max", "m/s", doc="linear speed limit", gt=0, le=20, typical=(0.5, 2.0), default=1.0
    )
    max_acceleration: float = param(
        "a_max", "m/s^2", doc="linear acceleration limit", gt=0, le=100, default=2.0
    )
    max_yaw_rate: float = param(
        "omega_max", "rad/s", doc="yaw-rate limit", gt=0, le=100, default=3.0
    )
    max_yaw_acceleration: float = param(
        "alpha_max", "rad/s^2", doc="yaw acceleration limit", gt=0, le=1000, default=6.0
    )
    limit_mode: str = param(
        kind="choice", choices=LIMIT_MODES, doc="how the linear limits act", default="norm"
    )
    wheel_radius: float = param(
        "R", "m", doc="mecanum wheel radius (wheel-level model)", gt=0, le=1, default=0.05
    )
    half_length_sum: float = param(
        "L_12",
        "m",
        doc="L1 + L2, half wheelbase plus half track (wheel-level model)",
        gt=0,
        le=10,
        default=0.40,
    )
    max_wheel_speed: float | None = param(
        "w_max",
        "rad/s",
        doc="wheel angular speed limit",
        gt=0,
        le=1e4,
        optional=True,
        none="no wheel-level limit",
        default=None,
    )

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


@declared
@dataclass(frozen=True)
class StringPotSensor(ParamsMixin):
    """String-pot sensor (d, theta_U, theta_R) of Wu et al. 2021, eqs. (7)-(8).

    Raw samples are taken at ``sample_rate * oversampling`` Hz, the last
    ``median_window`` raw samples are median-filtered, and the filtered value
    at each control instant is held for one control period (zero-order hold,
    down-sampling to ``sample_rate``; the paper: 2000 samples/s, median filter,
    50 samples/s, window not stated). With ``median_window = 1`` the samples
    between control instants would be discarded by the down-sampling, so only
    the sample at each control instant is simulated.

    A raw distance outside ``[min_range, max_range]`` (SHARP GP2Y0A02YK0F,
    0.20-1.50 m) is flagged and *not* used: the last valid distance is held in
    its place and the simulation result counts the flagged samples. The
    window must be odd and ``min_range < max_range``.

    Examples
    --------
    >>> StringPotSensor(median_window=5, distance_noise=0.005).raw_rate
    200.0
    >>> StringPotSensor(min_range=1.0, max_range=0.5)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: StringPotSensor.max_range = 0.5 m ...> min_range ...
    """

    sample_rate: float = param(
        "f_s",
        "Hz",
        doc="control (down-sampled) rate",
        gt=0,
        le=1000,
        typical=(20, 100),
        default=50.0,
    )
    oversampling: int = param(
        None, "", doc="raw samples per control period", kind="integer", ge=1, le=40, default=4
    )
    median_window: int = param(
        None,
        "",
        doc="raw samples in the median filter (odd; 1: no filter)",
        kind="integer",
        ge=1,
        le=15,
        default=1,
    )
    distance_noise: float = param(
        "sigma_d", "m", doc="standard deviation of white noise on raw d", ge=0, le=1, default=0.0
    )
    angle_noise: float = param(
        "sigma_theta",
        "rad",
        doc="standard deviation of white noise on raw theta_U, theta_R",
        ge=0,
        le=math.pi,
        default=0.0,
    )
    angle_resolution: float = param(
        "q",
        "rad",
        doc="encoder quantisation step (0: none; the 12-bit P3015: 2 pi/4096)",
        ge=0,
        le=math.pi / 2,
        default=0.0,
    )
    min_range: float = param(
        "d_min",
        "m",
        doc="lower end of the distance sensor's validity range",
        ge=0,
        le=10,
        default=0.20,
    )
    max_range: float = param(
        "d_max",
        "m",
        doc="upper end of the distance sensor's validity range",
        gt=0,
        le=10,
        default=1.50,
    )

    def __post_init__(self) -> None:
        c = "StringPotSensor."
        if self.median_window % 2 == 0:
            raise InvalidParameterError(c + "median_window", self.median_window, "must be odd")
        if self.max_range <= self.min_range:
            raise InvalidParameterError(
                c + "max_range", self.max_range, f"must be > min_range = {self.min_range} m", "m"
            )

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


def _pid_gain(symbol: str, unit: str, doc: str, le: float, default: float | None) -> object:
    if default is None:
        return param(
            symbol,
            unit,
            doc=doc,
            ge=0,
            le=le,
            optional=True,
            none="the linear axes' value",
            default=None,
        )
    return param(symbol, unit, doc=doc, ge=0, le=le, default=default)


@declared
@dataclass(frozen=True)
class UserFramePID(ParamsMixin):
    """Gains of the three user-frame PIDs (Wu et al. 2021, eq. 9; ``docs/following.md``).

    (e_x, e_y) in the robot frame give the lateral and forward velocity
    commands with one set of gains (the platform is isotropic); the heading
    error gives the yaw-rate command with its own (``None``: the linear
    axes' value). On every axis K_p or K_i must be > 0 (else nothing moves).

    Examples
    --------
    >>> UserFramePID(kp=1.0, ki=0.0, kd=0.0).is_p_only
    True
    >>> UserFramePID(kp=-1.0)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: UserFramePID.kp = -1.0 1/s is not allowed: ...
    """

    kp: float = _pid_gain("K_p", "1/s", "proportional gain of the linear axes", 1e3, 2.0)  # type: ignore[assignment]
    ki: float = _pid_gain("K_i", "1/s^2", "integral gain of the linear axes", 1e4, 0.5)  # type: ignore[assignment]
    kd: float = _pid_gain("K_d", "", "derivative gain of the linear axes", 100, 0.1)  # type: ignore[assignment]
    derivative_filter_time: float = param(
        "T_f",
        "s",
        doc="time constant of the derivative filter of the linear axes",
        ge=0,
        le=10,
        default=0.05,
    )
    kp_heading: float | None = _pid_gain(
        "K_p,h", "1/s", "proportional gain of the heading", 1e3, None
    )  # type: ignore[assignment]
    ki_heading: float | None = _pid_gain(
        "K_i,h", "1/s^2", "integral gain of the heading", 1e4, None
    )  # type: ignore[assignment]
    kd_heading: float | None = _pid_gain("K_d,h", "", "derivative gain of the heading", 100, None)  # type: ignore[assignment]
    heading_filter_time: float | None = param(
        "T_f,h",
        "s",
        doc="time constant of the derivative filter of the heading",
        ge=0,
        le=10,
        optional=True,
        none="derivative_filter_time",
        default=None,
    )

    def __post_init__(self) -> None:
        for name, base in (
            ("kp_heading", "kp"),
            ("ki_heading", "ki"),
            ("kd_heading", "kd"),
            ("heading_filter_time", "derivative_filter_time"),
        ):
            if getattr(self, name) is None:
                object.__setattr__(self, name, getattr(self, base))
        if self.kp + self.ki == 0.0 or self.kp_heading + self.ki_heading == 0.0:  # type: ignore[operator]
            raise InvalidParameterError(
                "UserFramePID.kp",
                self.kp,
                "kp or ki must be > 0 on every axis (else nothing moves)",
            )

    def gains(self, axis: str) -> tuple[float, float, float, float]:
        """(K_p, K_i, K_d, T_f) of one axis: ``"lateral"``, ``"forward"`` or ``"heading"``.

        Parameters
        ----------
        axis
            One of :data:`AXES`.
        """
        if axis in ("lateral", "forward"):
            return (self.kp, self.ki, self.kd, self.derivative_filter_time)
        if axis == "heading":
            return (self.kp_heading, self.ki_heading, self.kd_heading, self.heading_filter_time)  # type: ignore[return-value]
        raise InvalidParameterError("axis", axis, f"one of {AXES}")

    @property
    def is_p_only(self) -> bool:
        """True if every axis has K_i = K_d = 0."""
        return self.ki == self.kd == self.ki_heading == self.kd_heading == 0.0

    def vector(self) -> list[float]:
        """The 12 numbers (K_p, K_i, K_d, T_f) for lateral, forward, heading."""
        return [v for a in AXES for v in self.gains(a)]


# --- arguments of the walking tasks (declared once) --------------------------------------

#: Fastest user accepted (m/s): well above any walk (Wu et al. 2021 walk at about 0.5 m/s).
MAX_WALKING_SPEED = 10.0


def _arg(symbol: str | None, unit: str, doc: str, name: str, **kw: object) -> Param:
    return Param(symbol, unit, doc, name=name, **kw)  # type: ignore[arg-type]


#: Cruise walking speed of a task.
WALKING_SPEED = _arg(
    "v",
    "m/s",
    "cruise walking speed",
    "speed",
    gt=0,
    le=MAX_WALKING_SPEED,
    typical=(0.3, 1.5),
    optional=True,
    none="0.45 m/s forward, 0.4 m/s backward and lateral, 0.5 m/s on the rectangle and circles",
)
#: Cruise turning rate of the pivots.
YAW_RATE = _arg(
    "omega",
    "rad/s",
    "cruise turning rate of the pivots",
    "yaw_rate",
    gt=0,
    le=10,
    default=math.radians(45.0),
)
#: Walked distance of the straight tasks.
DISTANCE = _arg(
    "s",
    "m",
    "walked distance of the straight tasks",
    "distance",
    gt=0,
    le=100,
    optional=True,
    none="the paper's (Sec. 4.1): 1.95, 1.98, 1.52 and 1.56 m",
)
#: Pivot angle.
TURN_ANGLE = _arg(
    "alpha", "rad", "pivot angle", "turn_angle", gt=0, le=4 * math.pi, default=math.radians(90.0)
)
#: Circle radius of the circle tasks.
RADIUS = _arg("R", "m", "circle radius", "radius", gt=0, le=100, default=0.9)
#: A side of the rectangle task (forward side, lateral side).
RECTANGLE_SIDE = _arg(None, "m", "side of the rectangle", "rectangle", gt=0, le=100)
#: Raised-cosine acceleration time of each move.
RAMP_TIME = _arg(
    None, "s", "raised-cosine acceleration time", "ramp_time", gt=0, le=60, default=0.6
)
#: Standing time between the legs of the rectangle.
PAUSE = _arg(None, "s", "standing time between legs", "pause", ge=0, le=600, default=0.5)
#: Standing time before the walk.
STAND_BEFORE = _arg(
    None, "s", "standing time before the walk", "stand_before", ge=0, le=600, default=1.0
)
#: Standing time after the walk (the settled error is taken 10 s after the stop).
SETTLE_TIME = _arg(
    None, "s", "standing time after the walk", "settle_time", ge=0, le=600, default=10.0
)
#: Distance of the frame origin ahead of the turning centre in pivots.
PIVOT_OFFSET = _arg(
    None,
    "m",
    "frame origin ahead of the turning centre in pivots",
    "pivot_offset",
    ge=0,
    le=2,
    default=0.25,
)
#: Lateral pelvis sway amplitude.
SWAY_LATERAL = _arg(
    None, "m", "lateral pelvis sway amplitude", "sway_lateral", ge=0, le=1, default=0.0
)
#: Yaw pelvis sway amplitude.
SWAY_YAW = _arg(
    None, "rad", "yaw pelvis sway amplitude", "sway_yaw", ge=0, le=math.pi / 2, default=0.0
)
#: Steps per second (the sway has half this frequency).
STEP_FREQUENCY = _arg(None, "Hz", "steps per second", "step_frequency", gt=0, le=10, default=1.8)
#: The user's initial world heading.
START_HEADING = _arg(
    None,
    "rad",
    "initial world heading of the user",
    "start_heading",
    ge=-100,
    le=100,
    default=math.pi / 2,
)
#: Standing time appended after a recorded walk.
HOLD_AFTER = _arg(
    None,
    "s",
    "standing time appended after the recording",
    "hold_after",
    ge=0,
    le=600,
    default=10.0,
)
#: A recorded walk ends at the last sample faster than this.
SPEED_THRESHOLD = _arg(
    None, "m/s", "speed above which the user walks", "speed_threshold", gt=0, le=10, default=0.05
)
#: ... or turning faster than this.
YAW_RATE_THRESHOLD = _arg(
    None,
    "rad/s",
    "yaw rate above which the user turns",
    "yaw_rate_threshold",
    gt=0,
    le=10,
    default=0.15,
)

# --- arguments of the simulation and the analyses (declared once) -------------------------

#: Initial offset of the robot from its target (each coordinate).
INITIAL_OFFSET = _arg(
    None, "m", "initial offset of the robot from its target", "initial_offset", ge=-5, le=5
)
#: Seed of the sensor noise.
SEED = ARG.seed.but(doc="seed of the sensor noise", optional=True, none="fresh randomness")
#: Error band of the settling time.
SETTLE_BAND = _arg(
    None, "m", "error band of the settling time", "settle_band", gt=0, le=1, default=0.02
)
#: Points of the frequency grid of the loop analysis (a grid too coarse misses the peaks).
N_FREQUENCIES = _arg(
    None,
    "",
    "points of the log frequency grid",
    "n_frequencies",
    kind="integer",
    ge=50,
    le=100_000,
    default=2000,
)

# --- arguments of the tuners (declared once) ------------------------------------------------

#: Limit of the sensitivity peak |S|.
MS_MAX = _arg("M_s", "", "limit of the sensitivity peak |S|", "ms_max", ge=1, le=3, default=1.6)
#: Limit of the complementary sensitivity peak |T|.
MT_MAX = _arg(
    "M_t",
    "",
    "limit of the complementary sensitivity peak |T|",
    "mt_max",
    ge=1,
    le=3,
    default=1.3,
)
#: Upper bound of K_d (a practical limit on noise amplification).
KD_MAX = _arg(None, "", "upper bound of K_d", "kd_max", ge=0, le=100, default=5.0)
#: Limit of |C S|, the gain from measurement noise to the command.
MAX_NOISE_GAIN = _arg(
    "k_s",
    "1/s",
    "limit of |C S|, noise to command",
    "max_noise_gain",
    gt=0,
    le=1e4,
    optional=True,
    none="no limit",
)
#: Objective evaluations of the derivative-free tuner.
MAX_EVALUATIONS = _arg(
    None,
    "",
    "objective evaluations of the derivative-free tuner",
    "max_evaluations",
    kind="integer",
    ge=5,
    le=1000,
    default=150,
)
#: Convex programs of the convex-concave tuner.
MAX_ITERATIONS = _arg(
    None,
    "",
    "convex programs of the convex-concave iteration",
    "max_iterations",
    kind="integer",
    ge=1,
    le=1000,
    default=60,
)
#: The convex-concave iteration stops when K_i grows by less than this (relative).
TOLERANCE = _arg(
    None,
    "",
    "relative increase of K_i that ends the iteration",
    "tolerance",
    gt=0,
    le=1,
    default=1e-5,
)


def loop_parts(
    controller: object, platform: object, sensor: object
) -> tuple[UserFramePID, MecanumPlatform, StringPotSensor]:
    """The loop's controller, platform and sensor: each given one checked, the defaults for
    ``None``; anything else is refused by name.

    Parameters
    ----------
    controller, platform, sensor
        A :class:`UserFramePID`, :class:`MecanumPlatform` and :class:`StringPotSensor`,
        or ``None`` (the default one).

    Returns
    -------
    tuple

    Examples
    --------
    >>> loop_parts(None, None, None)[1] == MecanumPlatform()
    True
    >>> loop_parts("pid", None, None)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: controller = 'str' is not allowed: ...
    """
    parts = []
    for name, obj, cls in (
        ("controller", controller, UserFramePID),
        ("platform", platform, MecanumPlatform),
        ("sensor", sensor, StringPotSensor),
    ):
        obj = cls() if obj is None else obj
        if not isinstance(obj, cls):
            raise InvalidParameterError(name, type(obj).__name__, f"must be a {cls.__name__}")
        parts.append(obj)
    return parts[0], parts[1], parts[2]
