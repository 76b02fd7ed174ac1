"""The robot among JuPedSim's pedestrians, advanced in lock-step (see the package's text).

Per navigation period [t_k, t_k + T_s]:

1. the robot's field reads the pedestrians' state at t_k (positions, and velocities and
   accelerations from backward differences of positions up to t_k) through the K nearest
   slots (:mod:`~designlab.navigation.crowds.slots`) and the walls, and the compiled step
   integrates the robot over the period (the force held, 1 ms dynamics steps);
2. JuPedSim advances the pedestrians by T_s / dt_p steps; when they avoid the robot, its
   agent is steered before every pedestrian step to where the robot is at the end of that
   step (known from 1), so the pedestrians see the robot of the same instant;
3. distances to every pedestrian (positions interpolated linearly within a pedestrian step)
   and wall are measured at every dynamics step.

Neither side reads the other's state from the future nor from the past period: swapping 1 and
2 (``order="pedestrians_first"``) gives the same run when the pedestrians ignore the robot
(when they avoid it they then see the robot's position at t_k over the whole period).
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from itertools import combinations
from typing import Any

import casadi as ca
import numpy as np
import shapely
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.navigation.cbf_filter import CBFFilter
from designlab.navigation.criteria import EQUAL_WEIGHTS
from designlab.navigation.crowds.bookkeeping import area_edges, fill_candidates, period_measures
from designlab.navigation.crowds.field_metrics import first_entry, wall_distances
from designlab.navigation.crowds.pedestrians import PedestrianSim
from designlab.navigation.crowds.results import CrowdResult, CrowdStatus, PedestrianRun
from designlab.navigation.crowds.scenario import CrowdScenario
from designlab.navigation.crowds.slots import crowd_step, fill_slots
from designlab.navigation.dynamics import HOLONOMIC_FEEDFORWARD
from designlab.navigation.field import ObstacleGeometry
from designlab.navigation.methods import CROWD_METHOD, METHODS, STABILISING, TIE_SIDE
from designlab.navigation.parameters import (
    ARRIVAL_TOLERANCE,
    DYNAMICS_STEP,
    HolonomicRobot,
    check_cbf_gains,
)
from designlab.params import Param, check_size
from designlab.sx.functions import BufferedFunction
from designlab.sx.jit import AVAILABLE, say_no_jit

__all__ = [
    "AGENT_OFFSET_BOUND",
    "CROWD_METHOD",
    "ORDER",
    "OUTCOMES",
    "CrowdResult",
    "CrowdStatus",
    "PedestrianRun",
    "accepts_crowds",
    "simulate_crowd",
    "simulate_pedestrians",
]

Array = NDArray[np.float64]

#: Which side of the lock-step moves first in a period (the same run when pedestrians ignore
#: the robot; ``"robot_first"`` lets avoiding pedestrians see the robot of the same instant).
ORDER = Param(
    doc="lock-step order", kind="choice", choices=("robot_first", "pedestrians_first"), name="order"
)
#: Largest distance between the robot and its JuPedSim agent for which a run's pedestrians
#: count as seeing the robot where it is, m; a run beyond it is flagged
#: (``CrowdResult.coupling_exceeded``, a warning) and studies count it apart.
AGENT_OFFSET_BOUND = 0.02
#: Outcomes of a run, exclusive: the first of its events (a collision, the robot leaving the
#: walkable area, the pedestrian simulator failing, the arrival), ``timeout`` if none.
OUTCOMES = ("arrived", "collision", "timeout", "left_area", "simulator_failed")
#: Pedestrians that may enter a run per pedestrian initially in it (a cap of the records).
_INFLOW_FACTOR = 8
#: Whether runs use the compiled bookkeeping (:mod:`~designlab.navigation.crowds.bookkeeping`);
#: without numba, the numpy path (the same results, bit for bit).
COMPILED = AVAILABLE


# ------------------------------------------------------------------ the run
class _Frames:
    """Pedestrian positions by index at the last ``depth`` pedestrian steps (a ring)."""

    def __init__(self, capacity: int, depth: int) -> None:
        self.ring = np.full((max(depth, 3), capacity, 2), np.nan)
        self.ptr = -1
        self.count = 0  # rows in use (pedestrians that have entered)
        self._idx: dict[tuple[int, int], NDArray[np.int64]] = {}  # (n, ptr) -> ring rows

    def push(self, ids: NDArray[np.int64], P: Array, count: int) -> None:
        """Add the positions of a step; ``count``: pedestrians that have entered so far."""
        self.ptr = (self.ptr + 1) % self.ring.shape[0]
        now = self.ring[self.ptr]
        now[: self.count].fill(np.nan)
        now[ids] = P
        self.count = count

    def rows(self, n: int) -> NDArray[np.int64]:
        """The ring rows of the last ``n`` frames, oldest first."""
        idx = self._idx.get((n, self.ptr))
        if idx is None:
            idx = (self.ptr - np.arange(n - 1, -1, -1)) % self.ring.shape[0]
            self._idx[n, self.ptr] = idx
        return idx

    def last(self, n: int) -> Array:
        """The last ``n`` frames, oldest first, ``(n, count, 2)``."""
        return self.ring[self.rows(n), : self.count]

    def sensed(self) -> Array:
        """The last three frames ``(3, count, 2)`` (a copy: later steps do not touch it)."""
        return self.last(3)


def _derivatives(F: Array, dt: float) -> tuple[Array, Array, Array]:
    """Positions, velocities and accelerations at the last of three frames ``F``
    ``(3, n, 2)`` of pedestrians in the simulation now (backward differences; 0 where an
    earlier frame is unknown)."""
    prev2, prev, now = F
    V = (now - prev) / dt
    A = (V - (prev - prev2) / dt) / dt
    np.copyto(V, 0.0, where=np.isnan(V))
    np.copyto(A, 0.0, where=np.isnan(A))
    return now, V, A


def _slot_rows(F: Array, d2: list[float], dt: float) -> list[list[float]]:
    """Slot rows (position, velocity, acceleration) of the few pedestrians of ``F``
    ``(3, n, 2)``, nearest first (a stable sort of ``d2``): :func:`_derivatives` in plain
    floats, the same IEEE operations without a numpy call per step of the sum."""
    rows = []
    prev2, prev, now = F.tolist()
    for i in sorted(range(len(d2)), key=d2.__getitem__):
        (a, b), (c, d), (x, y) = prev2[i], prev[i], now[i]
        vx, vy = (x - c) / dt, (y - d) / dt
        ax, ay = (vx - (c - a) / dt) / dt, (vy - (d - b) / dt) / dt
        rows.append([x, y, *(0.0 if v != v else v for v in (vx, vy, ax, ay))])
    return rows


class _Step(BufferedFunction):
    """The compiled period step on preallocated buffers."""

    def __init__(self, f: ca.Function) -> None:
        super().__init__(f)
        self.nx = f.size1_out(0)

    def __call__(self) -> Array:  # type: ignore[override]
        self._trigger()
        return self.out[0].reshape((-1, self.nx)).T.copy()  # (nx, n_sub)


@dataclass
class _Setup:
    """What a run needs, checked."""

    crowd: CrowdScenario
    method: str
    row: Array
    stabilising: str
    tie: int
    tol: float
    dt: float
    n_sub: int
    per_ped: int
    n_ped: int
    n_samples: int
    order: str
    cbf_gains: tuple[float, float]
    settings: Any = None  # a velocity-commanding method's settings (None: a force field)


def _setup(crowd: Any, gains: Any, kw: dict[str, Any]) -> _Setup:
    if not isinstance(crowd, CrowdScenario):
        raise InvalidParameterError("crowd", crowd, "must be a CrowdScenario (navigation.crowd())")
    STABILISING.check(kw["stabilising"])
    TIE_SIDE.check(kw["tie_side"])
    ORDER.check(kw["order"])
    strategy = METHODS.get(CROWD_METHOD.check(kw["method"]), crowds=True)
    row = strategy.gain_row(gains)
    settings = None if strategy.force_field else strategy.gains(gains)
    if settings is not None and not isinstance(crowd.robot, HolonomicRobot):
        raise InvalidParameterError(
            "method", strategy.name, "commands a velocity in any direction: it needs a "
            "HolonomicRobot (CrowdScenario.robot)",
        )  # fmt: skip
    cbf = check_cbf_gains(kw["cbf_gains"])
    tol = ARRIVAL_TOLERANCE.check(kw["arrival_tolerance"])
    dt = DYNAMICS_STEP.check(kw["dynamics_step"])
    ts, dtp = crowd.sample_time, crowd.pedestrian_step
    n_sub, per = round(ts / dt), round(ts / dtp)
    q = n_sub / per
    if abs(ts / dt - n_sub) > 1e-6 or abs(q - round(q)) > 1e-9 or n_sub > 1000:
        raise InvalidParameterError(
            "dynamics_step", kw["dynamics_step"],
            f"must divide the pedestrian step {dtp} s (and T_s = {ts} s) into whole steps",
            "s",
        )  # fmt: skip
    n_samples = math.ceil(crowd.time_limit / ts - 1e-9)
    cap = crowd.pedestrians * _INFLOW_FACTOR
    check_size(
        "CrowdScenario.horizon", crowd.time_limit, (n_samples * per + 1) * cap * 2,
        what="the recorded pedestrian positions",
    )  # fmt: skip
    stab = kw["stabilising"] if strategy.stabilised else "off"
    return _Setup(
        crowd, strategy.name, row, stab, strategy.tie(gains, kw["tie_side"]), tol, dt, n_sub, per,
        cap, n_samples, kw["order"], cbf, settings,
    )  # fmt: skip


class _Run:
    """The lock-step loop and its running results."""

    def __init__(self, s: _Setup) -> None:
        c = s.crowd
        self.s = s
        self.walls = c.walls()
        self.geos = (
            tuple(ObstacleGeometry.of(w) for w in self.walls)
            + (c.pedestrian_geometry(),) * c.neighbours
        )
        robot = c.robot
        strategy = METHODS.get(s.method)
        # a velocity-commanding method: the step's buffers hold the state (its field unused)
        field = s.method if strategy.force_field else "cbf"
        self.step = _Step(crowd_step(self.geos, robot, field, s.n_sub, s.dt))
        self.command = None if strategy.force_field else strategy.controller(c, s.settings)
        inp = self.step.inp
        x0 = (
            np.array([*c.robot_start, 0.0, 0.0])
            if isinstance(robot, HolonomicRobot)
            else np.array(
                [
                    *c.robot_start,
                    math.atan2(
                        c.robot_goal[1] - c.robot_start[1], c.robot_goal[0] - c.robot_start[0]
                    ),
                    0.0,
                    0.0,
                ]
            )
        )
        inp[0][:] = x0
        inp[1][:] = c.robot_goal
        self.wall_obs = (
            np.concatenate([[*w.center, 0, 0, 0, 0] for w in self.walls])
            if self.walls
            else np.zeros(0)
        )
        inp[2][: self.wall_obs.size] = self.wall_obs
        self.slots = inp[2][self.wall_obs.size :].reshape(-1, 6)  # a view
        inp[3][:] = s.row
        inp[4][:] = (
            robot.mass,
            float(s.tie),
            1.0 if s.stabilising == "lyapunov" else 0.0,
            robot.max_accel,
        )
        fixed = tuple(replace(g, r2_input=False) for g in self.geos)  # CBF reads r3 alone
        filtered = strategy.filtered
        self.cbf = CBFFilter(fixed, robot, s.cbf_gains, nominal=s.method) if filtered else None
        self.r2, self.r3 = c.pedestrian_regions()
        sized = c.region_sizing == "closing_speed"
        if sized:  # the walls' radii (fixed), then one per slot (the largest until filled)
            inp[6][:] = [g.r2 for g in self.geos]
        # CBF has no active region (its filter sees every pedestrian within the largest r2)
        self.sizing = (
            c.closing_speed_sizing() if sized and not filtered and strategy.force_field else None
        )
        self.w2, self.w3 = c.wall_regions()
        self.ped = PedestrianSim(c, c.robot_start)
        self.frames = _Frames(s.n_ped, s.per_ped + 1)
        self.ped_dt = c.pedestrian_step
        self.parked = fill_slots(np.zeros(2), np.zeros((0, 2)), *np.zeros((2, 0, 2)), r2=1.0,
                                 slots=c.neighbours)[0].reshape(-1, 6)  # fmt: skip
        q = s.n_sub // s.per_ped
        self.frac_flat = np.arange(1, q + 1) / q
        self.frac = self.frac_flat[None, :, None, None]
        self.wall_frames = np.array(
            [[*w.center, math.cos(w.angle), math.sin(w.angle), w.length / 2, w.width / 2]
             for w in self.walls]
        ).reshape(-1, 6)  # fmt: skip
        self.rec_t: list[float] = [0.0]
        self.rec_ped: list[tuple[NDArray[np.int64], Array]] = []
        self.rec_X: list[Array] = [x0[:, None]]
        self.dmin = math.inf
        self.wmin = self.wall_last = math.inf
        self.wall_rows = [tuple(float(v) for v in row) for row in self.wall_frames]
        self.crit_time = 0.0
        self.energy = 0.0
        self.overflow = 0
        self.overlaps = 0
        self.agent_offset = 0.0
        self.arrival = math.inf
        self.failure = ""
        self.ped_time = self.total_time = 0.0
        self.area = c.geometry.area
        shapely.prepare(self.area)  # point-in-area tests every period
        self.goal = np.asarray(c.robot_goal)
        self.reach = self.r2 + (robot.max_speed + c.max_desired_speed) * s.n_sub * s.dt
        self.left_area = 0.0  # when the robot was first outside the walkable area (0: never)
        self.collision_time = math.inf  # the dynamics step of the first contact
        self.collision_by = self.critical_by = "none"  # who caused them (first_entry)
        self.failure_time = math.inf
        ids, P = self.ped.positions()
        self._push(ids, P)
        self._measure_start(x0[:2], P)
        _attribute(self, np.zeros(1), x0[None, :2], np.zeros((1, 2)), P[None])
        self._compiled_setup()

    def _compiled_setup(self) -> None:
        """Buffers of the compiled bookkeeping (or the numpy path, said once, without numba)."""
        self.compiled = COMPILED
        if not COMPILED:
            say_no_jit("crowd runs' bookkeeping")
            return
        cap = self.frames.ring.shape[1]
        self.d0, self.d2 = np.empty(cap), np.empty(cap)
        self.order = np.empty(cap, np.int64)
        self.state = np.array([self.dmin, self.wmin, self.wall_last, 0.0, 0.0])
        self.edges = area_edges(self.area)  # None: not axis-aligned, shapely tests the area
        self.no_edges = np.zeros((0, 4))
        self.sense_rows = np.arange(3, dtype=np.int64)
        self.wall_slack = self.s.crowd.robot.max_speed * self.s.crowd.sample_time

    def _push(self, ids: NDArray[np.int64], P: Array) -> None:
        count = self.ped.count
        if count > self.frames.ring.shape[1]:
            raise InvalidParameterError(
                "CrowdScenario.horizon", self.s.crowd.time_limit,
                f"lets more than {self.s.n_ped} pedestrians enter (the records' cap); shorten it",
            )  # fmt: skip
        self.frames.push(ids, P, count)
        self.rec_ped.append((ids, P))

    def _measure_start(self, p: Array, P: Array) -> None:
        if P.shape[0]:
            self.dmin = float(np.min(np.hypot(P[:, 0] - p[0], P[:, 1] - p[1])))
        if self.walls:
            self.wmin = self.wall_last = _wall_distance(self.wall_frames, p[None, :])

    # ---------------------------------------------------------------- period
    def sense(self) -> Array:
        """The pedestrians' last three frames as the robot senses them now (a copy)."""
        return self.frames.sensed()

    def robot_period(self, sensed: Array) -> Array:
        """The robot over one period from the pedestrians ``sensed`` at its start.

        Only the pedestrians within r2 (the candidates of the slots) get their velocities and
        accelerations differenced: the slots are the same as from every pedestrian's.
        """
        s, inp = self.s, self.step.inp
        if self.command is not None:
            return self._command_period(sensed)
        x, y = inp[0][0], inp[0][1]
        if self.compiled and self.sizing is None:  # closing-speed radii: _sized_slots
            n, overlap = fill_candidates(
                sensed, self.sense_rows, sensed.shape[1], x, y, self.r2 * self.r2, self.ped_dt,
                self.slots, self.parked, 2 * self.r3, self.d2, self.order,
            )  # fmt: skip
            if n <= s.crowd.neighbours:
                self.overlaps += int(overlap)
                return self._step_robot()
        now = sensed[2]
        d2 = (now[:, 0] - x) ** 2 + (now[:, 1] - y) ** 2
        inside = np.flatnonzero(d2 < self.r2 * self.r2)  # NaN rows (not in) compare False
        n = inside.size
        obs = self.slots  # a view of the step's obstacle input
        if self.sizing is not None:
            n = self._sized_slots(sensed[:, inside], d2[inside])
        elif n <= s.crowd.neighbours:  # as fill_slots, on the candidates only
            obs[n:] = self.parked[n:]
            if n:
                obs[:n] = _slot_rows(sensed[:, inside], d2[inside].tolist(), self.ped_dt)
        else:
            P, V, A = _derivatives(sensed[:, inside], self.ped_dt)
            obs[:] = fill_slots(inp[0][:2], P, V, A, r2=self.r2, slots=obs.shape[0])[0].reshape(
                -1, 6
            )
            self.overflow += 1
        if min(n, s.crowd.neighbours) > 1:  # Sec. 6.4.3: two critical regions of the slots
            # intersect, no path between them is safe
            Q = obs[: min(n, s.crowd.neighbours), 0:2].tolist()
            dx, dy = zip(*((a[0] - b[0], a[1] - b[1]) for a, b in combinations(Q, 2)), strict=True)
            self.overlaps += int((np.hypot(dx, dy) < 2 * self.r3).any())
        return self._step_robot()

    def _command_period(self, sensed: Array) -> Array:
        """The robot of a velocity-commanding method over one period: the method's velocity
        from every pedestrian in the simulation (positions and backward-difference
        velocities at t_k), tracked at the acceleration limit (:func:`_track`)."""
        s, x = self.s, self.step.inp[0]
        P, V, _ = _derivatives(sensed, self.ped_dt)
        here = ~np.isnan(P[:, 0])
        P, V = P[here], V[here]
        p = x[0:2].copy()
        cmd = self.command(p, x[2:4].copy(), P, V)
        X, power = _track(x, cmd, s.crowd.robot, s.n_sub, s.dt)
        self.step.out[1][:] = power
        near = P.shape[0] and float(np.min(np.hypot(*(P - p).T))) <= self.r3
        wall = bool(self.walls) and _wall_distance(self.wall_frames, p[None, :]) <= self.w3
        self.crit_time += float(bool(near) or wall) * s.n_sub * s.dt
        return X

    def _sized_slots(self, F: Array, d2: Array) -> int:
        """Fill the slots with the pedestrians of ``F`` ``(3, n, 2)`` (those within the largest
        r2) that are inside their own closing-speed active radius, nearest first, and set
        the slots' radii (:mod:`~designlab.navigation.crowds.regions`); returns how many."""
        robot = self.step.inp[0][:2]
        P, V, A = _derivatives(F, self.ped_dt)
        r2 = self.sizing.active_radii(robot, P, V)
        keep = np.flatnonzero(d2 < r2 * r2)
        keep = keep[np.argsort(d2[keep], kind="stable")]
        K = self.s.crowd.neighbours
        if keep.size > K:
            self.overflow += 1
        use = keep[:K]
        m = use.size
        obs, radii = self.slots, self.step.inp[6][len(self.walls) :]
        obs[m:] = self.parked[m:]
        obs[:m, 0:2], obs[:m, 2:4], obs[:m, 4:6] = P[use], V[use], A[use]
        radii[:] = self.r2
        radii[:m] = r2[use]
        return int(keep.size)

    def _step_robot(self) -> Array:
        """The compiled step on the inputs set (with the CBF filter's force for CBF)."""
        s, inp = self.s, self.step.inp
        if self.cbf is not None:
            x = inp[0].copy()
            inp[5][:] = self.cbf.force(x, inp[1].copy(), s.row, inp[2].copy(), s.crowd.robot, None)
        X = self.step()
        self.crit_time += float(self.step.out[3][0]) * s.n_sub * s.dt
        return X

    def pedestrians_period(self, X: Array | None) -> bool:
        """Advance the pedestrians one period; ``X``: the robot's states over it (or None)."""
        s = self.s
        q = s.n_sub // s.per_ped
        for j in range(s.per_ped):
            target = None
            if X is not None:
                target = (float(X[0, (j + 1) * q - 1]), float(X[1, (j + 1) * q - 1]))
            elif self.ped.robot_id is not None:
                target = (float(self.step.inp[0][0]), float(self.step.inp[0][1]))
            try:
                self.ped.step(target)
            except RuntimeError as exc:
                self.failure = f"JuPedSim stopped at t = {self.ped.time:.2f} s: {exc}"
                self.failure_time = self.ped.time
                return False
            ids, P = self.ped.positions()
            self._push(ids, P)
            if target is not None and self.ped.robot_id is not None:
                off = self.ped.robot_agent_position() - np.asarray(target)
                self.agent_offset = max(self.agent_offset, float(np.hypot(*off)))
        return True

    def measure(self, k: int, X: Array) -> bool:
        """Distances over period ``k`` (see :meth:`_pedestrian_distances`); True on arrival."""
        if self.compiled:
            return self._measure_compiled(k, X)
        s = self.s
        pts = X[0:2, :].T  # (n_sub, 2): the robot at the end of each dynamics step
        goal = self.goal
        gd = np.hypot(pts[:, 0] - goal[0], pts[:, 1] - goal[1])
        hit = np.flatnonzero(gd <= s.tol)
        upto = int(hit[0]) + 1 if hit.size else s.n_sub
        self._pedestrian_distances(pts[:upto])
        if self.walls:
            self._wall_distances(pts[:upto])
        self.energy += float(self.step.out[1][:upto].sum()) * s.dt
        if not self.left_area and not shapely.contains_xy(self.area, pts[-1, 0], pts[-1, 1]):
            self.left_area = k * s.n_sub * s.dt + s.n_sub * s.dt
        self.rec_X.append(X)
        if hit.size:
            self.arrival = (k * s.n_sub + upto) * s.dt
            return True
        return False

    def _measure_compiled(self, k: int, X: Array) -> bool:
        """:meth:`measure` in one call of the compiled
        :func:`~designlab.navigation.crowds.bookkeeping.period_measures` (bit-identical)."""
        s, st, fr = self.s, self.state, self.frames
        st[3], st[4] = self.rec_X[-1][0, -1], self.rec_X[-1][1, -1]  # the period's start
        check = not self.left_area
        edges = self.edges if self.edges is not None else self.no_edges
        hit, esum, outside = period_measures(
            X, self.goal, s.tol, fr.ring, fr.rows(s.per_ped + 1), fr.count, st,
            self.frac_flat, self.reach, self.d0, self.wall_frames, self.wall_slack, self.w2,
            self.step.out[1], edges, check and self.edges is not None,
        )  # fmt: skip
        self.dmin, self.wmin, self.wall_last = float(st[0]), float(st[1]), float(st[2])
        self.energy += esum * s.dt
        if check and self.edges is None:
            outside = not shapely.contains_xy(self.area, X[0, -1], X[1, -1])
        if outside:
            self.left_area = k * s.n_sub * s.dt + s.n_sub * s.dt
        self.rec_X.append(X)
        if hit >= 0:
            self.arrival = (k * s.n_sub + hit + 1) * s.dt
            return True
        return False

    def _wall_distances(self, pts: Array) -> None:
        """The running minimum of the distances to the walls' contours: at every dynamics step
        when a wall may come within its active distance r2 + V_mr T_s during the period, at the
        period's ends otherwise (every critical-region entry and collision is seen)."""
        start = self.wall_last
        self.wall_last = _wall_distance_point(self.wall_rows, float(pts[-1, 0]), float(pts[-1, 1]))
        if start - self.s.crowd.robot.max_speed * self.s.crowd.sample_time > self.w2:
            self.wmin = min(self.wmin, start, self.wall_last)
        else:
            self.wmin = min(self.wmin, _wall_distance(self.wall_frames, pts))

    def _pedestrian_distances(self, pts: Array) -> None:
        """The running minimum of the centre distances to the pedestrians.

        Exact at every dynamics step for the pedestrians within R = r2 + (V_mr + v_0,max) T_s
        of the robot at the period's start (positions interpolated linearly within a
        pedestrian step): no other can come within r2 during the period, so every
        critical-region entry and collision is seen. The others count at the sample.
        """
        F = self.frames.last(self.s.per_ped + 1)  # (per + 1, n, 2): the period's pedestrian steps
        P0 = F[0]
        p = self.rec_X[-1][0:2, -1]  # the robot at the period's start
        d0 = np.hypot(P0[:, 0] - p[0], P0[:, 1] - p[1])
        m = float(np.fmin.reduce(d0)) if d0.size else math.nan  # NaN: nobody is in
        if m != m:
            return
        self.dmin = min(self.dmin, m)
        near = np.flatnonzero(d0 < self.reach)
        if not near.size:
            return
        G = F[:, near]
        Ps = G[:-1, None] + self.frac * (G[1:] - G[:-1])[:, None]  # (per, q, n_near, 2)
        Ps = Ps.reshape(-1, near.size, 2)[: pts.shape[0]]
        d = np.hypot(Ps[:, :, 0] - pts[:, None, 0], Ps[:, :, 1] - pts[:, None, 1])
        m = float(np.fmin.reduce(d, axis=None))
        if m == m:
            self.dmin = min(self.dmin, m)


