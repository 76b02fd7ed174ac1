"""Linear and non-linear velocity obstacles (Fiorini & Shiller 1998; Large et al. 2005).

The velocity obstacle of a disc obstacle is the set of robot velocities v that, held,
bring the robot (a point after the Minkowski sum) within R = rho_o + rho_r of the
obstacle moving at its current velocity v_o: in relative terms, the cone with apex
v_o, axis along the obstacle's direction p and half-angle asin(R / |p|). Truncated at
a time horizon tau it keeps only the collisions before tau. :func:`time_to_collision`
is exact (the root of |p - (v - v_o) t| = R). :func:`choose_velocity` is the
Fiorini-Shiller selection among the reachable velocities: the velocity outside every
obstacle's VO closest to the preferred velocity (to the goal at full speed, slowing
to stop at it), else the one that postpones the first collision longest.

Examples
--------
A head-on obstacle 2 m ahead (R = 0.6 m) at rest: full speed at it collides after
(2 - 0.6) / 0.7 = 2 s; sideways is free:

>>> import numpy as np
>>> ttc = time_to_collision(np.zeros(2), np.array([[2.0, 0.0]]), np.zeros((1, 2)),
...                         np.array([0.6]), np.array([[0.7, 0.0], [0.0, 0.7]]))
>>> ttc.round(6).tolist()
[[2.0], [inf]]
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.navigation.parameters import HolonomicRobot
from designlab.navigation.planners.parameters import VOSettings
from designlab.navigation.planners.world import Snapshot
from designlab.params import params_of

__all__ = [
    "candidate_velocities",
    "choose_velocity",
    "in_velocity_obstacle",
    "predicted_centres",
    "time_to_collision",
    "time_to_collision_nonlinear",
]

#: Time step (s) at which the NLVO samples the obstacles' predicted trajectories.
NLVO_STEP = 0.02

Array = NDArray[np.float64]
#: The speed limit of the candidates: the robot's (one declaration).
_MAX_SPEED = params_of(HolonomicRobot)["max_speed"]


def time_to_collision(
    position: Array, centres: Array, velocities: Array, radii: Array, candidates: Array
) -> Array:
    """Time (s) until each candidate velocity ``(m, 2)`` meets each disc ``(n,)`` (inf: never).

    0 if the robot is already within a disc. Exact for constant velocities.

    Parameters
    ----------
    position
        The robot's position, ``(2,)`` (m).
    centres
        The discs' centres, ``(n, 2)`` (m).
    velocities
        The discs' velocities, ``(n, 2)`` (m/s), held constant.
    radii
        The discs' radii inflated by the robot's, rho_o + rho_r, ``(n,)`` (m).
    candidates
        Candidate robot velocities, ``(m, 2)`` (m/s).
    """
    p = centres[None, :, :] - position[None, None, :]  # (1, n, 2)
    w = candidates[:, None, :] - velocities[None, :, :]  # (m, n, 2)
    a = np.einsum("mnk,mnk->mn", w, w)
    b = np.einsum("mnk,mnk->mn", p, w)
    c = np.einsum("mnk,mnk->mn", p, p) - radii[None, :] ** 2
    disc = b**2 - a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = (b - np.sqrt(np.maximum(disc, 0.0))) / a
    out = np.where((disc >= 0) & (a > 0) & (t1 >= 0), t1, np.inf)
    return np.where(c <= 0, 0.0, out)


def predicted_centres(centres: Array, velocities: Array, accelerations: Array, t: Array) -> Array:
    """Second-order extrapolation of the discs' trajectories, ``(len(t), n, 2)`` (m).

    c(t) = c + v t + a t^2 / 2, except that a disc braking (a . v < 0) stops where its
    speed along v reaches zero instead of reversing (a walker who brakes stands).

    Parameters
    ----------
    centres, velocities, accelerations
        The discs' centres (m), velocities (m/s) and accelerations (m/s^2), ``(n, 2)``.
    t
        Times from now (s), ``(k,)``.
    """
    av = np.einsum("nk,nk->n", accelerations, velocities)
    vv = np.einsum("nk,nk->n", velocities, velocities)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_stop = np.where(av < 0, vv / -av, np.inf)  # (n,)
    tt = np.minimum(t[:, None], t_stop[None, :])[:, :, None]  # (k, n, 1)
    return centres[None] + velocities[None] * tt + 0.5 * accelerations[None] * tt**2


def time_to_collision_nonlinear(
    position: Array, centres: Array, velocities: Array, accelerations: Array, radii: Array,
    candidates: Array, horizon: float,
) -> Array:  # fmt: skip
    """Time (s) until each held candidate velocity meets each disc on its predicted path.

    The non-linear velocity obstacle (Large, Laugier & Shiller 2005): v is forbidden if
    |p + v t - c(t)| < R for some t in [0, horizon], c(t) the obstacle's trajectory, here
    :func:`predicted_centres` (second order), sampled every :data:`NLVO_STEP` s; ``(m, n)``,
    inf when not within the horizon. With zero accelerations it is the linear VO's
    :func:`time_to_collision` (to the sampling step).

    Parameters
    ----------
    position
        The robot's position, ``(2,)`` (m).
    centres, velocities, accelerations
        The discs' centres (m), velocities (m/s) and accelerations (m/s^2), ``(n, 2)``.
    radii
        The discs' radii inflated by the robot's, ``(n,)`` (m).
    candidates
        Candidate robot velocities, ``(m, 2)`` (m/s).
    horizon
        Time horizon (s).
    """
    t = np.arange(0.0, horizon + 1e-9, NLVO_STEP)
    c = predicted_centres(centres, velocities, accelerations, t)  # (k, n, 2)
    robot = position[None, None, :] + candidates[:, None, :] * t[None, :, None]  # (m, k, 2)
    gap = robot[:, :, None, :] - c[None, :, :, :]  # (m, k, n, 2)
    hit = np.einsum("mknj,mknj->mkn", gap, gap) < radii[None, None, :] ** 2
    return np.where(hit.any(axis=1), t[np.argmax(hit, axis=1)], np.inf)


def in_velocity_obstacle(
    position: Array, centres: Array, velocities: Array, radii: Array, candidates: Array,
    horizon: float,
) -> Array:  # fmt: skip
    """``(m,)`` True where a candidate velocity lies in some disc's VO truncated at ``horizon``.

    Parameters
    ----------
    position
        The robot's position, ``(2,)`` (m).
    centres
        The discs' centres, ``(n, 2)`` (m).
    velocities
        The discs' velocities, ``(n, 2)`` (m/s), held constant.
    radii
        The discs' radii inflated by the robot's, rho_o + rho_r, ``(n,)`` (m).
    candidates
        Candidate robot velocities, ``(m, 2)`` (m/s).
    horizon
        Time horizon tau of the truncated velocity obstacle (s).
    """
    ttc = time_to_collision(position, centres, velocities, radii, candidates)
    return np.asarray((ttc < horizon).any(axis=1)) if ttc.size else np.zeros(len(candidates), bool)


def candidate_velocities(max_speed: float, settings: VOSettings) -> Array:
    """Rest plus ``speeds - 1`` speeds up to V_mr in ``headings`` directions, ``(m, 2)``.

    Parameters
    ----------
    max_speed
        The robot's speed limit V_mr (m/s): the largest candidate speed.
    settings
        The numbers of speeds and headings (:class:`VOSettings`).

    Examples
    --------
    >>> candidate_velocities(0.7, VOSettings(speeds=2, headings=4)).round(3).tolist()
    [[0.0, 0.0], [0.7, 0.0], [0.0, 0.7], [-0.7, 0.0], [-0.0, -0.7]]
    """
    max_speed = _MAX_SPEED.check(max_speed, "max_speed")
    if not isinstance(settings, VOSettings):
        raise InvalidParameterError("settings", settings, "must be a VOSettings")
    s = np.linspace(0.0, max_speed, settings.speeds)[1:]
    th = np.linspace(0.0, 2 * np.pi, settings.headings, endpoint=False)
    grid = (s[:, None, None] * np.stack([np.cos(th), np.sin(th)], axis=1)[None]).reshape(-1, 2)
    return np.vstack([np.zeros((1, 2)), grid])


def _static_ttc(world: Snapshot, position: Array, cand: Array, horizon: float) -> Array:
    """Time until each candidate meets a rectangle (sampled every 0.05 s)."""
    if not world.rectangles:
        return np.full(len(cand), np.inf)
    ts = np.arange(0.0, horizon + 1e-9, 0.05)
    pts = position[None, None, :] + cand[:, None, :] * ts[None, :, None]
    hit = world.clearance(pts.reshape(-1, 2)).reshape(len(cand), ts.size) <= 0
    first = np.where(hit.any(axis=1), ts[np.argmax(hit, axis=1)], np.inf)
    return first


def choose_velocity(
    world: Snapshot,
    position: Array,
    velocity: Array,
    goal: Array,
    *,
    max_speed: float,
    max_accel: float,
    period: float,
    settings: VOSettings,
    nonlinear: bool = False,
) -> Array:
    """The commanded velocity for the next period (Fiorini-Shiller, to-goal rule).

    Parameters
    ----------
    world
        The obstacles now (:class:`Snapshot`), inflated by the robot radius.
    position
        The robot's position, ``(2,)`` (m).
    velocity
        The robot's velocity, ``(2,)`` (m/s): the centre of the reachable velocities.
    goal
        The goal position, ``(2,)`` (m).
    max_speed
        The robot's speed limit V_mr (m/s).
    max_accel
        The robot's acceleration limit a_mr (m/s^2).
    period
        The navigation period T_s (s): candidates within ``max_accel * period`` of
        ``velocity`` are reachable.
    settings
        Horizon tau and the numbers of candidate speeds and headings (:class:`VOSettings`).
    nonlinear
        Use the non-linear VO (:func:`time_to_collision_nonlinear`, the obstacles'
        trajectories extrapolated with their accelerations) instead of the linear one.
    """
    cand = candidate_velocities(max_speed, settings)
    reach = np.hypot(*(cand - velocity).T) <= max_accel * period + 1e-12
    cand = cand[reach] if reach.any() else cand
    e = goal - position
    dist = float(np.hypot(*e))
    speed = min(max_speed, np.sqrt(2 * max_accel * dist)) if dist > 0 else 0.0
    pref = e / dist * speed if dist > 0 else np.zeros(2)
    if nonlinear:
        acc = world.accelerations if world.accelerations is not None else 0 * world.velocities
        ttc = time_to_collision_nonlinear(position, world.centres, world.velocities, acc,
                                          world.radii, cand, settings.horizon)  # fmt: skip
    else:
        ttc = time_to_collision(position, world.centres, world.velocities, world.radii, cand)
    first = ttc.min(axis=1) if ttc.size else np.full(len(cand), np.inf)
    first = np.minimum(first, _static_ttc(world, position, cand, settings.horizon))
    cost = np.hypot(*(cand - pref).T)
    free = first >= settings.horizon
    if free.any():
        return np.asarray(cand[free][np.argmin(cost[free])], dtype=float)
    best = first == first.max()
    return np.asarray(cand[best][np.argmin(cost[best])], dtype=float)
