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
from designlab.validation import ParamsMixin

__all__ = [
    "FOAM_1",
    "FOAM_2",
    "FOAM_2_MEASURED",
    "FOAM_3",
    "HEAD_MAX",
    "HEAD_MIN",
    "MANIPULATOR_1",
    "MANIPULATOR_2",
    "TABLE_3_2_HEADS",
    "TEST_HEAD",
    "ContactDynamics",
    "Foam",
    "HeadNeck",
]


@dataclass(frozen=True)
class HeadNeck(ParamsMixin):
    """Human head on a neck spring-damper; the torso is infinitely massive.

    Parameters
    ----------
    mass
        Head mass M_h in kg (> 0). The thesis range is 4.4-5.3 kg.
    stiffness
        Neck stiffness K_h in N/m (>= 0). The thesis range is 3-5 kN/m.
    damping
        Neck damping C_h in N s/m (>= 0). The thesis range is 46-130 N s/m.
    name
        Optional label used in reports.

    Examples
    --------
    >>> HeadNeck(mass=4.4, stiffness=3e3, damping=46.0).natural_frequency
    26.111648393354674
    """

    mass: float
    stiffness: float
    damping: float
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", check_positive("HeadNeck.mass", self.mass, "kg"))
        object.__setattr__(
            self, "stiffness", check_nonnegative("HeadNeck.stiffness", self.stiffness, "N/m")
        )
        object.__setattr__(
            self, "damping", check_nonnegative("HeadNeck.damping", self.damping, "N s/m")
        )

    @property
    def natural_frequency(self) -> float:
        """Undamped natural frequency of the head on its neck, rad/s."""
        return math.sqrt(self.stiffness / self.mass)


@dataclass(frozen=True)
class ContactDynamics(ParamsMixin):
    """Effective single-DOF manipulator at the impact point (Sec. 3.4).

    Parameters
    ----------
    mass
        Effective mass M_r in kg (> 0).
    stiffness
        Effective (joint + controller) stiffness K_r in N/m (>= 0).
    damping
        Effective damping C_r in N s/m (>= 0).
    lever_arm
        Distance l_1 from the joint axis to the impact point in m, if known
        (Table 3.1); used to go back to joint level. ``None`` if not known.
    name
        Optional label used in reports.

    Examples
    --------
    >>> ContactDynamics(mass=9.6, stiffness=20e3, damping=250.0).stiffness
    20000.0
    """

    mass: float
    stiffness: float
    damping: float
    lever_arm: float | None = None
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", check_positive("ContactDynamics.mass", self.mass, "kg"))
        object.__setattr__(
            self,
            "stiffness",
            check_nonnegative("ContactDynamics.stiffness", self.stiffness, "N/m"),
        )
        object.__setattr__(
            self, "damping", check_nonnegative("ContactDynamics.damping", self.damping, "N s/m")
        )
        if self.lever_arm is not None:
            object.__setattr__(
                self,
                "lever_arm",
                check_positive("ContactDynamics.lever_arm", self.lever_arm, "m"),
            )


@dataclass(frozen=True)
class Foam(ParamsMixin):
    """Elastomeric foam covering: linear Kelvin-Voigt spring and damper.

    Parameters
    ----------
    stiffness
        Foam stiffness K_c in N/m (> 0).
    damping
        Foam damping C_c in N s/m (>= 0).
    linear_depth
        lambda, the compression up to which the foam is linear, in m (> 0).
        Results with a larger compression are flagged as bottoming
        (docs/impact.md, "Foam bottoming").
    thickness
        Uncompressed thickness T_u in m (>= linear_depth). Defaults to the
        Ch. 4 foam, 0.0254 m, scaled with ``linear_depth``.
    name
        Optional label used in reports.

    Examples
    --------
    >>> Foam.from_damping_ratio(24.25e3, 0.11, head_mass=4.4).damping
    71.8629...
    """

    stiffness: float
    damping: float
    linear_depth: float = 0.02
    thickness: float | None = None
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "stiffness", check_positive("Foam.stiffness", self.stiffness, "N/m")
        )
        object.__setattr__(
            self, "damping", check_nonnegative("Foam.damping", self.damping, "N s/m")
        )
        object.__setattr__(
            self, "linear_depth", check_positive("Foam.linear_depth", self.linear_depth, "m")
        )
        if self.thickness is None:
            object.__setattr__(self, "thickness", self.linear_depth * 0.0254 / 0.02)
        else:
            t = check_positive("Foam.thickness", self.thickness, "m")
            if t < self.linear_depth:
                raise InvalidParameterError(
                    "Foam.thickness",
                    self.thickness,
                    f"must be >= Foam.linear_depth = {self.linear_depth} m",
                    "m",
                )
            object.__setattr__(self, "thickness", t)

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


@dataclass(frozen=True)
class LinkImpact(ParamsMixin):
    """A revolute joint whose link can be struck anywhere in a range of lever arms.

    Scenarios 1 and 2 of Zeng 2011 (Sec. 3.4.3): at lever arm ``l`` the effective
    manipulator is M_r = m_ii/l^2, K_r = K_J/l^2, C_r = C_J/l^2 (3.4.17) and its
    speed is v_r = theta_dot l (3.4.11). Near the joint the manipulator is heavy
    and stiff but slow, far from it light and fast, so the worst impact point
    has to be searched (Sec. 3.7.3).

    Parameters
    ----------
    inertia
        m_ii, kg m^2 (> 0).
    joint_stiffness, joint_damping
        K_J (N m/rad, >= 0) and C_J (N m s/rad, >= 0) of the reduced joint.
    joint_speed
        theta_dot, rad/s (>= 0).
    lever_arm_min, lever_arm_max
        Range of the impact point along the link, m (0 < min <= max).

    Examples
    --------
    >>> link = LinkImpact.from_contact(MANIPULATOR_1, joint_speed=0.25 / 0.078,
    ...                                lever_arm_min=0.01, lever_arm_max=0.078)
    >>> round(link.contact(0.078).mass, 3), round(link.speed(0.078), 3)
    (9.6, 0.25)
    """

    inertia: float
    joint_stiffness: float
    joint_damping: float
    joint_speed: float
    lever_arm_min: float
    lever_arm_max: float
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "inertia", check_positive("LinkImpact.inertia", self.inertia, "kg m^2")
        )
        object.__setattr__(
            self,
            "joint_stiffness",
            check_nonnegative("LinkImpact.joint_stiffness", self.joint_stiffness, "N m/rad"),
        )
        object.__setattr__(
            self,
            "joint_damping",
            check_nonnegative("LinkImpact.joint_damping", self.joint_damping, "N m s/rad"),
        )
        object.__setattr__(
            self,
            "joint_speed",
            check_nonnegative("LinkImpact.joint_speed", self.joint_speed, "rad/s"),
        )
        lo = check_positive("LinkImpact.lever_arm_min", self.lever_arm_min, "m")
        hi = check_positive("LinkImpact.lever_arm_max", self.lever_arm_max, "m")
        if hi < lo:
            raise InvalidParameterError(
                "LinkImpact.lever_arm_max", hi, f"must be >= lever_arm_min = {lo} m", "m"
            )
        object.__setattr__(self, "lever_arm_min", lo)
        object.__setattr__(self, "lever_arm_max", hi)

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