def _track(x0: Array, cmd: Array, robot: Any, n: int, dt: float) -> tuple[Array, Array]:
    """A holonomic robot tracking the velocity ``cmd`` (capped at V_mr) for ``n`` steps of
    ``dt`` at its acceleration limit a_mr, as the planners' robot
    (:mod:`designlab.navigation.planners.simulate`): the velocity moves straight towards the
    command by a_mr dt per step, the position by the new velocity times dt. Returns the
    states ``(4, n)`` at the end of each step and the omni-wheel feed-forward copper loss per
    ohm of each step (App. D, as :func:`~designlab.navigation.planners.simulate.wheel_energy`).
    """
    c = np.asarray(cmd, dtype=float)
    sp = float(np.hypot(*c))
    if sp > robot.max_speed:
        c = c * (robot.max_speed / sp)
    v0, p0 = x0[2:4].copy(), x0[0:2].copy()
    dv = c - v0
    gap = float(np.hypot(*dv))
    k = np.arange(1, n + 1)
    frac = np.minimum(k * robot.max_accel * dt / gap, 1.0) if gap > 0 else np.ones(n)
    v = v0[None, :] + frac[:, None] * dv[None, :]
    p = p0[None, :] + np.cumsum(v, axis=0) * dt
    s3 = math.sqrt(3.0) / 2.0
    rows = np.array([(-s3, -0.5), (s3, -0.5), (0.0, 1.0)]) / robot.wheel_radius
    w = np.vstack([v0[None, :], v]) @ rows.T
    ff = np.asarray(HOLONOMIC_FEEDFORWARD)
    u = ff[:, 0] * np.diff(w, axis=0) / dt + ff[:, 1] * w[1:] + ff[:, 2] * np.sign(w[1:])
    return np.vstack([p.T, v.T]), (u**2).sum(axis=1)


