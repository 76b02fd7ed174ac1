"""Field D* on a grid (Ferguson & Stentz 2006): path costs interpolated along cell edges.

Nodes are the corners of square cells of size ``h``; a cell costs 1 per metre if free
and is impassable if an obstacle (inflated by the robot radius, as it is now) reaches
it. The cost to the goal g of every node is computed from the goal outwards in
Dijkstra order with Field D*'s interpolated update (:func:`compute_cost`): a path may
leave a node towards any point of the edge between two consecutive neighbours, not only
towards the neighbours, so paths are not restricted to the 8 grid headings. Each
navigation period the costs are recomputed for the obstacles' new positions, which
gives the costs Field D*'s incremental repair gives (the repair saves time, not
changes them); expansion stops once the robot's cell is settled.

Examples
--------
On a free grid, the cost of node (2, 1) from the goal at (0, 0) is the interpolated
1 + sqrt(1 + y^2) + f (1 - y) with f = sqrt(2) - 1 and y = f / sqrt(1 - f^2), between
the true distance sqrt(5) = 2.236 and the 8-connected 1 + sqrt(2) = 2.414:

>>> import numpy as np
>>> g = node_costs(np.ones((4, 3)), (0, 0))
>>> round(float(g[2, 1]), 4)
2.3244
"""

from __future__ import annotations

import heapq
import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.navigation.planners.parameters import GRID_CELLS, PLANNED_CELLS, FieldDStarSettings
from designlab.navigation.planners.world import Snapshot

__all__ = ["Grid", "check_grid", "compute_cost", "node_costs"]

Array = NDArray[np.float64]
#: The 8 neighbours of a node, counter-clockwise from +x (edge, diagonal, edge, ...).
_NEIGHBOURS = ((1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1))
_SQRT2 = math.sqrt(2.0)


def compute_cost(c: float, b: float, g1: float, g2: float) -> float:
    """Field D*'s cost of a node through the edge between its neighbours s1 (edge-adjacent,
    cost ``g1``) and s2 (diagonal, ``g2``); ``c`` is the cost of the cell holding s, s1, s2
    and ``b`` of the cell across the edge s-s1 (Ferguson & Stentz 2006, Fig. 9; unit cells).

    Parameters
    ----------
    c
        Cost per unit length of the cell holding s, s1 and s2 (1: free; inf: blocked).
    b
        Cost per unit length of the cell across the edge s-s1 (inf: blocked or off the grid).
    g1
        Cost to the goal of s1, the edge-adjacent neighbour (cell sizes times cell cost).
    g2
        Cost to the goal of s2, the diagonal neighbour (cell sizes times cell cost).

    Examples
    --------
    >>> compute_cost(1.0, 1.0, 1.0, 0.0) == math.sqrt(2)
    True
    """
    for name, v in (("c", c), ("b", b), ("g1", g1), ("g2", g2)):
        if isinstance(v, bool) or not isinstance(v, int | float | np.number) or not v >= 0:
            raise InvalidParameterError(name, v, "must be a number >= 0 (inf: blocked or unknown)")
    return _compute_cost(float(c), float(b), float(g1), float(g2))


def _compute_cost(c: float, b: float, g1: float, g2: float) -> float:
    """:func:`compute_cost` on checked numbers (the inner loop of :func:`node_costs`)."""
    if min(c, b) == math.inf:
        return math.inf
    if g1 <= g2:
        return min(c, b) + g1
    f = g1 - g2
    if f <= b:
        if c <= f:
            return c * _SQRT2 + g2
        y = min(f / math.sqrt(c * c - f * f), 1.0)
        return c * math.sqrt(1 + y * y) + f * (1 - y) + g2
    if c <= b:
        return c * _SQRT2 + g2
    x = 1 - min(b / math.sqrt(c * c - b * b), 1.0)
    return c * math.sqrt(1 + (1 - x) ** 2) + b * x + g2


def _cell(cost: Array, i: int, j: int) -> float:
    if 0 <= i < cost.shape[0] and 0 <= j < cost.shape[1]:
        return float(cost[i, j])
    return math.inf


def _update(
    g: Array, cost: Array, i: int, j: int, pairs: tuple[int, ...] = tuple(range(8))
) -> float:
    """The smallest interpolated cost of node (i, j) over its neighbour pairs ``pairs``
    (pair k: neighbours k and k + 1 counter-clockwise)."""
    nx, ny = g.shape
    best = math.inf
    for k in pairs:
        a, b_ = _NEIGHBOURS[k % 8], _NEIGHBOURS[(k + 1) % 8]
        e, d = (a, b_) if 0 in a else (b_, a)  # e: edge neighbour, d: diagonal
        s1, s2 = (i + e[0], j + e[1]), (i + d[0], j + d[1])
        if not (0 <= s1[0] < nx and 0 <= s1[1] < ny and 0 <= s2[0] < nx and 0 <= s2[1] < ny):
            continue
        ci, cj = i + min(e[0], d[0], 0), j + min(e[1], d[1], 0)
        if e[0] != 0:  # horizontal edge s-s1: the cells above and below it
            bi, bj = ci, (cj - 1 if cj == j else j)
        else:  # vertical edge: the cells left and right of it
            bi, bj = (ci - 1 if ci == i else i), cj
        v = _compute_cost(_cell(cost, ci, cj), _cell(cost, bi, bj), g[s1], g[s2])
        best = min(best, v)
    return best


