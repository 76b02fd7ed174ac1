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
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError, check_positive
from designlab.impact.criteria import Criterion, HeadAcceleration
from designlab.impact.full_joint import FullJointContact, FullJointLink, full_joint_params
from designlab.impact.metrics import impact_metrics
from designlab.impact.parameters import (
    HEAD_MAX,
    ContactDynamics,
    Foam,
    HeadNeck,
    LinkImpact,
)

__all__ = [
    "THESIS_HEAD_RANGE",
    "FoamEnvelope",
    "FoamThickness",
    "HeadRange",
    "SafeVelocity",
    "WorstCaseCheck",
    "check_worst_case",
    "foam_envelope",
    "max_safe_velocity",
    "min_foam_thickness",
]

log = logging.getLogger(__name__)

COMPRESSION = "eps_max"


@dataclass(frozen=True)
class HeadRange:
    """Ranges of the head-neck parameters (Sec. 3.5): ``(low, high)`` pairs, SI.

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

    def heads_for(self, key: str | Criterion) -> NDArray[np.float64]:
        if self.constrained:
            return np.array([[1.0, 0.0, 0.0]])
        if self.head_range is not None:
            return _head_rows(self.head_range.grid(self.head_levels))
        if key == COMPRESSION:
            return _head_rows([HEAD_MAX])
        return _head_rows([key.conservative_head])  # type: ignore[union-attr]

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
        self, key: str | Criterion, k: NDArray, c: NDArray, levers: NDArray | None = None
    ) -> tuple[NDArray, NDArray, int]:
        """Every head (and the robot at ``levers``) for foams ``(k, c)``.

        Returns ``(N * n_heads, 8)`` parameters, their velocities and ``n_heads``;
        rows ``i * n_heads ... (i + 1) * n_heads - 1`` belong to foam ``i``.
        """
        n = k.size
        if isinstance(self.robot, LinkImpact):
            rows, v = self._robot_rows(levers)
        else:
            rows, v = self._robot_rows(None)
            rows, v = np.repeat(rows, n, axis=0), np.repeat(v, n)
        return self._expand(key, k, c, rows, v)

    def _expand(
        self, key: str | Criterion, k: NDArray, c: NDArray, rows: NDArray, v: NDArray
    ) -> tuple[NDArray, NDArray, int]:
        heads = self.heads_for(key)
        n, nh = k.size, heads.shape[0]
        params = np.column_stack([rows[:, :3], k, c])
        extra = np.repeat(rows[:, 3:], nh, axis=0)  # full-joint controller columns, if any
        full = np.column_stack([np.repeat(params, nh, axis=0), np.tile(heads, (n, 1)), extra])
        return full, np.repeat(v, nh), nh

    def _values(
        self, key: str | Criterion, k: NDArray, c: NDArray, rows: NDArray, v: NDArray
    ) -> NDArray:
        """Metric for designs ``i`` x robot rows ``j`` (paired arrays, all length n)."""
        full, vv, nh = self._expand(key, k, c, rows, v)
        if key == COMPRESSION:
            m = impact_metrics(
                full, vv, constrained=self.constrained, with_force=False, stop_time=self.stop_time
            )
            vals = m.max_compression
        else:
            vals = key.values(full, vv, constrained=self.constrained)  # type: ignore[union-attr]
        return vals.reshape(k.size, nh).max(axis=1)

    def worst(self, key: str | Criterion, k: NDArray, c: NDArray) -> tuple[NDArray, NDArray]:
        """Worst-case metric over heads (and impact points) for foams ``(k, c)``.

        Returns the values and the worst lever arm (NaN for a fixed robot).
        """
        k = np.asarray(k, dtype=float).ravel()
        c = np.asarray(c, dtype=float).ravel()
        if not isinstance(self.robot, LinkImpact):
            rows, v = self._robot_rows(None)
            n = k.size
            return self._values(key, k, c, np.repeat(rows, n, axis=0), np.repeat(v, n)), np.full(
                n, np.nan
            )
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

    def limit(self, key: str | Criterion) -> float:
        return self.max_compression if key == COMPRESSION else key.limit  # type: ignore[union-attr]

    def log_excess(self, key: str | Criterion, u: NDArray, c: NDArray) -> NDArray:
        """``log(metric / limit)`` at ``K_c = exp(u)``: > 0 means violated."""
        vals, _ = self.worst(key, np.exp(u), c)
        with np.errstate(divide="ignore"):
            return np.log(np.maximum(vals, 1e-300)) - math.log(self.limit(key))

    def keys(self) -> list[str | Criterion]:
        return [*self.criteria, COMPRESSION]


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
    """Vectorised Illinois (modified regula falsi) on brackets with ``fa * fb < 0``."""
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
    return x


def _boundary(
    prob: _Problem, key: str | Criterion, c: NDArray, u_grid: NDArray, tol: float
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
    upper = key != COMPRESSION
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
class FoamEnvelope:
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
        first-lobe metrics can jump there (impact.md Sec. 2.10).
    worst_lever_arm
        For a robot at joint level, the worst impact point on the upper
        boundary of the first criterion (NaN otherwise).
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


def _solve(
    prob: _Problem, damping: NDArray, bounds: tuple[float, float], rtol: float, n_scan: int = 48
) -> FoamEnvelope:
    u_grid = np.linspace(math.log(bounds[0]), math.log(bounds[1]), n_scan)
    tol = math.log1p(rtol)
    upper: dict[str, NDArray] = {}
    upper_status: dict[str, NDArray] = {}
    multiple = np.zeros(damping.size, dtype=bool)
    for crit in prob.criteria:
        k, st, mult = _boundary(prob, crit, damping, u_grid, tol)
        upper[crit.name] = k
        upper_status[crit.name] = st
        multiple |= mult
    kmin, lower_status, mult = _boundary(prob, COMPRESSION, damping, u_grid, tol)
    multiple |= mult
    kmax = np.full(damping.size, np.inf)
    any_bounded = np.zeros(damping.size, dtype=bool)
    for name in upper:
        bounded = upper_status[name] == "bounded"
        kmax = np.where(bounded, np.minimum(kmax, upper[name]), kmax)
        any_bounded |= bounded
    kmax = np.where(any_bounded, kmax, np.nan)
    kmin = np.where(lower_status == "bounded", kmin, np.nan)

    overdamped = np.zeros(damping.size, dtype=bool)
    delicate = np.zeros(damping.size, dtype=bool)
    worst_l = np.full(damping.size, np.nan)
    first = prob.criteria[0] if prob.criteria else None
    if first is not None and np.any(np.isfinite(kmax)) and isinstance(prob.robot, LinkImpact):
        ok = np.isfinite(kmax)
        _, worst_l[ok] = prob.worst(first, kmax[ok], damping[ok])
    if not prob.constrained:
        # flag the boundary designs themselves (worst head, worst impact point)
        for key, kb in ((first, kmax), (COMPRESSION, kmin)):
            ok = np.isfinite(kb)
            if key is None or not np.any(ok):
                continue
            _, lev = prob.worst(key, kb[ok], damping[ok])
            params, v, nh = prob.designs(key, kb[ok], damping[ok], lev)
            m = impact_metrics(params, v, with_force=False, lobe_diagnostics=True)
            pac = (m.status == "peak_at_contact").reshape(-1, nh).any(axis=1)
            dl_ = m.delicate_lobe.reshape(-1, nh).any(axis=1)
            if key is first:
                overdamped[ok] |= pac
            delicate[ok] |= dl_
    warnings = []
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
            "can jump with small parameter changes (impact.md Sec. 2.10)"
        )
    if np.any(overdamped):
        warnings.append(
            f"{int(overdamped.sum())} upper-boundary point(s) are overdamped pulses (a_h peaks "
            "at contact, a_h,max = C_c v_c / M_h): outside the thesis's foam range xi_c 0.05-0.2"
        )
    return FoamEnvelope(
        robot=prob.robot,
        impact_velocity=prob.impact_velocity,
        criteria=prob.criteria,
        max_compression=prob.max_compression,
        damping=damping,
        stiffness_min=kmin,
        stiffness_max=kmax,
        upper=upper,
        upper_status=upper_status,
        lower_status=lower_status,
        multiple_roots=multiple,
        overdamped=overdamped,
        delicate=delicate,
        worst_lever_arm=worst_l,
        stiffness_bounds=bounds,
        constrained=prob.constrained,
        head_range=prob.head_range,
        warnings=tuple(warnings),
        _problem=prob,
    )


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
        if human_speed < 0 or not np.isfinite(human_speed):
            raise InvalidParameterError("human_speed", human_speed, "must be >= 0", "m/s")
    elif isinstance(robot, (ContactDynamics, FullJointContact)):
        v = check_positive(
            "impact_velocity", 1.25 if impact_velocity is None else impact_velocity, "m/s"
        )
    else:
        raise InvalidParameterError(
            "robot", robot, "must be a ContactDynamics, a FullJointContact or a LinkImpact"
        )
    crit = tuple(criteria) if criteria is not None else (HeadAcceleration(10.0),)
    for c in crit:
        if not isinstance(c, Criterion):
            raise InvalidParameterError("criteria", c, "must contain Criterion objects")
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
    """
    c = (
        np.linspace(0.0, 200.0, 41)
        if damping is None
        else np.atleast_1d(np.asarray(damping, float))
    )
    if c.ndim != 1 or c.size == 0 or np.any(~np.isfinite(c)) or np.any(c < 0):
        raise InvalidParameterError(
            "damping", damping, "must be a 1-D array of values >= 0", "N s/m"
        )
    lo, hi = stiffness_bounds
    if not (0 < lo < hi and np.isfinite(hi)):
        raise InvalidParameterError(
            "stiffness_bounds", stiffness_bounds, "must be (low, high) with 0 < low < high", "N/m"
        )
    if not 0 < rtol < 1e-2:
        raise InvalidParameterError("rtol", rtol, "must be in (0, 0.01)")
    prob = _make_problem(
        robot,
        impact_velocity,
        criteria,
        max_compression,
        head_range,
        constrained,
        human_speed,
        stop_time,
    )
    return _solve(prob, c, (float(lo), float(hi)), rtol)


