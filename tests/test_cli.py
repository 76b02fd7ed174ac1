"""The designlab command, through typer's CliRunner."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

import designlab
from designlab.cli import (
    EXIT_CACHE_INCOMPLETE,
    EXIT_DESIGNLAB_ERROR,
    EXIT_EXECUTOR_ERROR,
    EXIT_STUDY_ERROR,
    app,
)
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
    assert "impact_cases studies typically take " in result.stdout
    assert "last run took" not in result.stdout
    assert runner.invoke(app, ["run", "studies/tiny.yaml"]).exit_code == 0
    result = runner.invoke(app, ["list"])
    assert "typically take " in result.stdout and "; last run took " in result.stdout
    assert not list((tmp_path / "reports" / "tiny").glob(".designlab-run*"))

    (studies / "broken.yaml").write_text("designlab: 1\nkind: nope\nname: b\n")
    result = runner.invoke(app, ["list"])
    assert result.exit_code == EXIT_STUDY_ERROR
    assert "INVALID" in result.stdout and "studies/tiny.yaml" in result.stdout


def test_list_repository_studies(repo_root, monkeypatch, tmp_path):
    monkeypatch.chdir(repo_root)
    result = runner.invoke(app, ["list", "-o", str(tmp_path)])  # no report: no last run
    assert result.exit_code == 0, result.output
    assert "studies/zeng_ch4_validation.yaml" in result.stdout
    blocks = [b for b in result.stdout.split("\n\n") if b.strip()]
    assert len(blocks) == len(list((repo_root / "studies").glob("*.yaml")))
    for block in blocks:  # every committed study shows its kind's measured duration
        assert " studies typically take " in block, block


def test_every_kind_states_its_measured_duration():
    """One place per kind (``TYPICAL_DURATION``), in seconds, for ``designlab list``."""
    from designlab.report.builder import format_duration
    from designlab.study.registry import kind_of, study_kinds

    for name in study_kinds():
        seconds = kind_of(name).schema.TYPICAL_DURATION
        assert 0 < seconds < 3600, name
        assert format_duration(seconds)


@pytest.mark.parametrize("args", [[], ["run"], ["frobnicate"]])
def test_usage_errors_exit_2(args):
    assert runner.invoke(app, args).exit_code == 2


SWEEP_STUDY = """\
designlab: 1
kind: impact_sweep
name: cli_sweep
description: Foam stiffness against head acceleration.
base: {robot: MANIPULATOR_1, foam: FOAM_1, head: HEAD_MIN, impact_velocity: 1.25}
sweep:
  method: grid
  parameters:
    foam.stiffness: {low: 10e3, high: 60e3, num: 4}
