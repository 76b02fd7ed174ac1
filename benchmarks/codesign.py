"""Benchmark of the co-design layer: speed limits and injury probabilities.

Run from the repository root (about two minutes on one free core)::

    python benchmarks/codesign.py
    python benchmarks/codesign.py --reference 10000000 --samples 1000000

What is measured, in one process:

1. ``dl.codesign.speed_limit`` of Manipulator 1 with Foam 1 over the thesis's head
   range (every criterion), and ``speed_limit_map`` on a 40 x 40 foam grid: wall times.
2. ``dl.codesign.injury_probability`` with 1e6 samples (heads uniform over the thesis's
   ranges, closing speeds Rayleigh with a 1 m/s mode), crude and importance sampling:
   wall time (the issue's target: seconds) and the estimates.
3. The importance-sampling estimate at 1e5 samples against crude Monte Carlo at 1e7
   samples (``--reference``, pooled from runs of at most the declared cap, 2e6, with seeds
   3, 4, ...): the difference in units of their combined standard error (must be < 4).
4. A small probability (slow contacts, truncated normal closing speed): importance
   sampling resolves it with 1e4 samples; crude Monte Carlo at 1e7 samples sees no
   failure and only bounds it.
5. Subset simulation (``method="subset"``) on a small probability over the thesis's
   head range (Rayleigh closing speeds of mode 0.4 m/s, P about 1e-7): the mean of 20
   seeded runs at 2000 samples per level against importance sampling at 1e5, the scatter
   over the seeds against the stated c.o.v., and the evaluations per run
   (``--subset-only`` runs this part alone).
6. The front's cost (``--front-only`` runs this part alone): ``foam_limits`` of 40 foams
   in one lock-step search against 40 calls of ``speed_limit`` (the same answers; CPU
   ratio), and a ``pareto`` search of the committed study's shape (Configurations 2 and 4,
   THESIS_ROBOT, population 40) for ``--generations`` generations: designs per CPU second.
"""

from __future__ import annotations

import argparse
import logging
import math
import sys
import time
from types import SimpleNamespace

import numpy as np
from scipy import stats

import designlab as dl

log = logging.getLogger("benchmarks.codesign")
cd = dl.codesign
ROBOT, FOAM = dl.impact.MANIPULATOR_1, dl.impact.FOAM_1
CRITERIA = [
    dl.impact.HeadAcceleration(10),
    dl.impact.ImpactForce(660),
    dl.impact.HeadInjuryCriterion(650),
    dl.impact.IsoTransientForce("skull_forehead", transient_factor=2.0),
]


def timed(fn, *args, **kwargs):
    t0 = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - t0


def speed_limits() -> None:
    cd.speed_limit(ROBOT, FOAM)  # load the compiled kernel
    s, dt = timed(cd.speed_limit, ROBOT, FOAM, cd.SafetyCase(CRITERIA, human_speed=1.0))
    print(f"speed_limit (4 criteria + thickness, 27 heads): {dt * 1e3:.0f} ms")
    print(s.to_frame().to_string(index=False))
    print(f"  limit {s.max_speed:.3f} m/s robot ({s.closing_speed:.3f} m/s closing), "
          f"limiting: {s.limiting_criterion}")  # fmt: skip
    ks, cs = np.geomspace(5e3, 1e5, 40), np.linspace(10.0, 200.0, 40)
    m, dt = timed(cd.speed_limit_map, ROBOT, K_c=ks, C_c=cs,
                  criteria=CRITERIA[:2], human_speed=1.0)  # fmt: skip
    g, dg = timed(cd.speed_limit_map, ROBOT, K_c=ks, C_c=cs, criteria=CRITERIA[:2],
                  human_speed=1.0, refine=False)  # fmt: skip
    lower = 1 - m.closing_speed / g.closing_speed
    print(
        f"speed_limit_map 40 x 40 foams: {dt:.2f} s refined, {dg:.2f} s on the head grid "
        f"(ratio {dt / dg:.1f}); fastest foam {m.max_speed.max():.3f} m/s; off the grid "
        f"{int((lower > 1e-9).sum())} foams lower, by up to {100 * lower.max():.2f} %"
    )


