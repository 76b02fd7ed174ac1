"""Sweep evaluator of the navigation domain: whole chunks of gain sets and robot limits.

:func:`vff_metrics_chunk` is a plain module-level function
``(points: dict[str, ndarray], options: dict) -> dict[str, ndarray]`` that the
sweep engine sends to its workers by reference. Points are columns keyed
``k1, b, k3, k5`` (gains), ``v_max``, ``a_max`` (robot limits, m/s and m/s^2) and
``v_h`` (cruise speed of the synthetic human walk, m/s). Points sharing the robot
and walk are simulated together with :func:`~designlab.navigation.simulate_batch`.

Examples
--------
>>> import numpy as np
>>> pts = {"k1": np.array([4.3, 3.0]), "b": np.array([0.68, 0.25]), "k3": np.array([20.3, 20.0]),
...        "k5": np.array([240.7, 17.0]), "v_max": np.array([0.7, 0.7]),
...        "a_max": np.array([10.0, 10.0]), "v_h": np.array([1.0, 1.0])}
>>> out = vff_metrics_chunk(pts, {"scenarios": [[1, 6]], "stabilising": "off"})
>>> np.round(out["T_mean_s"], 2).tolist(), out["status"].tolist()
([5.98, 6.48], ['ok', 'ok'])
"""

from __future__ import annotations

from typing import Any

import numpy as np

from designlab.navigation.criteria import EQUAL_WEIGHTS
from designlab.navigation.parameters import GAIN_SETS, HolonomicRobot, NonholonomicRobot
from designlab.navigation.scenario_io import scenario_from_dict, with_limits
from designlab.navigation.scenarios import configuration
from designlab.navigation.simulate import simulate_batch
from designlab.results import Status

__all__ = ["VFF_METRICS", "VFF_POINT_KEYS", "PointStatus", "vff_metrics_chunk"]


class PointStatus(Status):
    """Status of one sweep point (the ``status`` column of a navigation sweep).

    ``OK``: every run arrived without a collision; ``NOT_ARRIVED``: a run did not reach the
    goal within its horizon; ``COLLISION``: a run touched an obstacle (checked first).
    """

    OK = "ok"
    NOT_ARRIVED = "not_arrived"
    COLLISION = "collision"


#: Metrics of a set of runs (column -> description with unit).
VFF_METRICS: dict[str, str] = {
    "H_mean": "mean of H over the scenarios (Sec. 5.6)",
    "T_mean_s": "mean arrival time, s (inf if a run never arrives)",
    "clearance_min_m": "smallest surface distance d_s over every scenario and obstacle, m",
    "critical_entries": "number of scenarios where the robot entered a critical region",
    "collisions": "number of scenarios with a collision",
}

#: The point keys of the evaluator (the last two are optional: defaults from ``options``).
VFF_POINT_KEYS = ("k1", "b", "k3", "k5", "v_max", "a_max", "v_h", "ramp", "tol")


def vff_metrics_chunk(points: dict[str, np.ndarray], options: dict[str, Any]) -> dict[str, Any]:
    """Simulate every point on every scenario and return the metrics of :data:`VFF_METRICS`.

    Parameters
    ----------
    points
        Columns ``k1, b, k3, k5, v_max, a_max, v_h`` and optionally ``ramp`` (ramp time of
        the synthetic walk, s; default 0.5) and ``tol`` (arrival tolerance, m; default
        ``options["arrival_tolerance"]``).
    options
        ``scenarios``: list of ``[configuration, chapter]`` (thesis configurations) or of
        a user's scenarios as plain data
        (:func:`~designlab.navigation.scenario_io.scenario_from_dict`; the point sets
        their robot limits and the speed and ramp time of every walk);
        ``stabilising``: ``"lyapunov"`` or ``"off"``; ``arrival_tolerance`` (m);
        ``jit``: simulate with the four-lane compiled step (default ``False``);
        ``weights``: criterion weights (w_T, w_D, w_E) of H (default 1/3 each).
    """
    n = np.asarray(points["k1"]).size
    defaults = {"ramp": 0.5, "tol": float(options.get("arrival_tolerance", 0.15))}
    cols = {
        k: np.asarray(points[k], dtype=float)
        if k in points
        else np.full(n, defaults[k], dtype=float)
        for k in VFF_POINT_KEYS
    }
    out = {k: np.zeros(n) for k in VFF_METRICS}
    status = np.full(n, PointStatus.OK.value, dtype=object)
    specs = [
        s if isinstance(s, dict) else tuple(s)
        for s in options.get("scenarios", [[1, 6], [2, 6], [3, 6]])
    ]
    stab = options.get("stabilising", "off")
    jit = bool(options.get("jit", False))
    weights = tuple(options.get("weights", EQUAL_WEIGHTS))
    groups = np.stack([cols[k] for k in ("v_max", "a_max", "v_h", "ramp", "tol")], axis=1)
    step = int(GAIN_SETS.le)  # type: ignore[arg-type]
    for key in np.unique(groups, axis=0):
        group = np.flatnonzero(np.all(groups == key, axis=1))
        v_max, a_max, v_h, ramp, tol = (float(x) for x in key)
        scenarios = []
        for spec in specs:
            if isinstance(spec, dict):  # a user's scenario (docs/navigation_scenarios.md)
                own = scenario_from_dict(spec)
                scenarios.append(with_limits(own, v_max, a_max, v_h, ramp))
                continue
            which, chapter = spec
            cls = HolonomicRobot if int(chapter) == 6 else NonholonomicRobot
            robot = cls(max_speed=v_max, max_accel=a_max)
            scenarios.append(
                configuration(
                    which, int(chapter), robot=robot, human_speed=v_h, human_ramp_time=ramp
                )
            )
        for start in range(0, group.size, step):  # at most GAIN_SETS per batch
            idx = group[start : start + step]
            gains = np.stack([cols[k][idx] for k in ("k1", "b", "k3", "k5")], axis=1)
            res = simulate_batch(scenarios, gains, stabilising=stab, arrival_tolerance=tol, jit=jit,
                                 weights=weights)  # fmt: skip
            _store(out, status, idx, scenarios, res)
    out_any: dict[str, Any] = dict(out)
    out_any["status"] = status
    return out_any


def _store(out: dict[str, Any], status: Any, idx: Any, scenarios: list[Any], res: Any) -> None:
    """The metrics of one batch into the chunk's columns."""
    surf = np.full(res.min_distance.shape, np.nan)
    for s, sc in enumerate(scenarios):
        off = np.array([o.collision_distance(sc.robot.radius) for o in sc.obstacles])
        surf[s, :, : off.size] = res.min_distance[s, :, : off.size] - off[None, :]
    out["H_mean"][idx] = res.H_mean
    out["T_mean_s"][idx] = res.arrival_time.mean(axis=0)
    out["clearance_min_m"][idx] = np.nanmin(surf, axis=(0, 2)) if surf.size else np.inf
    out["critical_entries"][idx] = res.entered_critical.sum(axis=0)
    out["collisions"][idx] = res.collided.sum(axis=0)
    not_arrived = np.isinf(res.arrival_time).any(axis=0)
    status[idx] = np.where(
        res.collided.any(axis=0),
        PointStatus.COLLISION.value,
        np.where(not_arrived, PointStatus.NOT_ARRIVED.value, PointStatus.OK.value),
    )
