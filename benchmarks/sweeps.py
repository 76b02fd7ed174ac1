"""Sweeps at scale: a million-point impact sweep end to end, against the bare kernel.

Measured in one run on this machine, each phase in a fresh subprocess (so that
its peak memory is its own):

``kernel``
    :func:`designlab.impact.impact_metrics` on the same designs, in slices of
    65 536, on one core: the bare vectorised computation (the baseline).
``run``
    ``designlab run`` of an ``impact_sweep`` study (LHS over head mass, foam
    stiffness and damping): sampling, chunked evaluation, the SQLite result
    store, the report (Parquet table, summary CSV, density figures).
``resume``
    The same command with ``--resume`` once everything is stored: every
    point is read back from the store and, the report being up to date, it
    is left as it is.
``report``
    ``designlab report``: the report rebuilt from the store (no target; shown
    for what a forced rebuild costs).

A first, untimed call of the kernel on a few designs fills numba's disk cache, so that no
phase pays a compilation the others do not. It prints the ratios (targets: run <= 2x
kernel, resume <= 0.25x kernel), the store's bytes per point (target < 100) and each
phase's peak resident memory.
``--envelope-points N`` adds a foam-envelope sweep on the serial and process
executors (every point solves an envelope, 14-25 ms with the chunk's designs solved
together: 100 000 points take about 1.8 hours for all phases here, so the default is 2 000;
``--points 0`` skips the impact sweep).

``--no-memory`` skips the memory scaling (run and resume again at n and 2 n points).

Run:  python benchmarks/sweeps.py [--points 1000000] [--envelope-points 2000] [--workers 2]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

from designlab.study.points_table import BLOCK_ROWS

STUDY = """\
designlab: 1
kind: impact_sweep
name: bench_sweep
base: {{robot: MANIPULATOR_1, foam: FOAM_1, head: HEAD_MIN, impact_velocity: 1.25}}
sweep:
  method: lhs
  samples: {n}
  seed: 1
  parameters:
    head.mass: {{low: 4.4, high: 5.3}}
    foam.stiffness: {{low: 13.48e3, high: 60.6e3, scale: log}}
    foam.damping: {{low: 30, high: 120}}
"""

ENVELOPE_STUDY = """\
designlab: 1
kind: foam_envelope_sweep
name: bench_envelope
base: {{robot: MANIPULATOR_1, foam: FOAM_1}}
damping: {{low: 0, high: 200, num: 11}}
sweep:
  method: lhs
  samples: {n}
  seed: 2011
  parameters:
    robot.mass: {{low: 5, high: 50}}
    robot.stiffness: {{low: 10e3, high: 30e3}}
    impact_velocity: {{low: 0.5, high: 1.5}}
    max_g: {{low: 8, high: 12}}
"""

KERNEL = """\
import json, resource, sys, time
import numpy as np
from designlab.analysis.sampling import LatinHypercubePoints
from designlab.impact import HEAD_MIN, MANIPULATOR_1, FOAM_1
from designlab.impact.metrics import impact_metrics
n = int(sys.argv[1])
cols = LatinHypercubePoints({"head.mass": (4.4, 5.3), "foam.stiffness": (13.48e3, 60.6e3),
                        "foam.damping": (30.0, 120.0)}, n, seed=1,
                       log={"foam.stiffness": True}).columns()
r, h = MANIPULATOR_1, HEAD_MIN
t0 = time.perf_counter()
c0 = time.process_time()
step = 65536
total = 0.0
for s in range(0, n, step):
    e = min(s + step, n)
    m = impact_metrics({"M_r": r.mass, "C_r": r.damping, "K_r": r.stiffness,
                        "K_c": cols["foam.stiffness"][s:e], "C_c": cols["foam.damping"][s:e],
                        "M_h": cols["head.mass"][s:e], "C_h": h.damping, "K_h": h.stiffness},
                       1.25, workers=1)
    total += float(np.nansum(m.peak_head_acceleration_g))
wall = time.perf_counter() - t0
cpu = time.process_time() - c0
use = resource.getrusage(resource.RUSAGE_SELF)
rss = use.ru_maxrss / 1024
print(json.dumps({"wall": wall, "cpu": cpu, "rss_mb": rss, "check": total,
                  "process_cpu": use.ru_utime + use.ru_stime}))
