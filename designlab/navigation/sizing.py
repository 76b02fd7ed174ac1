"""Region sizes for a user's robot among a user's obstacles (Zeng 2011, Sec. 5.3, 7.4, 7.5.5).

:func:`size_regions` applies :func:`~designlab.navigation.region_sizes` to each named
obstacle class (a :class:`~designlab.navigation.Human`, a
:class:`~designlab.navigation.CircularObstacle`, an
:class:`~designlab.navigation.ObstacleRobot` or a
:class:`~designlab.navigation.RectangularObstacle`) with the values the user adopts
(:class:`RegionChoice`: a rounded-up r3 or Delta t2 as the thesis adopts, and the
r2 to be used), and returns every intermediate quantity, the minimum and adopted
radii and what they imply (:class:`RegionPlan`).

Examples
--------
The thesis's human and circle (Zeng 2011, (6.3.1)-(6.3.9)):

>>> from designlab.navigation import CircularObstacle, HolonomicRobot, Human
>>> plan = size_regions(HolonomicRobot(), {"human": Human(), "circle": CircularObstacle()},
...                     0.06, {"circle": RegionChoice(critical_radius=0.4, active_radius=0.8)})
>>> plan.to_frame()[["obstacle", "r3_min_m", "r2_min_m", "r3_m", "r2_m"]].round(3).values.tolist()
[['human', 0.796, 2.096, 0.796, 2.096], ['circle', 0.367, 0.467, 0.4, 0.8]]
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import pandas as pd

from designlab.errors import InvalidParameterError
from designlab.navigation.parameters import (
    SAMPLE_TIME,
    CircularObstacle,
    HolonomicRobot,
    Human,
    NonholonomicRobot,
    ObstacleRobot,
    RectangularObstacle,
    declared_field,
)
from designlab.navigation.regions import (
    ADOPTED_R2,
    ADOPTED_R3,
    ADOPTED_SIDESTEP,
    ADOPTED_TURN,
    RegionSizes,
    region_sizes,
)
from designlab.params import declared
from designlab.results import OK, Result

__all__ = ["MAX_OBSTACLES", "RegionChoice", "RegionPlan", "size_regions"]

ObstacleClass = Human | CircularObstacle | ObstacleRobot | RectangularObstacle
#: Most obstacle classes sized at once.
MAX_OBSTACLES = 100


@declared
@dataclass(frozen=True)
class RegionChoice:
    """The values a user adopts for one obstacle class (each ``None``: the minimum).

    Examples
    --------
    >>> RegionChoice(critical_radius=0.4).active_radius is None
    True
    """

    critical_radius: float | None = declared_field(ADOPTED_R3, None)
    sidestep_time: float | None = declared_field(ADOPTED_SIDESTEP, None)
    turn_time: float | None = declared_field(ADOPTED_TURN, None)
    active_radius: float | None = declared_field(ADOPTED_R2, None)


@dataclass(frozen=True)
class RegionPlan(Result):
    """The region sizes of every obstacle class for one robot.

    Attributes
    ----------
    robot
        The robot sized for.
    sample_time
        Navigation period T_s in s.
    obstacles
        Name -> the obstacle class sized.
    sizes
        Name -> :class:`~designlab.navigation.RegionSizes` (every intermediate).
    radii
        Name -> (r2, r3) to put in a scenario (the adopted values, else the minima), m.
    status, warnings
        ``"ok"``; warnings name an adopted r2 below its minimum (the robot may not
        sidestep in time in the worst case) or an r2 not above r3.
    """

    robot: HolonomicRobot | NonholonomicRobot
    sample_time: float
    obstacles: dict[str, ObstacleClass]
    sizes: dict[str, RegionSizes]
    radii: dict[str, tuple[float, float]]
    status: str = OK
    warnings: tuple[str, ...] = field(default=())

    def to_frame(self) -> pd.DataFrame:
        """One row per obstacle: every intermediate quantity (with its unit) and the radii."""
        rows = []
        for name, s in self.sizes.items():
            kind = type(self.obstacles[name]).__name__
            row: dict[str, object] = {"obstacle": name, "class": kind}
            for q, v, u in s.to_frame().itertuples(index=False):
                key = {"r3": "r3_used", "r2": "r2_min"}.get(q, q)
                row[f"{key}_{u}"] = v
            r2, r3 = self.radii[name]
            row |= {"r3_m": r3, "r2_m": r2, "r2_margin_m": r2 - s.r2}
            rows.append(row)
        frame = pd.DataFrame(rows)
        return frame.rename(columns={"r3_used_m": "r3_sizing_m"})

    def scenario_regions(self) -> dict[str, dict[str, float]]:
        """``{name: {"r2": ..., "r3": ...}}``: the radii to put in a scenario file."""
        return {n: {"r2": r2, "r3": r3} for n, (r2, r3) in self.radii.items()}


def _check(robot: object, obstacles: Mapping[str, object], choices: object) -> None:
    if not isinstance(choices, Mapping):
        raise InvalidParameterError("choices", choices, "must map obstacle names to RegionChoice")
    if not isinstance(robot, HolonomicRobot | NonholonomicRobot):
        raise InvalidParameterError("robot", robot, "must be a HolonomicRobot or NonholonomicRobot")
    if not isinstance(obstacles, Mapping) or not 1 <= len(obstacles) <= MAX_OBSTACLES:
        raise InvalidParameterError(
            "obstacles", obstacles, f"must map 1-{MAX_OBSTACLES} names to obstacle classes"
        )
    for name, c in choices.items():
        if name not in obstacles:
            raise InvalidParameterError("choices", name, f"is not one of {sorted(obstacles)}")
        if not isinstance(c, RegionChoice):
            raise InvalidParameterError(f"choices[{name}]", c, "must be a RegionChoice")
    for name, o in obstacles.items():
        if not isinstance(name, str) or not name:
            raise InvalidParameterError("obstacles", name, "names must be non-empty texts")
        if not isinstance(o, ObstacleClass):
            raise InvalidParameterError(
                f"obstacles[{name!r}]", o,
                "must be a Human, CircularObstacle, ObstacleRobot or RectangularObstacle",
            )  # fmt: skip


def size_regions(
    robot: HolonomicRobot | NonholonomicRobot,
    obstacles: Mapping[str, ObstacleClass],
    sample_time: float,
    choices: Mapping[str, RegionChoice] | None = None,
) -> RegionPlan:
    """Size the critical and active regions of every obstacle class for one robot.

    Parameters
    ----------
    robot
        The robot (its radius and limits; a nonholonomic robot adds its quarter turn).
    obstacles
        Name -> :class:`Human`, :class:`CircularObstacle`, :class:`ObstacleRobot` or
        :class:`RectangularObstacle`.
    sample_time
        Navigation period T_s in s (the reaction delay).
    choices
        Name -> :class:`RegionChoice` (adopted r3, Delta t2, t_turn, r2); missing: minima.

    Returns
    -------
    RegionPlan

    Raises
    ------
    InvalidParameterError
        For a wrong type, or an adopted r3 or Delta t2 below its minimum.
    """
    choices = {} if choices is None else choices
    _check(robot, obstacles, choices)
    choices = dict(choices)
    sizes: dict[str, RegionSizes] = {}
    radii: dict[str, tuple[float, float]] = {}
    warnings: list[str] = []
    for name, obstacle in obstacles.items():
        c = choices.get(name, RegionChoice())
        s = region_sizes(
            obstacle,
            robot,
            sample_time,
            critical_radius=c.critical_radius,
            sidestep_time=c.sidestep_time,
            turn_time=c.turn_time,
        )
        r2 = s.r2 if c.active_radius is None else c.active_radius
        if r2 < s.r2 - 1e-12:
            warnings.append(
                f"{name}: the adopted r2 = {r2:g} m is below the minimum {s.r2:.3f} m: in the "
                "worst case (head-on at full speed) the robot cannot sidestep in time"
            )
        if r2 <= s.r3:
            warnings.append(f"{name}: r2 = {r2:g} m must exceed r3 = {s.r3:.3f} m")
        sizes[name], radii[name] = s, (r2, s.r3)
    return RegionPlan(
        robot=robot,
        sample_time=SAMPLE_TIME.check(sample_time),
        obstacles=dict(obstacles),
        sizes=sizes,
        radii=radii,
        warnings=tuple(warnings),
    )
