"""Gains for crowds: VFF's (K1, b, K3, K5) optimised over a set of crowds, robust over seeds.

A :class:`CrowdSet` names the crowds (layouts x densities x seeds, and the crowd options) and
the rates a gain set should keep over them (collision rate at most ``collision_rate``,
critical-entry rate at most ``critical_rate``). :func:`optimise_crowd_gains` (also
``navigation.optimise_gains(crowd_set, robust=...)``) searches log-gain space with CMA-ES.

The objective carries a signal (issue 35, item 7): every run has a time cost and an amount
of violation (:func:`run_penalties`), both continuous.

* Time cost (s): the arrival time; for a run that did not arrive, its time limit plus the
  distance it still had to go at the robot's free-run speed (shortest path / free-run time).
* Violation (dimensionless, 0 for a run that kept its distance): the share of the run spent
  inside critical regions, plus the clearance deficit ``max(0, d_c - s_min) / d_c``, where
  ``s_min`` is the smallest surface distance to a pedestrian and ``d_c`` the field's
  discomfort distance (0.2 m): 1 at touching, more with the depth of a collision.

A candidate's fitness is the ``"mean"`` or ``"cvar"`` of its runs' time costs
(:func:`~designlab.navigation.crowds.metrics.cvar`) plus ``penalty`` seconds per unit of mean
violation (default: the time limit, so a run spent wholly inside critical regions costs one
more time limit). Two candidates tie only if their runs do. The rates are kept as reported
constraints: the optimum is the fittest candidate keeping them (status ``ok``), else the
fittest of all (status ``infeasible``). :func:`at_bounds` names the gains of the optimum
that sit on the search box.

:func:`validate_gains` simulates gain sets on held-out crowds changing one factor at a time
(:func:`validation_steps`): new seeds; then also a new density; then also a new layout.
:class:`GainValidation` compares the optimum with a reference gain set on the same (paired)
crowds at each step: success rates with Wilson intervals and an exact McNemar test, and the
mean paired difference of the penalised cost with its t interval and a Wilcoxon test.
"""

from __future__ import annotations

import functools
import logging
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import pandas as pd

from designlab.errors import InvalidParameterError
from designlab.navigation.crowds.field_metrics import DISCOMFORT_DISTANCE
from designlab.navigation.crowds.metrics import CONFIDENCE, CVAR_ALPHA, cvar, wilson_interval
from designlab.navigation.crowds.study import (
    CrowdStudy,
    crowd_of,
    crowd_study,
)
from designlab.navigation.parameters import VFFGains
from designlab.params import ARG, Param
from designlab.progress import Progress, ProgressHook, report
from designlab.results import Result, Status

__all__ = [
    "PENALTY",
    "ROBUST",
    "VALIDATION_STEPS",
    "CrowdGainOptimum",
    "CrowdOptimumStatus",
    "CrowdSet",
    "GainValidation",
    "at_bounds",
    "check_disjoint",
    "crowd_sets",
    "optimise_crowd_gains",
    "paired_comparison",
    "run_penalties",
    "score_runs",
    "validate_gains",
    "validation_steps",
]

logger = logging.getLogger(__name__)

#: How the runs' costs of a candidate are combined.
ROBUST = Param(None, "", "robust cost over the runs", kind="choice", choices=("mean", "cvar"),
               default="mean", name="robust")  # fmt: skip
#: Bound on a rate (collision or critical entry) over the training runs.
RATE = Param(None, "", "largest rate allowed over the training runs", ge=0, le=1, name="rate")
#: CMA-ES generations at most.
GENERATIONS = Param(
    None, "", "CMA-ES generations", kind="integer", ge=1, le=1000, name="generations"
)
#: Candidates per CMA-ES generation.
POPULATION = Param(None, "", "candidates per CMA-ES generation", kind="integer", ge=4, le=64,
                   default=6, name="popsize")  # fmt: skip
#: Seconds added to a candidate's fitness per unit of mean violation (default: the time limit).
PENALTY = Param("lambda", "s", "seconds of fitness per unit of mean violation", gt=0, le=1e6,
                name="penalty")  # fmt: skip
#: Share of the log box within which a gain counts as sitting on a bound.
BOUND_TOLERANCE = 0.02
#: What each validation step changes, in order (each adds one change to the one before).
VALIDATION_STEPS = ("seeds", "density", "layout")
GAIN_KEYS = ("k1", "b", "k3", "k5")


