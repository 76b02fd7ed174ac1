"""Optimal gains of the new VFF: a seeded global search plus a batched local refinement.

Zeng 2011 (App. C.2) found K1 = 4.3, b = 0.68, K3 = 20.3, K5 = 240.7 by a grid
search refined three times and ``fmincon`` from the 20 best points: a week of
Matlab. :func:`optimise_gains` poses the same problem (Zeng 2011, Sec. 5.6 and
App. C; ``docs/navigation_gains.md``):

* decision vector (K1, b, K3, K5) with the Lyapunov gain structure
  K2 = b K1, K4 = b K3, K6 = b K5 built in (Zeng 2011, (5.5.7)), searched in
  log-space inside positive bounds (gains bounded away from zero);
* objective: the mean over the scenarios of the total criterion H (5.6.6);
* hard constraints: in every scenario (and every randomised walk) the robot
  arrives within the horizon and never enters a critical region (which also
  rules out collisions), and for the new VFF's PD attraction the loop sampled
  every T_s is stable (``dynamics.attraction_loop_radius`` < 1: otherwise the
  robot chatters near the goal and T*, L* no longer normalise H). A violating
  candidate is *infeasible*: it is ranked below every feasible one by its
  violation, its H is never reported as an objective value, and the optimum is
  always a feasible point.

The global stage is CMA-ES (Hansen's ``cma`` package) with box bounds; each
generation is simulated as one batch through
:func:`~designlab.navigation.simulate_batch` (or split over an executor). The
local stage is a batched compass search (Kolda, Lewis and Torczon 2003): the
2 x 4 poll points around the incumbent are simulated together; the step halves
when none improves.

Robust mode replaces every walking human by ``walks`` random walks (speed, start
time and lateral offset drawn with the seed) and scores each scenario by the
mean or the worst case over its walks; constraints must hold for every walk.

Examples
--------
>>> import designlab as dl
>>> nav = dl.navigation
>>> opt = nav.optimise_gains([nav.configuration(1)], stabilising="off", seed=1,
...                          max_evaluations=24, popsize=8, refine=False)
>>> opt.evaluations, opt.status in ("ok", "not_converged")
(24, True)
>>> round(opt.objective, 3) == round(float(opt.scenario_H.mean()), 3)
True
"""

from __future__ import annotations

import copy
import logging
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.navigation.criteria import EQUAL_WEIGHTS, check_weights
from designlab.navigation.crowds.tuning import crowd_sets
from designlab.navigation.dynamics import attraction_loop_radius
from designlab.navigation.methods import METHOD, STABILISING, TIE_SIDE, method_of
from designlab.navigation.parameters import (
    ARRIVAL_TOLERANCE,
    GAIN,
    GeCuiGains,
    MasoudGains,
    VFFGains,
)
from designlab.navigation.scenarios import Scenario
from designlab.navigation.simulate import simulate_batch
from designlab.navigation.tuning_results import (
    GAIN_NAMES,
    GainEvaluation,
    GainOptimum,
    OptimumStatus,
)
from designlab.navigation.walks import RandomWalks
from designlab.params import ARG, Param
from designlab.progress import Progress, ProgressHook, report

__all__ = [
    "DEFAULT_BOUNDS",
    "GAIN_NAMES",
    "GainEvaluation",
    "GainOptimum",
    "OptimumStatus",
    "RandomWalks",
    "evaluate_gains",
    "optimise_gains",
]

logger = logging.getLogger(__name__)

Array = NDArray[np.float64]

#: The thesis's search box (Zeng 2011, App. C.2: K1 <= 50, b <= 3, K3 <= 200, K5 <= 500),
#: with lower bounds kept away from zero as the Lyapunov structure requires.
DEFAULT_BOUNDS: dict[str, tuple[float, float]] = {
    "k1": (0.5, 50.0),
    "b": (0.05, 3.0),
    "k3": (0.5, 200.0),
    "k5": (0.5, 500.0),
}
_UNITS = {"k1": "N/m", "b": "s", "k3": "N/m", "k5": "N/m^2"}


# ------------------------------------------------------------------------ evaluation


