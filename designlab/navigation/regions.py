"""Active- and critical-region sizing (Zeng 2011, Sec. 5.3, 6.3, 7.4, 7.5.5).

The worst case is a head-on (collinear) approach at full speed with one sampling
period T_s of reaction delay. The critical radius r3 lets the robot stop before
contact; the active radius r2 lets it sidestep by r3 before the obstacle arrives.
Every intermediate of the derivation is returned so a report can show it.

Examples
--------
>>> import designlab as dl
>>> nav = dl.navigation
>>> s = nav.region_sizes(obstacle=nav.Human(radius=0.4, max_speed=1.0),
...                      robot=nav.HolonomicRobot(radius=0.2, max_speed=0.7, max_accel=10.0),
...                      sample_time=0.06)
>>> round(s.robot_stopping_distance, 4), round(s.r3, 4), round(s.r2, 3)
(0.0665, 0.7965, 2.096)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

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
)
from designlab.params import Param
from designlab.results import OK, Result

__all__ = ["RegionSizes", "region_sizes"]

Obstacle = Human | CircularObstacle | ObstacleRobot | RectangularObstacle
Robot = HolonomicRobot | NonholonomicRobot


@dataclass(frozen=True)
class RegionSizes(Result):
    """Minimum region sizes and every intermediate of their derivation.

    Radii are centre-to-centre for discs and from the contour for rectangles.
    ``r3`` is the critical radius used for the sidestep (the minimum, or the
    ``critical_radius`` the caller adopted); ``r2`` is the minimum active radius
    for that r3.

    Attributes
    ----------
    obstacle_kind
        ``"disc"`` or ``"rectangle"``.
    stopping_time
        Delta t1 = V_mr / a_mr (s) (5.3.2).
    accel_time
        t_a = V_mr / a_mr, time to reach full lateral speed (s) (5.3.6).
    robot_stopping_distance
        delta_r1 = V_mr T_s + a_mr Delta t1^2 / 2 (m) (5.3.1).
    obstacle_advance
        delta_o1 = V_o (Delta t1 + T_s), the obstacle's advance while the robot stops (m).
    r3_hat
        Minimum stopping distance r^3 = delta_o1 + delta_r1 (m) (5.3.1, 5.3.11a).
    r3_min
        Minimum critical radius: r^3 + rho_o + rho_r (discs, (5.3.3)/(5.3.8a)/(7.5.1)),
        r^3 + rho_r (rectangles, (5.3.11b)).
    r3
        Critical radius used downstream (``r3_min`` unless adopted larger).
    offset
        B for rectangles (m), 0 for discs.
    sidestep_time
        Minimum Delta t2 = (r3 + B - a t_a^2 / 2) / V_mr + t_a (s) (5.3.6b, 5.3.14),
        or the adopted value.
    turn_time
        t_turn for a nonholonomic robot (s) (7.4.2), 0 for a holonomic one.
    robot_sidestep_travel
        delta_rx2 = V_mr (Delta t2 + t_turn + T_s) (m) (5.3.7).
    obstacle_sidestep_travel
        delta_ox2 = V_o (Delta t2 + t_turn + T_s) (m).
    r2
        Minimum active radius delta_ox2 + delta_rx2 (m) ((5.3.7), (5.3.8b), (5.3.12),
        (7.4.3)-(7.4.6), (7.5.3)).
    sample_time
        Sample time T_s in s used for the sizes.
    status
        Status of the sizing (``"ok"``; see :class:`designlab.results.Result`).
    warnings
        What a user should know (e.g. an adopted radius below its bound).
    """

    obstacle_kind: str
    sample_time: float
    stopping_time: float
    accel_time: float
    robot_stopping_distance: float
    obstacle_advance: float
    r3_hat: float
    r3_min: float
    r3: float
    offset: float
    sidestep_time: float
    turn_time: float
    robot_sidestep_travel: float
    obstacle_sidestep_travel: float
    r2: float
    status: str = OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """One row per quantity: ``quantity``, ``value``, ``unit``."""
        units = {
            "sample_time": "s",
            "stopping_time": "s",
            "accel_time": "s",
            "robot_stopping_distance": "m",
            "obstacle_advance": "m",
            "r3_hat": "m",
            "r3_min": "m",
            "r3": "m",
            "offset": "m",
            "sidestep_time": "s",
            "turn_time": "s",
            "robot_sidestep_travel": "m",
            "obstacle_sidestep_travel": "m",
            "r2": "m",
        }
        return pd.DataFrame(
            {
                "quantity": list(units),
                "value": [getattr(self, k) for k in units],
                "unit": list(units.values()),
            }
        )


#: The values a user adopts instead of the minima: the arguments of :func:`region_sizes` and
#: the fields of :class:`~designlab.navigation.sizing.RegionChoice` (one declaration each).
ADOPTED_R3 = Param(
    "r_3", "m", "adopted critical radius (>= the minimum)", gt=0, le=100.0, optional=True,
    none="the minimum r3", name="critical_radius",
)  # fmt: skip
ADOPTED_SIDESTEP = Param(
    "Delta t_2", "s", "adopted sidestep time (>= the minimum)", gt=0, le=1e3, optional=True,
    none="the minimum Delta t2", name="sidestep_time",
)  # fmt: skip
ADOPTED_TURN = Param(
    "t_turn", "s", "quarter-turn time of a nonholonomic robot", gt=0, le=1e3, optional=True,
    none="sqrt(pi / omega_bar)", name="turn_time",
)  # fmt: skip
ADOPTED_R2 = Param(
    "r_2", "m", "active radius to be used (a warning if below the minimum)", gt=0, le=100.0,
    optional=True, none="the minimum r2", name="active_radius",
)  # fmt: skip


def _check_kinds(obstacle: Any, robot: Any) -> None:
    if not isinstance(robot, HolonomicRobot | NonholonomicRobot):
        raise InvalidParameterError("robot", robot, "must be a HolonomicRobot or NonholonomicRobot")
    if not isinstance(obstacle, Human | CircularObstacle | ObstacleRobot | RectangularObstacle):
        raise InvalidParameterError(
            "obstacle",
            obstacle,
            "must be a Human, CircularObstacle, ObstacleRobot or RectangularObstacle",
        )


def _adopted(name: str, value: float | None, minimum: float, unit: str) -> float:
    """The adopted value (>= the minimum), or the minimum."""
    if value is None:
        return minimum
    decl = ADOPTED_R3 if name == "critical_radius" else ADOPTED_SIDESTEP
    out = decl.check(value)
    if out < minimum - 1e-12:
        shown = f"{minimum:.4f} {unit}"
        what = "the minimum r3 = " if name == "critical_radius" else "the minimum "
        raise InvalidParameterError(name, value, f"must be >= {what}{shown}", unit)
    return out


def _turn_time(robot: Robot, turn_time: float | None) -> float:
    if isinstance(robot, NonholonomicRobot):
        return robot.turn_time if turn_time is None else ADOPTED_TURN.check(turn_time)
    if turn_time is not None:
        raise InvalidParameterError(
            "turn_time", turn_time, "applies only to a NonholonomicRobot", "s"
        )
    return 0.0


#: The vision period of the thesis's robots (16.7 Hz), for which the sizing was written.
THESIS_SAMPLE_TIME = 0.06


def _sizing_warnings(
    ts: float, stopping_time: float, r2: float, active_radius: float | None
) -> tuple[str, ...]:
    """What a user should know about a sizing (adopted r2 below its bound, a slow loop)."""
    out = []
    if active_radius is not None:
        adopted = ADOPTED_R2.check(active_radius)
        if adopted < r2:
            out.append(
                f"the adopted active radius {adopted:g} m is below the minimum {r2:.4g} m: "
                "the sidestep may not finish before the obstacle reaches the critical region"
            )
    if ts > stopping_time:
        out.append(
            f"the sample time {ts:g} s exceeds the stopping time {stopping_time:.3g} s: the "
            "reaction delay dominates the critical radius"
        )
    if ts > 2 * THESIS_SAMPLE_TIME:
        out.append(
            f"the sample time {ts:g} s is more than twice the thesis's {THESIS_SAMPLE_TIME} s "
            "(Sec. 5.3): the worst case assumes at most one period of delay, so check that "
            "the obstacles cannot change course within one period"
        )
    return tuple(out)


def region_sizes(
    obstacle: Obstacle,
    robot: Robot,
    sample_time: float,
    *,
    critical_radius: float | None = None,
    sidestep_time: float | None = None,
    turn_time: float | None = None,
    active_radius: float | None = None,
) -> RegionSizes:
    """Minimum critical and active region sizes for one obstacle class.

    Parameters
    ----------
    obstacle
        :class:`Human`, :class:`CircularObstacle`, :class:`ObstacleRobot` (moving and
        stationary discs) or :class:`RectangularObstacle` (with its offset B).
    robot
        :class:`HolonomicRobot`, or :class:`NonholonomicRobot` (adds the quarter-turn
        time to the sidestep, Sec. 7.4).
    sample_time
        Navigation (vision) period T_s in s; it acts as a reaction delay.
    critical_radius
        Adopt this r3 (m) instead of the minimum, as the thesis does (e.g. 0.4 m for
        the 0.367 m circle minimum). Must not be below the minimum.
    sidestep_time
        Adopt this Delta t2 (s), e.g. the thesis's rounded 1.18 s. Must not be below
        the minimum.
    turn_time
        Override t_turn (s) for a nonholonomic robot (the thesis uses 0.22 and 0.23 s
        where sqrt(pi/70) = 0.212 s).
    active_radius
        The r2 (m) the caller adopts; it does not change the result, but a value below
        the minimum r2 adds a warning (``None``: no check).

    Returns
    -------
    RegionSizes
        ``r3`` and ``r2`` with every intermediate.

    Raises
    ------
    InvalidParameterError
        For a non-positive sample time, a wrong obstacle/robot type, or an adopted
        value below its minimum.

    Examples
    --------
    Circle of Zeng 2011 (6.3.6)-(6.3.9), with the adopted r3 = 0.4 m:

    >>> from designlab.navigation import CircularObstacle, HolonomicRobot
    >>> s = region_sizes(CircularObstacle(0.1), HolonomicRobot(), 0.06, critical_radius=0.4)
    >>> round(s.r3_min, 3), round(s.sidestep_time, 4), round(s.r2, 3)
    (0.367, 0.6064, 0.467)

    The human's active region of (6.3.5): the thesis adopts 2.1 m, below the 2.108 m bound:

    >>> from designlab.navigation import Human
    >>> h = region_sizes(Human(), HolonomicRobot(), 0.06, critical_radius=0.8,
    ...                  sidestep_time=1.18, active_radius=2.1)
    >>> round(h.r2, 3), h.warnings[0][:40]
    (2.108, 'the adopted active radius 2.1 m is below')
    """
    ts = SAMPLE_TIME.check(sample_time)
    _check_kinds(obstacle, robot)
    v, a = robot.max_speed, robot.max_accel
    dt1 = t_a = v / a
    d_r1 = v * ts + 0.5 * a * dt1**2
    rect = isinstance(obstacle, RectangularObstacle)
    v_o = 0.0 if rect else float(obstacle.max_speed)
    d_o1 = v_o * (dt1 + ts)
    r3_hat = d_o1 + d_r1
    r3_min = r3_hat + robot.radius + (0.0 if rect else obstacle.radius)
    r3 = _adopted("critical_radius", critical_radius, r3_min, "m")
    offset = obstacle.effective_offset if rect else 0.0
    dt2_min = (r3 + offset - 0.5 * a * t_a**2) / v + t_a
    dt2 = _adopted("sidestep_time", sidestep_time, dt2_min, "s")
    t_turn = _turn_time(robot, turn_time)
    horizon = dt2 + t_turn + ts
    d_rx2 = v * horizon
    d_ox2 = v_o * horizon
    warnings = _sizing_warnings(ts, dt1, d_rx2 + d_ox2, active_radius)
    return RegionSizes(
        obstacle_kind="rectangle" if rect else "disc",
        sample_time=ts,
        stopping_time=dt1,
        accel_time=t_a,
        robot_stopping_distance=d_r1,
        obstacle_advance=d_o1,
        r3_hat=r3_hat,
        r3_min=r3_min,
        r3=r3,
        offset=offset,
        sidestep_time=dt2,
        turn_time=t_turn,
        robot_sidestep_travel=d_rx2,
        obstacle_sidestep_travel=d_ox2,
        r2=d_rx2 + d_ox2,
        warnings=warnings,
    )
