"""Shared fixtures. Tests never read outside the repository (no ../shared)."""

from __future__ import annotations

import textwrap
from collections.abc import Callable
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[1]
DEFAULT_STUDY = REPO_ROOT / "studies" / "zeng_ch4_validation.yaml"

TINY_STUDY = """\
designlab: 1
kind: impact_cases
name: tiny
description: Two impacts of the direct-drive arm on the test head.
cases:
  - label: slow
    robot: MANIPULATOR_1
    foam: FOAM_1
    head: TEST_HEAD
    impact_velocity: 0.4
    reference: {a_h_max_g: 2.10, t_imp_s: 0.033, eps_max_m: 0.0039,
                tolerance: {a_h_max_rel: 0.02, t_imp_abs_s: 0.003, eps_max_rel: 0.06}}
  - label: fast
    robot: {mass: 9.6, stiffness: 20e3, damping: 250}
    foam: {stiffness: 24.25e3, damping: 71.9, linear_depth: 0.02}
    head: {mass: 4.4, stiffness: 4.0e3, damping: 0}
    v_r: 0.25
    v_h: -1.0
"""


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return REPO_ROOT


@pytest.fixture(scope="session")
def tiny_study_text() -> str:
    return TINY_STUDY


@pytest.fixture
def write_study(tmp_path: Path) -> Callable[..., Path]:
    """Write YAML text (dedented) to ``tmp_path/<name>`` and return the path."""

    def _write(text: str, name: str = "study.yaml") -> Path:
        path = tmp_path / name
        path.write_text(textwrap.dedent(text), encoding="utf-8")
        return path

    return _write


@pytest.fixture
def refuses_edit(write_study: Callable[..., Path]) -> Callable[[str, str, str, str], None]:
    """Check that a study, with ``old`` replaced by ``new``, is refused naming ``field``."""
    from designlab.errors import StudyError
    from designlab.study import load_study

    def _check(text: str, old: str, new: str, field: str) -> None:
        edited = text.replace(old, new)
        assert edited != text
        with pytest.raises(StudyError, match=field):
            load_study(write_study(edited, "bad.yaml"))

    return _check