# -- checks and design answers ---------------------------------------------------


@dataclass(frozen=True)
class WorstCaseCheck:
    """Result of sampling the ranges at the envelope's boundary points.

    For each constraint, the sampled metric at the boundary stiffness divided by
    the limit. A ratio above 1 means a sampled case is worse than the case the
    envelope used. Samples whose first lobe is *delicate* (a_h dips close to
    zero inside the lobe or peaks at contact, so the lobe end and eps_max jump
    with small changes; impact.md Sec. 2.10) are reported apart.

    Attributes
    ----------
    max_ratio
        Largest ratio over the regular samples, per constraint.
    max_ratio_delicate
        Largest ratio over the delicate samples, per constraint (NaN if none).
    ratio_by_point
        Per constraint, the largest regular ratio at each damping value.
    delicate_points
        Per constraint, the damping values with a delicate sample above the limit.
    """

    max_ratio: dict[str, float]
    max_ratio_delicate: dict[str, float]
    ratio_by_point: dict[str, NDArray[np.float64]]
    delicate_points: dict[str, NDArray[np.float64]]
    samples: int
    tolerance: float

    @property
    def holds(self) -> bool:
        """Whether no regular sample exceeds the limit by more than the tolerance."""
        return all(not np.isfinite(r) or r <= 1 + self.tolerance for r in self.max_ratio.values())

    def to_frame(self) -> pd.DataFrame:
        """One row per constraint."""
        return pd.DataFrame(
            {
                "constraint": list(self.max_ratio),
                "max_sampled_ratio": list(self.max_ratio.values()),
                "max_sampled_ratio_delicate_lobes": list(self.max_ratio_delicate.values()),
                "n_points_delicate_above_limit": [len(v) for v in self.delicate_points.values()],
            }
        )


