"""The chunked sweep engine: result columns assembled in place, the same whatever the chunking."""

from __future__ import annotations

import numpy as np
import pandas as pd
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.analysis.sweep import run_points


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
    import designlab.analysis.sweep as sweep

    monkeypatch.setattr(sweep.pd.util, "hash_array", lambda a: np.zeros(len(a), dtype=np.uint64))
    xs = np.array([1.0, 2.0, 1.0, np.nan, np.nan, 3.0])
    first, inverse = sweep._distinct({"x": xs, "z": np.zeros(6)})
    assert list(first) == [0, 1, 3, 5]
    assert list(inverse) == [0, 1, 0, 2, 2, 3]
