"""Effective single-DOF manipulator at the impact point (Zeng 2011, Sec. 3.4.3-3.4.4).

The impact model sees the manipulator as one mass ``M_r`` on a spring ``K_r``
and damper ``C_r``, moving at ``v_r(0)`` along the impact normal. With
``j = n^T J_v(q)`` the 1 x n row mapping the rates of the free (compliant)
joints to the normal velocity of the impact point (docs/impact.md, "The model"):

.. math::

    M_r = \\frac{1}{j M^{-1} j^T},\\quad
    K_r = \\frac{1}{j K_J^{-1} j^T},\\quad
    C_r = \\frac{1}{j C_J^{-1} j^T},\\quad
    v_r(0) = j \\dot q_d .

With diagonal ``K_J`` and ``C_J`` the joints combine like springs (dampers) in
series, each scaled by ``j_i^2``. Scenarios 1 and 2 of the thesis, (3.4.17) and
(3.4.18), are the case of one free joint (``M_r = m_ii / l^2``), scenario 3,
(3.4.28)-(3.4.33), the case of joints 2 and 3 of a planar two-link arm.

Examples
--------
>>> from designlab.impact.effective import scenario_single_joint
>>> e = scenario_single_joint(0.059, 121.68, 1.521, lever_arm=0.078, joint_speed=5.2)
>>> round(e.mass, 2), round(e.stiffness), round(e.damping), round(e.velocity, 3)
(9.7, 20000, 250, 0.406)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pandas as pd

from designlab.errors import (
    InvalidParameterError,
    check_finite,
    check_nonnegative,
    check_positive,
)
from designlab.impact.metrics import metrics_of_matrix
from designlab.impact.model import param_vector
from designlab.impact.parameters import ContactDynamics, Foam, HeadNeck, LinkImpact
from designlab.params import params_of
from designlab.results import OK, Result
from designlab.validation import frozen_array, real_array

__all__ = [
    "EffectiveContact",
    "ImpactPointSweep",
    "effective_contact",
    "impact_point_sweep",
    "scenario_single_joint",
    "scenario_two_link",
    "single_joint_from_contact",
    "two_link_mass_matrix",
]

_K_UNIT = "N m/rad"
_C_UNIT = "N m s/rad"
_M_UNIT = "kg m^2"


# --- results -------------------------------------------------------------------


@dataclass(frozen=True)
class EffectiveContact(Result):
    """Effective manipulator at the impact point (:func:`effective_contact`).

    Attributes
    ----------
    mass
        Effective mass M_r in kg.
    stiffness
        Effective stiffness K_r in N/m.
    damping
        Effective damping C_r in N s/m.
    velocity
        Normal velocity v_r(0) of the impact point in m/s, or ``None`` if no
        joint velocity was given.
    status
        Status of the reduction (``"ok"``; see :class:`designlab.results.Result`).
    warnings
        What a user should know about the reduction.
    """

    mass: float
    stiffness: float
    damping: float
    velocity: float | None = None
    status: str = OK
    warnings: tuple[str, ...] = ()

    @property
    def contact(self) -> ContactDynamics:
        """The parameter object used by the impact model.

        Examples
        --------
        >>> EffectiveContact(9.6, 20e3, 250.0).contact.mass
        9.6
        """
        return ContactDynamics(mass=self.mass, stiffness=self.stiffness, damping=self.damping)

    def to_frame(self) -> pd.DataFrame:
        """One-row DataFrame with unit-carrying column names.

        Examples
        --------
        >>> EffectiveContact(9.6, 20e3, 250.0, 0.4).to_frame()
           m_r_kg  k_r_N_per_m  c_r_N_s_per_m  v_r_m_per_s
        0     9.6      20000.0          250.0          0.4
        """
        return pd.DataFrame(
            {
                "m_r_kg": [self.mass],
                "k_r_N_per_m": [self.stiffness],
                "c_r_N_s_per_m": [self.damping],
                "v_r_m_per_s": [math.nan if self.velocity is None else self.velocity],
            }
        )


@dataclass(frozen=True, eq=False)
class ImpactPointSweep(Result):
    """Effective single-joint manipulator along a link (:func:`impact_point_sweep`).

    All arrays have the length of ``lever_arm`` and are read-only.

    Attributes
    ----------
    lever_arm
        Distance l from the joint axis to the impact point, m.
    mass, stiffness, damping
        M_r (kg), K_r (N/m), C_r (N s/m) at each lever arm, (3.4.17).
    velocity
        v_r(0) = theta_dot l in m/s, (3.4.11).
    status
        Status of the sweep (``"ok"``; see :class:`designlab.results.Result`).
    warnings
        What a user should know about the sweep.
    """

    lever_arm: np.ndarray
    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    velocity: np.ndarray
    status: str = OK
    warnings: tuple[str, ...] = ()

    def __len__(self) -> int:
        return int(self.lever_arm.size)

    def contacts(self) -> list[ContactDynamics]:
        """One :class:`ContactDynamics` per lever arm (with ``lever_arm`` set)."""
        return [
            ContactDynamics(float(m), float(k), float(c), lever_arm=float(arm))
            for arm, m, k, c in zip(
                self.lever_arm, self.mass, self.stiffness, self.damping, strict=True
            )
        ]

    def evaluate(self, foam: Foam, head: HeadNeck | None, human_speed: float = 1.0) -> pd.DataFrame:
        """First-lobe impact metrics at every impact point (Sec. 3.7.3, Fig. 3.16).

        The head moves toward the link at ``human_speed`` (m/s), so
        v_c = v_r(0) + human_speed at each lever arm. Returns :meth:`to_frame`
        with the metric columns of :class:`~designlab.impact.metrics.ImpactMetrics`.

        Examples
        --------
        >>> from designlab.impact import FOAM_1, HEAD_MIN
        >>> sweep = impact_point_sweep(0.059, 121.68, 1.521, 0.5, [0.01, 0.078])
        >>> sweep.evaluate(FOAM_1, HEAD_MIN)["a_h_max_g"].round(2).tolist()
        [5.78, 5.09]
        """
        n = len(self)
        head_row = param_vector(self.contacts()[0], foam, head)[5:]
        params = np.column_stack(
            [self.mass, self.damping, self.stiffness, np.full(n, foam.stiffness),
             np.full(n, foam.damping), np.tile(head_row, (n, 1))]
        )  # fmt: skip
        v = self.velocity + check_finite("human_speed", human_speed, "m/s")
        m = metrics_of_matrix(params, v, constrained=head is None)
        out = self.to_frame()
        metrics = m.to_frame()
        for col in ("v_c_m_per_s", "a_h_max_g", "eps_max_m", "peak_force_N", "t_imp_s", "status"):
            out[col] = metrics[col].to_numpy()
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per lever arm.

        Examples
        --------
        >>> sweep = impact_point_sweep(0.059, 121.68, 1.521, 5.2, [0.078, 0.156])
        >>> sweep.to_frame().round(2)
           l_m  m_r_kg  k_r_N_per_m  c_r_N_s_per_m  v_r_m_per_s
        0  0.08    9.70     20000.00         250.00         0.41
        1  0.16    2.42      5000.00          62.50         0.81
        """
        return pd.DataFrame(
            {
                "l_m": self.lever_arm,
                "m_r_kg": self.mass,
                "k_r_N_per_m": self.stiffness,
                "c_r_N_s_per_m": self.damping,
                "v_r_m_per_s": self.velocity,
            }
        )


