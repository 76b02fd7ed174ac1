"""The rest of Zeng 2011 Ch. 5-7: the Sec. 6.4.5 Masoud K3 = 48 run, report figures."""

from __future__ import annotations

import numpy as np
import pytest

import designlab as dl

nav = dl.navigation


def test_masoud_with_doubled_repulsion_clears_the_parallel_human_at_a_cost_in_h() -> None:
    # Sec. 6.4.5: with K3 = 48 the robot clears the human (d_h > 0.61 m) but H drops by
    # about 8 % on average over the four configurations.
    base, doubled = nav.MasoudGains(), nav.MasoudGains(k3=48.0)
    par = nav.configuration("parallel")
    assert nav.simulate(par, base, method="masoud").collided
    run = nav.simulate(par, doubled, method="masoud")
    assert not run.collided and run.min_distance["human"] > 0.61
    h = [
        [nav.simulate(nav.configuration(c), g, method="masoud").criteria.H for c in (1, 2, 3, 4)]
        for g in (base, doubled)
    ]
    drop = 1 - np.mean(h[1]) / np.mean(h[0])
    assert 0.04 < drop < 0.15


def test_energy_trace_integrates_to_the_runs_energy_and_shows_the_turn() -> None:
    # Fig. 7.5: the nonholonomic robot's turn in front of the circle costs most of the energy
    res = nav.simulate(nav.configuration(1, chapter=7), nav.EXPERIMENT_GAINS, stabilising="off")
    e = res.energy_trace()
    k = int(np.searchsorted(res.t, res.arrival_time))
    assert e[k] == pytest.approx(res.energy, rel=1e-9)
    assert np.all(np.diff(e) >= 0)
    rate = np.diff(e) / np.diff(res.t)
    window = 1.0  # s: the busiest second
    n = round(float(window / (res.t[1] - res.t[0])))
    sums = np.convolve(rate, np.ones(n), "valid")
    busiest = sums.max() * (res.t[1] - res.t[0])
    # one second of the 8 s run holds over 40 % of the energy (three times its share; half
    # before the wheel-speed limit of issue 21 made the turn gentler), and it is the turn:
    # the heading changes fastest inside that second
    assert busiest > 0.4 * res.energy
    start = int(np.argmax(sums))
    turn = int(np.argmax(np.abs(np.diff(np.unwrap(res.trajectory_frame()["heading_rad"])))))
    assert start <= turn <= start + n


def test_force_map_splits_the_field_into_attraction_and_obstacles() -> None:
    from designlab.navigation.force_map import force_map

    sc = nav.configuration(3)
    x, y = np.linspace(-0.5, 4.5, 41), np.linspace(-1.0, 2.2, 33)
    total = force_map(sc, nav.EXPERIMENT_GAINS, x, y)
    obst = force_map(sc, nav.EXPERIMENT_GAINS, x, y, part="obstacles")
    X, Y = np.meshgrid(x, y)
    attraction = 3.0 * np.stack([sc.goal[0] - X, sc.goal[1] - Y], axis=2)
    ok = np.isfinite(total.norm) & (total.norm < 1e6)  # away from the singular r3
    assert np.allclose((total.force - obst.force)[ok], attraction[ok], atol=1e-9)
    # outside every active region only the attraction is left
    far = np.hypot(X - 2.45, Y - 1.4) > 0.81
    far &= (np.abs(X - 2.3) > 0.7 + 0.81) | (np.abs(Y) > 0.3 + 0.81)
    assert np.allclose(obst.norm[far], 0.0, atol=1e-9)
    _, _, mf = total.minimum
    assert np.isfinite(mf) and mf >= 0