def check_worst_case(
    env: FoamEnvelope,
    head_range: HeadRange = THESIS_HEAD_RANGE,
    samples: int = 64,
    seed: int = 0,
    tolerance: float = 1e-6,
) -> WorstCaseCheck:
    """Sample heads in ``head_range``, velocities up to the maximum and impact points.

    At every bounded boundary point, no sampled case may exceed the limit that
    the envelope's worst case meets there.

    Examples
    --------
    >>> import numpy as np, designlab as dl
    >>> env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, 1.25, np.linspace(10, 90, 5))
    >>> dl.impact.check_worst_case(env, samples=32).holds
    True
    """
    prob = env._require_problem()
    rng = np.random.default_rng(seed)
    ratios: dict[str, float] = {}
    ratios_d: dict[str, float] = {}
    by_point: dict[str, NDArray] = {}
    d_points: dict[str, NDArray] = {}
    keys: list[tuple[str | Criterion, NDArray]] = [
        (crit, env.upper[crit.name]) for crit in prob.criteria
    ]
    keys.append((COMPRESSION, env.stiffness_min))
    for key, kb in keys:
        ok = np.isfinite(kb)
        name = COMPRESSION if key == COMPRESSION else key.name  # type: ignore[union-attr]
        by_point[name] = np.full(env.damping.size, np.nan)
        if not np.any(ok):
            ratios[name] = ratios_d[name] = float("nan")
            d_points[name] = np.array([])
            continue
        k = np.repeat(kb[ok], samples)
        c = np.repeat(env.damping[ok], samples)
        n = k.size
        if prob.constrained:
            heads = np.tile([1.0, 0.0, 0.0], (n, 1))
        else:
            heads = head_range.sample(n, rng)
        frac = rng.random(n)
        if isinstance(prob.robot, LinkImpact):
            lr = prob.robot
            lev = lr.lever_arm_min + (lr.lever_arm_max - lr.lever_arm_min) * rng.random(n)
            rows, vmax = prob._robot_rows(lev)
        else:
            rows, vmax = prob._robot_rows(None)
            rows = np.repeat(rows, n, axis=0)
            vmax = np.repeat(vmax, n)
        v = vmax * np.where(frac < 0.25, 1.0, frac)  # a quarter at the maximum speed
        params = np.column_stack([rows[:, :3], k, c, heads, rows[:, 3:]])  # full joint: +2
        need_force = key != COMPRESSION and key.needs_force  # type: ignore[union-attr]
        m = impact_metrics(
            params,
            v,
            constrained=prob.constrained,
            with_force=need_force,
            stop_time=prob.stop_time,
            lobe_diagnostics=True,
        )
        vals = m.max_compression if key == COMPRESSION else key.from_metrics(m)  # type: ignore[union-attr]
        ratio = (vals / prob.limit(key)).reshape(-1, samples)
        delicate = m.delicate_lobe.reshape(-1, samples)
        regular = np.where(delicate, -np.inf, ratio).max(axis=1)
        special = np.where(delicate, ratio, -np.inf).max(axis=1)
        by_point[name][ok] = np.where(np.isfinite(regular), regular, np.nan)
        ratios[name] = (
            float(np.nanmax(by_point[name])) if np.any(np.isfinite(regular)) else float("nan")
        )
        ratios_d[name] = float(special.max()) if np.any(np.isfinite(special)) else float("nan")
        d_points[name] = env.damping[ok][special > 1 + tolerance]
    return WorstCaseCheck(ratios, ratios_d, by_point, d_points, samples, tolerance)


