"""Appendix-C sensitivity tables of the VFF gains (Zeng 2011, App. C.3).

Each gain (K1, b, K3, K5) alone is changed by -100 ... +100 % around a base gain
set (the thesis's optimum by default) and every configuration is simulated; the
tables give T_arrive, L_energy, the minimum distances and H per configuration,
H_mean and the relative sensitivity

    S_K = (1 - H_mean / H_opt) / (1 - K / K_opt)   (Zeng 2011, (C.3.1)-(C.3.4)), in %.

The perturbed points are produced and the S_K computed by the shared
one-at-a-time generator :func:`designlab.analysis.sensitivity.one_at_a_time`
with the batched simulator as its vectorised metric (one batch for all 49
points). The -100 % rows set a gain to zero, which the Lyapunov structure
excludes (all gains > 0): they are simulated with the gain at 1e-9 of its unit
and classified as the thesis does (arrives, no arrival, oscillation, critical
region, collision) from the full trajectory of each run.

Examples
--------
>>> import designlab as dl
>>> nav = dl.navigation
>>> sens = nav.gain_sensitivity([nav.configuration(1)], deltas_pct=(-10, 10), parameters=("k1",),
...                             stabilising="off")
>>> sens.appendix_c("k1")[0].columns.tolist()[:4]  # doctest: +NORMALIZE_WHITESPACE
['delta_pct', 'ch6_config1 T_arrive_s', 'ch6_config1 L_energy_J_per_ohm',
 'ch6_config1 d_circle_min_m']
>>> bool(abs(sens.s_summary().set_index("parameter").loc["k1", "S_max_pct"]) < 5)
True
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.analysis.sensitivity import (
    SensitivityTable,
    elasticities,
    one_at_a_time,
    sobol_indices,
)
from designlab.errors import InvalidParameterError
from designlab.navigation.methods import STABILISING
from designlab.navigation.parameters import ARRIVAL_TOLERANCE, GAIN_SETS, OPTIMAL_GAINS, VFFGains
from designlab.navigation.scenarios import Scenario, configuration
from designlab.navigation.simulate import NavigationResult, simulate, simulate_batch
from designlab.params import ARG
from designlab.results import OK, Result

__all__ = [
    "APPENDIX_C_DELTAS",
    "GainGlobalSensitivity",
    "GainSensitivity",
    "appendix_c_reference",
    "classify_run",
    "gain_global_sensitivity",
    "gain_sensitivity",
]

Array = NDArray[np.float64]

#: Perturbations of Zeng 2011, App. C.3 (%).
APPENDIX_C_DELTAS = (-100, -50, -20, -10, -5, -2, 2, 5, 10, 20, 50, 100)
#: A gain "at zero" (-100 %) is simulated at this value (its unit): the batch simulator
#: requires every gain > 0 (the structure of Zeng 2011, (5.5.7)).
ZERO_GAIN = 1e-9
_GAINS = ("k1", "b", "k3", "k5")
_DESCRIPTIONS = {
    "k1": "attractive gain K1 (N/m)",
    "b": "gain ratio b = K2/K1 = K4/K3 = K6/K5 (s)",
    "k3": "repulsive gain K3 (N/m)",
    "k5": "detour gain K5 (N/m^2)",
}


#: Our metric for each (configuration, quantity) of Tables C.2-C.9. The thesis's
#: Configuration 3 "cir"/"rect" columns are swapped relative to its Table 6.4 (its
#: "d_s_min_cir" values are the rectangle's), and its "d_s" are centre (contour) distances.
_APPENDIX_C_METRICS = {
    ("1", "T_arrive"): "ch6_config1 T_arrive_s",
    ("2", "T_arrive"): "ch6_config2 T_arrive_s",
    ("3", "T_arrive"): "ch6_config3 T_arrive_s",
    ("1", "d_s_min_cir"): "ch6_config1 d_circle_min_m",
    ("2", "d_s_min_h"): "ch6_config2 d_human_min_m",
    ("3", "d_s_min_cir"): "ch6_config3 d_rectangle_min_m",
    ("3", "d_s_min_rect"): "ch6_config3 d_circle_min_m",
    ("1", "H"): "ch6_config1 H",
    ("2", "H"): "ch6_config2 H",
    ("3", "H"): "ch6_config3 H",
    ("mean", "H_mean"): "H_mean",
    ("mean", "S_relative_sensitivity"): "S_pct",
}
_THESIS_GAIN = {"K1": "k1", "K3": "k3", "K5": "k5", "b": "b"}


def appendix_c_reference() -> pd.DataFrame:
    """Zeng 2011, Tables C.2-C.9 in long form (shipped with designlab).

    Columns ``table``, ``varied_gain`` (K1, K3, K5, b), ``delta_percent``,
    ``configuration`` (1, 2, 3, ``mean`` or ``all``), ``quantity`` (T_arrive, L_energy,
    d_s_min_cir, d_s_min_h, d_s_min_rect, H, H_mean, S_relative_sensitivity, outcome),
    ``value`` (text; ``-`` where the thesis prints none), ``unit`` and ``note`` (the
    thesis's words for the -100 % rows).

    Examples
    --------
    >>> t = appendix_c_reference()
    >>> t[(t.table == "C.2") & (t.delta_percent == 0) & (t.configuration == "1")].value.tolist()
    ['6.31', '3.64', '0.552']
    """
    from importlib.resources import files

    with (files("designlab") / "data" / "nav_sensitivity_appendixC.csv").open() as fh:
        return pd.read_csv(fh, dtype={"configuration": str, "value": str})


def classify_run(res: NavigationResult, *, moving_speed: float = 0.05, reversals: int = 4) -> str:
    """The outcome of one run in the words of Zeng 2011, App. C.3.

    ``"collision"`` (touched an obstacle), ``"critical region"`` (entered one without
    touching), ``"arrives"``, ``"oscillation"`` (no arrival and, over the second half of
    the run, still moving faster than ``moving_speed`` on average with at least
    ``reversals`` sign changes of a velocity component) or ``"no arrival"``.

    Parameters
    ----------
    res
        A single run (:func:`~designlab.navigation.simulate`) with its full trajectory.
    moving_speed
        Mean speed (m/s) over the second half of the run above which a robot that has
        not arrived counts as still moving.
    reversals
        Sign changes of a velocity component over the second half of the run that make
        a moving robot "oscillating".

    Examples
    --------
    >>> import designlab as dl
    >>> nav = dl.navigation
    >>> classify_run(nav.simulate(nav.configuration(1), nav.VFFGains(4.3, 0.68, 20.3, 240.7),
    ...                           stabilising="off"))
    'arrives'
    """
    if res.collided:
        return "collision"
    if res.entered_critical:
        return "critical region"
    if res.arrived:
        return "arrives"
    half = res.t >= res.t[-1] / 2
    v = res.velocity[half]
    if v.shape[0] > 2:
        speed = float(np.hypot(v[:, 0], v[:, 1]).mean())
        flips = max(
            int(
                np.count_nonzero(
                    np.diff(np.sign(np.where(np.abs(c) > 1e-3, c, 0.0))[np.abs(c) > 1e-3]) != 0
                )
            )
            for c in v.T
        )
        if speed > moving_speed and flips >= reversals:
            return "oscillation"
    return "no arrival"


def _settles(scenario: Scenario, gains: VFFGains, stabilising: str, tolerance: float) -> bool:
    """Whether the robot ends the horizon at rest near the goal (first-passage arrival off)."""
    res = simulate(scenario, gains, stabilising=stabilising, arrival_tolerance=1e-9)
    end = res.position[-1]
    return bool(
        math.dist(end, scenario.goal) <= tolerance and float(np.hypot(*res.velocity[-1])) < 0.05
    )


def _metric_factory(scenarios: list[Scenario], stabilising: str, arrival_tolerance: float):
    def batch(g: Array) -> dict[str, Array]:
        with np.errstate(
            invalid="ignore", divide="ignore"
        ):  # a gain at zero: T* = inf in the criteria
            r = simulate_batch(
                scenarios, g, stabilising=stabilising, arrival_tolerance=arrival_tolerance
            )
        out: dict[str, Array] = {}
        for s, sc in enumerate(scenarios):
            out[f"{sc.name} T_arrive_s"] = r.arrival_time[s]
            out[f"{sc.name} L_energy_J_per_ohm"] = r.energy[s]
            for i, name in enumerate(sc.obstacle_names):
                out[f"{sc.name} d_{name}_min_m"] = r.min_distance[s, :, i]
            out[f"{sc.name} H"] = r.H[s]
        out["H_mean"] = r.H_mean
        margin = np.full(r.H_mean.shape, np.inf)
        for s, sc in enumerate(scenarios):
            for i, o in enumerate(sc.obstacles):
                margin = np.minimum(margin, r.min_distance[s, :, i] - o.r3)
        out["critical_margin_min_m"] = margin
        return out

    def metric(points: dict[str, Array]) -> dict[str, Array]:
        g = np.column_stack(
            [np.maximum(np.asarray(points[n], dtype=float), ZERO_GAIN) for n in _GAINS]
        )
        # at most GAIN_SETS.le gain sets per batch (each member's arithmetic is its own)
        step = int(GAIN_SETS.le)  # type: ignore[arg-type]
        parts = [batch(g[i : i + step]) for i in range(0, g.shape[0], step)]
        return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}

    return metric


def _check_common(
    scenarios: Sequence[Scenario] | None, base: VFFGains | None, stabilising: str
) -> tuple[list[Scenario], VFFGains]:
    """The scenarios (default Configurations 1-3) and the base gains (default Table C.1)."""
    sc = [configuration(i) for i in (1, 2, 3)] if scenarios is None else list(scenarios)
    if not sc or not all(isinstance(s, Scenario) for s in sc):
        raise InvalidParameterError(
            "scenarios", scenarios, "must be a non-empty sequence of Scenario"
        )
    b0 = OPTIMAL_GAINS if base is None else base
    if not isinstance(b0, VFFGains):
        raise InvalidParameterError("base", base, "must be a VFFGains")
    STABILISING.check(stabilising)
    return sc, b0


@dataclass(frozen=True)
class GainSensitivity(Result):
    """Appendix-C sensitivity of the VFF gains.

    Attributes
    ----------
    base
        The base gains (K_opt).
    stabilising
        ``"off"`` or ``"lyapunov"``.
    scenario_names
        The configurations.
    table
        The shared one-at-a-time :class:`~designlab.analysis.sensitivity.SensitivityTable`
        (long form: metric, parameter, delta_pct, value, metric_value, change_pct, S_pct).
    outcomes
        One row per (gain, delta_pct, scenario): ``outcome`` of the run
        (:func:`classify_run`) for every -100 % row, and ``"arrives"`` / ``"no arrival"``
        / ``"critical region"`` / ``"collision"`` from the batch for the others.
    base_metrics
        Every metric at the base gains.
    status, warnings
        The result contract (:class:`~designlab.results.Result`).
    """

    base: VFFGains
    stabilising: str
    scenario_names: tuple[str, ...]
    table: SensitivityTable = field(repr=False)
    outcomes: pd.DataFrame = field(repr=False)
    base_metrics: dict[str, float] = field(default_factory=dict)
    status: str = OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """The long table (one row per metric, gain and perturbation)."""
        return self.table.to_frame()

    def value(self, metric: str, parameter: str, delta_pct: float) -> float:
        """One entry of the table (``delta_pct = 0``: the base value)."""
        if delta_pct == 0:
            return float(self.base_metrics[metric])
        f = self.table.frame
        row = f[
            (f["metric"] == metric)
            & (f["parameter"] == parameter)
            & (f["delta_pct"] == float(delta_pct))
        ]
        if row.empty:
            raise InvalidParameterError(
                "metric/parameter/delta_pct", (metric, parameter, delta_pct), "is not in the table"
            )
        return float(row["metric_value"].iloc[0])

    def appendix_c(self, parameter: str) -> tuple[pd.DataFrame, pd.DataFrame]:
        """The two tables of one gain in the thesis's form (e.g. Tables C.2 and C.3 for K1).

        Returns
        -------
        (performance, criterion)
            ``performance``: per delta_pct, T_arrive, L_energy and the minimum distances
            of every configuration (Tables C.2/C.4/C.6/C.8). ``criterion``: S_K in %, H
            per configuration and H_mean, with the -100 % row's outcome per
            configuration (Tables C.3/C.5/C.7/C.9).
        """
        if parameter not in _GAINS:
            raise InvalidParameterError("parameter", parameter, f"must be one of {_GAINS}")
        f = self.table.frame[self.table.frame["parameter"] == parameter]
        if f.empty:
            raise InvalidParameterError("parameter", parameter, "was not perturbed in this table")
        base = self.base_metrics
        metrics = list(dict.fromkeys(f["metric"]))
        deltas = sorted(set(f["delta_pct"].tolist()) | {0.0})
        wide = {
            m: {
                d: (
                    base[m]
                    if d == 0
                    else float(
                        f[(f["metric"] == m) & (f["delta_pct"] == d)]["metric_value"].iloc[0]
                    )
                )
                for d in deltas
            }
            for m in metrics
        }
        perf_cols = [
            f"{n} {q}" for n in self.scenario_names for q in ("T_arrive_s", "L_energy_J_per_ohm")
        ]
        perf_cols += [m for m in metrics if " d_" in m]
        perf_cols = sorted(
            (m for m in perf_cols if m in metrics),
            key=lambda m: (
                self.scenario_names.index(m.split(" ")[0]),
                "TLd".index(m.split(" ")[1][0]),
            ),
        )
        perf = pd.DataFrame(
            {"delta_pct": deltas, **{m: [wide[m][d] for d in deltas] for m in perf_cols}}
        )
        s = f[f["metric"] == "H_mean"].set_index("delta_pct")["S_pct"]
        crit = pd.DataFrame(
            {
                "delta_pct": deltas,
                "S_pct": [0.0 if d == 0 else float(s.get(d, math.nan)) for d in deltas],
            }
        )
        for m in [m for m in metrics if m.endswith(" H")] + ["H_mean"]:
            crit[m] = [wide[m][d] for d in deltas]
        o = self.outcomes[self.outcomes["parameter"] == parameter]
        crit["outcome"] = [
            "; ".join(
                f"{r.scenario}: {r.outcome}"
                for r in o[o["delta_pct"] == d].itertuples()
                if r.outcome != "arrives"
            )
            or ("" if d != -100 else "arrives everywhere")
            for d in deltas
        ]
        return perf, crit

    def compare_appendix_c(self) -> pd.DataFrame:
        """Our table against Zeng 2011, Tables C.2-C.9, entry by entry.

        Only for Configurations 1-3 of Ch. 6 (the thesis's set). L_energy is left out
        (its absolute value depends on the unknown winding resistance); the -100 % rows
        are compared in words by :meth:`appendix_c_outcomes`.

        Returns
        -------
        pandas.DataFrame
            ``table``, ``parameter``, ``delta_pct``, ``configuration``, ``quantity``,
            ``thesis``, ``designlab``, ``error`` (designlab - thesis) and ``unit``.

        Examples
        --------
        >>> import designlab as dl
        >>> sens = dl.navigation.gain_sensitivity(parameters=("k1",), deltas_pct=(-50, 50))
        >>> c = sens.compare_appendix_c()
        >>> sorted(c.loc[c.quantity == "d_s_min_cir", "delta_pct"].unique().tolist())
        [-50.0, 0.0, 50.0]
        >>> d1 = c[(c.configuration == "1") & (c.quantity == "d_s_min_cir")]
        >>> bool(d1.error.abs().max() < 0.03)
        True
        """
        ref = appendix_c_reference()
        rows = []
        for r in ref.itertuples():
            key = (r.configuration, r.quantity)
            gain = _THESIS_GAIN.get(r.varied_gain)
            if key not in _APPENDIX_C_METRICS or r.delta_percent == -100 or gain is None:
                continue
            try:
                thesis = float(r.value)
            except (TypeError, ValueError):
                continue
            metric = _APPENDIX_C_METRICS[key]
            try:
                if metric == "S_pct":
                    if r.delta_percent == 0:
                        continue
                    f = self.table.frame
                    sel = f[
                        (f["metric"] == "H_mean")
                        & (f["parameter"] == gain)
                        & (f["delta_pct"] == float(r.delta_percent))
                    ]
                    if sel.empty:
                        continue
                    ours = abs(float(sel["S_pct"].iloc[0]))  # the thesis prints |S_K|
                else:
                    ours = self.value(metric, gain, float(r.delta_percent))
            except (InvalidParameterError, KeyError):
                continue
            rows.append(
                {
                    "table": r.table,
                    "parameter": gain,
                    "delta_pct": float(r.delta_percent),
                    "configuration": r.configuration,
                    "quantity": r.quantity,
                    "thesis": thesis,
                    "designlab": ours,
                    "error": ours - thesis,
                    "unit": r.unit,
                }
            )
        return pd.DataFrame(
            rows,
            columns=[
                "table", "parameter", "delta_pct", "configuration", "quantity", "thesis",
                "designlab", "error", "unit",
            ],
        )  # fmt: skip

    def appendix_c_outcomes(self) -> pd.DataFrame:
        """The -100 % rows: the thesis's words (Tables C.3/C.5/C.7/C.9) next to our outcomes.

        Examples
        --------
        >>> import designlab as dl
        >>> sens = dl.navigation.gain_sensitivity(parameters=("k1",), deltas_pct=(-100,))
        >>> sens.appendix_c_outcomes().loc[0, "designlab"]
        'ch6_config1: no arrival; ch6_config2: no arrival; ch6_config3: no arrival'
        """
        ref = appendix_c_reference()
        ref = ref[ref["quantity"] == "outcome"]
        o = self.outcomes[self.outcomes["delta_pct"] == -100]
        rows = []
        for r in ref.itertuples():
            gain = _THESIS_GAIN[r.varied_gain]
            ours = o[o["parameter"] == gain]
            if ours.empty:
                continue
            rows.append(
                {
                    "parameter": gain,
                    "thesis": r.note,
                    "designlab": "; ".join(f"{x.scenario}: {x.outcome}" for x in ours.itertuples()),
                }
            )
        return pd.DataFrame(rows, columns=["parameter", "thesis", "designlab"])

    def s_summary(self) -> pd.DataFrame:
        """Max and mean |S_K| of H_mean per gain in % (App. C.3's summary), -100 % rows excluded."""
        f = self.table.frame
        f = f[(f["metric"] == "H_mean") & (f["delta_pct"] > -100)]
        g = f.assign(abs_S=f["S_pct"].abs()).groupby("parameter", sort=False)["abs_S"]
        return pd.DataFrame({"S_max_pct": g.max(), "S_mean_pct": g.mean()}).reset_index()


def _outcome(
    table: SensitivityTable,
    base: dict[str, float],
    p: str,
    d: float,
    sc_i: Scenario,
    stabilising: str,
    arrival_tolerance: float,
) -> str:
    """The outcome of one perturbed run: simulated (-100 %) or read from the table."""
    if d == -100:
        g = dict(base)
        g[p] = ZERO_GAIN
        res = simulate(
            sc_i, VFFGains(**g), stabilising=stabilising, arrival_tolerance=arrival_tolerance
        )
        outcome = classify_run(res)
        if outcome == "arrives" and not _settles(
            sc_i, VFFGains(**g), stabilising, arrival_tolerance
        ):
            outcome = "oscillation (passes the goal, never settles)"
        return outcome
    f = table.frame
    sel = f[(f["parameter"] == p) & (f["delta_pct"] == d)].set_index("metric")["metric_value"]
    arrived = math.isfinite(float(sel[f"{sc_i.name} T_arrive_s"]))
    dm = [(float(sel[f"{sc_i.name} d_{o.name}_min_m"]), o) for o in sc_i.obstacles]
    if any(x <= o.collision_distance(sc_i.robot.radius) for x, o in dm):
        return "collision"
    if any(x <= o.r3 for x, o in dm):
        return "critical region"
    return "arrives" if arrived else "no arrival"


def gain_sensitivity(
    scenarios: Sequence[Scenario] | None = None,
    base: VFFGains | None = None,
    *,
    deltas_pct: Sequence[float] = APPENDIX_C_DELTAS,
    parameters: Sequence[str] = _GAINS,
    stabilising: str = "off",
    arrival_tolerance: float = ARRIVAL_TOLERANCE.default,
) -> GainSensitivity:
    """The Appendix-C tables: each gain changed alone by ``deltas_pct`` around ``base``.

    Parameters
    ----------
    scenarios
        Default: Configurations 1, 2 and 3 of Ch. 6 (the thesis's set).
    base
        K_opt; default the thesis's optimum of Table C.1 (4.3, 0.68, 20.3, 240.7).
    deltas_pct
        Perturbations in %, each > -100 or exactly -100 (gain at zero, simulated at
        :data:`ZERO_GAIN`).
    parameters
        Gains to perturb, among ``("k1", "b", "k3", "k5")``.
    stabilising
        ``"off"`` (default, as the thesis's tables) or ``"lyapunov"``.
    arrival_tolerance
        Arrival radius (m).

    Returns
    -------
    GainSensitivity
    """
    sc, b0 = _check_common(scenarios, base, stabilising)
    params = list(parameters)
    bad = [p for p in params if p not in _GAINS]
    if bad or not params:
        raise InvalidParameterError(
            "parameters", parameters, f"must be a non-empty subset of {_GAINS}"
        )
    deltas = [float(d) for d in deltas_pct]
    if not deltas or any(not math.isfinite(d) or d < -100 or d == 0 for d in deltas):
        raise InvalidParameterError(
            "deltas_pct", deltas_pct, "must be finite, non-zero and >= -100", "%"
        )
    metric = _metric_factory(sc, stabilising, arrival_tolerance)
    base = dict(zip(_GAINS, b0.as_array().tolist(), strict=True))
    table = one_at_a_time(metric, base, params, deltas, _DESCRIPTIONS)
    base_vals = {
        m: float(v[0]) for m, v in metric({k: np.array([x]) for k, x in base.items()}).items()
    }
    rows = [
        {"parameter": p, "delta_pct": d, "scenario": sc_i.name,
         "outcome": _outcome(table, base, p, d, sc_i, stabilising, arrival_tolerance)}
        for p in params for d in deltas for sc_i in sc
    ]  # fmt: skip
    outcomes = pd.DataFrame(rows)
    warnings = []
    bad_base = [s.name for s in sc if not math.isfinite(base_vals[f"{s.name} T_arrive_s"])]
    if bad_base:
        warnings.append(f"the base gains do not arrive in {bad_base}")
    return GainSensitivity(
        b0,
        stabilising,
        tuple(s.name for s in sc),
        table,
        outcomes,
        base_vals,
        warnings=tuple(warnings),
    )


@dataclass(frozen=True)
class GainGlobalSensitivity(Result):
    """Local elasticities and Sobol indices of the VFF performance to its gains.

    Both tables come from the shared generators of :mod:`designlab.analysis.sensitivity`
    (:func:`~designlab.analysis.sensitivity.elasticities` and
    :func:`~designlab.analysis.sensitivity.sobol_indices`) with the batched simulator as
    the metric, so they read like every other sensitivity table of the project.

    Attributes
    ----------
    base
        The gains the box is centred on.
    stabilising
        ``"off"`` or ``"lyapunov"``.
    scenario_names
        The configurations.
    spread_pct
        Half-width of the Sobol box, % of each base gain.
    samples
        Base sample size N of the Saltelli sample (``N (4 + 2)`` gain sets).
    elasticity
        ``d ln m / d ln K`` at the base by central differences of ``relative_step``.
    sobol
        First-order (S1) and total (ST) indices over the box, with 95 % half-widths.
    infeasible_share
        Share of the Sobol sample that does not arrive or enters a critical region in
        some configuration (the optimiser would reject those points).
    status, warnings
        The result contract (:class:`~designlab.results.Result`).
    """

    base: VFFGains
    stabilising: str
    scenario_names: tuple[str, ...]
    spread_pct: float
    samples: int
    elasticity: SensitivityTable = field(repr=False)
    sobol: SensitivityTable = field(repr=False)
    infeasible_share: float
    status: str = OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """One row per (metric, gain): the elasticity, S1, ST and their half-widths."""
        e = self.elasticity.frame[["metric", "parameter", "elasticity"]]
        s = self.sobol.frame[["metric", "parameter", "S1", "S1_conf", "ST", "ST_conf"]]
        return e.merge(s, on=["metric", "parameter"], how="outer", sort=False)


def _check_global(spread_pct: Any, samples: Any, seed: Any, relative_step: Any) -> None:
    if isinstance(spread_pct, bool) or not (
        isinstance(spread_pct, int | float) and 0 < spread_pct < 100
    ):
        raise InvalidParameterError("spread_pct", spread_pct, "must be in (0, 100)", "%")
    if (
        isinstance(samples, bool)
        or not isinstance(samples, int | np.integer)
        or samples < 8
        or samples & (samples - 1)
    ):
        raise InvalidParameterError("samples", samples, "must be a power of two >= 8")
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise InvalidParameterError("seed", seed, "must be an integer >= 0")
    if isinstance(relative_step, bool) or not (
        isinstance(relative_step, int | float) and 0 < relative_step <= 0.5
    ):
        raise InvalidParameterError("relative_step", relative_step, "must be in (0, 0.5]")


def _global_metrics(inner: Any, sc: list[Scenario]) -> tuple[Any, Any, list[float]]:
    """The Sobol and the local metrics (H and the margin) and the Sobol sample's feasibility."""
    has_obstacles = any(s.obstacles for s in sc)

    def metric(points: dict[str, Array]) -> dict[str, Array]:
        out = inner(points)
        keep = {k: v for k, v in out.items() if k == "H_mean" or k.endswith(" H")}
        if has_obstacles:
            keep["critical_margin_min_m"] = out["critical_margin_min_m"]
        arrived = np.ones_like(out["H_mean"], dtype=bool)
        for s in sc:
            arrived &= np.isfinite(out[f"{s.name} T_arrive_s"])
        keep["_feasible"] = (arrived & (out["critical_margin_min_m"] > 0)).astype(float)
        return keep

    feasible: list[float] = []

    def sobol_metric(points: dict[str, Array]) -> dict[str, Array]:
        out = metric(points)
        feasible.extend(out.pop("_feasible").tolist())
        return out

    def local_metric(points: dict[str, Array]) -> dict[str, Array]:
        out = metric(points)
        out.pop("_feasible")
        return out

    return sobol_metric, local_metric, feasible


def gain_global_sensitivity(
    scenarios: Sequence[Scenario] | None = None,
    base: VFFGains | None = None,
    *,
    spread_pct: float = 50.0,
    samples: int = 128,
    seed: int = ARG.seed.default,
    relative_step: float = 0.02,
    stabilising: str = "off",
    arrival_tolerance: float = ARRIVAL_TOLERANCE.default,
) -> GainGlobalSensitivity:
    """Elasticities at ``base`` and Sobol indices over a box around it, of H and the safety margin.

    Complements the one-at-a-time tables of :func:`gain_sensitivity` (Zeng 2011, App. C.3,
    which vary one gain at a time) with the variance-based view a controls engineer uses
    to see which gains matter when all move together: which gain drives H_mean, H per
    configuration and the smallest margin to a critical region (``critical_margin_min_m``,
    m: the smallest centre/contour distance minus r3 over all obstacles and configurations).

    Parameters
    ----------
    scenarios
        Default: Configurations 1, 2 and 3 of Ch. 6.
    base
        Centre of the box; default the thesis's optimum (Table C.1).
    spread_pct
        Each gain varies uniformly within ``base * (1 -+ spread_pct/100)``, in (0, 100).
    samples
        Base sample size N of the Saltelli sample, a power of two >= 8 (``6 N`` gain
        sets, simulated as one batch).
    seed
        Seed of the sample and of the bootstrap confidence intervals.
    relative_step
        Relative step of the central differences of the elasticities, in (0, 0.5]. The
        simulated metrics are piecewise smooth (first passage, minima), so keep it well
        above the simulator's resolution.
    stabilising
        ``"off"`` (default) or ``"lyapunov"``.
    arrival_tolerance
        Arrival radius (m).

    Returns
    -------
    GainGlobalSensitivity

    Examples
    --------
    >>> import designlab as dl
    >>> nav = dl.navigation
    >>> g = nav.gain_global_sensitivity([nav.configuration(1)], samples=8)
    >>> g.sobol.ranked("H_mean")["parameter"].tolist()[0] in ("k1", "b", "k3", "k5")
    True
    >>> g.to_frame().columns.tolist()
    ['metric', 'parameter', 'elasticity', 'S1', 'S1_conf', 'ST', 'ST_conf']
    """
    sc, b0 = _check_common(scenarios, base, stabilising)
    _check_global(spread_pct, samples, seed, relative_step)
    sobol_metric, local_metric, feasible = _global_metrics(
        _metric_factory(sc, stabilising, arrival_tolerance), sc
    )
    base_pt = dict(zip(_GAINS, b0.as_array().tolist(), strict=True))
    f = spread_pct / 100
    box = {k: (v * (1 - f), v * (1 + f)) for k, v in base_pt.items()}
    el = elasticities(
        local_metric, base_pt, list(_GAINS), relative_step=float(relative_step),
        descriptions=_DESCRIPTIONS,
    )  # fmt: skip
    sob = sobol_indices(
        sobol_metric, base_pt, box, int(samples), seed=int(seed), descriptions=_DESCRIPTIONS
    )
    share = 1.0 - float(np.mean(feasible))
    warnings = []
    if share > 0:
        warnings.append(
            f"{100 * share:.1f} % of the Sobol sample does not arrive or enters a critical region "
            "in some configuration; their H still enters the indices"
        )
    bad = sob.frame[sob.frame["ST"].isna()]["metric"].unique().tolist()
    if bad:
        warnings.append(f"no Sobol indices for {bad} (non-finite or constant over the box)")
    return GainGlobalSensitivity(
        b0,
        stabilising,
        tuple(s.name for s in sc),
        float(spread_pct),
        int(samples),
        el,
        sob,
        share,
        warnings=tuple(warnings),
    )
