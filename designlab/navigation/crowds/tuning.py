"""Gains for crowds: VFF's (K1, b, K3, K5) optimised over a set of crowds, robust over seeds.

A :class:`CrowdSet` names the crowds (layouts x densities x seeds, and the crowd options) and
the rates a gain set must keep over them: collision rate at most ``collision_rate`` (0: no
collision in any training run) and critical-entry rate at most ``critical_rate``.
:func:`optimise_crowd_gains` (also ``navigation.optimise_gains(crowd_set, robust=...)``)
searches log-gain space with CMA-ES; a candidate's cost is the ``"mean"`` or the ``"cvar"``
(mean of the worst ``1 - alpha`` of the runs, :func:`~designlab.navigation.crowds.metrics.cvar`)
of its runs' costs: the arrival time, or twice the time limit (the longest of the training
layouts') for a run that did not arrive.
A candidate breaking a rate ranks below every candidate that keeps them, by how much it
breaks them.

:func:`validate_gains` simulates gain sets on a validation set that shares no seed and no
density with the training set (:func:`check_disjoint` refuses an overlap) and returns the
:class:`~designlab.navigation.crowds.study.CrowdStudy` of the comparison (e.g. the crowd
optimum against the thesis's gains and the Configurations 1-3 optimum).
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
from designlab.navigation.crowds.metrics import CVAR_ALPHA, cvar
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
    "ROBUST",
    "CrowdGainOptimum",
    "CrowdOptimumStatus",
    "CrowdSet",
    "check_disjoint",
    "crowd_sets",
    "optimise_crowd_gains",
    "score_runs",
    "validate_gains",
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


def check_disjoint(training: CrowdSet, validation: CrowdSet) -> None:
    """Refuse a validation set sharing a seed or a density with the training set.

    Parameters
    ----------
    training, validation
        The two sets.

    Examples
    --------
    >>> train = CrowdSet(("crossing",), (0.2,), (0, 1))
    >>> check_disjoint(train, CrowdSet(("crossing",), (0.4,), (5,)))
    """
    for name in ("seeds", "densities"):
        shared = sorted(set(getattr(training, name)) & set(getattr(validation, name)))
        if shared:
            raise InvalidParameterError(
                f"validation.{name}", shared, "must share nothing with the training set"
            )


@dataclass(frozen=True)
class CrowdGainOptimum(Result):
    """The gains found for a set of crowds.

    Attributes
    ----------
    gains
        The best :class:`VFFGains` (``None`` if nothing was evaluated).
    cost
        Its robust cost (s).
    collision_rate, critical_rate
        Its rates over the training runs.
    robust, alpha
        ``"mean"`` or ``"cvar"`` and the CVaR level.
    evaluations, seconds
        Gain sets simulated (each on every training crowd) and the wall time.
    history
        One row per candidate: ``generation``, the gains, ``cost_s``, the rates, ``feasible``.
    collision_bound, critical_bound
        The rates required (the training set's).
    status, warnings
        :class:`CrowdOptimumStatus` and what a user should know.
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

    def to_frame(self) -> pd.DataFrame:
        """The history of the search (one row per candidate)."""
        return self.history.copy()


def _costs(runs: pd.DataFrame, horizon: float) -> np.ndarray:
    """Cost of each run: the arrival time, twice the horizon when it did not arrive."""
    t = runs["arrival_time_s"].to_numpy(dtype=float)
    return np.where(runs["success"].to_numpy() > 0, t, 2.0 * horizon)


def score_runs(runs: pd.DataFrame, training: CrowdSet, horizon: float, robust: str,
               alpha: float) -> dict[str, float]:  # fmt: skip
    """The robust cost and rates of one gain set's runs, and its CMA-ES fitness.

    Parameters
    ----------
    runs
        The gain set's runs (``arrival_time_s``, ``success``, ``collided``, ``critical``).
    training
        The set (its rate bounds).
    horizon
        Horizon of a run (s): a run that did not arrive costs twice this.
    robust, alpha
        ``"mean"`` or ``"cvar"``; the CVaR level.

    Returns
    -------
    dict
        ``cost_s``, ``collision_rate``, ``critical_rate``, ``feasible`` and ``fitness``: the
        cost when the rates are kept, else ``4 horizon (1 + violation)``, above any kept one.
    """
    costs = _costs(runs, horizon)
    cost = float(costs.mean()) if robust == "mean" else cvar(costs, alpha)
    coll, crit = float(runs["collided"].mean()), float(runs["critical"].mean())
    violation = max(0.0, coll - training.collision_rate) + max(0.0, crit - training.critical_rate)
    fitness = cost if violation == 0 else 4.0 * horizon * (1.0 + violation)
    return {"cost_s": cost, "collision_rate": coll, "critical_rate": crit,
            "feasible": violation == 0, "fitness": fitness}  # fmt: skip


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
    stabilising: str = "lyapunov",
    executor: Any = None,
    store: Any = None,
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
    stabilising
        VFF's stabilising force, ``"lyapunov"`` or ``"off"``.
    executor, store
        As for :func:`~designlab.navigation.crowds.study.crowd_study` (each generation is one
        study: its runs go through the executor in parallel).
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
    horizon = max(crowd_of(opts, name, training.densities[0], training.seeds[0]).time_limit
                  for name in training.scenarios)  # fmt: skip
    u0 = _start(x0, box)
    es = cma.CMAEvolutionStrategy(u0.tolist(), float(sigma0), {"bounds": [0.0, 1.0], "popsize": pop,
                                  "seed": int(seed) + 1, "verbose": -9})  # fmt: skip
    kw = {"stabilising": stabilising, "executor": executor, "store": store}
    rows: list[dict[str, Any]] = []
    t0 = time.perf_counter()
    for g in range(gens):
        U = np.array(es.ask())
        gains, runs = _generation(training, U, box, kw)
        scores = [score_runs(runs[runs["method"] == f"vff:c{i}"], training, horizon, mode, a)
                  for i in range(len(gains))]  # fmt: skip
        es.tell(list(U), [s["fitness"] for s in scores])
        rows += [
            {"generation": g + 1, **vars_of(gi), **s} for gi, s in zip(gains, scores, strict=True)
        ]
        best = min((r["cost_s"] for r in rows if r["feasible"]), default=None)
        report(progress, Progress(g + 1, gens, best=best, label="generation"))
    opt = _optimum(pd.DataFrame(rows), mode, a, time.perf_counter() - t0)
    return replace(
        opt, collision_bound=training.collision_rate, critical_bound=training.critical_rate
    )


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
        "the gains shown break them (loosen a rate, widen the box or add generations)"
    ]  # fmt: skip
    return CrowdGainOptimum(
        gains=VFFGains(*(float(best[k]) for k in GAIN_KEYS)), cost=float(best["cost_s"]),
        collision_rate=float(best["collision_rate"]), critical_rate=float(best["critical_rate"]),
        robust=robust, alpha=alpha, evaluations=len(history), seconds=seconds, history=history,
        status=CrowdOptimumStatus.OK if len(feasible) else CrowdOptimumStatus.INFEASIBLE,
        warnings=tuple(warnings),
    )  # fmt: skip


def validate_gains(candidates: Mapping[str, VFFGains], validation: CrowdSet,
                   training: CrowdSet, **kw: Any) -> CrowdStudy:  # fmt: skip
    """Simulate gain sets on held-out crowds (no seed, no density shared with ``training``).

    Parameters
    ----------
    candidates
        Tag -> gains (simulated as method labels ``"vff:<tag>"``).
    validation
        The held-out crowds.
    training
        The crowds the gains were optimised on (to check they share nothing).
    **kw
        Other keywords of :func:`~designlab.navigation.crowds.study.crowd_study`.

    Returns
    -------
    CrowdStudy
    """
    check_disjoint(training, validation)
    labels = [f"vff:{tag}" for tag in candidates]
    return validation.study(labels, {f"vff:{t}": g for t, g in candidates.items()}, **kw)


#: Keywords of ``navigation.optimise_gains`` that a crowd set uses (the others are refused).
CROWD_KEYWORDS = ("bounds", "robust", "alpha", "x0", "sigma0", "popsize", "generations", "seed",
                  "stabilising", "executor", "store", "progress")  # fmt: skip


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