@dataclass(frozen=True)
class _Evaluation:
    H_mean: Array  # (P,) objective (mean over scenarios of the per-scenario score)
    H: Array  # (S, P) per original scenario (mean or worst over its walks)
    feasible: NDArray[np.bool_]  # (P,)
    violation: Array  # (P,) >= 0, 0 iff feasible
    arrived: NDArray[np.bool_]  # (S, P) all walks arrived
    safe: NDArray[np.bool_]  # (S, P) no walk entered a critical region
    T: Array  # (S, P) arrival time, s (mean over the walks; inf if one did not arrive)
    margin: Array  # (S, P) smallest distance minus r3 over obstacles and walks, m


def _batch_task(task: Mapping[str, Any]) -> dict[str, Array]:
    """Executor task: simulate one chunk of gain sets (top level so that it pickles)."""
    r = simulate_batch(
        task["scenarios"],
        task["gains"],
        stabilising=task["stabilising"],
        arrival_tolerance=task["arrival_tolerance"],
        jit=task.get("jit", False),
        method=task.get("method", "vff"),
        tie_side=task.get("tie_side", "+y"),
        weights=task.get("weights", EQUAL_WEIGHTS),
    )
    n_obs = [len(n) for n in r.obstacle_names]
    return {
        "H": r.H,
        "arrival_time": r.arrival_time,
        "entered_critical": r.entered_critical,
        "min_distance": r.min_distance,
        "n_obs": np.array(n_obs),
    }


def _check_stabilising(stabilising: str) -> str:
    return str(STABILISING.check(stabilising))


class _Evaluator:
    """Simulates a population of gain sets over the (expanded) scenarios."""

    def __init__(
        self,
        scenarios: Sequence[Scenario],
        stabilising: str,
        robust: RandomWalks | None,
        robust_mode: str,
        arrival_tolerance: float,
        executor: Any,
        chunks: int,
        critical_margin: float = 0.0,
        jit: bool = False,
        method: str = METHOD.default,
        weights: tuple[float, float, float] = EQUAL_WEIGHTS,
        tie_side: str = "+y",
    ) -> None:
        self.method, self.weights, self.tie_side = method, weights, tie_side
        self.margin = critical_margin
        self.jit = jit
        self.names = [s.name for s in scenarios]
        self.groups: list[list[Scenario]] = [robust.expand(s) if robust else [s] for s in scenarios]
        self.flat = [s for g in self.groups for s in g]
        self.owner = np.concatenate([[i] * len(g) for i, g in enumerate(self.groups)]).astype(int)
        self.r3 = [np.array([o.r3 for o in s.obstacles]) for s in self.flat]
        pd_attraction = method_of(method).gains_type is VFFGains
        self.loops = [(s.robot.mass, s.sample_time) for s in scenarios] if pd_attraction else []
        self.stabilising = stabilising
        self.mode = robust_mode
        self.tol = arrival_tolerance
        self.executor = executor
        self.chunks = chunks
        self.evaluations = 0
        self.simulations = 0

    def _simulate(self, gains: Array) -> dict[str, Array]:
        base = {
            "scenarios": self.flat,
            "stabilising": self.stabilising,
            "arrival_tolerance": self.tol,
            "jit": self.jit,
            "method": self.method,
            "weights": self.weights,
            "tie_side": self.tie_side,
        }
        if self.executor is None or self.chunks <= 1 or gains.shape[0] < 2:
            return _batch_task({**base, "gains": gains})
        parts = np.array_split(np.arange(gains.shape[0]), min(self.chunks, gains.shape[0]))
        tasks = [{**base, "gains": gains[p]} for p in parts]
        results: list[dict[str, Array] | None] = [None] * len(tasks)
        for i, res in self.executor.map_unordered(_batch_task, tasks):
            results[i] = res
        done = [r for r in results if r is not None]
        return {
            k: np.concatenate([r[k] for r in done], axis=1) if k != "n_obs" else done[0][k]
            for k in done[0]
        }

    def loop_excess(self, gains: Array) -> Array:
        """How far each gain set's sampled attraction loop is from stable (0: stable).

        A radius >= 1 (:func:`~designlab.navigation.dynamics.attraction_loop_radius`) makes
        the robot chatter at its acceleration limit near the goal, in the nominal run too, so
        T* and L* stop normalising H_T and H_E (H can exceed 1): such gains are infeasible.
        """
        out = np.zeros(gains.shape[0])
        for mass, ts in set(self.loops):
            rho = np.array([attraction_loop_radius(g[0], g[1], mass, ts) for g in gains])
            out = np.maximum(out, np.where(rho >= 1.0, rho, 0.0))
        return out

    def __call__(self, gains: Array) -> _Evaluation:
        gains = np.atleast_2d(gains)
        raw = self._simulate(gains)
        P = gains.shape[0]
        self.evaluations += P
        self.simulations += P * len(self.flat)
        # a run whose H is undefined (its nominal run never arrived) counts as not arrived
        arrived_run = np.isfinite(raw["arrival_time"]) & ~np.isnan(raw["H"])  # (R, P)
        safe_run = ~raw["entered_critical"]
        depth = np.zeros(raw["H"].shape)
        margin_run = np.full(raw["H"].shape, math.inf)
        cm = self.margin
        for r, r3 in enumerate(self.r3):
            if r3.size:
                d = raw["min_distance"][r, :, : r3.size]
                depth[r] = (np.maximum(r3[None, :] + cm - d, 0.0) / r3[None, :]).sum(axis=1)
                margin_run[r] = (d - r3[None, :]).min(axis=1)
        if cm > 0:
            safe_run = safe_run & (margin_run >= cm)
        S = len(self.groups)
        H = np.zeros((S, P))
        arrived = np.zeros((S, P), bool)
        safe = np.zeros((S, P), bool)
        T = np.zeros((S, P))
        margin = np.zeros((S, P))
        for s in range(S):
            m = self.owner == s
            T[s] = raw["arrival_time"][m].mean(axis=0)
            margin[s] = margin_run[m].min(axis=0)
            H[s] = raw["H"][m].min(axis=0) if self.mode == "worst" else raw["H"][m].mean(axis=0)
            arrived[s] = arrived_run[m].all(axis=0)
            safe[s] = safe_run[m].all(axis=0)
        chatter = self.loop_excess(gains)
        violation = (
            (~arrived_run).sum(axis=0) + (~safe_run).sum(axis=0) + depth.sum(axis=0) + chatter
        )
        feasible = arrived.all(axis=0) & safe.all(axis=0) & (chatter == 0)
        return _Evaluation(
            H.mean(axis=0), H, feasible, violation.astype(float), arrived, safe, T, margin
        )


