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
from dataclasses import dataclass, replace
from typing import Annotated, Any, ClassVar, Literal

import numpy as np
import pandas as pd
from pydantic import Field, create_model, model_validator

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
    Criterion,
    HeadAcceleration,
    HeadInjuryCriterion,
    ImpactForce,
    IsoQuasiStaticForce,
    IsoTransientForce,
)
from designlab.impact.parameters import (
    HUMAN_SPEED,
    IMPACT_VELOCITY,
    MAX_COMPRESSION,
    VERDICT_TOLERANCE,
    WORST_CASE_SAMPLES,
    ContactDynamics,
    Foam,
    HeadNeck,
)
from designlab.params import params_of
from designlab.progress import Progress
from designlab.results import OK, Result
from designlab.study.base import Flag, Model, StudyBase
from designlab.study.kinds.impact_specs import DampingGrid, FoamSpec, RobotSpec
from designlab.study.registry import StudyKind
from designlab.study.reproduction import ENVELOPE
from designlab.study.runner import RunContext
from designlab.study.specs import spec_model

__all__ = ["KIND", "FoamDesignResult", "FoamDesignStudy", "run"]

log = logging.getLogger(__name__)

# the YAML fields are the domain's declarations (designlab.params)
_HEAD = params_of(HeadNeck)
_WorstVelocity = replace(IMPACT_VELOCITY, doc="worst closing velocity").annotation()
_HumanSpeed = HUMAN_SPEED.annotation()
_MaxCompression = MAX_COMPRESSION.annotation()
_WorstCaseSamples = WORST_CASE_SAMPLES.annotation()
_VerdictTolerance = VERDICT_TOLERANCE.annotation()


def _criterion_spec(cls: type, kind: str, doc: str, exclude: tuple[str, ...] = ()) -> Any:
    """The YAML model of a criterion: its declared fields and the ``type`` discriminator."""
    fields = spec_model(cls, name=f"_{cls.__name__}Fields", exclude=exclude)

    def build(self: Any) -> Criterion:
        return cls(**self.model_dump(exclude={"type"}))  # type: ignore[no-any-return]

    model = create_model(  # type: ignore[call-overload]
        f"{cls.__name__}Spec", __base__=fields, __doc__=doc, type=(Literal[kind], ...)
    )
    model.build = build
    return model


HeadAccelerationSpec = _criterion_spec(
    HeadAcceleration,
    "head_acceleration",
    "a_h,max <= ``max_g`` (thesis: 10 g); conservative head set: minimum.",
)
ImpactForceSpec = _criterion_spec(
    ImpactForce, "force", "Peak contact force <= ``max_force`` N; conservative head set: maximum."
)
HicSpec = _criterion_spec(
    HeadInjuryCriterion,
    "hic",
    "HIC over the first lobe <= ``max_hic`` with window 0.015 s (HIC15) or 0.036 s (HIC36).",
    exclude=("samples",),
)


class _IsoBuild(Model):
    """What the ISO/TS 15066 spec does: check the contact and build the criterion."""

    @model_validator(mode="after")
    def _factor_only_for_transient(self) -> Any:
        given = self.model_dump()
        if given["transient_factor"] is not None and given["contact"] != "transient":
            raise ValueError("transient_factor applies only to contact: transient")
        self.build()  # the domain's own rules (no multiplier for the head regions)
        return self

    def build(self) -> Criterion:
        """The criterion (validated by its constructor)."""
        given = self.model_dump(exclude={"type"})
        if given.pop("contact") == "quasi_static":
            return IsoQuasiStaticForce(given["body_region"])
        return IsoTransientForce(**given)


_QUASI_STATIC = params_of(IsoQuasiStaticForce)
_TRANSIENT = params_of(IsoTransientForce)

#: ISO/TS 15066 force limit of a body region (Annex A, Table A.2): the fields of
#: :class:`~designlab.impact.criteria.IsoQuasiStaticForce` (``contact: quasi_static``,
#: the default) and of :class:`~designlab.impact.criteria.IsoTransientForce`.
IsoSpec = create_model(  # type: ignore[call-overload]
    "IsoSpec",
    __base__=_IsoBuild,
    __doc__="""ISO/TS 15066 force limit of a body region (Annex A, Table A.2).

    ``contact: quasi_static`` (default) uses the table's maximum permissible
    force; ``transient`` multiplies it by the table's transient factor, which
    the table does not give for the head regions: there ``transient_factor``
    must be stated (docs/impact.md, "Safety criteria").
    """,
    type=(Literal["iso_ts_15066"], ...),
    body_region=(_QUASI_STATIC["body_region"].annotation(), _QUASI_STATIC["body_region"].default),
    contact=(Literal["quasi_static", "transient"], "quasi_static"),
    transient_factor=(
        _TRANSIENT["transient_factor"].annotation(),
        _TRANSIENT["transient_factor"].default,
    ),
)


CriterionSpec = Annotated[
    HeadAccelerationSpec | ImpactForceSpec | HicSpec | IsoSpec,  # type: ignore[operator]
    Field(discriminator="type"),
]


class _HeadRangeBuild(Model):
    """What the head-neck range spec does: build (and so check) the range."""

    @model_validator(mode="after")
    def _ordered(self) -> Any:
        self.build()
        return self

    def build(self) -> HeadRange:
        """The :class:`~designlab.impact.HeadRange` (validated by its constructor)."""
        return HeadRange(**self.model_dump())


def _range_field(name: str, decl: Any) -> tuple[Any, Any]:
    """``[low, high]`` of the :class:`~designlab.impact.HeadNeck` parameter ``name``."""
    end = _HEAD[name].annotation()
    return (tuple[end, end], decl.default)  # type: ignore[valid-type]


