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
>>> sens.appendix_c("k1")[0].columns.tolist()[:4]
['delta_pct', 'ch6_config1 T_arrive_s', 'ch6_config1 L_energy_J_per_ohm', 'ch6_config1 d_circle_min_m']
>>> bool(abs(sens.s_summary().set_index("parameter").loc["k1", "S_max_pct"]) < 5)
True
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.analysis.sensitivity import SensitivityTable, one_at_a_time
from designlab.errors import InvalidParameterError
from designlab.navigation.parameters import VFFGains
from designlab.navigation.scenarios import Scenario, configuration
from designlab.navigation.simulate import NavigationResult, simulate, simulate_batch
from designlab.results import OK, Result

__all__ = ["APPENDIX_C_DELTAS", "GainSensitivity", "classify_run", "gain_sensitivity"]

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


def classify_run(res: NavigationResult, *, moving_speed: float = 0.05, reversals: int = 4) -> str:
    """The outcome of one run in the words of Zeng 2011, App. C.3.

    ``"collision"`` (touched an obstacle), ``"critical region"`` (entered one without
    touching), ``"arrives"``, ``"oscillation"`` (no arrival and, over the second half of
    the run, still moving faster than ``moving_speed`` on average with at least
    ``reversals`` sign changes of a velocity component) or ``"no arrival"``.

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
    """Whether the robot ends the horizon at rest near the goal (first-passage arrival switched off)."""
    res = simulate(scenario, gains, stabilising=stabilising, arrival_tolerance=1e-9)
    end = res.position[-1]
    return bool(
        math.dist(end, scenario.goal) <= tolerance and float(np.hypot(*res.velocity[-1])) < 0.05
    )


def _metric_factory(scenarios: list[Scenario], stabilising: str, arrival_tolerance: float):
    def metric(points: dict[str, Array]) -> dict[str, Array]:
        g = np.column_stack(
            [np.maximum(np.asarray(points[n], dtype=float), ZERO_GAIN) for n in _GAINS]
        )
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
        return out

    return metric


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

    def s_summary(self) -> pd.DataFrame:
        """Max and mean |S_K| of H_mean per gain in % (App. C.3's summary), -100 % rows excluded."""
        f = self.table.frame
        f = f[(f["metric"] == "H_mean") & (f["delta_pct"] > -100)]
        g = f.assign(abs_S=f["S_pct"].abs()).groupby("parameter", sort=False)["abs_S"]
        return pd.DataFrame({"S_max_pct": g.max(), "S_mean_pct": g.mean()}).reset_index()


def gain_sensitivity(
    scenarios: Sequence[Scenario] | None = None,
    base: VFFGains | None = None,
    *,
    deltas_pct: Sequence[float] = APPENDIX_C_DELTAS,
    parameters: Sequence[str] = _GAINS,
    stabilising: str = "off",
    arrival_tolerance: float = 0.15,
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
    sc = [configuration(i) for i in (1, 2, 3)] if scenarios is None else list(scenarios)
    if not sc or not all(isinstance(s, Scenario) for s in sc):
        raise InvalidParameterError(
            "scenarios", scenarios, "must be a non-empty sequence of Scenario"
        )
    b0 = VFFGains(4.3, 0.68, 20.3, 240.7) if base is None else base
    if not isinstance(b0, VFFGains):
        raise InvalidParameterError("base", base, "must be a VFFGains")
    if stabilising not in ("off", "lyapunov"):
        raise InvalidParameterError("stabilising", stabilising, "must be 'off' or 'lyapunov'")
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
    rows = []
    f = table.frame
    for p in params:
        for d in deltas:
            for sc_i in sc:
                if d == -100:
                    g = dict(base)
                    g[p] = ZERO_GAIN
                    res = simulate(
                        sc_i,
                        VFFGains(**g),
                        stabilising=stabilising,
                        arrival_tolerance=arrival_tolerance,
                    )
                    outcome = classify_run(res)
                    if outcome == "arrives" and not _settles(
                        sc_i, VFFGains(**g), stabilising, arrival_tolerance
                    ):
                        outcome = "oscillation (passes the goal, never settles)"
                else:
                    sel = f[(f["parameter"] == p) & (f["delta_pct"] == d)].set_index("metric")[
                        "metric_value"
                    ]
                    arrived = math.isfinite(float(sel[f"{sc_i.name} T_arrive_s"]))
                    dm = [(float(sel[f"{sc_i.name} d_{o.name}_min_m"]), o) for o in sc_i.obstacles]
                    outcome = (
                        "collision"
                        if any(x <= o.collision_distance(sc_i.robot.radius) for x, o in dm)
                        else "critical region"
                        if any(x <= o.r3 for x, o in dm)
                        else "arrives"
                        if arrived
                        else "no arrival"
                    )
                rows.append(
                    {"parameter": p, "delta_pct": d, "scenario": sc_i.name, "outcome": outcome}
                )
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