def evaluate_gains(
    scenarios: Sequence[Scenario],
    gains: Any,
    *,
    stabilising: str = "lyapunov",
    robust: RandomWalks | None = None,
    robust_mode: str = "mean",
    arrival_tolerance: float = ARRIVAL_TOLERANCE.default,
    critical_margin: float = 0.0,
    method: str = METHOD.default,
    weights: tuple[float, float, float] = EQUAL_WEIGHTS,
) -> GainEvaluation:
    """Score gain sets as :func:`optimise_gains` does: H per scenario, H_mean and feasibility.

    Parameters
    ----------
    scenarios
        The scenarios.
    gains
        A :class:`VFFGains`, a sequence of them, or an ``(N, 4)`` array of (k1, b, k3, k5).
    stabilising, robust, robust_mode, arrival_tolerance, critical_margin, method, weights
        As in :func:`optimise_gains`.

    Returns
    -------
    GainEvaluation
        ``to_frame()``: one row per gain set: ``k1``, ``b``, ``k3``, ``k5``,
        ``H_<scenario>``, ``H_mean``, ``feasible``, ``arrived_all``, ``critical_free``
        (every run stayed ``critical_margin`` or more outside every critical region), then
        per scenario ``T_arrive_s_<scenario>`` (s; the mean over the walks in robust mode,
        inf if a run did not arrive) and ``critical_margin_m_<scenario>`` (the smallest
        centre/contour distance minus the obstacle's r3 over obstacles and walks, m;
        negative: the robot entered a critical region; inf without obstacles).

    Examples
    --------
    >>> from designlab.navigation import configuration, VFFGains
    >>> e = evaluate_gains([configuration(1)], VFFGains(4.3, 0.68, 20.3, 240.7), stabilising="off")
    >>> str(e.status), round(float(e.frame["H_mean"][0]), 3), bool(e.frame["feasible"][0])
    ('ok', 0.695, True)
    """
    g = _gain_matrix(gains)
    sc = _check_scenarios(scenarios)
    ev = _Evaluator(
        sc,
        _check_stabilising(stabilising),
        _check_robust(robust),
        _check_mode(robust_mode),
        arrival_tolerance,
        None,
        1,
        _check_margin(critical_margin),
        method=_check_method(method),
        weights=check_weights(weights),
    )
    e = ev(g)
    frame = pd.DataFrame(g, columns=list(GAIN_NAMES))
    for s, sce in enumerate(sc):
        frame[f"H_{sce.name}"] = e.H[s]
    frame["H_mean"] = e.H_mean
    frame["feasible"] = e.feasible
    frame["arrived_all"] = e.arrived.all(axis=0)
    frame["critical_free"] = e.safe.all(axis=0)
    for q, arr in (("T_arrive_s", e.T), ("critical_margin_m", e.margin)):
        for s, sce in enumerate(sc):
            frame[f"{q}_{sce.name}"] = arr[s]
    bad = np.flatnonzero(~e.feasible).tolist()
    warnings = (
        (f"gain sets {bad} do not arrive, enter a critical region or have an unstable sampled "
         "attraction loop (dynamics.attraction_loop_radius >= 1)",) if bad else ()
    )  # fmt: skip
    status = OptimumStatus.OK if e.feasible.any() else OptimumStatus.INFEASIBLE
    return GainEvaluation(frame, status, warnings)


