"""A crowd scenario: a layout, its pedestrians (JuPedSim), the robot's task and the regions.

:class:`CrowdScenario` is a frozen, declared dataclass (every field checked against its
declaration, so the Python API and a YAML spec enforce the same limits); :func:`crowd`
builds one by name.

Regions
-------
The pedestrians' critical and active radii come from the thesis's sizing
(:func:`~designlab.navigation.region_sizes`, Sec. 5.3) for a :class:`~designlab.navigation.Human`
of radius ``pedestrian_radius`` walking at ``max_desired_speed`` (the fastest pedestrian of
the crowd), unless adopted with ``critical_radius`` / ``active_radius``.

A wall is a static rectangle, sized as the thesis's rectangle (5.3.11)-(5.3.12) with the
offset B = 0: the worst case is the robot heading straight at the wall, which must stop
outside r3 = V_mr T_s + a_mr Delta t1^2 / 2 + rho_r (from the contour) and, within the
active distance, turn to run along it. Unlike an obstacle of the thesis, a wall is not passed
around its end, so the sidestep only cancels the approach (B = 0, not half its length).

Two walls whose critical regions overlap without touching leave a gap no path crosses outside
both; the thesis merges such obstacles (Sec. 6.4.3), which for walls closes the gap: a
bottleneck that narrow is refused (``bottleneck_width``). Walls that touch (the blocks of the
bottleneck against the corridor walls) are one body and stay as they are. Pedestrians are
moving obstacles and are never merged (as in Sec. 6.4.3): their fields add up and the
critical-region rule (Sec. 5.3) applies to every region the robot is in.

Examples
--------
>>> import designlab as dl
>>> nav = dl.navigation
>>> c = nav.crowd("corridor_counterflow", pedestrians=40, width=4.0, length=30.0, seed=0)
>>> c.layout, c.pedestrians, c.model, c.react_to_robot
('corridor_counterflow', 40, 'collision_free_speed', False)
>>> r2, r3 = c.pedestrian_regions()
>>> round(r3, 3), round(r2, 3)
(0.7, 2.739)
>>> nav.crowd("open_plaza", density=0.2, width=10.0, length=10.0).pedestrians
20
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from functools import cached_property
from typing import Any

import numpy as np
from shapely.geometry import Point
from shapely.ops import unary_union

from designlab.errors import InvalidParameterError
from designlab.navigation.crowds.layouts import LAYOUTS, Layout, build_layout
from designlab.navigation.crowds.models import MODELS
from designlab.navigation.crowds.regions import REGION_SIZING, closing_speed_sizing
from designlab.navigation.field import ObstacleGeometry
from designlab.navigation.parameters import (
    MAX_HUMAN_SPEED,
    SAMPLE_TIME,
    HolonomicRobot,
    Human,
    NonholonomicRobot,
    RectangularObstacle,
    declared_field,
)
from designlab.navigation.regions import region_sizes
from designlab.navigation.scenarios import MAX_HORIZON, Rectangle, Scenario
from designlab.params import ARG, Param, declared, param

__all__ = ["DENSITY", "CrowdScenario", "check_crowd_options", "crowd"]

#: Most pedestrians a scenario holds (the recorded positions grow with it).
MAX_PEDESTRIANS = 1000
#: Spacing of the pedestrians placed at t = 0 beyond their two radii, m.
PLACEMENT_GAP = 0.1
#: Share of the area the random placement fills at most (random sequential adsorption
#: of discs jams at 0.547; the placement stays well below it to succeed quickly).
PLACEMENT_FILL = 0.4

#: Pedestrians per square metre of walkable area: the argument of :func:`crowd`.
DENSITY = Param(
    "rho_p", "1/m^2", "pedestrian density (persons per m^2 of walkable area)",
    gt=0, le=8.0, typical=(0.1, 1.0), name="density",
)  # fmt: skip

Point2 = tuple[float, float]


def _point(name: str, value: Any) -> Point2:
    try:
        x, y = (float(v) for v in value)
    except (TypeError, ValueError):
        raise InvalidParameterError(
            name, value, "must be a point (x, y) of finite numbers", "m"
        ) from None
    if not (math.isfinite(x) and math.isfinite(y)) or max(abs(x), abs(y)) > 1e4:
        raise InvalidParameterError(name, value, "must be finite, |x|, |y| <= 1e4", "m")
    return (x, y)


@declared
@dataclass(frozen=True)
class CrowdScenario:
    """A robot's task among pedestrians simulated by JuPedSim (see the module's text).

    Build one with :func:`crowd`. ``paths`` replaces the layout's random crowd by given
    pedestrians: each walks from its start to its destination and stands there (a pedestrian
    whose start is its destination stands from the start); none enter.

    Attributes
    ----------
    area_m2
        The walkable area in m^2.
    """

    layout: str = param(doc="layout", kind="choice", choices=tuple(LAYOUTS))
    pedestrians: int = param(
        "N_p", "", doc="pedestrians in the simulation", kind="integer", ge=1,
        le=MAX_PEDESTRIANS, default=40,
    )  # fmt: skip
    width: float = param(
        "W", "m", doc="corridor / arm / plaza width", gt=0.5, le=100.0, default=4.0
    )
    length: float = param("L", "m", doc="layout length", gt=4.0, le=200.0, default=30.0)
    seed: int = ARG.seed.field(doc="random seed of placement and speeds")
    model: str = param(
        doc="JuPedSim model", kind="choice", choices=tuple(MODELS), default="collision_free_speed"
    )
    react_to_robot: bool = param(doc="pedestrians avoid the robot", kind="flag", default=False)
    desired_speed: float = param(
        "v_0",
        "m/s",
        doc="mean desired walking speed",
        gt=0,
        le=3.0,
        default=1.34,
        typical=(1.0, 1.4),
    )
    desired_speed_sd: float = param(
        "sigma_v0",
        "m/s",
        doc="standard deviation of the desired speeds",
        ge=0,
        le=1.0,
        default=0.26,
    )
    max_desired_speed: float = param(
        "v_0,max", "m/s", doc="fastest desired speed (the normal draws are clipped)", gt=0,
        le=MAX_HUMAN_SPEED, default=1.8,
    )  # fmt: skip
    pedestrian_radius: float = param(
        "rho_p", "m", doc="pedestrian body radius", gt=0.05, le=0.5, default=0.2
    )
    bottleneck_width: float = param(
        "b", "m", doc="width of the bottleneck's constriction", gt=0.2, le=50.0, default=1.6
    )
    robot: HolonomicRobot | NonholonomicRobot = param(  # noqa: RUF009
        doc="HolonomicRobot or NonholonomicRobot", kind="object", default_factory=HolonomicRobot
    )
    horizon: float | None = param(
        "T_max", "s", doc="simulated time limit", gt=0, le=MAX_HORIZON, optional=True,
        none="horizon_factor x the free-run time", default=None,
    )  # fmt: skip
    horizon_factor: float = param(
        "k_T", "", doc="time limit as a multiple of the robot's free-run time", gt=1.0, le=50.0,
        default=2.5,
    )  # fmt: skip
    region_sizing: str = param(
        doc=REGION_SIZING.doc, kind="choice", choices=REGION_SIZING.choices,
        default=REGION_SIZING.default,
    )  # fmt: skip
    sample_time: float = declared_field(SAMPLE_TIME, 0.06)
    pedestrian_step: float = param(
        "dt_p", "s", doc="JuPedSim time step (divides the sample time; at least 1 ms, so a run's "
        "step count stays bounded)", ge=1e-3, le=0.1, default=0.01,
    )  # fmt: skip
    neighbours: int = param(
        "K", "", doc="pedestrian slots of the compiled step (nearest within r2)", kind="integer",
        ge=1, le=64, default=16,
    )  # fmt: skip
    critical_radius: float | None = param(
        "r_3", "m", doc="pedestrians' critical radius (centre distance)", gt=0, le=20.0,
        optional=True, none="sized (Sec. 5.3)", default=None,
    )  # fmt: skip
    active_radius: float | None = param(
        "r_2", "m", doc="pedestrians' active radius (centre distance)", gt=0, le=50.0,
        optional=True, none="sized (Sec. 5.3)", default=None,
    )  # fmt: skip
    start: tuple[float, float] | None = param(
        unit="m", doc="robot start", kind="object", optional=True, none="the layout's", default=None
    )
    goal: tuple[float, float] | None = param(
        unit="m", doc="robot goal", kind="object", optional=True, none="the layout's", default=None
    )
    origin: tuple[float, float] = param(
        unit="m", doc="lower-left corner of the layout", kind="object", default=(0.0, 0.0)
    )
    paths: tuple[tuple[tuple[float, float], tuple[float, float]], ...] = param(
        unit="m", doc="given pedestrians: (start, destination) each", kind="object", default=()
    )
    density: float | None = param(
        "rho_p", "1/m^2", doc="density the crowd was built for (a record)", gt=0, le=8.0,
        optional=True, none="built by number", default=None,
    )  # fmt: skip

    def __post_init__(self) -> None:
        if not isinstance(self.robot, HolonomicRobot | NonholonomicRobot):
            raise InvalidParameterError(
                "CrowdScenario.robot", self.robot, "must be a HolonomicRobot or NonholonomicRobot"
            )
        object.__setattr__(self, "origin", _point("CrowdScenario.origin", self.origin))
        for name in ("start", "goal"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, _point(f"CrowdScenario.{name}", getattr(self, name)))
        object.__setattr__(self, "paths", self._checked_paths())
        self._check_timing()
        self._check_regions()
        self._check_task()
        self._check_capacity()

    # ------------------------------------------------------------------ checks
    def _checked_paths(self) -> tuple:
        try:
            paths = tuple(
                (_point(f"CrowdScenario.paths[{i}]", a), _point(f"CrowdScenario.paths[{i}]", b))
                for i, (a, b) in enumerate(self.paths)
            )
        except (TypeError, ValueError) as exc:
            if isinstance(exc, InvalidParameterError):
                raise
            raise InvalidParameterError(
                "CrowdScenario.paths", self.paths, "must be pairs ((x0, y0), (x1, y1))", "m"
            ) from None
        if paths and len(paths) != self.pedestrians:
            raise InvalidParameterError(
                "CrowdScenario.pedestrians", self.pedestrians,
                f"must equal the number of paths ({len(paths)})",
            )  # fmt: skip
        return paths

    def _check_timing(self) -> None:
        if self.horizon is not None and self.horizon < self.sample_time:
            raise InvalidParameterError(
                "CrowdScenario.horizon", self.horizon,
                f"must hold at least one navigation period (sample_time = {self.sample_time} s)",
                "s",
            )  # fmt: skip
        ratio = self.sample_time / self.pedestrian_step
        if not math.isfinite(ratio) or abs(ratio - round(ratio)) > 1e-6 or round(ratio) < 1:
            raise InvalidParameterError(
                "CrowdScenario.pedestrian_step", self.pedestrian_step,
                f"must divide the sample time {self.sample_time} s into whole steps", "s",
            )  # fmt: skip
        if self.max_desired_speed < self.desired_speed:
            raise InvalidParameterError(
                "CrowdScenario.max_desired_speed", self.max_desired_speed,
                f"must be >= desired_speed = {self.desired_speed} m/s", "m/s",
            )  # fmt: skip

    def _check_regions(self) -> None:
        if self.region_sizing == "closing_speed" and self.active_radius is not None:
            raise InvalidParameterError(
                "CrowdScenario.active_radius", self.active_radius,
                "must be None with region_sizing='closing_speed' (the active radius is sized "
                "from each pedestrian's closing speed)", "m",
            )  # fmt: skip
        r2, r3 = self.pedestrian_regions()
        if r2 <= r3:
            raise InvalidParameterError(
                "CrowdScenario.active_radius",
                r2,
                f"must exceed the critical radius {r3:.4g} m",
                "m",
            )
        if self.layout == "bottleneck":
            w3 = self.wall_regions()[1]
            if self.bottleneck_width <= 2 * w3:
                raise InvalidParameterError(
                    "CrowdScenario.bottleneck_width", self.bottleneck_width,
                    f"must exceed the two walls' critical distances 2 r3 = {2 * w3:.3f} m: no "
                    "path through a narrower gap stays outside both (Zeng 2011, Sec. 6.4.3)",
                    "m",
                )  # fmt: skip

    def _check_task(self) -> None:
        area = self.geometry.area
        for name in ("start", "goal"):
            p = self.robot_start if name == "start" else self.robot_goal
            if not area.covers(Point(p)):
                raise InvalidParameterError(
                    f"CrowdScenario.{name}", p, "must lie in the walkable area", "m"
                )
        _, w3 = self.wall_regions()
        for w in self.walls():
            d = float(w.contour_distance(np.array([self.robot_goal]))[0])
            if d <= w3:
                raise InvalidParameterError(
                    "CrowdScenario.goal", self.robot_goal,
                    f"lies inside the critical region of {w.name!r} (distance {d:.3f} m <= "
                    f"r3 = {w3:.3f} m): widen the layout or move the goal", "m",
                )  # fmt: skip
            d = float(w.contour_distance(np.array([self.robot_start]))[0])
            if d <= self.robot.radius:
                raise InvalidParameterError(
                    "CrowdScenario.start", self.robot_start, f"overlaps {w.name!r}", "m"
                )

    def _check_capacity(self) -> None:
        if self.paths:
            return
        if self.density is not None and self.pedestrians != round(self.density * self.area_m2):
            raise InvalidParameterError(
                "CrowdScenario.pedestrians", self.pedestrians,
                f"must be density x area = {round(self.density * self.area_m2)} for density "
                f"{self.density} on {self.area_m2:.1f} m^2 (build it with crowd(density=...))",
            )  # fmt: skip
        cap = self.capacity()
        if self.pedestrians > cap:
            area = self.placement_area().area
            name = "density" if self.density is not None else "pedestrians"
            value = self.density if self.density is not None else self.pedestrians
            raise InvalidParameterError(
                f"CrowdScenario.{name}", value,
                f"the {area:.1f} m^2 free area holds at most {cap} pedestrians "
                f"({cap / area:.2f} persons/m^2 at a spacing of "
                f"{2 * self.pedestrian_radius + PLACEMENT_GAP:.2f} m)",
            )  # fmt: skip

    # ---------------------------------------------------------------- geometry
    @cached_property
    def geometry(self) -> Layout:
        """The :class:`~designlab.navigation.crowds.layouts.Layout`, shifted to ``origin``."""
        from shapely.affinity import translate

        lay = build_layout(
            self.layout, length=self.length, width=self.width,
            bottleneck_width=self.bottleneck_width,
        )  # fmt: skip
        ox, oy = self.origin

        def sh(p: tuple[float, float]) -> tuple[float, float]:
            return (p[0] + ox, p[1] + oy)

        return Layout(
            translate(lay.area, ox, oy),
            tuple((sh(a), sh(b)) for a, b in lay.walls),
            tuple(
                replace(s, spawn=translate(s.spawn, ox, oy), exit=translate(s.exit, ox, oy))
                for s in lay.streams
            ),
            sh(lay.start),
            sh(lay.goal),
        )

    @property
    def robot_start(self) -> Point2:
        """The robot's start, m."""
        return self.start if self.start is not None else self.geometry.start

    @property
    def robot_goal(self) -> Point2:
        """The robot's goal, m."""
        return self.goal if self.goal is not None else self.geometry.goal

    @property
    def free_run_time(self) -> float:
        """The robot's free-run time, s: the shortest time from rest at the start to rest at
        the goal along the straight line, at its speed and acceleration limits,
        |goal - start| / V_mr + V_mr / a_mr (no pedestrian, no gains: a property of the task).
        """
        r = self.robot
        (x0, y0), (x1, y1) = self.robot_start, self.robot_goal
        d = math.hypot(x1 - x0, y1 - y0)
        v, a = r.max_speed, r.max_accel
        return d / v + v / a if d >= v * v / a else 2.0 * math.sqrt(d / a)

    @property
    def time_limit(self) -> float:
        """The simulated time limit, s: ``horizon``, else ``horizon_factor`` x
        :attr:`free_run_time` (capped at the largest horizon)."""
        if self.horizon is not None:
            return float(self.horizon)
        return min(self.horizon_factor * self.free_run_time, MAX_HORIZON)

    @property
    def area_m2(self) -> float:
        return float(self.geometry.area.area)

    def placement_area(self) -> Any:
        """Where pedestrians are placed at t = 0: the walkable area without the exits and
        the disc of radius r3 + rho_p around the robot's start."""
        lay = self.geometry
        r3 = self.pedestrian_regions()[1]
        holes = [s.exit for s in lay.streams] + [
            Point(self.robot_start).buffer(r3 + self.pedestrian_radius)
        ]
        return lay.area.difference(unary_union(holes))

    def capacity(self) -> int:
        """Most pedestrians the random placement holds (:data:`PLACEMENT_FILL` of the area)."""
        s = 2 * self.pedestrian_radius + PLACEMENT_GAP
        return int(PLACEMENT_FILL * self.placement_area().area / (math.pi * s * s / 4))

    # ----------------------------------------------------------------- regions
    def pedestrian_regions(self) -> tuple[float, float]:
        """(r2, r3) of a pedestrian, centre distances in m (sized unless adopted)."""
        s = region_sizes(
            Human(radius=self.pedestrian_radius, max_speed=self.max_desired_speed),
            self.robot, self.sample_time,
        )  # fmt: skip
        r3 = self.critical_radius if self.critical_radius is not None else s.r3
        r2 = self.active_radius if self.active_radius is not None else s.r2
        if self.critical_radius is not None and self.active_radius is None:
            r2 = max(r2, r3 + 1e-6)
        return float(r2), float(r3)

    def wall_regions(self) -> tuple[float, float]:
        """(r2, r3) of a wall, from its contour in m (the rectangle sizing with B = 0)."""
        s = region_sizes(
            RectangularObstacle(length=1.0, width=0.2, offset=0.0), self.robot, self.sample_time
        )
        return float(s.r2), float(s.r3)

    def walls(self) -> tuple[Rectangle, ...]:
        """The walls as the robot's static rectangles."""
        r2, r3 = self.wall_regions()
        return tuple(
            Rectangle.from_corners(f"wall_{i}", [a, (b[0], a[1]), b, (a[0], b[1])], r2=r2, r3=r3)
            for i, (a, b) in enumerate(self.geometry.walls)
        )

    def pedestrian_geometry(self) -> ObstacleGeometry:
        """The compiled step's geometry of one pedestrian slot."""
        r2, r3 = self.pedestrian_regions()
        return ObstacleGeometry(
            "disc", r2, r3, moving=True, r2_input=self.region_sizing == "closing_speed"
        )

    def closing_speed_sizing(self) -> Any:
        """The :class:`~designlab.navigation.crowds.regions.ClosingSpeedSizing` of the
        pedestrians (used when ``region_sizing="closing_speed"``)."""
        return closing_speed_sizing(self)

    def robot_scenario(self) -> Scenario:
        """The robot's task with the walls alone (the nominal run has no pedestrians)."""
        return Scenario(
            f"{self.layout} (walls)", self.robot_start, self.robot_goal, self.walls(),
            self.robot, self.time_limit, self.sample_time,
        )  # fmt: skip

    def replace(self, **changes: Any) -> CrowdScenario:
        """Copy with fields changed (validated again)."""
        return replace(self, **changes)


