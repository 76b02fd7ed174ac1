"""Robots, obstacle classes and gains of the VFF navigation model (Zeng 2011, Ch. 5-7).

All fields are SI (m, s, kg, N). The defaults are the thesis's values
(Zeng 2011, Sec. 3.2 of ``docs/navigation.md``): a 0.2 m, 4.4 kg holonomic robot
limited to 0.7 m/s and 10 m/s^2, a 0.4 m human walking at up to 1.0 m/s.

Examples
--------
>>> from designlab.navigation import HolonomicRobot, Human, VFFGains
>>> HolonomicRobot().max_speed, Human().radius
(0.7, 0.4)
>>> g = VFFGains(k1=3.0, b=0.25, k3=20.0, k5=17.0)
>>> g.k2, g.k4, g.k6
(0.75, 5.0, 4.25)
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from designlab.errors import InvalidParameterError, check_positive
from designlab.params import Param, declared, param
from designlab.validation import ParamsMixin

__all__ = [
    "ARRIVAL_TOLERANCE",
    "CBF_K0",
    "CBF_K1",
    "DYNAMICS_STEP",
    "EXPERIMENT_GAINS",
    "GAIN",
    "GAIN_SETS",
    "MAX_GAIN",
    "MAX_HUMAN_SPEED",
    "MAX_SUBSTEPS",
    "OBSTACLES",
    "OPTIMAL_GAINS",
    "SAMPLE_TIME",
    "CircularObstacle",
    "GeCuiGains",
    "HolonomicRobot",
    "Human",
    "MasoudGains",
    "NonholonomicRobot",
    "ObstacleRobot",
    "RectangularObstacle",
    "VFFGains",
    "check_cbf_gains",
]


def declared_field(decl: Param, default: Any = dataclasses.MISSING, **kwargs: Any) -> Any:
    """A dataclass field carrying an existing declaration (one :class:`Param` for a field
    and a function argument, e.g. :data:`SAMPLE_TIME`)."""
    return dataclasses.field(default=default, metadata={"param": decl}, **kwargs)


# ------------------------------------------------------------------- shared limits

#: The navigation (vision) period T_s: the force is recomputed every T_s and held
#: (Zeng 2011, Sec. 5.3: 0.06 s). A field of :class:`~designlab.navigation.Scenario` and
#: the argument of :func:`~designlab.navigation.region_sizes` (one declaration for both).
SAMPLE_TIME = Param(
    "T_s",
    "s",
    "navigation period: the force is recomputed and held every T_s (a reaction delay)",
    gt=0,
    le=1.0,
    typical=(0.03, 0.1),
    name="sample_time",
)

#: Arrival radius around the goal: arrival is the first passage within it (docs/navigation.md,
#: "Arrival"; 0.15 m).
ARRIVAL_TOLERANCE = Param(
    "tol", "m", "arrival radius around the goal (first passage)", gt=0, le=1.0,
    typical=(0.05, 0.15), default=0.15, name="arrival_tolerance",
)  # fmt: skip
#: Integration step of the robot dynamics inside a navigation period (1 ms); it must
#: divide T_s into at most :data:`MAX_SUBSTEPS` steps.
DYNAMICS_STEP = Param(
    "dt", "s", "integration step of the robot dynamics (divides T_s)", gt=0, le=1.0,
    typical=(1e-3, 1e-3), name="dynamics_step",
)  # fmt: skip
#: Most dynamics steps per navigation period (T_s / dt): each is unrolled in the compiled
#: step, so more would take minutes to build (the thesis: 60).
MAX_SUBSTEPS = 1000
#: Gain sets one :func:`~designlab.navigation.simulate_batch` call simulates together: about
#: 4 ms of CPU per gain set and scenario (Configuration 1, virtual machine), so 4096 are
#: about a minute per scenario; split larger sets into several calls.
GAIN_SETS = Param(
    None, "", "gain sets simulated in one batch", kind="integer", ge=1, le=4096, name="gains"
)
#: Obstacles of one scenario at most: each adds its terms to the compiled field and its
#: distances to every recorded step (2,000 discs ran for minutes, then out of memory). The
#: cap of :class:`~designlab.navigation.Scenario` and of the study files' ``obstacles``.
OBSTACLES = Param(
    None, "", "obstacles of a scenario", kind="integer", ge=0, le=100, name="Scenario.obstacles"
)
#: (k_0, k_1) of the CBF constraint h'' + k_1 h' + k_0 h >= 0 (``method="cbf"``).
CBF_K0 = Param("k_0", "1/s^2", "CBF gain on h", gt=0, le=1e4, name="cbf_gains[0]")
CBF_K1 = Param("k_1", "1/s", "CBF gain on h'", gt=0, le=1e4, name="cbf_gains[1]")


def check_cbf_gains(k: Any) -> tuple[float, float]:
    """``(k_0, k_1)`` checked against :data:`CBF_K0` and :data:`CBF_K1` (every run that
    takes them: :func:`~designlab.navigation.simulate` and the crowd runs).

    Parameters
    ----------
    k
        The pair given.

    Returns
    -------
    tuple of float

    Examples
    --------
    >>> check_cbf_gains((4, 4.0))
    (4.0, 4.0)
    >>> check_cbf_gains("ab")
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: cbf_gains = 'ab' is not allowed: must be two ...
    """
    if isinstance(k, (str, bytes)) or not hasattr(k, "__len__") or len(k) != 2:
        raise InvalidParameterError(
            "cbf_gains", k, "must be two finite numbers (k_0, k_1) > 0 and <= 1e+04 (1/s^2, 1/s)"
        )
    return (CBF_K0.check(k[0]), CBF_K1.check(k[1]))


#: Fastest human accepted (m/s): above a sprint (the thesis uses 1 m/s walkers).
MAX_HUMAN_SPEED = 12.0
#: Fastest robot accepted (m/s): the thesis's robots move at 0.7 m/s.
_MAX_ROBOT_SPEED = 5.0
#: Largest size of a robot or a disc obstacle (m), and of a rectangle's side.
_MAX_RADIUS, _MAX_SIDE = 5.0, 100.0


def _radius(symbol: str, doc: str, default: float) -> Any:
    return param(symbol, "m", doc=doc, gt=0, le=_MAX_RADIUS, default=default)


def _speed_limit(symbol: str, default: float) -> Any:
    return param(
        symbol,
        "m/s",
        doc="speed limit (norm-clipped)",
        gt=0,
        le=_MAX_ROBOT_SPEED,
        default=default,
        typical=(0.5, 1.0),
    )


def _accel_limit(symbol: str, default: float) -> Any:
    return param(
        symbol,
        "m/s^2",
        doc="acceleration (= deceleration) limit (norm-clipped)",
        ge=1e-3,
        le=100.0,
        default=default,
        typical=(5.0, 10.0),
    )


def _mass(doc: str) -> Any:
    return param("m_mr", "kg", doc=doc, gt=0, le=1e4, default=4.4, typical=(3.7, 4.4))


# --------------------------------------------------------------------------- robots


@declared
@dataclass(frozen=True)
class HolonomicRobot(ParamsMixin):
    """Omni-wheel point-mass robot (Zeng 2011, Sec. 5.2, 6.2.1, App. D).

    The wheel radius and offset are not given in the thesis (project defaults, see
    ``docs/navigation.md``); they are used only for the energy.

    Examples
    --------
    >>> HolonomicRobot(radius=0.2, max_speed=0.7, max_accel=10.0).stopping_time
    0.07
    """

    radius: float = _radius("rho_r", "model radius (the robot is a disc)", 0.2)
    max_speed: float = _speed_limit("V_mr", 0.7)
    max_accel: float = _accel_limit("a_mr", 10.0)
    mass: float = _mass("virtual-force mass (a = F_v / m_mr, 5.2.1)")
    wheel_radius: float = param("r_w", "m", doc="omni-wheel radius", gt=0, le=1.0, default=0.038)
    wheel_offset: float = param(
        "l_w", "m", doc="wheel-to-centre distance", gt=0, le=_MAX_RADIUS, default=0.15
    )

    @property
    def stopping_time(self) -> float:
        """Time to stop from full speed, Delta t1 = V / a (s) (5.3.2)."""
        return self.max_speed / self.max_accel

    @property
    def kind(self) -> str:
        return "holonomic"


@declared
@dataclass(frozen=True)
class NonholonomicRobot(ParamsMixin):
    """Differential-drive robot tracking a virtual holonomic reference (Zeng 2011, Ch. 7, App. E).

    The limits are those of :class:`HolonomicRobot` (the thesis uses the same). The
    mass is that of the virtual holonomic reference robot the force field drives: the
    thesis leaves it open (the physical robot weighs 3.7 kg, Sec. 7.2); the default is the
    holonomic robot's 4.4 kg, the mass the gains were tuned for.

    Examples
    --------
    >>> round(NonholonomicRobot().turn_time, 4)
    0.2118
    """

    radius: float = _radius("rho_r", "model radius (the robot is a disc)", 0.2)
    max_speed: float = _speed_limit("V_mr", 0.7)
    max_accel: float = _accel_limit("a_mr", 10.0)
    max_angular_accel: float = param(
        "omega_bar",
        "rad/s^2",
        doc="maximum angular acceleration",
        ge=1e-3,
        le=1e4,
        default=70.0,
        typical=(70.0, 70.0),
    )
    mass: float = _mass("mass of the virtual holonomic reference robot")
    wheel_radius: float = param("r_w,nh", "m", doc="wheel radius", gt=0, le=1.0, default=0.025)
    track: float = param("l_nh", "m", doc="wheel span", gt=0, le=_MAX_RADIUS, default=0.28)
    xi: float = param(
        "xi_nh", "", doc="Klancar-Skrjanc damping gain (7.2.3)", gt=0, lt=1, default=0.95
    )
    k: float = param("k_nh", "", doc="Klancar-Skrjanc gain (7.2.3)", gt=0, le=1e4, default=10.0)
    wheel_speed_limit: bool = param(
        kind="flag",
        default=True,
        doc="V_mr bounds each wheel's rim speed |v +- omega l_nh / 2| (the commanded v and "
        "omega are scaled together, keeping the curvature); False: it bounds v only, the "
        "model before issue 21, whose outer wheel exceeded V_mr in turns",
    )

    @property
    def stopping_time(self) -> float:
        """Time to stop from full speed, Delta t1 = V / a (s)."""
        return self.max_speed / self.max_accel

    @property
    def turn_time(self) -> float:
        """Quarter-turn time t_turn = sqrt(pi / omega_bar) in s (7.4.2)."""
        return math.sqrt(math.pi / self.max_angular_accel)

    @property
    def kind(self) -> str:
        return "nonholonomic"


# ------------------------------------------------------------------ obstacle classes


@declared
@dataclass(frozen=True)
class Human(ParamsMixin):
    """A walking person modelled as a disc (Zeng 2011, Sec. 5.2).

    Examples
    --------
    >>> Human().radius, Human(max_speed=1.4).max_speed
    (0.4, 1.4)
    """

    radius: float = _radius("rho_h", "model radius (half the average step length)", 0.4)
    max_speed: float = param(
        "V_h",
        "m/s",
        doc="maximum walking speed",
        ge=0,
        le=MAX_HUMAN_SPEED,
        default=1.0,
        typical=(1.0, 1.4),
    )


@declared
@dataclass(frozen=True)
class CircularObstacle(ParamsMixin):
    """A stationary disc obstacle (Zeng 2011, Sec. 5.3.4).

    Examples
    --------
    >>> CircularObstacle(radius=0.1).max_speed
    0.0
    """

    radius: float = _radius("rho_circular", "model radius", 0.1)

    @property
    def max_speed(self) -> float:
        return 0.0


@declared
@dataclass(frozen=True)
class ObstacleRobot(ParamsMixin):
    """Another mobile robot, a moving disc (Zeng 2011, Sec. 7.5.5).

    Examples
    --------
    >>> ObstacleRobot().max_speed
    0.5
    """

    radius: float = _radius("rho_mobile", "model radius", 0.2)
    max_speed: float = param(
        "V_mob", "m/s", doc="its maximum speed", ge=0, le=_MAX_ROBOT_SPEED, default=0.5
    )


@declared
@dataclass(frozen=True)
class RectangularObstacle(ParamsMixin):
    """A stationary rectangle; regions are measured from its contour (Zeng 2011, Sec. 5.3.5).

    The thesis's experiments use the offset B = B_wid / 2 (the robot approaches the
    short side).

    Examples
    --------
    >>> RectangularObstacle(length=1.4, width=0.6, offset=0.3).offset
    0.3
    """

    length: float = param("B_len", "m", doc="length", gt=0, le=_MAX_SIDE, default=1.4)
    width: float = param("B_wid", "m", doc="width", gt=0, le=_MAX_SIDE, default=0.6)
    offset: float | None = param(
        "B",
        "m",
        doc="perpendicular offset of the robot's approach line from the rectangle's centre "
        "line (Fig. 5.4)",
        ge=0,
        le=_MAX_SIDE,
        optional=True,
        none="the worst case, B = B_len / 2",
        default=None,
    )

    @property
    def effective_offset(self) -> float:
        """B used in the sizing: the given offset, or B_len / 2 (worst case)."""
        return 0.5 * self.length if self.offset is None else float(self.offset)


# ----------------------------------------------------------------------------- gains


#: The largest gain accepted (any unit). The field's norm is taken in double precision,
#: so gains near 1e150 overflow it; far below that, 1e9 N/m is already beyond any
#: robot's actuators (the thesis's gains are below 300).
MAX_GAIN = 1e9

#: Any gain of the navigation fields: a finite number > 0 and <= :data:`MAX_GAIN`. The one
#: declaration of the gain limit: every gain field (and the batch simulator's gain arrays,
#: the optimiser's bounds and the study files) is checked against it.
GAIN = Param(None, "", "gain", gt=0, le=MAX_GAIN, name="gain")


def _gain(symbol: str | None, unit: str, doc: str, default: Any = dataclasses.MISSING) -> Any:
    decl = dataclasses.replace(GAIN, symbol=symbol, unit=unit, doc=doc)
    return declared_field(decl, default)


@declared
@dataclass(frozen=True)
class VFFGains(ParamsMixin):
    """Gains of the new VFF with the structure the stability proof needs (Zeng 2011, (5.5.7)).

    The proof (Sec. 5.5, App. B) requires K2/K1 = K4/K3 = K6/K5 = b > 0 with all gains
    positive, which leaves four free gains: K1, b, K3 and K5. The dependent gains
    K2 = b K1, K4 = b K3, K6 = b K5 are properties.

    Examples
    --------
    >>> VFFGains(k1=4.3, b=0.68, k3=20.3, k5=240.7).damping_ratio(4.4)
    0.3361...
    >>> VFFGains.from_full(k1=3, k2=0.75, k3=20, k4=5, k5=17, k6=4.25).b
    0.25
    """

    k1: float = _gain("K1", "N/m", "attractive gain")
    b: float = _gain(None, "s", "gain ratio b = K2/K1 = K4/K3 = K6/K5")  # symbol in the text
    k3: float = _gain("K3", "N/m", "repulsive gain")
    k5: float = _gain("K5", "N/m^2", "detour gain")

    @property
    def k2(self) -> float:
        """Attractive damping gain K2 = b K1 (N s/m)."""
        return self.b * self.k1

    @property
    def k4(self) -> float:
        """Repulsive damping gain K4 = b K3."""
        return self.b * self.k3

    @property
    def k6(self) -> float:
        """Detour damping gain K6 = b K5."""
        return self.b * self.k5

    def as_array(self) -> np.ndarray:
        """``[k1, b, k3, k5]``: one row of the batch simulator's gain array."""
        return np.array([self.k1, self.b, self.k3, self.k5])

    def damping_ratio(self, mass: float) -> float:
        """Damping ratio of the free-space loop, zeta = (b/2) sqrt(K1/m) (App. B.1)."""
        return 0.5 * self.b * math.sqrt(self.k1 / check_positive("mass", mass, "kg"))

    @classmethod
    def from_full(
        cls, *, k1: float, k2: float, k3: float, k4: float, k5: float, k6: float, rtol: float = 1e-9
    ) -> VFFGains:
        """Build from all six gains, checking the structure b = K2/K1 = K4/K3 = K6/K5.

        Raises
        ------
        InvalidParameterError
            If any gain is not positive or the three ratios differ (the Lyapunov
            condition (5.5.7) fails).
        """
        vals = {"k1": k1, "k2": k2, "k3": k3, "k4": k4, "k5": k5, "k6": k6}
        for n, v in vals.items():
            GAIN.check(v, f"VFFGains.{n}")
        b = float(k2) / float(k1)
        for num, den in (("k4", "k3"), ("k6", "k5")):
            r = float(vals[num]) / float(vals[den])
            if not math.isclose(r, b, rel_tol=rtol, abs_tol=0.0):
                raise InvalidParameterError(
                    f"VFFGains.{num}",
                    vals[num],
                    f"must equal b * {den} = {b * float(vals[den])!r} (b = K2/K1 = K4/K3 = K6/K5, "
                    "Zeng 2011 (5.5.7))",
                )
        return cls(k1=float(k1), b=b, k3=float(k3), k5=float(k5))


