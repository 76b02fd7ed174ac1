"""No number in docs/ restates a committed report by hand without being listed.

``report_values.typed_report_numbers`` finds, on every page, the numbers typed by hand that
equal (at the decimals shown) a cell of a report the page names. Each must be listed in
``tests/data/docs_report_numbers.csv`` with its cells and a status: ``not converted yet``
(to be replaced by ``{{ report(...) }}``) or the reason it is no report value (a source's
figure, an input). A new such number fails here until it comes from the hook or is listed;
a listed number whose report no longer gives it fails as stale. Regenerate the list's
candidates with ``python docs/hooks/report_values.py`` (keep the statuses).
"""

from __future__ import annotations

import csv
import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location(
    "report_values", ROOT / "docs" / "hooks" / "report_values.py"
)
rv = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(rv)

KNOWN = ROOT / "tests" / "data" / "docs_report_numbers.csv"


def _known() -> dict[tuple[str, str], tuple[set[str], str]]:
    with KNOWN.open(newline="") as f:
        return {
            (r["page"], r["number"]): (set(r["cells"].split(";")), r["status"])
            for r in csv.DictReader(f)
        }


@pytest.fixture(scope="module")
def found() -> dict[tuple[str, str], set[str]]:
    cache: dict = {}
    out = {}
    for page in sorted((ROOT / "docs").glob("*.md")):
        for number, cells in rv.typed_report_numbers(page.read_text(), rv.REPORTS, cache).items():
            out[(page.name, number)] = cells
    return out


def test_every_typed_report_number_is_listed(found):
    known = _known()
    new = {k: sorted(v)[:3] for k, v in found.items() if k not in known}
    assert not new, (
        "numbers typed in docs/ that a committed report gives; write them as "
        "{{ report(...) }} (docs/hooks/report_values.py) or list them with a reason in "
        f"{KNOWN.relative_to(ROOT)}: {new}"
    )


def test_no_listed_number_is_stale(found):
    """A listed number whose listed report cells no longer give it: the report moved."""
    stale = {
        k: sorted(cells) for k, (cells, _) in _known().items() if not (found.get(k, set()) & cells)
    }
    assert not stale, (
        "listed docs numbers that their report no longer gives (stale, or gone from the page):"
        f" update the page (better: {{{{ report(...) }}}}) and the list: {stale}"
    )


def test_every_listed_number_has_a_status():
    assert all(status.strip() for _, status in _known().values())


def test_a_planted_number_is_found(tmp_path):
    """A page typing a report's cell is caught; the same number from the hook is not."""
    (tmp_path / "r").mkdir()
    (tmp_path / "r" / "t.csv").write_text("a,x\nu,0.6533192\nv,2.0\n")
    page = "The r study gives H = 0.653 and 2.000, and 0.6533 again."
    got = rv.typed_report_numbers(page, tmp_path)
    assert got == {"0.653": {"r/t.csv:x"}, "0.6533": {"r/t.csv:x"}}
    hooked = 'The r study gives H = {{ report("r/t.csv", "x", a="u", fmt=".3f") }}.'
    assert rv.typed_report_numbers(hooked, tmp_path) == {}
    assert rv.typed_report_numbers("No report named: 0.653.", tmp_path) == {}
