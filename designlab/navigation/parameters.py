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

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from designlab.errors import InvalidParameterError, check_nonnegative, check_positive
from designlab.validation import ParamsMixin

__all__ = [
    "EXPERIMENT_GAINS",
    "OPTIMAL_GAINS",
    "CircularObstacle",
    "GeCuiGains",
    "HolonomicRobot",
    "Human",
    "MasoudGains",
    "NonholonomicRobot",
    "ObstacleRobot",
    "RectangularObstacle",
    "VFFGains",
]


# --------------------------------------------------------------------------- robots


@dataclass(frozen=True)
class HolonomicRobot(ParamsMixin):
    """Omni-wheel point-mass robot (Zeng 2011, Sec. 5.2, 6.2.1, App. D).

    Parameters
    ----------
    radius
        Model radius rho_r in m (the robot is a disc).
    max_speed
        Speed limit V_mr in m/s (norm-clipped).
    max_accel
        Acceleration (= deceleration) limit a_mr in m/s^2 (norm-clipped).
    mass
        Virtual-force mass m_mr in kg: a = F_v / m_mr (5.2.1).
    wheel_radius, wheel_offset
        Omni-wheel radius r_w and wheel-to-centre distance l_w in m (not given in the
        thesis; project defaults, see ``docs/navigation.md``). Used only for energy.

    Examples
    --------
    >>> HolonomicRobot(radius=0.2, max_speed=0.7, max_accel=10.0).stopping_time
    0.07
    """

    radius: float = 0.2
    max_speed: float = 0.7
    max_accel: float = 10.0
    mass: float = 4.4
    wheel_radius: float = 0.038
    wheel_offset: float = 0.15

    def __post_init__(self) -> None:
        for f, unit in (
            ("radius", "m"),
            ("max_speed", "m/s"),
            ("max_accel", "m/s^2"),
            ("mass", "kg"),
            ("wheel_radius", "m"),
            ("wheel_offset", "m"),
        ):
            object.__setattr__(
                self, f, check_positive(f"{type(self).__name__}.{f}", getattr(self, f), unit)
            )

    @property
    def stopping_time(self) -> float:
        """Time to stop from full speed, Delta t1 = V / a (s) (5.3.2)."""
        return self.max_speed / self.max_accel

    @property
    def kind(self) -> str:
        return "holonomic"


@dataclass(frozen=True)
class NonholonomicRobot(ParamsMixin):
    """Differential-drive robot tracking a virtual holonomic reference (Zeng 2011, Ch. 7, App. E).

    Parameters
    ----------
    radius, max_speed, max_accel
        As for :class:`HolonomicRobot` (the thesis uses the same limits).
    max_angular_accel
        Maximum angular acceleration in rad/s^2 (the thesis's "omega bar", about 70).
    mass
        Mass of the virtual holonomic reference robot that the force field drives, kg.
        The thesis leaves it open (the physical robot weighs 3.7 kg, Sec. 7.2); the
        default is the holonomic robot's 4.4 kg, the mass the gains were tuned for.
    wheel_radius, track
        Wheel radius r_w,nh and wheel span l_nh in m (0.025 m, 0.28 m).
    xi, k
        Klancar-Skrjanc tracking gains xi_nh and k_nh (7.2.3).

    Examples
    --------
    >>> round(NonholonomicRobot().turn_time, 4)
    0.2118
    """

    radius: float = 0.2
    max_speed: float = 0.7
    max_accel: float = 10.0
    max_angular_accel: float = 70.0
    mass: float = 4.4
    wheel_radius: float = 0.025
    track: float = 0.28
    xi: float = 0.95
    k: float = 10.0

    def __post_init__(self) -> None:
        for f, unit in (
            ("radius", "m"),
            ("max_speed", "m/s"),
            ("max_accel", "m/s^2"),
            ("max_angular_accel", "rad/s^2"),
            ("mass", "kg"),
            ("wheel_radius", "m"),
            ("track", "m"),
            ("k", ""),
        ):
            object.__setattr__(
                self, f, check_positive(f"{type(self).__name__}.{f}", getattr(self, f), unit)
            )
        xi = check_positive("NonholonomicRobot.xi", self.xi)
        if xi >= 1.0:
            raise InvalidParameterError(
                "NonholonomicRobot.xi", self.xi, "must be in (0, 1) (7.2.3)"
            )
        object.__setattr__(self, "xi", xi)

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


#: Fastest human accepted (m/s): above a sprint (the thesis uses 1 m/s walkers).
MAX_HUMAN_SPEED = 12.0


@dataclass(frozen=True)
class Human(ParamsMixin):
    """A walking person modelled as a disc (Zeng 2011, Sec. 5.2).

    Parameters
    ----------
    radius
        Model radius rho_h in m (0.4 m: half the average step length).
    max_speed
        Maximum walking speed in m/s (1.0 m/s).

    Examples
    --------
    >>> Human().radius, Human(max_speed=1.4).max_speed
    (0.4, 1.4)
    """

    radius: float = 0.4
    max_speed: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", check_positive("Human.radius", self.radius, "m"))
        object.__setattr__(
            self, "max_speed", check_nonnegative("Human.max_speed", self.max_speed, "m/s")
        )
        if self.max_speed > MAX_HUMAN_SPEED:
            raise InvalidParameterError(
                "Human.max_speed", self.max_speed, f"at most {MAX_HUMAN_SPEED:g} m/s", "m/s"
            )


@dataclass(frozen=True)
class CircularObstacle(ParamsMixin):
    """A stationary disc obstacle (Zeng 2011, Sec. 5.3.4).

    Parameters
    ----------
    radius
        Model radius rho_circular in m (0.1 m in the thesis).

    Examples
    --------
    >>> CircularObstacle(radius=0.1).max_speed
    0.0
    """

    radius: float = 0.1

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "radius", check_positive("CircularObstacle.radius", self.radius, "m")
        )

    @property
    def max_speed(self) -> float:
        return 0.0