class CrowdOptimumStatus(Status):
    """Status of a crowd gain optimisation.

    ``OK``: the best candidate keeps the rates; ``INFEASIBLE``: no candidate kept them
    (``gains`` is the least-violating one, for inspection only).
    """

    OK = "ok"
    INFEASIBLE = "infeasible"


@dataclass(frozen=True)
class CrowdSet:
    """Crowds to optimise or validate gains on, and the rates required over them.

    Attributes
    ----------
    scenarios
        Layout names.
    densities
        Persons per m^2.
    seeds
        Crowd seeds.
    crowd_options
        Other keywords of :func:`~designlab.navigation.crowd` (``length``, ``horizon``, ...).
    collision_rate, critical_rate
        Largest collision and critical-entry rates allowed over the runs.

    Examples
    --------
    >>> CrowdSet(("crossing",), (0.2,), (0, 1, 2)).runs
    3
    """

    scenarios: tuple[str, ...]
    densities: tuple[float, ...]
    seeds: tuple[int, ...]
    crowd_options: Mapping[str, Any] = field(default_factory=dict)
    collision_rate: float = 0.0
    critical_rate: float = 0.2

    def __post_init__(self) -> None:
        for name in ("scenarios", "densities", "seeds"):
            vals = getattr(self, name)
            if isinstance(vals, str) or not isinstance(vals, Sequence | range):
                raise InvalidParameterError(name, vals, "must be a list")
            object.__setattr__(self, name, tuple(vals))
        RATE.check(self.collision_rate, "collision_rate")
        RATE.check(self.critical_rate, "critical_rate")

    @property
    def runs(self) -> int:
        """Runs per gain set."""
        return len(self.scenarios) * len(self.densities) * len(self.seeds)

    def study(self, methods: Sequence[str], gains: Mapping[str, Any], **kw: Any) -> CrowdStudy:
        """:func:`~designlab.navigation.crowds.study.crowd_study` of gain sets on this set.

        Parameters
        ----------
        methods
            Method labels.
        gains
            Label -> gains.
        **kw
            Other keywords of ``crowd_study`` (``stabilising``, ``executor``, ...).
        """
        return crowd_study(self.scenarios, self.densities, self.seeds, methods, gains=gains,
                           crowd_options=self.crowd_options, **kw)  # fmt: skip


def check_disjoint(training: CrowdSet, validation: CrowdSet,
                   what: Sequence[str] = ("seeds", "densities")) -> None:  # fmt: skip
    """Refuse a validation set sharing a seed (or a density, ...) with the training set.

    Parameters
    ----------
    training, validation
        The two sets.
    what
        The fields that must share nothing (``"seeds"``, ``"densities"``, ``"scenarios"``).

    Examples
    --------
    >>> train = CrowdSet(("crossing",), (0.2,), (0, 1))
    >>> check_disjoint(train, CrowdSet(("crossing",), (0.4,), (5,)))
    >>> check_disjoint(train, CrowdSet(("crossing",), (0.2,), (5,)), what=("seeds",))
    """
    for name in what:
        shared = sorted(set(getattr(training, name)) & set(getattr(validation, name)))
        if shared:
            raise InvalidParameterError(
                f"validation.{name}", shared, "must share nothing with the training set"
            )


def validation_steps(training: CrowdSet, seeds: Sequence[int], density: float,
                     scenario: str) -> list[tuple[str, CrowdSet]]:  # fmt: skip
    """Held-out crowd sets changing one factor at a time (:data:`VALIDATION_STEPS`).

    ``seeds``: the training layouts and densities with new seeds; ``density``: the same with
    ``density`` instead of the training densities; ``layout``: the same with ``scenario``
    instead of the training layouts. Each step adds one change to the one before, so a
    difference between two consecutive steps is that factor's.

    Parameters
    ----------
    training
        The training set (its crowd options and rates are kept).
    seeds
        Validation seeds (none of the training's).
    density
        The new density (persons/m^2, not one of the training's).
    scenario
        The new layout (not one of the training's).

    Returns
    -------
    list of (str, CrowdSet)

    Examples
    --------
    >>> train = CrowdSet(("corridor_counterflow",), (0.3,), range(4))
    >>> [(n, s.scenarios, s.densities) for n, s in validation_steps(train, [9], 0.5, "crossing")]
    ... # doctest: +NORMALIZE_WHITESPACE
    [('seeds', ('corridor_counterflow',), (0.3,)), ('density', ('corridor_counterflow',), (0.5,)),
     ('layout', ('crossing',), (0.5,))]
    """
    first = replace(training, seeds=tuple(seeds))
    check_disjoint(training, first, what=("seeds",))
    second = replace(first, densities=(float(density),))
    third = replace(second, scenarios=(str(scenario),))
    check_disjoint(training, second, what=("densities",))
    check_disjoint(training, third, what=("scenarios",))
    return list(zip(VALIDATION_STEPS, (first, second, third), strict=True))


