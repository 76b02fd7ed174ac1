"""The ``joint_reduction`` study kind: where the reduced joint (3.4.9) may be used.

For each joint of the study it compares the impact with the full series joint
(Zeng 2011, eq. 3.4.6) with the Taylor reduction (3.4.9) and the band fit, at
the joint as given and over the transmission/controller stiffness ratio
K_mech/K_cont (:func:`designlab.impact.joint_reduction_sweep`), and marks where
each reduction is conservative (``docs/impact_joint.md``).

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: joint_reduction
... name: demo
... joints:
...   - {name: geared, inertia: 0.059, k_mech: 2000, c_mech: 2.0, k_cont: 1500, c_cont: 30,
...      lever_arm: 0.2}
... ratios: {low: 0.1, high: 100, num: 4}
... ''')
>>> result = run_study(study)
>>> round(100 * result.joints[0].nominal.relative_error("taylor", "a_h_max"), 1)
12.5
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import pandas as pd
from pydantic import Field, model_validator

from designlab.impact import (
    FullJointContact,
    JointReductionComparison,
    JointReductionSweep,
    SeriesJoint,
    compare_joint_reductions,
    joint_reduction_sweep,
)
from designlab.impact.parameters import (
    IMPACT_VELOCITY,
    OMEGA_MAX,
    RATIO_POINTS,
    STIFFNESS_RATIO,
    USABLE_TOLERANCE,
)
from designlab.results import OK, Result
from designlab.study.base import Grid, StudyBase
from designlab.study.kinds.impact_specs import FoamSpec, HeadSpec
from designlab.study.registry import StudyKind
from designlab.study.reproduction import METRIC_DIFFERENCES
from designlab.study.runner import RunContext
from designlab.study.specs import spec_model

__all__ = ["KIND", "JointReductionResult", "JointReductionStudy", "JointSpec", "run"]

# the YAML fields are the domain's declarations (designlab.params)
_Ratio = STIFFNESS_RATIO.annotation()
_RatioPoints = RATIO_POINTS.annotation()
_Velocity = IMPACT_VELOCITY.annotation()
_Tolerance = USABLE_TOLERANCE.annotation()
_OmegaMax = OMEGA_MAX.annotation()

_JointFields: Any = spec_model(SeriesJoint, name="_JointFields")


class JointSpec(_JointFields):  # type: ignore[misc, valid-type]
    """One joint at joint level (scenarios 1/2: divided by l^2 at the impact point).

    The fields are those of :class:`~designlab.impact.SeriesJoint`.
    """

    @model_validator(mode="after")
    def _valid(self) -> JointSpec:
        SeriesJoint(**self.model_dump())  # the domain's own rules (c_mech + c_cont > 0)
        return self

    def build(self, index: int = 0) -> FullJointContact:  # type: ignore[override]
        """The :class:`~designlab.impact.FullJointContact` of this joint.

        Parameters
        ----------
        index
            Position in the study, for the default name ``joint <index + 1>``.

        Returns
        -------
        FullJointContact
            Effective values at the impact point (divided by ``lever_arm**2``).
        """
        fields = self.model_dump()
        fields["name"] = fields["name"] or f"joint {index + 1}"
        return SeriesJoint(**fields).contact()


class RatioGrid(Grid):
    """Log-spaced K_mech/K_cont values: ``num`` of them from ``low`` to ``high``.

    Each value and their number are the declarations of
    :func:`~designlab.impact.joint_reduction_sweep` (the same cap in both).
    """

    low: _Ratio = 0.03
    high: _Ratio = 3000.0
    num: _RatioPoints = 41

    LOG: ClassVar[bool] = True


class JointReductionStudy(StudyBase):
    """Error of the reduced joint (3.4.9) on the impact metrics, over K_mech/K_cont."""

    kind: Literal["joint_reduction"]
    joints: list[JointSpec] = Field(min_length=1, max_length=20, description="joints compared")
    foam: FoamSpec = Field(default_factory=lambda: FoamSpec(preset="FOAM_1"))
    head: HeadSpec | None = Field(
        default_factory=lambda: HeadSpec(preset="HEAD_MIN"),
        description="head-neck set; null: constrained impact (head against a wall)",
    )
    impact_velocity: _Velocity = 1.25
    ratios: RatioGrid = Field(default_factory=RatioGrid)
    usable_tolerance: _Tolerance = 0.01
    omega_max: _OmegaMax = None

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "joint_reduction.csv",
        "nominal.csv",
        "joint_reduction.png",
        "study.yaml",
    )
    #: s: CPU time of studies/joint_reduction.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 8

    @model_validator(mode="after")
    def _distinct(self) -> JointReductionStudy:
        names = [j.build(i).name for i, j in enumerate(self.joints)]
        if len(set(names)) != len(names):
            raise ValueError("joints must have distinct names")
        self.foam.build()  # what run builds, validate builds (the domain's rules)
        if self.head is not None:
            self.head.build()
        return self

    def size(self) -> str:
        """Joints x ratios.

        Returns
        -------
        str
            E.g. ``2 joint(s) x 41 stiffness ratios``.
        """
        return f"{len(self.joints)} joint(s) x {self.ratios.num} stiffness ratios"


@dataclass(frozen=True)
class JointStudy:
    """What the study computed for one joint."""

    robot: FullJointContact
    nominal: JointReductionComparison
    sweep: JointReductionSweep


@dataclass(frozen=True)
class JointReductionResult(Result):
    """Result of a ``joint_reduction`` study.

    Attributes
    ----------
    study
        The validated study.
    joints
        Per joint, the comparison as given and the sweep over the ratios.
    """

    study: JointReductionStudy
    joints: list[JointStudy]

    @property
    def status(self) -> str:
        """``"ok"``, or the first status of a comparison or sweep that is not."""
        for j in self.joints:
            for part in (j.nominal, j.sweep):
                if part.status != OK:
                    return part.status
        return OK

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """The comparisons' and sweeps' warnings, by joint."""
        out = [
            f"{j.robot.name}: {w}" for j in self.joints for p in (j.nominal, j.sweep)
            for w in p.warnings
        ]  # fmt: skip
        return tuple(dict.fromkeys(out))

    def nominal_frame(self) -> pd.DataFrame:
        """Each joint as given.

        Returns
        -------
        pandas.DataFrame
            One row per (joint, reduction, metric), with the joint's K_mech/K_cont.
        """
        frames = []
        for j in self.joints:
            df = j.nominal.to_frame()
            df.insert(0, "joint", j.robot.name)
            df.insert(1, "ratio", j.robot.stiffness_ratio)
            frames.append(df)
        return pd.concat(frames, ignore_index=True)

    def to_frame(self) -> pd.DataFrame:
        """The sweeps.

        Returns
        -------
        pandas.DataFrame
            One row per (joint, ratio, reduction, metric).
        """
        frames = []
        for j in self.joints:
            df = j.sweep.to_frame()
            df.insert(0, "joint", j.robot.name)
            frames.append(df)
        return pd.concat(frames, ignore_index=True)


def run(study: JointReductionStudy, context: RunContext) -> JointReductionResult:
    """Compute the ``joint_reduction`` study (in this process; nothing is stored).

    Parameters
    ----------
    study
        The validated study.
    context
        How to run (this kind computes in the calling process and ignores the
        executor and the store).

    Returns
    -------
    JointReductionResult
        Per joint, the comparison as given and the sweep over the ratios.
    """
    foam = study.foam.build()
    head = study.head.build() if study.head is not None else None
    ratios = study.ratios.values()
    out = []
    for i, spec in enumerate(study.joints):
        robot = spec.build(i)
        nominal = compare_joint_reductions(
            robot, foam, head, study.impact_velocity, omega_max=study.omega_max
        )
        sweep = joint_reduction_sweep(
            robot, foam, head, study.impact_velocity, ratios, omega_max=study.omega_max
        )
        out.append(JointStudy(robot, nominal, sweep))
    return JointReductionResult(study, out)


KIND = StudyKind(
    name="joint_reduction",
    schema=JointReductionStudy,
    run=run,
    report="designlab.report.joint_reduction",
    reproduction=METRIC_DIFFERENCES,
)