@dataclass(frozen=True)
class SafeVelocity:
    """Largest impact velocity for which a foam satisfies every constraint.

    Attributes
    ----------
    impact_velocity
        Largest v_c, m/s.
    manipulator_speed
        ``impact_velocity - human_speed``: the largest manipulator speed when the
        person moves toward it at ``human_speed`` (negative: unsafe even at rest).
    per_constraint
        Largest v_c allowed by each constraint alone.
    limiting
        Name of the constraint that sets the answer.
    """

    impact_velocity: float
    manipulator_speed: float
    human_speed: float
    per_constraint: dict[str, float]
    limiting: str

    def to_frame(self) -> pd.DataFrame:
        """One row per constraint."""
        return pd.DataFrame(
            {
                "constraint": list(self.per_constraint),
                "v_c_max_m_per_s": list(self.per_constraint.values()),
            }
        )


def max_safe_velocity(
    robot: ContactDynamics,
    foam: Foam,
    criteria: Sequence[Criterion] | None = None,
    *,
    max_compression: float | None = None,
    human_speed: float = 1.0,
    head_range: HeadRange | None = None,
    constrained: bool = False,
) -> SafeVelocity:
    """Largest impact velocity (and manipulator speed) for which ``foam`` is safe.

    The metrics scale as v_c ** exponent (1 for a_h,max, force and eps_max, 2.5
    for HIC), so the answer is exact: ``v_i = v_0 (limit_i / metric_i(v_0))^(1/e_i)``.
    ``max_compression`` defaults to the foam's linear depth.

    Examples
    --------
    >>> import designlab as dl
    >>> sv = dl.impact.max_safe_velocity(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1)
    >>> sv.limiting, round(sv.impact_velocity, 2)
    ('eps_max', 1.81)
    """
    lam = foam.linear_depth if max_compression is None else max_compression
    prob = _make_problem(robot, 1.0, criteria, lam, head_range, constrained, human_speed, 0.05)
    k = np.array([foam.stiffness])
    c = np.array([foam.damping])
    per: dict[str, float] = {}
    for key in prob.keys():
        vals, _ = prob.worst(key, k, c)
        expo = 1.0 if key == COMPRESSION else key.velocity_exponent  # type: ignore[union-attr]
        name = COMPRESSION if key == COMPRESSION else key.name  # type: ignore[union-attr]
        per[name] = float(np.inf if vals[0] <= 0 else (prob.limit(key) / vals[0]) ** (1 / expo))
    limiting = min(per, key=lambda n: per[n])
    v = per[limiting]
    return SafeVelocity(v, v - human_speed, human_speed, per, limiting)


