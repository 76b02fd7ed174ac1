"""The ``designlab`` command.

``designlab run STUDY.yaml [--executor serial|processes|dask] [--resume]``
    Validate and run a study and write its report to
    ``<output-dir>/<study name>/`` (default output dir: ``reports``) and
    ``<output-dir>/index.md``. Finished chunks of sweep points are kept in
    the result store ``<cache-dir>/<study name>.sqlite`` as they finish.
``designlab report STUDY.yaml``
    Rebuild a report from the result store, computing nothing (a kind that
    keeps no store, one without sweeps, is recomputed, and says so).
``designlab validate STUDY.yaml ...``
    Check study files as ``run`` does before computing, without running them.
``designlab list``
    List the studies in ``./studies``, what each produces and how long its last
    run on this machine took (its run record, kept in the user cache directory) and its
    kind's typical duration.
``designlab schema``
    Print the JSON Schema of study files.
``designlab compile [--only STEP]``
    Compile ahead the numba kernels and the navigation step (cached on disk), so
    that no later run pays the compilation.
``designlab docs [--build]``
    Build and serve the documentation site (a source checkout with the docs extra).
``designlab --version``
    Print the version.

Exit codes: 0 success (failed sweep points are listed in the report and as
warnings); 1 a designlab error other than a bad study (a model or solver
failure, a report or cache that cannot be written); 2 an invalid study file or parameter
or bad command-line usage; 3 the executor cannot start (e.g. an unreachable
Dask scheduler) or lost its workers during the run (finished points stay
cached: rerun with ``--resume``); 4 ``report``: points missing from the cache;
130 interrupted (a sweep's finished points stay cached: rerun with ``--resume``).
"""

from __future__ import annotations

import logging
import shlex
import sys
import time
from pathlib import Path
from typing import Annotated, Any, NoReturn

import typer

from designlab import __version__
from designlab.errors import DesignlabError, InvalidParameterError, StudyError

__all__ = [
    "EXIT_CACHE_INCOMPLETE",
    "EXIT_DESIGNLAB_ERROR",
    "EXIT_EXECUTOR_ERROR",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "EXIT_STUDY_ERROR",
    "app",
    "main",
]

EXIT_OK = 0
EXIT_DESIGNLAB_ERROR = 1
EXIT_STUDY_ERROR = 2
EXIT_EXECUTOR_ERROR = 3
EXIT_CACHE_INCOMPLETE = 4
EXIT_INTERRUPTED = 130

#: Where sweep points are cached unless ``--cache-dir`` says otherwise.
DEFAULT_CACHE_DIR = Path(".designlab-cache")

#: ``designlab --help``'s end: examples and the exit codes (``\b``: click keeps the lines).
EPILOG = f"""\b
Examples:
  designlab run studies/zeng_ch4_validation.yaml       # the default study -> reports/
  designlab run studies/impact_sensitivity.yaml -e processes -j 2 --resume
  designlab validate studies/*.yaml                    # check files without running them
  designlab list                                       # the studies and their run times
  designlab compile                                    # compile ahead (once per machine)
  designlab run --help                                 # the options of one command

\b
Exit codes:
  {EXIT_OK:<4} success (failed sweep points are listed in the report and as warnings)
  {EXIT_DESIGNLAB_ERROR:<4} a designlab error other than a bad study (model, solver, report, cache)
  {EXIT_STUDY_ERROR:<4} an invalid study file or parameter, or bad command-line usage
  {EXIT_EXECUTOR_ERROR:<4} the executor cannot start or lost its workers (rerun with --resume)
  {EXIT_CACHE_INCOMPLETE:<4} report: points missing from the cache
  {EXIT_INTERRUPTED:<4} interrupted (a sweep's finished points stay cached: --resume)
"""

app = typer.Typer(
    name="designlab",
    help="Design studies for human-friendly robots: run YAML studies, write reports.",
    epilog=EPILOG,
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)


def _fail(exc: DesignlabError) -> NoReturn:
    from designlab.analysis.engine import CacheIncompleteError
    from designlab.analysis.executors import ExecutorError

    code = EXIT_DESIGNLAB_ERROR
    if isinstance(exc, StudyError | InvalidParameterError):  # bad input, found late
        code = EXIT_STUDY_ERROR
    elif isinstance(exc, ExecutorError):
        code = EXIT_EXECUTOR_ERROR
    elif isinstance(exc, CacheIncompleteError):
        code = EXIT_CACHE_INCOMPLETE
    typer.echo(f"error: {exc}", err=True)
    raise typer.Exit(code)


