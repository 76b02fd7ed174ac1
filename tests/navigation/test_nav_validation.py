"""Simulations against Zeng 2011, Tables 6.2-6.5 and 7.1-7.4 (tests/data/nav_results_ch*.csv).

Protocol (docs/navigation.md): force held for T_s = 0.06 s, 1 ms dynamics, arrival at the
first passage within 0.15 m, stabilising force off for the table comparisons (with it on
the thesis's tables do not come back: the robot brakes and creeps near obstacles).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import designlab as dl

nav = dl.navigation
DATA = Path(__file__).resolve().parents[1] / "data"
CH6 = pd.read_csv(DATA / "nav_results_ch6.csv")
CH7 = pd.read_csv(DATA / "nav_results_ch7.csv")
GAINS = pd.read_csv(DATA / "nav_gains.csv")
C1 = GAINS[GAINS.table == "C.1"].set_index("source")
OPT = nav.VFFGains(
    k1=C1.loc["New VFF", "attractive_gain"],
    b=C1.loc["New VFF", "b_s"],
    k3=C1.loc["New VFF", "repulsive_gain"],
    k5=C1.loc["New VFF", "detour_gain"],
)
EXP = nav.VFFGains(k1=3.0, b=0.25, k3=20.0, k5=17.0)  # Sec. 6.2.4 / 7.3.2
COLS = {"circle": "d_cir_min_m", "rectangle": "d_rect_min_m", "human": "d_h_min_m"}


def _row(table: pd.DataFrame, **kw: object) -> pd.Series:
    m = np.ones(len(table), bool)
    for k, v in kw.items():
        m &= table[k].astype(str) == str(v)
    assert m.sum() == 1, kw
    return table[m].iloc[0]


@pytest.mark.parametrize("config", [1, 3])
def test_new_vff_star_tables_6_2_and_6_4(config: int) -> None:
    res = nav.simulate(nav.configuration(config), OPT, stabilising="off")
    row = _row(CH6, configuration=config, method="New VFF*", sim_or_exp="sim")
    for name, d in res.min_distance.items():
        assert d == pytest.approx(row[COLS[name]], abs=0.03), name
    if config == 1:
        assert res.arrival_time == pytest.approx(row.T_arrive_s, rel=0.07)
    else:
        # Known discrepancy: Config 3 with the optimised gains arrives after 5.67 s against the
        # table's 6.2 s (-8.5 %). The thesis's optimised run is *slower* than its experiment-gain
        # run (6.1 s), ours is faster (5.94 s), as K1 = 4.3 > 3 predicts; the start point of
        # Config 3 is not stated. Checked: within 10 %, and faster than the experiment-gain run
        # by the K1 trend; the experiment-gain row (6.1 s) is within 7 %.
        assert res.arrival_time == pytest.approx(row.T_arrive_s, rel=0.10)
        slow = nav.simulate(nav.configuration(3), EXP, stabilising="off")
        exp_row = _row(CH6, configuration=3, method="New VFF", sim_or_exp="sim")
        assert slow.arrival_time == pytest.approx(exp_row.T_arrive_s, rel=0.07)
        # The unstated start is worth the difference: started 9 cm further out, at the start
        # of the Ch. 7 configurations ([3.99, 0.6]), both rows come within 7 % (measured
        # 5.80 s, -6.5 %, and 6.07 s, -0.5 %) and the distances stay within 0.03 m.
        ch7_start = dataclasses.replace(nav.configuration(3), start=(3.99, 0.6))
        for gains, ref in ((OPT, row), (EXP, exp_row)):
            moved = nav.simulate(ch7_start, gains, stabilising="off")
            assert moved.arrival_time == pytest.approx(ref.T_arrive_s, rel=0.07)
            for name, d in moved.min_distance.items():
                assert d == pytest.approx(ref[COLS[name]], abs=0.03), name
    assert not res.entered_critical and not res.collided


def test_new_vff_star_rows_within_7_percent_with_a_5_cm_first_passage() -> None:
    # The thesis does not state its arrival tolerance (docs/navigation.md, "Arrival"). With a
    # 0.05 m first passage both New VFF* rows of Tables 6.2 and 6.4 come within 7 % (measured
    # 6.15 vs 6.3 s and 5.86 vs 6.2 s); the default 0.15 m is kept because with the
    # experiment gains the robot passes the goal of Configuration 3 at 0.1-0.15 m and
    # circles it, which the 0.05 m tolerance turns from a 5.9 s run into a 17 s one.
    for config in (1, 3):
        res = nav.simulate(
            nav.configuration(config), OPT, stabilising="off", arrival_tolerance=0.05
        )
        row = _row(CH6, configuration=config, method="New VFF*", sim_or_exp="sim")
        assert res.arrival_time == pytest.approx(row.T_arrive_s, rel=0.07), config
        for name, d in res.min_distance.items():
            assert d == pytest.approx(row[COLS[name]], abs=0.03), name
    orbit = nav.simulate(nav.configuration(3), EXP, stabilising="off", arrival_tolerance=0.05)
    first = nav.simulate(nav.configuration(3), EXP, stabilising="off", arrival_tolerance=0.15)
    assert orbit.arrival_time > 2 * first.arrival_time


@pytest.mark.parametrize("config", [1, 2, 3, 4])
def test_chapter_7_holonomic_rows(config: int) -> None:
    sc = nav.configuration(config, chapter=7, robot=nav.HolonomicRobot())
    res = nav.simulate(sc, EXP, stabilising="off")
    row = _row(CH7, configuration=config, robot="holonomic", sim_or_exp="sim")
    assert res.arrival_time == pytest.approx(row.T_arrive_s, rel=0.07)
    for name, d in res.min_distance.items():
        if config == 4 and name in ("human", "circle"):
            # Synthetic walk (the measured one is not published): the human passes differently,
            # so the robot meets the circle on another path; d_h 1.25 vs 1.31 m, d_cir 0.50 vs
            # 0.59 m. Trend checked: both stay outside their critical regions with margin.
            o = {o.name: o for o in sc.obstacles}[name]
            assert d > o.r3 + 0.05
            continue
        assert d == pytest.approx(row[COLS[name]], abs=0.03), name


def test_configuration_2_never_inside_r3_and_the_synthetic_walk_trend() -> None:
    for gains in (EXP, OPT):
        res = nav.simulate(nav.configuration(2), gains, stabilising="off")
        assert res.min_distance["human"] > 0.8
        assert res.arrived
    # Table 6.3 prints d_h = 1.1 / 1.3 m and T = 8.2 / 8.7 s (experiment / optimised gains) with
    # the measured walk. The smooth synthetic walk gives closer passes (0.97 / 0.94 m), and the
    # optimised gains arrive earlier (6.8 s) instead of later: the thesis blames its larger b for
    # amplifying the noise of the measured human velocity, which a noise-free walk cannot show.
    # What carries over: the experiment-gain arrival time (8.4 vs 8.2 s).
    exp = nav.simulate(nav.configuration(2), EXP, stabilising="off")
    row = _row(CH6, configuration=2, method="New VFF", sim_or_exp="sim")
    assert exp.arrival_time == pytest.approx(row.T_arrive_s, rel=0.07)
    assert 0.8 < exp.min_distance["human"] < row.d_h_min_m


@pytest.mark.slow
@pytest.mark.parametrize("which", [1, 2, 3, 4, "parallel", "unpredictable"])
def test_with_the_stabilising_force_no_critical_entry_and_no_collision(which: object) -> None:
    for gains in (EXP, OPT):
        res = nav.simulate(nav.configuration(which), gains, stabilising="lyapunov")
        assert not res.entered_critical, res.min_distance
        assert not res.collided
        assert res.arrived


def test_ge_cui_fails_in_configuration_2() -> None:
    res = nav.simulate(nav.configuration(2), method="ge_cui")
    # Which failure: the collinear detour force of (2.2.13) is zero, so the robot is pushed back
    # by the approaching human and pinned: it never arrives (no contact with the synthetic walk,
    # which stops at x = 4.0 m; the thesis's measured walk produced a collision at t = 4 s).
    assert not res.arrived
    assert not res.collided
    assert res.status == "not_arrived"


def test_masoud_enters_the_parallel_humans_critical_region_but_the_new_vff_does_not() -> None:
    sc = nav.configuration("parallel")
    masoud = nav.simulate(sc, method="masoud")
    assert masoud.entered_critical
    # Sec. 6.4.5 / Fig. 6.20: its fixed detour sense drags the robot in front of the human,
    # contact at t = 2.7 s; with the synthetic walk contact (d_h <= rho_h + rho_r) at 2.82 s
    assert masoud.collided
    contact = masoud.t[np.argmax(masoud.distance[0] <= 0.4 + 0.2)]
    assert contact == pytest.approx(2.7, abs=0.2)
    new = nav.simulate(sc, OPT, stabilising="off")
    assert not new.entered_critical and not new.collided
    new_exp = nav.simulate(sc, EXP, stabilising="off")
    assert not new_exp.entered_critical
    # Sec. 6.4.5: T_arrive = 7.3 s for the new VFF (measured walk); within 20 % with ours
    assert new_exp.arrival_time == pytest.approx(7.3, rel=0.2)


def test_masoud_reproduces_its_rows_of_tables_6_2_and_6_4() -> None:
    for config in (1, 3):
        res = nav.simulate(nav.configuration(config), method="masoud")
        row = _row(CH6, configuration=config, method="Masoud*", sim_or_exp="sim")
        assert res.arrival_time == pytest.approx(row.T_arrive_s, rel=0.07)
        for name, d in res.min_distance.items():
            assert d == pytest.approx(row[COLS[name]], abs=0.05), name


@pytest.mark.parametrize("config", [1, 2, 3, 4])
def test_nonholonomic_is_slower_than_holonomic(config: int) -> None:
    nh = nav.simulate(nav.configuration(config, chapter=7), EXP, stabilising="off")
    ho = nav.simulate(
        nav.configuration(config, chapter=7, robot=nav.HolonomicRobot()), EXP, stabilising="off"
    )
    assert nh.arrived and ho.arrived
    assert nh.arrival_time > ho.arrival_time
    assert not nh.collided


def test_cbf_keeps_static_obstacles_outside_their_critical_regions() -> None:
    for config in (1, 3):
        res = nav.simulate(nav.configuration(config), method="cbf")
        assert res.arrived and not res.entered_critical and not res.collided
    # a head-on walker faster than the robot defeats a safety filter on the attractive field
    head_on = nav.simulate(nav.configuration(2), method="cbf")
    assert head_on.collided


def test_three_obstacle_case_of_sec_7_5_5() -> None:
    # Start and goal appear only in Fig. 7.12 (assumed here, docs/navigation.md); the thesis's
    # nonholonomic robot is trapped 3.1-5.3 s with every d > r3 and arrives at 15 s.
    sc = nav.configuration("multi", chapter=7)
    res = nav.simulate(sc, EXP, stabilising="lyapunov")
    assert res.arrived and not res.entered_critical and not res.collided
    assert set(res.min_distance) == {"circle", "human", "robot"}


def test_ge_cui_distances_of_tables_6_2_and_6_4_and_its_slow_arrival() -> None:
    # Distances come back within 0.01 m (0.752 vs 0.75; 0.745 / 0.762 vs 0.75 / 0.76). The
    # arrival is slower than printed (19.9 / 26.1 s vs 13.5 / 13.3 s; the thesis's own text
    # says 13.7 / 15.9 s). Its path oscillates around the obstacle (Sec. 6.4.1); the thesis
    # does not say which r3 Ge & Cui used or how its output drove the robot, so the longer
    # oscillation here is not pinned down. Checked: slower than the table, never colliding.
    for config in (1, 3):
        res = nav.simulate(nav.configuration(config), method="ge_cui")
        row = _row(CH6, configuration=config, method="Ge & Cui*", sim_or_exp="sim")
        for name, d in res.min_distance.items():
            assert d == pytest.approx(row[COLS[name]], abs=0.03), name
        assert res.arrived and res.arrival_time > row.T_arrive_s
        assert not res.collided


def _rim_speed(res: nav.NavigationResult, robot: nav.NonholonomicRobot) -> np.ndarray:
    """max |v +- omega l/2| along a run, from the recorded positions and headings."""
    tr = res.trajectory_frame()
    t = tr["t_s"].to_numpy()
    v = np.hypot(tr["vx_m_per_s"], tr["vy_m_per_s"]).to_numpy()
    omega = np.diff(np.unwrap(tr["heading_rad"].to_numpy())) / np.diff(t)
    return np.abs(v[1:]) + np.abs(omega) * robot.track / 2


def test_the_wheel_speed_limit_is_the_cause_of_the_early_chapter_7_arrivals() -> None:
    # Ch. 7 Config 1 (Table 7.1: 8.2 s): bounding v alone lets the outer wheel run faster
    # than V in the turn and the robot arrives 12 % early; bounding each wheel gives the row
    sc = nav.configuration(1, chapter=7)
    limited = nav.simulate(sc, nav.EXPERIMENT_GAINS, stabilising="off")
    free_robot = nav.NonholonomicRobot(wheel_speed_limit=False)
    free = nav.simulate(sc.replace(robot=free_robot), nav.EXPERIMENT_GAINS, stabilising="off")
    assert sc.robot.wheel_speed_limit
    assert _rim_speed(limited, sc.robot).max() <= sc.robot.max_speed + 1e-6
    assert _rim_speed(free, free_robot).max() > sc.robot.max_speed + 0.1
    assert abs(limited.arrival_time / 8.2 - 1) <= 0.07 < abs(free.arrival_time / 8.2 - 1)
    # Config 3 (11.2 s): with the limit, the unstated tolerance explains the rest (0.05 m:
    # the robot comes in off the line and loops once); without it the same tolerance does not
    sc3 = nav.configuration(3, chapter=7)
    tight = nav.simulate(sc3, nav.EXPERIMENT_GAINS, stabilising="off", arrival_tolerance=0.05)
    loose = nav.simulate(sc3.replace(robot=free_robot), nav.EXPERIMENT_GAINS,
                         stabilising="off", arrival_tolerance=0.05)  # fmt: skip
    assert abs(tight.arrival_time / 11.2 - 1) <= 0.07 < abs(loose.arrival_time / 11.2 - 1)
