"""Parameter sets of the impact model (Zeng 2011, Ch. 3-4).

All fields are SI: kg, N/m, N s/m, m. The presets reproduce the thesis's
Tables 3.1-3.3, the head-neck design sets of Sec. 3.6 and the Ch. 4 head
apparatus (docs/impact.md, "Unstated inputs").

Examples
--------
>>> from designlab.impact import MANIPULATOR_1, FOAM_1, HEAD_MIN
>>> MANIPULATOR_1.mass, FOAM_1.stiffness, HEAD_MIN.damping
(9.6, 24250.0, 46.0)
>>> round(FOAM_1.damping_ratio(HEAD_MIN.mass), 3)
0.11
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from designlab.errors import InvalidParameterError, check_nonnegative, check_positive
from designlab.params import Param, declared, param
from designlab.validation import ParamsMixin

__all__ = [
    "FOAM_1",
    "FOAM_2",
    "FOAM_2_MEASURED",
    "FOAM_3",
    "HEAD_MAX",
    "HEAD_MIN",
    "IMPACT_VELOCITY",
    "MANIPULATOR_1",
    "MANIPULATOR_2",
    "TABLE_3_2_HEADS",
    "TEST_HEAD",
    "ContactDynamics",
    "Foam",
    "HeadNeck",
]


@declared
@dataclass(frozen=True)
class HeadNeck(ParamsMixin):
    """Human head on a neck spring-damper; the torso is infinitely massive.

    Examples
    --------
    >>> HeadNeck(mass=4.4, stiffness=3e3, damping=46.0).natural_frequency
    26.111648393354674
    """

    mass: float = param("M_h", "kg", doc="head mass", gt=0, le=1e3, typical=(4.4, 5.3))
    stiffness: float = param("K_h", "N/m", doc="neck stiffness", ge=0, le=1e9, typical=(3e3, 5e3))
    damping: float = param("C_h", "N s/m", doc="neck damping", ge=0, le=1e7, typical=(46.0, 130.2))
    name: str = param(kind="text", default="", doc="optional label used in reports")

    @property
    def natural_frequency(self) -> float:
        """Undamped natural frequency of the head on its neck, rad/s."""
        return math.sqrt(self.stiffness / self.mass)


@declared
@dataclass(frozen=True)
class ContactDynamics(ParamsMixin):
    """Effective single-DOF manipulator at the impact point (Sec. 3.4).

    Examples
    --------
    >>> ContactDynamics(mass=9.6, stiffness=20e3, damping=250.0).stiffness
    20000.0
    """

    mass: float = param(
        "M_r",
        "kg",
        doc="effective manipulator mass (unbounded above: near the joint it grows as 1/l^2)",
        gt=0,
        typical=(9.6, 49.4),
    )
    stiffness: float = param(
        "K_r",
        "N/m",
        doc="effective (joint + controller) stiffness",
        ge=0,
        typical=(14.4e3, 20e3),
    )
    damping: float = param("C_r", "N s/m", doc="manipulator damping", ge=0, typical=(111.0, 250.0))
    lever_arm: float | None = param(
        "l_1",
        "m",
        doc="distance from the joint axis to the impact point (Table 3.1), used "
        "to go back to joint level",
        gt=0,
        le=100,
        optional=True,
        none="not known",
        default=None,
    )
    name: str = param(kind="text", default="", doc="optional label used in reports")


@declared
@dataclass(frozen=True)
class Foam(ParamsMixin):
    """Elastomeric foam covering: linear Kelvin-Voigt spring and damper.

    Results with a compression above ``linear_depth`` are flagged as bottoming
    (docs/impact.md, "Foam bottoming").

    Examples
    --------
    >>> Foam.from_damping_ratio(24.25e3, 0.11, head_mass=4.4).damping
    71.8629...
    """

    stiffness: float = param(
        "K_c", "N/m", doc="foam stiffness", gt=0, le=1e12, typical=(13.8e3, 60.6e3)
    )
    damping: float = param("C_c", "N s/m", doc="foam damping", ge=0, le=1e10, typical=(43.8, 113.6))
    linear_depth: float = param(
        "lambda",
        "m",
        doc="foam linear depth",
        gt=0,
        le=1,
        default=0.02,
        typical=(0.01, 0.03),
    )
    thickness: float | None = param(
        "T_u",
        "m",
        doc="uncompressed thickness (>= linear_depth)",
        gt=0,
        le=1,
        optional=True,
        none="the Ch. 4 foam, 0.0254 m, scaled with linear_depth",
        default=None,
    )
    name: str = param(kind="text", default="", doc="optional label used in reports")

    def __post_init__(self) -> None:
        if self.thickness is None:
            object.__setattr__(self, "thickness", self.linear_depth * 0.0254 / 0.02)
        elif self.thickness < self.linear_depth:
            raise InvalidParameterError(
                "Foam.thickness",
                self.thickness,
                f"must be >= Foam.linear_depth = {self.linear_depth} m",
                "m",
            )

    @classmethod
    def from_damping_ratio(
        cls,
        stiffness: float,
        damping_ratio: float,
        *,
        head_mass: float = 4.4,
        linear_depth: float = 0.02,
        thickness: float | None = None,
        name: str = "",
    ) -> Foam:
        """Build a foam from xi_c, defined with the head mass: C_c = 2 xi_c sqrt(M_h K_c).

        Examples
        --------
        >>> round(Foam.from_damping_ratio(60.6e3, 0.11).damping, 1)
        113.6
        """
        k = check_positive("Foam.stiffness", stiffness, "N/m")
        xi = check_nonnegative("damping_ratio", damping_ratio)
        m = check_positive("head_mass", head_mass, "kg")
        return cls(k, 2.0 * xi * math.sqrt(m * k), linear_depth, thickness, name)

    def damping_ratio(self, head_mass: float = 4.4) -> float:
        """xi_c = C_c / (2 sqrt(M_h K_c)) with the head mass (thesis convention)."""
        return self.damping / (2.0 * math.sqrt(head_mass * self.stiffness))


# --- parameters of the impact functions (declared once) --------------------

#: The closing velocity v_c of an impact (Sec. 3.5): the relative normal speed of robot
#: and head at first contact.
IMPACT_VELOCITY = Param(
    "v_c", "m/s", "closing velocity", gt=0, le=20, typical=(0.25, 2.0), name="impact_velocity"
)


# --- presets (Zeng 2011) ---------------------------------------------------

#: Table 3.1, Manipulator 1: the custom direct-drive arm (App. A.2), as printed. Recomputed
#: from its joint data (m_11 = 0.059 kg m^2, l_1 = 0.078 m, the PD gains of Sec. 4.3.1) it
#: is M_r = 9.70 kg, K_r = 20.0 kN/m, C_r = 250 N s/m: the printed 9.6 kg is 1 % low (the
#: thesis's own arithmetic); the preset keeps the printed values to reproduce the tables.
MANIPULATOR_1 = ContactDynamics(9.6, 20.0e3, 250.0, lever_arm=0.078, name="Manipulator 1")
#: Table 3.1, Manipulator 2: Puma 560 joint 1.
MANIPULATOR_2 = ContactDynamics(49.4, 14.4e3, 111.0, lever_arm=0.5, name="Manipulator 2")

#: Foam 1 as identified in App. A.1 and used in the Fig. 3.10-3.12/3.16 captions.
FOAM_1 = Foam(24.25e3, 71.9, name="Foam 1")
#: Foam 2 as printed in Table 3.3.
FOAM_2 = Foam(13.8e3, 43.8, name="Foam 2")
#: Foam 2 with the App. A.1 measured stiffness, used for Ch. 4 (docs/impact.md, "Unstated inputs").
FOAM_2_MEASURED = Foam(13.48e3, 43.8, name="Foam 2 (measured)")
#: Foam 3 of Table 3.3.
FOAM_3 = Foam(60.6e3, 113.6, name="Foam 3")

#: Minimum head-neck parameters (Sec. 3.6): conservative for head acceleration.
HEAD_MIN = HeadNeck(4.4, 3.0e3, 46.0, name="minimum head-neck")
#: Maximum head-neck parameters (Sec. 3.6): conservative for force and compression.
HEAD_MAX = HeadNeck(5.3, 5.0e3, 130.2, name="maximum head-neck")
#: Ch. 4 head apparatus: 4.4 kg head, 4 kN/m neck springs, no damper
#: (docs/impact.md, "Unstated inputs").
TEST_HEAD = HeadNeck(4.4, 4.0e3, 0.0, name="Ch. 4 test head")

#: Table 3.2 simulations 1-4 as (manipulator, head) pairs.
TABLE_3_2_HEADS: dict[int, tuple[ContactDynamics, HeadNeck]] = {
    1: (MANIPULATOR_1, HeadNeck(4.4, 5.0e3, 130.0, name="Table 3.2 sim 1")),
    2: (MANIPULATOR_2, HeadNeck(4.4, 5.0e3, 130.0, name="Table 3.2 sim 2")),
    3: (MANIPULATOR_1, HeadNeck(4.4, 3.0e3, 46.0, name="Table 3.2 sim 3")),
    4: (MANIPULATOR_2, HeadNeck(5.3, 5.0e3, 130.0, name="Table 3.2 sim 4")),
}


@declared
@dataclass(frozen=True)
class LinkImpact(ParamsMixin):
    """A revolute joint whose link can be struck anywhere in a range of lever arms.

    Scenarios 1 and 2 of Zeng 2011 (Sec. 3.4.3): at lever arm ``l`` the effective
    manipulator is M_r = m_ii/l^2, K_r = K_J/l^2, C_r = C_J/l^2 (3.4.17) and its
    speed is v_r = theta_dot l (3.4.11). Near the joint the manipulator is heavy
    and stiff but slow, far from it light and fast, so the worst impact point
    has to be searched (Sec. 3.7.3).

    Examples
    --------
    >>> link = LinkImpact.from_contact(MANIPULATOR_1, joint_speed=0.25 / 0.078,
    ...                                lever_arm_min=0.01, lever_arm_max=0.078)
    >>> round(link.contact(0.078).mass, 3), round(link.speed(0.078), 3)
    (9.6, 0.25)
    """

    inertia: float = param("m_ii", "kg m^2", doc="link inertia about the joint", gt=0, le=1e4)
    joint_stiffness: float = param(
        "K_J", "N m/rad", doc="stiffness of the reduced joint", ge=0, le=1e9
    )
    joint_damping: float = param(
        "C_J", "N m s/rad", doc="damping of the reduced joint", ge=0, le=1e7
    )
    joint_speed: float = param("theta_dot", "rad/s", doc="joint speed", ge=0, le=1e3)
    lever_arm_min: float = param(
        "l_min", "m", doc="nearest impact point along the link", gt=0, le=100
    )
    lever_arm_max: float = param(
        "l_max", "m", doc="farthest impact point along the link (>= lever_arm_min)", gt=0, le=100
    )
    name: str = param(kind="text", default="", doc="optional label used in reports")

    def __post_init__(self) -> None:
        if self.lever_arm_max < self.lever_arm_min:
            raise InvalidParameterError(
                "LinkImpact.lever_arm_max",
                self.lever_arm_max,
                f"must be >= lever_arm_min = {self.lever_arm_min} m",
                "m",
            )

    @classmethod
    def from_contact(
        cls,
        contact: ContactDynamics,
        *,
        joint_speed: float,
        lever_arm_min: float,
        lever_arm_max: float,
        lever_arm: float | None = None,
    ) -> LinkImpact:
        """Recover joint-level values from an effective manipulator by (3.4.17)."""
        arm = lever_arm if lever_arm is not None else contact.lever_arm
        if arm is None:
            raise InvalidParameterError(
                "lever_arm", None, "is needed: the ContactDynamics has no lever_arm", "m"
            )
        arm = check_positive("lever_arm", arm, "m")
        return cls(
            contact.mass * arm**2,
            contact.stiffness * arm**2,
            contact.damping * arm**2,
            joint_speed,
            lever_arm_min,
            lever_arm_max,
            name=contact.name,
        )

    def contact(self, lever_arm: float) -> ContactDynamics:
        """Effective manipulator at ``lever_arm`` (3.4.17)."""
        l2 = lever_arm**2
        return ContactDynamics(
            self.inertia / l2,
            self.joint_stiffness / l2,
            self.joint_damping / l2,
            lever_arm=lever_arm,
            name=self.name,
        )

    def speed(self, lever_arm: float) -> float:
        """Manipulator speed at ``lever_arm``, m/s (3.4.11)."""
        return self.joint_speed * lever_arm
