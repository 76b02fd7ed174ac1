"""The simulation engine shared by single runs and batches (internal).

Per navigation period one compiled CasADi function evaluates the field (or a
baseline), integrates the robot over the hold and measures the distances at every
dynamics step. It is called through CasADi's buffer interface with preallocated
numpy arrays, and mapped over a batch of gain sets with ``Function.map``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.navigation.cbf_filter import CBFFilter
from designlab.navigation.dynamics import build_hold, state_size
from designlab.navigation.field import (
    NORM_EPS,
    ObstacleGeometry,
    build_distance,
    build_field,
)
from designlab.navigation.methods import METHOD, METHODS
from designlab.navigation.noise import SensorNoise
from designlab.navigation.parameters import (
    ARRIVAL_TOLERANCE,
    DYNAMICS_STEP,
    MAX_SUBSTEPS,
    HolonomicRobot,
    NonholonomicRobot,
)
from designlab.navigation.recovery import critical_response
from designlab.navigation.scenarios import Scenario
from designlab.params import check_size
from designlab.sx import CompiledLanes, try_compile_lanes, with_cse
from designlab.sx.functions import BufferedFunction, cached_function

Array = NDArray[np.float64]

_STEP_OUT = (
    "X",
    "power",
    "D",
    "F",
    "critical",
    "V",
    "Vdot0",
    "Omega",
    "vL2",
    "FL",
    "g",
    "active",
    "d",
    "sigma",
    "Dmin",
    "gmin",
    "Esum",
)


def _field_velocity(robot: HolonomicRobot | NonholonomicRobot, x0: ca.SX) -> ca.SX:
    if isinstance(robot, HolonomicRobot):
        return x0[0:4]
    return ca.vertcat(x0[0], x0[1], x0[3] * ca.cos(x0[2]), x0[3] * ca.sin(x0[2]))


_EPS2 = NORM_EPS**2  # the eps**2 of the field's norm, so lean minima equal the recorded ones
# common subexpressions are evaluated once (exact: the same operation on the same operands)
_CSE = {"cse": True}
_LEAN_OUT = ("Xend", "critical", "Dmin", "Esum", "hit")
_HIT_MARGIN = 1e-9
_SHARED = [1, 2, 4, 5, 6, 7]  # inputs common to a batch: goal, obs, params, osub, fforce, tol


@lru_cache(maxsize=64)
def build_step(
    geometries: tuple[ObstacleGeometry, ...],
    robot: HolonomicRobot | NonholonomicRobot,
    method: str,
    n_sub: int,
    dt: float,
    lean: bool = False,
    stabilising: bool | None = None,
) -> ca.Function:
    """Field + hold + distances for one navigation period, as one SX function.

    ``stabilising`` True / False bakes the stabilising-force switch into the function
    (``params[2]`` is then ignored), so that with the force off its automatic-differentiation
    terms are not evaluated at all; ``None`` reads the switch from ``params[2]``.

    The full variant returns every dynamics step (for recorded runs); the lean one
    only what a batch needs: the final state, the period's minimum distances and
    energy, and whether the robot may have come within ``tol`` of the goal (``hit``, a
    test on the squared distance with a margin of 1e-9 ``tol``, so never missing a
    passage). The simulator recomputes the one period of a run where ``hit`` is set with
    the full variant, which decides, to stop its minima and energy at the first passage.
    """
    n = len(geometries)
    nx = state_size(robot)
    x0 = ca.SX.sym("x0", nx)
    goal = ca.SX.sym("goal", 2)
    obs = ca.SX.sym("obs", 6 * n)
    gains = ca.SX.sym("gains", 4)
    params = ca.SX.sym("params", 4)
    osub = ca.SX.sym("osub", 2 * n, n_sub)
    fforce = ca.SX.sym("fforce", 3)  # (use_override, Fx, Fy): the CBF filter's force
    tol = ca.SX.sym("tol")
    field = build_field(geometries, method)
    hold = build_hold(robot, n_sub, dt)
    dist = build_distance(geometries)
    fparams = params
    if stabilising is not None:
        fparams = ca.vertcat(params[0], params[1], ca.SX(1.0 if stabilising else 0.0), params[3])
    out = field(x=_field_velocity(robot, x0), goal=goal, obs=obs, gains=gains, params=fparams)
    F = ca.if_else(fforce[0], fforce[1:3], out["F"])
    F, brake = critical_response(geometries, robot, x0, obs, F, n_sub * dt)
    ho = hold(x0=x0, F=F, brake=brake)
    X = ho["X"]
    if n and not lean:
        D = ca.horzcat(*[dist(X[0:2, k], osub[:, k]) for k in range(n_sub)])
    else:
        D = ca.SX(0, n_sub)
    gd2 = (X[0, :] - goal[0]) ** 2 + (X[1, :] - goal[1]) ** 2
    names_in = ["x0", "goal", "obs", "gains", "params", "osub", "fforce", "tol"]
    ins = [x0, goal, obs, gains, params, osub, fforce, tol]
    if not lean:
        gd = ca.sqrt(gd2)
        dmin = ca.vertcat(*[ca.mmin(D[i, :]) for i in range(n)]) if n else ca.SX(0, 1)
        outs = (
            [X, ho["power"], D, F]
            + [out[k] for k in _STEP_OUT[4:14]]
            + [dmin, ca.mmin(gd), ca.sum2(ho["power"])]
        )
        return ca.Function(
            f"step_{method}_{robot.kind}_{n}", ins, outs, names_in, list(_STEP_OUT), _CSE
        )
    # Minima over the whole period, taken on the squared distances and rooted once
    # (bit-identical to the minimum of the roots, the root being monotone).
    dist2 = build_distance(geometries, squared=True)
    if n:
        D2 = ca.horzcat(*[dist2(X[0:2, k], osub[:, k]) for k in range(n_sub)])
        dmins = ca.vertcat(*[ca.sqrt(ca.mmin(D2[i, :]) + _EPS2) for i in range(n)])
    else:
        dmins = ca.SX(0, 1)
    # goal test on the squared distance, with a margin of 1e-9 tol: a superset of the
    # steps with sqrt(.) <= tol (the root is correctly rounded); the full variant decides
    hit = ca.mmin(gd2) <= (tol * (1.0 + _HIT_MARGIN)) ** 2
    outs = [X[:, -1], out["critical"], dmins, ca.sum2(ho["power"]), hit]
    return ca.Function(
        f"lean_{method}_{robot.kind}_{n}", ins, outs, names_in, list(_LEAN_OUT), _CSE
    )


@lru_cache(maxsize=512)  # a batch makes calls of every size as its members arrive
def _compiled(
    geometries: tuple[ObstacleGeometry, ...],
    robot: HolonomicRobot | NonholonomicRobot,
    method: str,
    n_sub: int,
    dt: float,
    n_batch: int,
    lean: bool,
    stabilising: bool | None = None,
) -> ca.Function:
    """The step for ``n_batch`` members on CasADi's virtual machine (mapped over them)."""
    f = build_step(geometries, robot, method, n_sub, dt, lean, stabilising)
    if n_batch > 1:
        f = f.map(f"{f.name()}_map{n_batch}", "serial", n_batch, _SHARED, [])
    return f


