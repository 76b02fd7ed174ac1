"""Reports: the only part of designlab that writes files.

Every file is written atomically and a report directory appears all at once
(see :mod:`designlab.report.atomic`): an interrupted run leaves the previous
report as it was.

Examples
--------
>>> import tempfile, pathlib, shutil
>>> from designlab.study import parse_study, run_study
>>> from designlab.report import write_report
>>> study = parse_study('''
... designlab: 1
... kind: impact_cases
... name: demo
... cases:
...   - {robot: MANIPULATOR_1, foam: FOAM_1, head: TEST_HEAD, impact_velocity: 0.4}
... ''')
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> out = write_report(run_study(study), d)
>>> sorted(p.name for p in out.iterdir())
['metrics.csv', 'summary.md', 'time_histories.png']
>>> shutil.rmtree(d)
"""

from __future__ import annotations

import hashlib
import importlib
import json
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from designlab.analysis.keys import package_hash
from designlab.report.atomic import (
    ReportError,
    atomic_write_bytes,
    atomic_write_text,
    report_directory,
)
from designlab.report.builder import ReportParts, move_run_record, write_parts
from designlab.report.writers import (
    csv_digits,
    markdown_table,
    write_csv,
    write_markdown,
    write_png,
)

__all__ = [
    "ReportError",
    "ReportParts",
    "atomic_write_bytes",
    "atomic_write_text",
    "current_report",
    "markdown_table",
    "register_writer",
    "report_directory",
    "write_csv",
    "write_index",
    "write_markdown",
    "write_png",
    "write_report",
]


#: A report writer: ``writer(result) -> ReportParts``.
Writer = Callable[[Any], ReportParts]

_WRITERS: dict[type, Writer] = {}


def register_writer(result_type: type) -> Callable[[Writer], Writer]:
    """Decorator: register the report writer of a result type.

    A writer is called ``writer(result)`` with the study's result and returns its
    :class:`~designlab.report.builder.ReportParts`: its tables, figures and the body of its
    main page. The framework (:func:`write_report`) adds the rest: the page's header and
    provenance, its warnings, the copy of the study, the reproduction section and the index.

    Parameters
    ----------
    result_type
        The result class (subclasses use it too unless they register their own).
    """

    def deco(fn: Writer) -> Writer:
        _WRITERS[result_type] = fn
        return fn

    return deco


def writer_for(result: Any) -> Writer:
    """The registered writer of ``result``'s type (imports its kind's report module).

    Parameters
    ----------
    result
        A study result (it has ``study.kind``).
    """
    study = getattr(result, "study", None)
    if study is not None:
        from designlab.study.registry import kind_of

        try:
            importlib.import_module(kind_of(study.kind).report)
        except KeyError:
            pass
    for cls in type(result).__mro__:
        if cls in _WRITERS:
            return _WRITERS[cls]
    raise TypeError(f"no report writer is registered for {type(result).__name__}")


def write_report(
    result: Any,
    output_dir: str | os.PathLike[str],
    *,
    command: str | None = None,
    study_text: str | None = None,
    index: bool = True,
) -> Path:
    """Write the report of a study result to ``<output_dir>/<study name>/``.

    The directory is replaced as a whole, atomically: if writing fails, the
    previous report stays intact and no temporary files are left behind.

    Parameters
    ----------
    result
        A study result from :func:`designlab.study.run_study`.
    output_dir
        Parent directory of the report (created if needed).
    command
        The command line that produced the result, recorded in the report.
    study_text
        The study file's text, copied into the report as ``study.yaml``.
    index
        Also rewrite ``<output_dir>/index.md`` (:func:`write_index`).

    Returns
    -------
    Path
        The report directory.

    Raises
    ------
    ReportError
        If the report cannot be written.
    """
    from designlab import __version__

    writer = writer_for(result)
    final = Path(output_dir) / result.study.name
    with report_directory(final) as tmp:
        try:
            parts = writer(result)
            write_parts(
                tmp, result, parts, command=command, version=__version__, study_text=study_text
            )
            state_reproduction(tmp, result)
            key = _report_key(result, study_text)
            if key:
                _write_manifest(tmp, key, result)
        except OSError as exc:
            if isinstance(exc, ReportError):
                raise
            raise ReportError(f"cannot write the report {final}: {exc}") from exc
    move_run_record(tmp, final)  # the writer's timings, recorded for the staging directory
    if index:
        write_index(Path(output_dir))
    return final


def state_reproduction(directory: Path, result: Any) -> None:
    """End the report's main Markdown page with how it reproduces on another machine.

    The paragraph is the kind's declaration
    (:attr:`designlab.study.registry.StudyKind.reproduction`, worded by
    :meth:`designlab.study.reproduction.Reproduction.sentence`); a writer that words
    its own section under the same heading (the gain searches: a flat optimum's
    near-optimal ranges) is left as it is.

    Parameters
    ----------
    directory
        The report directory, with its main Markdown page written.
    result
        The study result (``result.study.kind`` names the kind).
    """
    from designlab.study.registry import kind_of
    from designlab.study.reproduction import HEADING

    main = _main_md(directory)
    study = getattr(result, "study", None)
    if main is None or study is None:
        return
    try:
        rule = kind_of(study.kind).reproduction
    except KeyError:
        return
    text = main.read_text(encoding="utf-8")
    if HEADING[3:] in text:
        return
    sentence = rule.sentence(digits=csv_digits())
    atomic_write_text(main, f"{text.rstrip()}\n\n{HEADING}\n\n{sentence}\n")


