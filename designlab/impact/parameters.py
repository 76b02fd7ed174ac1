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

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError, check_nonnegative, check_positive
from designlab.params import ARG, Param, check_size, declared, param, params_of
from designlab.validation import ParamsMixin, real_array

__all__ = [
    "BAND_POINTS",
    "C_CONT",
    "C_MECH",
    "DAMPING_GRID",
    "DAMPING_POINTS",
    "FOAM_1",
    "FOAM_2",
    "FOAM_2_MEASURED",
    "FOAM_3",
    "FOAM_PRESETS",
    "HEAD_LEVELS",
    "HEAD_MAX",
    "HEAD_MIN",
    "HEAD_PRESETS",
    "HEAD_SPEED",
    "HEAD_VELOCITY",
    "HIC_SAMPLES",
    "HIC_WINDOW",
    "HUMAN_SPEED",
    "IMPACT_VELOCITY",
    "K_CONT",
    "K_MECH",
    "MANIPULATOR_1",
    "MANIPULATOR_2",
    "MAX_COMPRESSION",
    "MAX_LOBE_STEPS",
    "OMEGA_MAX",
    "RATIO_POINTS",
    "ROBOT_PRESETS",
    "ROBOT_VELOCITY",
    "RTOL",
    "SEED",
    "SIMULATION_DURATION",
    "SIMULATION_SAMPLES",
    "STIFFNESS_RATIO",
    "STOP_TIME",
    "TABLE_3_2_HEADS",
    "TEST_HEAD",
    "THESIS_HEAD_RANGE",
    "TIME_SCALE_RATIO",
    "USABLE_TOLERANCE",
    "VERDICT_TOLERANCE",
    "WORST_CASE_SAMPLES",
    "WORST_CASE_TOLERANCE",
    "ContactDynamics",
    "Foam",
    "HeadNeck",
    "HeadRange",
    "LinkImpact",
    "as_field",
    "check_closing_velocity",
    "check_grid",
    "check_pair",
]


def as_field(decl: Param, *, default: Any = dataclasses.MISSING, **kwargs: Any) -> Any:
    """A dataclass field declared by an existing :class:`~designlab.params.Param`.

    For a parameter that is both a function argument (a module-level ``Param``)
    and a field of a model, or a field of two models: it is declared once and
    every use refers to that declaration (:func:`designlab.params.declared`
    fills in the field's name, owner and default).

    Parameters
    ----------
    decl
        The declaration.
    default
        The field's default (omit for a required field).
    **kwargs
        Further arguments of :func:`dataclasses.field` (``init``, ``kw_only``, ...).

    Returns
    -------
    dataclasses.Field
    """
    if default is not dataclasses.MISSING:
        kwargs["default"] = default
    return dataclasses.field(metadata={"param": decl}, **kwargs)


def check_pair(decl: Param, value: Any, name: str, *, strict: bool = True) -> tuple[float, float]:
    """A ``(low, high)`` pair of values of one parameter, each checked by ``decl``.

    Parameters
    ----------
    decl
        The declaration of each end.
    value
        The pair given.
    name
        The parameter's name in the error message.
    strict
        ``low < high`` (else ``low <= high``).

    Returns
    -------
    tuple of float

    Examples
    --------
    >>> check_pair(params_of(HeadNeck)["mass"], (4.4, 5.3), "mass")
    (4.4, 5.3)
    """
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence | np.ndarray):
        raise InvalidParameterError(name, value, "must be a pair (low, high)", decl.unit)
    if len(value) != 2:
        raise InvalidParameterError(name, value, "must be a pair (low, high)", decl.unit)
    lo, hi = (decl.check(v, name) for v in value)
    if not (lo < hi if strict else lo <= hi):
        rel = "<" if strict else "<="
        raise InvalidParameterError(name, value, f"needs low {rel} high", decl.unit)
    return float(lo), float(hi)


