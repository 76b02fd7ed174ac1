"""Benchmark: how often does the stabilising force drive a robot into a critical region?

Run with ``python benchmarks/navigation_safety.py [--sets 1000] [--seed 0] [--jit]``. It draws
``--sets`` gain sets log-uniformly in the App. C.2 search box (K1 0.5-50 N/m, b 0.05-3 s,
K3 0.5-200 N/m, K5 0.5-500 N/m^2), simulates every set on Zeng 2011 Configurations 1-4 with
the stabilising force off and on (``simulate_batch``), and prints per configuration how many
sets enter a critical region or collide in each mode, and how many do so **only with the
force on** (the field alone keeps them out). This is the evidence behind
``docs/navigation.md``, "The stabilising force is not a safety guarantee": the force is a
Lyapunov device, not a safety layer, so gain sets are checked in the mode they run in.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import designlab as dl

BOX = np.array([[0.5, 50.0], [0.05, 3.0], [0.5, 200.0], [0.5, 500.0]])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--jit", action="store_true")
    args = ap.parse_args()
    nav = dl.navigation
    rng = np.random.default_rng(args.seed)
    lo, hi = np.log(BOX[:, 0]), np.log(BOX[:, 1])
    gains = np.exp(lo + (hi - lo) * rng.random((args.sets, 4)))
    print(f"{args.sets} gain sets, seed {args.seed}, log-uniform in the App. C.2 box")
    print(
        "config  critical off/on  collided off/on  critical only with F_L  collided only with F_L"
    )
    t0 = time.perf_counter()
    for c in (1, 2, 3, 4):
        sc = [nav.configuration(c)]
        off = nav.simulate_batch(sc, gains, stabilising="off", jit=args.jit)
        on = nav.simulate_batch(sc, gains, stabilising="lyapunov", jit=args.jit)
        co, cn = off.entered_critical[0], on.entered_critical[0]
        ko, kn = off.collided[0], on.collided[0]
        print(f"{c:6d}  {co.sum():5d} / {cn.sum():5d}  {ko.sum():6d} / {kn.sum():5d}  "
              f"{(cn & ~co).sum():22d}  {(kn & ~ko).sum():22d}")  # fmt: skip
    print(f"{time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