sensitivity: {metrics: [a_h_max_g], one_at_a_time: {deltas_pct: [-10, 10]}}
"""


def test_sweep_run_report_and_index(write_study, tmp_path):
    study = write_study(SWEEP_STUDY, "sweep.yaml")
    out, cache = tmp_path / "out", tmp_path / "cache"
    result = runner.invoke(app, ["validate", str(study)])
    assert f"ok: {study} (kind impact_sweep, 10 points)" in result.stdout
    args = ["run", str(study), "-o", str(out), "--cache-dir", str(cache)]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert (
        "points: 10 (8 computed, 0 from the store, 0 failed, 2 duplicates merged) on serial"
        in result.stdout
    )
    summary = (out / "cli_sweep" / "summary.md").read_text()
    command = f"designlab run {study} --output-dir {out} --cache-dir {cache}"
    assert f"`{command}` with designlab" in summary
    assert "### Local elasticities at the base design" in summary
    assert (out / "cli_sweep" / "tornado_a_h_max_g.png").is_file()
    index = (out / "index.md").read_text()
    assert (
        "| [cli_sweep](cli_sweep/summary.md) | Foam stiffness against head acceleration. |" in index
    )
    before = (out / "cli_sweep" / "results.csv").read_text()
    # rebuild from the cache: nothing computed, same numbers
    result = runner.invoke(app, ["report", str(study), "-o", str(out), "--cache-dir", str(cache)])
    assert result.exit_code == 0, result.output
    assert "(0 computed, 8 from the store, 0 failed, 2 duplicates merged)" in result.stdout
    assert (out / "cli_sweep" / "results.csv").read_text() == before
    # an empty cache: exit 4, report left as it was
    result = runner.invoke(
        app, ["report", str(study), "-o", str(out), "--cache-dir", str(tmp_path)]
    )
    assert result.exit_code == EXIT_CACHE_INCOMPLETE
    assert "no result store" in result.stderr and "run the study first" in result.stderr
    assert (out / "cli_sweep" / "results.csv").read_text() == before


def test_run_executor_errors(write_study, tmp_path):
    study = write_study(SWEEP_STUDY, "sweep.yaml")
    result = runner.invoke(app, ["run", str(study), "-o", str(tmp_path), "-e", "proceses"])
    assert result.exit_code == EXIT_STUDY_ERROR
    assert "--executor 'proceses' is not known; did you mean 'processes'?" in result.stderr
    pytest.importorskip("distributed", reason="dask[distributed] is not installed")
    args = ["run", str(study), "-o", str(tmp_path), "--executor", "dask",
            "--scheduler", "tcp://127.0.0.1:9", "--timeout", "1"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == EXIT_EXECUTOR_ERROR
    assert "error: cannot reach the Dask scheduler at tcp://127.0.0.1:9 within 1 s" in result.stderr
    assert not (tmp_path / "cli_sweep").exists()


def test_schema_export(tmp_path):
    import json

    result = runner.invoke(app, ["schema"])
    assert result.exit_code == 0
    schema = json.loads(result.stdout)
    assert {"impact_cases", "impact_sweep", "foam_envelope_sweep", "foam_design"} <= set(
        schema["discriminator"]["mapping"]
    )
    params = schema["$defs"]["ImpactSweepParameters"]
    assert params["additionalProperties"] is False
    assert params["properties"]["foam.stiffness"]["description"] == "foam stiffness K_c, N/m"
    result = runner.invoke(app, ["schema", "-o", str(tmp_path / "s.json")])
    assert json.loads((tmp_path / "s.json").read_text()) == schema


def test_every_example_study_validates(repo_root):
    studies = sorted((repo_root / "studies").glob("*.yaml"))
    result = runner.invoke(app, ["validate", *map(str, studies)])
    assert result.exit_code == 0, result.output


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--executor", "dask", "--scheduler", "nonsense"],
         "--scheduler 'nonsense' is not a scheduler address: give PROTOCOL://HOST:PORT"),
        (["--executor", "dask", "--scheduler", "tcp://h:99999"], "the port must be 1-65535"),
        (["--scheduler", "tcp://h:8786"], "--scheduler is only used with --executor dask"),
        (["--timeout", "-5"], "--timeout -5.0 is not allowed: give seconds > 0"),
        (["--timeout", "nan"], "--timeout nan is not allowed"),
    ],
)  # fmt: skip
def test_run_rejects_bad_executor_options_cleanly(write_study, tmp_path, extra, message):
    study = write_study(SWEEP_STUDY, "sweep.yaml")
    result = runner.invoke(app, ["run", str(study), "-o", str(tmp_path), *extra])
    assert result.exit_code == EXIT_STUDY_ERROR, result.output
    assert message in result.stderr
    assert "Traceback" not in result.output


def test_validate_checks_every_file_after_a_hostile_one(tmp_path, write_study, tiny_study_text):
    deep = tmp_path / "deep.yaml"
    deep.write_text("designlab: 1\nkind: impact_cases\nname: d\ncases: " + "[" * 5000 + "]" * 5000)
    good = write_study(tiny_study_text)
    result = runner.invoke(app, ["validate", str(deep), str(good)])
    assert result.exit_code == EXIT_STUDY_ERROR
    assert "deep.yaml:4: " in result.output and "levels deep" in result.output
    assert f"ok: {good}" in result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)


def test_index_md_directory_is_a_clear_report_error(tmp_path):
    from designlab.report import write_index

    (tmp_path / "index.md").mkdir()
    with pytest.raises(ReportError, match="is a directory"):
        write_index(tmp_path)


def test_summary_names_every_option_of_the_run(write_study, tiny_study_text, tmp_path):
    """The report's command line reproduces the run: -j 2, --cache-dir, --resume, timeouts."""
    study = write_study(tiny_study_text, "tiny.yaml")
    out, cache = tmp_path / "out", tmp_path / "cache"
    args = ["run", str(study), "-o", str(out), "--cache-dir", str(cache), "-j", "2",
            "--resume", "--worker-timeout", "30"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    summary = (out / "tiny" / "summary.md").read_text()
    assert (
        f"`designlab run {study} --output-dir {out} --cache-dir {cache} --workers 2 --resume "
        "--worker-timeout 30.0`" in summary
    ), summary


@pytest.mark.parametrize("umask", [0o077, 0o002])
def test_reports_follow_the_umask(write_study, tiny_study_text, tmp_path, umask):
    import os
    import stat

    study = write_study(tiny_study_text, "tiny.yaml")
    out = tmp_path / "out"
    old = os.umask(umask)
    try:
        result = runner.invoke(app, ["run", str(study), "--output-dir", str(out)])
    finally:
        os.umask(old)
    assert result.exit_code == 0, result.output
    written = [p for p in (out / "tiny").rglob("*")] + [out / "tiny", out / "index.md"]
    for path in written:
        mode = stat.S_IMODE(path.stat().st_mode)
        full = 0o777 if path.is_dir() else 0o666
        assert mode == full & ~umask, (path, oct(mode))


@pytest.mark.parametrize(
    ("make", "message"),
    [
        ("fifo", "is a FIFO (named pipe), not a regular file"),
        ("device", "is a character device, not a regular file"),
        ("nul", "a NUL byte at character"),
        ("digits", "written with 5,000 characters"),
        ("duplicate", "key 'name' appears twice in the same mapping, on lines 3 and 4"),
        ("syntax", "YAML syntax error"),
    ],
)
def test_validate_and_run_refuse_hostile_files_clearly(tmp_path, make, message):
    import os

    path = tmp_path / "s.yaml"
    head = "designlab: 1\nkind: impact_cases\nname: t\n"
    if make == "fifo":
        os.mkfifo(path)
    elif make == "device":
        path = "/dev/zero"
    else:
        text = {
            "nul": head + "description: a\x00b\n",
            "digits": head + "description: 1\nseed: " + "7" * 5000 + "\n",
            "duplicate": head + "name: u\n",
            "syntax": head + "cases: [\n",
        }[make]
        path.write_text(text, encoding="utf-8")
    for command in (["validate", str(path)], ["run", str(path), "-o", str(tmp_path / "r")]):
        result = runner.invoke(app, command)
        assert result.exit_code == EXIT_STUDY_ERROR, result.output
        assert result.exception is None or isinstance(result.exception, SystemExit)
        assert f"error: {path}" in result.stderr and message in result.stderr, result.stderr
    assert not (tmp_path / "r").exists()


def test_run_records_stay_outside_the_report_and_on_their_host(tmp_path, monkeypatch):
    """A run leaves no file of its own in the report; a record from another host is not shown."""
    import platform

    from designlab.report.builder import record_run, recorded_run, run_record_path

    report = tmp_path / "reports" / "tiny"
    report.mkdir(parents=True)
    path = record_run(report, 83.2, executor="serial")
    assert path is not None and report not in path.parents and list(report.iterdir()) == []
    assert path == run_record_path(report) and recorded_run(report) == 83.2
    monkeypatch.setattr(platform, "node", lambda: "another-machine")
    assert recorded_run(report) is None
