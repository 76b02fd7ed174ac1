"""Monte Carlo studies of robots among crowds: every scenario x density x seed x method.

:func:`crowd_study` simulates each run (a crowd from the pedestrian simulator, the robot with
one navigation method), measures it (:mod:`~designlab.navigation.crowds.metrics`) and
summarises the runs per scenario, density and method with Wilson intervals on the rates
(:meth:`CrowdStudy.to_frame`). The runs go through the sweep engine
(:func:`designlab.analysis.engine.run_points`): serially, in local processes or on Dask
(``executor``), with finished chunks kept in a result store (``store``, ``resume``).

A *method label* is a navigation method (``"vff"``, ``"cbf"``, ``"masoud"``, ``"ge_cui"``)
or ``"<method>:<tag>"`` to compare gain sets of one method (``"vff:thesis"``,
``"vff:crowd"``); ``gains`` maps labels to gains (a method without gains uses its
default: :data:`~designlab.navigation.OPTIMAL_GAINS` for ``vff``, the experiment gains for
the attractive part of ``cbf``, Table C.1 for the baselines).

Outcomes of a run are exclusive, its first event
(:data:`~designlab.navigation.crowds.simulate.OUTCOMES`): ``success`` (it arrived),
``collision`` (it touched a pedestrian or wall), ``left_area`` (it left the walkable area),
``simulator_failed`` (JuPedSim stopped), else ``timeout``. ``critical`` (it entered a
critical region) and ``coupling_exceeded`` (the pedestrians did not see the robot where it
was: :data:`~designlab.navigation.crowds.simulate.AGENT_OFFSET_BOUND`) are counted
separately.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from designlab.analysis.engine import run_points
from designlab.errors import InvalidParameterError
from designlab.navigation.crowds.decide import cell_keys
from designlab.navigation.crowds.faced import (
    faced_by,
    faced_by_runs,
    measurement_band,
    voronoi_density,
)
from designlab.navigation.crowds.field_metrics import run_measures, spl
from designlab.navigation.crowds.layouts import LAYOUTS
from designlab.navigation.crowds.metrics import (
    CONFIDENCE,
    PERSONAL_SPACE,
    clearance,
    path_deviation,
    pedestrian_delay,
    personal_space_time,
    wilson_interval,
)
from designlab.navigation.crowds.scenario import DENSITY, CrowdScenario, check_crowd_options, crowd
from designlab.navigation.crowds.simulate import CROWD_METHOD, simulate_crowd, simulate_pedestrians
from designlab.navigation.methods import METHOD, METHODS, STABILISING
from designlab.navigation.parameters import OPTIMAL_GAINS
from designlab.params import ARG, Param, params_of
from designlab.progress import Progress, ProgressHook, report
from designlab.results import Result, Status

__all__ = [
    "OUTCOMES",
    "RATES",
    "CrowdStudy",
    "CrowdStudyStatus",
    "abnormal_runs",
    "decode_gains",
    "encode_gains",
    "method_name",
    "run_row",
    "summarise_runs",
    "worst_run",
]

logger = logging.getLogger(__name__)

#: Exclusive outcomes of a run (see the module text).
OUTCOMES = ("success", "collision", "timeout", "left_area", "simulator_failed")
#: A crowd run's outcome (:data:`~designlab.navigation.crowds.simulate.OUTCOMES`) by its
#: name in a study.
_OUTCOME_OF_RUN = {
    "arrived": "success",
    "collision": "collision",
    "timeout": "timeout",
    "left_area": "left_area",
    "simulator_failed": "simulator_failed",
}
#: Runs of a study chunk whose crowd met is measured in one pedpy call
#: (:func:`~designlab.navigation.crowds.faced.faced_by_runs`: pedpy's per-call cost, about
#: 20 ms, is paid once for them; the records of that many runs are held until then).
FACED_BATCH = 16
#: Rates summarised with Wilson intervals: column of the runs -> rate name.
RATES = {
    "success": "success",
    "collided": "collision",
    "timeout": "timeout",
    "left_area": "left_area",
    "simulator_failed": "simulator_failed",
    "critical": "critical",
    "coupling_exceeded": "coupling_exceeded",
}
#: Gains classes by the ``type`` of their plain-data form: the unfiltered force-field methods
#: of :data:`~designlab.navigation.methods.METHODS` (a filtered method takes its nominal's).
GAIN_TYPES: dict[str, type] = {
    m.name: m.gains_type for m in METHODS.variants(force_field=True, filtered=False)
}


class CrowdStudyStatus(Status):
    """Status of a crowd study.

    ``OK``: every run finished (whatever its outcome); ``FAILED_RUNS``: some runs raised
    (their rows say ``status: error`` and why); ``EMPTY``: no runs.
    """

    OK = "ok"
    FAILED_RUNS = "failed_runs"
    EMPTY = "empty"


def method_name(label: str) -> str:
    """The navigation method of a label (``"vff:thesis"`` -> ``"vff"``).

    Parameters
    ----------
    label
        A method label.

    Examples
    --------
    >>> method_name("vff:crowd"), method_name("cbf")
    ('vff', 'cbf')
    """
    return str(label).split(":", 1)[0]


def encode_gains(gains: Any) -> dict[str, Any] | None:
    """Gains as plain data (for options sent to workers and for YAML).

    Parameters
    ----------
    gains
        :class:`VFFGains`, :class:`MasoudGains`, :class:`GeCuiGains` or ``None``.

    Examples
    --------
    >>> from designlab.navigation.parameters import VFFGains
    >>> encode_gains(VFFGains(4.3, 0.68, 20.3, 240.7))
    {'type': 'vff', 'k1': 4.3, 'b': 0.68, 'k3': 20.3, 'k5': 240.7}
    """
    if gains is None:
        return None
    for name, cls in GAIN_TYPES.items():
        if isinstance(gains, cls):
            return {"type": name, **asdict(gains)}
    raise InvalidParameterError(
        "gains", gains, f"must be one of {[c.__name__ for c in GAIN_TYPES.values()]}"
    )


def decode_gains(data: Mapping[str, Any] | None) -> Any:
    """The gains object of :func:`encode_gains`'s plain data.

    Parameters
    ----------
    data
        ``{"type": "vff", "k1": ..., ...}`` or ``None``.

    Examples
    --------
    >>> decode_gains({"type": "vff", "k1": 3.0, "b": 0.25, "k3": 20.0, "k5": 17.0}).k5
    17.0
    """
    if data is None:
        return None
    fields = dict(data)
    cls = GAIN_TYPES.get(str(fields.pop("type", "")))
    if cls is None:
        raise InvalidParameterError(
            "gains.type", data.get("type"), f"must be one of {list(GAIN_TYPES)}"
        )
    return cls(**fields)


def run_row(result: Any, pedestrians: Any = None, *, personal_space: float = PERSONAL_SPACE.default,
            robot_radius: float = 0.0, faced: bool = True) -> dict[str, Any]:  # fmt: skip
    """The metrics of one crowd run, as one row.

    Parameters
    ----------
    result
        A crowd run: ``arrival_time``, ``collided``, ``entered_critical``, ``min_distance``,
        ``status``, ``times``, ``robot_positions``, ``pedestrian_positions``.
    pedestrians
        The same crowd simulated without the robot (``times``, ``pedestrian_positions``) for
        the delay and path deviation the robot causes; ``None``: those are NaN.
    personal_space
        Radius of a pedestrian's personal space (m, :data:`PERSONAL_SPACE`).
    robot_radius
        The robot's radius (m): personal space counts when its disc enters.
    faced
        ``False``: leave out the two measures of the crowd met (a study measures its runs
        together with :func:`~designlab.navigation.crowds.faced.faced_by_runs`).

    Returns
    -------
    dict
        ``outcome`` (see the module text); ``success``, ``collided``, ``timeout``,
        ``left_area``, ``simulator_failed`` (the outcome, 0/1), ``critical``,
        ``coupling_exceeded`` (0/1), ``outcome_time_s``,
        ``arrival_time_s``, ``min_distance_m`` (the run's own), ``min_centre_distance_m``
        (robot to nearest pedestrian centre), ``personal_space_s``, ``ped_delay_mean_s``,
        ``ped_delay_max_s``, ``ped_beyond_window``, ``ped_deviation_mean_m``,
        ``ped_deviation_max_m``, ``run_status``; ``measured_density_per_m2`` and
        ``mean_ped_speed_m_per_s``: the density and speed of the pedestrians the robot met
        (pedpy, in the band along its path: :func:`~designlab.navigation.crowds.faced.faced_by`;
        NaN for a result without its ``crowd``); ``critical_time_s``,
        ``min_surface_distance_m`` and ``goal_distance_m`` (at the run's end) for the tuning.
    """
    t = np.asarray(result.times, dtype=float)
    robot, peds = result.robot_positions, result.pedestrian_positions
    collided, arrived = bool(result.collided), bool(np.isfinite(result.arrival_time))
    outcome = _OUTCOME_OF_RUN.get(
        getattr(result, "outcome", ""),
        "collision" if collided else ("success" if arrived else "timeout"),
    )
    row: dict[str, Any] = {
        "outcome": outcome,
        **{("collided" if o == "collision" else o): float(outcome == o) for o in OUTCOMES},
        "critical": float(bool(result.entered_critical)),
        "coupling_exceeded": float(bool(getattr(result, "coupling_exceeded", False))),
        "outcome_time_s": float(getattr(result, "outcome_time", math.nan)),
        "arrival_time_s": float(result.arrival_time),
        "min_distance_m": float(np.min(result.min_distance)),
        "min_centre_distance_m": float(np.min(clearance(robot, peds))),
        "personal_space_s": personal_space_time(t, robot, peds, personal_space, robot_radius),
        "run_status": str(result.status),
    }
    row.update(_caused(t, peds, pedestrians, getattr(result, "pedestrian_ids", None)))
    if getattr(result, "crowd", None) is not None:
        row.update(run_measures(result, personal_space))
        row["free_run_s"] = float(result.crowd.free_run_time)
        row["time_limit_s"] = float(result.crowd.time_limit)
        row.update(_violation_measures(result))
    if faced:
        row.update(_faced(result))
    return row


def _violation_measures(result: Any) -> dict[str, float]:
    """What the crowd gain tuning penalises (:mod:`~designlab.navigation.crowds.tuning`): the
    time inside critical regions, the smallest surface distance to a pedestrian (<= 0: a
    collision, its depth) and the distance left to the goal when the run ended."""
    goal = np.asarray(result.crowd.robot_goal, dtype=float)
    last = np.asarray(result.robot_positions, dtype=float)[-1]
    return {
        "critical_time_s": float(getattr(result, "critical_time", math.nan)),
        "min_surface_distance_m": float(getattr(result, "min_surface_distance", math.nan)),
        "goal_distance_m": float(np.hypot(*(goal - last))),
    }


def _faced(result: Any) -> dict[str, float]:
    """The measured density and pedestrian speed of :func:`faced_by` (NaN without a crowd)."""
    if getattr(result, "crowd", None) is None:
        return {"measured_density_per_m2": math.nan, "mean_ped_speed_m_per_s": math.nan}
    f = faced_by(result)
    return {
        "measured_density_per_m2": f.measured_density_per_m2,
        "mean_ped_speed_m_per_s": f.mean_ped_speed_m_per_s,
    }


def _common(peds: Any, ids: Any, alone: Any) -> tuple[np.ndarray, np.ndarray]:
    """Both runs' positions of the pedestrians present in both, matched by id (a stream may
    spawn a different number of pedestrians once the robot changes the flow)."""
    a = np.asarray(peds, dtype=float)
    b = np.asarray(alone.pedestrian_positions, dtype=float)
    ia = np.arange(a.shape[1]) if ids is None else np.asarray(ids)
    ib = np.asarray(getattr(alone, "pedestrian_ids", np.arange(b.shape[1])))
    both = np.intersect1d(ia, ib)
    pos_a = {v: k for k, v in enumerate(ia.tolist())}
    pos_b = {v: k for k, v in enumerate(ib.tolist())}
    return a[:, [pos_a[v] for v in both.tolist()]], b[:, [pos_b[v] for v in both.tolist()]]


def _caused(t: np.ndarray, peds: Any, alone: Any, ids: Any = None) -> dict[str, float]:
    """Delay and path deviation of the pedestrians caused by the robot (NaN without ``alone``)."""
    if alone is None:
        return dict.fromkeys(("ped_delay_mean_s", "ped_delay_max_s", "ped_beyond_window",
                              "ped_deviation_mean_m", "ped_deviation_max_m"), math.nan)  # fmt: skip
    peds, other = _common(peds, ids, alone)
    n = min(t.size, other.shape[0])
    delay = pedestrian_delay(t[:n], peds, other)
    dev = path_deviation(t[:n], peds, other)
    return {
        "ped_delay_mean_s": delay["mean_s"],
        "ped_delay_max_s": delay["max_s"],
        "ped_beyond_window": delay["beyond_window"],
        "ped_deviation_mean_m": dev["mean_m"],
        "ped_deviation_max_m": dev["max_m"],
    }


def _rate_columns(group: pd.DataFrame, confidence: float) -> dict[str, float]:
    out: dict[str, float] = {}
    n = len(group)
    for column, name in RATES.items():
        k = int(group[column].sum())
        lo, hi = wilson_interval(k, n, confidence)
        out.update(
            {f"{name}_rate": k / n if n else math.nan, f"{name}_low": lo, f"{name}_high": hi}
        )
    return out


def _distribution_columns(group: pd.DataFrame) -> dict[str, float]:
    arrived = group.loc[group["success"] > 0, "arrival_time_s"]
    d = group["min_centre_distance_m"].to_numpy(dtype=float)
    return {
        "time_to_goal_mean_s": float(arrived.mean()) if len(arrived) else math.nan,
        "time_to_goal_median_s": float(arrived.median()) if len(arrived) else math.nan,
        "clearance_min_m": float(np.min(d)) if d.size else math.nan,
        "clearance_p05_m": float(np.quantile(d, 0.05)) if d.size else math.nan,
        "clearance_median_m": float(np.median(d)) if d.size else math.nan,
        "personal_space_mean_s": float(group["personal_space_s"].mean()),
        "ped_delay_mean_s": float(group["ped_delay_mean_s"].mean()),
        "ped_deviation_mean_m": float(group["ped_deviation_mean_m"].mean()),
        "measured_density_per_m2": _mean(group, "measured_density_per_m2"),
        "mean_ped_speed_m_per_s": _mean(group, "mean_ped_speed_m_per_s"),
        **_field_columns(group),
    }


def _field_columns(group: pd.DataFrame) -> dict[str, float]:
    """The field's metrics over a cell's runs (NaN where a store lacks them)."""
    out = {f"{c}_mean": _mean(group, c) for c in _FIELD_MEANS}
    if {"success", "shortest_m", "path_length_m"} <= set(group):
        g = group[np.isfinite(group["path_length_m"].to_numpy(dtype=float))]
        out["spl"] = (
            float(spl(g["success"], g["shortest_m"], g["path_length_m"])) if len(g) else math.nan
        )
    else:
        out["spl"] = math.nan
    for who in ("robot", "pedestrian", "wall"):
        col = group.get("collision_by")
        out[f"collisions_by_{who}"] = float((col == who).sum()) if col is not None else math.nan
        col = group.get("critical_by")
        out[f"critical_by_{who}"] = float((col == who).sum()) if col is not None else math.nan
    out["voronoi_density_per_m2"] = _mean(group, "voronoi_density_per_m2")
    return out


#: Run columns averaged per cell (``<column>_mean``).
_FIELD_MEANS = ("path_length_m", "accel_mean", "jerk_mean", "discomfort_share",
                "intrusion_share", "ttc_min_s", "frozen")  # fmt: skip


def _mean(group: pd.DataFrame, column: str) -> float:
    """Mean of a column over the runs that have it (NaN if none; absent in old stores)."""
    if column not in group:
        return math.nan
    v = group[column].to_numpy(dtype=float)
    v = v[np.isfinite(v)]
    return float(v.mean()) if v.size else math.nan


def check_runs_frame(runs: Any, columns: Sequence[str]) -> None:
    """Refuse what is not a runs frame of a crowd study (naming the missing columns).

    Parameters
    ----------
    runs
        The frame given.
    columns
        The columns it must have.
    """
    if not isinstance(runs, pd.DataFrame):
        raise InvalidParameterError("runs", runs, "must be the runs DataFrame of a CrowdStudy")
    missing = [c for c in columns if c not in runs.columns]
    if missing:
        raise InvalidParameterError(
            "runs", f"columns {list(runs.columns)[:12]}", f"must have the columns {missing}"
        )


#: The columns of :func:`run_row` that the summary reads.
_METRIC_COLUMNS = (*RATES, "arrival_time_s", "min_centre_distance_m", "personal_space_s",
                   "ped_delay_mean_s", "ped_deviation_mean_m")  # fmt: skip


def summarise_runs(runs: pd.DataFrame, confidence: float = CONFIDENCE.default) -> pd.DataFrame:
    """One row per cell (pedestrian model when the runs have it, scenario, density) and method:
    rates with Wilson intervals and distributions.

    Parameters
    ----------
    runs
        One row per run: ``scenario``, ``density``, ``method`` and the columns of
        :func:`run_row` (runs with ``status == "error"`` are left out and counted).
    confidence
        Confidence level of the intervals.

    Returns
    -------
    DataFrame
        ``runs``, ``failed``, ``<rate>_rate``, ``<rate>_low``, ``<rate>_high`` for success,
        collision, critical and timeout, ``time_to_goal_mean_s``, ``time_to_goal_median_s``
        (successful runs), ``clearance_min_m``, ``clearance_p05_m``, ``clearance_median_m``
        (robot to nearest pedestrian centre over a run, distribution over runs),
        ``personal_space_mean_s``, ``ped_delay_mean_s``, ``ped_deviation_mean_m``,
        ``measured_density_per_m2`` and ``mean_ped_speed_m_per_s`` (the crowd the robot met,
        pedpy: mean over the runs; compare with the nominal ``density``).
    """
    check_runs_frame(runs, ("scenario", "density", "method"))
    CONFIDENCE.check(confidence)
    keys = [*cell_keys(runs), "method"]
    failed = (
        runs["status"].astype(str) == "error"
        if "status" in runs
        else pd.Series(False, index=runs.index)
    )
    rows = []
    # a grid whose every run failed has no metric column: its rates are 0 of 0 runs
    runs = runs.reindex(columns=[*runs.columns, *(c for c in _METRIC_COLUMNS if c not in runs)])
    for key, group in runs.groupby(keys, sort=False):
        ok = group[~failed.loc[group.index]]
        row = dict(zip(keys, key, strict=True))
        row.update(runs=float(len(ok)), failed=float(len(group) - len(ok)))
        row.update(_rate_columns(ok, confidence))
        row.update(_distribution_columns(ok))
        rows.append(row)
    return pd.DataFrame(rows)


def worst_run(runs: pd.DataFrame, method: str) -> pd.Series:
    """The worst run of a method: a collision first, then a critical entry, then a timeout,
    then the smallest distance to a pedestrian.

    Parameters
    ----------
    runs
        The runs frame of a :class:`CrowdStudy`.
    method
        A method label.
    """
    check_runs_frame(runs, ("method", "status", "collided", "critical", "timeout",
                            "min_centre_distance_m"))  # fmt: skip
    sub = runs[(runs["method"] == method) & (runs["status"].astype(str) != "error")]
    if sub.empty:
        raise InvalidParameterError(
            "method", method, f"has no finished runs (have {sorted(set(runs['method']))})"
        )
    order = sub.sort_values(["collided", "critical", "timeout", "min_centre_distance_m"],
                            ascending=[False, False, False, True], kind="stable")  # fmt: skip
    return order.iloc[0]


def representative_run(runs: pd.DataFrame, method: str) -> pd.Series:
    """A typical run of a method: the successful run whose arrival time is nearest the median
    (the worst run if none succeeded).

    Parameters
    ----------
    runs
        The runs frame of a :class:`CrowdStudy`.
    method
        A method label.
    """
    check_runs_frame(runs, ("method", "success", "arrival_time_s"))
    sub = runs[(runs["method"] == method) & (runs["success"] > 0)]
    if sub.empty:
        return worst_run(runs, method)
    med = sub["arrival_time_s"].median()
    return sub.loc[(sub["arrival_time_s"] - med).abs().sort_values(kind="stable").index[0]]


@dataclass(frozen=True)
class CrowdStudy(Result):
    """The runs of a crowd study and their summary.

    Attributes
    ----------
    runs
        One row per run: ``scenario``, ``density`` (persons/m^2), ``seed``, ``method`` and the
        metrics of :func:`run_row`; ``status`` (``"ok"`` or ``"error"``) and ``error``.
    settings
        What was simulated (scenarios, densities, seeds, methods, gains, crowd options).
    confidence
        Confidence level of the intervals of :meth:`to_frame`.
    status, warnings
        :class:`CrowdStudyStatus` and what a user should know (failed runs).
    """

    runs: pd.DataFrame = field(repr=False)
    settings: dict[str, Any] = field(default_factory=dict)
    confidence: float = ARG.confidence.default
    status: str = CrowdStudyStatus.OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """The summary per scenario, density and method (:func:`summarise_runs`)."""
        return summarise_runs(self.runs, self.confidence)

    def worst(self, method: str) -> pd.Series:
        """The worst run of ``method`` (:func:`worst_run`).

        Parameters
        ----------
        method
            A method label.
        """
        return worst_run(self.runs, method)

    def representative(self, method: str) -> pd.Series:
        """A typical run of ``method`` (:func:`representative_run`).

        Parameters
        ----------
        method
            A method label.
        """
        return representative_run(self.runs, method)


#: The fields of a crowd a study's grid sets (not crowd options).
_GRID_FIELDS = ("layout", "pedestrians", "density", "seed")
#: Runs of one study at most (each is a pedestrian simulation of up to a minute).
MAX_RUNS = Param("runs", "", "runs of a crowd study (scenarios x densities x seeds x methods)",
                 kind="integer", ge=1, le=100_000, name="runs")  # fmt: skip
#: A pedestrian model of a study's grid (the crowd's own declaration).
MODEL = params_of(CrowdScenario)["model"].but(name="models")
#: Seeds accepted (JuPedSim's and numpy's seeds are 32-bit).
SEED = ARG.seed.but(symbol="seed", doc="seed of a crowd", le=2**31 - 1, name="seeds")
#: Columns of a run row besides the point keys (for the chunk evaluator's result).
#: Frames per second of the Voronoi density (its cells cost about a run each at 1 frame/s).
VORONOI_FRAME_RATE = 0.5
RUN_COLUMNS = (
    "outcome", "success", "collided", "critical", "timeout", "left_area", "simulator_failed",
    "coupling_exceeded", "outcome_time_s", "free_run_s", "time_limit_s", "path_length_m",
    "shortest_m", "accel_mean", "accel_max", "jerk_mean", "jerk_max", "discomfort_share",
    "intrusion_share", "ttc_min_s", "frozen", "collision_by", "critical_by",
    "voronoi_density_per_m2", "arrival_time_s", "min_distance_m",
    "min_centre_distance_m", "personal_space_s", "ped_delay_mean_s", "ped_delay_max_s",
    "ped_beyond_window", "ped_deviation_mean_m", "ped_deviation_max_m", "run_status",
    "measured_density_per_m2", "mean_ped_speed_m_per_s", "critical_time_s",
    "min_surface_distance_m", "goal_distance_m",
)  # fmt: skip


def crowd_of(options: Mapping[str, Any], scenario: str, density: float, seed: int,
             model: str | None = None) -> CrowdScenario:  # fmt: skip
    """The crowd of one run: ``options["crowd"]`` (keywords of
    :func:`~designlab.navigation.crowd`) with the run's layout, density, seed and pedestrian
    model.

    Parameters
    ----------
    options
        The study's evaluator options.
    scenario, density, seed
        Layout name, persons/m^2 and seed.
    model
        JuPedSim model of the run (``None``: the crowd options').
    """
    kw = dict(options.get("crowd", {}))
    if model is not None:
        kw["model"] = str(model)
    return crowd(scenario, density=float(density), seed=int(seed), **kw)


def simulate_run(options: Mapping[str, Any], scenario: str, density: float, seed: int,
                 label: str, model: str | None = None) -> Any:  # fmt: skip
    """Simulate one run of a study again (runs are deterministic: the same result).

    Parameters
    ----------
    options
        The study's evaluator options (:attr:`CrowdStudy.settings` ``["options"]``).
    scenario, density, seed, label
        The run: layout, persons/m^2, seed and method label.
    model
        Its pedestrian model (``None``: the crowd options').

    Returns
    -------
    CrowdResult
    """
    gains = decode_gains(dict(options.get("gains", {})).get(label))
    stab = options.get("stabilising", "lyapunov")  # one setting, or label -> setting
    stab = dict(stab).get(label, "lyapunov") if isinstance(stab, Mapping) else stab
    return simulate_crowd(crowd_of(options, scenario, density, seed, model), gains,
                          method=method_name(label), stabilising=str(stab))  # fmt: skip


def crowd_runs_chunk(points: dict[str, np.ndarray], options: dict[str, Any]) -> dict[str, Any]:
    """Sweep-engine evaluator: one row of :func:`run_row` per point.

    Parameters
    ----------
    points
        Columns ``scenario`` (index into ``options["scenarios"]``), ``density`` (1/m^2),
        ``seed``, ``method`` (index into ``options["methods"]``) and optionally ``model``
        (index into ``options["models"]``: the pedestrian model).
    options
        ``scenarios``, ``methods`` (labels), ``gains`` (label -> plain gains),
        ``crowd`` (keywords of :func:`~designlab.navigation.crowd`), ``stabilising``,
        ``personal_space`` (m). Points of one crowd share its robot-free run (only
        simulated when the pedestrians avoid the robot: when they ignore it the robot
        changes nothing and the delay and deviation are exactly 0).
    """
    n = np.asarray(points["seed"]).size
    out: dict[str, list[Any]] = {k: [] for k in RUN_COLUMNS}
    alone: dict[tuple[int, float, int, str | None], Any] = {}
    reacts = bool(dict(options.get("crowd", {})).get("react_to_robot", False))
    measured = bool(options.get("measures", True))
    pending: list[tuple[Any, dict[str, Any]]] = []  # runs whose crowd met is still to measure
    models = points.get("model")
    for i in range(n):
        mi = None if models is None else options["models"][int(models[i])]
        key = (int(points["scenario"][i]), float(points["density"][i]), int(points["seed"][i]), mi)
        scenario, label = options["scenarios"][key[0]], options["methods"][int(points["method"][i])]
        res = simulate_run(options, scenario, key[1], key[2], label, mi)
        if reacts and measured and key not in alone:
            alone[key] = simulate_pedestrians(res.crowd)
        row = run_row(res, alone.get(key), personal_space=float(options.get("personal_space", 1.2)),
                      robot_radius=float(res.crowd.robot.radius), faced=False)  # fmt: skip
        first = measured and int(points["method"][i]) == 0
        row["voronoi_density_per_m2"] = _voronoi(res) if first else np.nan
        if not reacts:
            row.update(ped_delay_mean_s=0.0, ped_delay_max_s=0.0, ped_beyond_window=0.0,
                       ped_deviation_mean_m=0.0, ped_deviation_max_m=0.0)  # fmt: skip
        pending.append((res, row))
        if len(pending) == FACED_BATCH or i == n - 1:
            met = faced_by_runs([r for r, _ in pending]) if measured else [None] * len(pending)
            for (_, done), f in zip(pending, met, strict=True):
                names = ("measured_density_per_m2", "mean_ped_speed_m_per_s")
                done.update({k: getattr(f, k, np.nan) for k in names})
                for k in RUN_COLUMNS:
                    out[k].append(done[k])
            pending = []
    cols: dict[str, Any] = {k: np.asarray(v) for k, v in out.items()}
    cols["status"] = np.full(n, "ok", dtype=object)
    return cols


def _voronoi(res: Any) -> float:
    """pedpy's Voronoi density in the band along the robot's path (the first method's run
    of each crowd only: it costs about a run; :data:`VORONOI_FRAME_RATE`)."""
    c = res.crowd
    band = measurement_band(c.robot_start, c.robot_goal, c.geometry.area)
    return voronoi_density(res.times, res.pedestrian_positions, band, c.geometry.area,
                           VORONOI_FRAME_RATE)  # fmt: skip


def _check_labels(methods: Any, gains: Any) -> tuple[list[str], dict[str, Any]]:
    if isinstance(methods, str) or not isinstance(methods, Sequence) or not methods:
        raise InvalidParameterError("methods", methods, "must be a non-empty list of method labels")
    labels = [str(m) for m in methods]
    if len(set(labels)) != len(labels):
        raise InvalidParameterError("methods", methods, "must not repeat a label")
    for m in labels:
        CROWD_METHOD.check(method_name(m))
    table = dict(gains or {})
    unknown = sorted(set(table) - set(labels))
    if unknown:
        raise InvalidParameterError("gains", unknown, f"name labels not in methods {labels}")
    default = {METHOD.default: OPTIMAL_GAINS}  # the new VFF: the thesis's optimum
    return labels, {m: encode_gains(table.get(m, default.get(method_name(m)))) for m in labels}


def _check_grid(
    scenarios: Any, densities: Any, seeds: Any
) -> tuple[list[str], list[float], list[int]]:
    names = [scenarios] if isinstance(scenarios, str) else list(scenarios)
    for s in names:
        if s not in LAYOUTS:
            raise InvalidParameterError("scenarios", s, f"must be one of {list(LAYOUTS)}")
    rho = [DENSITY.check(d) for d in densities]
    seed_list = [SEED.check(s) for s in seeds]
    for name, vals in (("scenarios", names), ("densities", rho), ("seeds", seed_list)):
        if not vals or len(set(vals)) != len(vals):
            raise InvalidParameterError(name, vals, "must be non-empty with no repeats")
    return names, rho, seed_list


def _points(n_scen: int, density: float, seeds: list[int], n_methods: int,
            model: int | None = None) -> dict[str, np.ndarray]:  # fmt: skip
    """The runs of one layout and density (and pedestrian model, an index into the options'
    ``models``; ``None``: the crowd options'): seed-major, so a chunk of ``n_methods`` is a
    crowd."""
    seed_col = np.repeat(np.asarray(seeds, dtype=float), n_methods)
    extra = {} if model is None else {"model": np.full(seed_col.size, float(model))}
    return {
        **extra,
        "scenario": np.full(seed_col.size, float(n_scen)),
        "density": np.full(seed_col.size, density),
        "seed": seed_col,
        "method": np.tile(np.arange(n_methods, dtype=float), len(seeds)),
    }


def crowd_study(
    scenarios: Sequence[str] | str,
    densities: Sequence[float],
    seeds: Sequence[int] | range,
    methods: Sequence[str] = ("vff",),
    *,
    gains: Mapping[str, Any] | None = None,
    stabilising: str | Mapping[str, str] = "lyapunov",
    crowd_options: Mapping[str, Any] | None = None,
    personal_space: float = PERSONAL_SPACE.default,
    confidence: float = CONFIDENCE.default,
    executor: Any = None,
    store: Any = None,
    resume: bool = False,
    cache_only: bool = False,
    progress: ProgressHook | None = None,
    models: Sequence[str] | None = None,
    measures: bool = True,
) -> CrowdStudy:
    """Simulate every layout x density x seed x method and measure each run.

    Parameters
    ----------
    scenarios
        Layout names (:data:`~designlab.navigation.crowds.layouts.LAYOUTS`).
    densities
        Pedestrian densities, persons per m^2 of walkable area.
    seeds
        Crowd seeds (placement, streams, desired speeds); every method meets the same crowds.
    methods
        Method labels (``"vff"``, ``"cbf"``, ``"masoud"``, ``"ge_cui"``, ``"vff:<tag>"``).
    gains
        Label -> gains (defaults: see the module text).
    stabilising
        ``"lyapunov"`` or ``"off"``: VFF's stabilising force; or label -> setting (a label
        not listed: ``"lyapunov"``).
    crowd_options
        Other keywords of :func:`~designlab.navigation.crowd` (``width``, ``length``,
        ``model``, ``react_to_robot``, ``horizon``, ...).
    personal_space
        Personal-space radius, m (:data:`~designlab.navigation.crowds.metrics.PERSONAL_SPACE`).
    confidence
        Confidence level of the Wilson intervals.
    executor, store, resume, cache_only
        As for :func:`designlab.analysis.engine.run_points`: an executor (serial, processes,
        Dask), a chunk store, reuse stored chunks, compute nothing not stored.
    progress
        A :data:`designlab.progress.ProgressHook`: runs done after each layout and density.
    models
        JuPedSim models to run every crowd with (an outer axis of the grid, each crowd the
        same placement and streams under each; ``None``: the crowd options' model alone).
    measures
        ``False``: leave out what costs a simulation or pedpy's measures beside each run (the
        robot-free run for the pedestrians' delay and deviation, the Voronoi density, the
        crowd the robot met; those columns are NaN), as the gain tuning does.

    Returns
    -------
    CrowdStudy

    Examples
    --------
    >>> st = crowd_study(["corridor_counterflow"], [0.1], [0], ["vff"],
    ...                  crowd_options={"length": 8.0, "horizon": 1.0})
    >>> st.to_frame()[["method", "runs", "timeout_rate"]].to_dict("records")
    [{'method': 'vff', 'runs': 1.0, 'timeout_rate': 1.0}]
    """
    names, rho, seed_list = _check_grid(scenarios, densities, seeds)
    labels, coded = _check_labels(methods, gains)
    model_list = _check_models(models)
    CONFIDENCE.check(confidence)
    if crowd_options is not None:
        check_crowd_options(crowd_options, "crowd_options", _GRID_FIELDS)
    per_model = len(names) * len(rho) * len(seed_list) * len(labels)
    total = MAX_RUNS.check(per_model * max(len(model_list), 1))
    options = {
        "scenarios": names, "methods": labels, "gains": coded,
        "crowd": dict(crowd_options or {}), "stabilising": _stabilising(stabilising, labels),
        "personal_space": PERSONAL_SPACE.check(personal_space),
    }  # fmt: skip
    if model_list:
        options["models"] = model_list
    if not measures:  # only when asked: the stored chunks of measured studies keep their key
        options["measures"] = False
    crowd_of(options, names[0], rho[0], seed_list[0])  # bad crowd options fail before any run
    frames, done = [], 0
    for mi, model in enumerate(model_list or [None]):
        for si, name in enumerate(names):
            for d in rho:
                pts = _points(si, d, seed_list, len(labels), None if model is None else mi)
                run = run_points(pts, crowd_runs_chunk, options, executor=executor, store=store,
                                 resume=resume, cache_only=cache_only, chunk_size=len(labels),
                                 desc=f"crowds {model or ''} {name} {d:g}")  # fmt: skip
                frame = pd.concat([pd.DataFrame(pts), run.frame], axis=1)
                frames.append(_named(frame, names, labels, model or _model_of(options)))
                done += len(seed_list) * len(labels)
                note = f"{model + ' ' if model else ''}{name} {d:g}/m^2"
                report(progress, Progress(done, total, label="runs", note=note))
    return _study(pd.concat(frames, ignore_index=True), options, confidence)


def _check_models(models: Any) -> list[str]:
    """The pedestrian models of a grid checked (``None``: none, the crowd options' model)."""
    if models is None:
        return []
    names = [models] if isinstance(models, str) else list(models)
    if not names or len(set(names)) != len(names):
        raise InvalidParameterError("models", models, "must be non-empty with no repeats")
    return [str(MODEL.check(m)) for m in names]


def _model_of(options: Mapping[str, Any]) -> str:
    """The pedestrian model of the crowd options (the crowd's default when not given)."""
    return str(dict(options.get("crowd", {})).get("model", MODEL.default))


def _stabilising(value: Any, labels: list[str]) -> str | dict[str, str]:
    """The stabilising setting checked: one for every label, or label -> setting."""
    if not isinstance(value, Mapping):
        return str(STABILISING.check(value))
    unknown = sorted(set(value) - set(labels))
    if unknown:
        raise InvalidParameterError("stabilising", unknown, f"must name labels of {labels}")
    return {str(k): str(STABILISING.check(v)) for k, v in value.items()}


def _named(frame: pd.DataFrame, names: list[str], labels: list[str], model: str) -> pd.DataFrame:
    out = frame.copy()
    out["model"] = model
    out["scenario"] = [names[int(i)] for i in frame["scenario"]]
    out["method"] = [labels[int(i)] for i in frame["method"]]
    out["seed"] = frame["seed"].astype(int)
    return out


def abnormal_runs(runs: pd.DataFrame) -> list[str]:
    """One line per run that did not end normally: the robot left the walkable area, the
    pedestrian simulator failed, or the pedestrians did not see the robot where it was.

    Parameters
    ----------
    runs
        The runs frame of a :class:`CrowdStudy` (a frame without the columns: none).

    Examples
    --------
    >>> runs = pd.DataFrame({"scenario": ["crossing"], "density": [0.5], "seed": [3],
    ...     "method": ["vff"], "outcome": ["left_area"], "outcome_time_s": [4.2],
    ...     "coupling_exceeded": [0.0]})
    >>> abnormal_runs(runs)
    ['crossing 0.5/m^2 seed 3 vff: the robot left the walkable area at t = 4.20 s']
    """
    if "outcome" not in runs or "outcome_time_s" not in runs:
        return []
    causes = {"left_area": "the robot left the walkable area",
              "simulator_failed": "the pedestrian simulator (JuPedSim) failed"}  # fmt: skip
    out = []
    for _, r in runs.iterrows():
        among = f" among {r['model']} pedestrians" if "model" in r else ""
        cell = f"{r['scenario']} {r['density']:g}/m^2{among} seed {int(r['seed'])} {r['method']}"
        if r["outcome"] in causes:
            out.append(f"{cell}: {causes[r['outcome']]} at t = {r['outcome_time_s']:.2f} s")
        if r.get("coupling_exceeded", 0) > 0:
            out.append(f"{cell}: the robot's JuPedSim agent was more than the bound away from "
                       "the robot (the pedestrians did not see it where it was)")  # fmt: skip
    return out


def _study(runs: pd.DataFrame, options: dict[str, Any], confidence: float) -> CrowdStudy:
    failed = int((runs["status"].astype(str) == "error").sum())
    warnings = []
    if failed:
        first = runs.loc[runs["status"].astype(str) == "error", "error"].iloc[0]
        warnings.append(f"{failed} of {len(runs)} runs raised (first: {first})")
    warnings += abnormal_runs(runs)
    status = CrowdStudyStatus.FAILED_RUNS if failed else CrowdStudyStatus.OK
    return CrowdStudy(runs=runs, settings={"options": options}, confidence=confidence,
                      status=status, warnings=tuple(warnings))  # fmt: skip


__all__ += ["MAX_RUNS", "PERSONAL_SPACE", "crowd_runs_chunk", "crowd_study", "representative_run",
            "simulate_run"]  # fmt: skip
