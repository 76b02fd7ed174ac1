"""The CI slice of the kernel's fuzz harness (benchmarks/fuzz_kernel.py; issue 34).

100,000 seeded designs over the thesis's and the wide ranges go through the compiled
kernel with its self-check and through the numpy modal path (5 CPU seconds); every
disagreement above 1e-10 (relative) or in status is settled by a 40-digit
mpmath evaluation, and the kernel must be right on every design. The full run is
``python benchmarks/fuzz_kernel.py --designs 1e7`` (docs/impact.md, "Self-check").
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from designlab.impact import kernel

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
fuzz = pytest.importorskip("fuzz_kernel")
pytest.importorskip("mpmath")


#: designs per family. Near-critical damping is left to the benchmark (the numpy path is
#: off by about 1e-9 on one design in 150 there, and each such disagreement costs a
#: 40-digit evaluation); nearly repeated modes under a very soft foam too (the kernel is
#: not yet right on all of them: docs/impact.md, "Self-check")
SLICE = {"thesis": 50_000, "wide": 50_000}


@pytest.mark.skipif(not kernel.AVAILABLE, reason="compiled kernels unavailable")
@pytest.mark.slow
def test_hundred_thousand_designs_no_kernel_error() -> None:
    total = wrong = 0
    for family, n in SLICE.items():
        r = fuzz.run(family, n, seed=34, chunk=16_384, verbose=False)
        total += r["designs"]
        wrong += r["kernel_wrong"]
    assert total == 100_000
    assert wrong == 0
