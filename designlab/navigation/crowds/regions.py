"""Pedestrians' regions in a dense crowd: the closing-speed active region (Zeng 2011, Sec. 5.3).

The thesis sizes a walking human's regions for the worst case, a head-on approach at the
human's top speed V_o (Sec. 5.3, 6.3):

* critical radius r3 = V_o (Delta t1 + T_s) + V_mr T_s + a_mr Delta t1^2 / 2 + rho_o + rho_r,
  so that the robot, braking after one period of delay, stops before the human reaches it;
* active radius r2 = (V_o + V_mr) (Delta t2 + t_turn + T_s), so that the robot can sidestep by
  r3 before a human walking at V_o straight at it arrives.

Among tens of pedestrians this freezes the robot: with V_o = 1.8 m/s every pedestrian carries
a 2.74 m active region, wider than half a 4 m corridor, whether it walks towards the robot,
beside it or away from it (``docs/navigation_crowds.md``, "Why VFF froze").

``region_sizing="closing_speed"`` keeps the critical radius r3 of the worst case (the
stopping guarantee does not depend on what a pedestrian is doing now) and sizes each
pedestrian's **active** radius from its measured velocity v_o at every navigation sample:

    c = clip(v_o . u, 0, V_o),     u = (p_robot - p_o) / |p_robot - p_o|,
    r2(c) = (c + V_mr) (Delta t2 + t_turn + T_s),

the same sidestep argument with the pedestrian's closing speed along the line of sight
instead of its top speed. The robot's part stays its worst case V_mr (it may be heading at
the pedestrian). Hence

* r2(V_o) is the thesis's r2: a pedestrian walking straight at the robot at top speed gets
  the thesis's region;
* a pedestrian walking away or beside (c = 0) gets the robot-only radius
  r2(0) = V_mr (Delta t2 + t_turn + T_s) = r3 + V_mr^2 / (2 a_mr) + V_mr (T_s + t_turn) with
  the minimum Delta t2, always above r3, and exerts no force beyond it;
* r2 grows with c, so the region of an approaching pedestrian still lets the robot sidestep
  if the pedestrian keeps its velocity over the sidestep (the thesis assumes its top speed).

What is given up: a pedestrian that turns towards the robot and speeds up within Delta t2 is
met with a smaller active region than the worst case; the critical region (and the braking
it triggers) still covers it. The radius is held over a navigation period (like every input
of the field), so the Lyapunov function's decrease (Sec. 5.5) holds within a period; at a
sample where r2 changes, V may jump.

Examples
--------
>>> import numpy as np
>>> import designlab as dl
>>> c = dl.navigation.crowd("corridor_counterflow", 4, length=12.0, region_sizing="closing_speed")
>>> s = closing_speed_sizing(c)
>>> round(s.r3, 3), round(s.active_radius(0.0), 3), round(s.active_radius(1.8), 3)
(0.7, 0.767, 2.739)
>>> P = np.array([[3.0, 2.0], [3.0, 2.0]])
>>> V = np.array([[-1.2, 0.0], [1.2, 0.0]])          # towards the robot at (1.5, 2), away
>>> s.active_radii(np.array([1.5, 2.0]), P, V).round(3).tolist()
[2.082, 0.767]
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.navigation.parameters import Human
from designlab.navigation.regions import region_sizes
from designlab.params import Param

__all__ = ["REGION_SIZING", "ClosingSpeedSizing", "closing_speed_sizing"]

Array = NDArray[np.float64]

#: How a crowd's pedestrians' regions are sized (see the module's text).
REGION_SIZING = Param(
    doc="sizing of the pedestrians' active regions", kind="choice",
    choices=("worst_case", "closing_speed"), default="worst_case", name="region_sizing",
)  # fmt: skip


@dataclass(frozen=True)
class ClosingSpeedSizing:
    """The closing-speed active radius of a crowd's pedestrians (see the module's text).

    Attributes
    ----------
    r3
        Critical radius, the thesis's worst case (centre distance, m).
    robot_speed
        V_mr, m/s.
    max_speed
        V_o, the fastest pedestrian's speed: closing speeds are clipped to it (m/s).
    sidestep_horizon
        Delta t2 + t_turn + T_s of the thesis's sizing, s.
    """

    r3: float
    robot_speed: float
    max_speed: float
    sidestep_horizon: float

    @property
    def r2_min(self) -> float:
        """Active radius of a pedestrian that does not close in (c = 0), m."""
        return self.active_radius(0.0)

    @property
    def r2_max(self) -> float:
        """Active radius at the top closing speed V_o: the thesis's r2, m."""
        return self.active_radius(self.max_speed)

    def active_radius(self, closing_speed: float) -> float:
        """r2(c) = (c + V_mr) (Delta t2 + t_turn + T_s), m, for a closing speed ``c`` (m/s)."""
        c = min(max(float(closing_speed), 0.0), self.max_speed)
        return (c + self.robot_speed) * self.sidestep_horizon

    def closing_speeds(self, robot: Array, P: Array, V: Array) -> Array:
        """Each pedestrian's speed towards the robot, clipped to [0, V_o] (m/s).

        Parameters
        ----------
        robot
            The robot's position ``(2,)``, m.
        P, V
            The pedestrians' positions and velocities ``(n, 2)``.
        """
        D = np.asarray(robot, dtype=float)[None, :] - P
        d = np.hypot(D[:, 0], D[:, 1])
        along = (V[:, 0] * D[:, 0] + V[:, 1] * D[:, 1]) / np.where(d > 0, d, 1.0)
        return np.clip(np.where(d > 0, along, self.max_speed), 0.0, self.max_speed)

    def active_radii(self, robot: Array, P: Array, V: Array) -> Array:
        """Each pedestrian's active radius r2(c), m (see :meth:`closing_speeds`)."""
        return (self.closing_speeds(robot, P, V) + self.robot_speed) * self.sidestep_horizon


def closing_speed_sizing(crowd: Any) -> ClosingSpeedSizing:
    """The closing-speed sizing of a crowd's pedestrians.

    Built from the thesis's sizing (:func:`~designlab.navigation.region_sizes`) of a
    :class:`~designlab.navigation.Human` of radius ``pedestrian_radius`` walking at
    ``max_desired_speed``, with the crowd's adopted critical radius if any.

    Parameters
    ----------
    crowd
        A :class:`~designlab.navigation.CrowdScenario`.

    Returns
    -------
    ClosingSpeedSizing
    """
    s = region_sizes(
        Human(radius=crowd.pedestrian_radius, max_speed=crowd.max_desired_speed),
        crowd.robot, crowd.sample_time, critical_radius=crowd.critical_radius,
    )  # fmt: skip
    return ClosingSpeedSizing(
        r3=float(s.r3), robot_speed=float(crowd.robot.max_speed),
        max_speed=float(crowd.max_desired_speed),
        sidestep_horizon=float(s.sidestep_time + s.turn_time + s.sample_time),
    )  # fmt: skip
