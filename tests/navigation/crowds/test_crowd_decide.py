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
    mcnemar,
    minimum_detectable_difference,
    time_limit_curve,
)
from designlab.navigation.crowds.study import crowd_study
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
