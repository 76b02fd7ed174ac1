"""Brake mode and its selection algorithm (Allan 2015 Sec. 4.4, Fig. 4.13).

Each control period, after the tether is read and before the follower law runs,
the mode selector compares the tether length with a threshold: a tether shorter
than the threshold means the user is close (has stopped), so the robot enters
Brake mode and commands ``V = Omega = 0``; when the user walks on, the robot
returns to the mode it was in. On OxyDog the motor speed-control gains are also
raised to hold position on slopes; a kinematic robot holds still at zero
command, so that part is not modelled (``docs/tether_modes.md``).

The thesis gives no threshold, hysteresis or gain increase (A14). The project's
choice, stated in the docs: engage when ``l_m < l_d + engage_margin`` and release
when ``l_m > l_d + release_margin`` with ``release_margin > engage_margin``
(hysteresis, so sensor noise near the threshold does not toggle the mode), with
``l_d`` the wrapped mode's desired length. Brake mode wraps the modes that
follow from behind or beside; a front mode is refused (there a short tether
means the user is pushing the robot on).

Examples
--------
>>> brake_timeline([1.2, 1.03, 1.01, 1.04, 1.06, 1.2], 1.0, 0.02, 0.05).tolist()
[False, False, True, True, False, False]
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.following.tether.laws.base import (
    DESIRED_LENGTH,
    StepwiseController,
    TetherController,
    checked_law,
)
from designlab.following.tether.parameters import FollowerRobot
from designlab.following.tether.stepwise import ModeState, start_state
from designlab.params import declared, param, params_of
from designlab.validation import real_array

__all__ = ["BrakeMode", "brake_timeline"]


def brake_timeline(
    tether_length: Any, desired_length: float, engage_margin: float, release_margin: float
) -> NDArray[np.bool_]:
    """The selector's decision per period: True while in Brake mode.

    Parameters
    ----------
    tether_length
        Measured l_m per period in m.
    desired_length
        The wrapped mode's l_d in m.
    engage_margin, release_margin
        Brake when ``l_m < l_d + engage_margin``; resume when ``l_m > l_d + release_margin``
        (each checked against the declarations of :class:`BrakeMode`; release above engage).

    Examples
    --------
    >>> brake_timeline([1.1, 1.01, 1.04, 1.06], 1.0, 0.02, 0.05).tolist()
    [False, True, True, False]
    """
    lengths = real_array("tether_length", tether_length, "m")
    if lengths.ndim != 1:
        raise InvalidParameterError("tether_length", lengths.shape, "must be one value a period")
    decls = params_of(BrakeMode)
    desired_length = DESIRED_LENGTH.check(desired_length, "desired_length")
    engage_margin = decls["engage_margin"].check(engage_margin, "engage_margin")
    release_margin = decls["release_margin"].check(release_margin, "release_margin")
    if not release_margin > engage_margin:
        raise InvalidParameterError(
            "release_margin", release_margin,
            f"must be greater than engage_margin ({engage_margin:g} m): the hysteresis", "m",
        )  # fmt: skip
    on, out = False, []
    for lm in lengths.tolist():
        on = lm <= desired_length + release_margin if on else lm < desired_length + engage_margin
        out.append(on)
    return np.array(out, dtype=bool)


class _BrakeRun:
    """One run: the wrapped mode's state and the selector's."""

    def __init__(self, c: BrakeMode, robot: FollowerRobot) -> None:
        self.inner: ModeState = start_state(c.mode, robot)
        self.engage = c.mode.desired_length + c.engage_margin
        self.release = c.mode.desired_length + c.release_margin
        self.braking = False

    def command(
        self, x: float, y: float, g: float, l_m: float, theta_m: float
    ) -> tuple[float, float]:
        self.braking = l_m <= self.release if self.braking else l_m < self.engage
        v, om = self.inner.command(x, y, g, l_m, theta_m)  # keeps recording its path buffer
        return (0.0, 0.0) if self.braking else (v, om)


@declared
@dataclass(frozen=True)
class BrakeMode(StepwiseController):
    """Brake mode around a follower mode (Allan 2015 Sec. 4.4.2, Fig. 4.13).

    Brake (``V = Omega = 0``) when ``l_m < l_d + engage_margin``; return to
    ``mode`` when ``l_m > l_d + release_margin``. The wrapped mode keeps
    recording its path while braked. The margins are the project's (the
    thesis gives none, A14).

    Attributes
    ----------
    mode : TetherController
        The wrapped follower mode (not a front mode nor a BrakeMode); its desired
        length l_d (m) is the threshold's base and it drives the robot when not braked.

    Examples
    --------
    >>> from designlab.following.tether import PseudoJoystick
    >>> BrakeMode(PseudoJoystick()).desired_length
    1.0
    >>> BrakeMode(PseudoJoystick(), engage_margin=0.1, release_margin=0.05)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: BrakeMode.release_margin = 0.05 m is not allowed: ...
    """

    mode: TetherController
    engage_margin: float = param(
        "Delta l_on", "m", doc="brake when l_m < l_d + this", ge=-10, le=10, default=0.02
    )
    release_margin: float = param(
        "Delta l_off",
        "m",
        doc="resume when l_m > l_d + this (> engage_margin)",
        ge=-10,
        le=10,
        default=0.05,
    )

    label: ClassVar[str] = "Brake mode"
    short: ClassVar[str] = "Brake"
    doc: ClassVar[str] = "stop while the tether is short, around another mode (Sec. 4.4)"
    placement: ClassVar[str] = "wrapper"
    brakeable: ClassVar[bool] = False

    def __post_init__(self) -> None:
        mode = checked_law(self.mode, "BrakeMode.mode", "a follower mode (not a BrakeMode)")
        if mode.placement == self.placement:
            raise InvalidParameterError(
                "BrakeMode.mode", self.mode, "a follower mode (not a BrakeMode)"
            )
        if not mode.brakeable:
            raise InvalidParameterError(
                "BrakeMode.mode",
                mode.name,
                "a mode that follows from behind or beside (a front mode's short tether is a push)",
            )
        if not self.release_margin > self.engage_margin:
            raise InvalidParameterError(
                "BrakeMode.release_margin",
                self.release_margin,
                f"greater than engage_margin ({self.engage_margin:g} m): the hysteresis",
                "m",
            )

    @property
    def desired_length(self) -> float:  # type: ignore[override]
        """The wrapped mode's desired tether length in m."""
        return self.mode.desired_length

    def as_dict(self) -> dict[str, Any]:
        """Fields as a plain dict, the wrapped mode as its own dict."""
        return {
            "type": self.name,
            "mode": self.mode.as_dict(),
            "engage_margin": self.engage_margin,
            "release_margin": self.release_margin,
        }

    def start(self, robot: FollowerRobot) -> _BrakeRun:
        """A fresh run state."""
        return _BrakeRun(self, robot)

    def start_pose(self, point: Any, heading: float) -> tuple[float, float, float] | None:
        """The wrapped mode's start (None: behind the leader, the simulation's default)."""
        start = getattr(self.mode, "start_pose", None)
        return None if start is None else start(point, heading)
