"""A resumed streamed sweep finds its finished chunks by index: no point drawn, no chunk unpacked.

Every result is checked against the evaluator called directly on the whole sample
(an independent answer), never against the engine's own earlier output alone.
"""

from __future__ import annotations

import logging
import sqlite3

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.analysis.engine import HEAD_POINTS, run_points
from designlab.analysis.points import ArrayPoints, ConcatPoints
from designlab.analysis.sampling import GridPoints, LatinHypercubePoints, SobolPoints
from designlab.analysis.store import ChunkStore

N, CHUNK = 1000, 64  # 16 chunks, the last one short


def shifted_cube(points, options):
    """y = x^3 + c, a flag and a label; x within ``bad`` of 0.5 fails (status error)."""
    x = points["x"]
    if np.any(np.abs(x - 0.5) < options["bad"]):
        raise ValueError("x too close to 0.5")
    return {"y": x**3 + options["c"], "big": x > 0.7, "label": np.where(x > 0.2, "hi", "lo")}


class Counting(LatinHypercubePoints):
    """A Latin hypercube that counts the points the engine draws from it."""

    drawn = 0

    def _take(self, start, stop):
        Counting.drawn += stop - start
        return super()._take(start, stop)


def _source(seed: int = 4) -> Counting:
    return Counting({"x": (0.0, 1.0)}, N, seed=seed)


def _want(src, options) -> pd.DataFrame:
    """Written out from the evaluator's rule, independently of the engine."""
    x = src.columns()["x"]
    fails = np.abs(x - 0.5) < options["bad"]
    return pd.DataFrame({"y": np.where(fails, np.nan, x**3 + options["c"]),
                         "status": np.where(fails, "error", "ok")})  # fmt: skip


def _run(store, src, options, **kw):
    return run_points(src, shifted_cube, options, store=store, chunk_size=CHUNK, collect=False,
                      **kw)  # fmt: skip


def _table(run) -> pd.DataFrame:
    return pd.concat([f for _, f in run.rows.blocks(slice(0, N), 300)], ignore_index=True)


def _check(run, want) -> None:
    got = _table(run)
    np.testing.assert_allclose(got["y"].to_numpy(dtype=float), want["y"].to_numpy(), rtol=1e-15)
    assert got["status"].tolist() == want["status"].tolist()


@pytest.mark.parametrize("bad", [0.0, 0.002])
def test_a_resume_draws_no_point_and_unpacks_no_chunk(tmp_path, monkeypatch, bad):
    options = {"c": 1.0, "bad": bad}
    want = _want(_source(), options)
    with ChunkStore(tmp_path / "s.sqlite") as store:
        first = _run(store, _source(), options)
        assert first.computed == N
        _check(first, want)
    reads = []
    with ChunkStore(tmp_path / "s.sqlite") as store:
        monkeypatch.setattr(store, "get_chunk", lambda k, _g=store.get_chunk: reads.append(k)
                            or _g(k))  # fmt: skip
        Counting.drawn = 0
        again = _run(store, _source(), options, resume=True)
        assert Counting.drawn <= HEAD_POINTS  # the head of one chunk, to check the points
        assert reads == []  # finished chunks known from their summaries
        assert (again.computed, again.cached) == (0, N)
        assert again.digest == first.digest
        assert again.status_counts == want["status"].value_counts().to_dict()
        assert again.status_counts == first.status_counts
        assert again.rows.kinds == first.rows.kinds
        assert again.rows.partial == first.rows.partial
        _check(again, want)


def test_an_interrupted_run_loses_nothing_and_resumes_only_the_missing_chunks(tmp_path):
    options = {"c": 0.5, "bad": 0.0}
    want = _want(_source(), options)
    path = tmp_path / "s.sqlite"
    with ChunkStore(path) as store:
        done = []

        def put_then_stop(key, columns, summary=None, _put=store.put_chunk):
            _put(key, columns, summary)
            done.append(key)
            if len(done) == 5:
                raise KeyboardInterrupt

        store.put_chunk = put_then_stop
        with pytest.raises(KeyboardInterrupt):
            _run(store, _source(), options)
    with ChunkStore(path) as store:
        assert len(store) == 5
        Counting.drawn = 0
        resumed = _run(store, _source(), options, resume=True)
        assert (resumed.cached, resumed.computed) == (5 * CHUNK, N - 5 * CHUNK)
        assert Counting.drawn <= N - 5 * CHUNK + CHUNK  # the missing chunks and one check
        _check(resumed, want)