def _usage(message: str) -> NoReturn:
    typer.echo(f"error: {message}", err=True)
    raise typer.Exit(EXIT_STUDY_ERROR)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"designlab {__version__}")
        raise typer.Exit(EXIT_OK)


@app.callback()
def _main(
    version: Annotated[
        bool,
        typer.Option(
            "--version", callback=_version, is_eager=True, help="Print the version and exit."
        ),
    ] = False,
    verbose: Annotated[
        bool, typer.Option("--verbose", "-v", help="Log progress details to stderr.")
    ] = False,
) -> None:
    """Design studies for human-friendly robots: run YAML studies, write reports."""
    logging.basicConfig(
        level=logging.INFO if verbose else logging.WARNING,
        format="%(levelname)s: %(name)s: %(message)s",
        stream=sys.stderr,
        force=True,
    )


_CacheDir = Annotated[
    Path,
    typer.Option(
        "--cache-dir", help="Finished sweep points are kept in CACHE_DIR/<study name>.sqlite."
    ),
]
_OutputDir = Annotated[
    Path,
    typer.Option("--output-dir", "-o", help="Reports go to OUTPUT_DIR/<study name>/."),
]


def _write(
    result: object, study: Path, output_dir: Path, command: list[str], *, keep_current: bool = False
) -> bool:
    """Write the report (unless ``keep_current`` and it is up to date); whether it was written."""
    from designlab.report import current_report, write_report
    from designlab.yamlio import read_text_file

    text = read_text_file(study)  # read as the study was (it may have changed since: a clear error)
    record = current_report(result, output_dir, study_text=text) if keep_current else None
    kept = record is not None
    if record is not None:  # the report's own record: its warnings are not recomputed
        out = output_dir / result.study.name  # type: ignore[attr-defined]
        warnings, status = record.get("warnings", []), record.get("status", "ok")
    else:
        out = write_report(result, output_dir, command=shlex.join(command), study_text=text)
        warnings, status = result.warnings, result.status  # type: ignore[attr-defined]
    for warning in warnings:
        typer.echo(f"warning: {warning}", err=True)
    if status != "ok":
        typer.echo(f"status: {status} (see the report)", err=True)
    if kept:
        typer.echo(f"report up to date: {out}/ (same points, code and study; not rewritten)")
    else:
        files = sorted(p.name for p in out.iterdir() if not p.name.startswith("."))
        shown = ", ".join(files) if len(files) <= 6 else ", ".join(files[:5]) + ", ..."
        typer.echo(f"wrote {out}/ ({shown})")
    stats = getattr(result, "stats", None)
    if stats:
        merged = stats["points"] - stats.get("distinct", stats["points"])
        dup = f", {merged} duplicates merged" if merged else ""
        typer.echo(
            f"points: {stats['points']} ({stats['computed']} computed, {stats['cached']} "
            f"from the store, {stats['failed']} failed{dup}) on {stats['executor']}"
        )
    return not kept


def _record_duration(directory: Path, seconds: float, executor: str) -> None:
    """Keep the run's wall time in its run record, for ``designlab list`` (best effort)."""
    from designlab.report.builder import record_run

    try:
        record_run(directory, seconds, executor=executor)
    except OSError as exc:  # the report is written; a missing record only costs a list line
        logging.getLogger("designlab").info("run time of %s not recorded: %s", directory, exc)


def _duration_text(spec: object, report: Path) -> str:
    """``designlab list``'s duration: the kind's typical run time and the last run's."""
    from designlab.report.builder import format_duration, recorded_run

    parts = []
    typical = spec.typical_duration()  # type: ignore[attr-defined]
    if typical:
        kind = spec.kind  # type: ignore[attr-defined]
        parts.append(f"{kind} studies typically take {format_duration(typical)}")
    seconds = recorded_run(report)
    if seconds is not None:
        parts.append(f"last run took {format_duration(seconds)}")
    return "; ".join(parts) or "run time not measured yet on this machine (kept after a run)"


