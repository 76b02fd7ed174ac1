"""Profile: where the compiled impact kernel spends its time, and how much work it does per design.

Run with ``python benchmarks/kernel_profile.py`` (about two minutes: a fresh compile
of the kernel, ten seconds of sampling, a pure-Python count). Two parts:

* **time shares** (needs Linux ``perf``): the kernel is compiled in this process
  into a temporary numba cache (code loaded from a cache carries no addresses),
  the addresses of its compiled functions are taken from numba's code library,
  ``perf record`` samples this process while :func:`designlab.impact.kernel.reduced_metrics`
  runs on 20 000 designs over the wide ranges of issue 22, and every sample is
  charged to the compiled function that holds its address (inlined helpers count
  in their caller);
* **work per design**: the kernel's Python source (``DESIGNLAB_NO_JIT=1``, in a
  subprocess) on 400 of those designs, counting complex exponentials, derivative
  evaluations in Newton, march nodes, grid nodes, cells pushed and splits.

The figures quoted in ``docs/impact.md`` ("Where the fifth kernel's time goes") come
from this script.
"""

from __future__ import annotations

import argparse
import bisect
import collections
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def short_name(mangled: str) -> str:
    """``module.function`` of a numba-mangled symbol (``_ZN9designlab6impact...``)."""
    parts, i = [], mangled.find("_ZN") + 3
    while 2 < i < len(mangled) and mangled[i].isdigit():
        j = i
        while mangled[j].isdigit():
            j += 1
        n = int(mangled[i:j])
        parts.append(mangled[j : j + n])
        i = j + n
    return ".".join(parts[-2:]) if parts else mangled[:40]


def designs(n: int):  # type: ignore[no-untyped-def]
    """``n`` designs over the wide ranges of ``benchmarks/impact.py`` (its seed)."""
    import numpy as np

    sys.path.insert(0, os.path.join(_ROOT, "benchmarks"))
    from impact import wide_designs

    return wide_designs(n, np.random.default_rng(20110101))[0]


def _addresses(dispatcher):  # type: ignore[no-untyped-def]
    """Sorted ``(address, name)`` of every function compiled for ``dispatcher``."""
    lib = next(iter(dispatcher.overloads.values())).library
    found, seen, todo = set(), set(), [lib]
    while todo:
        lb = todo.pop()
        if id(lb) in seen:
            continue
        seen.add(id(lb))
        for f in lb.get_defined_functions():
            if f.name.startswith("_ZN") and "cpython" not in f.name:
                address = lib.get_pointer_to_function(f.name)
                if address:
                    found.add((address, short_name(f.name)))
        todo.extend(getattr(lb, "_linking_libraries", []))
    return sorted(found)


def time_shares(seconds: float) -> None:
    """Sample the kernel with ``perf`` and print each compiled function's share."""
    from designlab.impact import kernel

    p = designs(20_000)
    kw = dict(printed=False, stop_time=0.05, max_lobe_steps=4096, diagnostics=False)
    t0 = time.process_time()
    kernel.reduced_metrics(p[:16], (True, True, True), **kw)
    print(f"compiled in {time.process_time() - t0:.0f} s CPU")
    table = _addresses(kernel._reduced_block)
    starts = [a for a, _ in table]
    fd, data = tempfile.mkstemp(suffix=".perf")
    os.close(fd)
    perf = subprocess.Popen(["perf", "record", "-q", "-o", data, "-p", str(os.getpid())],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # fmt: skip
    time.sleep(1.0)
    runs, t0 = 0, time.process_time()
    while time.process_time() - t0 < seconds:
        kernel.reduced_metrics(p, (True, True, True), **kw)
        runs += 1
    per = (time.process_time() - t0) / (runs * len(p)) * 1e6
    perf.send_signal(signal.SIGINT)
    perf.wait()
    script = ["perf", "script", "-i", data, "-F", "ip,sym,dso"]
    lines = subprocess.run(script, capture_output=True, text=True, check=True).stdout.splitlines()
    os.unlink(data)
    shares: collections.Counter[str] = collections.Counter()
    for line in lines:
        fields = line.split()
        if not fields:
            continue
        ip = int(fields[0], 16)
        k = bisect.bisect_right(starts, ip) - 1
        if k >= 0 and ip - starts[k] < 0x20000 and ("[JIT]" in line or "unknown" in line):
            shares[table[k][1]] += 1
        else:
            shares[" ".join(fields[1:2]) or "?"] += 1
    total = sum(shares.values())
    print(f"{per:.2f} us per design under sampling; {total} samples; load {os.getloadavg()[0]:.1f}")
    for name, count in shares.most_common(16):
        print(f"  {100 * count / total:5.1f} %  {name}")


_COUNT = """
import collections, sys
sys.path.insert(0, {bench!r})
import numpy as np
from impact import wide_designs
import designlab.impact.kernel as K
import designlab.impact.kernel_lobe as L
import designlab.impact.kernel_modal as M
C = collections.Counter()
def counted(mod, name, key, size=None):
    f = getattr(mod, name)
    def g(*a):
        C[key] += 1
        if size:
            C[key + " nodes"] += size(a)
        return f(*a)
    setattr(mod, name, g)
for mod in (K, L, M):
    counted(mod, "cexp", "complex exponentials")
counted(M, "derivatives", "derivative evaluations")
counted(L, "grid", "grids", lambda a: a[6] + 1)
counted(L, "_push_grid", "cells pushed")
counted(L, "_split", "splits")
march = L.march
def counted_march(*a):
    res = march(*a)
    C["march nodes"] += round(res[2] / a[5]) if res[0] else a[6]
    return res
L.march = counted_march
p = wide_designs({n}, np.random.default_rng(20110101))[0]
K.reduced_metrics(p, (True, True, True), printed=False, stop_time=0.05, max_lobe_steps=4096,
                  diagnostics=False)
for k, v in sorted(C.items()):
    print(f"  {{v / {n}:6.2f}}  {{k}} per design")
"""


def work_counts(n: int) -> None:
    """Count the kernel's operations per design in its Python source (no compiler)."""
    env = dict(os.environ, DESIGNLAB_NO_JIT="1")
    code = _COUNT.format(bench=os.path.join(_ROOT, "benchmarks"), n=n)
    subprocess.run([sys.executable, "-c", code], env=env, check=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0, help="CPU seconds sampled")
    ap.add_argument("--designs", type=int, default=400, help="designs counted")
    args = ap.parse_args()
    print(f"work per design ({args.designs} wide-range designs, the kernel's Python source):")
    work_counts(args.designs)
    cache = tempfile.mkdtemp(prefix="designlab-profile-")
    os.environ["NUMBA_CACHE_DIR"] = cache  # a fresh compile: cached code carries no addresses
    try:
        from designlab.impact import kernel

        if not kernel.AVAILABLE:
            print("time shares: no compiled kernel on this machine (numba missing or disabled)")
        elif shutil.which("perf") is None:
            print("time shares: Linux perf is not installed")
        else:
            time_shares(args.seconds)
    finally:
        shutil.rmtree(cache, ignore_errors=True)


if __name__ == "__main__":
    main()
