"""Benchmark: the Sec. 5.7 planners' cost against a VFF run in the same process.

Run with ``PYTHONPATH=. python benchmarks/planners.py`` from the repository root (a few
minutes). For Zeng 2011 Configurations 1-4 it times, in CPU seconds of this process, one run
of each planner (VO, NLVO, ERRT with seed 1, Field D* with 0.1 m cells) and one VFF run
(Table C.1's gains, stabilising force on, CasADi's virtual machine) and prints each
planner's cost as a multiple of the VFF run's, and its simulated seconds per CPU second.
The planners replan in Python every navigation period; docs/navigation_planners.md quotes
these ratios.
"""

from __future__ import annotations

import time

import designlab as dl
from designlab.navigation.planners.parameters import ERRTSettings, FieldDStarSettings

nav = dl.navigation
GAINS = nav.VFFGains(4.3, 0.68, 20.3, 240.7)
PLANNERS = {
    "vo": None,
    "nlvo": None,
    "errt": ERRTSettings(seed=1),
    "field_dstar": FieldDStarSettings(cell=0.1),
}


def cpu(fn, *args, **kwargs):
    """The result of ``fn`` and the CPU seconds it took."""
    t0 = time.process_time()
    out = fn(*args, **kwargs)
    return out, time.process_time() - t0


def main() -> None:
    for i in (1, 2, 3, 4):
        sc = nav.configuration(i)
        nav.simulate(sc, GAINS)  # warm-up: build the step once
        _, t_vff = cpu(nav.simulate, sc, GAINS)
        print(f"Configuration {i}: VFF {t_vff * 1e3:.0f} ms CPU")
        for name, settings in PLANNERS.items():
            r, t = cpu(nav.simulate, sc, settings, method=name)
            span = float(r.t[-1]) if len(r.t) else float("nan")
            print(f"  {name:>11}: {t:7.2f} s CPU, {t / t_vff:8.0f}x the VFF run, "
                  f"{span / t:6.2f} simulated s per CPU s")  # fmt: skip


if __name__ == "__main__":
    main()
