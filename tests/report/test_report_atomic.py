"""Atomic writes: an interrupted report leaves the previous one intact and no debris."""

from __future__ import annotations

import os

import pytest

from designlab.report import ReportError, atomic_write_text, builder, report_directory, write_report
from designlab.study import parse_study, run_study


def _listing(root):
    return sorted(str(p.relative_to(root)) for p in root.rglob("*"))


def test_atomic_write_replaces_and_cleans_up_on_error(tmp_path, monkeypatch):
    target = tmp_path / "a.txt"
    atomic_write_text(target, "old")

    def boom(fd):
        raise OSError("disk full")

    monkeypatch.setattr(os, "fsync", boom)
    with pytest.raises(OSError, match="disk full"):
        atomic_write_text(target, "new")
    assert target.read_text() == "old"
    assert _listing(tmp_path) == ["a.txt"]


def test_report_directory_replaces_previous_report(tmp_path):
    final = tmp_path / "reports" / "study"
    with report_directory(final) as tmp:
        atomic_write_text(tmp / "one.txt", "1")
    with report_directory(final) as tmp:
        assert not (tmp / "one.txt").exists()
        atomic_write_text(tmp / "two.txt", "2")
    assert _listing(tmp_path / "reports") == ["study", "study/two.txt"]


@pytest.mark.parametrize("exc_type", [RuntimeError, KeyboardInterrupt])
def test_exception_mid_write_keeps_previous_report(tmp_path, exc_type):
    final = tmp_path / "study"
    with report_directory(final) as tmp:
        atomic_write_text(tmp / "summary.md", "previous")
    with pytest.raises(exc_type), report_directory(final) as tmp:
        atomic_write_text(tmp / "summary.md", "half")
        raise exc_type("interrupted")
    assert (final / "summary.md").read_text() == "previous"
    assert _listing(tmp_path) == ["study", "study/summary.md"]


def test_file_in_the_way_is_a_report_error(tmp_path):
    (tmp_path / "study").write_text("not a directory")
    with (
        pytest.raises(ReportError, match="not a report directory"),
        report_directory(tmp_path / "study") as tmp,
    ):
        atomic_write_text(tmp / "x", "x")
    assert _listing(tmp_path) == ["study"]


def test_recovers_after_a_killed_run(tmp_path):
    # a run killed between the two renames of the swap, and one killed while writing
    old = tmp_path / ".study.old-deadbeef"
    old.mkdir()
    (old / "summary.md").write_text("previous")
    stale = tmp_path / ".study.tmp-999999999-abc"
    stale.mkdir()
    with report_directory(tmp_path / "study") as tmp:
        assert (tmp_path / "study" / "summary.md").read_text() == "previous"
        atomic_write_text(tmp / "summary.md", "new")
    assert _listing(tmp_path) == ["study", "study/summary.md"]


def test_write_report_failure_mid_report_keeps_previous(tmp_path, tiny_study_text, monkeypatch):
    result = run_study(parse_study(tiny_study_text))
    out = write_report(result, tmp_path)
    before = {p.name: p.read_bytes() for p in out.iterdir()}

    def fail_png(fig, path, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(builder, "write_png", fail_png)  # what every writer draws with
    with pytest.raises(ReportError, match="No space left"):
        write_report(result, tmp_path, command="second run")
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    # nothing left behind but the report and the index of the first run
    assert sorted(p.name for p in tmp_path.iterdir()) == ["index.md", "tiny"]
