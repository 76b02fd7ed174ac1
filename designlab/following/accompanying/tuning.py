"""PID tuning of the accompanying robot's loops.

Two tuners, small strategy objects registered by name in :data:`TUNERS`, both
checked afterwards with python-control
(:func:`designlab.following.accompanying.loop_analysis`) and in the nonlinear
simulation over the given walking tasks:

* ``method="convex"`` (default, :class:`ConvexConcaveTuner`) -- convex-concave
  optimisation in the manner of Hast, Astrom, Bernhardsson and Boyd, "PID
  design by convex-concave optimization", ECC 2013: maximise the integral gain
  K_i (the integrated error after a load step is 1/K_i) subject to
  ``|S| <= Ms`` and ``|T| <= Mt`` on a frequency grid up to the Nyquist
  frequency. The loop is affine in (K_p, K_i, K_d) for a fixed derivative
  filter, so ``|T| <= Mt`` is ``|L| <= Mt |1 + L|`` and ``|S| <= Ms`` is
  ``|1 + L| >= 1/Ms``; the concave right-hand sides are replaced by their
  linearisation ``Re(conj(u0) (1 + L))`` with ``u0`` the phase of ``1 + L`` at
  the current iterate (an inner approximation), and the resulting
  second-order cone programs are solved with cvxpy until K_i stops growing.
  Every iterate is feasible for the true constraints.
* ``method="simulation"`` (:class:`SimulationTuner`) -- derivative-free
  (Nelder-Mead on the log gains) minimisation of the mean simulated RMS error
  over the tasks, with the same Ms and Mt limits (and noise-gain limit, if
  any) as penalties.

Examples
--------
>>> from designlab.following import accompanying as acc
>>> pid = acc.tune(tasks=[acc.walking_task("forward")])
>>> str(pid.status), bool(pid.margins["Ms"].max() <= 1.6 + 1e-3), pid.improvement > 0
('ok', True, True)
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import pandas as pd

from designlab.errors import InvalidParameterError
from designlab.following.accompanying.linear import (
    LoopAnalysis,
    delay_periods,
    frequency_grid,
    loop_analysis,
    pid_basis,
    plant_response,
    refined_peak,
)
from designlab.following.accompanying.parameters import (
    KD_MAX,
    MAX_EVALUATIONS,
    MAX_ITERATIONS,
    MAX_NOISE_GAIN,
    MS_MAX,
    MT_MAX,
    TOLERANCE,
    MecanumPlatform,
    StringPotSensor,
    UserFramePID,
)
from designlab.following.accompanying.simulate import AccompanyResult, simulate
from designlab.following.accompanying.tasks import WalkingTask
from designlab.params import Param, params_of
from designlab.progress import Progress, ProgressHook, report
from designlab.results import Result, Status

__all__ = [
    "CONVEX_FREQUENCIES",
    "TUNERS",
    "TUNING_METHODS",
    "ConvexConcaveSolution",
    "ConvexConcaveTuner",
    "PIDTuningResult",
    "PIDTuningStatus",
    "SimulationTuner",
    "TuningProblem",
    "convex_concave_pid",
    "tune",
    "tune_pid",
]

log = logging.getLogger(__name__)

#: Frequencies of the convex-concave grid (up to the Nyquist frequency).
CONVEX_FREQUENCIES = Param(
    None,
    "",
    "points of the convex-concave frequency grid",
    kind="integer",
    ge=50,
    le=20_000,
    default=300,
    name="n_frequencies",
)
_TF = params_of(UserFramePID)["derivative_filter_time"]
_SOLVED = ("optimal", "optimal_inaccurate")


class PIDTuningStatus(Status):
    """Status of a PID tuning.

    ``OK``: the tuner converged and the tuned loops pass python-control's check
    and the simulations. ``NOT_CONVERGED``: the iteration (or the evaluation
    budget) ended first; the gains are the last iterate. ``FAILED``: the solver
    failed, the tuned loop violates ``ms_max`` or is unstable, or a simulation
    with the tuned gains diverged.
    """

    OK = "ok"
    NOT_CONVERGED = "not_converged"
    FAILED = "failed"


@dataclass(frozen=True)
class ConvexConcaveSolution:
    """Gains of one loop from :func:`convex_concave_pid` and how the iteration went.

    Attributes
    ----------
    kp, ki, kd
        The gains.
    iterations
        Convex programs solved (over every refinement round).
    converged
        Whether K_i stopped growing.
    solver_status
        The last solver status (``"optimal"``, or the failure).
    ms, mt
        The peaks of |S| and |T| of the solution, refined between grid points.
    rounds
        Solves (the first, and one per grid refinement).
    """

    kp: float
    ki: float
    kd: float
    iterations: int
    converged: bool
    solver_status: str
    ms: float = math.nan
    mt: float = math.nan
    rounds: int = 1


#: Rounds of grid refinement of :func:`convex_concave_pid` (a peak between grid points
#: above its limit adds its frequency to the grid and the problem is solved again).
REFINE_ROUNDS = 8
#: Relative excess of a refined peak over its limit that is accepted.
PEAK_TOLERANCE = 1e-6


def _peaks(
    gains: np.ndarray, tau: float, ts: float, tf: float, delay: int, omega: np.ndarray
) -> dict[str, tuple[float, float]]:
    """Refined peaks (value, frequency) of |S|, |T| and |C S| of one loop."""

    def parts(w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        c = pid_basis(tf, ts, w) @ gains
        return c, c * plant_response(tau, ts, w, delay)

    return {
        "ms_max": refined_peak(lambda w: np.abs(1.0 / (1.0 + parts(w)[1])), omega),
        "mt_max": refined_peak(lambda w: np.abs(parts(w)[1] / (1.0 + parts(w)[1])), omega),
        "max_noise_gain": refined_peak(lambda w: np.abs(parts(w)[0] / (1.0 + parts(w)[1])), omega),
    }


def _cone_program(a: np.ndarray, basis: np.ndarray, limits: dict[str, Any]) -> tuple:
    """The second-order cone program of one convex-concave step (cvxpy), and its parameters."""
    import cvxpy as cp

    ar, ai = a.real, a.imag
    br, bi = basis.real, basis.imag
    k = cp.Variable(3)
    ur = cp.Parameter(a.shape[0])
    ui = cp.Parameter(a.shape[0])
    lin = cp.multiply(ur, 1 + ar @ k) + cp.multiply(ui, ai @ k)
    constraints = [
        lin >= 1.0 / limits["ms_max"],
        cp.norm(cp.vstack([ar @ k, ai @ k]), 2, axis=0) <= limits["mt_max"] * lin,
        k >= 0,
        k[2] <= limits["kd_max"],
    ]
    if limits["max_noise_gain"] is not None:
        # |C| <= ks |1 + L|, with |1 + L| replaced by its linearisation (inner approximation)
        constraints.append(
            cp.norm(cp.vstack([br @ k, bi @ k]), 2, axis=0) <= limits["max_noise_gain"] * lin
        )
    return cp.Problem(cp.Maximize(k[1]), constraints), k, ur, ui


def convex_concave_pid(
    tau: float,
    sample_time: float,
    derivative_filter_time: float,
    *,
    ms_max: float = MS_MAX.default,
    mt_max: float = MT_MAX.default,
    kd_max: float = KD_MAX.default,
    max_noise_gain: float | None = None,
    delay: int = 0,
    n_frequencies: int = CONVEX_FREQUENCIES.default,
    max_iterations: int = MAX_ITERATIONS.default,
    tolerance: float = TOLERANCE.default,
    progress: ProgressHook | None = None,
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
        Limits of |S| and |T| (:data:`MS_MAX`, :data:`MT_MAX`).
    kd_max
        Upper bound of K_d (a practical limit on noise amplification).
    max_noise_gain
        Optional limit of |C S|, the gain from measurement noise to the
        command, in (m/s)/m = 1/s (Hast et al. 2013's noise-sensitivity
        constraint); ``None``: no limit.
    delay
        Extra delay in control periods.
    n_frequencies
        Grid points up to the Nyquist frequency (:data:`CONVEX_FREQUENCIES`). After
        the iteration the peaks of |S|, |T| (and |C S|) are refined between the
        points of a 2000-point grid (:func:`~designlab.following.accompanying.linear.refined_peak`);
        a peak above its limit (relative excess over :data:`PEAK_TOLERANCE`) adds its
        frequency to the constraint grid and the problem is solved again (at most
        :data:`REFINE_ROUNDS` rounds), so the limits hold between grid points too.
    max_iterations, tolerance
        Stop when the relative increase of K_i is below ``tolerance``.
    progress
        Called after each convex program (the best K_i so far).

    Examples
    --------
    >>> sol = convex_concave_pid(0.15, 0.02, 0.05)
    >>> sol.converged, sol.ki > 0.5, sol.ms <= 1.6 * (1 + 1e-6), sol.mt <= 1.3 * (1 + 1e-6)
    (True, True, True, True)
    """
    limits = {
        "ms_max": MS_MAX.check(ms_max),
        "mt_max": MT_MAX.check(mt_max),
        "kd_max": KD_MAX.check(kd_max),
        "max_noise_gain": MAX_NOISE_GAIN.check(max_noise_gain),
    }
    max_iterations, tolerance = MAX_ITERATIONS.check(max_iterations), TOLERANCE.check(tolerance)
    omega = frequency_grid(sample_time, CONVEX_FREQUENCIES.check(n_frequencies), 1e-2)
    tf = _TF.check(derivative_filter_time)
    full = frequency_grid(sample_time, 2000, 1e-3)
    start = np.array([0.05, 0.0, 0.0])
    rounds = it = 0
    while rounds < REFINE_ROUNDS:
        rounds += 1
        basis = pid_basis(tf, sample_time, omega)
        a = basis * plant_response(tau, sample_time, omega, delay)[:, None]
        k0, n, converged, status = _iterate(
            a, basis, limits, start, (max_iterations, tolerance, it), progress
        )
        it += n
        peaks = _peaks(k0, tau, sample_time, tf, delay, full)
        over = [
            at
            for key, (value, at) in peaks.items()
            if limits[key] is not None and value > limits[key] * (1 + PEAK_TOLERANCE)
        ]
        if not over or status not in _SOLVED:
            break
        # a peak between grid points is above its limit: constrain it there (and around it)
        near = np.array([0.99, 0.997, 1.0, 1.003, 1.01])
        omega = np.unique(np.concatenate([omega, np.outer(over, near).ravel()]))
        start = 0.95 * k0  # warm start just inside the old optimum
    return ConvexConcaveSolution(
        float(k0[0]),
        float(k0[1]),
        float(k0[2]),
        it,
        converged,
        status,
        ms=peaks["ms_max"][0],
        mt=peaks["mt_max"][0],
        rounds=rounds,
    )


