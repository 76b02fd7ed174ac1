"""JuPedSim's four pedestrian models by name, and how each carries the robot as an agent.

Each model is a small strategy object: the JuPedSim model, the parameters of a pedestrian
(desired speed, body radius, journey) and how the robot's agent is steered when the
pedestrians avoid the robot.

The robot in JuPedSim (``react_to_robot=True``)
    JuPedSim (1.4) cannot place an agent at a given position (and refuses to add one that
    overlaps another, so removing and re-adding it fails exactly when a pedestrian is close),
    so the robot is an agent of radius rho_r on a direct-steering stage that follows it:
    before every pedestrian step its target is set to the robot's position at the end of that
    step and its desired speed (and, for the force models, its current velocity) to the speed
    that reaches it in one step. For the collision-free speed model the pedestrians are
    agents of JuPedSim's per-agent variant (``CollisionFreeSpeedModelV2``, with the model's
    defaults, so the same pedestrians) and the robot's agent has no repulsion from
    neighbours or walls and JuPedSim's smallest time gap (:data:`ROBOT_TIME_GAP`): nothing
    turns it, and only a pedestrian about to touch it ahead slows it. The pedestrians see
    it as one of them (a neighbour to keep their distance from). The simulator records the
    largest offset between the agent and the robot (``CrowdResult.robot_agent_offset``) and
    flags a run whose offset exceeds
    :data:`~designlab.navigation.crowds.simulate.AGENT_OFFSET_BOUND`.

Examples
--------
>>> sorted(MODELS)
['anticipation_velocity', 'collision_free_speed', 'generalized_centrifugal_force', 'social_force']
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from designlab.navigation.crowds.extra import jupedsim

__all__ = ["MODELS", "ROBOT_TIME_GAP", "PedestrianModel"]

#: Time gap of the robot's agent in the collision-free speed model, s (its speed is
#: capped at (gap - contact) / time gap to the agent ahead; JuPedSim's smallest, 0.1 s,
#: slows it only within V_mr x 0.1 s of touching a pedestrian ahead).
ROBOT_TIME_GAP = 0.1


@dataclass(frozen=True)
class PedestrianModel:
    """A JuPedSim model (the collision-free speed model's pedestrians; subclasses for each).

    Attributes
    ----------
    name
        The public name.
    """

    name: str

    def simulation_model(self, seed: int) -> Any:
        """The JuPedSim model object."""
        return jupedsim().CollisionFreeSpeedModelV2()

    def agent(
        self, position: tuple[float, float], speed: float, radius: float, journey: int, stage: int
    ) -> Any:
        """The parameters of one pedestrian (the model's defaults)."""
        return jupedsim().CollisionFreeSpeedModelV2AgentParameters(
            journey_id=journey, stage_id=stage, position=position, desired_speed=speed,
            radius=radius,
        )  # fmt: skip

    def robot_agent(
        self, position: tuple[float, float], radius: float, journey: int, stage: int, dt: float
    ) -> Any:
        """The parameters of the robot's agent (at rest; ``dt``: the pedestrian step)."""
        return self.agent(position, 0.0, radius, journey, stage)

    def steer(self, agent: Any, target: tuple[float, float], dt: float) -> None:
        """Steer the robot's agent to reach ``target`` in one step of ``dt``."""
        x, y = agent.position
        agent.target = target
        agent.model.desired_speed = math.hypot(target[0] - x, target[1] - y) / dt


class _CollisionFreeSpeed(PedestrianModel):
    def robot_agent(
        self, position: tuple[float, float], radius: float, journey: int, stage: int, dt: float
    ) -> Any:
        # no repulsion and a vanishing time gap: the agent goes where it is steered
        return jupedsim().CollisionFreeSpeedModelV2AgentParameters(
            journey_id=journey, stage_id=stage, position=position, desired_speed=0.0,
            radius=radius, time_gap=ROBOT_TIME_GAP, strength_neighbor_repulsion=0.0,
            strength_geometry_repulsion=0.0,
        )  # fmt: skip


class _SocialForce(PedestrianModel):
    def simulation_model(self, seed: int) -> Any:
        return jupedsim().SocialForceModel()

    def agent(
        self, position: tuple[float, float], speed: float, radius: float, journey: int, stage: int
    ) -> Any:
        return jupedsim().SocialForceModelAgentParameters(
            journey_id=journey, stage_id=stage, position=position, desired_speed=speed,
            radius=radius,
        )  # fmt: skip

    def steer(self, agent: Any, target: tuple[float, float], dt: float) -> None:
        x, y = agent.position
        super().steer(agent, target, dt)
        agent.model.velocity = ((target[0] - x) / dt, (target[1] - y) / dt)


class _GeneralizedCentrifugalForce(PedestrianModel):
    def simulation_model(self, seed: int) -> Any:
        return jupedsim().GeneralizedCentrifugalForceModel()

    def agent(
        self, position: tuple[float, float], speed: float, radius: float, journey: int, stage: int
    ) -> Any:
        # an ellipse: its semi-axes are set to the body radius (a disc at rest)
        return jupedsim().GeneralizedCentrifugalForceModelAgentParameters(
            journey_id=journey, stage_id=stage, position=position, desired_speed=speed,
            a_min=radius, b_min=radius, b_max=radius,
        )  # fmt: skip

    def steer(self, agent: Any, target: tuple[float, float], dt: float) -> None:
        x, y = agent.position
        dx, dy = target[0] - x, target[1] - y
        dist = math.hypot(dx, dy)
        agent.target = target
        m = agent.model
        m.desired_speed = m.speed = dist / dt
        m.tau = dt
        if dist > 0:
            m.desired_direction = (dx / dist, dy / dist)


class _AnticipationVelocity(PedestrianModel):
    def simulation_model(self, seed: int) -> Any:
        return jupedsim().AnticipationVelocityModel(rng_seed=seed)

    def robot_agent(
        self, position: tuple[float, float], radius: float, journey: int, stage: int, dt: float
    ) -> Any:
        # no anticipation and a reaction within one step: the agent goes where it is steered
        return jupedsim().AnticipationVelocityModelAgentParameters(
            journey_id=journey, stage_id=stage, position=position, desired_speed=0.0,
            radius=radius, reaction_time=dt, anticipation_time=0.0,
        )  # fmt: skip

    def agent(
        self, position: tuple[float, float], speed: float, radius: float, journey: int, stage: int
    ) -> Any:
        return jupedsim().AnticipationVelocityModelAgentParameters(
            journey_id=journey, stage_id=stage, position=position, desired_speed=speed,
            radius=radius,
        )  # fmt: skip


#: The models by name (JuPedSim 1.4).
MODELS: dict[str, PedestrianModel] = {
    m.name: m
    for m in (
        _CollisionFreeSpeed("collision_free_speed"),
        _GeneralizedCentrifugalForce("generalized_centrifugal_force"),
        _SocialForce("social_force"),
        _AnticipationVelocity("anticipation_velocity"),
    )
}
