"""Gain tuning of the tether follower laws (derivative-free, seeded).

Allan 2015 tuned its gains by hand, one parameter at a time (Sec. 2.5, 6.1 of
the project's notes); App. C holds the only numbers. :func:`tune` searches the
gains of one law with scipy's differential evolution over several leader paths
and speeds. Every generation is one batched simulation per (path, speed)
scenario (:func:`designlab.following.simulate_batch`), and the scenarios can
be spread over the project's executors (anything with ``map_unordered``,
e.g. :func:`designlab.analysis.executors.make_executor`).

The cost of a gain set is the mean over the scenarios of

* ``deviation``: mean normal path deviation in wheel tracks (App. A; the
  thesis's primary metric),
* ``length``: RMS(l_m - l_d)/l_d (the cannula length),
* ``smoothness``: RMS(dV/dt) [m/s^2] + 0.1 RMS(dOmega/dt) [rad/s^2] (the
  "jerky" bursts of Sec. 2.5.1),

weighted by ``weights``, plus penalties for leaving the tether range, for
wheels at their speed limit and for a failed run; and a constraint: the
damping ratio of the linearised lateral loop (:mod:`tether_linear`) must be
at least ``damping_floor`` at every tuning speed, so that tuned gains do not
weave. The thesis defaults are part of the initial population, so the tuned
cost on the tuning scenarios is never worse than theirs. The improvement is
reported on validation paths that were not tuned on.

Examples
--------
>>> from designlab.following import FollowTheLeader, figure_eight, slalom
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
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError, check_nonnegative, check_positive
from designlab.following.path_deviation import normal_path_deviation
from designlab.following.paths import LeaderPath, figure_eight, make_path, slalom, square_s
from designlab.following.tether_controllers import CONTROLLERS, TetherController
from designlab.following.tether_linear import damping_ratio
from designlab.following.tether_model import OXYDOG, FollowerRobot
from designlab.following.tether_simulate import simulate_batch
from designlab.results import Result

__all__ = ["DEFAULT_WEIGHTS", "TuningResult", "scenario_costs", "tune"]

logger = logging.getLogger(__name__)

#: Default cost weights.
DEFAULT_WEIGHTS = {"deviation": 1.0, "length": 0.5, "smoothness": 0.05}
_FAILED = 1e3


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
        ``1 - J/J_default`` over the validation scenarios (paths not tuned
        on), with J the weighted deviation + length + smoothness cost
        without the constraint penalties (so that one scenario where the
        defaults leave the tether range does not dominate); positive is better.
    training_improvement
        ``1 - cost/default_cost`` over the tuning scenarios (penalties included).
    violations
        Scenarios where the default and the tuned gains leave the tether range
        or saturate a wheel (``{"default": n, "tuned": n}`` per set).
    npd_improvement
        ``1 - mean NPD (tuned)/mean NPD (default)`` over the validation scenarios.
    scenarios
        Per scenario and controller: the cost and its parts.
    damping_ratios
        Linear lateral damping ratio of the tuned gains at each tuning speed.
    history
        Best cost after each generation.
    evaluations
        Gain sets simulated (per scenario).
    wall_time
        Seconds.
    status
        ``"ok"``, or ``"not_converged"`` when the search used all its generations.
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
    status: str = "ok"
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """The per-scenario table (``set`` is ``tuning`` or ``validation``)."""
        return self.scenarios


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
        ``length``, ``smoothness``, ``penalty``.
    """
    cls = CONTROLLERS[task["law"]]
    base = {k: v for k, v in task["base"].items() if k != "type"}
    ctrls = [cls(**{**base, **g}) for g in task["gains"]]
    robot = FollowerRobot(**task["robot"])
    path = LeaderPath(np.asarray(task["path"]), name=task.get("path_name", "path"))
    speed = float(task["speed"])
    w = task["weights"]
    lo, hi = task["tether_range"]
    batch = simulate_batch(
        ctrls, path, speed=speed, robot=robot, settle_time=task.get("settle_time", 4.0)
    )
    nb = len(ctrls)
    out = {
        k: np.zeros(nb) for k in ("cost", "deviation", "npd_m", "length", "smoothness", "penalty")
    }
    dt = robot.sample_time
    b = robot.wheel_track
    for i in range(nb):
        if batch.member_status[i] != "ok":
            for k in out:
                out[k][i] = _FAILED
            continue
        npd = normal_path_deviation(batch.leader_xy, batch.robot_xy[i], wheel_track=b)
        ld = ctrls[i].desired_length
        lm = batch.tether_length[i]
        dev = npd.mean_over_b if npd.status == "ok" else 10.0
        length = float(np.sqrt(np.mean((lm - ld) ** 2))) / ld
        smooth = float(np.sqrt(np.mean((np.diff(batch.speed[i]) / dt) ** 2))) + 0.1 * float(
            np.sqrt(np.mean((np.diff(batch.turn_rate[i]) / dt) ** 2))
        )
        pen = 10.0 * (max(0.0, lo - float(lm.min())) + max(0.0, float(lm.max()) - hi)) / ld
        if robot.max_wheel_speed < math.inf:
            wsat = (
                np.abs(batch.speed[i]) + 0.5 * b * np.abs(batch.turn_rate[i])
            ) / robot.wheel_radius
            pen += float(np.mean(wsat >= robot.max_wheel_speed * (1 - 1e-9)))
        out["deviation"][i] = dev
        out["npd_m"][i] = npd.mean
        out["length"][i] = length
        out["smoothness"][i] = smooth
        out["penalty"][i] = pen
        out["cost"][i] = (
            w["deviation"] * dev + w["length"] * length + w["smoothness"] * smooth + pen
        )
    return out


