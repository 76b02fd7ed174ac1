"""Injury probability: P(criterion exceeded | contact) over heads, closing speeds and impact points.

The model is the impact package's linear contact model (Zeng 2011, Ch. 3), so a
peak metric scales exactly with the closing speed, ``metric(v) = v**e metric(1)``
(``e = 1`` for head acceleration, force and compression, 2.5 for HIC). Each sample
draws a head-neck set (and, for a link, an impact point), and the compiled
impact kernel (:mod:`designlab.impact.kernel`, through the criterion's
``values``) gives its metric at 1 m/s, hence its *threshold* speed
``v* = (limit / metric(1)) ** (1/e)``: the contact exceeds the criterion exactly
when ``v_c > v*``. Two estimators (``method``):

``"crude"``
    Draw ``v_c`` too and count ``v_c > v*``; the interval is Wilson's score
    interval of the binomial proportion (``scipy.stats.binomtest``).
``"importance"``
    Importance sampling with the zero-variance proposal in ``v_c``: given the head,
    ``v_c`` is drawn from its distribution restricted to ``v_c > v*``, so every
    sample fails and weighs ``w = P(v_c > v* | contact)``; the estimate is the mean
    weight, its standard error ``std(w) / sqrt(n)`` and the interval the normal one.
    Only the head (and point) variability is left, so a probability of 1e-9 is
    resolved with 1e4 samples where crude Monte Carlo would need 1e11.
``"subset"``
    Subset simulation (Au and Beck 2001; :mod:`designlab.codesign.subset`) in the
    standard normal space of the random inputs (each head parameter that is a
    distribution, the closing speed, a link's impact point), with failure
    ``log v_c - log v* > 0``: nested levels of conditional probability 0.1 reached by
    Markov chains. It needs no closed form of the closing speed's tail, so it also
    serves where importance sampling's weights do not exist; ``samples`` is the sample
    size per level (the evaluations in all are reported), the interval is lognormal from
    Au and Beck's coefficient of variation (a lower bound: it neglects the correlation
    between levels).

Both are unbiased for the same probability; ``benchmarks/codesign.py`` compares them
with crude Monte Carlo at 1e7 samples. Samples are processed in blocks, so memory
stays bounded whatever ``samples``.

What the model does not cover: head rotation, the torso and the rest of the body,
clamping (a head pinned against a wall), foam beyond its linear depth (add
``CompressionLimit(foam.linear_depth)`` as the criterion to get the probability of
bottoming out), and correlations between the head-neck parameters (they are drawn
independently).

Examples
--------
>>> import designlab as dl
>>> from scipy import stats
>>> risk = dl.codesign.injury_probability(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1,
...                                       closing_speed=stats.rayleigh(scale=1.0),
...                                       samples=2000, seed=0)
>>> risk.method, risk.samples, bool(0.05 < risk.probability < 0.1)
('importance', 2000, True)
>>> lo, hi = risk.interval
>>> bool(lo <= risk.probability <= hi)
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from scipy import stats

from designlab.codesign.parameters import (
    CONFIDENCE,
    RISK_METHOD,
    RISK_SAMPLES,
    SEED,
    SUBSET_SAMPLES,
)
from designlab.codesign.population import ClosingSpeeds, HeadPopulation, lever_sampler
from designlab.codesign.speed import check_robot_foam
from designlab.errors import InvalidParameterError
from designlab.impact import (
    ContactDynamics,
    Criterion,
    Foam,
    FullJointContact,
    HeadAcceleration,
    LinkImpact,
)
from designlab.impact.parameters import IMPACT_VELOCITY
from designlab.impact.problem import make_problem
from designlab.progress import Progress, ProgressHook, report
from designlab.results import Result, Status

__all__ = [
    "BLOCK",
    "ESTIMATORS",
    "InjuryRisk",
    "RiskStatus",
    "ThresholdModel",
    "exceedance_probability",
    "injury_probability",
]

#: Samples evaluated per kernel call (memory stays bounded).
BLOCK = 1 << 18


class RiskStatus(Status):
    """Status of :func:`injury_probability`.

    Attributes
    ----------
    OK
        The probability and its interval are estimated.
    UNRESOLVED
        No sample exceeded the criterion (crude): the probability is below the
        interval's upper end only; use ``method="importance"``.
    """

    OK = "ok"
    UNRESOLVED = "unresolved"


@dataclass(frozen=True)
class InjuryRisk(Result):
    """Result of :func:`injury_probability`.

    Attributes
    ----------
    probability
        The estimate of P(criterion exceeded | contact).
    interval
        ``(low, high)`` confidence interval at ``confidence``.
    standard_error
        The estimator's standard error.
    samples
        Monte Carlo samples used.
    method
        ``"crude"`` or ``"importance"``.
    confidence
        The interval's confidence level.
    criterion
        Name of the criterion.
    contact_fraction
        ``P(v_c > 0)`` of the closing-speed input (the probability is conditional on a contact).
    failed_samples
        Samples that exceeded the criterion (crude) or had a positive weight (importance).
    unresolved_samples
        Samples whose impact metric could not be computed (counted as exceeded).
    seed
        The seed.
    status
        A :class:`RiskStatus`.
    warnings
        What a user should know.
    """

    probability: float
    interval: tuple[float, float]
    standard_error: float
    samples: int
    method: str
    confidence: float
    criterion: str
    contact_fraction: float
    failed_samples: int
    unresolved_samples: int
    seed: int
    status: str = RiskStatus.OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """One row: the estimate, its interval and the settings.

        Returns
        -------
        pandas.DataFrame
        """
        return pd.DataFrame(
            {
                "criterion": [self.criterion],
                "method": [self.method],
                "probability": [self.probability],
                "interval_low": [self.interval[0]],
                "interval_high": [self.interval[1]],
                "standard_error": [self.standard_error],
                "confidence": [self.confidence],
                "samples": [self.samples],
                "failed_samples": [self.failed_samples],
                "contact_fraction": [self.contact_fraction],
            }
        )


@dataclass
class _Tally:
    """Running sums of an estimator over the blocks."""

    n: int = 0
    total: float = 0.0
    squares: float = 0.0
    positive: int = 0
    #: the first value seen: the squares are summed about it, so that equal values give a
    #: variance of exactly 0 (no cancellation of sum(w^2)/n - mean^2)
    shift: float | None = None


class CrudeEstimator:
    """Count ``v_c > v*`` with ``v_c`` drawn from its distribution (Wilson interval)."""

    def add(self, tally: _Tally, thresholds: NDArray, speeds: ClosingSpeeds,
            rng: np.random.Generator) -> None:  # fmt: skip
        """Draw the closing speeds of a block and count the exceedances."""
        hits = int(np.count_nonzero(speeds.sample(thresholds.size, rng) > thresholds))
        tally.n += thresholds.size
        tally.total += hits
        tally.squares += hits
        tally.positive += hits

    def finish(self, tally: _Tally, confidence: float) -> tuple[float, tuple[float, float], float]:
        """Estimate, Wilson interval, standard error."""
        p = tally.total / tally.n
        ci = stats.binomtest(int(tally.total), tally.n).proportion_ci(confidence, "wilson")
        return p, (float(ci.low), float(ci.high)), math.sqrt(p * (1 - p) / tally.n)


class ImportanceEstimator:
    """Weights ``P(v_c > v* | contact)`` (the zero-variance proposal in ``v_c``)."""

    def add(self, tally: _Tally, thresholds: NDArray, speeds: ClosingSpeeds,
            rng: np.random.Generator) -> None:  # fmt: skip
        """The weights of a block."""
        w = speeds.sf(thresholds)
        if tally.shift is None and w.size:
            tally.shift = float(w[0])
        tally.n += w.size
        tally.total += float(w.sum())
        tally.squares += float(np.square(w - (tally.shift or 0.0)).sum())
        tally.positive += int(np.count_nonzero(w > 0))

    def finish(self, tally: _Tally, confidence: float) -> tuple[float, tuple[float, float], float]:
        """Estimate, normal interval from the weights' standard error, standard error."""
        n = tally.n
        p = tally.total / n
        d = p - (tally.shift or 0.0)  # the mean about the shift
        var = max(tally.squares / n - d * d, 0.0) * n / max(n - 1, 1)
        se = math.sqrt(var / n)
        z = float(stats.norm.isf((1 - confidence) / 2))
        return p, (max(0.0, p - z * se), min(1.0, p + z * se)), se


