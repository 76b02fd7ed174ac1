"""Optimal foam covering: the foam with the largest worst-case safety margin.

The margin of a design is the smallest of ``ln(limit / metric)`` over the
criteria and the thickness constraint (eps_max <= lambda), each evaluated at
its worst case (head-neck set, impact point), exactly as in
:func:`~designlab.impact.envelope.foam_envelope`. :func:`optimal_foam` solves::

    maximise  s   over  ln K_c, C_c (and optionally ln lambda), s
    subject   to  ln(limit_i) - ln(metric_i(K_c, C_c)) >= s      for every constraint i

with CasADi and IPOPT. The constraints are CasADi callbacks whose Jacobians are
exact: the metric gradients come from automatic differentiation of the CasADi
model at the maximising times (envelope theorem,
:mod:`designlab.impact.derivatives`); only HIC, which is defined on a time
grid, is differentiated by central differences. A coarse grid search supplies
the starting point.

With ``objective="thinnest"`` and a thickness range, the problem becomes:
minimise ln(lambda) subject to every margin >= ``min_margin``.

When even the best foam has a negative margin, the region is empty at this
velocity; the result names the velocity at which it reopens (metrics scale as
v_c ** e with e = 1, or 2.5 for HIC).

Examples
--------
>>> import designlab as dl
>>> opt = dl.impact.optimal_foam(dl.impact.MANIPULATOR_1, impact_velocity=1.25)
>>> opt.status, bool(opt.margin > 0)
('optimal', True)
>>> bool(20e3 < opt.stiffness < 40e3)
True
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import casadi as ca
import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.criteria import Criterion
from designlab.impact.derivatives import metric_gradients
from designlab.impact.envelope import COMPRESSION, HeadRange, _make_problem, _Problem
from designlab.impact.metrics import impact_metrics
from designlab.impact.parameters import ContactDynamics, LinkImpact

__all__ = ["OptimalFoam", "optimal_foam"]

_METRIC_ATTR = {
    "head_acceleration": "peak_head_acceleration",
    "force": "peak_force",
    COMPRESSION: "max_compression",
}


def _key_name(key: str | Criterion) -> str:
    return COMPRESSION if key == COMPRESSION else key.name  # type: ignore[union-attr]


def _exponent(key: str | Criterion) -> float:
    return 1.0 if key == COMPRESSION else key.velocity_exponent  # type: ignore[union-attr]


def _worst_design(prob: _Problem, key: str | Criterion, k: float, c: float):
    """Parameters and velocity of the worst case of ``key`` for foam ``(k, c)``."""
    vals, lev = prob.worst(key, np.array([k]), np.array([c]))
    params, vv, _ = prob.designs(key, np.array([k]), np.array([c]), lev)
    if key == COMPRESSION:
        m = impact_metrics(params, vv, constrained=prob.constrained, with_force=False)
        each = m.max_compression
    else:
        each = key.values(params, vv, constrained=prob.constrained)  # type: ignore[union-attr]
    j = int(np.argmax(each))
    return params[j], float(vv[j]), float(vals[0])


def _gradient_kc(prob: _Problem, key: str | Criterion, k: float, c: float) -> tuple[float, NDArray]:
    """Worst-case metric and its gradient w.r.t. (K_c, C_c)."""
    p, v, val = _worst_design(prob, key, k, c)
    metric = "compression" if key == COMPRESSION else key.metric  # type: ignore[union-attr]
    if metric == "hic":
        grads = []
        for j, x in ((3, k), (4, c)):
            h = max(abs(x), 1.0) * 1e-6
            up, dn = p.copy(), p.copy()
            up[j] += h
            dn[j] -= h
            fu = key.values(up[None, :], np.array([v]))[0]  # type: ignore[union-attr]
            fd = key.values(dn[None, :], np.array([v]))[0]  # type: ignore[union-attr]
            grads.append((fu - fd) / (2 * h))
        return val, np.array(grads)
    attr = _METRIC_ATTR[metric if metric != "compression" else COMPRESSION]
    g = metric_gradients(p, v, constrained=prob.constrained).gradients[attr][0]
    return val, g[[3, 4]]


class _Margins(ca.Callback):
    """``x = [ln K_c, C_c, ln lambda] -> ln(limit_i / metric_i)`` with exact Jacobian."""

    def __init__(self, name: str, prob: _Problem, opts: dict | None = None) -> None:
        ca.Callback.__init__(self)
        self.prob = prob
        self.keys = prob.keys()
        self.construct(name, opts or {})

    def get_n_in(self) -> int:
        return 1

    def get_n_out(self) -> int:
        return 1

    def get_sparsity_in(self, i: int) -> ca.Sparsity:
        return ca.Sparsity.dense(3, 1)

    def get_sparsity_out(self, i: int) -> ca.Sparsity:
        return ca.Sparsity.dense(len(self.keys), 1)

    def _limit(self, key: str | Criterion, lam: float) -> float:
        return lam if key == COMPRESSION else self.prob.limit(key)

    def eval(self, arg):  # type: ignore[no-untyped-def]
        u, c, ul = (float(a) for a in np.asarray(arg[0]).ravel())
        k, lam = math.exp(u), math.exp(ul)
        out = []
        for key in self.keys:
            vals, _ = self.prob.worst(key, np.array([k]), np.array([c]))
            out.append(math.log(self._limit(key, lam)) - math.log(max(float(vals[0]), 1e-300)))
        return [ca.DM(out)]

    def has_jacobian(self) -> bool:
        return True

    def get_jacobian(self, name, inames, onames, opts):  # type: ignore[no-untyped-def]
        cb = _MarginJacobian(name, self, opts)
        self._jac = cb  # keep alive
        return cb


class _MarginJacobian(ca.Callback):
    def __init__(self, name: str, parent: _Margins, opts: dict | None = None) -> None:
        ca.Callback.__init__(self)
        self.parent = parent
        self.construct(name, opts or {})

    def get_n_in(self) -> int:
        return 2

    def get_n_out(self) -> int:
        return 1

    def get_sparsity_in(self, i: int) -> ca.Sparsity:
        return ca.Sparsity.dense(3, 1) if i == 0 else ca.Sparsity.dense(len(self.parent.keys), 1)

    def get_sparsity_out(self, i: int) -> ca.Sparsity:
        return ca.Sparsity.dense(len(self.parent.keys), 3)

    def eval(self, arg):  # type: ignore[no-untyped-def]
        u, c, _ul = (float(a) for a in np.asarray(arg[0]).ravel())
        k = math.exp(u)
        jac = np.zeros((len(self.parent.keys), 3))
        for i, key in enumerate(self.parent.keys):
            val, g = _gradient_kc(self.parent.prob, key, k, c)
            jac[i, 0] = -g[0] * k / val
            jac[i, 1] = -g[1] / val
            if key == COMPRESSION:
                jac[i, 2] = 1.0
        return [ca.DM(jac)]


@dataclass(frozen=True)
class OptimalFoam:
    """Result of :func:`optimal_foam`.

    Attributes
    ----------
    stiffness, damping, linear_depth
        The optimal K_c (N/m), C_c (N s/m) and lambda (m).
    margin
        Worst-case margin, ``min_i ln(limit_i / metric_i)`` (0.1 ~ 10 % headroom).
    margins
        Per constraint name, its margin at the optimum.
    status
        ``"optimal"`` (margin >= 0), ``"empty"`` (the best foam violates a
        constraint: no feasible foam at this velocity), or ``"solver_failed: ..."``.
    reopen_velocity_factor
        For an empty region: the factor by which all speeds must be scaled for
        the region to reopen (< 1); 1 otherwise.
    reopen_velocity
        ``reopen_velocity_factor * impact_velocity`` (NaN for a LinkImpact robot).
    grid_margin
        Best margin found by the starting grid search (for comparison).
    """

    stiffness: float
    damping: float
    linear_depth: float
    margin: float
    margins: dict[str, float]
    status: str
    impact_velocity: float
    reopen_velocity_factor: float
    reopen_velocity: float
    grid_margin: float
    iterations: int
    objective: str
    stats: dict = field(default_factory=dict, repr=False)

    @property
    def headroom(self) -> float:
        """Smallest fractional headroom below a limit, ``exp(margin) - 1``."""
        return math.expm1(self.margin)

    def to_frame(self) -> pd.DataFrame:
        """One row per constraint at the optimum."""
        return pd.DataFrame(
            {
                "constraint": list(self.margins),
                "margin_ln": list(self.margins.values()),
                "headroom_percent": [100 * math.expm1(m) for m in self.margins.values()],
            }
        )


def optimal_foam(
    robot: ContactDynamics | LinkImpact,
    impact_velocity: float | None = 1.25,
    criteria: Sequence[Criterion] | None = None,
    max_compression: float = 0.02,
    *,
    stiffness_bounds: tuple[float, float] = (1e3, 2e5),
    damping_bounds: tuple[float, float] = (0.0, 200.0),
    thickness_bounds: tuple[float, float] | None = None,
    objective: str = "margin",
    min_margin: float = 0.0,
    head_range: HeadRange | None = None,
    constrained: bool = False,
    human_speed: float = 1.0,
    damping_ratio_bounds: tuple[float, float] | None = (0.05, 0.2),
    head_mass_for_ratio: float = 4.4,
    grid: int = 24,
    ipopt_options: dict | None = None,
) -> OptimalFoam:
    """Choose the foam (K_c, C_c and optionally lambda) with the best worst-case margin.

    Parameters
    ----------
    robot, impact_velocity, criteria, max_compression, head_range, constrained, human_speed
        As for :func:`~designlab.impact.envelope.foam_envelope`.
    stiffness_bounds, damping_bounds
        Ranges of K_c (N/m) and C_c (N s/m).
    thickness_bounds
        Range of lambda (m) to optimise the linear depth too; ``None`` keeps
        ``max_compression``.
    objective
        ``"margin"`` (maximise the worst-case margin) or ``"thinnest"``
        (minimise lambda with every margin >= ``min_margin``; needs
        ``thickness_bounds``).
    damping_ratio_bounds
        Range of the foam damping ratio xi_c = C_c / (2 sqrt(M_h K_c)) (thesis
        convention, ``head_mass_for_ratio`` = 4.4 kg). The default keeps to
        elastomeric foams, xi_c = 0.05-0.2 (Rivin 2003, quoted by the thesis);
        ``None`` lifts it.
    grid
        Points per axis of the starting grid search.
    ipopt_options
        Extra IPOPT options.

    Returns
    -------
    OptimalFoam
    """
    from designlab.impact.full_joint import FullJointLink

    if not isinstance(robot, (ContactDynamics, LinkImpact)) or isinstance(robot, FullJointLink):
        raise InvalidParameterError(
            "robot",
            robot,
            "must be a ContactDynamics or a LinkImpact (exact gradients exist for the reduced "
            "joint only; for a FullJointContact use its foam_envelope, or robot.taylor())",
        )
    if objective not in ("margin", "thinnest"):
        raise InvalidParameterError("objective", objective, "must be 'margin' or 'thinnest'")
    if objective == "thinnest" and thickness_bounds is None:
        raise InvalidParameterError(
            "thickness_bounds", None, "is needed with objective='thinnest'", "m"
        )
    klo, khi = stiffness_bounds
    clo, chi = damping_bounds
    if not (0 < klo < khi and np.isfinite(khi)):
        raise InvalidParameterError(
            "stiffness_bounds", stiffness_bounds, "need 0 < low < high", "N/m"
        )
    if not (0 <= clo < chi and np.isfinite(chi)):
        raise InvalidParameterError(
            "damping_bounds", damping_bounds, "need 0 <= low < high", "N s/m"
        )
    if thickness_bounds is not None:
        tlo, thi = thickness_bounds
        if not (0 < tlo <= thi and np.isfinite(thi)):
            raise InvalidParameterError(
                "thickness_bounds", thickness_bounds, "need 0 < low <= high", "m"
            )
        lam0 = thi
    else:
        tlo = thi = lam0 = max_compression
    prob = _make_problem(
        robot, impact_velocity, criteria, lam0, head_range, constrained, human_speed, 0.05
    )
    keys = prob.keys()

    # starting grid: metrics on (ln K, C), margins at the largest lambda
    ug = np.linspace(math.log(klo), math.log(khi), grid)
    cg = np.linspace(clo, chi, grid)
    uu, cc = np.meshgrid(ug, cg, indexing="ij")
    metric_grid = {}
    for key in keys:
        vals, _ = prob.worst(key, np.exp(uu.ravel()), cc.ravel())
        metric_grid[_key_name(key)] = vals.reshape(uu.shape)

    def grid_margins(lam: float, shift: float = 0.0) -> NDArray:
        out = np.full(uu.shape, np.inf)
        for key in keys:
            lim = lam if key == COMPRESSION else prob.limit(key)
            with np.errstate(divide="ignore"):
                g = math.log(lim) - np.log(np.maximum(metric_grid[_key_name(key)], 1e-300))
            out = np.minimum(out, g - _exponent(key) * shift)
        return out

    if damping_ratio_bounds is not None:
        xlo, xhi = damping_ratio_bounds
        if not (0 <= xlo <= xhi and np.isfinite(xhi)):
            raise InvalidParameterError(
                "damping_ratio_bounds", damping_ratio_bounds, "need 0 <= low <= high"
            )
        xi_grid = cc / (2.0 * np.sqrt(head_mass_for_ratio * np.exp(uu)))
        allowed = (xi_grid >= xlo) & (xi_grid <= xhi)
    else:
        allowed = np.ones(uu.shape, dtype=bool)
    if not np.any(allowed):
        raise InvalidParameterError(
            "damping_ratio_bounds",
            damping_ratio_bounds,
            "leaves no foam inside stiffness_bounds x damping_bounds",
        )
    gm = np.where(allowed, grid_margins(thi), -np.inf)
    i0 = np.unravel_index(int(np.argmax(gm)), gm.shape)
    grid_best = float(gm[i0])
    x0 = [float(uu[i0]), float(cc[i0]), math.log(thi)]

    cb = _Margins("margins", prob)
    x = ca.MX.sym("x", 4)  # ln K, C, ln lambda, s
    g_all = cb(x[:3])
    if objective == "margin":
        f = -x[3]
        g = g_all - x[3]
        lbx = [math.log(klo), clo, math.log(tlo), -50.0]
        ubx = [math.log(khi), chi, math.log(thi), 50.0]
        if thickness_bounds is None:
            lbx[2] = ubx[2] = math.log(lam0)
        x_init = [*x0, grid_best]
    else:
        f = x[2]
        g = g_all - min_margin
        lbx = [math.log(klo), clo, math.log(tlo), 0.0]
        ubx = [math.log(khi), chi, math.log(thi), 0.0]
        x_init = [*x0, 0.0]
    lbg = [0.0] * len(keys)
    ubg = [ca.inf] * len(keys)
    if damping_ratio_bounds is not None:
        # xi_lo <= C / (2 sqrt(M_h K)) <= xi_hi, written smoothly in (ln K, C)
        root = 2.0 * math.sqrt(head_mass_for_ratio) * ca.exp(x[0] / 2)
        g = ca.vertcat(
            g, x[1] - damping_ratio_bounds[0] * root, damping_ratio_bounds[1] * root - x[1]
        )
        lbg += [0.0, 0.0]
        ubg += [ca.inf, ca.inf]
    opts = {
        "ipopt.print_level": 0,
        "print_time": False,
        "ipopt.sb": "yes",
        "ipopt.hessian_approximation": "limited-memory",
        "ipopt.tol": 1e-8,
        "ipopt.acceptable_tol": 1e-6,
        "ipopt.max_iter": 200,
    }
    opts.update({f"ipopt.{k}": v for k, v in (ipopt_options or {}).items()})
    solver = ca.nlpsol("optimal_foam", "ipopt", {"x": x, "f": f, "g": g}, opts)
    try:
        sol = solver(x0=x_init, lbx=lbx, ubx=ubx, lbg=lbg, ubg=ubg)
        stats = dict(solver.stats())
        ok = bool(stats.get("success", False))
        xs = np.asarray(sol["x"]).ravel()
        status = "optimal" if ok else f"solver_failed: {stats.get('return_status', 'unknown')}"
    except RuntimeError as exc:  # pragma: no cover - IPOPT failures are reported, not raised
        stats, ok = {"error": str(exc)}, False
        xs = np.array([*x_init])
        status = f"solver_failed: {exc}"

    k_opt, c_opt, lam_opt = math.exp(xs[0]), float(xs[1]), math.exp(xs[2])
    gvals = np.asarray(cb(ca.DM([xs[0], xs[1], xs[2]]))).ravel()
    margins = {_key_name(key): float(gvals[i]) for i, key in enumerate(keys)}
    margin = float(min(margins.values()))
    if not ok and grid_best > margin:
        # keep the better of the grid point and the failed solve, and say so
        k_opt, c_opt, lam_opt = math.exp(x0[0]), x0[1], math.exp(x0[2])
        gvals = np.asarray(cb(ca.DM(x0))).ravel()
        margins = {_key_name(key): float(gvals[i]) for i, key in enumerate(keys)}
        margin = float(min(margins.values()))

    factor = 1.0
    if objective == "margin" and margin < 0 and not status.startswith("solver_failed"):
        status = "empty"
        if all(_exponent(k) == 1.0 for k in keys):
            factor = math.exp(margin)
        else:
            lo, hi = margin, 0.0  # shift = ln(factor): at lo every constraint reopens
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                if np.max(np.where(allowed, grid_margins(thi, mid), -np.inf)) >= 0:
                    lo = mid
                else:
                    hi = mid
            factor = math.exp(lo)
    v0 = prob.impact_velocity if isinstance(robot, ContactDynamics) else float("nan")
    return OptimalFoam(
        stiffness=k_opt,
        damping=c_opt,
        linear_depth=lam_opt,
        margin=margin,
        margins=margins,
        status=status,
        impact_velocity=v0,
        reopen_velocity_factor=factor,
        reopen_velocity=factor * v0,
        grid_margin=grid_best,
        iterations=int(stats.get("iter_count", 0)) if isinstance(stats, dict) else 0,
        objective=objective,
        stats=stats,
    )
