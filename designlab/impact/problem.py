"""The worst-case evaluation behind the foam envelope (Zeng 2011, Sec. 3.9).

A :class:`FoamProblem` evaluates, for foams (K_c, C_c), every constraint of a
foam design -- the safety criteria (upper boundary) and the thickness limit
eps_max <= lambda (lower boundary) -- at its worst case: the largest closing
velocity (the metrics rise linearly with v_c), the criterion's conservative
head-neck set or the worst corner of a :class:`~designlab.impact.parameters.HeadRange`,
and, for a robot given at joint level (:class:`~designlab.impact.parameters.LinkImpact`),
the worst impact point along the link (Sec. 3.7.3). :class:`FoamLanes` solves
several fixed-robot problems together. The boundaries themselves are solved by
:mod:`designlab.impact.boundaries`.

Examples
--------
>>> import numpy as np
>>> from designlab.impact import MANIPULATOR_1, HeadAcceleration
>>> prob = make_problem(MANIPULATOR_1, 1.25, [HeadAcceleration(10)], 0.02, None, False, 1.0, 0.05)
>>> vals, _ = prob.worst(prob.criteria[0], np.array([24.25e3]), np.array([71.9]))
>>> round(float(vals[0]) / 9.80665, 2)                  # a_h,max in g, minimum head set
6.12
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, fields

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.contact import ContactModel, contact_of
from designlab.impact.criteria import CompressionLimit, Criterion, HeadAcceleration
from designlab.impact.parameters import (
    HEAD_LEVELS,
    HUMAN_SPEED,
    IMPACT_VELOCITY,
    MAX_COMPRESSION,
    STOP_TIME,
    ContactDynamics,
    HeadNeck,
    HeadRange,
    LinkImpact,
)

__all__ = ["FoamLanes", "FoamProblem", "head_rows", "make_problem", "same_but_limits"]


def head_rows(heads: Sequence[HeadNeck]) -> NDArray[np.float64]:
    """``(n, 3)`` rows ``[M_h, C_h, K_h]`` of head-neck sets.

    Parameters
    ----------
    heads
        The head-neck sets.

    Returns
    -------
    numpy.ndarray
    """
    return np.array([[h.mass, h.damping, h.stiffness] for h in heads], dtype=float)


@dataclass
class FoamProblem:
    """Worst-case evaluation of the criteria and the compression for foams (K_c, C_c).

    The worst case over the head-neck sets (the criterion's conservative set or
    a :class:`~designlab.impact.parameters.HeadRange`) and, for a robot at
    joint level, over the impact points along the link (a grid, then a
    golden-section search). Built by :func:`make_problem`.

    Attributes
    ----------
    robot
        The manipulator (fixed, or a link struck anywhere).
    impact_velocity
        v_c of a fixed robot, m/s (NaN for a link).
    human_speed
        Head speed toward a link, m/s.
    criteria
        The safety criteria (upper boundary).
    max_compression
        lambda, m (the lower boundary).
    head_range
        The head-neck range, or ``None`` for each criterion's conservative set.
    constrained
        The constrained impact (head against a wall).
    stop_time
        Window of the constrained impact's metrics, s.
    head_levels
        Values per parameter of the head-range grid.
    lever_grid
        Lever arms of the grid search of the worst impact point.
    golden_iterations
        Golden-section iterations polishing it.
    foam
        The foam whose stiffness and damping are varied, for a non-linear law (its other
        parameters are kept); ``None``: the linear foam.
    """

    robot: ContactDynamics | LinkImpact
    impact_velocity: float
    human_speed: float
    criteria: tuple[Criterion, ...]
    max_compression: float
    head_range: HeadRange | None
    constrained: bool
    stop_time: float
    head_levels: int = HEAD_LEVELS.default
    lever_grid: int = 17
    golden_iterations: int = 24
    foam: object | None = None

    @property
    def contact(self) -> ContactModel:
        """The contact model of the robot and the foam (:mod:`designlab.impact.contact`)."""
        return contact_of(self.robot) if self.foam is None else contact_of(self.robot, self.foam)

    @property
    def compression(self) -> CompressionLimit:
        """The thickness constraint eps_max <= lambda (3.9.3) as a criterion."""
        return CompressionLimit(self.max_compression)

    def heads_for(self, key: Criterion) -> NDArray[np.float64]:
        if self.constrained:
            return np.array([[1.0, 0.0, 0.0]])
        if self.head_range is not None:
            return head_rows(self.head_range.grid(self.head_levels))
        return head_rows([key.conservative_head])

    def robot_rows(self, levers: NDArray | None) -> tuple[NDArray, NDArray]:
        """Robot rows (the contact model's ``robot_columns``) and v_c for lever arms (or the
        one robot)."""
        rows = self.contact.robot_row(self.robot, levers)
        if self.robot.along_link:
            levers = np.asarray(levers, dtype=float)
            return rows, self.robot.speed(levers) + self.human_speed
        return rows, np.array([self.impact_velocity])

    def designs(
        self, key: Criterion, k: NDArray, c: NDArray, levers: NDArray | None = None
    ) -> tuple[NDArray, NDArray, int]:
        """Every head (and the robot at ``levers``) for foams ``(k, c)``.

        Returns ``(N * n_heads, 8)`` parameters, their velocities and ``n_heads``;
        rows ``i * n_heads ... (i + 1) * n_heads - 1`` belong to foam ``i``.
        """
        if self.robot.along_link:
            rows, v = self.robot_rows(levers)
        else:
            c, rows, v = self._lane_inputs(c)
        return self._expand(key, k, c, rows, v)

    def _lane_inputs(self, c: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """Damping, robot rows and v_c of the lanes ``c`` (a fixed robot).

        The lane context that :func:`_boundary` and :func:`_illinois` carry is the
        damping itself here; :class:`FoamLanes` carries lane indices instead.
        """
        rows, v = self.robot_rows(None)
        return c, np.repeat(rows, c.size, axis=0), np.repeat(v, c.size)

    def log_limit(self, key: Criterion, c: NDArray) -> float | NDArray:
        """``log`` of the limit of ``key`` for the lanes ``c`` (one limit here)."""
        return math.log(self.limit(key))

    def _expand(
        self, key: Criterion, k: NDArray, c: NDArray, rows: NDArray, v: NDArray
    ) -> tuple[NDArray, NDArray, int]:
        heads = self.heads_for(key)
        n, nh = k.size, heads.shape[0]
        full = self.contact.assemble(
            np.repeat(rows, nh, axis=0),
            np.repeat(k, nh),
            np.repeat(c, nh),
            np.tile(heads, (n, 1)),
            self.foam,
        )
        return full, np.repeat(v, nh), nh

    def _values(self, key: Criterion, k: NDArray, c: NDArray, rows: NDArray, v: NDArray) -> NDArray:
        """Metric for designs ``i`` x robot rows ``j`` (paired arrays, all length n)."""
        full, vv, nh = self._expand(key, k, c, rows, v)
        vals = self.contact.values(
            key, full, vv, constrained=self.constrained, stop_time=self.stop_time
        )
        return vals.reshape(k.size, nh).max(axis=1)

    def worst(self, key: Criterion, k: NDArray, c: NDArray) -> tuple[NDArray, NDArray]:
        """Worst-case metric over heads (and impact points) for foams ``(k, c)``.

        Returns the values and the worst lever arm (NaN for a fixed robot).
        """
        k = np.asarray(k, dtype=float).ravel()
        c = np.asarray(c, dtype=float).ravel()
        if not self.robot.along_link:
            return self._values(key, k, *self._lane_inputs(c)), np.full(k.size, np.nan)
        lr = self.robot
        grid = np.geomspace(lr.lever_arm_min, lr.lever_arm_max, self.lever_grid)
        if lr.lever_arm_max == lr.lever_arm_min:
            grid = np.array([lr.lever_arm_min])
        n, ng = k.size, grid.size
        rows, v = self.robot_rows(grid)
        vals = self._values(
            key, np.repeat(k, ng), np.repeat(c, ng), np.tile(rows, (n, 1)), np.tile(v, n)
        ).reshape(n, ng)
        j = vals.argmax(axis=1)
        best = vals[np.arange(n), j]
        best_l = grid[j]
        if ng < 3:
            return best, best_l
        lo = grid[np.maximum(j - 1, 0)]
        hi = grid[np.minimum(j + 1, ng - 1)]
        cand, cand_l = self._golden(key, k, c, lo, hi)
        better = cand > best
        return np.where(better, cand, best), np.where(better, cand_l, best_l)

    def _golden(
        self, key: Criterion, k: NDArray, c: NDArray, lo: NDArray, hi: NDArray
    ) -> tuple[NDArray, NDArray]:
        """Golden-section search of the worst lever arm in ``[lo, hi]`` for each foam."""

        def f(levers: NDArray) -> NDArray:
            r, vv = self.robot_rows(levers)
            return self._values(key, k, c, r, vv)

        inv = (math.sqrt(5) - 1) / 2
        x1 = hi - inv * (hi - lo)
        x2 = lo + inv * (hi - lo)
        f1, f2 = f(x1), f(x2)
        for _ in range(self.golden_iterations):
            left = f1 >= f2
            hi = np.where(left, x2, hi)
            lo = np.where(left, lo, x1)
            nx1 = np.where(left, hi - inv * (hi - lo), x2)
            nx2 = np.where(left, x1, lo + inv * (hi - lo))
            fnew = f(np.where(left, nx1, nx2))
            f1, f2 = np.where(left, fnew, f2), np.where(left, f1, fnew)
            x1, x2 = nx1, nx2
        return np.where(f1 >= f2, f1, f2), np.where(f1 >= f2, x1, x2)

    def limit(self, key: Criterion) -> float:
        return key.limit

    def log_excess(self, key: Criterion, u: NDArray, c: NDArray) -> NDArray:
        """``log(metric / limit)`` at ``K_c = exp(u)``: > 0 means violated."""
        vals, _ = self.worst(key, np.exp(u), c)
        with np.errstate(divide="ignore"):
            return np.log(np.maximum(vals, 1e-300)) - self.log_limit(key, c)

    def keys(self) -> list[Criterion]:
        """Every constraint: the criteria (upper boundary) and the thickness limit (lower)."""
        return [*self.criteria, self.compression]


def metric_only(key: Criterion) -> bool:
    """Whether ``key``'s values depend on its metric alone (not on its fields)."""
    t = type(key)
    return t.values is Criterion.values and t.from_metrics is Criterion.from_metrics