# --- validation helpers ------------------------------------------------------------


def _mass_matrix(value: Any) -> np.ndarray:
    m = real_array("mass_matrix", value, _M_UNIT)
    if m.ndim == 0:
        m = m.reshape(1, 1)
    if m.ndim != 2 or m.shape[0] != m.shape[1] or m.shape[0] == 0:
        raise InvalidParameterError(
            "mass_matrix", f"array of shape {m.shape}", "must be a square n x n matrix", _M_UNIT
        )
    scale = float(np.max(np.abs(m)))
    if not np.allclose(m, m.T, rtol=1e-9, atol=1e-12 * scale):
        raise InvalidParameterError("mass_matrix", m.tolist(), "must be symmetric", _M_UNIT)
    try:
        np.linalg.cholesky(m)
    except np.linalg.LinAlgError:
        eig = float(np.min(np.linalg.eigvalsh(m)))
        raise InvalidParameterError(
            "mass_matrix",
            m.tolist(),
            f"must be positive definite (smallest eigenvalue {eig:.6g})",
            _M_UNIT,
        ) from None
    return m


def _jacobian_row(value: Any, n: int) -> np.ndarray:
    j = real_array("jacobian_row", value, "m")
    if j.ndim == 2 and j.shape[0] == 1:
        j = j[0]
    j = np.atleast_1d(j)
    if j.shape != (n,):
        raise InvalidParameterError(
            "jacobian_row",
            f"array of shape {j.shape}",
            f"must be a row of length {n} (the size of mass_matrix)",
            "m",
        )
    if not np.any(j != 0.0):
        raise InvalidParameterError(
            "jacobian_row",
            j.tolist(),
            "must have at least one non-zero entry (no joint moves the impact point "
            "along the normal)",
            "m",
        )
    return j