#: The estimators by ``method`` name.
ESTIMATORS: dict[str, Any] = {"crude": CrudeEstimator(), "importance": ImportanceEstimator()}


def _check_criterion(criterion: object) -> Criterion:
    if not isinstance(criterion, Criterion):
        raise InvalidParameterError("criterion", criterion, "must be a Criterion")
    return criterion


@dataclass(frozen=True)
class ThresholdModel:
    """The fixed part of every sample: the robot (or the link), the foam, the criterion.

    Attributes
    ----------
    robot
        The robot.
    foam
        The foam.
    criterion
        The criterion.
    points
        The lever-arm distribution of a link (:func:`lever_sampler`), else ``None``.
    """

    robot: ContactDynamics | FullJointContact | LinkImpact
    foam: Foam
    criterion: Criterion
    points: Any

    @classmethod
    def of(cls, robot: object, foam: object, criterion: object, points: object) -> ThresholdModel:
        """Check the inputs (default criterion: a_h,max <= 10 g) and build the model.

        Parameters
        ----------
        robot, foam, criterion, points
            As in :func:`injury_probability`.

        Returns
        -------
        ThresholdModel
        """
        check_robot_foam(robot, foam, scaling=True)
        crit = _check_criterion(HeadAcceleration(10.0) if criterion is None else criterion)
        return cls(robot, foam, crit, lever_sampler(robot, points))  # type: ignore[arg-type]

    def thresholds(
        self, heads: NDArray, rng: np.random.Generator, levers: NDArray | None = None
    ) -> NDArray[np.float64]:
        """The threshold closing speeds ``v*`` of a block of ``(n, 3)`` heads ``[M_h, C_h, K_h]``.

        A sample whose metric cannot be computed gets ``v* = 0`` (exceeded at any contact).

        Parameters
        ----------
        heads
            The heads.
        rng
            The generator of the impact points (a link).
        levers
            The impact points of a link, m (``None``: drawn with ``rng``).

        Returns
        -------
        numpy.ndarray
        """
        return self.threshold_speeds(self.rows(heads, rng, levers))

    def threshold_speeds(self, params: NDArray) -> NDArray[np.float64]:
        """The threshold closing speeds ``v*`` of a block of model rows (:meth:`rows`).

        Parameters
        ----------
        params
            The rows.

        Returns
        -------
        numpy.ndarray
        """
        n = params.shape[0]
        if np.all(params == params[0]):  # one design (a fixed head and point): one kernel call
            m1 = np.repeat(self.criterion.values(params[:1], np.ones(1)), n)
        else:
            m1 = self.criterion.values(params, np.ones(n))
        with np.errstate(divide="ignore", invalid="ignore"):
            v = (self.criterion.limit / m1) ** (1.0 / self.criterion.velocity_exponent)
        return np.where(np.isfinite(m1), v, 0.0)

    def rows(
        self, heads: NDArray, rng: np.random.Generator, levers: NDArray | None = None
    ) -> NDArray[np.float64]:
        """The model's parameter rows of a block of ``(n, 3)`` heads (as :meth:`thresholds`).

        Parameters
        ----------
        heads, rng, levers
            As in :meth:`thresholds` (``rng`` draws the impact points of a link).

        Returns
        -------
        numpy.ndarray
        """
        n = heads.shape[0]
        prob = make_problem(self.robot, None if self.robot.along_link else 1.0,
                            None, 1.0, None, False, 0.0, 0.05)  # fmt: skip
        if self.points is None:
            rows, _ = prob.robot_rows(None)
            rows = np.repeat(rows, n, axis=0)
        else:
            rows, _ = prob.robot_rows(_levers(self.points, n, rng) if levers is None else levers)
        return prob.contact.assemble(
            rows, np.full(n, self.foam.stiffness), np.full(n, self.foam.damping), heads
        )


