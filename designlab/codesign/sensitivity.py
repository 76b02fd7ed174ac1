"""Sensitivity of the front: Sobol indices of each objective to the design variables.

Which of the design variables (foam K_c, C_c, thickness T_u, speed limit V_mr, the VFF
gains K1, b, K3, K5) drive each objective of the front (arrival time, injury
probability, foam thickness, closing speed) over the whole design space, and which
decide whether a design is feasible? :func:`front_sensitivity` answers with the
first-order and total Sobol indices of each, with 95 % bootstrap confidence
half-widths, through the project's shared machinery
(:func:`designlab.analysis.sensitivity.sobol_indices`: SALib's Saltelli sample and
estimators). It scores every design of the sample as :func:`~designlab.codesign.pareto`
does (:func:`~designlab.codesign.evaluate_design`), so it costs ``N (D + 2)`` design
evaluations for D free variables, each a set of navigation runs.

The metrics are the objectives asked for, with two changes that keep them finite:
``arrival_time`` counts a run that never arrived at its horizon T_max (it is ``inf`` in
the front), and ``infeasible`` (1 when the design breaks a hard constraint, else 0) is
added. A variable whose bounds are equal in the :class:`~designlab.codesign.DesignSpace`
is held fixed and gets no index.

:func:`design_sobol` is the same over any function of a :class:`~designlab.codesign.Design`
(the tests check it against indices known in closed form).

Examples
--------
>>> from designlab.codesign import DesignSpace
>>> space = DesignSpace(damping_min=50.0, damping_max=50.0, speed_min=0.7, speed_max=0.7,
...                     k1_min=3.0, k1_max=3.0, b_min=0.5, b_max=0.5, k3_min=20.0,
...                     k3_max=20.0, k5_min=100.0, k5_max=100.0)
>>> t = design_sobol(lambda d: {"y": d.foam.thickness}, space, samples=64)
>>> t.frame.set_index("parameter")["ST"].round(3).to_dict()
{'K_c': 0.0, 'T_u': 1.0}
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from designlab.analysis.sensitivity import SensitivityTable, sobol_indices
from designlab.codesign.contacts import MEASURES
from designlab.codesign.crowd_encounters import CrowdEncounters
from designlab.codesign.front import (
    OBJECTIVES,
    VARIABLES,
    Design,
    DesignScore,
    DesignSpace,
    _check_scenarios,
    crowd_encounters,
    evaluate_design,
    risk_criterion,
)
from designlab.codesign.parameters import RISK_SAMPLES, SENSITIVITY_SAMPLES
from designlab.errors import InvalidParameterError
from designlab.impact import (
    MANIPULATOR_1,
    THESIS_HEAD_RANGE,
    ContactDynamics,
    Criterion,
    HeadRange,
)
from designlab.navigation import CrowdScenario, Scenario
from designlab.params import ARG
from designlab.progress import Progress, ProgressHook, report

__all__ = ["DESCRIPTIONS", "design_sobol", "front_sensitivity", "sensitivity_metrics"]

_UNITS = {"N_per_m": "N/m", "N_s_per_m": "N s/m", "m": "m", "m_per_s": "m/s", "": ""}
_DOCS = ("foam stiffness", "foam damping", "foam thickness", "robot speed limit",
         "VFF gain K1", "VFF gain b", "VFF gain K3", "VFF gain K5")  # fmt: skip

#: Design variable -> description with its unit (the rows of the tables).
DESCRIPTIONS: dict[str, str] = {
    name: doc + (f" ({_UNITS[unit]})" if unit else "")
    for (name, unit), doc in zip(VARIABLES, _DOCS, strict=True)
}


def _check_samples(samples: int) -> int:
    n = SENSITIVITY_SAMPLES.check(samples, "samples")
    if n & (n - 1):
        raise InvalidParameterError("samples", n, "must be a power of two (Saltelli's sample)")
    return int(n)


def design_sobol(
    metric: Callable[[Design], Mapping[str, float]],
    space: DesignSpace,
    *,
    samples: int = SENSITIVITY_SAMPLES.default,
    seed: int = ARG.seed.default,
    progress: ProgressHook | None = None,
) -> SensitivityTable:
    """Sobol indices of any function of a design over the free variables of a space.

    Parameters
    ----------
    metric
        ``design -> {name: value}`` (the same names for every design; finite values).
    space
        The box (:class:`~designlab.codesign.DesignSpace`); at least two free variables.
    samples
        Saltelli base sample size N, a power of two: ``N (D + 2)`` designs.
    seed
        Seed of the sample and of the bootstrap intervals.
    progress
        Called after each design (:mod:`designlab.progress`).

    Returns
    -------
    SensitivityTable
        ``S1``, ``S1_conf``, ``ST``, ``ST_conf`` per metric and free variable
        (:func:`designlab.analysis.sensitivity.sobol_table`).
    """
    if not isinstance(space, DesignSpace):
        raise InvalidParameterError("space", space, "must be a DesignSpace")
    if not callable(metric):
        raise InvalidParameterError("metric", metric, "must be a function Design -> {name: value}")
    n = _check_samples(samples)
    names = [v for v, _ in VARIABLES]
    lo, hi, free = space.lower, space.upper, space.free
    if int(free.sum()) < 2:
        raise InvalidParameterError(
            "space", space, "needs at least two free variables (bounds that differ)"
        )
    bounds = {names[j]: (lo[j], hi[j]) for j in np.flatnonzero(free)}
    base = {names[j]: lo[j] for j in np.flatnonzero(~free)}

    def columns(points: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        X = np.column_stack([points[v] for v in names])
        rows = []
        for i, x in enumerate(X, start=1):
            rows.append(_metric_row(metric, Design.from_vector(x), rows[0] if rows else None))
            report(progress, Progress(i, len(X), label="design"))
        return {k: np.array([r[k] for r in rows], dtype=float) for k in rows[0]}

    return sobol_indices(columns, base, bounds, n, seed=seed,
                         descriptions={k: DESCRIPTIONS[k] for k in bounds})  # fmt: skip


def _metric_row(
    metric: Callable[[Design], Mapping[str, float]], design: Design, first: dict | None
) -> dict[str, float]:
    """One design's metrics: finite numbers under the names of the first design's."""
    row = metric(design)
    if not isinstance(row, Mapping) or not row:
        raise InvalidParameterError("metric", row, "must return a non-empty {name: value}")
    if first is not None and set(row) != set(first):
        raise InvalidParameterError(
            "metric", sorted(row), f"must return the same names for every design {sorted(first)}"
        )
    out = {}
    for k, v in row.items():
        if (
            isinstance(v, bool)
            or not isinstance(v, (int, float, np.number))
            or not math.isfinite(float(v))
        ):
            raise InvalidParameterError(
                f"metric[{k!r}]", v, f"must be a finite number (design {design.vector().tolist()})"
            )
        out[k] = float(v)
    return out


def sensitivity_metrics(score: DesignScore, objectives: Sequence[str]) -> dict[str, float]:
    """The finite metrics of a scored design: its objectives and ``infeasible``.

    Parameters
    ----------
    score
        The design's :class:`~designlab.codesign.DesignScore`.
    objectives
        Names of :data:`~designlab.codesign.OBJECTIVES`; ``arrival_time`` counts a run
        that did not arrive at its horizon.

    Returns
    -------
    dict
        Objective -> value, and ``infeasible`` (1.0 or 0.0).
    """
    out = {
        o: score.capped_arrival_time if o == "arrival_time" else float(OBJECTIVES[o].of(score))
        for o in objectives
    }
    out["infeasible"] = 0.0 if score.feasible else 1.0
    return out


def front_sensitivity(
    scenarios: Scenario | Sequence[Scenario],
    *,
    space: DesignSpace | None = None,
    objectives: Sequence[str] = ("arrival_time", "injury_probability", "foam_thickness"),
    robot: ContactDynamics = MANIPULATOR_1,
    heads: HeadRange = THESIS_HEAD_RANGE,
    measure: str = "relative",
    criterion: Criterion | None = None,
    risk_samples: int = 20_000,
    samples: int = SENSITIVITY_SAMPLES.default,
    seed: int = ARG.seed.default,
    progress: ProgressHook | None = None,
    crowds: CrowdScenario | Sequence[CrowdScenario] | CrowdEncounters | None = None,
) -> SensitivityTable:
    """Sobol indices of the front's objectives (and feasibility) to the design variables.

    Parameters
    ----------
    scenarios, space, objectives, robot, heads, measure, criterion, risk_samples, crowds
        As in :func:`~designlab.codesign.pareto` (each design is scored the same way).
    samples
        Saltelli base sample size N, a power of two: ``N (D + 2)`` designs for D free
        variables (8 by default), each a set of navigation runs.
    seed
        Seed of the sample, of the bootstrap intervals and of the injury Monte Carlo.
    progress
        Called after each design.

    Returns
    -------
    SensitivityTable
        One row per metric and free variable: ``S1``, ``ST`` and their 95 % confidence
        half-widths (``*_conf``); the metrics are the objectives (``arrival_time`` with a
        non-arrival at its horizon) and ``infeasible``. A metric constant over the sample
        (e.g. no design is ever infeasible) has NaN indices.

    Examples
    --------
    >>> import designlab.navigation as nav
    >>> space = DesignSpace(stiffness_min=2e4, stiffness_max=3e4, damping_min=70.0,
    ...                     damping_max=70.0, k1_min=3.0, k1_max=3.0, b_min=0.5, b_max=0.5,
    ...                     k3_min=20.0, k3_max=20.0, k5_min=100.0, k5_max=100.0)
    >>> t = front_sensitivity([nav.configuration(2)], space=space, samples=2,
    ...                       objectives=("arrival_time", "foam_thickness"))
    >>> arrival = t.frame[t.frame["metric"] == "arrival_time"].set_index("parameter")
    >>> arrival.loc[["K_c", "T_u"], "ST"].tolist()     # the foam does not steer the robot
    [0.0, 0.0]
    """
    box = DesignSpace() if space is None else space
    items = _check_scenarios(scenarios)
    names = tuple(objectives)
    bad = [o for o in names if o not in OBJECTIVES]
    if bad or not names or len(set(names)) != len(names):
        raise InvalidParameterError(
            "objectives", objectives, f"must be one or more distinct of {tuple(OBJECTIVES)}"
        )
    if measure not in MEASURES:
        raise InvalidParameterError("measure", measure, f"must be one of {MEASURES}")
    risk = risk_criterion(names, criterion)
    RISK_SAMPLES.check(risk_samples, "risk_samples")
    encounters = crowd_encounters(names, crowds, measure)

    def metric(design: Design) -> dict[str, float]:
        score = evaluate_design(design, items, robot=robot, heads=heads, measure=measure,
                                criterion=risk, risk_samples=risk_samples, seed=seed,
                                crowds=encounters)  # fmt: skip
        return sensitivity_metrics(score, names)

    return design_sobol(metric, box, samples=samples, seed=seed, progress=progress)
