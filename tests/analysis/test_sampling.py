"""Samples generated a chunk at a time: the same points however they are split."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import qmc

from designlab.analysis import lhs_kernel, sampling
from designlab.analysis.points import ArrayPoints, ConcatPoints
from designlab.analysis.sampling import (
    GridPoints,
    LatinHypercubePoints,
    SobolPoints,
)


@settings(max_examples=80, deadline=None)
@given(
    n=st.integers(1, 3000),
    d=st.integers(1, 4),
    seed=st.integers(0, 2**32 - 1),
    cut=st.floats(0.0, 1.0),
)
def test_latin_hypercube_has_one_point_per_stratum_in_every_chunking(n, d, seed, cut):
    names = [f"p{j}" for j in range(d)]
    src = LatinHypercubePoints({k: (0.0, 1.0) for k in names}, n, seed=seed)
    whole = src.columns()
    for k in names:
        x = whole[k]
        assert np.all((x >= 0) & (x < 1))
        strata = np.floor(x * n).astype(int)  # exactly one point in each of the n strata
        assert sorted(strata.tolist()) == list(range(n))
    s = round(cut * n)
    parts = [src.take(0, s), src.take(s, n)]
    for k in names:
        assert np.array_equal(np.concatenate([p[k] for p in parts]), whole[k])


@pytest.mark.skipif(not lhs_kernel.AVAILABLE, reason="compiled kernels unavailable")
@settings(max_examples=30, deadline=None)
@given(n=st.integers(1, 5000), seed=st.integers(0, 2**64 - 1), start=st.floats(0.0, 1.0))
def test_compiled_latin_hypercube_equals_the_numpy_path_bit_for_bit(n, seed, start):
    src = LatinHypercubePoints({"a": (1.0, 9.0), "b": (1e3, 1e5)}, n, seed=seed, log={"b": True})
    lo = round(start * n)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(sampling, "COMPILED_FROM", 1)  # compiled for every range, however small
        fast = src.take(lo, n)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(lhs_kernel, "AVAILABLE", False)
        slow = src.take(lo, n)
    for k in fast:
        assert np.array_equal(fast[k], slow[k])


def test_latin_hypercube_is_seeded_scaled_and_uncorrelated():
    box = {"k": (1e4, 6e4), "c": (10.0, 200.0)}
    a = LatinHypercubePoints(box, 20_000, seed=3, log={"k": True}).columns()
    b = LatinHypercubePoints(box, 20_000, seed=3, log={"k": True}).columns()
    c = LatinHypercubePoints(box, 20_000, seed=4, log={"k": True}).columns()
    assert all(np.array_equal(a[k], b[k]) for k in box)
    assert not np.array_equal(a["k"], c["k"])
    u = (np.log(a["k"]) - math.log(1e4)) / (math.log(6e4) - math.log(1e4))
    assert sorted(np.floor(u * 20_000).astype(int).tolist()) == list(range(20_000))
    assert a["c"].min() >= 10.0 and a["c"].max() < 200.0
    # independent dimensions and no trend along the index (|r| ~ 1/sqrt(n) = 0.007)
    assert abs(np.corrcoef(a["k"], a["c"])[0, 1]) < 0.03
    assert abs(np.corrcoef(a["c"][:-1], a["c"][1:])[0, 1]) < 0.03
    # the permutation is not the identity in disguise: strata are scattered over the index
    strata = np.floor((a["c"] - 10.0) / 190.0 * 20_000)
    assert abs(np.corrcoef(strata, np.arange(20_000))[0, 1]) < 0.03


@settings(max_examples=30, deadline=None)
@given(m=st.integers(0, 11), seed=st.integers(0, 1000), cut=st.floats(0.0, 1.0))
def test_sobol_chunks_equal_scipys_whole_sequence(m, seed, cut):
    n = 2**m
    want = qmc.Sobol(d=3, scramble=True, rng=np.random.default_rng(seed)).random_base2(m)
    src = SobolPoints({"a": (0.0, 1.0), "b": (-1.0, 1.0), "c": (0.0, 1.0)}, n, seed=seed)
    s = round(cut * n)
    got = [src.take(0, s), src.take(s, n)]
    assert np.allclose(np.concatenate([g["a"] for g in got]), want[:, 0], rtol=0, atol=0)
    assert np.allclose(np.concatenate([g["b"] for g in got]), -1.0 + 2.0 * want[:, 1])


def test_sobol_refuses_a_size_that_is_not_a_power_of_two():
    with pytest.raises(ValueError, match="power of two, got 12"):
        SobolPoints({"a": (0.0, 1.0)}, 12)


@settings(max_examples=40, deadline=None)
@given(
    sizes=st.lists(st.integers(1, 5), min_size=1, max_size=4),
    start=st.integers(0, 700),
    length=st.integers(0, 700),
)
def test_grid_ranges_equal_rows_of_the_full_product(sizes, start, length):
    values = {f"p{j}": [10.0 * j + i for i in range(k)] for j, k in enumerate(sizes)}
    rows = [[]]
    for j in range(len(sizes)):  # the product written out: last name fastest
        rows = [[*r, v] for r in rows for v in values[f"p{j}"]]
    src = GridPoints(values)
    assert len(src) == len(rows)
    s = min(start, len(rows))
    e = min(s + length, len(rows))
    got = src.take(s, e)
    for j in range(len(sizes)):
        assert got[f"p{j}"].tolist() == [r[j] for r in rows[s:e]]


def test_concatenated_sources_and_bad_ranges():
    a = ArrayPoints({"x": np.arange(4.0), "y": np.full(4, 7.0)})
    b = GridPoints({"x": [10.0, 11.0], "y": [7.0]})
    both = ConcatPoints([a, ArrayPoints({"x": [], "y": []}), b])
    assert len(both) == 6
    got = both.take(3, 6)
    assert got["x"].tolist() == [3.0, 10.0, 11.0] and got["y"].tolist() == [7.0] * 3
    with pytest.raises(IndexError, match=r"points \[5, 9\) are not within \[0, 6\]"):
        both.take(5, 9)
    with pytest.raises(ValueError, match="different columns"):
        ConcatPoints([a, ArrayPoints({"x": [1.0]})])
    with pytest.raises(ValueError, match="1-D and of one length"):
        ArrayPoints({"x": [1.0, 2.0], "y": [1.0]})