def _levers(points: Any, n: int, rng: np.random.Generator) -> NDArray[np.float64]:
    if isinstance(points, float):
        return np.full(n, points)
    return np.asarray(points.rvs(size=n, random_state=rng), dtype=float).reshape(n)


def injury_probability(
    robot: ContactDynamics | FullJointContact | LinkImpact,
    foam: Foam,
    closing_speed: Any,
    *,
    heads: Any = None,
    criterion: Criterion | None = None,
    points: Any = None,
    samples: int = RISK_SAMPLES.default,
    method: str = RISK_METHOD.default,
    confidence: float = CONFIDENCE.default,
    seed: int = SEED.default,
    progress: ProgressHook | None = None,
) -> InjuryRisk:
    """P(criterion exceeded | contact) over heads, closing speeds and impact points.

    Parameters
    ----------
    robot
        The effective manipulator (fixed impact point) or a LinkImpact (any point).
    foam
        The foam covering.
    closing_speed
        The closing speed v_c at contact, m/s: a scipy frozen distribution or an array of
        samples (for instance from navigation runs). The part at ``v_c <= 0`` (no impact)
        is left out: the probability is conditional on a contact.
    heads
        ``None`` (uniform over the thesis's ranges), a
        :class:`~designlab.codesign.HeadPopulation` (any scipy distributions), a
        :class:`~designlab.impact.HeadRange` (uniform over it) or a
        :class:`~designlab.impact.HeadNeck` (one head).
    criterion
        The criterion (default: a_h,max <= 10 g).
    points
        For a LinkImpact: the distribution of the lever arm of the impact point, m
        (default: uniform over ``[lever_arm_min, lever_arm_max]``).
    samples
        Monte Carlo samples (each one impact-kernel evaluation; at most 2e6, about 6 s; for
        ``"subset"`` per level, at most 1e5, about 10 s).
    method
        ``"crude"``, ``"importance"`` or ``"subset"`` (the module text).
    confidence
        Two-sided confidence level of the interval.
    seed
        Seed of the random samples.
    progress
        Called after each block of samples.

    Returns
    -------
    InjuryRisk
    """
    design = ThresholdModel.of(robot, foam, criterion, points)
    crit = design.criterion
    speeds = ClosingSpeeds.of(closing_speed)
    population = HeadPopulation.of(heads)
    n = RISK_SAMPLES.check(samples)
    method = RISK_METHOD.check(method)
    level = CONFIDENCE.check(confidence)
    seed = SEED.check(seed)
    rng = np.random.default_rng(seed)
    if method == "subset":
        n = SUBSET_SAMPLES.check(n, "samples (per level of subset simulation)")
        return _subset(design, speeds, population, n, rng, level, seed)
    estimator = ESTIMATORS[method]
    tally, unresolved = _Tally(), 0
    blocks = math.ceil(n / BLOCK)
    for b in range(blocks):
        size = min(BLOCK, n - b * BLOCK)
        heads = population.sample(size, rng)
        if method == "crude" and isinstance(crit, HeadAcceleration):
            unresolved += _crude_block(design, heads, speeds, rng, tally)
        else:
            v_star = design.thresholds(heads, rng)
            unresolved += int(np.count_nonzero(v_star == 0.0))
            estimator.add(tally, v_star, speeds, rng)
        report(progress, Progress(step=b + 1, total=blocks, label="samples"))
    p, interval, se = estimator.finish(tally, level)
    return _summarise(p, interval, se, tally, method, level, crit, speeds, unresolved, seed)