def _wall_distance_point(walls: list[tuple[float, ...]], x: float, y: float) -> float:
    """The contour distance from one point to the nearest wall (plain floats: a few walls)."""
    best = math.inf
    for cx, cy, c, s, hl, hw in walls:
        rx, ry = x - cx, y - cy
        dx = max(abs(c * rx + s * ry) - hl, 0.0)
        dy = max(abs(-s * rx + c * ry) - hw, 0.0)
        best = min(best, math.hypot(dx, dy))
    return best


def _wall_distance(walls: Array, pts: Array) -> float:
    """Smallest contour distance from ``pts`` ``(n, 2)`` to the walls (rows: centre, cos,
    sin, half length, half width), as :meth:`Rectangle.contour_distance` for all at once."""
    return float(wall_distances(walls, pts).min())


def _outside(run: _Run, k: int, X: Array) -> bool:
    """Whether the robot leaves the walkable area during period ``k`` (``X``: its states);
    if so the run's ``left_area`` is the first dynamics step outside (the run ends there,
    before the pedestrians are stepped with a robot outside their area)."""
    inside = shapely.contains_xy(run.area, X[0], X[1])
    if inside.all():
        return False
    run.left_area = (k * run.s.n_sub + int(np.argmin(inside)) + 1) * run.s.dt
    return True


