"""The impact model with the full series joint (Zeng 2011, eq. 3.4.6), written once in CasADi.

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
exactly (3.4.6). The state space, the transfer functions and the exact modal
responses (:mod:`designlab.impact.state_space`) follow as for the reduced model.

Examples
--------
>>> from designlab.impact import FOAM_1, HEAD_MIN
>>> from designlab.impact.series_joint import FullJointContact
>>> arm = FullJointContact(10.0, 1e5, 10.0, 2e4, 250.0)
>>> full_joint_params(arm, FOAM_1, HEAD_MIN).tolist()
[10.0, 10.0, 100000.0, 24250.0, 71.9, 4.4, 46.0, 3000.0, 250.0, 20000.0]
"""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from designlab.impact.model import INPUT_NAMES, OUTPUT_NAMES, LinearImpactModel, derive_model
from designlab.impact.parameters import Foam, HeadNeck
from designlab.impact.series_joint import FullJointContact

__all__ = [
    "FULL_INPUT_NAMES",
    "FULL_PARAM_NAMES",
    "full_joint_model",
    "full_joint_params",
    "grid_rate",
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
    output_names = (*OUTPUT_NAMES, "transmission_force")  # the reduced model's, and f_t
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