def same_but_limits(a: FoamProblem, b: FoamProblem) -> bool:
    """Whether ``b`` differs from ``a`` only in its fixed robot, v_c and limits.

    Parameters
    ----------
    a, b
        Two problems.

    Returns
    -------
    bool
    """
    if b.robot.along_link or len(a.criteria) != len(b.criteria):
        return False
    if a.contact is not b.contact:
        return False
    setting = ("head_range", "constrained", "stop_time", "head_levels", "foam")
    if any(getattr(a, s) != getattr(b, s) for s in setting):
        return False
    return all(
        ka == kb
        or (
            metric_only(ka)
            and metric_only(kb)
            and ka.metric == kb.metric
            and ka.conservative_head == kb.conservative_head
        )
        for ka, kb in zip(a.keys(), b.keys(), strict=True)
    )


@dataclass(kw_only=True)
class FoamLanes(FoamProblem):
    """Several fixed-robot problems solved together: one lane per (problem, damping value).

    The lane context carried by :func:`~.boundaries.boundary` and :func:`~.boundaries.illinois`
    is a lane index (a float, exact): lane ``i`` is the robot row ``rows[i]`` at v_c
    ``velocity[i]`` and C_c ``damping[i]``, with ``log_limits[i]`` (one column per
    :meth:`keys`). The criteria evaluated are the first problem's; the others
    differ from them in their limits only (:func:`same_but_limits`).

    Attributes
    ----------
    rows
        Robot rows of the lanes.
    velocity
        v_c of the lanes, m/s.
    damping
        C_c of the lanes, N s/m.
    log_limits
        ``log`` of each constraint's limit, per lane.
    robot, impact_velocity, human_speed, criteria, max_compression, head_range
        As in :class:`FoamProblem` (the first problem's).
    constrained, stop_time, head_levels, lever_grid, golden_iterations, foam
        As in :class:`FoamProblem`.
    """

    rows: NDArray[np.float64]
    velocity: NDArray[np.float64]
    damping: NDArray[np.float64]
    log_limits: NDArray[np.float64]

    @classmethod
    def of(cls, problems: Sequence[FoamProblem], dampings: Sequence[NDArray]) -> FoamLanes:
        """The lanes of ``problems[i]`` at the damping values ``dampings[i]``, in order."""
        first = problems[0]
        if not all(same_but_limits(first, p) for p in problems):
            raise InvalidParameterError(
                "problems", len(problems), "must differ only in a fixed robot, v_c and limits"
            )
        sizes = [d.size for d in dampings]
        robots = [p.robot_rows(None) for p in problems]
        limits = [[math.log(p.limit(key)) for key in p.keys()] for p in problems]
        return cls(
            **{f.name: getattr(first, f.name) for f in fields(FoamProblem)},
            rows=np.repeat(np.concatenate([r for r, _ in robots]), sizes, axis=0),
            velocity=np.repeat(np.concatenate([v for _, v in robots]), sizes),
            damping=np.concatenate(dampings),
            log_limits=np.repeat(np.array(limits, dtype=float), sizes, axis=0),
        )

    def _lane_inputs(self, c: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        i = np.asarray(c).astype(np.intp)
        return self.damping[i], self.rows[i], self.velocity[i]

    def log_limit(self, key: Criterion, c: NDArray) -> float | NDArray:
        if key.boundary == "lower":
            j = len(self.criteria)
        else:
            j = next(j for j, crit in enumerate(self.criteria) if crit is key)
        return self.log_limits[np.asarray(c).astype(np.intp), j]


def _closing_velocity(robot: object, impact_velocity: float | None) -> float:
    """v_c of a fixed robot (checked; it must be given), NaN for a robot at joint level."""
    contact_of(robot)  # a robot that no contact model serves is refused, naming those served
    if robot.along_link:  # type: ignore[attr-defined]
        if impact_velocity is not None:
            raise InvalidParameterError(
                "impact_velocity",
                impact_velocity,
                "must be None for a LinkImpact robot (v_c = joint_speed * l + human_speed)",
                "m/s",
            )
        return float("nan")
    if impact_velocity is None:
        raise InvalidParameterError(
            "impact_velocity",
            None,
            f"must be given for a {type(robot).__name__} robot ({IMPACT_VELOCITY.allowed()} "
            "m/s); None only for a LinkImpact, whose speed comes from the joint",
            "m/s",
        )
    return IMPACT_VELOCITY.check(impact_velocity)


def _criteria(criteria: Sequence[Criterion] | None, constrained: bool) -> tuple[Criterion, ...]:
    """The safety criteria checked (default: a_h,max <= 10 g)."""
    if criteria is not None and (
        isinstance(criteria, (str, Criterion)) or not hasattr(criteria, "__iter__")
    ):
        raise InvalidParameterError("criteria", criteria, "must be a sequence of Criterion objects")
    crit = tuple(criteria) if criteria is not None else (HeadAcceleration(10.0),)
    for c in crit:
        if not isinstance(c, Criterion):
            raise InvalidParameterError("criteria", c, "must contain Criterion objects")
        if c.boundary != "upper":
            raise InvalidParameterError(
                "criteria",
                c.name,
                "holds safety criteria (upper boundary); the thickness limit is max_compression",
            )
        if constrained and c.metric != "force":
            raise InvalidParameterError(
                "criteria",
                c.name,
                "the constrained impact (head against a wall) has a_h = 0: use force criteria",
            )
    return crit


def make_problem(
    robot: ContactDynamics | LinkImpact,
    impact_velocity: float | None,
    criteria: Sequence[Criterion] | None,
    max_compression: float,
    head_range: HeadRange | None,
    constrained: bool,
    human_speed: float,
    stop_time: float,
    foam: object | None = None,
) -> FoamProblem:
    """The worst-case problem of a foam design, every argument checked.

    Parameters
    ----------
    robot
        Effective manipulator (reduced or full joint), or a
        :class:`~designlab.impact.parameters.LinkImpact` struck anywhere.
    impact_velocity
        v_c, m/s (``None``: 1.25 m/s; must be ``None`` for a ``LinkImpact``).
    criteria
        Safety criteria (default: a_h,max <= 10 g).
    max_compression
        lambda, m.
    head_range
        ``None`` (each criterion's conservative head set) or a head-neck range.
    constrained
        The constrained impact (head against a wall); force criteria only.
    human_speed
        Head speed toward a ``LinkImpact`` robot, m/s.
    stop_time
        Window of the constrained impact's metrics, s.
    foam
        The foam whose stiffness and damping are varied, for a non-linear law
        (:class:`~designlab.impact.contact.HuntCrossleyFoam`); ``None``: the linear foam.

    Returns
    -------
    FoamProblem
    """
    v = _closing_velocity(robot, impact_velocity)
    human_speed = HUMAN_SPEED.check(human_speed)
    stop_time = STOP_TIME.check(stop_time)
    if not isinstance(constrained, (bool, np.bool_)):
        raise InvalidParameterError("constrained", constrained, "must be True or False")
    if head_range is not None and not isinstance(head_range, HeadRange):
        raise InvalidParameterError("head_range", head_range, "must be a HeadRange or None")
    crit = _criteria(criteria, bool(constrained))
    lam = MAX_COMPRESSION.check(max_compression)
    if foam is not None:
        contact_of(robot, foam)  # a foam this robot's contact models cannot take is refused
    return FoamProblem(
        robot, v, human_speed, crit, lam, head_range, bool(constrained), float(stop_time),
        foam=foam,
    )  # fmt: skip
