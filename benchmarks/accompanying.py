"""Benchmark of the accompanying robot (Wu et al. 2021): simulation and PID tuning.

Run from the repository root (about half a minute)::

    python benchmarks/accompanying.py
    python benchmarks/accompanying.py --repeats 20 --dfo-evaluations 150

What is measured, in one process:

1. Simulation: the rectangle task trimmed to 28 s (walk + 6 s standing) at
   50 Hz control with 4 raw sensor samples per period, by
   ``dl.following.accompany`` (CasADi period function chained by ``mapaccum``)
   against a plain baseline: the same model stepped in a per-step Python loop
   with ``math`` scalars. Checks that the robot paths agree (< 1e-9 m) and
   prints the speed-up. Target (issue 12): under 50 ms per run.
2. PID tuning on three tasks (forward, left lateral, clockwise circle):
   convex-concave (Hast et al. 2013, cvxpy) vs the derivative-free
   Nelder-Mead tuner of the simulated RMS error: wall time, simulations, Ms,
   and the mean RMS error over the nine tasks. Target: under 1 minute.
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import numpy as np

import designlab as dl

fol = dl.following


def baseline_run(task, pid, platform, sensor):
    """Per-step Python loop of the same model (no noise, median window 1)."""
    ts = sensor.period
    s_n = sensor.oversampling
    h = ts / s_n
    n = math.ceil(task.duration / ts - 1e-9)
    t_raw = (np.arange(n)[:, None] * ts + np.arange(s_n)[None, :] * h).ravel()
    users = task.pose(t_raw).T
    tx, ty = task.target_position
    tg = task.target_heading
    u0 = task.pose(0.0)
    ps = u0[2]
    x = u0[0] + math.sin(ps) * tx + math.cos(ps) * ty
    y = u0[1] - math.cos(ps) * tx + math.sin(ps) * ty
    psi = ps + tg
    vel = [0.0, 0.0, 0.0]
    integ = [0.0, 0.0, 0.0]
    deriv = [0.0, 0.0, 0.0]
    e_prev = None
    gains = [pid.gains(a) for a in ("lateral", "forward", "heading")]
    vmax, amax = platform.max_speed, platform.max_acceleration
    wmax, alp = platform.max_yaw_rate, platform.max_yaw_acceleration
    a_lin = math.exp(-h / platform.time_constant)
    a_yaw = math.exp(-h / platform.yaw_tau)
    out = np.empty((n + 1, 3))
    out[0] = (x, y, psi)
    cmd = [0.0, 0.0, 0.0]

    def wrap(a):
        return math.atan2(math.sin(a), math.cos(a))

    for k in range(n):
        for j in range(s_n):
            xu, yu, pu = users[k * s_n + j]
            if j == 0:
                dx, dy = x - xu, y - yu
                xc = math.sin(pu) * dx - math.cos(pu) * dy
                yc = math.cos(pu) * dx + math.sin(pu) * dy
                gc = wrap(psi - pu)
                d = math.hypot(xc, yc)
                tu = math.atan2(yc, xc)
                tr = wrap(gc - tu)
                g = tu + tr
                exu, eyu = tx - d * math.cos(tu), ty - d * math.sin(tu)
                err = [
                    math.cos(g) * exu + math.sin(g) * eyu,
                    -math.sin(g) * exu + math.cos(g) * eyu,
                    wrap(tg - g),
                ]
                if e_prev is None:
                    e_prev = list(err)
                raw, cand = [], []
                for i in range(3):
                    kp, ki, kd, tf = gains[i]
                    ii = integ[i] + ki * ts * err[i]
                    deriv[i] = (tf * deriv[i] + kd * (err[i] - e_prev[i])) / (tf + ts)
                    raw.append(kp * err[i] + ii + deriv[i])
                    cand.append(ii)
                nrm = math.hypot(raw[0], raw[1])
                sc = vmax / max(nrm, vmax)
                sat = [nrm > vmax, nrm > vmax, abs(raw[2]) > wmax]
                cmd = [sc * raw[0], sc * raw[1], min(max(raw[2], -wmax), wmax)]
                for i in range(3):
                    if not (sat[i] and err[i] * raw[i] > 0):
                        integ[i] = cand[i]
                e_prev = err
            dv = [(cmd[i] - vel[i]) * (1 - (a_lin if i < 2 else a_yaw)) for i in range(3)]
            nd = math.hypot(dv[0], dv[1])
            sc = amax * h / max(nd, amax * h)
            dv[0] *= sc
            dv[1] *= sc
            dv[2] = min(max(dv[2], -alp * h), alp * h)
            new = [vel[i] + dv[i] for i in range(3)]
            avg = [0.5 * (vel[i] + new[i]) for i in range(3)]
            pm = psi + 0.5 * h * avg[2]
            x += h * (avg[0] * math.sin(pm) + avg[1] * math.cos(pm))
            y += h * (-avg[0] * math.cos(pm) + avg[1] * math.sin(pm))
            psi += h * avg[2]
            vel = new
        out[k + 1] = (x, y, psi)
    return out.T


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=10)
    ap.add_argument("--dfo-evaluations", type=int, default=150)
    args = ap.parse_args(argv)
    ok = True

    task = fol.walking_task("rectangle", settle_time=6.0)
    task = fol.WalkingTask(
        "rectangle_28s",
        task.time,
        task.x,
        task.y,
        task.heading,
        task.walk_start,
        min(task.walk_stop, 28.0),
        task.target_position,
        task.target_heading,
    )
    trimmed = task.time <= 28.0 + 1e-9
    task = fol.WalkingTask(
        "rectangle_28s",
        task.time[trimmed],
        task.x[trimmed],
        task.y[trimmed],
        task.heading[trimmed],
        task.walk_start,
        min(task.walk_stop, 28.0),
        task.target_position,
        task.target_heading,
    )
    pid = fol.UserFramePID()
    platform = fol.MecanumPlatform()
    sensor = fol.StringPotSensor()
    t0 = time.perf_counter()
    res = fol.accompany(task, pid)
    first = time.perf_counter() - t0
    times = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        res = fol.accompany(task, pid)
        times.append(time.perf_counter() - t0)
    t_dl = float(np.median(times))
    t0 = time.perf_counter()
    base = baseline_run(task, pid, platform, sensor)
    t_base = time.perf_counter() - t0
    diff = float(np.max(np.abs(base[:2] - res.robot_pose[:2])))
    print(
        f"1. simulation: {task.duration:.1f} s task, {res.command.shape[1]} periods at 50 Hz, "
        f"{sensor.oversampling} raw samples each"
    )
    print(
        f"   designlab accompany (median of {args.repeats}): {1e3 * t_dl:7.1f} ms "
        f"(first call, building the CasADi run: {1e3 * first:.1f} ms)"
    )
    print(f"   per-step Python loop baseline:            {1e3 * t_base:7.1f} ms")
    print(
        f"   speed-up {t_base / t_dl:5.1f}x; paths agree to {diff:.1e} m; "
        f"target < 50 ms: {'met' if t_dl < 0.05 else 'NOT met'}"
    )
    ok &= diff < 1e-9 and t_dl < 0.05

    tune_tasks = [fol.walking_task(n) for n in ("forward", "left_lateral", "circle_cw")]
    all_tasks = [fol.walking_task(n) for n in fol.TASK_NAMES]
    rows = []
    for method, kw in (("convex", {}), ("simulation", {"max_evaluations": args.dfo_evaluations})):
        t0 = time.perf_counter()
        r = fol.tune_pid(tune_tasks, method=method, **kw)
        total = time.perf_counter() - t0
        mean_all = np.mean([fol.accompany(t, r.controller).rms_error for t in all_tasks])
        rows.append((method, r, total, mean_all))
    mean_default = np.mean([fol.accompany(t, pid).rms_error for t in all_tasks])
    print("2. PID tuning on forward, left_lateral, circle_cw (Ms <= 1.6)")
    print(f"   default gains: mean RMS over the nine tasks {1e3 * mean_default:.1f} mm")
    for method, r, total, mean_all in rows:
        c = r.controller
        print(
            f"   {method:10s}: {total:6.2f} s total ({r.elapsed:6.2f} s tuning, "
            f"{r.simulations} simulations, {r.iterations} iterations), "
            f"Kp {c.kp:.3g} Ki {c.ki:.3g} Kd {c.kd:.3g}, Ms {r.margins['Ms'].max():.3f}, "
            f"mean RMS nine tasks {1e3 * mean_all:.1f} mm, status {r.status}"
        )
        ok &= total < 60.0
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
