"""Feasible foam stiffness-damping region (Zeng 2011, Sec. 3.9, Figs. 3.18-3.20).

For each foam damping C_c the envelope solves two boundaries in the foam
stiffness K_c:

* the **upper** (safety) boundary: the largest K_c for which every criterion
  (head acceleration, force, HIC, ISO/TS 15066 force) holds, using the
  criterion's conservative head-neck set (Sec. 3.9.1), and
* the **lower** (thickness) boundary: the smallest K_c for which the foam is
  not compressed beyond its linear depth, eps_max < lambda (3.9.3), using the
  maximum head-neck set (Sec. 3.9.2).

Each boundary is a bracketed root in log K_c: a scan over the whole stiffness
range finds every sign change (so a root cannot be missed silently, and more
than one is reported), then vectorised Illinois iterations polish the brackets
to ``rtol``. Every point carries a status: ``bounded``, ``unbounded`` (the
constraint holds over the whole range) or ``no_solution`` (it holds nowhere).

The worst case is searched where it is, not assumed: the response is linear in
the impact velocity (so the largest velocity is the worst), the head-neck set
can be the thesis's conservative one or the worst corner of a range
(:class:`HeadRange`), and for a robot given at joint level
(:class:`~designlab.impact.parameters.LinkImpact`) the worst impact point along
the link is found by a grid and golden-section search at every evaluation
(Sec. 3.7.3). :func:`check_worst_case` samples the ranges to confirm it.

Examples
--------
>>> import numpy as np
>>> import designlab as dl
>>> env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, impact_velocity=1.25,
...                               damping=np.linspace(0, 200, 41),
...                               criteria=[dl.impact.HeadAcceleration(max_g=10)],
...                               max_compression=0.02)
>>> env.is_feasible(24.3e3, 71.9)
True
>>> foam2 = dl.impact.FOAM_2_MEASURED          # 13.48 kN/m: just below the thickness boundary
>>> bool(env.is_feasible(foam2.stiffness, foam2.damping))
False
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError, check_nonnegative, check_positive
from designlab.impact.criteria import CompressionLimit, Criterion, HeadAcceleration
from designlab.impact.full_joint import FullJointContact, FullJointLink, full_joint_params
from designlab.impact.metrics import metrics_of_matrix
from designlab.impact.parameters import (
    ContactDynamics,
    HeadNeck,
    LinkImpact,
)
from designlab.impact.parameters import Foam as Foam
from designlab.results import OK, Result

__all__ = [
    "THESIS_HEAD_RANGE",
    "FoamEnvelope",
    "HeadRange",
    "foam_envelope",
]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class HeadRange:
    """Ranges of the head-neck parameters (Sec. 3.5): ``(low, high)`` pairs, SI.

    Attributes
    ----------
    mass
        ``(low, high)`` head mass M_h in kg.
    stiffness
        ``(low, high)`` neck stiffness K_h in N/m.
    damping
        ``(low, high)`` neck damping C_h in N s/m.

    Examples
    --------
    >>> len(THESIS_HEAD_RANGE.corners())
    8
    """

    mass: tuple[float, float] = (4.4, 5.3)
    stiffness: tuple[float, float] = (3.0e3, 5.0e3)
    damping: tuple[float, float] = (46.0, 130.2)

    def __post_init__(self) -> None:
        for name, unit in (("mass", "kg"), ("stiffness", "N/m"), ("damping", "N s/m")):
            lo, hi = getattr(self, name)
            if not (np.isfinite(lo) and np.isfinite(hi) and 0 <= lo <= hi):
                raise InvalidParameterError(
                    f"HeadRange.{name}", (lo, hi), "must be (low, high) with 0 <= low <= high", unit
                )
        if self.mass[0] <= 0:
            raise InvalidParameterError("HeadRange.mass", self.mass, "low must be > 0", "kg")

    def corners(self) -> list[HeadNeck]:
        """The 8 corner sets (duplicates removed)."""
        out: list[HeadNeck] = []
        for m in self.mass:
            for k in self.stiffness:
                for c in self.damping:
                    h = HeadNeck(m, k, c)
                    if h not in out:
                        out.append(h)
        return out

    def grid(self, levels: int = 3) -> list[HeadNeck]:
        """Full factorial of ``levels`` values per parameter (corners included)."""
        out: list[HeadNeck] = []
        for m in np.linspace(*self.mass, levels):
            for k in np.linspace(*self.stiffness, levels):
                for c in np.linspace(*self.damping, levels):
                    h = HeadNeck(float(m), float(k), float(c))
                    if h not in out:
                        out.append(h)
        return out

    def sample(self, n: int, rng: np.random.Generator) -> NDArray[np.float64]:
        """``(n, 3)`` uniform samples ``[M_h, C_h, K_h]``."""
        lo = np.array([self.mass[0], self.damping[0], self.stiffness[0]])
        hi = np.array([self.mass[1], self.damping[1], self.stiffness[1]])
        return lo + (hi - lo) * rng.random((n, 3))


#: The thesis's head-neck ranges: 4.4-5.3 kg, 3-5 kN/m, 46-130.2 N s/m.
THESIS_HEAD_RANGE = HeadRange()


def _head_rows(heads: Sequence[HeadNeck]) -> NDArray[np.float64]:
    return np.array([[h.mass, h.damping, h.stiffness] for h in heads], dtype=float)


@dataclass
class _Problem:
    """Worst-case evaluation of the criteria and the compression for foams (K_c, C_c)."""

    robot: ContactDynamics | LinkImpact
    impact_velocity: float
    human_speed: float
    criteria: tuple[Criterion, ...]
    max_compression: float
    head_range: HeadRange | None
    constrained: bool
    stop_time: float
    head_levels: int = 3
    lever_grid: int = 17
    golden_iterations: int = 24

    @property
    def compression(self) -> CompressionLimit:
        """The thickness constraint eps_max <= lambda (3.9.3) as a criterion."""
        return CompressionLimit(self.max_compression)

    def heads_for(self, key: Criterion) -> NDArray[np.float64]:
        if self.constrained:
            return np.array([[1.0, 0.0, 0.0]])
        if self.head_range is not None:
            return _head_rows(self.head_range.grid(self.head_levels))
        return _head_rows([key.conservative_head])

    def _robot_rows(self, levers: NDArray | None) -> tuple[NDArray, NDArray]:
        """``(n_l, 3)`` [M_r, C_r, K_r] and ``(n_l,)`` v_c for lever arms (or the one robot)."""
        if isinstance(self.robot, LinkImpact):
            lr = self.robot
            l2 = np.asarray(levers, dtype=float) ** 2
            rows = np.column_stack(
                [lr.inertia / l2, lr.joint_damping / l2, lr.joint_stiffness / l2]
            )
            if isinstance(lr, FullJointLink):  # the full series joint: 5 robot columns
                rows = lr.effective_rows(np.sqrt(l2))
            return rows, lr.joint_speed * np.sqrt(l2) + self.human_speed
        r = self.robot
        if isinstance(r, FullJointContact):  # full series joint: 5 robot columns
            p = full_joint_params(r, Foam(1.0, 0.0), None)
            return p[None, [0, 1, 2, 8, 9]], np.array([self.impact_velocity])
        return np.array([[r.mass, r.damping, r.stiffness]]), np.array([self.impact_velocity])

    def designs(
        self, key: Criterion, k: NDArray, c: NDArray, levers: NDArray | None = None
    ) -> tuple[NDArray, NDArray, int]:
        """Every head (and the robot at ``levers``) for foams ``(k, c)``.

        Returns ``(N * n_heads, 8)`` parameters, their velocities and ``n_heads``;
        rows ``i * n_heads ... (i + 1) * n_heads - 1`` belong to foam ``i``.
        """
        if isinstance(self.robot, LinkImpact):
            rows, v = self._robot_rows(levers)
        else:
            c, rows, v = self._lane_inputs(c)
        return self._expand(key, k, c, rows, v)

    def _lane_inputs(self, c: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """Damping, robot rows and v_c of the lanes ``c`` (a fixed robot).

        The lane context that :func:`_boundary` and :func:`_illinois` carry is the
        damping itself here; :class:`_Lanes` carries lane indices instead.
        """
        rows, v = self._robot_rows(None)
        return c, np.repeat(rows, c.size, axis=0), np.repeat(v, c.size)

    def log_limit(self, key: Criterion, c: NDArray) -> float | NDArray:
        """``log`` of the limit of ``key`` for the lanes ``c`` (one limit here)."""
        return math.log(self.limit(key))

    def _expand(
        self, key: Criterion, k: NDArray, c: NDArray, rows: NDArray, v: NDArray
    ) -> tuple[NDArray, NDArray, int]:
        heads = self.heads_for(key)
        n, nh = k.size, heads.shape[0]
        params = np.column_stack([rows[:, :3], k, c])
        extra = np.repeat(rows[:, 3:], nh, axis=0)  # full-joint controller columns, if any
        full = np.column_stack([np.repeat(params, nh, axis=0), np.tile(heads, (n, 1)), extra])
        return full, np.repeat(v, nh), nh

    def _values(self, key: Criterion, k: NDArray, c: NDArray, rows: NDArray, v: NDArray) -> NDArray:
        """Metric for designs ``i`` x robot rows ``j`` (paired arrays, all length n)."""
        full, vv, nh = self._expand(key, k, c, rows, v)
        vals = key.values(full, vv, constrained=self.constrained, stop_time=self.stop_time)
        return vals.reshape(k.size, nh).max(axis=1)

    def worst(self, key: Criterion, k: NDArray, c: NDArray) -> tuple[NDArray, NDArray]:
        """Worst-case metric over heads (and impact points) for foams ``(k, c)``.

        Returns the values and the worst lever arm (NaN for a fixed robot).
        """
        k = np.asarray(k, dtype=float).ravel()
        c = np.asarray(c, dtype=float).ravel()
        if not isinstance(self.robot, LinkImpact):
            return self._values(key, k, *self._lane_inputs(c)), np.full(k.size, np.nan)
        lr = self.robot
        grid = np.geomspace(lr.lever_arm_min, lr.lever_arm_max, self.lever_grid)
        if lr.lever_arm_max == lr.lever_arm_min:
            grid = np.array([lr.lever_arm_min])
        n, ng = k.size, grid.size
        rows, v = self._robot_rows(grid)
        vals = self._values(
            key, np.repeat(k, ng), np.repeat(c, ng), np.tile(rows, (n, 1)), np.tile(v, n)
        ).reshape(n, ng)
        j = vals.argmax(axis=1)
        best = vals[np.arange(n), j]
        best_l = grid[j]
        if ng < 3:
            return best, best_l
        lo = grid[np.maximum(j - 1, 0)]
        hi = grid[np.minimum(j + 1, ng - 1)]

        def f(levers: NDArray) -> NDArray:
            r, vv = self._robot_rows(levers)
            return self._values(key, k, c, r, vv)

        inv = (math.sqrt(5) - 1) / 2
        x1 = hi - inv * (hi - lo)
        x2 = lo + inv * (hi - lo)
        f1, f2 = f(x1), f(x2)
        for _ in range(self.golden_iterations):
            left = f1 >= f2
            hi = np.where(left, x2, hi)
            lo = np.where(left, lo, x1)
            nx1 = np.where(left, hi - inv * (hi - lo), x2)
            nx2 = np.where(left, x1, lo + inv * (hi - lo))
            fnew = f(np.where(left, nx1, nx2))
            f1, f2 = np.where(left, fnew, f2), np.where(left, f1, fnew)
            x1, x2 = nx1, nx2
        cand = np.where(f1 >= f2, f1, f2)
        cand_l = np.where(f1 >= f2, x1, x2)
        better = cand > best
        return np.where(better, cand, best), np.where(better, cand_l, best_l)

    def limit(self, key: Criterion) -> float:
        return key.limit

    def log_excess(self, key: Criterion, u: NDArray, c: NDArray) -> NDArray:
        """``log(metric / limit)`` at ``K_c = exp(u)``: > 0 means violated."""
        vals, _ = self.worst(key, np.exp(u), c)
        with np.errstate(divide="ignore"):
            return np.log(np.maximum(vals, 1e-300)) - self.log_limit(key, c)

    def keys(self) -> list[Criterion]:
        """Every constraint: the criteria (upper boundary) and the thickness limit (lower)."""
        return [*self.criteria, self.compression]


def _metric_only(key: Criterion) -> bool:
    """Whether ``key``'s values depend on its metric alone (not on its fields)."""
    t = type(key)
    return t.values is Criterion.values and t.from_metrics is Criterion.from_metrics


