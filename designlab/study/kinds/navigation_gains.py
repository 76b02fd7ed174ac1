"""The ``navigation_gains`` study kind: optimal VFF gains and their Appendix-C sensitivity.

For each stabilising mode it runs :func:`designlab.navigation.optimise_gains` on the
configurations of the study (Zeng 2011, App. C.2: Configurations 1-3 of Ch. 6),
compares H_mean of the experimental gains (3, 0.25, 20, 17), the thesis's optimum
(Table C.1) and ours in the same simulator, checks the optimum on the validation
configurations (Configuration 4, not optimised), optionally optimises over
randomised human walks, and builds the App. C.3 sensitivity tables around the
thesis's optimum and around ours.

Examples
--------
>>> from designlab.study import parse_study
>>> study = parse_study('''
... designlab: 1
... kind: navigation_gains
... name: demo
... modes: [off]
... max_evaluations: 32
... ''')
>>> study.configurations, study.validation, study.seed
([1, 2, 3], [4], 0)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Annotated, Any, ClassVar, Literal

import pandas as pd
from pydantic import AfterValidator, BeforeValidator, Field, model_validator

from designlab import navigation as nav
from designlab.navigation import tuning
from designlab.navigation.criteria import EQUAL_WEIGHTS, check_weights
from designlab.navigation.methods import METHOD, METHODS, method_of
from designlab.navigation.parameters import EXPERIMENT_GAINS, GAIN, OPTIMAL_GAINS
from designlab.params import params_of
from designlab.results import OK, Result
from designlab.study.base import Flag, Integer, Model, Number, StudyBase
from designlab.study.kinds.navigation_specs import ScenarioSpec, Stabilising
from designlab.study.registry import StudyKind
from designlab.study.runner import RunContext
from designlab.validation import reject_bool

__all__ = ["KIND", "NavigationGainsResult", "NavigationGainsStudy", "run"]

_Config = Annotated[Literal[1, 2, 3, 4], BeforeValidator(reject_bool)]
#: Criterion weights (w_T, w_D, w_E) of H (5.6.6) in the navigation kinds' YAML, checked by
#: :func:`designlab.navigation.criteria.check_weights` (non-negative, summing to 1).
Weights = Annotated[tuple[Number, Number, Number], AfterValidator(check_weights)]


#: Stabilising-force mode (``off`` may be written bare in YAML).
Mode = Stabilising
EXPERIMENTAL = EXPERIMENT_GAINS
#: Suffix of the optimisation keys (and history rows) of the bound check.
WIDER = "_wider_box"
THESIS_OPTIMUM = OPTIMAL_GAINS
Gain = GAIN.annotation()
_WALKS = params_of(nav.RandomWalks)
_Walks = _WALKS["n"].annotation()
_Seed = tuning.SEED.annotation()
_Popsize = tuning.POPSIZE.annotation()
_Budget = tuning.MAX_EVALUATIONS.annotation()
_Margin = tuning.CRITICAL_MARGIN.annotation()


class Range(Model):
    """A closed interval [low, high]."""

    low: Number = Field(allow_inf_nan=False)
    high: Number = Field(allow_inf_nan=False)

    @model_validator(mode="after")
    def _order(self) -> Range:
        if not self.low <= self.high:
            raise ValueError(f"low = {self.low} must not exceed high = {self.high}")
        return self


class GainBounds(Model):
    """Search box of the gains (K1 N/m, b s, K3 N/m, K5 N/m^2), lower bounds > 0."""

    k1: tuple[Gain, Gain] = tuning.DEFAULT_BOUNDS["k1"]
    b: tuple[Gain, Gain] = tuning.DEFAULT_BOUNDS["b"]
    k3: tuple[Gain, Gain] = tuning.DEFAULT_BOUNDS["k3"]
    k5: tuple[Gain, Gain] = tuning.DEFAULT_BOUNDS["k5"]

    @model_validator(mode="after")
    def _ordered(self) -> GainBounds:
        for name, (low, high) in self.as_dict().items():
            if not low < high:
                raise ValueError(
                    f"bounds.{name} = [{low:g}, {high:g}] is not allowed: give [low, high] "
                    "with low < high"
                )
        return self

    def as_dict(self) -> dict[str, tuple[float, float]]:
        return {"k1": self.k1, "b": self.b, "k3": self.k3, "k5": self.k5}


def _range(name: str) -> Range:
    low, high = _WALKS[name].default
    return Range(low=low, high=high)


class RobustSpec(Model):
    """Robust mode: every walking human replaced by ``walks`` random walks."""

    walks: _Walks = _WALKS["n"].default
    mode: Literal["mean", "worst"] = "mean"
    stabilising: Mode = "off"
    speed: Range = Field(default_factory=lambda: _range("speed"), description="cruise speed, m/s")
    start_time: Range = Field(
        default_factory=lambda: _range("start_time"), description="start time, s"
    )
    lateral_offset: Range = Field(
        default_factory=lambda: _range("lateral_offset"), description="offset, m"
    )


class NavigationGainsStudy(StudyBase):
    """Optimal VFF gains (Zeng 2011, App. C) and their sensitivity tables."""

    kind: Literal["navigation_gains"]
    configurations: list[_Config] = Field(
        default_factory=lambda: [1, 2, 3],
        description="Ch. 6 configurations optimised together",
    )
    scenarios: list[ScenarioSpec] = Field(  # type: ignore[valid-type]
        default_factory=list,
        max_length=20,
        description="scenarios of the user's optimised with the configurations "
        "(docs/navigation_scenarios.md; configurations: [] optimises over these alone)",
    )
    validation: list[_Config] = Field(
        default_factory=lambda: [4], description="configurations checked but not optimised"
    )
    modes: list[Mode] = Field(
        default_factory=lambda: ["off", "lyapunov"],
        min_length=1,
        description="stabilising-force modes",
    )
    bounds: GainBounds = Field(default_factory=GainBounds)
    seed: _Seed = tuning.SEED.default
    repeat_seeds: list[_Seed] = Field(
        default_factory=list,
        max_length=16,
        description="further seeds of each mode's optimisation, for its repeatability "
        "(repeatability.csv; the study's seed is the first row)",
    )
    popsize: _Popsize = 16
    max_evaluations: _Budget = 1600
    refine: Flag = True
    jit: Flag = Field(
        False,
        description="simulate with the step compiled to four gain sets per pass (needs a C "
        "compiler; the same optimum, several times faster)",
    )
    critical_margin: _Margin = 0.0
    bound_check: Flag = Field(
        False,
        description="when an optimum lies on a bound, optimise again with that bound moved "
        "10x outwards (row designlab_optimum_wider_box)",
    )
    robust: RobustSpec | None = None
    sensitivity: Flag = Field(
        True, description="App. C.3 tables around the thesis's optimum and ours"
    )
    deltas_pct: list[Annotated[Number, Field(ge=-100, le=1000, allow_inf_nan=False)]] = Field(
        default_factory=lambda: [-100, -50, -20, -10, -5, -2, 2, 5, 10, 20, 50, 100],
        description="perturbations of the sensitivity tables, %",
    )
    sobol_samples: Annotated[Integer, Field(ge=0, le=4096)] = Field(
        128,
        description="base sample N of the Sobol indices around each optimum (6 N gain sets; "
        "0: no Sobol indices or elasticities)",
    )
    sobol_spread_pct: Annotated[Number, Field(gt=0, lt=100, allow_inf_nan=False)] = Field(
        50.0, description="half-width of the Sobol box, % of each gain"
    )
    weights: Weights = Field(
        EQUAL_WEIGHTS,
        description="criterion weights (w_T, w_D, w_E) of H (5.6.6): non-negative, sum 1",
    )
    baselines: list[METHODS.literal(baseline=True)] = Field(  # type: ignore[valid-type]
        default_factory=list,
        description="baselines whose gains are optimised too (App. C.2, Table C.1)",
    )
    baseline_configurations: list[_Config] = Field(
        default_factory=lambda: [1, 2, 4],
        min_length=1,
        description="configurations the baselines and the new VFF are compared on "
        "(App. C.2: 1, 2 and 4)",
    )

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "gains.csv",
        "history.csv",
        "convergence.png",
        "sensitivity_*.csv",
        "global_sensitivity_*.csv",
        "appendix_c_comparison.csv",
        "appendix_c_outcomes.csv",
        "baseline_gains.csv",
        "repeatability.csv",
        "trajectories_*.png",
        "study.yaml",
    )
    #: s: CPU time of studies/navigation_gains.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 143

    @model_validator(mode="after")
    def _check(self) -> NavigationGainsStudy:
        if not self.configurations and not self.scenarios:
            raise ValueError("give at least one configuration or scenario to optimise over")
        if len(set(self.configurations)) != len(self.configurations):
            raise ValueError("configurations must not repeat")
        if len(set(self.modes)) != len(self.modes):
            raise ValueError("modes must not repeat")
        if self.seed in self.repeat_seeds or len(set(self.repeat_seeds)) != len(self.repeat_seeds):
            raise ValueError(
                f"repeat_seeds = {self.repeat_seeds} must not repeat nor hold seed = {self.seed}"
            )
        if self.max_evaluations < self.popsize:
            raise ValueError(
                f"max_evaluations = {self.max_evaluations} must be >= popsize = {self.popsize}"
            )
        if any(d == 0 for d in self.deltas_pct):
            raise ValueError("deltas_pct must not contain 0 (the base row is always there)")
        n = self.sobol_samples
        if n and (n < 8 or n & (n - 1)):
            raise ValueError(f"sobol_samples = {n} must be 0 or a power of two >= 8")
        return self

    def size(self) -> str:
        runs = len(self.modes) * (1 + (self.robust is not None) + len(self.repeat_seeds))
        return (
            f"{runs} optimisation(s) of up to {self.max_evaluations} gain sets x "
            f"{len(self.configurations) + len(self.scenarios)} configs"
            + (" (+1 per mode whose optimum lies on a bound)" if self.bound_check else "")
        )


@dataclass(frozen=True)
class NavigationGainsResult(Result):
    """Result of a ``navigation_gains`` study.

    Attributes
    ----------
    study
        The study.
    optima
        ``{mode: GainOptimum}``; with a robust spec also ``"robust"``; with the bound
        check ``"<mode>_wider_box"`` for each mode whose optimum lay on a bound.
    comparison
        The gains table (``gains.csv``): one row per (gains, stabilising).
    sensitivities
        ``{label: GainSensitivity}`` (``thesis_optimum_off``, ``designlab_optimum_<mode>``).
    runs
        ``{(mode, gains label, configuration): NavigationResult}`` for the trajectory plots.
    global_sensitivities
        ``{label: GainGlobalSensitivity}``: elasticities and Sobol indices around the
        same bases as ``sensitivities``.
    appendix_c
        Our table around the thesis's optimum (stabilising off) against Zeng 2011,
        Tables C.2-C.9, entry by entry (empty unless the study optimises
        Configurations 1-3 with sensitivity on).
    appendix_c_outcomes
        The -100 % rows: the thesis's words next to ours.
    baselines
        Table C.1 like for like (``baseline_gains.csv``): the thesis's gains and our optimum
        of every method in ``baselines`` and of the new VFF, each scored on the
        ``baseline_configurations`` (stabilising force off).
    baseline_optima
        ``{method: GainOptimum}`` of the baselines.
    repeatability
        Each mode's optimisation with the study's seed and each of ``repeat_seeds``
        (``repeatability.csv``): ``stabilising``, ``seed``, the gains, ``H_mean``,
        ``evaluations`` and ``status``.

    Examples
    --------
    A search cut short (8 evaluations) is ``not_converged``, and says so:

    >>> from designlab.study import parse_study, run_study
    >>> r = run_study(parse_study('''
    ... designlab: 1
    ... kind: navigation_gains
    ... name: demo
    ... modes: [off]
    ... configurations: [1]
    ... validation: []
    ... popsize: 4
    ... max_evaluations: 8
    ... refine: false
    ... sensitivity: false
    ... '''))
    >>> type(r).__name__, r.status, list(r.optima)
    ('NavigationGainsResult', 'not_converged', ['off'])
    """

    study: NavigationGainsStudy
    optima: dict[str, nav.GainOptimum]
    comparison: pd.DataFrame
    sensitivities: dict[str, nav.GainSensitivity] = field(repr=False)
    runs: dict[tuple[str, str, int], nav.NavigationResult] = field(repr=False)
    global_sensitivities: dict[str, nav.GainGlobalSensitivity] = field(
        default_factory=dict, repr=False
    )
    appendix_c: pd.DataFrame = field(default_factory=pd.DataFrame, repr=False)
    appendix_c_outcomes: pd.DataFrame = field(default_factory=pd.DataFrame, repr=False)
    baselines: pd.DataFrame = field(default_factory=pd.DataFrame, repr=False)
    baseline_optima: dict[str, nav.GainOptimum] = field(default_factory=dict, repr=False)
    repeatability: pd.DataFrame = field(default_factory=pd.DataFrame, repr=False)

    @property
    def status(self) -> str:
        """``"ok"``, or the first optimum's status that is not (the bound check's aside)."""
        bad = [o.status for k, o in self.optima.items() if o.status != OK and not k.endswith(WIDER)]
        return bad[0] if bad else OK

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        out = [f"{m}: {w}" for m, o in self.optima.items() for w in o.warnings]
        out += [
            f"{'baseline ' if m != METHOD.default else 'like for like '}{m}: {w}"
            for m, o in self.baseline_optima.items()
            for w in o.warnings
        ]
        out += [f"sensitivity {k}: {w}" for k, s in self.sensitivities.items() for w in s.warnings]
        out += [
            f"global sensitivity {k}: {w}"
            for k, s in self.global_sensitivities.items()
            for w in s.warnings
        ]
        return tuple(out)

    def to_frame(self) -> pd.DataFrame:
        """The gains table."""
        return self.comparison.copy()


def _rows(
    labels: list[str],
    mode: str,
    gains: list[nav.VFFGains],
    f_opt: pd.DataFrame,
    f_val: pd.DataFrame | None,
    opt_names: list[str],
    val_names: list[str],
) -> list[dict[str, object]]:
    out = []
    for j, (label, g) in enumerate(zip(labels, gains, strict=True)):
        r: dict[str, object] = {
            "gains": label,
            "stabilising": mode,
            "k1": g.k1,
            "b": g.b,
            "k3": g.k3,
            "k5": g.k5,
            "H_mean": float(f_opt["H_mean"].iloc[j]),
        }
        for n in opt_names:
            r[f"H_{n}"] = float(f_opt[f"H_{n}"].iloc[j])
        r["feasible"] = bool(f_opt["feasible"].iloc[j])
        if f_val is not None:
            for n in val_names:
                r[f"H_{n}"] = float(f_val[f"H_{n}"].iloc[j])
            r["validation_feasible"] = bool(f_val["feasible"].iloc[j])
        for frame, names in ((f_opt, opt_names), (f_val, val_names)):
            for q in ("T_arrive_s", "critical_margin_m"):
                for n in names if frame is not None else []:
                    r[f"{q}_{n}"] = float(frame[f"{q}_{n}"].iloc[j])
        out.append(r)
    return out


def run(study: NavigationGainsStudy, context: RunContext) -> NavigationGainsResult:
    """Compute the ``navigation_gains`` study (optimisations, comparison, sensitivity, runs).

    Parameters
    ----------
    study
        The validated study.
    context
        ``context.executor`` (if any) splits each population over its workers; each
        optimisation draws a progress bar (gain sets, best H_mean).
    """
    scen = [nav.configuration(i) for i in study.configurations]
    scen += [s.build() for s in study.scenarios]
    val = [nav.configuration(i) for i in study.validation if i not in study.configurations]
    optima: dict[str, nav.GainOptimum] = {}
    rows: list[dict[str, object]] = []
    for mode in study.modes:
        rows += _mode_block(study, context, scen, val, mode, optima)
    if study.robust is not None:
        rows += _robust_block(study, context, scen, val, optima)
    comp = _comparison(rows)
    sens, glob = _sensitivities(study, scen, optima)
    appc = pd.DataFrame()
    appc_out = pd.DataFrame()
    if "thesis_optimum_off" in sens and sorted(study.configurations) == [1, 2, 3]:
        appc = sens["thesis_optimum_off"].compare_appendix_c()
        appc_out = sens["thesis_optimum_off"].appendix_c_outcomes()
    base_frame, base_optima = _baseline_block(study, context, optima)
    return NavigationGainsResult(
        study, optima, comp, sens, _runs(study, optima), glob, appc, appc_out,
        base_frame, base_optima, _repeatability(study, context, scen, optima),
    )  # fmt: skip


def _repeatability(
    study: NavigationGainsStudy,
    context: RunContext,
    scen: list[Any],
    optima: dict[str, nav.GainOptimum],
) -> pd.DataFrame:
    """Each mode's optimisation again with every seed of ``repeat_seeds``: one row per run."""
    if not study.repeat_seeds:
        return pd.DataFrame()
    rows = []
    for mode in study.modes:
        runs = [(study.seed, optima[mode])]
        for s in study.repeat_seeds:
            runs.append((s, _optimise(study, context, scen, f"{mode}, seed {s}",
                                      stabilising=mode, seed=s)))  # fmt: skip
        for s, o in runs:
            rows.append({"stabilising": mode, "seed": s,
                         **{k: getattr(o.gains, k, float("nan")) for k in ("k1", "b", "k3", "k5")},
                         "H_mean": o.objective, "evaluations": o.evaluations,
                         "status": str(getattr(o.status, "value", o.status))})  # fmt: skip
    return pd.DataFrame(rows)