def _iterate(
    a: np.ndarray,
    basis: np.ndarray,
    limits: dict[str, Any],
    start: np.ndarray,
    stop: tuple[int, float, int],
    progress: ProgressHook | None,
) -> tuple[np.ndarray, int, bool, str]:
    """The convex-concave iteration on one grid: (gains, programs, converged, solver status).

    ``stop`` is (programs allowed, relative tolerance of K_i, programs solved before, which
    numbers the progress steps on from the earlier rounds).
    """
    import cvxpy as cp

    max_iterations, tolerance, before = stop
    problem, k, ur, ui = _cone_program(a, basis, limits)
    k0 = np.array(start, dtype=float)
    converged, status, it = False, "optimal", 0
    for it in range(1, max_iterations + 1):
        s0 = 1.0 + a @ k0
        u0 = s0 / np.abs(s0)
        ur.value, ui.value = u0.real, u0.imag
        try:
            problem.solve(solver=cp.CLARABEL)
        except cp.error.SolverError as exc:  # pragma: no cover - solver failure path
            status = f"solver error: {exc}"
            break
        status = str(problem.status)
        if problem.status not in _SOLVED or k.value is None:
            break
        k1 = np.maximum(np.asarray(k.value, dtype=float), 0.0)
        change = (k1[1] - k0[1]) / max(k1[1], 1e-12)
        k0 = k1
        report(
            progress,
            Progress(before + it, before + max_iterations, float(k0[1]), "program", "max K_i"),
        )
        if abs(change) < tolerance:
            converged = True
            break
    return k0, it, converged, status


