"""The report framework owns the ceremony: every writer returns its parts, nothing more."""

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


#: What the framework does for every report (:func:`designlab.report.builder.write_parts`).
CEREMONY = {"report_header", "warnings_section", "copy_study", "write_report", "record_timings"}


@pytest.mark.parametrize("path", WRITERS, ids=lambda p: p.stem)
def test_no_writer_does_the_ceremony_or_sees_the_command(path: Path) -> None:
    """A writer returns ReportParts: it neither writes a header, warnings, the study's copy
    or files itself, nor is handed the command line, version, study text or directory."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    used = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    used |= {a.name for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) for a in n.names}
    assert not used & CEREMONY
    params = {
        a.arg
        for n in ast.walk(tree)
        if isinstance(n, ast.FunctionDef)
        for a in [*n.args.args, *n.args.kwonlyargs]
    }
    assert not params & {"command", "version", "study_text", "directory"}


def test_main_page_orders_header_body_warnings_closing() -> None:
    from types import SimpleNamespace

    from designlab.report.builder import ReportParts, main_page

    result = SimpleNamespace(study=SimpleNamespace(name="s", description=""), warnings=["w1"])
    parts = ReportParts(body=["B"], closing=["C"], title="T")
    lines = main_page(result, parts, command="c", version="1").splitlines()
    assert lines == ["# T", "", provenance("c", "1"), "", "B", "## Warnings", "", "- w1", "", "C"]
    quiet = ReportParts(body=["B"], warnings=[], no_warnings="None.")
    assert main_page(result, quiet).splitlines()[-4:] == ["B", "## Warnings", "", "None."]
    assert main_page(result, ReportParts(body=["B"], warnings=[])).splitlines()[-1] == "B"


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
