"""Crowd encounters per candidate design: each design's gains and speed limit in the crowds."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import designlab as dl
import designlab.navigation as nav
from designlab.codesign import (
    THESIS_DESIGN,
    CrowdEncounters,
    Design,
    DesignSpace,
    contact_speeds,
    evaluate_design,
    injury_probability,
    pareto,
)
from designlab.errors import InvalidParameterError
from designlab.impact import FOAM_3, MANIPULATOR_1, HeadAcceleration

CROWD = nav.crowd("corridor_counterflow", 4, length=10.0, horizon=6.0, seed=2)
FAST = Design(FOAM_3, 1.3, nav.VFFGains(k1=5.0, b=0.2, k3=12.0, k5=30.0))


def _direct(design: Design, measure: str = "approach"):
    """The design's crowd encounters, simulated here without the cache."""
    sc = dataclasses.replace(CROWD, robot=dataclasses.replace(CROWD.robot, max_speed=design.speed))
    return contact_speeds([nav.simulate(sc, design.gains)], measure=measure)


@pytest.fixture(scope="module")
def encounters() -> CrowdEncounters:
    return CrowdEncounters([CROWD], measure="approach")


def test_each_design_meets_the_crowd_with_its_own_gains_and_speed(encounters) -> None:
    crit = HeadAcceleration(10)
    scores = {}
    for label, design in (("thesis", THESIS_DESIGN), ("fast", FAST)):
        s = evaluate_design(design, [nav.configuration(2)], measure="approach", criterion=crit,
                            risk_samples=4000, seed=5, crowds=encounters)  # fmt: skip
        direct = _direct(design)
        assert s.crowd_contacts is not None
        np.testing.assert_array_equal(s.crowd_contacts.samples, direct.samples)
        expected = 0.0
        if len(direct):
            expected = injury_probability(
                MANIPULATOR_1,
                design.foam,
                closing_speed=direct,
                criterion=crit,
                samples=4000,
                seed=5,
            ).probability
        assert s.crowd_injury_probability == expected
        scores[label] = s
    # a different speed limit and gains drive a different crowd encounter
    a, b = scores["thesis"].crowd_contacts, scores["fast"].crowd_contacts
    assert a is not None and b is not None
    assert not np.array_equal(a.samples, b.samples)


def test_runs_are_cached_per_speed_and_gains_not_per_foam(encounters) -> None:
    before = encounters.runs
    foam_only = dataclasses.replace(THESIS_DESIGN, foam=FOAM_3)
    first = encounters.of(THESIS_DESIGN.speed, THESIS_DESIGN.gains)
    s = evaluate_design(foam_only, [nav.configuration(2)], crowds=encounters)
    assert encounters.runs == before  # the thesis design's runs are reused
    assert s.crowd_contacts is first
    assert np.isnan(s.crowd_injury_probability)  # no criterion asked for


def test_the_front_takes_the_crowd_objective_per_candidate(encounters) -> None:
    space = DesignSpace(stiffness_min=24250.0, stiffness_max=24250.0, damping_min=71.9,
                        damping_max=71.9, k3_min=20.0, k3_max=20.0, k5_min=100.0,
                        k5_max=100.0)  # fmt: skip
    front = pareto([nav.configuration(2)], space=space, population=4, generations=1, seed=1,
                   objectives=("arrival_time", "crowd_injury_probability"), measure="approach",
                   risk_samples=2000, crowds=encounters, reference={})  # fmt: skip
    frame = front.designs_frame()
    assert len(frame) == 4
    for x, p in zip(front.X, front.F[:, 1], strict=True):
        d = Design.from_vector(x)
        direct = _direct(d)
        want = 0.0
        if len(direct):
            want = injury_probability(MANIPULATOR_1, d.foam, closing_speed=direct,
                                      criterion=HeadAcceleration(10), samples=2000,
                                      seed=1).probability  # fmt: skip
        assert p == want


def test_crowd_objective_needs_crowds() -> None:
    with pytest.raises(InvalidParameterError, match="crowds"):
        pareto([nav.configuration(2)], objectives=("arrival_time", "crowd_injury_probability"))
    with pytest.raises(InvalidParameterError, match="crowds"):
        dl.codesign.front_sensitivity([nav.configuration(2)],
                                      objectives=("crowd_injury_probability",))  # fmt: skip
    with pytest.raises(InvalidParameterError, match="crowds"):
        CrowdEncounters([])
    with pytest.raises(InvalidParameterError, match="crowds"):
        CrowdEncounters([nav.configuration(2)])
    with pytest.raises(InvalidParameterError, match="measure"):
        CrowdEncounters([CROWD], measure="fast")
    with pytest.raises(InvalidParameterError, match="crowds"):
        evaluate_design(THESIS_DESIGN, [nav.configuration(2)], crowds=[CROWD])