def _check_executor_options(executor: str, scheduler: str | None, timeout: float) -> None:
    """Refuse unknown executors, a bad ``--timeout`` or ``--scheduler`` (exit 2)."""
    from designlab.analysis.executors import EXECUTORS, check_scheduler_address
    from designlab.study import did_you_mean

    if executor not in EXECUTORS:
        _usage(
            f"--executor {executor!r} is not known{did_you_mean(executor, EXECUTORS)} "
            f"(known: {', '.join(EXECUTORS)})"
        )
    if not (timeout > 0 and timeout < 86400):
        _usage(f"--timeout {timeout!r} is not allowed: give seconds > 0 (and < 86400)")
    if scheduler is not None:
        if executor != "dask":
            _usage("--scheduler is only used with --executor dask")
        problem = check_scheduler_address(scheduler)
        if problem:
            _usage(f"--scheduler {scheduler!r} is not a scheduler address: {problem}")


@app.command()
def run(
    study: Annotated[Path, typer.Argument(help="The study file (YAML).", show_default=False)],
    output_dir: _OutputDir = Path("reports"),
    executor: Annotated[
        str,
        typer.Option("--executor", "-e", help="serial, processes or dask (sweep studies)."),
    ] = "serial",
    workers: Annotated[
        int | None,
        typer.Option("--workers", "-j", min=1, help="Worker processes (default: CPU count)."),
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            help="Dask scheduler address, e.g. tcp://host:8786 (default: a LocalCluster).",
        ),
    ] = None,
    resume: Annotated[
        bool, typer.Option("--resume", help="Reuse cached points; compute only missing ones.")
    ] = False,
    cache_dir: _CacheDir = DEFAULT_CACHE_DIR,
    timeout: Annotated[
        float,
        typer.Option("--timeout", help="Seconds (> 0) to wait for the Dask scheduler."),
    ] = 5.0,
    worker_timeout: Annotated[
        float,
        typer.Option(
            "--worker-timeout",
            help="Seconds (> 0) a Dask run waits while no worker is alive before failing.",
        ),
    ] = 60.0,
) -> None:
    """Run a study and write its report (CSV, Markdown, PNG)."""
    from designlab.analysis.executors import make_executor
    from designlab.study import RunContext, load_study, run_study

    _check_executor_options(executor, scheduler, timeout)
    if not (worker_timeout > 0 and worker_timeout < 86400):
        _usage(f"--worker-timeout {worker_timeout!r} is not allowed: give seconds > 0 (< 86400)")
    command = _command_line("run", study, output_dir, cache_dir, executor=(executor, "serial"),
                            workers=(workers, None), scheduler=(scheduler, None),
                            resume=(resume, False), timeout=(timeout, 5.0),
                            worker_timeout=(worker_timeout, 60.0))  # fmt: skip
    keeps_store = False
    try:
        spec = load_study(study)
        keeps_store = _keeps_store(spec)
        ex = None
        if executor != "serial" or scheduler is not None or workers is not None:
            ex = make_executor(executor, workers=workers, scheduler=scheduler, timeout=timeout,
                               worker_timeout=worker_timeout)  # fmt: skip
        logging.getLogger("designlab").info(
            "study %s (kind %s) on %s%s", spec.name, spec.kind,
            ex.describe() if ex is not None else "serial", " (resume)" if resume else "",
        )  # fmt: skip
        store = _open_store(cache_dir, spec) if keeps_store else None
        try:
            context = RunContext(
                progress=sys.stderr.isatty(), executor=ex, store=store, resume=resume
            )
            started = time.monotonic()
            result = run_study(spec, context)
        finally:
            if store is not None:
                store.close()
            if ex is not None:
                ex.close()
        if _write(result, study, output_dir, command, keep_current=resume):
            _record_duration(output_dir / spec.name, time.monotonic() - started, executor)
    except DesignlabError as exc:
        _fail(exc)
    except MemoryError:
        typer.echo(
            f"error: {study}: the study needs more memory than this machine can give; "
            "make it smaller (its sizes, durations or sample rates)",
            err=True,
        )
        raise typer.Exit(EXIT_DESIGNLAB_ERROR) from None
    except KeyboardInterrupt:
        kept = (
            f"finished points are kept in {cache_dir}/; no report was written. Run the same "
            "command with --resume to finish."
            if keeps_store
            else "no report was written and nothing was kept (this kind keeps no partial "
            "results): run it again."
        )
        typer.echo(f"interrupted: {kept}", err=True)
        raise typer.Exit(EXIT_INTERRUPTED) from None


