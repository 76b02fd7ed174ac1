"""What every report shares: the ceremony around what a writer computes.

A report writer returns its :class:`ReportParts`: its tables, figures and the body of
its main Markdown page (and perhaps further pages). The framework adds the rest, the
same way for every report (:func:`write_parts`): the page's header
(:func:`report_header`: the title, the study's description and one provenance
sentence naming the command and designlab version that produced it), the
``## Warnings`` section (:func:`warnings_section`), the copy of the study file
(:func:`copy_study`), and it writes the files in the order every report uses
(:func:`write_report`: tables, figures, pages, the study's copy).
:func:`designlab.report.write_report` then adds the reproduction section and the index.
The wording lives here once, so every report says it the same way.

Examples
--------
>>> print("\\n".join(report_header("demo", "Asks X.", command="designlab run s.yaml",
...                                version="1.0")))
# demo
<BLANKLINE>
Asks X.
<BLANKLINE>
Produced by `designlab run s.yaml` with designlab 1.0. Generated file: edit the study, not
this report, and regenerate it with the same command.
<BLANKLINE>
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import platform
import re
import sys
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from designlab.report.atomic import atomic_write_text
from designlab.report.writers import write_csv, write_markdown, write_png

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure

__all__ = [
    "RUNS_DIR",
    "STUDY_COPY",
    "ReportParts",
    "claims",
    "copy_study",
    "figure_section",
    "format_duration",
    "main_page",
    "move_run_record",
    "provenance",
    "record_run",
    "record_timings",
    "recorded_run",
    "report_header",
    "run_record",
    "run_record_path",
    "slug",
    "warnings_section",
    "write_parts",
    "write_report",
]

#: The name of the study file's copy inside a report directory.
STUDY_COPY = "study.yaml"


def provenance(
    command: str | None = None, version: str | None = None, *, cached: bool = False
) -> str:
    """The one sentence that says what produced a report and that it is generated.

    Parameters
    ----------
    command
        The command line that produced the report (quoted in backticks).
    version
        The designlab version.
    cached
        The study keeps its points in a result store, so ``designlab report``
        can rebuild the report without computing (sweep studies).

    Returns
    -------
    str

    Examples
    --------
    >>> provenance(version="1.0")
    'Produced by designlab 1.0. Generated file: edit the study, not this report, and regenerate it.'
    >>> provenance("designlab run s.yaml", cached=True)  # doctest: +NORMALIZE_WHITESPACE
    'Produced by `designlab run s.yaml`. Generated file: edit the study, not this report, and
    regenerate it with the same command (`designlab report` rebuilds it from the cache).'
    """
    if command:
        who = f"`{command}`" + (f" with designlab {version}" if version else "")
    else:
        who = f"designlab {version}" if version else "designlab"
    how = " with the same command" if command else ""
    if cached:
        how += " (`designlab report` rebuilds it from the cache)"
    return (
        f"Produced by {who}. Generated file: edit the study, not this report, "
        f"and regenerate it{how}."
    )


def report_header(
    title: str,
    description: str = "",
    *,
    command: str | None = None,
    version: str | None = None,
    cached: bool = False,
) -> list[str]:
    """The opening lines of a report's main Markdown file.

    ``# title``, the study's description (if any) and the :func:`provenance`
    sentence, each followed by a blank line.

    Parameters
    ----------
    title
        The report's title (usually the study name, perhaps after a few words).
    description
        The study's description (stripped; left out when empty).
    command, version, cached
        See :func:`provenance`.

    Returns
    -------
    list of str
        Lines, to be joined with ``"\\n"``.
    """
    lines = [f"# {title}", ""]
    if description.strip():
        lines += [description.strip(), ""]
    lines += [provenance(command, version, cached=cached), ""]
    return lines


def warnings_section(warnings: Iterable[str], *, none: str | None = None) -> list[str]:
    """The ``## Warnings`` section: one bullet a warning.

    Parameters
    ----------
    warnings
        The result's warnings.
    none
        The sentence shown when there are none; ``None``: no section at all.

    Examples
    --------
    >>> warnings_section(["eps_max > lambda"])
    ['## Warnings', '', '- eps_max > lambda', '']
    >>> warnings_section([])
    []
    """
    items = list(warnings)
    if not items:
        return [] if none is None else ["## Warnings", "", none, ""]
    return ["## Warnings", "", *[f"- {w}" for w in items], ""]


def claims(found: Iterable[str], *, lead: str = "Computed from the table:") -> list[str]:
    """The sentences a report computes from its table, one bullet each, after ``lead``.

    Parameters
    ----------
    found
        The sentences.
    lead
        The line before them.

    Examples
    --------
    >>> claims(["PJ < FTL"])
    ['Computed from the table:', '', '- PJ < FTL', '']
    """
    return [lead, "", *[f"- {c}" for c in found], ""]


def figure_section(
    figures: Mapping[str, str] | Iterable[tuple[str, str]],
    *,
    title: str = "Figures",
    level: int = 2,
    spaced: bool = True,
) -> list[str]:
    """A section of figures: its heading, then one Markdown image a figure.

    Parameters
    ----------
    figures
        Caption -> file name (relative to the report), in the order shown; or
        ``(caption, file name)`` pairs.
    title
        The section's heading.
    level
        The heading level (2: ``##``).
    spaced
        A blank line after each image (``False``: the images follow each other
        line by line, as one paragraph).

    Returns
    -------
    list of str
        Markdown lines, to join with ``"\\n"``.

    Examples
    --------
    >>> figure_section({"paths": "paths.png"})
    ['## Figures', '', '![paths](paths.png)', '']
    >>> figure_section([("a", "a.png"), ("b", "b.png")], title="Run", level=3, spaced=False)
    ['### Run', '', '![a](a.png)', '![b](b.png)']
    """
    items = figures.items() if isinstance(figures, Mapping) else figures
    out = [f"{'#' * level} {title}", ""]
    for caption, name in items:
        out += [f"![{caption}]({name})", ""] if spaced else [f"![{caption}]({name})"]
    return out


def copy_study(directory: str | os.PathLike[str], study_text: str | None) -> list[Path]:
    """Copy the study file's text into the report as ``study.yaml`` (atomically).

    Parameters
    ----------
    directory
        The report directory.
    study_text
        The study file's text; ``None``: nothing is copied.

    Returns
    -------
    list of pathlib.Path
        The file written (empty when there was no text), to add to a writer's list.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     [p.name for p in copy_study(d, "designlab: 1\\n")], copy_study(d, None)
    (['study.yaml'], [])
    """
    if study_text is None:
        return []
    return [atomic_write_text(Path(directory) / STUDY_COPY, study_text)]


def slug(text: str, empty: str = "") -> str:
    """A file-name part made of ``text``: letters and digits, ``_`` between, lower case.

    Parameters
    ----------
    text
        A label (a path name, a law's title).
    empty
        What to return when ``text`` has no letter or digit.

    Examples
    --------
    >>> slug("Figure-eight (5 m)")
    'figure_eight_5_m'
    >>> slug("--", empty="all")
    'all'
    """
    return re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_").lower() or empty


def write_report(
    directory: str | os.PathLike[str],
    *,
    tables: Mapping[str, pd.DataFrame] | None = None,
    figures: Mapping[str, Callable[[], Figure]] | None = None,
    pages: Mapping[str, str] | None = None,
    study_text: str | None = None,
) -> list[Path]:
    """Write a report's files, in the order every report uses, and list them.

    The tables (CSV), then the figures (each made, written as PNG and closed in
    turn, so one figure at a time is in memory), then the Markdown pages, then the
    study's copy (:func:`copy_study`).

    Parameters
    ----------
    directory
        The report directory (it exists).
    tables
        File name -> table, written with :func:`designlab.report.writers.write_csv`.
    figures
        File name -> function making the figure, written with
        :func:`designlab.report.writers.write_png`.
    pages
        File name -> Markdown text, written with
        :func:`designlab.report.writers.write_markdown`.
    study_text
        The study file's text (``None``: not copied).

    Returns
    -------
    list of pathlib.Path
        The files written, in that order.

    Examples
    --------
    >>> import tempfile
    >>> import pandas as pd
    >>> with tempfile.TemporaryDirectory() as d:
    ...     files = write_report(d, tables={"t.csv": pd.DataFrame({"a": [1]})},
    ...                          pages={"summary.md": "# demo"}, study_text="designlab: 1\\n")
    ...     [f.name for f in files]
    ['t.csv', 'summary.md', 'study.yaml']
    """
    folder = Path(directory)
    written = [write_csv(frame, folder / name) for name, frame in (tables or {}).items()]
    for name, make in (figures or {}).items():
        fig = make()
        written.append(write_png(fig, folder / name))
        _close(fig)
    written += [write_markdown(text, folder / name) for name, text in (pages or {}).items()]
    return written + copy_study(folder, study_text)


def _close(fig: Figure) -> None:
    """Release a figure pyplot manages; a ``Figure`` made directly needs nothing, and a
    process that never imported pyplot (about 0.5 CPU s) has none."""
    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        plt.close(fig)


@dataclass(frozen=True)
class ReportParts:
    """What a report writer returns: what its study computed, without the ceremony.

    The framework (:func:`write_parts`) makes the main page ``page`` of
    :func:`report_header`, ``body``, :func:`warnings_section` and ``closing``, and
    writes it with ``tables``, ``figures``, ``pages`` and the study's copy.

    Parameters
    ----------
    body
        Markdown lines of the main page between its header and its warnings.
    tables
        File name -> table (CSV).
    figures
        File name -> function making the figure (PNG).
    closing
        Markdown lines after the warnings (usually the figures' section).
    title
        The page's title (``None``: the study's name).
    page
        The main page's file name.
    pages
        File name -> Markdown text of further pages.
    warnings
        The warnings listed (``None``: the result's ``warnings``).
    no_warnings
        The sentence shown when there are none (``None``: no section then).
    files
        File name -> function writing that file at the path it is given (what is
        neither a table, a figure nor a page: animations, a Parquet table).
    timings
        Wall times of the run's parts, kept in the run record, not in the report
        (:func:`record_timings`).
    cached
        The study keeps its points in a result store (see :func:`provenance`).
    """

    body: Sequence[str] = ()
    tables: Mapping[str, pd.DataFrame] = field(default_factory=dict)
    figures: Mapping[str, Callable[[], Figure]] = field(default_factory=dict)
    closing: Sequence[str] = ()
    title: str | None = None
    page: str = "summary.md"
    pages: Mapping[str, str] = field(default_factory=dict)
    warnings: Sequence[str] | None = None
    no_warnings: str | None = None
    files: Mapping[str, Callable[[Path], Any]] = field(default_factory=dict)
    timings: Mapping[str, float] = field(default_factory=dict)
    cached: bool = False


def main_page(
    result: Any,
    parts: ReportParts,
    *,
    command: str | None = None,
    version: str | None = None,
) -> str:
    """The main Markdown page of a report: header, body, warnings, closing lines.

    Parameters
    ----------
    result
        The study result (its ``study`` gives the name and description; its
        ``warnings`` the warnings unless ``parts`` lists its own).
    parts
        What the writer returned.
    command, version
        See :func:`provenance`.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> r = NS(study=NS(name="demo", description="Asks X."), warnings=["w"])
    >>> print(main_page(r, ReportParts(body=["## Result", "", "42", ""])))
    # demo
    <BLANKLINE>
    Asks X.
    <BLANKLINE>
    Produced by designlab. Generated file: edit the study, not this report, and regenerate it.
    <BLANKLINE>
    ## Result
    <BLANKLINE>
    42
    <BLANKLINE>
    ## Warnings
    <BLANKLINE>
    - w
    <BLANKLINE>
    """
    study = result.study
    title = study.name if parts.title is None else parts.title
    warnings = getattr(result, "warnings", ()) if parts.warnings is None else parts.warnings
    out = report_header(
        title, study.description or "", command=command, version=version, cached=parts.cached
    )
    out += [*parts.body, *warnings_section(warnings, none=parts.no_warnings), *parts.closing]
    return "\n".join(out)


def write_parts(
    directory: str | os.PathLike[str],
    result: Any,
    parts: ReportParts,
    *,
    command: str | None = None,
    version: str | None = None,
    study_text: str | None = None,
) -> list[Path]:
    """Write a report's files from its writer's parts (:func:`main_page`, :func:`write_report`).

    Parameters
    ----------
    directory
        The report directory (it exists).
    result
        The study result.
    parts
        What the writer returned.
    command, version
        See :func:`provenance`.
    study_text
        The study file's text (``None``: not copied).

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    folder = Path(directory)
    page = main_page(result, parts, command=command, version=version)
    written = write_report(
        folder,
        tables=parts.tables,
        figures=parts.figures,
        pages={parts.page: page, **parts.pages},
        study_text=study_text,
    )
    for name, make in parts.files.items():
        make(folder / name)
        written.append(folder / name)
    if parts.timings:
        record_timings(folder, parts.timings)
    return written


#: The run records' subdirectory of the user cache directory (:func:`run_record_path`).
RUNS_DIR = "runs"


def run_record_path(directory: str | os.PathLike[str]) -> Path | None:
    """Where the run record of the report in ``directory`` is kept (``None``: nowhere).

    A run record holds how long the run that wrote a report took, and its parts
    (:func:`record_run`, :func:`record_timings`). Wall times belong to the machine and its
    load, not to the report, so the record is kept outside the report and outside the
    checkout: in ``runs/`` of the user cache directory (``$DESIGNLAB_CACHE_DIR``, else
    ``~/.cache/designlab``; :func:`designlab.sx.cache.cache_dir`), one file per report
    directory, named by a hash of its absolute path. Running a study therefore never
    modifies a committed file other than the report's own, and ``designlab list`` shows only
    runs of this machine.

    Parameters
    ----------
    directory
        The report directory.

    Returns
    -------
    Path or None
        ``None`` where no private cache directory can be made.
    """
    from designlab.sx.cache import private_cache_subdir

    root = private_cache_subdir(RUNS_DIR)
    if root is None:
        return None
    absolute = str(Path(directory).resolve())
    return root / f"{hashlib.sha256(absolute.encode()).hexdigest()[:32]}.json"


def run_record(directory: str | os.PathLike[str]) -> dict[str, Any]:
    """The run record of the report in ``directory`` on this machine (``{}`` if none).

    A record written on another host (a home directory shared between machines) is not
    this machine's, so it reads as ``{}``.

    Parameters
    ----------
    directory
        The report directory.
    """
    path = run_record_path(directory)
    try:
        record = json.loads(path.read_text(encoding="utf-8")) if path else {}
    except (OSError, ValueError):
        return {}
    if not isinstance(record, dict) or record.get("host") != platform.node():
        return {}
    return record


def _write_run_record(directory: str | os.PathLike[str], record: dict[str, Any]) -> Path | None:
    """Write a run record; drop this host's records of report directories that are gone."""
    path = run_record_path(directory)
    if path is None:
        return None
    for old in path.parent.glob("*.json"):
        try:
            gone = json.loads(old.read_text(encoding="utf-8"))
            if gone.get("host") == platform.node() and not Path(gone["report"]).is_dir():
                old.unlink()
        except (OSError, ValueError, KeyError, TypeError, AttributeError):
            continue
    record = {**record, "host": platform.node(), "report": str(Path(directory).resolve())}
    return atomic_write_text(path, json.dumps(record, sort_keys=True) + "\n")


def record_run(directory: str | os.PathLike[str], seconds: float, **extra: Any) -> Path | None:
    """Keep the wall time of the run that wrote a report in its run record.

    Parameters
    ----------
    directory
        The report directory.
    seconds
        Wall time of the run (computing and writing).
    **extra
        More facts to keep (``executor="serial"``).

    Returns
    -------
    Path or None
        The run record's file (:func:`run_record_path`), ``None`` if it could not be kept.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     _ = record_run(d, 83.2, executor="serial")
    ...     recorded_run(d)
    83.2
    """
    timings = run_record(directory).get("timings")
    kept = {"timings": timings} if isinstance(timings, dict) else {}
    return _write_run_record(directory, {**kept, "seconds": round(float(seconds), 1), **extra})


def record_timings(directory: str | os.PathLike[str], timings: Mapping[str, float]) -> Path | None:
    """Keep the wall times of a run's parts in its run record, not in the report.

    Wall times depend on the machine and its load, so a report's tables and Markdown never
    carry them (they would not reproduce); a report writer hands them here instead, and
    :func:`record_run` keeps them when it adds the whole run's time.

    Parameters
    ----------
    directory
        The report directory.
    timings
        ``{part: seconds}``; replaces the timings recorded before.

    Returns
    -------
    Path or None
        The run record's file (:func:`run_record_path`), ``None`` if it could not be kept.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     _ = record_timings(d, {"optimise off": 52.31})
    ...     _ = record_run(d, 83.2, executor="serial")
    ...     run_record(d)["timings"]
    {'optimise off': 52.3}
    """
    record = run_record(directory)
    record["timings"] = {str(k): round(float(v), 1) for k, v in timings.items()}
    return _write_run_record(directory, record)


def move_run_record(source: str | os.PathLike[str], target: str | os.PathLike[str]) -> None:
    """Give the run record of ``source`` (a report's staging directory) to ``target``.

    A report is written in a temporary directory that then replaces the report directory
    (:func:`designlab.report.atomic.report_directory`); what its writer recorded
    (:func:`record_timings`) belongs to the report directory. Without a record of ``source``
    nothing changes.

    Parameters
    ----------
    source, target
        The staging and the report directory.
    """
    record = run_record(source)
    path = run_record_path(source)
    if not record or path is None:
        return
    _write_run_record(target, {k: v for k, v in record.items() if k not in ("host", "report")})
    path.unlink(missing_ok=True)


def recorded_run(directory: str | os.PathLike[str]) -> float | None:
    """The wall time kept by :func:`record_run` on this machine (``None`` if none).

    Parameters
    ----------
    directory
        The report directory.
    """
    value = run_record(directory).get("seconds")
    ok = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    return float(value) if ok else None


def format_duration(seconds: float) -> str:
    """A duration for people: ``"under a second"``, ``"40 s"``, ``"3 min"``, ``"1.5 h"``.

    Parameters
    ----------
    seconds
        The duration.

    Examples
    --------
    >>> [format_duration(s) for s in (0.3, 42.4, 200, 5400)]
    ['under a second', '42 s', '3 min', '1.5 h']
    """
    if seconds < 1:
        return "under a second"
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"
