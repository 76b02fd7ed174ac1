"""Every report states how it reproduces on another machine, from its kind's declaration.

The statement is generated (:func:`designlab.report.state_reproduction` from
:attr:`StudyKind.reproduction`), so the committed reports must carry exactly what the
current declarations say; ``benchmarks/reproduce_reports.py`` checks the claims by
rerunning the studies as on a plain x86-64 CPU (docs/developers.md).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from designlab.report import write_report
from designlab.report.writers import csv_digits
from designlab.study import load_study, parse_study, run_study
from designlab.study.registry import kind_of, study_kinds
from designlab.study.reproduction import HEADING, Reproduction

ROOT = Path(__file__).resolve().parents[2]
STUDIES = sorted((ROOT / "studies").glob("*.yaml"))


def _main_md(directory: Path) -> Path:
    for name in ("summary.md", "envelope.md"):
        if (directory / name).is_file():
            return directory / name
    raise AssertionError(f"{directory} has no main Markdown page")


@pytest.mark.parametrize("study", STUDIES, ids=lambda p: p.stem)
def test_each_committed_report_states_its_kinds_declaration(study: Path) -> None:
    spec = load_study(study)
    text = _main_md(ROOT / "reports" / spec.name).read_text(encoding="utf-8")
    assert text.count(HEADING + "\n") <= 1, "one statement, under the shared heading"
    sentence = kind_of(spec.kind).reproduction.sentence(digits=csv_digits())
    if not text.endswith(f"{HEADING}\n\n{sentence}\n"):
        # the gain searches word their own (flat optima, near-optimal ranges)
        assert spec.kind in {"navigation_gains", "tether_tuning"}, spec.kind
        assert HEADING[3:] in text


def test_every_kind_declares_a_reproduction() -> None:
    for name, kind in study_kinds().items():
        assert isinstance(kind.reproduction, Reproduction), name
        rule = kind.reproduction
        assert rule.why or not rule.checked or rule.bound() == "a = b (to the bit)", name


def test_a_written_report_ends_with_the_statement(tmp_path: Path) -> None:
    study = parse_study(
        "designlab: 1\nkind: impact_cases\nname: demo\ncases:\n"
        "  - {robot: MANIPULATOR_1, foam: FOAM_1, head: TEST_HEAD, impact_velocity: 0.4}\n"
    )
    out = write_report(run_study(study), tmp_path, index=False)
    text = (out / "summary.md").read_text(encoding="utf-8")
    rule = kind_of("impact_cases").reproduction
    assert text.endswith(f"{HEADING}\n\n{rule.sentence(digits=csv_digits())}\n")


def test_close_follows_the_stated_bound() -> None:
    r = Reproduction(rtol=1e-8, atol=1e-12, why="x")
    assert r.close(1.0, 1.0 + 0.9e-8) and not r.close(1.0, 1.0 + 1.1e-8)
    assert r.close(0.0, 0.9e-12) and not r.close(0.0, 2e-12)
    assert r.close(math.nan, math.nan) and not r.close(math.nan, 0.0)
    assert r.close(math.inf, math.inf) and not r.close(math.inf, 1e308)
    # one unit in the last of 7 printed digits: 2.530612e-07 -> 2.530613e-07 is a flip
    exact = Reproduction()
    assert not exact.close(2.530612e-07, 2.530613e-07)
    assert exact.close(2.530612e-07, 2.530613e-07, digits=7)
    assert not exact.close(2.530612e-07, 2.530614e-07, digits=7)


@pytest.mark.parametrize("bad", [-1.0, math.nan, math.inf])
def test_a_tolerance_must_be_finite_and_non_negative(bad: float) -> None:
    with pytest.raises(ValueError, match="rtol"):
        Reproduction(rtol=bad)
