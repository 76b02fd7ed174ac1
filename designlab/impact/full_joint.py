"""Impact with the full series joint (Zeng 2011, eq. 3.4.6) and the error of its reductions.

The thesis replaces a position-controlled joint -- transmission (K_mech, C_mech)
in series with the PD controller (K_cont, C_cont) -- by one spring-damper
(K_J, C_J), the first two Taylor terms of (3.4.6) about s = 0, (3.4.9). This
module keeps the series joint in the impact model, so that a designer can see
how wrong a_h,max, eps_max, the peak force and the impact period are when the
reduced joint is used, and on which side (see ``docs/impact_joint.md``).

**Model.** Scenarios 1 and 2 (one free joint, (3.4.17)): every joint quantity is
divided by l^2 to act along the impact normal. The motor side of the transmission
(the encoder node, theta_enc of (3.4.3)-(3.4.5)) is massless, as in (3.4.6), so
the series joint adds one first-order state, the node's deflection delta_e from
the desired motion::

    p = [M_r, C_mech, K_mech, K_c, C_c, M_h, C_h, K_h, C_cont, K_cont]   (effective, per l^2)
    x = [delta_r, delta_r_dot, delta_e, delta_h, delta_h_dot]
    u = [s_c, v_c, a_d, a_ff]

    f_c = K_c (delta_r - delta_h + s_c) + C_c (delta_r_dot - delta_h_dot + v_c)   (3.5.1)
    f_t = K_mech (delta_r - delta_e) + C_mech (delta_r_dot - delta_e_dot)      transmission
        = K_cont delta_e + C_cont delta_e_dot - M_r a_ff                     controller (3.4.5)
    M_r delta_r_dd = -f_c - f_t - M_r (a_d + a_ff)                                (3.5.2)
    M_h delta_h_dd =  f_c - C_h delta_h_dot - K_h delta_h                         (3.5.3)

``a_ff`` is a desired acceleration compensated by a feed-forward force at the
motor, ``a_d`` one that is not (as in :mod:`designlab.impact.model`). As
K_mech -> infinity, delta_e -> delta_r and the model becomes the reduced one
with K_r = K_cont, C_r = C_cont; for finite K_mech its joint impedance is
exactly (3.4.6). The model is written once in CasADi; the state space, the
transfer functions and the exact modal responses follow as for the reduced
model, and :func:`~designlab.impact.simulate.simulate`,
:func:`~designlab.impact.metrics.impact_metrics` and
:func:`~designlab.impact.envelope.foam_envelope` accept a
:class:`FullJointContact` (or ``(N, 10)`` parameter rows) wherever they accept
the reduced manipulator.

**Comparison.** :func:`compare_joint_reductions` evaluates the full joint, the
Taylor reduction (3.4.9) and the frequency-band fit
(:func:`~designlab.impact.joint.fit_joint_band`, an extension of the thesis,
which has only the Taylor truncation) on the same arm, foam and head, and
reports each metric's relative error and whether the reduction is conservative
(overestimates the harm). :func:`joint_reduction_sweep` does the same over the
transmission/controller stiffness ratio K_mech/K_cont.

Units: SI, effective (prismatic) values in N/m and N s/m; joint values in
N m/rad and N m s/rad.

Examples
--------
>>> import designlab as dl
>>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
>>> cmp = dl.impact.compare_joint_reductions(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25)
>>> round(100 * cmp.relative_error("taylor", "a_h_max"), 1)
12.5
>>> cmp.conservative("taylor", "a_h_max")
True
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cache
from typing import Any

import casadi as ca
import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError, check_positive
from designlab.impact.joint import JointFit, fit_joint_band, reduced_joint
from designlab.impact.modal import ModalResponse, poles_of
from designlab.impact.model import INPUT_NAMES, LinearImpactModel, derive_model
from designlab.impact.parameters import ContactDynamics, Foam, HeadNeck, LinkImpact
from designlab.impact.peaks import first_local_maximum
from designlab.results import Result
from designlab.units import STANDARD_GRAVITY
from designlab.validation import ParamsMixin

__all__ = [
    "FULL_INPUT_NAMES",
    "FULL_PARAM_NAMES",
    "REDUCTIONS",
    "BandFitSweep",
    "FullJointContact",
    "FullJointLink",
    "JointReductionComparison",
    "JointReductionSweep",
    "band_fit_sweep",
    "compare_joint_reductions",
    "default_band",
    "full_joint_model",
    "full_joint_params",
    "grid_rate",
    "joint_reduction_sweep",
    "matrix_metrics",
    "modal_families",
]

#: Parameters of the full-joint model: those of the reduced model, with C_r, K_r
#: replaced by the transmission's C_mech, K_mech, then the controller's C_cont, K_cont.
FULL_PARAM_NAMES: tuple[str, ...] = (
    "M_r",
    "C_mech",
    "K_mech",
    "K_c",
    "C_c",
    "M_h",
    "C_h",
    "K_h",
    "C_cont",
    "K_cont",
)
#: Inputs of the full-joint model: those of the reduced model and the
#: feed-forward-compensated desired acceleration ``a_ff``.
FULL_INPUT_NAMES: tuple[str, ...] = (*INPUT_NAMES, "a_ff")

#: The reductions compared with the full joint.
REDUCTIONS: tuple[str, ...] = ("taylor", "band_fit")

#: Metrics compared: name -> (column of the comparison, unit). "f_c_first_peak"
#: is the first local maximum of the force (the thesis's "peak", Sec. 3.6),
#: "f_c_max" the maximum over the first lobe (docs/impact.md, "Metrics").
METRICS: dict[str, str] = {
    "a_h_max": "g",
    "eps_max": "m",
    "f_c_max": "N",
    "f_c_first_peak": "N",
    "t_imp": "s",
}
#: Relative difference below which a reduced metric counts as equal to the full one
#: (and so as conservative): rounding of two exact evaluations.
EQUAL_TOLERANCE = 1e-9

#: Metrics for which a larger value is the worse (harm) side.
HARM_METRICS: tuple[str, ...] = ("a_h_max", "eps_max", "f_c_max", "f_c_first_peak")

_UNITS = {
    "mass": "kg",
    "transmission_stiffness": "N/m",
    "transmission_damping": "N s/m",
    "control_stiffness": "N/m",
    "control_damping": "N s/m",
}


# --- the parameter object --------------------------------------------------------------


@dataclass(frozen=True)
class FullJointContact(ParamsMixin):
    """A single-joint manipulator with the full series joint (3.4.6), at the impact point.

    All values are effective (prismatic, along the impact normal): joint values
    divided by l^2, (3.4.17). Use :meth:`from_joint` for joint-level data.

    Parameters
    ----------
    mass
        M_r = m_ii / l^2 in kg (> 0).
    transmission_stiffness, transmission_damping
        K_mech / l^2 (N/m, > 0) and C_mech / l^2 (N s/m, >= 0).
    control_stiffness, control_damping
        K_cont / l^2 (N/m, > 0) and C_cont / l^2 (N s/m, >= 0): the P and D gains
        in torque units. The two dampings must not both be zero (the massless
        motor node then has no dynamics of its own).
    lever_arm
        l in m, if known.
    name
        Optional label.

    Examples
    --------
    >>> arm = FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    >>> round(arm.mass, 3), round(arm.taylor().stiffness, 1), round(arm.taylor().damping, 1)
    (1.475, 21428.6, 254.1)
    """

    mass: float
    transmission_stiffness: float
    transmission_damping: float
    control_stiffness: float
    control_damping: float
    lever_arm: float | None = None
    name: str = ""

    def __post_init__(self) -> None:
        from designlab.errors import check_nonnegative

        for f in ("mass", "transmission_stiffness", "control_stiffness"):
            value = check_positive(f"FullJointContact.{f}", getattr(self, f), _UNITS[f])
            object.__setattr__(self, f, value)
        for f in ("transmission_damping", "control_damping"):
            value = check_nonnegative(f"FullJointContact.{f}", getattr(self, f), _UNITS[f])
            object.__setattr__(self, f, value)
        if self.transmission_damping + self.control_damping <= 0.0:
            raise InvalidParameterError(
                "FullJointContact.control_damping",
                self.control_damping,
                "transmission_damping + control_damping must be > 0 (a massless motor "
                "node between two undamped springs has no dynamics)",
                "N s/m",
            )
        if self.lever_arm is not None:
            object.__setattr__(
                self,
                "lever_arm",
                check_positive("FullJointContact.lever_arm", self.lever_arm, "m"),
            )

    @classmethod
    def from_joint(
        cls,
        inertia: float,
        k_mech: float,
        c_mech: float,
        k_cont: float,
        c_cont: float,
        *,
        lever_arm: float,
        name: str = "",
    ) -> FullJointContact:
        """Build from joint-level values (kg m^2, N m/rad, N m s/rad) at lever arm ``l`` (m).

        Scenario 1/2 reduction (3.4.17): every value is divided by ``l^2``.
        """
        arm = check_positive("lever_arm", lever_arm, "m")
        l2 = arm * arm
        return cls(
            check_positive("inertia", inertia, "kg m^2") / l2,
            check_positive("k_mech", k_mech, "N m/rad") / l2,
            _nonneg("c_mech", c_mech, "N m s/rad") / l2,
            check_positive("k_cont", k_cont, "N m/rad") / l2,
            _nonneg("c_cont", c_cont, "N m s/rad") / l2,
            lever_arm=arm,
            name=name,
        )

    @property
    def stiffness_ratio(self) -> float:
        """K_mech / K_cont: large for a direct drive, where the reduction is exact in the limit."""
        return self.transmission_stiffness / self.control_stiffness

    @property
    def corner_frequency(self) -> float:
        """(K_mech + K_cont) / (C_mech + C_cont), rad/s: the pole of (3.4.6)."""
        return (self.transmission_stiffness + self.control_stiffness) / (
            self.transmission_damping + self.control_damping
        )

    def joint_values(self) -> tuple[float, float, float, float]:
        """The joint's values at the impact point.

        Returns
        -------
        tuple of float
            ``(K_mech, C_mech, K_cont, C_cont)`` in N/m and N s/m.
        """
        return (
            self.transmission_stiffness,
            self.transmission_damping,
            self.control_stiffness,
            self.control_damping,
        )

    def taylor(self) -> ContactDynamics:
        """The reduced manipulator of the thesis: K_r, C_r from (3.4.9) (Taylor truncation).

        Returns
        -------
        ContactDynamics
            M_r of this arm with the Taylor K_J, C_J (effective values).
        """
        k, c = reduced_joint(*self.joint_values())
        return ContactDynamics(self.mass, k, c, lever_arm=self.lever_arm, name=self.name)

    def band_fit(self, omega_max: float, **kwargs: Any) -> tuple[ContactDynamics, JointFit]:
        """The reduced manipulator fitted over ``[omega_max/1000, omega_max]`` rad/s.

        An extension of the thesis (:func:`~designlab.impact.joint.fit_joint_band`).

        Parameters
        ----------
        omega_max
            Upper end of the band, rad/s (> 0).
        **kwargs
            Further arguments of :func:`~designlab.impact.joint.fit_joint_band`
            (``n``, ``omega_min``, ``weights``).

        Returns
        -------
        tuple
            The manipulator (``None`` if the fit failed) and the
            :class:`~designlab.impact.joint.JointFit` (check ``fit.success``).
        """
        fit = fit_joint_band(*self.joint_values(), omega_max=omega_max, **kwargs)
        contact = None
        if fit.success:
            contact = ContactDynamics(
                self.mass, fit.stiffness, fit.damping, lever_arm=self.lever_arm, name=self.name
            )
        return contact, fit  # type: ignore[return-value]


@dataclass(frozen=True)
class FullJointLink(LinkImpact):
    """A joint with its full series joint (3.4.6), struck anywhere along its link (Sec. 3.7.3).

    The :class:`~designlab.impact.parameters.LinkImpact` of the thesis's
    scenarios 1 and 2, with the transmission kept: ``joint_stiffness`` and
    ``joint_damping`` are the controller's K_cont and C_cont (N m/rad,
    N m s/rad), ``transmission_stiffness`` and ``transmission_damping`` the
    transmission's K_mech and C_mech. At lever arm ``l`` the manipulator is
    :meth:`contact` ``(l)``, every value divided by ``l^2`` (3.4.17).
    :func:`~designlab.impact.envelope.foam_envelope` searches the worst impact
    point with the full joint.

    Parameters
    ----------
    inertia, joint_stiffness, joint_damping, joint_speed, lever_arm_min, lever_arm_max, name
        As in :class:`~designlab.impact.parameters.LinkImpact` (the joint
        stiffness and damping being the controller's; K_cont > 0).
    transmission_stiffness
        K_mech in N m/rad (> 0, required).
    transmission_damping
        C_mech in N m s/rad (>= 0).

    Examples
    --------
    >>> link = FullJointLink(0.059, 1.5e3, 30.0, 1.0, 0.05, 0.3,
    ...                      transmission_stiffness=2e3, transmission_damping=2.0)
    >>> arm = link.contact(0.2)
    >>> round(arm.mass, 3), round(arm.stiffness_ratio, 3)
    (1.475, 1.333)
    """

    transmission_stiffness: float | None = None
    transmission_damping: float = 0.0

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.transmission_stiffness is None:
            raise InvalidParameterError(
                "FullJointLink.transmission_stiffness", None, "is required (K_mech > 0)", "N m/rad"
            )
        k = check_positive(
            "FullJointLink.transmission_stiffness", self.transmission_stiffness, "N m/rad"
        )
        c = _nonneg("FullJointLink.transmission_damping", self.transmission_damping, "N m s/rad")
        check_positive("FullJointLink.joint_stiffness", self.joint_stiffness, "N m/rad")
        if c + self.joint_damping <= 0:
            raise InvalidParameterError(
                "FullJointLink.joint_damping",
                self.joint_damping,
                "transmission_damping + joint_damping must be > 0",
                "N m s/rad",
            )
        object.__setattr__(self, "transmission_stiffness", k)
        object.__setattr__(self, "transmission_damping", c)

    def contact(self, lever_arm: float) -> FullJointContact:  # type: ignore[override]
        """The full-joint manipulator at ``lever_arm`` (m), (3.4.17).

        Parameters
        ----------
        lever_arm
            l, m (> 0).

        Returns
        -------
        FullJointContact
            Every value divided by ``l^2``.
        """
        return FullJointContact.from_joint(
            self.inertia,
            float(self.transmission_stiffness),  # type: ignore[arg-type]
            self.transmission_damping,
            self.joint_stiffness,
            self.joint_damping,
            lever_arm=lever_arm,
            name=self.name,
        )

    def effective_rows(self, levers: ArrayLike) -> NDArray[np.float64]:
        """``(n, 5)`` rows ``[M_r, C_mech, K_mech, C_cont, K_cont]`` at the lever arms.

        Parameters
        ----------
        levers
            Lever arms, m.

        Returns
        -------
        numpy.ndarray
            Effective values (joint values divided by ``l^2``), SI units.
        """
        l2 = np.asarray(levers, dtype=float) ** 2
        return np.column_stack(
            [
                self.inertia / l2,
                self.transmission_damping / l2,
                float(self.transmission_stiffness) / l2,  # type: ignore[arg-type]
                self.joint_damping / l2,
                self.joint_stiffness / l2,
            ]
        )


def _nonneg(name: str, value: float, unit: str) -> float:
    from designlab.errors import check_nonnegative

    return check_nonnegative(name, value, unit)


# --- the model, written once ---------------------------------------------------------------


def _build(constrained: bool) -> LinearImpactModel:
    p = ca.SX.sym("p", len(FULL_PARAM_NAMES))
    m_r, c_m, k_m, k_c, c_c, m_h, c_h, k_h, c_q, k_q = (p[i] for i in range(p.shape[0]))
    u = ca.SX.sym("u", len(FULL_INPUT_NAMES))
    s_c, v_c, a_d, a_ff = u[0], u[1], u[2], u[3]
    if constrained:
        x = ca.SX.sym("x", 3)
        d_r, d_r_dot, d_e = x[0], x[1], x[2]
        d_h = d_h_dot = ca.SX(0.0)
        state_names: tuple[str, ...] = ("delta_r", "delta_r_dot", "delta_e")
    else:
        x = ca.SX.sym("x", 5)
        d_r, d_r_dot, d_e, d_h, d_h_dot = (x[i] for i in range(5))
        state_names = ("delta_r", "delta_r_dot", "delta_e", "delta_h", "delta_h_dot")

    compression = d_r - d_h + s_c
    compression_rate = d_r_dot - d_h_dot + v_c
    f_c = k_c * compression + c_c * compression_rate  # (3.5.1)
    # massless motor node: transmission force = controller force - feed-forward (3.4.5)
    d_e_dot = (k_m * (d_r - d_e) + c_m * d_r_dot - k_q * d_e + m_r * a_ff) / (c_m + c_q)
    f_t = k_q * d_e + c_q * d_e_dot - m_r * a_ff
    d_r_ddot = (-f_c - f_t) / m_r - a_d - a_ff  # (3.5.2) with the series joint
    if constrained:
        a_h = ca.SX(0.0)
        xdot = ca.vertcat(d_r_dot, d_r_ddot, d_e_dot)
    else:
        a_h = (f_c - c_h * d_h_dot - k_h * d_h) / m_h  # (3.5.3)
        xdot = ca.vertcat(d_r_dot, d_r_ddot, d_e_dot, d_h_dot, a_h)
    output_names = (
        "force",
        "head_acceleration",
        "compression",
        "compression_rate",
        "head_velocity",
        "robot_deflection",
        "transmission_force",
    )
    y = ca.vertcat(f_c, a_h, compression, compression_rate, d_h_dot, d_r, f_t)
    name = "full_joint_" + ("constrained" if constrained else "unconstrained")
    return derive_model(
        name, x, u, p, xdot, y, state_names, output_names, FULL_PARAM_NAMES, FULL_INPUT_NAMES
    )


@cache
def full_joint_model(constrained: bool = False) -> LinearImpactModel:
    """The impact model with the full series joint (built once, cached).

    Examples
    --------
    >>> m = full_joint_model()
    >>> m.n_states, m.param_names[-2:]
    (5, ('C_cont', 'K_cont'))
    """
    return _build(bool(constrained))


def full_joint_params(
    robot: FullJointContact, foam: Foam, head: HeadNeck | None
) -> NDArray[np.float64]:
    """Parameter vector :data:`FULL_PARAM_NAMES` of one design.

    Parameters
    ----------
    robot
        The full-joint manipulator.
    foam
        The covering.
    head
        The head on its neck; ``None`` (constrained impact) gives 1, 0, 0.

    Returns
    -------
    numpy.ndarray
        ``(10,)`` parameters in SI units.

    Examples
    --------
    >>> from designlab.impact import FOAM_1, HEAD_MIN
    >>> arm = FullJointContact(10.0, 1e5, 10.0, 2e4, 250.0)
    >>> full_joint_params(arm, FOAM_1, HEAD_MIN).tolist()
    [10.0, 10.0, 100000.0, 24250.0, 71.9, 4.4, 46.0, 3000.0, 250.0, 20000.0]
    """
    hm, hc, hk = (1.0, 0.0, 0.0) if head is None else (head.mass, head.damping, head.stiffness)
    return np.array(
        [
            robot.mass,
            robot.transmission_damping,
            robot.transmission_stiffness,
            foam.stiffness,
            foam.damping,
            hm,
            hc,
            hk,
            robot.control_damping,
            robot.control_stiffness,
        ],
        dtype=float,
    )


def grid_rate(poles: NDArray[np.complex128]) -> NDArray[np.float64]:
    """The fastest rate (1/s) a search grid must resolve, per design (``(N, n)`` poles).

    A stiff transmission gives a very fast real pole (the motor node's
    ``-(K_mech + K_cont)/(C_mech + C_cont)``) whose transient is over long
    before any maximum of the first lobe; resolving it would cost millions of
    grid steps. Real poles faster than ten times the fastest oscillatory (or,
    without one, the slowest) pole are therefore left out of the rate.

    Parameters
    ----------
    poles
        ``(N, n)`` poles of each design (one per conjugate pair is enough).

    Returns
    -------
    numpy.ndarray
        ``(N,)`` rates in 1/s.
    """
    mod = np.abs(poles)
    osc = np.abs(poles.imag) > 1e-9 * np.maximum(mod, 1e-300)
    base = np.where(osc.any(axis=1), np.where(osc, mod, 0.0).max(axis=1), mod.min(axis=1))
    keep = osc | (mod <= 10.0 * base[:, None])
    return np.where(keep, mod, 0.0).max(axis=1)


# --- exact responses from the state space -----------------------------------------------------

#: Input families of an impact: name -> ({input: power of s}, order m of the pole at 0).
#: ``y = (sum_j s^e_j G_j(s)) / s^m``: the constant-velocity ramp (v_c = 1), the
#: ramp of the closing speed (v_c = t), and steps of a_d and a_ff.
FAMILIES: dict[str, tuple[dict[str, int], int]] = {
    "ramp": ({"s_c": 0, "v_c": 1}, 2),
    "accel": ({"s_c": 0, "v_c": 1}, 3),
    "a_d": ({"a_d": 0}, 1),
    "a_ff": ({"a_ff": 0}, 1),
}


def modal_families(
    model: LinearImpactModel,
    params: NDArray[np.float64],
    outputs: Sequence[str],
    families: Sequence[str] = ("ramp",),
) -> dict[str, dict[str, ModalResponse]]:
    """Exact responses of the full-joint model from its state space (eigen-decomposition).

    A stiff transmission puts the motor node's pole many decades above the
    impact modes; the roots of the characteristic *polynomial* then lose all
    accuracy, while the eigenvalues of ``A`` keep it. With ``A = V diag(l) V^-1``
    each transfer function is ``G_j(s) = D_j + sum_i (C v_i)(w_i B_j)/(s - l_i)``,
    so the response ``y = (sum_j s^e_j G_j) / s^m`` has the residues
    ``(C v_i) sum_j l_i^e_j (w_i B_j) / l_i^m`` and a polynomial part from the
    Taylor coefficients ``G_j^(k)(0)/k! = [k=0] D_j - C A^-(k+1) B_j``.

    Parameters
    ----------
    model
        A model of :func:`full_joint_model` (any linear model works).
    params
        ``(N, n_p)`` parameters.
    outputs
        Output names.
    families
        Keys of :data:`FAMILIES`.

    Returns
    -------
    dict
        ``{family: {output: ModalResponse}}`` (unit input).

    Notes
    -----
    Where ``A`` is nearly defective (two modes coincide, condition number of
    the eigenvector matrix above ``1e8``) the design's responses come from the
    transfer-function route instead, whose partial fractions separate nearly
    repeated poles (:mod:`designlab.impact.modal`).
    """
    out = _eigen_families(model, params, outputs, families)
    a = model.matrices_batch(params)[0]
    with np.errstate(all="ignore"):
        cond = np.linalg.cond(np.linalg.eig(a)[1])
    bad = np.flatnonzero(~np.isfinite(cond) | (cond > _MAX_EIGVEC_CONDITION))
    if bad.size:
        fallback = _polynomial_families(model, params[bad], outputs, families)
        for fam in families:
            for name in outputs:
                out[fam][name] = _splice(out[fam][name], fallback[fam][name], bad)
    return out


#: Condition number of the eigenvector matrix above which a design's responses
#: are built from its transfer functions instead (nearly coincident modes).
_MAX_EIGVEC_CONDITION = 1e8


def _splice(base: ModalResponse, part: ModalResponse, rows: NDArray[np.intp]) -> ModalResponse:
    """``base`` with the designs ``rows`` replaced by ``part`` (columns padded with zeros)."""
    width = max(base.poles.shape[1], part.poles.shape[1])

    def pad(x: NDArray) -> NDArray:
        return np.pad(x, ((0, 0), (0, width - x.shape[1])))

    poles, residues = pad(base.poles), pad(base.residues)
    poles[rows], residues[rows] = pad(part.poles), pad(part.residues)
    poly = base.poly.copy()
    poly[rows] = part.poly
    return ModalResponse(poles, residues, poly)


def _polynomial_families(
    model: LinearImpactModel,
    params: NDArray[np.float64],
    outputs: Sequence[str],
    families: Sequence[str],
) -> dict[str, dict[str, ModalResponse]]:
    """The same responses from the model's transfer-function coefficients."""
    den, num = model.tf_coefficients(params)
    poles = poles_of(den)
    out: dict[str, dict[str, ModalResponse]] = {}
    for fam in families:
        powers, m = FAMILIES[fam]
        nums = {}
        for name in outputs:
            total = np.zeros((params.shape[0], den.shape[1] + 1))
            for k, e in powers.items():
                coef = num[name][:, model.input_names.index(k), :]
                shifted = np.concatenate([coef, np.zeros((coef.shape[0], e))], axis=1)
                total[:, total.shape[1] - shifted.shape[1] :] += shifted
            nums[name] = total
        out[fam] = ModalResponse.family(nums, den, m, poles)
    return out


def _eigen_families(
    model: LinearImpactModel,
    params: NDArray[np.float64],
    outputs: Sequence[str],
    families: Sequence[str],
) -> dict[str, dict[str, ModalResponse]]:
    """:func:`modal_families` by the eigen-decomposition of ``A``."""
    from designlab.impact.modal import _fold, _fold_plan

    a, b, c, d = model.matrices_batch(params)
    lam, vec = np.linalg.eig(a)
    w = np.linalg.inv(vec)
    cv = np.einsum("nyx,nxi->nyi", c, vec)  # (N, n_y, n)
    wb = np.einsum("nix,nxu->niu", w, b)  # (N, n, n_u)
    a_inv = np.linalg.inv(a)
    plan = _fold_plan(lam)
    out: dict[str, dict[str, ModalResponse]] = {}
    for fam in families:
        powers, m = FAMILIES[fam]
        idx = {model.input_names.index(k): e for k, e in powers.items()}
        # residues of (sum_j s^e_j G_j) / s^m at the eigenvalues
        gain = sum(lam**e * wb[:, :, j] for j, e in idx.items()) / lam**m  # (N, n)
        # Taylor coefficients of H(s) = sum_j s^e_j G_j(s), orders 0..m-1
        taylor = np.zeros((params.shape[0], len(model.output_names), m))
        a_pow = np.broadcast_to(np.eye(a.shape[1]), a.shape).copy()
        g_k = []
        for k in range(m):
            a_pow = a_pow @ a_inv  # A^-(k+1)
            g = -np.einsum("nyx,nxz,nzu->nyu", c, a_pow, b)
            if k == 0:
                g = g + d
            g_k.append(g)
        for lag in range(m):
            for j, e in idx.items():
                if lag - e >= 0:
                    taylor[:, :, lag] += g_k[lag - e][:, :, j]
        from math import factorial

        fam_out = {}
        for name in outputs:
            y = model.output_names.index(name)
            res = cv[:, y, :] * gain
            p_f, r_f = _fold(lam, res, plan)
            poly = np.stack(
                [taylor[:, y, lag] / factorial(m - 1 - lag) for lag in range(m)], axis=1
            )
            fam_out[name] = ModalResponse(p_f, r_f, poly)
        out[fam] = fam_out
    return out


# --- comparison of the reductions -------------------------------------------------------------


def default_band(robot: FullJointContact, foam: Foam, head: HeadNeck | None) -> float:
    """The fastest mode of the Taylor-reduced impact (largest pole modulus), rad/s.

    The default upper end of the band fit: the band then covers the impact's modes.

    Parameters
    ----------
    robot, foam, head
        The full-joint manipulator, the covering and the head (``None``: constrained).

    Returns
    -------
    float
        The largest pole modulus, rad/s.
    """
    from designlab.impact.model import constrained_model, param_vector, unconstrained_model

    model = constrained_model() if head is None else unconstrained_model()
    den = model.denominator(param_vector(robot.taylor(), foam, head))
    return float(np.abs(poles_of(den)).max())


def matrix_metrics(params: ArrayLike, impact_velocity: ArrayLike, **options: Any) -> Any:
    """First-lobe metrics of a parameter matrix in the model's column order.

    ``(N, 8)`` rows ordered as :data:`~designlab.impact.model.PARAM_NAMES` use
    the reduced joint, ``(N, 10)`` rows ordered as :data:`FULL_PARAM_NAMES` the
    full series joint (3.4.6). For callers that build the rows themselves (the
    comparisons here, the benchmark); a mapping by name goes to
    :func:`~designlab.impact.metrics.impact_metrics`.

    Parameters
    ----------
    params
        ``(N, 8)`` or ``(N, 10)`` rows (SI units).
    impact_velocity
        v_c in m/s, scalar or ``(N,)``.
    **options
        Passed on (``constrained``, ``stop_time``, ``with_force``, ...).

    Returns
    -------
    ImpactMetrics

    Examples
    --------
    >>> from designlab.impact import FOAM_1, HEAD_MIN
    >>> arm = FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    >>> m = matrix_metrics(full_joint_params(arm, FOAM_1, HEAD_MIN)[None, :], 1.25)
    >>> round(float(m.peak_head_acceleration_g[0]), 3)
    4.079
    """
    from designlab.impact import metrics

    # the matrix entry point of the metrics module where it has one, else the batch one
    evaluate = getattr(metrics, "metrics_of_matrix", metrics.impact_metrics)
    return evaluate(np.atleast_2d(np.asarray(params, dtype=float)), impact_velocity, **options)


def _metric_rows(
    params: NDArray[np.float64], v_c: float, constrained: bool, stop_time: float
) -> dict[str, NDArray[np.float64]]:
    """The compared metrics for designs ``params`` (rows of 8 or 10 parameters)."""
    from designlab.impact.metrics import ramp_responses, response_model

    m = matrix_metrics(params, v_c, constrained=constrained, stop_time=stop_time)
    model = response_model(params, constrained)
    resp = ramp_responses(model, params, ("force",))["force"]
    t_end = m.impact_duration
    ok = np.isfinite(t_end) & (t_end > 0)
    _, f1 = first_local_maximum(resp.take(np.flatnonzero(ok)), t_end[ok])
    first = np.full(len(m), np.nan)
    first[ok] = f1 * max(v_c, 0.0)
    return {
        "a_h_max": m.peak_head_acceleration / STANDARD_GRAVITY,
        "eps_max": m.max_compression,
        "f_c_max": m.peak_force,
        "f_c_first_peak": first,
        "t_imp": m.impact_duration,
        # per-design statuses (``design_status`` once ImpactMetrics is a Result)
        "status": np.broadcast_to(getattr(m, "design_status", m.status), (len(m),)),
    }


def _long_rows(
    key: dict[str, Any],
    full: dict[str, NDArray],
    reduced: dict[str, dict[str, NDArray]],
    index: int,
) -> list[dict[str, Any]]:
    rows = []
    for red, vals in reduced.items():
        for metric, unit in METRICS.items():
            f = float(full[metric][index])
            r = float(vals[metric][index])
            err = (r - f) / f if f != 0 and np.isfinite(f) else math.nan
            cons: Any = pd.NA
            if metric in HARM_METRICS and np.isfinite(err):
                cons = bool(err >= -EQUAL_TOLERANCE)
            rows.append(
                {
                    **key,
                    "reduction": red,
                    "metric": metric,
                    "unit": unit,
                    "full": f,
                    "reduced": r,
                    "relative_error": err,
                    "conservative": cons,
                }
            )
    return rows


@dataclass(frozen=True, eq=False)
class JointReductionComparison(Result):
    """Full joint vs its reductions on one arm, foam and head (:func:`compare_joint_reductions`).

    Attributes
    ----------
    robot
        The full-joint manipulator.
    reduced
        The reduced manipulators by name (``"taylor"``, ``"band_fit"``).
    band
        The band fit (:class:`~designlab.impact.joint.JointFit`) and its
        ``omega_max`` in :attr:`band_omega_max`.
    foam, head
        The foam and the head-neck set (``None``: constrained impact).
    band_omega_max
        Upper end of the band fit's band, rad/s.
    impact_velocity
        v_c, m/s.
    status
        ``"ok"``, or ``"band_fit_failed"`` (the band-fit rows are missing) or
        the first metric status that is not ``"ok"``.
    warnings
        Notes on the result (a failed band fit, metric warnings).
    """

    robot: FullJointContact
    foam: Foam
    head: HeadNeck | None
    impact_velocity: float
    reduced: dict[str, ContactDynamics]
    band: JointFit
    band_omega_max: float
    status: str
    warnings: tuple[str, ...]
    _frame: pd.DataFrame = field(repr=False)

    def to_frame(self) -> pd.DataFrame:
        """One row per (reduction, metric): full and reduced values, relative error, side.

        ``relative_error = (reduced - full) / full``; ``conservative`` is True when
        the reduction overestimates a harm metric (a_h_max, eps_max, the force
        peaks) and missing for t_imp.

        Returns
        -------
        pandas.DataFrame
            Columns ``reduction, metric, unit, full, reduced, relative_error,
            conservative``.
        """
        return self._frame.copy()

    def relative_error(self, reduction: str, metric: str) -> float:
        """``(reduced - full) / full`` of ``metric`` for ``reduction``.

        Parameters
        ----------
        reduction
            ``"taylor"`` or ``"band_fit"``.
        metric
            A key of :data:`METRICS` (``a_h_max``, ``eps_max``, ``f_c_max``,
            ``f_c_first_peak``, ``t_imp``).

        Returns
        -------
        float
            The relative error (NaN where the full value is zero).
        """
        return float(self._row(reduction, metric)["relative_error"])

    def conservative(self, reduction: str, metric: str) -> bool:
        """Whether ``reduction`` overestimates the harm metric ``metric``.

        Parameters
        ----------
        reduction
            ``"taylor"`` or ``"band_fit"``.
        metric
            A harm metric: ``a_h_max``, ``eps_max``, ``f_c_max`` or ``f_c_first_peak``.

        Returns
        -------
        bool
            True when the reduced value is at least the full one (within a
            relative :data:`EQUAL_TOLERANCE`).
        """
        if metric not in HARM_METRICS:
            raise InvalidParameterError("metric", metric, f"must be one of {HARM_METRICS}")
        return bool(self._row(reduction, metric)["conservative"])

    def value(self, model: str, metric: str) -> float:
        """A metric of the full joint or of a reduction.

        Parameters
        ----------
        model
            ``"full"``, ``"taylor"`` or ``"band_fit"``.
        metric
            A key of :data:`METRICS`.

        Returns
        -------
        float
            The value in the unit of :data:`METRICS` (g, m, N, s).
        """
        row = self._row("taylor" if model == "full" else model, metric)
        return float(row["full" if model == "full" else "reduced"])

    def _row(self, reduction: str, metric: str) -> pd.Series:
        if metric not in METRICS:
            raise InvalidParameterError("metric", metric, f"must be one of {tuple(METRICS)}")
        sel = self._frame[(self._frame.reduction == reduction) & (self._frame.metric == metric)]
        if sel.empty:
            raise InvalidParameterError(
                "reduction", reduction, f"must be one of {sorted(self.reduced)}"
            )
        return sel.iloc[0]


def _check_inputs(robot: Any, foam: Any, head: Any) -> None:
    if not isinstance(robot, FullJointContact):
        raise InvalidParameterError("robot", robot, "must be a FullJointContact")
    if not isinstance(foam, Foam):
        raise InvalidParameterError("foam", foam, "must be a Foam")
    if head is not None and not isinstance(head, HeadNeck):
        raise InvalidParameterError("head", head, "must be a HeadNeck or None")


def _reduced_rows(
    robots: Sequence[FullJointContact],
    foam: Foam,
    head: HeadNeck | None,
    omega_max: float | None,
) -> tuple[dict[str, list[ContactDynamics | None]], list[JointFit], list[float]]:
    """Taylor and band-fit manipulators for each robot (``None`` where the fit failed)."""
    taylor, band, fits, omegas = [], [], [], []
    for r in robots:
        w = omega_max if omega_max is not None else default_band(r, foam, head)
        contact, fit = r.band_fit(w)
        taylor.append(r.taylor())
        band.append(contact)
        fits.append(fit)
        omegas.append(w)
    return {"taylor": taylor, "band_fit": band}, fits, omegas


def _evaluate_all(
    robots: Sequence[FullJointContact],
    reduced: dict[str, list[ContactDynamics | None]],
    foam: Foam,
    head: HeadNeck | None,
    v_c: float,
    stop_time: float,
) -> tuple[dict[str, NDArray], dict[str, dict[str, NDArray]]]:
    from designlab.impact.model import param_vector

    constrained = head is None
    full = _metric_rows(
        np.array([full_joint_params(r, foam, head) for r in robots]), v_c, constrained, stop_time
    )
    out: dict[str, dict[str, NDArray]] = {}
    for name, contacts in reduced.items():
        ok = [i for i, c in enumerate(contacts) if c is not None]
        vals = {k: np.full(len(robots), np.nan) for k in METRICS}
        if ok:
            rows = np.array([param_vector(contacts[i], foam, head) for i in ok])
            got = _metric_rows(rows, v_c, constrained, stop_time)
            for k in METRICS:
                vals[k][ok] = got[k]
        out[name] = vals
    return full, out


def compare_joint_reductions(
    robot: FullJointContact,
    foam: Foam,
    head: HeadNeck | None,
    impact_velocity: float,
    *,
    omega_max: float | None = None,
    stop_time: float = 0.05,
) -> JointReductionComparison:
    """Error of the reduced joint on the safety metrics, against the full joint (3.4.6).

    Evaluates the full series joint, the Taylor reduction (3.4.9) and the band
    fit on the same arm, foam, head and v_c, and reports for each reduction
    and metric (a_h,max, eps_max, the lobe maximum and the first local maximum
    of the force, the impact period) the relative error and its sign.

    Parameters
    ----------
    robot
        The manipulator with its full joint.
    foam, head
        The covering and the head (``None``: constrained impact, head against a wall).
    impact_velocity
        v_c, m/s (> 0).
    omega_max
        Upper end of the band fit, rad/s. Default: three times the fastest
        mode of the Taylor-reduced impact model, so the band covers the impact.
    stop_time
        Window of the constrained impact, s.

    Returns
    -------
    JointReductionComparison

    Examples
    --------
    >>> import designlab as dl
    >>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    >>> c = compare_joint_reductions(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25)
    >>> f = c.to_frame()
    >>> f[f.metric == "a_h_max"].relative_error.round(3).tolist()   # Taylor, band fit
    [0.125, 0.044]
    """
    _check_inputs(robot, foam, head)
    v_c = check_positive("impact_velocity", impact_velocity, "m/s")
    stop = check_positive("stop_time", stop_time, "s")
    if omega_max is not None:
        omega_max = check_positive("omega_max", omega_max, "rad/s")
    reduced, fits, omegas = _reduced_rows([robot], foam, head, omega_max)
    full, vals = _evaluate_all([robot], reduced, foam, head, v_c, stop)
    rows = _long_rows({}, full, {k: v for k, v in vals.items() if reduced[k][0]}, 0)
    warnings: list[str] = []
    status = "ok"
    if reduced["band_fit"][0] is None:
        status = "band_fit_failed"
        warnings.append(f"the band fit failed ({fits[0].status}); only the Taylor rows are given")
    statuses = [str(full["status"][0])]
    if status == "ok" and statuses[0] != "ok":
        status = statuses[0]
        warnings.append(f"full-joint metrics status: {statuses[0]}")
    return JointReductionComparison(
        robot=robot,
        foam=foam,
        head=head,
        impact_velocity=v_c,
        reduced={k: v[0] for k, v in reduced.items() if v[0] is not None},
        band=fits[0],
        band_omega_max=omegas[0],
        status=status,
        warnings=tuple(warnings),
        _frame=pd.DataFrame(rows),
    )


# --- sweep over the stiffness ratio ----------------------------------------------------------


@dataclass(frozen=True, eq=False)
class JointReductionSweep(Result):
    """Errors of the reductions over K_mech/K_cont (:func:`joint_reduction_sweep`).

    Attributes
    ----------
    ratio
        K_mech / K_cont of each point.
    base
        The manipulator the sweep was built from (its controller, mass and
        transmission damping are kept; K_mech = ratio * K_cont).
    foam, head
        The foam and the head-neck set (``None``: constrained impact).
    impact_velocity
        v_c, m/s.
    status
        ``"ok"``, or what went wrong.
    warnings
        Notes on the result (fallbacks, failed fits).
    """

    base: FullJointContact
    foam: Foam
    head: HeadNeck | None
    impact_velocity: float
    ratio: NDArray[np.float64]
    status: str
    warnings: tuple[str, ...]
    _frame: pd.DataFrame = field(repr=False)

    def to_frame(self) -> pd.DataFrame:
        """One row per (ratio, reduction, metric).

        Returns
        -------
        pandas.DataFrame
            ``point, ratio, k_mech_N_per_m, band_omega_max_rad_per_s`` and the
            columns of :meth:`JointReductionComparison.to_frame`.
        """
        return self._frame.copy()

    def errors(self, reduction: str, metric: str) -> NDArray[np.float64]:
        """Relative errors of ``reduction`` on ``metric`` along :attr:`ratio`.

        Parameters
        ----------
        reduction
            ``"taylor"`` or ``"band_fit"``.
        metric
            A key of :data:`METRICS`.

        Returns
        -------
        numpy.ndarray
            One error per ratio (NaN where the reduction is missing).
        """
        f = self._frame
        sel = f[(f.reduction == reduction) & (f.metric == metric)]
        if sel.empty:
            raise InvalidParameterError("reduction/metric", (reduction, metric), "not in the sweep")
        by_point = sel.set_index("point").relative_error
        return by_point.reindex(range(self.ratio.size)).to_numpy(dtype=float)

    def conservative_region(self, reduction: str, metric: str) -> NDArray[np.bool_]:
        """Where ``reduction`` overestimates ``metric`` (a harm metric), along :attr:`ratio`.

        Parameters
        ----------
        reduction
            ``"taylor"`` or ``"band_fit"``.
        metric
            A harm metric: ``a_h_max``, ``eps_max``, ``f_c_max`` or ``f_c_first_peak``.

        Returns
        -------
        numpy.ndarray
            Booleans, one per ratio; False where the reduction is missing.
        """
        if metric not in HARM_METRICS:
            raise InvalidParameterError("metric", metric, f"must be one of {HARM_METRICS}")
        err = self.errors(reduction, metric)
        return np.isfinite(err) & (err >= -EQUAL_TOLERANCE)

    def conservative_intervals(
        self, reduction: str, metrics: Sequence[str] = ("a_h_max", "eps_max", "f_c_max")
    ) -> list[tuple[float, float]]:
        """Ratio intervals (of the sampled points) where ``reduction`` overestimates every metric.

        Parameters
        ----------
        reduction
            ``"taylor"`` or ``"band_fit"``.
        metrics
            Harm metrics that must all be overestimated.

        Returns
        -------
        list of tuple
            ``[(first ratio, last ratio), ...]`` of the runs of consecutive
            sampled ratios at which the reduction is conservative on all ``metrics``.

        Examples
        --------
        >>> import designlab as dl
        >>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0,
        ...                                              lever_arm=0.2)
        >>> s = dl.impact.joint_reduction_sweep(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN,
        ...                                     1.25, [0.03, 0.1, 1.0, 10.0])
        >>> s.conservative_intervals("taylor")
        [(0.03, 0.1)]
        >>> s.conservative_intervals("taylor", ["a_h_max"])
        [(0.03, 10.0)]
        """
        ok = np.ones(self.ratio.size, dtype=bool)
        for m in metrics:
            ok &= self.conservative_region(reduction, m)
        return self._runs(ok)

    def usable_intervals(
        self,
        reduction: str,
        tolerance: float = 0.01,
        metrics: Sequence[str] = ("a_h_max", "eps_max", "f_c_max"),
    ) -> list[tuple[float, float]]:
        """Ratio intervals where ``reduction`` may stand in for the full joint on ``metrics``.

        A reduction may be used where, on every metric, it either overestimates
        the harm (conservative) or underestimates it by at most ``tolerance``.

        Parameters
        ----------
        reduction
            ``"taylor"`` or ``"band_fit"``.
        tolerance
            Largest accepted underestimate, relative (0.01: 1 %), in ``[0, 1)``.
        metrics
            Harm metrics checked.

        Returns
        -------
        list of tuple
            ``[(first ratio, last ratio), ...]`` runs of consecutive sampled ratios.

        Examples
        --------
        >>> import designlab as dl
        >>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0,
        ...                                              lever_arm=0.2)
        >>> s = dl.impact.joint_reduction_sweep(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN,
        ...                                     1.25, [0.03, 0.1, 1.0, 10.0, 100.0])
        >>> s.usable_intervals("taylor")          # within 1 % from K_mech = 10 K_cont on
        [(0.03, 0.1), (10.0, 100.0)]
        >>> s.usable_intervals("taylor", tolerance=0.005)
        [(0.03, 0.1), (100.0, 100.0)]
        """
        if isinstance(tolerance, bool) or not (
            isinstance(tolerance, (int, float)) and 0 <= tolerance < 1
        ):
            raise InvalidParameterError("tolerance", tolerance, "must be a number in [0, 1)")
        ok = np.ones(self.ratio.size, dtype=bool)
        for m in metrics:
            if m not in HARM_METRICS:
                raise InvalidParameterError("metric", m, f"must be one of {HARM_METRICS}")
            err = self.errors(reduction, m)
            ok &= np.isfinite(err) & (err >= -(tolerance + EQUAL_TOLERANCE))
        return self._runs(ok)

    def _runs(self, ok: NDArray[np.bool_]) -> list[tuple[float, float]]:
        """``(first, last)`` ratios of the runs of consecutive True entries of ``ok``."""
        out: list[tuple[float, float]] = []
        start = None
        for i, flag in enumerate(ok):
            if flag and start is None:
                start = i
            if start is not None and (not flag or i == ok.size - 1):
                end = i if flag else i - 1
                out.append((float(self.ratio[start]), float(self.ratio[end])))
                start = None
        return out


def joint_reduction_sweep(
    robot: FullJointContact,
    foam: Foam,
    head: HeadNeck | None,
    impact_velocity: float,
    ratios: ArrayLike,
    *,
    omega_max: float | None = None,
    stop_time: float = 0.05,
) -> JointReductionSweep:
    """Errors of the Taylor and band-fit reductions over K_mech/K_cont.

    The controller (K_cont, C_cont), the mass and the transmission damping of
    ``robot`` are kept; the transmission stiffness is ``ratio * K_cont``. A large
    ratio is a direct drive (the reduction tends to exact), a ratio near or
    below one a compliant transmission.

    Parameters
    ----------
    robot, foam, head, impact_velocity, omega_max, stop_time
        As in :func:`compare_joint_reductions` (``omega_max`` per point by default).
    ratios
        K_mech / K_cont values (each > 0).

    Returns
    -------
    JointReductionSweep

    Examples
    --------
    >>> import designlab as dl
    >>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    >>> s = joint_reduction_sweep(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25, [0.5, 1e3])
    >>> err = s.errors("taylor", "a_h_max")
    >>> bool(abs(err[1]) < 1e-3 < abs(err[0]))
    True
    """
    _check_inputs(robot, foam, head)
    v_c = check_positive("impact_velocity", impact_velocity, "m/s")
    stop = check_positive("stop_time", stop_time, "s")
    r = np.atleast_1d(np.asarray(ratios, dtype=float))
    if r.ndim != 1 or r.size == 0 or not np.all(np.isfinite(r)) or np.any(r <= 0):
        raise InvalidParameterError(
            "ratios", r.tolist(), "must be a non-empty 1-D array of finite numbers > 0"
        )
    if omega_max is not None:
        omega_max = check_positive("omega_max", omega_max, "rad/s")
    robots = [
        FullJointContact(
            robot.mass,
            float(x) * robot.control_stiffness,
            robot.transmission_damping,
            robot.control_stiffness,
            robot.control_damping,
            robot.lever_arm,
            robot.name,
        )
        for x in r
    ]
    reduced, _, omegas = _reduced_rows(robots, foam, head, omega_max)
    full, vals = _evaluate_all(robots, reduced, foam, head, v_c, stop)
    rows: list[dict[str, Any]] = []
    for i, x in enumerate(r):
        key = {
            "point": i,
            "ratio": float(x),
            "k_mech_N_per_m": robots[i].transmission_stiffness,
            "band_omega_max_rad_per_s": omegas[i],
        }
        avail = {k: v for k, v in vals.items() if reduced[k][i] is not None}
        rows.extend(_long_rows(key, full, avail, i))
    failed = [float(x) for i, x in enumerate(r) if reduced["band_fit"][i] is None]
    warnings = []
    if failed:
        warnings.append(f"the band fit failed at ratios {failed}; those rows are missing")
    bad = sorted({str(s) for s in full["status"] if str(s) != "ok"})
    if bad:
        warnings.append(f"full-joint metric statuses other than ok: {bad}")
    return JointReductionSweep(
        base=robot,
        foam=foam,
        head=head,
        impact_velocity=v_c,
        ratio=r,
        status="ok" if not failed else "band_fit_failed",
        warnings=tuple(warnings),
        _frame=pd.DataFrame(rows),
    )


# --- sweep over the band of the fit ---------------------------------------------------------


@dataclass(frozen=True, eq=False)
class BandFitSweep(Result):
    """The band fit's errors as its band changes (:func:`band_fit_sweep`).

    Attributes
    ----------
    omega_max
        Upper ends of the bands, rad/s.
    rms_ratio
        Frequency-domain rms relative error of the fit divided by the Taylor
        truncation's, over each band (< 1: the fit is better *in frequency*).
    robot
        The full-joint manipulator.
    foam, head
        The foam and the head-neck set (``None``: constrained impact).
    impact_velocity
        v_c, m/s.
    status
        ``"ok"``, or what went wrong.
    warnings
        Notes on the result (fallbacks, failed fits).
    """

    robot: FullJointContact
    foam: Foam
    head: HeadNeck | None
    impact_velocity: float
    omega_max: NDArray[np.float64]
    rms_ratio: NDArray[np.float64]
    status: str
    warnings: tuple[str, ...]
    _frame: pd.DataFrame = field(repr=False)

    def to_frame(self) -> pd.DataFrame:
        """One row per band.

        Returns
        -------
        pandas.DataFrame
            The fit, the rms ratio and the relative error of each metric
            (``err_<metric>``), with the Taylor reduction's (``taylor_err_<metric>``).
        """
        return self._frame.copy()

    def errors(self, metric: str) -> NDArray[np.float64]:
        """The band fit's relative error on ``metric`` along :attr:`omega_max`.

        Parameters
        ----------
        metric
            A key of :data:`METRICS`.

        Returns
        -------
        numpy.ndarray
            One error per band (NaN where the fit failed).
        """
        if metric not in METRICS:
            raise InvalidParameterError("metric", metric, f"must be one of {tuple(METRICS)}")
        return self._frame[f"err_{metric}"].to_numpy(dtype=float)


def band_fit_sweep(
    robot: FullJointContact,
    foam: Foam,
    head: HeadNeck | None,
    impact_velocity: float,
    omega_max: ArrayLike,
    *,
    stop_time: float = 0.05,
) -> BandFitSweep:
    """How the band fit's errors on the impact metrics follow its band, against the Taylor's.

    A smaller frequency-domain error (``rms_ratio`` < 1) does not mean a smaller
    error on the safety metrics, nor one on the safe side: this puts the two
    side by side for each band ``[omega_max/1000, omega_max]``.

    Parameters
    ----------
    robot, foam, head, impact_velocity, stop_time
        As in :func:`compare_joint_reductions`.
    omega_max
        Upper ends of the bands, rad/s (each > 0).

    Returns
    -------
    BandFitSweep

    Examples
    --------
    >>> import designlab as dl
    >>> arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    >>> b = dl.impact.band_fit_sweep(arm, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25, [89.6, 200])
    >>> b.rms_ratio.round(2).tolist(), b.errors("a_h_max").round(3).tolist()
    ([0.84, 0.67], [0.089, 0.037])
    """
    from designlab.impact.model import param_vector

    _check_inputs(robot, foam, head)
    v_c = check_positive("impact_velocity", impact_velocity, "m/s")
    stop = check_positive("stop_time", stop_time, "s")
    w = np.atleast_1d(np.asarray(omega_max, dtype=float))
    if w.ndim != 1 or w.size == 0 or not np.all(np.isfinite(w)) or np.any(w <= 0):
        raise InvalidParameterError(
            "omega_max", w.tolist(), "must be a non-empty 1-D array of finite numbers > 0", "rad/s"
        )
    constrained = head is None
    full = _metric_rows(full_joint_params(robot, foam, head)[None, :], v_c, constrained, stop)
    taylor = _metric_rows(param_vector(robot.taylor(), foam, head)[None, :], v_c, constrained, stop)
    fits = [robot.band_fit(float(x)) for x in w]
    ok = [i for i, (c, _) in enumerate(fits) if c is not None]
    rows_p = np.array([param_vector(fits[i][0], foam, head) for i in ok]).reshape(len(ok), -1)
    band = _metric_rows(rows_p, v_c, constrained, stop) if ok else {}
    frame: dict[str, Any] = {
        "omega_max_rad_per_s": w,
        "K_fit_N_per_m": [f.stiffness for _, f in fits],
        "C_fit_N_s_per_m": [f.damping for _, f in fits],
        "rms_ratio": [f.rms_error / f.taylor_rms_error for _, f in fits],
        "fit_status": [f.status for _, f in fits],
    }
    for metric in METRICS:
        ref = float(full[metric][0])
        err = np.full(w.size, np.nan)
        if ok:
            err[ok] = (band[metric] - ref) / ref
        frame[f"err_{metric}"] = err
        frame[f"taylor_err_{metric}"] = (float(taylor[metric][0]) - ref) / ref
    failed = [float(w[i]) for i in range(w.size) if i not in ok]
    warnings = (f"the band fit failed for omega_max = {failed} rad/s",) if failed else ()
    return BandFitSweep(
        robot=robot,
        foam=foam,
        head=head,
        impact_velocity=v_c,
        omega_max=w,
        rms_ratio=np.asarray(frame["rms_ratio"], dtype=float),
        status="band_fit_failed" if failed else "ok",
        warnings=warnings,
        _frame=pd.DataFrame(frame),
    )
