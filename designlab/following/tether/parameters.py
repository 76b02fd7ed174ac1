"""Parameters of the tether follower (Allan 2015, Sec. 2.2-2.4, Table 3.1, App. C), declared once.

* :class:`FollowerRobot`: the differential-drive robot, its tether sensor and
  its control rate (the control laws declare their own gains in
  :mod:`designlab.following.tether.laws`, the leader paths theirs in
  :mod:`designlab.following.tether.paths`);
* the arguments of the simulation and of the tuner that are not fields of a
  model (:data:`LEADER_SPEED`, :data:`DURATION`, :data:`POPSIZE`, ...), each a
  :class:`~designlab.params.Param` checked with ``.check``.

Each declaration carries the caps that keep a run within memory and time
(stated in ``docs/following.md``, "Limits"); a simulation also checks the size
of its arrays before it allocates them (:func:`designlab.params.check_size`).

Examples
--------
>>> robot = FollowerRobot()
>>> robot.wheel_track, robot.wheel_radius, robot.sample_time
(0.28, 0.125, 0.01)
>>> FollowerRobot(max_wheel_speed=8.0).max_speed
1.0
>>> FollowerRobot(length_noise_std=1e6)
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: FollowerRobot.length_noise_std = 1000000.0 m is not ...
"""

from __future__ import annotations

import dataclasses
import math
import sys
from dataclasses import dataclass
from typing import Annotated, Any

from pydantic import AfterValidator, BeforeValidator, Field, WithJsonSchema

from designlab.params import ARG, Param, declared, param, params_of
from designlab.validation import ParamsMixin

__all__ = [
    "DAMPING_FLOOR",
    "DURATION",
    "LEADER_SPEED",
    "LEAD_IN",
    "MAXITER",
    "MAX_SATURATION",
    "OXYDOG",
    "POPSIZE",
    "SEED",
    "SETTLE_TIME",
    "TETHER_LIMIT",
    "TOLERANCE",
    "WHEEL_TRACK",
    "FollowerRobot",
    "LimitParam",
    "limit",
]


@dataclasses.dataclass(frozen=True)
class LimitParam(Param):
    """A positive limit for which ``inf`` means "no limit" (a wheel speed, an acceleration).

    The finite values keep the declared bounds (and cap); ``inf`` is allowed
    besides (``.inf`` in YAML). In the JSON Schema ``inf`` is the number above
    the largest float.

    Parameters
    ----------
    symbol, unit, doc, kind, gt, ge, lt, le, choices, typical, optional, none, default, name, owner
    min_length, max_length
        As :class:`designlab.params.Param`.

    Examples
    --------
    >>> w = LimitParam("w_max", "rad/s", "wheel speed limit", gt=0, le=1e4, name="w")
    >>> w.check(float("inf")), w.check(8)
    (inf, 8.0)
    >>> w.allowed()
    '> 0 and <= 10000, or inf (no limit)'
    """

    def within(self, value: float) -> bool:
        """Whether ``value`` is ``inf`` or a finite number inside the bounds.

        Parameters
        ----------
        value
            A value in the parameter's unit.
        """
        return value == math.inf or super().within(value)

    def allowed(self) -> str:
        """The allowed range as text (the finite bounds, or inf)."""
        return super().allowed() + ", or inf (no limit)"

    def annotation(self, *, optional: bool | None = None) -> Any:
        """The pydantic type: a number inside the bounds, or ``inf``.

        Parameters
        ----------
        optional
            Allow ``None`` (default: the declaration's ``optional``).
        """

        def number_only(value: Any) -> Any:
            if isinstance(value, (bool, str, bytes)):
                raise ValueError(f"must be a number ({self.allowed()})")
            return value

        def within(value: float) -> float:
            if not self.within(value):
                raise ValueError(f"must be {self.allowed()}")
            return value

        finite = {"type": "number", **self.json_bounds()}
        no_limit = {"type": "number", "exclusiveMinimum": sys.float_info.max}
        described = f"{self.description}, {self.unit}; allowed {self.allowed()}"
        base: Any = Annotated[
            float,
            BeforeValidator(number_only),
            AfterValidator(within),
            WithJsonSchema({"anyOf": [finite, no_limit]}),
        ]
        if self.optional if optional is None else optional:
            base = base | None
        return Annotated[base, Field(description=described)]


