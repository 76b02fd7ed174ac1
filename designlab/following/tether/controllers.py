"""Tether follower control laws (Allan 2015, Sec. 2.3, App. C).

Three laws, each a small frozen dataclass whose gains and desired tether
length are fields, so that tuning and sweeps can set them:

* :class:`PseudoJoystick` (Sec. 2.3.1, App. C mode 10): drive along the
  tether. The default is the App. C code, ``V = k_V max(0, l_m - l_d)``,
  ``Omega = k_O theta``; ``law="printed"`` gives eqs. (2.1)-(2.2) with the
  steering sign fixed to turn toward the tether, ``Omega = (2V/b) sin theta``.
* :class:`FollowTheLeader` (Sec. 2.3.2, mode 20): record the tether tip in a
  path buffer, take the recorded point nearest to the robot, look ahead
  ``delta`` along the recorded path, ``V = k_V (l_m - l_d)`` (no clip),
  ``Omega = k_O phi``.
* :class:`FollowTheLeaderConstDistance` (Sec. 2.3.3, mode 21): steer to the
  newest recorded point at least ``l_d`` (Euclidean) from the leader,
  ``V = max(0, K_p (l_m - l_d)(1 - K_a |phi|))``, ``Omega = K_b phi`` with the
  effective positive gains of the code (K_p = 2, K_a = 0.5, K_b = 2; the
  printed signs of eqs. 2.20-2.21 would drive the robot backwards).

Defaults are the App. C values (the thesis's only numerical gains); see
``docs/following.md``. Each class writes its law once as a CasADi function
(:meth:`law_function`).

Examples
--------
>>> ftl = FollowTheLeader(lookahead=0.4)
>>> ftl.gains
{'speed_gain': 1.0, 'turn_gain': 3.0, 'lookahead': 0.4}
>>> v, om = ftl.command(l_m=1.5, phi=0.1, wheel_track=0.28)
>>> round(v, 3), round(om, 3)
(0.5, 0.3)
>>> PseudoJoystick(turn_gain=-1.0)
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: PseudoJoystick.turn_gain = -1.0 1/s is not allowed: ...
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, fields, replace
from functools import cache
from typing import Any, ClassVar

import casadi as ca

from designlab.errors import InvalidParameterError
from designlab.following.tether_codegen import compile_sx
from designlab.params import declared, param

__all__ = [
    "CONTROLLERS",
    "FollowTheLeader",
    "FollowTheLeaderConstDistance",
    "PseudoJoystick",
    "TetherController",
    "controller_from_dict",
]


def _desired_length(default: float) -> Any:
    """The declaration of l_d, the desired tether length (one bound for every law)."""
    return param(
        "l_d",
        "m",
        doc="desired tether length",
        gt=0,
        le=10,
        typical=(0.6, 2.0),
        default=default,
    )


def _gain(symbol: str, unit: str, doc: str, default: float, *, ge: float | None = None) -> Any:
    """The declaration of a gain: > 0 (or >= ``ge``) and at most 1000 (one bound for every law)."""
    bounds = {"ge": ge} if ge is not None else {"gt": 0}
    return param(symbol, unit, doc=doc, le=1e3, default=default, **bounds)  # type: ignore[arg-type]


def _min_step() -> Any:
    """The declaration of Delta s_min, the least step between recorded points."""
    return param(
        "ds_min", "m", doc="least step between recorded path points", gt=0, le=1, default=0.01
    )


def _buffer_size() -> Any:
    """The declaration of the path buffer limit (App. C: 300)."""
    return param(
        None,
        "",
        doc="path buffer limit; at most buffer_size - 1 points are kept, as coded",
        kind="integer",
        ge=3,
        le=100_000,
        default=300,
    )


class TetherController:
    """Shared behaviour of the tether follower laws.

    Class attributes
    ----------------
    target
        How the steering angle ``phi`` is obtained: ``"tether"`` (the tether
        angle itself), ``"lookahead"`` (FTL) or ``"constant_distance"`` (FTL-CD).
    GAINS
        Field names a tuner may change (besides ``desired_length``).
    BOUNDS
        Widest tuning bounds per gain (Allan 2015 has none; ``tune`` keeps the
        FTL look-ahead within b-2b unless told otherwise; ``docs/following.md``).
    """

    target: ClassVar[str] = "tether"
    GAINS: ClassVar[tuple[str, ...]] = ()
    BOUNDS: ClassVar[dict[str, tuple[float, float]]] = {}
    LAW_PARAMS: ClassVar[tuple[str, ...]] = ()
    desired_length: float

    @property
    def gains(self) -> dict[str, float]:
        """The tunable gains as a dict."""
        return {k: getattr(self, k) for k in self.GAINS}

    def as_dict(self) -> dict[str, Any]:
        """All fields as a plain dict, with the class name under ``"type"``."""
        return {"type": type(self).__name__, **asdict(self)}  # type: ignore[call-overload]

    def replace(self, **changes: Any) -> Any:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)  # type: ignore[type-var]

    def law_values(self) -> tuple[float, ...]:
        """The numbers fed to :meth:`law_function` after ``l_m, phi, b``."""
        return tuple(float(getattr(self, k)) for k in self.LAW_PARAMS)

    @classmethod
    def law_function(cls, variant: str = "") -> ca.Function:  # pragma: no cover - overridden
        """CasADi function ``(l_m, phi, b, *LAW_PARAMS) -> (V, Omega)``."""
        raise NotImplementedError

    def law_key(self) -> str:
        """Which variant of the law this instance uses."""
        return ""

    def command(self, l_m: float, phi: float, wheel_track: float = 0.28) -> tuple[float, float]:
        """The commanded forward speed (m/s) and yaw rate (rad/s) for one reading.

        Parameters
        ----------
        l_m
            Measured tether length in m.
        phi
            Steering angle in rad: the tether angle (Pseudo-Joystick) or the
            direction of the path target relative to the heading (FTL, FTL-CD).
        wheel_track
            Wheel track b in m (used by the printed Pseudo-Joystick law).
        """
        f = _compiled_law(type(self), self.law_key(), False)
        v, om = f(float(l_m), float(phi), float(wheel_track), *self.law_values())
        return float(v), float(om)


@cache
def _compiled_law(cls: type, key: str, batch: bool) -> Any:
    return compile_sx(cls.law_function(key), batch=batch)  # type: ignore[attr-defined]


def _sym(*names: str) -> list[ca.SX]:
    return [ca.SX.sym(n) for n in names]


@declared
@dataclass(frozen=True)
class PseudoJoystick(TetherController):
    """Pseudo-Joystick: drive along the tether (Allan 2015 Sec. 2.3.1, App. C mode 10).

    ``law="coded"`` (default): ``V = k_V max(0, l_m - l_d)``, ``Omega = k_O theta``.
    ``law="printed"``: eqs. (2.1)-(2.2), ``V = k_V (l_m - l_d)``,
    ``Omega = (2V/b) sin theta`` (sign fixed to steer toward the tether). The
    defaults are App. C's: l_d 1.0 m, k_V 5.0, k_O 12.0.

    Examples
    --------
    >>> pj = PseudoJoystick()
    >>> pj.command(l_m=0.8, phi=0.5)       # tether slack: rotate in place
    (0.0, 6.0)
    >>> v, om = PseudoJoystick(law="printed").command(l_m=1.1, phi=0.5)
    >>> round(v, 3), round(om, 4)
    (0.5, 1.7122)
    """

    desired_length: float = _desired_length(1.0)
    speed_gain: float = _gain("k_V", "1/s", "speed gain", 5.0)
    turn_gain: float = _gain("k_O", "1/s", "turn gain", 12.0)
    law: str = param(
        kind="choice",
        choices=("coded", "printed"),
        doc="the App. C code or the printed eqs. 2.1-2.2",
        default="coded",
    )

    target: ClassVar[str] = "tether"
    GAINS: ClassVar[tuple[str, ...]] = ("speed_gain", "turn_gain")
    BOUNDS: ClassVar[dict[str, tuple[float, float]]] = {
        "speed_gain": (0.1, 20.0),
        "turn_gain": (0.1, 20.0),
    }
    LAW_PARAMS: ClassVar[tuple[str, ...]] = ("desired_length", "speed_gain", "turn_gain")

    def law_key(self) -> str:
        """Which variant of the law this instance uses (``law``)."""
        return self.law

    @classmethod
    @cache
    def law_function(cls, variant: str = "coded") -> ca.Function:
        """CasADi function ``(l_m, phi, b, l_d, k_V, k_O) -> (V, Omega)`` of one variant.

        Parameters
        ----------
        variant
            ``"coded"`` or ``"printed"``.
        """
        lm, phi, b, ld, kv, ko = _sym("l_m", "phi", "b", "l_d", "k_V", "k_O")
        if variant == "printed":
            v = kv * (lm - ld)  # eq. 2.1
            om = 2.0 * v / b * ca.sin(phi)  # eq. 2.2 with phi = theta (2.3), sign fixed
        else:
            v = kv * ca.fmax(lm - ld, 0.0)  # App. C mode 10
            om = ko * phi
        return ca.Function(f"pj_{variant or 'coded'}", [lm, phi, b, ld, kv, ko], [v, om])


@declared
@dataclass(frozen=True)
class FollowTheLeader(TetherController):
    """Follow the Leader: track the recorded leader path (Allan 2015 Sec. 2.3.2, App. C mode 20).

    ``V = K_V (l_m - l_d)`` (eq. 2.17), ``Omega = K_Omega phi`` (eq. 2.18) with
    phi the direction to the point ``lookahead`` along the recorded path beyond
    the nearest recorded point (the thesis's rule is b < delta < 2b). The
    defaults are App. C's: l_d 1.0 m, K_V 1.0, K_Omega 3.0, delta 0.5 m.

    Examples
    --------
    >>> FollowTheLeader().lookahead, FollowTheLeader().buffer_size
    (0.5, 300)
    """

    desired_length: float = _desired_length(1.0)
    speed_gain: float = _gain("K_V", "1/s", "speed gain", 1.0)
    turn_gain: float = _gain("K_Omega", "1/s", "turn gain", 3.0)
    lookahead: float = param(
        "delta",
        "m",
        doc="FTL look-ahead",
        gt=0,
        le=10,
        typical=(0.28, 0.56),
        default=0.5,
    )
    min_step: float = _min_step()
    buffer_size: int = _buffer_size()

    target: ClassVar[str] = "lookahead"
    GAINS: ClassVar[tuple[str, ...]] = ("speed_gain", "turn_gain", "lookahead")
    BOUNDS: ClassVar[dict[str, tuple[float, float]]] = {
        "speed_gain": (0.1, 20.0),
        "turn_gain": (0.1, 20.0),
        "lookahead": (0.05, 1.0),
    }
    LAW_PARAMS: ClassVar[tuple[str, ...]] = ("desired_length", "speed_gain", "turn_gain")

    @classmethod
    @cache
    def law_function(cls, variant: str = "") -> ca.Function:
        """CasADi function ``(l_m, phi, b, l_d, K_V, K_Omega) -> (V, Omega)``.

        Parameters
        ----------
        variant
            Unused (one variant).
        """
        lm, phi, b, ld, kv, ko = _sym("l_m", "phi", "b", "l_d", "k_V", "k_O")
        return ca.Function("ftl", [lm, phi, b, ld, kv, ko], [kv * (lm - ld), ko * phi + 0.0 * b])


@declared
@dataclass(frozen=True)
class FollowTheLeaderConstDistance(TetherController):
    """Follow the Leader with Constant Distance (Allan 2015 Sec. 2.3.3, App. C mode 21).

    ``V = max(0, K_p (l_m - l_d)(1 - K_a |phi|))``, ``Omega = K_b phi`` with phi
    the direction to the newest recorded point at least l_d (Euclidean) from the
    leader. The effective gains are the code's: App. C has K_p = -2 and K_b = -2
    with extra minus signs, i.e. 2.0 each; K_a 0.5; l_d 1.2 m.

    Examples
    --------
    >>> v, om = FollowTheLeaderConstDistance().command(l_m=1.45, phi=0.2)
    >>> round(v, 3), round(om, 3)
    (0.45, 0.4)
    """

    desired_length: float = _desired_length(1.2)
    speed_gain: float = _gain("K_p", "1/s", "effective speed gain", 2.0)
    angle_gain: float = _gain(
        "K_a", "1/rad", "angle gain: 1 - K_a |phi| slows a robot turned away", 0.5, ge=0
    )
    turn_gain: float = _gain("K_b", "1/s", "effective turn gain", 2.0)
    min_step: float = _min_step()
    buffer_size: int = _buffer_size()

    target: ClassVar[str] = "constant_distance"
    GAINS: ClassVar[tuple[str, ...]] = ("speed_gain", "angle_gain", "turn_gain")
    BOUNDS: ClassVar[dict[str, tuple[float, float]]] = {
        "speed_gain": (0.1, 20.0),
        "angle_gain": (0.0, 1.0 / 3.141592653589793),
        "turn_gain": (0.1, 20.0),
    }
    LAW_PARAMS: ClassVar[tuple[str, ...]] = (
        "desired_length",
        "speed_gain",
        "angle_gain",
        "turn_gain",
    )

    @classmethod
    @cache
    def law_function(cls, variant: str = "") -> ca.Function:
        """CasADi function ``(l_m, phi, b, l_d, K_p, K_a, K_b) -> (V, Omega)``.

        Parameters
        ----------
        variant
            Unused (one variant).
        """
        lm, phi, b, ld, kp, ka, kb = _sym("l_m", "phi", "b", "l_d", "K_p", "K_a", "K_b")
        v = ca.fmax(kp * (lm - ld) * (1.0 - ka * ca.fabs(phi)), 0.0)  # eq. 2.20, effective
        return ca.Function("ftlcd", [lm, phi, b, ld, kp, ka, kb], [v, kb * phi + 0.0 * b])


#: The laws by name (as used in study files).
CONTROLLERS: dict[str, type[TetherController]] = {
    "PseudoJoystick": PseudoJoystick,
    "FollowTheLeader": FollowTheLeader,
    "FollowTheLeaderConstDistance": FollowTheLeaderConstDistance,
}


def controller_from_dict(spec: dict[str, Any]) -> TetherController:
    """Build a controller from ``{"type": name, **fields}`` (the inverse of ``as_dict``).

    Parameters
    ----------
    spec
        ``{"type": class name, **fields}``, e.g. ``{"type": "FollowTheLeader", "lookahead": 0.3}``.

    Examples
    --------
    >>> controller_from_dict({"type": "FollowTheLeader", "lookahead": 0.3}).lookahead
    0.3
    """
    if not isinstance(spec, Mapping):
        raise InvalidParameterError("controller", spec, "a mapping {type: ..., field: value}")
    spec = dict(spec)
    name = spec.pop("type", None)
    if not isinstance(name, str) or name not in CONTROLLERS:
        raise InvalidParameterError("controller.type", name, f"one of {sorted(CONTROLLERS)}")
    allowed = [f.name for f in fields(CONTROLLERS[name])]
    for key in spec:
        if key not in allowed:
            raise InvalidParameterError(f"controller.{key}", spec[key], f"a field of {name}: "
                                        f"one of {allowed}")  # fmt: skip
    return CONTROLLERS[name](**spec)  # type: ignore[call-arg,no-any-return]