def _command_line(
    name: str, study: Path, output_dir: Path, cache_dir: Path, **options: tuple[Any, Any]
) -> list[str]:
    """The command as run, for the report's provenance: every option given that is not the
    default (``options``: name -> (value, default)), so that it reproduces the run."""
    command = ["designlab", name, str(study), "--output-dir", str(output_dir)]
    if cache_dir != DEFAULT_CACHE_DIR:
        command += ["--cache-dir", str(cache_dir)]
    for option, (value, default) in options.items():
        flag = "--" + option.replace("_", "-")
        if value == default:
            continue
        command += [flag] if isinstance(value, bool) else [flag, str(value)]
    return command


def _keeps_store(spec: Any) -> bool:
    """Whether a study's kind keeps finished points in a result store (the sweep kinds, and
    a kind that says so with ``KEEPS_STORE``: the crowd studies' runs)."""
    from designlab.study.sweeps import SweepStudyBase

    return isinstance(spec, SweepStudyBase) or bool(getattr(spec, "KEEPS_STORE", False))


def _open_store(cache_dir: Path, spec: Any) -> Any:
    """The study's result store (opened on first use), bound to its name and kind."""
    from designlab.analysis.store import open_store

    return open_store(cache_dir, spec.name, spec.kind)


@app.command()
def report(
    study: Annotated[Path, typer.Argument(help="The study file (YAML).", show_default=False)],
    output_dir: _OutputDir = Path("reports"),
    cache_dir: _CacheDir = DEFAULT_CACHE_DIR,
) -> None:
    """Rebuild a study's report from the result store, without computing any point."""
    from designlab.analysis.engine import CacheIncompleteError
    from designlab.analysis.store import StoreError
    from designlab.study import RunContext, load_study, run_study

    command = _command_line("report", study, output_dir, cache_dir)
    try:
        spec = load_study(study)
        if not _keeps_store(spec):
            typer.echo(
                f"kind {spec.kind} keeps no result store: recomputing "
                "the report, as `designlab run` does",
                err=True,
            )
            _write(run_study(spec, RunContext(progress=sys.stderr.isatty())), study,
                   output_dir, command)  # fmt: skip
            return
        store = _open_store(cache_dir, spec)
        if not store.path.exists() and not store.path.is_symlink():
            raise CacheIncompleteError(
                f"no result store {store.path}; run the study first (designlab run {study})"
            )
        if not store.path.is_symlink() and store.path.is_file() and store.path.stat().st_size == 0:
            raise StoreError(
                f"{store.path} is an empty file, not a designlab result store; move it away "
                f"or choose another --cache-dir (`designlab report` never creates a store)"
            )
        try:
            result = run_study(spec, RunContext(store=store, cache_only=True))
        finally:
            store.close()
        _write(result, study, output_dir, command)
    except DesignlabError as exc:
        _fail(exc)


@app.command("compile")
def compile_code(
    only: Annotated[
        list[str] | None,
        typer.Option("--only", help="A step to run: impact, sampling or navigation (repeatable)."),
    ] = None,
) -> None:
    """Compile ahead what designlab compiles on first use, so later runs only load it.

    The numba kernels and the navigation step in C are compiled by the first call that
    needs them and cached on disk; run this once after installing (each step says what
    it compiles and how long it took; a step already in the cache only loads).
    """
    from designlab.warm import compile_all

    try:
        compile_all(tuple(only) if only else None, say=typer.echo)
    except ValueError as exc:
        _usage(str(exc))


@app.command()
def schema(
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write to a file instead of stdout.")
    ] = None,
) -> None:
    """Print the JSON Schema of study files (for editors and CI)."""
    import json

    from designlab.study import study_json_schema

    text = json.dumps(study_json_schema(), indent=2) + "\n"
    if output is None:
        typer.echo(text, nl=False)
        return
    from designlab.report import atomic_write_text

    try:
        atomic_write_text(output, text)
    except OSError as exc:
        typer.echo(f"error: cannot write {output}: {exc}", err=True)
        raise typer.Exit(EXIT_DESIGNLAB_ERROR) from None
    typer.echo(f"wrote {output}")


