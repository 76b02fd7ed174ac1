"""The face of a tether follower law (Allan 2015 Sec. 2.3, Ch. 4, App. C).

Every law is a small frozen dataclass whose gains and desired tether length
are declared fields (so that tuning and sweeps can set them), and whose class
says everything the engines, tuners, study kinds and reports ask of it:

=====================  ==================================================================
class attribute        what it says
=====================  ==================================================================
``name``               the public name (the ``type`` of a study file)
``label``, ``short``   the name in prose, the short name in report tables (``"FTL-CD"``)
``doc``                one line: what the law does, with its source
``measured``           measured with people in Tables 3.2-3.3 (PJ, FTL-CD; Sec. 3.4)
``turn_claim``         what the thesis found on the inside and outside of turns (side modes)
``steadier_than``      the mode the thesis found this one holds its side offset steadier than
``placement``          where the robot walks: ``"behind"``, ``"side"``, ``"front"``, or
                       ``"wrapper"`` (a mode around another law)
``target_finder``      how the steering angle is obtained (the tether angle, or a point of
                       the recorded path: :mod:`designlab.following.tether.buffer`)
``stepwise``           a mode with memory, run one period at a time (:meth:`start`)
``linear``             the law has a linearised lateral loop (:meth:`effective_loop`)
``brakeable``          Brake mode may wrap it (Sec. 4.4: not a front mode)
``LENGTH_FIELD``       the field that holds the tether length (l_d, or a side offset l_H)
``GAINS``, ``BOUNDS``  the fields a tuner may change and their widest tuning bounds
``LAW_PARAMS``         the fields fed to :meth:`law_function` after ``l_m, phi, b``
``SWEEP_FIELDS``       the fields a sweep point may set (by their symbols)
=====================  ==================================================================

The laws register in :mod:`designlab.following.tether.laws.registry` (one line
each); engines look a law up there or ask the law object, and never test its
name or class. The shared declarations below (:data:`DESIRED_LENGTH`, gains,
buffer settings) hold each bound once for every law.

Examples
--------
>>> DESIRED_LENGTH.check(1.2)
1.2
>>> DESIRED_LENGTH.check(0.0)
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: desired_length = 0.0 m is not allowed: must be a finite ...
"""

from __future__ import annotations

import math
from dataclasses import asdict, replace
from functools import cache
from typing import Any, ClassVar

import casadi as ca

from designlab.errors import InvalidParameterError
from designlab.following.tether.buffer import TETHER_ANGLE, TargetFinder
from designlab.following.tether.parameters import WHEEL_TRACK, FollowerRobot
from designlab.params import Param, param
from designlab.sx.pycode import compile_sx

__all__ = [
    "DESIRED_LENGTH",
    "StepwiseController",
    "TetherController",
    "angle",
    "buffer_size",
    "cap",
    "checked_law",
    "gain",
    "length",
    "min_step",
    "side_pose",
    "tether_length",
]

#: The desired tether length l_d of every law (a side offset l_H too): its one bound.
DESIRED_LENGTH = Param(
    "l_d",
    "m",
    "desired tether length",
    gt=0,
    le=10,
    typical=(0.6, 2.0),
    name="desired_length",
)


def tether_length(
    default: float,
    symbol: str = "l_d",
    doc: str = DESIRED_LENGTH.doc,
    typical: tuple[float, float] | None = DESIRED_LENGTH.typical,
) -> Any:
    """A law's field declaring a tether length held, bounded as :data:`DESIRED_LENGTH`.

    Parameters
    ----------
    default
        The law's default in m.
    symbol, doc, typical
        The symbol, meaning and typical range in this law.
    """
    return param(
        symbol,
        DESIRED_LENGTH.unit,
        doc=doc,
        gt=DESIRED_LENGTH.gt,
        le=DESIRED_LENGTH.le,
        typical=typical,
        default=default,
    )


