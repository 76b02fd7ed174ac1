"""Benchmark: compiling a step cold vs loading it from the disk cache (designlab.sx).

Run with ``python benchmarks/compile_cache.py``. For two SX functions, the lean
navigation step of Zeng 2011 Configuration 4 (the one ``jit=True`` batches use) and the
tether follower's closed-loop step (FTL-CD with wheel limits, winch offset and noise),
it times :func:`designlab.sx.compile_lanes` in a fresh process with an empty cache
directory (cold: generate the C source, run the C compiler, store, load) and again in a
second fresh process (warm: find the entry by its key, check its hash, load). Each
process builds the CasADi function first (timed apart: model building, not compiling).
It prints both times and their ratio; the cache directory is temporary and removed.
For reference it also times :func:`designlab.sx.compile_sx` on the tether step (the
generated Python of a single run, not cached: it takes milliseconds).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time

CHILD = r"""
import json, sys, time
t0 = time.perf_counter()
import designlab as dl
from designlab import sx
t1 = time.perf_counter()
if sys.argv[1] == "navigation":
    from designlab.navigation import engine
    from designlab.navigation.field import ObstacleGeometry
    sc = dl.navigation.configuration(4)
    geos = tuple(ObstacleGeometry.of(o) for o in sc.obstacles)
    f = sx.with_cse(engine.build_step(geos, sc.robot, "vff", 60, 1e-3, True, True))
    shared = engine._SHARED
else:
    from designlab.following.tether.model import step_function
    law = dl.following.FollowTheLeaderConstDistance.law_function("")
    f = step_function(law, True, True, True, True)
    shared = []
t2 = time.perf_counter()
sx.compile_lanes(f, shared)
t3 = time.perf_counter()
py0 = time.perf_counter()
if sys.argv[1] == "tether":
    sx.compile_sx(f)
py1 = time.perf_counter()
print(json.dumps(dict(build=t2 - t1, compile=t3 - t2, python=py1 - py0, n=f.n_instructions())))
"""


def _child(kind: str, env: dict[str, str]) -> dict[str, float]:
    t0 = time.perf_counter()
    out = subprocess.run(
        [sys.executable, "-c", CHILD, kind], env=env, capture_output=True, text=True
    )
    if out.returncode:
        raise RuntimeError(out.stderr)
    res = json.loads(out.stdout.strip().splitlines()[-1])
    res["process"] = time.perf_counter() - t0
    return res


def main() -> int:
    print(
        f"cold compile vs warm cache load, each in a fresh process (load average "
        f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)",
        flush=True,
    )
    with tempfile.TemporaryDirectory(prefix="designlab_bench_cache_") as cache:
        env = {**os.environ, "DESIGNLAB_CACHE_DIR": cache}
        for kind, label in (("navigation", "navigation lean step"), ("tether", "tether step")):
            cold = _child(kind, env)
            warm = _child(kind, env)
            print(
                f"{label:22s} ({cold['n']:5.0f} SX instructions): cold compile "
                f"{cold['compile']:7.3f} s, warm load {warm['compile']:7.4f} s -> "
                f"{cold['compile'] / warm['compile']:6.0f}x; building the CasADi function "
                f"{warm['build']:.3f} s"
                + (
                    f"; compile_sx (Python, uncached) {warm['python']:.3f} s"
                    if warm["python"] > 1e-4
                    else ""
                )
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
