"""The boundary solver of the foam envelope: every sign change in K_c, polished by Illinois.

For each foam damping C_c and each constraint of a :class:`~designlab.impact.problem.FoamProblem`
the boundary in the foam stiffness K_c is a bracketed root in log K_c: a scan
over the whole stiffness range finds every sign change (so a root cannot be
missed silently, and more than one is reported), then vectorised Illinois
iterations polish the brackets to ``rtol``. Every point carries a status:
``bounded``, ``unbounded`` (the constraint holds over the whole range) or
``no_solution`` (it holds nowhere). :func:`solve_boundaries` solves several
problems (fixed robots differing in their limits) in one root-finding.

Examples
--------
>>> import numpy as np
>>> from designlab.impact import MANIPULATOR_1
>>> from designlab.impact.problem import make_problem
>>> prob = make_problem(MANIPULATOR_1, 1.25, None, 0.02, None, False, 1.0, 0.05)
>>> (sol,) = solve_boundaries([prob], [np.array([0.0, 100.0])], (1e2, 1e7), 1e-6)
>>> (sol.stiffness_max / 1e3).round(2).tolist(), (sol.stiffness_min / 1e3).round(2).tolist()
([46.04, 58.77], [16.67, 11.92])
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from designlab.impact.criteria import Criterion
from designlab.impact.metrics import ImpactStatus
from designlab.impact.problem import FoamLanes, FoamProblem
from designlab.results import Status

__all__ = [
    "BoundarySolution",
    "BoundaryStatus",
    "boundary",
    "flag_boundary_designs",
    "illinois",
    "solve_boundaries",
    "upper_bounds",
]


class BoundaryStatus(Status):
    """Status of one boundary of the foam envelope at one damping value.

    Attributes
    ----------
    BOUNDED
        The constraint changes sign in the stiffness range: the boundary is there.
    UNBOUNDED
        The constraint holds over the whole stiffness range.
    NO_SOLUTION
        The constraint holds nowhere in the stiffness range.
    """

    BOUNDED = "bounded"
    UNBOUNDED = "unbounded"
    NO_SOLUTION = "no_solution"


def illinois(
    fun: Callable[[NDArray, NDArray], NDArray],
    a: NDArray,
    b: NDArray,
    fa: NDArray,
    fb: NDArray,
    c: NDArray,
    tol: float,
    max_iter: int = 100,
) -> NDArray:
    """Vectorised Illinois (modified regula falsi) on brackets with ``fa * fb < 0``.

    Parameters
    ----------
    fun
        ``fun(x, c)``: the function of each lane (``c`` its context).
    a, b, fa, fb
        The brackets and the function's values at their ends.
    c
        The lanes' contexts.
    tol
        Bracket width at which a lane has converged.
    max_iter
        Most iterations.

    Returns
    -------
    numpy.ndarray
        The end of the final bracket where ``f <= 0`` (the feasible side).
    """
    a, b, fa, fb = a.copy(), b.copy(), fa.copy(), fb.copy()
    x = 0.5 * (a + b)
    act = np.flatnonzero(np.abs(b - a) > tol)
    side = np.zeros(a.size, dtype=int)
    for _ in range(max_iter):
        if act.size == 0:
            break
        aa, bb, ffa, ffb = a[act], b[act], fa[act], fb[act]
        with np.errstate(divide="ignore", invalid="ignore"):
            xx = bb - ffb * (bb - aa) / (ffb - ffa)
        bad = ~np.isfinite(xx) | (xx <= np.minimum(aa, bb)) | (xx >= np.maximum(aa, bb))
        xx = np.where(bad, 0.5 * (aa + bb), xx)
        fx = fun(xx, c[act])
        same = np.sign(fx) == np.sign(ffb)
        # replace b by x; if b's side repeats, halve the stale end's value (Illinois)
        a[act] = np.where(same, aa, bb)
        fa[act] = np.where(same, np.where(side[act] == 1, ffa / 2, ffa), ffb)
        b[act] = xx
        fb[act] = fx
        side[act] = np.where(same, 1, -1)
        x[act] = xx
        # converged when the bracket is small or the residual (a log-ratio of the
        # metric to its limit) is far below the requested relative accuracy
        done = (np.abs(b[act] - a[act]) <= tol) | (np.abs(fx) <= 1e-3 * tol)
        act = act[~done]
    # the end of the final bracket on the feasible side (excess <= 0): where the metric
    # jumps (a delicate first lobe), the root is the jump and the boundary must not be
    # reported on its violated side. A point converged on its residual (|excess| far
    # below the accuracy) is the root itself, even if its bracket is still wide.
    small = np.abs(b - a) <= tol
    return np.where(fb <= 0, b, np.where(small & (fa <= 0), a, x))


def boundary(
    prob: FoamProblem, key: Criterion, c: NDArray, u_grid: NDArray, tol: float
) -> tuple[NDArray, NDArray, NDArray]:
    """One boundary for every damping value: (K, status, multiple-root flag).

    For a criterion (upper boundary) the feasible side is ``excess < 0`` at small
    K; for the compression (lower boundary) the feasible side is at large K.

    Parameters
    ----------
    prob
        The problem.
    key
        The constraint (a criterion or the thickness limit).
    c
        The lanes (damping values, or lane indices of :class:`FoamLanes`).
    u_grid
        The scan in log K_c.
    tol
        Accuracy in log K_c.

    Returns
    -------
    tuple
        The boundary K_c (NaN where not bounded), its :class:`BoundaryStatus`, whether
        the constraint changes sign more than once, and the floor of a criterion violated
        at the soft end and met further up (a foam so soft that it is crushed: a
        densifying foam's, :mod:`designlab.impact.contact.hunt_crossley`), K_c below which
        it is violated again (NaN where the soft end meets it).
    """
    n, ns = c.size, u_grid.size
    ex = prob.log_excess(key, np.tile(u_grid, n), np.repeat(c, ns)).reshape(n, ns)
    viol = ex > 0
    changes = np.diff(viol.astype(int), axis=1) != 0
    n_changes = changes.sum(axis=1)
    upper = key.boundary == "upper"
    status = np.full(n, BoundaryStatus.BOUNDED, dtype=object)
    k_out = np.full(n, np.nan)
    floor = np.full(n, np.nan)
    if upper:
        status[~viol.any(axis=1)] = BoundaryStatus.UNBOUNDED
        status[viol.all(axis=1)] = BoundaryStatus.NO_SOLUTION
        floor = _floor(prob, key, c, u_grid, ex, tol)
        # first feasible -> violated transition (above the floor)
        trans = (~viol[:, :-1]) & viol[:, 1:]
    else:
        status[~viol.any(axis=1)] = BoundaryStatus.UNBOUNDED
        status[viol.all(axis=1)] = BoundaryStatus.NO_SOLUTION
        # last violated -> feasible transition
        trans = viol[:, :-1] & (~viol[:, 1:])
        trans = trans & (np.cumsum(trans[:, ::-1], axis=1)[:, ::-1] == 1)
    has = trans.any(axis=1) & (status == BoundaryStatus.BOUNDED)
    status[(status == BoundaryStatus.BOUNDED) & ~has] = BoundaryStatus.NO_SOLUTION
    idx = np.flatnonzero(has)
    if idx.size:
        j = trans[idx].argmax(axis=1)
        a, b = u_grid[j], u_grid[j + 1]
        fa, fb = ex[idx, j], ex[idx, j + 1]
        u = illinois(lambda x, cc: prob.log_excess(key, x, cc), a, b, fa, fb, c[idx], tol)
        k_out[idx] = np.exp(u)
    return k_out, status.astype(str), n_changes > 1, floor


def _floor(
    prob: FoamProblem, key: Criterion, c: NDArray, u_grid: NDArray, ex: NDArray, tol: float
) -> NDArray[np.float64]:
    """K_c of the first violated -> met transition of lanes violated at the soft end."""
    viol = ex > 0
    floor = np.full(c.size, np.nan)
    idx = np.flatnonzero(viol[:, 0] & ~viol.all(axis=1))
    if idx.size:
        j = (~viol[idx]).argmax(axis=1) - 1
        a, b = u_grid[j], u_grid[j + 1]
        fa, fb = ex[idx, j], ex[idx, j + 1]
        u = illinois(lambda x, cc: prob.log_excess(key, x, cc), a, b, fa, fb, c[idx], tol)
        floor[idx] = np.exp(u)
    return floor


def upper_bounds(
    prob: FoamProblem, damping: NDArray, u_grid: NDArray, tol: float
) -> tuple[dict[str, NDArray], dict[str, NDArray], NDArray, NDArray]:
    """Every criterion's upper boundary and status, and their minimum (NaN if none bounded).

    Parameters
    ----------
    prob
        The problem.
    damping
        The lanes.
    u_grid
        The scan in log K_c.
    tol
        Accuracy in log K_c.

    Returns
    -------
    tuple
        Per criterion its bound and status, the smallest bound, the multiple-root flags
        and the largest floor of the criteria (NaN where none has one; see :func:`boundary`).
    """
    upper: dict[str, NDArray] = {}
    upper_status: dict[str, NDArray] = {}
    multiple = np.zeros(damping.size, dtype=bool)
    floor = np.full(damping.size, np.nan)
    for crit in prob.criteria:
        k, st, mult, low = boundary(prob, crit, damping, u_grid, tol)
        floor = np.fmax(floor, low)
        upper[crit.name] = k
        upper_status[crit.name] = st
        multiple |= mult
    kmax = np.full(damping.size, np.inf)
    any_bounded = np.zeros(damping.size, dtype=bool)
    for name in upper:
        bounded = upper_status[name] == BoundaryStatus.BOUNDED
        kmax = np.where(bounded, np.minimum(kmax, upper[name]), kmax)
        any_bounded |= bounded
    return upper, upper_status, np.where(any_bounded, kmax, np.nan), multiple, floor


def flag_boundary_designs(
    prob: FoamProblem, damping: NDArray, kmax: NDArray, kmin: NDArray
) -> tuple[NDArray, NDArray, NDArray]:
    """Overdamped and delicate flags of the boundary designs, and the worst lever arm.

    The boundary designs themselves are evaluated (worst head, worst impact point).

    Parameters
    ----------
    prob
        The problem.
    damping
        The lanes.
    kmax, kmin
        The upper and lower boundaries.

    Returns
    -------
    tuple
        The overdamped and delicate flags and the worst lever arm (NaN for a fixed robot).
    """
    overdamped = np.zeros(damping.size, dtype=bool)
    delicate = np.zeros(damping.size, dtype=bool)
    worst_l = np.full(damping.size, np.nan)
    first = prob.criteria[0] if prob.criteria else None
    if first is not None and np.any(np.isfinite(kmax)) and prob.robot.along_link:
        ok = np.isfinite(kmax)
        _, worst_l[ok] = prob.worst(first, kmax[ok], damping[ok])
    if prob.constrained:
        return overdamped, delicate, worst_l
    for key, kb in ((first, kmax), (prob.compression, kmin)):
        ok = np.isfinite(kb)
        if key is None or not np.any(ok):
            continue
        _, lev = prob.worst(key, kb[ok], damping[ok])
        params, v, nh = prob.designs(key, kb[ok], damping[ok], lev)
        m = prob.contact.metrics(params, v, with_force=False, lobe_diagnostics=True)
        pac = (m.design_status == ImpactStatus.PEAK_AT_CONTACT).reshape(-1, nh).any(axis=1)
        if key is first:
            overdamped[ok] |= pac
        delicate[ok] |= m.delicate_lobe.reshape(-1, nh).any(axis=1)
    return overdamped, delicate, worst_l


@dataclass(frozen=True)
class BoundarySolution:
    """Both boundaries of one problem over its damping values (see :class:`FoamEnvelope`).

    Attributes
    ----------
    problem
        The problem solved.
    damping
        The C_c values, N s/m.
    stiffness_min, stiffness_max
        The lower (thickness) and upper (safety) boundaries, N/m (NaN where unbounded).
    upper, upper_status
        Per criterion name: its bound and :class:`BoundaryStatus`.
    lower_status
        Status of the thickness boundary.
    multiple_roots, overdamped, delicate
        Flags per damping value (see :class:`~designlab.impact.envelope.FoamEnvelope`).
    worst_lever_arm
        The worst impact point on the upper boundary (NaN for a fixed robot).
    """

    problem: FoamProblem
    damping: NDArray[np.float64]
    stiffness_min: NDArray[np.float64]
    stiffness_max: NDArray[np.float64]
    upper: dict[str, NDArray[np.float64]]
    upper_status: dict[str, NDArray[np.str_]]
    lower_status: NDArray[np.str_]
    multiple_roots: NDArray[np.bool_]
    overdamped: NDArray[np.bool_]
    delicate: NDArray[np.bool_]
    worst_lever_arm: NDArray[np.float64]


def solve_boundaries(
    problems: Sequence[FoamProblem],
    dampings: Sequence[NDArray],
    bounds: tuple[float, float],
    rtol: float,
    n_scan: int = 48,
) -> list[BoundarySolution]:
    """Both boundaries of ``problems[i]`` over ``dampings[i]``, all lanes in one root-finding.

    A scan of ``n_scan`` log-spaced K_c over ``bounds``, then Illinois to ``rtol``.
    Several problems must differ only in a fixed robot, v_c and limits
    (:class:`~designlab.impact.problem.FoamLanes`).

    Parameters
    ----------
    problems
        The problems.
    dampings
        C_c values of each problem, N s/m.
    bounds
        ``(low, high)`` stiffness search range, N/m.
    rtol
        Relative accuracy of the boundaries in K_c.
    n_scan
        Points of the scan.

    Returns
    -------
    list of BoundarySolution
    """
    prob: FoamProblem = problems[0]
    lanes = dampings[0]
    if len(problems) > 1:
        prob = FoamLanes.of(problems, dampings)
        lanes = np.arange(prob.damping.size, dtype=float)
    u_grid = np.linspace(math.log(bounds[0]), math.log(bounds[1]), n_scan)
    tol = math.log1p(rtol)
    upper, upper_status, kmax, multiple, floor = upper_bounds(prob, lanes, u_grid, tol)
    kmin, lower_status, mult, _ = boundary(prob, prob.compression, lanes, u_grid, tol)
    multiple = multiple | mult
    kmin = np.where(lower_status == BoundaryStatus.BOUNDED, kmin, np.nan)
    # a criterion violated by too soft a foam (crushed) raises the lower boundary
    raised = np.isfinite(floor) & ~(kmin >= floor)
    kmin = np.where(raised, floor, kmin)
    lower_status = np.where(raised, BoundaryStatus.BOUNDED, lower_status).astype(str)
    overdamped, delicate, worst_l = flag_boundary_designs(prob, lanes, kmax, kmin)
    out = []
    stop = 0
    for p, damping in zip(problems, dampings, strict=True):
        sl = slice(stop, stop + damping.size)
        stop = sl.stop
        # the lanes evaluate the first problem's criteria: each problem names its own
        names = [(key.name, own.name) for key, own in zip(prob.criteria, p.criteria, strict=True)]
        out.append(
            BoundarySolution(
                problem=p,
                damping=damping,
                stiffness_min=kmin[sl],
                stiffness_max=kmax[sl],
                upper={own: upper[key][sl] for key, own in names},
                upper_status={own: upper_status[key][sl] for key, own in names},
                lower_status=lower_status[sl],
                multiple_roots=multiple[sl],
                overdamped=overdamped[sl],
                delicate=delicate[sl],
                worst_lever_arm=worst_l[sl],
            )
        )
    return out
