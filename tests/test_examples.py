"""The examples gallery (``examples/``, rendered into the site by ``docs/gen_pages.py``): every
script runs, draws at least one figure with labelled axes, and every domain has one."""

from __future__ import annotations

import ast
import runpy
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SCRIPTS = sorted(EXAMPLES.glob("*.py"))
DOMAINS = ("impact", "navigation", "following", "codesign")


def test_every_domain_has_an_example() -> None:
    assert {s.name.split("_")[0] for s in SCRIPTS} >= set(DOMAINS)
    assert all(s.name.split("_")[0] in DOMAINS for s in SCRIPTS), [s.name for s in SCRIPTS]


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_an_example_runs_and_draws(script: Path, capsys: pytest.CaptureFixture[str]) -> None:
    doc = ast.get_docstring(ast.parse(script.read_text(encoding="utf-8")))
    assert doc and "\n\n" in doc, "a title line, a blank line and a description"
    plt.close("all")
    try:
        runpy.run_path(str(script), run_name="__main__")
        figures = [plt.figure(n) for n in plt.get_fignums()]
        assert figures, "the example draws nothing"
        for fig in figures:
            for ax in fig.axes:
                assert ax.get_xlabel() and ax.get_ylabel(), (ax.get_title(), "unlabelled axis")
    finally:
        plt.close("all")
    assert capsys.readouterr().out.strip(), "the example prints what it computed"
