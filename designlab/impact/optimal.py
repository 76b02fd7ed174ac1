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
('ok', True)
>>> bool(20e3 < opt.stiffness < 40e3)
True
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import casadi as ca
import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.contact import contact_of
from designlab.impact.criteria import Criterion
from designlab.impact.derivatives import metric_gradients
from designlab.impact.model import PARAM_NAMES
from designlab.impact.parameters import (
    DAMPING_GRID,
    MAX_COMPRESSION,
    ContactDynamics,
    Foam,
    HeadNeck,
    HeadRange,
    LinkImpact,
    check_pair,
)
from designlab.impact.problem import FoamProblem, make_problem
from designlab.params import Param, params_of
from designlab.results import Result, Status

__all__ = [
    "DAMPING_RATIO",
    "GRID_POINTS",
    "MIN_MARGIN",
    "OBJECTIVE",
    "OptimalFoam",
    "OptimalStatus",
    "optimal_foam",
]

log = logging.getLogger(__name__)

_FOAM = params_of(Foam)

#: The foam damping ratio xi_c = C_c / (2 sqrt(M_h K_c)) (thesis convention).
DAMPING_RATIO = Param(
    "xi_c", "", "foam damping ratio", ge=0, le=10, typical=(0.05, 0.2), name="damping_ratio_bounds"
)
#: What :func:`optimal_foam` optimises.
OBJECTIVE = Param(
    None, "", "what is optimised", kind="choice", choices=("margin", "thinnest"), name="objective"
)
#: The smallest worst-case margin the ``"thinnest"`` objective keeps (ln of limit / metric).
MIN_MARGIN = Param(
    None, "", "smallest worst-case margin ln(limit / metric)", ge=-10, le=10, name="min_margin"
)
#: Points per axis of the starting grid search (the grid has its square).
GRID_POINTS = Param(
    None, "", "points per axis of the starting grid search", kind="integer", ge=2, le=200,
    name="grid",
)  # fmt: skip


class OptimalStatus(Status):
    """Status of :func:`optimal_foam`.

    Attributes
    ----------
    OK
        The optimum was found (margin >= 0 for the ``"margin"`` objective).
    EMPTY
        The best foam violates a constraint: no feasible foam at this velocity.
    SOLVER_FAILED
        IPOPT did not converge; the better of the grid start and the last
        iterate is returned.
    """

    OK = "ok"
    EMPTY = "empty"
    SOLVER_FAILED = "solver_failed"


_METRIC_ATTR = {
    "head_acceleration": "peak_head_acceleration",
    "force": "peak_force",
    "compression": "max_compression",
}


#: the positions of K_c and C_c in the reduced joint's row (the only one with gradients)
_FOAM_COLUMNS = (PARAM_NAMES.index("K_c"), PARAM_NAMES.index("C_c"))


def _worst_design(
    prob: FoamProblem, key: Criterion, k: float, c: float
) -> tuple[NDArray, float, float]:
    """Parameters and velocity of the worst case of ``key`` for foam ``(k, c)``."""
    vals, lev = prob.worst(key, np.array([k]), np.array([c]))
    params, vv, _ = prob.designs(key, np.array([k]), np.array([c]), lev)
    each = key.values(params, vv, constrained=prob.constrained, stop_time=prob.stop_time)
    j = int(np.argmax(each))
    return params[j], float(vv[j]), float(vals[0])


def _gradient_kc(prob: FoamProblem, key: Criterion, k: float, c: float) -> tuple[float, NDArray]:
    """Worst-case metric and its gradient w.r.t. (K_c, C_c)."""
    p, v, val = _worst_design(prob, key, k, c)
    if key.metric == "hic":
        grads = []
        for j, x in zip(_FOAM_COLUMNS, (k, c), strict=True):
            h = max(abs(x), 1.0) * 1e-6
            up, dn = p.copy(), p.copy()
            up[j] += h
            dn[j] -= h
            fu = key.values(up[None, :], np.array([v]))[0]
            fd = key.values(dn[None, :], np.array([v]))[0]
            grads.append((fu - fd) / (2 * h))
        return val, np.array(grads)
    g = metric_gradients(
        np.atleast_2d(p), v, columns=PARAM_NAMES, constrained=prob.constrained
    ).gradients[_METRIC_ATTR[key.metric]][0]
    return val, g[list(_FOAM_COLUMNS)]


class _Margins(ca.Callback):
    """``x = [ln K_c, C_c, ln lambda] -> ln(limit_i / metric_i)`` with exact Jacobian."""

    def __init__(self, name: str, prob: FoamProblem, opts: dict | None = None) -> None:
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

    def _limit(self, key: Criterion, lam: float) -> float:
        return lam if key.boundary == "lower" else key.limit

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
            if key.boundary == "lower":
                jac[i, 2] = 1.0
        return [ca.DM(jac)]