def _crude_block(design: ThresholdModel, heads: NDArray, speeds: ClosingSpeeds,
                 rng: np.random.Generator, tally: _Tally) -> int:  # fmt: skip
    """A crude block against a head-acceleration limit: each sample's pass/fail
    (:func:`designlab.impact.passfail.head_acceleration_exceeds`, the full kernel's
    decisions without its maxima; docs/impact.md, "Pass/fail"), the same draws as
    :meth:`ThresholdModel.thresholds` and :class:`CrudeEstimator` make. One design (a fixed
    head and point) keeps its one kernel call. Returns the unresolved samples."""
    from designlab.impact.passfail import head_acceleration_exceeds

    params = design.rows(heads, rng)
    if params.shape[1] != 8 or np.all(params == params[0]):
        v_star = design.threshold_speeds(params)
        ESTIMATORS["crude"].add(tally, v_star, speeds, rng)
        return int(np.count_nonzero(v_star == 0.0))
    v = speeds.sample(heads.shape[0], rng)
    fast = v <= IMPACT_VELOCITY.le  # the model's range of v_c; beyond it, v* as before
    d = head_acceleration_exceeds(params[fast], v[fast], design.criterion.max_g)  # type: ignore[attr-defined]
    v_star = design.threshold_speeds(params[~fast]) if not fast.all() else np.zeros(0)
    hits = int(np.count_nonzero(d.exceeds)) + int(np.count_nonzero(v[~fast] > v_star))
    tally.n += heads.shape[0]
    tally.total += hits
    tally.squares += hits
    tally.positive += hits
    return int(np.count_nonzero(d.unresolved)) + int(np.count_nonzero(v_star == 0.0))


