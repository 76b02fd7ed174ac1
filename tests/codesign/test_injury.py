"""Issue 36.3 and 36.4: cited injury curves, ISO/TS 15066 Annex A, body regions, exposure."""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest

import designlab as dl
from designlab.codesign.assessment import exposure, iso_comparison
from designlab.codesign.injury import (
    body_regions,
    head_injury_risk,
    iso_permissible_speed,
    region_shares,
)
from designlab.errors import DesignlabError

#: ISO/TS 15066:2016 Annex A: (F quasi-static N, transient factor, k N/mm, m_H kg), as the
#: standard's Table A.2 and Table A.3 print them (a second copy to check the data file).
TABLE = {
    "skull_forehead": (130, None, 150, 4.4), "face": (65, None, 75, 4.4),
    "neck": (150, 2, 50, 1.2), "back_shoulders": (210, 2, 35, 40), "chest": (140, 2, 25, 40),
    "abdomen": (110, 2, 10, 40), "pelvis": (180, 2, 25, 40),
    "upper_arm_elbow": (150, 2, 30, 3), "lower_arm_wrist": (160, 2, 40, 2),
    "hand_finger": (140, 2, 75, 0.6), "thigh_knee": (220, 2, 50, 75),
    "lower_leg": (130, 2, 60, 75),
}  # fmt: skip


def test_the_data_file_is_the_standards_table_and_the_criteria_agree() -> None:
    regions = body_regions()
    assert set(regions) == set(TABLE)
    for name, (f, factor, k, m) in TABLE.items():
        r = regions[name]
        assert (r.quasi_static_force, r.spring_constant, r.effective_mass) == (f, k * 1e3, m)
        assert (math.isnan(r.transient_factor) if factor is None
                else r.transient_factor == factor)  # fmt: skip
        assert dl.impact.criteria.ISO_TS_15066_QUASI_STATIC_FORCE[name] == f
        assert "Table A.2" in r.source


@pytest.mark.parametrize("region", list(TABLE))
@pytest.mark.parametrize("m_r", [4.4, 9.6, 20.0])
def test_iso_permissible_speed_is_the_energy_transfer_closed_form(region: str, m_r: float) -> None:
    f, factor, k, m_h = TABLE[region]
    mp.mp.dps = 30
    mu = 1 / (1 / mp.mpf(m_h) + 1 / mp.mpf(m_r))
    want = mp.mpf(f) * (factor or 1) / mp.sqrt(mu * k * 1000)
    assert iso_permissible_speed(region, m_r) == pytest.approx(float(want), rel=1e-14)


def test_hic_curves_against_their_closed_forms() -> None:
    mp.mp.dps = 30
    for hic in (4.7, 250.0, 700.0, 1000.0, 2500.0):
        pm = mp.ncdf((mp.log(hic) - mp.mpf("7.45231")) / mp.mpf("0.73998"))
        assert head_injury_risk(hic) == pytest.approx(float(pm), rel=1e-12)
        for name, (a, c) in {"nhtsa_ais2": ("2.49", "0.00483"),
                             "nhtsa_ais3": ("3.39", "0.00372")}.items():  # fmt: skip
            x = mp.mpf(a) + 200 / mp.mpf(hic) - mp.mpf(c) * hic
            assert head_injury_risk(hic, name) == pytest.approx(float(1 / (1 + mp.exp(x))),
                                                                rel=1e-12)  # fmt: skip
    # the figure: HIC15 4.7 at the worst head at 2.2 m/s gives about 8e-16 (AIS3+)
    assert 7e-16 < head_injury_risk(4.7) < 8e-16
    with pytest.raises(DesignlabError, match="curve"):
        head_injury_risk(10.0, "wayne_state")
    with pytest.raises(DesignlabError, match="hic"):
        head_injury_risk(-1.0)


def test_region_shares_of_one_height_for_a_fixed_band() -> None:
    # 0.1 m is below every adult's knee (0.285 H >= 0.285 x 1.4 m): the lower leg alone
    s = region_shares(0.1, 0.1)
    assert s["lower_leg"] == pytest.approx(1.0, abs=1e-12) and s.sum() == pytest.approx(1.0)
    # shares of a band sum to 1 and follow the stature mixture: at 1.74 m a person of
    # stature below 1.74 m is missed; the mixture's CDF there is 0.5 x 0.5 + 0.5 x Phi(2.097)
    s = region_shares(1.74, 1.74)
    want = 0.25 + 0.5 * float(mp.ncdf((mp.mpf("1.74") - mp.mpf("1.61")) / mp.mpf("0.062")))
    assert s["above the head"] == pytest.approx(want, rel=1e-12)
    assert region_shares(0.1, 0.5).sum() == pytest.approx(1.0, abs=1e-12)


def test_iso_beside_zeng_names_what_binds() -> None:
    t = iso_comparison(dl.codesign.THESIS_ROBOT, dl.impact.FOAM_1, human_speed=1.0)
    zeng = dl.codesign.speed_limit(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1).max_speed
    head = t.loc["skull_forehead"]
    assert head["zeng_robot_speed_m_per_s"] == zeng
    assert head["iso_closing_speed_m_per_s"] == iso_permissible_speed("skull_forehead", 9.6)
    # the standard's head speed (0.19 m/s) is below the walker's: ISO binds, at rest
    assert head["iso_robot_speed_m_per_s"] == 0.0 and head["binding"] == "ISO/TS 15066"
    assert t["share"].sum() <= 1.0


