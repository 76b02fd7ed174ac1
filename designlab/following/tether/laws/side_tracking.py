"""Side Tracking: track a point beside the leader's path (Allan 2015 Sec. 4.2.4, App. C mode 31).

The newest 4 tips of a 10-point buffer give the leader's (backward-pointing)
tangent; rotated by ``offset_angle`` (pi/2 as coded; the text says pi, A12)
and scaled to ``offset_length`` it gives the side point K beside the newest
tip; K is recorded in a 300-point path buffer and tracked with FTL's nearest
point plus look-ahead, ``V = k_V (|K - P| - l_d)``, ``Omega = k_O phi`` (the
code writes the wheel speeds ``(k_V e_l -+ k_O b phi/2)/r``, the same thing).
Before K exists the code drives with ``phi = 0`` and ``e_l = 0.5``. With
``offset_angle = +pi/2`` the robot walks on the leader's right, as coded
(``docs/tether_modes.md``).

Examples
--------
>>> st = SideTracking()
>>> st.offset_length, st.side_gap, st.lookahead
(1.0, 0.1, 0.6)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from designlab.following.tether.laws.base import (
    StepwiseController,
    angle,
    buffer_size,
    gain,
    length,
    side_pose,
    tether_length,
)
from designlab.following.tether.model import wrap_angle
from designlab.following.tether.parameters import FollowerRobot
from designlab.following.tether.stepwise import TipRecorder
from designlab.params import declared, param

__all__ = ["SideTracking"]


class _SideTrackingRun:
    """One run of Side Tracking (App. C mode 31)."""

    TANGENT_POINTS: ClassVar[int] = 4

    def __init__(self, c: SideTracking, robot: FollowerRobot) -> None:
        self.c = c
        self.b = robot.wheel_track
        self.tips = TipRecorder(c.tip_buffer_size, c.min_step)
        self.side = TipRecorder(c.buffer_size, c.min_step)
        self.rot = (math.cos(c.offset_angle), math.sin(c.offset_angle))

    def side_point(self) -> tuple[float, float] | None:
        """K: the newest tip plus the rotated, scaled backward tangent (None before 4 tips)."""
        n = self.TANGENT_POINTS
        if len(self.tips) < n:
            return None
        nx, ny = self.tips.newest()
        ox, oy = self.tips.newest(n - 1)
        tx, ty = (ox - nx) / (n - 1), (oy - ny) / (n - 1)  # mean difference, pointing backwards
        norm = math.hypot(tx, ty)
        if not norm > 0.0:
            return None
        c, s = self.rot
        scale = self.c.offset_length / norm
        return nx + scale * (c * tx - s * ty), ny + scale * (s * tx + c * ty)

    def command(
        self, x: float, y: float, g: float, l_m: float, theta_m: float
    ) -> tuple[float, float]:
        c = self.c
        self.tips.record(x + l_m * math.cos(g + theta_m), y + l_m * math.sin(g + theta_m))
        k = self.side_point()
        if k is None:
            phi, e_l = 0.0, 0.5  # as coded, before K exists
        else:
            self.side.record(*k)
            tx, ty = self.side.lookahead_point(x, y, c.lookahead)
            phi = wrap_angle(math.atan2(ty - y, tx - x) - g)
            e_l = math.hypot(k[0] - x, k[1] - y) - c.side_gap
        return c.speed_gain * e_l, c.turn_gain * phi


@declared
@dataclass(frozen=True)
class SideTracking(StepwiseController):
    """Side Tracking: track a point beside the leader's path (Allan 2015 Sec. 4.2.4, mode 31).

    K = newest tip + the backward tangent (mean over 4 tips) rotated by
    ``offset_angle`` and scaled to ``offset_length``; K is recorded and tracked
    with FTL's nearest point plus ``lookahead``; ``V = k_V (|K - P| - l_d)``,
    ``Omega = k_O phi``. Defaults are App. C's (k_V 1.0, k_O 3.0, delta 0.6 m,
    l_d 0.1 m, offset pi/2 and 1.0 m, tip buffer 10, side buffer 300, 0.01 m).
    ``desired_length`` is ``offset_length`` (the tether length while abreast).

    Examples
    --------
    >>> SideTracking(offset_length=0.56).desired_length
    0.56
    """

    offset_length: float = tether_length(
        1.0, "l_H", "side offset of K from the newest tip", typical=None
    )
    side_gap: float = length("l_d", "distance to K at which V = 0", 0.1)
    speed_gain: float = gain("k_V", "1/s", "speed per metre of distance to K", 1.0)
    turn_gain: float = gain("k_O", "1/s", "yaw rate per radian of target angle", 3.0)
    lookahead: float = length("delta", "look-ahead along the recorded K path", 0.6)
    offset_angle: float = angle(
        "offset_angle", "rotation of the backward tangent (+pi/2: right)", math.pi / 2
    )
    min_step: float = param(
        "ds_min", "m", doc="least step between recorded points", gt=0, le=1, default=0.01
    )
    tip_buffer_size: int = param(
        None,
        "",
        doc="tip buffer limit (tangent from its newest 4)",
        kind="integer",
        ge=5,
        le=1000,
        default=10,
    )
    buffer_size: int = buffer_size("K path buffer limit")

    label: ClassVar[str] = "Side Tracking"
    short: ClassVar[str] = "Tracking"
    doc: ClassVar[str] = "track a point beside the leader's recorded path (Sec. 4.2.4, mode 31)"
    placement: ClassVar[str] = "side"
    turn_claim: ClassVar[str] = "the thesis: Side Tracking handles both, Fig. 4.7"
    steadier_than: ClassVar[str] = "SideJoystick"  # Fig. 4.7 against Fig. 4.5
    LENGTH_FIELD: ClassVar[str] = "offset_length"
    GAINS: ClassVar[tuple[str, ...]] = ("speed_gain", "turn_gain", "lookahead")

    @property
    def desired_length(self) -> float:  # type: ignore[override]
        """The side offset in m (the tether length while abreast)."""
        return self.offset_length

    def start(self, robot: FollowerRobot) -> _SideTrackingRun:
        """A fresh run state."""
        return _SideTrackingRun(self, robot)

    def start_pose(self, point: Any, heading: float) -> tuple[float, float, float]:
        """Abreast of the leader, on the side ``offset_angle`` puts K."""
        return side_pose(point, heading, self.offset_length, self.offset_angle)
