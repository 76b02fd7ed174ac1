"""The static force field over the plane (Zeng 2011, Figs. 5.10 and 6.12).

:func:`force_map` evaluates a method's field with the robot at rest at every point of a
grid, the obstacles where they are at time ``t``: the total force (whose zeros are the
local minima of Fig. 5.10: K1 E + K3 Lambda u_Lambda + K5 psi u_psi = 0, the "right
triangle") or the obstacles' part alone (the net repulsive and detour surface of Fig. 6.12,
whose valley between two obstacles makes the path oscillate in a passage).

Examples
--------
>>> import numpy as np
>>> import designlab as dl
>>> nav = dl.navigation
>>> m = force_map(nav.configuration(1), nav.EXPERIMENT_GAINS, np.linspace(0, 4, 9),
...               np.linspace(-0.4, 1.6, 5))
>>> m.force.shape, bool(np.isnan(m.norm[2, 5]))   # (2.5, 0.6) is inside the critical region
((5, 9, 2), True)
>>> # far from the circle the field is the attraction K1 E alone
>>> bool(np.allclose(m.force[0, 0], 3.0 * (np.array([0.0, 0.6]) - [0.0, -0.4])))
True
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.navigation.engine import obstacle_tracks
from designlab.navigation.field import ObstacleGeometry, build_field
from designlab.navigation.methods import METHOD, method_of
from designlab.navigation.scenarios import Scenario
from designlab.params import check_size
from designlab.results import Result

__all__ = ["ForceMap", "force_map"]

Array = NDArray[np.float64]
_PARTS = ("total", "obstacles")
#: Grid points of one map (one field evaluation each).
MAX_GRID = 250_000


@dataclass(frozen=True)
class ForceMap(Result):
    """The field on a grid, the robot at rest.

    Attributes
    ----------
    x, y
        Grid coordinates (m).
    force
        ``(len(y), len(x), 2)`` force in N (nan inside critical regions, where the field is
        not used).
    norm
        Its magnitude.
    part
        ``"total"`` or ``"obstacles"`` (the total minus the attraction K1 E).
    minimum
        ``(x, y, |F|)`` of the smallest total force among the points inside some active
        region (and no critical region): where a local minimum of Fig. 5.10 can lie.
    """

    x: Array = field(repr=False)
    y: Array = field(repr=False)
    force: Array = field(repr=False)
    norm: Array = field(repr=False)
    part: str = "total"
    minimum: tuple[float, float, float] = (np.nan, np.nan, np.nan)


def _grid(values: ArrayLike, name: str) -> Array:
    a = np.asarray(values, dtype=float).ravel()
    if a.size < 2 or not np.isfinite(a).all():
        raise InvalidParameterError(name, values, "must be at least two finite coordinates", "m")
    return a


def force_map(
    scenario: Scenario,
    gains: Any,
    x: ArrayLike,
    y: ArrayLike,
    *,
    t: float = 0.0,
    part: str = "total",
    method: str = METHOD.default,
    tie_side: str = "+y",
) -> ForceMap:
    """The field of ``method`` at rest over the grid ``x`` x ``y`` with the obstacles at ``t``.

    Parameters
    ----------
    scenario
        The scenario (obstacles, goal, robot).
    gains
        The method's gains.
    x, y
        Grid coordinates in m (at most 250 000 points).
    t
        Time at which the obstacles are taken (s).
    part
        ``"total"`` or ``"obstacles"`` (without the attraction K1 E).
    method
        ``"vff"``, ``"masoud"``, ``"ge_cui"``.
    tie_side
        The detour tie-break (Masoud: its rotational sense).

    Returns
    -------
    ForceMap
    """
    if part not in _PARTS:
        raise InvalidParameterError("part", part, f"must be one of {_PARTS}")
    strategy = method_of(method)
    row = strategy.gain_row(gains)
    xs, ys = _grid(x, "x"), _grid(y, "y")
    if xs.size * ys.size > MAX_GRID:
        raise InvalidParameterError(
            "x, y", (xs.size, ys.size), f"must have at most {MAX_GRID} grid points together"
        )
    check_size("x", xs.size, 20 * xs.size * ys.size, what="the force map's grid")
    geos = tuple(ObstacleGeometry.of(o) for o in scenario.obstacles)
    fn = build_field(geos, strategy.name)
    X, Y = np.meshgrid(xs, ys)
    n = X.size
    state = np.vstack([X.ravel(), Y.ravel(), np.zeros(n), np.zeros(n)])
    P, V, A = obstacle_tracks(scenario, np.array([float(t)]))
    obs = np.concatenate([P[:, 0], V[:, 0], A[:, 0]], axis=1).ravel()  # 6 per obstacle (or 0)
    robot = scenario.robot
    params = [robot.mass, float(strategy.tie(gains, tie_side)), 0.0, robot.max_accel]
    out = fn.map(n)(state, np.tile(np.asarray(scenario.goal, float)[:, None], n),
                    np.tile(obs[:, None], n), np.tile(row[:, None], n),
                    np.tile(np.asarray(params)[:, None], n))  # fmt: skip
    F = np.asarray(out[0]).T.reshape(ys.size, xs.size, 2)
    crit = np.asarray(out[1]).ravel().reshape(ys.size, xs.size) > 0.5
    flags = np.asarray(out[8]).reshape(len(geos), n)  # no obstacle: no active region
    active = flags.any(axis=0).reshape(ys.size, xs.size)
    F[crit] = np.nan
    total = np.linalg.norm(F, axis=2)
    if part == "obstacles":
        E = np.stack([scenario.goal[0] - X, scenario.goal[1] - Y], axis=2)
        F = F - row[0] * E
    norm = np.linalg.norm(F, axis=2)
    return ForceMap(xs, ys, F, norm, part, _minimum(X, Y, total, active))


def _minimum(X: Array, Y: Array, total: Array, active: NDArray[np.bool_]) -> tuple:
    masked = np.where(active & np.isfinite(total), total, np.inf)
    if not np.isfinite(masked).any():
        return (np.nan, np.nan, np.nan)
    k = np.unravel_index(np.argmin(masked), masked.shape)
    return (float(X[k]), float(Y[k]), float(masked[k]))
