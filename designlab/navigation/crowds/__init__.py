"""Navigation among crowds: the robot among pedestrians simulated by JuPedSim (issue 23).

The API (stable; later additions never rename)::

    nav = dl.navigation
    crowd = nav.crowd("corridor_counterflow", pedestrians=40, width=4.0, length=30.0, seed=0,
                      model="collision_free_speed", react_to_robot=False)  # -> nav.CrowdScenario
    res = nav.simulate(crowd, nav.VFFGains(4.3, 0.68, 20.3, 240.7), method="vff",
                       stabilising="lyapunov")                             # -> nav.CrowdResult
    res.arrival_time, res.min_distance, res.entered_critical, res.collided, res.status
    res.warnings, res.times (T,), res.robot_positions (T, 2), res.robot_velocities (T, 2)
    res.pedestrian_positions (T, N, 2)   # NaN where a pedestrian is not in the simulation
    res.pedestrian_ids (N,), res.nearest_distance (T,), res.desired_speeds (N,), res.to_frame()
    res.faced()    # the crowd the robot met (pedpy): measured density and pedestrian speed
    peds = nav.simulate_pedestrians(crowd)  # the same seed, no robot -> nav.PedestrianRun:
    peds.times (T,), peds.pedestrian_positions (T, N, 2), peds.pedestrian_ids, peds.to_frame()

``crowd(layout, pedestrians=None, *, density=None, ...)``: ``density`` (persons/m^2 of the
walkable area) instead of a number; any other field of :class:`CrowdScenario` by keyword
(``horizon``, ``desired_speed``, ``desired_speed_sd``, ``max_desired_speed``,
``pedestrian_radius``, ``robot``, ``neighbours``, ``critical_radius``, ``active_radius``,
``start``, ``goal``, ``origin``, ``paths``, ``bottleneck_width``, ``pedestrian_step``).
``nav.simulate(crowd, gains, *, method, stabilising, tie_side, arrival_tolerance,
dynamics_step, cbf_gains, order)`` is :func:`simulate_crowd`. The records are taken at every
pedestrian step (``pedestrian_step``, 0.01 s): ``times[i] = i * pedestrian_step``.

Modules: :mod:`~.layouts` (the four layouts), :mod:`~.scenario` (:class:`CrowdScenario`,
regions of pedestrians and walls), :mod:`~.models` (JuPedSim's four models, the robot as an
agent), :mod:`~.pedestrians` (the JuPedSim simulation), :mod:`~.slots` (N obstacles through
K slots of one compiled step), :mod:`~.simulate` (the lock-step), :mod:`~.bookkeeping` (its
per-period bookkeeping, compiled), :mod:`~.results` (what a run returns), :mod:`~.faced` (the
density and speed of the crowd the robot met, by pedpy).

Examples
--------
>>> import designlab as dl
>>> nav = dl.navigation
>>> crowd = nav.crowd("corridor_counterflow", pedestrians=10, length=12.0, seed=0, horizon=2.0)
>>> res = nav.simulate(crowd, nav.VFFGains(4.3, 0.68, 20.3, 240.7))
>>> res.times.shape, res.pedestrian_positions.shape[0]
((205,), 205)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from designlab._lazy import attach as _attach

if TYPE_CHECKING:  # the public names, imported on first use (designlab._lazy)
    from designlab.navigation.crowds.layouts import LAYOUTS
    from designlab.navigation.crowds.models import MODELS
    from designlab.navigation.crowds.scenario import DENSITY, CrowdScenario, crowd
    from designlab.navigation.crowds.simulate import (
        ORDER,
        CrowdResult,
        CrowdStatus,
        PedestrianRun,
        accepts_crowds,
        simulate_crowd,
        simulate_pedestrians,
    )

__all__ = [
    "DENSITY",
    "LAYOUTS",
    "MODELS",
    "ORDER",
    "CrowdResult",
    "CrowdScenario",
    "CrowdStatus",
    "PedestrianRun",
    "accepts_crowds",
    "crowd",
    "simulate_crowd",
    "simulate_pedestrians",
]

_attach(__name__)
