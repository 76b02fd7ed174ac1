"""Habits of the scientific-Python stack (issue 39, item 6): results pickle (process executors
and users' own multiprocessing send them between processes), their reprs are one line, and
``designlab --help`` shows examples and the exit codes.

Results of the other types pickle in their domains' tests (``test_nav_hostile``,
``test_crowd_scenario``, ``test_tether_hostile``, ``test_tether_modes_hostile``).
"""

from __future__ import annotations

import pickle

import pytest
from typer.testing import CliRunner

import designlab as dl
from designlab import cli
from designlab.results import Result, check_result


def _results() -> dict[str, Result]:
    imp, fol = dl.impact, dl.following
    return {
        "impact": imp.simulate(imp.MANIPULATOR_1, imp.FOAM_1, imp.TEST_HEAD, impact_velocity=1.25),
        "no impact": imp.simulate(imp.MANIPULATOR_1, imp.FOAM_1, imp.TEST_HEAD, impact_velocity=0),
        "accompany": fol.accompany(fol.walking_task("forward")),
    }


@pytest.fixture(scope="module")
def results() -> dict[str, Result]:
    return _results()


def test_results_pickle_with_what_they_compute(results: dict[str, Result]) -> None:
    for name, r in results.items():
        back = pickle.loads(pickle.dumps(r))
        assert type(back) is type(r), name
        assert back.to_frame().equals(r.to_frame()), name
        check_result(back)
    impact = pickle.loads(pickle.dumps(results["impact"]))  # its lobe's evaluator came along
    assert impact.hic() == results["impact"].hic()
    assert pickle.loads(pickle.dumps(results["no impact"])).hic() == 0.0


def test_reprs_are_one_short_line(results: dict[str, Result]) -> None:
    for name, r in results.items():
        text = repr(r)
        assert "\n" not in text and len(text) < 600, (name, len(text), text[:200])
        assert text.startswith(type(r).__name__ + "(") and "status=" in text
    text = repr(results["accompany"])  # arrays by shape, the run's options by value
    assert "time=<array " in text and "mount=None" in text


def test_help_shows_examples_and_exit_codes() -> None:
    out = CliRunner().invoke(cli.app, ["--help"])
    assert out.exit_code == 0
    assert "designlab run studies/zeng_ch4_validation.yaml" in out.output
    codes = (cli.EXIT_OK, cli.EXIT_DESIGNLAB_ERROR, cli.EXIT_STUDY_ERROR,
             cli.EXIT_EXECUTOR_ERROR, cli.EXIT_CACHE_INCOMPLETE, cli.EXIT_INTERRUPTED)  # fmt: skip
    for code in codes:
        assert f"\n    {code} " in out.output, code
