"""Contact speeds from crowd runs (issue 24, item 2): one pedestrian on a straight line gives
the exact encounter, and a crowd gives one encounter per pedestrian present."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as hst

import designlab as dl
from designlab.codesign import contact_speeds, injury_probability
from designlab.codesign.contacts import pedestrian_velocity
from designlab.errors import DesignlabError
from designlab.report.codesign import crowd_risk_section
from designlab.study.kinds.codesign import CodesignStudy, crowd_risk

nav = dl.navigation
GAINS = nav.VFFGains(4.3, 0.68, 20.3, 240.7)
V_PED, LANE = 1.0, 3.6  # the pedestrian walks along y = LANE at V_PED, 3 m beside the robot


def _passing_crowd(**kw):
    """A robot driving along y = 0.6 from x = 6 to x = 0 and one JuPedSim pedestrian walking
    from (0, 3.6) towards +x at 1 m/s, 3 m to the side: outside its active region (r2 = 2.1),
    so the robot never swerves; interaction off (the pedestrian ignores the robot)."""
    return nav.crowd(
        "open_plaza", 1, width=12.0, length=15.0, origin=(-5.0, -5.0),
        start=(6.0, 0.6), goal=(0.0, 0.6), paths=(((0.0, LANE), (9.0, LANE)),),
        desired_speed=V_PED, desired_speed_sd=0.0, max_desired_speed=V_PED,
        pedestrian_radius=0.4, critical_radius=0.8, active_radius=2.1, horizon=30.0, **kw,
    )  # fmt: skip


@pytest.fixture(scope="module")
def passing():
    return nav.simulate(_passing_crowd(), GAINS)


def test_straight_pass_of_one_pedestrian_is_exact(passing) -> None:
    res = passing
    assert res.status == "ok" and res.arrived
    end = int(np.searchsorted(res.times, res.arrival_time, side="right"))
    t = res.times[:end]
    walk = np.c_[V_PED * t, np.full_like(t, LANE)]  # the closed-form walk
    np.testing.assert_allclose(res.pedestrian_positions[:end, 0], walk, rtol=0, atol=1e-9)
    rel_p = res.robot_positions[:end] - walk
    d = np.hypot(rel_p[:, 0], rel_p[:, 1])
    i = int(np.argmin(d))
    rel_v = res.robot_velocities[i] - (V_PED, 0.0)
    s = contact_speeds(res)
    assert s.status == "ok" and len(s) == 1 and not s.contact[0]
    assert s.obstacle == ("pedestrian 0",)
    assert s.time[0] == t[i] and s.distance[0] == pytest.approx(d[i], abs=1e-9)
    assert s.surface_distance[0] == pytest.approx(d[i] - 0.4 - res.crowd.robot.radius, abs=1e-9)
    assert s.relative_speed[0] == pytest.approx(float(np.hypot(*rel_v)), abs=1e-9)
    assert s.normal_speed[0] == pytest.approx(-float(rel_p[i] @ rel_v) / d[i], abs=1e-9)
    assert s.obstacle_speed[0] == pytest.approx(V_PED, abs=1e-9)
    # the robot cruises straight at V_mr there: head-on closing speed V_mr + v_p, abeam at 3 m
    v_mr = res.crowd.robot.max_speed
    assert s.robot_speed[0] == pytest.approx(v_mr, abs=1e-6)
    assert s.relative_speed[0] == pytest.approx(v_mr + V_PED, abs=1e-6)
    assert s.distance[0] == pytest.approx(3.0, abs=(v_mr + V_PED) * 0.01)
    assert s.approach_speed[0] == 0.0  # never inside r2


def test_crowd_encounters_feed_the_injury_model(passing) -> None:
    nav_run = nav.simulate(nav.configuration(2), GAINS)
    s = contact_speeds([passing, nav_run])
    assert len(s) == 2 and s.obstacle == ("pedestrian 0", "human")
    assert contact_speeds(passing, obstacles="human").status == "empty"
    risk = injury_probability(
        dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, closing_speed=s, samples=2000, seed=0
    )
    assert 0.0 <= risk.probability <= 1.0


@settings(max_examples=25, deadline=None)
@given(
    v=hst.tuples(hst.floats(-2, 2), hst.floats(-2, 2)),
    p0=hst.tuples(hst.floats(-10, 10), hst.floats(-10, 10)),
    dt=hst.lists(hst.floats(0.001, 0.2), min_size=2, max_size=30),
    gap=hst.integers(0, 40),
)
def test_pedestrian_velocity_is_exact_for_straight_constant_walking(v, p0, dt, gap) -> None:
    t = np.concatenate([[0.0], np.cumsum(dt)])
    p = np.asarray(p0) + np.outer(t, v)
    p[gap : gap + 1] = np.nan  # an absence splits the record (or falls outside it)
    out = pedestrian_velocity(t, p)
    ok = np.isfinite(p).all(axis=1)
    alone = ok & ~np.r_[ok[1:], False] & ~np.r_[False, ok[:-1]]
    np.testing.assert_allclose(out[ok & ~alone], np.broadcast_to(v, out[ok & ~alone].shape),
                               rtol=0, atol=1e-6)  # fmt: skip
    assert np.isnan(out[~ok]).all() and (out[alone] == 0.0).all()


def test_crowd_gives_one_encounter_per_pedestrian_present() -> None:
    c = nav.crowd("corridor_counterflow", 6, length=12.0, seed=4, horizon=2.4)
    res = nav.crowds.simulate_crowd(c, GAINS)
    s = contact_speeds(res, measure="normal")
    end = int(np.searchsorted(res.times, res.arrival_time, side="right")) if res.arrived else None
    present = np.isfinite(res.pedestrian_positions[:end]).all(axis=2).any(axis=0)
    assert len(s) == int(present.sum())
    assert (s.relative_speed + 1e-12 >= np.abs(s.normal_speed)).all()
    assert s.distance.min() == pytest.approx(res.min_distance, abs=(1.8 + 3) * 0.01)
    assert (s.samples >= 0).all()


def test_bad_runs_are_refused() -> None:
    with pytest.raises(DesignlabError, match="CrowdResult"):
        contact_speeds(["not a run"])


def test_codesign_study_crowds_feed_the_risk(passing) -> None:
    study = CodesignStudy.model_validate({
        "designlab": 1, "kind": "codesign", "name": "t", "scenarios": [{"configuration": 2}],
        "risk": {"foams": ["FOAM_1"], "samples": 2000},
        "crowds": {"layout": "corridor_counterflow", "pedestrians": 6, "seeds": [4],
                   "options": {"length": 12.0, "horizon": 2.4}},
    })  # fmt: skip
    frame = crowd_risk(study, dl.impact.MANIPULATOR_1, None)
    c = nav.crowd("corridor_counterflow", 6, length=12.0, seed=4, horizon=2.4)
    s = contact_speeds(nav.simulate(c, nav.EXPERIMENT_GAINS))
    r = injury_probability(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, s, samples=2000, seed=0)
    assert frame is not None and len(frame) == 1 and frame["encounters"][0] == len(s)
    assert frame["probability"][0] == r.probability


def test_report_has_the_crowd_section_only_with_crowds() -> None:
    class _Result:  # the two attributes the section reads
        def __init__(self, study, frame):
            self.study, self.crowd_risk = study, frame

    base = {"designlab": 1, "kind": "codesign", "name": "t", "scenarios": [{"configuration": 2}]}
    crowds = {"crowds": {"layout": "crossing", "pedestrians": 3, "seeds": [1, 2]}}
    study = CodesignStudy.model_validate({**base, **crowds})
    frame = pd.DataFrame({"foam": ["Foam 1"], "probability": [0.25]})
    text = "\n".join(crowd_risk_section(_Result(study, frame)))
    assert "`crossing` crowds of 3 pedestrians (seeds 1, 2)" in text and "0.25" in text
    assert crowd_risk_section(_Result(CodesignStudy.model_validate(base), None)) == []


@pytest.mark.parametrize(
    "bad",
    [
        {"layout": "crossing", "pedestrians": 0},
        {"layout": "crossing", "pedestrians": 10**6},
        {"layout": "crossing", "seeds": [-1]},
        {"layout": "crossing", "seeds": []},
        {"layout": "nowhere"},
        {"layout": "crossing", "options": {"horizon": float("nan")}},
    ],
)
def test_bad_crowds_section_is_refused(bad) -> None:
    base = {"designlab": 1, "kind": "codesign", "name": "t", "scenarios": [{"configuration": 2}]}
    with pytest.raises(ValueError, match="crowds"):
        CodesignStudy.model_validate({**base, "crowds": bad})
