"""The Pareto front of a whole design: foam, speed limit and VFF gains chosen together.

A design is a foam covering (K_c, C_c, thickness T_u), the robot's speed limit V_mr in
the navigation scenarios and the four free VFF gains (K1, b, K3, K5). It is scored on
the navigation scenarios (simulated with the design's speed limit and gains) and, at
the closing speeds of those runs (:mod:`designlab.codesign.contacts`), on the impact
model. The objectives (all minimised; :data:`OBJECTIVES`) are

* ``arrival_time``: mean T_arrive over the scenarios (s);
* ``foam_thickness``: T_u (m);
* ``closing_speed``: the largest closing speed the runs met (m/s);
* ``injury_probability``: P(criterion exceeded | contact) at the closing speeds the runs
  met, over the head-neck range (:func:`designlab.codesign.injury_probability`; a design
  that meets nobody scores 0);
* ``crowd_injury_probability``: the same over the design's own encounters in a small set
  of crowds (its gains and speed limit; :class:`~designlab.codesign.CrowdEncounters`,
  optional: only with ``crowds=``);

and the hard constraints (a design that breaks one is infeasible, never traded) are:
no collision, no critical-region entry, arrival in every scenario, and a foam that
does not bottom out at the largest closing speed met (the worst-case compression of
:func:`designlab.impact.min_foam_thickness` within the linear depth).

:func:`pareto` (``dl.codesign.pareto``) searches the space with pymoo's NSGA-II
(seeded), keeps every design it evaluated, and returns a :class:`ParetoFront`: the
non-dominated feasible designs
(:func:`nondominated`), and the thesis's design (Foam 1, V_mr = 0.7 m/s, the
experiment gains; :data:`THESIS_DESIGN`) evaluated the same way with its distance from
the front.

Examples
--------
>>> import numpy as np
>>> nondominated(np.array([[1.0, 2.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0]])).tolist()
[True, True, False, True]
"""

from __future__ import annotations

import dataclasses
import math
import os
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from pymoo.algorithms.moo.nsga2 import NSGA2
from pymoo.core.problem import Problem
from pymoo.optimize import minimize

from designlab.codesign.contacts import MEASURES, ContactSpeeds, contact_speeds
from designlab.codesign.crowd_encounters import CrowdEncounters
from designlab.codesign.limits import FoamLimits, foam_limits
from designlab.codesign.parameters import RISK_SAMPLES
from designlab.codesign.risk import injury_probability
from designlab.codesign.robot import RobotDescription, people_names, sized_scenario
from designlab.codesign.speed import SafetyCase
from designlab.errors import InvalidParameterError
from designlab.impact import (
    FOAM_1,
    MANIPULATOR_1,
    THESIS_HEAD_RANGE,
    ContactDynamics,
    Criterion,
    Foam,
    HeadAcceleration,
    HeadRange,
)
from designlab.impact.parameters import HUMAN_SPEED
from designlab.navigation import (
    EXPERIMENT_GAINS,
    OPTIMAL_GAINS,
    CrowdScenario,
    HolonomicRobot,
    Scenario,
    VFFGains,
    simulate,
)
from designlab.params import ARG, Param, check_size, declared, params_of
from designlab.progress import Progress, ProgressHook, report
from designlab.results import Result, Status
from designlab.validation import real_array

__all__ = [
    "OBJECTIVES",
    "THESIS_DESIGN",
    "THESIS_DESIGNS",
    "Design",
    "DesignScore",
    "DesignSpace",
    "FrontStatus",
    "ParetoFront",
    "ReferencePoint",
    "evaluate_design",
    "nondominated",
    "nsga2",
    "pareto",
]

Array = NDArray[np.float64]

#: The linear fraction lambda / T_u of the Ch. 4 foam (0.02 m of 0.0254 m): a design's
#: linear depth is this share of its thickness.
LINEAR_FRACTION = 0.02 / 0.0254

#: The design variables, in the order of a design vector, with their units.
VARIABLES: tuple[tuple[str, str], ...] = (
    ("K_c", "N_per_m"),
    ("C_c", "N_s_per_m"),
    ("T_u", "m"),
    ("V_mr", "m_per_s"),
    ("k1", ""),
    ("b", ""),
    ("k3", ""),
    ("k5", ""),
)

#: Decimals of the speed limit V_mr a search evaluates (0.01 m/s, a controller's setting):
#: the speed and the regions sized for it are constants of the compiled navigation step, so
#: designs sharing V_mr share one compiled step instead of building one each (that build
#: was about 85 % of a design's navigation cost).
SPEED_DECIMALS = 2

#: Cap on the designs one search may evaluate (population x generations): each is a set
#: of navigation runs.
MAX_EVALUATIONS = 20_000

POPULATION = Param(
    None, "", "NSGA-II population size", kind="integer", ge=4, le=500, name="population"
)
GENERATIONS = Param(
    None, "", "NSGA-II generations (the first is the random start)", kind="integer", ge=1,
    le=1000, name="generations",
)  # fmt: skip
SEED = ARG.seed.but(doc="seed of the search")


# ------------------------------------------------------------------ the design space


def _bound(cls: type, fname: str, end: str, default: float) -> Any:
    """A search bound carrying the domain's own declaration of the variable."""
    decl = params_of(cls)[fname]
    word = "lowest" if end == "min" else "highest"
    symbol = f"{decl.symbol},{end}" if decl.symbol else f"{fname},{end}"
    bound = dataclasses.replace(
        decl, symbol=symbol, doc=f"{word} {decl.doc} searched", optional=False, typical=None
    )
    return dataclasses.field(default=default, metadata={"param": bound})


_PAIRS = (
    ("stiffness", Foam, "stiffness", (5.0e3, 80.0e3)),
    ("damping", Foam, "damping", (10.0, 200.0)),
    ("thickness", Foam, "thickness", (0.01, 0.06)),
    ("speed", HolonomicRobot, "max_speed", (0.3, 1.5)),
    ("k1", VFFGains, "k1", (1.0, 6.0)),
    ("b", VFFGains, "b", (0.1, 1.0)),
    ("k3", VFFGains, "k3", (10.0, 40.0)),
    ("k5", VFFGains, "k5", (10.0, 300.0)),
)