def _subset(design: ThresholdModel, speeds: ClosingSpeeds, population: HeadPopulation, n: int,
            rng: np.random.Generator, level: float, seed: int) -> InjuryRisk:  # fmt: skip
    """P(criterion exceeded | contact) by subset simulation over the random inputs."""
    from designlab.codesign.subset import subset_simulation

    dh = population.dimension
    link = design.points is not None and not isinstance(design.points, float)

    def g(u: NDArray) -> NDArray:
        heads = population.from_normal(u[:, :dh])
        v = speeds.from_normal(u[:, dh])
        levers = None
        if link:
            levers = np.asarray(design.points.isf(stats.norm.sf(u[:, dh + 1])), dtype=float)
        v_star = design.thresholds(heads, rng, levers)
        with np.errstate(divide="ignore"):
            return np.log(v) - np.log(v_star)

    out = subset_simulation(g, dh + 1 + int(link), n, rng)
    warnings = ()
    if out.failed == 0:
        warnings = ("no sample of the last level exceeded the criterion: P is below about "
                    f"{0.1 ** out.levels / n:.3g}",)  # fmt: skip
    return InjuryRisk(
        probability=out.probability, interval=out.interval(level),
        standard_error=out.cov * out.probability, samples=out.evaluations, method="subset",
        confidence=level, criterion=design.criterion.name,
        contact_fraction=speeds.contact_fraction, failed_samples=out.failed,
        unresolved_samples=0, seed=seed,
        status=RiskStatus.OK if out.failed else RiskStatus.UNRESOLVED, warnings=warnings,
    )  # fmt: skip


def _summarise(p: float, interval: tuple[float, float], se: float, tally: _Tally, method: str,
               level: float, crit: Criterion, speeds: ClosingSpeeds, unresolved: int,
               seed: int) -> InjuryRisk:  # fmt: skip
    """The result, its status and warnings."""
    warnings: list[str] = []
    status = RiskStatus.OK
    if tally.positive == 0 and method == "crude":
        status = RiskStatus.UNRESOLVED
        warnings.append(
            f"no sample of {tally.n} exceeded {crit.name}: the probability is below "
            f"{interval[1]:.3g} ({100 * level:g} % Wilson bound); use method='importance'"
        )
    if unresolved:
        warnings.append(f"{unresolved} samples had no computable metric: counted as exceeded")
    if speeds.contact_fraction < 1.0:
        warnings.append(
            f"{100 * (1 - speeds.contact_fraction):.3g} % of the closing speeds are <= 0 (no "
            "contact) and left out: the probability is conditional on a contact"
        )
    return InjuryRisk(
        probability=p, interval=interval, standard_error=se, samples=tally.n, method=method,
        confidence=level, criterion=crit.name, contact_fraction=speeds.contact_fraction,
        failed_samples=tally.positive, unresolved_samples=unresolved, seed=seed,
        status=status, warnings=tuple(warnings),
    )  # fmt: skip


#: P(criterion exceeded | contact) under its honest name: the same function as
#: :func:`injury_probability` (whose name is kept; issue 36.3). An injury risk from cited
#: curves is :func:`designlab.codesign.injury.head_injury_risk`.
exceedance_probability = injury_probability