@pytest.mark.parametrize(
    "other",
    [
        lambda: Counting({"x": (0.0, 1.0)}, N, seed=5),  # another seed
        lambda: Counting({"x": (0.0, 1.0 + 1e-12)}, N, seed=4),  # another bound
        lambda: SobolPoints({"x": (0.0, 1.0)}, 1024, seed=4),  # another sampler
    ],
)
def test_a_store_of_another_sampler_or_seed_is_never_reused(tmp_path, other):
    options = {"c": 1.0, "bad": 0.0}
    with ChunkStore(tmp_path / "s.sqlite") as store:
        _run(store, _source(), options)
        src = other()
        run = _run(store, src, options, resume=True)
    assert run.cached == 0 and run.computed == len(src)
    got = pd.concat([f for _, f in run.rows.blocks(slice(0, len(src)), 500)], ignore_index=True)
    np.testing.assert_allclose(got["y"].to_numpy(), src.columns()["x"] ** 3 + 1.0, rtol=1e-15)


def test_other_options_or_chunk_size_reuse_nothing(tmp_path):
    with ChunkStore(tmp_path / "s.sqlite") as store:
        _run(store, _source(), {"c": 1.0, "bad": 0.0})
        assert _run(store, _source(), {"c": 2.0, "bad": 0.0}, resume=True).cached == 0
        other = run_points(_source(), shifted_cube, {"c": 1.0, "bad": 0.0}, store=store,
                           chunk_size=CHUNK + 1, collect=False, resume=True)  # fmt: skip
        assert other.cached == 0


def test_a_damaged_chunk_is_found_on_resume_and_recomputed(tmp_path):
    options = {"c": 1.0, "bad": 0.0}
    want = _want(_source(), options)
    path = tmp_path / "s.sqlite"
    with ChunkStore(path) as store:
        first = _run(store, _source(), options)
        store.checkpoint()
    hurt = first.rows.keys[3]
    with sqlite3.connect(path) as db:  # same length, other bytes: only the checksum tells
        (data,) = db.execute("SELECT data FROM chunks WHERE key = ?", (hurt,)).fetchone()
        db.execute("UPDATE chunks SET data = ? WHERE key = ?", (bytes(b ^ 1 for b in data), hurt))
    with ChunkStore(path) as store:
        again = _run(store, _source(), options, resume=True)
    assert again.corrupt == [hurt]
    assert (again.cached, again.computed) == (N - CHUNK, CHUNK)
    _check(again, want)


def test_a_store_without_summaries_is_read_chunk_by_chunk_without_drawing(tmp_path):
    """A store written before summaries existed (or repaired: summaries are not salvaged)."""
    options = {"c": 1.0, "bad": 0.002}
    want = _want(_source(), options)
    path = tmp_path / "s.sqlite"
    with ChunkStore(path) as store:
        _run(store, _source(), options)
    with sqlite3.connect(path) as db:
        db.execute("DROP TABLE summaries")
    with ChunkStore(path) as store:
        Counting.drawn = 0
        again = _run(store, _source(), options, resume=True)
    assert Counting.drawn == 0 and again.computed == 0
    assert again.status_counts == want["status"].value_counts().to_dict()
    _check(again, want)


class Drifting(LatinHypercubePoints):
    """A defective source: its identity claims points it does not draw (a shifted copy)."""

    shift = 0.0

    def _take(self, start, stop):
        return {k: v + Drifting.shift for k, v in super()._take(start, stop).items()}


def test_a_source_whose_points_differ_from_its_identity_reuses_nothing(tmp_path, caplog):
    options = {"c": 1.0, "bad": 0.0}
    with ChunkStore(tmp_path / "s.sqlite") as store:
        _run(store, Drifting({"x": (0.0, 1.0)}, N, seed=1), options)
        Drifting.shift = 0.25
        src = Drifting({"x": (0.0, 1.0)}, N, seed=1)
        with caplog.at_level(logging.WARNING, logger="designlab.analysis.engine"):
            run = _run(store, src, options, resume=True)
        x = src.columns()["x"]
        Drifting.shift = 0.0
    assert "recomputing every chunk" in caplog.text
    assert run.cached == 0 and run.computed == N
    np.testing.assert_allclose(_table(run)["y"].to_numpy(), x**3 + 1.0, rtol=1e-15)


@settings(max_examples=30, deadline=None)
@given(
    lo=st.floats(-10, 10),
    width=st.floats(1e-6, 10),
    n=st.integers(1, 300),
    seed=st.integers(0, 2**32),
    log=st.booleans(),
)
def test_equal_identities_mean_equal_points(lo, width, n, seed, log):
    """Identity follows every parameter of a sampler, and equal identities draw equal points."""
    bounds = {"x": (abs(lo) + 1e-3, abs(lo) + 1e-3 + width)}
    a = LatinHypercubePoints(bounds, n, seed=seed, log={"x": log})
    b = LatinHypercubePoints(dict(bounds), n, seed=seed, log={"x": log})
    assert a.identity() == b.identity()
    assert np.array_equal(a.columns()["x"], b.columns()["x"])
    for other in (
        LatinHypercubePoints(bounds, n + 1, seed=seed, log={"x": log}),
        LatinHypercubePoints(bounds, n, seed=seed + 1, log={"x": log}),
        LatinHypercubePoints(bounds, n, seed=seed, log={"x": not log}),
        LatinHypercubePoints({"y": bounds["x"]}, n, seed=seed, log={"y": log}),
    ):
        assert other.identity() != a.identity()