def _gain_matrix(gains: Any) -> Array:
    if isinstance(gains, VFFGains):
        return gains.as_array()[None, :]
    if isinstance(gains, Sequence) and gains and all(isinstance(g, VFFGains) for g in gains):
        return np.array([g.as_array() for g in gains])
    g = np.atleast_2d(np.asarray(gains, dtype=float))
    if g.ndim != 2 or g.shape[1] != 4:
        raise InvalidParameterError(
            "gains", gains, "must be VFFGains or an (N, 4) array of (k1, b, k3, k5)"
        )
    return g


def _check_scenarios(scenarios: Sequence[Scenario]) -> list[Scenario]:
    sc = list(scenarios) if isinstance(scenarios, Sequence) else []
    if not sc or not all(isinstance(s, Scenario) for s in sc):
        raise InvalidParameterError(
            "scenarios", scenarios, "must be a non-empty sequence of Scenario"
        )
    names = [s.name for s in sc]
    if len(set(names)) != len(names):
        raise InvalidParameterError("scenarios", names, "scenario names must be unique")
    return sc


def _check_margin(margin: float) -> float:
    return float(CRITICAL_MARGIN.check(margin))


def _check_robust(robust: RandomWalks | None) -> RandomWalks | None:
    if robust is not None and not isinstance(robust, RandomWalks):
        raise InvalidParameterError("robust", robust, "must be None or a RandomWalks")
    return robust


def _check_mode(mode: str) -> str:
    if mode not in ("mean", "worst"):
        raise InvalidParameterError("robust_mode", mode, "must be 'mean' or 'worst'")
    return mode


def _check_bounds(bounds: Mapping[str, tuple[float, float]] | None) -> tuple[Array, Array]:
    b = dict(DEFAULT_BOUNDS)
    if bounds is not None:
        if not isinstance(bounds, Mapping):
            raise InvalidParameterError(
                "bounds", bounds, f"must be a mapping of {GAIN_NAMES} to (low, high)"
            )
        unknown = set(bounds) - set(GAIN_NAMES)
        if unknown:
            raise InvalidParameterError(
                "bounds", sorted(unknown), f"keys must be among {GAIN_NAMES}"
            )
        b.update(bounds)
    lo, hi = np.zeros(4), np.zeros(4)
    for j, name in enumerate(GAIN_NAMES):
        try:
            low, high = (float(v) for v in b[name])
        except (TypeError, ValueError):
            raise InvalidParameterError(
                f"bounds[{name!r}]", b[name], "must be a pair (low, high)", _UNITS[name]
            ) from None
        if not (GAIN.within(low) and GAIN.within(high) and low < high):
            raise InvalidParameterError(
                f"bounds[{name!r}]",
                b[name],
                f"must be finite with low < high, both {GAIN.allowed()} (gains bounded away "
                "from zero, Zeng 2011 (5.5.7))",
                _UNITS[name],
            )
        lo[j], hi[j] = low, high
    return lo, hi


# ------------------------------------------------------------- optimiser settings

#: Candidates per CMA-ES generation (each generation is one batch).
POPSIZE = Param(None, "", "candidates per CMA-ES generation", kind="integer", ge=4, le=256,
                name="popsize")  # fmt: skip
#: Budget of gain sets of the global stage.
MAX_EVALUATIONS = Param(None, "", "budget of gain sets of the CMA-ES stage", kind="integer",
                        ge=4, le=100_000, name="max_evaluations")  # fmt: skip
