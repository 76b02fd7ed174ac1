"""The ``impact_cases`` study kind: single impacts compared with reference values.

A list of impacts (manipulator, foam, head, closing speed), each simulated with
:func:`designlab.impact.simulate` and compared with optional reference values
(for example Zeng 2011, Tables 4.1-4.2).

Examples
--------
A case with a reference value is compared with it (``a_h_max_g`` against the table):

>>> from designlab.study import parse_study, run_study
>>> result = run_study(parse_study('''
... {designlab: 1, kind: impact_cases, name: table_4_1, cases: [
...   {robot: MANIPULATOR_1, foam: {preset: FOAM_1, linear_depth: 0.025}, head: TEST_HEAD,
...    impact_velocity: 0.4, reference: {source: Zeng 2011 Table 4.1, a_h_max_g: 2.1}}]}
... '''))
>>> result.status, result.study.cases[0].foam.build().linear_depth
('ok', 0.025)
"""

from __future__ import annotations

import logging
import math
import sys
from dataclasses import dataclass
from typing import Annotated, Any, ClassVar, Literal

import pandas as pd
from pydantic import Field, model_validator
from tqdm.auto import tqdm

from designlab.impact.parameters import (
    HEAD_VELOCITY,
    IMPACT_VELOCITY,
    ROBOT_VELOCITY,
    ContactDynamics,
    Foam,
    HeadNeck,
)
from designlab.results import OK, Result
from designlab.study.base import Integer, Model, Positive, StudyBase
from designlab.study.kinds.impact_specs import FoamSpec, HeadSpec, RobotSpec
from designlab.study.registry import StudyKind
from designlab.study.reproduction import CERTIFIED_IMPACT
from designlab.study.runner import RunContext

__all__ = [
    "KIND",
    "ImpactCase",
    "ImpactCaseResult",
    "ImpactCasesResult",
    "ImpactCasesStudy",
    "ImpactReference",
    "ImpactTolerance",
    "run",
]

logger = logging.getLogger(__name__)

#: Window of the HIC reported in the ``hic15`` column, s.
HIC_WINDOW_S = 0.015

# the YAML fields of an impact are the domain's declarations (designlab.params)
_Velocity = IMPACT_VELOCITY.annotation(optional=True)
_RobotVelocity = ROBOT_VELOCITY.annotation(optional=True)
_HeadVelocity = HEAD_VELOCITY.annotation(optional=True)


class ImpactTolerance(Model):
    """Acceptance band of the model against the reference (reported, not enforced)."""

    a_h_max_rel: Positive | None = Field(None, description="relative, e.g. 0.02 for 2 %")
    t_imp_abs_s: Positive | None = Field(None, description="absolute, s")
    eps_max_rel: Positive | None = Field(None, description="relative")


class ImpactReference(Model):
    """Reference values a case is compared with (e.g. a thesis table).

    ``a_h_max_g``, ``t_imp_s`` and ``eps_max_m`` are the reference *simulation*
    (the source's model); ``exp_*`` are experimental means.
    """

    source: str | None = Field(None, description="where the numbers come from")
    a_h_max_g: Positive | None = None
    t_imp_s: Positive | None = None
    eps_max_m: Positive | None = None
    peak_force_N: Positive | None = None
    exp_a_h_max_g: Positive | None = None
    exp_t_imp_s: Positive | None = None
    exp_eps_max_m: Positive | None = None
    exp_trials: Annotated[Integer, Field(ge=1)] | None = None
    tolerance: ImpactTolerance | None = None
    note: str | None = Field(
        None,
        description="why a comparison fails or what a reader should know; shown with the row",
    )


