"""The pedestrians of a crowd scenario, stepped by JuPedSim.

:class:`PedestrianSim` builds the JuPedSim simulation of a :class:`CrowdScenario` (its
walkable area, one exit stage and journey per stream, the seeded placement and desired
speeds), advances it one pedestrian step at a time and keeps the crowd's size: a pedestrian
that reaches its exit leaves, and a new one enters its stream's spawn strip (at a free
spot at least 2 rho_p + 0.1 m from every agent; if none is free it tries again at the next
step). Pedestrians get consecutive indices in the order they enter (``ids``).

Every pedestrian has an identity (:attr:`PedestrianSim.keys`) that does not depend on when it
enters: pedestrian i of the initial crowd is i, the k-th replacement of stream s is
N + k S + s (N pedestrians, S streams). Its desired speed is drawn in advance from a
generator of that stream alone (seeded by the crowd's seed and s), and its entry position
from another one, so replacement k of stream s is the same person (the same desired speed
and destination) with the robot and without it, whichever pedestrians leave first.

Velocities and accelerations are not states of every JuPedSim model, so the robot's field
sees backward differences of the positions over the last pedestrian step (zero before a
pedestrian has moved): at time t_k they use positions up to t_k only, never later ones.

Examples
--------
>>> import designlab as dl
>>> sim = PedestrianSim(dl.navigation.crowd("corridor_counterflow", 10, seed=1))
>>> ids, P = sim.positions()
>>> ids.tolist() == list(range(10)), P.shape
(True, (10, 2))
>>> sim.step(); round(sim.time, 2)
0.01
"""

from __future__ import annotations

import logging
import threading
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry import Polygon, box

from designlab.errors import InvalidParameterError
from designlab.navigation.crowds.extra import jupedsim
from designlab.navigation.crowds.models import MODELS
from designlab.navigation.crowds.scenario import PLACEMENT_GAP, CrowdScenario

__all__ = ["PedestrianSim", "desired_speeds"]

log = logging.getLogger(__name__)

Array = NDArray[np.float64]
#: Placement attempts per waiting replacement and step.
_SPAWN_TRIES = 20
#: Half side of the square around a given pedestrian's destination, in pedestrian steps at
#: its fastest speed (a straight walk has a position in it); it then stands at the destination.
_DESTINATION_HALF = 0.6
#: Lowest desired speed drawn, m/s.
MIN_DESIRED_SPEED = 0.3
#: JuPedSim's placement seeds and draws numpy's global generator (``np.random.seed``): one
#: placement at a time, so runs in threads (Dask workers) place as runs alone do.
_PLACEMENT_LOCK = threading.Lock()


def _distribute(**kw: Any) -> Any:
    """``jupedsim.distribute_by_number`` alone (under :data:`_PLACEMENT_LOCK`), leaving numpy's
    global generator as it found it."""
    with _PLACEMENT_LOCK:
        state = np.random.get_state()  # noqa: NPY002 - the legacy generator JuPedSim uses
        try:
            return jupedsim().distribute_by_number(**kw)
        finally:
            np.random.set_state(state)  # noqa: NPY002


def desired_speeds(crowd: CrowdScenario, rng: np.random.Generator, n: int) -> Array:
    """``n`` desired speeds: normal (mean, sd) clipped to [0.3 m/s, ``max_desired_speed``].

    Parameters
    ----------
    crowd
        The scenario.
    rng
        The generator drawn from.
    n
        How many.
    """
    v = (
        rng.normal(crowd.desired_speed, crowd.desired_speed_sd, n)
        if crowd.desired_speed_sd
        else np.full(n, crowd.desired_speed)
    )
    return np.clip(v, min(MIN_DESIRED_SPEED, crowd.desired_speed), crowd.max_desired_speed)


