"""CSV, Markdown and PNG writers (all atomic).

Examples
--------
>>> import tempfile, pathlib, shutil, pandas as pd
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> frame = pd.DataFrame({"case": ["a"], "a_h_max_g": [6.5712345]})
>>> print(write_csv(frame, d / "m.csv").read_text(), end="")
case,a_h_max_g
a,6.571235
>>> shutil.rmtree(d)
>>> print(markdown_table(frame, floatfmt=".2f"))
| case   |   a_h_max_g |
|:-------|------------:|
| a      |        6.57 |
"""

from __future__ import annotations

import io
import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pandas as pd

from designlab.report.atomic import atomic_write_bytes, atomic_write_text

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["csv_digits", "markdown_table", "write_csv", "write_markdown", "write_png"]

#: Significant digits of floats in CSV files: enough for any comparison, and
#: stable across platforms so regenerated reports diff cleanly.
CSV_FLOAT_FORMAT = "%.7g"


def csv_digits() -> int:
    """Significant digits of the floats in CSV files (from :data:`CSV_FLOAT_FORMAT`).

    Examples
    --------
    >>> csv_digits()
    7
    """
    return int(CSV_FLOAT_FORMAT.strip("%g").lstrip("."))


def write_csv(frame: pd.DataFrame, path: str | os.PathLike[str]) -> Path:
    """Write a data frame as CSV (no index, ``\\n`` line endings, 7 significant digits).

    Parameters
    ----------
    frame
        The table.
    path
        The CSV file.
    """
    text = frame.to_csv(index=False, float_format=CSV_FLOAT_FORMAT, lineterminator="\n")
    return atomic_write_text(path, text)


def write_markdown(text: str, path: str | os.PathLike[str]) -> Path:
    """Write Markdown text, ending it with exactly one newline.

    Parameters
    ----------
    text
        Markdown text.
    path
        The file.
    """
    return atomic_write_text(path, text.rstrip("\n") + "\n")


def write_png(fig: Figure, path: str | os.PathLike[str], *, dpi: int = 110) -> Path:
    """Render a matplotlib figure with the Agg backend and write it as PNG.

    The PNG carries no software/version metadata, so the bytes depend only on
    the figure.

    Parameters
    ----------
    fig
        A matplotlib figure.
    path
        The PNG file.
    dpi
        Resolution, dots per inch.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # only when drawing

    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": None})
    return atomic_write_bytes(path, buf.getvalue())


def markdown_table(
    frame: pd.DataFrame, *, missing: Mapping[str, str] | None = None, **kwargs: Any
) -> str:
    """A GitHub-style Markdown table of ``frame`` (no index), via tabulate.

    A missing value (NaN, None) is written ``n/a (reason)`` with the reason of its column
    in ``missing``, else ``n/a``: never ``nan``.

    Parameters
    ----------
    frame
        The table.
    missing
        Column -> why a value of that column can be missing (``"not in the thesis"``).
    **kwargs
        Passed to :meth:`pandas.DataFrame.to_markdown` (e.g. ``floatfmt``).

    Examples
    --------
    >>> t = pd.DataFrame({"law": ["PJ", "FTL"], "lookahead_m": [float("nan"), 0.5]})
    >>> print(markdown_table(t, missing={"lookahead_m": "not a parameter of the law"}))
    | law   |                        lookahead_m |
    |:------|-----------------------------------:|
    | PJ    | n/a (not a parameter of the law)   |
    | FTL   |                                0.5 |
    """
    kwargs.setdefault("index", False)
    reasons = dict(missing or {})
    unknown = sorted(set(reasons) - {str(c) for c in frame.columns})
    if unknown:
        raise ValueError(f"missing: reasons given for columns not in the table: {unknown}")
    if frame.isna().to_numpy().any():
        kwargs["missingval"] = ([""] if kwargs["index"] else []) + [
            f"n/a ({reasons[str(c)]})" if str(c) in reasons else "n/a" for c in frame.columns
        ]
        frame = frame.astype(object).where(frame.notna(), None)
    return str(frame.to_markdown(**kwargs))
