"""Large sweeps left in the result store: the same table, summary and report as in memory."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from designlab.analysis.store import open_store
from designlab.report import write_report
from designlab.study import RunContext, parse_study, points_table, run_study, sweep_runner
from designlab.study.points_table import FrameTable, StoredTable

LHS = """\
designlab: 1
kind: impact_sweep
name: big_sweep
base: {robot: MANIPULATOR_1, foam: FOAM_1, head: HEAD_MIN, impact_velocity: 1.25}
sweep:
  method: lhs
  samples: 700
  seed: 3
  parameters:
    foam.stiffness: {low: 2e3, high: 60e3, scale: log}
    foam.damping: {low: 0, high: 150}
    head.mass: {low: 4.4, high: 5.3}
sensitivity:
  metrics: [a_h_max_g, eps_max_m]
  tornado: true
"""


@settings(max_examples=50, deadline=None)
@given(
    values=arrays(
        float, st.integers(1, 300), elements=st.one_of(st.floats(-1e6, 1e6), st.just(np.nan))
    ),
    block=st.integers(1, 50),
)
@pytest.mark.slow
def test_block_moments_equal_numpy_on_the_whole_column(values, block):
    frame = pd.DataFrame({"x": values, "status": "ok", "error": None})
    table = FrameTable(frame)
    table.blocks = (
        lambda rows=block: (  # type: ignore[method-assign]
            frame.iloc[s : s + block] for s in range(0, len(frame), block)
        )
    )
    m = table.scan().moments["x"]
    finite = values[~np.isnan(values)]
    assert m["count"] == len(finite)
    if len(finite):
        assert m["min"] == finite.min() and m["max"] == finite.max()
        assert m["mean"] == pytest.approx(finite.mean(), rel=1e-9, abs=1e-6)
    if len(finite) > 1:
        assert m["std"] == pytest.approx(finite.std(ddof=1), rel=1e-7, abs=1e-6)


def _same(a: pd.DataFrame, b: pd.DataFrame) -> None:
    """Equal values, missing as missing (None, NaN or NA alike), whatever the dtypes."""

    def norm(f: pd.DataFrame) -> pd.DataFrame:
        f = f.reset_index(drop=True).astype(object)
        return f.where(f.notna(), None)

    pd.testing.assert_frame_equal(norm(a), norm(b))


@pytest.fixture
def small_limits(monkeypatch):
    """Stream from 100 points, Parquet from 100 rows, subsets of 64 rows, blocks of 50 rows."""
    from designlab.report import sweep as report_sweep

    monkeypatch.setattr(sweep_runner, "STREAM_FROM", 100)
    monkeypatch.setattr(report_sweep, "LARGE_SWEEP", 100)
    monkeypatch.setattr(points_table, "SUBSET_ROWS", 64)
    monkeypatch.setattr(points_table, "BLOCK_ROWS", 50)


def test_a_streamed_sweep_equals_the_one_in_memory(small_limits, tmp_path):
    study = parse_study(LHS)
    memory = run_study(study)
    assert isinstance(memory.table, FrameTable)
    with open_store(tmp_path / "cache", study.name) as store:
        streamed = run_study(study, RunContext(store=store))
        assert isinstance(streamed.table, StoredTable)
        _same(streamed.frame, memory.frame)
        assert streamed.warnings == memory.warnings
        assert streamed.stats["failed"] == memory.stats["failed"]
        for kind in memory.sensitivity:
            pd.testing.assert_frame_equal(
                streamed.sensitivity[kind].frame, memory.sensitivity[kind].frame
            )
        scan = streamed.table.scan()
        assert scan.step == 11 and len(scan.subset) == 64  # every 11th of 700 rows
        _same(scan.subset, memory.frame.iloc[::11])
        out = write_report(streamed, tmp_path / "reports")
    table = pd.read_parquet(out / "results.parquet")
    _same(table, memory.frame)
    summary = pd.read_csv(out / "results_summary.csv").set_index("column")
    whole = memory.frame
    for col in ("a_h_max_g", "K_c_N_per_m"):
        assert summary.loc[col, "count"] == whole[col].notna().sum()
        assert summary.loc[col, "max"] == pytest.approx(whole[col].max(), rel=1e-6)
        assert summary.loc[col, "std"] == pytest.approx(whole[col].std(), rel=1e-6)
        assert summary.loc[col, "50%"] == pytest.approx(whole[col].iloc[::11].median(), rel=1e-6)
        assert summary.loc[col, "quantiles_of"] == 64
    statuses = summary.loc[[i for i in summary.index if i.startswith("status=")], "count"]
    assert statuses.sum() == 700
    text = (out / "summary.md").read_text()
    assert "use every 11th point (64 points, evenly spread)" in text


@pytest.mark.slow
def test_a_streamed_sweep_on_worker_processes_writes_the_same_parquet(small_limits, tmp_path):
    from designlab.analysis.executors import make_executor

    study = parse_study(LHS)
    tables = {}
    for name in ("serial", "processes"):
        ex = make_executor(name, workers=2) if name == "processes" else None
        try:
            with open_store(tmp_path / name, study.name) as store:
                result = run_study(study, RunContext(store=store, executor=ex))
                assert isinstance(result.table, StoredTable)
                out = write_report(result, tmp_path / f"reports_{name}", index=False)
        finally:
            if ex is not None:
                ex.close()
        tables[name] = pd.read_parquet(out / "results.parquet")
    assert len(tables["serial"]) == 700
    pd.testing.assert_frame_equal(tables["processes"], tables["serial"])


def test_a_streamed_sweep_never_draws_its_whole_sample(small_limits, tmp_path, monkeypatch):
    """Memory bounded by the chunk: the LHS is drawn a chunk or a block at a time, never whole."""
    from designlab.analysis import sampling
    from designlab.impact import evaluators as impact_sweep

    monkeypatch.setattr(impact_sweep.impact_metrics_chunk, "chunk_size", 40)
    drawn: list[int] = []
    original = sampling.LatinHypercubePoints._take

    def spy(self, start, stop):
        drawn.append(stop - start)
        return original(self, start, stop)

    monkeypatch.setattr(sampling.LatinHypercubePoints, "_take", spy)
    study = parse_study(LHS)
    with open_store(tmp_path / "cache", study.name) as store:
        result = run_study(study, RunContext(store=store))
        write_report(result, tmp_path / "reports")
    assert drawn and max(drawn) <= 50  # chunks of 40 points, report blocks of 50 rows
    assert sum(drawn) >= 2 * 700  # evaluated, then read back for the report


@pytest.mark.slow
def test_the_scan_subset_keeps_no_block_alive(monkeypatch):
    """The evenly spread subset copies its rows: no block outlives its turn in the pass."""
    import gc
    import weakref

    monkeypatch.setattr(points_table, "SUBSET_ROWS", 64)  # every 16th of 1000 rows
    arrays: list[weakref.ref] = []
    alive_before: list[int] = []

    def blocks(rows=None):
        for s in range(0, 1000, 100):
            gc.collect()
            alive_before.append(sum(r() is not None for r in arrays))
            x = np.arange(s, s + 100, dtype=float)
            arrays.append(weakref.ref(x))
            yield pd.DataFrame({"x": x, "status": "ok", "error": None}, index=range(s, s + 100),
                               copy=False)  # fmt: skip
            del x

    table = FrameTable(pd.DataFrame({"x": [0.0], "status": "ok", "error": None}))
    table.blocks = blocks  # type: ignore[method-assign]
    monkeypatch.setattr(FrameTable, "__len__", lambda self: 1000)
    subset = table.scan().subset
    assert subset["x"].tolist() == list(np.arange(0.0, 1000.0, 16.0))
    assert max(alive_before) <= 1  # at most the block just handed over
