"""ORCA (van den Berg, Guy, Lin & Manocha 2011, "Reciprocal n-body collision avoidance"),
the field's standard crowd-navigation baseline, through RVO2's Python bindings (``pyrvo``,
in the ``crowds`` extra).

Each navigation period the robot's new velocity is ORCA's for the pedestrians as sensed
(positions and backward-difference velocities) and the walls (RVO2 obstacles): the velocity
nearest the preferred one (to the goal at the speed limit, slowing to stop at it) outside
every pedestrian's and wall's ORCA half-plane. The settings default to CrowdNav's ORCA
(Chen et al. 2019): neighbour distance 10 m, 10 neighbours, time horizons 5 s, and the
robot's disc grown by a safety space of 1 cm (ORCA's velocities keep the discs apart
exactly at contact, where rounding decides). The pedestrians are assumed to take half the
avoidance (ORCA's reciprocity), whatever they do. ORCA's linear programs switch between
constraints discontinuously: runs agree to the bit on one machine, but a last-bit
difference (another CPU's libm) can change a path.

Examples
--------
>>> from designlab.navigation.methods import METHODS
>>> m = METHODS.get("orca")
>>> m.force_field, m.crowds, m.default_gains().time_horizon
(False, True, 5.0)
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from designlab.errors import MissingExtraError
from designlab.navigation.methods.base import CrowdController, goal_velocity
from designlab.params import declared, param

__all__ = ["ORCA", "ORCAMethod", "ORCASettings"]


@declared
@dataclass(frozen=True)
class ORCASettings:
    """ORCA's settings (CrowdNav's, Chen et al. 2019)."""

    neighbor_dist: float = param("d_N", "m", doc="neighbours considered within", gt=0, le=100.0,
                                 default=10.0)  # fmt: skip
    max_neighbors: int = param("N_N", "", doc="neighbours considered at most", kind="integer",
                               ge=1, le=200, default=10)  # fmt: skip
    time_horizon: float = param("tau", "s", doc="time horizon for pedestrians", gt=0, le=60.0,
                                default=5.0)  # fmt: skip
    time_horizon_obst: float = param("tau_O", "s", doc="time horizon for walls", gt=0, le=60.0,
                                     default=5.0)  # fmt: skip
    safety_space: float = param("s_O", "m", doc="added to the robot's radius", ge=0, le=1.0,
                                default=0.01)  # fmt: skip


def _pyrvo() -> Any:
    try:
        return importlib.import_module("pyrvo")
    except ImportError as exc:
        raise MissingExtraError("pyrvo", "crowds", "the ORCA robot", str(exc)) from exc


class ORCAMethod(CrowdController):
    """ORCA through RVO2 (``pyrvo``)."""

    gains_type = ORCASettings

    def controller(self, crowd: Any, settings: Any) -> Callable[..., np.ndarray]:
        rvo = _pyrvo()
        s, robot = settings, crowd.robot
        goal = np.asarray(crowd.robot_goal, dtype=float)
        radius = robot.radius + s.safety_space
        walls = []
        for w in crowd.walls():  # RVO2 obstacles: counter-clockwise corners
            c = w.corners()
            walls.append([tuple(map(float, q)) for q in (c if _area(c) > 0 else c[::-1])])
        rho_p = crowd.pedestrian_radius
        args = (s.neighbor_dist, s.max_neighbors, s.time_horizon, s.time_horizon_obst)

        def command(p: np.ndarray, v: np.ndarray, P: np.ndarray, V: np.ndarray) -> np.ndarray:
            # a new simulator every period: RVO2 keeps no state of the last one (reusing one
            # with clear_agents gave runs that depended on the process's history)
            sim = rvo.RVOSimulator(crowd.sample_time, *args, radius, robot.max_speed)
            for w in walls:
                sim.add_obstacle(w)
            sim.process_obstacles()
            me = sim.add_agent((float(p[0]), float(p[1])), *args, radius, robot.max_speed,
                               (float(v[0]), float(v[1])))  # fmt: skip
            pref = goal_velocity(p, goal, robot.max_speed, robot.max_accel)
            sim.set_agent_pref_velocity(me, (float(pref[0]), float(pref[1])))
            for q, u in zip(P.tolist(), V.tolist(), strict=True):
                a = sim.add_agent((q[0], q[1]), *args, rho_p, max(float(np.hypot(*u)), 1e-3),
                                  (u[0], u[1]))  # fmt: skip
                sim.set_agent_pref_velocity(a, (u[0], u[1]))
            sim.do_step()
            out = sim.get_agent_velocity(me)
            return np.array([out.x, out.y])

        return command


def _area(c: Any) -> float:
    """Signed area of a polygon (> 0: counter-clockwise)."""
    x, y = np.asarray(c, dtype=float).T
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


#: ORCA through RVO2 (``method="orca"``).
ORCA = ORCAMethod("orca", "ORCA", "ORCA (van den Berg et al. 2011) through RVO2 (pyrvo)")
