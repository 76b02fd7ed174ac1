"""Joint reduced-order approximation (Zeng 2011, Sec. 3.4.2 and App. A.2.3).

A position-controlled joint is a transmission (stiffness ``K_mech``, damping
``C_mech``) in series with the controller (P and D gains in torque units,
``K_cont`` and ``C_cont``). Its complex stiffness, eq. (3.4.6),

.. math::

    \\frac{\\tau_J}{\\tilde\\theta}(s) =
    \\frac{(K_{mech} + C_{mech} s)(K_{cont} + C_{cont} s)}
         {(K_{mech} + K_{cont}) + (C_{mech} + C_{cont}) s},

is replaced in the impact model by a spring and damper ``K_J + C_J s``, the
first two terms of its Taylor series about ``s = 0`` (3.4.9a/b). This module
gives the closed forms, the transfer functions (python-control), the exact
truncation error ``E_m(s)`` of (3.4.10) (the thesis writes ``C_r`` there; it
means ``C_J``), a frequency-band least-squares alternative to the Taylor
truncation, and the PD-gain mapping of the direct-drive arm, (A.2.20)/(A.2.21).

Units: stiffness N m/rad, damping N m s/rad, frequency rad/s.

Examples
--------
>>> from designlab.impact.joint import reduced_joint
>>> k_j, c_j = reduced_joint(k_mech=1e9, c_mech=0.0, k_cont=121.7, c_cont=1.52)
>>> round(k_j, 3), round(c_j, 3)
(121.7, 1.52)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt
import pandas as pd

from designlab.errors import InvalidParameterError, check_nonnegative, check_positive
from designlab.results import Result
from designlab.validation import check_array, frozen_array

if TYPE_CHECKING:  # python-control is imported when a transfer function is built
    import control

__all__ = [
    "JointFit",
    "fit_joint_band",
    "full_joint_tf",
    "joint_error_tf",
    "joint_from_pd_gains",
    "pd_gains_for",
    "reduced_joint",
    "reduced_joint_tf",
]

_K_UNIT = "N m/rad"
_C_UNIT = "N m s/rad"

ArrayLike = npt.ArrayLike


# --- validation helpers -----------------------------------------------------


def _joint_args(k_mech: Any, c_mech: Any, k_cont: Any, c_cont: Any) -> tuple[Any, Any, Any, Any]:
    return (
        check_array("k_mech", k_mech, _K_UNIT, positive=True),
        check_array("c_mech", c_mech, _C_UNIT, positive=False),
        check_array("k_cont", k_cont, _K_UNIT, positive=True),
        check_array("c_cont", c_cont, _C_UNIT, positive=False),
    )


def _scalar_joint_args(
    k_mech: float, c_mech: float, k_cont: float, c_cont: float
) -> tuple[float, float, float, float]:
    return (
        check_positive("k_mech", k_mech, _K_UNIT),
        check_nonnegative("c_mech", c_mech, _C_UNIT),
        check_positive("k_cont", k_cont, _K_UNIT),
        check_nonnegative("c_cont", c_cont, _C_UNIT),
    )


def _taylor(km: Any, cm: Any, kc: Any, cc: Any) -> tuple[Any, Any]:
    ks = km + kc
    return km * kc / ks, (kc**2 * cm + km**2 * cc) / ks**2


def _full_response(km: float, cm: float, kc: float, cc: float, omega: np.ndarray) -> np.ndarray:
    s = 1j * omega
    return (km + cm * s) * (kc + cc * s) / ((km + kc) + (cm + cc) * s)


# --- closed forms and transfer functions -----------------------------------


def reduced_joint(
    k_mech: ArrayLike, c_mech: ArrayLike, k_cont: ArrayLike, c_cont: ArrayLike
) -> tuple[float, float] | tuple[np.ndarray, np.ndarray]:
    """Reduced-order joint stiffness and damping, eq. (3.4.9a/b).

    ``K_J = K_mech K_cont / (K_mech + K_cont)`` and
    ``C_J = (K_cont^2 C_mech + K_mech^2 C_cont) / (K_mech + K_cont)^2``:
    the first two Taylor terms about ``s = 0`` of the series connection
    (3.4.6) of transmission and controller.

    Parameters
    ----------
    k_mech
        Transmission stiffness K_mech in N m/rad (> 0).
    c_mech
        Transmission damping C_mech in N m s/rad (>= 0).
    k_cont
        Control stiffness K_cont (P gain in torque units) in N m/rad (> 0).
    c_cont
        Control damping C_cont (D gain in torque units) in N m s/rad (>= 0).

    Returns
    -------
    tuple
        ``(K_J, C_J)`` in N m/rad and N m s/rad: floats for scalar input,
        broadcast numpy arrays if any argument is an array.

    Raises
    ------
    InvalidParameterError
        If a stiffness is not > 0 or a damping is not >= 0 (or not finite).

    Examples
    --------
    >>> reduced_joint(1000.0, 2.0, 1000.0, 4.0)
    (500.0, 1.5)
    >>> import numpy as np
    >>> k, c = reduced_joint(np.array([1e3, 3e3]), 2.0, 1e3, 4.0)
    >>> k.round(1), c.round(3)
    (array([500., 750.]), array([1.5  , 2.375]))
    """
    km, cm, kc, cc = _joint_args(k_mech, c_mech, k_cont, c_cont)
    k_j, c_j = _taylor(km, cm, kc, cc)
    if np.ndim(k_j) == 0 and np.ndim(c_j) == 0:
        return float(k_j), float(c_j)
    k_b, c_b = np.broadcast_arrays(np.asarray(k_j, dtype=float), np.asarray(c_j, dtype=float))
    return np.array(k_b), np.array(c_b)


def full_joint_tf(
    k_mech: float, c_mech: float, k_cont: float, c_cont: float
) -> control.TransferFunction:
    """Full joint complex stiffness tau_J / theta~, eq. (3.4.6).

    ``(K_mech + C_mech s)(K_cont + C_cont s) / ((K_mech + K_cont) + (C_mech + C_cont) s)``.

    Parameters
    ----------
    k_mech, c_mech, k_cont, c_cont
        As in :func:`reduced_joint` (scalars).

    Returns
    -------
    control.TransferFunction
        Improper (numerator degree 2, denominator degree 1) SISO transfer
        function, N m/rad.

    Examples
    --------
    >>> g = full_joint_tf(1000.0, 2.0, 1000.0, 4.0)
    >>> complex(g(0.0)).real
    500.0
    """
    km, cm, kc, cc = _scalar_joint_args(k_mech, c_mech, k_cont, c_cont)
    num = [cm * cc, km * cc + cm * kc, km * kc]
    den = [cm + cc, km + kc]
    import control

    return control.tf(num, den)


def reduced_joint_tf(
    k_mech: float, c_mech: float, k_cont: float, c_cont: float
) -> control.TransferFunction:
    """Reduced joint ``K_J + C_J s`` of (3.4.7) as a transfer function.

    python-control accepts improper transfer functions, so this is the
    first-order polynomial ``C_J s + K_J`` over 1.

    Parameters
    ----------
    k_mech, c_mech, k_cont, c_cont
        As in :func:`reduced_joint` (scalars).

    Returns
    -------
    control.TransferFunction
        ``(C_J s + K_J) / 1`` in N m/rad.

    Examples
    --------
    >>> r = reduced_joint_tf(1000.0, 2.0, 1000.0, 4.0)
    >>> complex(r(10j))
    (500+15j)
    """
    km, cm, kc, cc = _scalar_joint_args(k_mech, c_mech, k_cont, c_cont)
    k_j, c_j = _taylor(km, cm, kc, cc)
    import control

    return control.tf([c_j, k_j], [1.0])


def joint_error_tf(
    k_mech: float, c_mech: float, k_cont: float, c_cont: float
) -> control.TransferFunction:
    """Truncation error ``E_m(s)`` of the reduced joint model, eq. (3.4.10).

    ``E_m(s) = [C_mech C_cont - (C_mech + C_cont) C_J] s^2 /
    [(K_mech + K_cont) + (C_mech + C_cont) s]``, so that
    full (3.4.6) = reduced (3.4.7) + E_m exactly. (The thesis prints ``C_r``
    instead of ``C_J`` in (3.4.10); that is a typo.)

    Parameters
    ----------
    k_mech, c_mech, k_cont, c_cont
        As in :func:`reduced_joint` (scalars).

    Returns
    -------
    control.TransferFunction
        ``E_m(s)`` in N m/rad.

    Examples
    --------
    >>> e = joint_error_tf(1000.0, 2.0, 1000.0, 4.0)
    >>> round(float(e.num[0][0][0]), 6)  # C_mech C_cont - (C_mech + C_cont) C_J
    -1.0
    """
    km, cm, kc, cc = _scalar_joint_args(k_mech, c_mech, k_cont, c_cont)
    _, c_j = _taylor(km, cm, kc, cc)
    a = cm * cc - (cm + cc) * c_j
    import control

    return control.tf([a, 0.0, 0.0], [cm + cc, km + kc])


# --- frequency-band fit ------------------------------------------------------


@dataclass(frozen=True, eq=False)
class JointFit(Result):
    """Frequency-band least-squares spring-damper fit of a joint (:func:`fit_joint_band`).

    Attributes
    ----------
    stiffness
        Fitted K_J in N m/rad (``nan`` if the solver failed).
    damping
        Fitted C_J in N m s/rad (``nan`` if the solver failed).
    omega
        Frequencies of the fit, rad/s (log-spaced).
    response
        Full joint complex stiffness G(i omega) of (3.4.6), N m/rad.
    relative_error
        ``|K_J + i omega C_J - G| / |G|`` of the fit at each frequency.
    taylor_stiffness, taylor_damping
        The Taylor (3.4.9) values, for comparison.
    taylor_relative_error
        The same relative error for the Taylor values.
    rms_error, taylor_rms_error
        Root mean square of the two relative-error arrays over the band.
    status
        cvxpy status (``"optimal"``, ``"optimal_inaccurate"``) or a
        description of the failure.
    warnings
        What a user should know about the fit.
    """

    stiffness: float
    damping: float
    omega: np.ndarray
    response: np.ndarray
    relative_error: np.ndarray
    taylor_stiffness: float
    taylor_damping: float
    taylor_relative_error: np.ndarray
    rms_error: float
    taylor_rms_error: float
    status: str
    warnings: tuple[str, ...] = ()

    @property
    def success(self) -> bool:
        """True if the solver reported an optimal (possibly inaccurate) solution."""
        return self.status in ("optimal", "optimal_inaccurate")

    @property
    def improvement(self) -> float:
        """Ratio ``taylor_rms_error / rms_error`` (> 1 when the fit is better)."""
        if not self.success or self.rms_error == 0.0:
            return math.nan if not self.success else math.inf
        return self.taylor_rms_error / self.rms_error

    def to_frame(self) -> pd.DataFrame:
        """One row per frequency: the full response and both relative errors.

        Examples
        --------
        >>> fit = fit_joint_band(2e3, 2.0, 1.5e3, 30.0, omega_max=50.0, n=5)
        >>> list(fit.to_frame().columns)  # doctest: +NORMALIZE_WHITESPACE
        ['omega_rad_per_s', 'full_re_N_m_per_rad', 'full_im_N_m_per_rad',
         'fit_rel_error', 'taylor_rel_error']
        """
        return pd.DataFrame(
            {
                "omega_rad_per_s": self.omega,
                "full_re_N_m_per_rad": self.response.real,
                "full_im_N_m_per_rad": self.response.imag,
                "fit_rel_error": self.relative_error,
                "taylor_rel_error": self.taylor_relative_error,
            }
        )


def fit_joint_band(
    k_mech: float,
    c_mech: float,
    k_cont: float,
    c_cont: float,
    omega_max: float,
    n: int = 200,
    omega_min: float | None = None,
    weights: ArrayLike | None = None,
) -> JointFit:
    """Fit ``K_J + C_J s`` to the full joint (3.4.6) over a frequency band.

    An extension of Zeng 2011, which has only the Taylor truncation (3.4.9);
    it is not one of the thesis's impact scenarios. The Taylor truncation is
    exact at ``omega = 0`` and degrades towards the corner frequency
    ``(K_mech + K_cont)/(C_mech + C_cont)``. This solves instead, with cvxpy,

    ``minimise sum_k w_k |K + i omega_k C - G(i omega_k)|^2 / |G(i omega_k)|^2``
    subject to ``K >= 0, C >= 0``

    on ``n`` log-spaced frequencies in ``[omega_min, omega_max]`` (real and
    imaginary parts as separate residuals).

    Parameters
    ----------
    k_mech, c_mech, k_cont, c_cont
        As in :func:`reduced_joint` (scalars).
    omega_max
        Upper end of the band in rad/s (> 0); typically a few times the
        impact's dominant frequency.
    n
        Number of frequencies (>= 2).
    omega_min
        Lower end of the band in rad/s (0 < omega_min < omega_max).
        Defaults to ``omega_max / 1000``.
    weights
        Optional non-negative weights ``w_k`` (length ``n``, not all zero).
        Default: all ones.

    Returns
    -------
    JointFit
        The fitted values, the error arrays of the fit and of the Taylor
        truncation, and the solver ``status``. A solver failure is reported
        in ``status`` (with ``nan`` fitted values), not raised.

    Raises
    ------
    InvalidParameterError
        For invalid joint parameters, band or weights.

    Notes
    -----
    A smaller frequency-domain error does not mean smaller errors on the
    impact metrics, nor errors on the safe side: compare the joints on the
    metrics with :func:`designlab.impact.full_joint.compare_joint_reductions`
    (``docs/impact_joint.md``).

    Examples
    --------
    >>> fit = fit_joint_band(2e3, 2.0, 1.5e3, 30.0, omega_max=50.0)
    >>> fit.status
    'optimal'
    >>> bool(fit.rms_error < fit.taylor_rms_error)
    True
    """
    km, cm, kc, cc = _scalar_joint_args(k_mech, c_mech, k_cont, c_cont)
    omega = _band_frequencies(omega_max, n, omega_min)
    wts = _band_weights(weights, omega.size)
    g = _full_response(km, cm, kc, cc, omega)
    k_t, c_t = _taylor(km, cm, kc, cc)
    k_fit, c_fit, status = _solve_band(omega, g, np.abs(g), wts, k_t, c_t)
    err_t = _relative_error(k_t, c_t, omega, g)
    err_f = _relative_error(k_fit, c_fit, omega, g)
    return JointFit(
        stiffness=k_fit,
        damping=c_fit,
        omega=frozen_array(omega, dtype=None),
        response=frozen_array(g, dtype=None),
        relative_error=frozen_array(err_f, dtype=None),
        taylor_stiffness=float(k_t),
        taylor_damping=float(c_t),
        taylor_relative_error=frozen_array(err_t, dtype=None),
        rms_error=float(np.sqrt(np.mean(err_f**2))),
        taylor_rms_error=float(np.sqrt(np.mean(err_t**2))),
        status=status,
    )


def _band_frequencies(omega_max: float, n: int, omega_min: float | None) -> np.ndarray:
    """``n`` log-spaced frequencies on ``[omega_min, omega_max]`` (default omega_max/1000)."""
    w_max = check_positive("omega_max", omega_max, "rad/s")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
        raise InvalidParameterError("n", n, "must be an integer >= 2")
    if omega_min is None:
        w_min = w_max / 1000.0
    else:
        w_min = check_positive("omega_min", omega_min, "rad/s")
        if w_min >= w_max:
            raise InvalidParameterError(
                "omega_min", omega_min, f"must be < omega_max = {w_max} rad/s", "rad/s"
            )
    return np.logspace(math.log10(w_min), math.log10(w_max), int(n))


def _band_weights(weights: ArrayLike | None, n: int) -> np.ndarray:
    """The least-squares weights: all ones, or validated user weights of length ``n``."""
    if weights is None:
        return np.ones(n)
    wts = np.asarray(weights, dtype=float)
    if wts.shape != (n,):
        raise InvalidParameterError(
            "weights", f"array of shape {wts.shape}", f"must have shape ({n},)"
        )
    if not np.all(np.isfinite(wts)) or np.any(wts < 0.0) or not np.any(wts > 0.0):
        raise InvalidParameterError(
            "weights", wts.tolist(), "must be finite, >= 0 and not all zero"
        )
    return wts


def _relative_error(k: float, c: float, omega: np.ndarray, g: np.ndarray) -> np.ndarray:
    """``|K + i omega C - G| / |G|`` (NaN where the spring-damper is unknown)."""
    if not math.isfinite(k):
        return np.full_like(omega, np.nan)
    return np.abs(k + 1j * omega * c - g) / np.abs(g)


def _solve_band(
    omega: np.ndarray,
    g: np.ndarray,
    mag: np.ndarray,
    wts: np.ndarray,
    k_t: float,
    c_t: float,
) -> tuple[float, float, str]:
    """Solve the scaled least-squares problem; never raises on solver failure."""
    import cvxpy as cp

    # Scale the unknowns so that both are O(1) at the Taylor solution.
    k_scale = k_t
    c_scale = max(c_t, k_t / float(omega[-1]))
    x = cp.Variable(nonneg=True)
    y = cp.Variable(nonneg=True)
    sw = np.sqrt(wts) / mag
    res_re = cp.multiply(sw, k_scale * x - g.real)
    res_im = cp.multiply(sw, c_scale * omega * y - g.imag)
    # Normalise the objective by the number of points to keep it O(1).
    objective = cp.Minimize((cp.sum_squares(res_re) + cp.sum_squares(res_im)) / omega.size)
    problem = cp.Problem(objective)
    try:
        problem.solve()
    except (cp.error.SolverError, ValueError, ArithmeticError) as exc:
        return math.nan, math.nan, f"solver_error: {exc}"
    status = str(problem.status)
    if status not in ("optimal", "optimal_inaccurate") or x.value is None or y.value is None:
        return math.nan, math.nan, status
    k_fit = k_scale * max(float(x.value), 0.0)
    c_fit = c_scale * max(float(y.value), 0.0)
    return k_fit, c_fit, status


# --- PD+FF gains of the direct-drive arm (App. A.2.3) -------------------------


def pd_gains_for(
    stiffness: float,
    damping: float,
    lever_arm: float,
    torque_constant: float,
    viscous_friction: float = 0.0,
) -> tuple[float, float]:
    """PD gains giving an effective stiffness and damping at the impact point.

    Inverts (A.2.20) with (3.4.17) for a direct-drive joint (``K_mech >>
    K_cont``, so ``K_J = K_t K_amp K_p`` and ``C_J = K_t K_amp K_d + B``):

    ``K_p = K_r l^2 / (K_t K_amp)``,  ``K_d = (C_r l^2 - B) / (K_t K_amp)``.

    (A.2.21) is printed as ``(C_r - B_dd) l_1^2 / (K_t K_amp)``, which
    subtracts a joint-level damping (N m s/rad) from an effective one
    (N s/m); the form above is the dimensionally consistent one. For the
    thesis numbers the two differ by 0.5 % and both round to 5.4 V s/rad.

    Parameters
    ----------
    stiffness
        Effective stiffness K_r at the impact point in N/m (>= 0).
    damping
        Effective damping C_r at the impact point in N s/m (>= 0); must be at
        least ``viscous_friction / lever_arm**2`` (a non-negative D gain).
    lever_arm
        l_1, distance from the joint axis to the impact point, in m (> 0).
    torque_constant
        Motor torque constant times amplifier gain, K_t K_amp, in N m/V (> 0).
    viscous_friction
        Joint viscous friction B in N m s/rad (>= 0), which already adds to
        the joint damping.

    Returns
    -------
    tuple of float
        ``(K_p, K_d)`` in V/rad and V s/rad.

    Examples
    --------
    Sec. 4.3.1 / App. A.2.3 (Table 3.1 Manipulator 1):

    >>> k_p, k_d = pd_gains_for(20e3, 250.0, 0.078, 0.2807, viscous_friction=0.0079)
    >>> round(k_p, 1), round(k_d, 1)
    (433.5, 5.4)
    """
    k_r = check_nonnegative("stiffness", stiffness, "N/m")
    c_r = check_nonnegative("damping", damping, "N s/m")
    arm = check_positive("lever_arm", lever_arm, "m")
    kt = check_positive("torque_constant", torque_constant, "N m/V")
    b = check_nonnegative("viscous_friction", viscous_friction, _C_UNIT)
    c_joint = c_r * arm**2
    if c_joint < b:
        raise InvalidParameterError(
            "damping",
            damping,
            f"must be >= viscous_friction / lever_arm^2 = {b / arm**2:.6g} N s/m "
            "(the D gain would be negative)",
            "N s/m",
        )
    return k_r * arm**2 / kt, (c_joint - b) / kt


def joint_from_pd_gains(
    k_p: float, k_d: float, torque_constant: float, viscous_friction: float = 0.0
) -> tuple[float, float]:
    """Joint stiffness and damping of a direct-drive PD(+FF) joint, eq. (A.2.20).

    ``K_J = K_t K_amp K_p`` and ``C_J = K_t K_amp K_d + B``. Divide by
    ``l_1**2`` for the effective values at the impact point (3.4.17); note
    that (4.3.3) drops ``B``.

    Parameters
    ----------
    k_p
        Proportional gain in V/rad (>= 0).
    k_d
        Derivative gain in V s/rad (>= 0).
    torque_constant
        K_t K_amp in N m/V (> 0).
    viscous_friction
        Joint viscous friction B in N m s/rad (>= 0).

    Returns
    -------
    tuple of float
        ``(K_J, C_J)`` in N m/rad and N m s/rad.

    Examples
    --------
    >>> k_j, c_j = joint_from_pd_gains(433.5, 5.39, 0.2807, viscous_friction=0.0079)
    >>> round(k_j / 0.078**2), round(c_j / 0.078**2)
    (20001, 250)
    """
    kp = check_nonnegative("k_p", k_p, "V/rad")
    kd = check_nonnegative("k_d", k_d, "V s/rad")
    kt = check_positive("torque_constant", torque_constant, "N m/V")
    b = check_nonnegative("viscous_friction", viscous_friction, _C_UNIT)
    return kt * kp, kt * kd + b