def length(symbol: str, doc: str, default: float, typical: Any = None) -> Any:
    """The declaration of another length of a law (> 0 and at most 10 m).

    Parameters
    ----------
    symbol, doc
        Its symbol and meaning.
    default
        Its default in m.
    typical
        Its typical range in m, if any.
    """
    return param(symbol, "m", doc=doc, gt=0, le=10, typical=typical, default=default)


def gain(symbol: str, unit: str, doc: str, default: float, *, ge: float | None = None) -> Any:
    """The declaration of a gain: > 0 (or >= ``ge``) and at most 1000 (one bound for every law).

    Parameters
    ----------
    symbol, unit, doc
        Its symbol, unit and meaning.
    default
        Its default.
    ge
        An inclusive lower bound instead of > 0.
    """
    bounds = {"ge": ge} if ge is not None else {"gt": 0}
    return param(symbol, unit, doc=doc, le=1e3, default=default, **bounds)  # type: ignore[arg-type]


def angle(symbol: str, doc: str, default: float) -> Any:
    """The declaration of an angle of a law, in [-pi, pi].

    Parameters
    ----------
    symbol, doc
        Its symbol and meaning.
    default
        Its default in rad.
    """
    return param(symbol, "rad", doc=doc, ge=-math.pi, le=math.pi, default=default)


def cap(symbol: str, unit: str, doc: str) -> Any:
    """The declaration of an upper clamp on V or Omega (App. C: 100, effectively none).

    Parameters
    ----------
    symbol, unit, doc
        Its symbol, unit and meaning.
    """
    return param(symbol, unit, doc=doc, gt=0, le=1e6, default=100.0)


def min_step() -> Any:
    """The declaration of Delta s_min, the least step between recorded points."""
    return param(
        "ds_min", "m", doc="least step between recorded path points", gt=0, le=1, default=0.01
    )


def buffer_size(
    doc: str = "path buffer limit; at most buffer_size - 1 points are kept, as coded",
) -> Any:
    """The declaration of the path buffer limit (App. C: 300).

    Parameters
    ----------
    doc
        Its meaning in this law.
    """
    return param(None, "", doc=doc, kind="integer", ge=3, le=100_000, default=300)


def side_pose(
    point: Any, heading: float, offset: float, angle: float
) -> tuple[float, float, float]:
    """Pose ``offset`` from ``point`` at ``angle`` from ``heading`` *as seen from the robot*.

    The robot faces ``heading`` and sees the point at ``angle`` (``+pi/2``: on
    its left, so the robot is on the point's right).

    Parameters
    ----------
    point
        The leader's position ``(x, y)`` in m.
    heading
        The robot's heading in rad.
    offset
        Distance in m.
    angle
        Direction of the point relative to the robot's heading in rad.

    Examples
    --------
    >>> [round(v, 9) for v in side_pose((0.0, 0.0), 0.0, 1.0, math.pi / 2)]
    [0.0, -1.0, 0.0]
    """
    px, py = float(point[0]), float(point[1])
    d = heading + angle
    return px - offset * math.cos(d), py - offset * math.sin(d), float(heading)


