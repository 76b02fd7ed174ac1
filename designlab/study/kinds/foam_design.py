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
... worst_case_samples: 0
... ''')
>>> result = run_study(study)
>>> result.verdicts()[["robot", "foam", "feasible"]]
           robot    foam  feasible
0  Manipulator 1  Foam 1      True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated, ClassVar, Literal

import numpy as np
import pandas as pd
from pydantic import Field, model_validator

from designlab.impact import (
    FoamEnvelope,
    HeadRange,
    OptimalFoam,
    SafeVelocity,
    WorstCaseCheck,
    check_worst_case,
    foam_envelope,
    max_safe_velocity,
    min_foam_thickness,
    optimal_foam,
)
from designlab.impact.criteria import (
    ISO_TS_15066_QUASI_STATIC_FORCE,
    Criterion,
    HeadAcceleration,
    HeadInjuryCriterion,
    ImpactForce,
    IsoTransientForce,
)
from designlab.impact.parameters import ContactDynamics, Foam
from designlab.results import OK, Result
from designlab.study.base import Model, StudyBase
from designlab.study.kinds.foam_envelope import DampingGrid
from designlab.study.kinds.impact_specs import FoamSpec, RobotSpec
from designlab.study.registry import StudyKind
from designlab.study.runner import RunContext

__all__ = ["KIND", "FoamDesignResult", "FoamDesignStudy", "run"]

_Pos = Annotated[float, Field(gt=0, allow_inf_nan=False)]


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
    """ISO/TS 15066 transient-contact force limit for a body region."""

    type: Literal["iso_ts_15066"]
    body_region: Literal[tuple(ISO_TS_15066_QUASI_STATIC_FORCE)] = "skull_forehead"  # type: ignore[valid-type]

    def build(self) -> Criterion:
        return IsoTransientForce(self.body_region)


CriterionSpec = Annotated[
    HeadAccelerationSpec | ImpactForceSpec | HicSpec | IsoSpec, Field(discriminator="type")
]


class HeadRangeSpec(Model):
    """Head-neck ranges ``[low, high]``: the envelope takes the worst case over them."""

    mass: tuple[_Pos, _Pos] = (4.4, 5.3)
    stiffness: tuple[float, float] = (3.0e3, 5.0e3)
    damping: tuple[float, float] = (46.0, 130.2)

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
    impact_velocity: Annotated[float, Field(gt=0, le=20, allow_inf_nan=False)] = Field(
        1.25, description="worst closing velocity v_c, m/s"
    )
    human_speed: Annotated[float, Field(ge=0, le=20, allow_inf_nan=False)] = Field(
        1.0, description="head speed toward the robot, m/s (for the safe manipulator speed)"
    )
    max_compression: _Pos = Field(0.02, description="lambda, linear depth of the foam, m")
    damping: DampingGrid = Field(default_factory=lambda: DampingGrid(low=0, high=200, num=41))
    head_range: HeadRangeSpec | None = Field(
        None, description="worst case over these ranges instead of the thesis's sets"
    )
    optimal: bool = Field(True, description="also find the foam with the best margin")
    worst_case_samples: Annotated[int, Field(ge=0, le=10000)] = Field(
        64, description="samples per boundary point of the worst-case check (0: skip)"
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
        """``"ok"``, or ``"empty"`` when some robot has no feasible foam at all."""
        return "empty" if any(d.envelope.is_empty for d in self.designs) else OK

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
        """One row per (robot, foam): feasibility, margin, safe speeds, thickness."""
        rows = []
        for d in self.designs:
            for foam, sv, th in zip(self.foams, d.safe, d.thickness, strict=True):
                margin = float(d.envelope.margin(foam.stiffness, foam.damping))
                rows.append(
                    {
                        "robot": d.label,
                        "foam": foam.name,
                        "K_c_N_per_m": foam.stiffness,
                        "C_c_N_s_per_m": foam.damping,
                        "feasible": bool(d.envelope.is_feasible(foam.stiffness, foam.damping)),
                        "margin_decades": margin,
                        "margin_percent": 100 * (10**margin - 1)
                        if math.isfinite(margin)
                        else margin,
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
        env = foam_envelope(
            robot,
            study.impact_velocity,
            damping,
            criteria,
            study.max_compression,
            head_range=head_range,
        )
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
            if study.worst_case_samples
            else None
        )
        designs.append(RobotDesign(robot, label, env, safe, thick, opt, check))
    return FoamDesignResult(study, foams, designs)


KIND = StudyKind(
    name="foam_design",
    schema=FoamDesignStudy,
    run=run,
    report="designlab.report.envelope",
)