def _same_but_limits(a: _Problem, b: _Problem) -> bool:
    """Whether ``b`` differs from ``a`` only in its fixed robot, v_c and limits."""
    if isinstance(b.robot, LinkImpact) or len(a.criteria) != len(b.criteria):
        return False
    setting = ("head_range", "constrained", "stop_time", "head_levels")
    if any(getattr(a, s) != getattr(b, s) for s in setting):
        return False
    return all(
        ka == kb
        or (
            _metric_only(ka)
            and _metric_only(kb)
            and ka.metric == kb.metric
            and ka.conservative_head == kb.conservative_head
        )
        for ka, kb in zip(a.keys(), b.keys(), strict=True)
    )


@dataclass(kw_only=True)
class _Lanes(_Problem):
    """Several fixed-robot problems solved together: one lane per (problem, damping value).

    The lane context carried by :func:`_boundary` and :func:`_illinois` is a lane
    index (a float, exact): lane ``i`` is the robot row ``rows[i]`` at v_c
    ``velocity[i]`` and C_c ``damping[i]``, with ``log_limits[i]`` (one column per
    :meth:`keys`). The criteria evaluated are the first problem's; the others
    differ from them in their limits only (:func:`_same_but_limits`).
    """

    rows: NDArray[np.float64]
    velocity: NDArray[np.float64]
    damping: NDArray[np.float64]
    log_limits: NDArray[np.float64]

    @classmethod
    def of(cls, problems: Sequence[_Problem], dampings: Sequence[NDArray]) -> _Lanes:
        """The lanes of ``problems[i]`` at the damping values ``dampings[i]``, in order."""
        first = problems[0]
        if not all(_same_but_limits(first, p) for p in problems):
            raise InvalidParameterError(
                "problems", len(problems), "must differ only in a fixed robot, v_c and limits"
            )
        sizes = [d.size for d in dampings]
        robots = [p._robot_rows(None) for p in problems]
        limits = [[math.log(p.limit(key)) for key in p.keys()] for p in problems]
        return cls(
            **{f.name: getattr(first, f.name) for f in fields(_Problem)},
            rows=np.repeat(np.concatenate([r for r, _ in robots]), sizes, axis=0),
            velocity=np.repeat(np.concatenate([v for _, v in robots]), sizes),
            damping=np.concatenate(dampings),
            log_limits=np.repeat(np.array(limits, dtype=float), sizes, axis=0),
        )

    def _lane_inputs(self, c: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        i = np.asarray(c).astype(np.intp)
        return self.damping[i], self.rows[i], self.velocity[i]

    def log_limit(self, key: Criterion, c: NDArray) -> float | NDArray:
        if key.boundary == "lower":
            j = len(self.criteria)
        else:
            j = next(j for j, crit in enumerate(self.criteria) if crit is key)
        return self.log_limits[np.asarray(c).astype(np.intp), j]


def _illinois(
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

    Returns the end of the final bracket where ``f <= 0`` (the feasible side).
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


def _boundary(
    prob: _Problem, key: Criterion, c: NDArray, u_grid: NDArray, tol: float
) -> tuple[NDArray, NDArray, NDArray]:
    """One boundary for every damping value: (K, status, multiple-root flag).

    For a criterion (upper boundary) the feasible side is ``excess < 0`` at small
    K; for the compression (lower boundary) the feasible side is at large K.
    """
    n, ns = c.size, u_grid.size
    ex = prob.log_excess(key, np.tile(u_grid, n), np.repeat(c, ns)).reshape(n, ns)
    viol = ex > 0
    changes = np.diff(viol.astype(int), axis=1) != 0
    n_changes = changes.sum(axis=1)
    upper = key.boundary == "upper"
    status = np.full(n, "bounded", dtype=object)
    k_out = np.full(n, np.nan)
    if upper:
        status[~viol.any(axis=1)] = "unbounded"
        status[viol[:, 0]] = "no_solution"
        # first feasible -> violated transition
        trans = (~viol[:, :-1]) & viol[:, 1:]
    else:
        status[~viol.any(axis=1)] = "unbounded"
        status[viol.all(axis=1)] = "no_solution"
        # last violated -> feasible transition
        trans = viol[:, :-1] & (~viol[:, 1:])
        trans = trans & (np.cumsum(trans[:, ::-1], axis=1)[:, ::-1] == 1)
    has = trans.any(axis=1) & (status == "bounded")
    status[(status == "bounded") & ~has] = "no_solution"
    idx = np.flatnonzero(has)
    if idx.size:
        j = trans[idx].argmax(axis=1)
        a, b = u_grid[j], u_grid[j + 1]
        fa, fb = ex[idx, j], ex[idx, j + 1]
        u = _illinois(lambda x, cc: prob.log_excess(key, x, cc), a, b, fa, fb, c[idx], tol)
        k_out[idx] = np.exp(u)
    return k_out, status.astype(str), n_changes > 1


@dataclass(frozen=True)
class FoamEnvelope(Result):
    """Feasible foam region: boundaries in K_c over a damping grid (SI units).

    Attributes
    ----------
    damping
        C_c grid, N s/m.
    stiffness_max
        Upper (safety) boundary, N/m: the smallest of the criteria's bounds.
        NaN where no bound exists (see ``upper_status``).
    stiffness_min
        Lower (thickness) boundary, N/m; NaN where no bound exists.
    upper, upper_status
        Per criterion name: its bound and status (``bounded``, ``unbounded``,
        ``no_solution``).
    lower_status
        Status of the thickness boundary.
    multiple_roots
        Points where a constraint changes sign more than once over the
        stiffness range (the feasible K_c set is not an interval there).
    overdamped
        Points where the head acceleration peaks at contact on the upper
        boundary (an overdamped pulse; the impact period is delicate).
    delicate
        Points where a boundary design's first lobe is delicate (a_h lingers
        near zero before the lobe ends, or peaks at contact): the thesis's
        first-lobe metrics can jump there (docs/impact.md, "Metrics").
    worst_lever_arm
        For a robot at joint level, the worst impact point on the upper
        boundary of the first criterion (NaN otherwise).
    robot
        The manipulator (effective contact dynamics or a link struck anywhere).
    impact_velocity
        Closing speed v_c in m/s.
    criteria
        The safety criteria of the upper boundary.
    max_compression
        Usable foam depth lambda in m (the lower boundary).
    stiffness_bounds
        ``(low, high)`` K_c search range in N/m.
    constrained
        Whether the head is constrained (no neck; Sec. 3.4).
    head_range
        The head-neck ranges the boundaries hold for (``None``: one head).
    warnings
        What a user should know (several roots, delicate lobes, ...).
    status
        ``"ok"``, or ``"empty"`` when no foam is feasible.
    """

    robot: ContactDynamics | LinkImpact
    impact_velocity: float
    criteria: tuple[Criterion, ...]
    max_compression: float
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
    stiffness_bounds: tuple[float, float]
    constrained: bool
    head_range: HeadRange | None
    warnings: tuple[str, ...] = ()
    status: str = OK
    _problem: _Problem | None = field(default=None, repr=False, compare=False)

    # -- effective bounds (unbounded sides clipped to the search range) ----------
    def _effective(self) -> tuple[NDArray, NDArray]:
        lo, hi = self.stiffness_bounds
        kmax = np.full(self.damping.size, hi)
        for name, k in self.upper.items():
            st = self.upper_status[name]
            kk = np.where(st == "bounded", k, np.where(st == "unbounded", hi, -np.inf))
            kmax = np.minimum(kmax, kk)
        kmin = np.where(
            self.lower_status == "bounded",
            self.stiffness_min,
            np.where(self.lower_status == "unbounded", lo, np.inf),
        )
        return kmin, kmax

    @property
    def region_status(self) -> NDArray[np.str_]:
        """Per damping value: ``feasible`` or ``empty``."""
        kmin, kmax = self._effective()
        return np.where(kmin <= kmax, "feasible", "empty").astype(str)

    @property
    def is_empty(self) -> bool:
        """True if no damping value of the grid has a feasible stiffness."""
        return bool(np.all(self.region_status == "empty"))

    def is_feasible(self, stiffness: ArrayLike, damping: ArrayLike) -> bool | NDArray[np.bool_]:
        """Whether foams ``(K_c, C_c)`` satisfy every criterion and the thickness limit.

        Evaluated exactly with the model and the envelope's worst case, at any
        damping (not interpolated from the grid).
        """
        prob = self._require_problem()
        k, c = np.broadcast_arrays(np.asarray(stiffness, float), np.asarray(damping, float))
        ok = np.ones(k.shape, dtype=bool)
        for key in prob.keys():
            vals, _ = prob.worst(key, k.ravel(), c.ravel())
            ok &= (vals <= prob.limit(key)).reshape(k.shape)
        return bool(ok) if ok.ndim == 0 else ok

    def margin(self, stiffness: ArrayLike, damping: ArrayLike) -> float | NDArray[np.float64]:
        """Signed distance to the nearest boundary in log10(K_c), decades.

        Positive inside the region, negative outside; ``-inf`` where no
        stiffness is feasible at that damping.
        """
        prob = self._require_problem()
        k, c = np.broadcast_arrays(np.asarray(stiffness, float), np.asarray(damping, float))
        cu, inv = np.unique(c.ravel(), return_inverse=True)
        env = _solve(prob, cu, self.stiffness_bounds, 1e-9)
        kmin, kmax = env._effective()
        kk = k.ravel()
        kx, kn = kmax[inv], kmin[inv]
        with np.errstate(divide="ignore", invalid="ignore"):
            up = np.where(kx > 0, np.log10(np.where(kx > 0, kx, 1.0) / kk), -np.inf)
            dn = np.where(
                np.isfinite(kn), np.log10(kk / np.where(np.isfinite(kn), kn, 1.0)), -np.inf
            )
        m = np.minimum(up, dn)
        m = np.where(kmin[inv] > kmax[inv], np.minimum(m, -np.inf), m)
        m = m.reshape(k.shape)
        return float(m) if m.ndim == 0 else m

    def area(self, log: bool = False) -> float:
        """Area of the feasible region over the damping grid.

        ``log=False``: in (N/m)(N s/m), the integral of ``K_max - K_min``;
        ``log=True``: in decades x N s/m, the integral of ``log10(K_max/K_min)``.
        Unbounded sides are clipped to the stiffness search range.
        """
        kmin, kmax = self._effective()
        if log:
            with np.errstate(divide="ignore", invalid="ignore"):
                w = np.log10(kmax) - np.log10(kmin)
        else:
            w = kmax - kmin
        w = np.where(np.isfinite(w) & (w > 0), w, 0.0)
        if self.damping.size < 2:
            return 0.0
        return float(np.sum(0.5 * (w[1:] + w[:-1]) * np.diff(self.damping)))

    def to_frame(self) -> pd.DataFrame:
        """One row per damping value, columns with units."""
        df = pd.DataFrame(
            {
                "C_c_N_s_per_m": self.damping,
                "K_c_min_N_per_m": self.stiffness_min,
                "K_c_max_N_per_m": self.stiffness_max,
                "lower_status": self.lower_status,
                "region": self.region_status,
            }
        )
        for name in self.upper:
            df[f"K_c_max[{name}]_N_per_m"] = self.upper[name]
            df[f"status[{name}]"] = self.upper_status[name]
        df["multiple_roots"] = self.multiple_roots
        df["overdamped_pulse"] = self.overdamped
        df["delicate_lobe"] = self.delicate
        if np.any(np.isfinite(self.worst_lever_arm)):
            df["worst_lever_arm_m"] = self.worst_lever_arm
        return df

    def _require_problem(self) -> _Problem:
        if self._problem is None:  # pragma: no cover - only for hand-built objects
            raise InvalidParameterError("FoamEnvelope", None, "was not built by foam_envelope")
        return self._problem


def _upper_bounds(
    prob: _Problem, damping: NDArray, u_grid: NDArray, tol: float
) -> tuple[dict[str, NDArray], dict[str, NDArray], NDArray, NDArray]:
    """Every criterion's upper boundary and status, and their minimum (NaN if none bounded)."""
    upper: dict[str, NDArray] = {}
    upper_status: dict[str, NDArray] = {}
    multiple = np.zeros(damping.size, dtype=bool)
    for crit in prob.criteria:
        k, st, mult = _boundary(prob, crit, damping, u_grid, tol)
        upper[crit.name] = k
        upper_status[crit.name] = st
        multiple |= mult
    kmax = np.full(damping.size, np.inf)
    any_bounded = np.zeros(damping.size, dtype=bool)
    for name in upper:
        bounded = upper_status[name] == "bounded"
        kmax = np.where(bounded, np.minimum(kmax, upper[name]), kmax)
        any_bounded |= bounded
    return upper, upper_status, np.where(any_bounded, kmax, np.nan), multiple


def _flag_boundary_designs(
    prob: _Problem, damping: NDArray, kmax: NDArray, kmin: NDArray
) -> tuple[NDArray, NDArray, NDArray]:
    """Overdamped and delicate flags of the boundary designs, and the worst lever arm.

    The boundary designs themselves are evaluated (worst head, worst impact point).
    """
    overdamped = np.zeros(damping.size, dtype=bool)
    delicate = np.zeros(damping.size, dtype=bool)
    worst_l = np.full(damping.size, np.nan)
    first = prob.criteria[0] if prob.criteria else None
    if first is not None and np.any(np.isfinite(kmax)) and isinstance(prob.robot, LinkImpact):
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
        m = metrics_of_matrix(params, v, with_force=False, lobe_diagnostics=True)
        pac = (m.design_status == "peak_at_contact").reshape(-1, nh).any(axis=1)
        if key is first:
            overdamped[ok] |= pac
        delicate[ok] |= m.delicate_lobe.reshape(-1, nh).any(axis=1)
    return overdamped, delicate, worst_l


def _envelope_warnings(
    empty: bool, multiple: NDArray, overdamped: NDArray, delicate: NDArray
) -> list[str]:
    warnings = []
    if empty:
        warnings.append(
            "the feasible region is empty at every damping value of the grid: reduce the "
            'impact velocity (docs/impact.md, "Foam design")'
        )
    if np.any(multiple):
        warnings.append(
            f"{int(multiple.sum())} damping value(s) have a constraint that changes sign more "
            "than once over the stiffness range; the boundary reported is the one nearest the "
            "feasible side"
        )
    if np.any(delicate & ~overdamped):
        warnings.append(
            f"{int((delicate & ~overdamped).sum())} boundary point(s) have a delicate first lobe "
            "(a_h lingers near zero before the lobe ends), so eps_max and the impact period "
            'can jump with small parameter changes (docs/impact.md, "Metrics")'
        )
    if np.any(overdamped):
        warnings.append(
            f"{int(overdamped.sum())} upper-boundary point(s) are overdamped pulses (a_h peaks "
            "at contact, a_h,max = C_c v_c / M_h): outside the thesis's foam range xi_c 0.05-0.2"
        )
    return warnings


def _solve(
    prob: _Problem, damping: NDArray, bounds: tuple[float, float], rtol: float, n_scan: int = 48
) -> FoamEnvelope:
    """Both boundaries over ``damping`` (scan of ``n_scan`` log-spaced K_c, then Illinois)."""
    return _solve_many([prob], [damping], bounds, rtol, n_scan)[0]


def _solve_many(
    problems: Sequence[_Problem],
    dampings: Sequence[NDArray],
    bounds: tuple[float, float],
    rtol: float,
    n_scan: int = 48,
) -> list[FoamEnvelope]:
    """:func:`_solve` of ``problems[i]`` over ``dampings[i]``, all lanes in one root-finding.

    Several problems must differ only in a fixed robot, v_c and limits (:class:`_Lanes`).
    """
    prob: _Problem = problems[0]
    lanes = dampings[0]
    if len(problems) > 1:
        prob = _Lanes.of(problems, dampings)
        lanes = np.arange(prob.damping.size, dtype=float)
    u_grid = np.linspace(math.log(bounds[0]), math.log(bounds[1]), n_scan)
    tol = math.log1p(rtol)
    upper, upper_status, kmax, multiple = _upper_bounds(prob, lanes, u_grid, tol)
    kmin, lower_status, mult = _boundary(prob, prob.compression, lanes, u_grid, tol)
    multiple = multiple | mult
    kmin = np.where(lower_status == "bounded", kmin, np.nan)
    overdamped, delicate, worst_l = _flag_boundary_designs(prob, lanes, kmax, kmin)
    out = []
    stop = 0
    for p, damping in zip(problems, dampings, strict=True):
        sl = slice(stop, stop + damping.size)
        stop = sl.stop
        # the lanes evaluate the first problem's criteria: each problem names its own
        names = [(key.name, own.name) for key, own in zip(prob.criteria, p.criteria, strict=True)]
        env = FoamEnvelope(
            robot=p.robot,
            impact_velocity=p.impact_velocity,
            criteria=p.criteria,
            max_compression=p.max_compression,
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
            stiffness_bounds=bounds,
            constrained=p.constrained,
            head_range=p.head_range,
            _problem=p,
        )
        empty = env.is_empty
        warnings = _envelope_warnings(empty, multiple[sl], overdamped[sl], delicate[sl])
        # one-point solves (verdicts, margins, the worst-case onset) are debug detail
        log.log(
            logging.INFO if damping.size > 1 else logging.DEBUG,
            "foam_envelope: %d damping values, %d-point scan in K_c: upper bounded at %d, "
            "lower bounded at %d, %d delicate, %d with several roots",
            damping.size, n_scan, int(np.isfinite(kmax[sl]).sum()),
            int(np.isfinite(kmin[sl]).sum()), int(delicate[sl].sum()), int(multiple[sl].sum()),
        )  # fmt: skip
        out.append(replace(env, warnings=tuple(warnings), status="empty" if empty else OK))
    return out


def _make_problem(
    robot: ContactDynamics | LinkImpact,
    impact_velocity: float | None,
    criteria: Sequence[Criterion] | None,
    max_compression: float,
    head_range: HeadRange | None,
    constrained: bool,
    human_speed: float,
    stop_time: float,
) -> _Problem:
    if isinstance(robot, LinkImpact):
        if impact_velocity is not None:
            raise InvalidParameterError(
                "impact_velocity",
                impact_velocity,
                "must be None for a LinkImpact robot (v_c = joint_speed * l + human_speed)",
                "m/s",
            )
        v = float("nan")
    elif isinstance(robot, (ContactDynamics, FullJointContact)):
        v = check_positive(
            "impact_velocity", 1.25 if impact_velocity is None else impact_velocity, "m/s"
        )
    else:
        raise InvalidParameterError(
            "robot", robot, "must be a ContactDynamics, a FullJointContact or a LinkImpact"
        )
    human_speed = check_nonnegative("human_speed", human_speed, "m/s")
    stop_time = check_positive("stop_time", stop_time, "s")
    if not isinstance(constrained, (bool, np.bool_)):
        raise InvalidParameterError("constrained", constrained, "must be True or False")
    if head_range is not None and not isinstance(head_range, HeadRange):
        raise InvalidParameterError("head_range", head_range, "must be a HeadRange or None")
    if criteria is not None and (
        isinstance(criteria, (str, Criterion)) or not hasattr(criteria, "__iter__")
    ):
        raise InvalidParameterError("criteria", criteria, "must be a sequence of Criterion objects")
    crit = tuple(criteria) if criteria is not None else (HeadAcceleration(10.0),)
    for c in crit:
        if not isinstance(c, Criterion):
            raise InvalidParameterError("criteria", c, "must contain Criterion objects")
        if c.boundary != "upper":
            raise InvalidParameterError(
                "criteria",
                c.name,
                "holds safety criteria (upper boundary); the thickness limit is max_compression",
            )
        if constrained and c.metric != "force":
            raise InvalidParameterError(
                "criteria",
                c.name,
                "the constrained impact (head against a wall) has a_h = 0: use force criteria",
            )
    lam = check_positive("max_compression", max_compression, "m")
    return _Problem(robot, v, human_speed, crit, lam, head_range, constrained, float(stop_time))


def foam_envelope(
    robot: ContactDynamics | LinkImpact,
    impact_velocity: float | None = 1.25,
    damping: ArrayLike | None = None,
    criteria: Sequence[Criterion] | None = None,
    max_compression: float = 0.02,
    *,
    head_range: HeadRange | None = None,
    constrained: bool = False,
    stiffness_bounds: tuple[float, float] = (1e2, 1e7),
    rtol: float = 1e-6,
    human_speed: float = 1.0,
    stop_time: float = 0.05,
) -> FoamEnvelope:
    """Feasible region of foam stiffness and damping (Zeng 2011, Sec. 3.9).

    Parameters
    ----------
    robot
        Effective manipulator at the worst impact point, or a
        :class:`~designlab.impact.parameters.LinkImpact` to search the impact
        point along the link.
    impact_velocity
        Maximum v_c, m/s (the response is linear in v_c, so the maximum is the
        worst case). ``None`` for a ``LinkImpact`` (its speed comes from the joint).
    damping
        C_c grid, N s/m (default: 41 points over 0-200 N s/m).
    criteria
        Safety criteria for the upper boundary (default: a_h,max <= 10 g).
    max_compression
        lambda, the linear depth of the foam, m (lower boundary, (3.9.3)).
    head_range
        ``None`` (default) uses each criterion's conservative head-neck set as
        the thesis does; a :class:`HeadRange` takes the worst of its corners.
    constrained
        Constrained impact (head against a wall; (3.6.1) and (3.9.4)); force
        criteria only.
    stiffness_bounds
        Search range of K_c, N/m.
    rtol
        Relative accuracy of the boundaries in K_c.
    human_speed
        Head speed toward the robot for a ``LinkImpact``, m/s.
    stop_time
        Window of the constrained impact's metrics, s.

    Returns
    -------
    FoamEnvelope

    Examples
    --------
    >>> import designlab as dl
    >>> env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, 1.25, [0.0, 100.0])
    >>> (env.stiffness_max / 1e3).round(2).tolist(), (env.stiffness_min / 1e3).round(2).tolist()
    ([46.04, 58.77], [16.67, 11.92])
    """
    design = (robot, impact_velocity, criteria, max_compression)
    return _foam_envelopes(
        [design],
        damping,
        head_range=head_range,
        constrained=constrained,
        stiffness_bounds=stiffness_bounds,
        rtol=rtol,
        human_speed=human_speed,
        stop_time=stop_time,
    )[0]


#: One design of :func:`_foam_envelopes`: robot, impact velocity, criteria, max_compression.
_Design = tuple[ContactDynamics | LinkImpact, float | None, Sequence[Criterion] | None, float]


def _foam_envelopes(
    designs: Sequence[_Design], damping: ArrayLike | None, **settings: Any
) -> list[FoamEnvelope]:
    """:func:`foam_envelope` of several designs over one damping grid, solved together.

    ``settings`` are keyword arguments of :func:`foam_envelope` (its defaults
    where not given). Several designs must have fixed robots and criteria
    differing in their limits only.
    """
    s = {**(foam_envelope.__kwdefaults__ or {}), **settings}
    c = (
        np.linspace(0.0, 200.0, 41)
        if damping is None
        else np.atleast_1d(np.asarray(damping, float))
    )
    if c.ndim != 1 or c.size == 0 or np.any(~np.isfinite(c)) or np.any(c < 0):
        raise InvalidParameterError(
            "damping", damping, "must be a 1-D array of values >= 0", "N s/m"
        )
    lo, hi = s["stiffness_bounds"]
    if not (0 < lo < hi and np.isfinite(hi)):
        raise InvalidParameterError(
            "stiffness_bounds",
            s["stiffness_bounds"],
            "must be (low, high) with 0 < low < high",
            "N/m",
        )
    if not 0 < s["rtol"] < 1e-2:
        raise InvalidParameterError("rtol", s["rtol"], "must be in (0, 0.01)")
    setting = (s["head_range"], s["constrained"], s["human_speed"], s["stop_time"])
    problems = [_make_problem(r, v, crit, lam, *setting) for r, v, crit, lam in designs]
    return _solve_many(problems, [c] * len(problems), (float(lo), float(hi)), s["rtol"])