def limit(symbol: str, unit: str, *, doc: str, gt: float, le: float, default: float) -> Any:
    """Declare a dataclass field as a :class:`LimitParam` (``inf``: no limit).

    Parameters
    ----------
    symbol, unit, doc
        As :func:`designlab.params.param`.
    gt, le
        Bounds of the finite values.
    default
        The default (``math.inf`` for no limit).
    """
    decl = LimitParam(symbol=symbol, unit=unit, doc=doc, gt=gt, le=le, default=default)
    return dataclasses.field(default=default, metadata={"param": decl})


@declared
@dataclass(frozen=True)
class FollowerRobot(ParamsMixin):
    """Differential-drive tether follower: geometry, limits, sensing and control rate.

    The robot is kinematic (Allan 2015 gives no masses, motor or friction
    data; Sec. 2.4.1). A wheel-speed demand beyond ``max_wheel_speed`` scales
    both wheels by the same factor, which keeps the demanded curvature (the
    thesis does not say how its firmware saturates; a project choice,
    ``docs/following.md``). The winch offset is rotated properly (the App. C
    listing's ``off_y`` terms are not a rotation). With a tip height the sensor
    measures the 3-D length while the controllers treat it as planar, as the
    thesis does. The thesis states no control period (Sec. 2.4.1).

    Examples
    --------
    >>> FollowerRobot(max_wheel_speed=8.0).max_speed
    1.0
    >>> FollowerRobot(wheel_track=-1.0)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: FollowerRobot.wheel_track = -1.0 m is not allowed: ...
    """

    wheel_track: float = param(
        "b",
        "m",
        doc="distance between the wheel centres (Allan 2015 Table 3.1)",
        gt=0,
        le=10,
        typical=(0.2, 0.6),
        default=0.28,
    )
    wheel_radius: float = param(
        "r", "m", doc="wheel radius (Table 3.1)", gt=0, le=5, typical=(0.05, 0.2), default=0.125
    )
    body_length: float = param(
        "L_r",
        "m",
        doc="overall robot length (Table 3.1); the desired tether length must exceed half of it",
        gt=0,
        le=20,
        typical=(0.4, 1.0),
        default=0.67,
    )
    max_wheel_speed: float = limit(
        "w_max",
        "rad/s",
        doc="wheel angular speed limit (App. C: none; OxyDog 8 rad/s, 1.0 m/s)",
        gt=0,
        le=1e4,
        default=math.inf,
    )
    max_wheel_acceleration: float = limit(
        "dw_max",
        "rad/s^2",
        doc="wheel angular acceleration limit (none in the thesis)",
        gt=0,
        le=1e6,
        default=math.inf,
    )
    winch_offset_x: float = param(
        "o_x",
        "m",
        doc="winch position ahead of the robot centre (App. C offsets)",
        ge=-10,
        le=10,
        default=0.0,
    )
    winch_offset_y: float = param(
        "o_y", "m", doc="winch position left of the robot centre", ge=-10, le=10, default=0.0
    )
    tip_height: float = param(
        "h",
        "m",
        doc="height of the tether tip above the winch (0: the planar model)",
        ge=0,
        le=10,
        default=0.0,
    )
    length_noise_std: float = param(
        "sigma_l", "m", doc="standard deviation of Gaussian noise on l_m (at most 0.1 m: a "
        "larger noise makes the measured length of a 1 m tether negative)", ge=0, le=0.1,
        default=0.0,
    )  # fmt: skip
    angle_noise_std: float = param(
        "sigma_theta",
        "rad",
        doc="standard deviation of Gaussian noise on theta_m",
        ge=0,
        le=math.pi,
        default=0.0,
    )
    sample_time: float = param(
        "dt",
        "s",
        doc="control (and simulation) period; 0.01 s is 100 Hz",
        gt=0,
        le=1,
        typical=(0.005, 0.05),
        default=0.01,
    )

    @property
    def max_speed(self) -> float:
        """Forward speed in m/s with both wheels at ``max_wheel_speed``."""
        return self.max_wheel_speed * self.wheel_radius

    @property
    def noisy(self) -> bool:
        """True when the tether sensor has noise."""
        return self.length_noise_std > 0.0 or self.angle_noise_std > 0.0

    @property
    def limited(self) -> bool:
        """True when a wheel speed or acceleration limit is set."""
        return self.max_wheel_speed < math.inf or self.max_wheel_acceleration < math.inf

    @property
    def planar(self) -> bool:
        """True when the winch sits at the robot centre, level with the tether tip."""
        return self.winch_offset_x == 0.0 and self.winch_offset_y == 0.0 and self.tip_height == 0.0