def _attribute(run: _Run, times: Array, pts: Array, vel: Array, Ps: Array) -> None:
    """Time and cause of the first contact and the first critical entry, once the running
    minima show them: :func:`~designlab.navigation.crowds.field_metrics.first_entry` on the
    steps given (``times`` ``(n,)``, the robot's positions and velocities ``(n, 2)``, the
    pedestrians ``(n, N, 2)``), so a contact between two recorded samples is attributed."""
    c = run.s.crowd
    rho = c.robot.radius
    if run.collision_by == "none" and (run.dmin <= rho + c.pedestrian_radius or run.wmin <= rho):
        t, run.collision_by = _entry(run, times, pts, vel, Ps, rho + c.pedestrian_radius, rho)
        run.collision_time = t
    if run.critical_by == "none" and (run.dmin <= run.r3 or run.wmin <= run.w3):
        run.critical_by = _entry(run, times, pts, vel, Ps, run.r3, run.w3)[1]


def _entry(run: _Run, times: Array, pts: Array, vel: Array, Ps: Array, radius: float,
           wall_radius: float) -> tuple[float, str]:  # fmt: skip
    """:func:`first_entry` on the steps; the running minima and these steps' distances are
    the same numbers, so it finds the entry (a last-digit difference of the compiled
    interpolation is taken up by a relative 1e-12 on the radii)."""
    slack = 1.0 + 1e-12
    return first_entry(times, pts, vel, Ps, radius * slack, run.wall_frames, wall_radius * slack)