@lru_cache(maxsize=16)
def _lane_step(
    geometries: tuple[ObstacleGeometry, ...],
    robot: HolonomicRobot | NonholonomicRobot,
    method: str,
    n_sub: int,
    dt: float,
    stabilising: bool,
) -> CompiledLanes | None:
    """The lean step compiled to evaluate four members per pass (``None``: no C compiler).

    Equal to the virtual machine to the bit (:mod:`designlab.sx`), and 2-7x faster per
    member than CasADi's scalar code mapped over the batch; cached on disk, so a second
    process or run loads it instead of compiling.
    """
    f = cached_function(  # a later process loads the built step (designlab.sx.functions)
        repr(("lean step", geometries, robot, method, n_sub, dt, stabilising)),
        lambda: with_cse(build_step(geometries, robot, method, n_sub, dt, True, stabilising)),
        (str(Path(__file__).parent), str(Path(with_cse.__code__.co_filename).parent)),
    )
    return try_compile_lanes(f, _SHARED)


def _step_call(
    geometries: tuple[ObstacleGeometry, ...],
    robot: HolonomicRobot | NonholonomicRobot,
    method: str,
    n_sub: int,
    dt: float,
    n: int,
    jit: bool,
    lean: bool,
    stabilising: bool,
) -> BufferedFunction:
    """The step for ``n`` members: with ``jit``, a lean step compiled to four lanes (where a C
    compiler exists), else CasADi's (mapped) function on its virtual machine (the same results;
    a recorded run's full step is not compiled: it runs once, compiling it costs far more)."""
    if jit and lean:
        lanes = _lane_step(geometries, robot, method, n_sub, dt, stabilising)
        if lanes is not None:
            return _Lanes(lanes, n)
    return BufferedFunction(
        _compiled(geometries, robot, method, n_sub, dt, n, lean, stabilising if lean else None)
    )


