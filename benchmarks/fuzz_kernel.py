"""Fuzz: the compiled impact kernel against an independent evaluator, settled by mpmath.

Run from the repository root::

    python benchmarks/fuzz_kernel.py --designs 1e6            # 1e6 designs per family
    python benchmarks/fuzz_kernel.py --designs 1e7 --seed 7   # a larger run, another seed
    python benchmarks/fuzz_kernel.py --families full_wide,full_stiff   # the full joint

Designs are drawn (seeded) from six families of valid designs of the reduced
model (docs/impact.md, "Self-check"):

* ``thesis``: the thesis's ranges of benchmarks/impact.py (M_r 5-60 kg, C_r
  100-600 N s/m, K_r 10-50 kN/m, K_c 5-100 kN/m, xi_c 0.05-0.2, the head-neck
  ranges 4.4-5.3 kg, 46-130 N s/m, 3-5 kN/m);
* ``wide``: the wide ranges of issue 22 (M_r 2-20, C_r 0-800, K_r 5e3-5e4,
  K_c 5e3-8e4, C_c 0-300, M_h 3-6, C_h 0-150, K_h 1e3-1e4);
* ``critical``: the arm's and the head's own modes critically damped within
  1e-3 (C_r = 2 sqrt(K_r M_r) (1 + d), likewise C_h; nearly double real poles);
* ``repeated``: the arm's own mode equal to the head's (K_r / M_r = K_h / M_h,
  C_r / M_r = C_h / M_h) and a soft foam (K_c, C_c 1e-3 of the wide ranges):
  nearly repeated complex pairs;
* ``overdamped``: dampers 10-100 times the wide ranges;
* ``heavy``: M_r log-uniform up to 1e3 kg and K_r up to 1e7 N/m.

and two of the full series joint (10 parameters, :data:`FULL_FAMILIES`): the
compiled full joint's certificate sends a design it does not certify to the
eigen path, and the harness counts those fallbacks.

Each design goes through the kernel as :func:`designlab.impact.metrics_of_matrix`
uses it (its a-posteriori self-check, suspects settled by the numpy path) and
through an independent evaluator: the numpy modal path (the eigenvalues of the
companion matrix, the vectorised lobe search and branch and bound of
:mod:`designlab.impact.modal`). Every design where a_h,max, eps_max, F_max or
t_imp differ by more than 1e-10 (relative), or the statuses differ, is settled
by a 40-digit mpmath evaluation written for the tests
(``tests/impact/exact_reference.py``, :class:`MpImpact`): each evaluator is
wrong where it is off the mpmath value by more than its certified tolerance
(1e-8 relative for the maxima, 1e-9 for t_imp). Printed: designs, CPU seconds
(this process), the kernel's self-check fallbacks, the disagreements and who was
right. A design the kernel reports ``uncertified`` (metrics NaN, said in a warning) is
counted apart: it is not a number presented as exact. The exit status is 1 if the
kernel was wrong on any design.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this checkout's designlab
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "impact"))

from designlab.impact import kernel, kernel_full
from designlab.impact import metrics as _m
from designlab.impact.full_joint_model import grid_rate

NAMES = ("force", "head_acceleration", "compression")
WIDE = [(2, 20), (0, 800), (5e3, 5e4), (5e3, 8e4), (0, 300), (3, 6), (0, 150), (1e3, 1e4)]
#: relative tolerances of the certified values: maxima (the branch and bound's 1e-8), t_imp
TOLERANCE = (1e-8, 1e-8, 1e-8, 1e-9)
#: relative difference above which the two evaluators disagree
DISAGREE = 1e-10
#: least grid cells of the mpmath referee over the window (none wider than a twelfth of
#: the fastest resolved period, whatever this is; :class:`exact_reference.MpImpact`)
SAMPLES = 256


def _uniform(rng: np.random.Generator, n: int, ranges: list) -> np.ndarray:
    return np.stack([rng.uniform(a, b, n) for a, b in ranges], axis=1)


def draw(family: str, rng: np.random.Generator, n: int) -> np.ndarray:
    """``(n, 8)`` designs of one family (module docstring)."""
    if family == "thesis":
        p = _uniform(rng, n, [(5, 60), (100, 600), (1e4, 5e4), (5e3, 1e5), (0.05, 0.2),
                              (4.4, 5.3), (46, 130.2), (3e3, 5e3)])  # fmt: skip
        p[:, 4] = 2 * p[:, 4] * np.sqrt(4.4 * p[:, 3])
        return p
    p = _uniform(rng, n, WIDE)
    if family == "critical":
        p[:, 1] = 2 * np.sqrt(p[:, 2] * p[:, 0]) * (1 + rng.uniform(-1e-3, 1e-3, n))
        p[:, 6] = 2 * np.sqrt(p[:, 7] * p[:, 5]) * (1 + rng.uniform(-1e-3, 1e-3, n))
    elif family == "repeated":
        p[:, 2] = p[:, 7] / p[:, 5] * p[:, 0]
        p[:, 1] = p[:, 6] / p[:, 5] * p[:, 0]
        p[:, 3] *= 1e-3
        p[:, 4] *= 1e-3
    elif family == "overdamped":
        f = np.exp(rng.uniform(np.log(10.0), np.log(100.0), (n, 3)))
        p[:, [1, 4, 6]] *= f
    elif family == "heavy":
        p[:, 0] = np.exp(rng.uniform(np.log(2.0), np.log(1e3), n))
        p[:, 2] = np.exp(rng.uniform(np.log(5e3), np.log(1e7), n))
    return p


FAMILIES = ("thesis", "wide", "critical", "repeated", "overdamped", "heavy")
#: full-joint families (10 parameters, docs/impact_joint.md): wide ranges with K_mech /
#: K_cont log-uniform in [0.03, 3000], and a stiff motor node (C_mech 0, C_cont 1e-4-1e-2)
FULL_FAMILIES = ("full_wide", "full_stiff")


def draw_full(family: str, rng: np.random.Generator, n: int) -> np.ndarray:
    """``(n, 10)`` full-joint designs (M_r, C_mech, K_mech, K_c, C_c, M_h, C_h, K_h, C_cont,
    K_cont)."""
    k_q = rng.uniform(5e3, 5e4, n)
    k_m = k_q * np.exp(rng.uniform(np.log(0.03), np.log(3000.0), n))
    p = np.column_stack([
        rng.uniform(2, 20, n), rng.uniform(0, 500, n), k_m, rng.uniform(5e3, 8e4, n),
        rng.uniform(0, 300, n), rng.uniform(3, 6, n), rng.uniform(0, 150, n),
        rng.uniform(1e3, 1e4, n), rng.uniform(1, 800, n), k_q,
    ])  # fmt: skip
    if family == "full_stiff":
        p[:, 1] = 0.0
        p[:, 8] = np.exp(rng.uniform(np.log(1e-4), np.log(1e-2), n))
    return p


def by_kernel(p: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """The kernel's unit-v_c rows ``(a_max, eps_max, f_max, t_imp)``, status codes and the
    number of self-check fallbacks (as :func:`designlab.impact.metrics_of_matrix`)."""
    rows, codes = kernel.reduced_metrics(p, (True, True, True), printed=False, stop_time=0.05,
                                         max_lobe_steps=4096, diagnostics=False)  # fmt: skip
    sus = np.flatnonzero(codes >= kernel.SUSPECT_POLES)
    if sus.size:
        resp = _m.ramp_responses(_m.response_model(p[sus], False), p[sus], NAMES)
        h = 0.4 / np.abs(resp[NAMES[0]].poles).max(axis=1)
        rows[sus], codes[sus], _ = _m._settle(resp, h, codes[sus], False, 0.05, 4096, False)
    return rows[:, :4], codes, int(sus.size)


def by_kernel_full(p: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """The full joint as :func:`designlab.impact.metrics_of_matrix` evaluates it: rows,
    status codes, and how many designs the compiled certificate (distinct poles,
    condition <= 1e4, backward error <= 1e-13) sent to the eigen path."""
    _, codes = kernel_full.full_metrics(p, (True, True, True), constrained=False,
                                        stop_time=0.05, max_lobe_steps=4096,
                                        diagnostics=False)  # fmt: skip
    fb = int(np.sum(codes == kernel_full.FALLBACK))
    m = _m._full_kernel(p, np.ones(p.shape[0]), NAMES, False, 0.05, 4096, False)
    rows = np.stack([m.peak_head_acceleration, m.max_compression, m.peak_force,
                     m.impact_duration], axis=1)  # fmt: skip
    status = np.array([list(_m._KERNEL_STATUS).index(s) for s in m.design_status], np.int8)
    return rows, status, fb


def by_numpy(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The independent evaluator: the numpy modal path's rows and status codes (the
    eigen-decomposition of the state space for the full joint)."""
    resp = _m.ramp_responses(_m.response_model(p, False), p, NAMES)
    poles = resp[NAMES[0]].poles
    h = 0.4 / (grid_rate(poles) if p.shape[1] == 10 else np.abs(poles).max(axis=1))
    rows, codes = _m._numpy_rows(resp, h, False, 0.05, 4096, False)
    return rows[:, :4], codes


