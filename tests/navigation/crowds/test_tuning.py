"""Gains for crowds: disjoint validation, the robust cost and rates, the optimise_gains entry."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import designlab as dl
from designlab.errors import DesignlabError
from designlab.navigation.crowds.metrics import cvar, wilson_interval
from designlab.navigation.crowds.tuning import (
    CrowdSet,
    at_bounds,
    check_disjoint,
    optimise_crowd_gains,
    paired_comparison,
    run_penalties,
    validate_gains,
    validation_steps,
)
from designlab.navigation.crowds.tuning import score_runs as score
from designlab.navigation.tuning import DEFAULT_BOUNDS

SHORT = {"length": 8.0, "horizon": 1.0}


@pytest.mark.parametrize(
    ("seeds", "densities"), [((1, 5), (0.4,)), ((7,), (0.2, 0.4)), ((0,), (0.2,))]
)
def test_validation_sharing_a_seed_or_density_is_refused(seeds: tuple, densities: tuple) -> None:
    train = CrowdSet(("crossing",), (0.2,), (0, 1))
    with pytest.raises(DesignlabError, match="share nothing"):
        check_disjoint(train, CrowdSet(("crossing",), densities, seeds))
    if set(seeds) & {0, 1}:
        with pytest.raises(DesignlabError, match="share nothing"):
            validate_gains({"x": dl.navigation.OPTIMAL_GAINS, "y": dl.navigation.EXPERIMENT_GAINS},
                           [("seeds", CrowdSet(("crossing",), densities, seeds))], train,
                           reference="y", penalty=40.0)  # fmt: skip


def test_disjoint_sets_pass() -> None:
    check_disjoint(
        CrowdSet(("crossing",), (0.2,), range(3)), CrowdSet(("bottleneck",), (0.5,), range(3, 6))
    )


def _runs(
    arrival: list[float], collided: list[int], critical: list[int], **cols: list
) -> pd.DataFrame:
    """Hand-built runs: 40 s limit, 12 s free run over 9 m (0.75 m/s), clear by default."""
    a = np.asarray(arrival, dtype=float)
    n = a.size
    ok = np.isfinite(a) & (np.asarray(collided) == 0)
    base = {"arrival_time_s": a, "success": ok.astype(float), "collided": collided,
            "critical": critical, "time_limit_s": 40.0, "free_run_s": 12.0, "shortest_m": 9.0,
            "goal_distance_m": np.zeros(n), "critical_time_s": np.zeros(n),
            "outcome_time_s": np.where(ok, a, 40.0),
            "min_surface_distance_m": np.ones(n)}  # fmt: skip
    base.update({k: np.asarray(v, dtype=float) for k, v in cols.items()})
    return pd.DataFrame(base)


def test_run_penalties_against_hand_built_runs() -> None:
    runs = _runs([10.0, np.inf, np.inf, np.inf], [0, 0, 0, 1], [0, 1, 1, 1],
                 goal_distance_m=[0.0, 3.0, 0.0, 6.0], critical_time_s=[0.0, 10.0, 40.0, 5.0],
                 outcome_time_s=[10.0, 40.0, 40.0, 20.0],
                 min_surface_distance_m=[0.5, 0.15, 0.0, -0.04])  # fmt: skip
    pen = run_penalties(runs)
    # time cost: the arrival time; else the limit + the distance left at 9 m / 12 s
    assert pen["time_cost_s"].tolist() == pytest.approx([10.0, 44.0, 40.0, 48.0])
    assert pen["critical_share"].tolist() == pytest.approx([0.0, 0.25, 1.0, 0.25])
    # deficit below 0.2 m: 0 when clear, 1 at touching, + depth / 0.2 m in a collision
    assert pen["clearance_deficit"].tolist() == pytest.approx([0.0, 0.25, 1.0, 1.2])
    assert pen["violation"].tolist() == pytest.approx([0.0, 0.5, 2.0, 1.45])
    with pytest.raises(DesignlabError, match="columns"):
        run_penalties(runs.drop(columns="goal_distance_m"))
    with pytest.raises(DesignlabError):
        run_penalties(runs, distance=-0.1)


def test_score_mean_cvar_and_rates() -> None:
    train = CrowdSet(("crossing",), (0.2,), (0, 1, 2, 3), critical_rate=0.25)
    runs = _runs(
        [10.0, 12.0, np.inf, 20.0], [0, 0, 0, 0], [0, 1, 0, 0], goal_distance_m=[0, 0, 1.5, 0]
    )
    costs = [10.0, 12.0, 42.0, 20.0]  # 40 s limit + 1.5 m at 0.75 m/s
    mean = score(runs, train, 30.0, "mean", 0.8)
    assert mean["cost_s"] == pytest.approx(np.mean(costs)) and mean["feasible"]
    assert mean["violation"] == 0 and mean["fitness"] == mean["cost_s"]
    assert mean["success_rate"] == 0.75
    assert (
        score(runs, train, 30.0, "cvar", 0.5)["cost_s"] == pytest.approx(cvar(costs, 0.5)) == 31.0
    )
    bad = _runs([10.0, 12.0, 9.0, 20.0], [0, 1, 0, 0], [1, 1, 0, 0],
                min_surface_distance_m=[0.1, -0.02, 1.0, 1.0],
                critical_time_s=[2.5, 3.0, 0.0, 0.0])  # fmt: skip
    s = score(bad, train, 30.0, "mean", 0.8)
    assert not s["feasible"] and s["collision_rate"] == 0.25 and s["critical_rate"] == 0.5
    # violation: (0.25 + 0.5) + (0.075 + 1.1) over four runs; fitness = cost + 30 s x violation
    assert s["violation"] == pytest.approx((0.25 + 0.5 + 0.075 + 1.1) / 4)
    assert s["fitness"] == pytest.approx(s["cost_s"] + 30.0 * s["violation"])
    assert score(bad, train, 30.0, "mean", 0.8, penalty=5.0)["fitness"] == pytest.approx(
        s["cost_s"] + 5.0 * s["violation"]
    )


def test_the_penalty_has_a_signal_where_the_count_had_none() -> None:
    """Issue 35.6: every infeasible candidate scored 4 x horizon x 1.5. Candidates that all
    collide and time out now rank by how deep, how long and how far from the goal."""
    train = CrowdSet(("crossing",), (0.2,), (0, 1, 2))

    def fit(depth: float, crit: float, left: float) -> float:
        runs = _runs([np.inf] * 3, [1, 1, 1], [1, 1, 1], min_surface_distance_m=[-depth] * 3,
                     critical_time_s=[crit] * 3, goal_distance_m=[left] * 3)  # fmt: skip
        return score(runs, train, 40.0, "mean", 0.8)["fitness"]

    base = fit(0.02, 5.0, 2.0)
    assert fit(0.04, 5.0, 2.0) > base > fit(0.01, 5.0, 2.0)
    assert fit(0.02, 6.0, 2.0) > base > fit(0.02, 4.0, 2.0)
    assert fit(0.02, 5.0, 3.0) > base > fit(0.02, 5.0, 1.0)
    # exactly: 40 + 2 / 0.75 s, plus 40 s x (5/40 + 1 + 0.02/0.2)
    assert base == pytest.approx(40 + 2 / 0.75 + 40 * (0.125 + 1.1))


def test_at_bounds() -> None:
    box = {"k1": (1.0, 10.0), "b": (0.1, 1.0), "k3": (1.0, 100.0), "k5": (1.0, 100.0)}
    g = dl.navigation.VFFGains(k1=1.0, b=1.0, k3=10.0, k5=10 ** (2 * 0.985))
    assert at_bounds(g, box) == ("b: upper", "k1: lower", "k5: upper")
    assert at_bounds(g, box, tolerance=0.01) == ("b: upper", "k1: lower")
    inside = dl.navigation.VFFGains(k1=3.0, b=0.3, k3=10.0, k5=10.0)
    assert at_bounds(inside, box) == ()
    with pytest.raises(DesignlabError):
        at_bounds(inside, box, tolerance=0.6)


def test_validation_changes_one_factor_at_a_time() -> None:
    train = CrowdSet(("corridor_counterflow",), (0.3,), range(4), SHORT, collision_rate=0.1)
    steps = validation_steps(train, [10, 11], 0.5, "crossing")
    assert [n for n, _ in steps] == ["seeds", "density", "layout"]
    sets = [s for _, s in steps]
    assert [(s.scenarios, s.densities, s.seeds) for s in sets] == [
        (("corridor_counterflow",), (0.3,), (10, 11)),
        (("corridor_counterflow",), (0.5,), (10, 11)),
        (("crossing",), (0.5,), (10, 11)),
    ]
    assert all(s.crowd_options == SHORT and s.collision_rate == 0.1 for s in sets)
    for args, what in ((([3, 10], 0.5, "crossing"), "seeds"),
                       (([10], 0.3, "crossing"), "densities"),
                       (([10], 0.5, "corridor_counterflow"), "scenarios")):  # fmt: skip
        with pytest.raises(DesignlabError, match=f"validation.{what}.*share nothing"):
            validation_steps(train, *args)


def _paired(d_costs: list[float], a_success: list[int], b_success: list[int]) -> pd.DataFrame:
    rows = []
    for k, (d, sa, sb) in enumerate(zip(d_costs, a_success, b_success, strict=True)):
        for m, s, extra in (("p", sa, d), ("q", sb, 0.0)):
            r = _runs([20.0 + extra], [0], [0]).iloc[0].to_dict()
            # a 20 s limit: a run that did not arrive (0 m from the goal) costs 20 s
            rows.append({**r, "success": float(s), "time_limit_s": 20.0, "scenario": "x",
                         "density": 0.3, "seed": k, "method": m, "status": "ok"})  # fmt: skip
    return pd.DataFrame(rows)


def test_paired_comparison_against_closed_forms() -> None:
    from scipy.stats import t

    runs = _paired([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0], [1, 1, 1, 1, 1, 1, 1], [0] * 7)
    r = paired_comparison(runs, "p", "q", 40.0)
    assert r["pairs"] == 7 and r["a_success"] == 7 and r["b_success"] == 0
    assert r["mcnemar_p"] == pytest.approx(2 * 0.5**7)  # 7 discordant pairs, all one way
    assert r["difference_s"] == pytest.approx(4.0)
    half = t.ppf(0.975, 6) * np.std(np.arange(1, 8), ddof=1) / np.sqrt(7)
    assert r["difference_low_s"] == pytest.approx(4.0 - half)
    assert r["difference_high_s"] == pytest.approx(4.0 + half) and r["decided"]
    assert r["wilcoxon_p"] == pytest.approx(2 / 2**7)  # exact: all seven ranks one sign
    assert r["a_success_low"] == pytest.approx(wilson_interval(7, 7)[0])
    even = paired_comparison(
        _paired([1.0, -1.0, 2.0, -2.0], [1, 1, 1, 1], [1, 1, 1, 1]), "p", "q", 40.0
    )
    assert even["difference_s"] == 0 and not even["decided"] and even["mcnemar_p"] == 1.0
    # a raised run leaves its crowd out of the pairs
    runs.loc[0, "status"] = "error"
    assert paired_comparison(runs, "p", "q", 40.0)["pairs"] == 6


def test_bad_sets_and_options() -> None:
    with pytest.raises(DesignlabError):
        CrowdSet(("crossing",), (0.2,), (0,), critical_rate=1.5)
    with pytest.raises(DesignlabError):
        CrowdSet("crossing", (0.2,), (0,))
    train = CrowdSet(("corridor_counterflow",), (0.1,), (0,), SHORT)
    for bad in ({"robust": "worst"}, {"alpha": 1.0}, {"popsize": 2}, {"generations": 0},
                {"bounds": {**DEFAULT_BOUNDS, "k1": (5.0, 1.0)}}):  # fmt: skip
        with pytest.raises(DesignlabError):
            optimise_crowd_gains(train, **{"bounds": DEFAULT_BOUNDS, **bad})
    with pytest.raises(DesignlabError, match="CrowdSet takes only"):
        dl.navigation.optimise_gains(train, refine=False)


def test_optimise_gains_over_a_crowd_set() -> None:
    """One generation of four candidates on one short crowd: a result with its history."""
    train = CrowdSet(
        ("corridor_counterflow",), (0.1,), (0,), SHORT, critical_rate=1.0, collision_rate=1.0
    )
    opt = dl.navigation.optimise_gains(train, robust="cvar", popsize=4, generations=1, seed=3)
    assert opt.evaluations == 4 and len(opt.to_frame()) == 4
    assert opt.status == "ok" and opt.robust == "cvar"
    lo = {k: v[0] for k, v in DEFAULT_BOUNDS.items()}
    hi = {k: v[1] for k, v in DEFAULT_BOUNDS.items()}
    assert all(lo[k] <= getattr(opt.gains, k) <= hi[k] for k in lo)
    # every horizon-1 s run times out: its cost is the 1 s limit plus the distance left at
    # the free-run speed; the fitness adds the 1 s penalty per unit of violation
    h = opt.to_frame()
    assert (h["cost_s"] > 1.0).all() and (h["success_rate"] == 0).all()
    assert h["fitness"].tolist() == pytest.approx((h["cost_s"] + h["violation"]).tolist())
    assert opt.penalty == 1.0 and opt.runs == 1


def test_tuning_runs_leave_out_the_side_measures_only() -> None:
    """``measures=False`` (tuning and validation) changes no run, only leaves out the
    robot-free run, the Voronoi density and the crowd met (NaN)."""
    from designlab.navigation.crowds.study import crowd_study

    opts = {"length": 8.0, "horizon": 3.0, "react_to_robot": True}
    full = crowd_study(["corridor_counterflow"], [0.2], [0], ["vff"], crowd_options=opts).runs
    bare = crowd_study(
        ["corridor_counterflow"], [0.2], [0], ["vff"], crowd_options=opts, measures=False
    ).runs
    left_out = ["ped_delay_mean_s", "ped_deviation_max_m", "voronoi_density_per_m2",
                "measured_density_per_m2", "mean_ped_speed_m_per_s"]  # fmt: skip
    assert bare[left_out].isna().all(axis=None) and full[left_out].notna().all(axis=None)
    same = ["outcome", "outcome_time_s", "min_distance_m", "critical_time_s",
            "min_surface_distance_m", "goal_distance_m", "path_length_m"]  # fmt: skip
    pd.testing.assert_frame_equal(full[same], bare[same])
    assert bare["goal_distance_m"].iloc[0] > 0  # 3 s is too short to arrive
