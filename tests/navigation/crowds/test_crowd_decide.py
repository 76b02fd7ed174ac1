"""Issue 35, item 6: the study's decisions (exact McNemar on paired crowds, minimum
detectable difference, the time-limit curve) and the study file's methods."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from scipy.stats import binom

from designlab.errors import InvalidParameterError
from designlab.navigation.crowds.decide import (
    decision_findings,
    holm,
    mcnemar,
    minimum_detectable_difference,
    time_limit_curve,
)
from designlab.navigation.crowds.study import crowd_study, simulate_run
from designlab.study import parse_study


def test_mcnemar_is_the_exact_binomial_test_of_the_discordant_crowds():
    # 10 crowds: a alone arrived in 7, b alone in 1, both in 2 -> p = 2 P(X <= 1), X~B(8, .5)
    a = [1] * 7 + [0] + [1, 1]
    b = [0] * 7 + [1] + [1, 1]
    runs = pd.DataFrame({"scenario": "s", "density": 0.5, "seed": np.repeat(range(10), 2),
                         "method": ["a", "b"] * 10,
                         "success": np.ravel(np.column_stack([a, b]))})  # fmt: skip
    r = mcnemar(runs).iloc[0]
    assert (r.a_only, r.b_only, r.pairs) == (7, 1, 10)
    assert r.p_value == pytest.approx(2 * binom.cdf(1, 8, 0.5), rel=1e-12)
    with pytest.raises(InvalidParameterError):
        mcnemar(runs.drop(columns="seed"))


def test_minimum_detectable_difference_closed_form():
    # (z_.975 + z_.8) sqrt(0.5 / n): 2.8015852 sqrt(0.005) at n = 100
    assert minimum_detectable_difference(100) == pytest.approx(
        (1.959963984540054 + 0.8416212335729143) * math.sqrt(0.005), rel=1e-12
    )
    with pytest.raises(InvalidParameterError):
        minimum_detectable_difference(0)


def test_the_time_limit_curve_counts_arrivals_within_each_limit():
    runs = pd.DataFrame({"scenario": "s", "density": 1.0, "method": "m",
                         "success": [1.0, 1.0, 1.0, 0.0],
                         "arrival_time_s": [12.0, 19.9, 20.1, np.inf],
                         "outcome_time_s": [12.0, 19.9, 20.1, 5.0], "free_run_s": 10.0,
                         "time_limit_s": 40.0})  # fmt: skip
    c = time_limit_curve(runs, [1.0, 2.0, 4.0])
    assert c["success_rate"].tolist() == [0.0, 0.5, 0.75]
    with pytest.raises(InvalidParameterError, match="factors"):
        time_limit_curve(runs, [5.0])


def test_a_study_runs_the_baselines_and_measures_the_field_metrics():
    st = crowd_study(["corridor_counterflow"], [0.3], [0, 1], ["orca", "social_force"],
                     crowd_options={"length": 8.0, "width": 3.0, "horizon": 3.0})  # fmt: skip
    runs = st.runs
    assert set(runs["method"]) == {"orca", "social_force"} and len(runs) == 4
    for col in (
        "path_length_m",
        "jerk_mean",
        "discomfort_share",
        "ttc_min_s",
        "frozen",
        "collision_by",
        "outcome_time_s",
        "left_area",
    ):
        assert col in runs
    # the Voronoi density: once per crowd (the first method's run)
    v = runs.groupby("method")["voronoi_density_per_m2"].apply(lambda s: np.isfinite(s).sum())
    assert v.to_dict() == {"orca": 2, "social_force": 0}
    summary = st.to_frame()
    assert {"spl", "left_area_rate", "simulator_failed_rate", "collisions_by_robot"} <= set(
        summary.columns
    )


def test_the_study_file_refuses_a_method_a_crowd_cannot_run():
    text = """