@dataclass(frozen=True)
class TuningProblem:
    """What a tuner works on: the tasks, the models and the checked limits.

    Attributes
    ----------
    tasks
        Walking tasks of the simulated check (and the simulation tuner's objective).
    baseline
        The gains compared with (and the simulation tuner's start).
    platform, sensor
        The models.
    ms_max, mt_max
        Limits of |S| and |T|.
    derivative_filter_time
        T_f of the tuned PIDs in s.
    kd_max
        Upper bound of K_d.
    max_noise_gain
        Limit of |C S| in 1/s, or ``None``.
    progress
        The caller's progress hook, or ``None``.
    """

    tasks: tuple[WalkingTask, ...]
    baseline: UserFramePID
    platform: MecanumPlatform
    sensor: StringPotSensor
    ms_max: float
    mt_max: float
    derivative_filter_time: float
    kd_max: float
    max_noise_gain: float | None
    progress: ProgressHook | None = None

    def simulate(self, controller: UserFramePID) -> list[AccompanyResult]:
        """Every task simulated with ``controller``.

        Parameters
        ----------
        controller
            The gains.
        """
        return [
            simulate(t, controller, platform=self.platform, sensor=self.sensor) for t in self.tasks
        ]


@dataclass
class _Tuned:
    controller: UserFramePID
    iterations: int
    simulations: int = 0
    status: PIDTuningStatus = PIDTuningStatus.OK
    warnings: list[str] = field(default_factory=list)


