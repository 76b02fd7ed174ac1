"""Pass/fail of a head-acceleration limit against the full kernel (issue 40.5), in one process.

For blocks of random designs, alternately: the full kernel
(:func:`designlab.impact.metrics.metrics_of_matrix` for a_h alone, as the exceedance
probability's criterion asks it) compared with the limit, and
:func:`designlab.impact.passfail.head_acceleration_exceeds`. Both on one thread
(``workers=1``), CPU seconds; the full kernel with every metric (``impact_metrics``'
default, a sweep's) is timed too. Prints the rate of each, their ratio per block (median and
range), the share decided by the bounds, and the number of designs whose decisions differ
from the full kernel's where it gives a maximum (must be 0: it is certified, so equal
decisions are an exact check), and how many designs it leaves uncertified (NaN) the bounds
decided.

Two populations:

``wide``
    Designs over wide ranges (robot 2-60 kg, foam 5e3-1e5 N/m, 10-300 N s/m, heads
    3.5-6 kg, necks 1e3-1e4 N/m, v_c 0.3-2 m/s; log-uniform where the range spans
    decades) against 10 g: the envelope's and the speed limit's kind of question.
``risk``
    MANIPULATOR_1 with FOAM_1, heads uniform over the thesis's ranges (THESIS_HEAD_RANGE) and
    v_c uniform over 0.5-2.5 m/s against 10 g: the samples of an exceedance probability.

Run:  python benchmarks/passfail.py [--designs 1000000] [--block 262144]
(``--designs 10000000`` for the issue's 1e7 when the machine allows).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

from designlab.impact import FOAM_1, MANIPULATOR_1, THESIS_HEAD_RANGE
from designlab.impact.metrics import metrics_of_matrix
from designlab.impact.passfail import A_H_ONLY, decisions_of_metrics, head_acceleration_exceeds

LIMIT_G = 10.0


def wide(n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Designs over wide ranges and their closing speeds."""

    def lu(lo: float, hi: float) -> np.ndarray:
        return np.exp(rng.uniform(np.log(lo), np.log(hi), n))

    heads = (rng.uniform(3.5, 6.0, n), rng.uniform(0, 50, n), lu(1e3, 1e4))
    p = np.column_stack(
        [lu(2, 60), lu(10, 1000), lu(5e3, 50e3), lu(5e3, 100e3), lu(10, 300), *heads]
    )
    return p, rng.uniform(0.3, 2.0, n)


def risk(n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """MANIPULATOR_1 with FOAM_1, heads uniform over THESIS_HEAD_RANGE, v_c uniform 0.5-2.5 m/s."""
    r, f, h = MANIPULATOR_1, FOAM_1, THESIS_HEAD_RANGE
    p = np.empty((n, 8))
    p[:, 0], p[:, 1], p[:, 2] = r.mass, r.damping, r.stiffness
    p[:, 3], p[:, 4] = f.stiffness, f.damping
    p[:, 5] = rng.uniform(h.mass[0], h.mass[1], n)
    p[:, 6] = rng.uniform(h.damping[0], h.damping[1], n)
    p[:, 7] = rng.uniform(h.stiffness[0], h.stiffness[1], n)
    return p, rng.uniform(0.5, 2.5, n)


def run(name: str, draw, designs: int, block: int) -> None:  # type: ignore[no-untyped-def]
    """Alternate the two paths over blocks of ``block`` designs; print the figures."""
    rng = np.random.default_rng(40)
    p, v = draw(256, rng)  # warm-up: both paths compiled and loaded before timing
    head_acceleration_exceeds(p, v, LIMIT_G, workers=1)
    metrics_of_matrix(p, v, workers=1, **A_H_ONLY)
    ratios, cpu_full, cpu_fast, cpu_all = [], 0.0, 0.0, 0.0
    bounds = differ = extra = done = 0
    while done < designs:
        n = min(block, designs - done)
        p, v = draw(n, rng)
        c0 = time.process_time()
        m = metrics_of_matrix(p, v, workers=1, **A_H_ONLY)
        ref = decisions_of_metrics(m.peak_head_acceleration_g, LIMIT_G)
        c1 = time.process_time()
        d = head_acceleration_exceeds(p, v, LIMIT_G, workers=1)
        c2 = time.process_time()
        metrics_of_matrix(p, v, workers=1)  # every metric, impact_metrics' default
        cpu_all += time.process_time() - c2
        cpu_full += c1 - c0
        cpu_fast += c2 - c1
        ratios.append((c1 - c0) / (c2 - c1))
        bounds += int(d.by_bounds.sum())
        sure = np.isfinite(m.peak_head_acceleration_g)  # the full kernel's certified maxima
        differ += int(np.count_nonzero((d.exceeds != ref) & sure))
        extra += int(np.count_nonzero(~sure & d.by_bounds))
        done += n
    print(f"{name}: {done:,} designs against {LIMIT_G:g} g, one thread, CPU seconds")
    print(
        f"  full kernel + comparison  {cpu_full:8.2f} s  {done / cpu_full / 1e3:8.0f} k designs/s"
    )
    print(
        f"  pass/fail                 {cpu_fast:8.2f} s  {done / cpu_fast / 1e3:8.0f} k designs/s"
    )
    print(f"  full kernel, every metric {cpu_all:8.2f} s  {done / cpu_all / 1e3:8.0f} k designs/s"
          f"  (pass/fail {cpu_all / cpu_fast:.2f}x faster)")  # fmt: skip
    print(f"  ratio to the a_h kernel {cpu_full / cpu_fast:.2f}x overall; per block median "
          f"{statistics.median(ratios):.2f}x, range {min(ratios):.2f}-{max(ratios):.2f}x "
          f"({len(ratios)} blocks; target >= 3x)")  # fmt: skip
    print(f"  decided by the bounds {100 * bounds / done:.3f} %; designs whose decisions "
          f"differ from the full kernel's certified ones: {differ} (must be 0); designs the "
          f"kernel left uncertified (NaN) that the bounds decided: {extra}")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", type=int, default=1_000_000)
    parser.add_argument("--block", type=int, default=1 << 18)
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.1f}")
    t0 = time.perf_counter()
    for name, draw in (("wide", wide), ("risk", risk)):
        run(name, draw, args.designs, args.block)
    print(f"load average after: {os.getloadavg()[0]:.1f}; wall {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