class PedestrianSim:
    """The JuPedSim simulation of a crowd scenario (see the module's text).

    Parameters
    ----------
    crowd
        The scenario.
    robot_position
        The robot's start (m) when the pedestrians avoid it (``crowd.react_to_robot``).
    """

    def __init__(
        self, crowd: CrowdScenario, robot_position: tuple[float, float] | None = None
    ) -> None:
        self.crowd = crowd
        self.model = MODELS[crowd.model]
        self.rng = np.random.default_rng(crowd.seed)
        self.dt = crowd.pedestrian_step
        lay = crowd.geometry
        self.sim = jupedsim().Simulation(
            model=self.model.simulation_model(crowd.seed), geometry=lay.area, dt=self.dt
        )
        self.index: dict[int, int] = {}  # JuPedSim id -> pedestrian index
        self.stream_of: list[int] = []
        self.speeds: list[float] = []  # desired speed of each pedestrian, m/s
        self.waiting: list[tuple[int, int, float]] = []  # (stream, k, speed) not entered yet
        self.keys: list[int] = []  # identity of each pedestrian (see the module's text)
        n_streams = len(crowd.geometry.streams)
        self._queued = [0] * n_streams  # replacements queued per stream
        self._speed_rng = [np.random.default_rng([crowd.seed, 1, s]) for s in range(n_streams)]
        self._spot_rng = [np.random.default_rng([crowd.seed, 2, s]) for s in range(n_streams)]
        self.steps = 0
        self._leaving: list[int] = []
        self.parked: dict[int, tuple[float, float]] = {}  # given pedestrians at their destination
        self._order: NDArray[np.int64] | None = None  # pedestrian index of each agent, in order
        self._keep = self._ids = np.zeros(0, np.int64)
        self._journeys: list[tuple[int, int]] = []
        if crowd.paths:
            self._add_given()
        else:
            self._add_streams()
        self.robot_id: int | None = None
        if crowd.react_to_robot:
            self._add_robot(robot_position if robot_position is not None else crowd.robot_start)

    # ----------------------------------------------------------------- set-up
    def _journey(self, exit_polygon: Polygon) -> tuple[int, int]:
        stage = self.sim.add_exit_stage(exit_polygon)
        return self.sim.add_journey(jupedsim().JourneyDescription([stage])), stage

    def _add(
        self, position: tuple[float, float], speed: float, stream: int, key: int | None = None
    ) -> int:
        journey, stage = self._journeys[stream]
        jid = self.sim.add_agent(
            self.model.agent(position, float(speed), self.crowd.pedestrian_radius, journey, stage)
        )
        self.index[jid] = len(self.stream_of)
        self.keys.append(len(self.stream_of) if key is None else key)
        self._order = None  # the agents changed: read everything next time
        self.stream_of.append(stream)
        self.speeds.append(float(speed))
        return jid

    def _add_given(self) -> None:
        speeds = desired_speeds(self.crowd, self.rng, len(self.crowd.paths))
        h = _DESTINATION_HALF * self.crowd.max_desired_speed * self.dt
        for i, ((a, b), v) in enumerate(zip(self.crowd.paths, speeds, strict=True)):
            standing = max(abs(a[0] - b[0]), abs(a[1] - b[1])) <= h
            if standing:  # already at its destination: an agent that stands (steered to itself)
                stage = self.sim.add_direct_steering_stage()
                self._journeys.append(
                    (self.sim.add_journey(jupedsim().JourneyDescription([stage])), stage)
                )
            else:
                self._journeys.append(self._journey(box(b[0] - h, b[1] - h, b[0] + h, b[1] + h)))
            try:
                self._add(a, 0.0 if standing else v, i)
            except RuntimeError as exc:
                raise InvalidParameterError(
                    f"CrowdScenario.paths[{i}]", a, f"JuPedSim refuses the pedestrian: {exc}", "m"
                ) from None

    def _add_streams(self) -> None:
        c = self.crowd
        streams = c.geometry.streams
        self._journeys = [self._journey(s.exit) for s in streams]
        r = c.pedestrian_radius
        try:
            points = _distribute(
                polygon=c.placement_area(), number_of_agents=c.pedestrians,
                distance_to_agents=2 * r + PLACEMENT_GAP, distance_to_polygon=r + 0.05,
                seed=c.seed, max_iterations=20_000,
            )  # fmt: skip
        except Exception as exc:  # JuPedSim's own errors (no free spot left)
            name = "density" if c.density is not None else "pedestrians"
            raise InvalidParameterError(
                f"CrowdScenario.{name}", c.density if c.density is not None else c.pedestrians,
                f"JuPedSim could not place the crowd in the free area ({exc})",
            ) from None  # fmt: skip
        shares = np.array([s.share for s in streams])
        which = self.rng.choice(len(streams), size=c.pedestrians, p=shares / shares.sum())
        speeds = desired_speeds(c, self.rng, c.pedestrians)
        for p, s, v in zip(points, which, speeds, strict=True):
            self._add((float(p[0]), float(p[1])), v, int(s))

    def _add_robot(self, position: tuple[float, float]) -> None:
        stage = self.sim.add_direct_steering_stage()
        journey = self.sim.add_journey(jupedsim().JourneyDescription([stage]))
        try:
            self.robot_id = self.sim.add_agent(
                self.model.robot_agent(position, self.crowd.robot.radius, journey, stage, self.dt)
            )
            self._order = None
        except RuntimeError as exc:
            raise InvalidParameterError(
                "CrowdScenario.start", position, f"JuPedSim refuses the robot's agent: {exc}", "m"
            ) from None

    # ------------------------------------------------------------------ state
    @property
    def time(self) -> float:
        """Simulated time in s."""
        return self.steps * self.dt

    @property
    def count(self) -> int:
        """Pedestrians that have entered so far."""
        return len(self.stream_of)

    def positions(self) -> tuple[NDArray[np.int64], Array]:
        """(indices, positions ``(n, 2)``) of the pedestrians in the simulation now.

        JuPedSim keeps its agents in order (an agent that leaves drops out, a new one comes
        last), so while no agent has entered or left only the positions are read (the
        indices of the last full read are reused; a changed count reads everything again).
        """
        if self._order is not None and not self.parked:
            pts = [a.position for a in self._agents()]
            if len(pts) == self._order.size:
                if not pts:
                    return np.zeros(0, np.int64), np.zeros((0, 2))
                return self._ids, np.asarray(pts, dtype=float)[self._keep]
        return self._read_all()

    def _read_all(self) -> tuple[NDArray[np.int64], Array]:
        """Indices and positions from a full read (and the order reused until it changes)."""
        ids, pts, order = [], [], []
        rid = self.robot_id
        parked = self.parked
        for a in self._agents():
            jid = a.id
            order.append(self.index.get(jid, -1) if jid != rid else -1)
            if jid != rid:
                i = self.index[jid]
                if i not in parked:
                    ids.append(i)
                    pts.append(a.position)
        self._forget_unreported(len(order) - (rid is not None))
        self._order = np.asarray(order, np.int64)
        self._keep = self._order >= 0
        self._ids = self._order[self._keep]
        for i, p in parked.items():
            ids.append(i)
            pts.append(p)
        if not ids:
            return np.zeros(0, np.int64), np.zeros((0, 2))
        return np.asarray(ids, np.int64), np.asarray(pts, dtype=float)

    def _forget_unreported(self, present: int) -> None:
        """Agents JuPedSim removed without listing them (none seen so far in random crowds):
        forget them, and their streams get replacements."""
        if present >= len(self.index) - len(self._leaving):
            return
        alive = {a.id for a in self._agents()}
        for jid in [j for j in self.index if j not in alive and j not in self._leaving]:
            i = self.index.pop(jid)
            if not self.crowd.paths:
                self._queue(self.stream_of[i])

    def _queue(self, stream: int) -> None:
        """Queue the next replacement of ``stream`` (its identity and desired speed drawn now)."""
        k = self._queued[stream]
        self._queued[stream] += 1
        key = self.crowd.pedestrians + k * len(self._queued) + stream
        speed = float(desired_speeds(self.crowd, self._speed_rng[stream], 1)[0])
        self.waiting.append((stream, key, speed))

    def _agents(self) -> Any:
        """The agents, read through JuPedSim's native simulation where it is exposed (twice as
        fast as through its Python handles, which resolve the agent again on every access)."""
        native = getattr(self.sim, "_obj", None)
        return native.agents() if native is not None else self.sim.agents()

    def robot_agent_position(self) -> Array | None:
        """Where JuPedSim has the robot's agent (``None`` when the pedestrians ignore it)."""
        if self.robot_id is None:
            return None
        return np.asarray(self.sim.agent(self.robot_id).position, dtype=float)

    # ------------------------------------------------------------------- step
    def step(self, robot_target: tuple[float, float] | None = None) -> None:
        """One pedestrian step; ``robot_target``: the robot's position at its end.

        Parameters
        ----------
        robot_target
            Where the robot will be at the end of the step (its agent is steered there).
        """
        if self.robot_id is not None and robot_target is not None:
            agent = self.sim.agent(self.robot_id)
            if shapely.contains_xy(self.crowd.geometry.area, *robot_target):
                self.model.steer(agent, robot_target, self.dt)
            else:  # the robot has left the walkable area: its agent waits at the edge
                self.model.steer(agent, agent.position, self.dt)
        self.sim.iterate()
        self.steps += 1
        for jid in self._leaving:  # reached their exit in the previous step: gone now
            self.index.pop(jid, None)
            self._order = None
        # JuPedSim lists the agents that reached their exit; they go at the next step
        self._leaving = [j for j in self.sim.removed_agents() if j in self.index]
        if not self.crowd.paths:
            for j in self._leaving:
                self._queue(self.stream_of[self.index[j]])
        else:  # a given pedestrian stops at its destination and stands there
            for j in self._leaving:
                i = self.index[j]
                self.parked[i] = self.crowd.paths[i][1]
        if self.waiting:
            self._respawn()

    def _respawn(self) -> None:
        """Enter the waiting replacements where there is room (the robot's agent, when the
        pedestrians avoid it, is one of the agents kept clear of)."""
        c = self.crowd
        r = c.pedestrian_radius
        gap = 2 * r + PLACEMENT_GAP
        streams = c.geometry.streams
        still: list[tuple[int, int, float]] = []
        for item in self.waiting:
            s, key, speed = item
            rng = self._spot_rng[s]
            spawn = streams[s].spawn
            x0, y0, x1, y1 = spawn.bounds
            placed = False
            for _ in range(_SPAWN_TRIES):
                p = (
                    float(rng.uniform(x0 + r + 0.05, x1 - r - 0.05)),
                    float(rng.uniform(y0 + r + 0.05, y1 - r - 0.05)),
                )
                if next(iter(self.sim.agents_in_range(p, gap)), None) is not None:
                    continue
                try:
                    self._add(p, speed, s, key)
                except RuntimeError:
                    continue
                placed = True
                break
            if not placed:
                still.append(item)
        self.waiting = still

    def state_at(self) -> dict[str, Any]:
        """A small summary (time, pedestrians in the simulation, entered so far)."""
        return {"time": self.time, "in_simulation": len(self.index), "entered": self.count}