@dataclass(frozen=True)
class CrowdGainOptimum(Result):
    """The gains found for a set of crowds.

    Attributes
    ----------
    gains
        The best :class:`VFFGains` (``None`` if nothing was evaluated).
    cost
        Its robust time cost (s).
    collision_rate, critical_rate
        Its rates over the training runs.
    robust, alpha
        ``"mean"`` or ``"cvar"`` and the CVaR level.
    evaluations, seconds
        Gain sets simulated (each on every training crowd) and the wall time.
    history
        One row per candidate: ``generation``, the gains, ``cost_s``, ``violation``,
        ``fitness``, the rates, ``feasible`` (:func:`score_runs`).
    collision_bound, critical_bound
        The rates required (the training set's).
    status, warnings
        :class:`CrowdOptimumStatus` and what a user should know.
    violation, fitness, success_rate
        The optimum's mean violation, fitness (s) and training success rate.
    penalty
        Seconds of fitness per unit of mean violation.
    at_bounds
        Gains of the optimum on the search box (:func:`at_bounds`), e.g. ``("b: lower",)``.
    runs
        Training crowds per candidate.
    """

    gains: VFFGains | None
    cost: float
    collision_rate: float
    critical_rate: float
    robust: str
    alpha: float
    evaluations: int
    seconds: float
    history: pd.DataFrame = field(repr=False)
    collision_bound: float = 0.0
    critical_bound: float = 0.2
    status: str = CrowdOptimumStatus.OK
    warnings: tuple[str, ...] = ()
    violation: float = math.nan
    fitness: float = math.nan
    success_rate: float = math.nan
    penalty: float = math.nan
    at_bounds: tuple[str, ...] = ()
    runs: int = 0

    def to_frame(self) -> pd.DataFrame:
        """The history of the search (one row per candidate)."""
        return self.history.copy()


#: The clearance below which a run is penalised (m).
PENALTY_DISTANCE = Param("d_c", "m", "surface clearance below which a run is penalised", gt=0,
                         le=10, default=DISCOMFORT_DISTANCE, name="distance")  # fmt: skip


#: Columns of a runs frame that :func:`run_penalties` reads.
PENALTY_COLUMNS = (
    "success", "arrival_time_s", "time_limit_s", "goal_distance_m", "free_run_s", "shortest_m",
    "critical_time_s", "outcome_time_s", "min_surface_distance_m",
)  # fmt: skip


def run_penalties(runs: pd.DataFrame, distance: float = DISCOMFORT_DISTANCE) -> pd.DataFrame:
    """Each run's time cost and amount of violation (the module text gives the definitions).

    Parameters
    ----------
    runs
        Runs of a crowd study (the columns of :data:`PENALTY_COLUMNS`).
    distance
        ``d_c``, m: the surface clearance below which a run is penalised.

    Returns
    -------
    DataFrame
        ``time_cost_s``, ``critical_share``, ``clearance_deficit`` and ``violation`` (their
        sum), one row per run, on ``runs``' index.

    Examples
    --------
    >>> runs = pd.DataFrame({"success": [1.0, 0.0], "arrival_time_s": [20.0, math.inf],
    ...     "time_limit_s": 40.0, "goal_distance_m": [0.0, 3.0], "free_run_s": 12.0,
    ...     "shortest_m": 9.0, "critical_time_s": [0.0, 10.0], "outcome_time_s": [20.0, 40.0],
    ...     "min_surface_distance_m": [0.5, -0.05]})
    >>> run_penalties(runs).round(3).values.tolist()
    [[20.0, 0.0, 0.0, 0.0], [44.0, 0.25, 1.25, 1.5]]
    """
    missing = [c for c in PENALTY_COLUMNS if c not in getattr(runs, "columns", ())]
    if missing:
        raise InvalidParameterError("runs", missing, "must have the columns of PENALTY_COLUMNS")
    d_c = PENALTY_DISTANCE.check(distance)
    col = {c: runs[c].to_numpy(dtype=float) for c in PENALTY_COLUMNS}
    speed = col["shortest_m"] / col["free_run_s"]
    late = col["time_limit_s"] + col["goal_distance_m"] / speed
    time_cost = np.where(col["success"] > 0, col["arrival_time_s"], late)
    with np.errstate(invalid="ignore", divide="ignore"):
        share = np.clip(col["critical_time_s"] / col["outcome_time_s"], 0.0, 1.0)
    share = np.where(col["critical_time_s"] > 0, share, 0.0)
    deficit = np.maximum(0.0, d_c - col["min_surface_distance_m"]) / d_c
    return pd.DataFrame({"time_cost_s": time_cost, "critical_share": share,
                         "clearance_deficit": deficit, "violation": share + deficit},
                        index=runs.index)  # fmt: skip


