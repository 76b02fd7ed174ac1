"""Report values: a number a guide restates from a committed report is read from its CSV.

A MkDocs hook (``hooks`` in ``mkdocs.yml``). A page writes, instead of the number,

``{{ report("tether_modes/modes.csv", "npd_std_m", agg="range", path="straight_line") }}``

and the built page shows the number the committed report gives, so the guide cannot go
stale when the report is regenerated. The first argument is a CSV under ``reports/``, the
second a column (or a list of columns: their selected cells together, for ``min``/``max``...);
every other keyword that is not one of the options below selects rows (``column=value``,
``column=[v1, v2]`` for any of them, ``column=None`` for an empty cell).
Options:

``agg``
    ``"one"`` (default: exactly one row must match), ``"min"``, ``"max"``, ``"absmax"``
    (the largest magnitude, as a non-negative number), ``"mean"``,
    ``"range"`` (``lo-hi``, or one number when both show the same; ``lo to hi`` when ``lo``
    is negative), ``"count"`` (how many rows match, possibly none; the column is not read).
``fmt``
    a format spec for the number (``".3f"``, ``".1%"``; default ``"g"``).
``scale``
    a factor applied before formatting (for example 100 for a percentage column in 0-1).
``shown``
    the text the page expects; the build fails if the report gives another. A page can keep a
    number visible in its source this way, and a planted wrong number fails the build.

``{{ ratio("tether_step_size/step_size.csv", "npd_mean_m", num={...}, den={...}, fmt=".1f") }}``
shows the ratio of two one-row selections.

Anything wrong (a file, a column or a row that is not there, a ``shown`` that differs, an
argument that is not a literal) is an error naming the page and the expression, so
``mkdocs build`` fails. ``expand`` is also what ``tests/test_docs_report_values.py`` runs
over every page, so the test suite fails too.

:func:`typed_report_numbers` finds the numbers a page still types by hand that equal a cell
of a report it names; ``tests/test_docs_report_numbers.py`` fails on any that is neither
written through the hook nor listed with its reason in ``tests/data/docs_report_numbers.csv``,
and on a listed one whose report no longer gives it (``python docs/hooks/report_values.py``
prints the current candidates).
"""

from __future__ import annotations

import ast
import math
import re
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
REPORTS = ROOT / "reports"
#: ``{{ report(...) }}`` or ``{{ ratio(...) }}``; the call is parsed with :mod:`ast`.
PATTERN = re.compile(r"\{\{\s*((?:report|ratio)\(.*?\))\s*\}\}", re.S)
OPTIONS = ("agg", "fmt", "scale", "shown")
AGGREGATES = ("one", "min", "max", "absmax", "mean", "range", "count")


class ReportValueError(ValueError):
    """A report reference in a docs page that does not resolve, or disagrees with ``shown``."""


def _literal_call(source: str) -> tuple[str, list[Any], dict[str, Any]]:
    try:
        node = ast.parse(source, mode="eval").body
    except SyntaxError as exc:
        raise ReportValueError(f"not a call: {source!r} ({exc.msg})") from exc
    if not isinstance(node, ast.Call) or not isinstance(node.func, ast.Name):
        raise ReportValueError(f"not a call of report or ratio: {source!r}")
    try:
        args = [ast.literal_eval(a) for a in node.args]
        kwargs = {k.arg: ast.literal_eval(k.value) for k in node.keywords}
    except ValueError as exc:
        raise ReportValueError(f"arguments must be literals: {source!r}") from exc
    if None in kwargs:
        raise ReportValueError(f"no **kwargs allowed: {source!r}")
    return node.func.id, args, kwargs


def _table(path: str, reports: Path):
    import pandas as pd

    file = reports / path
    if not file.is_file():
        raise ReportValueError(f"no report file reports/{path}")
    return pd.read_csv(file)


def _select(frame, path: str, where: dict[str, Any], *, allow_empty: bool = False):
    mask = None
    for column, wanted in where.items():
        if column not in frame.columns:
            raise ReportValueError(
                f"reports/{path} has no column {column!r} (columns: {list(frame.columns)})"
            )
        values = wanted if isinstance(wanted, list | tuple) else [wanted]
        col = frame[column]
        hit = col.isin(values) | col.astype(str).isin([str(v) for v in values if v is not None])
        if None in values:  # ``column=None``: the empty cells
            hit = hit | col.isna()
        mask = hit if mask is None else mask & hit
    rows = frame if mask is None else frame[mask]
    if rows.empty and not allow_empty:
        raise ReportValueError(f"no row of reports/{path} matches {where}")
    return rows