class ImpactCase(Model):
    """One impact: manipulator, foam and head meeting at a closing speed.

    Give either ``impact_velocity`` (the closing speed v_c, m/s) or both
    ``v_r`` and ``v_h`` (manipulator and head velocities; v_c = v_r - v_h,
    a negative v_h moves the head toward the robot, docs/impact.md, "Impact velocity").
    """

    label: str | None = Field(None, min_length=1, max_length=80)
    group: str | None = Field(
        None, min_length=1, max_length=80, description="cases of a group share a figure"
    )
    robot: RobotSpec
    foam: FoamSpec
    head: HeadSpec
    impact_velocity: _Velocity = None
    v_r: _RobotVelocity = None
    v_h: _HeadVelocity = None
    reference: ImpactReference | None = None

    @model_validator(mode="after")
    def _one_velocity(self) -> ImpactCase:
        pair = (self.v_r is not None, self.v_h is not None)
        if self.impact_velocity is not None and any(pair):
            raise ValueError("give either impact_velocity or v_r and v_h, not both")
        if self.impact_velocity is None:
            if pair != (True, True):
                raise ValueError("give impact_velocity (m/s) or both v_r and v_h (m/s)")
            v_c = float(self.v_r) - float(self.v_h)  # type: ignore[arg-type]
            if not v_c > 0.0:
                raise ValueError(
                    f"v_r - v_h = {v_c:g} m/s must be > 0 for an impact "
                    "(a negative v_h moves the head toward the robot)"
                )
        self.robot.build()  # what run builds, validate builds (the domain's rules)
        self.foam.build()
        self.head.build()
        return self

    @property
    def closing_velocity(self) -> float:
        """v_c in m/s."""
        if self.impact_velocity is not None:
            return float(self.impact_velocity)
        return round(float(self.v_r) - float(self.v_h), 12)  # type: ignore[arg-type]

    def title(self, index: int) -> str:
        """The label, or ``"case <index+1>"``.

        Parameters
        ----------
        index
            Position of the case in the study (0-based).
        """
        return self.label or f"case {index + 1}"


class ImpactCasesStudy(StudyBase):
    """Simulate a list of impacts and compare them with reference values."""

    kind: Literal["impact_cases"]
    cases: list[ImpactCase] = Field(min_length=1)

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "metrics.csv",
        "time_histories*.png",
        "study.yaml",
    )
    #: s: CPU time of studies/zeng_ch4_validation.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 7

    def size(self) -> str:
        """The number of cases."""
        return f"{len(self.cases)} case{'s' if len(self.cases) != 1 else ''}"

    @model_validator(mode="after")
    def _unique_labels(self) -> ImpactCasesStudy:
        seen: set[str] = set()
        for i, case in enumerate(self.cases):
            title = case.title(i)
            if title in seen:
                raise ValueError(f"case label {title!r} is used twice; labels must be unique")
            seen.add(title)
        return self


@dataclass(frozen=True)
class ImpactCaseResult:
    """One simulated impact of an ``impact_cases`` study.

    Attributes
    ----------
    index
        Position of the case in the study.
    case
        The case as written in the study.
    robot, foam, head
        The parameter objects that were simulated.
    closing_velocity
        v_c in m/s.
    response
        The :class:`designlab.impact.ImpactResponse`.
    """

    index: int
    case: ImpactCase
    robot: ContactDynamics
    foam: Foam
    head: HeadNeck
    closing_velocity: float
    response: Any

    @property
    def title(self) -> str:
        """The case label (or ``case <n>``)."""
        return self.case.title(self.index)

    @property
    def group(self) -> str:
        """The case group (``""`` if none)."""
        return self.case.group or ""

    def metrics(self) -> dict[str, Any]:
        """Model metrics, reference values, errors and tolerance check, one row."""
        r = self.response
        row: dict[str, Any] = {
            "case": self.title,
            "group": self.group,
            "v_c_m_per_s": self.closing_velocity,
            "a_h_max_g": float(r.peak_head_acceleration_g),
            "t_imp_s": float(r.impact_duration),
            "eps_max_m": float(r.max_compression),
            "peak_force_N": float(r.peak_force),
            "hic15": float(r.hic(HIC_WINDOW_S)),
            "bottoming": bool(r.bottoming),
            "status": str(r.status),
        }
        ref = self.case.reference
        get = (lambda name: getattr(ref, name)) if ref is not None else (lambda name: None)
        nan = math.nan

        def rel_pct(model: float, reference: float | None) -> float:
            return nan if reference is None else 100.0 * (model - reference) / reference

        def diff(model: float, reference: float | None) -> float:
            return nan if reference is None else model - reference

        for key in ("a_h_max_g", "t_imp_s", "eps_max_m"):
            value = get(key)
            row[f"ref_{key}"] = nan if value is None else float(value)
        row["err_a_h_max_pct"] = rel_pct(row["a_h_max_g"], get("a_h_max_g"))
        row["err_t_imp_s"] = diff(row["t_imp_s"], get("t_imp_s"))
        row["err_eps_max_pct"] = rel_pct(row["eps_max_m"], get("eps_max_m"))
        for key in ("a_h_max_g", "t_imp_s", "eps_max_m"):
            value = get(f"exp_{key}")
            row[f"exp_{key}"] = nan if value is None else float(value)
        row["err_exp_a_h_max_pct"] = rel_pct(row["a_h_max_g"], get("exp_a_h_max_g"))
        row["err_exp_t_imp_s"] = diff(row["t_imp_s"], get("exp_t_imp_s"))
        row["err_exp_eps_max_pct"] = rel_pct(row["eps_max_m"], get("exp_eps_max_m"))
        row["within_tolerance"] = self.within_tolerance(row)
        return row

    def within_tolerance(self, row: dict[str, Any] | None = None) -> bool | None:
        """Whether the model is within the case's reference tolerance (None if none set).

        Parameters
        ----------
        row
            The case's :meth:`metrics` row (computed when not given).
        """
        ref = self.case.reference
        tol = ref.tolerance if ref is not None else None
        if tol is None:
            return None
        row = self.metrics() if row is None else row
        checks = []
        if tol.a_h_max_rel is not None and ref is not None and ref.a_h_max_g is not None:
            checks.append(abs(row["err_a_h_max_pct"]) <= 100.0 * tol.a_h_max_rel)
        if tol.t_imp_abs_s is not None and ref is not None and ref.t_imp_s is not None:
            checks.append(abs(row["err_t_imp_s"]) <= tol.t_imp_abs_s)
        if tol.eps_max_rel is not None and ref is not None and ref.eps_max_m is not None:
            checks.append(abs(row["err_eps_max_pct"]) <= 100.0 * tol.eps_max_rel)
        return all(checks) if checks else None


