"""Memory: designs streamed through the chunked sweep engine at bounded memory.

Run with ``python benchmarks/memory_stream.py --points 100000000`` (1e8 designs take
about 10-20 CPU minutes on one core; the default is 1e7). Points over the wide
ranges of issue 22 are generated a chunk at a time (a seeded
:class:`~designlab.analysis.points.PointSource`), each chunk goes through the
engine's :func:`~designlab.analysis.engine.evaluate_chunk` with the impact
evaluator (:func:`~designlab.impact.evaluators.impact_metrics_chunk`, the compiled
kernel), and only running summaries are kept (counts by status, the largest a_h,max),
as a study that writes its rows to the result store does. The peak resident
memory of the process (``ru_maxrss``) is printed at every power of ten of points:
it stays flat, because the kernel works design by design on preallocated blocks
and holds nothing between chunks.

Speed is printed as a ratio to an in-process baseline (CPU seconds of this process,
robust to a shared machine): before the stream, :func:`designlab.impact.impact_metrics`
is called directly on the first ``--baseline`` designs (default 262 144, after a
warm-up), and the stream's CPU time per design is divided by the baseline's.
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import time

import numpy as np

from designlab.analysis.engine import evaluate_chunk
from designlab.analysis.points import PointSource
from designlab.impact.evaluators import impact_metrics_chunk
from designlab.impact.metrics import impact_metrics

WIDE = {"M_r": (2.0, 20.0), "C_r": (0.0, 800.0), "K_r": (5e3, 5e4), "K_c": (5e3, 8e4),
        "C_c": (0.0, 300.0), "M_h": (3.0, 6.0), "C_h": (0.0, 150.0), "K_h": (1e3, 1e4),
        "v_c": (0.2, 2.0)}  # fmt: skip


class RandomPoints(PointSource):
    """``n`` uniform points over :data:`WIDE`, drawn chunk by chunk (seeded by position)."""

    def __init__(self, n: int, chunk: int) -> None:
        self.n, self.chunk = n, chunk

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(WIDE)

    def __len__(self) -> int:
        return self.n

    def _take(self, start: int, stop: int) -> dict[str, np.ndarray]:
        rng = np.random.default_rng([start, 22])
        return {k: rng.uniform(*b, stop - start) for k, b in WIDE.items()}


def peak_mib() -> float:
    """Peak resident memory of this process in MiB (Linux reports KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def kernel_cpu_per_design(src: PointSource, n: int, chunk: int) -> float:
    """CPU seconds per design of ``impact_metrics`` called directly on the first ``n`` designs."""
    first = src.take(0, min(chunk, 1024))
    impact_metrics({k: first[k] for k in WIDE if k != "v_c"}, first["v_c"])  # warm-up
    t0 = time.process_time()
    for start in range(0, n, chunk):
        pts = src.take(start, min(start + chunk, n))
        impact_metrics({k: pts[k] for k in WIDE if k != "v_c"}, pts["v_c"])
    return (time.process_time() - t0) / n


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=float, default=1e7)
    ap.add_argument("--chunk", type=int, default=65_536)
    ap.add_argument("--baseline", type=int, default=262_144)
    args = ap.parse_args(argv)
    n, chunk = int(args.points), args.chunk
    src = RandomPoints(n, chunk)
    per_design = kernel_cpu_per_design(src, min(args.baseline, n), chunk)
    print(f"baseline: impact_metrics called directly, {1e6 * per_design:.2f} CPU us per design")
    print(f"streaming {n:,} designs in chunks of {chunk:,} through evaluate_chunk")
    print(f"  peak RSS before the first chunk: {peak_mib():8.1f} MiB")
    counts: dict[str, int] = {}
    worst = 0.0
    mark = 10**5
    t0 = time.process_time()
    for start in range(0, n, chunk):
        stop = min(start + chunk, n)
        out = evaluate_chunk(
            {"evaluator": impact_metrics_chunk, "options": {}, "points": src.take(start, stop)}
        )
        for s, c in zip(*np.unique(out["status"], return_counts=True), strict=True):
            counts[str(s)] = counts.get(str(s), 0) + int(c)
        worst = max(worst, float(np.nanmax(out["a_h_max_g"])))
        while stop >= mark:
            cpu = time.process_time() - t0
            print(f"  {mark:>13,} designs: peak RSS {peak_mib():8.1f} MiB, CPU per design "
                  f"{cpu / mark / per_design:.2f}x the baseline")  # fmt: skip
            mark *= 10
    print(f"  load average (1 min) at the end: {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    print(f"  done: {n:,} designs, peak RSS {peak_mib():.1f} MiB; status counts {counts}; "
          f"largest a_h,max {worst:.1f} g")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