def _column(rows, path: str, column: str | list[str]):
    columns = list(column) if isinstance(column, list | tuple) else [column]
    for c in columns:
        if c not in rows.columns:
            raise ReportValueError(
                f"reports/{path} has no column {c!r} (columns: {list(rows.columns)})"
            )
    values = rows[columns].astype(float).to_numpy().ravel()
    if not all(math.isfinite(v) for v in values):
        raise ReportValueError(f"reports/{path} column {column!r}: a selected cell is not finite")
    return values


def _format(value: float, fmt: str) -> str:
    text = format(value, fmt)
    return "0" + text[2:] if text.startswith("-0") and float(text) == 0.0 else text


def report_value(
    path: str, column: str | list[str], /, *, _reports: Path = REPORTS, **kw: Any
) -> str:
    """The text a ``{{ report(...) }}`` shows (see the module docstring)."""
    agg = kw.pop("agg", "one")
    fmt = kw.pop("fmt", "g")
    scale = float(kw.pop("scale", 1.0))
    if agg not in AGGREGATES:
        raise ReportValueError(f"agg={agg!r}; allowed: {AGGREGATES}")
    rows = _select(_table(path, _reports), path, kw, allow_empty=agg == "count")
    if agg == "count":
        return str(len(rows))
    values = _column(rows, path, column) * scale
    if agg == "one":
        if len(values) != 1:
            raise ReportValueError(
                f"{len(values)} rows of reports/{path} match {kw}; agg='one' needs exactly one"
            )
        return _format(values[0], fmt)
    if agg == "range":
        lo, hi = _format(values.min(), fmt), _format(values.max(), fmt)
        if lo == hi:
            return lo
        return f"{lo} to {hi}" if lo.startswith("-") else f"{lo}-{hi}"
    if agg == "absmax":
        return _format(float(abs(values).max()), fmt)
    value = {"min": values.min, "max": values.max, "mean": values.mean}[agg]()
    return _format(float(value), fmt)


def ratio_value(
    path: str,
    column: str,
    /,
    *,
    num: dict[str, Any],
    den: dict[str, Any],
    fmt: str = "g",
    _reports: Path = REPORTS,
) -> str:
    """The text a ``{{ ratio(...) }}`` shows: one selected cell over another."""
    frame = _table(path, _reports)
    top = _column(_select(frame, path, num), path, column)
    bottom = _column(_select(frame, path, den), path, column)
    if len(top) != 1 or len(bottom) != 1:
        raise ReportValueError(f"ratio needs one row each in reports/{path}: {num} / {den}")
    return _format(float(top[0] / bottom[0]), fmt)


def evaluate(source: str, reports: Path = REPORTS) -> str:
    """The text one ``report(...)``/``ratio(...)`` call shows; checks its ``shown``."""
    name, args, kwargs = _literal_call(source)
    shown = kwargs.pop("shown", None)
    if name == "report":
        text = report_value(*args, _reports=reports, **kwargs)
    elif name == "ratio":
        text = ratio_value(*args, _reports=reports, **kwargs)
    else:
        raise ReportValueError(f"unknown function {name!r}; allowed: report, ratio")
    if shown is not None and str(shown) != text:
        raise ReportValueError(f"the page shows {shown!r} but the report gives {text!r}")
    return text


def expand(markdown: str, page: str = "<page>", reports: Path = REPORTS) -> str:
    """Replace every ``{{ report(...) }}`` and ``{{ ratio(...) }}`` of a page by its value."""

    def one(match: re.Match[str]) -> str:
        try:
            return evaluate(match.group(1), reports)
        except ReportValueError as exc:
            raise ReportValueError(f"{page}: {match.group(0)}: {exc}") from exc

    return PATTERN.sub(one, markdown)


def on_page_markdown(markdown: str, page: Any, **kwargs: Any) -> str:
    """MkDocs hook: expand the report values; a reference that fails stops the build."""
    from mkdocs.exceptions import PluginError

    try:
        return expand(markdown, page.file.src_uri)
    except ReportValueError as exc:
        raise PluginError(str(exc)) from exc


