"""Simulate a Sec. 5.7 planner: velocity obstacles, ERRT or Field D* (Zeng 2011, Sec. 5.7).

The robot is the holonomic point mass of Ch. 6: each navigation period T_s the planner
sees the obstacles where they are (and, for velocity obstacles, how fast they move),
plans and commands a velocity, which the robot tracks at its acceleration limit
(norm-clipped, as the force-field methods, ``docs/navigation.md``) with a 10 ms step.
Arrival, minimum distances, critical-region entries and collisions are measured as for
:func:`designlab.navigation.simulate`; a run goes on after a collision (the thesis's
Figs. 5.11-5.12 show the collision) and stops at arrival or the horizon.

Examples
--------
>>> from designlab import navigation as nav
>>> r = simulate_planner(nav.configuration(1), "vo")
>>> r.arrived, r.collided
(True, False)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.navigation import methods
from designlab.navigation.criteria import Criteria, criteria
from designlab.navigation.dynamics import HOLONOMIC_FEEDFORWARD
from designlab.navigation.parameters import (
    ARRIVAL_TOLERANCE,
    DYNAMICS_STEP,
    HolonomicRobot,
    NonholonomicRobot,
)
from designlab.navigation.planners.world import Snapshot
from designlab.navigation.scenarios import Scenario
from designlab.params import check_size
from designlab.progress import Progress, ProgressHook, report
from designlab.results import Result, Status
from designlab.validation import real_array

__all__ = [
    "PlannerResult",
    "PlannerStatus",
    "simulate_planner",
    "wheel_energy",
]

Array = NDArray[np.float64]
_STEP = 0.01


class PlannerStatus(Status):
    """Status of a planner run: ``OK`` (arrived) or ``NOT_ARRIVED`` (collisions are warnings)."""

    OK = "ok"
    NOT_ARRIVED = "not_arrived"


@dataclass(frozen=True)
class PlannerResult(Result):
    """One planner run.

    Attributes
    ----------
    scenario, method, settings
        What was simulated.
    arrival_time
        First time within ``arrival_tolerance`` of the goal (s); inf if never.
    min_distance
        Minimum centre distance per obstacle (contour distance for rectangles), m.
    collision_time
        Obstacle name -> first time of contact (s; inf: none).
    critical_entries
        Obstacle name -> whether the robot entered its critical region (d <= r3).
    criteria
        H_T, H_D, H_E, H (Sec. 5.6) against the planner's own obstacle-free run.
    energy
        L_energy per ohm of the feed-forward wheel currents (:func:`wheel_energy`).
    t, position, velocity, obstacle_positions
        Trajectories at every 10 ms step (obstacles ``n_obs x len(t) x 2``).
    status
        ``"ok"`` (arrived) or ``"not_arrived"`` (:class:`PlannerStatus`; collisions are
        warnings).
    warnings
        What a user should know about the run (collisions, no arrival within the horizon).
    stabilising
        Always ``"off"``: a planner has no stabilising force (as in a navigation result).
    stability
        Always ``None``: a planner has no Lyapunov audit.
    """

    scenario: Scenario
    method: str
    settings: Any
    arrival_time: float
    min_distance: dict[str, float]
    collision_time: dict[str, float]
    critical_entries: dict[str, bool]
    criteria: Criteria | None
    energy: float
    t: Array = field(repr=False)
    position: Array = field(repr=False)
    velocity: Array = field(repr=False)
    obstacle_positions: Array = field(repr=False)
    status: str = PlannerStatus.OK
    warnings: tuple[str, ...] = ()

    #: A planner has no stabilising force and no Lyapunov audit (read like a NavigationResult).
    stabilising: str = "off"
    stability: None = None

    @property
    def arrived(self) -> bool:
        return math.isfinite(self.arrival_time)

    @property
    def entered_critical(self) -> bool:
        return any(self.critical_entries.values())

    @property
    def distance(self) -> Array:
        """Distance to each obstacle at every step, ``n_obs x len(t)`` (m)."""
        rows = [
            o.contour_distance(self.position) if o.kind == "rectangle"
            else np.hypot(*(self.position - self.obstacle_positions[i]).T)
            for i, o in enumerate(self.scenario.obstacles)
        ]  # fmt: skip
        return np.asarray(rows).reshape(len(rows), len(self.t))

    @property
    def collided(self) -> bool:
        return any(math.isfinite(t) for t in self.collision_time.values())

    @property
    def first_collision(self) -> float:
        """Time of the first contact with any obstacle (s; inf: none)."""
        return min(self.collision_time.values(), default=math.inf)

    def to_frame(self) -> pd.DataFrame:
        """One row: scenario, method, arrival, distances, collision times."""
        row: dict[str, Any] = {"scenario": self.scenario.name, "method": self.method,
                               "T_arrive_s": self.arrival_time}  # fmt: skip
        for n, d in self.min_distance.items():
            row[f"d_{n}_min_m"] = d
        row["entered_critical"] = any(self.critical_entries.values())
        row["collided"] = self.collided
        row["first_collision_s"] = self.first_collision
        if self.criteria is not None:
            c = self.criteria
            row |= {"H_T": c.H_T, "H_D": c.H_D, "H_E": c.H_E, "H": c.H}
        return pd.DataFrame([row])


def wheel_energy(robot: Any, velocity: Array, dt: float = _STEP) -> float:
    """L_energy per ohm of the omni-wheel feed-forward currents (App. D, (D.1.2), (D.3.2)).

    The same model as the force-field simulations (constant heading, K_amp = 1 A/V):
    u_i = J/K w_i' + B/K w_i + tau/K sgn(w_i) with w_i = R_i . v / r_w, summed u_i^2 dt.

    Parameters
    ----------
    robot
        The robot (:class:`~designlab.navigation.HolonomicRobot` or
        :class:`~designlab.navigation.NonholonomicRobot`); its wheel radius r_w (m) is used.
    velocity
        The robot's velocity at every step, ``(n, 2)`` (m/s).
    dt
        The time step between the velocities (s; default the 10 ms simulation step).

    Examples
    --------
    >>> from designlab.navigation import HolonomicRobot
    >>> wheel_energy(HolonomicRobot(), np.zeros((5, 2)))
    0.0
    """
    if not isinstance(robot, HolonomicRobot | NonholonomicRobot):
        raise InvalidParameterError("robot", robot, "must be a HolonomicRobot or NonholonomicRobot")
    velocity = real_array("velocity", velocity, "m/s")
    if velocity.ndim != 2 or velocity.shape[1] != 2:
        raise InvalidParameterError("velocity", velocity.shape, "must have shape (n, 2)", "m/s")
    dt = DYNAMICS_STEP.check(dt, "dt")
    s3 = math.sqrt(3.0) / 2.0
    rows = np.array([(-s3, -0.5), (s3, -0.5), (0.0, 1.0)]) / robot.wheel_radius
    w = velocity @ rows.T  # (n, 3) wheel speeds
    wd = np.diff(w, axis=0, prepend=w[:1]) / dt
    ff = np.asarray(HOLONOMIC_FEEDFORWARD)
    u = ff[:, 0] * wd + ff[:, 1] * w + ff[:, 2] * np.sign(w)
    return float(np.sum(u[1:] ** 2) * dt)


def _commander(scenario: Scenario, planner: Any, settings: Any) -> Callable[..., Array]:
    """The planner as ``command(world, position, velocity) -> velocity``."""
    robot, goal = scenario.robot, np.asarray(scenario.goal)

    def toward(p: Array, target: Array) -> Array:
        e, dist = goal - p, float(np.hypot(*(goal - p)))
        d = target - p
        n = float(np.hypot(*d))
        speed = min(robot.max_speed, math.sqrt(2 * robot.max_accel * dist))
        return d / n * speed if n > 1e-12 else np.zeros(2) * e

    return planner.commander(scenario, settings, toward)


def simulate_planner(
    scenario: Scenario,
    method: str,
    settings: Any = None,
    *,
    arrival_tolerance: float = ARRIVAL_TOLERANCE.default,
    progress: ProgressHook | None = None,
) -> PlannerResult:
    """Simulate one scenario with a Sec. 5.7 planner.

    Parameters
    ----------
    scenario
        A holonomic-robot scenario (a nonholonomic robot is simulated as holonomic).
    method
        ``"vo"``, ``"nlvo"`` (the non-linear VO), ``"errt"`` or ``"field_dstar"``: a
        planner of :data:`designlab.navigation.methods.METHODS`
        (:data:`~designlab.navigation.methods.PLANNER`).
    settings
        The planner's ``settings_type``:
        :class:`~designlab.navigation.planners.parameters.VOSettings` (``"vo"``,
        ``"nlvo"``), :class:`~designlab.navigation.planners.parameters.ERRTSettings` or
        :class:`~designlab.navigation.planners.parameters.FieldDStarSettings` (default:
        their defaults).
    arrival_tolerance
        Arrival radius around the goal (m).
    progress
        Called after each navigation period.
    """
    planner = methods.METHODS.get(method, planner=True)
    name = planner.name
    settings = planner.settings(settings)
    if not isinstance(scenario, Scenario):
        raise InvalidParameterError("scenario", scenario, "must be a Scenario")
    tol = ARRIVAL_TOLERANCE.check(arrival_tolerance)
    n = round(scenario.horizon / _STEP)
    check_size("horizon", scenario.horizon, n * 4.0 * (1 + len(scenario.obstacles)))
    planner.check_run(scenario, settings, n, _STEP)
    run = _run(scenario, name, settings, _commander(scenario, planner, settings), n, tol,
               progress)  # fmt: skip
    free = scenario.without_obstacles()
    nominal = _run(free, name, settings, _commander(free, planner, settings), n, tol,
                   None)  # fmt: skip
    rho = scenario.robot.radius
    crit = criteria(
        arrival_time=run.arrival_time,
        nominal_arrival_time=nominal.arrival_time,
        energy=run.energy,
        nominal_energy=nominal.energy,
        surface_clearance={o.name: run.min_distance[o.name] - o.collision_distance(rho)
                           for o in scenario.obstacles},
        nominal_clearance={o.name: o.r2 - o.collision_distance(rho) for o in scenario.obstacles},
    )  # fmt: skip
    return replace(run, criteria=crit, warnings=run.warnings + _robot_warnings(scenario))


def _robot_warnings(scenario: Scenario) -> tuple[str, ...]:
    """Say so when the planners' holonomic point model stands in for the scenario's robot."""
    if isinstance(scenario.robot, NonholonomicRobot):
        return ("the planners move a holonomic robot (velocity commands in any direction); this "
                "scenario's nonholonomic robot was simulated as holonomic with its speed and "
                "acceleration limits (docs/navigation_planners.md)",)  # fmt: skip
    return ()


def _run(scenario: Scenario, name: str, settings: Any, command: Callable[..., Array], n: int,
         tol: float, progress: ProgressHook | None) -> PlannerResult:  # fmt: skip
    robot, goal = scenario.robot, np.asarray(scenario.goal)
    hold = max(1, round(scenario.sample_time / _STEP))
    t = np.arange(n + 1) * _STEP
    obs = np.stack([o.state(t)[0] for o in scenario.obstacles]) if scenario.obstacles else (
        np.zeros((0, n + 1, 2)))  # fmt: skip
    pos, vel = np.zeros((n + 1, 2)), np.zeros((n + 1, 2))
    pos[0] = scenario.start
    cmd, arrival, last = np.zeros(2), math.inf, n
    for k in range(n):
        if k % hold == 0:
            cmd = command(Snapshot.of(scenario, t[k]), pos[k], vel[k])
            report(progress, Progress(k // hold + 1, n // hold + 1, label=name))
        dv = cmd - vel[k]
        dn = float(np.hypot(*dv))
        cap = robot.max_accel * _STEP
        vel[k + 1] = vel[k] + (dv if dn <= cap else dv / dn * cap)
        sp = float(np.hypot(*vel[k + 1]))
        if sp > robot.max_speed:
            vel[k + 1] *= robot.max_speed / sp
        pos[k + 1] = pos[k] + vel[k + 1] * _STEP
        if np.hypot(*(pos[k + 1] - goal)) <= tol:
            arrival, last = float(t[k + 1]), k + 1
            break
    return _summary(scenario, name, settings, t[: last + 1], pos[: last + 1], vel[: last + 1],
                    obs[:, : last + 1], arrival)  # fmt: skip


def _summary(scenario: Scenario, name: str, settings: Any, t: Array, pos: Array, vel: Array,
             obs: Array, arrival: float) -> PlannerResult:  # fmt: skip
    rho = scenario.robot.radius
    mind, coll, crit = {}, {}, {}
    for i, o in enumerate(scenario.obstacles):
        if o.kind == "rectangle":
            d = o.contour_distance(pos)
        else:
            d = np.hypot(*(pos - obs[i]).T)
        touch = np.flatnonzero(d <= o.collision_distance(rho))
        mind[o.name] = float(d.min())
        coll[o.name] = float(t[touch[0]]) if touch.size else math.inf
        crit[o.name] = bool(d.min() <= o.r3)
    warnings = [f"collision with {k!r} at t = {v:.2f} s" for k, v in coll.items() if v < math.inf]
    if not math.isfinite(arrival):
        warnings.append(f"the robot did not reach the goal within {scenario.horizon} s")
    return PlannerResult(
        scenario=scenario, method=name, settings=settings, arrival_time=arrival,
        min_distance=mind, collision_time=coll, critical_entries=crit, criteria=None,
        energy=wheel_energy(scenario.robot, vel), t=t, position=pos,
        velocity=vel, obstacle_positions=obs,
        status=PlannerStatus.OK if math.isfinite(arrival) else PlannerStatus.NOT_ARRIVED,
        warnings=tuple(warnings),
    )  # fmt: skip