class _Lanes(BufferedFunction):
    """A lane-compiled lean step bound to ``n`` members: the arrays and views of the
    function mapped over ``n`` members (member after member), evaluated four at a time."""

    def __init__(self, lanes: CompiledLanes, n: int) -> None:
        self._call = lanes.bind(n)
        self.inp, self.out = self._call.inp, self._call.out
        f = self.f = lanes.f
        self.shape_in = [
            (f.size1_in(i), f.size2_in(i) * (1 if i in lanes.shared else n))
            for i in range(f.n_in())
        ]
        self.shape_out = [(f.size1_out(o), f.size2_out(o) * n) for o in range(f.n_out())]

    def __call__(self) -> None:
        self._call()


@dataclass
class RawRun:
    """Arrays of a (batched) run; the public results are built from it.

    Attributes
    ----------
    arrival_time
        First arrival time of each gain set in s (inf if it never arrives), (N,).
    min_distance
        Minimum distance to each obstacle in m (as in :class:`NavigationResult`), (N, n_obs).
    energy
        Control energy of each run (Sec. 5.6), (N,).
    critical_time
        Time spent inside a critical region in s, (N,).
    t_end
        Simulated time in s.
    record
        Time histories (with ``record=True``), else ``None``.
    """

    arrival_time: Array  # (N,)
    min_distance: Array  # (N, n_obs)
    energy: Array  # (N,)
    critical_time: Array  # (N,)
    t_end: float
    record: dict[str, Any] | None


def obstacle_tracks(scenario: Scenario, times: Array) -> tuple[Array, Array, Array]:
    """Positions, velocities, accelerations of every obstacle at ``times``.

    Each array has the shape (n_obs, len(times), 2).

    Parameters
    ----------
    scenario
        The scenario.
    times
        Times in s.
    """
    if not scenario.obstacles:
        z = np.zeros((0, times.size, 2))
        return z, z, z
    ps, vs, accs = zip(*(o.state(times) for o in scenario.obstacles), strict=True)
    return np.stack(ps), np.stack(vs), np.stack(accs)


def initial_state(scenario: Scenario) -> Array:
    """The robot's start state for ``scenario`` (its start pose, at rest).

    Parameters
    ----------
    scenario
        The scenario.
    """
    if isinstance(scenario.robot, HolonomicRobot):
        return np.array([*scenario.start, 0.0, 0.0])
    return np.array([*scenario.start, scenario.heading0, 0.0, 0.0])


def _check_timing(
    scenario: Scenario, arrival_tolerance: float, dynamics_step: float, force_every_step: bool
) -> tuple[float, float, int]:
    """(tolerance, dynamics step, dynamics steps per period), checked."""
    tol = ARRIVAL_TOLERANCE.check(arrival_tolerance)
    dt = DYNAMICS_STEP.check(dynamics_step)
    ts = scenario.sample_time
    ratio = ts / dt
    if abs(ratio - round(ratio)) > 1e-6 or round(ratio) < 1 or round(ratio) > MAX_SUBSTEPS:
        raise InvalidParameterError(
            "dynamics_step",
            dynamics_step,
            f"must divide the sample time {ts} s into 1 to {MAX_SUBSTEPS} whole steps",
            "s",
        )
    return tol, dt, 1 if force_every_step else round(ratio)


