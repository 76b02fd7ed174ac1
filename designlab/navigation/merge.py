"""Merging static obstacles whose critical regions overlap (Zeng 2011, Sec. 6.4.3).

When two critical regions intersect, no path between the two obstacles stays outside both,
and the thesis merges the obstacles into one, merging both their critical and their active
regions. The thesis does not say how; :func:`merge_critical_regions` does it conservatively,
so that the merged regions contain the originals:

* two discs -> the smallest disc containing both critical discs (its radius is the merged
  r3); the merged r2 and body radius are the smallest, about the same centre, that contain
  both active discs and both bodies;
* a rectangle with a disc or another rectangle -> the axis-aligned rectangle bounding both
  bodies (rotated rectangles by their corners), with the larger clearance of the two as r3
  and as r2 (a disc's clearance from its body is r3 - rho_o, r2 - rho_o).

Pairs are merged one at a time until no critical regions intersect. Moving obstacles are
never merged (their overlap changes with time). A goal that ends up inside a merged
critical region is refused by :class:`~designlab.navigation.Scenario`.

Examples
--------
>>> from designlab.navigation import Disc, Scenario, Stationary
>>> pillar = lambda n, x: Disc(n, 0.1, r2=0.8, r3=0.4, motion=Stationary((x, 1.0)))
>>> sc = Scenario("gate", start=(4.0, 0.0), goal=(0.0, 0.0),
...               obstacles=(pillar("a", 2.0), pillar("b", 2.7)))
>>> merged = merge_critical_regions(sc)
>>> (o,) = merged.obstacles
>>> o.name, round(o.r3, 3), round(o.r2, 3), round(o.radius, 3)
('a+b', 0.75, 1.15, 0.45)
>>> merged.intersecting_critical_regions()
()
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from designlab.navigation.scenarios import Disc, Rectangle, Scenario, Stationary

__all__ = ["merge_critical_regions"]

Obstacle = Disc | Rectangle


def _centre(o: Disc) -> NDArray[np.float64]:
    return np.asarray(o.motion.state(np.zeros(1))[0][0], dtype=float)


def _merge_discs(a: Disc, b: Disc) -> Disc:
    ca, cb = _centre(a), _centre(b)
    d = float(np.hypot(*(cb - ca)))
    if d + b.r3 <= a.r3:
        c, R = ca, a.r3
    elif d + a.r3 <= b.r3:
        c, R = cb, b.r3
    else:
        R = (d + a.r3 + b.r3) / 2
        c = ca + (R - a.r3) * (cb - ca) / d
    off = [float(np.hypot(*(c - ca))), float(np.hypot(*(c - cb)))]
    r2 = max(off[0] + a.r2, off[1] + b.r2)
    rho = max(off[0] + a.radius, off[1] + b.radius)
    return Disc(f"{a.name}+{b.name}", rho, r2=max(r2, R + 1e-9), r3=R,
                motion=Stationary((float(c[0]), float(c[1]))))  # fmt: skip


def _body_points(o: Obstacle) -> NDArray[np.float64]:
    if isinstance(o, Rectangle):
        return np.asarray(o.corners(), dtype=float)
    c = _centre(o)
    return c + o.radius * np.array([[-1.0, -1.0], [1.0, 1.0]])


def _clearances(o: Obstacle) -> tuple[float, float]:
    """(r3, r2) measured from the body's contour."""
    if isinstance(o, Rectangle):
        return o.r3, o.r2
    return o.r3 - o.radius, o.r2 - o.radius


def _merge_boxes(a: Obstacle, b: Obstacle) -> Rectangle:
    pts = np.vstack([_body_points(a), _body_points(b)])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    (r3a, r2a), (r3b, r2b) = _clearances(a), _clearances(b)
    r3, r2 = max(r3a, r3b), max(r2a, r2b)
    centre = (float((lo[0] + hi[0]) / 2), float((lo[1] + hi[1]) / 2))
    return Rectangle(f"{a.name}+{b.name}", centre, float(hi[0] - lo[0]), float(hi[1] - lo[1]),
                     r2=max(r2, r3 + 1e-9), r3=r3)  # fmt: skip


def merge_critical_regions(scenario: Scenario) -> Scenario:
    """The scenario with every pair of static obstacles whose critical regions overlap merged.

    Parameters
    ----------
    scenario
        The scenario.

    Returns
    -------
    Scenario
        A copy (the same scenario if nothing overlaps); merged obstacles are named
        ``"a+b"`` and take the place of the first of the pair.
    """
    sc = scenario
    for _ in range(len(scenario.obstacles)):
        pairs = sc.intersecting_critical_regions()
        if not pairs:
            break
        na, nb, _overlap = pairs[0]
        by_name = {o.name: o for o in sc.obstacles}
        a, b = by_name[na], by_name[nb]
        both_discs = isinstance(a, Disc) and isinstance(b, Disc)
        merged = _merge_discs(a, b) if both_discs else _merge_boxes(a, b)
        obstacles = tuple(merged if o.name == na else o for o in sc.obstacles if o.name != nb)
        sc = sc.replace(obstacles=obstacles)
    return sc
