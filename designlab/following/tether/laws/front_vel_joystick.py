"""FrontVelJoystick: move with the tether tip's relative velocity (App. C mode 42, code only).

5-sample buffers of ``l_m`` and ``theta_m`` give the tip's velocity *relative
to the robot* ``(l_new cos th_new - l_old cos th_old, ...)/(dt (size + 1))``;
``V = |v_tip|``, ``Omega = k_O atan2(v_y, v_x)``. As coded the time span is
``dt (size + 1)`` for ``size - 1`` sample intervals, and no tether length is
held (``k_V`` and ``l_d`` are unused): a robot ahead of a leader walking
straight at ``v`` settles where ``V = (4/6)(v - V)``, i.e. ``V = 0.4 v``
(``docs/tether_modes.md``). The robot starts ``l_d`` ahead of the leader,
facing the path's heading.

Examples
--------
>>> FrontVelJoystick().placement
'front'
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from typing import Any, ClassVar

from designlab.following.tether.laws.base import (
    StepwiseController,
    angle,
    cap,
    gain,
    side_pose,
    tether_length,
)
from designlab.following.tether.parameters import FollowerRobot
from designlab.params import declared, param

__all__ = ["FrontVelJoystick"]


class _FrontVelRun:
    """One run of FrontVelJoystick (App. C mode 42)."""

    def __init__(self, c: FrontVelJoystick, robot: FollowerRobot) -> None:
        self.c = c
        self.dt = robot.sample_time
        self.ls: deque[float] = deque(maxlen=c.samples)
        self.ths: deque[float] = deque(maxlen=c.samples)

    def command(
        self, x: float, y: float, g: float, l_m: float, theta_m: float
    ) -> tuple[float, float]:
        self.ls.append(l_m)
        self.ths.append(theta_m)
        size = len(self.ls)
        span = self.dt * (size + 1)  # as coded
        vx = (self.ls[-1] * math.cos(self.ths[-1]) - self.ls[0] * math.cos(self.ths[0])) / span
        vy = (self.ls[-1] * math.sin(self.ths[-1]) - self.ls[0] * math.sin(self.ths[0])) / span
        v = min(math.hypot(vx, vy), self.c.max_speed)
        om = min(self.c.turn_gain * math.atan2(vy, vx), self.c.max_turn_rate) if v > 0 else 0.0
        return v, om


@declared
@dataclass(frozen=True)
class FrontVelJoystick(StepwiseController):
    """FrontVelJoystick: move with the tether tip's relative velocity (App. C mode 42, code only).

    ``V = |v_tip|``, ``Omega = k_O atan2(v_tip)`` with ``v_tip`` from the
    newest and oldest of ``samples`` readings over ``dt (samples + 1)`` (as
    coded); k_O 0.8. The code's k_V = 1.0 and l_d = 1.0 m are unused;
    ``desired_length`` only places the robot at the start.

    Examples
    --------
    >>> FrontVelJoystick().turn_gain, FrontVelJoystick().samples
    (0.8, 5)
    """

    desired_length: float = tether_length(
        1.0, doc="desired tether length (robot ahead)", typical=None
    )
    turn_gain: float = gain("k_O", "1/s", "yaw rate per radian of tip velocity direction", 0.8)
    samples: int = param(
        None,
        "",
        doc="length of the l_m and theta_m buffers",
        kind="integer",
        ge=2,
        le=1000,
        default=5,
    )
    desired_angle: float = angle("theta_d", "tether angle held (pi: straight behind)", math.pi)
    max_speed: float = cap("V_max", "m/s", "upper clamp on V (App. C: 100)")
    max_turn_rate: float = cap("Omega_max", "rad/s", "upper clamp on Omega (App. C: 100)")

    label: ClassVar[str] = "FrontVelJoystick"
    short: ClassVar[str] = "FVJ"
    doc: ClassVar[str] = "move with the tether tip's relative velocity (App. C mode 42, code only)"
    placement: ClassVar[str] = "front"
    brakeable: ClassVar[bool] = False
    GAINS: ClassVar[tuple[str, ...]] = ("turn_gain",)

    def start(self, robot: FollowerRobot) -> _FrontVelRun:
        """A fresh run state."""
        return _FrontVelRun(self, robot)

    def start_pose(self, point: Any, heading: float) -> tuple[float, float, float]:
        """``l_d`` ahead of the leader, facing the path's heading."""
        return side_pose(point, heading, self.desired_length, self.desired_angle)
