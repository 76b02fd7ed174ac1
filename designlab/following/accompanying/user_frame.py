"""The user-frame error transform of Wu et al. 2021, eqs. (1)-(8), in CasADi.

Frames (Wu et al. 2021, Sec. 2.1; ``docs/following.md``): in each local frame
Y points forward and X to the right; world headings psi are counter-clockwise
from the world X axis, so a heading of pi/2 faces +Y.

* robot in the user frame (eq. 4, world form):
  ``p_C = R(psi_U - pi/2)^T (p_R - p_U)``, ``gamma_C = wrap(psi_R - psi_U)``;
* string-pot readings (eq. 7): ``d = |p_C|``, ``theta_U = atan2(Y_C, X_C)``,
  ``theta_R = wrap(gamma_C - theta_U)``;
* error in the robot frame from the readings (eq. 8):
  ``e_R = R(theta_U + theta_R)^T (p_T - d [cos theta_U, sin theta_U])`` and the
  heading error ``e_theta = wrap(gamma_T - (theta_U + theta_R))``.

The expressions are built once as CasADi functions (used by the closed-loop
simulation) and evaluated on numpy arrays by the wrappers below.

Examples
--------
>>> import numpy as np
>>> # user at the origin facing +Y, robot 0.5 m ahead, same heading
>>> p_c, g = robot_in_user_frame([0, 0, np.pi / 2], [0, 0.5, np.pi / 2])
>>> np.round(p_c, 12), round(float(g), 12)
(array([0. , 0.5]), 0.0)
>>> d, tu, tr = string_pot_readings(p_c, g)
>>> round(float(d), 3), round(float(np.degrees(tu)), 1), round(float(np.degrees(tr)), 1)
(0.5, 90.0, -90.0)
>>> e = robot_frame_error([0.0, 0.6], 0.0, d, tu, tr)   # target 0.1 m further ahead
>>> np.round(e, 12)
array([0. , 0.1, 0. ])
"""

from __future__ import annotations

from functools import lru_cache

import casadi as ca
import numpy as np
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.sx.replay import vectorize
from designlab.validation import real_array

__all__ = [
    "robot_frame_error",
    "robot_in_user_frame",
    "string_pot_readings",
    "sx_robot_frame_error",
    "sx_robot_in_user_frame",
    "sx_string_pot",
    "wrap_angle",
]


def wrap_angle(a: ArrayLike) -> NDArray[np.float64]:
    """Wrap angles to (-pi, pi].

    Parameters
    ----------
    a
        Angles (rad).

    Examples
    --------
    >>> float(np.round(wrap_angle(3 * np.pi / 2), 6))
    -1.570796
    """
    a = np.asarray(a, dtype=float)
    return np.arctan2(np.sin(a), np.cos(a))


def _wrap(a):  # casadi or numpy
    return ca.atan2(ca.sin(a), ca.cos(a))


def sx_robot_in_user_frame(user_pose, robot_pose):
    """Robot position (X_C, Y_C) and orientation gamma_C in LCS_U (symbolic, eq. 4).

    Parameters
    ----------
    user_pose
        User pose (x_U, y_U, psi_U) in the world frame (m, m, rad), CasADi symbols.
    robot_pose
        Robot pose (x_R, y_R, psi_R) in the world frame (m, m, rad), CasADi symbols.
    """
    xu, yu, psu = user_pose[0], user_pose[1], user_pose[2]
    xr, yr, psr = robot_pose[0], robot_pose[1], robot_pose[2]
    dx, dy = xr - xu, yr - yu
    # R(psi_U - pi/2)^T [dx, dy]: columns of R are the user's right and forward axes
    right_x, right_y = ca.sin(psu), -ca.cos(psu)
    fwd_x, fwd_y = ca.cos(psu), ca.sin(psu)
    xc = right_x * dx + right_y * dy
    yc = fwd_x * dx + fwd_y * dy
    return xc, yc, _wrap(psr - psu)


def sx_string_pot(xc, yc, gamma_c):
    """String-pot readings (d, theta_U, theta_R) from the pose in LCS_U (eq. 7).

    Parameters
    ----------
    xc
        Robot position X_C in the user's frame LCS_U (m).
    yc
        Robot position Y_C in LCS_U (m).
    gamma_c
        Robot bearing gamma_C in LCS_U (rad).
    """
    d = ca.sqrt(xc**2 + yc**2)
    tu = ca.atan2(yc, xc)
    tr = _wrap(gamma_c - tu)
    return d, tu, tr


def sx_robot_frame_error(target_x, target_y, target_gamma, d, tu, tr):
    """Error (e_x, e_y) in LCS_R and heading error e_theta from the readings (eq. 8).

    Parameters
    ----------
    target_x
        Desired robot position x in LCS_U (m).
    target_y
        Desired robot position y in LCS_U (m).
    target_gamma
        Desired robot heading in LCS_U (rad).
    d
        String-pot length reading (m).
    tu
        String-pot angle theta_U at the user (rad).
    tr
        String-pot angle theta_R at the robot (rad).
    """
    g = tu + tr
    ex_u = target_x - d * ca.cos(tu)
    ey_u = target_y - d * ca.sin(tu)
    c, s = ca.cos(g), ca.sin(g)
    ex = c * ex_u + s * ey_u
    ey = -s * ex_u + c * ey_u
    return ex, ey, _wrap(target_gamma - g)


