"""One robot read by navigation, impact and co-design (issue 36.1).

A :class:`RobotDescription` is the robot a designer signs for: its footprint (a disc of
radius rho_r), its physical mass, its speed and acceleration limits, and the part that can
touch a person with that part's contact dynamics (the effective mass, stiffness and
damping of the impact model, Zeng 2011, Sec. 3.2) and height above the floor. From it

* navigation takes :meth:`RobotDescription.navigation_robot` (a
  :class:`~designlab.navigation.HolonomicRobot` with the description's radius, speed
  and acceleration limits; its ``mass`` is the virtual-force mass the VFF gains were
  tuned for, Sec. 5.2.1, a controller setting, not the physical mass);
* impact takes :attr:`RobotDescription.contact` (a
  :class:`~designlab.impact.ContactDynamics`);
* co-design takes both, and sizes each scenario's regions for the design's speed limit
  with :func:`~designlab.navigation.region_sizes` (:func:`sized_scenario`): a region
  is never made smaller than the scenario's, and grows where the speed needs it.

The thesis's robot (:data:`THESIS_ROBOT`) is the Ch. 5-7 holonomic base (0.2 m radius,
10 m/s^2) carrying the Ch. 3 manipulator (MANIPULATOR_1, effective mass 9.6 kg) whose link
meets a standing adult's head. A mobile base whose bumper is the touching part
(:data:`BUMPER_BASE`) meets shins, knees, thighs and hands instead
(:func:`designlab.codesign.injury.region_shares`).

Examples
--------
>>> import designlab as dl
>>> THESIS_ROBOT.navigation_robot(1.0).max_speed, THESIS_ROBOT.contact.mass
(1.0, 9.6)
>>> sc = sized_scenario(dl.navigation.configuration(2), THESIS_ROBOT.navigation_robot(1.0), 1.0)
>>> [round(o.r3, 3) for o in sc.obstacles if o.name == "human"]
[0.87]
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from designlab.errors import InvalidParameterError
from designlab.impact import MANIPULATOR_1, ContactDynamics
from designlab.navigation import (
    CircularObstacle,
    HolonomicRobot,
    Human,
    RectangularObstacle,
    Scenario,
    region_sizes,
)
from designlab.navigation.scenarios import Disc, Rectangle
from designlab.params import Param, declared, param, params_of

__all__ = ["BUMPER_BASE", "THESIS_ROBOT", "RobotDescription", "people_names", "sized_scenario"]

_NAV = params_of(HolonomicRobot)

#: Which part of the robot can touch a person.
CONTACT_PART = Param(
    None, "", "the part of the robot that can touch a person", kind="choice",
    choices=("manipulator_link", "bumper"), name="part",
)  # fmt: skip


@declared
@dataclass(frozen=True)
class RobotDescription:
    """The robot of a co-design: footprint, mass, limits and the part that touches people.

    The navigation radius and limits are the navigation robot's declarations (a design's
    own speed limit replaces ``max_speed``); the touching part's effective mass cannot
    exceed ``mass``.

    Attributes
    ----------
    contact
        The impact model of the touching part (effective mass, stiffness, damping).
    """

    name: str = param(kind="text", doc="label in reports", min_length=1, max_length=80)
    radius: float = dataclasses.field(default=0.2, metadata={"param": _NAV["radius"]})
    max_speed: float = dataclasses.field(default=0.7, metadata={"param": _NAV["max_speed"]})
    max_accel: float = dataclasses.field(default=10.0, metadata={"param": _NAV["max_accel"]})
    mass: float = param("m_R", "kg", doc="physical mass of the robot", gt=0, le=1e4, default=20.0)
    contact: ContactDynamics = dataclasses.field(default=MANIPULATOR_1)
    part: str = dataclasses.field(default="manipulator_link", metadata={"param": CONTACT_PART})
    contact_low: float = param("h_lo", "m", doc="lowest point of the touching part", ge=0,
                               le=3.0, default=1.4)  # fmt: skip
    contact_high: float = param("h_hi", "m", doc="highest point of the touching part", ge=0,
                                le=3.0, default=1.8)  # fmt: skip

    def __post_init__(self) -> None:
        if not isinstance(self.contact, ContactDynamics):
            raise InvalidParameterError(
                "RobotDescription.contact", self.contact, "must be an impact ContactDynamics"
            )
        if self.contact.mass > self.mass:
            raise InvalidParameterError(
                "RobotDescription.contact", self.contact,
                f"has an effective mass {self.contact.mass:g} kg: it must be <= the robot's "
                f"mass {self.mass:g} kg",
            )  # fmt: skip
        if self.contact_low > self.contact_high:
            raise InvalidParameterError(
                "RobotDescription.contact_low", self.contact_low,
                f"must be <= contact_high = {self.contact_high:g} m", "m",
            )  # fmt: skip

    def navigation_robot(self, speed: float | None = None) -> HolonomicRobot:
        """The navigation robot at speed limit ``speed`` (default the description's).

        Parameters
        ----------
        speed
            V_mr, m/s.

        Returns
        -------
        HolonomicRobot
        """
        v = self.max_speed if speed is None else speed
        return HolonomicRobot(radius=self.radius, max_speed=v, max_accel=self.max_accel)


#: The thesis's robot: the Ch. 5-7 holonomic base (rho_r = 0.2 m, a_mr = 10 m/s^2) with
#: the Ch. 3 manipulator (Table 3.1, MANIPULATOR_1: 9.6 kg effective) whose link meets a
#: standing adult's head (1.4-1.8 m). Its total mass is not given by the thesis: 20 kg is
#: this project's assumption (only the effective mass enters the impact model).
THESIS_ROBOT = RobotDescription("thesis base with manipulator (MANIPULATOR_1)")

#: A hospital mobile base whose foam-covered bumper (0.1-0.5 m above the floor) is the
#: touching part: the whole base's mass (20 kg) moves into the contact, on a stiff
#: bumper frame (the MANIPULATOR_1 stiffness and damping).
BUMPER_BASE = RobotDescription(
    "mobile base with bumper", mass=20.0,
    contact=dataclasses.replace(MANIPULATOR_1, mass=20.0), part="bumper",
    contact_low=0.1, contact_high=0.5,
)  # fmt: skip


def people_names(scenario: Scenario) -> tuple[str, ...]:
    """The names of a scenario's moving discs: its people (a static pole is not a person).

    Parameters
    ----------
    scenario
        A navigation scenario.

    Returns
    -------
    tuple of str
    """
    return tuple(o.name for o in scenario.obstacles if isinstance(o, Disc) and o.motion.moving)


def _grown(obstacle: Disc | Rectangle, robot: HolonomicRobot, walker: float,
           sample_time: float) -> Disc | Rectangle:  # fmt: skip
    """The obstacle with r3 and r2 at least the minima for ``robot`` (never smaller)."""
    if isinstance(obstacle, Rectangle):
        cls_ = RectangularObstacle(length=obstacle.length, width=obstacle.width)
    elif obstacle.motion.moving:
        cls_ = Human(radius=obstacle.radius, max_speed=walker)
    else:
        cls_ = CircularObstacle(radius=obstacle.radius)
    r3 = region_sizes(cls_, robot, sample_time).r3_min
    r3 = max(obstacle.r3, r3)
    r2 = max(obstacle.r2, region_sizes(cls_, robot, sample_time, critical_radius=r3).r2)
    if r3 == obstacle.r3 and r2 == obstacle.r2:
        return obstacle
    return dataclasses.replace(obstacle, r2=r2, r3=r3)


def sized_scenario(scenario: Scenario, robot: HolonomicRobot, walker_speed: float) -> Scenario:
    """The scenario with ``robot`` and every region at least the minimum for it.

    Each disc that moves is a person walking at up to ``walker_speed`` (a
    :class:`~designlab.navigation.Human`), a still disc a
    :class:`~designlab.navigation.CircularObstacle`, a rectangle a
    :class:`~designlab.navigation.RectangularObstacle` (the worst offset);
    :func:`~designlab.navigation.region_sizes` gives the minimum r3 and, for the r3 kept,
    the minimum r2 (Zeng 2011, Sec. 5.3). The scenario's own radii are kept where they
    are larger.

    Parameters
    ----------
    scenario
        A navigation scenario.
    robot
        The robot with the design's speed limit.
    walker_speed
        The people's largest walking speed, m/s.

    Returns
    -------
    Scenario
    """
    v = params_of(Human)["max_speed"].check(walker_speed, "walker_speed")
    obstacles = tuple(_grown(o, robot, v, scenario.sample_time) for o in scenario.obstacles)
    return scenario.replace(robot=robot, obstacles=obstacles)