"""

#: where a run's CPU time goes: (label, module path suffix, function) whose cumulative time
#: is the share (the rest: imports, numba's cache load, the CLI, the study's loading)
PHASES = (
    ("kernel (impact_metrics)", "designlab/analysis/engine.py", "evaluate_chunk"),
    ("sample drawing", "designlab/analysis/engine.py", "_draw"),
    ("result store", "designlab/analysis/store.py", "put_chunk"),
    ("engine bookkeeping", "designlab/analysis/engine.py", "_keep"),
    ("report: table (Parquet)", "designlab/report/sweep.py", "_write_large_table"),
    ("report: figure", "designlab/report/sweep.py", "_scatter_figure"),
    ("report: figure to PNG", "designlab/report/writers.py", "write_png"),
    ("report: all", "designlab/report/__init__.py", "write_report"),
    ("numba start-up (first calls)", "numba/core/dispatcher.py", "_compile_for_args"),
)

SHARES = """\
import cProfile, json, pstats, sys, time
from designlab.cli import app
phases = json.loads(sys.argv[1])
prof = cProfile.Profile(time.process_time)
c0 = time.process_time()
prof.enable()
try:
    app(sys.argv[2:], prog_name="designlab", standalone_mode=False)
finally:
    prof.disable()
    cpu = time.process_time() - c0
    stats = pstats.Stats(prof).stats
    got = {}
    for label, path, name in phases:
        got[label] = sum(v[3] for (f, _, fn), v in stats.items()
                         if fn == name and f.endswith(path))
    print("BENCH " + json.dumps({"cpu": cpu, "phases": got}), file=sys.stderr)
"""

CLI = """\
import json, resource, sys, time
from designlab.cli import app
t0 = time.perf_counter()
c0 = time.process_time()
try:
    app(sys.argv[1:], prog_name="designlab", standalone_mode=False)
finally:
    wall = time.perf_counter() - t0
    cpu = time.process_time() - c0
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print("BENCH " + json.dumps({"wall": wall, "cpu": cpu, "rss_mb": rss}), file=sys.stderr)
"""


def _bench(code: str, *args: str) -> dict[str, float]:
    out = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"benchmark phase failed:\n{out.stdout}\n{out.stderr}")
    for line in (out.stdout + "\n" + out.stderr).splitlines():
        if line.startswith("BENCH "):
            return json.loads(line[6:])
        if line.startswith("{"):
            return json.loads(line)
    raise SystemExit(f"no measurement:\n{out.stdout}\n{out.stderr}")


def _store_bytes(cache: Path) -> int:
    return sum(p.stat().st_size for p in cache.glob("*.sqlite*"))


def impact_sweep(n: int, tmp: Path, memory: bool = True) -> None:
    study = tmp / "bench_sweep.yaml"
    study.write_text(STUDY.format(n=n))
    cache, out = tmp / "cache", tmp / "reports"
    _bench(KERNEL, "4096")  # warm-up: numba's disk cache filled before any phase is timed
    kernel = _bench(KERNEL, str(n))
    args = ["run", str(study), "-o", str(out), "--cache-dir", str(cache)]
    run = _bench(CLI, *args)
    resume = _bench(CLI, *args, "--resume")
    rebuild = _bench(CLI, "report", str(study), "-o", str(out), "--cache-dir", str(cache))
    size = _store_bytes(cache)
    shares = _shares(args, tmp)
    files = sorted(p.name for p in (out / "bench_sweep").iterdir())
    print(
        f"impact_sweep, {n:,} points (LHS over M_h, K_c, C_c), one core "
        "(CPU seconds are robust to a busy machine; wall seconds shown too):"
    )
    for label, m, target in (
        ("bare kernel (impact_metrics)", kernel, None),
        ("designlab run (store, report)", run, 2.0),
        ("designlab run --resume", resume, 0.25),
        ("designlab report (rebuild)", rebuild, None),
    ):
        ratio = (
            f"   ratio cpu {m['cpu'] / kernel['cpu']:.2f}x (no target)"
            if target is None and m is not kernel
            else ""
            if target is None
            else (
                f"   ratio cpu {m['cpu'] / kernel['cpu']:.2f}x,"
                f" wall {m['wall'] / kernel['wall']:.2f}x"
                f" (target <= {target:g}x)"
            )
        )
        print(
            f"  {label:30s} cpu {m['cpu']:7.2f} s  wall {m['wall']:7.2f} s  "
            f"peak RSS {m['rss_mb']:5.0f} MB{ratio}"
        )
    total = kernel["process_cpu"]
    print(
        f"  {'bare kernel, whole process':30s} cpu {total:7.2f} s  (with its imports and numba's "
        f"start-up, which the run pays too)   run / this {run['cpu'] / total:.2f}x, "
        f"resume / this {resume['cpu'] / total:.2f}x"
    )
    print(
        f"  result store on disk           {size / 1e6:8.1f} MB = {size / n:.1f} bytes/point "
        "(target < 100)"
    )
    print(f"  report files: {', '.join(files)}")
    _print_shares(shares, kernel)
    if n >= 10_000 and memory:
        _memory_scaling(n, tmp)


def _shares(args: list[str], tmp: Path) -> dict[str, object]:
    """The run again (a fresh store), under a CPU-time profiler: each phase's cumulative time."""
    again = [*args]
    again[again.index("--cache-dir") + 1] = str(tmp / "cache_shares")
    again[again.index("-o") + 1] = str(tmp / "reports_shares")
    return _bench(SHARES, json.dumps(PHASES), *again)  # type: ignore[return-value]