#: Table C.1's gains and H_opt of the baselines.
TABLE_C1: dict[str, tuple[Any, float]] = {
    "masoud": (nav.MasoudGains(), 0.66),
    "ge_cui": (nav.GeCuiGains(), 0.52),
    "vff": (OPTIMAL_GAINS, 0.69),
}


def _baseline_block(
    study: NavigationGainsStudy, context: RunContext, optima: dict[str, nav.GainOptimum]
) -> tuple[pd.DataFrame, dict[str, nav.GainOptimum]]:
    """Table C.1 like for like: each baseline optimised, every method scored on one set."""
    if not study.baselines:
        return pd.DataFrame(), {}
    scen = [nav.configuration(i) for i in study.baseline_configurations]
    found: dict[str, nav.GainOptimum] = {}
    rows = []
    for method in study.baselines:
        found[method] = _optimise(study, context, scen, method, method=method, stabilising="off")
    ours = {m: o.gains for m, o in found.items()}
    same = not study.scenarios and sorted(study.configurations) == sorted(
        study.baseline_configurations
    )
    if same and "off" in optima:
        vff = optima["off"]
    else:  # like for like: the new VFF optimised on the baselines' configurations too
        vff = _optimise(study, context, scen, METHOD.default, stabilising="off")
        found[METHOD.default] = vff
    if vff.gains is not None:
        ours[METHOD.default] = vff.gains
    for method in (METHOD.default, *study.baselines):
        cands = [("table_C1", TABLE_C1[method][0])]
        if ours.get(method) is not None:
            cands.append(("designlab_optimum", ours[method]))
        for label, g in cands:
            strategy = method_of(method)
            row = strategy.gain_row(g)
            row[1] = row[1] if "b" in strategy.used_gains else 1.0  # b is not Masoud's
            e = nav.evaluate_gains(scen, row[None, :], method=method, stabilising="off",
                                   weights=study.weights).to_frame()  # fmt: skip
            thesis_h = TABLE_C1[method][1] if label == "table_C1" else None
            rows.append({"method": method, "gains": label,
                         **{k: float(v) for k, v in zip(("k1", "b", "k3", "k5"), row, strict=True)},
                         "H_mean": float(e["H_mean"][0]), "feasible": bool(e["feasible"][0]),
                         "H_opt_table_C1": thesis_h})  # fmt: skip
    frame = pd.DataFrame(rows)
    no_b = [m for m in frame["method"].unique() if "b" not in method_of(m).used_gains]
    frame.loc[frame["method"].isin(no_b), "b"] = float("nan")
    return frame, found


