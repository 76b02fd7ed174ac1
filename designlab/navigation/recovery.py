"""What the robot does in a critical region: brake, wait, or back out (Zeng 2011, Sec. 5.3).

In a critical region (d <= r3) the field is not used: the robot brakes at its maximum
deceleration to a stop (Sec. 5.3) and waits while an obstacle whose critical region it
is in comes closer. Once it is stopped and no such obstacle approaches (a static circle or
rectangle, a human standing or walking away), it **backs out**: it accelerates along the
outward normal of the critical regions it is in, from rest, with the constant
acceleration that carries it ``BACK_OUT_MARGIN`` beyond the deepest region's edge within
one navigation period (at most its acceleration limit); the field resumes at the next
sample. Waiting "until the obstacle leaves" alone (the first reading of the rule) never
ends for a static obstacle: the robot of Sec. 7.5.5 stopped 2 mm inside the circle's
critical region for the rest of the run, while the thesis's robot goes on
(``docs/navigation.md``, "Critical region").

Examples
--------
>>> import casadi as ca
>>> from designlab.navigation import HolonomicRobot
>>> from designlab.navigation.field import ObstacleGeometry
>>> geo = (ObstacleGeometry("disc", r2=0.8, r3=0.4),)
>>> x0, obs, F = ca.SX.sym("x0", 4), ca.SX.sym("obs", 6), ca.SX.sym("F", 2)
>>> Fo, brake = critical_response(geo, HolonomicRobot(), x0, obs, F, period=0.06)
>>> f = ca.Function("f", [x0, obs, F], [Fo, brake])
>>> Fb, b = f([0.398, 0, 0, 0], [0, 0, 0, 0, 0, 0], [-5.0, 0])   # stopped 2 mm inside
>>> float(b), round(float(Fb[0]) / 4.4 * 0.06**2 / 2, 4)   # at its 10 m/s^2 limit: 18 mm
(0.0, 0.018)
>>> float(f([0.398, 0, -0.1, 0], [0, 0, 0, 0, 0, 0], [-5.0, 0])[1])  # still moving: brakes
1.0
"""

from __future__ import annotations

import casadi as ca

from designlab.navigation.field import ObstacleGeometry, build_distance
from designlab.navigation.parameters import HolonomicRobot, NonholonomicRobot

__all__ = ["BACK_OUT_MARGIN", "STOPPED_SPEED", "critical_response"]

#: How far beyond the critical region's edge one backing-out period carries the robot, m.
BACK_OUT_MARGIN = 0.03
#: Speed below which the robot counts as stopped, m/s (braking ends at exactly 0).
STOPPED_SPEED = 1e-6
#: Rate of approach above which an obstacle counts as coming closer, m/s.
_APPROACH = 1e-9


def _speed(robot: HolonomicRobot | NonholonomicRobot, x0: ca.SX) -> ca.SX:
    if isinstance(robot, HolonomicRobot):
        return ca.sqrt(ca.sumsqr(x0[2:4]))
    return ca.fabs(x0[3])


def critical_response(
    geometries: tuple[ObstacleGeometry, ...],
    robot: HolonomicRobot | NonholonomicRobot,
    x0: ca.SX,
    obs: ca.SX,
    F: ca.SX,
    period: float,
) -> tuple[ca.SX, ca.SX]:
    """The force held over the period and the braking flag, for the critical-region rule.

    Parameters
    ----------
    geometries
        The obstacles' constants.
    robot
        The robot (its mass and acceleration limit).
    x0
        The robot's state at the sample (symbolic).
    obs
        Positions, velocities and accelerations of the obstacles (6 per obstacle).
    F
        The force of the navigation method (used outside critical regions).
    period
        The navigation period T_s in s.

    Returns
    -------
    tuple
        ``(F, brake)``: the force to hold and 1 if the robot brakes (0 otherwise).
    """
    n = len(geometries)
    if not n:
        return F, ca.SX(0)
    p = x0[0:2]
    dist = build_distance(geometries)
    op = ca.vertcat(*[obs[6 * i : 6 * i + 2] for i in range(n)])
    vo = ca.vertcat(*[obs[6 * i + 2 : 6 * i + 4] for i in range(n)])
    d = dist(p, op)
    grad_p = ca.jacobian(d, p)  # outward unit normals, one row per obstacle
    approach = ca.jtimes(d, op, vo)  # d' of a stopped robot: the obstacles' own motion
    inside = ca.SX(0)
    closing = ca.SX(0)
    direction = ca.SX.zeros(2)
    depth = ca.SX(0)
    for i, g in enumerate(geometries):
        crit = d[i] <= g.r3
        inside = ca.logic_or(inside, crit)
        closing = ca.logic_or(closing, ca.logic_and(crit, approach[i] < -_APPROACH))
        direction = direction + ca.if_else(crit, grad_p[i, :].T, ca.SX.zeros(2))
        depth = ca.fmax(depth, ca.if_else(crit, g.r3 - d[i], 0.0))
    stopped = _speed(robot, x0) <= STOPPED_SPEED
    norm = ca.sqrt(ca.sumsqr(direction))
    back_out = ca.logic_and(ca.logic_and(inside, stopped), ca.logic_not(closing))
    back_out = ca.logic_and(back_out, norm > 1e-9)
    accel = ca.fmin(robot.max_accel, 2.0 * (depth + BACK_OUT_MARGIN) / period**2)
    F_out = robot.mass * accel * direction / ca.fmax(norm, 1e-9)
    brake = ca.logic_and(inside, ca.logic_not(back_out))
    return ca.if_else(back_out, F_out, F), brake