def test_identities_of_grids_arrays_and_joined_sets():
    g = GridPoints({"a": [1.0, 2.0], "b": [3.0, 4.0, 5.0]})
    swapped = GridPoints({"b": [3.0, 4.0, 5.0], "a": [1.0, 2.0]})  # other point order
    assert g.identity() != swapped.identity()
    assert g.identity() == GridPoints({"a": [1, 2], "b": [3, 4, 5]}).identity()
    a = ArrayPoints({"p": [1.0, 2.0], "q": [3.0, 4.0]})
    assert a.identity() != ArrayPoints({"p": [3.0, 4.0], "q": [1.0, 2.0]}).identity()
    assert a.identity() != ArrayPoints({"p": [1.0, 2.0], "q": [3.0, 4.0 + 1e-15]}).identity()
    both = ConcatPoints([a, ArrayPoints({"p": [5.0], "q": [6.0]})])
    assert both.identity() != ConcatPoints([ArrayPoints({"p": [5.0], "q": [6.0]}), a]).identity()

    class Unknown(ArrayPoints):
        def identity(self):
            return None

    assert ConcatPoints([a, Unknown({"p": [5.0], "q": [6.0]})]).identity() is None


STUDY = """\
designlab: 1
kind: impact_sweep
name: lhs_demo
base: {robot: MANIPULATOR_1, foam: FOAM_1, head: HEAD_MIN, impact_velocity: 1.25}
sweep:
  method: lhs
  samples: 300
  seed: 7
  parameters:
    head.mass: {low: 4.4, high: 5.3}
    foam.stiffness: {low: 13.48e3, high: 60.6e3, scale: log}
sensitivity: {tornado: true}
"""


def test_a_streamed_study_resumes_from_the_cli_without_drawing_its_sample(tmp_path, monkeypatch):
    """`designlab run` then `--resume` of a streamed LHS study (with its tornado set)."""
    from typer.testing import CliRunner

    from designlab.cli import app
    from designlab.report import sweep as report_sweep
    from designlab.study import sweep_runner

    monkeypatch.setattr(sweep_runner, "STREAM_FROM", 100)  # stream (index keys) from 100 points
    monkeypatch.setattr(report_sweep, "LARGE_SWEEP", 100)  # and write Parquet
    drawn = []
    take = LatinHypercubePoints._take
    monkeypatch.setattr(LatinHypercubePoints, "_take",
                        lambda self, s, e: drawn.append(e - s) or take(self, s, e))  # fmt: skip
    study = tmp_path / "lhs_demo.yaml"
    study.write_text(STUDY)
    out, cache = tmp_path / "out", tmp_path / "cache"
    args = ["run", str(study), "-o", str(out), "--cache-dir", str(cache)]
    first = CliRunner().invoke(app, args)
    assert first.exit_code == 0, first.output
    n = 1 + 300 + 4 + 1  # base, sample, tornado ends, the local elasticities' base
    assert f"({n} computed, 0 from the store" in first.output
    table = (out / "lhs_demo" / "results.parquet").read_bytes()
    drawn.clear()
    again = CliRunner().invoke(app, [*args, "--resume"])
    assert again.exit_code == 0, again.output
    assert f"(0 computed, {n} from the store" in again.output
    assert "report up to date" in again.output
    assert sum(drawn) <= HEAD_POINTS  # the check of one chunk's head, nothing else
    assert (out / "lhs_demo" / "results.parquet").read_bytes() == table
    # the table against the evaluator called on the sample directly
    got = pd.read_parquet(out / "lhs_demo" / "results.parquet")
    box = {"foam.stiffness": (13.48e3, 60.6e3), "head.mass": (4.4, 5.3)}  # the kind's order
    src = LatinHypercubePoints(box, 300, seed=7, log={"foam.stiffness": True}).columns()
    from designlab.impact import FOAM_1, HEAD_MIN, MANIPULATOR_1, impact_metrics

    r, f, h = MANIPULATOR_1, FOAM_1, HEAD_MIN
    want = impact_metrics({"M_r": r.mass, "C_r": r.damping, "K_r": r.stiffness,
                           "K_c": src["foam.stiffness"], "C_c": f.damping,
                           "M_h": src["head.mass"], "C_h": h.damping, "K_h": h.stiffness},
                          1.25)  # fmt: skip
    np.testing.assert_array_equal(got["K_c_N_per_m"].to_numpy(), src["foam.stiffness"])
    np.testing.assert_allclose(got["a_h_max_g"].to_numpy(), want.peak_head_acceleration_g,
                               rtol=1e-12)  # fmt: skip
