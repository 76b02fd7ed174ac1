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

3. a study's per-run metrics of that run (``run_row``: clearance, personal space and the
   crowd met, by pedpy).

It prints simulated seconds per CPU second (``time.process_time``: the cost on one core,
whatever else runs on the machine; the best of ``--repeats`` runs), the ratio robot side /
pedestrian side, and the same with the per-run metrics added.
Targets: robot side <= 50 % of the pedestrian simulator's cost; 50 pedestrians >= 20x real
time on one core, pedestrian simulation included. In the 30 m corridor the robot cannot
arrive within the default 20 s, so every run lasts the whole horizon.

Measured on 2026-12-02 (2 cores shared with seven other jobs, load about 10; CPU seconds, 20 s
runs, best of 3, four runs of the benchmark): JuPedSim alone 144-204x / 35-50x / 16-20x real
time for 10 / 50 / 100 pedestrians; coupled 47-74x / 21-31x / 11-15x; robot side 70-110 % /
31-44 % / 18-23 % of the pedestrian side.

After the robot side's per-period cost was cut (issue 23 item 5: velocities differenced for
the slot candidates only, slot rows in plain floats written into the step's input, running
minima with one reduction, cached ring rows; results bit-identical), same day, same load,
the old and new code run alternately: robot side at 10 pedestrians 84-85 % -> 57-61 % of the
pedestrian side, at 50 pedestrians 32-36 % -> 24 %, at 100 (one run) 15 %; coupled
53-75x / 21-27x / 11x real time. The 50 % target holds from 50 pedestrians on; at 10 it is
still missed: the compiled step itself costs about 60-70 us of CPU per period on this loaded
machine and the remaining numpy calls (distances at every dynamics step, arrival, records)
about 0.1-0.2 ms, against JuPedSim's cheap 10-agent step (about 0.5-0.6 ms per period).

