"""Reports: the only part of designlab that writes files.

Every file is written atomically and a report directory appears all at once
(see :mod:`designlab.report.atomic`): an interrupted run leaves the previous
report as it was.

Examples
--------
>>> import tempfile, pathlib
>>> from designlab.study import parse_study, run_study
>>> from designlab.report import write_report
>>> study = parse_study('''
... designlab: 1
... kind: impact_cases
... name: demo
... cases:
...   - {robot: MANIPULATOR_1, foam: FOAM_1, head: TEST_HEAD, impact_velocity: 0.4}
... ''')
>>> out = write_report(run_study(study), pathlib.Path(tempfile.mkdtemp()))
>>> sorted(p.name for p in out.iterdir())
['metrics.csv', 'summary.md', 'time_histories.png']
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from designlab.report.atomic import (
    ReportError,
    atomic_write_bytes,
    atomic_write_text,
    report_directory,
)
from designlab.report.writers import markdown_table, write_csv, write_markdown, write_png

__all__ = [
    "ReportError",
    "atomic_write_bytes",
    "atomic_write_text",
    "markdown_table",
    "report_directory",
    "write_csv",
    "write_markdown",
    "write_png",
    "write_report",
]


def write_report(
    result: Any,
    output_dir: str | os.PathLike[str],
    *,
    command: str | None = None,
    study_text: str | None = None,
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
    from designlab.report.impact import write_impact_report
    from designlab.study.runner import ImpactCasesResult

    final = Path(output_dir) / result.study.name
    with report_directory(final) as tmp:
        try:
            if isinstance(result, ImpactCasesResult):
                write_impact_report(
                    result, tmp, command=command, version=__version__, study_text=study_text
                )
            else:  # pragma: no cover - only impact studies exist so far
                raise TypeError(f"no report writer for {type(result).__name__}")
        except OSError as exc:
            if isinstance(exc, ReportError):
                raise
            raise ReportError(f"cannot write the report {final}: {exc}") from exc
    return final
