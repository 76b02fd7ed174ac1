"""Sweep evaluator of the tether follower: a chunk of designs at once.

A plain module-level function ``(points, options) -> columns`` for the shared
sweep engine (:mod:`designlab.analysis.engine`). Points are columns keyed by
the declarations' symbols, ``l_d, k_V, k_O, delta, K_a, v, w_max, dt, sigma_l,
sigma_theta`` (:data:`POINT_KEYS`, SI units);
the law, its fixed fields, the path and the rest of the robot are options.
Points that share a leader speed and a robot are simulated as one batch
(:func:`designlab.following.tether.simulate_batch`).

Examples
--------
>>> import numpy as np
>>> from designlab.following.tether import FollowTheLeader, slalom
>>> opts = sweep_options(FollowTheLeader(), slalom())
>>> pts = {"delta": np.array([0.1, 0.5]), "v": np.array([0.5, 0.5])}
>>> out = follower_metrics_chunk(pts, opts)
>>> out["status"].tolist(), bool(out["damping_ratio"][0] < out["damping_ratio"][1])
(['ok', 'ok'], True)
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from designlab.following.tether.laws.base import TetherController
from designlab.following.tether.laws.registry import LAWS, controller_from_dict
from designlab.following.tether.linear import damping_ratio
from designlab.following.tether.parameters import LEADER_SPEED, FollowerRobot
from designlab.following.tether.path_deviation import normal_path_deviations
from designlab.following.tether.paths import LeaderPath
from designlab.following.tether.simulate import simulate_batch
from designlab.params import ARG, params_of

__all__ = ["FOLLOWER_METRICS", "POINT_KEYS", "follower_metrics_chunk", "sweep_options"]

#: Metrics of one run (column -> description with unit).
FOLLOWER_METRICS: dict[str, str] = {
    "npd_mean_m": "mean normal path deviation (Allan 2015 App. A), m",
    "npd_mean_over_b": "mean normal path deviation in wheel tracks",
    "npd_std_m": "standard deviation of the normal path deviation, m",
    "length_error_rms_m": "RMS tether-length error l_m - l_d, m",
    "tether_max_m": "longest measured tether, m",
    "accel_rms_m_per_s2": "RMS of dV/dt, m/s^2",
    "path_length_ratio": "robot distance over leader distance",
    "damping_ratio": "damping ratio of the linear lateral loop",
}


def _keys(cls: type, where: str, names: tuple[str, ...]) -> dict[str, tuple[str, str]]:
    decls = params_of(cls)
    return {str(decls[n].symbol): (where, n) for n in names}


#: Point key (the declaration's symbol) -> (what it sets, field name).
POINT_KEYS: dict[str, tuple[str, str]] = {
    **{k: v for law in LAWS for k, v in _keys(law, "controller", law.SWEEP_FIELDS).items()},
    str(LEADER_SPEED.symbol): ("leader", "speed"),
    **_keys(
        FollowerRobot,
        "robot",
        ("max_wheel_speed", "sample_time", "length_noise_std", "angle_noise_std"),
    ),
}


def sweep_options(
    controller: TetherController,
    path: LeaderPath,
    robot: FollowerRobot | None = None,
    seed: int = ARG.seed.default,
) -> dict[str, Any]:
    """Plain (picklable) options of :func:`follower_metrics_chunk`.

    Parameters
    ----------
    controller
        The base controller (swept gains replace its fields).
    path
        The leader's path.
    robot
        The robot (default :class:`FollowerRobot`).
    seed
        Seed of the sensor noise.
    """
    return {
        "controller": controller.as_dict(),
        "path": np.asarray(path.points).tolist(),
        "path_name": path.name,
        "initial_heading": path.initial_heading,
        "robot": (robot or FollowerRobot()).as_dict(),
        "seed": seed,
    }


def _designs(cols: dict[str, Any], n: int, options: dict[str, Any]) -> tuple:
    """Each point's controller, robot and leader speed; invalid points get a status."""
    status = np.full(n, "ok", dtype=object)
    ctrls: list[TetherController | None] = []
    robots: list[FollowerRobot | None] = []
    speeds = np.full(n, 0.5)
    groups: dict[tuple[Any, ...], list[int]] = {}
    for i in range(n):
        fields: dict[str, dict[str, Any]] = {
            "controller": dict(options["controller"]),
            "robot": dict(options["robot"]),
            "leader": {"speed": 0.5},
        }
        for key, col in cols.items():
            where, name = POINT_KEYS[key]
            fields[where][name] = float(col[i])
        try:
            ctrl = controller_from_dict(fields["controller"])
            robot = FollowerRobot(**fields["robot"])
            v = LEADER_SPEED.check(fields["leader"]["speed"])
        except (ValueError, TypeError) as exc:
            status[i] = f"invalid: {exc}"
            ctrls.append(None)
            robots.append(None)
            continue
        ctrls.append(ctrl)
        robots.append(robot)
        speeds[i] = v
        groups.setdefault((v, tuple(sorted(fields["robot"].items()))), []).append(i)
    return ctrls, robots, speeds, groups, status


