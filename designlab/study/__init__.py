"""YAML studies: the shared schema, the kind registry, loading and running.

A study is a YAML file that asks one design question and names the source
result it reproduces. ``designlab run STUDY.yaml`` loads it with
:func:`load_study`, computes it with :func:`run_study` and hands the result
to :mod:`designlab.report`. Each study kind is one module of
:mod:`designlab.study.kinds`; :mod:`designlab.study.registry` lists them.

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

from designlab.study.base import FORMAT_VERSION, StudyBase, did_you_mean
from designlab.study.loader import format_path, load_study, parse_study
from designlab.study.registry import (
    StudyKind,
    kind_of,
    register_kind,
    study_adapter,
    study_json_schema,
    study_kinds,
    unregister_kind,
)
from designlab.study.runner import RunContext, run_study

__all__ = [
    "FORMAT_VERSION",
    "RunContext",
    "StudyBase",
    "StudyKind",
    "did_you_mean",
    "format_path",
    "kind_of",
    "load_study",
    "parse_study",
    "register_kind",
    "run_study",
    "study_adapter",
    "study_json_schema",
    "study_kinds",
    "unregister_kind",
]