#: Gains of all the thesis's Ch. 6/7 simulations and experiments (Sec. 6.2.4, 7.3.2).
EXPERIMENT_GAINS = VFFGains(k1=3.0, b=0.25, k3=20.0, k5=17.0)
#: Optimised gains of Table C.1.
OPTIMAL_GAINS = VFFGains(k1=4.3, b=0.68, k3=20.3, k5=240.7)


@declared
@dataclass(frozen=True)
class MasoudGains(ParamsMixin):
    """Gains of Masoud (2007) as used in Zeng 2011, Sec. 2.2.4 (Table C.1: 5, 24, 36).

    The attraction is K_MM1 E (no damping), the repulsion K_MM3 D in the active region
    and the detour K_MM5 |D| u_MMpsi with a fixed rotational sense (the thesis does not
    state it).

    Examples
    --------
    >>> MasoudGains(direction=-1).k3
    24.0
    """

    k1: float = _gain("K_MM1", "N/m", "attractive gain", 5.0)
    k3: float = _gain("K_MM3", "N/m", "repulsive gain", 24.0)
    k5: float = _gain("K_MM5", "N/m", "detour gain", 36.0)
    direction: int = param(
        doc="rotational sense of the detour field: +1 counter-clockwise, -1 clockwise",
        kind="integer",
        ge=-1,
        le=1,
        default=1,
    )

    def __post_init__(self) -> None:
        if self.direction not in (1, -1):
            raise InvalidParameterError("MasoudGains.direction", self.direction, "must be +1 or -1")


@declared
@dataclass(frozen=True)
class GeCuiGains(ParamsMixin):
    """Gains of Ge & Cui (2002) as used in Zeng 2011, Sec. 2.2.4.

    Defaults are Table C.1's: 1.0, 0.75, 14.2, 14.2. The attraction is the PD law
    K1 E + b K1 E'.

    Examples
    --------
    >>> GeCuiGains().b
    0.75
    """

    k1: float = _gain("K_G1", "N/m", "attractive gain", 1.0)
    b: float = _gain("b_G", "s", "attractive damping ratio K2/K1", 0.75)
    k3: float = _gain("K_G3", "", "repulsive gain of (2.2.12)", 14.2)
    k5: float = _gain("K_G5", "", "detour gain of (2.2.13)", 14.2)
