"""Executors: identical results whichever runs the sweep; failures recorded; clear errors."""

from __future__ import annotations

import math

import pytest

from designlab.analysis.engine import run_points
from designlab.analysis.executors import ExecutorError, make_executor
from designlab.analysis.sampling import LatinHypercubePoints
from designlab.impact.sweep import impact_metrics_chunk

BASE = {"M_r": 9.6, "C_r": 250.0, "K_r": 20e3, "K_c": 24.25e3, "C_c": 71.9,
        "lambda": 0.02, "M_h": 4.4, "C_h": 46.0, "K_h": 3e3, "v_c": 1.25}  # fmt: skip


def _points(n: int = 40) -> list[dict[str, float]]:
    box = {"K_c": (5e3, 60e3), "C_c": (10.0, 150.0), "M_h": (4.4, 5.3), "v_c": (0.4, 2.0)}
    cols = LatinHypercubePoints(box, n, seed=3).columns()
    pts = [dict(BASE, **{k: float(v[i]) for k, v in cols.items()}) for i in range(n)]
    pts[7] = dict(pts[7], K_r=0.0, K_h=0.0)  # no restoring stiffness: the model refuses it
    return pts


def _check_failure_recorded(run) -> None:
    assert run.failed == [7]
    bad = run.results[7]
    assert bad["status"] == "error"
    assert bad["error"].startswith("ModelError: design 0: the model has a pole at s = 0"), bad
    assert math.isnan(bad["a_h_max_g"])
    assert all(
        r["status"] in ("ok", "peak_at_contact") for i, r in enumerate(run.results) if i != 7
    )


@pytest.fixture(scope="module")
def serial_run():
    run = run_points(_points(), impact_metrics_chunk, chunk_size=8)
    _check_failure_recorded(run)
    return run


def test_processes_match_serial(serial_run):
    with make_executor("processes", workers=2) as ex:
        run = run_points(_points(), impact_metrics_chunk, executor=ex, chunk_size=5)
    _check_failure_recorded(run)
    assert run.frame.equals(serial_run.frame)  # bit for bit, whatever the chunking


def test_dask_local_cluster_matches_serial(serial_run):
    pytest.importorskip("distributed", reason="dask[distributed] is not installed")
    with make_executor("dask", workers=2, processes=False) as ex:
        assert ex.describe() == "dask LocalCluster (2 workers)"
        run = run_points(_points(), impact_metrics_chunk, executor=ex, chunk_size=3)
    _check_failure_recorded(run)
    assert run.frame.equals(serial_run.frame)


def test_unreachable_dask_scheduler_fails_fast():
    pytest.importorskip("distributed", reason="dask[distributed] is not installed")
    with pytest.raises(
        ExecutorError, match=r"cannot reach the Dask scheduler at tcp://127.0.0.1:9 "
    ):
        make_executor("dask", scheduler="tcp://127.0.0.1:9", timeout=1.0)


def test_bad_executor_options():
    with pytest.raises(ExecutorError, match="unknown executor 'threads'"):
        make_executor("threads")
    with pytest.raises(ExecutorError, match="--scheduler is only used by the dask executor"):
        make_executor("processes", scheduler="tcp://x:1")
    with pytest.raises(ExecutorError, match="workers = 0 is not allowed"):
        make_executor("processes", workers=0)


def test_failing_point_alone_in_its_chunk_and_nan_free_neighbours(serial_run):
    ok = [r for i, r in enumerate(serial_run.results) if i != 7]
    assert all(math.isfinite(r["a_h_max_g"]) for r in ok)


def _square(x: float) -> float:
    return x * x


@pytest.mark.parametrize("name", ["serial", "processes", "dask"])
def test_lazy_tasks_are_drawn_only_as_workers_free_up(name):
    """At most ``window`` tasks exist at once: a million-point sweep never holds all chunks."""
    if name == "dask":
        pytest.importorskip("distributed", reason="dask[distributed] is not installed")
    opts = {"processes": False} if name == "dask" else {}
    drawn = 0

    def tasks():
        nonlocal drawn
        for i in range(60):
            drawn += 1
            yield float(i)

    with make_executor(name, **({"workers": 2} if name != "serial" else {}), **opts) as ex:
        got = {}
        for yielded, (i, value) in enumerate(ex.map_unordered(_square, tasks()), start=1):
            assert drawn - yielded <= ex.window, (drawn, yielded, ex.window)
            got[i] = value
    assert got == {i: float(i) ** 2 for i in range(60)}
    assert ex.window == (8 if name != "serial" else 4)
