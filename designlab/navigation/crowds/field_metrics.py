"""The crowd-navigation field's per-run metrics (issue 35, item 4), on plain arrays.

Each works on the records of a run (sample times ``(T,)``, the robot's positions and
velocities ``(T, 2)``, pedestrians ``(T, N, 2)`` with NaN where absent), so it applies to
any run. The definitions are the ones of the crowd-navigation literature:

* :func:`path_length` and :func:`spl` -- success weighted by (normalised inverse) path
  length, S l / max(p, l) (Anderson et al. 2018), with l the straight start-goal distance;
* :func:`motion_smoothness` -- acceleration and jerk of the robot by finite differences of
  its velocity resampled every :data:`SMOOTHING_PERIOD` (the stated filter: a zero-order
  decimation to one sample per navigation period, so the 1 kHz integration's steps do not
  show as jerk);
* :func:`discomfort_share` -- the share of the run's time with a surface distance to some
  pedestrian below :data:`DISCOMFORT_DISTANCE` (0.2 m, CrowdNav, Chen et al. 2019);
* :func:`intrusion_share` -- the share of the run's time the robot's disc is inside some
  pedestrian's personal space (time-normalised personal-space intrusion);
* :func:`time_to_collision` -- per sample, the smallest time until the robot's and a
  pedestrian's discs touch at their current velocities (constant-velocity extrapolation);
* :func:`freezing` -- whether the robot stood still (speed below :data:`FREEZE_SPEED`) for
  :data:`FREEZE_TIME` or longer away from its goal (the freezing-robot problem, Trautman &
  Krause 2010);
* :func:`attribute_contact` -- who caused a contact or a critical-region entry: the robot
  when its velocity towards the person is positive at that instant, else the person; a wall
  contact is the wall's (:func:`first_entry`).

Examples
--------
>>> import numpy as np
>>> path_length(np.array([[0.0, 0.0], [3.0, 4.0], [3.0, 5.0]]))
6.0
>>> spl([1, 0], [5.0, 5.0], [6.0, 5.0])
0.4166666666666667
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.validation import real_array

__all__ = [
    "DISCOMFORT_DISTANCE",
    "FREEZE_SPEED",
    "FREEZE_TIME",
    "SMOOTHING_PERIOD",
    "attribute_contact",
    "discomfort_share",
    "freezing",
    "intrusion_share",
    "motion_smoothness",
    "path_length",
    "spl",
    "time_to_collision",
]

Array = NDArray[np.float64]

#: Surface distance below which a pedestrian is taken to be discomforted, m (CrowdNav).
DISCOMFORT_DISTANCE = 0.2
#: Resampling period of the velocity for acceleration and jerk, s (the navigation period).
SMOOTHING_PERIOD = 0.06
#: Speed below which the robot stands, m/s.
FREEZE_SPEED = 0.05
#: Standing this long away from the goal is freezing, s.
FREEZE_TIME = 2.0


def _track(name: str, x: ArrayLike) -> Array:
    a = real_array(name, x, "m")
    if a.ndim != 2 or a.shape[1] != 2 or not a.shape[0]:
        raise InvalidParameterError(name, a.shape, "must have shape (T, 2) with T >= 1")
    return a


def _durations(times: ArrayLike, n: int) -> Array:
    """The duration each sample stands for (forward steps; the last sample: none)."""
    t = np.asarray(times, dtype=float)
    if t.ndim != 1 or t.size != n or (t.size > 1 and np.any(np.diff(t) <= 0)):
        raise InvalidParameterError("times", t.shape, f"must be {n} increasing times", "s")
    return np.append(np.diff(t), 0.0)


def path_length(robot: ArrayLike) -> float:
    """The length of the robot's path, m (the polyline through its samples).

    Parameters
    ----------
    robot
        Positions ``(T, 2)``, m.
    """
    p = _track("robot", robot)
    return float(np.hypot(*np.diff(p, axis=0).T).sum())


def spl(success: ArrayLike, shortest: ArrayLike, length: ArrayLike) -> float:
    """Success weighted by path length over runs: mean of S_i l_i / max(p_i, l_i).

    Parameters
    ----------
    success
        1 for a run that arrived, else 0, per run.
    shortest
        The shortest path length l_i of each run's task, m (> 0).
    length
        The path length p_i the robot drove, m.

    Examples
    --------
    >>> spl([1, 1], [4.0, 4.0], [4.0, 8.0])
    0.75
    """
    s = np.asarray(success, dtype=float)
    ll, p = np.asarray(shortest, dtype=float), np.asarray(length, dtype=float)
    if not (s.shape == ll.shape == p.shape) or s.ndim != 1 or not s.size:
        raise InvalidParameterError(
            "success", s.shape, "success, shortest and length: (n,), n >= 1"
        )
    if np.any(ll <= 0):
        raise InvalidParameterError("shortest", ll.min(), "must be > 0", "m")
    return float(np.mean(s * ll / np.maximum(p, ll)))


def motion_smoothness(times: ArrayLike, velocity: ArrayLike,
                      period: float = SMOOTHING_PERIOD) -> dict[str, float]:  # fmt: skip
    """Acceleration and jerk of the robot: its velocity resampled every ``period`` (the
    nearest earlier sample: a zero-order decimation), then first and second differences.

    Parameters
    ----------
    times
        Sample times ``(T,)``, s (a multiple of ``period`` apart, or finer).
    velocity
        The robot's velocity ``(T, 2)``, m/s.
    period
        The resampling period, s.

    Returns
    -------
    dict
        ``accel_mean`` and ``accel_max`` (m/s^2), ``jerk_mean`` and ``jerk_max`` (m/s^3):
        means and maxima of the magnitudes; NaN when the run is too short.

    Examples
    --------
    >>> t = np.arange(0.0, 1.0001, 0.01)
    >>> v = np.stack([t**2, np.zeros_like(t)], axis=1)     # a = 2t, jerk 2
    >>> round(motion_smoothness(t, v, 0.1)["jerk_mean"], 9)
    2.0
    """
    v = real_array("velocity", velocity, "m/s")
    t = np.asarray(times, dtype=float)
    _durations(t, v.shape[0])
    if not (period > 0 and math.isfinite(period)):
        raise InvalidParameterError("period", period, "must be > 0", "s")
    grid = np.arange(t[0], t[-1] + 1e-9, period)
    idx = np.searchsorted(t, grid + 1e-9, side="right") - 1
    vs = v[idx]
    a = np.diff(vs, axis=0) / period
    j = np.diff(a, axis=0) / period
    na, nj = np.hypot(*a.T) if a.size else a, np.hypot(*j.T) if j.size else j
    nan = math.nan
    return {
        "accel_mean": float(na.mean()) if na.size else nan,
        "accel_max": float(na.max()) if na.size else nan,
        "jerk_mean": float(nj.mean()) if nj.size else nan,
        "jerk_max": float(nj.max()) if nj.size else nan,
    }


def _surface(robot: Array, peds: Array, contact: float) -> Array:
    """Per sample, the smallest surface distance to a pedestrian (inf when none)."""
    d = np.hypot(peds[..., 0] - robot[:, None, 0], peds[..., 1] - robot[:, None, 1])
    d = np.where(np.isnan(d), np.inf, d)
    return (d.min(axis=1) if d.shape[1] else np.full(d.shape[0], np.inf)) - contact


def _peds(pedestrians: ArrayLike, T: int) -> Array:
    P = np.asarray(pedestrians, dtype=float)
    if P.ndim != 3 or P.shape[0] != T or P.shape[2] != 2:
        raise InvalidParameterError("pedestrians", P.shape, f"must have shape ({T}, N, 2)", "m")
    return P


def discomfort_share(times: ArrayLike, robot: ArrayLike, pedestrians: ArrayLike,
                     contact: float, distance: float = DISCOMFORT_DISTANCE) -> float:  # fmt: skip
    """The share of the run's time with a surface distance below ``distance`` to some
    pedestrian (each sample stands for the time to the next).

    Parameters
    ----------
    times
        ``(T,)`` s.
    robot
        ``(T, 2)`` m.
    pedestrians
        ``(T, N, 2)`` m, NaN where absent.
    contact
        The centre distance at contact, rho_r + rho_p, m.
    distance
        The discomfort distance, m.

    Examples
    --------
    >>> P = np.array([[[1.0, 0.0]], [[0.5, 0.0]], [[0.3, 0.0]]])
    >>> discomfort_share([0.0, 1.0, 3.0], np.zeros((3, 2)), P, 0.4)
    0.6666666666666666
    """
    p = _track("robot", robot)
    w = _durations(times, p.shape[0])
    s = _surface(p, _peds(pedestrians, p.shape[0]), contact)
    total = w.sum()
    return float(w[s < distance].sum() / total) if total > 0 else math.nan


def intrusion_share(times: ArrayLike, robot: ArrayLike, pedestrians: ArrayLike,
                    personal_space: float, robot_radius: float) -> float:  # fmt: skip
    """The share of the run's time the robot's disc is inside some pedestrian's personal
    space (centre distance below r_ps + rho_r).

    Parameters
    ----------
    times, robot, pedestrians
        As for :func:`discomfort_share`.
    personal_space
        r_ps, m.
    robot_radius
        rho_r, m.
    """
    return discomfort_share(times, robot, pedestrians, personal_space + robot_radius, 0.0)


def time_to_collision(p: ArrayLike, v: ArrayLike, P: ArrayLike, V: ArrayLike,
                      contact: float) -> float:  # fmt: skip
    """The smallest time until the robot's disc touches a pedestrian's at the current
    velocities, s (0 if touching now; inf if never).

    Parameters
    ----------
    p, v
        The robot's position (m) and velocity (m/s), ``(2,)``.
    P, V
        The pedestrians' positions and velocities ``(n, 2)``.
    contact
        rho_r + rho_p, m.

    Examples
    --------
    >>> time_to_collision([0, 0], [1, 0], [[5.0, 0.0]], [[-1.0, 0.0]], 1.0)
    2.0
    >>> time_to_collision([0, 0], [1, 0], [[5.0, 3.0]], [[-1.0, 0.0]], 1.0)
    inf
    """
    dp = np.asarray(P, dtype=float).reshape(-1, 2) - np.asarray(p, dtype=float)
    dv = np.asarray(V, dtype=float).reshape(-1, 2) - np.asarray(v, dtype=float)
    if not dp.size:
        return math.inf
    c = (dp**2).sum(axis=1) - contact**2
    if np.any(c <= 0):
        return 0.0
    a = (dv**2).sum(axis=1)
    b = (dp * dv).sum(axis=1)
    disc = b * b - a * c
    ok = (a > 0) & (b < 0) & (disc >= 0)
    t = np.full(dp.shape[0], np.inf)
    t[ok] = (-b[ok] - np.sqrt(disc[ok])) / a[ok]
    return float(t.min())


def freezing(times: ArrayLike, velocity: ArrayLike, robot: ArrayLike, goal: ArrayLike,
             tolerance: float, speed: float = FREEZE_SPEED,
             duration: float = FREEZE_TIME) -> bool:  # fmt: skip
    """Whether the robot stood (speed below ``speed``) for ``duration`` or longer at once
    while farther than ``tolerance`` from its goal.

    Parameters
    ----------
    times
        ``(T,)`` s.
    velocity, robot
        ``(T, 2)``: the robot's velocity (m/s) and position (m).
    goal
        ``(2,)`` m.
    tolerance
        The arrival radius, m.
    speed, duration
        The standing speed (m/s) and the shortest freeze (s).

    Examples
    --------
    >>> t = np.arange(6.0)
    >>> v = np.array([[1, 0], [0, 0], [0, 0], [0, 0], [1, 0], [1, 0]], float)
    >>> freezing(t, v, np.zeros((6, 2)), [9.0, 0.0], 0.1, duration=2.0)
    True
    """
    v, p = _track("velocity", velocity), _track("robot", robot)
    t = np.asarray(times, dtype=float)
    _durations(t, v.shape[0])
    g = np.asarray(goal, dtype=float)
    still = (np.hypot(*v.T) < speed) & (np.hypot(*(p - g).T) > tolerance)
    start = None
    for k, s in enumerate(still):
        if s and start is None:
            start = t[k]
        elif not s:
            start = None
        if start is not None and t[k] - start >= duration:
            return True
    return False


def attribute_contact(robot: ArrayLike, velocity: ArrayLike, person: ArrayLike) -> str:
    """Who caused a contact (or a critical-region entry) at one sample: ``"robot"`` when the
    robot's velocity towards the person is positive, else ``"pedestrian"``.

    Parameters
    ----------
    robot, velocity
        The robot's position (m) and velocity (m/s) at the sample, ``(2,)``.
    person
        The person's position, ``(2,)`` m.

    Examples
    --------
    >>> attribute_contact([0, 0], [0.5, 0.0], [1.0, 0.2]), attribute_contact([0, 0], [0, 1], [1, 0])
    ('robot', 'pedestrian')
    """
    d = np.asarray(person, dtype=float) - np.asarray(robot, dtype=float)
    return "robot" if float(np.dot(np.asarray(velocity, dtype=float), d)) > 0 else "pedestrian"


def wall_distances(walls: ArrayLike, pts: ArrayLike) -> Array:
    """Per point, the contour distance to the nearest wall, m (inf without walls).

    Parameters
    ----------
    walls
        One row per wall ``(n_w, 6)``: centre x and y (m), cos and sin of its angle, half
        length and half width (m) -- a rectangle.
    pts
        Points ``(n, 2)``, m.

    Examples
    --------
    >>> wall_distances([[0.0, 0.0, 1.0, 0.0, 2.0, 0.1]], [[0.0, 1.1], [3.0, 0.1]]).tolist()
    [1.0, 1.0]
    """
    w = np.asarray(walls, dtype=float).reshape(-1, 6)
    p = np.asarray(pts, dtype=float).reshape(-1, 2)
    if not w.shape[0]:
        return np.full(p.shape[0], np.inf)
    rx = p[None, :, 0] - w[:, 0:1]
    ry = p[None, :, 1] - w[:, 1:2]
    c, s = w[:, 2:3], w[:, 3:4]
    dx = np.maximum(np.abs(c * rx + s * ry) - w[:, 4:5], 0.0)
    dy = np.maximum(np.abs(-s * rx + c * ry) - w[:, 5:6], 0.0)
    return np.hypot(dx, dy).min(axis=0)


def first_entry(times: ArrayLike, robot: ArrayLike, velocity: ArrayLike,
                pedestrians: ArrayLike, radius: float, walls: ArrayLike = (),
                wall_radius: float = -math.inf) -> tuple[float, str]:  # fmt: skip
    """The first sample with a pedestrian's centre within ``radius`` of the robot's (or a
    wall's contour within ``wall_radius``), and who caused it: ``"robot"`` or
    ``"pedestrian"`` (:func:`attribute_contact`) or ``"wall"``; ``(inf, "none")`` if never.

    It sees only the samples it is given: a contact that starts and ends between two of them
    is missed. The crowd simulator therefore calls it on every dynamics step of a navigation
    period (pedestrians interpolated within their steps) as soon as the period's running
    minimum shows an entry, and a run's ``collision_by`` and ``critical_by`` come from there
    (:class:`~designlab.navigation.crowds.results.CrowdResult`), not from the recorded samples.

    Parameters
    ----------
    times, robot, velocity, pedestrians
        The run's records (or a period's dynamics steps).
    radius
        The centre distance: rho_r + rho_p for a contact, r3 for a critical entry, m.
    walls
        The walls as rows of :func:`wall_distances` (none: no wall is checked).
    wall_radius
        The contour distance to a wall: rho_r for a contact, the walls' r3 for a critical
        entry, m.

    Examples
    --------
    >>> P = np.array([[[2.0, 0.0]], [[1.0, 0.0]], [[0.5, 0.0]]])
    >>> first_entry([0.0, 1.0, 2.0], np.zeros((3, 2)), np.zeros((3, 2)), P, 1.0)
    (1.0, 'pedestrian')
    >>> wall = [[0.0, -1.2, 1.0, 0.0, 5.0, 0.1]]         # a wall's face at y = -1.1
    >>> first_entry([0.0, 1.0, 2.0], np.zeros((3, 2)), np.zeros((3, 2)), P, 0.4, wall, 1.1)
    (0.0, 'wall')
    """
    p, v = _track("robot", robot), _track("velocity", velocity)
    t = np.asarray(times, dtype=float)
    _durations(t, p.shape[0])
    P = _peds(pedestrians, p.shape[0])
    d = np.hypot(P[..., 0] - p[:, None, 0], P[..., 1] - p[:, None, 1])
    d = np.where(np.isnan(d), np.inf, d)
    near = d <= radius
    k_ped = int(np.argmax(near.any(axis=1))) if near.any() else p.shape[0]
    wall = wall_distances(walls, p) <= wall_radius
    k_wall = int(np.argmax(wall)) if wall.any() else p.shape[0]
    if k_ped < min(k_wall, p.shape[0]) or (k_ped == k_wall < p.shape[0]):  # a tie: the person
        i = int(np.argmin(d[k_ped]))
        return float(t[k_ped]), attribute_contact(p[k_ped], v[k_ped], P[k_ped, i])
    if k_wall < p.shape[0]:
        return float(t[k_wall]), "wall"
    return math.inf, "none"


def run_measures(result: Any, personal_space: float) -> dict[str, Any]:
    """The field's metrics of one crowd run (a :class:`CrowdResult`), as one row.

    Parameters
    ----------
    result
        The run.
    personal_space
        r_ps, m.

    Returns
    -------
    dict
        ``path_length_m``, ``shortest_m``, ``accel_mean``, ``accel_max``, ``jerk_mean``,
        ``jerk_max``, ``discomfort_share``, ``intrusion_share``, ``ttc_min_s``, ``frozen``
        (0/1), ``collision_by`` and ``critical_by`` (``"robot"``, ``"pedestrian"``,
        ``"wall"``, ``"none"``: the run's own, attributed at the dynamics step of the first
        contact or critical entry).
    """
    c = result.crowd
    t, p, v = result.times, result.robot_positions, result.robot_velocities
    P = result.pedestrian_positions
    rho = c.robot.radius
    contact = rho + c.pedestrian_radius
    shortest = float(np.hypot(*(np.asarray(c.robot_goal) - np.asarray(c.robot_start))))
    row: dict[str, Any] = {"path_length_m": path_length(p), "shortest_m": shortest}
    row.update(motion_smoothness(t, v, c.sample_time))
    row["discomfort_share"] = discomfort_share(t, p, P, contact)
    row["intrusion_share"] = intrusion_share(t, p, P, personal_space, rho)
    per = max(1, round(c.sample_time / c.pedestrian_step))  # TTC at the navigation samples
    dt = c.pedestrian_step
    ttc = math.inf
    for k in range(1, t.size, per):
        here = ~np.isnan(P[k, :, 0]) & ~np.isnan(P[k - 1, :, 0])
        ttc = min(ttc, time_to_collision(p[k], v[k], P[k, here], (P[k, here] - P[k - 1, here]) / dt,
                                         contact))  # fmt: skip
    row["ttc_min_s"] = ttc
    row["frozen"] = float(freezing(t, v, p, c.robot_goal, 0.15))
    row["collision_by"] = result.collision_by  # attributed at the contact's dynamics step
    row["critical_by"] = result.critical_by
    return row


__all__ += ["first_entry", "run_measures", "wall_distances"]