#: Budget of gain sets of the compass refinement.
REFINE_EVALUATIONS = Param(None, "", "budget of gain sets of the compass refinement",
                           kind="integer", ge=0, le=100_000, name="refine_evaluations")  # fmt: skip
#: Seed of the search (the same seed gives the same result).
SEED = ARG.seed.but(doc="seed")
#: Initial CMA-ES step in normalised log units (the box is [0, 1]^4).
SIGMA0 = Param(None, "", "initial CMA-ES step (normalised log units)", gt=0, le=0.5,
               name="sigma0")  # fmt: skip
#: Clearance every run must keep outside every critical region.
CRITICAL_MARGIN = Param(None, "m", "clearance every run must keep outside every critical region",
                        ge=0, le=2.0, name="critical_margin")  # fmt: skip


@dataclass(frozen=True)
class _Search:
    """The checked settings of one optimisation."""

    scenarios: list[Scenario]
    lo: Array
    hi: Array
    u0: Array
    seed: int
    sigma0: float
    popsize: int
    max_evaluations: int
    refine_evaluations: int

    def to_gains(self, u: Array) -> Array:
        llo, lhi = np.log(self.lo), np.log(self.hi)
        return np.exp(llo + np.clip(u, 0.0, 1.0) * (lhi - llo))


def _start(x0: VFFGains | None, lo: Array, hi: Array) -> Array:
    if x0 is None:
        return np.full(4, 0.5)
    if not isinstance(x0, VFFGains):
        raise InvalidParameterError("x0", x0, "must be a VFFGains")
    u0 = (np.log(x0.as_array()) - np.log(lo)) / (np.log(hi) - np.log(lo))
    if np.any(u0 < 0) or np.any(u0 > 1):
        raise InvalidParameterError("x0", x0, "must lie inside the bounds")
    return u0


class _Incumbent:
    """The best feasible point so far, the history rows and the progress reports."""

    def __init__(
        self,
        search: _Search,
        ev: _Evaluator,
        callback: Callable[[dict[str, Any]], None] | None,
        progress: ProgressHook | None,
        total: int,
    ) -> None:
        self.search, self.ev, self.callback, self.progress = search, ev, callback, progress
        self.total = total
        self.u: Array | None = None
        self.H = -math.inf
        self.H_s: Array | None = None
        self.history: list[dict[str, Any]] = []
        self.feasible: list[tuple[Array, Array]] = []  # (gains, H_mean) of feasible candidates

    def keep_feasible(self, U: Array, e: _Evaluation) -> None:
        """Keep every feasible candidate's gains and H_mean (for the near-optimal ranges)."""
        if e.feasible.any():
            self.feasible.append((self.search.to_gains(U[e.feasible]), e.H_mean[e.feasible]))

    def consider(self, U: Array, e: _Evaluation) -> bool:
        """Take the best feasible candidate of ``U`` if it beats the incumbent."""
        self.keep_feasible(U, e)
        feas_H = np.where(e.feasible, e.H_mean, -np.inf)
        j = int(np.argmax(feas_H))
        if feas_H[j] > self.H:
            self.u, self.H, self.H_s = U[j].copy(), float(feas_H[j]), e.H[:, j].copy()
            return True
        return False

    def record(self, phase: str, it: int, e: _Evaluation, step: float) -> None:
        """One history row (a CMA-ES generation or a compass poll)."""
        feas_H = np.where(e.feasible, e.H_mean, -np.inf)
        j = int(np.argmax(feas_H))
        best = self.H if math.isfinite(self.H) else math.nan
        row = {
            "phase": phase,
            "iteration": it,
            "evaluations": self.ev.evaluations,
            "best_H_mean": best,
            "iteration_best_H_mean": float(feas_H[j]) if math.isfinite(feas_H[j]) else math.nan,
            "feasible_share": float(e.feasible.mean()),
            "step": float(step),
        }
        if self.u is not None:
            row.update(dict(zip(GAIN_NAMES, self.search.to_gains(self.u).tolist(), strict=True)))
        self.history.append(row)
        if self.callback is not None:
            self.callback(dict(row))
        label = "generation" if phase == "cma" else "refinement poll"
        info = Progress(min(self.ev.evaluations, self.total), self.total, None if math.isnan(best)
                        else best, label, f"{phase} {it}")  # fmt: skip
        report(self.progress, info)