@lru_cache(maxsize=1)
def _functions() -> tuple:
    u = ca.SX.sym("user", 3)
    r = ca.SX.sym("robot", 3)
    xc, yc, g = sx_robot_in_user_frame(u, r)
    f_pose = ca.Function("robot_in_user_frame", [u, r], [ca.vertcat(xc, yc, g)])
    p = ca.SX.sym("pose_c", 3)
    f_pot = ca.Function("string_pot", [p], [ca.vertcat(*sx_string_pot(p[0], p[1], p[2]))])
    t = ca.SX.sym("target", 3)
    m = ca.SX.sym("reading", 3)
    f_err = ca.Function(
        "robot_frame_error",
        [t, m],
        [ca.vertcat(*sx_robot_frame_error(t[0], t[1], t[2], m[0], m[1], m[2]))],
    )
    # numpy replays of the SX functions, vectorised over columns
    return vectorize(f_pose), vectorize(f_pot), vectorize(f_err)


def robot_in_user_frame(
    user_pose: ArrayLike, robot_pose: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Robot position (X_C, Y_C) in m and orientation gamma_C in rad in the user's frame.

    Parameters
    ----------
    user_pose, robot_pose
        World (x, y, psi) in m, m, rad; shape (3,) or (3, n).

    Returns
    -------
    p_c, gamma_c
        Shape (2,) / scalar, or (2, n) / (n,).
    """
    u, r = real_array("user_pose", user_pose), real_array("robot_pose", robot_pose)
    if (
        u.ndim not in (1, 2)
        or r.ndim not in (1, 2)
        or u.shape[0] != 3
        or r.shape[0] != 3
        or (u.ndim == r.ndim == 2 and u.shape != r.shape)
    ):
        raise InvalidParameterError(
            "user_pose, robot_pose", (u.shape, r.shape), "3 rows (x, y, psi) each"
        )
    res = _functions()[0](u.reshape(3, -1), r.reshape(3, -1))[0]
    if u.ndim == 1 and r.ndim == 1:
        return res[:2, 0], float(res[2, 0])
    return res[:2], res[2]


def string_pot_readings(
    p_c: ArrayLike, gamma_c: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Noise-free string-pot readings (d, theta_U, theta_R) for a pose in LCS_U (eq. 7).

    Parameters
    ----------
    p_c
        (X_C, Y_C) in m; shape (2,) or (2, n).
    gamma_c
        Robot orientation in LCS_U in rad; scalar or (n,).
    """
    pc, gc = real_array("p_c", p_c, "m"), real_array("gamma_c", gamma_c, "rad")
    if (
        pc.ndim not in (1, 2)
        or pc.shape[0] != 2
        or gc.size != pc.size // 2
        or (pc.ndim == 1 and gc.ndim != 0)
    ):
        raise InvalidParameterError(
            "p_c, gamma_c", (pc.shape, gc.shape), "(2,) and a scalar, or (2, n) and (n,)"
        )
    pose = np.vstack([pc.reshape(2, -1), gc.reshape(1, -1)])
    res = _functions()[1](pose)[0]
    if pc.ndim == 1:
        return float(res[0, 0]), float(res[1, 0]), float(res[2, 0])
    return res[0], res[1], res[2]


def robot_frame_error(
    target: ArrayLike, target_gamma: float, d: ArrayLike, theta_u: ArrayLike, theta_r: ArrayLike
) -> NDArray[np.float64]:
    """Position error in LCS_R and heading error (e_x, e_y, e_theta) from readings (eq. 8).

    Parameters
    ----------
    target
        Target (X_T, Y_T) in LCS_U in m.
    target_gamma
        Target orientation of the robot in LCS_U in rad.
    d, theta_u, theta_r
        String-pot readings in m, rad, rad (scalars or arrays of one length).
    """
    rows = [np.atleast_1d(real_array(n, v)) for n, v in (("d", d), ("theta_u", theta_u),
                                                          ("theta_r", theta_r))]  # fmt: skip
    if any(r.ndim != 1 or r.shape != rows[0].shape for r in rows):
        raise InvalidParameterError(
            "d, theta_u, theta_r", [r.shape for r in rows], "scalars or arrays of one length"
        )
    m = np.vstack(rows)
    tp = real_array("target", target, "m")
    if tp.shape != (2,):
        raise InvalidParameterError("target", target, "must be (X_T, Y_T)", "m")
    t = np.array([tp[0], tp[1], float(real_array("target_gamma", target_gamma, "rad"))])
    res = _functions()[2](t, m)[0]
    return res[:, 0] if np.ndim(d) == 0 else res
