"""What a crowd run returns: :class:`CrowdResult` (the robot among the pedestrians) and
:class:`PedestrianRun` (the pedestrians alone), with their status :class:`CrowdStatus`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.navigation.crowds.faced import MEASURE_HALF_WIDTH, FacedCrowd, faced_by
from designlab.navigation.crowds.scenario import CrowdScenario
from designlab.results import Result, Status

__all__ = ["CrowdResult", "CrowdStatus", "PedestrianRun"]

Array = NDArray[np.float64]


class CrowdStatus(Status):
    """Status of a crowd run (:class:`CrowdResult`, :class:`PedestrianRun`).

    ``OK``: the robot arrived (a pedestrian-only run: simulated to the horizon);
    ``NOT_ARRIVED``: the robot did not reach the goal within the horizon;
    ``PEDESTRIAN_SIMULATOR_FAILED``: JuPedSim stopped with an error (in ``warnings``); the
    run is kept up to that time. Collisions and critical-region entries are flags and warnings.
    """

    OK = "ok"
    NOT_ARRIVED = "not_arrived"
    PEDESTRIAN_SIMULATOR_FAILED = "pedestrian_simulator_failed"


@dataclass(frozen=True)
class PedestrianRun(Result):
    """The pedestrians of a crowd scenario over time (with or without the robot).

    Attributes
    ----------
    crowd
        The :class:`CrowdScenario`.
    times
        Times of the records, s ``(T,)``: every pedestrian step.
    pedestrian_positions
        ``(T, N, 2)`` positions in m; NaN where a pedestrian is not in the simulation.
    pedestrian_ids
        ``(N,)`` the pedestrians' identities, in the order they entered (the same person has
        the same identity with and without the robot:
        :mod:`~designlab.navigation.crowds.pedestrians`).
    desired_speeds
        ``(N,)`` their desired speeds, m/s.
    status
        ``"ok"`` or ``"pedestrian_simulator_failed"``.
    warnings
        What a user should know.
    """

    crowd: CrowdScenario
    times: Array = field(repr=False)
    pedestrian_positions: Array = field(repr=False)
    pedestrian_ids: NDArray[np.int64] = field(repr=False)
    desired_speeds: Array = field(repr=False)
    status: str = CrowdStatus.OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """Long format: ``t_s``, ``pedestrian``, ``x_m``, ``y_m`` (rows where it is present)."""
        return long_frame(self.times, self.pedestrian_positions, self.pedestrian_ids)


def long_frame(times: Array, P: Array, ids: NDArray[np.int64]) -> pd.DataFrame:
    """Positions ``(T, N, 2)`` in long format (rows where a pedestrian is present).

    Parameters
    ----------
    times
        ``(T,)`` s.
    P
        ``(T, N, 2)`` m, NaN where absent.
    ids
        ``(N,)`` pedestrian indices.
    """
    T, N = P.shape[:2]
    tt = np.repeat(times, N)
    ii = np.tile(ids, T)
    xy = P.reshape(T * N, 2)
    keep = ~np.isnan(xy[:, 0])
    return pd.DataFrame(
        {"t_s": tt[keep], "pedestrian": ii[keep], "x_m": xy[keep, 0], "y_m": xy[keep, 1]}
    )


@dataclass(frozen=True)
class CrowdResult(Result):
    """One run of the robot among the pedestrians.

    Attributes
    ----------
    crowd
        The :class:`CrowdScenario`.
    method, stabilising, gains
        Navigation method, stabilising-force mode and gains.
    arrival_time
        First time within the arrival tolerance of the goal, s (inf if never).
    min_distance
        Smallest centre distance to any pedestrian before arrival, m: at every dynamics step
        for the pedestrians that may come within r2 in a period, at the navigation samples
        for the others (so exact whenever it is below r2).
    min_surface_distance
        ``min_distance`` minus rho_r + rho_p, m (<= 0: a collision).
    min_wall_distance
        Smallest distance to a wall's contour, m (exact whenever it is below the walls' r2).
    entered_critical
        Whether the robot entered a pedestrian's (d <= r3) or a wall's critical region.
    collided
        Whether it touched a pedestrian or a wall.
    critical_time
        Time spent inside critical regions, s.
    energy
        L_energy per ohm of winding resistance (A^2 s).
    slot_overflow
        Navigation periods with more pedestrians in the active region than slots.
    robot_agent_offset
        Largest distance between the robot's JuPedSim agent and where it was steered (the
        robot at the end of each pedestrian step; with ``order="pedestrians_first"``, the
        robot at the period's start), m (0 when the pedestrians ignore the robot).
    times
        ``(T,)`` times of the records, s: every pedestrian step.
    robot_positions, robot_velocities
        ``(T, 2)`` in m and m/s.
    pedestrian_positions
        ``(T, N, 2)`` in m; NaN where a pedestrian is not in the simulation.
    pedestrian_ids
        ``(N,)`` the pedestrians' identities (the same person has the same identity with and
        without the robot: :mod:`~designlab.navigation.crowds.pedestrians`).
    nearest_distance
        ``(T,)`` centre distance to the nearest pedestrian, m (inf when there is none).
    desired_speeds
        ``(N,)`` the pedestrians' desired speeds, m/s.
    status
        :class:`CrowdStatus`.
    warnings
        What a user should know.
    critical_overlaps
        Navigation periods in which two pedestrians in the active region had intersecting
        critical regions (Sec. 6.4.3: no path between them stays outside both; the thesis
        merges such obstacles, which for pedestrians would change from period to period, so
        their fields are summed and the critical-region rule applies to each).
    outcome
        One of ``arrived``, ``collision``, ``timeout``, ``left_area``, ``simulator_failed``:
        the run's first event (a contact with a pedestrian or wall, the robot leaving the
        walkable area, JuPedSim stopping, the arrival), ``timeout`` if none
        (:data:`~designlab.navigation.crowds.simulate.OUTCOMES`).
    outcome_time
        When it happened, s (a contact: its dynamics step; a timeout: the time limit).
    coupling_exceeded
        Whether ``robot_agent_offset`` exceeded
        :data:`~designlab.navigation.crowds.simulate.AGENT_OFFSET_BOUND` (the pedestrians
        then did not see the robot where it was).
    collision_by, critical_by
        Who caused the first contact and the first critical-region entry: ``"robot"`` (its
        velocity towards the person positive at that instant), ``"pedestrian"``, ``"wall"``
        or ``"none"`` (no such event), found at the event's own dynamics step
        (:func:`~designlab.navigation.crowds.field_metrics.first_entry` on the period's
        steps, pedestrians interpolated within theirs), not at the recorded samples.
    pedestrian_seconds, robot_seconds
        CPU time spent in JuPedSim (stepping and reading the pedestrians) and on the robot's
        side (slots, compiled step, CBF, distances and records), s.
    """

    crowd: CrowdScenario
    method: str
    stabilising: str
    gains: dict[str, float]
    arrival_time: float
    min_distance: float
    min_surface_distance: float
    min_wall_distance: float
    entered_critical: bool
    collided: bool
    critical_time: float
    energy: float
    slot_overflow: int
    robot_agent_offset: float
    times: Array = field(repr=False)
    robot_positions: Array = field(repr=False)
    robot_velocities: Array = field(repr=False)
    pedestrian_positions: Array = field(repr=False)
    pedestrian_ids: NDArray[np.int64] = field(repr=False)
    nearest_distance: Array = field(repr=False)
    desired_speeds: Array = field(repr=False)
    status: str = CrowdStatus.OK
    warnings: tuple[str, ...] = ()
    critical_overlaps: int = 0
    outcome: str = "timeout"
    outcome_time: float = math.nan
    coupling_exceeded: bool = False
    collision_by: str = "none"
    critical_by: str = "none"
    pedestrian_seconds: float = field(default=0.0, repr=False, compare=False)
    robot_seconds: float = field(default=0.0, repr=False, compare=False)

    @property
    def arrived(self) -> bool:
        return math.isfinite(self.arrival_time)

    def pedestrians(self) -> PedestrianRun:
        """The pedestrians of this run as a :class:`PedestrianRun`."""
        return PedestrianRun(
            self.crowd, self.times, self.pedestrian_positions, self.pedestrian_ids,
            self.desired_speeds, self.status, self.warnings,
        )  # fmt: skip

    def faced(self, half_width: float = MEASURE_HALF_WIDTH.default) -> FacedCrowd:
        """The density and speed of the pedestrians the robot met (pedpy, in the band of half
        width ``half_width`` m along its straight path), as
        :func:`~designlab.navigation.crowds.faced.faced_by`.

        Parameters
        ----------
        half_width
            h_M in m (cut to the path's clearance from the walls).
        """
        return faced_by(self, half_width)

    def to_frame(self) -> pd.DataFrame:
        """One row: the scenario's settings, the method, the run's outcome and the crowd it
        met (``measured_density_per_m2``, ``mean_ped_speed_m_per_s``: :meth:`faced`)."""
        c = self.crowd
        met = self.faced()
        row: dict[str, Any] = {
            "layout": c.layout, "pedestrians": c.pedestrians, "density": c.density,
            "seed": c.seed, "model": c.model, "react_to_robot": c.react_to_robot,
            "method": self.method, "stabilising": self.stabilising,
            "T_arrive_s": self.arrival_time, "d_min_m": self.min_distance,
            "d_surface_min_m": self.min_surface_distance, "d_wall_min_m": self.min_wall_distance,
            "entered_critical": self.entered_critical, "collided": self.collided,
            "critical_time_s": self.critical_time, "L_energy_J_per_ohm": self.energy,
            "slot_overflow": self.slot_overflow, "critical_overlaps": self.critical_overlaps,
            "outcome": self.outcome, "outcome_time_s": self.outcome_time,
            "robot_agent_offset_m": self.robot_agent_offset,
            "coupling_exceeded": self.coupling_exceeded, "collision_by": self.collision_by,
            "critical_by": self.critical_by,
            "measured_density_per_m2": met.measured_density_per_m2,
            "mean_ped_speed_m_per_s": met.mean_ped_speed_m_per_s, "status": str(self.status),
        }  # fmt: skip
        return pd.DataFrame([row])