def _group_metrics(
    members: list[int],
    ctrls: list,
    robot: FollowerRobot,
    v: float,
    path: LeaderPath,
    seed: int,
    out: dict[str, Any],
    status: Any,
) -> None:
    """Simulate the points of one (speed, robot) group as a batch and store their metrics."""
    batch = simulate_batch([ctrls[i] for i in members], path, speed=v, robot=robot, seed=seed)
    ok = [j for j in range(len(members)) if batch.member_status[j] == "ok"]
    npds = normal_path_deviations(
        batch.leader_xy, [batch.robot_xy[j] for j in ok], wheel_track=robot.wheel_track
    )
    lead = np.hypot(*np.diff(batch.leader_xy, axis=0).T).sum()
    dt = robot.sample_time
    for j, i in enumerate(members):
        if batch.member_status[j] != "ok":
            status[i] = str(batch.member_status[j])
    for j, npd in zip(ok, npds, strict=True):
        i, c, lm = members[j], ctrls[members[j]], batch.tether_length[j]
        step = np.hypot(*np.diff(batch.robot_xy[j], axis=0).T).sum()
        out["npd_mean_m"][i] = npd.mean
        out["npd_mean_over_b"][i] = npd.mean_over_b
        out["npd_std_m"][i] = npd.std
        out["length_error_rms_m"][i] = float(np.sqrt(np.mean((lm - c.desired_length) ** 2)))
        out["tether_max_m"][i] = float(lm.max())
        out["accel_rms_m_per_s2"][i] = float(np.sqrt(np.mean((np.diff(batch.speed[j]) / dt) ** 2)))
        out["path_length_ratio"][i] = float(step / lead)
        out["damping_ratio"][i] = damping_ratio(c, v, robot.wheel_track)
        if npd.status != "ok":
            status[i] = str(npd.status)


def follower_metrics_chunk(points: dict[str, Any], options: dict[str, Any]) -> dict[str, Any]:
    """Simulate every point and return its metrics (:data:`FOLLOWER_METRICS`) and ``status``.

    Parameters
    ----------
    points
        Columns of :data:`POINT_KEYS` (any subset; the rest come from ``options``).
    options
        From :func:`sweep_options`: the base controller, path and robot.
    """
    cols = {k: np.asarray(v, dtype=float) for k, v in points.items() if k in POINT_KEYS}
    n = len(next(iter(cols.values()))) if cols else 0
    path = LeaderPath(
        np.asarray(options["path"], dtype=float),
        name=options.get("path_name", "path"),
        initial_heading=options.get("initial_heading"),
    )
    out: dict[str, Any] = {k: np.full(n, math.nan) for k in FOLLOWER_METRICS}
    ctrls, robots, speeds, groups, status = _designs(cols, n, options)
    seed = int(options.get("seed", 0))
    for members in groups.values():
        robot = robots[members[0]]
        assert robot is not None
        _group_metrics(members, ctrls, robot, float(speeds[members[0]]), path, seed, out, status)
    out["status"] = status
    return out


follower_metrics_chunk.chunk_size = 64  # type: ignore[attr-defined]