@dataclass(frozen=True)
class ObstacleRobot(ParamsMixin):
    """Another mobile robot, a moving disc (Zeng 2011, Sec. 7.5.5).

    Parameters
    ----------
    radius
        Model radius rho_mobile in m (0.2 m).
    max_speed
        Its maximum speed V_mob in m/s (0.5 m/s).

    Examples
    --------
    >>> ObstacleRobot().max_speed
    0.5
    """

    radius: float = 0.2
    max_speed: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", check_positive("ObstacleRobot.radius", self.radius, "m"))
        object.__setattr__(
            self, "max_speed", check_nonnegative("ObstacleRobot.max_speed", self.max_speed, "m/s")
        )


@dataclass(frozen=True)
class RectangularObstacle(ParamsMixin):
    """A stationary rectangle; regions are measured from its contour (Zeng 2011, Sec. 5.3.5).

    Parameters
    ----------
    length, width
        B_len and B_wid in m.
    offset
        B, the perpendicular offset of the robot's approach line from the rectangle's
        centre line in m (Fig. 5.4). ``None`` means the worst case, B = B_len / 2. The
        thesis's experiments use B = B_wid / 2 (the robot approaches the short side).

    Examples
    --------
    >>> RectangularObstacle(length=1.4, width=0.6, offset=0.3).offset
    0.3
    """

    length: float = 1.4
    width: float = 0.6
    offset: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "length", check_positive("RectangularObstacle.length", self.length, "m")
        )
        object.__setattr__(
            self, "width", check_positive("RectangularObstacle.width", self.width, "m")
        )
        if self.offset is not None:
            object.__setattr__(
                self, "offset", check_nonnegative("RectangularObstacle.offset", self.offset, "m")
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


def _gain(cls: str, name: str, value: Any, unit: str) -> float:
    out = check_positive(f"{cls}.{name}", value, unit)
    if out > MAX_GAIN:
        raise InvalidParameterError(
            f"{cls}.{name}", value, f"must be a finite number > 0 and <= {MAX_GAIN:g}", unit
        )
    return out


@dataclass(frozen=True)
class VFFGains(ParamsMixin):
    """Gains of the new VFF with the structure the stability proof needs (Zeng 2011, (5.5.7)).

    The proof (Sec. 5.5, App. B) requires K2/K1 = K4/K3 = K6/K5 = b > 0 with all gains
    positive, which leaves four free gains: K1, b, K3 and K5. The dependent gains
    K2 = b K1, K4 = b K3, K6 = b K5 are properties.

    Parameters
    ----------
    k1
        Attractive gain K1 in N/m.
    b
        Gain ratio b in s.
    k3
        Repulsive gain K3 in N/m.
    k5
        Detour gain K5 in N/m^2.

    Examples
    --------
    >>> VFFGains(k1=4.3, b=0.68, k3=20.3, k5=240.7).damping_ratio(4.4)
    0.3361...
    >>> VFFGains.from_full(k1=3, k2=0.75, k3=20, k4=5, k5=17, k6=4.25).b
    0.25
    """

    k1: float
    b: float
    k3: float
    k5: float

    def __post_init__(self) -> None:
        for f, unit in (("k1", "N/m"), ("b", "s"), ("k3", "N/m"), ("k5", "N/m^2")):
            object.__setattr__(self, f, _gain("VFFGains", f, getattr(self, f), unit))

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
            _gain("VFFGains", n, v, "")
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


@dataclass(frozen=True)
class MasoudGains(ParamsMixin):
    """Gains of Masoud (2007) as used in Zeng 2011, Sec. 2.2.4 (Table C.1: 5, 24, 36).

    Parameters
    ----------
    k1
        Attractive gain K_MM1 in N/m (F_a = K_MM1 E, no damping).
    k3
        Repulsive gain K_MM3 in N/m (F_Lambda = K_MM3 D in the active region).
    k5
        Detour gain K_MM5 in N/m (F_psi = K_MM5 |D| u_MMpsi).
    direction
        The fixed rotational sense of the detour field: +1 counter-clockwise, -1
        clockwise (the thesis does not state it).

    Examples
    --------
    >>> MasoudGains(direction=-1).k3
    24.0
    """

    k1: float = 5.0
    k3: float = 24.0
    k5: float = 36.0
    direction: int = 1

    def __post_init__(self) -> None:
        for f in ("k1", "k3", "k5"):
            object.__setattr__(self, f, _gain("MasoudGains", f, getattr(self, f), ""))
        if self.direction not in (1, -1):
            raise InvalidParameterError("MasoudGains.direction", self.direction, "must be +1 or -1")


@dataclass(frozen=True)
class GeCuiGains(ParamsMixin):
    """Gains of Ge & Cui (2002) as used in Zeng 2011, Sec. 2.2.4.

    Defaults are Table C.1's: 1.0, 0.75, 14.2, 14.2.

    Parameters
    ----------
    k1
        Attractive gain in N/m (PD attraction K1 E + b K1 E').
    b
        Attractive damping ratio K2/K1 in s.
    k3
        Repulsive gain K_G3 of (2.2.12).
    k5
        Detour gain of (2.2.13).

    Examples
    --------
    >>> GeCuiGains().b
    0.75
    """

    k1: float = 1.0
    b: float = 0.75
    k3: float = 14.2
    k5: float = 14.2

    def __post_init__(self) -> None:
        for f in ("k1", "b", "k3", "k5"):
            object.__setattr__(self, f, _gain("GeCuiGains", f, getattr(self, f), ""))