def run(
    scenario: Scenario,
    gains: Array,
    *,
    method: str = METHOD.default,
    stabilising: bool = True,
    tie: int = 1,
    arrival_tolerance: float = ARRIVAL_TOLERANCE.default,
    dynamics_step: float = 1e-3,
    force_every_step: bool = False,
    record: bool = False,
    jit: bool = False,
    cbf_gains: tuple[float, float] = (4.0, 4.0),
    noise: SensorNoise | None = None,
) -> RawRun:
    """Simulate ``scenario`` for each row of ``gains`` (N, 4) together.

    Parameters
    ----------
    scenario
        The scenario.
    gains
        (N, 4) rows of (K1, b, K3, K5), simulated together.
    method
        A force-field method of :data:`~designlab.navigation.methods.METHODS`.
    stabilising
        Whether the Lyapunov stabilising force F_L of (5.4.6) is on.
    tie
        Detour side (+1 or -1) when the direction rules leave it open.
    arrival_tolerance
        Arrival radius around the goal in m.
    dynamics_step
        Integration step in s (must divide the sample time).
    force_every_step
        Recompute the force at every dynamics step instead of holding it for T_s.
    record
        Keep the time histories (for plots and the stability audit).
    jit
        Compile the step to four members per pass (:mod:`designlab.sx`; CasADi's
        virtual machine where no C compiler exists, with the same results).
    cbf_gains
        (k_0, k_1) of the CBF constraint (a ``filtered`` method: ``"cbf"``, ``"vff_cbf"``).
    noise
        Measurement noise of what the field sees (:class:`SensorNoise`; single runs only).
    """
    tol, dt, n_sub = _check_timing(scenario, arrival_tolerance, dynamics_step, force_every_step)
    period = n_sub * dt
    gains = np.atleast_2d(np.asarray(gains, dtype=float))
    N = gains.shape[0]
    variant = METHODS.get(method, force_field=True)
    if not variant.batched and N != 1:
        raise InvalidParameterError(
            "method", method, f"{method!r} solves one QP per step and is not batched"
        )
    geos = tuple(ObstacleGeometry.of(o) for o in scenario.obstacles)
    n_samples = math.ceil(scenario.horizon / period - 1e-9)
    if record:  # the histories: state, power, distances, obstacle positions per step
        per_step = state_size(scenario.robot) + 1 + 3 * len(geos)
        check_size(
            "Scenario.horizon", scenario.horizon, n_samples * n_sub * per_step,
            what="the recorded run (horizon / dynamics_step steps)",
        )  # fmt: skip
    if noise is not None and N != 1:
        raise InvalidParameterError("noise", noise, "is simulated one run at a time")
    if not record and N > 1:
        return _run_batch(
            scenario, gains, geos, method, n_sub, dt, tol, stabilising, tie, jit, n_samples
        )
    run = _SingleRun(scenario, gains, geos, method, n_sub, dt, tol, stabilising, tie, jit, record)
    run.cbf = None
    if variant.filtered:
        run.cbf = CBFFilter(geos, scenario.robot, cbf_gains, nominal=method,
                            stabilising=stabilising, tie=tie, period=period)  # fmt: skip
    if noise is not None:
        run.noise = (noise, noise.generator(), np.array([g.moving for g in geos], dtype=bool))
    tracks = _Tracks(scenario, n_samples, n_sub, dt, keep=record)
    k_done = run.recorded(tracks, n_samples) if record else run.lean(tracks, n_samples)
    record_out = None
    if run.rec is not None:
        P = np.concatenate(tracks.P_all, axis=1)
        record_out = _assemble(run.rec, n_sub, period, dt, P, state_size(scenario.robot))
        record_out["stab"] = 1.0 if stabilising else 0.0
        record_out["period"] = period
    return RawRun(run.arrival, run.dmin, run.energy, run.crit_time, k_done * period, record_out)


_RECORDED = ("F", "critical", "V", "Vdot0", "Omega", "vL2", "FL", "g", "active", "sigma")
_RECORDED_OUT = (3, 4, 5, 6, 7, 8, 9, 10, 11, 13)  # their outputs of the full step


