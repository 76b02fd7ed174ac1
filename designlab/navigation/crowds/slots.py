"""Many obstacles through a fixed number of slots: one compiled step serves any crowd.

The field of Zeng 2011 is a sum over the obstacles whose active region holds the robot
(d < r2); an obstacle outside it contributes exactly nothing (every term is switched off by
the active-region test, Sec. 5.4). So the compiled step (:func:`crowd_step`) is built once
for the walls and ``K`` pedestrian slots: at each navigation sample the ``K`` nearest
pedestrians within r2 fill the slots (:func:`fill_slots`), and an empty slot holds a
pedestrian parked at (1e6, 1e6) m at rest, whose force, Lyapunov terms and critical-region
flags are exactly zero. A step then costs O(K) whatever the crowd's size: the selection is
one vectorised distance test over the pedestrians, and the field, the critical-region rule
and the robot's dynamics see K + walls obstacles. More than K pedestrians in the active
region at once is counted (``CrowdResult.slot_overflow``) and warned about: the farthest
of them are then left out.

Every method of :data:`~designlab.navigation.methods.METHODS` (VFF with or without the
stabilising force, Masoud, Ge & Cui, CBF) is built on the same slots.

Examples
--------
>>> import numpy as np
>>> P = np.array([[1.0, 0.0], [5.0, 0.0], [0.5, 0.0]])
>>> obs, n_active, overflow = fill_slots(np.zeros(2), P, np.zeros((3, 2)), np.zeros((3, 2)),
...                                      r2=2.0, slots=2)
>>> obs.reshape(2, 6)[:, :2].tolist(), n_active, overflow
([[0.5, 0.0], [1.0, 0.0]], 2, False)
"""

from __future__ import annotations

from functools import lru_cache

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from designlab.navigation.dynamics import build_hold, state_size
from designlab.navigation.field import ObstacleGeometry, build_field
from designlab.navigation.parameters import HolonomicRobot, NonholonomicRobot
from designlab.navigation.recovery import critical_response

__all__ = ["PARKED", "crowd_step", "fill_slots"]

Array = NDArray[np.float64]
#: Where an empty slot's pedestrian is parked, m (outside every active region).
PARKED = 1.0e6
_OUT = ("X", "power", "F", "critical", "V", "Vdot0", "Omega", "FL")


def fill_slots(
    robot: Array, P: Array, V: Array, A: Array, *, r2: float, slots: int
) -> tuple[Array, int, bool]:
    """The slot inputs ``(6 K,)``: the ``K`` nearest pedestrians within r2, the rest parked.

    Parameters
    ----------
    robot
        The robot's position, m.
    P, V, A
        Positions, velocities, accelerations of the pedestrians ``(n, 2)`` (rows with NaN
        are not in the simulation).
    r2
        The active radius, m (centre distance).
    slots
        K.

    Returns
    -------
    tuple
        (slot inputs, pedestrians in the active region, whether they were more than K).
    """
    obs = np.zeros((slots, 6))
    obs[:, 0:2] = PARKED
    if P.shape[0] == 0:
        return obs.ravel(), 0, False
    d2 = (P[:, 0] - robot[0]) ** 2 + (P[:, 1] - robot[1]) ** 2
    inside = np.flatnonzero(d2 < r2 * r2)  # NaN rows compare False
    n = inside.size
    if n > slots:
        inside = inside[np.argpartition(d2[inside], slots - 1)[:slots]]
    inside = inside[np.argsort(d2[inside], kind="stable")]
    m = inside.size
    obs[:m, 0:2] = P[inside]
    obs[:m, 2:4] = V[inside]
    obs[:m, 4:6] = A[inside]
    return obs.ravel(), int(n), n > slots


def _field_velocity(robot: HolonomicRobot | NonholonomicRobot, x0: ca.SX) -> ca.SX:
    if isinstance(robot, HolonomicRobot):
        return x0[0:4]
    return ca.vertcat(x0[0], x0[1], x0[3] * ca.cos(x0[2]), x0[3] * ca.sin(x0[2]))


@lru_cache(maxsize=32)
def crowd_step(
    geometries: tuple[ObstacleGeometry, ...],
    robot: HolonomicRobot | NonholonomicRobot,
    method: str,
    n_sub: int,
    dt: float,
) -> ca.Function:
    """One navigation period among ``geometries`` (walls, then the slots) as one SX function.

    The same field, critical-region rule and hold as the scenario simulator's step
    (:mod:`designlab.navigation.engine`), without its distances (the crowd simulator measures
    them against every pedestrian). Inputs ``x0``, ``goal``, ``obs`` (6 per obstacle),
    ``gains``, ``params`` (mass, tie, stabilising 1/0, a_max), ``fforce`` (use, F_x, F_y: the
    CBF filter's force) and, with obstacles of ``r2_input``, ``r2`` (their active radii);
    outputs the states of the ``n_sub`` dynamics steps ``X``, the
    copper loss ``power``, the force ``F``, ``critical`` and the Lyapunov terms.

    Parameters
    ----------
    geometries
        The obstacles' constants.
    robot
        The robot.
    method
        A method of :data:`~designlab.navigation.methods.METHODS`.
    n_sub
        Dynamics steps per period.
    dt
        Dynamics step, s.
    """
    nx = state_size(robot)
    n = len(geometries)
    x0 = ca.SX.sym("x0", nx)
    goal = ca.SX.sym("goal", 2)
    obs = ca.SX.sym("obs", 6 * n)
    gains = ca.SX.sym("gains", 4)
    params = ca.SX.sym("params", 4)
    fforce = ca.SX.sym("fforce", 3)
    r2 = ca.SX.sym("r2", n)  # an input only with r2_input obstacles (after fforce)
    extra = {"r2": r2} if any(g.r2_input for g in geometries) else {}
    out = build_field(geometries, method)(
        x=_field_velocity(robot, x0), goal=goal, obs=obs, gains=gains, params=params, **extra
    )
    F = ca.if_else(fforce[0], fforce[1:3], out["F"])
    F, brake = critical_response(geometries, robot, x0, obs, F, n_sub * dt)
    ho = build_hold(robot, n_sub, dt)(x0=x0, F=F, brake=brake)
    outs = [
        ho["X"],
        ho["power"],
        F,
        out["critical"],
        out["V"],
        out["Vdot0"],
        out["Omega"],
        out["FL"],
    ]
    return ca.Function(
        f"crowd_step_{method}_{robot.kind}_{n}",
        [x0, goal, obs, gains, params, fforce, *extra.values()],
        outs,
        ["x0", "goal", "obs", "gains", "params", "fforce", *extra],
        list(_OUT),
        {"cse": True},
    )