#: Inside a report directory: what it was written from (results, study, code) and its files.
MANIFEST = ".designlab-report.json"


def _report_key(result: Any, study_text: str | None) -> str:
    """``""`` unless the result has a ``fingerprint`` (a hash of its points and code)."""
    from designlab import __version__

    fingerprint = getattr(result, "fingerprint", "")
    if not fingerprint:
        return ""
    parts = {
        "result": fingerprint,
        "study": study_text,
        "designlab": __version__,
        "report_code": package_hash(__name__),  # a changed writer makes every report stale
    }
    return hashlib.sha256(json.dumps(parts, sort_keys=True).encode()).hexdigest()


def _file_digest(path: Path) -> str:
    """SHA-256 of a file's content: a report file changed in place, even at the same size,
    is no longer up to date."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _write_manifest(directory: Path, key: str, result: Any) -> None:
    files = {
        p.name: _file_digest(p)
        for p in sorted(directory.iterdir())
        if p.is_file() and p.name != MANIFEST
    }
    record = {
        "key": key,
        "files": files,
        "status": str(getattr(result, "status", "")),
        "warnings": list(getattr(result, "warnings", ())),
    }
    atomic_write_text(directory / MANIFEST, json.dumps(record, indent=1, sort_keys=True) + "\n")


def current_report(
    result: Any, output_dir: str | os.PathLike[str], *, study_text: str | None = None
) -> dict[str, Any] | None:
    """The record of ``<output_dir>/<study name>/`` if it already holds this result's report.

    The record (``status``, ``warnings``, ``files``) is what the report was
    written with, so a caller can repeat its warnings without recomputing
    them. ``None`` for a result without a ``fingerprint`` (only sweep studies have one),
    or when the report was written from other points, code, study text or designlab
    version, or one of its files is missing or its content has changed (SHA-256).

    Parameters
    ----------
    result
        A study result.
    output_dir
        Parent directory of the report.
    study_text
        The study file's text (part of what the report depends on).
    """
    key = _report_key(result, study_text)
    if not key:
        return None
    directory = Path(output_dir) / result.study.name
    try:
        record = json.loads((directory / MANIFEST).read_text(encoding="utf-8"))
        if record.get("key") != key:
            return None
        for name, digest in record["files"].items():
            if _file_digest(directory / name) != digest:
                return None
        return dict(record)
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return None


#: The main Markdown file of a report, by preference.
_MAIN_MD = ("summary.md", "envelope.md")


def _main_md(directory: Path) -> Path | None:
    for name in _MAIN_MD:
        if (directory / name).is_file():
            return directory / name
    return None


def _report_title(directory: Path) -> tuple[str, str]:
    """``(title, first line of the description)`` of a report's main Markdown file."""
    main = _main_md(directory)
    if main is None:
        return directory.name, ""
    try:
        lines = main.read_text(encoding="utf-8").splitlines()
    except OSError:
        return directory.name, ""
    title = directory.name
    desc = ""
    for i, line in enumerate(lines):
        if line.startswith("# "):
            title = line[2:].strip()
            for nxt in lines[i + 1 :]:
                if nxt.strip():
                    desc = "" if nxt.startswith(("Produced by", "#")) else nxt.strip()
                    break
            break
    return title, desc


def write_index(output_dir: str | os.PathLike[str]) -> Path:
    """Write ``<output_dir>/index.md``: every report directory with its summary line.

    Parameters
    ----------
    output_dir
        The directory holding one report directory per study.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> (d / "a").mkdir(); _ = (d / "a" / "summary.md").write_text("# a\\n\\nAsks X.\\n")
    >>> print(write_index(d).read_text())
    # Reports
    <BLANKLINE>
    Generated by `designlab run` / `designlab report`; one directory per study.
    <BLANKLINE>
    | study | what it asks | files |
    |---|---|---|
    | [a](a/summary.md) | Asks X. | 1 (md) |
    <BLANKLINE>
    >>> import shutil; shutil.rmtree(d)
    """
    root = Path(output_dir)
    rows = ["| study | what it asks | files |", "|---|---|---|"]
    for d in sorted(p for p in root.iterdir() if p.is_dir() and not p.name.startswith(".")):
        main = _main_md(d)
        if main is None:
            continue
        _, desc = _report_title(d)
        names = sorted(f.name for f in d.iterdir() if f.is_file() and not f.name.startswith("."))
        kinds = sorted({n.rsplit(".", 1)[-1] for n in names})
        files = f"{len(names)} ({', '.join(kinds)})"
        link = f"{d.name}/{main.name}"
        rows.append(f"| [{d.name}]({link}) | {desc.replace('|', '/')} | {files} |")
    text = "\n".join(
        [
            "# Reports",
            "",
            "Generated by `designlab run` / `designlab report`; one directory per study.",
            "",
            *rows,
            "",
        ]
    )
    index = root / "index.md"
    if index.exists() and not index.is_file():
        raise ReportError(
            f"cannot write the reports index {index}: it is a directory (a report of a study "
            "named 'index.md'?); move it away"
        )
    return write_markdown(text, index)