def _series(name: str, value: Any, j: np.ndarray, unit: str) -> float:
    """1/(j X^-1 j^T) for a diagonal (1-D or diagonal matrix) or SPD matrix X."""
    n = j.size
    x = real_array(name, value, unit)
    if x.ndim == 0 and n == 1:
        x = x.reshape(1)
    if x.ndim == 2 and x.shape == (n, n) and np.count_nonzero(x - np.diag(np.diag(x))) == 0:
        x = np.diag(x).copy()
    if x.ndim == 1:
        if x.shape != (n,):
            raise InvalidParameterError(
                name, f"array of shape {x.shape}", f"must have length {n} (one per joint)", unit
            )
        if np.any(x < 0.0):
            raise InvalidParameterError(name, x.tolist(), "every entry must be >= 0", unit)
        active = j != 0.0
        if np.any(x[active] == 0.0):
            return 0.0  # a zero element in series: the chain has no stiffness/damping
        return float(1.0 / np.sum(j[active] ** 2 / x[active]))
    if x.shape != (n, n):
        raise InvalidParameterError(
            name,
            f"array of shape {x.shape}",
            f"must be a length-{n} diagonal or an {n} x {n} matrix",
            unit,
        )
    scale = float(np.max(np.abs(x)))
    if not np.allclose(x, x.T, rtol=1e-9, atol=1e-12 * scale):
        raise InvalidParameterError(name, x.tolist(), "must be symmetric", unit)
    try:
        chol = np.linalg.cholesky(x)
    except np.linalg.LinAlgError:
        raise InvalidParameterError(
            name, x.tolist(), "a non-diagonal matrix must be positive definite", unit
        ) from None
    y = np.linalg.solve(chol, j)
    return float(1.0 / (y @ y))


# --- general reduction -------------------------------------------------------------


def effective_contact(
    mass_matrix: npt.ArrayLike,
    joint_stiffness: npt.ArrayLike,
    joint_damping: npt.ArrayLike,
    jacobian_row: npt.ArrayLike,
    joint_velocity: npt.ArrayLike | None = None,
) -> EffectiveContact:
    """Reduce a manipulator to a single-DOF contact at the impact point.

    See docs/impact.md, "The model".

    ``M_r = 1/(j M^-1 j^T)``, ``K_r = 1/(j K_J^-1 j^T)``,
    ``C_r = 1/(j C_J^-1 j^T)`` and ``v_r(0) = j q_dot``.

    Parameters
    ----------
    mass_matrix
        Joint-space mass matrix M (n x n, symmetric positive definite) of the
        free joints, in kg m^2 for revolute joints. To lock a joint (treat it
        as rigid, as scenarios 1 and 2 do for the other joints), remove its
        row and column. The matrix is used in full: a free joint with
        ``j_i = 0`` still lowers M_r through inertial coupling.
    joint_stiffness
        Joint stiffnesses K_J in N m/rad: the diagonal as a length-n array
        (entries >= 0), or a full n x n matrix (symmetric positive definite
        unless diagonal).
    joint_damping
        Joint dampings C_J in N m s/rad, in the same forms.
    jacobian_row
        j, the 1 x n row mapping joint rates to the velocity of the impact
        point along the contact normal (m/rad for revolute joints). Joints with
        ``j_i = 0`` do not contribute to the diagonal series sums; a zero
        stiffness (damping) in a joint with ``j_i != 0`` gives ``K_r = 0``
        (``C_r = 0``).
    joint_velocity
        Optional desired joint rates q_dot (length n) just before impact, in
        rad/s; gives ``v_r(0) = j q_dot``.

    Returns
    -------
    EffectiveContact
        M_r (kg), K_r (N/m), C_r (N s/m) and v_r(0) (m/s or ``None``).

    Raises
    ------
    InvalidParameterError
        If M is not square, symmetric and positive definite, if shapes do not
        agree, if a stiffness or damping is negative, or if ``j`` is all zero.

    Examples
    --------
    A single joint (scenario 1, (3.4.17)):

    >>> e = effective_contact([[0.059]], [121.68], [1.521], [0.078], joint_velocity=[5.2])
    >>> round(e.mass, 2), round(e.stiffness), round(e.damping), round(e.velocity, 3)
    (9.7, 20000, 250, 0.406)

    Two joints in series:

    >>> e = effective_contact(np.eye(2), [100.0, 100.0], [1.0, 0.0], [1.0, 1.0])
    >>> e.mass, e.stiffness, e.damping
    (0.5, 50.0, 0.0)
    """
    m = _mass_matrix(mass_matrix)
    n = m.shape[0]
    j = _jacobian_row(jacobian_row, n)
    k_r = _series("joint_stiffness", joint_stiffness, j, _K_UNIT)
    c_r = _series("joint_damping", joint_damping, j, _C_UNIT)
    x = np.linalg.solve(m, j)
    m_r = float(1.0 / (j @ x))
    v_r: float | None = None
    if joint_velocity is not None:
        qd = np.atleast_1d(real_array("joint_velocity", joint_velocity, "rad/s"))
        if qd.shape != (n,):
            raise InvalidParameterError(
                "joint_velocity", f"array of shape {qd.shape}", f"must have length {n}", "rad/s"
            )
        v_r = float(j @ qd)
    return EffectiveContact(mass=m_r, stiffness=k_r, damping=c_r, velocity=v_r)


