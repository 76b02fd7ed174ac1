"""Settings of the Sec. 5.7 planners (Zeng 2011 gives none; the papers' usual values).

Examples
--------
>>> VOSettings().horizon, ERRTSettings().goal_bias, FieldDStarSettings().cell
(3.0, 0.1, 0.1)
"""

from __future__ import annotations

from dataclasses import dataclass

from designlab.errors import InvalidParameterError
from designlab.params import ARG, Param, declared, param
from designlab.validation import ParamsMixin

__all__ = ["GRID_CELLS", "PLANNED_CELLS", "ERRTSettings", "FieldDStarSettings", "VOSettings"]

#: Cells of one Field D* grid at most: each plan settles cells in plain Python (about 50 us
#: a cell), so a 200 x 200 grid takes up to 2 s a plan (docs/navigation_planners.md).
GRID_CELLS = Param(
    None, "", "cells of one Field D* grid (the scene with its margin over the cell size squared)",
    kind="integer", ge=1, le=40_000, name="grid cells",
)  # fmt: skip
#: Cells a Field D* run may plan at most (cells of the grid x plans, one a navigation period;
#: an upper bound: replanning settles only the cells whose costs changed). The committed
#: ``navigation_planners`` study bounds 5.4 million and plans in about 30 s; the bound
#: refuses runs whose every plan would settle the whole grid for longer than about 15 minutes.
PLANNED_CELLS = Param(None, "", "cells planned in one Field D* run (grid cells x plans)",
                      kind="integer", ge=1, le=20_000_000, name="planned cells")  # fmt: skip


@declared
@dataclass(frozen=True)
class VOSettings(ParamsMixin):
    """Velocity obstacles (Fiorini & Shiller 1998; Large, Laugier & Shiller 2005).

    A velocity is forbidden if, held, it brings the robot within rho_r + rho_o of an
    obstacle moving at its current velocity within ``horizon`` (the truncated VO).
    """

    horizon: float = param(
        "tau", "s", doc="time horizon of the velocity obstacle", gt=0, le=60.0, default=3.0
    )
    speeds: int = param(None, "", doc="candidate speeds (0 to V_mr)", kind="integer", ge=2,
                        le=50, default=8)  # fmt: skip
    headings: int = param(None, "", doc="candidate headings", kind="integer", ge=4, le=720,
                          default=72)  # fmt: skip


@declared
@dataclass(frozen=True)
class ERRTSettings(ParamsMixin):
    """Execution-extended RRT (Bruce & Veloso 2002, 2006), replanned every period."""

    step: float = param("epsilon", "m", doc="extension step", gt=0, le=5.0, default=0.2)
    max_nodes: int = param(None, "", doc="nodes per plan", kind="integer", ge=10, le=20_000,
                           default=800)  # fmt: skip
    goal_bias: float = param("p_goal", "", doc="probability of extending to the goal", ge=0,
                             le=1, default=0.1)  # fmt: skip
    waypoint_bias: float = param("p_waypoint", "", doc="probability of extending to a cached "
                                 "waypoint of the last plan", ge=0, le=1, default=0.6)  # fmt: skip
    margin: float = param(None, "m", doc="sampling box margin around the scene (> 0: the box of "
                          "a scene on one line has no width without it)", gt=0, le=50.0,
                          default=1.5)  # fmt: skip
    seed: int = ARG.seed.field(doc="random seed")

    def __post_init__(self) -> None:
        if not self.goal_bias + self.waypoint_bias < 1.0:
            raise InvalidParameterError(
                "ERRTSettings.goal_bias", self.goal_bias,
                f"plus waypoint_bias ({self.waypoint_bias:g}) must stay below 1: the tree must "
                "also extend to random points to explore (a tree that only heads for the goal "
                "never gets around an obstacle, and every plan spends max_nodes)",
            )  # fmt: skip


@declared
@dataclass(frozen=True)
class FieldDStarSettings(ParamsMixin):
    """Field D* on a grid (Ferguson & Stentz 2006), replanned every period."""

    cell: float = param("h", "m", doc="grid cell size", gt=0.01, le=2.0, default=0.1)
    margin: float = param(None, "m", doc="grid margin around the scene", ge=0, le=50.0,
                          default=1.5)  # fmt: skip
