"""Single calls and every core: the scalar fast path and the threaded batch, in one run.

What is measured, in one process, interleaved (the machine's load moves both sides alike):

1. **Single calls** (issue 40.2): per design, CPU microseconds of
   :func:`designlab.impact.single.impact_metrics_one` called design by design (what
   ``scipy.optimize`` or another project's loop does), of
   :func:`designlab.impact.impact_metrics` called with one design, and of the compiled
   kernel in one batch of the same designs on one thread (the baseline). Printed: each
   call's overhead over the batch per design (target: under 10 us for the fast path) and
   its ratio to the batch; every fast result is checked equal, to the bit, to the batch's.
2. **Every core** (issue 40.3): wall seconds of ``impact_metrics`` on the same batch with
   ``workers=1`` and ``workers=N`` (default every core), alternated ``--repeats`` times;
   printed: each pair's speed-up, the median (target >= 1.8x on 2 cores), whether the
   results are identical, and the load average before and after (other processes on
   the machine take cores from the threaded side: the speed-up is only meaningful on a
   quiet machine).

Run:  python benchmarks/single_calls.py [--designs 200000] [--calls 20000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

from designlab.impact import kernel
from designlab.impact.metrics import impact_metrics
from designlab.impact.model import PARAM_NAMES
from designlab.impact.single import ImpactPoint, impact_metrics_one
from designlab.workers import core_count

FIELDS = ImpactPoint._fields[:-1]


def designs(n: int, seed: int = 1) -> np.ndarray:
    """The sweep benchmark's box (M_h, K_c log, C_c) around MANIPULATOR_1, FOAM_1, HEAD_MIN."""
    rng = np.random.default_rng(seed)
    p = np.empty((n, 8))
    p[:] = [9.6, 250.0, 20e3, 24.25e3, 71.9, 4.4, 0.0, 4e3]
    p[:, 5] = rng.uniform(4.4, 5.3, n)
    p[:, 3] = np.exp(rng.uniform(np.log(13.48e3), np.log(60.6e3), n))
    p[:, 4] = rng.uniform(30.0, 120.0, n)
    return p


def _cpu(fn) -> float:  # type: ignore[no-untyped-def]
    c0 = time.process_time()
    fn()
    return time.process_time() - c0


def single_calls(p: np.ndarray, v: float, rounds: int = 3) -> None:
    """Per-design CPU time of the fast path, of impact_metrics per design and of the batch."""
    rows = [list(map(float, q)) for q in p]
    sel = (True, True, True)
    batch = one = slow = np.inf
    slow_rows = rows[: max(len(rows) // 20, 1)]  # impact_metrics per design is slow
    for _ in range(rounds):  # interleaved, best of each
        batch = min(batch, _cpu(lambda: kernel.reduced_metrics(
            p, sel, printed=False, stop_time=0.05, max_lobe_steps=4096, diagnostics=False,
        )) / len(rows))  # fmt: skip
        one = min(one, _cpu(lambda: [impact_metrics_one(q, v) for q in rows]) / len(rows))
        slow = min(slow, _cpu(lambda: [impact_metrics([q], v, columns=PARAM_NAMES, workers=1)
                                       for q in slow_rows]) / len(slow_rows))  # fmt: skip
    m = impact_metrics(p, v, columns=PARAM_NAMES, workers=1)
    same = all(
        np.array_equal(
            np.array([getattr(impact_metrics_one(q, v), f) for q in rows[:2000]]),
            getattr(m, f)[:2000],
            equal_nan=True,
        )
        for f in FIELDS
    )
    print(f"single calls, {len(rows):,} designs (CPU us per design, best of {rounds}):")
    print(f"  batch kernel, one thread            {batch * 1e6:8.2f} us   (baseline)")
    for label, t, target in (
        ("impact_metrics_one (fast path)", one, 10.0),
        ("impact_metrics, one design a call", slow, None),
    ):
        goal = f"  (target < {target:g} us)" if target else ""
        print(f"  {label:35s} {t * 1e6:8.2f} us   overhead {(t - batch) * 1e6:8.2f} us, "
              f"{t / batch:5.2f}x the batch{goal}")  # fmt: skip
    print(f"  fast path equal to the batch rows, to the bit (first 2,000): {same}")


def every_core(p: np.ndarray, v: float, workers: int, repeats: int) -> None:
    """Wall time of impact_metrics on one thread and on ``workers``, alternated."""
    load0 = os.getloadavg()
    ratios = []
    ref = impact_metrics(p, v, columns=PARAM_NAMES, workers=1)
    same = True
    for _ in range(repeats):
        t0 = time.perf_counter()
        impact_metrics(p, v, columns=PARAM_NAMES, workers=1)
        t1 = time.perf_counter()
        m = impact_metrics(p, v, columns=PARAM_NAMES, workers=workers)
        t2 = time.perf_counter()
        ratios.append((t1 - t0) / (t2 - t1))
        same &= all(np.array_equal(getattr(m, f), getattr(ref, f), equal_nan=True)
                    for f in ("peak_head_acceleration", "max_compression", "peak_force",
                              "impact_duration"))  # fmt: skip
        same &= bool(np.array_equal(m.design_status, ref.design_status))
    load1 = os.getloadavg()
    print(f"every core, impact_metrics on {len(p):,} designs, workers=1 vs workers={workers} "
          f"({core_count()} cores for this process), alternated {repeats}x:")  # fmt: skip
    print(
        f"  speed-ups {', '.join(f'{r:.2f}' for r in ratios)}; median "
        f"{statistics.median(ratios):.2f}x (target >= 1.8x on 2 cores); identical: {same}"
    )
    print(
        f"  load average (1 min) {load0[0]:.1f} before, {load1[0]:.1f} after "
        f"(> 0.5 means other processes took cores from the threads)"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", type=int, default=200_000)
    parser.add_argument("--calls", type=int, default=20_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--workers", type=int, default=core_count())
    args = parser.parse_args()
    impact_metrics(designs(64), 1.25, columns=PARAM_NAMES)  # warm-up (numba's cache)
    impact_metrics_one(designs(1)[0].tolist(), 1.25)
    single_calls(designs(args.calls, seed=2), 1.25)
    every_core(designs(args.designs), 1.25, args.workers, args.repeats)


if __name__ == "__main__":
    main()
