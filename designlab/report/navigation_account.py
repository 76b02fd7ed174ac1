"""Report of a ``navigation_account`` study: the thesis's rows, ours, the differences and causes.

Files written into the report directory:

``account.csv``
    One row per (thesis row, quantity): thesis, ours, difference, relative, within the
    band, cause, the value of the run without the cause, what was tried, the row's note.
``summary.md``
    The counts and the table.
``study.yaml``
    The study file as it was run (when given).
"""

from __future__ import annotations

from pathlib import Path

from designlab.navigation.account import CAUSES, account_markdown
from designlab.report import register_writer
from designlab.report.builder import ReportParts
from designlab.report.writers import markdown_table
from designlab.study.kinds.navigation_account import NavigationAccountResult

__all__ = [
    "BEGIN",
    "END",
    "account_summary",
    "navigation_account_report",
    "regenerate_docs",
    "update_docs",
]

#: The markers around the generated table in ``docs/navigation.md``.
BEGIN, END = "<!-- account table: generated, do not edit -->", "<!-- end of account table -->"


def update_docs(text: str, result: NavigationAccountResult) -> str:
    """``text`` with the table between :data:`BEGIN` and :data:`END` regenerated.

    Parameters
    ----------
    text
        The page's text (``docs/navigation.md``), containing both markers.
    result
        A ``navigation_account`` result (the whole account).

    Examples
    --------
    >>> update_docs("no markers", None)
    Traceback (most recent call last):
    ...
    ValueError: the page has no account-table markers
    """
    i, j = text.find(BEGIN), text.find(END)
    if i < 0 or j < i:
        raise ValueError("the page has no account-table markers")
    return text[: i + len(BEGIN)] + "\n" + account_markdown(result.account) + "\n" + text[j:]


def account_summary(result: NavigationAccountResult) -> str:
    """The body of the Markdown summary (the framework adds header and warnings).

    Parameters
    ----------
    result
        A ``navigation_account`` result.
    """
    acc = result.account
    f = acc.frame
    causes = f.loc[~f["within"], "cause"].value_counts()
    unexplained = f["cause"].str.endswith("not found")
    unexplained_rows = [
        f"Table {r['table']} {r['method']} ({r['sim_or_exp']}, config {r['configuration']}) "
        f"{r['quantity']}"
        for _, r in f[unexplained].iterrows()
    ]
    out = [
        f"Agreement band: {acc.time_band:.0%} in arrival time, {acc.distance_band} m in "
        "distance (stabilising force off, tolerance 0.15 m, `docs/navigation.md`). "
        f"{int(f['within'].sum())} of {len(f)} quantities lie inside it. Outside it, by "
        "cause: " + ", ".join(f"{k} {v}" for k, v in causes.items()) + ".",
        "",
        "A cause is demonstrated by a run that removes it and brings the quantity inside "
        "the band (`run without it`); `tried` lists the candidates that did not (the range "
        "of their runs). `thesis text`: the thesis's own text gives the value we find. "
        "Experiment rows are compared with the simulation, the vision noise being one "
        "candidate (the motors are not modelled). H and energy are not compared (the motor "
        "data are unknown).",
        "",
        "Every quantity outside the band is run against every candidate cause that changes "
        "its run (a walk cause needs a walking human, `start` Ch. 6 Configurations 3-4, "
        "`noise` an experiment row, the gain causes Table 5.1, `masoud_sense` Masoud):",
        "",
        *[f"- `{c.name}`: {c.description}" for c in CAUSES],
        "",
        f"No cause found after every applicable candidate: {int(unexplained.sum())} of "
        f"{int((~f['within']).sum())} quantities outside the band"
        + (": " + "; ".join(unexplained_rows) if len(unexplained_rows) else "")
        + ".",
        "",
        account_markdown(acc),
        "",
    ]
    out += _noise_section(result)
    return "\n".join(out)


def _noise_section(result: NavigationAccountResult) -> list[str]:
    """The Config 2/4 ordering of the two gain sets without and with sensor noise."""
    f = result.noise
    if f.empty:
        return []
    n = result.study.noise_seeds
    return [
        "## The Config 2/4 ordering under sensor noise",
        "",
        "The thesis finds its optimised gains (New VFF*) worse than the experiment gains "
        "(New VFF) in Configurations 2 and 4 and blames measurement noise. Each row: H "
        f"without noise and over {n} seeded noise draws (`SensorNoise` defaults: 0.0125 m "
        "per axis on every measured position, 0.1 m/s on a moving obstacle's velocity; "
        "stabilising force off; `noise.csv`).",
        "",
        markdown_table(f, floatfmt=".3g"),
        "",
    ]


@register_writer(NavigationAccountResult)
def navigation_account_report(result: NavigationAccountResult) -> ReportParts:
    """The report's parts: account.csv, noise.csv (if any) and the summary's body.

    Parameters
    ----------
    result
        A ``navigation_account`` result.
    """
    tables = {"noise.csv": result.noise} if len(result.noise) else {}
    return ReportParts(
        body=[account_summary(result)],
        tables={**tables, "account.csv": result.to_frame()},
    )


def regenerate_docs(page: str | Path, study: str | Path) -> None:
    """Run the account study ``study`` and rewrite its table in ``page``.

    ``python -c "from designlab.report.navigation_account import regenerate_docs;
    regenerate_docs('docs/navigation.md', 'studies/navigation_account.yaml')"``

    Parameters
    ----------
    page
        The Markdown page with the markers (``docs/navigation.md``).
    study
        The ``navigation_account`` study file.
    """
    from designlab.study import load_study, run_study

    result = run_study(load_study(Path(study)))
    path = Path(page)
    path.write_text(update_docs(path.read_text(), result))