class _SingleRun:
    """One run (or a recorded batch): the step bound to its inputs and the running results."""

    def __init__(
        self,
        scenario: Scenario,
        gains: Array,
        geos: tuple[ObstacleGeometry, ...],
        method: str,
        n_sub: int,
        dt: float,
        tol: float,
        stabilising: bool,
        tie: int,
        jit: bool,
        record: bool,
    ) -> None:
        robot = scenario.robot
        N = gains.shape[0]
        self.scenario, self.gains, self.n_sub, self.dt, self.tol = scenario, gains, n_sub, dt, tol
        self.N, self.n_obs, self.nx = N, len(geos), state_size(robot)
        # lean steps bake the stabilising switch in: with the force off, its AD terms drop
        f = self.f = _step_call(
            geos, robot, method, n_sub, dt, N, jit, not record, bool(stabilising)
        )
        f.view_in(7)[:, 0] = tol
        f.view_in(1)[:, 0] = scenario.goal
        f.view_in(3)[:, :] = gains.T
        f.view_in(4)[:, 0] = (robot.mass, float(tie), 1.0 if stabilising else 0.0, robot.max_accel)
        f.view_in(6)[:, 0] = 0.0
        self.X = np.tile(initial_state(scenario)[:, None], (1, N))
        f.view_in(0)[:, :] = self.X
        self.arrival = np.full(N, np.inf)
        self.dmin = np.full((N, self.n_obs), np.inf)
        self.energy = np.zeros(N)
        self.crit_time = np.zeros(N)
        if self.n_obs:
            start_d = np.array(
                [
                    float(o.contour_distance(np.array([scenario.start]))[0])
                    for o in scenario.obstacles
                ]
            )
            self.dmin[:] = start_d[None, :]
        self.rec: dict[str, list[Any]] | None = None
        if record:
            self.rec = {k: [] for k in ("X", "D", "power", *_RECORDED, "x_sample", "qp_status")}
        else:
            self.arrival_period = _ArrivalPeriod(f, geos, robot, method, n_sub, dt, tol)
        self.cbf: CBFFilter | None = None
        self.noise: tuple[SensorNoise, np.random.Generator, NDArray[np.bool_]] | None = None

    def _inputs(self, tracks: _Tracks, k: int) -> None:
        """The obstacles of period ``k`` (as measured) and, with the CBF filter, its force."""
        f = self.f
        obs_k, osub_k = tracks.at(k)
        if self.noise is not None:
            model, rng, moving = self.noise
            obs_k, goal = model.measure(rng, obs_k, np.asarray(self.scenario.goal), moving)
            f.view_in(1)[:, 0] = goal
        if self.n_obs:
            f.view_in(2)[:, 0] = obs_k
            f.inp[5][:] = osub_k
        if self.rec is not None:
            f.view_in(0)[:, :] = self.X
        if self.cbf is not None:
            x = f.view_in(0)[:, 0].copy()
            goal = f.view_in(1)[:, 0].copy()  # the measured goal (with noise, seen from the robot)
            force = self.cbf.force(
                x, goal, self.gains[0], obs_k, self.scenario.robot, self.scenario
            )
            f.view_in(6)[:, 0] = force

    def lean(self, tracks: _Tracks, n_samples: int) -> int:
        """A single lean run: scalar bookkeeping (it spends its time in the step)."""
        f, n_obs = self.f, self.n_obs
        o_crit, o_dmin, o_esum, o_hit = (f.view_out(i) for i in range(1, 5))
        o_crit, o_esum, o_hit = (a.reshape(-1) for a in (o_crit, o_esum, o_hit))
        dmin0 = self.dmin[0]
        e_sum = c_sum = 0.0
        k_done = 0
        for k in range(n_samples):
            self._inputs(tracks, k)
            f()
            c_sum += float(o_crit[0])
            k_done = k + 1
            first = self.arrival_period(0) if o_hit[0] > 0.5 else None
            if first is not None:  # stop the minima and the energy at the first passage
                count, dm, es = first
                if n_obs:
                    np.minimum(dmin0, dm, out=dmin0)
                e_sum += es
                self.arrival[0] = (k * self.n_sub + count) * self.dt
                break
            if n_obs:
                np.minimum(dmin0, o_dmin[:, 0], out=dmin0)
            e_sum += float(o_esum[0])
            np.copyto(f.inp[0], f.out[0])
        self.energy[0] += e_sum * self.dt
        self.crit_time[0] += c_sum * (self.n_sub * self.dt)
        return k_done

    def recorded(self, tracks: _Tracks, n_samples: int) -> int:
        """A run with its time histories (every dynamics step of every period)."""
        live = np.ones(self.N, bool)
        k_done = 0
        for k in range(n_samples):
            self._inputs(tracks, k)
            self.f()
            Xs = self._period(k, live)
            self.X = Xs[:, -1, :].copy()
            k_done = k + 1
            if not live.any():
                break
        return k_done

    def _period(self, k: int, live: NDArray[np.bool_]) -> Array:
        """Accumulate one recorded period; return its states ``(nx, n_sub, N)``."""
        f, N, n_sub, n_obs, dt, tol = self.f, self.N, self.n_sub, self.n_obs, self.dt, self.tol
        outX, outP, outD = f.view_out(0), f.view_out(1), f.view_out(2)
        if N > 1:  # mapped layout: columns are [member 0 steps..., member 1 steps..., ...]
            Xs = outX.reshape(self.nx, N, n_sub).transpose(0, 2, 1)
            Ds = outD.reshape(n_obs, N, n_sub).transpose(0, 2, 1)
            Pw = outP.reshape(N, n_sub).T
        else:
            Xs = outX[:, :, None]
            Ds = outD[:, :, None]
            Pw = outP.reshape(n_sub, 1)
        arriving = live & (f.view_out(15).reshape(-1) <= tol)
        if arriving.any():
            goal = np.asarray(self.scenario.goal)
            gx, gy = Xs[0] - goal[0], Xs[1] - goal[1]
            gd = np.sqrt(gx * gx + gy * gy)  # (n_sub, N), the same operations as the step's
            hit = gd <= tol
            first = np.where(hit.any(axis=0), hit.argmax(axis=0), n_sub)
            upto = np.where(live, np.minimum(first + 1, n_sub), 0)
            mask = np.arange(n_sub)[:, None] < upto[None, :]  # (n_sub, N)
            if n_obs:
                dm = np.where(mask[None, :, :], Ds, np.inf).min(axis=1)
                self.dmin = np.minimum(self.dmin, dm.T)
            self.energy += np.where(mask, Pw, 0.0).sum(axis=0) * dt
            self.arrival[arriving] = (k * n_sub + first[arriving] + 1) * dt
        else:
            if n_obs:
                self.dmin[live] = np.minimum(self.dmin[live], Ds.min(axis=1).T[live])
            self.energy[live] += Pw.sum(axis=0)[live] * dt
        self.crit_time[live] += f.view_out(4).reshape(-1)[live] * (n_sub * dt)
        live &= ~arriving
        self._keep(Xs, Ds, Pw)
        return Xs

    def _keep(self, Xs: Array, Ds: Array, Pw: Array) -> None:
        """Append the first member's period to the records."""
        rec = self.rec
        assert rec is not None
        rec["x_sample"].append(self.X[:, 0].copy())
        rec["X"].append(Xs[:, :, 0].copy())
        rec["D"].append(Ds[:, :, 0].copy())
        rec["power"].append(Pw[:, 0].copy())
        for name, idx_out in zip(_RECORDED, _RECORDED_OUT, strict=True):
            rec[name].append(self.f.view_out(idx_out)[:, 0].copy())
        rec["qp_status"].append(self.cbf.last_status if self.cbf is not None else "")


