"""Fragility curve: P(criterion exceeded | contact at closing speed v) over a head population.

Because the impact model is linear, each sampled head (and impact point) has one
threshold speed ``v*`` (:mod:`designlab.codesign.risk`), and a contact at ``v``
exceeds the criterion exactly when ``v > v*``. The fragility curve is therefore the
distribution function of the thresholds, ``P(v* < v)``, for every speed at once; its
interval at each speed is Wilson's. Averaging the curve over a closing-speed
distribution gives :func:`~designlab.codesign.injury_probability`.

Examples
--------
>>> import designlab as dl
>>> c = dl.codesign.fragility_curve(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1,
...                                 speeds=[1.0, 2.0, 2.5, 3.0], samples=2000)
>>> [round(float(p), 2) for p in c.probability]      # a_h,max <= 10 g, the thesis's heads
[0.0, 0.0, 0.95, 1.0]
>>> round(c.speed_at(0.5), 2)                         # half the heads exceed 10 g above
2.32
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from scipy import stats

from designlab.codesign.parameters import CONFIDENCE, CURVE_POINTS, RISK_SAMPLES, SEED
from designlab.codesign.population import HeadPopulation
from designlab.codesign.risk import BLOCK, ThresholdModel
from designlab.errors import InvalidParameterError
from designlab.impact import ContactDynamics, Criterion, Foam, FullJointContact, LinkImpact
from designlab.impact.parameters import IMPACT_VELOCITY
from designlab.params import check_size
from designlab.progress import Progress, ProgressHook, report
from designlab.results import OK, Result
from designlab.validation import real_array

__all__ = ["FragilityCurve", "fragility_curve"]


@dataclass(frozen=True)
class FragilityCurve(Result):
    """Result of :func:`fragility_curve`.

    Attributes
    ----------
    speeds
        The closing speeds, m/s.
    probability
        P(criterion exceeded | contact at that closing speed).
    low, high
        Wilson interval of each probability at ``confidence``.
    thresholds
        The sorted threshold speeds ``v*`` of the samples, m/s.
    samples
        Heads (and points) sampled.
    criterion
        Name of the criterion.
    confidence
        The intervals' confidence level.
    seed
        The seed.
    status
        ``"ok"``.
    warnings
        What a user should know.
    """

    speeds: NDArray[np.float64]
    probability: NDArray[np.float64]
    low: NDArray[np.float64]
    high: NDArray[np.float64]
    thresholds: NDArray[np.float64]
    samples: int
    criterion: str
    confidence: float
    seed: int
    status: str = OK
    warnings: tuple[str, ...] = ()

    def speed_at(self, probability: float) -> float:
        """The closing speed at which the exceedance probability reaches ``probability``.

        Parameters
        ----------
        probability
            In ``(0, 1]``.

        Returns
        -------
        float
            The ``probability`` quantile of the thresholds, m/s.
        """
        if not (isinstance(probability, (int, float)) and 0 < probability <= 1):
            raise InvalidParameterError("probability", probability, "must be in (0, 1]")
        return float(np.quantile(self.thresholds, probability))

    def to_frame(self) -> pd.DataFrame:
        """One row per closing speed.

        Returns
        -------
        pandas.DataFrame
        """
        return pd.DataFrame(
            {
                "v_c_m_per_s": self.speeds,
                "probability": self.probability,
                "interval_low": self.low,
                "interval_high": self.high,
            }
        )


def _speeds(value: object) -> NDArray[np.float64]:
    raw = np.asarray(value, dtype=object) if not isinstance(value, np.ndarray) else value
    if raw.dtype == bool or any(isinstance(x, bool | np.bool_) for x in np.ravel(raw)):
        raise InvalidParameterError("speeds", value, "must be closing speeds, not booleans", "m/s")
    v = np.atleast_1d(real_array("speeds", value, "m/s"))
    if v.ndim != 1:
        raise InvalidParameterError("speeds", value, "must be a flat list of closing speeds", "m/s")
    if v.size == 0:
        raise InvalidParameterError("speeds", [], "needs at least one closing speed", "m/s")
    CURVE_POINTS.check(int(v.size), "len(speeds)")
    for x in v:
        IMPACT_VELOCITY.check(float(x), "speeds")
    return v


def fragility_curve(
    robot: ContactDynamics | FullJointContact | LinkImpact,
    foam: Foam,
    speeds: Any,
    *,
    heads: Any = None,
    criterion: Criterion | None = None,
    points: Any = None,
    samples: int = 10_000,
    confidence: float = CONFIDENCE.default,
    seed: int = SEED.default,
    progress: ProgressHook | None = None,
) -> FragilityCurve:
    """P(criterion exceeded | contact at closing speed v) for each ``v`` of ``speeds``.

    Parameters
    ----------
    robot, foam, heads, criterion, points, confidence, seed, progress
        As in :func:`~designlab.codesign.injury_probability` (the same seed draws the
        same heads).
    speeds
        Closing speeds, m/s (each in (0, 20]; at most 10 000).
    samples
        Heads (and points) sampled.

    Returns
    -------
    FragilityCurve
    """
    model = ThresholdModel.of(robot, foam, criterion, points)
    v = _speeds(speeds)
    population = HeadPopulation.of(heads)
    n = RISK_SAMPLES.check(samples)
    check_size("samples", n, n, what="the threshold speeds")
    level = CONFIDENCE.check(confidence)
    seed = SEED.check(seed)
    rng = np.random.default_rng(seed)
    blocks = math.ceil(n / BLOCK)
    parts = []
    for b in range(blocks):
        size = min(BLOCK, n - b * BLOCK)
        parts.append(model.thresholds(population.sample(size, rng), rng))
        report(progress, Progress(step=b + 1, total=blocks, label="samples"))
    thr = np.sort(np.concatenate(parts))
    hits = np.searchsorted(thr, v, side="left")  # v* < v
    low, high = np.empty(v.size), np.empty(v.size)
    for i, k in enumerate(hits):
        ci = stats.binomtest(int(k), n).proportion_ci(level, "wilson")
        low[i], high[i] = ci.low, ci.high
    return FragilityCurve(
        speeds=v, probability=hits / n, low=low, high=high, thresholds=thr, samples=n,
        criterion=model.criterion.name, confidence=level, seed=seed,
    )  # fmt: skip