# --- thesis scenarios ----------------------------------------------------------------


def scenario_single_joint(
    inertia: float,
    joint_stiffness: float,
    joint_damping: float,
    lever_arm: float,
    joint_speed: float | None = None,
) -> EffectiveContact:
    """Scenarios 1 and 2: one revolute joint as a prismatic joint, (3.4.17)/(3.4.18).

    ``M_r = m_ii / l^2``, ``K_r = K_J / l^2``, ``C_r = C_J / l^2`` and
    ``v_r(0) = theta_dot l`` (3.4.11). The other joints are locked, so the
    diagonal element ``m_ii`` is used, not ``1/(M^-1)_ii``.

    Parameters
    ----------
    inertia
        m_ii, the inertia driven by the joint with the other joints locked,
        kg m^2 (> 0).
    joint_stiffness
        K_J in N m/rad (>= 0), e.g. from :func:`designlab.impact.joint.reduced_joint`.
    joint_damping
        C_J in N m s/rad (>= 0).
    lever_arm
        l, the perpendicular distance from the joint axis to the line of the
        impact normal through the impact point, m (> 0). The link radius
        does not matter (3.4.12).
    joint_speed
        Optional desired joint speed theta_dot in rad/s.

    Returns
    -------
    EffectiveContact

    Examples
    --------
    Table 3.1, Manipulator 1 (m_11 = 0.059 kg m^2, l_1 = 0.078 m); the thesis
    prints M_r = 9.6 kg:

    >>> round(scenario_single_joint(0.059, 0.0, 0.0, 0.078).mass, 2)
    9.7
    """
    m = check_positive("inertia", inertia, _M_UNIT)
    k = check_nonnegative("joint_stiffness", joint_stiffness, _K_UNIT)
    c = check_nonnegative("joint_damping", joint_damping, _C_UNIT)
    arm = check_positive("lever_arm", lever_arm, "m")
    v = None if joint_speed is None else check_finite("joint_speed", joint_speed, "rad/s") * arm
    l2 = arm * arm
    return EffectiveContact(mass=m / l2, stiffness=k / l2, damping=c / l2, velocity=v)