def score_runs(runs: pd.DataFrame, training: CrowdSet, horizon: float, robust: str,
               alpha: float, penalty: float | None = None) -> dict[str, float]:  # fmt: skip
    """The robust cost, violation, rates and CMA-ES fitness of one gain set's runs.

    Parameters
    ----------
    runs
        The gain set's runs (:data:`PENALTY_COLUMNS`, ``collided``, ``critical``).
    training
        The set (its rate bounds).
    horizon
        The time limit of a run (s): the default ``penalty``.
    robust, alpha
        ``"mean"`` or ``"cvar"`` of the time costs; the CVaR level.
    penalty
        Seconds of fitness per unit of mean violation (default: ``horizon``).

    Returns
    -------
    dict
        ``cost_s`` (robust time cost), ``violation`` (mean), ``fitness`` (``cost_s +
        penalty * violation``), ``success_rate``, ``collision_rate``, ``critical_rate`` and
        ``feasible`` (both rates within the set's bounds).
    """
    lam = PENALTY.check(horizon if penalty is None else penalty)
    pen = run_penalties(runs)
    costs = pen["time_cost_s"].to_numpy()
    cost = float(costs.mean()) if robust == "mean" else cvar(costs, alpha)
    violation = float(pen["violation"].mean())
    coll, crit = float(runs["collided"].mean()), float(runs["critical"].mean())
    kept = coll <= training.collision_rate and crit <= training.critical_rate
    return {"cost_s": cost, "violation": violation, "fitness": cost + lam * violation,
            "success_rate": float(runs["success"].mean()), "collision_rate": coll,
            "critical_rate": crit, "feasible": bool(kept)}  # fmt: skip


def at_bounds(gains: VFFGains, bounds: Mapping[str, tuple[float, float]],
              tolerance: float = BOUND_TOLERANCE) -> tuple[str, ...]:  # fmt: skip
    """The gains within ``tolerance`` of the log box's width from a bound.

    Parameters
    ----------
    gains
        The gains.
    bounds
        ``{"k1": (low, high), ...}`` (the search box).
    tolerance
        Share of the log width (0-0.5).

    Returns
    -------
    tuple of str
        ``"<gain>: lower"`` or ``"<gain>: upper"`` for each gain on a bound.

    Examples
    --------
    >>> box = {"k1": (1.0, 10.0), "b": (0.1, 1.0), "k3": (1.0, 100.0), "k5": (1.0, 100.0)}
    >>> at_bounds(VFFGains(k1=3.0, b=0.1, k3=99.0, k5=10.0), box)
    ('b: lower', 'k3: upper')
    """
    if not 0 <= tolerance < 0.5:
        raise InvalidParameterError("tolerance", tolerance, "must be in [0, 0.5)")
    lo, hi = _log_box(bounds)
    u = (np.log([getattr(gains, k) for k in GAIN_KEYS]) - lo) / (hi - lo)
    out = [f"{k}: lower" for k, x in zip(GAIN_KEYS, u, strict=True) if x <= tolerance]
    out += [f"{k}: upper" for k, x in zip(GAIN_KEYS, u, strict=True) if x >= 1 - tolerance]
    return tuple(sorted(out))