# ---------------------------------------------------------------- numbers typed by hand
#: A decimal number as a page writes it (``0.653``, ``27.6``); not part of a word, a path,
#: a version or a longer number.
NUMBER = re.compile(r"(?<![\w.\-/])(\d+\.\d+)(?![\w.]*\d)")
#: Columns holding the sources' own figures (the thesis's, a paper's), which a page may quote.
SOURCE_COLUMN = re.compile(r"thesis|paper|reference|published|source|target|^ref_|^exp_", re.I)
#: A section, figure, table or equation number is a citation, not a value.
CITATION = re.compile(
    r"(?:Secs?|Sections?|Figs?|Figures?|Tables?|eqs?|Eqs?|App|Ch|Chapters?)\.?\s*$"
)
#: A block generated from a report's table, which its own test checks: the claims
#: (``tests/following/test_report_claims.py`` and the studies' tests) and the navigation
#: account's table (``tests/navigation/test_nav_account.py``).
CLAIMS = re.compile(
    r"<!-- claims:[\w-]+ -->.*?<!-- /claims -->"
    r"|<!-- account table: generated, do not edit -->.*?<!-- end of account table -->",
    re.S,
)
#: Tables longer than this (time histories, sensitivity sweeps) are not searched: a page quotes
#: their summaries, and their thousands of cells match unrelated numbers by chance. Measured
#: on 8 December 2026 (issue 37): searching every table adds 58 (page, number) candidates to
#: the 122, and also searching numbers of two significant digits adds 265, nearly all chance
#: matches of inputs (0.25, 1.0, the thesis's gains); a list of them would bury the real
#: restatements, so both stay out and such numbers should be written through the hook.
MAX_ROWS = 300


def _report_cells(name: str, reports: Path) -> dict[str, set[str]]:
    """Every non-integer numeric cell of ``reports/<name>/*.csv`` as a page could print it:
    the text of the value (and its negative) at 1-4 decimals -> ``"<name>/<file>:<column>"``."""
    import numpy as np
    import pandas as pd

    out: dict[str, set[str]] = {}
    for file in sorted((reports / name).glob("*.csv")):
        try:
            frame = pd.read_csv(file)
        except (ValueError, OSError, pd.errors.ParserError):
            continue
        if len(frame) > MAX_ROWS:
            continue
        for column in frame.select_dtypes("number").columns:
            if SOURCE_COLUMN.search(str(column)):
                continue
            values = frame[column].to_numpy(float)
            for x in np.unique(values[np.isfinite(values)]):
                if x == round(x):
                    continue
                for dec in range(1, 5):
                    for v in (x, -x):
                        out.setdefault(f"{v:.{dec}f}", set()).add(f"{name}/{file.name}:{column}")
    return out


def typed_report_numbers(
    markdown: str, reports: Path = REPORTS, cache: dict[str, Any] | None = None
) -> dict[str, set[str]]:
    """The numbers a page types by hand that a committed report it names also gives.

    A number counts when it has at least 3 significant digits, is written outside a
    ``{{ report(...) }}``/``{{ ratio(...) }}`` and outside a generated ``<!-- claims:... -->``
    block, is no section, figure or table number, and equals, at the decimals the page shows,
    a non-integer cell of a CSV of a report the page names (``reports/<name>`` or the bare
    study name), outside the columns holding the sources' own figures. Returns the number's
    text -> the ``"<report>/<file>:<column>"`` cells it matches. Used by
    ``tests/test_docs_report_numbers.py``: such a number must come from the hook, or be
    listed there with the reason it does not.
    """
    cache = {} if cache is None else cache
    text = CLAIMS.sub(" ", PATTERN.sub(" ", markdown))
    names = sorted(
        p.name
        for p in reports.iterdir()
        if p.is_dir() and re.search(rf"(?<![\w-]){re.escape(p.name)}(?![\w-])", text)
    )
    found: dict[str, set[str]] = {}
    for match in NUMBER.finditer(text):
        number = match.group(1)
        if len(number.replace(".", "").lstrip("0")) < 3 or CITATION.search(
            text, max(0, match.start() - 12), match.start()
        ):
            continue
        for name in names:
            if name not in cache:
                cache[name] = _report_cells(name, reports)
            hits = cache[name].get(number)
            if hits:
                found.setdefault(number, set()).update(hits)
    return found


if __name__ == "__main__":  # list every page's typed report numbers (tests/data/...csv)
    import csv
    import sys

    cache: dict[str, Any] = {}
    writer = csv.writer(sys.stdout, lineterminator="\n")
    writer.writerow(["page", "number", "cells", "status"])
    for page in sorted((ROOT / "docs").glob("*.md")):
        found = typed_report_numbers(page.read_text(), REPORTS, cache)
        for number, cells in sorted(found.items(), key=lambda kv: float(kv[0])):
            writer.writerow([page.name, number, ";".join(sorted(cells)), "not converted yet"])
