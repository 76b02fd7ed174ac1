"""The ``vff_gains`` study kind: optimal VFF gains and their Appendix-C sensitivity.

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
... kind: vff_gains
... name: demo
... modes: [off]
... max_evaluations: 32
... ''')
>>> study.configurations, study.validation, study.seed
([1, 2, 3], [4], 0)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Annotated, ClassVar, Literal

import pandas as pd
from pydantic import BeforeValidator, Field, model_validator

from designlab import navigation as nav
from designlab.results import OK, Result
from designlab.study.base import Flag, Integer, Model, Number, StudyBase
from designlab.study.kinds.vff_specs import Gain
from designlab.study.registry import StudyKind
from designlab.study.runner import RunContext
from designlab.validation import reject_bool

__all__ = ["KIND", "VffGainsResult", "VffGainsStudy", "run"]

_Config = Annotated[Literal[1, 2, 3, 4], BeforeValidator(reject_bool)]


def _yaml_off(value: object) -> object:
    # YAML 1.1 reads a bare ``off`` as false; in this field it can only mean the mode "off".
    return "off" if value is False else value


#: Stabilising-force mode (``off`` may be written bare in YAML).
Mode = Annotated[Literal["off", "lyapunov"], BeforeValidator(_yaml_off)]
EXPERIMENTAL = nav.VFFGains(k1=3.0, b=0.25, k3=20.0, k5=17.0)
#: Suffix of the optimisation keys (and history rows) of the bound check.
WIDER = "_wider_box"
THESIS_OPTIMUM = nav.VFFGains(k1=4.3, b=0.68, k3=20.3, k5=240.7)


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

    k1: tuple[Gain, Gain] = (0.5, 50.0)
    b: tuple[Gain, Gain] = (0.05, 3.0)
    k3: tuple[Gain, Gain] = (0.5, 200.0)
    k5: tuple[Gain, Gain] = (0.5, 500.0)

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


class RobustSpec(Model):
    """Robust mode: every walking human replaced by ``walks`` random walks."""

    walks: Annotated[Integer, Field(ge=1, le=64)] = 8
    mode: Literal["mean", "worst"] = "mean"
    stabilising: Mode = "off"
    speed: Range = Field(
        default_factory=lambda: Range(low=0.8, high=1.2), description="cruise speed, m/s"
    )
    start_time: Range = Field(
        default_factory=lambda: Range(low=0.0, high=0.5), description="start time, s"
    )
    lateral_offset: Range = Field(
        default_factory=lambda: Range(low=-0.1, high=0.1), description="offset, m"
    )


class VffGainsStudy(StudyBase):
    """Optimal VFF gains (Zeng 2011, App. C) and their sensitivity tables."""

    kind: Literal["vff_gains"]
    configurations: list[_Config] = Field(
        default_factory=lambda: [1, 2, 3],
        min_length=1,
        description="Ch. 6 configurations optimised together",
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
    seed: Annotated[Integer, Field(ge=0)] = 0
    popsize: Annotated[Integer, Field(ge=4, le=256)] = 16
    max_evaluations: Annotated[Integer, Field(ge=4, le=100000)] = 1600
    refine: Flag = True
    jit: Flag = Field(
        False,
        description="simulate with the step compiled to four gain sets per pass (needs a C "
        "compiler; the same optimum, several times faster)",
    )
    critical_margin: Annotated[Number, Field(ge=0, le=2, allow_inf_nan=False)] = Field(
        0.0,
        description="clearance (m) every run must keep outside every critical region "
        "(0: never enter one)",
    )
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

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "gains.csv",
        "history.csv",
        "convergence.png",
        "sensitivity_*.csv",
        "global_sensitivity_*.csv",
        "appendix_c_comparison.csv",
        "appendix_c_outcomes.csv",
        "trajectories_*.png",
        "study.yaml",
    )

    @model_validator(mode="after")
    def _check(self) -> VffGainsStudy:
        if len(set(self.configurations)) != len(self.configurations):
            raise ValueError("configurations must not repeat")
        if len(set(self.modes)) != len(self.modes):
            raise ValueError("modes must not repeat")
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
        runs = len(self.modes) * (1 + (self.robust is not None))
        return (
            f"{runs} optimisation(s) of up to {self.max_evaluations} gain sets x "
            f"{len(self.configurations)} configs"
            + (" (+1 per mode whose optimum lies on a bound)" if self.bound_check else "")
        )


@dataclass(frozen=True)
class VffGainsResult(Result):
    """Result of a ``vff_gains`` study.

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
    """

    study: VffGainsStudy
    optima: dict[str, nav.GainOptimum]
    comparison: pd.DataFrame
    sensitivities: dict[str, nav.GainSensitivity] = field(repr=False)
    runs: dict[tuple[str, str, int], nav.NavigationResult] = field(repr=False)
    global_sensitivities: dict[str, nav.GainGlobalSensitivity] = field(
        default_factory=dict, repr=False
    )
    appendix_c: pd.DataFrame = field(default_factory=pd.DataFrame, repr=False)
    appendix_c_outcomes: pd.DataFrame = field(default_factory=pd.DataFrame, repr=False)

    @property
    def status(self) -> str:
        """``"ok"``, or the first optimum's status that is not (the bound check's aside)."""
        bad = [o.status for k, o in self.optima.items() if o.status != OK and not k.endswith(WIDER)]
        return bad[0] if bad else OK

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        out = [f"{m}: {w}" for m, o in self.optima.items() for w in o.warnings]
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


def run(study: VffGainsStudy, context: RunContext) -> VffGainsResult:
    """Compute the ``vff_gains`` study (optimisations, comparison, sensitivity, trajectories).

    Parameters
    ----------
    study
        The validated study.
    context
        ``context.executor`` (if any) splits each population over its workers.
    """
    scen = [nav.configuration(i) for i in study.configurations]
    val = [nav.configuration(i) for i in study.validation if i not in study.configurations]
    opt_names = [s.name for s in scen]
    val_names = [s.name for s in val]
    ex = context.executor
    chunks = 2 if ex is not None else 1
    optima: dict[str, nav.GainOptimum] = {}
    rows = []
    for mode in study.modes:
        opt = nav.optimise_gains(
            scen,
            bounds=study.bounds.as_dict(),
            stabilising=mode,
            critical_margin=study.critical_margin,
            seed=study.seed,
            popsize=study.popsize,
            max_evaluations=study.max_evaluations,
            refine=study.refine,
            executor=ex,
            chunks=chunks,
            jit=study.jit,
        )
        optima[mode] = opt
        cand = [("experimental", EXPERIMENTAL), ("thesis_optimum", THESIS_OPTIMUM)]
        if opt.gains is not None:
            cand.append(("designlab_optimum", opt.gains))
        hit = opt.on_bounds()
        if study.bound_check and hit:
            wide = study.bounds.as_dict()
            for n, side in hit.items():
                lo, hi = wide[n]
                wide[n] = (lo / 10, hi) if side == "low" else (lo, hi * 10)
            opt_w = nav.optimise_gains(
                scen,
                bounds=wide,
                stabilising=mode,
                critical_margin=study.critical_margin,
                seed=study.seed,
                popsize=study.popsize,
                max_evaluations=study.max_evaluations,
                refine=study.refine,
                executor=ex,
                chunks=chunks,
                jit=study.jit,
            )
            optima[f"{mode}{WIDER}"] = opt_w
            if opt_w.gains is not None:
                cand.append(("designlab_optimum_wider_box", opt_w.gains))
        labels, gs = [c[0] for c in cand], [c[1] for c in cand]
        cm = study.critical_margin
        f_opt = nav.evaluate_gains(scen, gs, stabilising=mode, critical_margin=cm)
        f_val = nav.evaluate_gains(val, gs, stabilising=mode, critical_margin=cm) if val else None
        rows += _rows(labels, mode, gs, f_opt, f_val, opt_names, val_names)
    if study.robust is not None:
        rs = study.robust
        walks = nav.RandomWalks(
            n=rs.walks,
            speed=(rs.speed.low, rs.speed.high),
            start_time=(rs.start_time.low, rs.start_time.high),
            lateral_offset=(rs.lateral_offset.low, rs.lateral_offset.high),
            seed=study.seed,
        )
        opt = nav.optimise_gains(
            scen,
            bounds=study.bounds.as_dict(),
            stabilising=rs.stabilising,
            critical_margin=study.critical_margin,
            seed=study.seed,
            popsize=study.popsize,
            max_evaluations=study.max_evaluations,
            refine=study.refine,
            robust=walks,
            robust_mode=rs.mode,
            executor=ex,
            chunks=chunks,
            jit=study.jit,
        )
        optima["robust"] = opt
        cand = [("experimental", EXPERIMENTAL), ("thesis_optimum", THESIS_OPTIMUM)]
        if opt.gains is not None:
            cand.append(("designlab_robust_optimum", opt.gains))
        labels, gs = [c[0] for c in cand], [c[1] for c in cand]
        kw = dict(
            stabilising=rs.stabilising,
            robust=walks,
            robust_mode=rs.mode,
            critical_margin=study.critical_margin,
        )
        f_opt = nav.evaluate_gains(scen, gs, **kw)
        f_val = nav.evaluate_gains(val, gs, **kw) if val else None
        for r in _rows(labels, rs.stabilising, gs, f_opt, f_val, opt_names, val_names):
            r["robust"] = f"{rs.mode} over {rs.walks} walks"
            rows.append(r)
    comp = pd.DataFrame(rows)
    if "robust" not in comp:
        comp["robust"] = ""
    comp["robust"] = comp["robust"].fillna("")
    # improvement of ours over the references, per mode (and robust block)
    for _, grp in comp.groupby(["stabilising", "robust"], sort=False):
        ref = grp.set_index("gains")["H_mean"]
        for idx in grp.index:
            comp.loc[idx, "vs_experimental_pct"] = 100 * (
                comp.loc[idx, "H_mean"] / ref["experimental"] - 1
            )
            comp.loc[idx, "vs_thesis_optimum_pct"] = 100 * (
                comp.loc[idx, "H_mean"] / ref["thesis_optimum"] - 1
            )
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
    appc = pd.DataFrame()
    appc_out = pd.DataFrame()
    if "thesis_optimum_off" in sens and sorted(study.configurations) == [1, 2, 3]:
        appc = sens["thesis_optimum_off"].compare_appendix_c()
        appc_out = sens["thesis_optimum_off"].appendix_c_outcomes()
    runs: dict[tuple[str, str, int], nav.NavigationResult] = {}
    for mode in study.modes:
        opt = optima[mode]
        sets = [("thesis_optimum", THESIS_OPTIMUM)] + (
            [("designlab_optimum", opt.gains)] if opt.gains else []
        )
        for i in sorted(set(study.configurations) | set(study.validation)):
            for label, g in sets:
                runs[(mode, label, i)] = nav.simulate(nav.configuration(i), g, stabilising=mode)
    return VffGainsResult(study, optima, comp, sens, runs, glob, appc, appc_out)


KIND = StudyKind(
    name="vff_gains", schema=VffGainsStudy, run=run, report="designlab.report.vff_gains"
)
