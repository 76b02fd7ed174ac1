"""Study-file specifications shared by the tether-follower kinds (Allan 2015).

* :class:`FollowerRobotSpec`: ``DEFAULT`` (the App. C model: no wheel limits,
  100 Hz) or ``OXYDOG`` (Table 3.1's 1.0 m/s), optionally with fields replaced;
* :class:`ControllerSpec`: a law (``PseudoJoystick``, ``FollowTheLeader``,
  ``FollowTheLeaderConstDistance``) with optional gains (App. C defaults otherwise);
* :class:`PathSpec`: a named leader path with its arguments, or points.

Examples
--------
>>> PathSpec(type="figure_eight", a=4.0).build().name
'figure_eight_a4'
>>> ControllerSpec(type="FollowTheLeader", lookahead=0.3).build().lookahead
0.3
>>> FollowerRobotSpec.model_validate("OXYDOG").build().max_speed
1.0
"""

from __future__ import annotations

from typing import Annotated, Any, ClassVar, Literal

from pydantic import Field, model_validator

from designlab.errors import InvalidParameterError
from designlab.following import OXYDOG, FollowerRobot, LeaderPath, controller_from_dict, make_path
from designlab.following.tether_controllers import TetherController
from designlab.study.base import Flag, Integer, Model, NonNegative, Number, Positive
from designlab.study.specs import ComponentSpec as _ComponentSpec

__all__ = ["ControllerSpec", "FollowerRobotSpec", "PathSpec"]

WheelLimit = Annotated[Number, Field(gt=0)]  # inf allowed: no limit


class FollowerRobotSpec(_ComponentSpec):
    """The differential-drive follower (:class:`designlab.following.FollowerRobot`).

    Presets: ``DEFAULT`` (App. C: no wheel limits, 100 Hz), ``OXYDOG`` (1.0 m/s).
    """

    PRESETS: ClassVar[dict[str, Any]] = {"DEFAULT": FollowerRobot(), "OXYDOG": OXYDOG}
    REQUIRED: ClassVar[tuple[str, ...]] = ()
    WHAT: ClassVar[str] = "follower robot"
    BUILDS: ClassVar[type] = FollowerRobot

    wheel_track: Positive | None = Field(None, description="wheel track b, m")
    wheel_radius: Positive | None = Field(None, description="wheel radius r, m")
    body_length: Positive | None = Field(None, description="robot length, m")
    max_wheel_speed: WheelLimit | None = Field(
        None, description="wheel speed limit, rad/s (.inf: none)"
    )
    max_wheel_acceleration: WheelLimit | None = Field(None, description="rad/s^2 (.inf: none)")
    winch_offset_x: Number | None = Field(None, description="winch ahead of the centre, m")
    winch_offset_y: Number | None = Field(None, description="winch left of the centre, m")
    tip_height: NonNegative | None = Field(None, description="tether tip above the winch, m")
    length_noise_std: NonNegative | None = Field(None, description="l_m noise, m")
    angle_noise_std: NonNegative | None = Field(None, description="theta_m noise, rad")
    sample_time: Positive | None = Field(None, description="control period, s")

    @model_validator(mode="after")
    def _buildable(self) -> FollowerRobotSpec:
        try:
            self.build()
        except InvalidParameterError as exc:
            raise ValueError(str(exc)) from None
        return self


class ControllerSpec(Model):
    """A tether-follower law with optional gains (App. C defaults for the rest)."""

    type: Literal["PseudoJoystick", "FollowTheLeader", "FollowTheLeaderConstDistance"]
    label: str | None = Field(None, min_length=1, max_length=40)
    desired_length: Positive | None = Field(None, description="l_d, m")
    speed_gain: Positive | None = Field(None, description="k_V or K_p, 1/s")
    turn_gain: Positive | None = Field(None, description="k_O, K_Omega or K_b, 1/s")
    lookahead: Positive | None = Field(None, description="delta (FTL), m")
    angle_gain: NonNegative | None = Field(None, description="K_a (FTL-CD), 1/rad")
    min_step: Positive | None = Field(None, description="Delta s_min (FTL, FTL-CD), m")
    buffer_size: Annotated[Integer, Field(ge=3, le=100_000)] | None = None
    law: Literal["coded", "printed"] | None = Field(None, description="Pseudo-Joystick variant")

    @model_validator(mode="after")
    def _buildable(self) -> ControllerSpec:
        try:
            self.build()
        except (InvalidParameterError, TypeError) as exc:
            raise ValueError(str(exc)) from None
        return self

    def build(self, **changes: Any) -> TetherController:
        """The controller object (``changes`` override fields, e.g. ``desired_length``)."""
        fields = {k: v for k, v in self.model_dump(exclude={"label"}).items() if v is not None}
        fields.update(changes)
        return controller_from_dict(fields)

    @property
    def title(self) -> str:
        """The label, or a short name of the law."""
        short = {
            "PseudoJoystick": "PJ",
            "FollowTheLeader": "FTL",
            "FollowTheLeaderConstDistance": "FTL-CD",
        }
        return self.label or short[self.type]


class PathSpec(Model):
    """A leader path: a named shape with its arguments (m), or recorded points (m)."""

    type: Literal[
        "figure_eight", "square_s", "slalom", "corridor_corner", "straight_line", "circle", "points"
    ]
    name: str | None = Field(None, min_length=1, max_length=60)
    a: Positive | None = Field(None, description="figure_eight loop parameter, m")
    side: Positive | None = Field(None, description="square_s side, m")
    spacing: Positive | None = Field(None, description="slalom cone spacing, m")
    cones: Annotated[Integer, Field(ge=1, le=50)] | None = None
    amplitude: Positive | None = Field(None, description="slalom weave amplitude, m")
    out_and_back: Flag | None = None
    width: Positive | None = Field(None, description="corridor width, m")
    leg: Positive | None = Field(None, description="corridor leg length, m")
    radius: Positive | None = Field(None, description="circle/corner radius, m")
    turns: Positive | None = None
    length: Positive | None = Field(None, description="straight line length, m")
    points: list[tuple[Number, Number]] | None = Field(None, description="[[x, y], ...] in m")

    @model_validator(mode="after")
    def _buildable(self) -> PathSpec:
        try:
            self.build()
        except (InvalidParameterError, TypeError) as exc:
            raise ValueError(str(exc)) from None
        return self

    def build(self) -> LeaderPath:
        """The :class:`designlab.following.LeaderPath`."""
        args = {k: v for k, v in self.model_dump(exclude={"type", "name"}).items() if v is not None}
        if self.type == "points":
            if "points" not in args:
                raise InvalidParameterError(
                    "path.points", None, "give points for type: points", "m"
                )
            path = make_path({"points": args["points"], "name": self.name or "recorded"})
        else:
            if "points" in args:
                raise InvalidParameterError(
                    "path.points", "...", f"only with type: points, not {self.type}"
                )
            path = make_path({"type": self.type, **args})
        if self.name:
            path = LeaderPath(
                path.points,
                name=self.name,
                obstacles=path.obstacles,
                initial_heading=path.initial_heading,
            )
        return path
