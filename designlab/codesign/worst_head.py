"""The worst head of a range, polished off the grid: a bounded local search.

The impact package's worst case (:mod:`designlab.impact.problem`) takes the worst
head of a grid over the range (the corners and, with 3 levels, the mid-points). The
worst head need not be on that grid: with a strongly damped foam the largest
compression can lie inside the range (a fraction of a percent above the grid's).
:func:`refine_worst_head` starts from the grid's worst head and maximises the
metric at v_c = 1 m/s over the box with a derivative-free bounded search
(``scipy.optimize.minimize``, Powell), keeping the better of the two.

Examples
--------
>>> import designlab as dl
>>> from designlab.codesign.speed import problem_for
>>> prob = problem_for(dl.impact.MANIPULATOR_1, None, 0.02, None, 0.0, 3)
>>> key = prob.keys()[0]
>>> m, head = refine_worst_head(prob, key, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 48.0)
>>> head.mass, bool(m >= 48.0)
(4.4, True)
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import minimize

from designlab.impact import Criterion, Foam, HeadNeck
from designlab.impact.problem import FoamProblem

__all__ = ["MAX_EVALUATIONS", "refine_worst_head"]

#: Metric evaluations of the local search per criterion.
MAX_EVALUATIONS = 150


def _box(prob: FoamProblem) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lower and upper ends ``[M_h, C_h, K_h]`` of the head range."""
    hr = prob.head_range
    lo = np.array([hr.mass[0], hr.damping[0], hr.stiffness[0]], dtype=float)
    hi = np.array([hr.mass[1], hr.damping[1], hr.stiffness[1]], dtype=float)
    return lo, hi


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
    lo, hi = _box(prob)
    span = hi - lo
    rows, _ = prob.robot_rows(None)
    fixed = np.concatenate([rows[0, :3], [foam.stiffness, foam.damping]])
    extra = rows[0, 3:]

    def value(x: NDArray[np.float64]) -> float:
        h = lo + np.clip(x, 0.0, 1.0) * span
        p = np.concatenate([fixed, h, extra])[None, :]
        out = float(key.values(p, np.ones(1))[0])
        return out if np.isfinite(out) else 0.0

    start = np.array([head.mass, head.damping, head.stiffness])
    x0 = np.where(span > 0, (start - lo) / np.where(span > 0, span, 1.0), 0.0)
    scale = max(metric, 1e-300)
    res = minimize(lambda x: -value(x) / scale, x0, method="Powell", bounds=[(0.0, 1.0)] * 3,
                   options={"maxfev": MAX_EVALUATIONS, "xtol": 1e-6, "ftol": 1e-10})  # fmt: skip
    best = -float(res.fun) * scale
    if not best > metric:
        return metric, head
    h = lo + np.clip(res.x, 0.0, 1.0) * span
    return best, HeadNeck(mass=float(h[0]), stiffness=float(h[2]), damping=float(h[1]))