def single_joint_from_contact(
    contact: ContactDynamics, lever_arm: float | None = None
) -> tuple[float, float, float]:
    """Joint-level (m_11, K_J, C_J) of an effective single-joint manipulator, by (3.4.17).

    ``m_11 = M_r l^2``, ``K_J = K_r l^2``, ``C_J = C_r l^2``: needed to move the
    impact point along the link (Sec. 3.7.3, Fig. 3.16).

    Parameters
    ----------
    contact
        Effective manipulator, e.g. ``MANIPULATOR_1`` of Table 3.1.
    lever_arm
        l in m; defaults to ``contact.lever_arm``.

    Returns
    -------
    tuple of float
        ``(m_11, K_J, C_J)`` in kg m^2, N m/rad, N m s/rad.

    Examples
    --------
    >>> from designlab.impact.parameters import MANIPULATOR_1
    >>> m11, k_j, c_j = single_joint_from_contact(MANIPULATOR_1)
    >>> round(m11, 4), round(k_j, 2), round(c_j, 3)
    (0.0584, 121.68, 1.521)
    """
    arm = contact.lever_arm if lever_arm is None else lever_arm
    if arm is None:
        raise InvalidParameterError(
            "lever_arm", None, "must be given when contact.lever_arm is None", "m"
        )
    arm = check_positive("lever_arm", arm, "m")
    l2 = arm * arm
    return contact.mass * l2, contact.stiffness * l2, contact.damping * l2


def two_link_mass_matrix(
    m2: float, m3: float, a2: float, a3: float, theta3: float = 0.0, *, printed: bool = False
) -> np.ndarray:
    """Mass matrix M_23 of links 2 and 3 as uniform rods, eq. (3.4.22).

    ``m22 = (1/3) m2 a2^2 + m3 a2^2 + (1/3) m3 a3^2 + m3 a2 a3 cos th3``,
    ``m23 = m32 = (1/3) m3 a3^2 + (1/2) m3 a2 a3 cos th3`` (uniform-rod
    result, docs/impact.md, "The model"), ``m33 = (1/3) m3 a3^2``.

    Parameters
    ----------
    m2, m3
        Link masses in kg (> 0).
    a2, a3
        Link lengths in m (> 0).
    theta3
        Joint-3 angle in rad (0: links aligned, the worst case).
    printed
        If True, use the thesis's printed off-diagonal
        ``(1/3) m3 a3^2 + m3 a2 a3 cos th3``. That matrix is not a rigid-body
        mass matrix and can be indefinite (e.g. equal links at th3 = 0), in
        which case :func:`effective_contact` rejects it.

    Returns
    -------
    numpy.ndarray
        The 2 x 2 matrix in kg m^2.

    Examples
    --------
    >>> two_link_mass_matrix(3.0, 3.0, 1.0, 1.0)
    array([[8. , 2.5],
           [2.5, 1. ]])
    >>> float(two_link_mass_matrix(3.0, 3.0, 1.0, 1.0, printed=True)[0, 1])
    4.0
    """
    m2 = check_positive("m2", m2, "kg")
    m3 = check_positive("m3", m3, "kg")
    a2 = check_positive("a2", a2, "m")
    a3 = check_positive("a3", a3, "m")
    c3 = math.cos(check_finite("theta3", theta3, "rad"))
    m33 = m3 * a3**2 / 3.0
    m22 = m2 * a2**2 / 3.0 + m3 * a2**2 + m33 + m3 * a2 * a3 * c3
    m23 = m33 + (1.0 if printed else 0.5) * m3 * a2 * a3 * c3
    return np.array([[m22, m23], [m23, m33]])


