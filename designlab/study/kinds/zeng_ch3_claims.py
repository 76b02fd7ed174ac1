"""The ``zeng_ch3_claims`` study kind: Zeng 2011 Ch. 3 statements, recomputed and restated.

It recomputes four statements of Ch. 3 with :mod:`designlab.impact.ch3_claims`
(``docs/impact_joint.md``, Sec. 5): the Sec. 3.8 force and a_h,max changes under
+/-0.51 g for each reading of the unstated head speed and feed-forward, with the
force's first local maximum (the thesis's "peak") and its first-lobe maximum;
the worst impact point of Fig. 3.16 and the l -> 0 change for each
joint-speed/head-speed ratio; the effect of the printed q2 (docs/impact.md, "q2") on
every metric of the Table 3.2 simulations; and Manipulator 1 of Table 3.1
recomputed from its joint data (App. A.2).

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: zeng_ch3_claims
... name: demo
... readings:
...   - {name: "(b)", impact_velocity: 0.25, feedforward: false}
... speed_ratios: [1.0]
... ''')
>>> result = run_study(study)
>>> round(result.profiles[0].change.force_first_peak_pct, 2)
4.95
>>> round(result.worst_points[0].lever_arm, 3)
0.016
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import ClassVar, Literal

import pandas as pd
from pydantic import Field, model_validator

from designlab.impact.ch3_claims import (
    REFERENCE_LEVER_ARM,
    SPEED_RATIO,
    ProfileChange,
    Q2Effect,
    WorstImpactPoint,
    manipulator_1_recomputed,
    profile_change,
    q2_effect,
    worst_impact_point,
)
from designlab.impact.parameters import (
    FOAM_1,
    HEAD_MIN,
    IMPACT_VELOCITY,
    MANIPULATOR_1,
    TABLE_3_2_HEADS,
    ContactDynamics,
)
from designlab.impact.simulate import VelocityProfile
from designlab.params import Param, params_of
from designlab.results import OK, Result
from designlab.study.base import Model, StudyBase
from designlab.study.registry import StudyKind
from designlab.study.reproduction import CH3_CLAIMS
from designlab.study.runner import RunContext
from designlab.units import STANDARD_GRAVITY

__all__ = ["KIND", "THESIS_SEC_3_8", "Ch3ClaimsResult", "Ch3ClaimsStudy", "Reading", "run"]

#: Zeng 2011 Sec. 3.8: printed changes (force %, a_h,max %) for +0.51 g and -0.51 g.
THESIS_SEC_3_8: dict[int, tuple[float, float]] = {+1: (5.0, 4.0), -1: (-4.0, -3.0)}

#: The magnitude of the Sec. 3.8 acceleration, in g (applied as + and -; the thesis's 0.51 g).
ACCELERATION_G = Param(
    "a", "g", "Sec. 3.8 acceleration magnitude (applied as + and -)", gt=0, le=10,
    typical=(0.51, 0.51), name="acceleration_g",
)  # fmt: skip

# the YAML fields are the domain's declarations (designlab.params)
_PROFILE = params_of(VelocityProfile)
_Velocity = IMPACT_VELOCITY.annotation(optional=False)
_Feedforward = replace(
    _PROFILE["feedforward"], doc="the controller compensates the acceleration"
).annotation()
_AccelerationG = ACCELERATION_G.annotation()
_Duration = _PROFILE["duration"].annotation()
_SpeedRatio = SPEED_RATIO.annotation()
_ReferenceLever = REFERENCE_LEVER_ARM.annotation()
_Q2Velocity = replace(
    IMPACT_VELOCITY, doc="closing velocity of the printed-q2 comparison"
).annotation()


class Reading(Model):
    """One reading of the unstated Sec. 3.8 details: closing speed and feed-forward."""

    name: str = Field(min_length=1, max_length=120, description="label for the report")
    impact_velocity: _Velocity
    feedforward: _Feedforward


def _default_readings() -> list[Reading]:
    return [
        Reading(name="(a) head at -1 m/s, feed-forward", impact_velocity=1.25, feedforward=True),
        Reading(name="(b) head still, no feed-forward", impact_velocity=0.25, feedforward=False),
    ]


class Ch3ClaimsStudy(StudyBase):
    """Zeng 2011 Ch. 3 statements recomputed (Sec. 3.8, Fig. 3.16, the printed q2, Table 3.1)."""

    kind: Literal["zeng_ch3_claims"]
    acceleration_g: _AccelerationG = 0.51
    profile_duration: _Duration = 0.05
    readings: list[Reading] = Field(default_factory=_default_readings, min_length=1, max_length=10)
    speed_ratios: list[_SpeedRatio] = Field(
        default_factory=lambda: [0.5, 0.62, 1.0, 2.3],
        min_length=1,
        max_length=20,
        description="Fig. 3.16 joint-speed/head-speed ratios, (rad/s)/(m/s)",
    )
    reference_lever_arm: _ReferenceLever = 0.01
    q2_impact_velocity: _Q2Velocity = 1.25

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "sec_3_8.csv",
        "fig_3_16.csv",
        "q2.csv",
        "table_3_1.csv",
        "zeng_ch3_claims.png",
        "study.yaml",
    )
    #: s: CPU time of studies/zeng_ch3_claims.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 7

    @model_validator(mode="after")
    def _distinct(self) -> Ch3ClaimsStudy:
        names = [r.name for r in self.readings]
        if len(set(names)) != len(names):
            raise ValueError("readings must have distinct names")
        return self

    def size(self) -> str:
        """Impacts simulated.

        Returns
        -------
        str
            E.g. ``2 reading(s) x 2 signs, 4 speed ratio(s)``.
        """
        return f"{len(self.readings)} reading(s) x 2 signs, {len(self.speed_ratios)} speed ratio(s)"


@dataclass(frozen=True)
class ReadingChange:
    """One Sec. 3.8 reading at one sign of the acceleration."""

    reading: Reading
    sign: int
    change: ProfileChange


@dataclass(frozen=True)
class Ch3ClaimsResult(Result):
    """Result of a ``zeng_ch3_claims`` study.

    Attributes
    ----------
    study
        The validated study.
    profiles
        Sec. 3.8: one :class:`ReadingChange` per reading and sign of the acceleration.
    worst_points
        Fig. 3.16: one :class:`~designlab.impact.ch3_claims.WorstImpactPoint` per ratio.
    q2
        ``(case, Q2Effect)`` for each Table 3.2 simulation.
    recomputed, printed
        Table 3.1's Manipulator 1 recomputed from its joint data, and as printed.
    """

    study: Ch3ClaimsStudy
    profiles: list[ReadingChange]
    worst_points: list[WorstImpactPoint]
    q2: list[tuple[str, Q2Effect]]
    recomputed: ContactDynamics
    printed: ContactDynamics

    @property
    def status(self) -> str:
        """``"ok"``, or the first status of a part that is not."""
        parts = [p.change for p in self.profiles] + self.worst_points + [e for _, e in self.q2]
        for p in parts:
            if p.status != OK:
                return p.status
        return OK

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """The parts' warnings."""
        parts = [p.change for p in self.profiles] + self.worst_points + [e for _, e in self.q2]
        return tuple(dict.fromkeys(w for p in parts for w in p.warnings))

    def profiles_frame(self) -> pd.DataFrame:
        """Sec. 3.8: one row per reading and sign, next to the thesis's changes.

        Returns
        -------
        pandas.DataFrame
        """
        rows = []
        for p in self.profiles:
            df = p.change.to_frame()
            df.insert(0, "reading", p.reading.name)
            thesis = THESIS_SEC_3_8[p.sign]
            df["thesis_d_f_c_pct"] = thesis[0]
            df["thesis_d_a_h_max_pct"] = thesis[1]
            rows.append(df)
        return pd.concat(rows, ignore_index=True)

    def worst_frame(self) -> pd.DataFrame:
        """Fig. 3.16: one row per speed ratio.

        Returns
        -------
        pandas.DataFrame
        """
        return pd.concat([w.to_frame() for w in self.worst_points], ignore_index=True)

    def q2_frame(self) -> pd.DataFrame:
        """The printed q2 (docs/impact.md, "q2"): one row per Table 3.2 simulation and metric.

        Returns
        -------
        pandas.DataFrame
        """
        frames = []
        for name, e in self.q2:
            df = e.to_frame()
            df.insert(0, "case", name)
            frames.append(df)
        return pd.concat(frames, ignore_index=True)

    def table_3_1_frame(self) -> pd.DataFrame:
        """Table 3.1, Manipulator 1: printed and recomputed values.

        Returns
        -------
        pandas.DataFrame
        """
        rows = []
        for q, unit in (("mass", "kg"), ("stiffness", "N/m"), ("damping", "N s/m")):
            a, b = getattr(self.printed, q), getattr(self.recomputed, q)
            rows.append(
                {"quantity": q, "unit": unit, "printed": a, "recomputed": b,
                 "difference_pct": 100.0 * (b / a - 1.0)}
            )  # fmt: skip
        return pd.DataFrame(rows)

    def to_frame(self) -> pd.DataFrame:
        """The Sec. 3.8 changes (see the other ``*_frame`` methods for the rest).

        Returns
        -------
        pandas.DataFrame
        """
        return self.profiles_frame()


