"""Gain tuning of the tether follower laws (derivative-free, seeded).

Allan 2015 tuned its gains by hand, one parameter at a time (Sec. 2.5, 6.1 of
the project's notes); App. C holds the only numbers. :func:`tune` searches the
gains of one law over several leader paths and speeds with a search chosen by
name from :data:`TUNERS` (small strategy objects: scipy's differential
evolution, the default, or a bounded Nelder-Mead simplex from the defaults).
Every generation is one batched simulation per (path, speed) scenario
(:func:`designlab.following.tether.simulate_batch`), and the scenarios can be
spread over the project's executors (anything with ``map_unordered``, e.g.
:func:`designlab.analysis.executors.make_executor`).

The cost of a gain set is the mean over the scenarios of

* ``deviation``: mean normal path deviation in wheel tracks (App. A; the
  thesis's primary metric),
* ``length``: RMS(l_m - l_d)/l_d (the cannula length),
* ``smoothness``: RMS(dV/dt) [m/s^2] + 0.1 RMS(dOmega/dt) [rad/s^2] (the
  "jerky" bursts of Sec. 2.5.1),

weighted by ``weights``, plus the penalties of three constraints: the tether
stays in ``tether_range`` (10 x the excess / l_d), a wheel runs at its speed
limit for at most ``max_saturation`` of the run (default 5 %; 10 x the excess
fraction), and the run does not fail. The wheel-limit bound is also a hard
constraint of the search (:func:`wheel_limit_barrier`): a gain set that exceeds
it on any tuning scenario ranks below every set that does not, so the tuned
gains keep it on the tuning paths whenever any evaluated set does (otherwise the
status is ``infeasible``); on unseen paths it is measured, not imposed. A fourth
constraint is checked on the model: the damping ratio of the linearised lateral loop
(:mod:`~designlab.following.tether.linear`) must be at least ``damping_floor``
at every tuning speed, so that tuned gains do not weave. The thesis defaults are
part of the initial population, so the tuned cost on the tuning scenarios is
never worse than theirs when the defaults keep the wheel-limit bound.

The improvement is reported on validation paths that share no stretch with
the tuning paths (:mod:`~designlab.following.tether.overlap`; by default the
square S, the corridor corner, a circle and two random smooth walks whose seeds
no tuning walk uses), with the penalties (the headline) and without them
beside it, and the constraint violations before and after. A ``progress`` hook
hears of every generation (:mod:`designlab.progress`).

Examples
--------
>>> from designlab.following.tether import FollowTheLeader, figure_eight, slalom
>>> res = tune(FollowTheLeader, paths=[figure_eight(a=2.0)], speeds=[0.5],
...            validation_paths=[slalom()], popsize=4, maxiter=2, seed=1)
>>> res.cost <= res.default_cost, sorted(res.controller.gains)
(True, ['lookahead', 'speed_gain', 'turn_gain'])
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.following.tether.laws.base import TetherController, checked_law
from designlab.following.tether.laws.registry import LAWS
from designlab.following.tether.linear import damping_ratio
from designlab.following.tether.overlap import overlapping_paths
from designlab.following.tether.parameters import (
    DAMPING_FLOOR,
    LEADER_SPEED,
    MAX_SATURATION,
    MAXITER,
    OXYDOG,
    POPSIZE,
    SEED,
    TETHER_LIMIT,
    TOLERANCE,
    FollowerRobot,
)
from designlab.following.tether.path_deviation import normal_path_deviations
from designlab.following.tether.paths import (
    LeaderPath,
    circle,
    corridor_corner,
    make_path,
    smooth_walk,
    square_s,
)
from designlab.following.tether.simulate import simulate_batch
from designlab.params import declared, param
from designlab.progress import Progress, ProgressHook, report
from designlab.results import Result, Status
from designlab.validation import ParamsMixin

__all__ = [
    "DEFAULT_WEIGHTS",
    "NEAR_OPTIMAL_COST",
    "TUNERS",
    "VALIDATION_WALK_SEEDS",
    "WHEEL_LIMIT_INFEASIBLE",
    "CostWeights",
    "DifferentialEvolutionTuner",
    "NelderMeadTuner",
    "TuningResult",
    "TuningStatus",
    "default_validation",
    "scenario_costs",
    "tune",
    "wheel_limit_barrier",
]

logger = logging.getLogger(__name__)

_FAILED = 1e3

#: Gain sets whose cost is within this (relative) of the best are near-optimal
#: (:meth:`TuningResult.near_optimal`): which of them a seeded search returns depends on the
#: last bits of the arithmetic, so a report gives their range (docs/following.md).
NEAR_OPTIMAL_COST = 1e-4


@declared
@dataclass(frozen=True)
class CostWeights(ParamsMixin):
    """Weights of the tuning cost (see the module notes)."""

    deviation: float = param(
        None, "", doc="weight of the mean normal path deviation / b", ge=0, le=1e3, default=1.0
    )
    length: float = param(None, "", doc="weight of RMS(l_m - l_d) / l_d", ge=0, le=1e3, default=0.5)
    smoothness: float = param(
        None, "", doc="weight of RMS(dV/dt) + 0.1 RMS(dOmega/dt)", ge=0, le=1e3, default=0.05
    )


#: Default cost weights (:class:`CostWeights`).
DEFAULT_WEIGHTS = CostWeights().as_dict()


class TuningStatus(Status):
    """Status of a gain tuning.

    ``OK``: differential evolution converged and the tuned gains meet the
    damping floor. ``NOT_CONVERGED``: it used all its generations (the gains
    are the best found; never worse than the defaults on the tuning paths).
    ``INFEASIBLE``: the tuned gains violate the damping floor.
    """

    OK = "ok"
    NOT_CONVERGED = "not_converged"
    INFEASIBLE = "infeasible"


@dataclass(frozen=True, eq=False)
class TuningResult(Result):
    """Tuned gains of one law and their improvement over the thesis defaults.

    Attributes
    ----------
    controller, default
        The tuned controller and the thesis-default one it started from.
    cost, default_cost
        Mean cost over the tuning scenarios (tuned, default).
    improvement
        ``1 - J/J_default`` over the validation scenarios (paths that share no
        stretch with the tuning paths), with J the full cost: the weighted
        deviation + length + smoothness cost plus the constraint penalties
        (the headline); positive is better.
    training_improvement
        ``1 - cost/default_cost`` over the tuning scenarios (penalties included).
    violations
        Scenarios where the default and the tuned gains violate a constraint
        (leave the tether range, or a wheel at its limit for more than
        ``max_saturation`` of the run): ``{"default": n, "tuned": n}`` per set.
    npd_improvement
        ``1 - mean NPD (tuned)/mean NPD (default)`` over the validation scenarios.
    scenarios
        Per scenario and controller: the cost and its parts.
    improvement_unpenalised
        ``1 - J/J_default`` on the validation scenarios without the penalties
        (reported beside the headline).
    saturation
        Largest fraction of a run with a wheel at its speed limit,
        ``{"default": f, "tuned": f}`` per set (``tuning``, ``validation``).
    max_saturation
        The bound on that fraction (a constraint of the tuning).
    damping_ratios
        Linear lateral damping ratio of the tuned gains at each tuning speed.
    history
        Best cost after each generation.
    evaluations
        Gain sets simulated (per scenario).
    wall_time
        Seconds (for the run record; a report never shows it).
    evaluated
        Every gain set the search evaluated with its cost, one row each (what
        :meth:`near_optimal` reads).
    status
        ``"ok"``, ``"not_converged"`` or ``"infeasible"`` (:class:`TuningStatus`).
    warnings
        What a user should know about the tuning.
    """

    controller: TetherController
    default: TetherController
    cost: float
    default_cost: float
    improvement: float
    training_improvement: float
    npd_improvement: float
    violations: dict[str, dict[str, int]]
    scenarios: pd.DataFrame
    damping_ratios: dict[float, float]
    history: tuple[float, ...]
    evaluations: int
    wall_time: float
    status: TuningStatus = TuningStatus.OK
    warnings: tuple[str, ...] = ()
    improvement_unpenalised: float = math.nan
    saturation: dict[str, dict[str, float]] | None = None
    max_saturation: float = MAX_SATURATION.default
    evaluated: pd.DataFrame = field(default_factory=pd.DataFrame, repr=False)

    def to_frame(self) -> pd.DataFrame:
        """The per-scenario table (``set`` is ``tuning`` or ``validation``)."""
        return self.scenarios

    def near_optimal(self, tolerance: float = NEAR_OPTIMAL_COST) -> pd.DataFrame:
        """Per gain, the range of the evaluated gain sets within ``tolerance`` of the best cost.

        Where the cost is this flat, which of these sets a seeded search returns depends on
        the last bits of the arithmetic (another CPU), so a report gives the range.

        Parameters
        ----------
        tolerance
            Relative cost above the best that still counts as near-optimal (>= 0).

        Returns
        -------
        pandas.DataFrame
            ``gain``, ``low``, ``high``, ``tuned`` per gain; ``attrs["sets"]``: how many
            evaluated gain sets lie within the tolerance (0 if none was recorded).

        Examples
        --------
        >>> import pandas as pd
        >>> from designlab.following.tether import FollowTheLeader
        >>> tuned = FollowTheLeader(speed_gain=1.2, turn_gain=2.9, lookahead=0.45)
        >>> evaluated = pd.DataFrame({"speed_gain": [1.2, 1.1, 2.0], "turn_gain": [2.9, 3.1, 1.0],
        ...                           "lookahead": [0.45, 0.44, 0.9],
        ...                           "cost": [0.50000, 0.50004, 0.7]})
        >>> r = TuningResult(tuned, FollowTheLeader(), 0.5, 0.6, 0.17, 0.17, 0.1, {},
        ...                  pd.DataFrame(), {}, (0.5,), 3, 0.0, evaluated=evaluated)
        >>> near = r.near_optimal(1e-4)   # costs within 1e-4 (relative) of the best
        >>> near.attrs["sets"]
        2
        >>> print(near.to_string(index=False))
              gain  low  high  tuned
        speed_gain 1.10  1.20   1.20
         turn_gain 2.90  3.10   2.90
         lookahead 0.44  0.45   0.45
        """
        if not (isinstance(tolerance, int | float) and math.isfinite(tolerance)) or tolerance < 0:
            raise InvalidParameterError("tolerance", tolerance, "must be a finite number >= 0")
        f = self.evaluated
        tuned = self.controller.gains
        if f.empty or "cost" not in f:
            out = pd.DataFrame(columns=["gain", "low", "high", "tuned"])
            out.attrs["sets"] = 0
            return out
        best = float(f["cost"].min())
        near = f[f["cost"] <= best + tolerance * abs(best)]
        names = [c for c in f.columns if c != "cost"]
        out = pd.DataFrame(
            [(n, float(near[n].min()), float(near[n].max()), float(tuned[n])) for n in names],
            columns=["gain", "low", "high", "tuned"],
        )
        out.attrs["sets"] = len(near)
        return out


# --- the cost of a batch of gain sets on one scenario (a plain function for executors) ----


def _member_cost(batch: Any, i: int, npd: Any, task: dict[str, Any]) -> dict[str, float]:
    """Cost parts of member ``i`` of a batch whose run finished."""
    robot, w = batch.robot, task["weights"]
    lo, hi = task["tether_range"]
    dt, b = robot.sample_time, robot.wheel_track
    ld = batch.controllers[i].desired_length
    lm = batch.tether_length[i]
    dev = npd.mean_over_b if npd.status == "ok" else 10.0
    length = float(np.sqrt(np.mean((lm - ld) ** 2))) / ld
    smooth = float(np.sqrt(np.mean((np.diff(batch.speed[i]) / dt) ** 2))) + 0.1 * float(
        np.sqrt(np.mean((np.diff(batch.turn_rate[i]) / dt) ** 2))
    )
    pen = 10.0 * (max(0.0, lo - float(lm.min())) + max(0.0, float(lm.max()) - hi)) / ld
    sat = 0.0
    if robot.max_wheel_speed < math.inf:
        wsat = (np.abs(batch.speed[i]) + 0.5 * b * np.abs(batch.turn_rate[i])) / robot.wheel_radius
        sat = float(np.mean(wsat >= robot.max_wheel_speed * (1 - 1e-9)))
        pen += 10.0 * max(0.0, sat - task.get("max_saturation", MAX_SATURATION.default))
    cost = w["deviation"] * dev + w["length"] * length + w["smoothness"] * smooth + pen
    return {
        "cost": cost,
        "deviation": dev,
        "npd_m": npd.mean,
        "length": length,
        "smoothness": smooth,
        "penalty": pen,
        "saturation": sat,
    }


def scenario_costs(task: dict[str, Any]) -> dict[str, Any]:
    """Cost parts of a batch of gain sets on one (path, speed) scenario.

    A top-level function of plain data, so that executors can ship it to
    worker processes. ``task`` holds ``law`` (class name), ``base`` (fields of
    the base controller), ``gains`` (list of dicts), ``path`` ((N, 2) points),
    ``path_name``, ``speed``, ``robot`` (fields), ``weights`` and
    ``tether_range``.

    Parameters
    ----------
    task
        The scenario and the gain sets, as plain data (see above).

    Returns
    -------
    dict
        Arrays (one value per gain set): ``cost``, ``deviation``, ``npd_m``,
        ``length``, ``smoothness``, ``penalty``, ``saturation`` (fraction of
        the run with a wheel at its limit).
    """
    cls = LAWS.get(task["law"])
    base = {k: v for k, v in task["base"].items() if k != "type"}
    ctrls = [cls(**{**base, **g}) for g in task["gains"]]
    robot = FollowerRobot(**task["robot"])
    path = LeaderPath(np.asarray(task["path"]), name=task.get("path_name", "path"))
    batch = simulate_batch(
        ctrls,
        path,
        speed=float(task["speed"]),
        robot=robot,
        settle_time=task.get("settle_time", 4.0),
    )
    keys = ("cost", "deviation", "npd_m", "length", "smoothness", "penalty", "saturation")
    out = {k: np.full(len(ctrls), _FAILED) for k in keys}
    ok = [i for i in range(len(ctrls)) if batch.member_status[i] == "ok"]
    npds = normal_path_deviations(
        batch.leader_xy, [batch.robot_xy[i] for i in ok], wheel_track=robot.wheel_track
    )
    for i, npd in zip(ok, npds, strict=True):
        for k, v in _member_cost(batch, i, npd, task).items():
            out[k][i] = v
    return out


# --- the search -----------------------------------------------------------------------------


#: Seeds of the random smooth walks of the default validation set; a tuning walk with one
#: of these seeds removes it.
VALIDATION_WALK_SEEDS = (101, 102)


def default_validation(paths: Sequence[LeaderPath]) -> list[LeaderPath]:
    """Validation paths that share no stretch with ``paths`` (the tuning paths).

    The square S, the corridor corner, a circle of radius 1.5 m and random smooth
    walks with seeds :data:`VALIDATION_WALK_SEEDS`; a candidate that overlaps a
    tuning path (:func:`~designlab.following.tether.overlap.overlapping_paths`) or
    has its name is left out.

    Parameters
    ----------
    paths
        The tuning paths.
    """
    names = {p.name for p in paths}
    cands = [square_s(), corridor_corner(), circle(radius=1.5)]
    cands += [smooth_walk(seed=s) for s in VALIDATION_WALK_SEEDS]
    clash = {v for v, _, _ in overlapping_paths(cands, paths)}
    return [p for p in cands if p.name not in names and p.name not in clash]


@dataclass(frozen=True)
class _Setup:
    """The checked tuning problem: the law, its search box, scenarios and settings."""

    base: TetherController
    names: tuple[str, ...]
    bounds: tuple[tuple[float, float], ...]
    paths: tuple[LeaderPath, ...]
    validation: tuple[LeaderPath, ...]
    speeds: tuple[float, ...]
    robot: FollowerRobot
    weights: dict[str, float]
    damping_floor: float
    tether_range: tuple[float, float]
    max_saturation: float = MAX_SATURATION.default

    def tasks(self, gain_sets: list[dict[str, float]], paths: Sequence[LeaderPath]) -> list:
        """The plain-data tasks of :func:`scenario_costs`, one per (path, speed)."""
        base, robot = self.base.as_dict(), self.robot.as_dict()
        return [
            {
                "law": self.base.name,
                "base": base,
                "gains": gain_sets,
                "path": p.points,
                "path_name": p.name,
                "speed": v,
                "robot": robot,
                "weights": self.weights,
                "tether_range": self.tether_range,
                "max_saturation": self.max_saturation,
            }
            for p in paths
            for v in self.speeds
        ]

    def damping_penalty(self, gain_sets: list[dict[str, float]]) -> NDArray[np.float64]:
        """100 x the shortfall of the linear damping ratio below the floor, summed over speeds."""
        pen = np.zeros(len(gain_sets))
        for i, g in enumerate(gain_sets):
            c = self.base.replace(**g)
            for v in self.speeds:
                zeta = damping_ratio(c, v, self.robot.wheel_track)
                pen[i] += 100.0 * max(0.0, self.damping_floor - zeta)
        return pen


#: Added by the search to a gain set that holds a wheel at its speed limit for more than
#: ``max_saturation`` of any tuning scenario: more than any feasible set's cost, so that the
#: wheel-limit bound is a hard constraint (feasible sets always rank first).
WHEEL_LIMIT_INFEASIBLE = 100.0


def wheel_limit_barrier(parts: Sequence[dict[str, Any]], bound: float) -> NDArray[np.float64]:
    """The search's hard wheel-limit constraint, per gain set.

    0 where every tuning scenario keeps a wheel at its limit for at most ``bound`` of the
    run; otherwise :data:`WHEEL_LIMIT_INFEASIBLE` plus 10 x the largest excess (so that the
    search is drawn toward the feasible sets). The reported costs keep the soft penalty only.

    Parameters
    ----------
    parts
        :func:`scenario_costs` results, one per tuning scenario (their ``saturation``).
    bound
        The largest allowed fraction of a run at the wheel limit.

    Examples
    --------
    >>> wheel_limit_barrier([{"saturation": np.array([0.01, 0.07])}], 0.05).tolist()
    [0.0, 100.2]
    """
    sat = np.max([np.asarray(p["saturation"], dtype=float) for p in parts], axis=0)
    excess = sat - bound
    return np.where(excess > 0.0, WHEEL_LIMIT_INFEASIBLE + 10.0 * excess, 0.0)


def _base_controller(controller: Any) -> TetherController:
    law = controller() if controller in LAWS.variants() else controller  # a class: its defaults
    return checked_law(law, "controller", "a tether controller class or instance")


def _search_box(
    cls: type[TetherController], robot: FollowerRobot, bounds: dict[str, Any] | None
) -> dict[str, tuple[float, float]]:
    """The gain bounds: the law's ``BOUNDS``, delta within b-2b, then the caller's."""
    box = dict(cls.BOUNDS)
    if "lookahead" in box:
        # the thesis's rule b < delta < 2b (Allan 2015 Sec. 2.3.2.2)
        box["lookahead"] = (robot.wheel_track, 2.0 * robot.wheel_track)
    for k, v in (bounds or {}).items():
        if k not in cls.GAINS:
            raise InvalidParameterError(f"bounds.{k}", v, f"one of {list(cls.GAINS)}")
        try:
            lo, hi = (float(x) for x in v)
        except (TypeError, ValueError):
            raise InvalidParameterError(f"bounds.{k}", v, "(low, high)") from None
        if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo < hi <= 1e3):
            raise InvalidParameterError(
                f"bounds.{k}", v, "(low, high) with 0 <= low < high <= 1000"
            )
        box[k] = (lo, hi)
    return box


def _listed(name: str, values: Any, make: Any) -> tuple[Any, ...]:
    if isinstance(values, (str, bytes, dict)) or not isinstance(values, Sequence):
        raise InvalidParameterError(name, values, "a list")
    if not values:
        raise InvalidParameterError(name, values, "at least one")
    if len(values) > 100:
        raise InvalidParameterError(name, f"{len(values)} items", "at most 100")
    return tuple(make(v) for v in values)


def _checked_setup(controller: Any, paths: Any, speeds: Any, options: dict[str, Any]) -> _Setup:
    """Validate every argument of :func:`tune` before the search starts."""
    base = _base_controller(controller)
    robot = OXYDOG if options["robot"] is None else options["robot"]
    if not isinstance(robot, FollowerRobot):
        raise InvalidParameterError("robot", robot, "a FollowerRobot")
    weights = CostWeights(**{**DEFAULT_WEIGHTS, **_weights(options["weights"])}).as_dict()
    lo, hi = (TETHER_LIMIT.check(v, "tether_range[]") for v in options["tether_range"])
    if hi <= lo:
        raise InvalidParameterError(
            "tether_range", options["tether_range"], "(min, max) with min < max", "m"
        )
    box = _search_box(type(base), robot, options["bounds"])
    paths_t = _listed("paths", paths, make_path)
    val = options["validation_paths"]
    return _Setup(
        base=base,
        names=type(base).GAINS,
        bounds=tuple(box[k] for k in type(base).GAINS),
        paths=paths_t,
        validation=tuple(
            default_validation(paths_t) if val is None else (make_path(p) for p in val)
        ),
        speeds=_listed("speeds", speeds, lambda v: LEADER_SPEED.check(v, "speeds[]")),
        robot=robot,
        weights=weights,
        damping_floor=DAMPING_FLOOR.check(options["damping_floor"]),
        tether_range=(lo, hi),
        max_saturation=MAX_SATURATION.check(options["max_saturation"]),
    )


def _weights(weights: Any) -> dict[str, Any]:
    if weights is None:
        return {}
    if not isinstance(weights, dict):
        raise InvalidParameterError("weights", weights, f"a dict with keys {list(DEFAULT_WEIGHTS)}")
    for k, v in weights.items():
        if k not in DEFAULT_WEIGHTS:
            raise InvalidParameterError(f"weights.{k}", v, f"one of {sorted(DEFAULT_WEIGHTS)}")
    return dict(weights)


class _Scenarios:
    """Runs the scenario tasks of a generation, serially or through an executor."""

    def __init__(self, executor: Any) -> None:
        self.executor = executor

    def __call__(self, tasks: list[dict[str, Any]]) -> list[dict[str, Any]]:
        if self.executor is None:
            return [scenario_costs(t) for t in tasks]
        res: list[Any] = [None] * len(tasks)
        for i, r in self.executor.map_unordered(scenario_costs, tasks):
            res[i] = r
        return res


class _Objective:
    """The vectorised objective of differential evolution and its per-generation callback."""

    def __init__(self, setup: _Setup, run: _Scenarios, total: int, progress: Any) -> None:
        self.setup, self.run, self.total, self.progress = setup, run, total, progress
        self.label = "generation"
        self.evaluations = 0
        self.history: list[float] = []
        self.evaluated: list[tuple[list[dict[str, float]], NDArray[np.float64]]] = []

    def evaluated_frame(self) -> pd.DataFrame:
        """Every gain set evaluated and its cost, best first."""
        rows = [
            {**g, "cost": float(c)}
            for gs, cs in self.evaluated
            for g, c in zip(gs, cs, strict=True)
        ]
        if not rows:
            return pd.DataFrame(columns=[*self.setup.names, "cost"], dtype=float)
        return pd.DataFrame(rows).sort_values("cost", kind="stable", ignore_index=True)

    def gain_sets(self, x: NDArray[np.float64]) -> list[dict[str, float]]:
        return [
            {k: float(x[j, i]) for j, k in enumerate(self.setup.names)} for i in range(x.shape[1])
        ]

    def __call__(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        x = np.atleast_2d(x.T).T if x.ndim == 1 else x
        gain_sets = self.gain_sets(x)
        self.evaluations += len(gain_sets)
        parts = self.run(self.setup.tasks(gain_sets, self.setup.paths))
        cost = np.mean([p["cost"] for p in parts], axis=0) + self.setup.damping_penalty(gain_sets)
        cost = cost + wheel_limit_barrier(parts, self.setup.max_saturation)
        self.evaluated.append((gain_sets, np.atleast_1d(np.asarray(cost, dtype=float))))
        return cost

    def callback(self, intermediate_result: Any) -> None:
        self.history.append(float(intermediate_result.fun))
        report(
            self.progress,
            Progress(
                step=len(self.history),
                total=self.total,
                best=self.history[-1],
                label=self.label,
                note=self.setup.base.name,
            ),
        )


class DifferentialEvolutionTuner:
    """``method="differential_evolution"`` (default): scipy's seeded differential evolution.

    A Latin-hypercube population of ``popsize x (number of gains)`` members
    holding the defaults, ``maxiter`` generations, each one vectorised batch of
    simulations per scenario.
    """

    name: ClassVar[str] = "differential_evolution"
    #: What one progress step is.
    step_label: ClassVar[str] = "generation"

    @staticmethod
    def steps(maxiter: int, popsize: int, n_gains: int) -> int:
        """Progress steps of a search (generations).

        Parameters
        ----------
        maxiter
            Generations.
        popsize
            Population multiplier (unused: one step per generation).
        n_gains
            Number of tuned gains (unused).
        """
        return maxiter

    def search(
        self, setup: _Setup, objective: _Objective, seed: int | None, sizes: tuple[int, int, float]
    ) -> Any:
        """Run the search; returns scipy's result (``x``, ``success``, ``message``).

        Parameters
        ----------
        setup
            The checked problem.
        objective
            The vectorised cost and its progress callback.
        seed
            Seed of the optimiser.
        sizes
            ``(popsize, maxiter, tol)``.
        """
        from scipy.optimize import differential_evolution
        from scipy.stats import qmc

        popsize, maxiter, tol = sizes
        rng = np.random.default_rng(seed)
        n_pop = max(popsize * len(setup.names), 5)
        sampler = qmc.LatinHypercube(d=len(setup.names), seed=rng)
        lows, highs = _box(setup)
        init = qmc.scale(sampler.random(n_pop), lows, highs)
        init[0] = np.clip([setup.base.gains[k] for k in setup.names], lows, highs)
        return differential_evolution(
            objective,
            list(setup.bounds),
            seed=seed,
            maxiter=maxiter,
            tol=tol,
            init=init,
            polish=False,
            vectorized=True,
            updating="deferred",
            callback=objective.callback,
        )


class NelderMeadTuner:
    """``method="nelder_mead"``: a bounded Nelder-Mead simplex from the defaults (local).

    The same budget of simulations as differential evolution with the same
    ``popsize`` and ``maxiter`` (``popsize x gains x (maxiter + 1)`` cost
    evaluations); ``tol`` is the absolute cost tolerance. Deterministic (the
    seed is not used). A local search: it refines the defaults rather than
    exploring the box.
    """

    name: ClassVar[str] = "nelder_mead"
    #: What one progress step is.
    step_label: ClassVar[str] = "iteration"

    @staticmethod
    def steps(maxiter: int, popsize: int, n_gains: int) -> int:
        """Progress steps of a search (simplex iterations, at most one per evaluation).

        Parameters
        ----------
        maxiter
            Generations of the equivalent differential evolution.
        popsize
            Population multiplier.
        n_gains
            Number of tuned gains.
        """
        return max(popsize * n_gains, 5) * (maxiter + 1)

    def search(
        self, setup: _Setup, objective: _Objective, seed: int | None, sizes: tuple[int, int, float]
    ) -> Any:
        """Run the search; returns scipy's result (``x``, ``success``, ``message``).

        Parameters
        ----------
        setup
            The checked problem.
        objective
            The vectorised cost and its progress callback.
        seed
            Not used (the simplex is deterministic).
        sizes
            ``(popsize, maxiter, tol)``.
        """
        from scipy.optimize import minimize

        popsize, maxiter, tol = sizes
        lows, highs = _box(setup)
        x0 = np.clip([setup.base.gains[k] for k in setup.names], lows, highs)
        budget = self.steps(maxiter, popsize, len(setup.names))
        return minimize(
            lambda x: float(objective(np.asarray(x)[:, None])[0]),
            x0,
            method="Nelder-Mead",
            bounds=list(setup.bounds),
            callback=objective.callback,
            options={"maxfev": budget, "fatol": tol, "xatol": 1e-4},
        )


#: The tether tuners by name: small strategy objects with ``steps`` and ``search``.
TUNERS: dict[str, Any] = {
    DifferentialEvolutionTuner.name: DifferentialEvolutionTuner,
    NelderMeadTuner.name: NelderMeadTuner,
}


def _box(setup: _Setup) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    return np.array([b[0] for b in setup.bounds]), np.array([b[1] for b in setup.bounds])


def _tuner(method: Any) -> Any:
    if not isinstance(method, str) or method not in TUNERS:
        raise InvalidParameterError("method", method, f"one of {tuple(TUNERS)}")
    return TUNERS[method]()


def _scenario_table(setup: _Setup, run: _Scenarios, tuned: TetherController) -> pd.DataFrame:
    """Cost parts of the default and tuned gains on the tuning and validation scenarios."""
    gain_sets = [{k: setup.base.gains[k] for k in setup.names}, tuned.gains]
    rows = []
    for set_name, plist in (("tuning", setup.paths), ("validation", setup.validation)):
        if not plist:
            continue
        tasks = setup.tasks(gain_sets, plist)
        for t, p in zip(tasks, run(tasks), strict=True):
            for j, who in enumerate(("default", "tuned")):
                rows.append(
                    {
                        "set": set_name,
                        "path": t["path_name"],
                        "speed_m_per_s": t["speed"],
                        "controller": who,
                        "cost": float(p["cost"][j]),
                        "cost_unpenalised": float(p["cost"][j] - p["penalty"][j]),
                        "npd_mean_over_b": float(p["deviation"][j]),
                        "npd_mean_m": float(p["npd_m"][j]),
                        "length_error_rms_over_ld": float(p["length"][j]),
                        "smoothness": float(p["smoothness"][j]),
                        "penalty": float(p["penalty"][j]),
                        "wheel_saturation": float(p["saturation"][j]),
                    }
                )
    return pd.DataFrame(rows)


def _mean_of(table: pd.DataFrame, set_name: str, who: str, col: str) -> float:
    sel = table[(table["set"] == set_name) & (table["controller"] == who)]
    return float(sel[col].mean()) if len(sel) else math.nan


def _violations(table: pd.DataFrame) -> dict[str, dict[str, int]]:
    return {
        set_name: {
            who: int(
                (
                    (table["set"] == set_name)
                    & (table["controller"] == who)
                    & (table["penalty"] > 1e-3)
                ).sum()
            )
            for who in ("default", "tuned")
        }
        for set_name in ("tuning", "validation")
    }


def _status(
    result: Any,
    zetas: dict[float, float],
    floor: float,
    improvement: float,
    setup: _Setup,
    tuning_saturation: float = 0.0,
) -> tuple:
    warns = [
        f"validation path {v} shares a stretch with tuning path {t} "
        f"({st.in_place:.2f} m in place, {100 * st.normalised:.0f} % normalised): "
        "it does not measure the gains on unseen paths"
        for v, t, st in overlapping_paths(setup.validation, setup.paths)
    ]
    status = TuningStatus.OK
    if not result.success:
        status = TuningStatus.NOT_CONVERGED
        warns.append(f"the search stopped: {result.message}")
    if min(zetas.values()) < floor - 1e-9:
        status = TuningStatus.INFEASIBLE
        warns.append(f"the tuned gains violate the damping floor {floor:g}")
    if tuning_saturation > setup.max_saturation:
        status = TuningStatus.INFEASIBLE
        warns.append(
            f"no gain set found keeps a wheel at its limit for at most "
            f"{100 * setup.max_saturation:g} % of every tuning run (tuned: "
            f"{100 * tuning_saturation:.1f} %)"
        )
    if not math.isfinite(improvement):
        warns.append("no validation paths: the improvement is not measured")
    elif improvement < 0:
        warns.append("the tuned gains are worse than the defaults on the validation paths")
    return status, warns


def _validation_warnings(table: pd.DataFrame, bound: float) -> list[str]:
    """What the validation scenarios show that the tuning cost did not: violations, NPD."""
    val = table[table["set"] == "validation"]
    if not len(val):
        return []
    out = []
    by = {who: val[val["controller"] == who] for who in ("default", "tuned")}
    bad = {who: int((g["penalty"] > 1e-3).sum()) for who, g in by.items()}
    if bad["tuned"] > bad["default"]:
        out.append(
            f"the tuned gains violate a constraint on {bad['tuned']} validation scenarios "
            f"(the defaults on {bad['default']})"
        )
    sat = float(by["tuned"]["wheel_saturation"].max())
    if sat > bound:
        worst = by["tuned"].loc[by["tuned"]["wheel_saturation"].idxmax()]
        out.append(
            f"the tuned gains hold a wheel at its speed limit for {100 * sat:.0f} % of a run on "
            f"{worst['path']} at {worst['speed_m_per_s']:g} m/s (bound {100 * bound:g} %)"
        )
    npd = {who: float(g["npd_mean_m"].mean()) for who, g in by.items()}
    if npd["tuned"] > npd["default"]:
        out.append(
            f"the tuned gains deviate more than the defaults on the validation paths "
            f"(mean NPD {npd['tuned']:.3f} m against {npd['default']:.3f} m)"
        )
    return out


def _summary(
    setup: _Setup, run: _Scenarios, objective: _Objective, result: Any, t_start: float
) -> TuningResult:
    """The tuned controller, its costs against the defaults, and the status."""
    tuned = setup.base.replace(**{k: float(v) for k, v in zip(setup.names, result.x, strict=True)})
    table = _scenario_table(setup, run, tuned)
    default_gains = {k: setup.base.gains[k] for k in setup.names}
    def_cost = _mean_of(table, "tuning", "default", "cost") + float(
        setup.damping_penalty([default_gains])[0]
    )
    tuned_cost = _mean_of(table, "tuning", "tuned", "cost") + float(
        setup.damping_penalty([tuned.gains])[0]
    )
    improvement = 1.0 - _mean_of(table, "validation", "tuned", "cost") / _mean_of(
        table, "validation", "default", "cost"
    )
    unpenalised = 1.0 - _mean_of(table, "validation", "tuned", "cost_unpenalised") / _mean_of(
        table, "validation", "default", "cost_unpenalised"
    )
    npd_impr = 1.0 - _mean_of(table, "validation", "tuned", "npd_mean_m") / _mean_of(
        table, "validation", "default", "npd_mean_m"
    )
    zetas = {v: damping_ratio(tuned, v, setup.robot.wheel_track) for v in setup.speeds}
    saturation = {
        set_name: {
            who: float(
                table[(table["set"] == set_name) & (table["controller"] == who)][
                    "wheel_saturation"
                ].max()
            )
            for who in ("default", "tuned")
        }
        for set_name in ("tuning", "validation")
    }
    status, warns = _status(
        result, zetas, setup.damping_floor, improvement, setup, saturation["tuning"]["tuned"]
    )
    warns += _validation_warnings(table, setup.max_saturation)
    return TuningResult(
        controller=tuned,
        default=setup.base,
        cost=tuned_cost,
        default_cost=def_cost,
        improvement=improvement,
        training_improvement=1.0 - tuned_cost / def_cost,
        npd_improvement=npd_impr,
        violations=_violations(table),
        scenarios=table,
        damping_ratios=zetas,
        history=tuple(objective.history),
        evaluations=objective.evaluations,
        wall_time=time.perf_counter() - t_start,
        evaluated=objective.evaluated_frame(),
        status=status,
        warnings=tuple(warns),
        improvement_unpenalised=unpenalised,
        saturation=saturation,
        max_saturation=setup.max_saturation,
    )


def tune(
    controller: type[TetherController] | TetherController,
    paths: Sequence[LeaderPath | str | dict[str, Any]],
    speeds: Sequence[float] = (0.5,),
    *,
    robot: FollowerRobot | None = None,
    bounds: dict[str, tuple[float, float]] | None = None,
    weights: dict[str, float] | None = None,
    damping_floor: float = DAMPING_FLOOR.default,
    tether_range: tuple[float, float] = (0.2, 2.0),
    max_saturation: float = MAX_SATURATION.default,
    validation_paths: Sequence[LeaderPath | str | dict[str, Any]] | None = None,
    method: str = "differential_evolution",
    seed: int = SEED.default,
    popsize: int = POPSIZE.default,
    maxiter: int = MAXITER.default,
    tol: float = TOLERANCE.default,
    executor: Any = None,
    progress: ProgressHook | None = None,
) -> TuningResult:
    """Tune the gains of a tether-follower law over paths and speeds.

    Parameters
    ----------
    controller
        The law (a class, whose defaults are the thesis's App. C values), or
        an instance whose non-gain fields (``desired_length``, buffer) are kept
        and whose gains start the search.
    paths
        Tuning paths (:class:`LeaderPath`, names or dicts for :func:`make_path`).
    speeds
        Leader speeds in m/s.
    robot
        The robot (default :data:`OXYDOG`: the 1.0 m/s wheel limit of Table 3.1).
    bounds
        Gain bounds (default: the law's ``BOUNDS``: gains 0.1-20 1/s, K_a 0-1/pi;
        the look-ahead within the thesis's rule b-2b, Sec. 2.3.2.2; pass
        ``{"lookahead": (0.05, 1.0)}`` to explore beyond it).
    weights
        Cost weights ``deviation``, ``length``, ``smoothness`` (:class:`CostWeights`).
    damping_floor
        Least damping ratio of the linear lateral loop at every speed (:data:`DAMPING_FLOOR`).
    tether_range
        Allowed tether length ``(min, max)`` in m (Table 1.1: 0.2-1.0 m "or
        greater"); leaving it is penalised.
    max_saturation
        Largest fraction of a run with a wheel at its speed limit (a
        constraint: 10 x the excess is added to the cost; :data:`MAX_SATURATION`).
    validation_paths
        Paths for the improvement (default: :func:`default_validation`, paths
        that share no stretch with ``paths``; a given path that does is
        reported in the warnings).
    method
        The search, one of :data:`TUNERS`: ``"differential_evolution"``
        (default, global) or ``"nelder_mead"`` (a local simplex from the defaults
        with the same simulation budget).
    seed
        Seed of the optimiser (results are reproducible).
    popsize, maxiter, tol
        Differential-evolution population multiplier, generations and
        relative tolerance (scipy; :data:`POPSIZE`, :data:`MAXITER`, :data:`TOLERANCE`).
    executor
        Runs the scenarios of a generation (``map_unordered``); default serial.
    progress
        Called with a :class:`~designlab.progress.Progress` after each generation
        (its best cost).

    Returns
    -------
    TuningResult
    """
    t_start = time.perf_counter()
    setup = _checked_setup(
        controller,
        paths,
        speeds,
        {
            "robot": robot,
            "bounds": bounds,
            "weights": weights,
            "damping_floor": damping_floor,
            "tether_range": tether_range,
            "max_saturation": max_saturation,
            "validation_paths": validation_paths,
        },
    )
    tuner = _tuner(method)
    seed, popsize = SEED.check(seed), POPSIZE.check(popsize)
    maxiter, tol = MAXITER.check(maxiter), TOLERANCE.check(tol)
    run = _Scenarios(executor)
    total = tuner.steps(maxiter, popsize, len(setup.names))
    objective = _Objective(setup, run, total, progress)
    objective.label = tuner.step_label
    result = tuner.search(setup, objective, seed, (popsize, maxiter, tol))
    return _summary(setup, run, objective, result, t_start)