def _optimise(
    study: NavigationGainsStudy, context: RunContext, scen: list[Any], label: str, **kw: Any
) -> nav.GainOptimum:
    """One optimisation with the study's settings and a progress bar."""
    settings: dict[str, Any] = dict(
        bounds=study.bounds.as_dict(),
        critical_margin=study.critical_margin,
        seed=study.seed,
        popsize=study.popsize,
        max_evaluations=study.max_evaluations,
        refine=study.refine,
        executor=context.executor,
        chunks=2 if context.executor is not None else 1,
        jit=study.jit,
        weights=study.weights,
    )
    with context.bar(f"{study.kind}: optimise ({label})") as hook:
        return nav.optimise_gains(scen, **{**settings, **kw}, progress=hook)


def _mode_block(
    study: NavigationGainsStudy,
    context: RunContext,
    scen: list[Any],
    val: list[Any],
    mode: str,
    optima: dict[str, nav.GainOptimum],
) -> list[dict[str, object]]:
    """The optimisation of one stabilising mode (and its bound check): gains-table rows."""
    opt = optima[mode] = _optimise(study, context, scen, mode, stabilising=mode)
    cand = [("experimental", EXPERIMENTAL), ("thesis_optimum", THESIS_OPTIMUM)]
    if opt.gains is not None:
        cand.append(("designlab_optimum", opt.gains))
    hit = opt.on_bounds()
    if study.bound_check and hit:
        wide = study.bounds.as_dict()
        for n, side in hit.items():
            lo, hi = wide[n]
            wide[n] = (lo / 10, hi) if side == "low" else (lo, hi * 10)
        opt_w = optima[f"{mode}{WIDER}"] = _optimise(
            study, context, scen, f"{mode}, wider box", stabilising=mode, bounds=wide
        )
        if opt_w.gains is not None:
            cand.append(("designlab_optimum_wider_box", opt_w.gains))
    kw = dict(stabilising=mode, critical_margin=study.critical_margin, weights=study.weights)
    return _scored(cand, mode, scen, val, kw)


