"""Executors: identical results whichever runs the sweep; failures recorded; clear errors."""

from __future__ import annotations

import contextlib
import importlib
import math
import os
import signal
import socket
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
import typer

from designlab.analysis.engine import run_points
from designlab.analysis.executors import ExecutorError, make_executor
from designlab.analysis.sampling import LatinHypercubePoints
from designlab.analysis.store import ChunkStore
from designlab.impact.evaluators import impact_metrics_chunk

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


TASK_MODULE = '''\
import os, time
from pathlib import Path


def forking_double(points, options):
    """y = 2x; the first call forks a process that holds the worker's connections open
    (as a task starting a helper process does) and records its pid."""
    mark = Path(os.environ["DESIGNLAB_TEST_FORK_MARK"])
    if not mark.exists():
        pid = os.fork()
        if pid == 0:
            time.sleep(120)
            os._exit(0)
        mark.write_text(str(pid))
    time.sleep(0.1)
    return {"y": 2.0 * points["x"]}
'''


def _loopback_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def external_cluster(tmp_path, monkeypatch):
    """A ``dask scheduler`` and one ``--no-nanny`` worker, processes of their own, on 127.0.0.1."""
    pytest.importorskip("distributed", reason="dask[distributed] is not installed")
    (tmp_path / "dl_fault_task.py").write_text(TASK_MODULE)
    monkeypatch.syspath_prepend(str(tmp_path))
    mark = tmp_path / "forked.pid"
    env = {**os.environ, "DESIGNLAB_TEST_FORK_MARK": str(mark),
           "PYTHONPATH": os.pathsep.join([str(tmp_path), *sys.path])}  # fmt: skip
    port = _loopback_port()
    address = f"tcp://127.0.0.1:{port}"
    roles = {
        "scheduler": ["--host", "127.0.0.1", "--port", str(port),
                      "--dashboard-address", "127.0.0.1:0"],
        "worker": [address, "--no-nanny", "--nthreads", "1", "--host", "127.0.0.1",
                   "--dashboard-address", "127.0.0.1:0", "--local-directory", str(tmp_path)],
    }  # fmt: skip
    procs = {
        role: subprocess.Popen(
            [sys.executable, "-m", f"distributed.cli.dask_{role}", *args],
            env=env,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        for role, args in roles.items()
    }
    try:
        yield address, procs
    finally:
        pids = [p.pid for p in procs.values()] + ([int(mark.read_text())] if mark.exists() else [])
        for pid in pids:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
                os.kill(pid, signal.SIGCONT)
        for p in procs.values():
            p.wait(timeout=30)


def _run_until_fault(tmp_path, address, procs, fault):
    """40 slow points on the external cluster; ``fault()`` once two chunks are stored.

    Returns the error, the seconds from the fault to the end of the run (the client
    closed), and the store. Should the run hang, a watchdog kills the scheduler after
    60 s (the run then ends and the time check fails, instead of the suite hanging).
    """
    from dl_fault_task import forking_double  # written by the fixture

    from designlab.analysis.executors import WorkerLostError

    ex = make_executor("dask", scheduler=address, timeout=20.0, worker_timeout=WORKER_TIMEOUT)
    for _ in range(300):  # the worker registers (a few seconds on a busy machine)
        if ex._client.scheduler_info()["workers"]:
            break
        time.sleep(0.1)
    # the worker imports what the tasks need before the clock runs: a worker busy
    # importing (its event loop blocked, no heartbeat) for longer than the timeout
    # would be taken for a lost one
    for module in ("designlab.analysis.engine", "dl_fault_task"):
        ex._client.run(importlib.import_module, module)
    store = ChunkStore(tmp_path / "d.sqlite")
    faulted: list[float] = []

    def put_chunk(key, columns, _put=store.put_chunk):
        _put(key, columns)
        if len(store) == 2:
            faulted.append(time.monotonic())
            fault()

    def last_resort() -> None:
        for sig in (signal.SIGKILL, signal.SIGCONT):
            with contextlib.suppress(ProcessLookupError):
                os.kill(procs["scheduler"].pid, sig)

    store.put_chunk = put_chunk
    watchdog = threading.Timer(60.0, last_resort)
    watchdog.start()
    try:
        with pytest.raises(WorkerLostError) as info:
            run_points({"x": np.arange(40.0)}, forking_double, executor=ex, store=store,
                       chunk_size=2)  # fmt: skip
    finally:
        ex.close()
        watchdog.cancel()
    assert faulted, f"the run ended before the fault: {info.value}"
    return info.value, time.monotonic() - faulted[0], store


WORKER_TIMEOUT = 3.0


@pytest.mark.dask
def test_a_killed_dask_worker_ends_the_run_within_the_timeout(tmp_path, external_cluster):
    """SIGKILL of the only (no-nanny) worker while a process it forked keeps its connection
    open: the scheduler never hears of the loss, the run ends on the missing heartbeats."""
    from designlab.cli import EXIT_EXECUTOR_ERROR, _fail

    address, procs = external_cluster
    err, seconds, store = _run_until_fault(
        tmp_path, address, procs, lambda: procs["worker"].send_signal(signal.SIGKILL)
    )
    said = str(err)  # the worker's silence, or a result it held that never came
    assert f"no Dask worker has been alive for {WORKER_TIMEOUT:g} s" in said or (
        "or the Dask worker holding a finished result" in said
    )
    assert "--resume" in str(err)
    assert seconds < WORKER_TIMEOUT + 8.0, seconds
    with store:
        assert len(store) >= 2
    with pytest.raises(typer.Exit) as code:  # what `designlab run` does with it
        _fail(err)
    assert code.value.exit_code == EXIT_EXECUTOR_ERROR == 3


@pytest.mark.dask
def test_a_stopped_dask_scheduler_ends_the_run_within_the_timeout(tmp_path, external_cluster):
    """A scheduler that stops answering (SIGSTOP: its connections stay open) is lost."""
    address, procs = external_cluster
    err, seconds, store = _run_until_fault(
        tmp_path, address, procs, lambda: procs["scheduler"].send_signal(signal.SIGSTOP)
    )
    assert f"lost the Dask scheduler at {address}" in str(err)
    assert "--resume" in str(err)
    assert seconds < WORKER_TIMEOUT + 8.0, seconds
    store.close()