@declared
@dataclass(frozen=True)
class DesignSpace:
    """The box searched for a whole design: foam, speed limit and VFF gains.

    Each variable has a lowest and a highest value, bounded by the domain's own
    declaration (:class:`~designlab.impact.Foam`,
    :class:`~designlab.navigation.HolonomicRobot`, :class:`~designlab.navigation.VFFGains`).
    A variable whose bounds are equal is held fixed; a lowest value above the highest is
    refused (naming the bound).

    Examples
    --------
    >>> DesignSpace(speed_min=0.5, speed_max=0.5).free.tolist()
    [True, True, True, False, True, True, True, True]
    >>> DesignSpace(stiffness_min=9e4, stiffness_max=1e4)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: DesignSpace.stiffness_min = 90000.0 N/m is not ...
    """

    stiffness_min: float = _bound(Foam, "stiffness", "min", 5.0e3)
    stiffness_max: float = _bound(Foam, "stiffness", "max", 80.0e3)
    damping_min: float = _bound(Foam, "damping", "min", 10.0)
    damping_max: float = _bound(Foam, "damping", "max", 200.0)
    thickness_min: float = _bound(Foam, "thickness", "min", 0.01)
    thickness_max: float = _bound(Foam, "thickness", "max", 0.06)
    speed_min: float = _bound(HolonomicRobot, "max_speed", "min", 0.3)
    speed_max: float = _bound(HolonomicRobot, "max_speed", "max", 1.5)
    k1_min: float = _bound(VFFGains, "k1", "min", 1.0)
    k1_max: float = _bound(VFFGains, "k1", "max", 6.0)
    b_min: float = _bound(VFFGains, "b", "min", 0.1)
    b_max: float = _bound(VFFGains, "b", "max", 1.0)
    k3_min: float = _bound(VFFGains, "k3", "min", 10.0)
    k3_max: float = _bound(VFFGains, "k3", "max", 40.0)
    k5_min: float = _bound(VFFGains, "k5", "min", 10.0)
    k5_max: float = _bound(VFFGains, "k5", "max", 300.0)

    NAMES: ClassVar[tuple[str, ...]] = tuple(p[0] for p in _PAIRS)

    def snap(self, X: ArrayLike) -> Array:
        """Designs ``(n, 8)`` with V_mr rounded to :data:`SPEED_DECIMALS` decimals (in the box).

        Examples
        --------
        >>> DesignSpace().snap([[2e4, 50, 0.02, 0.7049, 3, 0.3, 20, 20]])[0, 3]
        np.float64(0.7)
        """
        out = np.array(X, dtype=float, ndmin=2)
        i = self.NAMES.index("speed")
        v = np.round(out[:, i], SPEED_DECIMALS)
        out[:, i] = np.clip(v, self.speed_min, self.speed_max)
        return out

    def __post_init__(self) -> None:
        for name in self.NAMES:
            lo, hi = getattr(self, f"{name}_min"), getattr(self, f"{name}_max")
            if lo > hi:
                unit = params_of(self)[f"{name}_min"].unit
                raise InvalidParameterError(
                    f"DesignSpace.{name}_min",
                    lo,
                    f"must be <= {name}_max = {hi:g} (an empty range)",
                    unit,
                )

    @property
    def lower(self) -> Array:
        """Lowest values in the order of :data:`VARIABLES`."""
        return np.array([getattr(self, f"{n}_min") for n in self.NAMES])

    @property
    def upper(self) -> Array:
        """Highest values in the order of :data:`VARIABLES`."""
        return np.array([getattr(self, f"{n}_max") for n in self.NAMES])

    @property
    def free(self) -> NDArray[np.bool_]:
        """Which variables are searched (their bounds differ)."""
        return self.upper > self.lower


@dataclass(frozen=True)
class Design:
    """One whole design: the foam covering, the speed limit and the VFF gains.

    Attributes
    ----------
    foam
        The foam covering (K_c, C_c, linear depth and thickness T_u).
    speed
        The robot's speed limit V_mr in the navigation scenarios (m/s).
    gains
        The VFF gains.

    Examples
    --------
    >>> THESIS_DESIGN.vector().tolist()[:4]
    [24250.0, 71.9, 0.0254, 0.7]
    """

    foam: Foam
    speed: float
    gains: VFFGains

    def __post_init__(self) -> None:
        if not isinstance(self.foam, Foam):
            raise InvalidParameterError("Design.foam", self.foam, "must be an impact Foam")
        if not isinstance(self.gains, VFFGains):
            raise InvalidParameterError("Design.gains", self.gains, "must be VFFGains")
        speed = params_of(HolonomicRobot)["max_speed"].check(self.speed, "Design.speed")
        object.__setattr__(self, "speed", speed)

    def vector(self) -> Array:
        """``[K_c, C_c, T_u, V_mr, k1, b, k3, k5]``."""
        f = self.foam
        return np.array([f.stiffness, f.damping, f.thickness, self.speed, *self.gains.as_array()])

    @classmethod
    def from_vector(cls, x: ArrayLike) -> Design:
        """The design of a vector ``[K_c, C_c, T_u, V_mr, k1, b, k3, k5]``."""
        vec = real_array("x", x)
        if vec.shape != (len(VARIABLES),):
            raise InvalidParameterError(
                "x", vec, f"must be {len(VARIABLES)} values {[n for n, _ in VARIABLES]}"
            )
        k, c, t, v, k1, b, k3, k5 = (float(a) for a in vec)
        foam = Foam(k, c, linear_depth=t * LINEAR_FRACTION, thickness=t)
        return cls(foam, v, VFFGains(k1=k1, b=b, k3=k3, k5=k5))


#: The thesis's design: Foam 1 (Table 3.3, 25.4 mm), V_mr = 0.7 m/s (Ch. 6), the
#: experiment gains (Sec. 6.2.4).
THESIS_DESIGN = Design(FOAM_1, 0.7, EXPERIMENT_GAINS)

#: The thesis's designs placed against a front by default: Foam 1 at V_mr = 0.7 m/s with
#: the experiment gains and with the optimised gains of Table C.1.
THESIS_DESIGNS: dict[str, Design] = {
    "thesis, experiment gains": THESIS_DESIGN,
    "thesis, optimal gains": Design(FOAM_1, 0.7, OPTIMAL_GAINS),
}


# ---------------------------------------------------------------- non-dominated filter