def scenario_two_link(
    m2: float,
    m3: float,
    a2: float,
    a3: float,
    l3: float,
    k_j2: float,
    c_j2: float,
    k_j3: float,
    c_j3: float,
    theta3: float = 0.0,
    joint_speeds: npt.ArrayLike | None = None,
    *,
    printed: bool = False,
) -> EffectiveContact:
    """Scenario 3: joints 2 and 3 of a planar arm reduced to one DOF, (3.4.19)-(3.4.33).

    The impact point lies on link 3 at distance ``l3`` from joint 3 and the
    normal is perpendicular to link 3 in the plane of motion: in the base
    frame of (3.4.20), ``n = [-sin th23, cos th23]``. Projecting (3.4.20)
    on it gives

    ``j = [a2 cos th3 + l3, l3]``,

    independent of theta2; at ``th3 = 0`` (worst case, Fig. 3.8) this is the
    thesis's ``[a2 + l3, l3]``, and then ``K_r``, ``C_r`` are (3.4.28),
    (3.4.29) and ``M_r`` is (3.4.33).

    Parameters
    ----------
    m2, m3, a2, a3
        Masses (kg) and lengths (m) of links 2 and 3 (uniform rods).
    l3
        Distance from the joint-3 axis to the impact point, m (0 < l3 <= a3).
    k_j2, c_j2, k_j3, c_j3
        Joint stiffnesses (N m/rad) and dampings (N m s/rad), e.g. from
        :func:`designlab.impact.joint.reduced_joint`.
    theta3
        Joint-3 angle in rad; 0 is the worst case.
    joint_speeds
        Optional ``(theta2_dot, theta3_dot)`` in rad/s; gives
        ``v_r(0) = (a2 cos th3 + l3) theta2_dot + l3 theta3_dot`` (3.4.23).
    printed
        Use the thesis's printed mass matrix (see :func:`two_link_mass_matrix`).

    Returns
    -------
    EffectiveContact

    Examples
    --------
    >>> e = scenario_two_link(3.0, 2.0, 0.5, 0.5, 0.4, 400.0, 4.0, 200.0, 2.0,
    ...                       joint_speeds=(1.0, 0.5))
    >>> round(e.stiffness, 2), round(e.velocity, 2)  # (3.4.28), (3.4.23)
    (353.98, 1.1)
    """
    a3 = check_positive("a3", a3, "m")
    arm = check_positive("l3", l3, "m")
    if arm > a3:
        raise InvalidParameterError("l3", l3, f"must be <= a3 = {a3} m (on link 3)", "m")
    mass = two_link_mass_matrix(m2, m3, a2, a3, theta3, printed=printed)
    j = np.array([a2 * math.cos(theta3) + arm, arm])
    k = [
        check_nonnegative("k_j2", k_j2, _K_UNIT),
        check_nonnegative("k_j3", k_j3, _K_UNIT),
    ]
    c = [
        check_nonnegative("c_j2", c_j2, _C_UNIT),
        check_nonnegative("c_j3", c_j3, _C_UNIT),
    ]
    return effective_contact(mass, k, c, j, joint_velocity=joint_speeds)


# --- Sec. 3.7.3: moving the impact point along the link ------------------------------


def impact_point_sweep(
    inertia: float,
    joint_stiffness: float,
    joint_damping: float,
    joint_speed: float,
    lever_arms: npt.ArrayLike,
) -> ImpactPointSweep:
    """Effective single-joint manipulator for a range of impact points (Sec. 3.7.3).

    Near the joint M_r, K_r and C_r are large (all scale with ``1/l^2``) but
    ``v_r(0) = theta_dot l`` is small; the worst impact point must be
    searched. This gives the inputs of the impact model at each ``l``; it
    computes no impact metric.

    Parameters
    ----------
    inertia
        Joint inertia m_11 in kg m^2 (declared on
        :class:`~designlab.impact.parameters.LinkImpact`, as the next three).
    joint_stiffness
        K_J in N m/rad.
    joint_damping
        C_J in N m s/rad.
    joint_speed
        Desired joint speed theta_dot in rad/s (>= 0).
    lever_arms
        Distances l from the joint axis to the impact point, m (each > 0).

    Returns
    -------
    ImpactPointSweep

    Examples
    --------
    >>> s = impact_point_sweep(0.059, 121.68, 1.521, 5.2, np.linspace(0.1, 0.5, 5))
    >>> s.mass.round(3)
    array([5.9  , 1.475, 0.656, 0.369, 0.236])
    """
    link = params_of(LinkImpact)  # the same bounds as a link's (Sec. 3.7.3)
    m = link["inertia"].check(inertia, "inertia")
    k = link["joint_stiffness"].check(joint_stiffness, "joint_stiffness")
    c = link["joint_damping"].check(joint_damping, "joint_damping")
    w = link["joint_speed"].check(joint_speed, "joint_speed")
    arms = np.atleast_1d(real_array("lever_arms", lever_arms, "m"))
    if arms.ndim != 1 or arms.size == 0:
        raise InvalidParameterError(
            "lever_arms", f"array of shape {arms.shape}", "must be a non-empty 1-D array", "m"
        )
    top = link["lever_arm_max"].le
    bad = ~((arms > 0.0) & (arms <= top))
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise InvalidParameterError(
            f"lever_arms[{i}]", float(arms[i]), f"every entry must be > 0 and <= {top:g}", "m"
        )
    l2 = arms**2
    return ImpactPointSweep(
        lever_arm=frozen_array(arms),
        mass=frozen_array(m / l2),
        stiffness=frozen_array(k / l2),
        damping=frozen_array(c / l2),
        velocity=frozen_array(w * arms),
    )