@dataclass(frozen=True)
class FoamThickness:
    """Thickness a foam needs so that it does not bottom out.

    ``linear_depth`` (lambda) is the worst-case eps_max; ``thickness`` scales it by the
    foam's ratio T_u / lambda (0.0254/0.02 for the thesis's foam).
    """

    linear_depth: float
    thickness: float
    impact_velocity: float


def min_foam_thickness(
    robot: ContactDynamics,
    foam: Foam,
    impact_velocity: float = 1.25,
    *,
    head_range: HeadRange | None = None,
    constrained: bool = False,
) -> FoamThickness:
    """Smallest linear depth (and total thickness) for ``foam`` at ``impact_velocity``.

    Examples
    --------
    >>> import designlab as dl
    >>> t = dl.impact.min_foam_thickness(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, 1.25)
    >>> round(t.linear_depth * 1000, 1)     # mm, maximum head-neck set
    13.8
    """
    prob = _make_problem(robot, impact_velocity, (), 1.0, head_range, constrained, 1.0, 0.05)
    vals, _ = prob.worst(COMPRESSION, np.array([foam.stiffness]), np.array([foam.damping]))
    lam = float(vals[0])
    assert foam.thickness is not None
    return FoamThickness(lam, lam * foam.thickness / foam.linear_depth, float(impact_velocity or 0))
