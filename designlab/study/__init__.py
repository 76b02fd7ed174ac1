"""YAML studies: schema, loading with line-accurate errors, and the runner.

A study is a YAML file that asks one design question and names the source
result it reproduces. ``designlab run STUDY.yaml`` loads it with
:func:`load_study`, computes it with :func:`run_study` and hands the result
to :mod:`designlab.report`.

Examples
--------
>>> from designlab.study import parse_study
>>> study = parse_study('''
... designlab: 1
... kind: impact_cases
... name: demo
... cases:
...   - robot: MANIPULATOR_1
...     foam: {preset: FOAM_1, linear_depth: 0.025}
...     head: TEST_HEAD
...     impact_velocity: 0.4
... ''')
>>> study.kind, study.cases[0].foam.build().linear_depth
('impact_cases', 0.025)
"""

from __future__ import annotations

from designlab.study.loader import format_path, load_study, parse_study
from designlab.study.runner import ImpactCaseResult, ImpactCasesResult, StudyResult, run_study
from designlab.study.schema import (
    STUDY_ADAPTER,
    STUDY_KINDS,
    ImpactCase,
    ImpactCasesStudy,
    Study,
    StudyBase,
)

__all__ = [
    "STUDY_ADAPTER",
    "STUDY_KINDS",
    "ImpactCase",
    "ImpactCaseResult",
    "ImpactCasesResult",
    "ImpactCasesStudy",
    "Study",
    "StudyBase",
    "StudyResult",
    "format_path",
    "load_study",
    "parse_study",
    "run_study",
]