def _check_costs(
    cell_cost: Any, goal: Any, stop: Any
) -> tuple[Array, tuple[int, int], tuple[tuple[int, int], ...]]:
    """The arguments of :func:`node_costs` checked: a grid within :data:`GRID_CELLS` of costs
    >= 0 (inf: blocked) and nodes on it."""
    try:
        cost = np.asarray(cell_cost, dtype=float)
    except (TypeError, ValueError):
        cost = np.empty(0)
    if cost.ndim != 2 or not cost.size or not (cost >= 0).all():
        raise InvalidParameterError(
            "cell_cost", getattr(cost, "shape", cell_cost), "must be an (nx, ny) grid of costs "
            ">= 0 per cell size (inf: blocked)",
        )  # fmt: skip
    GRID_CELLS.check(cost.size, "cell_cost (cells)")
    nodes = []
    for name, node in (("goal", goal), *((f"stop[{i}]", n) for i, n in enumerate(stop))):
        ok = isinstance(node, tuple | list | np.ndarray) and len(node) == 2
        ok = ok and all(isinstance(v, int | np.integer) and not isinstance(v, bool) for v in node)
        if not ok or not (0 <= node[0] <= cost.shape[0] and 0 <= node[1] <= cost.shape[1]):
            raise InvalidParameterError(
                name, node, f"must be a node (i, j) with 0 <= i <= {cost.shape[0]} and "
                f"0 <= j <= {cost.shape[1]}",
            )  # fmt: skip
        nodes.append((int(node[0]), int(node[1])))
    return cost, nodes[0], tuple(nodes[1:])


def node_costs(
    cell_cost: Array, goal: tuple[int, int], stop: tuple[tuple[int, int], ...] = ()
) -> Array:
    """Cost to the goal node of every node of a grid with ``cell_cost`` ``(nx, ny)`` (per cell
    size; inf: blocked); ``(nx + 1, ny + 1)`` nodes. Stops once every node of ``stop`` is
    settled (unsettled nodes keep inf).

    Parameters
    ----------
    cell_cost
        Cost per unit length (cell sizes) of crossing each cell, ``(nx, ny)`` (1: free;
        inf: blocked).
    goal
        Index ``(i, j)`` of the goal node, ``0 <= i <= nx``, ``0 <= j <= ny``.
    stop
        Nodes ``(i, j)`` whose costs are wanted: expansion stops once all are settled
        (empty: every reachable node is settled).
    """
    cell_cost, goal, stop = _check_costs(cell_cost, goal, stop)
    g = np.full((cell_cost.shape[0] + 1, cell_cost.shape[1] + 1), math.inf)
    g[goal] = 0.0
    heap: list[tuple[float, tuple[int, int]]] = [(0.0, goal)]
    settled = np.zeros(g.shape, dtype=bool)
    wanted = set(stop)
    while heap:
        gv, (i, j) = heapq.heappop(heap)
        if settled[i, j] or gv > g[i, j]:
            continue
        settled[i, j] = True
        wanted.discard((i, j))
        if stop and not wanted:
            break
        for k, (di, dj) in enumerate(_NEIGHBOURS):
            n = (i + di, j + dj)
            if 0 <= n[0] < g.shape[0] and 0 <= n[1] < g.shape[1] and not settled[n]:
                back = (k + 4) % 8  # the popped node seen from n: in pairs back - 1 and back
                v = _update(g, cell_cost, *n, pairs=(back - 1, back))
                if v < g[n]:
                    g[n] = v
                    heapq.heappush(heap, (v, n))
    return g


def _cells(lo: Array, hi: Array, s: FieldDStarSettings) -> int:
    """Cells of the grid over the box ``lo``-``hi`` (m) with the margin."""
    size = np.ceil((hi - lo + 2 * s.margin) / s.cell)
    return int(max(size[0], 1.0) * max(size[1], 1.0))