def _scored(
    cand: list[tuple[str, nav.VFFGains]],
    mode: str,
    scen: list[Any],
    val: list[Any],
    kw: dict[str, Any],
) -> list[dict[str, object]]:
    """The candidates scored on the optimised and the validation configurations."""
    labels, gs = [c[0] for c in cand], [c[1] for c in cand]
    f_opt = nav.evaluate_gains(scen, gs, **kw).to_frame()
    f_val = nav.evaluate_gains(val, gs, **kw).to_frame() if val else None
    return _rows(labels, mode, gs, f_opt, f_val, [s.name for s in scen], [s.name for s in val])


def _robust_block(
    study: NavigationGainsStudy,
    context: RunContext,
    scen: list[Any],
    val: list[Any],
    optima: dict[str, nav.GainOptimum],
) -> list[dict[str, object]]:
    """The optimisation over randomised walks: gains-table rows."""
    rs = study.robust
    assert rs is not None
    walks = nav.RandomWalks(
        n=rs.walks,
        speed=(rs.speed.low, rs.speed.high),
        start_time=(rs.start_time.low, rs.start_time.high),
        lateral_offset=(rs.lateral_offset.low, rs.lateral_offset.high),
        seed=study.seed,
    )
    robust = dict(stabilising=rs.stabilising, robust=walks, robust_mode=rs.mode)
    opt = optima["robust"] = _optimise(study, context, scen, "robust", **robust)
    cand = [("experimental", EXPERIMENTAL), ("thesis_optimum", THESIS_OPTIMUM)]
    if opt.gains is not None:
        cand.append(("designlab_robust_optimum", opt.gains))
    rows = _scored(
        cand, rs.stabilising, scen, val, {**robust, "critical_margin": study.critical_margin}
    )
    for r in rows:
        r["robust"] = f"{rs.mode} over {rs.walks} walks"
    return rows


