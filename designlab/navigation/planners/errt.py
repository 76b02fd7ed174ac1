"""Execution-extended RRT (Bruce & Veloso 2002; 2006), replanned every navigation period.

A rapidly-exploring random tree grows from the robot towards, with probability
``goal_bias``, the goal; with probability ``waypoint_bias``, a waypoint cached from the
previous plan (what makes ERRT's replanning cheap and its plans coherent); otherwise a
uniform random point of the scene's box. Each extension moves ``step`` towards the
target if the segment keeps a positive clearance from the obstacles *as they are now*.
The plan is the tree path to the goal (or, if the goal is not reached within
``max_nodes``, to the node nearest it), shortened by straight-line shortcuts.

Examples
--------
In free space the plan is the straight line to the goal:

>>> import numpy as np
>>> from designlab.navigation import Scenario
>>> w = Snapshot.of(Scenario("free", (4.0, 0.0), (0.0, 0.0)), 0.0)
>>> path, cache = plan(w, np.array([4.0, 0.0]), np.array([0.0, 0.0]), ERRTSettings(),
...                    np.random.default_rng(0), np.zeros((0, 2)))
>>> path.tolist()
[[4.0, 0.0], [0.0, 0.0]]
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from designlab.navigation.planners.parameters import ERRTSettings
from designlab.navigation.planners.world import Snapshot

__all__ = ["ERRTSettings", "Snapshot", "plan", "shortcut"]

Array = NDArray[np.float64]
#: Waypoints kept from one plan for the next.
CACHE_SIZE = 50
#: Extension attempts per node allowed (a plan gives up after ATTEMPTS * max_nodes).
ATTEMPTS = 4


def _box(world: Snapshot, start: Array, goal: Array, margin: float) -> tuple[Array, Array]:
    pts = [start, goal, *world.centres]
    pts += [r.corners() for r in world.rectangles]
    allp = np.vstack([np.atleast_2d(p) for p in pts])
    return allp.min(axis=0) - margin, allp.max(axis=0) + margin


def _target(rng: np.random.Generator, s: ERRTSettings, goal: Array, cache: Array,
            box: tuple[Array, Array]) -> Array:  # fmt: skip
    r = rng.random()
    if r < s.goal_bias:
        return goal
    if r < s.goal_bias + s.waypoint_bias and len(cache):
        return np.asarray(cache[rng.integers(len(cache))])
    return box[0] + rng.random(2) * (box[1] - box[0])


def _free(world: Snapshot, a: Array, b: Array, escaping: bool, inside: float) -> bool:
    """A free extension; from a start inside an obstacle, any step that moves out of it."""
    if escaping:
        return bool(world.clearance(b)[0] > inside)
    return world.segment_free(a, b)


def _grow(world: Snapshot, start: Array, goal: Array, s: ERRTSettings,
          rng: np.random.Generator, cache: Array) -> tuple[Array, Array, int]:  # fmt: skip
    """The tree (nodes, parents) and the index of the node that reached the goal (-1: none)."""
    box = _box(world, start, goal, s.margin)
    nodes = np.zeros((s.max_nodes + 1, 2))
    parent = np.full(s.max_nodes + 1, -1)
    nodes[0], n = start, 1
    inside = float(world.clearance(start)[0])  # <= 0: the robot is already too close
    for _ in range(ATTEMPTS * s.max_nodes):
        if n >= s.max_nodes:
            break
        target = _target(rng, s, goal, cache, box)
        near = int(np.argmin(np.hypot(*(nodes[:n] - target).T)))
        delta = target - nodes[near]
        dist = float(np.hypot(*delta))
        new = target if dist <= s.step else nodes[near] + delta / dist * s.step
        if dist == 0 or not _free(world, nodes[near], new, near == 0 and inside <= 0, inside):
            continue
        nodes[n], parent[n] = new, near
        n += 1
        if np.hypot(*(goal - new)) <= s.step and world.segment_free(new, goal):
            nodes[n], parent[n] = goal, n - 1
            return nodes[: n + 1], parent[: n + 1], n
    return nodes[:n], parent[:n], -1


def shortcut(world: Snapshot, path: Array) -> Array:
    """Greedy shortcuts: from each vertex, jump to the farthest one in sight.

    Parameters
    ----------
    world
        The obstacles now (:class:`Snapshot`), inflated by the robot radius.
    path
        The path's vertices in order, ``(n, 2)`` (m); the first and last are kept.
    """
    out, i = [path[0]], 0
    while i < len(path) - 1:
        j = len(path) - 1
        while j > i + 1 and not world.segment_free(path[i], path[j]):
            j -= 1
        out.append(path[j])
        i = j
    return np.asarray(out)


def plan(
    world: Snapshot,
    start: Array,
    goal: Array,
    settings: ERRTSettings,
    rng: np.random.Generator,
    cache: Array,
) -> tuple[Array, Array]:
    """One ERRT plan from ``start`` to ``goal`` and the waypoint cache for the next one.

    Parameters
    ----------
    world
        The obstacles now (:class:`Snapshot`), inflated by the robot radius.
    start
        The robot's position, ``(2,)`` (m): the root of the tree.
    goal
        The goal position, ``(2,)`` (m).
    settings
        Step, node budget, goal and waypoint biases and sampling-box margin
        (:class:`ERRTSettings`).
    rng
        The random generator of the samples (advanced in place, kept across plans).
    cache
        Waypoints of the previous plan, ``(k, 2)`` (m; ``(0, 2)``: none).
    """
    if world.segment_free(start, goal):
        path = np.vstack([start, goal])
        return path, path
    nodes, parent, end = _grow(world, start, goal, settings, rng, cache)
    if end < 0:  # the best partial plan: to the node nearest the goal
        end = int(np.argmin(np.hypot(*(nodes - goal).T)))
    idx = [end]
    while parent[idx[-1]] >= 0:
        idx.append(int(parent[idx[-1]]))
    path = nodes[idx[::-1]]
    if len(path) < 2:
        return np.vstack([start, start]), cache
    smooth = shortcut(world, path)
    return smooth, path[-CACHE_SIZE:]
