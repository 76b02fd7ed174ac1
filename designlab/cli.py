"""The ``designlab`` command.

``designlab run STUDY.yaml``
    Validate and run a study and write its report to
    ``<output-dir>/<study name>/`` (default output dir: ``reports``).
``designlab validate STUDY.yaml ...``
    Check study files against the schema without running them.
``designlab list``
    List the studies in ``./studies`` and what each produces.
``designlab --version``
    Print the version.

Exit codes: 0 success; 1 a designlab error other than a bad study (a model
or solver failure, a report that cannot be written); 2 an invalid study file
or bad command-line usage.
"""

from __future__ import annotations

import logging
import shlex
import sys
from pathlib import Path
from typing import Annotated, NoReturn

import typer

from designlab import __version__
from designlab.errors import DesignlabError, StudyError

__all__ = ["EXIT_DESIGNLAB_ERROR", "EXIT_OK", "EXIT_STUDY_ERROR", "app", "main"]

EXIT_OK = 0
EXIT_DESIGNLAB_ERROR = 1
EXIT_STUDY_ERROR = 2

app = typer.Typer(
    name="designlab",
    help="Design studies for human-friendly robots: run YAML studies, write reports.",
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)


def _fail(exc: DesignlabError) -> NoReturn:
    code = EXIT_STUDY_ERROR if isinstance(exc, StudyError) else EXIT_DESIGNLAB_ERROR
    typer.echo(f"error: {exc}", err=True)
    raise typer.Exit(code)


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


@app.command()
def run(
    study: Annotated[Path, typer.Argument(help="The study file (YAML).", show_default=False)],
    output_dir: Annotated[
        Path,
        typer.Option("--output-dir", "-o", help="Reports go to OUTPUT_DIR/<study name>/."),
    ] = Path("reports"),
) -> None:
    """Run a study and write its report (CSV, Markdown, PNG)."""
    from designlab.report import write_report
    from designlab.study import load_study, run_study

    try:
        spec = load_study(study)
        text = study.read_text(encoding="utf-8")
        result = run_study(spec, progress=sys.stderr.isatty())
        command = shlex.join(["designlab", "run", str(study), "--output-dir", str(output_dir)])
        out = write_report(result, output_dir, command=command, study_text=text)
    except DesignlabError as exc:
        _fail(exc)
    for warning in getattr(result, "warnings", []):
        typer.echo(f"warning: {warning}", err=True)
    files = ", ".join(sorted(p.name for p in out.iterdir()))
    typer.echo(f"wrote {out}/ ({files})")


@app.command()
def validate(
    studies: Annotated[
        list[Path], typer.Argument(help="Study files (YAML) to check.", show_default=False)
    ],
) -> None:
    """Check study files against the schema, without running them."""
    from designlab.study import load_study

    failed: list[StudyError] = []
    for path in studies:
        try:
            spec = load_study(path)
        except StudyError as exc:
            failed.append(exc)
            typer.echo(f"error: {exc}", err=True)
            continue
        n = len(getattr(spec, "cases", ()))
        detail = f", {n} case{'s' if n != 1 else ''}" if n else ""
        typer.echo(f"ok: {path} (kind {spec.kind}{detail})")
    if failed:
        raise typer.Exit(EXIT_STUDY_ERROR)


@app.command("list")
def list_studies(
    studies_dir: Annotated[
        Path, typer.Option("--studies-dir", help="Where to look for *.yaml studies.")
    ] = Path("studies"),
    output_dir: Annotated[
        Path, typer.Option("--output-dir", "-o", help="Where `run` writes reports.")
    ] = Path("reports"),
) -> None:
    """List the studies in ./studies and what each produces."""
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
        typer.echo(f"    -> {output_dir / spec.name}/: {produces}\n")
    if invalid:
        raise typer.Exit(EXIT_STUDY_ERROR)


def main() -> None:  # pragma: no cover - console entry point alternative
    """Entry point (``python -m designlab.cli``)."""
    app()


if __name__ == "__main__":  # pragma: no cover
    main()