def _contact(run: _Run, k: int, X: Array) -> None:
    """Attribute the first contact and critical entry if period ``k`` (robot states ``X``)
    holds them, at their own dynamics step (pedestrians interpolated within their steps)."""
    c, s = run.s.crowd, run.s
    rho = c.robot.radius
    new_contact = run.collision_by == "none" and (
        run.dmin <= rho + c.pedestrian_radius or run.wmin <= rho
    )
    new_critical = run.critical_by == "none" and (run.dmin <= run.r3 or run.wmin <= run.w3)
    if not (new_contact or new_critical):
        return
    F = run.frames.last(s.per_ped + 1)  # the period's pedestrian steps
    Ps = (F[:-1, None] + run.frac * (F[1:] - F[:-1])[:, None]).reshape(-1, F.shape[1], 2)
    if isinstance(c.robot, HolonomicRobot):
        vel = X[2:4].T
    else:
        vel = (X[3] * np.stack([np.cos(X[2]), np.sin(X[2])])).T
    times = (k * s.n_sub + np.arange(1, s.n_sub + 1)) * s.dt
    _attribute(run, times, X[0:2].T, vel, Ps)


def _loop(run: _Run) -> int:
    s = run.s
    k_done = 0
    clock = time.process_time  # CPU time: the cost on one core, whatever the load
    for k in range(s.n_samples):
        t0 = clock()
        sensed = run.sense()  # the pedestrians at t_k, whichever side moves first
        if s.order == "robot_first":
            X = run.robot_period(sensed)
            if _outside(run, k, X):
                break
            t1 = clock()
            ok = run.pedestrians_period(X)
            t2 = clock()
        else:
            ok = run.pedestrians_period(None)
            t1 = clock()
            X = run.robot_period(sensed) if ok else None
            t2 = clock()
            if X is not None and _outside(run, k, X):
                break
        run.ped_time += t2 - t1 if s.order == "robot_first" else t1 - t0
        if not ok or X is None:
            break
        k_done = k + 1
        arrived = run.measure(k, X)
        _contact(run, k, X)
        np.copyto(run.step.inp[0], X[:, -1])
        run.total_time += clock() - t0
        if arrived:
            break
    return k_done