def disagreements(a: np.ndarray, ca: np.ndarray, b: np.ndarray, cb: np.ndarray) -> np.ndarray:
    """Indices where the rows differ by more than :data:`DISAGREE` or the statuses differ."""
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(a == b, 0.0, np.abs(a - b) / np.abs(b))
    rel = np.where(np.isnan(a) & np.isnan(b), 0.0, rel)
    rel = np.where(np.isnan(rel), np.inf, rel)
    return np.flatnonzero((rel.max(axis=1) > DISAGREE) | (ca != cb))


def referee(q: np.ndarray, rows: list[np.ndarray]) -> tuple[np.ndarray, list[bool]]:
    """The 40-digit values ``(a_max, eps_max, f_max, t_imp)`` of design ``q`` and, for each of
    ``rows``, whether it is right (within :data:`TOLERANCE`; NaN right only where mpmath
    finds no lobe end before the latest t_imp claimed)."""
    from exact_reference import MpFullJoint, MpImpact

    mp = MpFullJoint(q, dps=40) if q.size == 10 else MpImpact(q, dps=40)
    ends = [float(r[3]) for r in rows if np.isfinite(r[3])]
    t_hi = 1.05 * max(ends) if ends else 0.05
    t = mp.first_zero(t_hi, samples=SAMPLES)
    truth = np.array([np.nan, np.nan, np.nan, t])
    if np.isfinite(t):
        truth[:3] = [mp.maximum(o, t, samples=SAMPLES) for o in (1, 2, 0)]
    verdict = []
    for r in rows:
        if not np.isfinite(t):
            verdict.append(bool(np.all(np.isnan(r))))
            continue
        err = np.abs(r - truth) / np.abs(truth)
        verdict.append(bool(np.all(err <= np.array(TOLERANCE))))
    return truth, verdict


