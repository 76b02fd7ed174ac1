"""The ``tether_snagging`` study kind: the corridor-corner study of Allan 2015 Sec. 4.5.

The follower of :func:`designlab.following.tether.snag.simulate_snag` runs the
corridor corner at every gap of a grid, without and with the snag compensation;
the report sets the first snagging gap, the collision limits, the fit (4.6) and
the detection points against the thesis's numbers (``docs/tether_modes.md``).

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> r = run_study(parse_study('''
... designlab: 1
... kind: tether_snagging
... name: demo
... gaps: {low: 1.0, high: 2.5, num: 4}
... detail_gaps: [2.5]
... '''))
>>> r.to_frame()["snagged"].tolist()
[False, False, True, True]
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np
import pandas as pd
from pydantic import Field, model_validator

from designlab.following.tether.snag import (
    SnagRun,
    SnagScenario,
    first_snag_gap,
    simulate_snag,
    snag_limits,
)
from designlab.following.tether.snag_geometry import constant_speed_limits
from designlab.params import params_of
from designlab.progress import Progress
from designlab.results import OK, Result
from designlab.study.base import Grid, Model, StudyBase
from designlab.study.registry import StudyKind
from designlab.study.reproduction import SAME_ON_A_GENERIC_CPU
from designlab.study.runner import RunContext
from designlab.study.specs import spec_model

__all__ = ["KIND", "GapGrid", "TetherSnaggingResult", "TetherSnaggingStudy", "run"]

_GAP = params_of(SnagScenario)["gap"]

#: Leader distance (m) around the wrap and release points counted as "near" them.
NEAR = 0.1
#: The detection features of eqs. 4.10-4.12 (columns of ``SnagRun.feature_rates``).
FEATURES = {
    "dtheta_ds_rad_per_m": "d theta / d s_L (4.10)",
    "dl_ds": "d L / d s_L (4.11)",
    "dbeta_ds_rad_per_m": "d beta_path / d s_L (4.12)",
}

#: The corridor and the follower (Table 4.1); the gap and the compensation are set per run.
SnagScenarioSpec = spec_model(SnagScenario, exclude=("gap", "compensate"))


_SC = params_of(SnagScenario)
#: The settings a cause run may change (each bounded as the scenario's field).
CAUSE_FIELDS = ("sample_time", "step", "approach", "exit", "winch_offset", "tether_height")
_O_SAMPLE_TIME = _SC["sample_time"].annotation(optional=True)
_O_STEP = _SC["step"].annotation(optional=True)
_O_APPROACH = _SC["approach"].annotation(optional=True)
_O_EXIT = _SC["exit"].annotation(optional=True)
_O_WINCH_OFFSET = _SC["winch_offset"].annotation(optional=True)
_O_TETHER_HEIGHT = _SC["tether_height"].annotation(optional=True)


class CauseRun(Model):
    """One candidate cause of a difference to the thesis: the scenario with these changes.

    The constant-speed follower's collision and wall limits are found by bisection on the
    gap (to ``CAUSE_TOLERANCE`` w) and set beside the closed form
    (:func:`designlab.following.tether.snag_geometry.constant_speed_limits`).
    """

    label: str = Field(min_length=1, max_length=80, description="what the run changes")
    sample_time: _O_SAMPLE_TIME = None  # type: ignore[valid-type]
    step: _O_STEP = None  # type: ignore[valid-type]
    approach: _O_APPROACH = None  # type: ignore[valid-type]
    exit: _O_EXIT = None  # type: ignore[valid-type]
    winch_offset: _O_WINCH_OFFSET = None  # type: ignore[valid-type]
    tether_height: _O_TETHER_HEIGHT = None  # type: ignore[valid-type]

    def changes(self) -> dict[str, float]:
        """The scenario fields this run sets."""
        return {k: getattr(self, k) for k in CAUSE_FIELDS if getattr(self, k) is not None}


#: Bisection tolerance of the cause runs' limits (over w).
CAUSE_TOLERANCE = 2e-4


class GapGrid(Grid):
    """Evenly spaced gaps: ``num`` of them from ``low`` to ``high`` (m)."""

    low: _GAP.annotation() = 1.0  # type: ignore[valid-type]
    high: _GAP.annotation() = 3.0  # type: ignore[valid-type]
    num: int = Field(41, ge=2, le=400, description="number of gaps")


class TetherSnaggingStudy(StudyBase):
    """Tether snagging on a corridor corner over a range of following gaps (Sec. 4.5)."""

    kind: Literal["tether_snagging"]
    scenario: SnagScenarioSpec = Field(default_factory=SnagScenarioSpec)  # type: ignore[valid-type]
    gaps: GapGrid = Field(default_factory=GapGrid)
    detail_gaps: list[_GAP.annotation()] = Field(  # type: ignore[valid-type]
        default_factory=lambda: [2.0, 2.5, 5.0],
        max_length=6,
        description="gaps shown in the figures and the detection table (the thesis: 5 m)",
    )

    compare_followers: list[Literal["constant_speed", "gap"]] = Field(
        default_factory=lambda: ["gap"],
        max_length=2,
        description=(
            "other followers run over the same gaps (without the compensation) for the "
            "comparison with the thesis: 'gap' is the project's gap-keeping robot"
        ),
    )

    causes: list[CauseRun] = Field(
        default_factory=list,
        max_length=12,
        description="candidate causes of the difference to the thesis's limits: the "
        "constant-speed follower's limits with each change (causes.csv)",
    )
    fit_causes: list[str] = Field(
        default_factory=list,
        max_length=4,
        description="labels of cause runs whose constant-speed follower is also run over "
        "the grid gaps, for the fit (4.6) over each set of fitted gaps (fits.csv)",
    )

    @model_validator(mode="after")
    def _known_fit_causes(self) -> TetherSnaggingStudy:
        labels = [c.label for c in self.causes]
        for label in self.fit_causes:
            if label not in labels:
                raise ValueError(
                    f"fit_causes: {label!r} is not the label of a cause run; causes: {labels}"
                )
        return self

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "snagging.csv",
        "limits.csv",
        "causes.csv",
        "fits.csv",
        "features.csv",
        "snagging_*.png",
        "study.yaml",
    )
    TYPICAL_DURATION: ClassVar[float] = 27  # s, the committed study, serial, this machine

    def size(self) -> str:
        """Runs."""
        n = self.gaps.num + len(self.detail_gaps)
        fits = len(self.fit_causes) * self.gaps.num
        return f"{(2 + len(self.compare_followers)) * n + fits} runs"


@dataclass(frozen=True)
class TetherSnaggingResult(Result):
    """Results of a ``tether_snagging`` study.

    Attributes
    ----------
    study
        The study.
    plain, compensated
        Runs at every grid gap without and with the compensation.
    detail, detail_compensated
        Runs at the detail gaps.
    others
        Per follower of ``compare_followers``: its runs at the grid gaps, then at the detail
        gaps (without the compensation).
    causes
        One row per cause run (``causes.csv``): its changes, the constant-speed follower's
        collision and wall limits found by bisection (``*_gap_over_w``) and in closed form
        (``*_closed_form``), the first snag in closed form, all over w; and the string's
        wrapped span along the recorded path at the largest detail gap (``span_recorded_m``).
    cause_grids
        Per label of ``fit_causes``: the constant-speed follower's runs at the grid gaps with
        that cause's changes (without the compensation), fitted in ``fits.csv``.
    """

    study: TetherSnaggingStudy
    plain: tuple[SnagRun, ...]
    compensated: tuple[SnagRun, ...]
    detail: tuple[SnagRun, ...]
    detail_compensated: tuple[SnagRun, ...]
    others: dict[str, tuple[SnagRun, ...]] = dataclasses.field(default_factory=dict)
    causes: pd.DataFrame = dataclasses.field(default_factory=pd.DataFrame, repr=False)
    cause_grids: dict[str, tuple[SnagRun, ...]] = dataclasses.field(default_factory=dict)

    status: ClassVar[str] = OK

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        return tuple(
            f"compensated, gap {r.scenario.gap:g} m: {w}"
            for r in (*self.compensated, *self.detail_compensated)
            for w in r.warnings
        )

    def to_frame(self) -> pd.DataFrame:
        """One row per grid gap: snag span, d_col and status, without and with compensation."""
        rows = []
        for r, c in zip(self.plain, self.compensated, strict=True):
            span = r.snag_span or (np.nan, np.nan)
            rows.append(
                {
                    "gap_m": r.scenario.gap,
                    "gap_over_w": r.scenario.gap / r.scenario.width,
                    "snagged": bool(r.snagged.any()),
                    "snag_start_s_leader_m": span[0],
                    "snag_end_s_leader_m": span[1],
                    "d_col_over_w": r.d_col,
                    "status": str(r.status),
                    "detections_s_leader_m": " ".join(f"{d:.3f}" for d in r.detections),
                    "compensated_d_col_over_w": c.d_col,
                    "compensated_status": str(c.status),
                }
            )
        return pd.DataFrame(rows)

    def feature_prominence(self) -> pd.DataFrame:
        """Per detail gap and feature (4.10-4.12): its largest |rate| within ``NEAR`` m (leader
        distance) of where the string wraps or frees, against its largest |rate| elsewhere."""
        rows = []
        for r in self.detail:
            if r.snag_span is None:
                continue
            f = r.feature_rates().dropna()
            s = f["s_leader_m"].to_numpy()
            near = (np.abs(s - r.snag_span[0]) < NEAR) | (np.abs(s - r.snag_span[1]) < NEAR)
            for col, name in FEATURES.items():
                v = f[col].abs().to_numpy()
                top, rest = float(v[near].max()), float(v[~near].max())
                rows.append({"gap_m": r.scenario.gap, "feature": name, "near_max": top,
                             "elsewhere_max": rest, "ratio": top / rest})  # fmt: skip
        return pd.DataFrame(rows)

    @property
    def follower(self) -> str:
        """The follower of the main runs (the scenario's)."""
        return str(self.study.scenario.build().follower)

    def runs_of(self, follower: str) -> tuple[tuple[SnagRun, ...], tuple[SnagRun, ...]]:
        """The grid runs and the detail runs of a follower (without the compensation)."""
        if follower == self.follower:
            return self.plain, self.detail
        if follower not in self.others:
            raise KeyError(f"follower {follower!r} was not run; run: {self.followers}")
        runs, n = self.others[follower], self.study.gaps.num
        return runs[:n], runs[n:]

    @property
    def followers(self) -> tuple[str, ...]:
        """The main follower, then the compared ones."""
        return (self.follower, *(f for f in self.others if f != self.follower))

    def limits(self, follower: str | None = None) -> dict[str, float]:
        """First snagging gap, collision limits and the fit (4.6), all over w."""
        grid, detail = self.runs_of(follower or self.follower)
        f = _frame(grid)
        sc = self.study.scenario.build()
        w, rcol = sc.width, sc.collision_radius / sc.width
        snag = f[f["snagged"]]
        inside = snag[snag["d_col_over_w"] >= 0.0]
        out: dict[str, float] = {
            "first_snag_gap_over_w": float(snag["gap_over_w"].min()) if len(snag) else np.nan,
            "geometric_snag_gap_over_w": first_snag_gap(w) / w,
            "collision_gap_over_w": _crossing(f, rcol),
            "wall_gap_over_w": _crossing(f, 0.0),
            "r_col_over_w": rcol,
        }
        if len(inside) >= 3:
            out.update({f"fit_{k}": v for k, v in snag_limits(
                inside["d_col_over_w"].to_numpy(), inside["gap_over_w"].to_numpy(), rcol
            ).items()})  # fmt: skip
        spans = [(r.scenario.gap, r.snag_span_recorded) for r in detail if r.snag_span]
        if spans:
            gap, (a, b) = max(spans, key=lambda s: s[0])  # type: ignore[misc]
            out.update({"span_gap_m": gap, "span_recorded_m": b - a})
        return out

    def limits_frame(self) -> pd.DataFrame:
        """:meth:`limits` of every follower run, one row each (``limits.csv``)."""
        return pd.DataFrame([{"follower": f, **self.limits(f)} for f in self.followers])


def _frame(runs: tuple[SnagRun, ...]) -> pd.DataFrame:
    return pd.DataFrame(
        [
            {
                "gap_over_w": r.scenario.gap / r.scenario.width,
                "snagged": bool(r.snagged.any()),
                "d_col_over_w": r.d_col,
            }
            for r in runs
        ]
    )


def _crossing(frame: pd.DataFrame, level: float) -> float:
    """The gap (/w) at which d_col first falls below ``level`` (linear interpolation)."""
    g, d = frame["gap_over_w"].to_numpy(), frame["d_col_over_w"].to_numpy()
    below = np.flatnonzero(d < level)
    if len(below) == 0 or below[0] == 0:
        return float("nan")
    i = below[0]
    return float(g[i - 1] + (level - d[i - 1]) * (g[i] - g[i - 1]) / (d[i] - d[i - 1]))


def run(study: TetherSnaggingStudy, context: RunContext) -> TetherSnaggingResult:
    """Run every gap without and with the compensation.

    Parameters
    ----------
    study, context
        The study, and how to run it (its progress bar: one step a gap).
    """
    base = study.scenario.build()
    jobs: list[Any] = [*study.gaps.values(), *study.detail_gaps]
    plain, comp = [], []
    with context.bar(f"{study.kind}: gaps", total=len(jobs)) as hook:
        for i, g in enumerate(jobs):
            sc = dataclasses.replace(base, gap=float(g))
            plain.append(simulate_snag(sc))
            comp.append(simulate_snag(dataclasses.replace(sc, compensate=True)))
            hook(Progress(i + 1, len(jobs), label="gap", note=f"{g:g} m"))
    others = {}
    for follower in dict.fromkeys(study.compare_followers):
        if follower == base.follower:
            continue
        with context.bar(f"{study.kind}: {follower} follower", total=len(jobs)) as hook:
            runs = []
            for i, g in enumerate(jobs):
                runs.append(simulate_snag(dataclasses.replace(base, gap=float(g),
                                                              follower=follower)))  # fmt: skip
                hook(Progress(i + 1, len(jobs), label="gap", note=f"{g:g} m"))
        others[follower] = tuple(runs)
    n = study.gaps.num
    return TetherSnaggingResult(
        study, tuple(plain[:n]), tuple(comp[:n]), tuple(plain[n:]), tuple(comp[n:]), others,
        _causes(study, context), _cause_grids(study, context),
    )  # fmt: skip


def _bisect(sc: SnagScenario, level: float, lo: float, hi: float) -> float:
    """The gap (/w) at which the run's d_col falls to ``level`` (d_col decreases with it)."""
    w = sc.width

    def d_col(g: float) -> float:
        return simulate_snag(dataclasses.replace(sc, gap=g * w)).d_col

    if d_col(lo) < level or d_col(hi) >= level:
        return float("nan")
    while hi - lo > CAUSE_TOLERANCE:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if d_col(mid) >= level else (lo, mid)
    return 0.5 * (lo + hi)


def _span(sc: SnagScenario, study: TetherSnaggingStudy) -> dict[str, float]:
    """The string's wrapped span along the recorded path at the largest detail gap (m)."""
    if not study.detail_gaps:
        return {}
    gap = max(study.detail_gaps)
    span = simulate_snag(dataclasses.replace(sc, gap=gap)).snag_span_recorded
    return {"span_gap_m": gap, "span_recorded_m": np.nan if span is None else span[1] - span[0]}


def _causes(study: TetherSnaggingStudy, context: RunContext) -> pd.DataFrame:
    """The constant-speed follower's limits under each candidate cause (causes.csv)."""
    base = dataclasses.replace(study.scenario.build(), follower="constant_speed")
    rows = []
    with context.bar(f"{study.kind}: causes", total=len(study.causes)) as hook:
        for i, cause in enumerate(study.causes):
            sc = dataclasses.replace(base, **cause.changes())
            w, rcol = sc.width, sc.collision_radius / sc.width
            exact = constant_speed_limits(rcol, sc.winch_offset / w, sc.tether_height / w)
            lo = exact["first_snag"] + 0.05
            rows.append({"cause": cause.label, "sample_time_s": sc.sample_time,
                         "step_m": sc.step, "approach_m": sc.approach, "exit_m": sc.exit,
                         "winch_offset_over_w": sc.winch_offset / w,
                         "tether_height_over_w": sc.tether_height / w,
                         "first_snag_closed_form": exact["first_snag"],
                         "collision_gap_over_w": _bisect(sc, rcol, lo, lo + 1.5),
                         "collision_closed_form": exact["collision"],
                         "wall_gap_over_w": _bisect(sc, 0.0, lo, lo + 1.5),
                         "wall_closed_form": exact["wall"], **_span(sc, study)})  # fmt: skip
            hook(Progress(i + 1, len(study.causes), label="cause", note=cause.label))
    return pd.DataFrame(rows)


def _cause_grids(study: TetherSnaggingStudy, context: RunContext) -> dict[str, tuple[SnagRun, ...]]:
    """The constant-speed follower over the grid gaps under each cause of ``fit_causes``."""
    base = dataclasses.replace(study.scenario.build(), follower="constant_speed")
    causes = {c.label: c for c in study.causes}
    out = {}
    for label in study.fit_causes:
        sc = dataclasses.replace(base, **causes[label].changes())
        gaps = study.gaps.values()
        with context.bar(f"{study.kind}: fit, {label}", total=len(gaps)) as hook:
            runs = []
            for i, g in enumerate(gaps):
                runs.append(simulate_snag(dataclasses.replace(sc, gap=float(g))))
                hook(Progress(i + 1, len(gaps), label="gap", note=f"{g:g} m"))
        out[label] = tuple(runs)
    return out


KIND = StudyKind(
    name="tether_snagging",
    schema=TetherSnaggingStudy,
    run=run,
    report="designlab.report.tether_snagging",
    reproduction=SAME_ON_A_GENERIC_CPU,
)