def cpu_timed(fn, *args, **kwargs):
    t0 = time.process_time()
    out = fn(*args, **kwargs)
    return out, time.process_time() - t0


def naive_per_sample(samples: int, speeds) -> float:
    """CPU seconds a sample of the baseline: ``dl.impact.simulate`` called once per sampled
    head and closing speed (the single-impact API in a Python loop), then the 10 g test."""
    rng = np.random.default_rng(7)
    hr = dl.impact.THESIS_HEAD_RANGE
    t0 = time.process_time()
    for _ in range(samples):
        head = dl.impact.HeadNeck(mass=rng.uniform(*hr.mass), stiffness=rng.uniform(*hr.stiffness),
                                  damping=rng.uniform(*hr.damping))  # fmt: skip
        v = float(speeds.rvs(random_state=rng))
        r = dl.impact.simulate(ROBOT, FOAM, head, impact_velocity=v)
        _ = r.peak_head_acceleration_g > 10.0
    return (time.process_time() - t0) / samples


def million(samples: int, speeds, naive: int = 300) -> dict[str, object]:
    out = {}
    base = naive_per_sample(naive, speeds)
    print(f"baseline: simulate() per sample in a loop ({naive} samples): {base * 1e3:.2f} ms CPU")
    for method in ("crude", "importance"):
        r, dt = cpu_timed(cd.injury_probability, ROBOT, FOAM, speeds, samples=samples,
                          method=method, seed=1)  # fmt: skip
        print(
            f"injury_probability {method:>10} {samples:.0e} samples: {dt:6.2f} CPU s, "
            f"{base * samples / dt:,.0f}x the baseline per sample  "
            f"P = {r.probability:.5g}  95 % [{r.interval[0]:.5g}, {r.interval[1]:.5g}]"
        )
        out[method] = r
    n = max(samples // 500, 200)
    _, d_hic = cpu_timed(cd.injury_probability, ROBOT, FOAM, speeds, samples=n,
                         criterion=CRITERIA[2], seed=1)  # fmt: skip
    _, d_acc = cpu_timed(cd.injury_probability, ROBOT, FOAM, speeds, samples=n, seed=1)
    print(
        f"HIC criterion, {n} samples: {d_hic / n * 1e3:.2f} ms CPU a sample, "
        f"{d_hic / d_acc:,.0f}x the 10 g criterion's cost and {base * n / d_hic:.2f}x the baseline"
    )
    return out


def crude_pooled(speeds, samples: int, seed: int) -> tuple[int, int]:
    """(failures, samples) of crude Monte Carlo at ``samples``, pooled from runs of at most
    the declared cap (RISK_SAMPLES) with seeds ``seed, seed + 1, ...``."""
    from designlab.codesign.parameters import RISK_SAMPLES

    failed, done, k = 0, 0, 0
    while done < samples:
        n = max(min(int(RISK_SAMPLES.le), samples - done), int(RISK_SAMPLES.ge))
        r = cd.injury_probability(ROBOT, FOAM, speeds, samples=n, method="crude", seed=seed + k)
        failed, done, k = failed + r.failed_samples, done + n, k + 1
    return failed, done


def against_reference(reference: int, speeds) -> bool:
    imp = cd.injury_probability(ROBOT, FOAM, speeds, samples=100_000, seed=2)
    (failed, n), dt = timed(crude_pooled, speeds, reference, 3)
    p = failed / n
    ref = SimpleNamespace(probability=p, standard_error=math.sqrt(p * (1 - p) / n))
    z = (imp.probability - ref.probability) / math.hypot(imp.standard_error, ref.standard_error)
    print(
        f"crude reference {reference:.0e} samples ({dt:.1f} s): P = {ref.probability:.6g} "
        f"+- {ref.standard_error:.2g}; importance 1e5: {imp.probability:.6g} "
        f"+- {imp.standard_error:.2g}; difference {z:+.2f} standard errors"
    )
    return abs(z) < 4


def small(reference: int) -> None:
    slow = stats.truncnorm(-3.0, np.inf, loc=0.9, scale=0.15)
    imp = cd.injury_probability(ROBOT, FOAM, slow, samples=10_000, seed=4)
    failed, n = crude_pooled(slow, reference, 5)
    high = stats.binomtest(failed, n).proportion_ci(0.95, "wilson").high
    print(
        f"small probability: importance 1e4 P = {imp.probability:.3g} "
        f"[{imp.interval[0]:.3g}, {imp.interval[1]:.3g}]; crude {reference:.0e}: "
        f"{failed} failures, P < {high:.3g}"
    )


def subset_check(runs: int = 20) -> None:
    slow = stats.rayleigh(scale=0.4)
    imp = cd.injury_probability(ROBOT, FOAM, slow, samples=100_000, seed=6)
    outs = [cd.injury_probability(ROBOT, FOAM, slow, samples=2000, method="subset", seed=s)
            for s in range(runs)]  # fmt: skip
    ps = np.array([o.probability for o in outs])
    stated = np.mean([o.standard_error / o.probability for o in outs if o.probability > 0])
    evals = np.mean([o.samples for o in outs])
    print(
        f"subset simulation, {runs} seeds x 2000 per level ({evals:.0f} evaluations a run): "
        f"mean P = {ps.mean():.4g}, importance 1e5: {imp.probability:.4g} +- "
        f"{imp.standard_error:.2g}; scatter c.o.v. {ps.std(ddof=1) / ps.mean():.2f}, "
        f"stated c.o.v. {stated:.2f}"
    )


def front_cost(generations: int) -> None:
    rng = np.random.default_rng(1)
    k, c = rng.uniform(5e3, 8e4, 40), rng.uniform(10.0, 200.0, 40)
    t = rng.uniform(0.01, 0.06, 40)
    lam = t * 0.02 / 0.0254
    cd.speed_limit(ROBOT, FOAM)  # load the compiled kernel
    t0 = time.process_time()
    lim = cd.foam_limits(ROBOT, k, c, lam, t)
    batch = time.process_time() - t0
    t0 = time.process_time()
    one = [cd.speed_limit(ROBOT, dl.impact.Foam(a, b, linear_depth=d, thickness=e)).max_speed
           for a, b, d, e in zip(k, c, lam, t, strict=True)]  # fmt: skip
    single = time.process_time() - t0
    same = np.allclose(lim.max_speed, one, rtol=1e-12, atol=0.0)
    print(f"foam_limits, 40 foams: {batch:.2f} CPU s in one search, {single:.2f} CPU s one by "
          f"one (ratio {single / batch:.2f}); same limits: {same}")  # fmt: skip
    nav = dl.navigation
    t0 = time.process_time()
    front = cd.pareto([nav.configuration(2), nav.configuration(4)], robot=cd.THESIS_ROBOT,
                      objectives=("arrival_time", "foam_thickness", "closing_speed"),
                      population=40, generations=generations, risk_bound=0.01,
                      risk_samples=20_000, seed=0)  # fmt: skip
    cpu = time.process_time() - t0
    print(
        f"pareto, 40 x {generations} designs: {cpu:.1f} CPU s, "
        f"{len(front.X) / cpu:.2f} designs per CPU second; 2,000 designs would take "
        f"{2000 / (len(front.X) / cpu) / 60:.1f} CPU min"
    )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--samples", type=int, default=1_000_000)
    ap.add_argument("--reference", type=int, default=10_000_000)
    ap.add_argument("--subset-only", action="store_true")
    ap.add_argument("--front-only", action="store_true")
    ap.add_argument("--generations", type=int, default=2)
    args = ap.parse_args(argv)
    if args.front_only:
        front_cost(args.generations)
        return 0
    if args.subset_only:
        subset_check()
        return 0
    speeds = stats.rayleigh(scale=1.0)
    speed_limits()
    million(args.samples, speeds)
    ok = against_reference(args.reference, speeds)
    small(args.reference)
    subset_check()
    front_cost(args.generations)
    print("importance sampling agrees with crude Monte Carlo:", "yes" if ok else "NO")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
