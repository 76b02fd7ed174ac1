"""The figures a reproduction statement quotes are measured, not typed: they come from the
reruns ``benchmarks/reproduce_reports.py --record`` wrote to ``designlab/data/reproduction.json``
(issue 34, item 5)."""

from __future__ import annotations

import re

import pytest

from designlab.study.registry import study_kinds
from designlab.study.reproduction import Reproduction, measured_figures


def test_every_quoted_figure_has_a_recorded_rerun() -> None:
    record = measured_figures()
    quoting = [k for k in study_kinds().values() if k.reproduction.figures]
    assert quoting, "the statements that quote measurements declare their figures"
    for kind in quoting:
        rule = kind.reproduction
        assert rule.measured in record, rule.measured
        text = rule.explanation()
        assert "{" not in text and "}" not in text, text
        for field, _, _ in rule.figures:
            assert "{" + field + "}" in rule.why, field


def test_a_statement_without_its_rerun_is_an_error() -> None:
    rule = Reproduction(why="moved by {x}", measured="no such study", figures=(("x", "rel", "*"),))
    with pytest.raises(ValueError, match="no recorded rerun"):
        rule.explanation()


def test_figures_are_printed_from_the_record() -> None:
    """A recorded difference of 2.07e-7 prints as 2e-7, a count with thousands separators."""
    name = next(iter(measured_figures()))
    rule = Reproduction(
        why="{rows} rows, {d}", measured=name, figures=(("rows", "rows", ""), ("d", "rel", "*"))
    )
    text = rule.explanation()
    assert re.fullmatch(r"[\d,]+ rows, \de-?\d+", text), text
