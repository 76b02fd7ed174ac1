"""Simulate a scenario with the new VFF or a baseline, one run or a batch of gain sets.

:func:`simulate` runs one scenario with one gain set and returns a
:class:`NavigationResult` (arrival time, minimum distances, critical-region
entries, collisions, the Sec. 5.6 criteria, the Lyapunov audit and the
trajectories). :func:`simulate_batch` runs many gain sets over several
scenarios together (one CasADi call per navigation period for the whole batch)
and returns a :class:`BatchResult`: the function a gain optimiser calls.

Timing (``docs/navigation.md``): the force is recomputed every T_s = 0.06 s and
held; the robot is integrated with a 1 ms step; arrival is the first time the
robot is within ``arrival_tolerance`` (0.15 m) of the goal.

Examples
--------
>>> import designlab as dl
>>> nav = dl.navigation
>>> res = nav.simulate(nav.configuration(1), nav.VFFGains(k1=4.3, b=0.68, k3=20.3, k5=240.7),
...                    stabilising="off")
>>> round(res.arrival_time, 2), round(res.min_distance["circle"], 3)
(5.98, 0.55)
>>> res.entered_critical, res.collided
(False, False)
>>> batch = nav.simulate_batch([nav.configuration(1)],
...                            [[4.3, 0.68, 20.3, 240.7], [3, 0.25, 20, 17]],
...                            stabilising="off")
>>> batch.arrival_time.round(2)
array([[5.98, 6.48]])
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.navigation import engine
from designlab.navigation.criteria import (
    EQUAL_WEIGHTS,
    UNDEFINED,
    Criteria,
    check_weights,
    criteria,
)
from designlab.navigation.crowds import CrowdResult, CrowdScenario, accepts_crowds
from designlab.navigation.dynamics import attraction_loop_radius
from designlab.navigation.hold_audit import HoldAudit, hold_audit
from designlab.navigation.lyapunov import StabilityAudit, audit_run
from designlab.navigation.methods import (
    METHOD,
    METHODS,
    STABILISING,
    TIE_SIDE,
    NavigationMethod,
    method_of,
)
from designlab.navigation.noise import SensorNoise
from designlab.navigation.parameters import (
    ARRIVAL_TOLERANCE,
    GAIN,
    GAIN_SETS,
    GeCuiGains,
    HolonomicRobot,
    MasoudGains,
    VFFGains,
    check_cbf_gains,
)
from designlab.navigation.planners.simulate import PlannerResult, simulate_planner
from designlab.navigation.scenarios import Disc, Scenario
from designlab.results import Result, Status

__all__ = ["BatchResult", "NavigationResult", "RunStatus", "simulate", "simulate_batch"]

Array = NDArray[np.float64]


class RunStatus(Status):
    """Status of a simulated run or batch (:class:`NavigationResult`, :class:`BatchResult`).

    ``OK``: the robot arrived (every run of a batch: see its warnings otherwise);
    ``NOT_ARRIVED``: the robot did not reach the goal within the horizon. Collisions and
    critical-region entries are warnings.
    """

    OK = "ok"
    NOT_ARRIVED = "not_arrived"


def _nominal_clearance(scenario: Scenario) -> dict[str, float]:
    rho_r = scenario.robot.radius
    return {
        o.name: (o.r2 - rho_r - o.radius) if isinstance(o, Disc) else (o.r2 - rho_r)
        for o in scenario.obstacles
    }


def _surface(scenario: Scenario, dmin: Array) -> Array:
    """Surface distances d_s = d - rho_r - rho_o (discs), d_rect - rho_r (rectangles)."""
    rho_r = scenario.robot.radius
    off = np.array([o.collision_distance(rho_r) for o in scenario.obstacles])
    return dmin - off


@dataclass(frozen=True)
class NavigationResult(Result):
    """One simulated run.

    Attributes
    ----------
    scenario
        The :class:`Scenario` simulated.
    method, stabilising
        Navigation method and stabilising-force mode.
    gains
        The gains used (a dict).
    arrival_time
        First time within ``arrival_tolerance`` of the goal (s); ``inf`` if never.
    min_distance
        Minimum centre distance per obstacle (contour distance for rectangles), m,
        before arrival.
    min_surface_distance
        d_s,min per obstacle: ``min_distance`` minus rho_r (+ rho_o for discs), m.
    entered_critical, collided
        Whether the robot entered any critical region (d <= r3) / touched any
        obstacle (d_s <= 0). ``critical_entries`` and ``collisions`` give them per
        obstacle.
    criteria
        H_T, H_D, H_E, H (:class:`~designlab.navigation.criteria.Criteria`).
    stability
        The Lyapunov audit (:class:`~designlab.navigation.lyapunov.StabilityAudit`);
        ``None`` for the baselines, whose fields have no Lyapunov function.
    energy
        L_energy per ohm of winding resistance (A^2 s).
    t, position, velocity, heading, distance, obstacle_positions
        Trajectories at every dynamics step: times (s), robot position and
        velocity (m, m/s), heading (rad; constant for the holonomic robot), the
        distance to each obstacle (``n_obs x len(t)``; the first column repeats the
        start) and the obstacle positions (``n_obs x len(t) x 2``).
    critical_entries
        Obstacle name -> whether the robot entered its critical region.
    collisions
        Obstacle name -> whether the robot touched it.
    critical_time
        Time spent inside a critical region in s.
    tie, period
        The detour tie-break side (+1/-1) and the period the force was held (s).
    power
        Copper loss per ohm (A^2) at every dynamics step (:meth:`energy_trace` integrates it).
    status
        ``"ok"``, or ``"not_arrived"`` (collisions and critical-region entries are warnings).
    warnings
        What a user should know about the run (collisions, critical-region entries).
    """

    scenario: Scenario
    method: str
    stabilising: str
    gains: dict[str, float]
    arrival_time: float
    min_distance: dict[str, float]
    min_surface_distance: dict[str, float]
    critical_entries: dict[str, bool]
    collisions: dict[str, bool]
    criteria: Criteria
    stability: StabilityAudit | None
    energy: float
    t: Array = field(repr=False)
    position: Array = field(repr=False)
    velocity: Array = field(repr=False)
    heading: Array = field(repr=False)
    distance: Array = field(repr=False)
    obstacle_positions: Array = field(repr=False)
    critical_time: float = 0.0
    status: str = RunStatus.OK
    warnings: tuple[str, ...] = ()
    tie: int = 1
    period: float = 0.06
    power: Array = field(default_factory=lambda: np.zeros(0), repr=False)

    def energy_trace(self) -> Array:
        """Cumulative L_energy per ohm (A^2 s) at every time of :attr:`t` (Fig. 7.5)."""
        dt = float(self.t[1] - self.t[0]) if self.t.size > 1 else 0.0
        return np.concatenate([[0.0], np.cumsum(self.power) * dt])[: self.t.size]

    def hold_audit(self) -> HoldAudit:
        """V at every dynamics step, checked over each held period (new VFF runs, filtered or not).

        See :func:`designlab.navigation.hold_audit.hold_audit`.
        """
        if not METHODS.get(self.method).stabilised:
            raise InvalidParameterError(
                "method", self.method, "the hold audit needs the new VFF's Lyapunov function"
            )
        row = np.array([self.gains[k] for k in ("k1", "b", "k3", "k5")])
        return hold_audit(
            self.scenario, self.t, self.position, self.velocity, row,
            stabilising=self.stabilising == "lyapunov", tie=self.tie, period=self.period,
            method=self.method,
        )  # fmt: skip

    @property
    def entered_critical(self) -> bool:
        return any(self.critical_entries.values())

    @property
    def collided(self) -> bool:
        return any(self.collisions.values())

    @property
    def arrived(self) -> bool:
        return math.isfinite(self.arrival_time)

    def to_frame(self) -> pd.DataFrame:
        """One row: scenario, method, arrival time, distances per obstacle, flags, criteria."""
        row: dict[str, Any] = {
            "scenario": self.scenario.name,
            "method": self.method,
            "stabilising": self.stabilising,
            "T_arrive_s": self.arrival_time,
        }
        for name, d in self.min_distance.items():
            row[f"d_{name}_min_m"] = d
        row["entered_critical"] = self.entered_critical
        row["collided"] = self.collided
        c = self.criteria
        row.update(
            {"H_T": c.H_T, "H_D": c.H_D, "H_E": c.H_E, "H": c.H, "L_energy_J_per_ohm": self.energy}
        )
        if self.stability is not None:
            row["lyapunov_share"] = self.stability.share_satisfied
        return pd.DataFrame([row])

    def trajectory_frame(self) -> pd.DataFrame:
        """The run at every dynamics step.

        Columns ``t_s``, ``x_m``, ``y_m``, ``vx_m_per_s``, ... ``d_<name>_m``.
        """
        data: dict[str, Any] = {
            "t_s": self.t,
            "x_m": self.position[:, 0],
            "y_m": self.position[:, 1],
            "vx_m_per_s": self.velocity[:, 0],
            "vy_m_per_s": self.velocity[:, 1],
            "heading_rad": self.heading,
        }
        for i, name in enumerate(self.scenario.obstacle_names):
            data[f"d_{name}_m"] = self.distance[i]
        return pd.DataFrame(data)


@accepts_crowds  # a CrowdScenario runs among JuPedSim's pedestrians (navigation.crowds)
def simulate(
    scenario: Scenario | CrowdScenario,
    gains: VFFGains | MasoudGains | GeCuiGains | Any = None,
    *,
    stabilising: str = "lyapunov",
    method: str = METHOD.default,
    arrival_tolerance: float = ARRIVAL_TOLERANCE.default,
    dynamics_step: float = 1e-3,
    force_every_step: bool = False,
    tie_side: str = "+y",
    cbf_gains: tuple[float, float] = (4.0, 4.0),
    jit: bool = False,
    weights: tuple[float, float, float] = EQUAL_WEIGHTS,
    noise: SensorNoise | None = None,
) -> NavigationResult | PlannerResult | CrowdResult:
    """Simulate one scenario (a force-field method, a Sec. 5.7 planner, or a crowd).

    Parameters
    ----------
    scenario
        From :func:`configuration`, by hand, or a :class:`CrowdScenario` (-> :class:`CrowdResult`).
    gains
        :class:`VFFGains` for ``"vff"``/``"vff_cbf"`` (required) and ``"cbf"`` (default
        the experiment gains); :class:`MasoudGains` / :class:`GeCuiGains` (default Table
        C.1); a planner's settings (``VOSettings``, ... of :mod:`~.planners`).
    stabilising
        ``"lyapunov"``: the stabilising force F_L of (5.4.6) is on; ``"off"``: it is
        left out (how the thesis's tables come back, ``docs/navigation.md``).
    method
        ``"vff"``, ``"masoud"``, ``"ge_cui"``, ``"cbf"`` (CBF filter, d >= r3, on the PD
        attraction) or ``"vff_cbf"`` (the new VFF filtered by it), :data:`~.methods.METHODS`;
        a Sec. 5.7 planner (``"vo"``, ``"nlvo"``, ``"errt"``, ``"field_dstar"``) runs through
        :func:`~.planners.simulate_planner` (force-field options refused).
    arrival_tolerance
        Arrival radius around the goal, m (first passage; at most 1 m).
    dynamics_step
        Integration step in s (must divide the sample time into at most 1000 steps).
    force_every_step
        Recompute the force at every dynamics step instead of holding it for T_s.
    tie_side
        ``"+y"`` or ``"-y"``: the detour side when the rules leave it open (exactly
        collinear robot, obstacle and goal). For Masoud, the rotational sense:
        ``"+y"`` counter-clockwise.
    cbf_gains
        (k_0, k_1) of the CBF constraint h'' + k_1 h' + k_0 h >= 0.
    jit
        Compile the step with CasADi's JIT (a few seconds once per scenario structure,
        then several times faster; worth it for many runs of one scenario).
    weights
        (w_T, w_D, w_E) of H (5.6.6): non-negative, summing to 1 (the thesis: 1/3 each).
    noise
        Seeded measurement noise of what the field sees (:class:`SensorNoise`); ``None``:
        exact measurements. The nominal run of the criteria stays noise-free.

    Returns
    -------
    NavigationResult or PlannerResult

    Raises
    ------
    InvalidParameterError
        For an unknown method or mode, gains of the wrong kind, or a run too long to
        record (docs/navigation.md, "Limits").

    Examples
    --------
    >>> import designlab as dl; nav = dl.navigation
    >>> res = nav.simulate(nav.configuration(1), nav.EXPERIMENT_GAINS, stabilising="off")
    >>> round(res.arrival_time, 2), round(res.min_distance["circle"], 3), res.collided
    (6.48, 0.486, False)
    >>> nav.simulate(nav.configuration(1), nav.EXPERIMENT_GAINS, method="bug")
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: method = 'bug' is not allowed: ...
    """
    if METHODS.get(method).planner:  # an unknown name is refused naming every method
        _check_planner_options(stabilising, force_every_step, noise)
        return simulate_planner(scenario, method, gains, arrival_tolerance=arrival_tolerance)
    STABILISING.check(stabilising)
    strategy = method_of(method)
    TIE_SIDE.check(tie_side)
    w = check_weights(weights)
    _check_flags(force_every_step=force_every_step, jit=jit)
    cbf = check_cbf_gains(cbf_gains)
    _check_run_inputs(scenario, noise)
    row = strategy.gain_row(gains)
    kw: dict[str, Any] = dict(
        method=strategy.name,
        stabilising=stabilising == "lyapunov" and strategy.stabilised,
        tie=strategy.tie(gains, tie_side),
        arrival_tolerance=arrival_tolerance,
        dynamics_step=dynamics_step,
        force_every_step=force_every_step,
        cbf_gains=cbf,
        jit=jit,
    )
    raw = engine.run(scenario, row[None, :], record=True, noise=noise, **kw)
    nominal = engine.run(scenario.without_obstacles(), row[None, :], record=False, **kw)
    res = _summarise_run(scenario, strategy, row, stabilising, raw, nominal, w)
    return _flag_chatter(replace(res, tie=int(kw["tie"])), strategy, row, kw)


def _flag_chatter(
    res: NavigationResult, strategy: NavigationMethod, row: Array, kw: dict[str, Any]
) -> NavigationResult:
    """``res``, warned if the sampled PD attraction is unstable (``attraction_loop_radius``)."""
    if strategy.gains_type is not VFFGains:
        return res
    dt = float(kw["dynamics_step"])
    period = dt if kw["force_every_step"] else res.scenario.sample_time
    k1, b, m = float(row[0]), float(row[1]), res.scenario.robot.mass
    rho = attraction_loop_radius(k1, b, m, period, dt)
    if rho < 1.0:
        return res
    note = (
        f"the attraction loop sampled every {period} s is unstable at K1 = {k1:g}, b = {b:g} "
        f"(spectral radius {rho:.3f} >= 1; stable iff b > (T - dt)/2 and K2 T/m + K1 T dt/(2 m) "
        f"< 2, here {b * k1 * period / m + k1 * period * dt / (2 * m):.3f}): the robot chatters "
        "at its acceleration limit near the goal, in the nominal run too, so H_T and H_E "
        "can exceed 1 (docs/navigation.md, Criteria)"
    )
    return replace(res, warnings=(*res.warnings, note))


def _summarise_run(
    scenario: Scenario,
    strategy: NavigationMethod,
    row: Array,
    stabilising: str,
    raw: engine.RawRun,
    nominal: engine.RawRun,
    weights: tuple[float, float, float] = EQUAL_WEIGHTS,
) -> NavigationResult:
    """The :class:`NavigationResult` of a recorded run and its nominal (obstacle-free) run."""
    rec = raw.record
    assert rec is not None
    names = scenario.obstacle_names
    dmin = raw.min_distance[0]
    surf = _surface(scenario, dmin) if names else np.zeros(0)
    min_distance = {n: float(v) for n, v in zip(names, dmin, strict=True)}
    min_surface = {n: float(v) for n, v in zip(names, surf, strict=True)}
    crit = {o.name: bool(dmin[i] <= o.r3) for i, o in enumerate(scenario.obstacles)}
    coll = {n: bool(surf[i] <= 0.0) for i, n in enumerate(names)}
    arrival = float(raw.arrival_time[0])
    crit_res = criteria(
        arrival_time=arrival,
        nominal_arrival_time=float(nominal.arrival_time[0]),
        energy=float(raw.energy[0]),
        nominal_energy=float(nominal.energy[0]),
        surface_clearance=min_surface,
        nominal_clearance=_nominal_clearance(scenario),
        weights=weights,
    )
    pos, vel, heading = _trajectories(scenario, rec["X"])
    audit = None
    if strategy.stabilised:
        robot = scenario.robot
        audit = audit_run(
            rec,
            b=float(row[1]),
            mass=robot.mass,
            max_accel=robot.max_accel,
            max_speed=robot.max_speed,
            period=rec["period"],
            holonomic=isinstance(robot, HolonomicRobot),
        )
    warnings = _run_warnings(scenario, arrival, min_distance, min_surface, crit, coll, rec)
    if crit_res.status == UNDEFINED:
        warnings = (*warnings, *(w for w in crit_res.warnings if "nominal run never" in w))
    return NavigationResult(
        scenario=scenario,
        method=strategy.name,
        stabilising=stabilising if strategy.stabilised else "off",
        gains=strategy.gains_dict(row),
        arrival_time=arrival,
        min_distance=min_distance,
        min_surface_distance=min_surface,
        critical_entries=crit,
        collisions=coll,
        criteria=crit_res,
        stability=audit,
        energy=float(raw.energy[0]),
        t=rec["t"],
        position=pos,
        velocity=vel,
        heading=heading,
        distance=_distances_from_start(scenario, rec["D"], rec["X"].shape[1]),
        obstacle_positions=rec["obstacle_positions"],
        critical_time=float(raw.critical_time[0]),
        status=RunStatus.OK if math.isfinite(arrival) else RunStatus.NOT_ARRIVED,
        warnings=warnings,
        period=float(rec["period"]),
        power=np.asarray(rec["power"], dtype=float),
    )


def _trajectories(scenario: Scenario, X: Array) -> tuple[Array, Array, Array]:
    """Positions, velocities and headings at every dynamics step."""
    if isinstance(scenario.robot, HolonomicRobot):
        return X[0:2].T, X[2:4].T, np.zeros(X.shape[1])
    vel = (X[3] * np.stack([np.cos(X[2]), np.sin(X[2])])).T
    return X[0:2].T, vel, X[2]


def _distances_from_start(scenario: Scenario, D: Array, n_t: int) -> Array:
    """The recorded distances with the distance at the start as their first column."""
    if not scenario.obstacles:
        return np.zeros((0, n_t))
    start = np.array(
        [[float(o.contour_distance(np.array([scenario.start]))[0])] for o in scenario.obstacles]
    ).reshape(len(scenario.obstacles), 1)
    return np.concatenate([start, D], axis=1)


def _run_warnings(
    scenario: Scenario,
    arrival: float,
    min_distance: dict[str, float],
    min_surface: dict[str, float],
    crit: dict[str, bool],
    coll: dict[str, bool],
    rec: dict[str, Any],
) -> tuple[str, ...]:
    """What a user should know about one run."""
    warnings: list[str] = []
    if not math.isfinite(arrival):
        warnings.append(f"the robot did not reach the goal within {scenario.horizon} s")
    for n in scenario.obstacle_names:
        if coll[n]:
            warnings.append(f"collision with {n!r}: surface distance {min_surface[n]:.3f} m")
        elif crit[n]:
            warnings.append(
                f"entered the critical region of {n!r}: distance {min_distance[n]:.3f} m"
            )
    for a, b, overlap in scenario.intersecting_critical_regions():
        warnings.append(
            f"the critical regions of {a!r} and {b!r} overlap by {overlap:.3f} m: no path "
            "between them stays outside both (Zeng 2011, Sec. 6.4.3 merges such obstacles: "
            "merge_critical_regions)"
        )
    bad = sum(1 for s in rec["qp_status"] if s and s not in ("solved", "solved inaccurate"))
    if bad:
        warnings.append(f"the CBF QP was not solved at {bad} steps; the robot braked there")
    return tuple(warnings)


@dataclass(frozen=True)
class BatchResult(Result):
    """Many gain sets over several scenarios.

    Arrays are indexed ``[scenario, gain set]``; ``min_distance`` adds a last axis
    over the scenario's obstacles (padded with ``nan`` to the largest count).

    Attributes
    ----------
    scenario_names, obstacle_names
        Names of the scenarios and, per scenario, of its obstacles.
    gains
        The ``(N, 4)`` array of (k1, b, k3, k5) simulated.
    arrival_time, nominal_arrival_time
        T_arrive and T*_arrive (s; inf if never).
    min_distance
        Minimum centre/contour distance (m), ``(S, N, max_obs)``.
    entered_critical, collided
        ``(S, N)`` booleans (any obstacle).
    energy, nominal_energy
        L_energy and L*_energy per ohm (A^2 s).
    H, H_T, H_D, H_E
        Sec. 5.6 criteria, ``(S, N)``; H_T, H_E and H are NaN where a run arrived and its
        nominal run did not (``criteria.UNDEFINED``).
    status
        Status of the batch (``"ok"``; see :class:`designlab.results.Result`).
    warnings
        What a user should know about the runs.
    """

    scenario_names: tuple[str, ...]
    obstacle_names: tuple[tuple[str, ...], ...]
    gains: Array
    arrival_time: Array
    nominal_arrival_time: Array
    min_distance: Array
    entered_critical: NDArray[np.bool_]
    collided: NDArray[np.bool_]
    energy: Array
    nominal_energy: Array
    H: Array
    H_T: Array
    H_D: Array
    H_E: Array
    status: str = RunStatus.OK
    warnings: tuple[str, ...] = ()

    @property
    def H_mean(self) -> Array:
        """Mean H over the scenarios for each gain set, ``(N,)`` (App. C's H_mean)."""
        return self.H.mean(axis=0)

    def to_frame(self) -> pd.DataFrame:
        """Long format: one row per (scenario, gain set)."""
        rows = []
        for s, name in enumerate(self.scenario_names):
            for j in range(self.gains.shape[0]):
                r: dict[str, Any] = {
                    "scenario": name,
                    "set": j,
                    "k1": self.gains[j, 0],
                    "b": self.gains[j, 1],
                    "k3": self.gains[j, 2],
                    "k5": self.gains[j, 3],
                    "T_arrive_s": self.arrival_time[s, j],
                }
                for i, on in enumerate(self.obstacle_names[s]):
                    r[f"d_{on}_min_m"] = self.min_distance[s, j, i]
                r.update(
                    {
                        "entered_critical": bool(self.entered_critical[s, j]),
                        "collided": bool(self.collided[s, j]),
                        "H_T": self.H_T[s, j],
                        "H_D": self.H_D[s, j],
                        "H_E": self.H_E[s, j],
                        "H": self.H[s, j],
                    }
                )
                rows.append(r)
        return pd.DataFrame(rows)


def _check_run_inputs(scenario: object, noise: object) -> None:
    """Refuse a scenario or a noise model of the wrong type."""
    if noise is not None and not isinstance(noise, SensorNoise):
        raise InvalidParameterError("noise", noise, "must be a SensorNoise or None")
    if not isinstance(scenario, Scenario):
        raise InvalidParameterError("scenario", scenario, "must be a Scenario (configuration())")


def _check_planner_options(stabilising: str, force_every_step: bool, noise: object) -> None:
    """Refuse the force-field options a Sec. 5.7 planner does not have."""
    for name, value, default in (("stabilising", stabilising, "lyapunov"),
                                 ("force_every_step", force_every_step, False),
                                 ("noise", noise, None)):  # fmt: skip
        if value != default:
            raise InvalidParameterError(name, value, "does not apply to a Sec. 5.7 planner")


def _check_flags(**flags: object) -> None:
    for name, value in flags.items():
        if not isinstance(value, bool | np.bool_):
            raise InvalidParameterError(name, value, "must be True or False")


def _check_gain_array(gains: ArrayLike) -> Array:
    """An ``(N, 4)`` array of gains, each checked against the one gain declaration."""
    if isinstance(gains, np.ndarray):
        has_bool = gains.dtype == bool or (
            gains.dtype == object and any(isinstance(v, bool | np.bool_) for v in gains.ravel())
        )
    else:
        raw = np.asarray(gains, dtype=object)
        has_bool = any(isinstance(v, bool | np.bool_) for v in raw.ravel())
    if has_bool:
        raise InvalidParameterError("gains", gains, "must be numbers, not booleans")
    try:
        g = np.asarray(gains, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameterError(
            "gains", gains, "must be an (N, 4) array of numbers (k1, b, k3, k5)"
        ) from None
    if g.ndim == 1:
        g = g[None, :]
    if g.ndim != 2 or g.shape[1] != 4 or g.shape[0] < 1:
        raise InvalidParameterError(
            "gains",
            gains if np.size(g) <= 8 else f"shape {g.shape}",
            f"must be an (N, 4) array of (k1, b, k3, k5), not shape {g.shape}",
        )
    GAIN_SETS.check(g.shape[0], "gains (number of gain sets)")
    bad = ~(np.isfinite(g) & (g > 0) & (g <= GAIN.le))  # the vectorised GAIN.within
    if bad.any():
        i, j = np.argwhere(bad)[0]
        GAIN.check(float(g[i, j]), f"gains[{i}, {j}]")
    return g


def _check_scenarios(scenarios: Any) -> list[Scenario]:
    if isinstance(scenarios, Scenario):
        scenarios = [scenarios]
    try:
        scenarios = list(scenarios)
    except TypeError:
        scenarios = []
    if not scenarios or not all(isinstance(s, Scenario) for s in scenarios):
        raise InvalidParameterError(
            "scenarios", scenarios, "must be a non-empty sequence of Scenario"
        )
    return scenarios


def simulate_batch(
    scenarios: Sequence[Scenario],
    gains: ArrayLike,
    *,
    stabilising: str = "lyapunov",
    arrival_tolerance: float = ARRIVAL_TOLERANCE.default,
    dynamics_step: float = 1e-3,
    tie_side: str = "+y",
    jit: bool = False,
    method: str = METHOD.default,
    weights: tuple[float, float, float] = EQUAL_WEIGHTS,
) -> BatchResult:
    """Simulate every gain set on every scenario, vectorised over the gain sets.

    Parameters
    ----------
    scenarios
        The scenarios (e.g. ``[configuration(i) for i in (1, 2, 3)]``).
    gains
        ``(N, 4)`` array of (k1, b, k3, k5); K2 = b K1, K4 = b K3, K6 = b K5. At most
        4096 gain sets per call (:data:`~designlab.navigation.parameters.GAIN_SETS`).
    stabilising, arrival_tolerance, dynamics_step, tie_side
        As in :func:`simulate`.
    jit
        Compile the batched step to machine code that evaluates four gain sets per pass
        (:mod:`designlab.sx.lanes`, the system C compiler): a few seconds once per scenario
        structure, then 5-7x faster per holonomic member-period (about 2x for the
        nonholonomic robot) than CasADi's virtual machine, with results equal to it to
        the bit. Worth it for optimisations and large sweeps.
    method
        ``"vff"`` (default), ``"masoud"`` (columns k1, -, k3, k5; the rotational sense is
        ``tie_side``: ``"+y"`` counter-clockwise) or ``"ge_cui"``; ``"cbf"`` is not
        batched.
    weights
        (w_T, w_D, w_E) of H (5.6.6), as in :func:`simulate`.

    Returns
    -------
    BatchResult
        Arrival times, minimum distances, critical entries, collisions and H per
        (scenario, gain set); ``H_mean`` averages over the scenarios.

    Examples
    --------
    >>> import designlab as dl
    >>> nav = dl.navigation
    >>> b = nav.simulate_batch([nav.configuration(1), nav.configuration(3)],
    ...                        [[3.0, 0.25, 20.0, 17.0]], stabilising="off")
    >>> b.arrival_time.round(2)
    array([[6.48],
           [5.94]])
    """
    STABILISING.check(stabilising)
    TIE_SIDE.check(tie_side)
    strategy = method_of(method)
    if not strategy.batched:
        raise InvalidParameterError("method", method, "is not batched: use simulate()")
    w = check_weights(weights)
    _check_flags(jit=jit)
    scenarios = _check_scenarios(scenarios)
    g = _check_gain_array(gains)
    kw: dict[str, Any] = dict(
        method=strategy.name,
        stabilising=stabilising == "lyapunov" and strategy.stabilised,
        tie=strategy.tie(None, tie_side),
        arrival_tolerance=arrival_tolerance,
        dynamics_step=dynamics_step,
        jit=jit,
    )
    rows = [_batch_scenario(sc, g, kw, w) for sc in scenarios]
    return _batch_result(scenarios, g, rows)


def _weighted(w: tuple[float, float, float], h_t: Array, h_d: Array, h_e: Array) -> Array:
    """w_T H_T + w_D H_D + w_E H_E; the equal weights as (H_T + H_D + H_E)/3, as before."""
    if w == EQUAL_WEIGHTS:
        return (h_t + h_d + h_e) / 3.0
    return w[0] * h_t + w[1] * h_d + w[2] * h_e


def _batch_scenario(
    sc: Scenario, g: Array, kw: dict[str, Any], w: tuple[float, float, float] = EQUAL_WEIGHTS
) -> dict[str, Array]:
    """Every gain set on one scenario and its nominal runs: the arrays of one row of S."""
    N = g.shape[0]
    raw = engine.run(sc, g, **kw)
    nom = engine.run(sc.without_obstacles(), g, **kw)
    n_obs = len(sc.obstacles)
    r3 = np.array([o.r3 for o in sc.obstacles])
    surf = _surface(sc, raw.min_distance) if n_obs else np.zeros((N, 0))
    coll = (surf <= 0).any(axis=1) if n_obs else np.zeros(N, bool)
    dstar = np.array(list(_nominal_clearance(sc).values()))
    with np.errstate(divide="ignore", invalid="ignore"):  # the ratio where not arrived: unused
        h_t = np.where(np.isfinite(raw.arrival_time), nom.arrival_time / raw.arrival_time, 0.0)
    h_d = (
        np.minimum(1.0, np.maximum(surf, 0) / dstar[None, :]).mean(axis=1) if n_obs else np.ones(N)
    )
    h_e = np.where(raw.energy > 0, nom.energy / np.where(raw.energy > 0, raw.energy, 1.0), 1.0)
    # arrived while the nominal run did not: H_T, H_E undefined (criteria's UNDEFINED status)
    undefined = np.isfinite(raw.arrival_time) & np.isinf(nom.arrival_time)
    h_t, h_e = np.where(undefined, np.nan, h_t), np.where(undefined, np.nan, h_e)
    k = (~coll).astype(float)
    return {
        "T": raw.arrival_time,
        "T0": nom.arrival_time,
        "L": raw.energy,
        "L0": nom.energy,
        "HT": h_t,
        "HD": h_d,
        "HE": h_e,
        "H": k * _weighted(w, h_t, h_d, h_e),
        "dmin": raw.min_distance,
        "crit": (raw.min_distance <= r3[None, :]).any(axis=1) if n_obs else np.zeros(N, bool),
        "coll": coll,
    }


def _batch_result(scenarios: list[Scenario], g: Array, rows: list[dict[str, Array]]) -> BatchResult:
    """Stack the per-scenario arrays into a :class:`BatchResult`."""
    S, N = len(scenarios), g.shape[0]
    max_obs = max(len(s.obstacles) for s in scenarios)
    dmin = np.full((S, N, max_obs), np.nan)
    for s, r in enumerate(rows):
        dmin[s, :, : r["dmin"].shape[1]] = r["dmin"]

    def stack(key: str) -> Array:
        return np.stack([r[key] for r in rows])

    T = stack("T")
    warnings = []
    n_not = int(np.isinf(T).sum())
    if n_not:
        warnings.append(f"{n_not} of {S * N} runs did not arrive within their horizon")
    n_undef = int((np.isfinite(T) & np.isinf(stack("T0"))).sum())
    if n_undef:
        warnings.append(
            f"{n_undef} of {S * N} runs arrived while their obstacle-free nominal run did not: "
            "their H_T, H_E and H are undefined (NaN; docs/navigation.md, Criteria)"
        )
    return BatchResult(
        tuple(s.name for s in scenarios),
        tuple(s.obstacle_names for s in scenarios),
        g,
        T,
        stack("T0"),
        dmin,
        stack("crit"),
        stack("coll"),
        stack("L"),
        stack("L0"),
        stack("H"),
        stack("HT"),
        stack("HD"),
        stack("HE"),
        warnings=tuple(warnings),
    )