#: Head-neck ranges ``[low, high]``: the fields of :class:`~designlab.impact.HeadRange`,
#: each end a value of the :class:`~designlab.impact.HeadNeck` parameter.
HeadRangeSpec = create_model(  # type: ignore[call-overload]
    "HeadRangeSpec",
    __base__=_HeadRangeBuild,
    __doc__="""Head-neck ranges ``[low, high]``: the envelope takes the worst case over them.

    Each end is a value of the :class:`~designlab.impact.HeadNeck` parameter
    (its unit and allowed range); ``low <= high``.
    """,
    **{n: _range_field(n, d) for n, d in params_of(HeadRange).items()},
)


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
    impact_velocity: _WorstVelocity = 1.25
    human_speed: _HumanSpeed = 1.0
    max_compression: _MaxCompression = 0.02
    damping: DampingGrid = Field(default_factory=lambda: DampingGrid(low=0, high=200, num=41))
    head_range: HeadRangeSpec | None = Field(  # type: ignore[valid-type]
        None, description="worst case over these ranges instead of the thesis's sets"
    )
    optimal: Flag = Field(True, description="also find the foam with the best margin")
    worst_case_samples: _WorstCaseSamples = 64
    worst_case_check: Flag = Field(True, description="check the envelope's worst case")
    verdict_tolerance: _VerdictTolerance = 0.01

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "envelope.md",
        "envelope.csv",
        "envelope.png",
        "study.yaml",
    )
    #: s: CPU time of studies/foam_design.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 8

    @model_validator(mode="after")
    def _distinct(self) -> FoamDesignStudy:
        names = [r.build().name or f"robot {i + 1}" for i, r in enumerate(self.robots)]
        if len(set(names)) != len(names):
            raise ValueError(
                "robots must be distinct (give each explicit robot a different preset)"
            )
        for spec in self.foams:  # what run builds, validate builds (the domain's rules)
            spec.build()
        return self

    def size(self) -> str:
        """Robots x damping values.

        Returns
        -------
        str
        """
        return f"{len(self.robots)} robot(s) x {self.damping.num} damping values"


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


def _robot_design(
    study: FoamDesignStudy,
    robot: ContactDynamics,
    label: str,
    criteria: list[Criterion],
    foams: list[Foam],
    head_range: HeadRange | None,
) -> RobotDesign:
    """Envelope, verdicts, safe speeds, thicknesses, optimum and worst-case check of one robot."""
    damping = np.asarray(study.damping.values())
    env = foam_envelope(
        robot, study.impact_velocity, damping, criteria, study.max_compression,
        head_range=head_range,
    )  # fmt: skip
    verdicts = [foam_verdict(env, f, tolerance=study.verdict_tolerance) for f in foams]
    safe = [
        max_safe_velocity(robot, f, criteria, max_compression=study.max_compression,
                          human_speed=study.human_speed, head_range=head_range)
        for f in foams
    ]  # fmt: skip
    thick = [
        min_foam_thickness(robot, f, study.impact_velocity, head_range=head_range).linear_depth
        for f in foams
    ]
    opt = (
        optimal_foam(
            robot, study.impact_velocity, criteria, study.max_compression,
            damping_bounds=(float(damping.min()), float(damping.max())), head_range=head_range,
        )
        if study.optimal
        else None
    )  # fmt: skip
    check = (
        check_worst_case(env, head_range or HeadRange(), samples=study.worst_case_samples)
        if study.worst_case_check
        else None
    )
    return RobotDesign(robot, label, env, verdicts, safe, thick, opt, check)


def _log_design(study: FoamDesignStudy, d: RobotDesign, foams: list[Foam]) -> None:
    for f, v in zip(foams, d.verdicts, strict=True):
        log.info("%s: %s: %s: %s (%s)", study.name, d.label, f.name, v.verdict, v.statement)
    if d.optimal is not None:
        log.info("%s: %s: optimal foam: status %s", study.name, d.label, d.optimal.status)
    if d.check is not None:
        log.info(
            "%s: %s: worst-case check (8 corners + %d samples per point): %s",
            study.name, d.label, study.worst_case_samples, d.check.status,
        )  # fmt: skip
    for w in d.envelope.warnings:
        log.info("%s: %s: envelope: %s", study.name, d.label, w)


def run(study: FoamDesignStudy, context: RunContext) -> FoamDesignResult:
    """Compute the ``foam_design`` study (in this process; nothing is stored).

    Parameters
    ----------
    study
        The validated study.
    context
        How to run it (nothing of this kind is stored; a progress bar per robot).
    """
    criteria = [c.build() for c in study.criteria]
    foams = []
    for i, spec in enumerate(study.foams):
        f = spec.build()
        foams.append(f if f.name else f.replace(name=f"foam {i + 1}"))
    head_range = study.head_range.build() if study.head_range else None
    designs = []
    with context.bar(f"{study.kind}: robots", len(study.robots)) as hook:
        for i, spec in enumerate(study.robots):
            robot = spec.build()
            label = robot.name or f"robot {i + 1}"
            t0 = time.perf_counter()
            log.info(
                "%s: %s: envelope over %d damping values, %d criteria, %d foams",
                study.name, label, study.damping.num, len(criteria), len(foams),
            )  # fmt: skip
            d = _robot_design(study, robot, label, criteria, foams, head_range)
            _log_design(study, d, foams)
            log.info("%s: %s: done in %.1f s", study.name, label, time.perf_counter() - t0)
            designs.append(d)
            hook(Progress(step=i + 1, total=len(study.robots), label="robot", note=label))
    return FoamDesignResult(study, foams, designs)


KIND = StudyKind(
    name="foam_design",
    schema=FoamDesignStudy,
    run=run,
    report="designlab.report.envelope",
    reproduction=ENVELOPE,
)