class ConvexConcaveTuner:
    """``method="convex"``: Hast et al. 2013 on the linear and (if different) the yaw loop."""

    name: ClassVar[str] = "convex"

    @classmethod
    def from_options(cls, max_evaluations: int) -> ConvexConcaveTuner:
        """The tuner; ``max_evaluations`` is checked (the same limits for every method).

        Parameters
        ----------
        max_evaluations
            Checked against :data:`MAX_EVALUATIONS`, not used (the method solves cone programs).
        """
        MAX_EVALUATIONS.check(max_evaluations)
        return cls()

    def tune(self, problem: TuningProblem) -> _Tuned:
        """Solve the linear axes' loop (and the heading loop if its lag differs).

        Parameters
        ----------
        problem
            The tuning problem.
        """
        pf, tf = problem.platform, problem.derivative_filter_time
        solve = {
            "tau": None,
            "sample_time": problem.sensor.period,
            "derivative_filter_time": tf,
            "ms_max": problem.ms_max,
            "mt_max": problem.mt_max,
            "kd_max": problem.kd_max,
            "max_noise_gain": problem.max_noise_gain,
            "delay": delay_periods(problem.sensor),
            "progress": problem.progress,
        }
        sols = {"linear": convex_concave_pid(**{**solve, "tau": pf.time_constant})}
        same = pf.yaw_tau == pf.time_constant
        sols["heading"] = (
            sols["linear"] if same else convex_concave_pid(**{**solve, "tau": pf.yaw_tau})
        )
        lin, hdg = sols["linear"], sols["heading"]
        out = _Tuned(
            UserFramePID(
                kp=lin.kp,
                ki=lin.ki,
                kd=lin.kd,
                derivative_filter_time=tf,
                kp_heading=hdg.kp,
                ki_heading=hdg.ki,
                kd_heading=hdg.kd,
                heading_filter_time=tf,
            ),
            iterations=lin.iterations + (0 if same else hdg.iterations),
        )
        for axis, s in sols.items():
            if s.solver_status not in _SOLVED:
                out.status = PIDTuningStatus.FAILED
                out.warnings.append(
                    f"convex-concave step of the {axis} loop: solver {s.solver_status}"
                )
            elif not s.converged:
                out.status = PIDTuningStatus.NOT_CONVERGED
                out.warnings.append(
                    f"convex-concave iteration of the {axis} loop stopped after {s.iterations} "
                    "programs before K_i converged"
                )
        return out


