"""The robot side's per-period bookkeeping of a crowd run, compiled (numba, cached on disk).

:func:`~designlab.navigation.crowds.simulate.simulate_crowd` spends, per navigation period,
one compiled step of the robot and the bookkeeping around it: the slots from the sensed
pedestrians (:func:`fill_candidates`) and the arrival, distance, energy and walkable-area
measures (:func:`period_measures`). Each is one call of a numba kernel
(:func:`designlab.sx.jit.kernel`) doing what the numpy code before it did, operation by
operation (IEEE, no fast-math; the sums in numpy's pairwise order, :func:`pairwise_sum`), so
the runs are bit-identical to it (``tests/navigation/crowds/test_bookkeeping.py``).

The walkable area is tested by :func:`inside_area` on the edges of its rings
(:func:`area_edges`): a point is inside when it is in the polygon's interior, as
``shapely.contains_xy`` (a point on an edge is not). The crossing-number test and the
on-edge test are exact for axis-aligned edges (every layout of
:mod:`~designlab.navigation.crowds.layouts`); :func:`area_edges` returns ``None`` for a
polygon with another edge and the caller keeps shapely.

Examples
--------
>>> from shapely.geometry import box
>>> E = area_edges(box(0.0, 0.0, 2.0, 1.0))
>>> bool(inside_area(E, 1.0, 0.5)), bool(inside_area(E, 2.0, 0.5)), bool(inside_area(E, 3.0, 0.5))
(True, False, False)
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.sx.jit import kernel

__all__ = [
    "area_edges",
    "farthest_from_path",
    "fill_candidates",
    "inside_area",
    "pairwise_sum",
    "period_measures",
]

Array = NDArray[np.float64]


def area_edges(area: Any) -> Array | None:
    """The edges ``(m, 4)`` (x1, y1, x2, y2) of a polygon's rings (exterior and holes), or
    ``None`` when an edge is not axis-aligned (:func:`inside_area` is exact for those only).

    Parameters
    ----------
    area
        A shapely ``Polygon`` or ``MultiPolygon``.

    Examples
    --------
    >>> from shapely.geometry import Polygon, box
    >>> area_edges(box(0.0, 0.0, 2.0, 1.0)).shape
    (4, 4)
    >>> area_edges(Polygon([(0, 0), (1, 0), (0, 1)])) is None
    True
    """
    polygons = getattr(area, "geoms", [area])
    rows = []
    for poly in polygons:
        for ring in (poly.exterior, *poly.interiors):
            xy = np.asarray(ring.coords, dtype=float)
            rows.append(np.hstack([xy[:-1], xy[1:]]))
    edges = np.concatenate(rows) if rows else np.zeros((0, 4))
    straight = (edges[:, 0] == edges[:, 2]) | (edges[:, 1] == edges[:, 3])
    return np.ascontiguousarray(edges) if bool(straight.all()) else None


@kernel
def inside_area(edges: Array, x: float, y: float) -> bool:
    """Whether (x, y) is in the interior of the polygon of ``edges`` (:func:`area_edges`):
    not on an edge, and inside by the crossing number (even-odd over every ring).

    Parameters
    ----------
    edges
        ``(m, 4)`` axis-aligned edges.
    x, y
        The point, m (NaN: outside).
    """
    inside = False
    for i in range(edges.shape[0]):
        x1, y1, x2, y2 = edges[i, 0], edges[i, 1], edges[i, 2], edges[i, 3]
        if min(x1, x2) <= x <= max(x1, x2) and min(y1, y2) <= y <= max(y1, y2):
            return False  # on an axis-aligned edge (its bounding box is the edge)
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            inside = not inside
    return inside


@kernel
def _block_sum(a: Array, lo: int, n: int) -> float:
    """numpy's pairwise sum of a block of at most 128 (eight partial sums from 8 on)."""
    if n < 8:
        res = 0.0
        for i in range(lo, lo + n):
            res += a[i]
        return res
    r0, r1, r2, r3 = a[lo], a[lo + 1], a[lo + 2], a[lo + 3]
    r4, r5, r6, r7 = a[lo + 4], a[lo + 5], a[lo + 6], a[lo + 7]
    i = 8
    while i < n - (n % 8):
        j = lo + i
        r0, r1, r2, r3 = r0 + a[j], r1 + a[j + 1], r2 + a[j + 2], r3 + a[j + 3]
        r4, r5, r6, r7 = r4 + a[j + 4], r5 + a[j + 5], r6 + a[j + 6], r7 + a[j + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[lo + i]
        i += 1
    return res


@kernel
def pairwise_sum(a: Array, lo: int, n: int) -> float:
    """``a[lo:lo + n].sum()`` of a contiguous float64 array in numpy's order (pairwise: halves
    cut at a multiple of 8 down to blocks of at most 128, each with eight partial sums), so
    bit-identical to numpy's. Without recursion (numba's disk cache does not keep recursive
    functions): the halves are visited depth first on an explicit stack.

    Parameters
    ----------
    a
        The array.
    lo, n
        Start and length of the slice.
    """
    task = np.empty((128, 3), np.int64)  # (start, length, 0: sum it | 1: add the last two)
    vals = np.empty(128)
    task[0, 0], task[0, 1], task[0, 2] = lo, n, 0
    nt, nv = 1, 0
    while nt:
        nt -= 1
        start, m, kind = task[nt, 0], task[nt, 1], task[nt, 2]
        if kind == 1:
            nv -= 1
            vals[nv - 1] = vals[nv - 1] + vals[nv]
        elif m <= 128:
            vals[nv] = _block_sum(a, start, m)
            nv += 1
        else:
            m2 = m // 2
            m2 -= m2 % 8
            task[nt, 0], task[nt, 1], task[nt, 2] = 0, 0, 1
            task[nt + 1, 0], task[nt + 1, 1], task[nt + 1, 2] = start + m2, m - m2, 0
            task[nt + 2, 0], task[nt + 2, 1], task[nt + 2, 2] = start, m2, 0
            nt += 3
    return vals[0]


@kernel(inline=True)
def _fmin(m: float, d: float) -> float:
    """``np.fmin``: the smaller, ignoring a NaN."""
    if m != m or d < m:
        return d
    return m


@kernel(inline=True)
def _wall_point(walls: Array, x: float, y: float) -> float:
    """Contour distance from (x, y) to the nearest wall (rows: centre, cos, sin, half length,
    half width), as ``Rectangle.contour_distance``."""
    best = math.inf
    for w in range(walls.shape[0]):
        cx, cy, c, s = walls[w, 0], walls[w, 1], walls[w, 2], walls[w, 3]
        hl, hw = walls[w, 4], walls[w, 5]
        rx, ry = x - cx, y - cy
        dx = abs(c * rx + s * ry) - hl
        dy = abs(-s * rx + c * ry) - hw
        dx = dx if not dx < 0.0 else 0.0
        dy = dy if not dy < 0.0 else 0.0
        d = math.hypot(dx, dy)
        if d < best:  # as min(best, d) in Python
            best = d
    return best


@kernel(inline=True)
def _wall_min(walls: Array, X: Array, upto: int) -> float:
    """Smallest contour distance from the first ``upto`` points of ``X`` to the walls (NaN
    propagates, as numpy's ``min``)."""
    best = math.inf
    for w in range(walls.shape[0]):
        cx, cy, c, s = walls[w, 0], walls[w, 1], walls[w, 2], walls[w, 3]
        hl, hw = walls[w, 4], walls[w, 5]
        for i in range(upto):
            rx, ry = X[0, i] - cx, X[1, i] - cy
            dx = abs(c * rx + s * ry) - hl
            dy = abs(-s * rx + c * ry) - hw
            dx = dx if not dx < 0.0 else 0.0
            dy = dy if not dy < 0.0 else 0.0
            d = math.hypot(dx, dy)
            if d < best or d != d:
                best = d
                if d != d:
                    return d
    return best


@kernel
def _pedestrian_min(
    X: Array, upto: int, ring: Array, rows: NDArray[np.int64], count: int, px: float, py: float,
    frac: Array, reach: float, d0: Array,
) -> tuple[float, float]:  # fmt: skip
    """(nearest at the period's start, nearest over its dynamics steps): NaN when none."""
    r0 = rows[0]
    m0 = math.nan
    for i in range(count):
        d0[i] = math.hypot(ring[r0, i, 0] - px, ring[r0, i, 1] - py)
        m0 = _fmin(m0, d0[i])
    m = math.nan
    if m0 != m0:
        return m0, m
    q = frac.size
    for i in range(count):
        if not d0[i] < reach:
            continue
        for j in range(rows.size - 1):
            a, b = rows[j], rows[j + 1]
            gx, gy = ring[a, i, 0], ring[a, i, 1]
            hx, hy = ring[b, i, 0] - gx, ring[b, i, 1] - gy
            for k in range(q):
                idx = j * q + k
                if idx >= upto:
                    break
                d = math.hypot(gx + frac[k] * hx - X[0, idx], gy + frac[k] * hy - X[1, idx])
                m = _fmin(m, d)
    return m0, m


@kernel
def period_measures(
    X: Array, goal: Array, tol: float, ring: Array, rows: NDArray[np.int64], count: int,
    state: Array, frac: Array, reach: float, d0: Array, walls: Array, wall_slack: float,
    w2: float, energy: Array, edges: Array, check_area: bool,
) -> tuple[int, float, bool]:  # fmt: skip
    """The measures of one navigation period (``simulate_crowd``'s numpy bookkeeping fused).

    Parameters
    ----------
    X
        ``(nx, n_sub)`` the robot's states at the ends of the period's dynamics steps.
    goal, tol
        The goal (m) and the arrival tolerance (m).
    ring, rows, count
        The pedestrians' positions ``ring[rows[j], :count]`` at the period's pedestrian steps
        (``rows``: ``per + 1`` ring rows, oldest first).
    state
        ``[d_min, w_min, w_last, x0, y0]``: running minima of the centre distance to the
        pedestrians and of the contour distance to the walls, the wall distance at the
        previous period's end and the robot at the period's start; the minima and ``w_last``
        are updated in place.
    frac
        ``(q,)`` the dynamics steps' fractions of a pedestrian step, ``(1..q) / q``.
    reach
        R = r2 + (V_mr + v_0,max) T_s: pedestrians nearer than this at the start are
        measured at every dynamics step.
    d0
        Scratch of at least ``count`` floats.
    walls, wall_slack, w2
        Wall rows (centre, cos, sin, half length, half width), V_mr T_s and the walls' r2:
        the walls are measured at every dynamics step when one may come within r2.
    energy
        ``(n_sub,)`` the energy per dynamics step (summed up to the arrival).
    edges, check_area
        The walkable area's edges and whether to test the period's last point.

    Returns
    -------
    tuple
        (index of the first dynamics step within ``tol`` of the goal, -1 if none; the energy
        sum up to it, or over the period; whether the period's last point is outside the
        walkable area (False when not checked)).
    """
    n_sub = X.shape[1]
    hit = -1
    for i in range(n_sub):
        if math.hypot(X[0, i] - goal[0], X[1, i] - goal[1]) <= tol:
            hit = i
            break
    upto = hit + 1 if hit >= 0 else n_sub
    m0, m = _pedestrian_min(X, upto, ring, rows, count, state[3], state[4], frac, reach, d0)
    if m0 == m0:
        if m0 < state[0]:
            state[0] = m0
        if m == m and m < state[0]:
            state[0] = m
    if walls.shape[0]:
        start = state[2]
        state[2] = _wall_point(walls, X[0, upto - 1], X[1, upto - 1])
        if start - wall_slack > w2:
            if start < state[1]:
                state[1] = start
            if state[2] < state[1]:
                state[1] = state[2]
        else:
            full = _wall_min(walls, X, upto)
            if full < state[1]:
                state[1] = full
    outside = check_area and not inside_area(edges, X[0, n_sub - 1], X[1, n_sub - 1])
    return hit, pairwise_sum(energy, 0, upto), outside


@kernel
def fill_candidates(
    ring: Array, rows: NDArray[np.int64], count: int, x: float, y: float, r2sq: float,
    dt: float, obs: Array, parked: Array, lim: float, d2: Array, order: NDArray[np.int64],
) -> tuple[int, bool]:  # fmt: skip
    """The slots of the pedestrians sensed at a period's start (within r2 of the robot).

    Parameters
    ----------
    ring, rows, count
        The last three pedestrian frames ``ring[rows[j], :count]``, oldest first.
    x, y
        The robot, m.
    r2sq
        r2 squared, m^2 (candidates: d^2 < r2^2).
    dt
        The pedestrian step, s (backward differences; 0 where an earlier frame is unknown).
    obs
        ``(K, 6)`` the slots (position, velocity, acceleration), nearest first, written when
        there are at most K candidates; the others get the rows of ``parked``.
    parked
        ``(K, 6)`` empty slots.
    lim
        2 r3: two candidates nearer than this have intersecting critical regions.
    d2, order
        Scratch of at least ``count`` floats and integers.

    Returns
    -------
    tuple
        (candidates n; whether two of the first min(n, K) slots' critical regions
        intersect, False when n > K: the slots were not written).
    """
    a, b, c = rows[0], rows[1], rows[2]
    n = 0
    for i in range(count):
        dx, dy = ring[c, i, 0] - x, ring[c, i, 1] - y
        d = dx * dx + dy * dy
        if d < r2sq:  # NaN (not in) compares False
            j = n  # insertion: a stable sort by d^2
            while j > 0 and d2[j - 1] > d:
                d2[j], order[j] = d2[j - 1], order[j - 1]
                j -= 1
            d2[j], order[j] = d, i
            n += 1
    K = obs.shape[0]
    if n > K:
        return n, False
    for s in range(n, K):
        obs[s, :] = parked[s, :]
    for s in range(n):
        i = order[s]
        px, py = ring[c, i, 0], ring[c, i, 1]
        vx, vy = (px - ring[b, i, 0]) / dt, (py - ring[b, i, 1]) / dt
        ax = (vx - (ring[b, i, 0] - ring[a, i, 0]) / dt) / dt
        ay = (vy - (ring[b, i, 1] - ring[a, i, 1]) / dt) / dt
        obs[s, 0], obs[s, 1] = px, py
        obs[s, 2] = 0.0 if vx != vx else vx
        obs[s, 3] = 0.0 if vy != vy else vy
        obs[s, 4] = 0.0 if ax != ax else ax
        obs[s, 5] = 0.0 if ay != ay else ay
    for s in range(n):
        for t in range(s + 1, n):
            if math.hypot(obs[s, 0] - obs[t, 0], obs[s, 1] - obs[t, 1]) < lim:
                return n, True
    return n, False


@kernel
def farthest_from_path(points: Array, path: Array) -> float:
    """The largest distance of ``points`` ``(P, 2)`` from the polyline ``path`` ``(S + 1, 2)``
    (m; S >= 1): :func:`~designlab.navigation.crowds.metrics.point_to_path`'s maximum, the
    same nearest point of each segment, without its ``(P, S, 2)`` temporaries (a pedestrian's
    path deviation took a quarter of a dense crowd run's time through them).

    Parameters
    ----------
    points
        Points ``(P, 2)``, P >= 1.
    path
        Vertices ``(S + 1, 2)`` of the polyline, S >= 1.
    """
    worst = 0.0
    for p in range(points.shape[0]):
        qx, qy = points[p, 0], points[p, 1]
        best = np.inf
        for s in range(path.shape[0] - 1):
            ax, ay = path[s, 0], path[s, 1]
            bx, by = path[s + 1, 0] - ax, path[s + 1, 1] - ay
            ll = bx * bx + by * by
            t = ((qx - ax) * bx + (qy - ay) * by) / ll if ll > 0 else 0.0
            t = min(max(t, 0.0), 1.0)
            dx, dy = qx - (ax + t * bx), qy - (ay + t * by)
            d = math.sqrt(dx * dx + dy * dy)
            if d < best:
                best = d
        if best > worst:
            worst = best
    return worst