@app.command()
def validate(
    studies: Annotated[
        list[Path], typer.Argument(help="Study files (YAML) to check.", show_default=False)
    ],
) -> None:
    """Check study files as `run` does before computing (schema, domain rules, caps)."""
    from designlab.study import load_study

    code = EXIT_OK
    for path in studies:
        try:
            spec = load_study(path)
        except StudyError as exc:
            code = max(code, EXIT_STUDY_ERROR)
            typer.echo(f"error: {exc}", err=True)
            continue
        except DesignlabError as exc:  # every file is still checked
            code = max(code, EXIT_DESIGNLAB_ERROR)
            typer.echo(f"error: {path}: {exc}", err=True)
            continue
        size = spec.size()
        typer.echo(f"ok: {path} (kind {spec.kind}{', ' + size if size else ''})")
    if code:
        raise typer.Exit(code)


@app.command("list")
def list_studies(
    studies_dir: Annotated[
        Path, typer.Option("--studies-dir", help="Where to look for *.yaml studies.")
    ] = Path("studies"),
    output_dir: Annotated[
        Path, typer.Option("--output-dir", "-o", help="Where `run` writes reports.")
    ] = Path("reports"),
) -> None:
    """List the studies in ./studies, what each produces and how long it takes to run."""
    from designlab.study import load_study

    if not studies_dir.is_dir():
        typer.echo(f"error: {studies_dir}: no such directory", err=True)
        raise typer.Exit(EXIT_STUDY_ERROR)
    files = sorted([*studies_dir.glob("*.yaml"), *studies_dir.glob("*.yml")])
    if not files:
        typer.echo(f"no studies in {studies_dir}/")
        return
    invalid = False
    for path in files:
        try:
            spec = load_study(path)
        except StudyError as exc:
            invalid = True
            typer.echo(f"{path}\n    INVALID: {exc}\n")
            continue
        summary = spec.description.strip().splitlines()[0] if spec.description.strip() else ""
        produces = ", ".join(type(spec).PRODUCES)
        typer.echo(f"{path}  [{spec.kind}]")
        if summary:
            typer.echo(f"    {summary}")
        typer.echo(f"    -> {output_dir / spec.name}/: {produces}")
        typer.echo(f"    {_duration_text(spec, output_dir / spec.name)}\n")
    if invalid:
        raise typer.Exit(EXIT_STUDY_ERROR)


#: The documentation site's configuration (a source checkout: the site is built from docs/).
MKDOCS_CONFIG = Path(__file__).resolve().parent.parent / "mkdocs.yml"


@app.command()
def docs(
    build: Annotated[
        bool, typer.Option("--build", help="Build the site strictly into --site-dir; no server.")
    ] = False,
    site_dir: Annotated[Path, typer.Option("--site-dir", help="Where --build writes.")] = Path(
        "site"
    ),
    open_browser: Annotated[
        bool, typer.Option("--open/--no-open", help="Open the served site in a browser.")
    ] = True,
    dev_addr: Annotated[str, typer.Option("--dev-addr", help="Serve at IP:PORT.")] = (
        "127.0.0.1:8000"
    ),
) -> None:
    """Build and serve the documentation site (`mkdocs serve`); needs the docs extra."""
    import importlib.util
    import os
    import subprocess

    if not MKDOCS_CONFIG.is_file():
        typer.echo(f"error: {MKDOCS_CONFIG} not found: the site builds from a checkout", err=True)
        raise typer.Exit(EXIT_DESIGNLAB_ERROR)
    if importlib.util.find_spec("mkdocs") is None:
        typer.echo("error: the site needs the docs tools: pip install -e '.[docs]'", err=True)
        raise typer.Exit(EXIT_DESIGNLAB_ERROR)
    mkdocs = [sys.executable, "-m", "mkdocs"]
    if build:
        command = [*mkdocs, "build", "--strict", "--site-dir", str(site_dir.resolve())]
    else:
        command = [*mkdocs, "serve", "--dev-addr", dev_addr, *(["--open"] if open_browser else [])]
    command += ["--config-file", str(MKDOCS_CONFIG)]
    env = {**os.environ, "DISABLE_MKDOCS_2_WARNING": "true", "NO_MKDOCS_2_WARNING": "1"}
    try:
        code = subprocess.run(command, cwd=MKDOCS_CONFIG.parent, env=env, check=False).returncode
    except KeyboardInterrupt:  # stopping the server is the normal end of `serve`
        code = EXIT_OK
    raise typer.Exit(code)


def main() -> None:  # pragma: no cover - console entry point alternative
    """Entry point (``python -m designlab.cli``)."""
    app()


if __name__ == "__main__":  # pragma: no cover
    main()
