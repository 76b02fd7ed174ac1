"""What the gain optimiser returns (:mod:`designlab.navigation.tuning`, which still exports
these names): the decision vector's names, the statuses, :class:`GainEvaluation` and
:class:`GainOptimum`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.navigation.criteria import EQUAL_WEIGHTS
from designlab.navigation.methods import METHOD, METHODS
from designlab.navigation.parameters import GeCuiGains, MasoudGains, VFFGains
from designlab.results import Result, Status

__all__ = [
    "GAIN_NAMES",
    "NEAR_OPTIMAL_H_MEAN",
    "REPRO_H_FIXED",
    "REPRO_H_OPTIMUM",
    "GainEvaluation",
    "GainOptimum",
    "OptimumStatus",
]

Array = NDArray[np.float64]

#: Order of the decision vector (the batch simulator's gain columns).
GAIN_NAMES = ("k1", "b", "k3", "k5")

#: Gain sets whose H_mean is within this of the best are near-optimal
#: (:meth:`GainOptimum.near_optimal`): H_mean is flat there, so which of them a seeded search
#: returns depends on the last bits of the arithmetic (another CPU, libm or compiler), and
#: a report gives their range instead of the optimum's digits (docs/navigation_gains.md).
NEAR_OPTIMAL_H_MEAN = 1e-4

#: How far H (per configuration) and H_mean of a fixed gain set may move on another machine:
#: a last-bit change can move an arrival by one 1 ms dynamics step (H_T ~ T_0/T changes by
#: ~1e-4 at T ~ 6-12 s).
REPRO_H_FIXED = 2e-4

#: How far the best H_mean of a seeded optimisation may move on another machine (the search
#: may end at another gain set of the flat optimum; measured: 1e-4 on an AMD EPYC against
#: the committed report, issue 34).
REPRO_H_OPTIMUM = 1e-3


@dataclass(frozen=True)
class GainEvaluation(Result):
    """Gain sets scored as :func:`optimise_gains` scores them (:func:`evaluate_gains`).

    Attributes
    ----------
    frame
        One row per gain set (see :func:`evaluate_gains`).
    status
        ``"ok"`` if at least one gain set is feasible, else ``"infeasible"``
        (:class:`OptimumStatus`).
    warnings
        Which gain sets are infeasible.
    """

    frame: pd.DataFrame = field(repr=False)
    status: str = "ok"
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """The table (a copy)."""
        return self.frame.copy()


class OptimumStatus(Status):
    """Status of :func:`optimise_gains` (and :func:`evaluate_gains`).

    ``OK``: both stages converged (a feasible point exists); ``NOT_CONVERGED``: a budget
    ran out first; ``INFEASIBLE``: no candidate arrived and stayed out of every critical
    region (``gains`` is then ``None``).
    """

    OK = "ok"
    NOT_CONVERGED = "not_converged"
    INFEASIBLE = "infeasible"


@dataclass(frozen=True)
class GainOptimum(Result):
    """The optimal gains found by :func:`optimise_gains`.

    Attributes
    ----------
    gains
        The best feasible :class:`VFFGains` (``None`` if no feasible point was found).
    objective
        Its H_mean (the mean over the scenarios of H, or of the robust score); ``nan``
        if none was feasible.
    scenario_names
        The scenarios optimised over.
    scenario_H
        H per scenario at the optimum (robust score in robust mode).
    history
        One row per CMA-ES generation and per refinement iteration: ``phase``,
        ``iteration``, ``evaluations`` (cumulative), ``best_H_mean`` (best feasible so
        far), ``iteration_best_H_mean``, ``feasible_share``, ``step`` (CMA-ES sigma or
        the compass step, in normalised log-gain units) and the incumbent gains.
    evaluations
        Gain sets simulated (each over every scenario and walk).
    simulations
        Closed-loop runs (evaluations x scenarios x walks; the nominal runs of the
        criteria are not counted).
    wall_time
        Seconds.
    stabilising, robust_mode, walks
        The settings (``walks`` = random walks per walking scenario, 0 if not robust).
    bounds
        ``{gain: (low, high)}`` searched.
    seed
        The seed.
    critical_margin
        The clearance (m) every run had to keep outside every critical region.
    feasible
        Every feasible gain set evaluated (columns ``k1``, ``b``, ``k3``, ``k5``,
        ``H_mean``), best first: the data of :meth:`near_optimal`.
    method, weights
        Whose gains were optimised (``"vff"``, ``"masoud"``, ``"ge_cui"``) and the
        criterion weights (w_T, w_D, w_E).
    status, warnings
        The result contract (:class:`~designlab.results.Result`).
    """

    gains: VFFGains | MasoudGains | GeCuiGains | None
    objective: float
    scenario_names: tuple[str, ...]
    scenario_H: Array
    history: pd.DataFrame = field(repr=False)
    evaluations: int
    simulations: int
    wall_time: float
    stabilising: str
    robust_mode: str
    walks: int
    bounds: dict[str, tuple[float, float]]
    seed: int
    critical_margin: float = 0.0
    status: str = OptimumStatus.OK
    warnings: tuple[str, ...] = ()
    method: str = METHOD.default
    weights: tuple[float, float, float] = EQUAL_WEIGHTS
    feasible: pd.DataFrame = field(
        default_factory=lambda: pd.DataFrame(columns=[*GAIN_NAMES, "H_mean"], dtype=float),
        repr=False,
    )

    def near_optimal(self, tolerance: float = NEAR_OPTIMAL_H_MEAN) -> pd.DataFrame:
        """The evaluated feasible gain sets within ``tolerance`` of the best H_mean, as ranges.

        Where H_mean is this flat, the optimum's digits are not reproducible (another CPU
        changes the last bits of each run and the seeded search may end at another of these
        sets); the range is.

        Parameters
        ----------
        tolerance
            Absolute H_mean below the best that still counts as near-optimal (>= 0).

        Returns
        -------
        pandas.DataFrame
            One row per gain (``gain``, ``low``, ``high``, ``optimum``) and the attribute
            ``attrs["sets"]``: how many evaluated gain sets lie within ``tolerance``
            (empty if no feasible set was found).

        Examples
        --------
        >>> import pandas as pd
        >>> o = GainOptimum(None, 0.6, ("c1",), np.array([0.6]), pd.DataFrame(), 3, 3, 0.0,
        ...                 "off", "", 0, {}, 0, feasible=pd.DataFrame(
        ...                     {"k1": [8.3, 7.8, 3.0], "b": [0.05] * 3, "k3": [16.0] * 3,
        ...                      "k5": [29.0] * 3, "H_mean": [0.55054, 0.55049, 0.4]}))
        >>> r = o.near_optimal(1e-4)
        >>> r.attrs["sets"], r.loc[0, "gain"], float(r.loc[0, "low"]), float(r.loc[0, "high"])
        (2, 'k1', 7.8, 8.3)
        """
        if not (isinstance(tolerance, int | float) and math.isfinite(tolerance)) or tolerance < 0:
            raise InvalidParameterError("tolerance", tolerance, "must be a finite number >= 0")
        f = self.feasible
        cols = ["gain", "low", "high", "optimum"]
        if f.empty:
            out = pd.DataFrame(columns=cols)
            out.attrs["sets"] = 0
            return out
        near = f[f["H_mean"] >= f["H_mean"].max() - tolerance]
        rows = [
            (n, float(near[n].min()), float(near[n].max()), float(f[n].iloc[0]))
            for n in GAIN_NAMES
            if n in METHODS.get(self.method).used_gains
        ]
        out = pd.DataFrame(rows, columns=cols)
        out.attrs["sets"] = len(near)
        return out

    def on_bounds(self, tolerance: float = 1e-3) -> dict[str, str]:
        """Gains of the optimum that lie on a bound of the box: ``{gain: "low" | "high"}``.

        Parameters
        ----------
        tolerance
            Distance to the bound in normalised log-gain units (the box is [0, 1]^4).
        """
        if self.gains is None:
            return {}
        out = {}
        for n in GAIN_NAMES:
            if not hasattr(self.gains, n):  # Masoud has no b
                continue
            lo, hi = self.bounds[n]
            u = (math.log(getattr(self.gains, n)) - math.log(lo)) / (math.log(hi) - math.log(lo))
            if u < tolerance:
                out[n] = "low"
            elif u > 1 - tolerance:
                out[n] = "high"
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row: the gains, H per scenario, H_mean and the search effort."""
        row: dict[str, Any] = {"stabilising": self.stabilising}
        g = self.gains
        row.update({n: getattr(g, n, math.nan) if g is not None else math.nan for n in GAIN_NAMES})
        for name, h in zip(self.scenario_names, self.scenario_H, strict=True):
            row[f"H_{name}"] = float(h)
        row.update(
            {
                "H_mean": self.objective,
                "evaluations": self.evaluations,
                "wall_time_s": self.wall_time,
                "robust_mode": self.robust_mode if self.walks else "",
                "walks": self.walks,
            }
        )
        return pd.DataFrame([row])