def _default_validation(paths: Sequence[LeaderPath]) -> list[LeaderPath]:
    names = {p.name for p in paths}
    cands = [
        figure_eight(a=2.0),
        figure_eight(a=4.0),
        square_s(),
        slalom(),
        slalom(out_and_back=True),
    ]
    return [p for p in cands if p.name not in names][:3]


def tune(
    controller: type[TetherController] | TetherController,
    paths: Sequence[LeaderPath | str | dict[str, Any]],
    speeds: Sequence[float] = (0.5,),
    *,
    robot: FollowerRobot | None = None,
    bounds: dict[str, tuple[float, float]] | None = None,
    weights: dict[str, float] | None = None,
    damping_floor: float = 0.5,
    tether_range: tuple[float, float] = (0.2, 2.0),
    validation_paths: Sequence[LeaderPath | str | dict[str, Any]] | None = None,
    seed: int = 0,
    popsize: int = 6,
    maxiter: int = 12,
    tol: float = 0.01,
    executor: Any = None,
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
        Cost weights ``deviation``, ``length``, ``smoothness`` (see the module notes).
    damping_floor
        Least damping ratio of the linear lateral loop at every speed (>= 0).
    tether_range
        Allowed tether length ``(min, max)`` in m (Table 1.1: 0.2-1.0 m "or
        greater"); leaving it is penalised.
    validation_paths
        Paths for the improvement (default: three of the thesis paths not in
        ``paths``).
    seed
        Seed of the optimiser (results are reproducible).
    popsize, maxiter, tol
        Differential-evolution population multiplier, generations and
        relative tolerance (scipy).
    executor
        Runs the scenarios of a generation (``map_unordered``); default serial.

    Returns
    -------
    TuningResult
    """
    from scipy.optimize import differential_evolution
    from scipy.stats import qmc

    t_start = time.perf_counter()
    if isinstance(controller, type) and issubclass(controller, TetherController):
        base = controller()
    elif isinstance(controller, TetherController):
        base = controller
    else:
        raise InvalidParameterError(
            "controller", controller, "a tether controller class or instance"
        )
    cls = type(base)
    paths_l = [make_path(p) for p in paths]
    if not paths_l:
        raise InvalidParameterError("paths", paths, "at least one path")
    speeds_l = [check_positive("speeds[]", v, "m/s") for v in speeds]
    if not speeds_l:
        raise InvalidParameterError("speeds", speeds, "at least one speed")
    robot = robot or OXYDOG
    w = dict(DEFAULT_WEIGHTS)
    for k, v in (weights or {}).items():
        if k not in w:
            raise InvalidParameterError(f"weights.{k}", v, f"one of {sorted(w)}")
        w[k] = check_nonnegative(f"weights.{k}", v)
    damping_floor = check_nonnegative("damping_floor", damping_floor)
    lo_l, hi_l = (check_positive("tether_range[]", v, "m") for v in tether_range)
    if hi_l <= lo_l:
        raise InvalidParameterError("tether_range", tether_range, "(min, max) with min < max", "m")
    bnds = dict(cls.BOUNDS)
    if "lookahead" in bnds:
        # the thesis's rule b < delta < 2b (Allan 2015 Sec. 2.3.2.2)
        bnds["lookahead"] = (robot.wheel_track, 2.0 * robot.wheel_track)
    for k, v in (bounds or {}).items():
        if k not in cls.GAINS:
            raise InvalidParameterError(f"bounds.{k}", v, f"one of {list(cls.GAINS)}")
        lo, hi = (float(x) for x in v)
        if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo < hi):
            raise InvalidParameterError(f"bounds.{k}", v, "finite (low, high) with 0 <= low < high")
        bnds[k] = (lo, hi)
    names = list(cls.GAINS)
    de_bounds = [bnds[k] for k in names]
    val_l = (
        [make_path(p) for p in validation_paths]
        if validation_paths is not None
        else _default_validation(paths_l)
    )
    base_fields = base.as_dict()
    robot_fields = robot.as_dict()
    weights_t = dict(w)

    def tasks_for(
        gain_sets: list[dict[str, float]], plist: list[LeaderPath]
    ) -> list[dict[str, Any]]:
        return [
            {
                "law": cls.__name__,
                "base": base_fields,
                "gains": gain_sets,
                "path": p.points,
                "path_name": p.name,
                "speed": v,
                "robot": robot_fields,
                "weights": weights_t,
                "tether_range": (lo_l, hi_l),
            }
            for p in plist
            for v in speeds_l
        ]

    def run_tasks(tasks: list[dict[str, Any]]) -> list[dict[str, Any]]:
        if executor is None:
            return [scenario_costs(t) for t in tasks]
        res: list[Any] = [None] * len(tasks)
        for i, r in executor.map_unordered(scenario_costs, tasks):
            res[i] = r
        return res

    def damping_penalty(gain_sets: list[dict[str, float]]) -> NDArray[np.float64]:
        pen = np.zeros(len(gain_sets))
        for i, g in enumerate(gain_sets):
            c = base.replace(**g)
            for v in speeds_l:
                pen[i] += 100.0 * max(0.0, damping_floor - damping_ratio(c, v, robot.wheel_track))
        return pen

    evaluations = 0
    history: list[float] = []

    def objective(x: NDArray[np.float64]) -> NDArray[np.float64]:
        nonlocal evaluations
        x = np.atleast_2d(x.T).T if x.ndim == 1 else x
        gain_sets = [{k: float(x[j, i]) for j, k in enumerate(names)} for i in range(x.shape[1])]
        evaluations += len(gain_sets)
        parts = run_tasks(tasks_for(gain_sets, paths_l))
        cost = np.mean([p["cost"] for p in parts], axis=0) + damping_penalty(gain_sets)
        return cost

    def callback(intermediate_result: Any) -> None:
        history.append(float(intermediate_result.fun))

    rng = np.random.default_rng(seed)
    n_pop = max(popsize * len(names), 5)
    sampler = qmc.LatinHypercube(d=len(names), seed=rng)
    lows = np.array([b[0] for b in de_bounds])
    highs = np.array([b[1] for b in de_bounds])
    init = qmc.scale(sampler.random(n_pop), lows, highs)
    init[0] = np.clip([base.gains[k] for k in names], lows, highs)
    result = differential_evolution(
        objective,
        de_bounds,
        seed=seed,
        maxiter=maxiter,
        tol=tol,
        init=init,
        polish=False,
        vectorized=True,
        updating="deferred",
        callback=callback,
    )
    tuned = base.replace(**{k: float(v) for k, v in zip(names, result.x, strict=True)})
    default_gains = {k: base.gains[k] for k in names}
    tuned_gains = tuned.gains

    rows = []
    for set_name, plist in (("tuning", paths_l), ("validation", val_l)):
        if not plist:
            continue
        parts = run_tasks(tasks_for([default_gains, tuned_gains], plist))
        for t, p in zip(tasks_for([default_gains, tuned_gains], plist), parts, strict=True):
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
                    }
                )
    table = pd.DataFrame(rows)

    def mean_of(set_name: str, who: str, col: str) -> float:
        sel = table[(table["set"] == set_name) & (table["controller"] == who)]
        return float(sel[col].mean()) if len(sel) else math.nan

    def_cost = mean_of("tuning", "default", "cost") + float(damping_penalty([default_gains])[0])
    tuned_cost = mean_of("tuning", "tuned", "cost") + float(damping_penalty([tuned_gains])[0])
    improvement = 1.0 - mean_of("validation", "tuned", "cost_unpenalised") / mean_of(
        "validation", "default", "cost_unpenalised"
    )
    violations = {
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
    npd_impr = 1.0 - mean_of("validation", "tuned", "npd_mean_m") / mean_of(
        "validation", "default", "npd_mean_m"
    )
    zetas = {v: damping_ratio(tuned, v, robot.wheel_track) for v in speeds_l}
    warns = []
    status = "ok"
    if not result.success:
        status = "not_converged"
        warns.append(f"differential evolution stopped: {result.message}")
    if min(zetas.values()) < damping_floor - 1e-9:
        status = "infeasible"
        warns.append(f"the tuned gains violate the damping floor {damping_floor:g}")
    if not math.isfinite(improvement):
        warns.append("no validation paths: the improvement is not measured")
    elif improvement < 0:
        warns.append("the tuned gains are worse than the defaults on the validation paths")
    return TuningResult(
        controller=tuned,
        default=base,
        cost=tuned_cost,
        default_cost=def_cost,
        improvement=improvement,
        training_improvement=1.0 - tuned_cost / def_cost,
        npd_improvement=npd_impr,
        violations=violations,
        scenarios=table,
        damping_ratios=zetas,
        history=tuple(history),
        evaluations=evaluations,
        wall_time=time.perf_counter() - t_start,
        status=status,
        warnings=tuple(warns),
    )
