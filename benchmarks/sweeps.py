"""Sweep executors: a 2000-point foam-envelope sensitivity sweep, serial vs processes vs Dask.

Every point solves a full foam envelope (Zeng 2011, Sec. 3.9: upper and lower
K_c boundaries over an 11-value damping grid, plus the boundaries at Foam 1's
damping) for a Latin-hypercube design of the manipulator (M_r, K_r, C_r), the
closing speed and the two limits (max_g, lambda). The same points run, in
this one process, through

* the serial executor (the baseline),
* local processes (``--workers``, default 2), and
* a Dask LocalCluster of the same number of single-threaded worker processes,

without the cache (pure compute + transport). The script checks that the three
give identical results and prints wall times, speed-ups against serial, and
the per-point overhead of each executor: (wall time x workers - serial
time) / points, i.e. the time a worker spends on a point beyond the
computation itself. A second, small run measures the cache write cost per
point.

Run:  python benchmarks/sweeps.py [--points 2000] [--workers 2]
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time

from designlab.analysis.executors import make_executor
from designlab.analysis.sampling import latin_hypercube
from designlab.analysis.sweep import run_points
from designlab.report.cache import PointCache

DAMPING = [float(c) for c in range(0, 201, 20)]  # N s/m, 11 values
BOX = {
    "M_r": (5.0, 50.0),
    "K_r": (10e3, 30e3),
    "C_r": (100.0, 400.0),
    "v_c": (0.5, 1.5),
    "max_g": (8.0, 12.0),
    "lambda": (0.015, 0.025),
}
FOAM_1 = {"K_c": 24.25e3, "C_c": 71.9}


def points(n: int) -> list[dict[str, float]]:
    return [dict(p, **FOAM_1) for p in latin_hypercube(BOX, n, seed=2011)]


def same(a: list[dict], b: list[dict]) -> bool:
    """Equal results, NaN equal to NaN (a NaN from another process is another object)."""
    norm = [json.dumps(r, sort_keys=True) for r in a]
    return norm == [json.dumps(r, sort_keys=True) for r in b]


def timed(name: str, pts: list[dict[str, float]], workers: int) -> tuple[float, list]:
    opts = {"damping": DAMPING}
    t0 = time.perf_counter()
    ex = make_executor(name, workers=workers) if name != "serial" else make_executor("serial")
    start = time.perf_counter() - t0
    with ex:
        t1 = time.perf_counter()
        run = run_points(pts, "foam_envelope", opts, executor=ex)
        wall = time.perf_counter() - t1
    print(f"  {name:<9s} start-up {start:6.2f} s   sweep {wall:7.2f} s   ({ex.describe()})")
    return wall, run.results


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=2000)
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    pts = points(args.points)
    n, w = len(pts), args.workers
    print(f"{n}-point foam-envelope sweep, {len(DAMPING)} damping values per envelope, "
          f"{w} workers, {os.cpu_count()} CPUs")  # fmt: skip
    serial, ref = timed("serial", pts, 1)
    rows = [("serial", serial)]
    for name in ("processes", "dask"):
        try:
            wall, res = timed(name, pts, w)
        except Exception as exc:  # e.g. dask not installed
            print(f"  {name}: skipped ({exc})")
            continue
        assert same(res, ref), f"{name} results differ from serial"
        rows.append((name, wall))
    print("\nexecutor   wall (s)  speed-up  per-point (ms)  overhead/point (ms)")
    for name, wall in rows:
        k = 1 if name == "serial" else w
        over = (wall * k - serial) / n * 1e3
        print(f"{name:<9s} {wall:9.2f} {serial / wall:9.2f}x {wall / n * 1e3:14.2f} {over:20.2f}")
    print("identical results across executors: yes")

    # cache write cost per point (serial, small run)
    few = pts[:100]
    with tempfile.TemporaryDirectory() as d:
        t0 = time.perf_counter()
        run_points(few, "foam_envelope", {"damping": DAMPING})
        bare = time.perf_counter() - t0
        t0 = time.perf_counter()
        run_points(few, "foam_envelope", {"damping": DAMPING}, cache=PointCache(d))
        cached = time.perf_counter() - t0
        t0 = time.perf_counter()
        run_points(few, "foam_envelope", {"damping": DAMPING}, cache=PointCache(d), resume=True)
        resumed = time.perf_counter() - t0
    print(f"\ncache: {(cached - bare) / len(few) * 1e3:.2f} ms/point to write, "
          f"{resumed / len(few) * 1e3:.2f} ms/point to resume from it "
          f"(vs {bare / len(few) * 1e3:.1f} ms/point to compute)")  # fmt: skip


if __name__ == "__main__":
    main()