class SimulationTuner:
    """``method="simulation"``: Nelder-Mead on the log gains of the simulated mean RMS error.

    Parameters
    ----------
    max_evaluations
        Objective evaluations (:data:`MAX_EVALUATIONS`).
    """

    name: ClassVar[str] = "simulation"

    def __init__(self, max_evaluations: int = MAX_EVALUATIONS.default) -> None:
        self.max_evaluations = MAX_EVALUATIONS.check(max_evaluations)

    @classmethod
    def from_options(cls, max_evaluations: int) -> SimulationTuner:
        """The tuner with its evaluation budget.

        Parameters
        ----------
        max_evaluations
            Objective evaluations (:data:`MAX_EVALUATIONS`).
        """
        return cls(max_evaluations)

    def _objective(self, problem: TuningProblem, out: _Tuned) -> Any:
        ts, tf = problem.sensor.period, problem.derivative_filter_time
        omega = frequency_grid(ts, 600, 1e-2)
        c_basis = pid_basis(tf, ts, omega)
        tau = problem.platform.time_constant
        basis = c_basis * plant_response(tau, ts, omega, delay_periods(problem.sensor))[:, None]
        best = [math.inf]

        def objective(logk: np.ndarray) -> float:
            kp, ki, kd = np.exp(logk)
            gains = np.array([kp, ki, kd])
            loop = basis @ gains
            sens = 1.0 / np.abs(1.0 + loop)
            penalty = _penalty(problem, float(np.max(sens)), float(np.max(np.abs(loop) * sens)))
            if problem.max_noise_gain is not None:
                ku = float(np.max(np.abs(c_basis @ gains) * sens))
                if ku > problem.max_noise_gain:
                    penalty += 0.01 * (ku - problem.max_noise_gain)
            if kd > problem.kd_max:
                penalty += kd - problem.kd_max
            try:
                gains_pid = UserFramePID(kp=kp, ki=ki, kd=kd, derivative_filter_time=tf)
            except InvalidParameterError:  # outside the declared ranges: refuse the step
                return 1e3 + penalty
            res = problem.simulate(gains_pid)
            out.simulations += len(res)
            cost = (
                1e3
                if any(r.status != "ok" for r in res)
                else float(np.mean([r.rms_error for r in res])) + penalty
            )
            best[0] = min(best[0], cost)
            step = out.simulations // len(problem.tasks)
            report(problem.progress, Progress(step, self.max_evaluations, best[0], "evaluation"))
            return cost

        return objective

    def tune(self, problem: TuningProblem) -> _Tuned:
        """Minimise the simulated mean RMS error from the baseline gains.

        Parameters
        ----------
        problem
            The tuning problem.
        """
        from scipy.optimize import minimize

        b = problem.baseline
        out = _Tuned(b, 0)
        start = np.log([max(b.kp, 1e-3), max(b.ki, 1e-3), max(b.kd, 1e-3)])
        # initial simplex: each gain scaled by 3 (scipy's default, 5 %, crawls)
        simplex = np.vstack([start, start + np.log(3.0) * np.eye(3)])
        opt = minimize(
            self._objective(problem, out),
            start,
            method="Nelder-Mead",
            options={
                "maxfev": self.max_evaluations,
                "xatol": 1e-3,
                "fatol": 1e-5,
                "initial_simplex": simplex,
            },
        )
        out.iterations = int(opt.nfev)
        kp, ki, kd = np.exp(opt.x)
        out.controller = UserFramePID(
            kp=kp, ki=ki, kd=kd, derivative_filter_time=problem.derivative_filter_time
        )
        if not opt.success:
            out.status = PIDTuningStatus.NOT_CONVERGED
            out.warnings.append(f"Nelder-Mead: {opt.message}")
        return out


def _penalty(problem: TuningProblem, ms: float, mt: float) -> float:
    penalty = 10.0 * (ms - problem.ms_max) if ms > problem.ms_max else 0.0
    if mt > problem.mt_max:
        penalty += 10.0 * (mt - problem.mt_max)
    return penalty


