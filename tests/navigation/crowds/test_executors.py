"""crowd_study through the sweep engine's executors and chunk store (issue 23, item 5): the
same table from local processes and Dask as serially, and a study killed after its first
chunks resumes from the store."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import threading

import pandas as pd
import pytest

from designlab.analysis.executors import make_executor
from designlab.analysis.store import ChunkStore
from designlab.navigation.crowds.study import crowd_study

OPTS = {"length": 8.0, "horizon": 1.0}
#: one layout, two seeds, two methods: a chunk is one crowd (its two methods)
GRID = (["corridor_counterflow"], [0.3], [0, 1], ["vff", "cbf"])
#: the same and a second density (the study that is killed and resumed)
TWO = (["corridor_counterflow"], [0.3, 0.5], [0, 1], ["vff", "cbf"])


@pytest.fixture(scope="module")
def whole():
    return crowd_study(*TWO, crowd_options=OPTS)


@pytest.fixture(scope="module")
def serial(whole) -> pd.DataFrame:
    return whole.runs.iloc[:4]  # the first density: the runs of GRID


def _same(study, runs: pd.DataFrame) -> None:
    pd.testing.assert_frame_equal(study.runs, runs)
    assert study.status == "ok" and len(runs) == 4


@pytest.mark.slow
def test_processes_give_the_serial_table(serial):
    with make_executor("processes", workers=2) as ex:
        _same(crowd_study(*GRID, crowd_options=OPTS, executor=ex), serial)


@pytest.mark.dask
def test_dask_local_cluster_gives_the_serial_table(serial):
    pytest.importorskip("distributed", reason="dask[distributed] is not installed")
    with make_executor("dask", workers=2, processes=False) as ex:
        _same(crowd_study(*GRID, crowd_options=OPTS, executor=ex), serial)


CHILD = """\
import sys, time
from designlab.analysis.store import ChunkStore
from designlab.navigation.crowds.study import crowd_study


def hold(progress):
    print("done", progress.step, flush=True)
    time.sleep(600)  # held after the first density's chunks until killed


with ChunkStore(sys.argv[1]) as store:
    crowd_study(["corridor_counterflow"], [0.3, 0.5], [0, 1], ["vff", "cbf"],
                crowd_options={OPTS!r}, store=store, progress=hold)
"""


def _tail(proc: subprocess.Popen) -> str:
    """The child's last error lines when it has ended (else nothing: it is still running)."""
    return proc.stderr.read()[-2000:] if proc.poll() is not None else ""


def test_a_study_killed_after_its_first_chunks_resumes_from_the_store(tmp_path, serial, whole):
    """SIGKILL once the first density's two chunks are stored; --resume computes the rest."""
    path = tmp_path / "crowds.sqlite"
    script = tmp_path / "child.py"
    script.write_text(textwrap.dedent(CHILD.replace("{OPTS!r}", repr(OPTS))))
    proc = subprocess.Popen([sys.executable, str(script), str(path)], start_new_session=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
    line: list[str] = []
    reader = threading.Thread(target=lambda: line.append(proc.stdout.readline()), daemon=True)
    reader.start()
    reader.join(timeout=240)
    try:
        assert line and line[0].strip() == "done 4", (line, proc.poll(), _tail(proc))
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    with ChunkStore(path) as store:
        assert len(store) == 2  # the first density's chunks, nothing of the second
        kept = crowd_study(*GRID, crowd_options=OPTS, store=store, cache_only=True)
        _same(kept, serial)  # read back from the store, nothing computed
        resumed = crowd_study(*TWO, crowd_options=OPTS, store=store, resume=True)
        assert len(store) == 4
    pd.testing.assert_frame_equal(resumed.runs, whole.runs)
    pd.testing.assert_frame_equal(resumed.to_frame(), whole.to_frame())


def test_placements_in_threads_equal_placements_alone():
    """JuPedSim places with numpy's global generator: runs in threads (Dask workers' threads)
    must not draw from each other's stream, nor move the caller's."""
    from concurrent.futures import ThreadPoolExecutor

    import numpy as np

    import designlab as dl
    from designlab.navigation.crowds.pedestrians import PedestrianSim

    def placed(seed: int) -> np.ndarray:
        c = dl.navigation.crowd("corridor_counterflow", density=0.5, length=8.0, seed=seed)
        return PedestrianSim(c).positions()[1]

    np.random.seed(123)  # noqa: NPY002 - the caller's global stream, checked below
    alone = [placed(s) for s in range(6)]
    after = np.random.random()  # noqa: NPY002
    with ThreadPoolExecutor(3) as ex:
        for _ in range(3):
            threaded = list(ex.map(placed, range(6)))
            assert all(np.array_equal(a, b) for a, b in zip(alone, threaded, strict=True))
    np.random.seed(123)  # noqa: NPY002
    assert np.random.random() == after  # noqa: NPY002
