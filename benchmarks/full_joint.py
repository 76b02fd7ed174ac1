"""Benchmark: full-joint impact metrics, compiled kernel vs eigen path vs numpy vs solve_ivp.

Run with ``PYTHONPATH=. python benchmarks/full_joint.py`` from the repository root. In one
process it times, for the illustrative joint of docs/impact_joint.md swept over 41
ratios K_mech/K_cont in [0.03, 3000] (Foam 1, minimum head-neck set, v_c = 1.25 m/s):

* the compiled path: ``matrix_metrics`` on the ``(41, 10)`` full-joint rows, poles,
  residues, lobe end and certified maxima in one compiled loop
  (:mod:`designlab.impact.kernel_full`);
* the eigen path it replaces: the exact modal responses from numpy's
  eigen-decomposition of the state matrix (:func:`~designlab.impact.metrics.ramp_responses`)
  and the compiled lobe and maxima (:func:`~designlab.impact.metrics.metrics_from_responses`);
* the numpy path: the same with the compiled kernels switched off in-process
  (``designlab.impact.kernel.AVAILABLE = False``, as without numba);
* a plain baseline: one ``scipy.integrate.solve_ivp`` per ratio (LSODA, which
  handles the stiff motor node; rtol 1e-10) with a terminal event at the end of
  the first lobe and a dense-output search for the maxima.

The designlab paths run on the 41 rows repeated ``--repeat`` times (per-design times
are stable on a busy machine); times are CPU seconds of this process
(``time.process_time``), the best of 3 runs after one warm-up of each path (the
``solve_ivp`` loop: one run). It checks that a_h,max and
eps_max agree with the baseline to 1e-4 and prints the ratios per design, and the
largest relative difference between the compiled and the eigen path.

``--random N`` (default 10,000) repeats the comparison of the compiled and the eigen path on
N seeded random designs over wide ranges (M_r 2-20 kg, K_cont 5e3-5e4, K_mech/K_cont
0.03-3000 log-uniform, C_mech 0-500, C_cont 1-800, K_c 5e3-8e4, C_c 0-300, M_h 3-6,
C_h 0-150, K_h 1e3-1e4; v_c 0.2-2 m/s): the CPU time of each, the designs whose status
differs, the share of designs within 1e-12 and the largest relative difference of
a_h,max, eps_max, the peak force and t_imp, and the designs the kernel did not certify.
"""

from __future__ import annotations

import argparse
import logging
import time

import numpy as np
from scipy.integrate import solve_ivp

import designlab as dl
from designlab.impact import kernel
from designlab.impact.full_joint_model import full_joint_params, grid_rate
from designlab.impact.metrics import (
    matrix_metrics,
    metrics_from_responses,
    ramp_responses,
    response_model,
)
from designlab.impact.series_joint import FullJointContact


def baseline(p: np.ndarray, v: float) -> tuple[float, float]:
    """a_h,max (m/s^2) and eps_max (m) of the full-joint impact by solve_ivp."""
    mr, cm, km, kc, cc, mh, ch, kh, cq, kq = p

    def rhs(t, x):
        dr, drd, de, dh, dhd = x
        fc = kc * (dr - dh + v * t) + cc * (drd - dhd + v)
        ded = (km * (dr - de) + cm * drd - kq * de) / (cm + cq)
        ft = kq * de + cq * ded
        return [drd, (-fc - ft) / mr, ded, dhd, (fc - ch * dhd - kh * dh) / mh]

    def a_h(t, x):
        return rhs(t, x)[4]

    def event(t, x):
        return a_h(t, x) if t > 1e-7 else 1.0

    event.terminal = True
    event.direction = -1
    sol = solve_ivp(rhs, (0, 0.5), np.zeros(5), method="LSODA", events=event,
                    dense_output=True, rtol=1e-10, atol=1e-13)  # fmt: skip
    t_end = sol.t_events[0][0]
    t = np.linspace(0, t_end, 4001)
    x = sol.sol(t)
    a = np.array([a_h(tt, xx) for tt, xx in zip(t, x.T, strict=True)])
    eps = x[0] - x[3] + v * t
    return float(a.max()), float(eps.max())


def _cpu(func, *args, **kwargs):  # type: ignore[no-untyped-def]
    """``func(*args, **kwargs)`` and its CPU seconds, best of 3 after one warm-up call."""
    func(*args, **kwargs)
    best = np.inf
    for _ in range(3):
        t0 = time.process_time()
        out = func(*args, **kwargs)
        best = min(best, time.process_time() - t0)
    return out, best


def _eigen_path(rows: np.ndarray, v: float):  # type: ignore[no-untyped-def]
    names = ("force", "head_acceleration", "compression")
    resp = ramp_responses(response_model(rows, False), rows, names)
    speed = np.full(rows.shape[0], v)
    return metrics_from_responses(resp, rows, speed, rate=grid_rate(resp["force"].poles))