def nondominated(F: ArrayLike) -> NDArray[np.bool_]:
    """Which rows of ``F`` (objectives to minimise) no other row dominates.

    Row j dominates row i when it is no worse in every objective and better in one.
    Equal rows do not dominate each other (both are kept).

    Parameters
    ----------
    F
        ``(n, m)`` objective values (finite or ``inf``; not NaN).

    Returns
    -------
    numpy.ndarray
        ``(n,)`` booleans.

    Examples
    --------
    >>> nondominated([[0.0, 1.0], [1.0, 0.0], [1.0, 1.0]]).tolist()
    [True, True, False]
    """
    try:
        A = np.asarray(F, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameterError("F", F, "must be an (n, m) array of numbers") from None
    if A.ndim != 2 or np.isnan(A).any():
        raise InvalidParameterError("F", "array", "must be an (n, m) array without NaN")
    check_size("F", f"{A.shape[0]} rows", 2.0 * A.shape[0] ** 2 * A.shape[1],
               what="the pairwise comparison of its rows")  # fmt: skip
    no_worse = (A[:, None, :] <= A[None, :, :]).all(axis=2)  # [j, i]: j no worse than i
    better = (A[:, None, :] < A[None, :, :]).any(axis=2)
    return ~(no_worse & better).any(axis=0)


# ------------------------------------------------------------------------- the search


@dataclass(frozen=True)
class SearchOutcome:
    """Every design a :func:`nsga2` search evaluated, in order.

    Attributes
    ----------
    X, F, G
        Variables ``(n, n_var)``, objectives ``(n, n_obj)`` and constraints
        ``(n, n_constr)`` (feasible: every G <= 0).
    generations
        The generation of each evaluated design (1-based).
    """

    X: Array
    F: Array
    G: Array
    generations: NDArray[np.int_]

    @property
    def feasible(self) -> NDArray[np.bool_]:
        """Designs whose constraints all hold."""
        return (self.G <= 0.0).all(axis=1) if self.G.shape[1] else np.ones(len(self.X), bool)


class _Archived(Problem):  # type: ignore[misc]
    """A pymoo problem that evaluates row by row and keeps every evaluation."""

    def __init__(self, evaluate: Callable[[Array], tuple[Array, Array]], lower: Array,
                 upper: Array, n_obj: int, n_constr: int, total: int,
                 progress: ProgressHook | None,
                 prepare: Callable[[Array], None] | None = None,
                 snap: Callable[[Array], Array] | None = None) -> None:  # fmt: skip
        super().__init__(n_var=lower.size, n_obj=n_obj, n_ieq_constr=n_constr, xl=lower, xu=upper)
        self.evaluate_row = evaluate
        self.prepare = prepare
        self.snap = snap
        self.rows: list[tuple[Array, Array, Array, int]] = []
        self.batch = 0
        self.total = total
        self.progress = progress

    def _evaluate(self, x: Array, out: dict[str, Any], *args: Any, **kwargs: Any) -> None:
        self.batch += 1
        if self.snap is not None:  # the points evaluated and archived are the snapped ones
            x = self.snap(np.atleast_2d(x))
        if self.prepare is not None:
            self.prepare(x)
        F, G = zip(*(self.evaluate_row(row) for row in x), strict=True)
        out["F"], out["G"] = np.array(F), np.array(G)
        self.rows += [(r, f, g, self.batch) for r, f, g in zip(x, F, G, strict=True)]
        feasible = [f[0] for _, f, g, _ in self.rows if (np.asarray(g) <= 0).all()]
        best = float(min(feasible)) if feasible else None
        report(self.progress, Progress(self.batch, self.total, best, "generation"))


#: Objectives and constraints of one :func:`nsga2` search.
N_OBJ = Param(None, "", "objectives of the search", kind="integer", ge=1, le=20, name="n_obj")
N_CONSTR = Param(
    None, "", "constraints of the search", kind="integer", ge=0, le=100, name="n_constr"
)
#: Variables of one :func:`nsga2` search.
N_VAR = Param(None, "", "variables of the search", kind="integer", ge=1, le=1000, name="lower")


def _check_box(lower: ArrayLike, upper: ArrayLike) -> tuple[Array, Array]:
    """The box of a search: two finite 1-d arrays of one length with lower <= upper."""
    lo, hi = real_array("lower", lower), real_array("upper", upper)
    if lo.ndim != 1 or hi.shape != lo.shape:
        raise InvalidParameterError(
            "upper", hi, f"must be a 1-d array of the length of lower ({lo.shape})"
        )
    N_VAR.check(lo.size, "lower (how many variables)")
    if (lo > hi).any():
        i = int(np.argmax(lo > hi))
        raise InvalidParameterError(f"lower[{i}]", float(lo[i]), f"must be <= upper[{i}] = "
                                    f"{float(hi[i]):g} (an empty range)")  # fmt: skip
    return lo, hi


def _checked_evaluate(
    evaluate: Callable[[Array], tuple[Array, Array]], n_obj: int, n_constr: int
) -> Callable[[Array], tuple[Array, Array]]:
    """``evaluate`` whose answers are checked: ``n_obj`` objectives (no NaN) and
    ``n_constr`` constraints (a wrong answer names the point, not pymoo's internals)."""

    def checked(x: Array) -> tuple[Array, Array]:
        try:
            f, g = evaluate(x)
        except (TypeError, ValueError) as exc:
            if isinstance(exc, InvalidParameterError):
                raise
            raise InvalidParameterError(
                "evaluate", x.tolist(), f"must return (f, g); it raised {exc!r}"
            ) from None
        f, g = np.asarray(f, dtype=float).ravel(), np.asarray(g, dtype=float).ravel()
        if f.shape != (n_obj,) or np.isnan(f).any():
            raise InvalidParameterError(
                "evaluate", x.tolist(), f"must return {n_obj} objectives without NaN, got {f}"
            )
        if g.shape != (n_constr,) or np.isnan(g).any():
            raise InvalidParameterError(
                "evaluate", x.tolist(), f"must return {n_constr} constraints without NaN, got {g}"
            )
        return f, g

    return checked


def nsga2(
    evaluate: Callable[[Array], tuple[Array, Array]],
    lower: ArrayLike,
    upper: ArrayLike,
    *,
    n_obj: int,
    n_constr: int = 0,
    population: int = 16,
    generations: int = 8,
    seed: int = ARG.seed.default,
    progress: ProgressHook | None = None,
    initial: ArrayLike | None = None,
    prepare: Callable[[Array], None] | None = None,
    snap: Callable[[Array], Array] | None = None,
) -> SearchOutcome:
    """Minimise several objectives in a box with pymoo's NSGA-II; keep every evaluation.

    Parameters
    ----------
    evaluate
        ``x -> (f, g)``: the objectives ``(n_obj,)`` and constraints ``(n_constr,)`` of one
        point (feasible when every g <= 0).
    lower, upper
        The box (equal values hold a variable fixed).
    n_obj, n_constr
        Numbers of objectives and constraints.
    population, generations
        NSGA-II population size and number of generations.
    seed
        Seed of the search (the same seed gives the same designs).
    progress
        Called after each generation (:mod:`designlab.progress`).
    initial
        Points ``(k, n_var)`` (k <= population, inside the box) placed in the first
        population; the rest of it is drawn uniformly (seeded).
    prepare
        Called with each generation's points ``(n, n_var)`` before they are evaluated one
        by one (e.g. to compute something for the whole batch at once).
    snap
        Maps a generation's points ``(n, n_var)`` to the points evaluated (e.g. a variable
        rounded to its resolution, staying in the box); the outcome holds the snapped
        points. ``None``: evaluated as drawn.

    Returns
    -------
    SearchOutcome

    Examples
    --------
    >>> out = nsga2(lambda x: (np.array([x[0] ** 2, (x[0] - 2) ** 2]), np.zeros(0)),
    ...             [-5.0], [5.0], n_obj=2, population=8, generations=3, seed=1)
    >>> out.X.shape, int(out.generations.max())
    ((24, 1), 3)
    """
    lo, hi = _check_box(lower, upper)
    if not callable(evaluate):
        raise InvalidParameterError("evaluate", evaluate, "must be a function x -> (f, g)")
    n_obj, n_constr = N_OBJ.check(n_obj), N_CONSTR.check(n_constr)
    evaluate = _checked_evaluate(evaluate, n_obj, n_constr)
    pop = POPULATION.check(population)
    gens = GENERATIONS.check(generations)
    if pop * gens > MAX_EVALUATIONS:
        raise InvalidParameterError(
            "generations", gens, f"population x generations must be <= {MAX_EVALUATIONS}"
        )
    free = hi > lo
    if not free.any():  # nothing to search: the one design
        f, g = evaluate(lo)
        one = np.array([1])
        return SearchOutcome(
            lo[None, :], np.reshape(f, (1, n_obj)), np.reshape(g, (1, n_constr)), one
        )

    def on_free(z: Array) -> tuple[Array, Array]:
        x = lo.copy()
        x[free] = z
        return evaluate(x)

    def expand(Z: Array) -> Array:
        X = np.tile(lo, (len(Z), 1))
        X[:, free] = Z
        return X

    hook = None if prepare is None else (lambda Z: prepare(expand(np.atleast_2d(Z))))
    snapped = None if snap is None else (lambda Z: np.asarray(snap(expand(Z)))[:, free])
    problem = _Archived(on_free, lo[free], hi[free], n_obj, n_constr, gens, progress, hook,
                        snapped)  # fmt: skip
    start = _first_population(initial, lo, hi, pop, SEED.check(seed))[:, free]
    minimize(problem, NSGA2(pop_size=pop, sampling=start), ("n_gen", gens), seed=seed,
             verbose=False)  # fmt: skip
    X = np.tile(lo, (len(problem.rows), 1))
    X[:, free] = np.array([r[0] for r in problem.rows]).reshape(len(problem.rows), -1)
    return SearchOutcome(
        X=X,
        F=np.array([r[1] for r in problem.rows], dtype=float).reshape(len(X), n_obj),
        G=np.array([r[2] for r in problem.rows], dtype=float).reshape(len(X), n_constr),
        generations=np.array([r[3] for r in problem.rows], dtype=int),
    )


def _first_population(initial: ArrayLike | None, lo: Array, hi: Array, pop: int,
                      seed: int) -> Array:  # fmt: skip
    """The first population: the ``initial`` points, then uniform draws (seeded)."""
    rng = np.random.default_rng(seed)
    X = lo + rng.random((pop, lo.size)) * (hi - lo)
    if initial is None:
        return X
    given = np.atleast_2d(real_array("initial", initial))
    if given.shape[1] != lo.size or len(given) > pop:
        raise InvalidParameterError(
            "initial", given.shape, f"must be at most {pop} rows of {lo.size} values"
        )
    outside = (given < lo) | (given > hi)
    if outside.any():
        i, j = np.argwhere(outside)[0]
        raise InvalidParameterError(f"initial[{i}][{j}]", float(given[i, j]),
                                    f"must lie in [{lo[j]:g}, {hi[j]:g}]")  # fmt: skip
    X[: len(given)] = given
    return X


# ------------------------------------------------------- scoring one design


@dataclass(frozen=True)
class DesignScore:
    """What one design gives: its navigation runs' outcome and its impact numbers.

    Attributes
    ----------
    design
        The :class:`Design`.
    arrival_time
        Mean T_arrive over the scenarios (s; ``inf`` if a run did not arrive).
    collisions, critical_entries, not_arrived
        How many runs collided, entered a critical region, did not arrive.
    contacts
        The runs' encounters (:class:`~designlab.codesign.ContactSpeeds`).
    closing_speed
        The largest closing speed met (m/s).
    required_thickness
        The thickness T_u the foam needs not to bottom out at the larger of that speed and
        the worst contact of its speed limit, V_mr + the walker's speed, for the worst
        head of the range found off the grid (:func:`~designlab.codesign.foam_limits`; m).
    injury_probability
        P(criterion exceeded | contact) at the encounters' closing speeds (``nan`` when
        not asked for).
    capped_arrival_time
        Mean T_arrive with a run that did not arrive counted at its horizon T_max (s;
        finite, for the sensitivity of the front, :mod:`designlab.codesign.sensitivity`).
    crowd_contacts
        The design's encounters in the crowds (``None`` without crowds).
    crowd_injury_probability
        P(criterion exceeded | contact) over them (``nan`` without crowds or criterion; 0
        when it met nobody).
    speed_limit
        The robot speed the design's foam allows for the stated walker speed
        (:func:`~designlab.codesign.speed_limit`, m/s).
    risk_bound
        The stated upper bound on P(criterion exceeded | contact).
    """

    design: Design
    arrival_time: float
    collisions: int
    critical_entries: int
    not_arrived: int
    contacts: ContactSpeeds = field(repr=False)
    closing_speed: float
    required_thickness: float
    injury_probability: float = math.nan
    capped_arrival_time: float = math.nan
    crowd_contacts: ContactSpeeds | None = field(default=None, repr=False)
    crowd_injury_probability: float = math.nan
    speed_limit: float = math.inf
    risk_bound: float = 1.0

    @property
    def exceedance_probability(self) -> float:
        """P(criterion exceeded | contact): :attr:`injury_probability` under its honest name."""
        return self.injury_probability

    @property
    def constraints(self) -> Array:
        """G <= 0 when feasible, in the order of :data:`CONSTRAINTS`.

        Collisions, critical-region entries, non-arrivals, the foam's thickness shortfall
        (m), the speed limit V_mr above what the foam allows (m/s;
        :func:`~designlab.codesign.speed_limit`), and the exceedance probability above the
        stated bound (both probabilities, when asked for).
        """
        risk = [p for p in (self.injury_probability, self.crowd_injury_probability)
                if not math.isnan(p)]  # fmt: skip
        return np.array(
            [
                self.collisions,
                self.critical_entries,
                self.not_arrived,
                self.required_thickness - self.design.foam.thickness,
                self.design.speed - self.speed_limit,
                (max(risk) if risk else 0.0) - self.risk_bound,
            ],
            dtype=float,
        )

    @property
    def feasible(self) -> bool:
        """Every hard constraint holds."""
        return bool((self.constraints <= 0.0).all())


#: The hard constraints, in the order of :attr:`DesignScore.constraints`.
CONSTRAINTS = (
    "collisions",
    "critical_entries",
    "not_arrived",
    "thickness_shortfall_m",
    "speed_over_limit_m_per_s",
    "risk_over_bound",
)


@dataclass(frozen=True)
class Objective:
    """An objective to minimise: its name, unit and how a score gives it.

    Attributes
    ----------
    name, unit, doc
        Its name (a key of :data:`OBJECTIVES`), unit (in column names) and meaning.
    of
        ``score -> value`` for a :class:`DesignScore`.
    """

    name: str
    unit: str
    doc: str
    of: Callable[[DesignScore], float]

    @property
    def column(self) -> str:
        """Column name with the unit (``arrival_time_s``)."""
        return f"{self.name}_{self.unit}" if self.unit else self.name


#: The objectives :func:`pareto` knows (all minimised).
OBJECTIVES: dict[str, Objective] = {
    o.name: o
    for o in (
        Objective("arrival_time", "s", "mean arrival time over the scenarios",
                  lambda s: s.arrival_time),
        Objective("foam_thickness", "m", "foam thickness T_u", lambda s: s.design.foam.thickness),
        Objective("closing_speed", "m_per_s", "largest closing speed met",
                  lambda s: s.closing_speed),
        Objective("exceedance_probability", "", "P(criterion exceeded | contact)",
                  lambda s: s.injury_probability),
        Objective("injury_probability", "",
                  "P(criterion exceeded | contact) (the former name of exceedance_probability)",
                  lambda s: s.injury_probability),
        Objective("crowd_injury_probability", "",
                  "P(criterion exceeded | contact) over the design's crowd encounters",
                  lambda s: s.crowd_injury_probability),
    )
}  # fmt: skip


#: Navigation scenarios every design is simulated in (each design runs each of them).
SCENARIOS = Param(None, "", "navigation scenarios of a design's score", kind="integer", ge=1,
                  le=100, name="scenarios")  # fmt: skip


def _check_scenarios(scenarios: Any) -> tuple[Scenario, ...]:
    if isinstance(scenarios, Scenario):
        return (scenarios,)
    if isinstance(scenarios, (str, bytes)) or not hasattr(scenarios, "__len__"):
        raise InvalidParameterError("scenarios", scenarios, "must be one or more Scenario objects")
    SCENARIOS.check(len(scenarios), "scenarios (how many)")
    items = tuple(scenarios)
    if not items or not all(isinstance(s, Scenario) for s in items):
        raise InvalidParameterError("scenarios", scenarios, "must be one or more Scenario objects")
    return items


def _check_scoring(robot: Any, heads: Any, measure: Any, risk_samples: Any, seed: Any) -> None:
    """The impact side of a design's score, checked before any run."""
    if not isinstance(robot, ContactDynamics | RobotDescription):
        raise InvalidParameterError(
            "robot", robot, "must be an impact ContactDynamics or a RobotDescription"
        )
    if not isinstance(heads, HeadRange):
        raise InvalidParameterError("heads", heads, "must be an impact HeadRange")
    if not isinstance(measure, str) or measure not in MEASURES:
        raise InvalidParameterError("measure", measure, f"must be one of {MEASURES}")
    RISK_SAMPLES.check(risk_samples, "risk_samples")
    SEED.check(seed)


#: The stated upper bound on P(criterion exceeded | contact) of a design (1: no bound).
RISK_BOUND = Param(
    None, "", "upper bound on P(criterion exceeded | contact) of a feasible design", ge=0,
    le=1, default=1.0, name="risk_bound",
)  # fmt: skip


def contact_of(robot: ContactDynamics | RobotDescription) -> ContactDynamics:
    """The impact model of the part that touches people.

    Parameters
    ----------
    robot
        A :class:`~designlab.impact.ContactDynamics` or a
        :class:`~designlab.codesign.RobotDescription`.
    """
    return robot.contact if isinstance(robot, RobotDescription) else robot


def design_limits(
    designs: Sequence[Design], robot: ContactDynamics | RobotDescription, heads: HeadRange,
    human_speed: float,
) -> FoamLimits:  # fmt: skip
    """The speed limit and thickness needs of the designs' foams (one lock-step search).

    Parameters
    ----------
    designs
        The designs.
    robot, heads, human_speed
        As in :func:`evaluate_design`.

    Returns
    -------
    FoamLimits
    """
    f = [d.foam for d in designs]
    return foam_limits(
        contact_of(robot), [x.stiffness for x in f], [x.damping for x in f],
        [x.linear_depth for x in f], [x.thickness for x in f],
        SafetyCase(head_range=heads, human_speed=human_speed),
    )  # fmt: skip


def design_runs(design: Design, items: Sequence[Scenario], robot: Any, walker: float) -> list[Any]:
    """The design's navigation runs: its speed limit, gains and regions sized for it.

    Parameters
    ----------
    design
        The design.
    items
        The scenarios.
    robot
        A :class:`~designlab.codesign.RobotDescription` (its footprint and limits) or an
        impact model (the scenarios' robot is kept).
    walker
        The people's largest speed the regions are sized for, m/s.
    """
    out = []
    for sc in items:
        if isinstance(robot, RobotDescription):
            nav_robot = robot.navigation_robot(design.speed)
        else:
            nav_robot = dataclasses.replace(sc.robot, max_speed=design.speed)
        out.append(simulate(sized_scenario(sc, nav_robot, walker), design.gains))
    return out


def evaluate_design(
    design: Design,
    scenarios: Scenario | Sequence[Scenario],
    *,
    robot: ContactDynamics | RobotDescription = MANIPULATOR_1,
    heads: HeadRange = THESIS_HEAD_RANGE,
    measure: str = "relative",
    criterion: Criterion | None = None,
    risk_samples: int = 20_000,
    seed: int = ARG.seed.default,
    crowds: CrowdEncounters | None = None,
    human_speed: float = 1.0,
    risk_bound: float = RISK_BOUND.default,
    limits: FoamLimits | None = None,
) -> DesignScore:
    """Simulate the scenarios with the design's speed limit and gains and score it.

    Parameters
    ----------
    design
        The :class:`Design`.
    scenarios
        Navigation scenarios (their robot's speed limit is replaced by the design's, and
        every region grows to at least the minimum for it:
        :func:`~designlab.codesign.sized_scenario`).
    robot
        The robot (:class:`~designlab.codesign.RobotDescription`: navigation takes its
        footprint and limits, impact its touching part), or only the impact model of the
        touching part (navigation keeps the scenarios' robot).
    heads
        The head-neck range whose worst head (off the grid) sets the speed limit and the
        foam thickness needed.
    measure
        Which closing speed of the encounters counts (:func:`contact_speeds`).
    criterion
        The criterion of :attr:`DesignScore.injury_probability`; ``None``: not computed.
    risk_samples, seed
        Monte Carlo samples and seed of :func:`designlab.codesign.injury_probability`.
    crowds
        Crowd encounters of the design's gains and speed limit
        (:class:`~designlab.codesign.CrowdEncounters`), for
        :attr:`DesignScore.crowd_injury_probability`; ``None``: no crowd runs.
    human_speed
        The walker's speed toward the robot the speed limit assumes, and the people's
        largest speed the regions are sized for (m/s).
    risk_bound
        The stated upper bound on P(criterion exceeded | contact) (a hard constraint).
    limits
        The design's foam limits when already computed (one row of
        :func:`design_limits`); ``None``: computed here.

    Returns
    -------
    DesignScore

    Examples
    --------
    >>> import designlab.navigation as nav
    >>> s = evaluate_design(THESIS_DESIGN, [nav.configuration(2)])
    >>> s.feasible, round(s.arrival_time, 2), round(s.speed_limit, 3)
    (True, 12.12, 0.807)
    """
    if not isinstance(design, Design):
        raise InvalidParameterError("design", design, "must be a Design")
    _check_scoring(robot, heads, measure, risk_samples, seed)
    walker = HUMAN_SPEED.check(human_speed, "human_speed")
    bound = RISK_BOUND.check(risk_bound)
    if crowds is not None and not isinstance(crowds, CrowdEncounters):
        raise InvalidParameterError("crowds", crowds, "must be a CrowdEncounters or None")
    items = _check_scenarios(scenarios)
    return _score(design, items, robot, heads, measure, criterion, risk_samples, seed, crowds,
                  walker, bound, limits)  # fmt: skip


def _exceedance(contact: ContactDynamics, foam: Foam, c: ContactSpeeds | None, heads: HeadRange,
                criterion: Criterion | None, samples: int, seed: int) -> float:  # fmt: skip
    """P(criterion exceeded | contact) over encounters ``c`` (nan: not asked; 0: no contact)."""
    if criterion is None or c is None:
        return math.nan
    if not len(c) or not (np.asarray(c.samples) > 0).any():
        return 0.0  # nobody met, or met at rest: no contact
    return float(injury_probability(contact, foam, closing_speed=c, heads=heads,
                                    criterion=criterion, samples=samples,
                                    seed=seed).probability)  # fmt: skip


def _score(design: Design, items: tuple[Scenario, ...], robot: Any, heads: HeadRange,
           measure: str, criterion: Criterion | None, risk_samples: int, seed: int,
           crowds: CrowdEncounters | None, walker: float, bound: float,
           limits: FoamLimits | None) -> DesignScore:  # fmt: skip
    """The checked body of :func:`evaluate_design`."""
    lim = design_limits([design], robot, heads, walker) if limits is None else limits
    runs = design_runs(design, items, robot, walker)
    capped = [min(r.arrival_time, sc.horizon) for r, sc in zip(runs, items, strict=True)]
    people = sorted({n for sc in items for n in people_names(sc)})
    # people only: a still disc (a pole) is not a person
    contacts = contact_speeds(runs if people else [], measure=measure, obstacles=people or None)
    v = float(contacts.samples.max()) if len(contacts) else 0.0
    contact = contact_of(robot)

    def risk_over(c: ContactSpeeds | None) -> float:
        return _exceedance(contact, design.foam, c, heads, criterion, risk_samples, seed)

    crowd = None if crowds is None else crowds.of(design.speed, design.gains)
    worst = max(v, design.speed + walker)
    return DesignScore(
        design=design,
        arrival_time=float(np.mean([r.arrival_time for r in runs])),
        collisions=sum(r.collided for r in runs),
        critical_entries=sum(r.entered_critical for r in runs),
        not_arrived=sum(not r.arrived for r in runs),
        contacts=contacts,
        closing_speed=v,
        required_thickness=float(lim.required_thickness(worst)[0]),
        injury_probability=float(risk_over(contacts)),
        capped_arrival_time=float(np.mean(capped)),
        crowd_contacts=crowd,
        crowd_injury_probability=risk_over(crowd),
        speed_limit=float(lim.max_speed[0]),
        risk_bound=bound,
    )


# ----------------------------------------------------------------------- the front


class FrontStatus(Status):
    """Status of a :class:`ParetoFront`.

    ``OK``: at least one feasible design; ``NO_FEASIBLE``: every design evaluated broke
    a hard constraint (the front is empty).
    """

    OK = "ok"
    NO_FEASIBLE = "no_feasible"


def _variable_columns() -> list[str]:
    return [f"{n}_{u}" if u else n for n, u in VARIABLES]


@dataclass(frozen=True)
class ReferencePoint:
    """A design placed against a front.

    Attributes
    ----------
    label
        Its name (``"thesis, experiment gains"``).
    score
        Its :class:`DesignScore`.
    objectives
        Its objectives, in the front's order.
    distance
        Normalised distance to the nearest front design (each objective divided by its span
        over the front and this point); 0 on the front, ``inf`` with an empty front.
    dominated_by
        How many front designs are no worse in every objective and better in one.
    """

    label: str
    score: DesignScore
    objectives: Array
    distance: float
    dominated_by: int


@dataclass(frozen=True)
class ParetoFront(Result):
    """The designs a search evaluated, its non-dominated feasible ones, and the reference.

    Attributes
    ----------
    objectives
        Names of the objectives (:data:`OBJECTIVES`), all minimised.
    X, F, G
        Every evaluated design: variables (:data:`VARIABLES`), objectives and
        constraints (:data:`CONSTRAINTS`; feasible: all <= 0).
    generations
        The generation each design was evaluated in.
    feasible, front
        Which designs are feasible, and which feasible ones are non-dominated.
    references
        The designs placed against the front (:class:`ReferencePoint`; by default the
        thesis's, :data:`THESIS_DESIGNS`); :attr:`reference` and the ``reference_*``
        properties are the first one's.
    seed
        The seed of the search.
    status, warnings
        See :class:`FrontStatus`.
    hypervolume
        The hypervolume of the feasible designs found up to each generation
        (:func:`hypervolume_trace`).
    worker_cpu_seconds
        CPU time the executor's workers spent scoring designs (s; 0 in this process alone:
        add it to this process's CPU time for the search's whole cost).
    """

    objectives: tuple[str, ...]
    X: Array = field(repr=False)
    F: Array = field(repr=False)
    G: Array = field(repr=False)
    generations: NDArray[np.int_] = field(repr=False)
    feasible: NDArray[np.bool_] = field(repr=False)
    front: NDArray[np.bool_] = field(repr=False)
    references: tuple[ReferencePoint, ...] = field(repr=False)
    seed: int = ARG.seed.default
    status: str = FrontStatus.OK
    warnings: tuple[str, ...] = ()
    hypervolume: Array = field(default_factory=lambda: np.zeros(0), repr=False)
    worker_cpu_seconds: float = 0.0

    @property
    def hypervolume_change(self) -> float:
        """Relative change of the hypervolume over the last :data:`HV_WINDOW` generations."""
        return hypervolume_change(self.hypervolume)

    @property
    def converged(self) -> bool:
        """Whether the hypervolume changed less than :data:`HV_TOLERANCE` over the last
        :data:`HV_WINDOW` generations."""
        return self.hypervolume_change < HV_TOLERANCE

    def knee(self) -> int:
        """The knee of the front: the row of :meth:`to_frame` farthest below the hyperplane
        through its extreme points, in objectives normalised over the front (Das 1999;
        :func:`knee_point`)."""
        return knee_point(self.to_frame()[self.columns].to_numpy())

    def pick(self, weights: Sequence[float]) -> int:
        """The row of :meth:`to_frame` that minimises the weighted sum of the objectives
        normalised over the front (a stated preference: ``weights`` per objective).

        Parameters
        ----------
        weights
            One non-negative weight per objective, not all zero.
        """
        return preference_pick(self.to_frame()[self.columns].to_numpy(), weights)

    @property
    def reference(self) -> DesignScore | None:
        """The first reference design's score, or ``None``."""
        return self.references[0].score if self.references else None

    @property
    def reference_objectives(self) -> Array:
        """The first reference's objectives (empty without one)."""
        return self.references[0].objectives if self.references else np.zeros(0)

    @property
    def reference_distance(self) -> float:
        """The first reference's normalised distance from the front (``nan`` without one)."""
        return self.references[0].distance if self.references else math.nan

    @property
    def reference_dominated_by(self) -> int:
        """How many front designs dominate the first reference."""
        return self.references[0].dominated_by if self.references else 0

    @property
    def columns(self) -> list[str]:
        """Objective columns with units."""
        return [OBJECTIVES[o].column for o in self.objectives]

    def designs(self) -> list[Design]:
        """The front's designs, sorted by the first objective."""
        return [Design.from_vector(x) for x in self.to_frame()[_variable_columns()].to_numpy()]

    def to_frame(self) -> pd.DataFrame:
        """The non-dominated feasible designs: variables and objectives, by the first objective."""
        frame = self.designs_frame()
        front = frame[frame["on_front"]].drop(columns=["on_front", "feasible", *CONSTRAINTS])
        return front.sort_values(self.columns[0], kind="stable").reset_index(drop=True)

    def designs_frame(self) -> pd.DataFrame:
        """Every evaluated design: generation, variables, objectives, constraints, flags."""
        frame = pd.DataFrame(self.X, columns=_variable_columns())
        frame.insert(0, "generation", self.generations)
        for j, col in enumerate(self.columns):
            frame[col] = self.F[:, j]
        for j, name in enumerate(CONSTRAINTS):
            frame[name] = self.G[:, j]
        frame["feasible"] = self.feasible
        frame["on_front"] = self.front
        return frame

    def reference_frame(self) -> pd.DataFrame:
        """One row per reference: its design, objectives, constraints and distance."""
        rows = []
        for ref in self.references:
            row: dict[str, Any] = {"label": ref.label}
            row.update(zip(_variable_columns(), ref.score.design.vector(), strict=True))
            row.update(zip(self.columns, ref.objectives, strict=True))
            row.update(zip(CONSTRAINTS, ref.score.constraints, strict=True))
            row["feasible"] = ref.score.feasible
            row["distance_to_front"] = ref.distance
            row["dominated_by"] = ref.dominated_by
            rows.append(row)
        return pd.DataFrame(rows)


def _reference_position(front_F: Array, ref: Array, feasible: bool = True) -> tuple[float, int]:
    """Normalised distance from ``ref`` to the nearest front point, and how many dominate it
    (0 for a feasible point nothing dominates: it is on the front)."""
    if front_F.size == 0 or not np.isfinite(ref).all():
        return (0.0 if feasible and front_F.size == 0 else math.inf), 0
    both = np.vstack([front_F, ref])
    span = np.ptp(both, axis=0)
    span[span == 0.0] = 1.0
    dist = float(np.min(np.linalg.norm((front_F - ref) / span, axis=1)))
    dominating = (front_F <= ref).all(axis=1) & (front_F < ref).any(axis=1)
    if feasible and not dominating.any():
        return 0.0, 0
    return dist, int(dominating.sum())


#: Generations over which the hypervolume's change is measured, and the largest relative
#: change of a converged search.
HV_WINDOW = 5
HV_TOLERANCE = 0.01


def _normalised(F: Array) -> Array:
    """``F`` scaled to [0, 1] per objective over its own rows (a constant column: 0)."""
    lo, span = F.min(axis=0), np.ptp(F, axis=0)
    return (F - lo) / np.where(span > 0, span, 1.0)


def hypervolume_trace(
    F: Array, feasible: NDArray[np.bool_], generations: NDArray[np.int_]
) -> Array:
    """Hypervolume of the feasible designs evaluated up to each generation.

    Objectives are normalised to [0, 1] over every feasible design evaluated, and the
    reference point is 1.1 in each (pymoo's exact hypervolume).

    Parameters
    ----------
    F, feasible, generations
        The search's objectives, feasibility and generation of each design.

    Returns
    -------
    numpy.ndarray
        One value per generation (0 before the first feasible design).

    Examples
    --------
    >>> F = np.array([[0.0, 1.0], [1.0, 0.0], [0.5, 0.5]])
    >>> hypervolume_trace(F, np.ones(3, bool), np.array([1, 1, 2])).round(4).tolist()
    [0.21, 0.46]
    """
    from pymoo.indicators.hv import HV

    gens = int(generations.max()) if generations.size else 0
    out = np.zeros(gens)
    if not feasible.any():
        return out
    Z = np.full(F.shape, np.inf)
    Z[feasible] = _normalised(F[feasible])
    hv = HV(ref_point=np.full(F.shape[1], 1.1))
    for g in range(1, gens + 1):
        rows = feasible & (generations <= g)
        if rows.any():
            P = Z[rows]
            out[g - 1] = float(hv(P[nondominated(P)]))
    return out


def hypervolume_change(trace: Array, window: int = HV_WINDOW) -> float:
    """``(HV[-1] - HV[-1 - window]) / HV[-1]`` (inf with too short a trace or no volume).

    Examples
    --------
    >>> hypervolume_change(np.array([0.5, 0.9, 0.99, 1.0, 1.0, 1.0, 1.0]), window=3)
    0.0
    """
    if len(trace) <= window or not trace[-1] > 0:
        return math.inf
    return float((trace[-1] - trace[-1 - window]) / trace[-1])


def _convergence_note(trace: Array) -> tuple[str, ...]:
    change = hypervolume_change(trace)
    if change < HV_TOLERANCE:
        return ()
    if not math.isfinite(change):
        return (f"convergence not measured: {len(trace)} generations with a feasible front "
                f"(needs more than {HV_WINDOW}); run more generations",)  # fmt: skip
    return (f"not converged: the hypervolume changed {change:.1%} over the last {HV_WINDOW} "
            f"generations (converged: < {HV_TOLERANCE:.0%}); run more generations",)  # fmt: skip


def knee_point(F: ArrayLike) -> int:
    """The knee of a front: the point farthest on the ideal side of the hyperplane through
    the front's extreme points (objectives normalised over the front; Das 1999, "On
    characterizing the knee of the Pareto curve", Struct. Optim. 18).

    With a degenerate hyperplane (fewer distinct extremes than objectives) the point
    nearest the ideal point in the normalised objectives.

    Examples
    --------
    >>> knee_point([[0.0, 1.0], [1.0, 0.0], [0.5, 0.45], [0.2, 0.2]])
    3
    """
    A = real_array("F", F)
    if A.ndim != 2 or len(A) == 0:
        raise InvalidParameterError("F", A.shape, "must be a non-empty (n, m) front")
    Z = _normalised(A)
    m = Z.shape[1]
    ext = Z[np.argmin(Z, axis=0)]  # one extreme point per objective
    try:
        w = np.linalg.solve(ext, np.ones(m))  # hyperplane w . z = 1 through the extremes
    except np.linalg.LinAlgError:
        return int(np.argmin(np.linalg.norm(Z, axis=1)))
    return int(np.argmax((1.0 - Z @ w) / np.linalg.norm(w)))


def preference_pick(F: ArrayLike, weights: Sequence[float]) -> int:
    """The point minimising ``sum(w_j z_j)`` of the objectives normalised over the front.

    Examples
    --------
    >>> preference_pick([[0.0, 1.0], [1.0, 0.0], [0.4, 0.4]], [1.0, 3.0])
    1
    """
    A = real_array("F", F)
    w = real_array("weights", weights)
    if w.shape != (A.shape[1],) or (w < 0).any() or not w.sum() > 0:
        raise InvalidParameterError(
            "weights", weights, f"must be {A.shape[1]} non-negative weights, not all zero"
        )
    return int(np.argmin(_normalised(A) @ w))


def _check_objectives(objectives: Any) -> tuple[str, ...]:
    names = (objectives,) if isinstance(objectives, str) else tuple(objectives)
    bad = [o for o in names if o not in OBJECTIVES]
    if bad or len(names) < 2 or len(set(names)) != len(names):
        raise InvalidParameterError(
            "objectives", objectives, f"must be two or more distinct of {tuple(OBJECTIVES)}"
        )
    return names


#: What a non-finite objective (a run that never arrived) counts as inside the search;
#: such a design is infeasible anyway.
_PENALTY = 1.0e6


def pareto(
    scenarios: Scenario | Sequence[Scenario],
    *,
    space: DesignSpace | None = None,
    objectives: Sequence[str] = ("arrival_time", "injury_probability", "foam_thickness"),
    robot: ContactDynamics = MANIPULATOR_1,
    heads: HeadRange = THESIS_HEAD_RANGE,
    measure: str = "relative",
    criterion: Criterion | None = None,
    risk_samples: int = 20_000,
    population: int = 16,
    generations: int = 8,
    seed: int = ARG.seed.default,
    reference: Design | Mapping[str, Design] | None = None,
    progress: ProgressHook | None = None,
    crowds: CrowdScenario | Sequence[CrowdScenario] | CrowdEncounters | None = None,
    human_speed: float = 1.0,
    risk_bound: float = RISK_BOUND.default,
    seed_references: bool = True,
    executor: Any = None,
) -> ParetoFront:
    """The Pareto front of foam, speed limit and VFF gains over navigation scenarios.

    Parameters
    ----------
    scenarios, robot, heads, measure
        As in :func:`evaluate_design`.
    space
        The box searched (:class:`DesignSpace`; default its defaults).
    objectives
        Two or more names of :data:`OBJECTIVES` (all minimised).
    criterion, risk_samples
        The criterion of the exceedance probability (default
        :class:`~designlab.impact.HeadAcceleration` of 10 g) and its Monte Carlo samples
        per design (the search's seed).
    population, generations
        NSGA-II population size and generations (population x generations designs,
        each a set of navigation runs; at most :data:`MAX_EVALUATIONS`).
    seed
        Seed of the search.
    reference
        Designs placed against the front: a :class:`Design`, a mapping label -> design,
        or ``None`` (default): the thesis's two, :data:`THESIS_DESIGNS`; ``{}``: none.
    progress
        Called after each generation (:mod:`designlab.progress`).
    crowds
        Crowd scenarios each design also drives through with its own gains and speed limit
        (:class:`~designlab.codesign.CrowdEncounters`, runs cached per gains and speed),
        needed by the objective ``crowd_injury_probability`` and only run for it.
    human_speed, risk_bound
        As in :func:`evaluate_design` (the walker speed of the speed-limit constraint and
        the stated bound on P(criterion exceeded | contact)).
    seed_references
        Place the reference designs that lie in the box in the first population.
    executor
        An executor of :func:`designlab.analysis.executors.make_executor` (``processes``,
        ``dask``) that scores each generation's designs, two chunks per worker, each with
        its foam limits; ``None``: in this process. The front is the same.

    Returns
    -------
    ParetoFront

    Examples
    --------
    >>> import designlab.navigation as nav
    >>> front = pareto([nav.configuration(2)], population=4, generations=1,
    ...                objectives=("arrival_time", "foam_thickness"), seed=0)
    >>> front.status, len(front.X), list(front.to_frame().columns[-2:])
    ('ok', 4, ['arrival_time_s', 'foam_thickness_m'])
    """
    box = DesignSpace() if space is None else space
    if not isinstance(box, DesignSpace):
        raise InvalidParameterError("space", space, "must be a DesignSpace")
    names = _check_objectives(objectives)
    items = _check_scenarios(scenarios)
    _check_scoring(robot, heads, measure, risk_samples, seed)
    refs = _check_references(reference)
    encounters = crowd_encounters(names, crowds, measure)
    walker = HUMAN_SPEED.check(human_speed, "human_speed")
    bound = RISK_BOUND.check(risk_bound)
    # a stated bound needs the probability it bounds
    risk = risk_criterion(names if bound == 1.0 else (*names, "exceedance_probability"),
                          criterion)  # fmt: skip
    scorer = _Scorer(names, items, dict(robot=robot, heads=heads, measure=measure,
                     criterion=risk, risk_samples=risk_samples, seed=seed, crowds=encounters,
                     human_speed=walker, risk_bound=bound), executor)  # fmt: skip
    initial = _initial(refs, box, population) if seed_references else None
    out = nsga2(scorer.evaluate, box.lower, box.upper, n_obj=len(names), n_constr=len(CONSTRAINTS),
                population=population, generations=generations, seed=seed,
                progress=progress, initial=initial, prepare=scorer.prepare,
                snap=box.snap)  # fmt: skip
    scored = {label: scorer.score(d.vector()) for label, d in refs.items()}
    return dataclasses.replace(_front(out, names, scored, seed),
                               worker_cpu_seconds=scorer.worker_cpu)  # fmt: skip


def _evaluate_task(task: tuple[Any, ...]) -> tuple[list[tuple[Array, Array]], float, int]:
    """A chunk of a generation's designs scored in a worker (a top-level, picklable task):
    their foam limits in one lock-step search, then each design; with the worker's CPU time
    (s) and process id."""
    names, items, kw, X = task
    cpu = time.process_time()
    designs = [Design.from_vector(x) for x in X]
    lim = design_limits(designs, kw["robot"], kw["heads"], kw["human_speed"])
    out = []
    for i, d in enumerate(designs):
        s = evaluate_design(d, items, limits=lim.row(i), **kw)
        f = np.array([OBJECTIVES[o].of(s) for o in names])
        out.append((np.where(np.isfinite(f), f, _PENALTY), s.constraints))
    return out, time.process_time() - cpu, os.getpid()


class _Scorer:
    """A search's design scores: the foam limits of each generation computed at once, the
    designs then scored in this process; with an executor, the generation is split into
    chunks (two per worker), each scored by a worker, limits included (a foam's limits do
    not depend on the other foams of its lock-step search, so the scores are the same)."""

    def __init__(self, names: tuple[str, ...], items: tuple[Scenario, ...],
                 kw: dict[str, Any], executor: Any = None) -> None:  # fmt: skip
        self.names, self.items, self.kw = names, items, kw
        self.executor = executor
        self.batch: dict[bytes, FoamLimits] = {}
        self.done: dict[bytes, tuple[Array, Array]] = {}
        self.worker_cpu = 0.0

    def prepare(self, X: Array) -> None:
        """The foam limits of a generation's designs, in one lock-step search (with an
        executor: the generation's scores, chunk by chunk in its workers)."""
        self.batch.clear()
        self.done.clear()
        keys = [np.asarray(x, float).tobytes() for x in X]
        if self.executor is not None:
            parts = np.array_split(np.arange(len(X)), max(1, 2 * int(self.executor.workers)))
            parts = [p for p in parts if p.size]
            tasks = [(self.names, self.items, self.kw, np.asarray(X, float)[p]) for p in parts]
            for j, (outs, cpu, pid) in self.executor.map_unordered(_evaluate_task, tasks):
                for i, out in zip(parts[j], outs, strict=True):
                    self.done[keys[i]] = out
                self.worker_cpu += cpu if pid != os.getpid() else 0.0  # another process's
            return
        designs = [Design.from_vector(x) for x in X]
        lim = design_limits(designs, self.kw["robot"], self.kw["heads"], self.kw["human_speed"])
        for i, key in enumerate(keys):
            self.batch[key] = lim.row(i)

    def score(self, x: Array) -> DesignScore:
        """The design of vector ``x`` scored (its limits from the batch when there)."""
        limits = self.batch.get(np.asarray(x, float).tobytes())
        return evaluate_design(Design.from_vector(x), self.items, limits=limits, **self.kw)

    def evaluate(self, x: Array) -> tuple[Array, Array]:
        """Objectives (a non-finite one penalised) and constraints of ``x``."""
        key = np.asarray(x, float).tobytes()
        if key in self.done:
            return self.done[key]
        s = self.score(x)
        f = np.array([OBJECTIVES[o].of(s) for o in self.names])
        return np.where(np.isfinite(f), f, _PENALTY), s.constraints


def risk_criterion(names: Sequence[str], criterion: Any) -> Criterion | None:
    """The injury criterion the objectives ``names`` need (default a_h,max <= 10 g), or None.

    Parameters
    ----------
    names
        The objectives.
    criterion
        The criterion given (``None``: the default).
    """
    if criterion is not None and not isinstance(criterion, Criterion):
        raise InvalidParameterError("criterion", criterion, "must be an impact Criterion or None")
    if not {"injury_probability", "exceedance_probability", "crowd_injury_probability"} & set(
        names
    ):
        return None
    return HeadAcceleration(10.0) if criterion is None else criterion


def crowd_encounters(names: Sequence[str], crowds: Any, measure: str) -> CrowdEncounters | None:
    """The crowd encounters of ``crowd_injury_probability`` (``None`` when not asked for).

    Parameters
    ----------
    names
        The objectives.
    crowds
        Crowd scenarios, a :class:`~designlab.codesign.CrowdEncounters` or ``None``.
    measure
        Which closing speed counts.
    """
    if "crowd_injury_probability" not in names:
        many = isinstance(crowds, Sequence) and not isinstance(crowds, (str, bytes))
        if not (
            crowds is None
            or isinstance(crowds, CrowdEncounters | CrowdScenario)
            or (many and crowds and all(isinstance(c, CrowdScenario) for c in crowds))
        ):
            raise InvalidParameterError(
                "crowds", crowds, "must be a CrowdScenario, a list of them, a CrowdEncounters "
                "or None",
            )  # fmt: skip
        return None
    if crowds is None:
        raise InvalidParameterError(
            "crowds", None, "is needed by the objective crowd_injury_probability"
        )
    return crowds if isinstance(crowds, CrowdEncounters) else CrowdEncounters(crowds, measure)


def _initial(refs: dict[str, Design], box: DesignSpace, population: int) -> Array | None:
    """The reference designs that lie in the box (at most a population), or ``None``."""
    inside = [d.vector() for d in refs.values()
              if ((d.vector() >= box.lower) & (d.vector() <= box.upper)).all()]  # fmt: skip
    return np.array(inside[:population]) if inside else None


def _check_references(reference: Any) -> dict[str, Design]:
    if reference is None:
        return dict(THESIS_DESIGNS)
    if isinstance(reference, Design):
        return {"reference": reference}
    if isinstance(reference, Mapping) and all(
        isinstance(k, str) and isinstance(v, Design) for k, v in reference.items()
    ):
        return dict(reference)
    raise InvalidParameterError(
        "reference", reference, "must be a Design, a mapping label -> Design, or None"
    )


def _front(
    out: SearchOutcome, names: tuple[str, ...], refs: dict[str, DesignScore], seed: int
) -> ParetoFront:
    """The :class:`ParetoFront` of a search's evaluations."""
    feasible = out.feasible
    front = np.zeros(len(out.X), dtype=bool)
    if feasible.any():
        front[np.flatnonzero(feasible)] = nondominated(out.F[feasible])
    points = []
    for label, ref in refs.items():
        ref_f = np.array([OBJECTIVES[o].of(ref) for o in names])
        dist, dominated = _reference_position(out.F[front], ref_f, ref.feasible)
        points.append(ReferencePoint(label, ref, ref_f, dist, dominated))
    trace = hypervolume_trace(out.F, feasible, out.generations)
    warnings = []
    if not feasible.any():
        warnings.append(
            f"none of the {len(out.X)} designs evaluated meets every hard constraint "
            f"({', '.join(CONSTRAINTS)}): widen the space or run more generations"
        )
    for label, ref in refs.items():
        if not ref.feasible:
            broken = [c for c, g in zip(CONSTRAINTS, ref.constraints, strict=True) if g > 0]
            warnings.append(f"the reference design {label!r} breaks {', '.join(broken)}")
    return ParetoFront(
        objectives=names, X=out.X, F=out.F, G=out.G, generations=out.generations,
        feasible=feasible, front=front, references=tuple(points), seed=seed,
        status=FrontStatus.OK if feasible.any() else FrontStatus.NO_FEASIBLE,
        warnings=(*warnings, *_convergence_note(trace)), hypervolume=trace,
    )  # fmt: skip
