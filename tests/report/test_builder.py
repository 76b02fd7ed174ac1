"""Every report writer opens, signs and copies its study through one builder."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import designlab.report as report_pkg
from designlab.report.builder import copy_study, provenance, report_header, warnings_section

REPORT_DIR = Path(report_pkg.__file__).parent
WRITERS = sorted(
    p
    for p in REPORT_DIR.glob("*.py")
    if p.name not in {"__init__.py", "builder.py", "atomic.py", "writers.py", "store.py"}
)


@pytest.mark.parametrize("path", WRITERS, ids=lambda p: p.stem)
def test_no_writer_words_its_own_provenance_or_study_copy(path: Path) -> None:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    strings = [
        n.value for n in ast.walk(tree) if isinstance(n, ast.Constant) and isinstance(n.value, str)
    ]
    docstrings = {
        ast.get_docstring(n, clean=False)
        for n in ast.walk(tree)
        if isinstance(n, (ast.Module, ast.FunctionDef, ast.ClassDef))
    }
    code_strings = [s for s in strings if s not in docstrings]
    assert not [s for s in code_strings if "Produced by" in s or "Generated file" in s]
    assert "study.yaml" not in code_strings


@pytest.mark.parametrize("command", [None, "designlab run s.yaml"])
@pytest.mark.parametrize("version", [None, "9.9"])
@pytest.mark.parametrize("cached", [False, True])
def test_one_provenance_sentence(command: str | None, version: str | None, cached: bool) -> None:
    text = provenance(command, version, cached=cached)
    assert text.startswith("Produced by ") and text.endswith(".")
    assert text.count("Produced by") == 1
    assert ("`designlab run s.yaml`" in text) is (command is not None)
    assert ("designlab 9.9" in text) is (version is not None)
    assert ("designlab report" in text) is cached
    assert "Generated file: edit the study, not this report" in text


def test_header_title_description_then_provenance() -> None:
    lines = report_header("t", "  Asks X.\n", command="c", version="1")
    assert lines[:4] == ["# t", "", "Asks X.", ""]
    assert lines[4] == provenance("c", "1") and lines[5] == ""
    assert report_header("t")[:2] == ["# t", ""]
    assert report_header("t")[2].startswith("Produced by")


def test_warnings_section_and_study_copy(tmp_path: Path) -> None:
    assert warnings_section([]) == []
    assert warnings_section([], none="None.") == ["## Warnings", "", "None.", ""]
    assert warnings_section(["a", "b"])[2:4] == ["- a", "- b"]
    assert copy_study(tmp_path, None) == []
    (path,) = copy_study(tmp_path, "designlab: 1\n")
    assert path.read_text() == "designlab: 1\n" and path.name == "study.yaml"