class _Tracks:
    """Obstacle inputs of each navigation period, computed 2 s of simulated time at a time."""

    def __init__(
        self, scenario: Scenario, n_samples: int, n_sub: int, dt: float, keep: bool = False
    ) -> None:
        self.scenario, self.n_samples, self.n_sub, self.dt = scenario, n_samples, n_sub, dt
        self.chunk = max(1, round(2.0 / (n_sub * dt)))
        self.n_obs = len(scenario.obstacles)
        self.keep = keep
        self.P_all: list[Array] = []  # the positions at every dynamics step (with ``keep``)
        self.OBS = self.OSUB = np.zeros((0, 0))

    def at(self, k: int) -> tuple[Array, Array]:
        """(positions, velocities, accelerations at the period start; positions at its steps)."""
        chunk, n_sub, n_obs = self.chunk, self.n_sub, self.n_obs
        kc = k % chunk
        if kc == 0:
            t_grid = (k * n_sub + np.arange(chunk * n_sub + 1)) * self.dt
            P, Vo, Ao = obstacle_tracks(self.scenario, t_grid)
            if self.keep:
                self.P_all.append(P[:, :-1] if k + chunk < self.n_samples else P)
            starts = np.arange(chunk) * n_sub
            OBS = np.concatenate(
                [P[:, starts], Vo[:, starts], Ao[:, starts]], axis=2
            )  # (n, chunk, 6)
            self.OBS = OBS.transpose(1, 0, 2).reshape(chunk, 6 * n_obs)
            idx = starts[:, None] + 1 + np.arange(n_sub)[None, :]  # (chunk, n_sub)
            self.OSUB = P[:, idx, :].transpose(1, 2, 0, 3).reshape(chunk, n_sub * 2 * n_obs)
        return self.OBS[kc], self.OSUB[kc]