def _log_box(bounds: Mapping[str, tuple[float, float]]) -> tuple[np.ndarray, np.ndarray]:
    lo, hi = [], []
    for k in GAIN_KEYS:
        a, b = (float(v) for v in bounds[k])
        if not (0 < a < b and math.isfinite(b)):
            raise InvalidParameterError(f"bounds[{k!r}]", (a, b), "must be 0 < low < high < inf")
        lo.append(math.log(a))
        hi.append(math.log(b))
    return np.array(lo), np.array(hi)


def _generation(training: CrowdSet, U: np.ndarray, box: tuple[np.ndarray, np.ndarray],
                kw: dict[str, Any]) -> tuple[list[VFFGains], pd.DataFrame]:  # fmt: skip
    """Simulate every candidate of a generation on every training crowd (one study)."""
    lo, hi = box
    gains = [VFFGains(*np.exp(lo + u * (hi - lo)).tolist()) for u in U]
    labels = [f"vff:c{i}" for i in range(len(gains))]
    study = training.study(labels, dict(zip(labels, gains, strict=True)), **kw)
    return gains, study.runs


def optimise_crowd_gains(
    training: CrowdSet,
    *,
    bounds: Mapping[str, tuple[float, float]],
    robust: str = ROBUST.default,
    alpha: float = CVAR_ALPHA.default,
    x0: VFFGains | None = None,
    sigma0: float = 0.25,
    popsize: int = POPULATION.default,
    generations: int = 4,
    seed: int = ARG.seed.default,
    penalty: float | None = None,
    stabilising: str = "lyapunov",
    executor: Any = None,
    store: Any = None,
    resume: bool = False,
    cache_only: bool = False,
    progress: ProgressHook | None = None,
) -> CrowdGainOptimum:
    """Optimise VFF's gains over a :class:`CrowdSet` with CMA-ES (robust over its runs).

    Parameters
    ----------
    training
        The training crowds and the rates required over them.
    bounds
        ``{"k1": (low, high), "b": ..., "k3": ..., "k5": ...}`` (searched in log space;
        ``navigation.optimise_gains`` passes its ``DEFAULT_BOUNDS``).
    robust
        ``"mean"`` or ``"cvar"`` of the runs' costs.
    alpha
        CVaR level: the worst ``1 - alpha`` of the runs are averaged.
    x0, sigma0
        Start (default: the box centre in log space) and initial step (normalised log units).
    popsize, generations
        Candidates per generation and generations (budget ``popsize * generations`` gain
        sets, each simulated on every training crowd).
    seed
        Seed of CMA-ES.
    penalty
        Seconds of fitness per unit of mean violation (default: the longest training time
        limit; :func:`score_runs`).
    stabilising
        VFF's stabilising force, ``"lyapunov"`` or ``"off"``.
    executor, store, resume, cache_only
        As for :func:`~designlab.navigation.crowds.study.crowd_study` (each generation is one
        study: its runs go through the executor in parallel; with ``resume`` the runs already
        in the store are read back, so a rebuilt report computes nothing).
    progress
        A :data:`designlab.progress.ProgressHook`: generations done, best feasible cost.

    Returns
    -------
    CrowdGainOptimum

    Examples
    --------
    >>> from designlab.navigation.tuning import DEFAULT_BOUNDS
    >>> train = CrowdSet(("corridor_counterflow",), (0.1,), (0,), {"length": 8.0, "horizon": 1.0})
    >>> opt = optimise_crowd_gains(train, bounds=DEFAULT_BOUNDS, popsize=4, generations=1)
    >>> str(opt.status), opt.evaluations
    ('ok', 4)
    """
    import cma

    mode, a = ROBUST.check(robust), CVAR_ALPHA.check(alpha)
    pop, gens = POPULATION.check(popsize), GENERATIONS.check(generations)
    box = _log_box(bounds)
    opts = {"crowd": dict(training.crowd_options)}
    horizon = max(crowd_of(opts, name, rho, training.seeds[0]).time_limit
                  for name in training.scenarios for rho in training.densities)  # fmt: skip
    lam = PENALTY.check(horizon if penalty is None else penalty)
    u0 = _start(x0, box)
    es = cma.CMAEvolutionStrategy(u0.tolist(), float(sigma0), {"bounds": [0.0, 1.0], "popsize": pop,
                                  "seed": int(seed) + 1, "verbose": -9})  # fmt: skip
    kw = {"stabilising": stabilising, "executor": executor, "store": store, "measures": False,
          "resume": resume, "cache_only": cache_only}  # fmt: skip
    rows: list[dict[str, Any]] = []
    t0 = time.perf_counter()
    for g in range(gens):
        U = np.array(es.ask())
        gains, runs = _generation(training, U, box, kw)
        scores = [score_runs(runs[runs["method"] == f"vff:c{i}"], training, horizon, mode, a, lam)
                  for i in range(len(gains))]  # fmt: skip
        es.tell(list(U), [s["fitness"] for s in scores])
        rows += [
            {"generation": g + 1, **vars_of(gi), **s} for gi, s in zip(gains, scores, strict=True)
        ]
        best = min((r["fitness"] for r in rows if r["feasible"]), default=None)
        report(progress, Progress(g + 1, gens, best=best, label="generation"))
    opt = _optimum(pd.DataFrame(rows), mode, a, time.perf_counter() - t0)
    edges = at_bounds(opt.gains, bounds) if opt.gains is not None else ()
    warn = [f"the optimum sits on the search box ({', '.join(edges)}): a better point may lie "
            "outside it (widen the box)"] if edges else []  # fmt: skip
    return replace(opt, collision_bound=training.collision_rate, runs=training.runs,
                   critical_bound=training.critical_rate, penalty=lam, at_bounds=edges,
                   warnings=opt.warnings + tuple(warn))  # fmt: skip


