"""Any method's gains through the batch and the optimiser; criterion weights everywhere."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.errors import InvalidParameterError

nav = dl.navigation


@pytest.mark.parametrize(
    ("method", "gains", "row"),
    [
        ("masoud", nav.MasoudGains(k1=4.0, k3=30.0, k5=40.0), [4.0, 1.0, 30.0, 40.0]),
        ("ge_cui", nav.GeCuiGains(k1=1.5, b=0.6, k3=12.0, k5=16.0), [1.5, 0.6, 12.0, 16.0]),
    ],
)
def test_batch_of_a_baseline_equals_its_single_runs(method: str, gains: object, row: list) -> None:
    sc = nav.configuration(1)
    single = nav.simulate(sc, gains, method=method)
    batch = nav.simulate_batch([sc], [row, row], method=method)
    assert batch.arrival_time[0, 0] == single.arrival_time == batch.arrival_time[0, 1]
    assert batch.H[0, 0] == pytest.approx(single.criteria.H, rel=1e-12)
    assert batch.min_distance[0, 0, 0] == single.min_distance["circle"]


@settings(max_examples=10, deadline=None)
@given(w=st.tuples(st.floats(0, 1), st.floats(0, 1), st.floats(0, 1)).filter(lambda w: sum(w) > 0))
def test_weights_combine_the_three_criteria(w: tuple[float, float, float]) -> None:
    weights = tuple(x / sum(w) for x in w)
    res = nav.simulate(nav.configuration(1), nav.OPTIMAL_GAINS, stabilising="off")
    c = res.criteria
    expected = weights[0] * c.H_T + weights[1] * c.H_D + weights[2] * c.H_E
    weighted = nav.criteria(
        arrival_time=c.arrival_time, nominal_arrival_time=c.nominal_arrival_time,
        energy=c.energy, nominal_energy=c.nominal_energy,
        surface_clearance=res.min_surface_distance,
        nominal_clearance={"circle": 0.8 - 0.2 - 0.1}, weights=weights,
    )  # fmt: skip
    assert weighted.H == pytest.approx(expected, rel=1e-12)


def test_weights_reach_simulate_batch_and_the_optimiser_objective() -> None:
    sc = [nav.configuration(1)]
    g = [[4.3, 0.68, 20.3, 240.7]]
    only_time = nav.simulate_batch(sc, g, stabilising="off", weights=(1.0, 0.0, 0.0))
    assert only_time.H[0, 0] == pytest.approx(only_time.H_T[0, 0], rel=1e-12)
    single = nav.simulate(sc[0], nav.OPTIMAL_GAINS, stabilising="off", weights=(0.0, 1.0, 0.0))
    assert single.criteria.H == pytest.approx(single.criteria.H_D, rel=1e-12)
    e = nav.evaluate_gains(sc, g, stabilising="off", weights=(0.0, 0.0, 1.0)).to_frame()
    assert e["H_mean"][0] == pytest.approx(only_time.H_E[0, 0], rel=1e-12)


@pytest.mark.parametrize("bad", [(1, 1, 1), (0.5, 0.5), (float("nan"), 0.5, 0.5), (-1, 1, 1), "x"])
def test_bad_weights_are_refused_everywhere(bad: object) -> None:
    sc = nav.configuration(1)
    for call in (
        lambda: nav.simulate(sc, nav.OPTIMAL_GAINS, weights=bad),
        lambda: nav.simulate_batch([sc], [[4.3, 0.68, 20.3, 240.7]], weights=bad),
        lambda: nav.optimise_gains([sc], weights=bad, max_evaluations=8, popsize=8),
    ):
        with pytest.raises(InvalidParameterError, match="weights"):
            call()


def test_optimiser_takes_a_baselines_gains() -> None:
    opt = nav.optimise_gains([nav.configuration(1)], method="masoud", stabilising="off",
                             seed=1, max_evaluations=4, popsize=4, refine=False)  # fmt: skip
    assert isinstance(opt.gains, nav.MasoudGains) and opt.method == "masoud"
    check = nav.simulate(nav.configuration(1), opt.gains, method="masoud")
    assert check.criteria.H == pytest.approx(opt.objective, rel=1e-9)
    assert "b" not in opt.on_bounds()
    with pytest.raises(InvalidParameterError, match="method"):
        nav.optimise_gains([nav.configuration(1)], method="cbf", max_evaluations=8, popsize=8)
    assert np.isfinite(opt.objective)


def test_weights_from_yaml_reach_the_runs() -> None:
    from designlab.navigation.evaluators import vff_metrics_chunk
    from designlab.study import parse_study, run_study

    study = parse_study(
        "designlab: 1\nkind: navigation_scenarios\nname: w\nscenarios: [{configuration: 1}]\n"
        "methods: [{label: a, gains: {k1: 4.3, b: 0.68, k3: 20.3, k5: 240.7}, "
        "stabilising: 'off'}]\nweights: [1, 0, 0]\n"
    )
    row = run_study(study).to_frame().iloc[0]
    assert row["H"] == pytest.approx(row["H_T"], rel=1e-12)
    pts = {"k1": np.array([4.3]), "b": np.array([0.68]), "k3": np.array([20.3]),
           "k5": np.array([240.7]), "v_max": np.array([0.7]), "a_max": np.array([10.0]),
           "v_h": np.array([1.0])}  # fmt: skip
    out = vff_metrics_chunk(pts, {"scenarios": [[1, 6]], "stabilising": "off",
                                  "weights": [1.0, 0.0, 0.0]})  # fmt: skip
    assert out["H_mean"][0] == pytest.approx(row["H_T"], rel=1e-12)