class TetherController:
    """The face of a tether follower law: what every law says and does.

    Class attributes are listed in the module notes; a law overrides those that
    differ from these defaults (a memoryless law steering along the tether,
    followed from behind).
    """

    name: ClassVar[str] = ""
    label: ClassVar[str] = ""
    short: ClassVar[str] = ""
    doc: ClassVar[str] = ""
    placement: ClassVar[str] = "behind"
    measured: ClassVar[bool] = False
    turn_claim: ClassVar[str] = ""
    steadier_than: ClassVar[str] = ""
    target_finder: ClassVar[TargetFinder] = TETHER_ANGLE
    stepwise: ClassVar[bool] = False
    linear: ClassVar[bool] = False
    brakeable: ClassVar[bool] = True
    LENGTH_FIELD: ClassVar[str] = "desired_length"
    GAINS: ClassVar[tuple[str, ...]] = ()
    BOUNDS: ClassVar[dict[str, tuple[float, float]]] = {}
    LAW_PARAMS: ClassVar[tuple[str, ...]] = ()
    SWEEP_FIELDS: ClassVar[tuple[str, ...]] = ()
    desired_length: float

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if "name" not in cls.__dict__:
            cls.name = cls.__name__
        cls.short = cls.__dict__.get("short") or cls.name

    @property
    def gains(self) -> dict[str, float]:
        """The tunable gains as a dict."""
        return {k: getattr(self, k) for k in self.GAINS}

    @classmethod
    def holding(cls, value: float) -> TetherController:
        """The law with its defaults, holding the tether length ``value`` in :attr:`LENGTH_FIELD`.

        Parameters
        ----------
        value
            l_d (or the side offset l_H) in m.
        """
        return cls(**{cls.LENGTH_FIELD: value})  # type: ignore[call-arg]

    def as_dict(self) -> dict[str, Any]:
        """All fields as a plain dict, with the law's name under ``"type"``."""
        return {"type": self.name, **asdict(self)}  # type: ignore[call-overload]

    def replace(self, **changes: Any) -> Any:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)  # type: ignore[type-var]

    def law_values(self) -> tuple[float, ...]:
        """The numbers fed to :meth:`law_function` after ``l_m, phi, b``."""
        return tuple(float(getattr(self, k)) for k in self.LAW_PARAMS)

    def search_distance(self) -> float:
        """The distance (m) the law's target finder searches the recorded path with."""
        return self.target_finder.distance(self)

    @classmethod
    def law_function(cls, variant: str = "") -> ca.Function:  # pragma: no cover - overridden
        """CasADi function ``(l_m, phi, b, *LAW_PARAMS) -> (V, Omega)``."""
        raise NotImplementedError

    def law_key(self) -> str:
        """Which variant of the law this instance uses."""
        return ""

    def effective_loop(self, speed: Any, wheel_track: float) -> tuple[Any, Any, Any]:
        """Turn gain K (1/s), effective look-ahead L (m) and steady tether length (m).

        Only a law with ``linear = True`` has one
        (:func:`designlab.following.tether.linear.effective_loop`).

        Parameters
        ----------
        speed
            Leader speed in m/s.
        wheel_track
            Wheel track b in m.
        """
        raise InvalidParameterError(
            "controller", self.name, "a law with a linear lateral loop (PJ, FTL, FTL-CD)"
        )

    def command(
        self, l_m: float, phi: float, wheel_track: float = WHEEL_TRACK.default
    ) -> tuple[float, float]:
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


class StepwiseController(TetherController):
    """A follower mode with memory: :meth:`start` gives the state of one run."""

    stepwise: ClassVar[bool] = True

    def start(self, robot: FollowerRobot) -> Any:  # pragma: no cover - overridden
        """A fresh state for one run on ``robot`` (a ``ModeState``)."""
        raise NotImplementedError


def checked_law(
    controller: Any,
    parameter: str = "controller",
    allowed: str = "a tether controller (e.g. FollowTheLeader())",
) -> TetherController:
    """``controller`` if it is a tether law, else an error naming ``parameter``.

    Parameters
    ----------
    controller
        The object given.
    parameter
        Its name in the error message.
    allowed
        What is allowed, in the error message.

    Examples
    --------
    >>> checked_law("FTL")
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: controller = 'FTL' is not allowed: a tether ...
    """
    if not isinstance(controller, TetherController):
        raise InvalidParameterError(parameter, controller, allowed)
    return controller


@cache
def _compiled_law(cls: type, key: str, batch: bool) -> Any:
    return compile_sx(cls.law_function(key), batch=batch)  # type: ignore[attr-defined]


def symbols(*names: str) -> list[ca.SX]:
    """CasADi symbols of the given names (the inputs of a law function)."""
    return [ca.SX.sym(n) for n in names]