def vars_of(gains: VFFGains) -> dict[str, float]:
    """The four gains of a :class:`VFFGains` as a dict.

    Parameters
    ----------
    gains
        The gains.
    """
    return {k: float(getattr(gains, k)) for k in GAIN_KEYS}


def _start(x0: VFFGains | None, box: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    lo, hi = box
    if x0 is None:
        return np.full(4, 0.5)
    u = (np.log([getattr(x0, k) for k in GAIN_KEYS]) - lo) / (hi - lo)
    return np.clip(u, 0.0, 1.0)


def _optimum(history: pd.DataFrame, robust: str, alpha: float, seconds: float) -> CrowdGainOptimum:
    feasible = history[history["feasible"]]
    pool = feasible if len(feasible) else history
    best = pool.sort_values("fitness", kind="stable").iloc[0]
    warnings = [] if len(feasible) else [
        "no candidate kept the collision and critical-entry rates over the training runs: "
        "the gains shown (the fittest) break them (loosen a rate, widen the box or add "
        "generations)"
    ]  # fmt: skip
    return CrowdGainOptimum(
        gains=VFFGains(*(float(best[k]) for k in GAIN_KEYS)), cost=float(best["cost_s"]),
        collision_rate=float(best["collision_rate"]), critical_rate=float(best["critical_rate"]),
        robust=robust, alpha=alpha, evaluations=len(history), seconds=seconds, history=history,
        status=CrowdOptimumStatus.OK if len(feasible) else CrowdOptimumStatus.INFEASIBLE,
        warnings=tuple(warnings), violation=float(best["violation"]),
        fitness=float(best["fitness"]), success_rate=float(best["success_rate"]),
    )  # fmt: skip


def paired_comparison(runs: pd.DataFrame, a: str, b: str, penalty: float,
                      confidence: float = CONFIDENCE.default) -> dict[str, Any]:  # fmt: skip
    """Method ``a`` against method ``b`` on the crowds both ran (paired by crowd).

    Parameters
    ----------
    runs
        A study's runs (``scenario``, ``density``, ``seed``, ``method``, ``status``,
        ``collided`` and :data:`PENALTY_COLUMNS`); runs that raised are left out with their
        crowds.
    a, b
        Method labels.
    penalty
        Seconds per unit of violation in the penalised cost (:func:`score_runs`).
    confidence
        Level of the Wilson and t intervals.

    Returns
    -------
    dict
        ``pairs``; ``a_success``, ``b_success`` (counts) and their Wilson intervals
        (``*_low``, ``*_high``); ``mcnemar_p`` (exact, two-sided); ``a_cost_s`` and
        ``b_cost_s`` (mean penalised cost: time cost + penalty x violation); ``a_violation``,
        ``b_violation``, ``a_collisions``, ``b_collisions``; ``difference_s`` (mean of a - b),
        its t interval ``difference_low_s``, ``difference_high_s``; ``wilcoxon_p`` (exact when
        it can be) and ``decided`` (the interval excludes 0: narrower than the difference).

    Examples
    --------
    >>> base = {"scenario": "x", "density": 0.3, "status": "ok", "collided": 0.0,
    ...     "arrival_time_s": 10.0, "time_limit_s": 40.0, "goal_distance_m": 0.0,
    ...     "free_run_s": 10.0, "shortest_m": 9.0, "critical_time_s": 0.0, "outcome_time_s": 10.0,
    ...     "min_surface_distance_m": 1.0}
    >>> rows = [{**base, "seed": k, "method": m, "success": float(m == "p" or k % 2),
    ...     "arrival_time_s": 10.0 + k if m == "p" else 20.0 + k} for k in range(6) for m in "pq"]
    >>> r = paired_comparison(pd.DataFrame(rows), "p", "q", 40.0)
    >>> r["pairs"], r["a_success"], r["b_success"], round(r["mcnemar_p"], 3)
    (6, 6, 3, 0.25)
    """
    from scipy.stats import binomtest, t, wilcoxon

    ok = runs[runs["status"].astype(str) != "error"] if "status" in runs else runs
    keys = [k for k in ("model", "scenario", "density", "seed") if k in ok.columns]
    pen = run_penalties(ok)
    frame = ok[[*keys, "method", "success", "collided"]].assign(
        cost=pen["time_cost_s"] + PENALTY.check(penalty) * pen["violation"],
        violation=pen["violation"])  # fmt: skip
    A = frame[frame["method"] == a].set_index(keys)
    B = frame[frame["method"] == b].set_index(keys)
    both = A.index.intersection(B.index)
    A, B = A.loc[both], B.loc[both]
    n = len(both)
    sa, sb = int(A["success"].sum()), int(B["success"].sum())
    a_only = int(((A["success"] > 0) & (B["success"] <= 0)).sum())
    b_only = int(((B["success"] > 0) & (A["success"] <= 0)).sum())
    p_mc = binomtest(a_only, a_only + b_only).pvalue if a_only + b_only else 1.0
    d = (A["cost"] - B["cost"]).to_numpy(dtype=float)
    mean = float(d.mean()) if n else math.nan
    half = float(t.ppf(0.5 + confidence / 2, n - 1) * d.std(ddof=1) / math.sqrt(n)) if n > 1 \
        else math.nan  # fmt: skip
    p_w = float(wilcoxon(d).pvalue) if n > 1 and np.any(d != 0) else 1.0
    (la, ha), (lb, hb) = wilson_interval(sa, n, confidence), wilson_interval(sb, n, confidence)
    return {"pairs": n, "a_success": sa, "a_success_low": la, "a_success_high": ha,
            "b_success": sb, "b_success_low": lb, "b_success_high": hb,
            "mcnemar_p": float(p_mc), "a_cost_s": float(A["cost"].mean()),
            "b_cost_s": float(B["cost"].mean()), "a_violation": float(A["violation"].mean()),
            "b_violation": float(B["violation"].mean()),
            "a_collisions": int(A["collided"].sum()), "b_collisions": int(B["collided"].sum()),
            "difference_s": mean, "difference_low_s": mean - half,
            "difference_high_s": mean + half, "wilcoxon_p": p_w,
            "decided": bool(n > 1 and (mean - half > 0 or mean + half < 0))}  # fmt: skip


@dataclass(frozen=True)
class GainValidation(Result):
    """Gain sets on held-out crowds, one factor changed at a time (:func:`validate_gains`).

    Attributes
    ----------
    studies
        Step (:data:`VALIDATION_STEPS`) -> its :class:`CrowdStudy`.
    sets
        Step -> its :class:`CrowdSet`.
    candidate, reference
        The labels compared (``vff:<tag>``): the tuned gains and the gains to beat.
    penalty
        Seconds per unit of violation in the penalised cost.
    confidence
        Level of the intervals.

    Examples
    --------
    >>> v = GainValidation({}, {}, "vff:crowd_optimum", "vff:thesis", 40.0)
    >>> v.to_frame().empty
    True
    """

    studies: Mapping[str, CrowdStudy] = field(repr=False)
    sets: Mapping[str, CrowdSet] = field(repr=False)
    candidate: str
    reference: str
    penalty: float
    confidence: float = CONFIDENCE.default

    @property
    def status(self) -> str:  # type: ignore[override]
        """``"ok"`` unless a step's study is not."""
        bad = [str(s.status) for s in self.studies.values() if str(s.status) != "ok"]
        return bad[0] if bad else "ok"

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """The steps' warnings, each prefixed by its step."""
        return tuple(f"validation ({k}): {w}" for k, s in self.studies.items() for w in s.warnings)

    @property
    def runs(self) -> pd.DataFrame:
        """Every step's runs, with a ``step`` column."""
        parts = [s.runs.assign(step=k) for k, s in self.studies.items()]
        return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()

    def to_frame(self) -> pd.DataFrame:
        """One row per step: what it changed and :func:`paired_comparison` of the
        candidate against the reference."""
        rows = []
        for k, st in self.studies.items():
            cs = self.sets[k]
            rows.append({"step": k, "scenarios": " ".join(cs.scenarios),
                         "densities": " ".join(f"{d:g}" for d in cs.densities),
                         "seeds": len(cs.seeds), "candidate": self.candidate,
                         "reference": self.reference,
                         **paired_comparison(st.runs, self.candidate, self.reference,
                                             self.penalty, self.confidence)})  # fmt: skip
        return pd.DataFrame(rows)


def validate_gains(candidates: Mapping[str, VFFGains], steps: Sequence[tuple[str, CrowdSet]],
                   training: CrowdSet, *, reference: str, penalty: float,
                   **kw: Any) -> GainValidation:  # fmt: skip
    """Simulate gain sets on held-out crowds, one study per step of :func:`validation_steps`.

    Parameters
    ----------
    candidates
        Tag -> gains (simulated as method labels ``"vff:<tag>"``); the first is compared
        with ``reference``.
    steps
        ``(step, CrowdSet)`` pairs (:func:`validation_steps`).
    training
        The crowds the gains were optimised on (no validation seed may be one of its).
    reference
        The tag of the gains to beat (one of ``candidates``).
    penalty
        Seconds per unit of violation in the penalised cost.
    **kw
        Other keywords of :func:`~designlab.navigation.crowds.study.crowd_study`.

    Returns
    -------
    GainValidation
    """
    tags = list(candidates)
    if reference not in tags or tags[0] == reference:
        raise InvalidParameterError("reference", reference, f"must be one of {tags[1:]}")
    for _, cs in steps:
        check_disjoint(training, cs, what=("seeds",))
    labels = [f"vff:{tag}" for tag in tags]
    gains = {f"vff:{t}": g for t, g in candidates.items()}
    studies = {name: cs.study(labels, gains, **kw) for name, cs in steps}
    return GainValidation(studies, dict(steps), labels[0], f"vff:{reference}",
                          PENALTY.check(penalty),
                          kw.get("confidence", CONFIDENCE.default))  # fmt: skip


#: Keywords of ``navigation.optimise_gains`` that a crowd set uses (the others are refused).
CROWD_KEYWORDS = ("bounds", "robust", "alpha", "x0", "sigma0", "popsize", "generations", "seed",
                  "penalty", "stabilising", "executor", "store", "resume", "cache_only",
                  "progress")  # fmt: skip


def crowd_sets(default_bounds: Mapping[str, tuple[float, float]]) -> Callable[[Callable], Callable]:
    """Decorator: ``optimise_gains(crowd_set, ...)`` optimises over crowds.

    Parameters
    ----------
    default_bounds
        The gain box used when ``bounds`` is not given.
    """

    def wrap(optimise: Callable) -> Callable:
        @functools.wraps(optimise)
        def dispatch(scenarios: Any, *args: Any, **kw: Any) -> Any:
            if not isinstance(scenarios, CrowdSet):
                return optimise(scenarios, *args, **kw)
            other = sorted(set(kw) - set(CROWD_KEYWORDS))
            if args or other:
                allowed = f"a CrowdSet takes only {list(CROWD_KEYWORDS)}"
                raise InvalidParameterError("optimise_gains", other or args, allowed)
            kw["bounds"] = {**default_bounds, **dict(kw.get("bounds") or {})}
            kw["robust"] = kw.get("robust") or "mean"
            return optimise_crowd_gains(scenarios, **kw)

        return dispatch

    return wrap
