"""Run a validated study and collect its results.

:func:`run_study` dispatches on the study's ``kind``. It computes, it does
not write: the result objects go to :mod:`designlab.report`.

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: impact_cases
... name: demo
... cases:
...   - {label: fast, robot: MANIPULATOR_1, foam: FOAM_1, head: TEST_HEAD, v_r: 0.25, v_h: -1.0}
... ''')
>>> result = run_study(study)
>>> result.to_frame()[["case", "v_c_m_per_s", "a_h_max_g"]].round(2)
   case  v_c_m_per_s  a_h_max_g
0  fast         1.25       6.57
"""

from __future__ import annotations

import logging
import math
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd
from tqdm.auto import tqdm

from designlab.impact.parameters import ContactDynamics, Foam, HeadNeck
from designlab.study.schema import ImpactCase, ImpactCasesStudy, StudyBase
from designlab.study.sweep_runner import SweepStudyResult, run_sweep_study

__all__ = [
    "ImpactCaseResult",
    "ImpactCasesResult",
    "StudyResult",
    "SweepStudyResult",
    "run_study",
]

logger = logging.getLogger(__name__)

#: Window of the HIC reported in the ``hic15`` column, s.
HIC_WINDOW_S = 0.015


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
        """Whether the model is within the case's reference tolerance (None if none set)."""
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
class ImpactCasesResult:
    """Results of an ``impact_cases`` study, in the study's case order."""

    study: ImpactCasesStudy
    cases: tuple[ImpactCaseResult, ...]

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
    def warnings(self) -> list[str]:
        """Every warning of every case, prefixed with the case label."""
        out = []
        for c in self.cases:
            if c.response.status != "ok":
                out.append(f"{c.title}: status {c.response.status}")
            out.extend(f"{c.title}: {w}" for w in c.response.warnings)
        return out


#: The result of any study kind.
StudyResult = ImpactCasesResult | SweepStudyResult


def _run_impact_cases(study: ImpactCasesStudy, progress: bool, **_: Any) -> ImpactCasesResult:
    # a handful of simulations: run in process, not cached (``cache_only`` recomputes)
    from designlab.impact import simulate  # the physics; imported when needed

    results = []
    cases = tqdm(
        study.cases,
        desc=study.name,
        unit="case",
        file=sys.stderr,
        disable=not progress,
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


def _run_foam_design(study: Any, **_: Any) -> Any:
    from designlab.study.foam_design import run_foam_design

    return run_foam_design(study)


_RUNNERS: dict[str, Callable[..., Any]] = {
    "impact_cases": _run_impact_cases,
    "impact_sweep": run_sweep_study,
    "foam_envelope": run_sweep_study,
    "foam_design": _run_foam_design,
}


def run_study(
    study: StudyBase,
    *,
    progress: bool = False,
    executor: Any = None,
    cache_dir: str | Path | None = None,
    resume: bool = False,
    cache_only: bool = False,
) -> StudyResult:
    """Compute every result of a study.

    Parameters
    ----------
    study
        A validated study (see :func:`designlab.study.load_study`).
    progress
        Show a tqdm progress bar on stderr (the CLI turns it on only when
        stderr is a terminal).
    executor
        Sweep kinds: an executor from
        :func:`designlab.analysis.executors.make_executor` (default: serial,
        in this process). The caller closes it.
    cache_dir
        Sweep kinds: keep every finished point in ``<cache_dir>/<name>/``.
    resume
        Sweep kinds: reuse cached points; compute only the missing ones.
    cache_only
        Sweep kinds: compute nothing; raise
        :class:`~designlab.analysis.sweep.CacheIncompleteError` if a point is
        missing (``designlab report``). ``impact_cases`` studies are not
        cached and are recomputed (they take well under a second).

    Returns
    -------
    StudyResult
        The result object of the study's kind: :class:`ImpactCasesResult` or
        :class:`~designlab.study.sweep_runner.SweepStudyResult`.
    """
    try:
        runner = _RUNNERS[study.kind]
    except KeyError:  # pragma: no cover - the schema only admits known kinds
        raise NotImplementedError(f"no runner for study kind {study.kind!r}") from None
    return runner(  # type: ignore[no-any-return]
        study,
        progress=progress,
        executor=executor,
        cache_dir=cache_dir,
        resume=resume,
        cache_only=cache_only,
    )