def _cma_stage(search: _Search, ev: _Evaluator, inc: _Incumbent) -> tuple[bool, dict, float]:
    """CMA-ES, infeasible candidates ranked below every feasible one: (converged, stop, sigma)."""
    import cma

    opts = {
        "bounds": [0.0, 1.0],
        "popsize": search.popsize,
        "seed": search.seed + 1,
        "verbose": -9,
        "maxfevals": search.max_evaluations,
        "tolfun": 1e-4,
        "tolx": 1e-3,
        "tolflatfitness": 10,
    }
    es = cma.CMAEvolutionStrategy(search.u0.tolist(), search.sigma0, opts)
    it = 0
    budget_hit = False
    while not es.stop():
        if ev.evaluations + search.popsize > search.max_evaluations:
            budget_hit = True
            break
        U = np.array(es.ask())
        e = ev(search.to_gains(U))
        inc.consider(U, e)
        # feasible: -H (<= 0); infeasible: 1 + violation (> 0), never a "good-looking" number
        fitness = np.where(e.feasible, -e.H_mean, 1.0 + e.violation)
        es.tell(list(U), fitness.tolist())
        it += 1
        inc.record("cma", it, e, float(es.sigma))
    stop = dict(es.stop())
    if budget_hit:
        stop["max_evaluations"] = search.max_evaluations
    converged = not budget_hit and not any(k in stop for k in ("maxfevals", "maxiter"))
    logger.info("CMA-ES stopped after %d generations (%s)", it, stop)
    return converged, stop, float(es.sigma)


def _compass_stage(search: _Search, ev: _Evaluator, inc: _Incumbent, sigma: float) -> bool:
    """Batched compass search in normalised log-gain space; True if its step fell below 1e-3."""
    step = min(0.05, max(4 * sigma, 0.01))
    used = 0
    k = 0
    while used + 8 <= search.refine_evaluations:
        dirs = np.vstack([np.eye(4), -np.eye(4)]) * step
        U = np.clip(inc.u[None, :] + dirs, 0.0, 1.0)  # type: ignore[index]
        e = ev(search.to_gains(U))
        used += U.shape[0]
        k += 1
        improved = inc.consider(U, e)
        inc.record("refine", k, e, step)
        if not improved:
            step /= 2
            if step < 1e-3:
                return True
    return False


