"""The first-category planners of Zeng 2011, Sec. 5.7: velocity obstacles, ERRT, Field D*.

Each is built from its paper (Fiorini & Shiller 1998 / Large, Laugier & Shiller 2005;
Bruce & Veloso 2002, 2006; Ferguson & Stentz 2006) and run on the same scenarios and
robot as the force-field methods by :func:`simulate_planner`
(``docs/navigation_planners.md``).
"""

from __future__ import annotations

from designlab.navigation.planners.parameters import ERRTSettings, FieldDStarSettings, VOSettings
from designlab.navigation.planners.simulate import PlannerResult, simulate_planner

__all__ = ["ERRTSettings", "FieldDStarSettings", "PlannerResult", "VOSettings", "simulate_planner"]