#: The tuners by method name.
TUNERS: dict[str, Any] = {"convex": ConvexConcaveTuner, "simulation": SimulationTuner}
#: Tuning methods of :func:`tune`.
TUNING_METHODS = tuple(TUNERS)


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
        ``"ok"``, ``"not_converged"`` or ``"failed"`` (:class:`PIDTuningStatus`).
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
    status: PIDTuningStatus = PIDTuningStatus.OK
    warnings: tuple[str, ...] = field(default=())

    def _gains(self) -> dict[str, float]:
        c = self.controller
        return {
            "kp_1_s": c.kp,
            "ki_1_s2": c.ki,
            "kd": c.kd,
            "Tf_s": c.derivative_filter_time,
            "kp_heading": c.kp_heading,  # type: ignore[dict-item]
            "ki_heading": c.ki_heading,  # type: ignore[dict-item]
            "kd_heading": c.kd_heading,  # type: ignore[dict-item]
        }

    def to_frame(self) -> pd.DataFrame:
        """Per task: errors of the baseline and tuned gains (m), and the tuned gains."""
        return self.per_task.assign(method=self.method, **self._gains())

    def gains_frame(self) -> pd.DataFrame:
        """One row: the method, the tuned gains, Ms, Mt, improvement and the cost."""
        return pd.DataFrame(
            [
                {
                    "method": self.method,
                    **self._gains(),
                    "Ms": float(self.margins["Ms"].max()),
                    "Mt": float(self.margins["Mt"].max()),
                    "phase_margin_deg": float(self.margins["phase_margin_deg"].min()),
                    "mean_rms_baseline_m": float(self.per_task["rms_baseline_m"].mean()),
                    "mean_rms_tuned_m": float(self.per_task["rms_tuned_m"].mean()),
                    "improvement": self.improvement,
                    "iterations": self.iterations,
                    "simulations": self.simulations,
                    "elapsed_s": self.elapsed,
                    "status": str(self.status),
                }
            ]
        )


def _checked_problem(tasks: Any, options: dict[str, Any]) -> TuningProblem:
    """Validate the arguments of :func:`tune` before anything is computed."""
    if isinstance(tasks, WalkingTask):
        tasks = [tasks]
    if isinstance(tasks, (str, bytes)) or not isinstance(tasks, Iterable):
        raise InvalidParameterError("tasks", tasks, "a non-empty list of WalkingTask")
    tasks = tuple(tasks)
    if not tasks or not all(isinstance(t, WalkingTask) for t in tasks) or len(tasks) > 100:
        raise InvalidParameterError("tasks", tasks, "a non-empty list of at most 100 WalkingTask")
    models = {
        "baseline": (options["baseline"], UserFramePID),
        "platform": (options["platform"], MecanumPlatform),
        "sensor": (options["sensor"], StringPotSensor),
    }
    built = {}
    for name, (obj, cls) in models.items():
        built[name] = cls() if obj is None else obj
        if not isinstance(built[name], cls):
            raise InvalidParameterError(name, type(obj).__name__, f"must be a {cls.__name__}")
    return TuningProblem(
        tasks=tasks,
        ms_max=MS_MAX.check(options["ms_max"]),
        mt_max=MT_MAX.check(options["mt_max"]),
        derivative_filter_time=_TF.check(
            options["derivative_filter_time"], "derivative_filter_time"
        ),
        kd_max=KD_MAX.check(options["kd_max"]),
        max_noise_gain=MAX_NOISE_GAIN.check(options["max_noise_gain"]),
        progress=options["progress"],
        **built,
    )


def _checked_tuner(method: Any, max_evaluations: Any) -> Any:
    if not isinstance(method, str) or method not in TUNERS:
        raise InvalidParameterError("method", method, f"one of {TUNING_METHODS}")
    return TUNERS[method].from_options(max_evaluations)


def _per_task(problem: TuningProblem, base: list, tuned: list) -> pd.DataFrame:
    return pd.DataFrame(
        {
            "task": [t.name for t in problem.tasks],
            "rms_baseline_m": [r.rms_error for r in base],
            "rms_tuned_m": [r.rms_error for r in tuned],
            "max_baseline_m": [r.max_error for r in base],
            "max_tuned_m": [r.max_error for r in tuned],
            "settled_baseline_m": [r.settled_error for r in base],
            "settled_tuned_m": [r.settled_error for r in tuned],
            "status_tuned": [str(r.status) for r in tuned],
        }
    )


def _checked_result(problem: TuningProblem, tuned: _Tuned, la: LoopAnalysis) -> None:
    """python-control's check of the tuned loops (status and warnings added to ``tuned``)."""
    if la.status != "ok":
        tuned.status = PIDTuningStatus.FAILED
        tuned.warnings.extend(la.warnings)
    elif la.ms > problem.ms_max * (1 + 10 * PEAK_TOLERANCE):
        tuned.status = PIDTuningStatus.FAILED
        tuned.warnings.append(
            f"python-control check: Ms = {la.ms:.3f} exceeds ms_max = {problem.ms_max} "
            "(peaks refined between grid frequencies)"
        )
    if la.mt > problem.mt_max * (1 + 10 * PEAK_TOLERANCE):
        tuned.warnings.append(
            f"python-control check: Mt = {la.mt:.3f} exceeds mt_max = {problem.mt_max}"
        )