def _records(run: _Run, k_done: int) -> dict[str, Any]:
    s = run.s
    q = s.n_sub // s.per_ped
    X = np.concatenate(run.rec_X, axis=1)  # (nx, 1 + k_done n_sub)
    idx = np.arange(0, X.shape[1], q)
    T = idx.size
    frames = run.rec_ped[:T]
    n = run.ped.count
    P = np.full((T, n, 2), np.nan)
    for t, (ids, Pt) in enumerate(frames):
        P[t, ids] = Pt
    Xr = X[:, idx]
    if isinstance(s.crowd.robot, HolonomicRobot):
        vel = Xr[2:4].T
    else:
        vel = (Xr[3] * np.stack([np.cos(Xr[2]), np.sin(Xr[2])])).T
    pos = Xr[0:2].T
    near = np.hypot(P[:, :, 0] - pos[:, None, 0], P[:, :, 1] - pos[:, None, 1])
    nearest = np.where(
        np.isnan(near).all(axis=1),
        np.inf,
        np.nanmin(np.where(np.isnan(near), np.inf, near), axis=1),
    )
    return {
        "times": idx * s.dt, "robot_positions": pos, "robot_velocities": vel,
        "pedestrian_positions": P, "pedestrian_ids": np.asarray(run.ped.keys[:n], np.int64),
        "nearest_distance": nearest,
    }  # fmt: skip


