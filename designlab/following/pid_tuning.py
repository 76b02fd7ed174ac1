"""PID tuning of the accompanying robot's loops.

Two tuners, both checked afterwards with python-control
(:func:`designlab.following.loop_analysis`) and in the nonlinear simulation
over the given walking tasks:

* ``method="convex"`` (default) -- convex-concave optimisation in the manner
  of Hast, Astrom, Bernhardsson and Boyd, "PID design by convex-concave
  optimization", ECC 2013: maximise the integral gain K_i (the integrated
  error after a load step is 1/K_i) subject to ``|S| <= Ms`` and
  ``|T| <= Mt`` on a frequency grid up to the Nyquist frequency. The loop is
  affine in (K_p, K_i, K_d) for a fixed derivative filter, so
  ``|T| <= Mt`` is ``|L| <= Mt |1 + L|`` and ``|S| <= Ms`` is
  ``|1 + L| >= 1/Ms``; the concave right-hand sides are replaced by their
  linearisation ``Re(conj(u0) (1 + L))`` with ``u0`` the phase of ``1 + L`` at
  the current iterate (an inner approximation), and the resulting
  second-order cone programs are solved with cvxpy until K_i stops growing.
  Every iterate is feasible for the true constraints.
* ``method="simulation"`` -- derivative-free (Nelder-Mead on the log gains)
  minimisation of the mean simulated RMS error over the tasks, with the
  same Ms and Mt limits (and noise-gain limit, if any) as penalties.

Examples
--------
>>> import designlab as dl
>>> fol = dl.following
>>> pid = fol.tune_pid(tasks=[fol.walking_task("forward")])
>>> pid.status, bool(pid.margins["Ms"].max() <= 1.6 + 1e-3), pid.improvement > 0
('ok', True, True)
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from designlab.errors import InvalidParameterError, check_nonnegative, check_positive
from designlab.following.accompany_linear import (
    _delay_periods,
    frequency_grid,
    loop_analysis,
    pid_basis,
    plant_response,
)
from designlab.following.accompany_model import MecanumPlatform, StringPotSensor
from designlab.following.accompany_simulate import accompany
from designlab.following.user_frame_pid import UserFramePID
from designlab.following.walking_tasks import WalkingTask
from designlab.results import OK, Result

__all__ = ["TUNING_METHODS", "PIDTuningResult", "convex_concave_pid", "tune_pid"]

log = logging.getLogger(__name__)

#: Tuning methods of :func:`tune_pid`.
TUNING_METHODS = ("convex", "simulation")


@dataclass(frozen=True)
class ConvexConcaveSolution:
    """Gains of one loop from :func:`convex_concave_pid` and how the iteration went."""

    kp: float
    ki: float
    kd: float
    iterations: int
    converged: bool
    solver_status: str


def convex_concave_pid(
    tau: float,
    sample_time: float,
    derivative_filter_time: float,
    *,
    ms_max: float = 1.6,
    mt_max: float = 1.3,
    kd_max: float = 5.0,
    max_noise_gain: float | None = None,
    delay: int = 0,
    n_frequencies: int = 300,
    max_iterations: int = 60,
    tolerance: float = 1e-5,
) -> ConvexConcaveSolution:
    """Maximise K_i of one axis subject to Ms and Mt (Hast et al. 2013), by cvxpy.

    Parameters
    ----------
    tau
        Platform lag time constant of the axis in s.
    sample_time
        Control period in s.
    derivative_filter_time
        T_f of the derivative filter in s (fixed during the optimisation).
    ms_max, mt_max
        Limits of |S| and |T| (>= 1).
    kd_max
        Upper bound of K_d (a practical limit on noise amplification).
    max_noise_gain
        Optional limit of |C S|, the gain from measurement noise to the
        command, in (m/s)/m = 1/s (Hast et al. 2013's noise-sensitivity
        constraint); ``None``: no limit.
    delay
        Extra delay in control periods.
    n_frequencies
        Grid points up to the Nyquist frequency.
    max_iterations, tolerance
        Stop when the relative increase of K_i is below ``tolerance``.

    Examples
    --------
    >>> sol = convex_concave_pid(0.15, 0.02, 0.05)
    >>> sol.converged, sol.ki > 0.5
    (True, True)
    """
    import cvxpy as cp

    omega = frequency_grid(sample_time, n_frequencies, 1e-2)
    a = (
        pid_basis(derivative_filter_time, sample_time, omega)
        * plant_response(tau, sample_time, omega, delay)[:, None]
    )
    ar, ai = a.real, a.imag
    basis = pid_basis(derivative_filter_time, sample_time, omega)
    br, bi = basis.real, basis.imag
    k = cp.Variable(3)
    ur = cp.Parameter(omega.size)
    ui = cp.Parameter(omega.size)
    lin = cp.multiply(ur, 1 + ar @ k) + cp.multiply(ui, ai @ k)
    constraints = [
        lin >= 1.0 / ms_max,
        cp.norm(cp.vstack([ar @ k, ai @ k]), 2, axis=0) <= mt_max * lin,
        k >= 0,
        k[2] <= kd_max,
    ]
    if max_noise_gain is not None:
        # |C| <= ks |1 + L|, with |1 + L| replaced by its linearisation (inner approximation)
        constraints.append(cp.norm(cp.vstack([br @ k, bi @ k]), 2, axis=0) <= max_noise_gain * lin)
    problem = cp.Problem(cp.Maximize(k[1]), constraints)
    k0 = np.array([0.05, 0.0, 0.0])
    converged = False
    status = "optimal"
    it = 0
    for it in range(1, max_iterations + 1):  # noqa: B007
        s0 = 1.0 + a @ k0
        u0 = s0 / np.abs(s0)
        ur.value = u0.real
        ui.value = u0.imag
        try:
            problem.solve(solver=cp.CLARABEL)
        except cp.error.SolverError as exc:  # pragma: no cover - solver failure path
            status = f"solver error: {exc}"
            break
        status = str(problem.status)
        if problem.status not in ("optimal", "optimal_inaccurate") or k.value is None:
            break
        k1 = np.maximum(np.asarray(k.value, dtype=float), 0.0)
        change = (k1[1] - k0[1]) / max(k1[1], 1e-12)
        k0 = k1
        if abs(change) < tolerance:
            converged = True
            break
    return ConvexConcaveSolution(float(k0[0]), float(k0[1]), float(k0[2]), it, converged, status)


@dataclass(frozen=True, eq=False)
class PIDTuningResult(Result):
    """A tuned :class:`UserFramePID`, its margins and its simulated improvement.

    Attributes
    ----------
    controller
        The tuned gains.
    baseline
        The gains it is compared with.
    margins
        Per axis: gain and phase margins, crossover, Ms, Mt, stability
        (python-control, :func:`loop_analysis`).
    improvement
        ``1 - mean RMS(tuned) / mean RMS(baseline)`` over the tasks (> 0 is better).
    per_task
        Per task: RMS, max and settled errors of baseline and tuned gains.
    method
        ``"convex"`` or ``"simulation"``.
    ms_max, mt_max
        The limits used.
    iterations
        Convex programs solved (convex) or objective evaluations (simulation).
    simulations
        Closed-loop simulations run (for the tuning, not the final check).
    elapsed
        Wall time of the tuning in s (without the final check).
    status
        ``"ok"``, or the solver's failure (the default gains are then returned).
    warnings
        What a user should know about the tuning (e.g. a margin target not met).
    """

    controller: UserFramePID
    baseline: UserFramePID
    margins: pd.DataFrame
    improvement: float
    per_task: pd.DataFrame
    method: str
    ms_max: float
    mt_max: float
    iterations: int
    simulations: int
    elapsed: float
    status: str = OK
    warnings: tuple[str, ...] = field(default=())

    def to_frame(self) -> pd.DataFrame:
        """Per-task errors of the baseline and tuned gains (m)."""
        return self.per_task.copy()

    def gains_frame(self) -> pd.DataFrame:
        """One row: the method, the tuned gains, Ms, Mt, improvement and the cost."""
        c = self.controller
        return pd.DataFrame(
            [
                {
                    "method": self.method,
                    "kp_1_s": c.kp,
                    "ki_1_s2": c.ki,
                    "kd": c.kd,
                    "Tf_s": c.derivative_filter_time,
                    "kp_heading": c.kp_heading,
                    "ki_heading": c.ki_heading,
                    "kd_heading": c.kd_heading,
                    "Ms": float(self.margins["Ms"].max()),
                    "Mt": float(self.margins["Mt"].max()),
                    "phase_margin_deg": float(self.margins["phase_margin_deg"].min()),
                    "mean_rms_baseline_m": float(self.per_task["rms_baseline_m"].mean()),
                    "mean_rms_tuned_m": float(self.per_task["rms_tuned_m"].mean()),
                    "improvement": self.improvement,
                    "iterations": self.iterations,
                    "simulations": self.simulations,
                    "elapsed_s": self.elapsed,
                    "status": self.status,
                }
            ]
        )


def _evaluate(
    controller: UserFramePID,
    tasks: Sequence[WalkingTask],
    platform: MecanumPlatform,
    sensor: StringPotSensor,
) -> list:
    return [accompany(t, controller, platform=platform, sensor=sensor) for t in tasks]


def tune_pid(
    tasks: Sequence[WalkingTask],
    *,
    method: str = "convex",
    baseline: UserFramePID | None = None,
    platform: MecanumPlatform | None = None,
    sensor: StringPotSensor | None = None,
    ms_max: float = 1.6,
    mt_max: float = 1.3,
    derivative_filter_time: float = 0.05,
    kd_max: float = 5.0,
    max_noise_gain: float | None = None,
    max_evaluations: int = 150,
) -> PIDTuningResult:
    """Tune the three PIDs; verify with python-control margins and by simulating ``tasks``.

    Parameters
    ----------
    tasks
        Walking tasks of the simulated check (and the objective of
        ``method="simulation"``); at least one.
    method
        ``"convex"`` (Hast et al. 2013 convex-concave, default) or
        ``"simulation"`` (Nelder-Mead on the simulated mean RMS error).
    baseline
        Gains to compare with; default :class:`UserFramePID()`.
    platform, sensor
        Models; defaults as :func:`designlab.following.accompany`.
    ms_max, mt_max
        Limits of the sensitivity and complementary sensitivity peaks (>= 1);
        ``method="simulation"`` enforces them as penalties.
    derivative_filter_time
        T_f of the derivative filters in s (>= 0).
    kd_max
        Upper bound of K_d.
    max_noise_gain
        Optional limit of |C S| (noise to command) in 1/s, for both methods;
        ``None``: none. Without it the convex tuner puts K_d near 2 and passes
        measurement noise to the command about 40 times (see ``docs/following.md``).
    max_evaluations
        Objective evaluations of ``method="simulation"``.

    Returns
    -------
    PIDTuningResult
        ``status`` ``"ok"``; ``"not_converged"`` if the convex-concave
        iteration stopped early; ``"failed"`` if the solver failed or the
        tuned loop violates ``ms_max`` on python-control's check; warnings if
        the tuned gains do not improve the simulated RMS error.

    Examples
    --------
    >>> from designlab.following import walking_task
    >>> r = tune_pid([walking_task("left_lateral")], method="convex")
    >>> round(r.controller.ki, 1) > r.baseline.ki
    True
    """
    if method not in TUNING_METHODS:
        raise InvalidParameterError("method", method, f"one of {TUNING_METHODS}")
    tasks = list(tasks)
    if not tasks or not all(isinstance(t, WalkingTask) for t in tasks):
        raise InvalidParameterError("tasks", tasks, "a non-empty list of WalkingTask")
    baseline = UserFramePID() if baseline is None else baseline
    platform = MecanumPlatform() if platform is None else platform
    sensor = StringPotSensor() if sensor is None else sensor
    for name, v in (("ms_max", ms_max), ("mt_max", mt_max)):
        if check_positive(name, v) < 1.0:
            raise InvalidParameterError(name, v, "must be >= 1")
    tf = check_nonnegative("derivative_filter_time", derivative_filter_time, "s")
    kd_max = check_nonnegative("kd_max", kd_max)
    if max_noise_gain is not None:
        max_noise_gain = check_positive("max_noise_gain", max_noise_gain, "1/s")
    ts = sensor.period
    delay = _delay_periods(sensor)
    warnings: list[str] = []
    status = OK
    t0 = time.perf_counter()
    simulations = 0
    if method == "convex":
        sols = {}
        for axis, tau in (("linear", platform.time_constant), ("heading", platform.yaw_tau)):
            if axis == "heading" and platform.yaw_tau == platform.time_constant:
                sols[axis] = sols["linear"]
                continue
            sols[axis] = convex_concave_pid(
                tau,
                ts,
                tf,
                ms_max=ms_max,
                mt_max=mt_max,
                kd_max=kd_max,
                max_noise_gain=max_noise_gain,
                delay=delay,
            )
        iterations = sum(s.iterations for s in {id(s): s for s in sols.values()}.values())
        for axis, s in sols.items():
            if s.solver_status not in ("optimal", "optimal_inaccurate"):
                status = "failed"
                warnings.append(f"convex-concave step of the {axis} loop: solver {s.solver_status}")
            elif not s.converged:
                status = "not_converged"
                warnings.append(
                    f"convex-concave iteration of the {axis} loop stopped after {s.iterations} "
                    "programs before K_i converged"
                )
        lin, hdg = sols["linear"], sols["heading"]
        controller = UserFramePID(
            kp=lin.kp,
            ki=lin.ki,
            kd=lin.kd,
            derivative_filter_time=tf,
            kp_heading=hdg.kp,
            ki_heading=hdg.ki,
            kd_heading=hdg.kd,
            heading_filter_time=tf,
        )
    else:
        from scipy.optimize import minimize

        omega = frequency_grid(ts, 600, 1e-2)
        c_basis = pid_basis(tf, ts, omega)
        basis = c_basis * plant_response(platform.time_constant, ts, omega, delay)[:, None]

        def objective(logk: np.ndarray) -> float:
            nonlocal simulations
            kp, ki, kd = np.exp(logk)
            c = UserFramePID(kp=kp, ki=ki, kd=kd, derivative_filter_time=tf)
            gains = np.array([kp, ki, kd])
            loop = basis @ gains
            sens = 1.0 / np.abs(1.0 + loop)
            ms = float(np.max(sens))
            mt = float(np.max(np.abs(loop) * sens))
            penalty = 0.0
            if ms > ms_max:
                penalty = 10.0 * (ms - ms_max)
            if mt > mt_max:
                penalty += 10.0 * (mt - mt_max)
            if max_noise_gain is not None:
                ku = float(np.max(np.abs(c_basis @ gains) * sens))
                if ku > max_noise_gain:
                    penalty += 0.01 * (ku - max_noise_gain)
            if kd > kd_max:
                penalty += kd - kd_max
            res = _evaluate(c, tasks, platform, sensor)
            simulations += len(res)
            if any(r.status != OK for r in res):
                return 1e3
            return float(np.mean([r.rms_error for r in res])) + penalty

        start = np.log([max(baseline.kp, 1e-3), max(baseline.ki, 1e-3), max(baseline.kd, 1e-3)])
        # initial simplex: each gain scaled by 3 (scipy's default, 5 %, crawls)
        simplex = np.vstack([start, start + np.log(3.0) * np.eye(3)])
        opt = minimize(
            objective,
            start,
            method="Nelder-Mead",
            options={
                "maxfev": max_evaluations,
                "xatol": 1e-3,
                "fatol": 1e-5,
                "initial_simplex": simplex,
            },
        )
        iterations = int(opt.nfev)
        kp, ki, kd = np.exp(opt.x)
        controller = UserFramePID(kp=kp, ki=ki, kd=kd, derivative_filter_time=tf)
        if not opt.success:
            status = "not_converged"
            warnings.append(f"Nelder-Mead: {opt.message}")
    elapsed = time.perf_counter() - t0

    la = loop_analysis(controller, platform, sensor)
    margins = la.to_frame()
    if la.status != OK:
        status = "failed"
        warnings.extend(la.warnings)
    elif la.ms > ms_max * (1 + 2e-3):
        status = "failed"
        warnings.append(
            f"python-control check: Ms = {la.ms:.3f} exceeds ms_max = {ms_max} "
            "(peak between grid frequencies)"
        )
    if la.mt > mt_max * (1 + 2e-3):
        warnings.append(f"python-control check: Mt = {la.mt:.3f} exceeds mt_max = {mt_max}")
    base_runs = _evaluate(baseline, tasks, platform, sensor)
    tuned_runs = _evaluate(controller, tasks, platform, sensor)
    per_task = pd.DataFrame(
        {
            "task": [t.name for t in tasks],
            "rms_baseline_m": [r.rms_error for r in base_runs],
            "rms_tuned_m": [r.rms_error for r in tuned_runs],
            "max_baseline_m": [r.max_error for r in base_runs],
            "max_tuned_m": [r.max_error for r in tuned_runs],
            "settled_baseline_m": [r.settled_error for r in base_runs],
            "settled_tuned_m": [r.settled_error for r in tuned_runs],
            "status_tuned": [r.status for r in tuned_runs],
        }
    )
    mean_b = float(per_task["rms_baseline_m"].mean())
    mean_t = float(per_task["rms_tuned_m"].mean())
    improvement = 1.0 - mean_t / mean_b if mean_b > 0 else math.nan
    if not improvement > 0:
        warnings.append(
            f"the tuned gains do not lower the mean simulated RMS error ({mean_t:.4f} m vs "
            f"{mean_b:.4f} m with the baseline)"
        )
    if any(r.status != OK for r in tuned_runs):
        status = "failed"
        warnings.append("a simulation with the tuned gains diverged")
    log.info(
        "tune_pid %s: %s, improvement %.3f in %.2f s", method, controller, improvement, elapsed
    )
    return PIDTuningResult(
        controller=controller,
        baseline=baseline,
        margins=margins,
        improvement=improvement,
        per_task=per_task,
        method=method,
        ms_max=ms_max,
        mt_max=mt_max,
        iterations=iterations,
        simulations=simulations,
        elapsed=elapsed,
        status=status,
        warnings=tuple(warnings),
    )