def tune(
    tasks: Sequence[WalkingTask],
    *,
    method: str = "convex",
    baseline: UserFramePID | None = None,
    platform: MecanumPlatform | None = None,
    sensor: StringPotSensor | None = None,
    ms_max: float = MS_MAX.default,
    mt_max: float = MT_MAX.default,
    derivative_filter_time: float = _TF.default,
    kd_max: float = KD_MAX.default,
    max_noise_gain: float | None = None,
    max_evaluations: int = MAX_EVALUATIONS.default,
    progress: ProgressHook | None = None,
) -> PIDTuningResult:
    """Tune the three PIDs; verify with python-control margins and by simulating ``tasks``.

    Parameters
    ----------
    tasks
        Walking tasks of the simulated check (and the objective of
        ``method="simulation"``); one to 100.
    method
        ``"convex"`` (Hast et al. 2013 convex-concave, default) or
        ``"simulation"`` (Nelder-Mead on the simulated mean RMS error); see :data:`TUNERS`.
    baseline
        Gains to compare with; default :class:`UserFramePID()`.
    platform, sensor
        Models; defaults as :func:`designlab.following.accompanying.simulate`.
    ms_max, mt_max
        Limits of the sensitivity and complementary sensitivity peaks
        (:data:`MS_MAX`, :data:`MT_MAX`); ``method="simulation"`` enforces them as
        penalties.
    derivative_filter_time
        T_f of the derivative filters in s.
    kd_max
        Upper bound of K_d (:data:`KD_MAX`).
    max_noise_gain
        Optional limit of |C S| (noise to command) in 1/s, for both methods;
        ``None``: none. Without it the convex tuner puts K_d near 2 and passes
        measurement noise to the command about 40 times (see ``docs/following.md``).
    max_evaluations
        Objective evaluations of ``method="simulation"`` (:data:`MAX_EVALUATIONS`).
    progress
        Called with a :class:`~designlab.progress.Progress` after each convex
        program or objective evaluation (the best objective so far).

    Returns
    -------
    PIDTuningResult
        With a :class:`PIDTuningStatus` and warnings (e.g. no improvement).

    Examples
    --------
    >>> from designlab.following.accompanying import walking_task
    >>> r = tune([walking_task("left_lateral")], method="convex")
    >>> round(r.controller.ki, 1) > r.baseline.ki
    True
    """
    tuner = _checked_tuner(method, max_evaluations)
    problem = _checked_problem(tasks, dict(locals()))
    t0 = time.perf_counter()
    tuned = tuner.tune(problem)
    elapsed = time.perf_counter() - t0
    la = loop_analysis(tuned.controller, problem.platform, problem.sensor)
    _checked_result(problem, tuned, la)
    per_task = _per_task(
        problem, problem.simulate(problem.baseline), problem.simulate(tuned.controller)
    )
    mean_b = float(per_task["rms_baseline_m"].mean())
    mean_t = float(per_task["rms_tuned_m"].mean())
    improvement = 1.0 - mean_t / mean_b if mean_b > 0 else math.nan
    if not improvement > 0:
        tuned.warnings.append(
            f"the tuned gains do not lower the mean simulated RMS error ({mean_t:.4f} m vs "
            f"{mean_b:.4f} m with the baseline)"
        )
    if any(s != "ok" for s in per_task["status_tuned"]):
        tuned.status = PIDTuningStatus.FAILED
        tuned.warnings.append("a simulation with the tuned gains diverged")
    log.info(
        "tune %s: %s, improvement %.3f in %.2f s", method, tuned.controller, improvement, elapsed
    )
    return PIDTuningResult(
        controller=tuned.controller,
        baseline=problem.baseline,
        margins=la.to_frame(),
        improvement=improvement,
        per_task=per_task,
        method=tuner.name,
        ms_max=problem.ms_max,
        mt_max=problem.mt_max,
        iterations=tuned.iterations,
        simulations=tuned.simulations,
        elapsed=elapsed,
        status=tuned.status,
        warnings=tuple(tuned.warnings),
    )


tune_pid = tune
"""The name of :func:`tune` in the package's API: ``designlab.following.tune_pid``."""