def check_grid(decl: Param, count: Param, value: Any, name: str) -> NDArray[np.float64]:
    """A 1-D grid of values of one parameter: each checked by ``decl``, their number by ``count``.

    The number of values is checked before the array is built, so a cap on
    ``count`` bounds the work of whatever runs over the grid.

    Parameters
    ----------
    decl
        The declaration of each value.
    count
        The declaration of the number of values (an ``"integer"`` with its cap).
    value
        Array-like values.
    name
        The parameter's name in the error message.

    Returns
    -------
    numpy.ndarray
    """
    if isinstance(value, (str, bytes, bool, np.bool_)):
        raise InvalidParameterError(name, value, "must be a 1-D array of numbers", decl.unit)
    size = np.size(value) if isinstance(value, np.ndarray) else None
    if size is None:
        try:
            size = len(value) if hasattr(value, "__len__") else 1
        except TypeError:
            size = 1
    try:
        count.check(int(size), f"{name} (number of values)")
    except InvalidParameterError as err:
        if size > 10:
            raise
        raise InvalidParameterError(  # a few values: shown as given
            name, value, f"must have {count.allowed()} values, not {size}", decl.unit
        ) from err
    check_size(name, f"{size} values", float(size))
    if isinstance(value, (list, tuple)) or (isinstance(value, np.ndarray) and value.dtype == bool):
        for i, x in enumerate(value if isinstance(value, (list, tuple)) else value.flat):
            if isinstance(x, (bool, np.bool_)):
                raise InvalidParameterError(f"{name}[{i}]", x, "must be a number, not a boolean")
    try:
        arr = np.atleast_1d(np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        raise InvalidParameterError(
            name, value, "must be a 1-D array of numbers", decl.unit
        ) from None
    if arr.ndim != 1:
        raise InvalidParameterError(name, value, "must be a 1-D array of numbers", decl.unit)
    for i, x in enumerate(arr):
        decl.check(float(x), f"{name}[{i}]")
    return arr


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

    # M_r and K_r have no upper bound: near the joint they grow as 1/l^2 (3.4.17)
    mass: float = param("M_r", "kg", doc="effective manipulator mass", gt=0, typical=(9.6, 49.4))
    stiffness: float = param(
        "K_r", "N/m", doc="manipulator stiffness", ge=0, typical=(14.4e3, 20e3)
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

    #: a fixed manipulator: struck at one point, at a given v_c
    along_link: ClassVar[bool] = False


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


def check_closing_velocity(value: Any, name: str = "impact_velocity") -> Any:
    """v_c of a response (a scalar or an array): finite, at most the cap of :data:`IMPACT_VELOCITY`.

    The one declaration of the closing velocity holds for every impact function.
    A response (:func:`~designlab.impact.simulate`, the metrics, the transfer
    functions) also takes v_c <= 0: the documented no-impact case (zero
    response, status ``no_impact``, item I5); any positive value must satisfy
    :data:`IMPACT_VELOCITY`.

    Parameters
    ----------
    value
        v_c in m/s, a number or an array of numbers.
    name
        The name in the error message.

    Returns
    -------
    float or numpy.ndarray
        ``value`` as a float (a scalar) or a float array.

    Examples
    --------
    >>> check_closing_velocity(1.25), check_closing_velocity(-0.5)
    (1.25, -0.5)
    >>> check_closing_velocity([0.4, 1e6])
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: impact_velocity = 1000000.0 m/s is not allowed: ...
    """
    arr = real_array(name, value, IMPACT_VELOCITY.unit)
    closing = arr[arr > 0]
    if closing.size:
        IMPACT_VELOCITY.check(float(closing.max()), name)
    return float(arr) if arr.ndim == 0 else arr


#: The speed of the person's head toward the robot (Sec. 3.4): added to the
#: manipulator's speed to give v_c, subtracted to give the safe manipulator speed.
HUMAN_SPEED = Param(
    "v_h", "m/s", "head speed toward the robot", ge=0, le=20, typical=(0.0, 1.0),
    name="human_speed",
)  # fmt: skip

#: Values per parameter of the head-range grid on which the worst head is sought.
HEAD_LEVELS = Param(
    None, "", "values per head-neck parameter of the worst-head grid", kind="integer", ge=2,
    le=9, default=3, name="head_levels",
)  # fmt: skip

#: The manipulator's speed at contact along the contact normal, v_r(0) (Sec. 3.4).
ROBOT_VELOCITY = Param(
    "v_r", "m/s", "manipulator velocity at contact along the normal", ge=-20, le=20, name="v_r"
)
#: The head's velocity along the normal, v_h(0) (negative: toward the robot; v_c = v_r - v_h).
HEAD_VELOCITY = Param(
    "v_h", "m/s", "head velocity along the normal (negative: toward the robot)", ge=-20,
    le=20, name="v_h",
)  # fmt: skip

#: A head speed that must be non-zero (the worst impact point of Fig. 3.16 scales with it).
HEAD_SPEED = Param("v_h", "m/s", "head speed toward the link", gt=0, le=20, name="head_speed")

#: Window of the constrained impact's metrics (head against a wall): the time within
#: which the thesis recommends stopping the manipulator (Sec. 3.6), 0.05 s.
STOP_TIME = Param(
    "t_stop", "s", "window of the constrained impact's metrics", gt=0, le=1.0,
    typical=(0.05, 0.05), default=0.05, name="stop_time",
)  # fmt: skip

#: The HIC window t2 - t1 (docs/impact.md, "HIC"): 0.015 s (HIC15) or 0.036 s (HIC36).
HIC_WINDOW = Param(
    "T_HIC", "s", "longest HIC window t2 - t1", gt=0, le=0.036, typical=(0.015, 0.036),
    default=0.015, name="window",
)  # fmt: skip

#: A value of the C_c grid of a foam envelope (Sec. 3.9).
DAMPING_GRID = Param(
    "C_c", "N s/m", "foam damping of the envelope's grid", ge=0, le=1e5, typical=(0.0, 200.0),
    name="damping",
)  # fmt: skip

#: How many damping values a foam envelope solves (each costs a root-finding per boundary).
DAMPING_POINTS = Param(
    None, "", "number of damping values of the envelope's grid", kind="integer", ge=1, le=2001,
    name="damping",
)  # fmt: skip

#: Relative accuracy of a foam envelope's boundaries in K_c.
RTOL = Param(None, "", "relative accuracy of the boundaries in K_c", gt=0, lt=1e-2, name="rtol")

#: The thickness limit eps_max <= lambda (3.9.3): the foam's linear depth, as declared
#: on :class:`Foam` (a foam envelope's ``max_compression``).
MAX_COMPRESSION = dataclasses.replace(
    params_of(Foam)["linear_depth"], name="max_compression", owner="", default=None
)

#: Grid steps after which the search for the end of the first lobe gives up.
MAX_LOBE_STEPS = Param(
    None, "", "grid steps of the search for the end of the first lobe", kind="integer",
    ge=1, le=1_000_000, default=4096, name="max_lobe_steps",
)  # fmt: skip

#: Grid points over the first lobe of the HIC window search.
HIC_SAMPLES = Param(
    None, "", "grid points over the first lobe of the HIC window search", kind="integer",
    ge=3, le=100_000, name="samples",
)  # fmt: skip

#: Relative distance in K_c to the nearest boundary within which a foam is "on the
#: boundary" (:func:`~designlab.impact.verdict.foam_verdict`).
VERDICT_TOLERANCE = Param(
    None, "", "relative distance in K_c within which a foam is on the boundary", ge=0, lt=0.5,
    typical=(0.01, 0.01), default=0.01, name="tolerance",
)  # fmt: skip

#: Random cases per boundary point of the worst-case check, after its deterministic corners.
WORST_CASE_SAMPLES = Param(
    None, "", "random samples per boundary point of the worst-case check, after its "
    "deterministic corners (0: corners only)", kind="integer", ge=0, le=10_000,
    typical=(0.0, 64.0), name="samples",
)  # fmt: skip
#: Seed of the random cases of the worst-case check.
SEED = ARG.seed.but(doc="seed of the random cases")
#: Relative excess of a metric over its limit that the worst-case check tolerates
#: (the solver's accuracy).
WORST_CASE_TOLERANCE = Param(
    None, "", "relative excess of a ratio over 1 tolerated (solver accuracy)", ge=0, lt=0.1,
    name="tolerance",
)  # fmt: skip

#: How many samples :func:`~designlab.impact.simulate` returns of each time history (six
#: float arrays of this length; a million is 48 MB).
SIMULATION_SAMPLES = Param(
    None, "", "number of samples of the time histories", kind="integer", ge=2, le=1_000_000,
    typical=(2001.0, 2001.0), name="samples",
)  # fmt: skip
#: Length of the time histories of :func:`~designlab.impact.simulate`.
SIMULATION_DURATION = Param(
    "t_end", "s", "length of the returned time histories", gt=0, le=1e3, optional=True,
    none="twice the impact period (stop_time for the constrained impact)", name="duration",
)  # fmt: skip

#: The widest spread of time scales of one design that double precision serves: the ratio
#: of its fastest to its slowest mode, estimated from the characteristic polynomial's
#: coefficients (:func:`designlab.impact.conditioning.time_scale_ratio`; docs/impact.md,
#: "Limits"). Beyond it the first lobe is a small difference of huge slow-mode terms.
TIME_SCALE_RATIO = Param(
    None, "", "estimated from the characteristic polynomial's coefficients", ge=1, le=1e4,
    typical=(2.0, 100.0), name="time_scale_ratio",
)  # fmt: skip

# --- the series joint (3.4.6) and its reductions (docs/impact_joint.md) ----------

#: Transmission stiffness K_mech of the series joint (3.4.6), joint level.
K_MECH = Param("K_mech", "N m/rad", "transmission stiffness", gt=0, le=1e12, typical=(1e2, 1e6))
#: Transmission damping C_mech, joint level.
C_MECH = Param("C_mech", "N m s/rad", "transmission damping", ge=0, le=1e7)
#: Control stiffness K_cont (the P gain in torque units), joint level.
K_CONT = Param("K_cont", "N m/rad", "control stiffness (P gain)", gt=0, le=1e9, typical=(1e2, 1e4))
#: Control damping C_cont (the D gain in torque units), joint level.
C_CONT = Param("C_cont", "N m s/rad", "control damping (D gain)", ge=0, le=1e7)

#: The transmission/controller stiffness ratio K_mech/K_cont of a joint-reduction sweep.
STIFFNESS_RATIO = Param(
    "K_mech/K_cont", "", "transmission/controller stiffness ratio", gt=0, le=1e9,
    typical=(0.03, 3000.0), name="ratios",
)  # fmt: skip
#: How many stiffness ratios a joint-reduction sweep evaluates (each costs a band fit
#: and three impacts): the one cap of the Python API and of the study file.
RATIO_POINTS = Param(
    None, "", "number of stiffness ratios", kind="integer", ge=1, le=1001, name="ratios"
)
#: Upper end of the band of the band fit (an extension of the thesis).
OMEGA_MAX = Param(
    "omega_max", "rad/s", "upper end of the band fit", gt=0, le=1e9, optional=True,
    none="the fastest mode of the Taylor-reduced impact, per point", name="omega_max",
)  # fmt: skip
#: How many bands a band-fit sweep evaluates.
BAND_POINTS = Param(None, "", "number of bands", kind="integer", ge=1, le=1001, name="omega_max")
#: Largest underestimate of a harm metric with which a reduction may still stand in
#: for the full joint (relative; 0.01 = 1 %).
USABLE_TOLERANCE = Param(
    None, "", "largest accepted underestimate of a harm metric where a reduction is still "
    "usable (relative; 0.01 = 1 %)", ge=0, lt=1, typical=(0.005, 0.05), default=0.01,
    name="tolerance",
)  # fmt: skip


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

#: The presets by the name a study file gives them (the names of the constants above).
ROBOT_PRESETS: dict[str, ContactDynamics] = {
    "MANIPULATOR_1": MANIPULATOR_1, "MANIPULATOR_2": MANIPULATOR_2,
}  # fmt: skip
#: The foam presets by name (see :data:`ROBOT_PRESETS`).
FOAM_PRESETS: dict[str, Foam] = {
    "FOAM_1": FOAM_1, "FOAM_2": FOAM_2, "FOAM_2_MEASURED": FOAM_2_MEASURED, "FOAM_3": FOAM_3,
}  # fmt: skip
#: The head-neck presets by name (see :data:`ROBOT_PRESETS`).
HEAD_PRESETS: dict[str, HeadNeck] = {
    "HEAD_MIN": HEAD_MIN, "HEAD_MAX": HEAD_MAX, "TEST_HEAD": TEST_HEAD,
}  # fmt: skip

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

    inertia: float = param("m_ii", "kg m^2", doc="inertia driven by the joint", gt=0, le=1e4)
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

    #: struck anywhere along its link: its v_c comes from the joint speed (3.4.11)
    along_link: ClassVar[bool] = True

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
        """Effective manipulator at ``lever_arm`` (3.4.17).

        Parameters
        ----------
        lever_arm
            l, m.

        Returns
        -------
        ContactDynamics
        """
        l2 = lever_arm**2
        return ContactDynamics(
            self.inertia / l2,
            self.joint_stiffness / l2,
            self.joint_damping / l2,
            lever_arm=lever_arm,
            name=self.name,
        )

    def speed(self, lever_arm: float) -> float:
        """Manipulator speed at ``lever_arm``, m/s (3.4.11).

        Parameters
        ----------
        lever_arm
            l, m.

        Returns
        -------
        float
        """
        return self.joint_speed * lever_arm


_HEAD = params_of(HeadNeck)


@declared
@dataclass(frozen=True)
class HeadRange(ParamsMixin):
    """Ranges of the head-neck parameters (Sec. 3.5): ``(low, high)`` pairs, SI.

    Each end is a value of the corresponding :class:`HeadNeck` parameter (same
    unit and allowed range), with ``low <= high``.

    Examples
    --------
    >>> len(THESIS_HEAD_RANGE.corners())
    8
    >>> HeadRange(mass=(5.3, 4.4))
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: HeadRange.mass = (5.3, 4.4) kg is not allowed: ...
    """

    mass: tuple[float, float] = param(
        "M_h", "kg", doc="(low, high) head mass", kind="object", default=(4.4, 5.3)
    )
    stiffness: tuple[float, float] = param(
        "K_h", "N/m", doc="(low, high) neck stiffness", kind="object", default=(3.0e3, 5.0e3)
    )
    damping: tuple[float, float] = param(
        "C_h", "N s/m", doc="(low, high) neck damping", kind="object", default=(46.0, 130.2)
    )

    def __post_init__(self) -> None:
        for name in ("mass", "stiffness", "damping"):
            pair = check_pair(_HEAD[name], getattr(self, name), f"HeadRange.{name}", strict=False)
            object.__setattr__(self, name, pair)

    def corners(self) -> list[HeadNeck]:
        """The 8 corner sets (duplicates removed).

        Returns
        -------
        list of HeadNeck
        """
        return self.grid(2)

    def grid(self, levels: int = 3) -> list[HeadNeck]:
        """Full factorial of ``levels`` values per parameter (corners included).

        Parameters
        ----------
        levels
            Values per parameter (>= 2).

        Returns
        -------
        list of HeadNeck
        """
        out: list[HeadNeck] = []
        for m in np.linspace(*self.mass, levels):
            for k in np.linspace(*self.stiffness, levels):
                for c in np.linspace(*self.damping, levels):
                    h = HeadNeck(float(m), float(k), float(c))
                    if h not in out:
                        out.append(h)
        return out

    def sample(self, n: int, rng: np.random.Generator) -> NDArray[np.float64]:
        """``(n, 3)`` uniform samples ``[M_h, C_h, K_h]``.

        Parameters
        ----------
        n
            Number of samples.
        rng
            The random generator.

        Returns
        -------
        numpy.ndarray
        """
        lo = np.array([self.mass[0], self.damping[0], self.stiffness[0]])
        hi = np.array([self.mass[1], self.damping[1], self.stiffness[1]])
        return lo + (hi - lo) * rng.random((n, 3))


#: The thesis's head-neck ranges: 4.4-5.3 kg, 3-5 kN/m, 46-130.2 N s/m.
THESIS_HEAD_RANGE = HeadRange()
