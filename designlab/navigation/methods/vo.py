"""Velocity obstacles, linear (Fiorini & Shiller 1998) and non-linear (Large, Laugier &
Shiller 2005), Sec. 5.7 planners: each period the robot picks the admissible velocity
closest to the one toward the goal outside every obstacle's velocity obstacle over the
horizon (:func:`designlab.navigation.planners.velocity_obstacle.choose_velocity`;
``docs/navigation_planners.md``).

Examples
--------
>>> from designlab.navigation.methods import METHODS
>>> m = METHODS.get("nlvo")
>>> m.planner, m.nonlinear, m.settings(None).horizon
(True, True, 3.0)
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from designlab.navigation.methods.base import Planner
from designlab.navigation.planners.parameters import VOSettings
from designlab.navigation.planners.velocity_obstacle import choose_velocity

__all__ = ["NLVO", "VO", "VelocityObstacle"]


class VelocityObstacle(Planner):
    """The velocity-obstacle planner, linear or non-linear.

    Parameters
    ----------
    name, label, doc
        As for :class:`~designlab.navigation.methods.base.NavigationMethod`.
    nonlinear
        The non-linear VO: the obstacles' trajectories extrapolated with their
        accelerations, not at constant velocity.
    """

    settings_type = VOSettings

    def __init__(self, name: str, label: str, doc: str = "", *, nonlinear: bool) -> None:
        super().__init__(name, label, doc)
        self.nonlinear = bool(nonlinear)

    def commander(
        self, scenario: Any, settings: Any, toward: Callable[[Any, Any], Any]
    ) -> Callable[..., Any]:
        robot, goal, ts = scenario.robot, np.asarray(scenario.goal), scenario.sample_time
        return lambda w, p, v: choose_velocity(
            w, p, v, goal, max_speed=robot.max_speed, max_accel=robot.max_accel, period=ts,
            settings=settings, nonlinear=self.nonlinear,
        )  # fmt: skip


#: The linear velocity obstacle (``method="vo"``).
VO = VelocityObstacle("vo", "VO", "velocity obstacles (Fiorini & Shiller 1998)", nonlinear=False)
#: The non-linear velocity obstacle (``method="nlvo"``).
NLVO = VelocityObstacle(
    "nlvo", "NLVO", "non-linear velocity obstacles (Large et al. 2005)", nonlinear=True
)
