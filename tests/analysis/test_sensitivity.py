"""The sensitivity generators on callable metrics, against exact answers of power laws."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.analysis.sensitivity import elasticities, one_at_a_time, sobol_indices

exponent = st.floats(-3, 3).filter(lambda a: abs(a) > 1e-3)
value = st.floats(0.1, 100)


@settings(max_examples=40, deadline=None)
@given(a=exponent, b=exponent, pa=value, pb=value, d=st.sampled_from([-50.0, -10.0, 5.0, 100.0]))
def test_power_law_sensitivities_are_exact(a, b, pa, pb, d):
    # m = pa^a pb^b: the elasticity is the exponent, and the App.-C sensitivity of a
    # change by d % is ((1 + d/100)^a - 1) / (d/100) exactly
    def metric(p):
        return {"m": p["a"] ** a * p["b"] ** b}

    base = {"a": pa, "b": pb}
    el = elasticities(metric, base, ["a", "b"], relative_step=1e-5).frame.set_index("parameter")
    assert el.loc["a", "elasticity"] == pytest.approx(a, rel=1e-6, abs=1e-6)
    assert el.loc["b", "elasticity"] == pytest.approx(b, rel=1e-6, abs=1e-6)
    oat = one_at_a_time(metric, base, ["a", "b"], [d]).frame.set_index("parameter")
    x = d / 100
    assert oat.loc["a", "S_pct"] == pytest.approx(100 * ((1 + x) ** a - 1) / x, rel=1e-9)
    assert oat.loc["b", "S_pct"] == pytest.approx(100 * ((1 + x) ** b - 1) / x, rel=1e-9)


def test_sobol_indices_of_an_additive_model():
    # y = 4 x1 + x2, uniform on [0, 1]^2: S1 = ST = 16/17 and 1/17 exactly
    t = sobol_indices(lambda p: {"y": 4 * p["x1"] + p["x2"]}, {}, {"x1": (0, 1), "x2": (0, 1)},
                      1024, seed=3).frame.set_index("parameter")  # fmt: skip
    assert t.loc["x1", "ST"] == pytest.approx(16 / 17, abs=0.03)
    assert t.loc["x2", "S1"] == pytest.approx(1 / 17, abs=0.03)


def test_bad_inputs_are_named():
    with pytest.raises(ValueError, match="not in the base point"):
        one_at_a_time(lambda p: {"y": p["a"]}, {"a": 1.0}, ["b"])
    with pytest.raises(ValueError, match="is 0 at the base"):
        elasticities(lambda p: {"y": p["a"]}, {"a": 0.0}, ["a"])
    with pytest.raises(ValueError, match="returned 1 values for 3 points"):
        one_at_a_time(lambda p: {"y": np.ones(1)}, {"a": 1.0}, ["a"], [1, 2])


def test_sobol_intervals_are_reproducible_with_seed_zero() -> None:
    # SALib leaves its bootstrap unseeded for seed 0 (``if seed:``); the table seeds it
    from designlab.analysis.sensitivity import sobol_indices

    box = {"a": (0.0, 1.0), "b": (0.0, 1.0), "c": (0.0, 1.0)}

    def f(p):
        return {"y": p["a"] * p["b"] + p["c"]}

    for seed in (0, 1):
        one = sobol_indices(f, {}, box, 32, seed=seed).frame
        two = sobol_indices(f, {}, box, 32, seed=seed).frame
        assert one.equals(two)
