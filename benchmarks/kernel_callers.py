"""Benchmark: everything that calls the impact kernel, before (numpy path) and after (compiled).

Run with ``python benchmarks/kernel_callers.py`` (a few minutes; ``--quick`` for a
smaller run). In one process, each caller is timed twice on the same inputs: with
the compiled kernel (:mod:`designlab.impact.kernel`) and on the numpy path
(``designlab.impact.kernel.AVAILABLE`` switched off, the code before issue 22), and
the ratio is printed. Times are CPU seconds of this process (``time.process_time``;
on a shared machine wall clocks are not comparable), after one warm-up.

* sweep chunk: :func:`designlab.impact.evaluators.impact_metrics_chunk` (what the
  sweep engine's workers run) on random designs over the wide ranges of issue 22;
* Sobol: the Saltelli sample of the 8 model parameters and v_c (``2^k (D + 2)``
  points), a_h,max and eps_max by :func:`designlab.impact.impact_metrics`, and the
  first/total indices (:func:`designlab.analysis.sensitivity.sobol_table`);
* worst-case search: :func:`designlab.impact.check_worst_case` (corners and 64 random
  head-neck cases at every boundary point) of a 21-point envelope;
* envelope: :func:`designlab.impact.foam_envelope` with 41 damping values.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from typing import Any

import numpy as np
from _machine import machine  # benchmarks/_machine.py

import designlab as dl
from designlab.analysis.sampling import saltelli
from designlab.analysis.sensitivity import sobol_table
from designlab.impact import kernel
from designlab.impact.evaluators import impact_metrics_chunk

WIDE = {"M_r": (2.0, 20.0), "C_r": (0.0, 800.0), "K_r": (5e3, 5e4), "K_c": (5e3, 8e4),
        "C_c": (0.0, 300.0), "M_h": (3.0, 6.0), "C_h": (0.0, 150.0), "K_h": (1e3, 1e4),
        "v_c": (0.2, 2.0)}  # fmt: skip


def cpu(fn: Callable[[], Any]) -> float:
    """CPU seconds of one call (after the caller's warm-up)."""
    t0 = time.process_time()
    fn()
    return time.process_time() - t0


def before_after(fn: Callable[[], Any]) -> tuple[float, float]:
    """(compiled, numpy path) CPU seconds of ``fn``."""
    fn()
    fast = cpu(fn)
    kernel.AVAILABLE = False
    try:
        slow = cpu(fn)
    finally:
        kernel.AVAILABLE = True
    return fast, slow


def sweep_chunk(n: int) -> Callable[[], Any]:
    rng = np.random.default_rng(1)
    pts = {k: rng.uniform(*b, n) for k, b in WIDE.items()}
    return lambda: impact_metrics_chunk(pts, {})


def sobol(base_log2: int) -> tuple[Callable[[], Any], int]:
    bounds = dict(WIDE)
    x = saltelli(bounds, 2**base_log2, seed=1)
    names = dl.impact.PARAM_NAMES

    def run() -> Any:
        m = dl.impact.impact_metrics({k: x[k] for k in names}, x["v_c"], with_force=False)
        outputs = {"a_h_max": m.peak_head_acceleration, "eps_max": m.max_compression}
        return sobol_table(list(bounds), list(bounds.values()), outputs, seed=1)

    return run, len(x["v_c"])


def worst_case() -> Callable[[], Any]:
    env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, 1.25, np.linspace(20, 200, 21))
    return lambda: dl.impact.check_worst_case(env, samples=64)


def envelope() -> Callable[[], Any]:
    damping = np.linspace(0, 200, 41)
    crit = [dl.impact.HeadAcceleration(max_g=10)]
    return lambda: dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, 1.25, damping, crit, 0.02)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--chunk", type=int, default=200_000, help="designs of the sweep chunk")
    ap.add_argument("--sobol-log2", type=int, default=14, help="Saltelli base sample 2^k")
    ap.add_argument("--quick", action="store_true", help="20 000 designs, 2^11 Sobol base")
    args = ap.parse_args(argv)
    if args.quick:
        args.chunk, args.sobol_log2 = 20_000, 11
    print("designlab: callers of the impact kernel, compiled vs numpy path (CPU time)")
    print(f"  {machine()}; compiled kernel {'on' if kernel.AVAILABLE else 'OFF'}")
    run_sobol, n_sobol = sobol(args.sobol_log2)
    cases = [
        (f"sweep chunk, {args.chunk:,} designs", sweep_chunk(args.chunk), args.chunk),
        (f"Sobol, {n_sobol:,} points (2^{args.sobol_log2} x 11)", run_sobol, n_sobol),
        ("worst-case search, 21-point envelope", worst_case(), 0),
        ("foam envelope, 41 damping values", envelope(), 0),
    ]
    print(f"  {'caller':<42}{'compiled':>12}{'numpy path':>12}{'ratio':>9}")
    for label, fn, n in cases:
        fast, slow = before_after(fn)
        rate = f"   ({n / fast:,.0f} designs/s compiled)" if n else ""
        print(f"  {label:<42}{fast:10.3f} s{slow:10.3f} s{slow / fast:8.1f}x{rate}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
