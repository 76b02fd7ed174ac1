"""The chunked sweep engine: result columns assembled in place, the same whatever the chunking."""

from __future__ import annotations

import numpy as np
import pandas as pd
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.analysis.engine import run_points
from designlab.analysis.sampling import LatinHypercubePoints


def flaky(points, options):
    """y = 2x, a flag x > 0 and a label; raises for any x in the ``bad`` set."""
    x = points["x"]
    bad = np.isin(x, options["bad"])
    if bad.any():
        raise ValueError(f"bad x {x[bad][0]:g}")
    return {"y": 2 * x, "positive": x > 0, "label": np.where(x > 0, "pos", "neg")}


def _expected(xs: list[float], bad: set[float]) -> pd.DataFrame:
    """Row by row, independently of the engine: NaN / None where a point failed."""
    rows = []
    for x in xs:
        if x in bad:
            rows.append({"y": np.nan, "positive": None, "label": None, "status": "error",
                         "error": f"ValueError: bad x {x:g}"})  # fmt: skip
        else:
            rows.append({"y": 2 * x, "positive": x > 0, "label": "pos" if x > 0 else "neg",
                         "status": "ok", "error": None})  # fmt: skip
    return pd.DataFrame(rows)


@settings(max_examples=60, deadline=None)
@given(
    xs=st.lists(st.integers(-5, 5).map(float), min_size=1, max_size=40),
    bad=st.sets(st.integers(-5, 5).map(float), max_size=3),
    chunk=st.integers(1, 9),
)
def test_assembled_columns_match_a_row_by_row_evaluation(xs, bad, chunk):
    run = run_points({"x": np.array(xs)}, flaky, {"bad": sorted(bad)}, chunk_size=chunk)
    want = _expected(xs, bad)
    got = run.frame
    assert list(got["status"]) == list(want["status"])
    assert list(got["error"]) == list(want["error"])
    if set(xs) <= bad:  # nothing returned a result: no result columns to know of
        assert set(got.columns) == {"status", "error"}
        return
    np.testing.assert_array_equal(got["y"].to_numpy(), want["y"].to_numpy())
    for col in ("positive", "label"):
        assert [None if v is None else v for v in got[col]] == list(want[col])
    if not (set(xs) & bad):  # no failure: booleans stay boolean
        assert got["positive"].dtype == bool
    assert run.distinct == len(set(xs)) and run.duplicates == len(xs) - len(set(xs))
    assert len(run.digest) == 64


def test_digest_follows_points_and_options():
    a = run_points({"x": np.array([1.0, 2.0])}, flaky, {"bad": []})
    b = run_points({"x": np.array([1.0, 2.0])}, flaky, {"bad": []})
    c = run_points({"x": np.array([2.0, 1.0])}, flaky, {"bad": []})
    d = run_points({"x": np.array([1.0, 2.0])}, flaky, {"bad": [7.0]})
    assert a.digest == b.digest
    assert len({a.digest, c.digest, d.digest}) == 3


def test_hash_collisions_never_merge_different_points(monkeypatch):
    """With every row hashing alike, the value check still keeps distinct points apart."""
    import designlab.analysis.columns as columns

    monkeypatch.setattr(columns.pd.util, "hash_array", lambda a: np.zeros(len(a), dtype=np.uint64))
    xs = np.array([1.0, 2.0, 1.0, np.nan, np.nan, 3.0])
    first, inverse = columns.distinct_rows({"x": xs, "z": np.zeros(6)})
    assert list(first) == [0, 1, 3, 5]
    assert list(inverse) == [0, 1, 0, 2, 2, 3]


@settings(max_examples=200, deadline=None)
@given(
    rows=st.lists(
        st.tuples(st.sampled_from([0.0, 1.0, -2.5, np.nan]), st.sampled_from([3.0, 4.0])),
        min_size=1,
        max_size=30,
    )
)
def test_distinct_points_numbered_in_order_of_first_appearance(rows):
    """Against a dictionary of the rows, written here (NaN equal to NaN)."""
    from designlab.analysis.columns import distinct_rows

    keys = [tuple("nan" if v != v else v for v in r) for r in rows]
    seen: dict = {}
    want_inverse = [seen.setdefault(k, len(seen)) for k in keys]
    want_first = [keys.index(k) for k in seen]
    first, inverse = distinct_rows({"a": np.array([r[0] for r in rows]),
                                      "b": np.array([r[1] for r in rows])})  # fmt: skip
    if len(seen) == len(rows):
        assert first is None and inverse is None
    else:
        assert list(first) == want_first and list(inverse) == want_inverse


class DictStore:
    """The store protocol over a dict (what the engine needs, nothing more)."""

    def __init__(self):
        self.chunks = {}

    def get_chunk(self, key):
        return ("ok", self.chunks[key]) if key in self.chunks else ("missing", None)

    def put_chunk(self, key, columns):
        self.chunks[key] = {k: np.array(v, copy=True) for k, v in columns.items()}

    def discard(self, key):
        self.chunks.pop(key, None)