@dataclass(frozen=True)
class ImpactCasesResult(Result):
    """Results of an ``impact_cases`` study, in the study's case order.

    Attributes
    ----------
    study
        The study.
    cases
        One result per case, in the study's order.
    """

    study: ImpactCasesStudy
    cases: tuple[ImpactCaseResult, ...]

    @property
    def status(self) -> str:
        """``"ok"``, or the first case status that is not (e.g. ``"bottoming"``)."""
        for c in self.cases:
            if c.response.status != OK:
                return str(c.response.status)
        return OK

    def to_frame(self) -> pd.DataFrame:
        """One row per case: model metrics, reference values and errors.

        Column names carry units (``a_h_max_g``, ``t_imp_s``, ``eps_max_m``,
        ``peak_force_N``, ``hic15``); ``ref_*`` are the reference simulation,
        ``exp_*`` the experimental means; ``err_*_pct`` are relative errors of
        the model in percent, ``err_*_s`` differences in seconds.
        """
        return pd.DataFrame([c.metrics() for c in self.cases])

    def inputs_frame(self) -> pd.DataFrame:
        """One row per case: the simulated parameters (SI units)."""
        rows = []
        for c in self.cases:
            rows.append(
                {
                    "case": c.title,
                    "M_r_kg": c.robot.mass,
                    "K_r_N_per_m": c.robot.stiffness,
                    "C_r_N_s_per_m": c.robot.damping,
                    "K_c_N_per_m": c.foam.stiffness,
                    "C_c_N_s_per_m": c.foam.damping,
                    "lambda_m": c.foam.linear_depth,
                    "M_h_kg": c.head.mass,
                    "K_h_N_per_m": c.head.stiffness,
                    "C_h_N_s_per_m": c.head.damping,
                    "v_r_m_per_s": c.case.v_r,
                    "v_h_m_per_s": c.case.v_h,
                    "v_c_m_per_s": c.closing_velocity,
                }
            )
        return pd.DataFrame(rows)

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """Every warning of every case, prefixed with the case label."""
        out: list[str] = []
        for c in self.cases:
            if c.response.status != "ok":
                out.append(f"{c.title}: status {c.response.status}")
            out.extend(f"{c.title}: {w}" for w in c.response.warnings)
        return tuple(out)


def run(study: ImpactCasesStudy, context: RunContext) -> ImpactCasesResult:
    """Simulate every case (a handful: in this process, never stored).

    Parameters
    ----------
    study
        The validated study.
    context
        How to run it (cases are never stored).
    """
    from designlab.impact import simulate  # the physics; imported when needed

    results = []
    cases = tqdm(
        study.cases,
        desc=study.name,
        unit="case",
        file=sys.stderr,
        disable=not context.progress,
        leave=False,
    )
    for i, case in enumerate(cases):
        robot, foam, head = case.robot.build(), case.foam.build(), case.head.build()
        v_c = case.closing_velocity
        logger.debug("simulating %s: v_c = %g m/s", case.title(i), v_c)
        response = simulate(robot, foam, head, impact_velocity=v_c)
        for warning in response.warnings:
            logger.warning("%s: %s", case.title(i), warning)
        results.append(ImpactCaseResult(i, case, robot, foam, head, v_c, response))
    return ImpactCasesResult(study, tuple(results))


KIND = StudyKind(
    name="impact_cases",
    schema=ImpactCasesStudy,
    run=run,
    report="designlab.report.impact",
    reproduction=CERTIFIED_IMPACT,
)