def _run_batch(
    scenario: Scenario,
    gains: Array,
    geos: tuple[ObstacleGeometry, ...],
    method: str,
    n_sub: int,
    dt: float,
    tol: float,
    stabilising: bool,
    tie: int,
    jit: bool,
    n_samples: int,
) -> RawRun:
    """A batch of gain sets without records: one mapped call per period over the live members.

    Once members arrive, the call is remade for the members still on their way (each
    member's arithmetic is its own, so the results do not depend on who else is in the call).
    """
    robot = scenario.robot
    N, n_obs, period = gains.shape[0], len(geos), n_sub * dt
    params = (robot.mass, float(tie), 1.0 if stabilising else 0.0, robot.max_accel)

    def call(n: int) -> BufferedFunction:
        f = _step_call(geos, robot, method, n_sub, dt, n, jit, True, bool(stabilising))
        f.view_in(1)[:, 0] = scenario.goal
        f.view_in(4)[:, 0] = params
        f.view_in(6)[:, 0] = 0.0
        f.view_in(7)[:, 0] = tol
        return f

    f = call(N)
    f.view_in(0)[:, :] = initial_state(scenario)[:, None]
    f.view_in(3)[:, :] = gains.T
    arrival_period = _ArrivalPeriod(f, geos, robot, method, n_sub, dt, tol)
    arrival = np.full(N, np.inf)
    dmin = np.full((N, n_obs), np.inf)
    if n_obs:
        dmin[:] = [
            float(o.contour_distance(np.array([scenario.start]))[0]) for o in scenario.obstacles
        ]
    energy = np.zeros(N)
    crit_time = np.zeros(N)
    lanes = np.arange(N)  # the members in the call, in its order
    # their running minima, energies and critical times (one row or entry per member in the call)
    dm, en, ct = dmin.copy(), energy.copy(), crit_time.copy()
    tracks = _Tracks(scenario, n_samples, n_sub, dt)
    k_done = 0
    while True:  # one pass per set of members in the call
        k_done, found = _batch_periods(f, tracks, k_done, n_samples, (dm, en, ct), arrival_period)
        if not found:  # the horizon ends with members on their way
            dmin[lanes], energy[lanes], crit_time[lanes] = dm, en, ct
            break
        k = k_done - 1
        rest = np.ones(lanes.size, bool)
        for j, (count, dm_j, es) in found.items():
            rest[j] = False
            i = lanes[j]
            dmin[i] = np.minimum(dm[j], dm_j)
            energy[i] = en[j] + es * dt
            crit_time[i] = ct[j]
            arrival[i] = (k * n_sub + count) * dt
        if not rest.any() or k_done == n_samples:
            _close_period(f, dm, en, dt)
            dmin[lanes[rest]], energy[lanes[rest]], crit_time[lanes[rest]] = (
                dm[rest],
                en[rest],
                ct[rest],
            )
            break
        # the members still on their way continue in a call of their size
        _close_period(f, dm, en, dt)
        lanes, dm, en, ct = lanes[rest], dm[rest], en[rest], ct[rest]
        x_next, g_next = f.view_out(0)[:, rest], f.view_in(3)[:, rest]
        f = call(lanes.size)
        f.view_in(0)[:, :] = x_next
        f.view_in(3)[:, :] = g_next
        arrival_period.lean = f
    return RawRun(arrival, dmin, energy, crit_time, k_done * period, None)


def _close_period(f: BufferedFunction, dm: Array, en: Array, dt: float) -> None:
    """Take the call's last period into the running minima and energies (in place)."""
    np.minimum(dm, f.view_out(2).T, out=dm)
    en += np.multiply(f.out[3], dt, out=np.empty(en.shape[0]))