Measured on 2026-12-05 after the bookkeeping was compiled (numba, one call for the slots and
one for the period's arrival, distance, energy and walkable-area measures; runs bit-identical
to the numpy path and to the code before on 68 compared runs), 2 cores shared with seven
other jobs, load average 12-15, the code before (same commit's benchmark script) and after run
alternately, two rounds each:

| pedestrians | robot / ped side, before | after | coupled x real time, before | after |
|---|---|---|---|---|
| 10 | 61-62 % | 28 % | 88-102x | 126-140x |
| 50 | 20-23 % | 8-9 % | 34-39x | 42-46x |
| 100 | 12-18 % | 5 % | 15-17x | 17-20x |

What is left on the robot side is the compiled step itself (about 0.1 ms per period). A
study adds its per-run metrics after a run: 3 ms before pedpy, now 29-31 / 64-78 /
102-123 ms for 10 / 50 / 100 pedestrians (pedpy's pandas calls cost about 25 ms whatever
the size); with them, the robot side and metrics are 55-58 % / 25-28 % / 15-18 % of the
pedestrian side (63-64 % / 24-27 % / 16-19 % before).

A study measures the crowd met of its runs together (``faced_by_runs``: runs in one band
share each pedpy call, up to 20,000 pedestrian-frames per call, so 16 runs of 10 pedestrians
pay pedpy's fixed cost once; values identical to run by run). The last two columns are a
study's per-run metrics of ``--study-runs`` runs (default 16) and the ratio with them.
Measured on 2026-12-05, 2 cores, load average 1.5-2.3 (the other jobs idle), the code before
and after run alternately, six runs of each (after: the last two with the final settings);
metrics per run in ms, "ratio" = (robot side + metrics) / pedestrian side:

| pedestrians | before | after, one run | after, in a study | ratio before | after, in a study |
|---|---|---|---|---|---|
| 10 | 23-29 | 21-26 | 8 | 50-59 % | 34-36 % |
| 50 | 50-58 | 42-46 | 55 | 22-25 % | 23 % |
| 100 | 64-87 | 58-73 | 93-104 | 11-14 % | 15-16 % |

At 10 pedestrians the target now holds for a study's runs (a single run's metrics, with
pedpy's ~20 ms fixed cost, still give 47-54 %). From 50 pedestrians on a study's runs are
measured one per pedpy call (more rows per call cost more per row), yet the benchmark's
study loop costs 20-60 % more per run than one run alone; not yet explained (the records
of 16 runs held in memory?).

``--methods`` instead measures what a run of each method costs in the deciding studies'
cells (``studies/pending/crowds_decide_*.yaml``: 4 m x 12 m sealed layouts, pedestrians
avoiding the robot, the limit 4 x the free-run time), the run's metrics included, and prints
CPU seconds per run and runs per CPU second per method and density::

    python benchmarks/crowds.py --methods --densities 0.25 1.0 --seeds 0 1
"""

from __future__ import annotations

import argparse
import time

import designlab as dl
from designlab.navigation.crowds.faced import faced_by_runs
from designlab.navigation.crowds.study import FACED_BATCH, run_row

nav = dl.navigation
GAINS = nav.VFFGains(4.3, 0.68, 20.3, 240.7)


def measure(
    n: int, horizon: float, seed: int, repeats: int, study_runs: int = FACED_BATCH
) -> dict[str, float]:
    """CPU times of JuPedSim alone and of the coupled run for ``n`` pedestrians (best of
    ``repeats``), and of a study's per-run metrics, alone and per run of ``study_runs``."""
    crowd = nav.crowd("corridor_counterflow", n, width=4.0, length=30.0, seed=seed, horizon=horizon)
    nav.simulate(crowd.replace(horizon=0.12), GAINS)  # build the compiled step once
    alone, best = [], None
    for _ in range(repeats):
        t0 = time.process_time()
        nav.simulate_pedestrians(crowd)
        alone.append(time.process_time() - t0)
        t0 = time.process_time()
        res = nav.simulate(crowd, GAINS)
        total = time.process_time() - t0
        if best is None or total < best[0]:
            best = (total, res)
    total, res = best
    sim_t = float(res.times[-1])
    metrics, study = [], []
    for _ in range(repeats):  # a study's per-run metrics (clearance, personal space, pedpy)
        t0 = time.process_time()
        run_row(res, robot_radius=res.crowd.robot.radius)
        metrics.append(time.process_time() - t0)
        t0 = time.process_time()  # in a study: the crowd met of FACED_BATCH runs in one call
        for _ in range(study_runs):
            run_row(res, robot_radius=res.crowd.robot.radius, faced=False)
        faced_by_runs([res] * study_runs)
        study.append((time.process_time() - t0) / study_runs)
    return {
        "n": n,
        "alone_x": horizon / min(alone),
        "coupled_x": sim_t / total,
        "ped_s": res.pedestrian_seconds,
        "robot_s": res.robot_seconds,
        "ratio": res.robot_seconds / res.pedestrian_seconds,
        "metrics_s": min(metrics),
        "with_metrics": (res.robot_seconds + min(metrics)) / res.pedestrian_seconds,
        "study_s": min(study),
        "with_study": (res.robot_seconds + min(study)) / res.pedestrian_seconds,
    }


#: The methods of the deciding studies (``studies/pending/crowds_decide_*.yaml``).
DECIDE_METHODS = ("vff", "cbf", "masoud", "ge_cui", "orca", "social_force")


def measure_methods(layout: str, densities: list[float], seeds: list[int],
                    model: str) -> list[dict[str, float]]:  # fmt: skip
    """CPU seconds of one run (simulation and its study row) per method and density."""
    rows = []
    for rho in densities:
        for m in DECIDE_METHODS:
            cpu = []
            for seed in seeds:
                c = nav.crowd(layout, density=rho, width=4.0, length=12.0, seed=seed, model=model,
                              react_to_robot=True, region_sizing="closing_speed",
                              horizon_factor=4.0)  # fmt: skip
                t0 = time.process_time()
                res = nav.simulate(c, nav.OPTIMAL_GAINS if m == "vff" else None, method=m)
                run_row(res, robot_radius=c.robot.radius, faced=False)
                cpu.append(time.process_time() - t0)
            mean = sum(cpu) / len(cpu)
            rows.append({"density": rho, "method": m, "cpu_s": mean, "runs_per_cpu_s": 1 / mean})
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--horizon", type=float, default=20.0, help="simulated seconds per run")
    ap.add_argument("--sizes", type=int, nargs="+", default=[10, 50, 100])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeats", type=int, default=3, help="runs per size (the best counts)")
    ap.add_argument("--study-runs", type=int, default=FACED_BATCH,
                    help="runs whose crowd met is measured in one pedpy call")  # fmt: skip
    ap.add_argument("--methods", action="store_true", help="CPU per run of each method")
    ap.add_argument("--layout", default="corridor_counterflow")
    ap.add_argument("--model", default="collision_free_speed")
    ap.add_argument("--densities", type=float, nargs="+", default=[0.25, 0.5, 1.0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    args = ap.parse_args()
    if args.methods:
        nav.simulate(nav.crowd(args.layout, 4, width=4.0, length=12.0, horizon=0.12),
                     nav.OPTIMAL_GAINS)  # fmt: skip
        print(f"{'density':>8} {'method':>13} {'CPU s / run':>12} {'runs / CPU s':>13}")
        for r in measure_methods(args.layout, args.densities, args.seeds, args.model):
            print(f"{r['density']:>8g} {r['method']:>13} {r['cpu_s']:>12.2f} "
                  f"{r['runs_per_cpu_s']:>13.2f}")  # fmt: skip
        return
    print(
        f"{'N':>4} {'JuPedSim alone':>15} {'coupled':>9} {'ped side s':>11} {'robot side s':>13} "
        f"{'robot/ped':>10} {'metrics s':>10} {'(robot+metrics)/ped':>20} "
        f"{'in a study: metrics s':>22} {'(robot+metrics)/ped':>20}"
    )
    for n in args.sizes:
        m = measure(n, args.horizon, args.seed, args.repeats, args.study_runs)
        print(
            f"{m['n']:>4} {m['alone_x']:>13.1f}x {m['coupled_x']:>8.1f}x {m['ped_s']:>11.3f} "
            f"{m['robot_s']:>13.3f} {m['ratio']:>9.0%} {m['metrics_s']:>10.3f} "
            f"{m['with_metrics']:>19.0%} {m['study_s']:>22.3f} {m['with_study']:>19.0%}"
        )
    print("targets: robot/ped <= 50 %; 50 pedestrians coupled >= 20x real time")


if __name__ == "__main__":
    main()