def _event(run: _Run) -> tuple[str, float]:
    """The run's outcome (:data:`OUTCOMES`: its first event) and that event's time, s."""
    events = [
        ("collision", run.collision_time),
        ("left_area", run.left_area or math.inf),
        ("simulator_failed", run.failure_time if run.failure else math.inf),
        ("arrived", run.arrival),
    ]
    name, t = min(events, key=lambda e: e[1])  # a tie: the order above (contact first)
    return (name, t) if math.isfinite(t) else ("timeout", run.s.crowd.time_limit)


def _outcome(run: _Run) -> dict[str, Any]:
    c = run.s.crowd
    rho = c.robot.radius
    surf = run.dmin - rho - c.pedestrian_radius
    crit = run.dmin <= run.r3 or run.wmin <= run.w3
    coll = surf <= 0 or run.wmin <= rho
    outcome, at = _event(run)
    warnings = [f"outcome {outcome} at t = {at:.2f} s"] if outcome != "arrived" else []
    if run.failure:
        warnings.append(run.failure)
        status = CrowdStatus.PEDESTRIAN_SIMULATOR_FAILED
    elif math.isfinite(run.arrival):
        status = CrowdStatus.OK
    else:
        status = CrowdStatus.NOT_ARRIVED
    if surf <= 0:
        warnings.append(f"collision with a pedestrian: surface distance {surf:.3f} m")
    elif run.dmin <= run.r3:
        warnings.append(f"entered a pedestrian's critical region: distance {run.dmin:.3f} m")
    if run.wmin <= rho:
        warnings.append(f"collision with a wall: distance {run.wmin:.3f} m")
    if run.left_area:
        warnings.append(f"the robot left the walkable area at t = {run.left_area:.2f} s")
    if run.overflow:
        warnings.append(
            f"in {run.overflow} periods more than {c.neighbours} pedestrians were in the active "
            "region: the farthest were left out of the field (raise neighbours)"
        )
    exceeded = run.agent_offset > AGENT_OFFSET_BOUND
    if exceeded:
        warnings.append(
            f"JuPedSim held the robot's agent up to {run.agent_offset:.3f} m from the robot "
            f"(bound {AGENT_OFFSET_BOUND} m): the pedestrians did not see the robot where it was"
        )
    return {
        "arrival_time": run.arrival, "min_distance": run.dmin, "min_surface_distance": surf,
        "min_wall_distance": run.wmin, "entered_critical": bool(crit), "collided": bool(coll),
        "critical_time": run.crit_time, "energy": run.energy, "slot_overflow": run.overflow,
        "robot_agent_offset": run.agent_offset, "critical_overlaps": run.overlaps,
        "status": status, "warnings": tuple(warnings), "outcome": outcome, "outcome_time": at,
        "coupling_exceeded": bool(exceeded), "collision_by": run.collision_by,
        "critical_by": run.critical_by,
    }  # fmt: skip


