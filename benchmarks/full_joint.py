"""Benchmark: full-joint impact metrics over a stiffness-ratio sweep vs a scipy baseline.

Run with ``PYTHONPATH=. python benchmarks/full_joint.py`` from the repository root. In one
process it times, for the
illustrative joint of docs/impact_joint.md swept over 41 ratios K_mech/K_cont in
[0.03, 3000] (Foam 1, minimum head-neck set, v_c = 1.25 m/s):

* designlab: ``matrix_metrics`` (the batch metrics of a matrix) on the ``(41, 10)``
  full-joint rows (exact modal responses from the state space, Newton-polished maxima), and
* a plain baseline: one ``scipy.integrate.solve_ivp`` per ratio (LSODA, which
  handles the stiff motor node; rtol 1e-10) with a terminal event at the end of
  the first lobe and a dense-output search for the maxima,

checks that a_h,max and eps_max agree to 1e-4 and prints the speed-up.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.integrate import solve_ivp

import designlab as dl
from designlab.impact.full_joint_model import full_joint_params
from designlab.impact.metrics import matrix_metrics
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=41)
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
    matrix_metrics(rows[:2], 1.25)  # build the CasADi functions once
    t0 = time.perf_counter()
    m = matrix_metrics(rows, 1.25)
    t_dl = time.perf_counter() - t0
    t0 = time.perf_counter()
    base = np.array([baseline(p, 1.25) for p in rows])
    t_base = time.perf_counter() - t0
    err_a = np.max(np.abs(m.peak_head_acceleration / base[:, 0] - 1))
    err_e = np.max(np.abs(m.max_compression / base[:, 1] - 1))
    print(f"full-joint metrics, {args.points} stiffness ratios")
    print(f"  designlab matrix_metrics : {t_dl * 1e3:8.1f} ms")
    print(f"  solve_ivp (LSODA) loop   : {t_base * 1e3:8.1f} ms")
    print(f"  speed-up                 : {t_base / t_dl:8.1f} x")
    print(f"  max relative difference  : a_h,max {err_a:.1e}, eps_max {err_e:.1e}")
    if max(err_a, err_e) > 1e-4:
        raise SystemExit("designlab and the baseline disagree")


if __name__ == "__main__":
    main()
