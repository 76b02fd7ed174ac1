"""Benchmark of the robot among JuPedSim's pedestrians (issue 23, item 5).

Run from the repository root (about a minute)::

    python benchmarks/crowds.py
    python benchmarks/crowds.py --horizon 20 --sizes 10 50 100

For 10, 50 and 100 pedestrians in the 30 m x 4 m counterflow corridor (the pedestrians
ignore the robot, collision-free speed model, dt_p = 0.01 s, T_s = 0.06 s, 1 ms dynamics):

1. JuPedSim alone (``navigation.simulate_pedestrians``: stepping and reading the positions);
2. the coupled run (``navigation.simulate`` with the thesis's gains, VFF with the stabilising
   force), split into the pedestrian side and the robot side (slots, compiled step,
   distances to every pedestrian and wall at every dynamics step, records).

It prints simulated seconds per wall second and the ratio robot side / pedestrian side.
Targets: robot side <= 50 % of the pedestrian simulator's cost; 50 pedestrians >= 20x real
time on one core, pedestrian simulation included. The robot is kept from arriving (its goal
is the far end of a long horizon) so every run lasts the whole horizon.
"""

from __future__ import annotations

import argparse
import time

import designlab as dl

nav = dl.navigation
GAINS = nav.VFFGains(4.3, 0.68, 20.3, 240.7)


def measure(n: int, horizon: float, seed: int) -> dict[str, float]:
    """Wall times of JuPedSim alone and of the coupled run for ``n`` pedestrians."""
    crowd = nav.crowd("corridor_counterflow", n, width=4.0, length=30.0, seed=seed, horizon=horizon)
    t0 = time.perf_counter()
    nav.simulate_pedestrians(crowd)
    alone = time.perf_counter() - t0
    nav.simulate(crowd.replace(horizon=0.12), GAINS)  # build the compiled step once
    t0 = time.perf_counter()
    res = nav.simulate(crowd, GAINS)
    total = time.perf_counter() - t0
    sim_t = float(res.times[-1])
    return {
        "n": n,
        "simulated_s": sim_t,
        "alone_x": horizon / alone,
        "coupled_x": sim_t / total,
        "ped_s": res.pedestrian_seconds,
        "robot_s": res.robot_seconds,
        "ratio": res.robot_seconds / res.pedestrian_seconds,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--horizon", type=float, default=20.0, help="simulated seconds per run")
    ap.add_argument("--sizes", type=int, nargs="+", default=[10, 50, 100])
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    print(
        f"{'N':>4} {'JuPedSim alone':>15} {'coupled':>9} {'ped side s':>11} {'robot side s':>13} "
        f"{'robot/ped':>10}"
    )
    for n in args.sizes:
        m = measure(n, args.horizon, args.seed)
        print(
            f"{m['n']:>4} {m['alone_x']:>13.1f}x {m['coupled_x']:>8.1f}x {m['ped_s']:>11.3f} "
            f"{m['robot_s']:>13.3f} {m['ratio']:>9.0%}"
        )
    print("targets: robot/ped <= 50 %; 50 pedestrians coupled >= 20x real time")


if __name__ == "__main__":
    main()
