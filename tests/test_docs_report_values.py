"""The numbers the guides restate from committed reports are read from the reports' CSVs.

``docs/hooks/report_values.py`` expands ``{{ report(...) }}``/``{{ ratio(...) }}`` at build
time; here every page is expanded the same way (no mkdocs build needed), and a planted wrong
number, a missing row and a changed report are shown to fail or to follow.
"""

from __future__ import annotations

import importlib.util
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location(
    "report_values", ROOT / "docs" / "hooks" / "report_values.py"
)
rv = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(rv)

CSV = "a,b,x\nu,1,0.125\nv,1,0.5\nw,2,-0.25\n"


@pytest.fixture
def reports(tmp_path: Path) -> Path:
    (tmp_path / "r").mkdir()
    (tmp_path / "r" / "t.csv").write_text(CSV)
    return tmp_path


def test_every_page_resolves_against_the_committed_reports():
    pages = sorted((ROOT / "docs").glob("*.md"))
    used = 0
    for page in pages:
        text = page.read_text()
        out = rv.expand(text, page.name)
        assert "{{ report(" not in out and "{{ ratio(" not in out, page.name
        used += len(rv.PATTERN.findall(text))
    assert used > 0  # the mechanism is in use (tether_modes.md at least)


def test_values_aggregates_and_ratio_from_a_table_written_in_the_test(reports):
    def ev(src: str) -> str:
        return rv.evaluate(src, reports)

    assert ev('report("r/t.csv", "x", a="v")') == "0.5"
    assert ev('report("r/t.csv", "x", b=1, agg="range", fmt=".2f")') == "0.12-0.50"
    assert ev('report("r/t.csv", "x", agg="range", fmt=".2f")') == "-0.25 to 0.50"
    assert ev('report("r/t.csv", "x", a=["u", "w"], agg="max", scale=100, fmt=".1f")') == "12.5"
    assert ev('report("r/t.csv", "x", b=1, agg="count")') == "2"
    assert ev('report("r/t.csv", "x", b=3, agg="count")') == "0"
    assert ev('ratio("r/t.csv", "x", num={"a": "v"}, den={"a": "u"}, fmt=".1f")') == "4.0"
    assert ev('report("r/t.csv", "x", a="u", fmt=".3f", shown="0.125")') == "0.125"


def test_an_empty_cell_selects_with_none(tmp_path):
    (tmp_path / "r").mkdir()
    (tmp_path / "r" / "t.csv").write_text("a,robust,x\nu,,0.5\nu,mean,0.75\n")
    assert rv.evaluate('report("r/t.csv", "x", a="u", robust=None)', tmp_path) == "0.5"
    assert rv.evaluate('report("r/t.csv", "x", a="u", robust="mean")', tmp_path) == "0.75"


def test_several_columns_aggregate_together(reports):
    assert rv.evaluate('report("r/t.csv", ["b", "x"], a="w", agg="min")', reports) == "-0.25"
    assert rv.evaluate('report("r/t.csv", ["b", "x"], agg="max")', reports) == "2"
    assert rv.evaluate('report("r/t.csv", "x", a=["u", "w"], agg="absmax")', reports) == "0.25"


def test_a_planted_wrong_number_fails(reports):
    with pytest.raises(rv.ReportValueError, match=r"shows '0\.126' but the report gives '0\.125'"):
        rv.expand('a {{ report("r/t.csv", "x", a="u", fmt=".3f", shown="0.126") }} b', "p", reports)


@pytest.mark.parametrize(
    ("source", "message"),
    [
        ('report("r/t.csv", "x", a="z")', "no row"),
        ('report("r/t.csv", "y", a="u")', "no column 'y'"),
        ('report("r/t.csv", "x", c="u")', "no column 'c'"),
        ('report("r/t.csv", "x", b=1)', "2 rows .* agg='one' needs exactly one"),
        ('report("r/none.csv", "x")', "no report file"),
        ('report("r/t.csv", "x", agg="median")', "agg='median'"),
        ('report("r/t.csv", open("x"))', "literals"),
    ],
)
def test_a_reference_that_does_not_resolve_fails(reports, source, message):
    with pytest.raises(rv.ReportValueError, match=message):
        rv.expand("{{ " + source + " }}", "p", reports)


def test_a_page_follows_a_regenerated_report(tmp_path):
    """Copy a committed report, change one cell: the expanded page changes with it."""
    src = ROOT / "reports" / "tether_modes" / "brake.csv"
    (tmp_path / "tether_modes").mkdir()
    shutil.copy(src, tmp_path / "tether_modes" / "brake.csv")
    ref = (
        '{{ report("tether_modes/brake.csv", "turned_after_stop_rad", fmt=".2g", '
        'law="PseudoJoystick", brake=False) }}'
    )
    before = rv.expand(ref, "p", tmp_path)
    text = (tmp_path / "tether_modes" / "brake.csv").read_text()
    (tmp_path / "tether_modes" / "brake.csv").write_text(text.replace("9.500073", "7.25"))
    assert before == "9.5"
    assert rv.expand(ref, "p", tmp_path) == "7.2"


def test_the_hook_stops_the_build_on_a_planted_wrong_number():
    """mkdocs calls on_page_markdown; a wrong number becomes a PluginError (build fails)."""
    from types import SimpleNamespace

    from mkdocs.exceptions import PluginError

    page = SimpleNamespace(file=SimpleNamespace(src_uri="planted.md"))
    wrong = (
        '{{ report("tether_modes/brake.csv", "turned_after_stop_rad", fmt=".2g", '
        'law="PseudoJoystick", brake=False, shown="9.4") }}'
    )
    with pytest.raises(PluginError, match=r"planted\.md"):
        rv.on_page_markdown(wrong, page)
    right = wrong.replace('shown="9.4"', 'shown="9.5"')
    assert rv.on_page_markdown(right, page) == "9.5"