@crowd_sets(DEFAULT_BOUNDS)  # a CrowdSet: crowds.tuning.optimise_crowd_gains (issue 23)
def optimise_gains(
    scenarios: Sequence[Scenario],
    *,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    stabilising: str = "lyapunov",
    seed: int = SEED.default,
    x0: VFFGains | None = None,
    sigma0: float = 0.25,
    popsize: int = 16,
    max_evaluations: int = 1600,
    refine: bool = True,
    refine_evaluations: int = 400,
    robust: RandomWalks | None = None,
    robust_mode: str = "mean",
    arrival_tolerance: float = ARRIVAL_TOLERANCE.default,
    critical_margin: float = 0.0,
    executor: Any = None,
    chunks: int = 1,
    jit: bool = False,
    callback: Callable[[dict[str, Any]], None] | None = None,
    progress: ProgressHook | None = None,
    method: str = METHOD.default,
    weights: tuple[float, float, float] = EQUAL_WEIGHTS,
    tie_side: str = "+y",
) -> GainOptimum:
    """Maximise the mean total criterion H over scenarios with respect to (K1, b, K3, K5).

    Parameters
    ----------
    scenarios
        The scenarios optimised together (the thesis: Configurations 1, 2 and 3).
    bounds
        ``{"k1": (low, high), ...}`` in N/m, s, N/m, N/m^2; missing gains use
        :data:`DEFAULT_BOUNDS` (the thesis's ranges with positive lower bounds).
    stabilising
        ``"lyapunov"`` (the stabilising force on) or ``"off"`` (as the thesis's tables).
    seed
        Seed of CMA-ES (nothing else is random; the same seed gives the same result).
    x0, sigma0
        Start of the search (default: the box centre in log-space); the initial CMA-ES
        step in normalised log units (the box is [0, 1]^4), in (0, 0.5].
    popsize, max_evaluations
        Candidates per CMA-ES generation (one batch, 4-256); the global stage's budget of
        gain sets (>= popsize, <= 100 000).
    refine, refine_evaluations
        Run the batched compass search from the best global point; its budget.
    robust, robust_mode
        :class:`RandomWalks` (randomised human walks) or ``None``; ``"mean"`` or ``"worst"``.
    arrival_tolerance
        Arrival radius (m).
    critical_margin
        Clearance (m, 0-2) kept outside every critical region: feasible only if, in every
        run, each obstacle's smallest centre/contour distance is at least r3 + this.
    executor, chunks
        Optional executor with ``map_unordered(fn, tasks)`` (``make_executor`` of
        ``designlab.analysis.executors``); parallel batches each population is split into.
    jit
        Compiled step, four gain sets per pass (:func:`simulate_batch`): the same optimum.
    callback
        Called with each history row (a dict) as the search goes.
    progress
        A :data:`designlab.progress.ProgressHook`: gain sets evaluated, best feasible H_mean.
    method
        ``"vff"`` (K1, b, K3, K5), ``"masoud"`` (K1, K3, K5; b unused; sense ``tie_side``)
        or ``"ge_cui"`` ((2.2.11)-(2.2.13)): Table C.1's baselines optimised like for like
        (``gains`` is then a :class:`MasoudGains` or :class:`GeCuiGains`).
    weights
        (w_T, w_D, w_E) of H (5.6.6); the thesis: 1/3 each.
    tie_side
        ``"+y"`` or ``"-y"`` (for Masoud: counter-clockwise or clockwise).

    Returns
    -------
    GainOptimum
        ``status`` (:class:`OptimumStatus`): ``"ok"`` (both stages converged),
        ``"not_converged"`` (a budget ran out), ``"infeasible"`` (``gains`` is ``None``).

    Raises
    ------
    InvalidParameterError
        For bad scenarios, bounds, modes or budgets.
    """
    t_start = time.perf_counter()
    search = _check_search(scenarios, bounds, x0, seed, sigma0, popsize, max_evaluations,
                           refine_evaluations)  # fmt: skip
    _check_options(executor, jit)
    stab, mode = _check_stabilising(stabilising), _check_mode(robust_mode)
    rob, cm = _check_robust(robust), _check_margin(critical_margin)
    meth, w, _ = _check_method(method), check_weights(weights), TIE_SIDE.check(tie_side)
    ev = _Evaluator(search.scenarios, stab, rob, mode, arrival_tolerance, executor, int(chunks),
                    cm, bool(jit), method=meth, weights=w, tie_side=tie_side)  # fmt: skip
    total = search.max_evaluations + (search.refine_evaluations if refine else 0)
    inc = _Incumbent(search, ev, callback, progress, total)
    global_converged, stop, sigma = _cma_stage(search, ev, inc)
    refined = refine and inc.u is not None and search.refine_evaluations > 0
    local_converged = _compass_stage(search, ev, inc, sigma) if refined else True
    settings = dict(stabilising=stab, robust_mode=mode, walks=rob.n if rob is not None else 0,
                    seed=search.seed, critical_margin=cm, method=meth, weights=w)  # fmt: skip
    return _optimum(search, ev, inc, (global_converged, local_converged, refine), stop,
                    time.perf_counter() - t_start, settings)  # fmt: skip


def _check_search(
    scenarios: Any,
    bounds: Any,
    x0: Any,
    seed: Any,
    sigma0: Any,
    popsize: Any,
    max_evaluations: Any,
    refine_evaluations: Any,
) -> _Search:
    """The search settings, each checked against its declaration."""
    lo, hi = _check_bounds(bounds)
    popsize = POPSIZE.check(popsize)
    return _Search(
        _check_scenarios(scenarios), lo, hi, _start(x0, lo, hi), SEED.check(seed),
        SIGMA0.check(sigma0), popsize, _check_budget(max_evaluations, popsize),
        REFINE_EVALUATIONS.check(refine_evaluations),
    )  # fmt: skip


def _check_options(executor: Any, jit: Any) -> None:
    if executor is not None and not hasattr(executor, "map_unordered"):
        raise InvalidParameterError("executor", executor, "must have map_unordered(fn, tasks)")
    if not isinstance(jit, bool | np.bool_):
        raise InvalidParameterError("jit", jit, "must be True or False")


def _check_budget(max_evaluations: Any, popsize: int) -> int:
    n = MAX_EVALUATIONS.check(max_evaluations)
    if n < popsize:
        raise InvalidParameterError(
            "max_evaluations", max_evaluations, f"must be an integer >= popsize = {popsize}"
        )
    return n