def test_exposure_counts_people_only_with_a_poisson_bound() -> None:
    runs = [dl.navigation.simulate(dl.navigation.configuration(4), dl.navigation.EXPERIMENT_GAINS)]
    e = exposure(runs)
    assert e.contacts == 0 and e.per_hour == 0.0 and e.per_hour_lower == 0.0 and e.runs == 1
    assert e.per_hour_upper * e.hours == pytest.approx(-math.log(0.05), rel=1e-12)


def test_exposure_of_known_contacts_matches_the_poisson_closed_form() -> None:
    # 2 contacts at 0.5 and 1.0 m/s in 1 h and 1 km, harm(v) = v / 10: 0.15 harms per hour;
    # the 95 % upper bound lambda solves P(N <= 2 | lambda) = 0.05 (mpmath, independently)
    from designlab.codesign.assessment import _exposure

    e = _exposure([0.5, 1.0], 3600.0, 1000.0, 0.0, lambda v: v / 10.0, 2.0)
    lam = mp.findroot(lambda x: mp.exp(-x) * (1 + x + x**2 / 2) - mp.mpf("0.05"), 6.3)
    assert e.contacts == 2 and e.per_hour == 2.0 and e.per_km == 2.0
    assert e.per_hour_upper == pytest.approx(float(lam), rel=1e-10)
    assert e.risk_per_hour == pytest.approx(0.15, rel=1e-15)
    assert e.risk_per_hour_upper == pytest.approx(float(lam) * 0.2, rel=1e-10)  # harm(2 m/s)
    # the 95 % lower bound solves P(N >= 2 | lambda) = 0.05
    low = mp.findroot(lambda x: 1 - mp.exp(-x) * (1 + x) - mp.mpf("0.05"), 0.35)
    assert e.per_hour_lower == pytest.approx(float(low), rel=1e-10)
    assert e.per_km_lower == pytest.approx(float(low), rel=1e-10)


def test_closing_speed_after_braking_is_the_braked_robot_plus_the_person() -> None:
    # the run's robot speed v, v_h = 1 m/s, no reaction, a = 2 m/s^2, detected at 0.2 m: the
    # gap closes when (v + 1) t - t^2 = 0.2, the robot then at v - 2 t
    from designlab.codesign.assessment import _closing_after_braking
    from designlab.codesign.speed import Braking

    c = dl.codesign.contact_speeds(
        dl.navigation.simulate(dl.navigation.configuration(2), dl.navigation.EXPERIMENT_GAINS)
    )
    brake = Braking.check(0.0, 2.0, 0.2)
    i = 0
    v_r, v_o = float(c.robot_speed[i]), float(c.obstacle_speed[i])
    got = _closing_after_braking(c, i, brake, 1.0)
    t = (v_r + 1.0 - math.sqrt((v_r + 1.0) ** 2 - 2 * 2.0 * 0.2)) / 2.0
    assert 0 < t < v_r / 2.0  # still moving at contact
    assert got == pytest.approx(v_r - 2.0 * t + v_o, rel=1e-12)
    # no detection distance: the run's own closing speed
    assert _closing_after_braking(c, i, Braking.check(0.0, 5.0, 0.0), 1.0) == c.relative_speed[i]


def test_exposure_counts_crowd_pedestrians_as_people() -> None:
    nav = dl.navigation
    crowd = nav.crowd("corridor_counterflow", pedestrians=30, width=2.0, length=12.0, seed=1,
                      horizon=4.0)  # fmt: skip
    run = nav.simulate(crowd, nav.EXPERIMENT_GAINS)
    e = exposure([run], harm=lambda v: 0.5)
    # independently: pedestrians whose centre came within the two radii of the robot's
    P = run.pedestrian_positions[: len(run.times)]
    d = np.linalg.norm(P - run.robot_positions[:, None, :], axis=2)
    end = np.searchsorted(run.times, run.arrival_time, side="right") if run.arrived else None
    touched = int((np.nanmin(d[:end], axis=0) <= crowd.robot.radius + crowd.pedestrian_radius)
                  .sum())  # fmt: skip
    assert e.contacts == touched
    assert e.crowd_hours == e.hours == pytest.approx(float(run.times[-1]) / 3600.0, rel=1e-12)
    assert e.risk_per_hour == pytest.approx(0.5 * touched / e.hours, rel=1e-12)


@pytest.mark.parametrize(
    ("kw", "name"),
    [({"harm": 3.0}, "harm"), ({"worst_speed": math.nan}, "worst_speed"),
     ({"worst_speed": -1.0}, "worst_speed"), ({"human_speed": math.inf}, "human_speed"),
     ({"detection_distance": -1.0}, "detection_distance")],
)  # fmt: skip
def test_exposure_refuses_hostile_inputs_by_name(kw, name) -> None:
    run = dl.navigation.simulate(dl.navigation.configuration(2), dl.navigation.EXPERIMENT_GAINS)
    with pytest.raises(DesignlabError, match=name):
        exposure([run], **kw)
    with pytest.raises(DesignlabError, match="runs"):
        exposure(["not a run"])
