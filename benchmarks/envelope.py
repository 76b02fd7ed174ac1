"""Benchmark: the 41-point, two-boundary foam envelope vs a scipy baseline.

Run with ``python benchmarks/envelope.py``. In one process it times

* designlab: ``dl.impact.foam_envelope(MANIPULATOR_1, 1.25, linspace(0, 200, 41))``
  (a_h,max <= 10 g with the minimum head-neck set; eps_max <= 20 mm with the
  maximum set), and
* a plain baseline: for every damping value, ``scipy.optimize.brentq`` on the
  stiffness, each evaluation one ``scipy.integrate.solve_ivp`` (RK45,
  rtol 1e-9) with a terminal event at the lobe end and dense post-processing,

checks that the boundaries agree to 0.1 %, and prints the speed-up, also of the
envelope on the numpy path (``designlab.impact.kernel.AVAILABLE`` off, the code
before the compiled kernel of issue 22). Times are CPU seconds of this process
(``time.process_time``; on a shared machine wall clocks are not comparable).
Targets (issue 22): at least 100x faster than the baseline.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np
from _machine import machine  # benchmarks/_machine.py
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

import designlab as dl
from designlab.impact import kernel

G = 9.80665  # standard gravity, as designlab (docs/impact.md, "Standard gravity")


def baseline_metrics(p: list[float], v: float) -> tuple[float, float]:
    """a_h,max (m/s^2) and eps_max (m) over the first lobe, by solve_ivp."""
    mr, cr, kr, kc, cc, mh, ch, kh = p

    def rhs(t, x):
        dr, drd, dh, dhd = x
        fc = kc * (dr - dh + v * t) + cc * (drd - dhd + v)
        return [drd, (-fc - cr * drd - kr * dr) / mr, dhd, (fc - ch * dhd - kh * dh) / mh]

    def a_h(t, x):
        dr, drd, dh, dhd = x
        fc = kc * (dr - dh + v * t) + cc * (drd - dhd + v)
        return (fc - ch * dhd - kh * dh) / mh

    def event(t, x):
        return a_h(t, x) if t > 1e-7 else 1.0

    event.terminal = True
    event.direction = -1
    sol = solve_ivp(
        rhs, (0, 0.5), [0, 0, 0, 0], rtol=1e-9, atol=1e-12, events=event, dense_output=True
    )
    t_imp = sol.t_events[0][0]
    t = np.linspace(0, t_imp, 2001)
    x = sol.sol(t)
    a = a_h(t, x)
    eps = x[0] - x[2] + v * t
    j = int(np.argmax(a))
    if 0 < j < t.size - 1:
        r = minimize_scalar(
            lambda s: -a_h(s, sol.sol(s)), bounds=(t[j - 1], t[j + 1]), method="bounded",
            options={"xatol": 1e-10},
        )  # fmt: skip
        a_max = max(a[j], -r.fun)
    else:
        a_max = a[j]
    k = int(np.argmax(eps))
    if 0 < k < t.size - 1:
        r = minimize_scalar(
            lambda s: -(sol.sol(s)[0] - sol.sol(s)[2] + v * s), bounds=(t[k - 1], t[k + 1]),
            method="bounded", options={"xatol": 1e-10},
        )  # fmt: skip
        eps_max = max(eps[k], -r.fun)
    else:
        eps_max = eps[k]
    return a_max, eps_max


def baseline_envelope(damping: np.ndarray, v: float) -> tuple[np.ndarray, np.ndarray]:
    robot = [9.6, 250.0, 20e3]
    hmin = [4.4, 46.0, 3e3]
    hmax = [5.3, 130.2, 5e3]
    kmax, kmin = [], []
    for c in damping:

        def upper(logk: float, c: float = c) -> float:
            return baseline_metrics([*robot, np.exp(logk), c, *hmin], v)[0] - 10 * G

        def lower(logk: float, c: float = c) -> float:
            return baseline_metrics([*robot, np.exp(logk), c, *hmax], v)[1] - 0.02

        kmax.append(np.exp(brentq(upper, np.log(1e4), np.log(2e5), xtol=1e-7)))
        kmin.append(np.exp(brentq(lower, np.log(2e3), np.log(1e5), xtol=1e-7)))
    return np.array(kmin), np.array(kmax)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=41)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    damping = np.linspace(0, 200, args.points)
    crit = [dl.impact.HeadAcceleration(max_g=10)]

    def envelope() -> tuple[float, dl.impact.FoamEnvelope]:
        dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, 1.25, damping, crit, 0.02)  # warm-up
        times = []
        for _ in range(args.repeat):
            t0 = time.process_time()
            env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, 1.25, damping, crit, 0.02)
            times.append(time.process_time() - t0)
        return min(times), env

    t_dl, env = envelope()
    kernel.AVAILABLE = False
    try:
        t_np, _ = envelope()
    finally:
        kernel.AVAILABLE = True

    t0 = time.process_time()
    kmin_b, kmax_b = baseline_envelope(damping, 1.25)
    t_base = time.process_time() - t0

    err_max = np.max(np.abs(env.stiffness_max / kmax_b - 1))
    err_min = np.max(np.abs(env.stiffness_min / kmin_b - 1))
    ratio = t_base / t_dl
    print(
        f"foam envelope, Manipulator 1, v_c = 1.25 m/s, {args.points} damping values x 2 boundaries"
    )
    print(f"  CPU time of this process; {machine()}")
    print(f"  designlab foam_envelope   {t_dl * 1e3:9.1f} ms  (best of {args.repeat}, kernel)")
    print(f"  the same, numpy path      {t_np * 1e3:9.1f} ms  (before issue 22)")
    print(f"  solve_ivp + brentq        {t_base * 1e3:9.1f} ms")
    met_ratio = "met" if ratio >= 100 else "NOT met"
    print(f"  speed-up                  {ratio:9.1f} x   (target >= 100 x: {met_ratio})")
    print(f"  numpy path vs baseline    {t_base / t_np:9.1f} x;  kernel vs numpy path "
          f"{t_np / t_dl:.1f} x")  # fmt: skip
    print(f"  max rel. difference K_c,max {err_max:.2e}, K_c,min {err_min:.2e}  (target < 1e-3)")
    ok = err_max < 1e-3 and err_min < 1e-3
    if not ok:
        print("  ACCURACY TARGET NOT MET", file=sys.stderr)
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