def _print_shares(shares: dict[str, object], kernel: dict[str, float]) -> None:
    """Each phase's share of the profiled run, and its ratio to the bare kernel."""
    total = float(shares["cpu"])  # type: ignore[arg-type]
    phases: dict[str, float] = shares["phases"]  # type: ignore[assignment]
    print(f"  where the run's CPU time goes (a second run under cProfile, {total:.2f} CPU s; "
          "the profiler inflates Python-heavy phases; numba's start-up, paid by the first\n"
          "    compiled call, is inside the phase that makes it: sample drawing):")  # fmt: skip
    named = 0.0
    for label, t in phases.items():
        print(f"    {label:28s} {t:7.2f} s  {100 * t / total:5.1f} %  "
              f"{t / kernel['cpu']:5.2f}x the bare kernel")  # fmt: skip
        if not label.startswith(("report: ", "numba start-up")):
            named += t
    named += phases.get("report: all", 0.0)
    rest = total - named
    label = "rest (imports, CLI)"
    print(f"    {label:28s} {rest:7.2f} s  {100 * rest / total:5.1f} %  "
          f"{rest / kernel['cpu']:5.2f}x the bare kernel")  # fmt: skip


def _memory_scaling(n: int, tmp: Path) -> None:
    """Peak memory of run and resume at n and 2 n points: what each extra point costs.

    Both sizes are past the report's evenly spread subset of at most 200 000 rows
    (for n >= 200 000), so the difference is what grows with the sweep itself.
    """
    small, n = n, 2 * n
    peaks = {}
    for size in (small, n):
        d = tmp / f"scale_{size}"
        d.mkdir()
        study = d / "bench_sweep.yaml"
        study.write_text(STUDY.format(n=size))
        args = ["run", str(study), "-o", str(d / "reports"), "--cache-dir", str(d / "cache")]
        peaks[size] = (_bench(CLI, *args)["rss_mb"], _bench(CLI, *args, "--resume")["rss_mb"])
    (run_s, res_s), (run_n, res_n) = peaks[small], peaks[n]
    per_point = [(big - little) * 2**20 / (n - small) for big, little in
                 ((run_n, run_s), (res_n, res_s))]  # fmt: skip
    print(
        f"  memory: peak RSS run {run_s:.0f} MB at {small:,} points, {run_n:.0f} MB at {n:,} "
        f"({per_point[0]:.0f} bytes per extra point); resume {res_s:.0f} / {res_n:.0f} MB "
        f"({per_point[1]:.0f} bytes per extra point). The sample is drawn and the results "
        f"read back a chunk or a block of {BLOCK_ROWS:,} rows at a time."
    )


