"""optimise_gains: the machinery on tiny seeded runs (the real optimisation is in
benchmarks/vff_gains.py and studies/navigation_gains.yaml)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.navigation.tuning import DEFAULT_BOUNDS
from designlab.results import check_result

nav = dl.navigation
THESIS = nav.VFFGains(4.3, 0.68, 20.3, 240.7)


@pytest.fixture(scope="module")
def tiny():
    # the second run simulates with the four-lane compiled step: the same path to the bit
    kw = dict(stabilising="off", seed=3, popsize=6, max_evaluations=12, refine_evaluations=16)
    return nav.optimise_gains([nav.configuration(1)], **kw), nav.optimise_gains(
        [nav.configuration(1)], **kw, jit=True
    )


def test_tiny_run_is_reproducible_and_consistent(tiny):
    a, b = tiny
    check_result(a)
    assert a.gains is not None and a.gains == b.gains and a.objective == b.objective
    assert a.history.equals(b.history)  # every candidate scored alike
    # budget: 2 CMA-ES generations of 6, then at most two polls of 8
    assert a.evaluations == 12 + 8 * (len(a.history) - 2)
    assert list(a.history["phase"][:2]) == ["cma", "cma"]
    assert a.history["best_H_mean"].dropna().is_monotonic_increasing
    # the reported objective is the simulator's H of the reported gains, and that point is feasible
    f = nav.evaluate_gains([nav.configuration(1)], a.gains, stabilising="off").frame
    assert bool(f["feasible"][0])
    assert math.isclose(a.objective, float(f["H_mean"][0]), rel_tol=1e-12)
    lo = np.array([DEFAULT_BOUNDS[n][0] for n in ("k1", "b", "k3", "k5")])
    hi = np.array([DEFAULT_BOUNDS[n][1] for n in ("k1", "b", "k3", "k5")])
    g = a.gains.as_array()
    assert np.all(g >= lo * (1 - 1e-12)) and np.all(g <= hi * (1 + 1e-12))
    row = a.to_frame().iloc[0]
    assert row["H_mean"] == a.objective and row["evaluations"] == a.evaluations


def test_a_violating_candidate_is_infeasible_not_scored():
    # K3 -> 0 in Configuration 2: the robot enters the human's critical region
    # (Zeng 2011, App. C.3) yet its H is well above zero: it must not count.
    f = nav.evaluate_gains(
        [nav.configuration(2)], [[4.3, 0.68, 1e-6, 240.7], THESIS.as_array()], stabilising="off"
    ).frame
    assert not f["feasible"][0] and not f["critical_free"][0] and f["H_mean"][0] > 0.3
    assert f["feasible"][1]


def test_no_feasible_point_gives_status_infeasible():
    opt = nav.optimise_gains(
        [nav.configuration(2)],
        stabilising="off",
        seed=0,
        popsize=4,
        max_evaluations=4,
        bounds=dict(k3=(1e-6, 2e-6), k5=(1e-6, 2e-6)),
        refine=False,
    )
    check_result(opt)
    assert opt.status == "infeasible" and opt.gains is None and math.isnan(opt.objective)
    assert opt.history["feasible_share"].max() == 0.0 and opt.warnings


def test_random_walks_draws_and_worst_case():
    rw = nav.RandomWalks(
        n=3, speed=(0.8, 1.2), start_time=(0.0, 0.5), lateral_offset=(-0.1, 0.1), seed=4
    )
    walks = rw.expand(nav.configuration(2))
    assert [s.name for s in walks] == [f"ch6_config2_walk{k}" for k in range(3)]
    for s in walks:
        w = s.obstacles[0].motion
        assert 0.8 <= w.speed <= 1.2 and 0.0 <= w.start_time <= 0.5
        assert (
            abs(w.start[1] - 0.6) <= 0.1 + 1e-12 and w.start[1] == w.end[1]
        )  # lateral to an x-walk
    assert [s.obstacles[0].motion for s in rw.expand(nav.configuration(2))] == [
        s.obstacles[0].motion for s in walks
    ]
    assert rw.expand(nav.configuration(3)) == [nav.configuration(3)]  # nothing walks
    sc = [nav.configuration(2)]
    mean = nav.evaluate_gains(sc, THESIS, stabilising="off", robust=rw, robust_mode="mean").frame
    worst = nav.evaluate_gains(sc, THESIS, stabilising="off", robust=rw, robust_mode="worst").frame
    assert worst["H_mean"][0] <= mean["H_mean"][0]


@pytest.mark.parametrize(
    "kw",
    [
        dict(bounds={"k1": (0.0, 5.0)}),
        dict(bounds={"k1": (5.0, 1.0)}),
        dict(bounds={"k1": (math.nan, 5.0)}),
        dict(bounds={"k2": (1.0, 2.0)}),
        dict(bounds={"b": 3.0}),
        dict(stabilising="on"),
        dict(robust_mode="median"),
        dict(popsize=2),
        dict(max_evaluations=3),
        dict(seed=-1),
        dict(sigma0=0.0),
        dict(robust="walks"),
        dict(x0=nav.VFFGains(100.0, 0.5, 10.0, 10.0)),
        dict(executor=object()),
        dict(jit="yes"),
        dict(jit=1),
    ],
)
def test_bad_input_is_rejected(kw):
    with pytest.raises(InvalidParameterError):
        nav.optimise_gains([nav.configuration(1)], **kw)


@pytest.mark.parametrize(
    "kw",
    [
        dict(n=0),
        dict(speed=(0.0, 1.0)),
        dict(start_time=(-1.0, 0.0)),
        dict(lateral_offset=(0.2, 0.1)),
        dict(speed=(math.inf, 1.0)),
        dict(n=2.5),
    ],
)
def test_bad_random_walks(kw):
    with pytest.raises(InvalidParameterError):
        nav.RandomWalks(**kw)


def test_bad_scenarios():
    with pytest.raises(InvalidParameterError):
        nav.optimise_gains([])
    with pytest.raises(InvalidParameterError):
        nav.optimise_gains([nav.configuration(1), nav.configuration(1)])


def test_arrival_times_and_margins_match_single_runs():
    # T_arrive and the margin to the critical region, written out from single simulate() runs
    sc = [nav.configuration(1), nav.configuration(3)]
    gains = [THESIS, nav.VFFGains(3.0, 0.25, 20.0, 17.0)]
    f = nav.evaluate_gains(sc, gains, stabilising="off").frame
    for j, g in enumerate(gains):
        for s in sc:
            run = nav.simulate(s, g, stabilising="off")
            assert f[f"T_arrive_s_{s.name}"][j] == pytest.approx(run.arrival_time, abs=1e-9)
            margin = min(run.min_distance[o.name] - o.r3 for o in s.obstacles)
            assert f[f"critical_margin_m_{s.name}"][j] == pytest.approx(margin, abs=1e-9)
            assert (margin > 0) == (not run.entered_critical)


def test_margin_is_negative_when_the_critical_region_is_entered():
    f = nav.evaluate_gains(
        [nav.configuration(2)], [[4.3, 0.68, 1e-6, 240.7]], stabilising="off"
    ).frame
    assert not f["critical_free"][0] and f["critical_margin_m_ch6_config2"][0] < 0


def test_on_bounds_reads_the_box(tiny):
    a, _ = tiny
    g = a.gains
    for n, side in a.on_bounds().items():
        lo, hi = a.bounds[n]
        assert math.isclose(getattr(g, n), lo if side == "low" else hi, rel_tol=0.01)
    inside = [n for n in ("k1", "b", "k3", "k5") if n not in a.on_bounds()]
    for n in inside:
        lo, hi = a.bounds[n]
        assert lo * 1.001 < getattr(g, n) < hi / 1.001


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(1, 6),
    seed=st.integers(0, 2**31),
    v=st.tuples(st.floats(0.1, 2.0), st.floats(0.0, 1.0)),
    t0=st.tuples(st.floats(0.0, 2.0), st.floats(0.0, 2.0)),
    off=st.tuples(st.floats(-0.5, 0.5), st.floats(0.0, 0.5)),
)
def test_random_walks_stay_in_their_ranges(n, seed, v, t0, off):
    speed = (v[0], v[0] + v[1])
    start = (t0[0], t0[0] + t0[1])
    lateral = (off[0], off[0] + off[1])
    rw = nav.RandomWalks(n=n, speed=speed, start_time=start, lateral_offset=lateral, seed=seed)
    base = nav.configuration(2).obstacles[0].motion
    walks = rw.expand(nav.configuration(2))
    assert len(walks) == n
    for s in walks:
        w = s.obstacles[0].motion
        assert speed[0] <= w.speed <= speed[1]
        assert start[0] <= w.start_time <= start[1]
        # the walk is shifted normal to its direction (+y for a walk along +x), unchanged in x
        dy = w.start[1] - base.start[1]
        assert lateral[0] - 1e-12 <= dy <= lateral[1] + 1e-12
        assert w.end[1] - base.end[1] == pytest.approx(dy, abs=1e-12)
        assert w.start[0] == pytest.approx(base.start[0]) and w.end[0] == pytest.approx(base.end[0])
    assert [s.obstacles[0].motion for s in rw.expand(nav.configuration(2))] == [
        s.obstacles[0].motion for s in walks
    ]


def test_robust_worst_case_optimum_is_scored_by_its_worst_walk():
    rw = nav.RandomWalks(n=2, seed=1)
    sc = [nav.configuration(2)]
    kw = dict(stabilising="off", seed=2, popsize=4, max_evaluations=8, refine=False)
    opt = nav.optimise_gains(sc, robust=rw, robust_mode="worst", **kw)
    check_result(opt)
    assert opt.walks == 2 and opt.robust_mode == "worst" and opt.simulations == 8 * 2
    # the worst of the two walks, written out from the batch simulator
    h = nav.simulate_batch(rw.expand(sc[0]), opt.gains.as_array()[None, :], stabilising="off").H
    assert opt.objective == pytest.approx(float(h[:, 0].min()), rel=1e-12)
    again = nav.optimise_gains(sc, robust=rw, robust_mode="worst", **kw)
    assert again.gains == opt.gains


def test_a_clearance_margin_tightens_feasibility():
    # Configuration 1 with the experimental gains: the robot passes the circle's critical
    # region by about 0.086 m (reports/navigation_gains); a 0.1 m clearance makes it infeasible
    sc = [nav.configuration(1)]
    g = nav.VFFGains(3.0, 0.25, 20.0, 17.0)
    run = nav.simulate(sc[0], g, stabilising="off")
    gap = min(run.min_distance[o.name] - o.r3 for o in sc[0].obstacles)
    assert 0 < gap < 0.5
    below = nav.evaluate_gains(sc, g, stabilising="off", critical_margin=gap * 0.9).frame
    above = nav.evaluate_gains(sc, g, stabilising="off", critical_margin=gap * 1.1).frame
    assert bool(below["feasible"][0]) and not bool(above["feasible"][0])
    assert not bool(above["critical_free"][0]) and bool(above["arrived_all"][0])
    # the optimiser then only returns points that keep the clearance
    opt = nav.optimise_gains(
        sc, stabilising="off", seed=0, popsize=6, max_evaluations=12, refine=False,
        critical_margin=0.1,
    )  # fmt: skip
    assert opt.critical_margin == 0.1 and opt.gains is not None
    f = nav.evaluate_gains(sc, opt.gains, stabilising="off").frame
    assert f["critical_margin_m_ch6_config1"][0] >= 0.1


@pytest.mark.parametrize("bad", [-0.1, math.nan, math.inf, True, "0.1"])
def test_bad_critical_margin(bad):
    with pytest.raises(InvalidParameterError, match="critical_margin"):
        nav.evaluate_gains([nav.configuration(1)], THESIS, critical_margin=bad)
