"""The designlab command, through typer's CliRunner."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

import designlab
from designlab.cli import EXIT_DESIGNLAB_ERROR, EXIT_STUDY_ERROR, app
from designlab.report import ReportError

runner = CliRunner()


def test_version():
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0
    assert result.stdout.strip() == f"designlab {designlab.__version__}"


def test_validate_ok_and_bad(write_study, tiny_study_text):
    good = write_study(tiny_study_text, "good.yaml")
    result = runner.invoke(app, ["validate", str(good)])
    assert result.exit_code == 0, result.output
    assert f"ok: {good} (kind impact_cases, 2 cases)" in result.stdout

    bad = write_study(tiny_study_text.replace("    foam: FOAM_1", "    fom: FOAM_1"), "bad.yaml")
    result = runner.invoke(app, ["validate", str(good), str(bad)])
    assert result.exit_code == EXIT_STUDY_ERROR
    assert f"error: {bad}:8: cases[0].fom: unknown field; did you mean 'foam'?" in result.stderr
    assert result.stderr.count("error:") == 1


def test_validate_missing_file(tmp_path):
    result = runner.invoke(app, ["validate", str(tmp_path / "nope.yaml")])
    assert result.exit_code == EXIT_STUDY_ERROR
    assert "study file not found" in result.stderr


def test_run_writes_report(write_study, tiny_study_text, tmp_path):
    study = write_study(tiny_study_text, "tiny.yaml")
    out = tmp_path / "out"
    result = runner.invoke(app, ["run", str(study), "--output-dir", str(out)])
    assert result.exit_code == 0, result.output
    assert f"wrote {out / 'tiny'}/" in result.stdout
    assert (out / "tiny" / "study.yaml").read_text() == tiny_study_text
    summary = (out / "tiny" / "summary.md").read_text()
    assert f"`designlab run {study} --output-dir {out}`" in summary
    assert result.stderr == ""  # no progress bar when stderr is not a terminal


def test_run_bad_study_exits_2_and_writes_nothing(write_study, tmp_path):
    study = write_study("designlab: 1\nkind: impact_cases\nname: x\ncases: 3\n")
    result = runner.invoke(app, ["run", str(study), "-o", str(tmp_path / "out")])
    assert result.exit_code == EXIT_STUDY_ERROR
    assert f"{study}:4: cases: Input should be a valid list" in result.stderr
    assert not (tmp_path / "out").exists()


def test_run_other_designlab_error_exits_1(write_study, tiny_study_text, tmp_path, monkeypatch):
    import designlab.report

    def fail(*args, **kwargs):
        raise ReportError("cannot write the report: read-only file system")

    monkeypatch.setattr(designlab.report, "write_report", fail)
    study = write_study(tiny_study_text)
    result = runner.invoke(app, ["run", str(study), "-o", str(tmp_path)])
    assert result.exit_code == EXIT_DESIGNLAB_ERROR
    assert "error: cannot write the report" in result.stderr


def test_list(tmp_path, write_study, tiny_study_text, monkeypatch):
    studies = tmp_path / "studies"
    studies.mkdir()
    (studies / "tiny.yaml").write_text(tiny_study_text)
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(app, ["list"])
    assert result.exit_code == 0, result.output
    assert "studies/tiny.yaml  [impact_cases]" in result.stdout
    assert "Two impacts of the direct-drive arm" in result.stdout
    assert "-> reports/tiny/: summary.md, metrics.csv" in result.stdout

    (studies / "broken.yaml").write_text("designlab: 1\nkind: nope\nname: b\n")
    result = runner.invoke(app, ["list"])
    assert result.exit_code == EXIT_STUDY_ERROR
    assert "INVALID" in result.stdout and "studies/tiny.yaml" in result.stdout


def test_list_repository_studies(repo_root, monkeypatch):
    monkeypatch.chdir(repo_root)
    result = runner.invoke(app, ["list"])
    assert result.exit_code == 0, result.output
    assert "studies/zeng_ch4_validation.yaml" in result.stdout


@pytest.mark.parametrize("args", [[], ["run"], ["frobnicate"]])
def test_usage_errors_exit_2(args):
    assert runner.invoke(app, args).exit_code == 2
