"""Field D* (Ferguson & Stentz 2006), a Sec. 5.7 planner: a grid planner with interpolated
costs, replanned every period on the obstacles where they are; the robot heads for the
next point of the path (:mod:`designlab.navigation.planners.field_dstar`;
``docs/navigation_planners.md``). Its grids are bounded before a run starts.

Examples
--------
>>> from designlab.navigation.methods import METHODS
>>> m = METHODS.get("field_dstar")
>>> m.label, m.settings(None).cell
('Field D*', 0.1)
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from designlab.navigation.methods.base import Planner
from designlab.navigation.planners import field_dstar
from designlab.navigation.planners.parameters import FieldDStarSettings
from designlab.navigation.scenarios import Rectangle

__all__ = ["FIELD_DSTAR", "FieldDStarPlanner"]


class FieldDStarPlanner(Planner):
    """Field D*: deterministic; its grids over a run are bounded before it starts."""

    settings_type = FieldDStarSettings

    def check_run(self, scenario: Any, settings: Any, steps: int, step: float) -> None:
        hold = max(1, round(scenario.sample_time / step))
        t = np.arange(0, steps + 1, hold) * step
        pts = [np.asarray([scenario.start, scenario.goal], dtype=float)]
        for o in scenario.obstacles:
            pts.append(o.corners() if isinstance(o, Rectangle) else o.state(t)[0])
        field_dstar.check_grid(np.vstack(pts), 2 * t.size, settings)  # and the nominal run

    def commander(
        self, scenario: Any, settings: Any, toward: Callable[[Any, Any], Any]
    ) -> Callable[..., Any]:
        goal = np.asarray(scenario.goal)

        def dstar_command(w: Any, p: Any, v: Any) -> Any:
            nxt = field_dstar.Grid(w, p, goal, settings).next_point(p)
            return np.zeros(2) if nxt is None else toward(p, nxt)

        return dstar_command


#: Field D* (``method="field_dstar"``).
FIELD_DSTAR = FieldDStarPlanner("field_dstar", "Field D*", "Field D* (Ferguson & Stentz 2006)")