def simulate_crowd(
    crowd: CrowdScenario,
    gains: Any = None,
    *,
    method: str = CROWD_METHOD.default,
    stabilising: str = "lyapunov",
    tie_side: str = "+y",
    arrival_tolerance: float = ARRIVAL_TOLERANCE.default,
    dynamics_step: float = 1e-3,
    cbf_gains: tuple[float, float] = (4.0, 4.0),
    order: str = "robot_first",
) -> CrowdResult:
    """Simulate the robot among the pedestrians of ``crowd`` (also ``navigation.simulate``).

    Parameters
    ----------
    crowd
        From :func:`~designlab.navigation.crowd`.
    gains
        As for :func:`~designlab.navigation.simulate` (:class:`VFFGains` required for VFF).
    method
        A method of :data:`~designlab.navigation.methods.CROWD_METHOD`: a force field
        (``"vff"``, ``"masoud"``, ``"ge_cui"``, ``"cbf"``) or a baseline commanding a velocity
        (``"orca"``, ``"social_force"``: a holonomic robot; ``gains`` are then its settings).
    stabilising
        ``"lyapunov"`` or ``"off"`` (VFF's stabilising force F_L).
    tie_side
        ``"+y"`` or ``"-y"``: the detour side where the rules leave it open.
    arrival_tolerance
        Arrival radius around the goal, m.
    dynamics_step
        Integration step, s (divides the pedestrian step).
    cbf_gains
        (k_0, k_1) of the CBF constraint.
    order
        ``"robot_first"`` (default) or ``"pedestrians_first"`` (see the module's text).

    Returns
    -------
    CrowdResult

    Examples
    --------
    >>> import designlab as dl
    >>> nav = dl.navigation
    >>> c = nav.crowd("corridor_counterflow", 6, length=10.0, seed=2, horizon=3.0)
    >>> res = nav.simulate(c, nav.VFFGains(4.3, 0.68, 20.3, 240.7))
    >>> res.status, res.robot_positions.shape, res.pedestrian_positions.shape[1] >= 6
    ('not_arrived', (301, 2), True)
    """
    s = _setup(crowd, gains, dict(
        method=method, stabilising=stabilising, tie_side=tie_side,
        arrival_tolerance=arrival_tolerance, dynamics_step=dynamics_step,
        cbf_gains=cbf_gains, order=order,
    ))  # fmt: skip
    run = _Run(s)
    k_done = _loop(run)
    strategy = METHODS.get(s.method)
    return CrowdResult(
        crowd=crowd, method=s.method, stabilising=s.stabilising,
        gains=strategy.gains_dict(s.row), **_outcome(run), **_records(run, k_done),
        desired_speeds=_speeds(run.ped), pedestrian_seconds=run.ped_time,
        robot_seconds=run.total_time - run.ped_time,
    )  # fmt: skip


def _speeds(ped: PedestrianSim) -> Array:
    return np.asarray(ped.speeds, dtype=float)


def simulate_pedestrians(crowd: CrowdScenario) -> PedestrianRun:
    """The pedestrians of ``crowd`` alone (the same seed, no robot) over its horizon.

    With ``react_to_robot=False`` these are exactly the pedestrians of
    :func:`simulate_crowd` (they ignore the robot); the difference of the two shows what the
    robot costs the pedestrians when they avoid it.

    Parameters
    ----------
    crowd
        The scenario.

    Returns
    -------
    PedestrianRun

    Examples
    --------
    >>> import designlab as dl
    >>> c = dl.navigation.crowd("bottleneck", 8, length=10.0, seed=1, horizon=1.0)
    >>> run = dl.navigation.simulate_pedestrians(c)
    >>> run.times.shape, run.pedestrian_positions.shape[1:]
    ((101,), (8, 2))
    """
    if not isinstance(crowd, CrowdScenario):
        raise InvalidParameterError("crowd", crowd, "must be a CrowdScenario (navigation.crowd())")
    alone = crowd.replace(react_to_robot=False)
    ped = PedestrianSim(alone)
    n_steps = round(crowd.time_limit / crowd.pedestrian_step)
    check_size(
        "CrowdScenario.horizon", crowd.time_limit,
        (n_steps + 1) * crowd.pedestrians * _INFLOW_FACTOR * 2,
        what="the recorded pedestrian positions",
    )  # fmt: skip
    frames = [ped.positions()]
    failure = ""
    for _ in range(n_steps):
        try:
            ped.step()
        except RuntimeError as exc:
            failure = f"JuPedSim stopped at t = {ped.time:.2f} s: {exc}"
            break
        frames.append(ped.positions())
    n = ped.count
    P = np.full((len(frames), n, 2), np.nan)
    for t, (ids, Pt) in enumerate(frames):
        P[t, ids] = Pt
    keys = np.asarray(ped.keys[:n], np.int64)
    return PedestrianRun(
        crowd, np.arange(len(frames)) * crowd.pedestrian_step, P, keys,
        _speeds(ped), CrowdStatus.PEDESTRIAN_SIMULATOR_FAILED if failure else CrowdStatus.OK,
        (failure,) if failure else (),
    )  # fmt: skip


#: Arguments of ``navigation.simulate`` that do not apply to a crowd, with their defaults.
_NOT_FOR_CROWDS = {"force_every_step": False, "jit": False, "weights": EQUAL_WEIGHTS, "noise": None}


def accepts_crowds(simulate: Callable[..., Any]) -> Callable[..., Any]:
    """Let ``simulate(scenario, ...)`` take a :class:`CrowdScenario` (run by simulate_crowd).

    Parameters
    ----------
    simulate
        The scenario simulator (:func:`designlab.navigation.simulate`).

    Returns
    -------
    callable
        The same function, dispatching a :class:`CrowdScenario` to :func:`simulate_crowd`;
        an argument that does not apply to a crowd (``jit``, ``noise``, ``weights``,
        ``force_every_step``) is refused unless left at its default.
    """

    @functools.wraps(simulate)
    def dispatch(scenario: Any, gains: Any = None, **kw: Any) -> Any:
        if not isinstance(scenario, CrowdScenario):
            return simulate(scenario, gains, **kw)
        for name, default in _NOT_FOR_CROWDS.items():
            if name in kw and kw.pop(name) != default:
                raise InvalidParameterError(name, "given", "does not apply to a CrowdScenario")
        return simulate_crowd(scenario, gains, **kw)

    return dispatch
