"""Why a robot is slow among a crowd: the field's forces at every navigation sample of a run.

:func:`force_breakdown` evaluates the navigation field (the same compiled field as the run,
:func:`~designlab.navigation.field.build_field`) at each navigation sample t_k of a
:class:`~designlab.navigation.crowds.results.CrowdResult`, from the recorded robot state and
the pedestrians sensed at t_k (velocities by backward differences, as the run senses them),
and splits the force into

* ``attraction``: K1 E + K2 E' (5.4.2);
* ``walls``: the walls' repulsive and detour forces (the field with every pedestrian away);
* ``pedestrians``: the pedestrians' repulsive and detour forces (the rest, without F_L);
* ``stabilising``: F_L (5.4.6) times the run's stabilising switch,

which add up to the field's force exactly (for CBF: its nominal force, before the filter).
Each is given along the direction to the goal (positive: towards it). :func:`stall_summary`
counts the samples where the robot is stopped or slow (little progress towards the goal) and
says which component held it back: ``critical`` (braking in a critical region),
else the component pulling away from the goal the most.

Examples
--------
>>> import designlab as dl
>>> nav = dl.navigation
>>> c = nav.crowd("corridor_counterflow", 6, length=10.0, seed=2, horizon=1.2)
>>> res = nav.simulate(c, nav.VFFGains(4.3, 0.68, 20.3, 240.7))
>>> f = force_breakdown(res)
>>> len(f), {"speed_mps", "attraction_n", "pedestrians_n"} <= set(f.columns)
(21, True)
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pandas as pd

from designlab.errors import InvalidParameterError
from designlab.navigation.crowds.results import CrowdResult
from designlab.navigation.crowds.slots import PARKED, fill_slots
from designlab.navigation.field import ObstacleGeometry, build_field
from designlab.navigation.methods import method_of
from designlab.navigation.parameters import HolonomicRobot
from designlab.params import params_of

__all__ = ["COMPONENTS", "force_breakdown", "stall_summary"]

#: The parts of the field's force (see the module's text).
COMPONENTS = ("attraction", "walls", "pedestrians", "stabilising")
#: A robot below this fraction of its speed limit is "stopped"; below SLOW, "slow".
STOPPED = 0.1
SLOW = 0.5


def _sensed(result: Any, k: int, per: int) -> tuple[np.ndarray, np.ndarray]:
    """Positions and velocities of the pedestrians at sample k (backward difference)."""
    P = result.pedestrian_positions
    i = k * per
    now, prev = P[i], P[max(i - 1, 0)]
    V = (now - prev) / result.crowd.pedestrian_step
    return now, np.where(np.isnan(V), 0.0, V)


def force_breakdown(result: Any) -> pd.DataFrame:
    """The field's force split into its parts at every navigation sample of a crowd run.

    Parameters
    ----------
    result
        A :class:`~designlab.navigation.crowds.results.CrowdResult`.

    Returns
    -------
    pandas.DataFrame
        One row per sample: ``time_s``, ``speed_mps``, ``critical`` (the robot within a
        critical radius of a pedestrian or wall), ``active_pedestrians``, and per part of
        :data:`COMPONENTS` its component towards the goal ``<part>_n`` (N).
    """
    if not isinstance(result, CrowdResult):
        raise InvalidParameterError("result", result, "must be a CrowdResult (a crowd run)")
    c = result.crowd
    strategy = method_of(result.method)
    walls = c.walls()
    r2, r3 = c.pedestrian_regions()
    sizing = c.closing_speed_sizing() if c.region_sizing == "closing_speed" else None
    geos = tuple(ObstacleGeometry.of(w) for w in walls) + (c.pedestrian_geometry(),) * c.neighbours
    field = build_field(geos, strategy.name)
    row = [float(result.gains.get(k, 0.0)) for k in ("k1", "b", "k3", "k5")]  # gain_row
    stab = 1.0 if result.stabilising == "lyapunov" else 0.0
    params = [c.robot.mass, 1.0, stab, c.robot.max_accel]
    wall_obs = [v for w in walls for v in (*w.center, 0.0, 0.0, 0.0, 0.0)]
    per = round(c.sample_time / c.pedestrian_step)
    goal = np.asarray(c.robot_goal)
    rows = []
    for k in range(0, len(result.times), per):
        p, v = result.robot_positions[k], result.robot_velocities[k]
        P, V = _sensed(result, k // per, per)
        inside = ~np.isnan(P[:, 0])
        slots, n, _ = fill_slots(p, P[inside], V[inside], np.zeros_like(V[inside]), r2=r2,
                                 slots=c.neighbours)  # fmt: skip
        kw: dict[str, Any] = {"x": [*p, *v], "goal": goal, "gains": row}
        if sizing is not None:
            S = slots.reshape(-1, 6)
            kw["r2"] = [g.r2 for g in geos[: len(walls)]] + sizing.active_radii(
                p, S[:, 0:2], S[:, 2:4]
            ).tolist()
        full = field(obs=np.concatenate([wall_obs, slots]), params=params, **kw)
        parked = np.tile([PARKED, PARKED, 0, 0, 0, 0], c.neighbours)
        bare = field(obs=np.concatenate([wall_obs, parked]), params=params, **kw)
        none = field(obs=np.tile([PARKED, PARKED, 0, 0, 0, 0], len(geos)), params=params, **kw)
        rows.append(_split(result, k, p, v, goal, (full, bare, none), stab, n, r3))
    return pd.DataFrame(rows)


def _split(
    result: Any,
    k: int,
    p: np.ndarray,
    v: np.ndarray,
    goal: np.ndarray,
    fields: tuple[Any, Any, Any],
    stab: float,
    n: int,
    r3: float,
) -> dict[str, float]:
    """One sample's row of :func:`force_breakdown` from the field with every obstacle, with
    the walls alone and with none."""
    c = result.crowd
    full, bare, none = fields
    E = goal - p
    u = E / max(float(np.hypot(*E)), 1e-12)
    att = np.array(none["F"]).ravel()
    FL = np.array(full["FL"]).ravel() * stab
    F = np.array(full["F"]).ravel()
    Fw = np.array(bare["F"]).ravel() - np.array(bare["FL"]).ravel() * stab - att
    Fp = F - FL - att - Fw
    wall_d = min((float(w.contour_distance(p[None, :])[0]) for w in c.walls()), default=math.inf)
    near = float(result.nearest_distance[k])
    return {
        "time_s": float(result.times[k]), "speed_mps": float(np.hypot(*v)),
        "progress_mps": float(v @ u),
        "critical": bool(near <= r3 or wall_d <= c.wall_regions()[1]),
        "active_pedestrians": int(n),
        **{f"{name}_n": float(f @ u) for name, f in zip(COMPONENTS, (att, Fw, Fp, FL),
                                                        strict=True)},
    }  # fmt: skip


def stall_summary(frame: pd.DataFrame, max_speed: float) -> dict[str, float]:
    """Fractions of a run's samples where the robot is stopped or slow, and why.

    Parameters
    ----------
    frame
        From :func:`force_breakdown`.
    max_speed
        The robot's speed limit V_mr, m/s.

    Returns
    -------
    dict
        Fractions of the samples: ``stopped`` (speed < 0.1 V_mr), ``slow`` (progress
        towards the goal, v . u_goal, below 0.5 V_mr) and ``receding`` (progress < 0); the
        mean progress ``progress_mps``; and among the slow samples the fraction held by
        each cause: ``critical`` (braking in a critical region), else the part of
        :data:`COMPONENTS` (walls, pedestrians, stabilising) pulling away from the goal the
        most (``none`` if no part does: the robot is slow while every part pulls it on).
    """
    if not isinstance(frame, pd.DataFrame):
        raise InvalidParameterError("frame", frame, "must be the DataFrame of force_breakdown()")
    need = ["speed_mps", "progress_mps", "critical", *(f"{p}_n" for p in COMPONENTS[1:])]
    missing = [c for c in need if c not in frame.columns]
    if missing:
        raise InvalidParameterError(
            "frame", list(frame.columns), f"must have the columns {missing}"
        )
    max_speed = params_of(HolonomicRobot)["max_speed"].check(max_speed, "max_speed")
    n = max(len(frame), 1)
    slow = frame[frame["progress_mps"] < SLOW * max_speed]
    out = {
        "stopped": float((frame["speed_mps"] < STOPPED * max_speed).sum() / n),
        "slow": len(slow) / n,
        "receding": float((frame["progress_mps"] < 0).sum() / n),
        "progress_mps": float(frame["progress_mps"].mean()) if len(frame) else math.nan,
    }
    parts = [f"{p}_n" for p in COMPONENTS[1:]]
    cause = np.where(
        slow["critical"].to_numpy(bool), "critical",
        np.where(slow[parts].min(axis=1) < 0, slow[parts].idxmin(axis=1).str[:-2], "none"),
    ) if len(slow) else np.array([], dtype=str)  # fmt: skip
    for name in ("critical", *COMPONENTS[1:], "none"):
        out[f"slow_by_{name}"] = float((cause == name).sum() / max(len(slow), 1))
    return out