def check_crowd_options(
    options: Any, name: str = "options", reserved: tuple[str, ...] = ()
) -> None:
    """Refuse a keyword that is not a field of :class:`CrowdScenario` (naming the allowed ones).

    Parameters
    ----------
    options
        The keywords given (a mapping).
    name
        How the error names them (``"crowd_options"`` in a study).
    reserved
        Fields set otherwise (by a study's grid), refused too.

    Examples
    --------
    >>> check_crowd_options({"lenght": 8.0})
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: options = 'lenght' is not allowed: is not a ...
    """
    if not isinstance(options, Mapping):
        raise InvalidParameterError(name, options, "must be a mapping of CrowdScenario fields")
    allowed = [f.name for f in fields(CrowdScenario) if f.name not in reserved]
    for key in options:
        if key not in allowed:
            raise InvalidParameterError(
                name, key, f"is not a keyword of navigation.crowd(); allowed: {', '.join(allowed)}"
            )


def crowd(
    layout: str,
    pedestrians: int | None = None,
    *,
    density: float | None = None,
    width: float = 4.0,
    length: float = 30.0,
    seed: int = ARG.seed.default,
    model: str = "collision_free_speed",
    react_to_robot: bool = False,
    **options: Any,
) -> CrowdScenario:
    """A crowd scenario by layout name.

    Parameters
    ----------
    layout
        ``"corridor_counterflow"``, ``"crossing"``, ``"bottleneck"`` or ``"open_plaza"``.
    pedestrians
        How many pedestrians (default 40 when ``density`` is not given either).
    density
        Persons per m^2 of walkable area instead of a number (not both).
    width, length
        W and L of the layout in m.
    seed
        Seed of the placement, the streams and the desired speeds.
    model
        ``"collision_free_speed"``, ``"generalized_centrifugal_force"``, ``"social_force"``
        or ``"anticipation_velocity"`` (JuPedSim's models).
    react_to_robot
        ``False``: the pedestrians ignore the robot (the thesis's worst case); ``True``:
        they avoid it (see :mod:`designlab.navigation.crowds.pedestrians`).
    **options
        Any other field of :class:`CrowdScenario`.

    Returns
    -------
    CrowdScenario

    Examples
    --------
    >>> c = crowd("bottleneck", 30, width=4.0, length=20.0, seed=3)
    >>> c.layout, c.pedestrians, round(c.area_m2, 1)
    ('bottleneck', 30, 77.6)
    >>> crowd("corridor_counterflow", 0)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: CrowdScenario.pedestrians = 0 is not allowed: ...
    """
    if isinstance(layout, str) and layout not in LAYOUTS:
        raise InvalidParameterError("layout", layout, f"must be one of {tuple(LAYOUTS)}")
    check_crowd_options(options)
    if density is not None:
        if pedestrians is not None:
            raise InvalidParameterError(
                "density", density, "give either pedestrians or density, not both"
            )
        rho = DENSITY.check(density)
        area = CrowdScenario(layout, 1, width, length, **{**options, "paths": ()}).area_m2
        pedestrians = round(rho * area)
        if pedestrians < 1:
            raise InvalidParameterError(
                "density", density, f"gives no pedestrian on the {area:.1f} m^2 area", "1/m^2"
            )
        options["density"] = rho
    return CrowdScenario(
        layout, 40 if pedestrians is None else pedestrians, width, length, seed, model,
        react_to_robot, **options,
    )  # fmt: skip
