"""A social-force robot (Helbing, Farkas & Vicsek 2000), the field's other standard
crowd-navigation baseline: the robot moves as a pedestrian of JuPedSim's social force
model would.

Per unit mass, its acceleration is the drive to the preferred velocity (to the goal at the
speed limit, slowing to stop at it) over the reaction time tau, plus a repulsion
A/m exp((r_ij - d_ij)/B) from every pedestrian (r_ij: the two radii, d_ij: the centre
distance, along the line of centres) and A/m exp((rho_r - d_w)/B) from every wall (d_w:
the distance to its contour, away from its nearest point). The settings default to
JuPedSim's social force model (A = 2000 N, B = 0.08 m, m = 80 kg, tau = 0.5 s). Each
navigation period the robot is commanded v + a T_s (tracked at its acceleration limit).

Examples
--------
>>> import numpy as np
>>> from designlab.navigation.methods import METHODS
>>> m = METHODS.get("social_force")
>>> m.default_gains()
SocialForceSettings(strength=2000.0, range=0.08, mass=80.0, reaction_time=0.5)
>>> round(float(repulsion(np.zeros(2), np.array([[0.5, 0.0]]), 0.4, 25.0, 0.08)[0]), 6)
-7.16262
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from designlab.navigation.methods.base import CrowdController, goal_velocity
from designlab.params import declared, param

__all__ = ["SOCIAL_FORCE", "SocialForceMethod", "SocialForceSettings", "repulsion"]


@declared
@dataclass(frozen=True)
class SocialForceSettings:
    """The social force model's settings (JuPedSim's defaults, Helbing et al. 2000)."""

    strength: float = param("A", "N", doc="repulsion strength", ge=0, le=1e5, default=2000.0)
    range: float = param("B", "m", doc="repulsion range", gt=0, le=5.0, default=0.08)
    mass: float = param("m", "kg", doc="mass the repulsion acts on", gt=0, le=1e4, default=80.0)
    reaction_time: float = param("tau", "s", doc="reaction time (relaxation to the preferred "
                                 "velocity)", gt=0, le=10.0, default=0.5)  # fmt: skip


def repulsion(p: np.ndarray, P: np.ndarray, contact: float, a: float, b: float) -> np.ndarray:
    """The summed repulsion per unit mass a exp((contact - d)/b) along the unit vectors from
    the points ``P`` ``(n, 2)`` to ``p`` (m/s^2).

    Parameters
    ----------
    p
        The robot's position ``(2,)``, m.
    P
        The other centres ``(n, 2)``, m.
    contact
        The centre distance at contact (the two radii), m.
    a, b
        Strength per unit mass (m/s^2) and range (m).
    """
    if not len(P):
        return np.zeros(2)
    d = p[None, :] - P
    dist = np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-9)
    f = a * np.exp((contact - dist) / b) / dist
    return (d * f[:, None]).sum(axis=0)


class SocialForceMethod(CrowdController):
    """The social force model as the robot's controller."""

    gains_type = SocialForceSettings

    def controller(self, crowd: Any, settings: Any) -> Callable[..., np.ndarray]:
        robot = crowd.robot
        goal = np.asarray(crowd.robot_goal, dtype=float)
        a = settings.strength / settings.mass
        b, tau, ts = settings.range, settings.reaction_time, crowd.sample_time
        contact = robot.radius + crowd.pedestrian_radius
        corners = [w.corners() for w in crowd.walls()]
        boxes = np.array([[*c.min(axis=0), *c.max(axis=0)] for c in corners]).reshape(-1, 4)

        def command(p: np.ndarray, v: np.ndarray, P: np.ndarray, V: np.ndarray) -> np.ndarray:
            pref = goal_velocity(p, goal, robot.max_speed, robot.max_accel)
            acc = (pref - v) / tau + repulsion(p, P, contact, a, b)
            nearest = np.clip(p[None, :], boxes[:, 0:2], boxes[:, 2:4])  # axis-aligned walls
            acc = acc + repulsion(p, nearest, robot.radius, a, b)
            return v + acc * ts

        return command


#: The social-force robot (``method="social_force"``).
SOCIAL_FORCE = SocialForceMethod(
    "social_force", "Social force", "social force model (Helbing, Farkas & Vicsek 2000)"
)