def _numpy_path(rows: np.ndarray, v: float):  # type: ignore[no-untyped-def]
    saved, kernel.AVAILABLE = kernel.AVAILABLE, False
    quiet = logging.getLogger("designlab.sx")
    level = quiet.level
    quiet.setLevel(logging.ERROR)  # the "numpy path" notice: switched off on purpose here
    try:
        return matrix_metrics(rows, v)
    finally:
        kernel.AVAILABLE = saved
        quiet.setLevel(level)


def random_rows(n: int, seed: int) -> np.ndarray:
    """``(n, 10)`` full-joint rows over the wide ranges of ``--random``."""
    rng = np.random.default_rng(seed)
    k_q = rng.uniform(5e3, 5e4, n)
    k_m = k_q * np.exp(rng.uniform(np.log(0.03), np.log(3000.0), n))
    return np.column_stack([
        rng.uniform(2, 20, n), rng.uniform(0, 500, n), k_m, rng.uniform(5e3, 8e4, n),
        rng.uniform(0, 300, n), rng.uniform(3, 6, n), rng.uniform(0, 150, n),
        rng.uniform(1e3, 1e4, n), rng.uniform(1, 800, n), k_q,
    ])  # fmt: skip


def random_comparison(n: int) -> None:
    """The compiled and the eigen path on ``n`` random designs (see the module)."""
    rows = random_rows(n, 22)
    v = np.random.default_rng(23).uniform(0.2, 2.0, n)
    m, t_fast = _cpu(matrix_metrics, rows, v)
    e, t_eig = _cpu(_eigen_path, rows, v)
    fields = ("peak_head_acceleration", "max_compression", "peak_force", "impact_duration")
    a = np.stack([getattr(m, k) for k in fields], axis=1)
    b = np.stack([getattr(e, k) for k in fields], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.nanmax(np.where(a == b, 0.0, np.abs(a - b) / np.abs(b)), axis=1)
    fallback = sum(int(w.split()[0]) for w in m.warnings if "nearly repeated" in w)
    print(f"{n:,} random designs (CPU s per design)")
    print(f"  compiled kernel          : {t_fast / n * 1e6:9.2f} us  ({n / t_fast:,.0f} designs/s)")
    ratio = t_eig / t_fast
    print(f"  eigen path (numpy eig)   : {t_eig / n * 1e6:9.2f} us  ({ratio:6.1f} x compiled)")
    print(f"  status differs           : {int(np.sum(m.design_status != e.design_status))}")
    print(
        f"  within 1e-12 relative    : {100 * np.mean(rel <= 1e-12):.2f} %; largest {rel.max():.1e}"
    )
    print(f"  not certified (eigen)    : {fallback}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=41)
    parser.add_argument("--repeat", type=int, default=100, help="copies of the rows timed")
    parser.add_argument("--random", type=int, default=10_000, help="random designs compared")
    args = parser.parse_args()
    arm = FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    ratios = np.geomspace(0.03, 3000.0, args.points)
    rows = np.array([
        full_joint_params(
            FullJointContact(arm.mass, r * arm.control_stiffness, arm.transmission_damping,
                             arm.control_stiffness, arm.control_damping),
            dl.impact.FOAM_1, dl.impact.HEAD_MIN,
        )
        for r in ratios
    ])  # fmt: skip
    many = np.tile(rows, (args.repeat, 1))
    m, t_fast = _cpu(matrix_metrics, many, 1.25)
    e, t_eig = _cpu(_eigen_path, many, 1.25)
    _, t_np = _cpu(_numpy_path, many, 1.25)
    t0 = time.process_time()
    base = np.array([baseline(p, 1.25) for p in rows])
    t_base = (time.process_time() - t0) / rows.shape[0]
    t_fast, t_eig, t_np = (t / many.shape[0] for t in (t_fast, t_eig, t_np))
    a = m.peak_head_acceleration[: rows.shape[0]]
    err_a = np.max(np.abs(a / base[:, 0] - 1))
    err_e = np.max(np.abs(m.max_compression[: rows.shape[0]] / base[:, 1] - 1))
    fields = ("peak_head_acceleration", "max_compression", "peak_force", "impact_duration")
    diff = max(np.max(np.abs(getattr(m, k) / getattr(e, k) - 1)) for k in fields)
    print(f"full-joint metrics, {args.points} stiffness ratios x {args.repeat} (CPU s per design)")
    print(f"  compiled kernel          : {t_fast * 1e6:9.2f} us  ({1 / t_fast:,.0f} designs/s)")
    print(f"  eigen path (numpy eig)   : {t_eig * 1e6:9.2f} us  ({t_eig / t_fast:6.1f} x compiled)")
    print(f"  numpy path (no JIT)      : {t_np * 1e6:9.2f} us  ({t_np / t_fast:6.1f} x compiled)")
    ratio = t_base / t_fast
    print(f"  solve_ivp (LSODA)        : {t_base * 1e6:9.0f} us  ({ratio:6.0f} x compiled)")
    print(f"  max relative difference  : vs solve_ivp a_h,max {err_a:.1e}, eps_max {err_e:.1e};")
    print(f"                             compiled vs eigen path {diff:.1e}")
    if max(err_a, err_e) > 1e-4:
        raise SystemExit("designlab and the baseline disagree")
    if args.random:
        random_comparison(args.random)


if __name__ == "__main__":
    main()
