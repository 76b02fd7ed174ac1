"""Benchmark: how often does the stabilising force drive a robot into a critical region?

Run with ``python benchmarks/navigation_safety.py [--sets 1000] [--seed 0] [--jit]``. It draws
``--sets`` gain sets log-uniformly in the App. C.2 search box (K1 0.5-50 N/m, b 0.05-3 s,
K3 0.5-200 N/m, K5 0.5-500 N/m^2), simulates every set on Zeng 2011 Configurations 1-4 with
the stabilising force off and on (``simulate_batch``), and prints per configuration how many
sets enter a critical region or collide in each mode, and how many do so **only with the
force on** (the field alone keeps them out). This is the evidence behind
``docs/navigation.md``, "The stabilising force is not a safety guarantee": the force is a
Lyapunov device, not a safety layer, so gain sets are checked in the mode they run in.

The last two columns run the same sets with the safety layer, ``method="vff_cbf"`` (the new
VFF with its stabilising force, corrected by the CBF filter, one QP per period; not batched,
so ``--cbf-sets`` can take fewer of the sets): critical-region entries and collisions with
the layer, and how many of them arrive (the layer can stop a robot in a narrow passage).
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
    ap.add_argument("--cbf-sets", type=int, default=None, help="sets run with vff_cbf")
    ap.add_argument("--configs", type=int, nargs="+", default=[1, 2, 3, 4])
    args = ap.parse_args()
    nav = dl.navigation
    rng = np.random.default_rng(args.seed)
    lo, hi = np.log(BOX[:, 0]), np.log(BOX[:, 1])
    gains = np.exp(lo + (hi - lo) * rng.random((args.sets, 4)))
    print(f"{args.sets} gain sets, seed {args.seed}, log-uniform in the App. C.2 box")
    n_cbf = args.sets if args.cbf_sets is None else min(args.cbf_sets, args.sets)
    print(
        "config  critical off/on  collided off/on  critical only with F_L  collided only with F_L"
        f"  | vff_cbf ({n_cbf} sets): critical  collided  arrived"
    )
    t0 = time.perf_counter()
    for c in args.configs:
        sc = [nav.configuration(c)]
        off = nav.simulate_batch(sc, gains, stabilising="off", jit=args.jit)
        on = nav.simulate_batch(sc, gains, stabilising="lyapunov", jit=args.jit)
        co, cn = off.entered_critical[0], on.entered_critical[0]
        ko, kn = off.collided[0], on.collided[0]
        layer = [nav.simulate(sc[0], nav.VFFGains(*g), method="vff_cbf") for g in gains[:n_cbf]]
        lc = sum(r.entered_critical for r in layer)
        lk = sum(r.collided for r in layer)
        la = sum(r.arrived for r in layer)
        print(f"{c:6d}  {co.sum():5d} / {cn.sum():5d}  {ko.sum():6d} / {kn.sum():5d}  "
              f"{(cn & ~co).sum():22d}  {(kn & ~ko).sum():22d}  | {lc:8d}  {lk:8d}  {la:7d}",
              flush=True)  # fmt: skip
    print(f"{time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