def _check_method(method: Any) -> str:
    """A batched method whose gains can be optimised (a filtered one solves a QP per period)."""
    return method_of(method, batched=True).name


def _gains_of(method: str, row: Array, tie_side: str) -> VFFGains | MasoudGains | GeCuiGains:
    """The gains object of a decision vector (k1, b, k3, k5)."""
    return method_of(method).gains_of_row(row, tie_side)


def _other_mode_warnings(ev: _Evaluator, gains: VFFGains) -> list[str]:
    """Whether the optimum is also safe with the stabilising force switched the other way.

    The force can drive a robot into a critical region that the field alone keeps it out
    of (``docs/navigation.md``, "The stabilising force is not a safety guarantee"), so an
    optimum found with one mode is re-simulated with the other and flagged if it fails.
    """
    other = copy.copy(ev)
    other.stabilising = "off" if ev.stabilising == "lyapunov" else "lyapunov"
    e = other(gains.as_array()[None, :])
    if bool(e.feasible[0]):
        return []
    bad = [n for n, ok in zip(ev.names, e.safe[:, 0] & e.arrived[:, 0], strict=True) if not ok]
    return [
        f"with stabilising={other.stabilising!r} the optimum enters a critical region or does "
        f"not arrive in {bad}: do not switch the stabilising force for these gains"
    ]


def _feasible_frame(parts: list[tuple[Array, Array]]) -> pd.DataFrame:
    """Every feasible candidate evaluated: the gains and H_mean, best first."""
    cols = [*GAIN_NAMES, "H_mean"]
    if not parts:
        return pd.DataFrame(columns=cols, dtype=float)
    g = np.vstack([p[0] for p in parts])
    h = np.concatenate([p[1] for p in parts])
    frame = pd.DataFrame(np.column_stack([g, h]), columns=cols)
    return frame.sort_values("H_mean", ascending=False, kind="stable", ignore_index=True)


def _optimum(
    search: _Search,
    ev: _Evaluator,
    inc: _Incumbent,
    converged: tuple[bool, bool, bool],
    stop: dict[str, Any],
    wall_time: float,
    settings: dict[str, Any],
) -> GainOptimum:
    """The :class:`GainOptimum`: status, warnings and the incumbent."""
    global_converged, local_converged, refine = converged
    warnings: list[str] = []
    cm = settings["critical_margin"]
    if inc.u is None:
        status = OptimumStatus.INFEASIBLE
        warnings.append(
            f"no candidate among {ev.evaluations} arrived and stayed out of every critical region "
            + (f"(by {cm} m or more) " if cm > 0 else "")
            + "in all scenarios"
        )
        gains = None
        H_s = np.full(len(search.scenarios), math.nan)
    else:
        gains = _gains_of(ev.method, search.to_gains(inc.u), ev.tie_side)
        H_s = inc.H_s
        ok = global_converged and local_converged
        status = OptimumStatus.OK if ok else OptimumStatus.NOT_CONVERGED
        if not global_converged:
            warnings.append(f"CMA-ES stopped on its budget ({stop}), not on convergence")
        if refine and not local_converged:
            warnings.append(
                "the compass refinement stopped on its budget before its step fell below 1e-3"
            )
        strategy = method_of(ev.method)
        if strategy.stabilised:  # the other stabilising mode is worth checking
            warnings.extend(_other_mode_warnings(ev, gains))
        used = [n for n in GAIN_NAMES if n in strategy.used_gains]
        at_bound = [
            n
            for j, n in enumerate(GAIN_NAMES)
            if n in used and (inc.u[j] < 1e-3 or inc.u[j] > 1 - 1e-3)
        ]
        if at_bound:
            warnings.append(
                f"the optimum lies on the bound of {at_bound}: widen the bounds to check"
            )
    return GainOptimum(
        gains=gains,
        objective=float(inc.H) if inc.u is not None else math.nan,
        scenario_names=tuple(s.name for s in search.scenarios),
        scenario_H=np.asarray(H_s, dtype=float),
        history=pd.DataFrame(inc.history),
        feasible=_feasible_frame(inc.feasible),
        evaluations=ev.evaluations,
        simulations=ev.simulations,
        wall_time=wall_time,
        bounds={n: (float(search.lo[j]), float(search.hi[j])) for j, n in enumerate(GAIN_NAMES)},
        status=status,
        warnings=tuple(warnings),
        **settings,
    )