designlab: 1
kind: navigation_crowds
name: x
scenarios: [corridor_counterflow]
densities: [0.1]
seeds: [0]
methods: [{method: %s}]
"""
    assert parse_study(text % "orca").methods[0].method == "orca"
    for bad in ("vff_cbf", "vo", "bug"):
        with pytest.raises(Exception, match="method"):
            parse_study(text % bad)


def test_holm_is_the_step_down_adjustment():
    # sorted p 0.01, 0.03, 0.04 (m = 3): 3 x 0.01, max(0.03, 2 x 0.03), max(0.06, 1 x 0.04)
    assert holm([0.01, 0.04, 0.03]).tolist() == pytest.approx([0.03, 0.06, 0.06], rel=1e-15)
    assert holm([0.5, 0.9]).tolist() == [1.0, 1.0]  # capped at 1
    assert holm([]).size == 0
    with pytest.raises(InvalidParameterError, match="p_values"):
        holm([0.2, math.nan])


def test_findings_call_a_difference_after_holm_and_cells_carry_the_model():
    # two cells (one per pedestrian model), 20 crowds: p arrives in all, q in 14 (cfs) and 19
    rows = []
    for model, q_arrivals in (("collision_free_speed", 14), ("social_force", 19)):
        for seed in range(20):
            rows += [{"model": model, "scenario": "s", "density": 1.0, "seed": seed,
                      "method": "p", "success": 1.0},
                     {"model": model, "scenario": "s", "density": 1.0, "seed": seed,
                      "method": "q", "success": float(seed < q_arrivals)}]  # fmt: skip
    tests = mcnemar(pd.DataFrame(rows))
    assert tests["model"].tolist() == ["collision_free_speed", "social_force"]
    assert tests["a_only"].tolist() == [6, 1] and tests["b_only"].tolist() == [0, 0]
    # exact: 2 x 0.5^6 = 1/32 and 1; Holm over 2 tests: 1/16 and 1
    assert tests["p_value"].tolist() == pytest.approx([1 / 32, 1.0], rel=1e-12)
    lines = decision_findings(tests, 20)
    assert "among collision_free_speed pedestrians" in lines[0]
    assert "no difference shown" in lines[0] and "Holm-adjusted 0.062" in lines[0]
    assert lines[-2].startswith("- 0 of 2 pairwise tests show a difference")
    called = decision_findings(tests, 20, alpha=0.1)
    assert "p more often (6 vs 0" in called[0] and called[-2].startswith("- 1 of 2")


def test_the_grid_runs_every_crowd_under_each_pedestrian_model():
    st = crowd_study(["corridor_counterflow"], [0.3], [0], ["vff", "orca"],
                     crowd_options={"length": 8.0, "horizon": 1.2, "react_to_robot": True},
                     models=["collision_free_speed", "social_force"])  # fmt: skip
    runs = st.runs
    assert sorted(zip(runs.model, runs.method, strict=True)) == [
        ("collision_free_speed", "orca"), ("collision_free_speed", "vff"),
        ("social_force", "orca"), ("social_force", "vff")]  # fmt: skip
    summary = st.to_frame()
    assert summary[["model", "method"]].values.tolist() == [
        ["collision_free_speed", "vff"], ["collision_free_speed", "orca"],
        ["social_force", "vff"], ["social_force", "orca"]]  # fmt: skip
    # the same robot among different pedestrians: the models are not one run twice
    cfs = runs[(runs.model == "collision_free_speed") & (runs.method == "vff")].iloc[0]
    sf = runs[(runs.model == "social_force") & (runs.method == "vff")].iloc[0]
    assert cfs["min_centre_distance_m"] != sf["min_centre_distance_m"]
    again = simulate_run(st.settings["options"], "corridor_counterflow", 0.3, 0, "vff",
                         "social_force")  # fmt: skip
    assert again.crowd.model == "social_force"


@pytest.mark.parametrize("models", [[], ["boids"], ["social_force", "social_force"], [3]])
def test_a_bad_model_list_is_refused_before_any_run(models):
    with pytest.raises(InvalidParameterError, match="models"):
        crowd_study(["crossing"], [0.1], [0], ["vff"], models=models,
                    crowd_options={"length": 8.0, "horizon": 0.5})  # fmt: skip


def test_the_compiled_path_deviation_is_the_polyline_distance():
    from designlab.navigation.crowds.bookkeeping import farthest_from_path

    path = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]])
    # (1, 2): 2 from the first leg; (-1, 0): 1 from the start; (6, 8): 5 from the corner (3, 4)
    pts = np.array([[1.0, 2.0], [-1.0, 0.0], [6.0, 8.0]])
    assert farthest_from_path(pts, path) == 5.0
    assert farthest_from_path(pts[:2], path) == 2.0
    # a repeated vertex (a zero-length segment) is a point
    assert farthest_from_path(np.array([[0.0, 1.0]]), np.array([[0.0, 0.0], [0.0, 0.0]])) == 1.0


def test_a_warning_names_the_pedestrian_model_of_its_run():
    from designlab.navigation.crowds.study import abnormal_runs

    runs = pd.DataFrame({"scenario": ["crossing"] * 2, "density": [0.5] * 2, "seed": [3, 3],
                         "method": ["vff"] * 2, "model": ["collision_free_speed", "social_force"],
                         "outcome": ["success", "left_area"], "outcome_time_s": [9.0, 4.2],
                         "coupling_exceeded": [1.0, 0.0]})  # fmt: skip
    assert abnormal_runs(runs) == [
        "crossing 0.5/m^2 among collision_free_speed pedestrians seed 3 vff: the robot's "
        "JuPedSim agent was more than the bound away from the robot (the pedestrians did not "
        "see it where it was)",
        "crossing 0.5/m^2 among social_force pedestrians seed 3 vff: the robot left the "
        "walkable area at t = 4.20 s",
    ]