def run(study: Ch3ClaimsStudy, context: RunContext) -> Ch3ClaimsResult:
    """Compute the ``zeng_ch3_claims`` study (in this process; nothing is stored).

    Parameters
    ----------
    study
        The validated study.
    context
        How to run (ignored: the study is small).

    Returns
    -------
    Ch3ClaimsResult
    """
    head_3 = TABLE_3_2_HEADS[3][1]  # Sec. 3.8 uses Table 3.2's simulation 3
    acc = study.acceleration_g * STANDARD_GRAVITY
    profiles = [
        ReadingChange(
            r, sign,
            profile_change(MANIPULATOR_1, FOAM_1, head_3, r.impact_velocity, sign * acc,
                           duration=study.profile_duration, feedforward=r.feedforward),
        )
        for r in study.readings
        for sign in (+1, -1)
    ]  # fmt: skip
    l1 = MANIPULATOR_1.lever_arm or 0.078
    m11, k_j, c_j = (MANIPULATOR_1.mass * l1**2, MANIPULATOR_1.stiffness * l1**2,
                     MANIPULATOR_1.damping * l1**2)  # fmt: skip
    worst = [
        worst_impact_point(m11, k_j, c_j, ratio, FOAM_1, HEAD_MIN,
                           reference_lever_arm=study.reference_lever_arm)
        for ratio in study.speed_ratios
    ]  # fmt: skip
    q2 = [
        (f"Table 3.2 sim {i}: {robot.name}, head {head.mass:g} kg, {head.stiffness:g} N/m, "
         f"{head.damping:g} N s/m",
         q2_effect(robot, FOAM_1, head, study.q2_impact_velocity))
        for i, (robot, head) in TABLE_3_2_HEADS.items()
    ]  # fmt: skip
    return Ch3ClaimsResult(study, profiles, worst, q2, manipulator_1_recomputed(), MANIPULATOR_1)


KIND = StudyKind(
    name="zeng_ch3_claims",
    schema=Ch3ClaimsStudy,
    run=run,
    report="designlab.report.zeng_ch3_claims",
    reproduction=CH3_CLAIMS,
)
