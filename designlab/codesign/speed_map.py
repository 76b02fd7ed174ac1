"""The speed limit over foam stiffness x damping: which covering allows how fast a robot.

:func:`speed_limit_map` evaluates :func:`~designlab.codesign.speed_limit` on a grid of
foams (K_c, C_c) at once: the worst-case metric of every constraint at 1 m/s over the
head range, for all foams in one batch of the impact kernel, then the closing speed
each allows, ``(limit / metric) ** (1/e)``, the smallest of them, and the robot's
share ``v_c - v_h`` (with the braking model, the robot speed whose contact speed is that).
With ``refine=True`` (the default) each foam's worst head is polished off the grid by the
same multi-start local search as :func:`~designlab.codesign.speed_limit`
(:func:`designlab.codesign.worst_head.refine_heads`), so the map's limit of a foam is the
speed limit of that foam: any head in the range, not only the grid's.

Examples
--------
>>> import designlab as dl
>>> m = dl.codesign.speed_limit_map(dl.impact.MANIPULATOR_1, K_c=[10e3, 40e3], C_c=[50.0, 100.0])
>>> m.max_speed.shape, m.to_frame().shape
((2, 2), (4, 9))
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.codesign.parameters import (
    MAP_POINTS,
)
from designlab.codesign.speed import SafetyCase, SpeedLimitStatus, problem_for
from designlab.codesign.worst_head import grid_worst_heads, refine_heads
from designlab.errors import InvalidParameterError
from designlab.impact import ContactDynamics, Criterion, Foam, FullJointContact
from designlab.params import params_of
from designlab.results import Result

__all__ = ["SpeedLimitMap", "speed_limit_map"]

_FOAM = params_of(Foam)


@dataclass(frozen=True)
class SpeedLimitMap(Result):
    """Result of :func:`speed_limit_map`: arrays indexed ``[i, j]`` = ``(K_c[i], C_c[j])``.

    Attributes
    ----------
    stiffness, damping
        The grid's K_c (N/m) and C_c (N s/m) axes.
    max_speed
        The robot's speed limit, m/s (0 where no speed is safe).
    closing_speed
        The largest closing speed at contact, m/s.
    limiting
        Index into ``criteria`` of the constraint that sets the limit.
    criteria
        Names of the constraints (the criteria, then the thickness limit).
    per_criterion
        Per constraint name: the closing speed it allows alone, m/s.
    grid_closing_speed
        The largest closing speed at contact with the worst heads of the grid only, m/s
        (equal to ``closing_speed`` without ``refine``; above it where a head off the grid
        is worse).
    head_speed
        The head's speed toward the robot, m/s.
    linear_depth
        The foams' linear depth lambda (the thickness limit), m.
    status
        ``"ok"``, or ``"unsafe_at_rest"`` when some foam of the grid allows no robot speed.
    warnings
        What a user should know.
    """

    stiffness: NDArray[np.float64]
    damping: NDArray[np.float64]
    max_speed: NDArray[np.float64]
    closing_speed: NDArray[np.float64]
    limiting: NDArray[np.int64]
    criteria: tuple[str, ...]
    per_criterion: dict[str, NDArray[np.float64]]
    grid_closing_speed: NDArray[np.float64]
    head_speed: float
    linear_depth: float
    status: str = SpeedLimitStatus.OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """One row per foam of the grid.

        Returns
        -------
        pandas.DataFrame
        """
        kk, cc = np.meshgrid(self.stiffness, self.damping, indexing="ij")
        frame = pd.DataFrame(
            {
                "K_c_N_per_m": kk.ravel(),
                "C_c_N_s_per_m": cc.ravel(),
                "max_speed_m_per_s": self.max_speed.ravel(),
                "v_c_max_m_per_s": self.closing_speed.ravel(),
                "v_c_max_grid_m_per_s": self.grid_closing_speed.ravel(),
                "limiting": [self.criteria[i] for i in self.limiting.ravel()],
            }
        )
        frame["head_speed_m_per_s"] = self.head_speed
        frame["linear_depth_m"] = self.linear_depth
        frame["xi_c"] = cc.ravel() / (2.0 * np.sqrt(4.4 * kk.ravel()))
        return frame


def _axis(decl: Any, value: object, name: str) -> NDArray[np.float64]:
    """A grid axis: non-empty, each value within the declaration, at most the cap."""
    raw = np.asarray(value, dtype=object) if not isinstance(value, np.ndarray) else value
    if (
        value is None
        or raw.dtype == bool
        or any(x is None or isinstance(x, bool | np.bool_) for x in np.ravel(raw))
    ):
        raise InvalidParameterError(name, value, "must be an array of real numbers")
    try:
        arr = np.atleast_1d(np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        raise InvalidParameterError(name, value, "must be an array of real numbers") from None
    if arr.ndim != 1:
        raise InvalidParameterError(name, value, "must be a flat list of values (one axis)")
    if arr.size == 0:
        raise InvalidParameterError(name, [], "needs at least one value (the range is empty)")
    MAP_POINTS.check(int(arr.size), f"len({name})")
    for x in arr:
        decl.check(float(x), name)
    return arr


def _allowed(key: Criterion, unit_metric: NDArray[np.float64]) -> NDArray[np.float64]:
    """The closing speed ``key`` allows at each worst metric at 1 m/s (inf at 0)."""
    with np.errstate(divide="ignore"):
        v = (key.limit / unit_metric) ** (1.0 / key.velocity_exponent)
    return np.where(unit_metric > 0, v, np.inf)


def speed_limit_map(
    robot: ContactDynamics | FullJointContact,
    *,
    K_c: Sequence[float] | NDArray,
    C_c: Sequence[float] | NDArray,
    linear_depth: float = 0.02,
    case: SafetyCase | None = None,
    refine: bool = True,
) -> SpeedLimitMap:
    """The robot's speed limit over a grid of foams (K_c x C_c).

    Parameters
    ----------
    robot
        The effective manipulator at the impact point (a fixed impact point; for a link,
        call :func:`~designlab.codesign.speed_limit` per foam).
    K_c
        Foam stiffnesses, N/m (at most 400).
    C_c
        Foam dampings, N s/m (at most 400).
    linear_depth
        The foams' linear depth lambda, m (the thickness limit eps_max <= lambda).
    case
        The criteria, people, braking and worst-head grid
        (:class:`~designlab.codesign.SafetyCase`; ``None``: its defaults).
    refine
        As in :func:`~designlab.codesign.speed_limit` (``refine=False``: the grid's worst
        heads only, one kernel batch, about 20 times faster on a 40 x 40 grid).

    Returns
    -------
    SpeedLimitMap
    """
    if not isinstance(robot, (ContactDynamics, FullJointContact)):
        raise InvalidParameterError(
            "robot", robot, "must be a ContactDynamics or a FullJointContact (a fixed point)"
        )
    ks = _axis(_FOAM["stiffness"], K_c, "K_c")
    cs = _axis(_FOAM["damping"], C_c, "C_c")
    lam = _FOAM["linear_depth"].check(linear_depth, "linear_depth")
    case = SafetyCase.of(case)
    v_h, brake = case.human_speed, case.braking
    if not isinstance(refine, (bool, np.bool_)):
        raise InvalidParameterError("refine", refine, "must be True or False")
    prob = problem_for(robot, case, lam)
    kk, cc = np.meshgrid(ks, cs, indexing="ij")
    per: dict[str, NDArray[np.float64]] = {}
    on_grid: dict[str, NDArray[np.float64]] = {}
    for key in prob.keys():
        grid, heads = grid_worst_heads(prob, key, kk.ravel(), cc.ravel())
        vals = refine_heads(prob, key, kk.ravel(), cc.ravel(), heads, grid)[0] if refine else grid
        on_grid[key.name] = _allowed(key, grid).reshape(kk.shape)
        per[key.name] = _allowed(key, vals).reshape(kk.shape)
    stack = np.stack(list(per.values()))
    limiting = np.argmin(stack, axis=0)
    v_c = np.min(stack, axis=0)
    speed = np.vectorize(lambda u: brake.robot_limit(u - v_h, v_h))(v_c).astype(float)
    unsafe = v_c <= v_h
    warnings: tuple[str, ...] = brake.notes()
    if np.any(unsafe):
        warnings += (
            f"{int(unsafe.sum())} of {unsafe.size} foams allow no robot speed: a person moving "
            f"at {v_h:g} m/s into the robot at rest alone exceeds a limit",
        )
    return SpeedLimitMap(
        stiffness=ks, damping=cs, max_speed=speed, closing_speed=v_c, limiting=limiting,
        criteria=tuple(per), per_criterion=per,
        grid_closing_speed=np.min(np.stack(list(on_grid.values())), axis=0), head_speed=v_h,
        linear_depth=lam,
        status=SpeedLimitStatus.UNSAFE_AT_REST if np.any(unsafe) else SpeedLimitStatus.OK,
        warnings=warnings,
    )  # fmt: skip
