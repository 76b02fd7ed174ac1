"""Metrics of robot runs among crowds: rates with Wilson intervals, CVaR, clearance, personal
space, and the delay and path deviation the robot causes to pedestrians.

Every function works on plain arrays (``times (T,)``, ``robot (T, 2)``, pedestrians
``(T, N, 2)`` with NaN where a pedestrian is not in the simulation), so it applies to any
run: a crowd run, a thesis configuration or recorded trajectories.

* :func:`wilson_interval` -- the Wilson score interval of a binomial rate (Wilson 1927;
  :meth:`scipy.stats.binomtest` ``proportion_ci(method="wilson")``).
* :func:`cvar` -- the conditional value at risk of costs (the mean of the worst
  ``1 - alpha`` tail, Rockafellar & Uryasev 2000).
* :func:`clearance` -- the robot's centre distance to its nearest pedestrian per sample.
* :func:`personal_space_time` -- time the robot spends inside a pedestrian's personal space
  (:data:`PERSONAL_SPACE`: 1.2 m, the outer edge of Hall's (1966) personal distance).
* :func:`exit_times`, :func:`pedestrian_delay`, :func:`path_deviation` -- what the robot
  costs the pedestrians, compared with the same seed simulated without the robot.

Examples
--------
>>> lo, hi = wilson_interval(0, 10)
>>> round(lo, 4), round(hi, 4)
(0.0, 0.2775)
>>> float(cvar([1.0, 2.0, 3.0, 4.0], alpha=0.5))
3.5
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.navigation.crowds.bookkeeping import farthest_from_path
from designlab.params import ARG, Param
from designlab.sx.jit import AVAILABLE as COMPILED
from designlab.validation import real_array

__all__ = [
    "CONFIDENCE",
    "CVAR_ALPHA",
    "PATH_VERTICES",
    "PERSONAL_SPACE",
    "clearance",
    "cvar",
    "exit_times",
    "path_deviation",
    "pedestrian_delay",
    "personal_space_time",
    "point_to_path",
    "wilson_interval",
]

Array = NDArray[np.float64]

#: Confidence level of the rate intervals.
CONFIDENCE = ARG.confidence.but(symbol="confidence", doc="confidence level of a Wilson interval")
#: Tail level of CVaR: the mean of the worst ``1 - alpha`` of the runs.
CVAR_ALPHA = Param("alpha", "", "CVaR level (the worst 1 - alpha of the runs are averaged)",
                   ge=0, lt=1, default=0.8, name="alpha")  # fmt: skip
#: Personal-space radius around a pedestrian's centre (m): Hall's (1966) personal distance
#: ends at 1.2 m (4 ft); inside it is where a passer-by is felt as intruding.
PERSONAL_SPACE = Param("r_ps", "m", "personal-space radius around a pedestrian's centre",
                       gt=0, le=10, default=1.2, name="personal_space")  # fmt: skip


def wilson_interval(
    successes: int, trials: int, confidence: float = CONFIDENCE.default
) -> tuple[float, float]:
    """The Wilson score interval of a rate ``successes / trials``.

    Parameters
    ----------
    successes
        Number of runs with the event (0 <= successes <= trials).
    trials
        Number of runs; with 0 the interval is ``(nan, nan)`` (nothing is known).
    confidence
        Confidence level in (0, 1).

    Returns
    -------
    tuple of float
        ``(low, high)``, both within [0, 1].

    Examples
    --------
    >>> [round(v, 4) for v in wilson_interval(5, 10)]
    [0.2366, 0.7634]
    """
    conf = CONFIDENCE.check(confidence)
    k, n = _count(successes, "successes"), _count(trials, "trials")
    if k > n:
        raise InvalidParameterError("successes", successes, f"must be <= trials = {n}")
    if n == 0:
        return (math.nan, math.nan)
    from scipy.stats import binomtest  # on first use: scipy.stats takes ~0.3 CPU s to import

    ci = binomtest(k, n).proportion_ci(confidence_level=conf, method="wilson")
    return (max(0.0, float(ci.low)), min(1.0, float(ci.high)))


def _count(value: Any, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 0:
        raise InvalidParameterError(name, value, "must be an integer >= 0")
    return int(value)


def cvar(costs: ArrayLike, alpha: float = CVAR_ALPHA.default) -> float:
    """Conditional value at risk of equally likely costs: the mean of the worst ``1 - alpha``.

    The tail holds ``m = (1 - alpha) n`` runs; when ``m`` is fractional the run at its edge
    counts with the fraction, so the value equals Rockafellar & Uryasev's (2000)
    ``min_t t + E[(X - t)+] / (1 - alpha)``. ``alpha = 0`` is the mean.

    Parameters
    ----------
    costs
        One cost per run (higher is worse; ``inf`` allowed, NaN refused).
    alpha
        Level in [0, 1).

    Returns
    -------
    float
        The CVaR (``nan`` for no costs).

    Examples
    --------
    >>> float(cvar([0.0, 10.0, 1.0, 2.0, 3.0], alpha=0.6))
    6.5
    """
    a = CVAR_ALPHA.check(alpha)
    x = np.sort(np.asarray(costs, dtype=float).ravel())[::-1]
    if np.isnan(x).any():
        raise InvalidParameterError("costs", "NaN", "must hold no NaN (a failed run is +inf)")
    if x.size == 0:
        return math.nan
    m = (1.0 - a) * x.size
    whole = math.floor(m + 1e-12)
    frac = m - whole
    head = float(np.sum(x[:whole])) if whole else 0.0
    edge = frac * float(x[whole]) if frac > 1e-12 and whole < x.size else 0.0
    return (head + edge) / m


def clearance(robot: ArrayLike, pedestrians: ArrayLike) -> Array:
    """Centre distance from the robot to its nearest pedestrian at each sample (m).

    Parameters
    ----------
    robot
        Robot positions, shape ``(T, 2)``.
    pedestrians
        Pedestrian positions, shape ``(T, N, 2)``, NaN where a pedestrian is absent.

    Returns
    -------
    ndarray
        Shape ``(T,)``; ``inf`` at a sample with no pedestrian present.

    Examples
    --------
    >>> clearance([[0.0, 0.0]], [[[3.0, 4.0], [np.nan, np.nan]]]).tolist()
    [5.0]
    """
    r, p = _tracks(robot, pedestrians)
    d = np.linalg.norm(p - r[:, None, :], axis=2)
    d = np.where(np.isnan(d), np.inf, d)
    return d.min(axis=1) if d.shape[1] else np.full(d.shape[0], np.inf)


def _tracks(robot: ArrayLike, pedestrians: ArrayLike) -> tuple[Array, Array]:
    r = real_array("robot", robot, "m")  # finite: the robot is always somewhere
    try:
        p = np.asarray(pedestrians, dtype=float)  # NaN: a pedestrian not (yet) present
    except (TypeError, ValueError):
        raise InvalidParameterError(
            "pedestrians", pedestrians, "must be numbers (T, N, 2)"
        ) from None
    if np.isinf(p).any():
        raise InvalidParameterError("pedestrians", "inf", "must be finite or NaN (absent)", "m")
    if r.ndim != 2 or r.shape[1] != 2:
        raise InvalidParameterError("robot", r.shape, "must have shape (T, 2)")
    if p.ndim != 3 or p.shape[2] != 2 or p.shape[0] != r.shape[0]:
        raise InvalidParameterError("pedestrians", p.shape, f"must have shape ({r.shape[0]}, N, 2)")
    return r, p


def _steps(times: ArrayLike, n: int) -> Array:
    """Duration of each sample (forward difference; the last sample lasts as the one before)."""
    t = np.asarray(times, dtype=float)
    if t.shape != (n,) or (n > 1 and np.any(np.diff(t) <= 0)) or not np.isfinite(t).all():
        raise InvalidParameterError("times", t.shape, f"must be {n} finite increasing times (s)")
    if n < 2:
        return np.zeros(n)
    dt = np.diff(t)
    return np.append(dt, dt[-1])


def personal_space_time(
    times: ArrayLike,
    robot: ArrayLike,
    pedestrians: ArrayLike,
    radius: float = 1.2,
    robot_radius: float = 0.0,
) -> float:
    """Time (s) during which the robot's body is inside some pedestrian's personal space.

    A sample counts when the centre distance to a pedestrian is below
    ``radius + robot_radius`` (the robot's disc overlaps the personal-space disc); it lasts
    until the next sample (the last one as long as the step before it).

    Parameters
    ----------
    times
        Sample times, shape ``(T,)``, increasing (s).
    robot, pedestrians
        Positions, ``(T, 2)`` and ``(T, N, 2)`` (NaN: absent), m.
    radius
        Personal-space radius :data:`PERSONAL_SPACE` (m; default 1.2 m, Hall 1966).
    robot_radius
        Radius of the robot's disc (m, >= 0).

    Returns
    -------
    float
        Seconds inside.

    Examples
    --------
    >>> t = [0.0, 0.1, 0.2, 0.3]
    >>> peds = [[[2.0, 0.0]], [[1.0, 0.0]], [[0.5, 0.0]], [[3.0, 0.0]]]
    >>> round(personal_space_time(t, [[0.0, 0.0]] * 4, peds), 12)
    0.2
    """
    r_ps = PERSONAL_SPACE.check(radius)
    if not (np.isfinite(robot_radius) and 0 <= robot_radius <= 10):
        raise InvalidParameterError("robot_radius", robot_radius, "must be in [0, 10] m")
    d = clearance(robot, pedestrians)
    dt = _steps(times, d.size)
    return float(np.sum(dt[d < r_ps + robot_radius]))


def exit_times(times: ArrayLike, pedestrians: ArrayLike) -> Array:
    """When each pedestrian left the simulation (s): the sample after its last present one.

    Parameters
    ----------
    times
        Sample times ``(T,)`` (s).
    pedestrians
        Positions ``(T, N, 2)``, NaN where absent.

    Returns
    -------
    ndarray
        Shape ``(N,)``; ``inf`` for a pedestrian still present at the last sample, ``nan``
        for one never present.

    Examples
    --------
    >>> p = np.full((4, 2, 2), np.nan); p[:2, 0] = 0.0; p[:, 1] = 1.0
    >>> exit_times([0.0, 0.5, 1.0, 1.5], p).tolist()
    [1.0, inf]
    """
    t = np.asarray(times, dtype=float)
    p = np.asarray(pedestrians, dtype=float)
    _steps(t, p.shape[0] if p.ndim == 3 else -1)
    present = ~np.isnan(p).any(axis=2)
    out = np.full(p.shape[1], np.nan)
    seen = present.any(axis=0)
    last = p.shape[0] - 1 - np.argmax(present[::-1], axis=0)
    out[seen] = np.where(
        last[seen] == p.shape[0] - 1, np.inf, t[np.minimum(last[seen] + 1, t.size - 1)]
    )
    return out


def pedestrian_delay(
    times: ArrayLike, with_robot: ArrayLike, without_robot: ArrayLike
) -> dict[str, float]:
    """The delay the robot causes: exit times with the robot minus without it (same seed).

    Both runs are cut to their common time window. A pedestrian that left in both counts
    with its delay; one that left without the robot but not with it was delayed beyond the
    window (counted, not averaged).

    Parameters
    ----------
    times
        Sample times of the shorter run, ``(T,)`` (s): both runs share the sample grid.
    with_robot, without_robot
        Pedestrian positions ``(T_a, N, 2)`` and ``(T_b, N, 2)`` with the same pedestrians
        in the same order (``T_a, T_b >= T``).

    Returns
    -------
    dict
        ``mean_s``, ``max_s`` (over pedestrians that left in both runs; ``nan`` if none),
        ``compared`` (that many), ``beyond_window`` (left only without the robot).

    Examples
    --------
    >>> a = np.zeros((3, 1, 2)); a[2] = np.nan
    >>> b = np.zeros((3, 1, 2)); b[1:] = np.nan
    >>> pedestrian_delay([0.0, 1.0, 2.0], a, b)["mean_s"]
    1.0
    """
    t, a, b = _paired(times, with_robot, without_robot)
    ea, eb = exit_times(t, a), exit_times(t, b)
    both = np.isfinite(ea) & np.isfinite(eb)
    delay = ea[both] - eb[both]
    return {
        "mean_s": float(delay.mean()) if delay.size else math.nan,
        "max_s": float(delay.max()) if delay.size else math.nan,
        "compared": float(delay.size),
        "beyond_window": float(np.sum(np.isinf(ea) & np.isfinite(eb))),
    }


def _paired(times: ArrayLike, a: ArrayLike, b: ArrayLike) -> tuple[Array, Array, Array]:
    t = np.asarray(times, dtype=float)
    pa, pb = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    for name, p in (("with_robot", pa), ("without_robot", pb)):
        if p.ndim != 3 or p.shape[2] != 2 or p.shape[0] < t.size:
            raise InvalidParameterError(name, p.shape, f"must have shape (>= {t.size}, N, 2)")
    if pa.shape[1] != pb.shape[1]:
        raise InvalidParameterError(
            "without_robot", pb.shape, f"must hold {pa.shape[1]} pedestrians"
        )
    return t, pa[: t.size], pb[: t.size]


def point_to_path(points: ArrayLike, path: ArrayLike) -> Array:
    """Distance from each point to a polyline (m), exact (nearest point of each segment).

    Parameters
    ----------
    points
        Shape ``(P, 2)``.
    path
        Vertices ``(S + 1, 2)`` of the polyline (one vertex: a point).

    Returns
    -------
    ndarray
        Shape ``(P,)``.

    Examples
    --------
    >>> point_to_path([[1.0, 2.0], [-1.0, 0.0]], [[0.0, 0.0], [3.0, 0.0]]).tolist()
    [2.0, 1.0]
    """
    q, v = real_array("points", points, "m"), real_array("path", path, "m")
    if q.ndim != 2 or q.shape[1] != 2 or v.ndim != 2 or v.shape[1] != 2 or not v.shape[0]:
        raise InvalidParameterError(
            "path", (q.shape, v.shape), "points (P, 2) and path (S + 1, 2) with S + 1 >= 1", "m"
        )
    if v.shape[0] == 1:
        return np.linalg.norm(q - v[0], axis=1)
    a, ab = v[:-1], np.diff(v, axis=0)
    ll = np.einsum("ij,ij->i", ab, ab)
    rel = q[:, None, :] - a[None, :, :]
    s = np.where(ll > 0, np.einsum("psj,sj->ps", rel, ab) / np.where(ll > 0, ll, 1.0), 0.0)
    near = a[None] + np.clip(s, 0.0, 1.0)[..., None] * ab[None]
    return np.linalg.norm(q[:, None, :] - near, axis=2).min(axis=1)


#: Samples of a path kept for :func:`path_deviation` (evenly, the ends included): bounds its
#: memory and time; at walking speed over a minute the vertices are ~0.2 m apart, so the chord
#: of a smooth path is off its arc by far less than a pedestrian's radius.
PATH_VERTICES = 400


def _thin(points: Array) -> Array:
    if len(points) <= PATH_VERTICES:
        return points
    return points[np.linspace(0, len(points) - 1, PATH_VERTICES).round().astype(int)]


def _farthest(pa: Array, pb: Array) -> float:
    """``point_to_path(pa, pb).max()``, compiled when numba is there and ``pb`` is a path."""
    if COMPILED and len(pb) > 1:
        return float(farthest_from_path(np.ascontiguousarray(pa), np.ascontiguousarray(pb)))
    return float(point_to_path(pa, pb).max())


def path_deviation(
    times: ArrayLike, with_robot: ArrayLike, without_robot: ArrayLike
) -> dict[str, float]:
    """How far the robot pushes pedestrians off their own path (m), per pedestrian the
    largest distance of its path with the robot from its path without it (same seed).

    Long paths are thinned to :data:`PATH_VERTICES` samples each before the (exact)
    point-to-polyline distances.

    Parameters
    ----------
    times
        Sample times of the common window ``(T,)`` (s).
    with_robot, without_robot
        Pedestrian positions as for :func:`pedestrian_delay`.

    Returns
    -------
    dict
        ``mean_m`` (mean over pedestrians of their largest deviation), ``max_m``,
        ``compared`` (pedestrians present in both runs).

    Examples
    --------
    >>> a = np.array([[[0.0, 0.0]], [[1.0, 0.5]], [[2.0, 0.0]]])
    >>> b = np.array([[[0.0, 0.0]], [[1.0, 0.0]], [[2.0, 0.0]]])
    >>> path_deviation([0.0, 1.0, 2.0], a, b)["max_m"]
    0.5
    """
    _, a, b = _paired(times, with_robot, without_robot)
    worst = []
    for i in range(a.shape[1]):
        pa = _thin(a[:, i][~np.isnan(a[:, i]).any(axis=1)])
        pb = _thin(b[:, i][~np.isnan(b[:, i]).any(axis=1)])
        if len(pa) and len(pb):
            worst.append(_farthest(pa, pb))
    w = np.asarray(worst)
    return {
        "mean_m": float(w.mean()) if w.size else math.nan,
        "max_m": float(w.max()) if w.size else math.nan,
        "compared": float(w.size),
    }