def check_grid(points: Array, plans: int, s: FieldDStarSettings) -> int:
    """Refuse a cell size whose grids exceed :data:`GRID_CELLS` or whose run would plan more
    than :data:`PLANNED_CELLS`, before the run (named: ``FieldDStarSettings.cell``).

    Parameters
    ----------
    points
        Every point a grid must hold over the run, ``(n, 2)`` in m (start, goal, the
        obstacles' centres at each period and the rectangles' corners).
    plans
        Plans of the run (one a navigation period).
    s
        The settings.

    Returns
    -------
    int
        Cells of the largest grid.

    Examples
    --------
    >>> pts = np.array([[0.0, 0.0], [4.0, 1.0]])
    >>> check_grid(pts, 100, FieldDStarSettings())
    2800
    >>> check_grid(pts, 100, FieldDStarSettings(cell=0.0101))
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: FieldDStarSettings.cell = 0.0101 m is not allowed: ...
    """
    lo, hi = points.min(axis=0), points.max(axis=0)
    cells = _cells(lo, hi, s)
    extent = (
        f"{hi[0] - lo[0] + 2 * s.margin:.3g} m x {hi[1] - lo[1] + 2 * s.margin:.3g} m "
        f"(margin = {s.margin:g} m on each side)"
    )
    if not GRID_CELLS.within(cells):
        raise InvalidParameterError(
            "FieldDStarSettings.cell", s.cell,
            f"gives a grid of {cells} cells over the scene's {extent}; at most "
            f"{GRID_CELLS.le:.0f} cells are allowed: a larger cell or a smaller margin "
            "(docs/navigation_planners.md)", "m",
        )  # fmt: skip
    if not PLANNED_CELLS.within(cells * plans):
        raise InvalidParameterError(
            "FieldDStarSettings.cell", s.cell,
            f"gives {cells} cells a plan over {plans} plans ({cells * plans} cells); at most "
            f"{PLANNED_CELLS.le:.0f} are allowed: a larger cell or a shorter horizon "
            "(docs/navigation_planners.md)", "m",
        )  # fmt: skip
    return cells


class Grid:
    """The grid of one plan: origin, cell size, cell costs and node costs to the goal.

    Parameters
    ----------
    world
        The obstacles now (:class:`Snapshot`), inflated by the robot radius; a cell is
        blocked if the clearance at its centre is at most ``h / sqrt(2)``.
    robot
        The robot's position, ``(2,)`` (m); expansion stops once its cell's four nodes
        are settled.
    goal
        The goal position, ``(2,)`` (m), rounded to the nearest node.
    s
        Cell size h (m) and margin around the scene (m) (:class:`FieldDStarSettings`).
    """

    def __init__(self, world: Snapshot, robot: Array, goal: Array, s: FieldDStarSettings) -> None:
        pts = np.vstack([robot, goal, *world.centres] + [r.corners() for r in world.rectangles])
        self.h = s.cell
        self.origin = pts.min(axis=0) - s.margin
        size = np.maximum(np.ceil((pts.max(axis=0) + s.margin - self.origin) / self.h), 1)
        size = size.astype(int)  # a scene on one line with no margin: one cell wide
        check_grid(pts, 1, s)  # the robot may have left the box checked before the run
        centres = self.origin + (np.indices(size).reshape(2, -1).T + 0.5) * self.h
        blocked = world.clearance(centres) <= self.h / _SQRT2
        self.cost = np.where(blocked, math.inf, 1.0).reshape(size)
        goal_node = tuple(np.rint((goal - self.origin) / self.h).astype(int))
        # the robot's cell (one on the grid's far edge, as with no margin, is the last one)
        ci, cj = np.clip(np.floor((robot - self.origin) / self.h).astype(int), 0, size - 1)
        stop = ((ci, cj), (ci + 1, cj), (ci, cj + 1), (ci + 1, cj + 1))
        self.g = node_costs(self.cost, goal_node, stop) * self.h  # type: ignore[arg-type]

    def value(self, p: Array) -> Array:
        """Cost to the goal at points ``(n, 2)``: bilinear between the cell's node costs."""
        q = (np.atleast_2d(p) - self.origin) / self.h
        i = np.clip(np.floor(q[:, 0]).astype(int), 0, self.g.shape[0] - 2)
        j = np.clip(np.floor(q[:, 1]).astype(int), 0, self.g.shape[1] - 2)
        u, v = q[:, 0] - i, q[:, 1] - j
        g = self.g
        with np.errstate(invalid="ignore"):
            out = (g[i, j] * (1 - u) * (1 - v) + g[i + 1, j] * u * (1 - v)
                   + g[i, j + 1] * (1 - u) * v + g[i + 1, j + 1] * u * v)  # fmt: skip
        return np.where(np.isnan(out), math.inf, out)

    def next_point(self, p: Array, headings: int = 72) -> Array | None:
        """The point one cell away that lowers the interpolated cost most (None: no path)."""
        th = np.linspace(0.0, 2 * np.pi, headings, endpoint=False)
        q = p[None, :] + self.h * np.stack([np.cos(th), np.sin(th)], axis=1)
        total = self.value(q) + self.h
        k = int(np.argmin(total))
        return None if not math.isfinite(total[k]) else q[k]
