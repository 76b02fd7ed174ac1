"""Faults during a run: killed workers and clients, lost schedulers, concurrent report swaps.

Each test causes the fault for real (SIGKILL, a closed scheduler, racing processes)
and checks what the user is promised: a clear error, the finished chunks kept (so
``--resume`` finishes the run), no process of the run left behind, no debris.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from designlab.analysis.engine import run_points
from designlab.analysis.executors import WorkerLostError, make_executor
from designlab.analysis.store import ChunkStore
from designlab.report.atomic import report_directory

posix_only = pytest.mark.skipif(
    not Path("/proc/self/stat").exists(), reason="needs Linux /proc to list processes"
)


def suicidal(points, options):
    """y = 2x; a worker process (never the client) kills itself by SIGKILL at x = 13."""
    x = points["x"]
    if multiprocessing.parent_process() is not None and np.any(x == 13.0):
        os.kill(os.getpid(), signal.SIGKILL)
    return {"y": 2.0 * x}


def _group(pgid: int) -> list[tuple[int, str]]:
    """Live (not zombie) processes of a process group, from /proc: ``(pid, command)``."""
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            text = stat.read_text()
        except OSError:
            continue
        fields = text[text.rindex(")") + 2 :].split()
        if int(fields[2]) == pgid and fields[0] != "Z":
            try:
                cmd = (stat.parent / "cmdline").read_bytes().replace(b"\0", b" ").decode()
            except OSError:
                cmd = "?"
            out.append((int(stat.parent.name), cmd[:120]))
    return out


CLIENT = """\
import sys, time
import numpy as np
from designlab.analysis.engine import run_points
from designlab.analysis.executors import make_executor


def slow(points, options):
    time.sleep(0.3)
    return {"y": points["x"]}


if __name__ == "__main__":
    with make_executor("processes", workers=2) as ex:
        run_points({"x": np.arange(2000.0)}, slow, executor=ex, chunk_size=1)
"""


@posix_only
def test_a_killed_client_leaves_no_process_of_its_run(tmp_path):
    """SIGKILL of the client: its workers, fork server and resource tracker all exit."""
    script = tmp_path / "client.py"
    script.write_text(CLIENT)
    proc = subprocess.Popen([sys.executable, str(script)], start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)  # fmt: skip
    pgid = proc.pid
    try:
        deadline = time.monotonic() + 120
        # the client, the resource tracker, the fork server and two workers
        while len(_group(pgid)) < 5 and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.2)
        assert proc.poll() is None, proc.stderr.read().decode()
        assert len(_group(pgid)) >= 5, _group(pgid)
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
        deadline = time.monotonic() + 30
        while _group(pgid) and time.monotonic() < deadline:
            time.sleep(0.2)
        survivors = _group(pgid)
    finally:
        if _group(pgid):
            os.killpg(pgid, signal.SIGKILL)
    assert survivors == []


def test_a_killed_worker_is_a_clear_error_and_resume_finishes(tmp_path):
    points = {"x": np.arange(40.0)}
    with ChunkStore(tmp_path / "s.sqlite") as store:
        with (
            make_executor("processes", workers=2) as ex,
            pytest.raises(WorkerLostError, match=r"a worker process died .*--resume"),
        ):
            run_points(points, suicidal, executor=ex, store=store, chunk_size=2)
        kept = len(store)
        assert kept < 20  # the chunk of x = 13 was never stored
        run = run_points(points, suicidal, store=store, resume=True, chunk_size=2)  # serial
    assert (run.cached, run.computed) == (2 * kept, 40 - 2 * kept)
    assert run.frame["y"].tolist() == [2.0 * x for x in range(40)]


def slow_double(points, options):
    time.sleep(0.1)
    return {"y": 2.0 * points["x"]}


def _dask_fault(tmp_path, fault, worker_timeout=30.0):
    """Run 40 slow points on an in-process cluster; ``fault(cluster)`` after the first results."""
    pytest.importorskip("distributed", reason="dask[distributed] is not installed")
    store = ChunkStore(tmp_path / "d.sqlite")
    ex = make_executor("dask", workers=1, processes=False, worker_timeout=worker_timeout)
    cluster = ex._cluster
    done = []

    def put_chunk(key, columns, _put=store.put_chunk):
        _put(key, columns)
        done.append(key)
        if len(done) == 2:
            fault(cluster)

    store.put_chunk = put_chunk
    started = time.monotonic()
    try:
        with pytest.raises(WorkerLostError) as info:
            run_points({"x": np.arange(40.0)}, slow_double, executor=ex, store=store,
                       chunk_size=2)  # fmt: skip
    finally:
        ex.close()
    return info.value, time.monotonic() - started, store


@pytest.mark.dask
def test_a_lost_dask_scheduler_is_a_clear_error_and_keeps_the_chunks(tmp_path):
    err, _, store = _dask_fault(tmp_path, lambda c: c.sync(c.scheduler.close))
    assert "lost the Dask cluster during the run" in str(err) and "--resume" in str(err)
    with store:
        run = run_points({"x": np.arange(40.0)}, slow_double, store=store, resume=True,
                         chunk_size=2)  # fmt: skip
    assert run.cached >= 4 and run.frame["y"].tolist() == [2.0 * x for x in range(40)]


@pytest.mark.dask
def test_no_live_dask_worker_fails_after_the_stated_timeout(tmp_path):
    def kill_the_worker(cluster):
        (worker,) = cluster.workers.values()
        cluster.sync(worker.close)

    err, seconds, store = _dask_fault(tmp_path, kill_the_worker, worker_timeout=2.0)
    store.close()
    assert "no Dask worker has been alive for 2 s" in str(err) and "--resume" in str(err)
    assert seconds < 60


def _swap_many(final: str, rounds: int, tag: int) -> None:
    failures = 0
    for i in range(rounds):
        try:
            with report_directory(final) as tmp:
                (tmp / "a.txt").write_text(f"{tag}-{i}")
                (tmp / "b.txt").write_text(f"{tag}-{i}")
        except Exception:
            failures += 1
    os._exit(min(failures, 100))


@pytest.mark.skipif(sys.platform == "win32", reason="swaps are serialised with flock")
def test_concurrent_runs_replace_one_report_safely(tmp_path):
    """Four processes replacing one report 40 times each: no failure, no debris, whole reports."""
    ctx = multiprocessing.get_context("fork")
    final = tmp_path / "reports" / "study"
    procs = [ctx.Process(target=_swap_many, args=(str(final), 40, k)) for k in range(4)]
    for p in procs:
        p.start()
    for p in procs:
        p.join(120)
    assert [p.exitcode for p in procs] == [0, 0, 0, 0]  # failed swaps per process
    assert sorted(p.name for p in final.parent.iterdir()) == ["study"]
    assert sorted(p.name for p in final.iterdir()) == ["a.txt", "b.txt"]
    assert (final / "a.txt").read_text() == (final / "b.txt").read_text()


def test_an_interrupted_report_leaves_no_half_written_file(tmp_path):
    final = tmp_path / "study"
    with report_directory(final) as tmp:
        (tmp / "a.txt").write_text("first")
    with pytest.raises(KeyboardInterrupt), report_directory(final) as tmp:
        (tmp / "a.txt").write_text("half")
        raise KeyboardInterrupt
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study"]
    assert (final / "a.txt").read_text() == "first"