#: The wheel track's declaration, for the functions that take it as an argument.
WHEEL_TRACK = params_of(FollowerRobot)["wheel_track"]

#: OxyDog hardware (Allan 2015 Table 3.1): b = 0.28 m, r = 0.125 m, 1.0 m/s top speed.
OXYDOG = FollowerRobot(max_wheel_speed=1.0 / 0.125)


# --- arguments of the simulation (declared once) -----------------------------------------

#: Leader speed (Allan 2015 Sec. 2.4.1: a constant-speed leader at 0.5 m/s).
LEADER_SPEED = Param(
    "v", "m/s", "leader speed", gt=0, le=10, typical=(0.3, 0.8), default=0.5, name="speed"
)
#: Simulated time; a longer run is refused before anything is allocated.
DURATION = Param("T", "s", "simulated time", gt=0, le=1e4, typical=(10, 100), name="duration")
#: Time the simulation continues after the leader stops.
SETTLE_TIME = Param(
    "T_s", "s", "time after the leader stops", ge=0, le=600, default=5.0, name="settle_time"
)
#: Straight approach already walked (and recorded by FTL/FTL-CD) before t = 0.
LEAD_IN = Param(
    "s_0", "m", "straight approach walked before t = 0", ge=0, le=100, default=0.0, name="lead_in"
)
#: Seed of the sensor noise and of the optimiser.
SEED = ARG.seed.but(optional=True, none="fresh randomness")

# --- arguments of the tuner (declared once) ------------------------------------------------

#: Least damping ratio of the linear lateral loop at every tuning speed (no weaving).
DAMPING_FLOOR = Param(
    "zeta_min",
    "",
    "least damping ratio of the linear lateral loop",
    ge=0,
    le=5,
    default=0.5,
    name="damping_floor",
)
#: Tuning constraint: the largest fraction of a run with a wheel at its speed limit.
MAX_SATURATION = Param(
    None,
    "",
    "largest fraction of a run with a wheel at its speed limit (tuning constraint)",
    ge=0,
    le=1,
    default=0.05,
    name="max_saturation",
)
#: Either end of the allowed tether range (Allan 2015 Table 1.1: 0.2-1.0 m "or greater").
TETHER_LIMIT = Param("l", "m", "end of the allowed tether range", gt=0, le=100, name="tether_range")
#: Differential-evolution population multiplier (scipy's ``popsize``).
POPSIZE = Param(
    None,
    "",
    "population multiplier of differential evolution",
    kind="integer",
    ge=2,
    le=100,
    default=6,
    name="popsize",
)
#: Differential-evolution generations.
MAXITER = Param(
    None,
    "",
    "generations of differential evolution",
    kind="integer",
    ge=1,
    le=1000,
    default=12,
    name="maxiter",
)
#: Relative tolerance of differential evolution (scipy's ``tol``).
TOLERANCE = Param(
    None, "", "relative tolerance of differential evolution", ge=0, le=1, default=0.01, name="tol"
)
