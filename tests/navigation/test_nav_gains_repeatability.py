"""The navigation_gains study's repeat_seeds: each mode optimised again with other seeds."""

from __future__ import annotations

import pytest

from designlab.errors import StudyError
from designlab.study import parse_study, run_study

_SMALL = """
designlab: 1
kind: navigation_gains
name: demo
modes: ["off"]
configurations: [1]
validation: []
popsize: 4
max_evaluations: 8
refine: false
sensitivity: false
"""


def test_repeat_seeds_give_one_row_per_mode_and_seed() -> None:
    r = run_study(parse_study(_SMALL + "repeat_seeds: [1]\n"))
    rep = r.repeatability
    assert rep[["stabilising", "seed"]].values.tolist() == [["off", 0], ["off", 1]]
    assert rep.loc[0, "H_mean"] == r.optima["off"].objective  # the study's seed is row one
    assert rep.loc[0, "k1"] == r.optima["off"].gains.k1
    assert (rep["evaluations"] >= 4).all()


@pytest.mark.parametrize("seeds", ["[0]", "[1, 1]", "[-1]", "[1.5]"])
def test_repeat_seeds_that_repeat_or_are_not_seeds_are_refused(seeds: str) -> None:
    with pytest.raises(StudyError, match="repeat_seeds"):
        parse_study(_SMALL + f"repeat_seeds: {seeds}\n")
