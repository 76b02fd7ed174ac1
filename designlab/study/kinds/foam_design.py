"""The ``foam_design`` study kind: the foam covering design report (Zeng 2011, Sec. 3.9).

For every robot of the study it computes the feasible foam region
(:func:`designlab.impact.foam_envelope`), the verdict and margin of every foam,
the largest safe speed and the thickness each foam needs, the optimal foam
(:func:`designlab.impact.optimal_foam`) and a sampled worst-case check.

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: foam_design
... name: demo
... robots: [MANIPULATOR_1]
... foams: [FOAM_1]
... damping: {low: 20, high: 100, num: 5}
... optimal: false
... worst_case_check: false
... ''')
>>> result = run_study(study)
>>> result.verdicts()[["robot", "foam", "verdict"]]
           robot    foam   verdict
0  Manipulator 1  Foam 1  feasible
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from typing import Annotated, ClassVar, Literal

import numpy as np
import pandas as pd
from pydantic import Field, model_validator

from designlab.impact import (
    FoamEnvelope,
    FoamVerdict,
    HeadRange,
    OptimalFoam,
    SafeVelocity,
    WorstCaseCheck,
    check_worst_case,
    foam_envelope,
    foam_verdict,
    max_safe_velocity,
    min_foam_thickness,
    optimal_foam,
)
from designlab.impact.criteria import (
    ISO_TS_15066_QUASI_STATIC_FORCE,
    ISO_TS_15066_TRANSIENT_FACTOR,
    Criterion,
    HeadAcceleration,
    HeadInjuryCriterion,
    ImpactForce,
    IsoQuasiStaticForce,
    IsoTransientForce,
)
from designlab.impact.parameters import ContactDynamics, Foam
from designlab.results import OK, Result
from designlab.study.base import Flag, Integer, Model, Number, StudyBase
from designlab.study.kinds.foam_envelope import DampingGrid
from designlab.study.kinds.impact_specs import FoamSpec, RobotSpec
from designlab.study.registry import StudyKind
from designlab.study.runner import RunContext

__all__ = ["KIND", "FoamDesignResult", "FoamDesignStudy", "run"]

log = logging.getLogger(__name__)

_Pos = Annotated[Number, Field(gt=0, allow_inf_nan=False)]


class HeadAccelerationSpec(Model):
    """a_h,max <= ``max_g`` (thesis: 10 g); conservative head set: minimum."""

    type: Literal["head_acceleration"]
    max_g: _Pos = 10.0

    def build(self) -> Criterion:
        return HeadAcceleration(max_g=self.max_g)


class ImpactForceSpec(Model):
    """Peak contact force <= ``max_force`` N; conservative head set: maximum."""

    type: Literal["force"]
    max_force: _Pos = 660.0

    def build(self) -> Criterion:
        return ImpactForce(max_force=self.max_force)


class HicSpec(Model):
    """HIC over the first lobe <= ``max_hic`` with window 0.015 s or 0.036 s."""

    type: Literal["hic"]
    max_hic: _Pos = 650.0
    window: Literal[0.015, 0.036] = 0.015

    def build(self) -> Criterion:
        return HeadInjuryCriterion(max_hic=self.max_hic, window=self.window)


class IsoSpec(Model):
    """ISO/TS 15066 force limit of a body region (Annex A, Table A.2).

    ``contact: quasi_static`` (default) uses the table's maximum permissible
    force; ``transient`` multiplies it by the table's transient factor, which
    the table does not give for the head regions: there ``transient_factor``
    must be stated (docs/impact.md, "Safety criteria").
    """

    type: Literal["iso_ts_15066"]
    body_region: Literal[tuple(ISO_TS_15066_QUASI_STATIC_FORCE)] = "skull_forehead"  # type: ignore[valid-type]
    contact: Literal["quasi_static", "transient"] = "quasi_static"
    transient_factor: _Pos | None = Field(
        None, description="multiplier of the quasi-static value for transient contact"
    )

    @model_validator(mode="after")
    def _factor_only_for_transient(self) -> IsoSpec:
        if self.transient_factor is not None and self.contact != "transient":
            raise ValueError("transient_factor applies only to contact: transient")
        if (
            self.contact == "transient"
            and self.transient_factor is None
            and self.body_region not in ISO_TS_15066_TRANSIENT_FACTOR
        ):
            raise ValueError(
                f"ISO/TS 15066 Table A.2 gives no transient-contact multiplier for "
                f"{self.body_region!r}: state transient_factor or use contact: quasi_static"
            )
        return self

    def build(self) -> Criterion:
        if self.contact == "quasi_static":
            return IsoQuasiStaticForce(self.body_region)
        return IsoTransientForce(self.body_region, transient_factor=self.transient_factor)


CriterionSpec = Annotated[
    HeadAccelerationSpec | ImpactForceSpec | HicSpec | IsoSpec, Field(discriminator="type")
]


class HeadRangeSpec(Model):
    """Head-neck ranges ``[low, high]``: the envelope takes the worst case over them."""

    mass: tuple[_Pos, _Pos] = (4.4, 5.3)
    stiffness: tuple[Number, Number] = (3.0e3, 5.0e3)
    damping: tuple[Number, Number] = (46.0, 130.2)

    def build(self) -> HeadRange:
        return HeadRange(self.mass, self.stiffness, self.damping)


class FoamDesignStudy(StudyBase):
    """Feasible foam region, foam verdicts, safe speed and optimal foam for each robot."""

    kind: Literal["foam_design"]
    robots: list[RobotSpec] = Field(min_length=1, description="effective manipulators")
    foams: list[FoamSpec] = Field(default_factory=list, description="foams to check")
    criteria: list[CriterionSpec] = Field(  # type: ignore[valid-type]
        default_factory=lambda: [HeadAccelerationSpec(type="head_acceleration", max_g=10.0)],
        min_length=1,
        description="safety criteria of the upper boundary",
    )
    impact_velocity: Annotated[Number, Field(gt=0, le=20, allow_inf_nan=False)] = Field(
        1.25, description="worst closing velocity v_c, m/s"
    )
    human_speed: Annotated[Number, Field(ge=0, le=20, allow_inf_nan=False)] = Field(
        1.0, description="head speed toward the robot, m/s (for the safe manipulator speed)"
    )
    max_compression: _Pos = Field(0.02, description="lambda, linear depth of the foam, m")
    damping: DampingGrid = Field(default_factory=lambda: DampingGrid(low=0, high=200, num=41))
    head_range: HeadRangeSpec | None = Field(
        None, description="worst case over these ranges instead of the thesis's sets"
    )
    optimal: Flag = Field(True, description="also find the foam with the best margin")
    worst_case_samples: Annotated[Integer, Field(ge=0, le=10000)] = Field(
        64,
        description="random samples per boundary point of the worst-case check, after its "
        "deterministic corners (0: corners only)",
    )
    worst_case_check: Flag = Field(True, description="check the envelope's worst case")
    verdict_tolerance: Annotated[Number, Field(ge=0, lt=0.5, allow_inf_nan=False)] = Field(
        0.01, description="relative distance in K_c within which a foam is on the boundary"
    )

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "envelope.md",
        "envelope.csv",
        "envelope.png",
        "study.yaml",
    )

    @model_validator(mode="after")
    def _distinct(self) -> FoamDesignStudy:
        names = [r.build().name or f"robot {i + 1}" for i, r in enumerate(self.robots)]
        if len(set(names)) != len(names):
            raise ValueError(
                "robots must be distinct (give each explicit robot a different preset)"
            )
        return self


@dataclass(frozen=True)
class RobotDesign:
    """Everything the study computed for one robot."""

    robot: ContactDynamics
    label: str
    envelope: FoamEnvelope
    verdicts: list[FoamVerdict]
    safe: list[SafeVelocity]
    thickness: list[float]
    optimal: OptimalFoam | None
    check: WorstCaseCheck | None


@dataclass(frozen=True)
class FoamDesignResult(Result):
    """Result of a ``foam_design`` study.

    Attributes
    ----------
    study
        The study.
    foams
        The candidate foams, in the study's order.
    designs
        One design (envelope, optimum, worst-case check) per robot.
    """

    study: FoamDesignStudy
    foams: list[Foam]
    designs: list[RobotDesign]

    @property
    def status(self) -> str:
        """``"ok"``; ``"empty"`` when some robot has no feasible foam at all;
        ``"worst_case_violated"`` when a worst-case check found a case beyond a limit."""
        if any(d.envelope.is_empty for d in self.designs):
            return "empty"
        if any(d.check is not None and not d.check.holds for d in self.designs):
            return "worst_case_violated"
        return OK

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """The warnings of every envelope, optimisation and worst-case check, by robot."""
        out: list[str] = []
        for d in self.designs:
            for part in (d.envelope, d.optimal, d.check):
                out.extend(f"{d.label}: {w}" for w in (getattr(part, "warnings", None) or ()))
        return tuple(dict.fromkeys(out))

    def envelope_frame(self) -> pd.DataFrame:
        """All boundaries, one row per (robot, damping)."""
        frames = []
        for d in self.designs:
            df = d.envelope.to_frame()
            df.insert(0, "robot", d.label)
            frames.append(df)
        return pd.concat(frames, ignore_index=True)

    def verdicts(self) -> pd.DataFrame:
        """One row per (robot, foam): verdict, distances to the boundaries, safe speeds,
        thickness (all computed by :func:`run`; nothing is solved here)."""
        rows = []
        for d in self.designs:
            for foam, fv, sv, th in zip(self.foams, d.verdicts, d.safe, d.thickness, strict=True):
                margin = fv.margin_decades
                rows.append(
                    {
                        "robot": d.label,
                        "foam": foam.name,
                        "K_c_N_per_m": foam.stiffness,
                        "C_c_N_s_per_m": foam.damping,
                        "verdict": fv.verdict,
                        "feasible": fv.feasible,
                        "statement": fv.statement,
                        "K_c_max_N_per_m": fv.stiffness_max,
                        "K_c_min_N_per_m": fv.stiffness_min,
                        "upper_excess_percent": 100 * fv.upper_excess,
                        "lower_deficit_percent": 100 * fv.lower_deficit,
                        "margin_decades": margin,
                        "v_c_max_m_per_s": sv.impact_velocity,
                        "v_r_max_m_per_s": sv.manipulator_speed,
                        "limiting": sv.limiting,
                        "lambda_needed_m": th,
                    }
                )
        return pd.DataFrame(rows)

    def to_frame(self) -> pd.DataFrame:
        """The foam verdicts (:meth:`verdicts`)."""
        return self.verdicts()


def run(study: FoamDesignStudy, context: RunContext) -> FoamDesignResult:
    """Compute the ``foam_design`` study (in this process; nothing is stored).

    Parameters
    ----------
    study
        The validated study.
    context
        How to run it (nothing of this kind is stored).
    """
    criteria = [c.build() for c in study.criteria]
    foams = []
    for i, spec in enumerate(study.foams):
        f = spec.build()
        foams.append(f if f.name else f.replace(name=f"foam {i + 1}"))
    head_range = study.head_range.build() if study.head_range else None
    damping = np.asarray(study.damping.values())
    designs = []
    for i, spec in enumerate(study.robots):
        robot = spec.build()
        label = robot.name or f"robot {i + 1}"
        t0 = time.perf_counter()
        log.info(
            "%s: %s: envelope over %d damping values, %d criteria, %d foams",
            study.name, label, damping.size, len(criteria), len(foams),
        )  # fmt: skip
        env = foam_envelope(
            robot,
            study.impact_velocity,
            damping,
            criteria,
            study.max_compression,
            head_range=head_range,
        )
        verdicts = [foam_verdict(env, f, tolerance=study.verdict_tolerance) for f in foams]
        safe = [
            max_safe_velocity(
                robot,
                f,
                criteria,
                max_compression=study.max_compression,
                human_speed=study.human_speed,
                head_range=head_range,
            )
            for f in foams
        ]
        thick = [
            min_foam_thickness(robot, f, study.impact_velocity, head_range=head_range).linear_depth
            for f in foams
        ]
        opt = (
            optimal_foam(
                robot,
                study.impact_velocity,
                criteria,
                study.max_compression,
                damping_bounds=(float(damping.min()), float(damping.max())),
                head_range=head_range,
            )
            if study.optimal
            else None
        )
        check = (
            check_worst_case(env, head_range or HeadRange(), samples=study.worst_case_samples)
            if study.worst_case_check
            else None
        )
        for f, v in zip(foams, verdicts, strict=True):
            log.info("%s: %s: %s: %s (%s)", study.name, label, f.name, v.verdict, v.statement)
        if opt is not None:
            log.info("%s: %s: optimal foam: status %s", study.name, label, opt.status)
        if check is not None:
            log.info(
                "%s: %s: worst-case check (8 corners + %d samples per point): %s",
                study.name, label, study.worst_case_samples, check.status,
            )  # fmt: skip
        for w in env.warnings:
            log.info("%s: %s: envelope: %s", study.name, label, w)
        log.info("%s: %s: done in %.1f s", study.name, label, time.perf_counter() - t0)
        designs.append(RobotDesign(robot, label, env, verdicts, safe, thick, opt, check))
    return FoamDesignResult(study, foams, designs)


KIND = StudyKind(
    name="foam_design",
    schema=FoamDesignStudy,
    run=run,
    report="designlab.report.envelope",
)