@dataclass(frozen=True)
class OptimalFoam(Result):
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
        ``"ok"`` (optimum found, margin >= 0), ``"empty"`` (the best foam
        violates a constraint: no feasible foam at this velocity), or
        ``"solver_failed"`` (IPOPT did not converge; see ``warnings``: the
        better of the grid start and the last iterate is returned).
    reopen_velocity_factor
        For an empty region: the factor by which all speeds must be scaled for
        the region to reopen (< 1); 1 otherwise.
    reopen_velocity
        ``reopen_velocity_factor * impact_velocity`` (NaN for a LinkImpact robot).
    grid_margin
        Best margin found by the starting grid search (for comparison).
    impact_velocity
        Closing speed v_c in m/s the foam was optimised for.
    iterations
        IPOPT iterations.
    objective
        ``"margin"`` or ``"thinnest"``.
    warnings
        What a user should know (solver fallbacks, constraints active).
    stats
        IPOPT's statistics.
    """

    stiffness: float
    damping: float
    linear_depth: float
    margin: float
    margins: dict[str, float]
    impact_velocity: float
    reopen_velocity_factor: float
    reopen_velocity: float
    grid_margin: float
    iterations: int
    objective: str
    status: str = OptimalStatus.OK
    warnings: tuple[str, ...] = ()
    stats: dict = field(default_factory=dict, repr=False)

    @property
    def headroom(self) -> float:
        """Smallest fractional headroom below a limit, ``exp(margin) - 1``."""
        return math.expm1(self.margin)

    @property
    def binding(self) -> tuple[str, ...]:
        """Constraints whose margin equals the worst one (within 1e-4)."""
        return tuple(k for k, m in self.margins.items() if m - self.margin < 1e-4)

    def damping_ratio(self, head_mass: float = 4.4) -> float:
        """xi_c = C_c / (2 sqrt(M_h K_c)) of the optimum (thesis convention, 4.4 kg)."""
        return self.damping / (2.0 * math.sqrt(head_mass * self.stiffness))

    def to_frame(self) -> pd.DataFrame:
        """One row per constraint at the optimum."""
        return pd.DataFrame(
            {
                "constraint": list(self.margins),
                "margin_ln": list(self.margins.values()),
                "headroom_percent": [100 * math.expm1(m) for m in self.margins.values()],
            }
        )


@dataclass(frozen=True)
class _Start:
    """The starting grid search: metrics on (ln K_c, C_c), admissible points, best point."""

    uu: NDArray[np.float64]
    cc: NDArray[np.float64]
    metrics: dict[str, NDArray[np.float64]]
    allowed: NDArray[np.bool_]
    x0: list[float]
    margin: float

    def margins(self, keys: list[Criterion], lam: float, shift: float = 0.0) -> NDArray:
        """Worst margin at every grid point for depth ``lam``, speeds scaled by ``e^shift``."""
        out = np.full(self.uu.shape, np.inf)
        for key in keys:
            lim = lam if key.boundary == "lower" else key.limit
            with np.errstate(divide="ignore"):
                g = math.log(lim) - np.log(np.maximum(self.metrics[key.name], 1e-300))
            out = np.minimum(out, g - key.velocity_exponent * shift)
        return np.where(self.allowed, out, -np.inf)


def _grid_start(
    prob: FoamProblem,
    k_range: tuple[float, float],
    c_range: tuple[float, float],
    lam: float,
    xi_range: tuple[float, float] | None,
    head_mass: float,
    grid: int,
) -> _Start:
    """Step 1: worst-case metrics on a (ln K_c, C_c) grid; the best admissible point."""
    ug = np.linspace(math.log(k_range[0]), math.log(k_range[1]), grid)
    cg = np.linspace(c_range[0], c_range[1], grid)
    uu, cc = np.meshgrid(ug, cg, indexing="ij")
    metrics = {}
    for key in prob.keys():
        vals, _ = prob.worst(key, np.exp(uu.ravel()), cc.ravel())
        metrics[key.name] = vals.reshape(uu.shape)
    if xi_range is not None:
        xi_grid = cc / (2.0 * np.sqrt(head_mass * np.exp(uu)))
        allowed = (xi_grid >= xi_range[0]) & (xi_grid <= xi_range[1])
    else:
        allowed = np.ones(uu.shape, dtype=bool)
    if not np.any(allowed):
        raise InvalidParameterError(
            "damping_ratio_bounds",
            xi_range,
            "leaves no foam inside stiffness_bounds x damping_bounds",
        )
    start = _Start(uu, cc, metrics, allowed, [], 0.0)
    gm = start.margins(prob.keys(), lam)
    i0 = np.unravel_index(int(np.argmax(gm)), gm.shape)
    return _Start(uu, cc, metrics, allowed, [float(uu[i0]), float(cc[i0]), math.log(lam)],
                  float(gm[i0]))  # fmt: skip


def _solve_nlp(
    cb: _Margins,
    start: _Start,
    k_range: tuple[float, float],
    c_range: tuple[float, float],
    t_range: tuple[float, float],
    objective: str,
    min_margin: float,
    xi_range: tuple[float, float] | None,
    head_mass: float,
    ipopt_options: dict | None,
) -> tuple[NDArray, bool, dict, str]:
    """Step 2: the margin (or thinnest-foam) problem with CasADi/IPOPT."""
    n_keys = len(cb.keys)
    x = ca.MX.sym("x", 4)  # ln K, C, ln lambda, s
    g_all = cb(x[:3])
    lbx = [math.log(k_range[0]), c_range[0], math.log(t_range[0]), -50.0]
    ubx = [math.log(k_range[1]), c_range[1], math.log(t_range[1]), 50.0]
    if objective == "margin":
        f, g = -x[3], g_all - x[3]
        x_init = [*start.x0, start.margin]
    else:
        f, g = x[2], g_all - min_margin
        lbx[3] = ubx[3] = 0.0
        x_init = [*start.x0, 0.0]
    lbg = [0.0] * n_keys
    ubg = [ca.inf] * n_keys
    if xi_range is not None:
        # xi_lo <= C / (2 sqrt(M_h K)) <= xi_hi, written smoothly in (ln K, C)
        root = 2.0 * math.sqrt(head_mass) * ca.exp(x[0] / 2)
        g = ca.vertcat(g, x[1] - xi_range[0] * root, xi_range[1] * root - x[1])
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
    except RuntimeError as exc:  # pragma: no cover - IPOPT failures are reported, not raised
        return np.array(x_init), False, {"error": str(exc)}, str(exc)
    stats = dict(solver.stats())
    ok = bool(stats.get("success", False))
    return np.asarray(sol["x"]).ravel(), ok, stats, str(stats.get("return_status", "unknown"))


def _reopen_factor(start: _Start, keys: list[Criterion], lam: float, margin: float) -> float:
    """Step 3: the speed factor at which an empty region reopens (metrics ~ v_c ** e)."""
    if all(k.velocity_exponent == 1.0 for k in keys):
        return math.exp(margin)
    lo, hi = margin, 0.0  # shift = ln(factor): at lo every constraint reopens
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if np.max(start.margins(keys, lam, mid)) >= 0:
            lo = mid
        else:
            hi = mid
    return math.exp(lo)


@dataclass(frozen=True)
class _Settings:
    """The checked settings of :func:`optimal_foam`."""

    k_range: tuple[float, float]
    c_range: tuple[float, float]
    t_range: tuple[float, float]
    objective: str
    min_margin: float
    xi_range: tuple[float, float] | None
    head_mass: float
    grid: int
    optimise_depth: bool


def _check_robot(robot: object) -> None:
    if not contact_of(robot).gradients:
        raise InvalidParameterError(
            "robot",
            robot,
            "must be a ContactDynamics or a LinkImpact (exact gradients exist for the reduced "
            "joint only; for a FullJointContact use its foam_envelope, or robot.taylor())",
        )


def _settings(
    objective: str,
    stiffness_bounds: object,
    damping_bounds: object,
    thickness_bounds: object,
    max_compression: float,
    damping_ratio_bounds: object,
    head_mass_for_ratio: float,
    grid: int,
    min_margin: float,
) -> _Settings:
    """Validate the settings, each against its declaration."""
    objective = OBJECTIVE.check(objective)
    if objective == "thinnest" and thickness_bounds is None:
        raise InvalidParameterError(
            "thickness_bounds", None, "is needed with objective='thinnest'", "m"
        )
    if thickness_bounds is not None:
        t_range = check_pair(
            _FOAM["linear_depth"], thickness_bounds, "thickness_bounds", strict=False
        )
    else:
        lam = MAX_COMPRESSION.check(max_compression)
        t_range = (lam, lam)
    xi_range = None
    if damping_ratio_bounds is not None:
        xi_range = check_pair(DAMPING_RATIO, damping_ratio_bounds, "damping_ratio_bounds")
    return _Settings(
        k_range=check_pair(_FOAM["stiffness"], stiffness_bounds, "stiffness_bounds"),
        c_range=check_pair(DAMPING_GRID, damping_bounds, "damping_bounds"),
        t_range=t_range,
        objective=objective,
        min_margin=MIN_MARGIN.check(min_margin),
        xi_range=xi_range,
        head_mass=params_of(HeadNeck)["mass"].check(head_mass_for_ratio, "head_mass_for_ratio"),
        grid=GRID_POINTS.check(grid),
        optimise_depth=thickness_bounds is not None,
    )


def _fallback(
    cb: _Margins, start: _Start, xs: NDArray, gvals: NDArray, message: str
) -> tuple[NDArray, NDArray, list[str]]:
    """After a failed solve: the better of the grid start and the last iterate."""
    warnings = [f"IPOPT did not converge ({message})"]
    g0 = np.asarray(cb(ca.DM(start.x0))).ravel()
    if start.margin > float(gvals.min()):
        xs = np.array([*start.x0, 0.0])
        gvals = g0
        warnings.append("the grid start is returned: it has the better margin")
    log.warning("optimal_foam: %s", "; ".join(warnings))
    return xs, gvals, warnings


def _summarise(
    prob: FoamProblem,
    st: _Settings,
    start: _Start,
    cb: _Margins,
    xs: NDArray,
    ok: bool,
    stats: dict,
    message: str,
) -> OptimalFoam:
    """Step 3: the margins at the solution, the status, and for an empty region its reopening."""
    keys = prob.keys()
    thi = st.t_range[1]
    gvals = np.asarray(cb(ca.DM(xs[:3].tolist()))).ravel()
    log.info(
        "optimal_foam: grid start margin %+.4f; IPOPT %s after %s iterations",
        start.margin, message, stats.get("iter_count", "?"),
    )  # fmt: skip
    warnings: list[str] = []
    status = OptimalStatus.OK
    if not ok:
        status = OptimalStatus.SOLVER_FAILED
        xs, gvals, warnings = _fallback(cb, start, xs, gvals, message)
    margins = {key.name: float(gvals[i]) for i, key in enumerate(keys)}
    margin = float(min(margins.values()))
    factor = 1.0
    if st.objective == "margin" and margin < 0 and ok:
        status = OptimalStatus.EMPTY
        factor = _reopen_factor(start, keys, thi, margin)
        warnings.append(
            f"no foam meets every constraint at this velocity (best margin {margin:+.3f}); "
            f"the region reopens at {factor:.3f} x the speeds"
        )
    v0 = float("nan") if prob.robot.along_link else prob.impact_velocity
    return OptimalFoam(
        stiffness=math.exp(xs[0]),
        damping=float(xs[1]),
        linear_depth=math.exp(xs[2]),
        margin=margin,
        margins=margins,
        impact_velocity=v0,
        reopen_velocity_factor=factor,
        reopen_velocity=factor * v0,
        grid_margin=start.margin,
        iterations=int(stats.get("iter_count", 0)),
        objective=st.objective,
        status=status,
        warnings=tuple(warnings),
        stats=stats,
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

    Three steps: a grid search for a start, the nonlinear program (CasADi and
    IPOPT), and the margins at the solution with, for an empty region, the
    speed at which it reopens.

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
    min_margin
        Smallest worst-case margin, ``min_i ln(limit_i / metric_i)``, that the
        ``"thinnest"`` objective must keep (0.05 ~ 5 % headroom).
    head_mass_for_ratio
        Head mass of the damping-ratio convention, kg (thesis: 4.4 kg).
    grid
        Points per axis of the starting grid search.
    ipopt_options
        Extra IPOPT options.

    Returns
    -------
    OptimalFoam

    Examples
    --------
    >>> import designlab as dl
    >>> opt = dl.impact.optimal_foam(dl.impact.MANIPULATOR_1, 1.25)
    >>> opt.status, round(opt.stiffness / 1e3, 1), round(opt.damping_ratio(), 2)
    ('ok', 25.2, 0.2)
    """
    _check_robot(robot)
    st = _settings(
        objective, stiffness_bounds, damping_bounds, thickness_bounds, max_compression,
        damping_ratio_bounds, head_mass_for_ratio, grid, min_margin,
    )  # fmt: skip
    thi = st.t_range[1]
    prob = make_problem(
        robot, impact_velocity, criteria, thi, head_range, constrained, human_speed, 0.05
    )
    start = _grid_start(prob, st.k_range, st.c_range, thi, st.xi_range, st.head_mass, st.grid)
    cb = _Margins("margins", prob)
    xs, ok, stats, message = _solve_nlp(
        cb, start, st.k_range, st.c_range, st.t_range, st.objective, st.min_margin,
        st.xi_range, st.head_mass, ipopt_options,
    )  # fmt: skip
    if not st.optimise_depth:
        xs[2] = math.log(thi)
    return _summarise(prob, st, start, cb, xs, ok, stats, message)