@settings(max_examples=40, deadline=None)
@given(
    xs=st.lists(st.integers(-6, 6).map(float), min_size=1, max_size=60),
    bad=st.sets(st.integers(-6, 6).map(float), max_size=2),
    chunk=st.integers(1, 7),
    block=st.integers(1, 13),
)
def test_results_left_in_the_store_read_back_equal_the_collected_ones(xs, bad, chunk, block):
    points = {"x": np.array(xs)}
    options = {"bad": sorted(bad)}
    collected = run_points(points, flaky, options, chunk_size=chunk)
    store = DictStore()
    lazy = run_points(points, flaky, options, chunk_size=chunk, store=store, collect=False)
    assert lazy.frame.empty and len(lazy.rows) == len(xs)
    assert lazy.status_counts == collected.frame["status"].value_counts().to_dict()
    assert lazy.failed_count == len(collected.failed)
    parts = [f for _, f in lazy.rows.blocks(slice(0, len(xs)), block)]
    read = pd.concat(parts, ignore_index=True)
    want = collected.frame
    assert list(read.columns) == list(want.columns)
    for c in want.columns:
        assert [None if (isinstance(v, float) and np.isnan(v)) else v for v in read[c]] == [
            None if (isinstance(v, float) and np.isnan(v)) else v for v in want[c]
        ], c
    some = lazy.rows.read(slice(len(xs) // 2, len(xs)), columns=["status"])
    assert list(some.columns) == ["status"]
    assert list(some["status"]) == list(want["status"][len(xs) // 2 :])


def test_a_chunk_gone_from_the_store_is_reported_when_read():
    from designlab.analysis.engine import CacheIncompleteError

    store = DictStore()
    lazy = run_points({"x": np.arange(10.0)}, flaky, {"bad": []}, chunk_size=4,
                      store=store, collect=False)  # fmt: skip
    store.chunks.clear()
    import pytest

    with pytest.raises(CacheIncompleteError, match="missing since it was written"):
        lazy.rows.read(slice(0, 3))
    with pytest.raises(ValueError, match="give a store"):
        run_points({"x": np.arange(3.0)}, flaky, {"bad": []}, collect=False)


def test_blocks_read_back_have_every_column_typed_alike():
    """A block whose chunks all failed still has the metric columns (NaN / None)."""
    store = DictStore()
    xs = np.array([5.0, 5.0, 1.0, 2.0, -1.0, 3.0])
    lazy = run_points({"x": xs}, flaky, {"bad": [5.0]}, chunk_size=1, store=store, collect=False)
    first = lazy.rows.read(slice(0, 2))
    later = lazy.rows.read(slice(2, 6))
    assert list(first.columns) == list(later.columns)
    assert first["y"].isna().all() and list(first["positive"]) == [None, None]
    assert later["positive"].dtype == object
    assert list(later["positive"]) == [True, True, False, True]


def doubling_in_place(points, options):
    """An evaluator that reuses its input arrays (allowed: they are its own copies)."""
    x = points["x"]
    x *= 2.0
    return {"y": x + points["c"]}


def test_evaluators_get_writable_copies_of_broadcast_points():
    x = np.arange(5.0)
    c = np.broadcast_to(np.float64(1.0), (5,))  # a constant column, as sweeps build them
    run = run_points({"x": x, "c": c}, doubling_in_place, chunk_size=2)
    assert list(run.frame["y"]) == [1.0, 3.0, 5.0, 7.0, 9.0]
    assert list(x) == [0.0, 1.0, 2.0, 3.0, 4.0]  # the caller's points are untouched


class CountingSource(LatinHypercubePoints):
    """A Latin hypercube that records the largest range the engine asks for."""

    largest = 0

    def _take(self, start, stop):
        CountingSource.largest = max(CountingSource.largest, stop - start)
        return super()._take(start, stop)


def test_a_streamed_source_is_drawn_a_chunk_at_a_time_and_gives_the_same_results():
    src = CountingSource({"x": (-3.0, 3.0)}, 1000, seed=2)
    want = run_points(src.columns(), flaky, {"bad": []}, chunk_size=64)
    CountingSource.largest = 0
    store = DictStore()
    lazy = run_points(src, flaky, {"bad": []}, chunk_size=64, store=store, collect=False)
    assert 0 < CountingSource.largest <= 64  # never the whole sample
    assert lazy.points == lazy.distinct == 1000
    again = run_points(src, flaky, {"bad": []}, chunk_size=64, store=store, resume=True,
                       collect=False)  # fmt: skip
    assert again.computed == 0 and again.digest == lazy.digest
    read = pd.concat([f for _, f in lazy.rows.blocks(slice(0, 1000), 300)], ignore_index=True)
    assert np.array_equal(read["y"].to_numpy(), want.frame["y"].to_numpy())
    assert read["status"].tolist() == ["ok"] * 1000