ENVELOPE_KERNEL = """\
import json, resource, sys, time
import numpy as np
from designlab.analysis.sampling import LatinHypercubePoints
from designlab.impact import FOAM_1, MANIPULATOR_1
from designlab.impact.evaluators import foam_envelope_chunk
n = int(sys.argv[1])
box = {"robot.mass": (5.0, 50.0), "robot.stiffness": (10e3, 30e3),
       "impact_velocity": (0.5, 1.5), "max_g": (8.0, 12.0)}
cols = LatinHypercubePoints(box, n, seed=2011).columns()
r, f = MANIPULATOR_1, FOAM_1
points = {"M_r": cols["robot.mass"], "C_r": np.full(n, r.damping),
          "K_r": cols["robot.stiffness"], "v_c": cols["impact_velocity"],
          "max_g": cols["max_g"], "lambda": np.full(n, f.linear_depth),
          "K_c": np.full(n, f.stiffness), "C_c": np.full(n, f.damping)}
t0, c0 = time.perf_counter(), time.process_time()
out = foam_envelope_chunk(points, {"damping": list(np.linspace(0.0, 200.0, 11))})
wall, cpu = time.perf_counter() - t0, time.process_time() - c0
rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps({"wall": wall, "cpu": cpu, "rss_mb": rss,
                  "check": float(np.nansum(out["k_c_max_N_per_m"]))}))
"""


def envelope_sweep(n: int, workers: int, tmp: Path) -> None:
    """A foam-envelope sweep: the evaluator called directly, then run, resume, processes."""
    study = tmp / "bench_envelope.yaml"
    study.write_text(ENVELOPE_STUDY.format(n=n))
    kernel = _bench(ENVELOPE_KERNEL, str(n))
    per_point = 1e3 * kernel["cpu"] / n
    print(f"  {'bare evaluator (one process)':30s} cpu {kernel['cpu']:7.2f} s  "
          f"wall {kernel['wall']:7.2f} s  peak RSS {kernel['rss_mb']:5.0f} MB  "
          f"({per_point:.1f} ms per point)")  # fmt: skip
    walls = {}
    for ex in ("serial", "processes"):
        cache = tmp / f"cache_{ex}"
        args = ["run", str(study), "-o", str(tmp / f"out_{ex}"), "--cache-dir", str(cache),
                "--executor", ex]  # fmt: skip
        if ex != "serial":
            args += ["--workers", str(workers)]
        walls[ex] = m = _bench(CLI, *args)
        size = _store_bytes(cache)
        print(
            f"  run, {ex:10s}              cpu {m['cpu']:7.2f} s  wall {m['wall']:7.2f} s  "
            f"peak RSS {m['rss_mb']:5.0f} MB   ratio cpu {m['cpu'] / kernel['cpu']:.2f}x "
            f"(target <= 2x; processes: this process only)  store {size / n:.1f} bytes/point"
        )
        if ex == "serial":
            again = _bench(CLI, *args, "--resume")
            print(
                f"  run --resume                   cpu {again['cpu']:7.2f} s  "
                f"wall {again['wall']:7.2f} s  peak RSS {again['rss_mb']:5.0f} MB   "
                f"ratio cpu {again['cpu'] / kernel['cpu']:.3f}x (target <= 0.25x)"
            )
    print(
        f"  processes speed-up {walls['serial']['wall'] / walls['processes']['wall']:.2f}x "
        f"on {workers} workers; identical tables: "
        f"{_table(tmp / 'out_serial').equals(_table(tmp / 'out_processes'))}"
    )


def _table(out: Path) -> pd.DataFrame:
    """The envelope report's full table: results.csv, or results.parquet for a large sweep."""
    d = out / "bench_envelope"
    if (d / "results.parquet").exists():
        return pd.read_parquet(d / "results.parquet")
    return pd.read_csv(d / "results.csv")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--envelope-points", type=int, default=2000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--no-memory", action="store_true", help="skip the memory scaling")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        t0 = time.perf_counter()
        if args.points:
            impact_sweep(args.points, tmp, memory=not args.no_memory)
        if args.envelope_points:
            print(f"foam_envelope, {args.envelope_points:,} points (11-value damping grid):")
            envelope_sweep(args.envelope_points, args.workers, tmp)
        print(f"(benchmark wall time {time.perf_counter() - t0:.0f} s)")


if __name__ == "__main__":
    main()
