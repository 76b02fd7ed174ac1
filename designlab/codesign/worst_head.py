"""The worst head of a range, polished off the grid: a multi-start bounded local search.

The impact package's worst case (:mod:`designlab.impact.problem`) takes the worst
head of a grid over the range (the corners and, with 3 levels, the mid-points). The
worst head need not be on that grid: with a strongly damped foam the largest
compression lies inside the range, and a peak force or acceleration can peak on a ridge
between grid points (where the two largest peaks in time swap), and a metric can have
several local maxima (a peak force at a corner and a larger one along an edge). The metric
at v_c = 1 m/s is evaluated on a lattice of :data:`LATTICE_LEVELS` values per head
parameter (729 heads, corners, edges and faces included; about 2 ms of the kernel per
foam); :func:`refine_worst_head` starts from the grid's worst head and from each of the
best :data:`STARTS` local maxima of the lattice and maximises the metric over the box with
a derivative-free bounded pattern search (:func:`compass_search`: steps along the
axes and the diagonals, halving down to 1e-9 of the range, then :data:`ROUNDS` - 1
restarts along seeded rotations of that pattern, which climb ridges no fixed pattern
climbs; Kolda, Lewis and Torczon 2003), keeping the best. Guaranteed: the result is a head
of the range whose metric is at least the grid's worst head's and every lattice head's, and
is a local maximum of the pattern search. Not guaranteed: a separate maximum whose basin
falls between lattice points (narrower than 1/8 of the range) or beyond the best
:data:`STARTS` lattice maxima can be missed. The search of many foams runs in lock-step,
one kernel batch per step. :func:`grid_worst_heads` gives the
grid's worst head of many foams in one kernel batch, and :func:`refine_heads` polishes
each: the speed limit of one foam (:func:`~designlab.codesign.speed_limit`, through
:func:`worst_heads`) and the map over many (:func:`~designlab.codesign.speed_limit_map`)
both call it, so they agree exactly. For a link struck anywhere,
:func:`refine_link_worst` searches the impact point and the head together at a joint
speed, with the same multi-start (:func:`multi_start`: the grid's worst case and the best
local maxima of a lattice over the impact point and the head).

Examples
--------
>>> import designlab as dl
>>> from designlab.codesign.speed import SafetyCase, problem_for
>>> prob = problem_for(dl.impact.MANIPULATOR_1, SafetyCase(human_speed=0.0), 0.02)
>>> key = prob.keys()[0]
>>> m, head = refine_worst_head(prob, key, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 48.0)
>>> head.mass, bool(m >= 48.0)
(4.4, True)
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import maximum_filter

from designlab.impact import Criterion, Foam, HeadNeck
from designlab.impact.problem import FoamProblem

__all__ = [
    "LATTICE_LEVELS",
    "MAX_STEPS",
    "ROUNDS",
    "STARTS",
    "STEP_TOLERANCE",
    "compass_search",
    "grid_worst_heads",
    "multi_start",
    "refine_heads",
    "refine_link_worst",
    "refine_worst_head",
    "worst_heads",
]

#: Steps of the pattern search (each one kernel batch over the foams still searching).
MAX_STEPS = 400

#: The pattern search stops when its step is below this share of the range.
STEP_TOLERANCE = 1e-9

#: Rounds of the pattern search (the first along the axes and diagonals, then rotated).
ROUNDS = 4

#: Values per head parameter of the lattice whose local maxima start the search (9: its
#: 729 heads include the corners, edges, faces and the 3- and 5-level head grids).
LATTICE_LEVELS = 9

#: Most lattice local maxima (best first) the search starts from, per foam.
STARTS = 4

Array = NDArray[np.float64]


def _box(prob: FoamProblem) -> tuple[Array, Array]:
    """Lower and upper ends ``[M_h, C_h, K_h]`` of the head range."""
    hr = prob.head_range
    lo = np.array([hr.mass[0], hr.damping[0], hr.stiffness[0]], dtype=float)
    hi = np.array([hr.mass[1], hr.damping[1], hr.stiffness[1]], dtype=float)
    return lo, hi


def _directions(d: int) -> Array:
    """The 2d axis directions and the 2**d diagonals (unit steps) of a d-cube."""
    axes = np.vstack([np.eye(d), -np.eye(d)])
    diag = np.array(list(itertools.product((-1.0, 1.0), repeat=d)))
    return np.vstack([axes, diag])


def _direction_sets(d: int) -> list[Array]:
    """The pattern of each round: axes and diagonals, then seeded random rotations of it.

    A non-smooth metric (a peak over time whose two largest peaks swap) has ridges along
    which no fixed pattern climbs; the rotated patterns of the later rounds do.
    """
    base = _directions(d)
    sets = [base]
    for r in range(1, ROUNDS):
        q, _ = np.linalg.qr(np.random.default_rng(r).standard_normal((d, d)))
        sets.append(base @ q.T)
    return sets


def compass_search(
    values: Callable[[NDArray[np.int_], Array], Array], x0: Array, f0: Array,
    step: float = 0.25,
) -> tuple[Array, Array]:  # fmt: skip
    """Maximise a function over the unit box from each row of ``x0``, all rows in lock-step.

    Each step tries, for every start still searching, a step along each direction of the
    round's pattern (clipped to the box), in one call of ``values``; a point moves to its
    best trial if that beats it, else halves its step, until the step is below
    :data:`STEP_TOLERANCE` (or after :data:`MAX_STEPS`). The first round's pattern is the
    axes and the diagonals; each of the :data:`ROUNDS` - 1 later rounds restarts the step
    with a seeded random rotation of it (the same for every row, so a row's result does not
    depend on the others). The value never falls.

    Parameters
    ----------
    values
        ``values(rows, z)``: ``z`` is ``(m, t, d)``, trial points of the starts ``rows``
        (``(m,)`` indices into ``x0``); returns ``(m, t)`` finite values.
    x0, f0
        ``(n, d)`` starts and their values.
    step
        The first step of each round, a share of the range.

    Returns
    -------
    tuple
        ``(x, f)``: the points found and their values.

    Examples
    --------
    >>> peak = lambda rows, z: -((z - 0.3) ** 2).sum(axis=2)
    >>> x, f = compass_search(peak, np.zeros((2, 2)), np.full(2, -0.18))
    >>> np.round(x, 6).tolist(), bool(abs(f).max() < 1e-15)
    ([[0.3, 0.3], [0.3, 0.3]], True)
    """
    x, f = np.array(x0, dtype=float), np.array(f0, dtype=float)
    for dirs in _direction_sets(x.shape[1]):
        s = np.full(len(x), float(step))
        for _ in range(MAX_STEPS):
            idx = np.flatnonzero(s >= STEP_TOLERANCE)
            if idx.size == 0:
                break
            trial = np.clip(x[idx, None, :] + s[idx, None, None] * dirs[None], 0.0, 1.0)
            ft = values(idx, trial)
            j = np.argmax(ft, axis=1)
            best = ft[np.arange(idx.size), j]
            up = best > f[idx]
            x[idx[up]] = trial[np.flatnonzero(up), j[up]]
            f[idx[up]] = best[up]
            s[idx[~up]] *= 0.5
    return x, f


def _head(h: Array) -> HeadNeck:
    return HeadNeck(mass=float(h[0]), stiffness=float(h[2]), damping=float(h[1]))


def refine_worst_head(
    prob: FoamProblem, key: Criterion, foam: Foam, head: HeadNeck, metric: float
) -> tuple[float, HeadNeck]:
    """The worst metric at 1 m/s over the head range of a fixed robot, and its head.

    Parameters
    ----------
    prob
        The worst-case problem (a fixed robot, a head range).
    key
        The criterion.
    foam
        The foam.
    head
        The grid's worst head (the start).
    metric
        Its metric at v_c = 1 m/s.

    Returns
    -------
    tuple
        ``(metric, head)``: the larger of the grid's and the search's.
    """
    m, heads = refine_heads(prob, key, np.array([foam.stiffness]), np.array([foam.damping]),
                             [head], np.array([metric]))  # fmt: skip
    return float(m[0]), heads[0]


def _lattice(d: int) -> Array:
    """The :data:`LATTICE_LEVELS` ** d points of the unit box (corners, edges, faces)."""
    axis = np.linspace(0.0, 1.0, LATTICE_LEVELS)
    return np.stack(np.meshgrid(*[axis] * d, indexing="ij"), axis=-1).reshape(-1, d)


def _lattice_starts(vals: Array, d: int) -> tuple[NDArray[np.int_], NDArray[np.int_]]:
    """Each foam's best :data:`STARTS` local maxima of its lattice values ``vals`` ``(n, L)``.

    A lattice point is a local maximum when no point of its 3^d neighbourhood (clipped to
    the box) beats it; the lattice's maximum always is one. Returns ``(foam, point)``
    index pairs, best first per foam.
    """
    n = LATTICE_LEVELS
    cube = vals.reshape((len(vals),) + (n,) * d)
    peak = maximum_filter(cube, size=(1,) + (3,) * d, mode="nearest").reshape(vals.shape)
    score = np.where(vals >= peak, vals, -np.inf)
    top = np.argsort(-score, axis=1, kind="stable")[:, :STARTS]
    foam = np.repeat(np.arange(len(vals)), top.shape[1])
    point = top.ravel()
    keep = np.isfinite(score[foam, point])
    return foam[keep], point[keep]


def refine_heads(
    prob: FoamProblem, key: Criterion, k: Array, c: Array, heads: list[HeadNeck], f0: Array
) -> tuple[Array, list[HeadNeck]]:
    """The multi-start pattern search of each foam's worst head (the start kept unless beaten).

    The metric at v_c = 1 m/s is evaluated on a lattice of :data:`LATTICE_LEVELS` values per
    head parameter (corners, edges and faces of the range included); the pattern search
    (:func:`compass_search`) climbs from the start head and from each of the best
    :data:`STARTS` local maxima of the lattice, all foams and starts in lock-step, and the
    best is kept. The result is never below the start or any lattice head.

    Parameters
    ----------
    prob
        The worst-case problem of a fixed robot.
    key
        The criterion.
    k, c
        Foam stiffnesses and dampings, paired.
    heads, f0
        Each foam's start head and its metric at v_c = 1 m/s.

    Returns
    -------
    tuple
        ``(metrics, heads)``, one per foam.
    """
    lo, hi = _box(prob)
    span = hi - lo
    rows, _ = prob.robot_rows(None)
    unit = np.where(span > 0, 1.0 / np.where(span > 0, span, 1.0), 0.0)
    f0 = np.asarray(f0, dtype=float)
    x0 = (np.array([[h.mass, h.damping, h.stiffness] for h in heads]) - lo) * unit

    def values(foam: NDArray[np.int_], z: Array) -> Array:
        m, t, _ = z.shape
        flat = z.reshape(m * t, 3)
        at = np.repeat(foam, t)
        kk, cc = np.asarray(k, dtype=float)[at], np.asarray(c, dtype=float)[at]
        p = prob.contact.assemble(np.repeat(rows, m * t, axis=0), kk, cc, lo + flat * span)
        out = prob.contact.values(key, p, np.ones(m * t))
        return np.where(np.isfinite(out), out, 0.0).reshape(m, t)

    lattice = _lattice(3)
    on_lattice = values(np.arange(k.size), np.broadcast_to(lattice, (k.size, *lattice.shape)))
    foam, point = _lattice_starts(on_lattice, 3)
    of = np.concatenate([np.arange(k.size), foam])
    start = np.vstack([x0, lattice[point]])
    x, f = compass_search(lambda idx, z: values(of[idx], z), start,
                          np.concatenate([f0, on_lattice[foam, point]]))  # fmt: skip
    order = np.lexsort((-f, of))  # by foam, best first
    row = order[np.searchsorted(of[order], np.arange(k.size))]
    best_f = f[row]
    better = best_f > f0
    out = [_head(lo + x[r] * span) if b else h for r, b, h in zip(row, better, heads, strict=True)]
    return np.where(better, best_f, f0), out


def grid_worst_heads(
    prob: FoamProblem, key: Criterion, k: Array, c: Array
) -> tuple[Array, list[HeadNeck]]:
    """The worst metric at 1 m/s on the head grid of each foam ``(k[i], c[i])``, and its head.

    Parameters
    ----------
    prob
        The worst-case problem of a fixed robot.
    key
        The criterion.
    k, c
        Foam stiffnesses (N/m) and dampings (N s/m), paired.

    Returns
    -------
    tuple
        ``(metrics, heads)``, one per foam.
    """
    params, vv, nh = prob.designs(key, np.asarray(k, float), np.asarray(c, float))
    vals = prob.contact.values(key, params, vv).reshape(-1, nh)
    j = np.argmax(vals, axis=1)
    rows = params.reshape(-1, nh, params.shape[1])[np.arange(len(j)), j]
    heads = [HeadNeck(**prob.contact.head_values(r)) for r in rows]
    return vals[np.arange(len(j)), j], heads


def worst_heads(
    prob: FoamProblem, key: Criterion, k: Array, c: Array, refine: bool
) -> tuple[Array, list[HeadNeck]]:
    """The worst metric at 1 m/s over the head range of each foam, polished when asked.

    Parameters
    ----------
    prob
        The worst-case problem of a fixed robot.
    key
        The criterion.
    k, c
        Foam stiffnesses and dampings, paired.
    refine
        Polish each foam's grid worst head with :func:`refine_worst_head`.

    Returns
    -------
    tuple
        ``(metrics, heads)``, one per foam.
    """
    vals, heads = grid_worst_heads(prob, key, k, c)
    if not refine:
        return vals, heads
    k, c = np.asarray(k, dtype=float).ravel(), np.asarray(c, dtype=float).ravel()
    return refine_heads(prob, key, k, c, heads, vals)


def multi_start(values: Callable[[Array], Array], x0: Array, f0: float) -> tuple[Array, float, int]:
    """Maximise ``values`` over the unit d-box from ``x0`` and the best lattice local maxima.

    The lattice of :data:`LATTICE_LEVELS` values per axis (corners, edges and faces of the
    box included) is evaluated in one call; the pattern search (:func:`compass_search`)
    climbs from ``x0`` and from each of the best :data:`STARTS` local maxima of the lattice,
    in lock-step, and the best point is kept. The result is never below ``f0`` nor any
    lattice value: a separate maximum whose basin holds a lattice point is found even when
    a single start at ``x0`` would climb the wrong hill.

    Parameters
    ----------
    values
        ``values(z)``: ``z`` is ``(..., d)`` points of the unit box; returns ``z.shape[:-1]``
        finite values.
    x0, f0
        The start ``(d,)`` and its value.

    Returns
    -------
    tuple
        ``(x, f, starts)``: the best point, its value and the number of starts climbed.

    Examples
    --------
    >>> hill = lambda z: 1.0 - ((z - 0.2) ** 2).sum(axis=-1)        # a hill at the start
    >>> peak = lambda z: 3.0 - 10.0 * np.sqrt(((z - 0.7) ** 2).sum(axis=-1))
    >>> f = lambda z: np.maximum(hill(z), peak(z))
    >>> x, fx, n = multi_start(f, np.full(2, 0.2), 1.0)
    >>> np.round(x, 6).tolist(), round(fx, 6)
    ([0.7, 0.7], 3.0)
    """
    x0 = np.asarray(x0, dtype=float)
    d = x0.size
    lattice = _lattice(d)
    on = np.asarray(values(lattice), dtype=float)[None]
    _, point = _lattice_starts(on, d)
    start = np.vstack([x0[None], lattice[point]])
    f_start = np.concatenate([[float(f0)], on[0, point]])
    x, f = compass_search(lambda _, z: values(z), start, f_start)
    j = int(np.argmax(f))
    return x[j], float(f[j]), len(start)


def refine_link_worst(
    prob: FoamProblem, key: Criterion, foam: Foam, lever: float, metric: float
) -> tuple[float, float, HeadNeck | None]:
    """The worst metric of a link at its joint speed over the impact point and the head.

    A multi-start search over ``(lever arm, M_h, C_h, K_h)`` (:func:`multi_start`): from
    the grid's worst lever arm with the grid's worst head, and from the best local maxima
    of a :data:`LATTICE_LEVELS` ** 4 lattice of the box, so a worst case in another basin
    than the grid's (a head inside the range at another impact point) is found.

    Parameters
    ----------
    prob
        The worst-case problem of a :class:`~designlab.impact.LinkImpact` (its joint speed
        set).
    key
        The criterion.
    foam
        The foam.
    lever
        The grid search's worst lever arm, m.
    metric
        Its worst metric there (over the head grid).

    Returns
    -------
    tuple
        ``(metric, lever, head)``: the search's when it beats ``metric``, else
        ``(metric, lever, None)``.
    """
    lo_h, hi_h = _box(prob)
    lr = prob.robot
    lo = np.concatenate([[lr.lever_arm_min], lo_h])
    span = np.concatenate([[lr.lever_arm_max], hi_h]) - lo

    def values(u: Array) -> Array:
        z = lo + u.reshape(-1, 4) * span
        rows, v = prob.robot_rows(z[:, 0])
        n = len(z)
        p = prob.contact.assemble(
            rows, np.full(n, foam.stiffness), np.full(n, foam.damping), z[:, 1:]
        )
        out = prob.contact.values(key, p, v)
        return np.where(np.isfinite(out), out, 0.0).reshape(u.shape[:-1])

    heads = prob.heads_for(key)
    unit = np.where(span > 0, 1.0 / np.where(span > 0, span, 1.0), 0.0)
    starts = (np.column_stack([np.full(len(heads), lever), heads]) - lo) * unit
    f_starts = values(starts)
    j = int(np.argmax(f_starts))
    x, f, _ = multi_start(values, starts[j], float(f_starts[j]))
    if not f > metric:
        return metric, lever, None
    z = lo + x * span
    return f, float(z[0]), _head(z[1:])