def run(family: str, n: int, seed: int, chunk: int, verbose: bool = True) -> dict:
    """Fuzz ``n`` designs of ``family``; counts and CPU seconds."""
    out = {"designs": 0, "fallbacks": 0, "disagreements": 0, "kernel_wrong": 0, "uncertified": 0,
           "numpy_wrong": 0, "cpu_kernel": 0.0, "cpu_numpy": 0.0, "cpu_mpmath": 0.0}  # fmt: skip
    for start in range(0, n, chunk):
        m = min(chunk, n - start)
        full = family in FULL_FAMILIES
        rng = np.random.default_rng([seed, (*FAMILIES, *FULL_FAMILIES).index(family), start])
        p = draw_full(family, rng, m) if full else draw(family, rng, m)
        t0 = time.process_time()
        a, ca, fb = by_kernel_full(p) if full else by_kernel(p)
        t1 = time.process_time()
        b, cb = by_numpy(p)
        t2 = time.process_time()
        out["cpu_kernel"] += t1 - t0
        out["cpu_numpy"] += t2 - t1
        out["designs"] += m
        out["fallbacks"] += fb
        for i in disagreements(a, ca, b, cb):
            out["disagreements"] += 1
            truth, (k_ok, n_ok) = referee(p[i], [a[i], b[i]])
            if ca[i] >= kernel.SUSPECT_POLES:  # said so (metrics NaN): not an error
                out["uncertified"] += 1
                k_ok = True
            out["kernel_wrong"] += not k_ok
            out["numpy_wrong"] += not n_ok
            if verbose:
                kv, nv = ("right" if ok else "WRONG" for ok in (k_ok, n_ok))
                print(
                    f"  {family} design {p[i].tolist()}: kernel {a[i].tolist()} ({kv}), "
                    f"numpy {b[i].tolist()} ({nv}), mpmath {truth.tolist()}",
                    flush=True,
                )
        out["cpu_mpmath"] += time.process_time() - t2
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=float, default=1e5, help="designs per family")
    ap.add_argument("--seed", type=int, default=34)
    ap.add_argument("--chunk", type=int, default=65_536)
    ap.add_argument("--families", default=",".join((*FAMILIES, *FULL_FAMILIES)))
    args = ap.parse_args(argv)
    wrong = 0
    for family in args.families.split(","):
        r = run(family, int(args.designs), args.seed, args.chunk)
        wrong += r["kernel_wrong"]
        print(f"{family}: {r['designs']:,} designs, kernel {r['cpu_kernel']:.1f} CPU s, numpy "
              f"{r['cpu_numpy']:.1f} CPU s, mpmath {r['cpu_mpmath']:.1f} CPU s; self-check "
              f"fallbacks {r['fallbacks']}; disagreements > {DISAGREE:g}: "
              f"{r['disagreements']} (kernel wrong {r['kernel_wrong']}, numpy wrong "
              f"{r['numpy_wrong']}); uncertified {r['uncertified']}", flush=True)  # fmt: skip
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main())
