"""The long run of tests/study/test_valid_studies.py: many valid studies per kind.

The test suite runs each kind's carrier and one seeded variant (a quick slice). This script
draws ``--examples`` valid studies of each kind (all kinds, or those named), runs each and
writes its report, and prints per kind how many ran, how many crashed and the first crash.
A crash is any exception: ``validate`` accepted the study, so ``run`` and the report writer
must finish (failed points are listed in the report).

Run: ``python benchmarks/fuzz_valid_studies.py [--examples 20] [--seed 0] [KIND ...]``
(from a source checkout; heavy kinds take seconds per study).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import traceback
from pathlib import Path
from typing import Any

from hypothesis import HealthCheck, given, seed, settings
from hypothesis import strategies as st

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests" / "study"))

from test_valid_studies import _check  # noqa: E402

from designlab.study import study_kinds  # noqa: E402


def fuzz(kind: str, examples: int, rng_seed: int) -> tuple[int, list[str]]:
    """Draw ``examples`` studies of ``kind``: (studies run, crashes)."""
    crashes: list[str] = []
    count = 0

    @seed(rng_seed)
    @settings(max_examples=examples, database=None, deadline=None,
              suppress_health_check=list(HealthCheck))  # fmt: skip
    @given(data=st.data())
    def one(data: Any) -> None:
        nonlocal count
        count += 1
        with tempfile.TemporaryDirectory() as tmp:
            try:
                _check(kind, data, Path(tmp) / "r")
            except Exception:
                crashes.append(traceback.format_exc(limit=-3))

    one()
    return count, crashes


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("kinds", nargs="*", help="kinds to fuzz (default: every kind)")
    ap.add_argument("--examples", type=int, default=20, help="studies per kind")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    total = 0
    for kind in args.kinds or sorted(study_kinds()):
        start = time.perf_counter()
        count, crashes = fuzz(kind, args.examples, args.seed)
        total += len(crashes)
        print(f"{kind:24s} {count:4d} studies {len(crashes):3d} crashes "
              f"{time.perf_counter() - start:7.1f} s", flush=True)  # fmt: skip
        if crashes:
            print("    first: " + crashes[0].strip().replace("\n", "\n    "))
    sys.exit(1 if total else 0)


if __name__ == "__main__":
    main()
