"""ERRT (Bruce & Veloso 2002), a Sec. 5.7 planner: an RRT replanned every period, biased
toward the goal and the waypoints of its last path; the robot heads for the path's first
waypoint (:func:`designlab.navigation.planners.errt.plan`; ``docs/navigation_planners.md``).

Examples
--------
>>> from designlab.navigation.methods import METHODS
>>> m = METHODS.get("errt")
>>> m.planner, m.seeded, m.settings(None).goal_bias
(True, True, 0.1)
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from designlab.navigation.methods.base import Planner
from designlab.navigation.planners import errt
from designlab.navigation.planners.parameters import ERRTSettings

__all__ = ["ERRT", "ERRTPlanner"]


class ERRTPlanner(Planner):
    """ERRT: randomised (its settings' ``seed``), replanned every navigation period."""

    settings_type = ERRTSettings
    seeded = True

    def commander(
        self, scenario: Any, settings: Any, toward: Callable[[Any, Any], Any]
    ) -> Callable[..., Any]:
        goal = np.asarray(scenario.goal)
        rng = np.random.default_rng(settings.seed)
        cache = [np.zeros((0, 2))]

        def errt_command(w: Any, p: Any, v: Any) -> Any:
            path, cache[0] = errt.plan(w, p, goal, settings, rng, cache[0])
            return toward(p, path[1])

        return errt_command


#: ERRT (``method="errt"``).
ERRT = ERRTPlanner("errt", "ERRT", "execution-extended RRT (Bruce & Veloso 2002)")