def _comparison(rows: list[dict[str, object]]) -> pd.DataFrame:
    """The gains table with the improvement of ours over the references, per block."""
    comp = pd.DataFrame(rows)
    if "robust" not in comp:
        comp["robust"] = ""
    comp["robust"] = comp["robust"].fillna("")
    for _, grp in comp.groupby(["stabilising", "robust"], sort=False):
        ref = grp.set_index("gains")["H_mean"]
        for idx in grp.index:
            comp.loc[idx, "vs_experimental_pct"] = 100 * (
                comp.loc[idx, "H_mean"] / ref["experimental"] - 1
            )
            comp.loc[idx, "vs_thesis_optimum_pct"] = 100 * (
                comp.loc[idx, "H_mean"] / ref["thesis_optimum"] - 1
            )
    return comp


def _sensitivities(
    study: NavigationGainsStudy, scen: list[Any], optima: dict[str, nav.GainOptimum]
) -> tuple[dict[str, nav.GainSensitivity], dict[str, nav.GainGlobalSensitivity]]:
    """The App. C.3 tables and the Sobol indices around the thesis's optimum and ours."""
    sens: dict[str, nav.GainSensitivity] = {}
    if study.sensitivity:
        sens["thesis_optimum_off"] = nav.gain_sensitivity(
            scen, THESIS_OPTIMUM, deltas_pct=study.deltas_pct, stabilising="off"
        )
        for mode in study.modes:
            opt = optima[mode]
            if opt.gains is not None:
                sens[f"designlab_optimum_{mode}"] = nav.gain_sensitivity(
                    scen, opt.gains, deltas_pct=study.deltas_pct, stabilising=mode
                )
    glob: dict[str, nav.GainGlobalSensitivity] = {}
    if study.sensitivity and study.sobol_samples:
        for label, s in sens.items():
            glob[label] = nav.gain_global_sensitivity(
                scen,
                s.base,
                spread_pct=study.sobol_spread_pct,
                samples=study.sobol_samples,
                seed=study.seed,
                stabilising=s.stabilising,
            )
    return sens, glob


def _runs(
    study: NavigationGainsStudy, optima: dict[str, nav.GainOptimum]
) -> dict[tuple[str, str, int], nav.NavigationResult]:
    """The runs drawn in the trajectory figures."""
    runs: dict[tuple[str, str, int], nav.NavigationResult] = {}
    for mode in study.modes:
        opt = optima[mode]
        sets = [("thesis_optimum", THESIS_OPTIMUM)] + (
            [("designlab_optimum", opt.gains)] if opt.gains else []
        )
        for i in sorted(set(study.configurations) | set(study.validation)):
            for label, g in sets:
                runs[(mode, label, i)] = nav.simulate(nav.configuration(i), g, stabilising=mode)
    return runs


KIND = StudyKind(
    name="navigation_gains",
    schema=NavigationGainsStudy,
    run=run,
    report="designlab.report.navigation_gains",
)