def _batch_periods(
    f: BufferedFunction,
    tracks: _Tracks,
    k_done: int,
    n_samples: int,
    running: tuple[Array, Array, Array],
    arrival_period: _ArrivalPeriod,
) -> tuple[int, dict[int, tuple[int, Array, float]]]:
    """Step the members in the call until some arrive: (periods done, {member: arrival}).

    The running minima, energies and critical times are updated in place.
    """
    dm, en, ct = running
    n_obs, period, dt = tracks.n_obs, tracks.n_sub * tracks.dt, tracks.dt
    # the call's arrays, bound once: this loop is the batch's whole Python overhead
    x_in, x_out, obs_in, osub_in = f.inp[0], f.out[0], f.inp[2], f.inp[5]
    o_crit, o_esum, o_hit = f.out[1], f.out[3], f.out[4]
    o_dmin = f.view_out(2).T  # (members, n_obs)
    tmp = np.empty(dm.shape[0])
    found: dict[int, tuple[int, Array, float]] = {}
    for k in range(k_done, n_samples):
        obs_k, osub_k = tracks.at(k)
        if n_obs:
            obs_in[:] = obs_k
            osub_in[:] = osub_k
        f()
        k_done = k + 1
        ct += np.multiply(o_crit, period, out=tmp)
        if o_hit.any():
            for j in np.flatnonzero(o_hit > 0.5):
                first = arrival_period(j)
                if first is not None:  # (else a last-bit disagreement: keep going)
                    found[int(j)] = first
            if found:
                break
        np.minimum(dm, o_dmin, out=dm)
        en += np.multiply(o_esum, dt, out=tmp)
        np.copyto(x_in, x_out)
    return k_done, found


def _assemble(
    rec: dict[str, list[Any]], n_sub: int, period: float, dt: float, P: Array, nx: int
) -> dict[str, Any]:
    K = len(rec["X"])
    X = np.concatenate(rec["X"], axis=1)  # (nx, K*n_sub)
    t = np.arange(1, K * n_sub + 1) * dt
    out: dict[str, Any] = {
        "t": np.concatenate([[0.0], t]),
        "X": np.concatenate([rec["x_sample"][0][:, None], X], axis=1),
        "D": np.concatenate(rec["D"], axis=1)
        if rec["D"] and rec["D"][0].size
        else np.zeros((0, K * n_sub)),
        "power": np.concatenate(rec["power"]),
        "t_sample": np.arange(K) * period,
        "x_sample": np.array(rec["x_sample"]),
        "obstacle_positions": P[:, : K * n_sub + 1, :],
        "qp_status": rec["qp_status"],
    }
    for k in ("F", "critical", "V", "Vdot0", "Omega", "vL2", "FL", "g", "active", "sigma"):
        out[k] = np.array(rec[k])
    return out


class _ArrivalPeriod:
    """Recompute the period in which a member reaches the goal with the full step function.

    The lean step reports minima and energy over a whole period and only whether the
    goal was reached in it; for that one period per run, the full step gives every
    dynamics step, so the minima and the energy stop at the first passage exactly.
    """

    def __init__(
        self,
        lean: BufferedFunction,
        geos: tuple[ObstacleGeometry, ...],
        robot: HolonomicRobot | NonholonomicRobot,
        method: str,
        n_sub: int,
        dt: float,
        tol: float,
    ) -> None:
        self.lean = lean
        self.full = BufferedFunction(_compiled(geos, robot, method, n_sub, dt, 1, False))
        self.nx = state_size(robot)
        self.tol = tol
        self.n_obs = len(geos)

    def __call__(self, i: int) -> tuple[int, Array, float] | None:
        """(steps up to and including the first passage, minima, energy sum) or None."""
        full, lean, nx = self.full, self.lean, self.nx
        full.inp[0][:] = lean.inp[0][nx * i : nx * (i + 1)]  # the member's state
        full.inp[3][:] = lean.inp[3][4 * i : 4 * (i + 1)]  # its gains
        for j in _SHARED:
            full.inp[j][:] = lean.inp[j]
        full()
        X = full.view_out(0)
        gx, gy = X[0] - lean.inp[1][0], X[1] - lean.inp[1][1]
        hits = np.flatnonzero(np.sqrt(gx * gx + gy * gy) <= self.tol)
        if not hits.size:
            return None
        count = int(hits[0]) + 1
        power = full.view_out(1).reshape(-1)
        dm = full.view_out(2)[:, :count].min(axis=1) if self.n_obs else np.zeros(0)
        return count, dm, float(power[:count].sum())
