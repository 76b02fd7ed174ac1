"""Lyapunov conditions and the stability audit of a run (Zeng 2011, Sec. 5.5, App. B).

The field (:mod:`designlab.navigation.field`) obtains V2, dV/dt and Omega by
automatic differentiation. This module keeps

* :func:`omega_closed_form`, the corrected closed-form Omega for one disc
  obstacle (``docs/navigation.md``: the printed (5.5.8) misses M_r on a_o and
  has a wrong last detour term), used as a cross-check of the AD value;
* :func:`omega_printed`, Omega exactly as printed in (5.5.8)/(B.2.7), to show
  what the typos change;
* :class:`StabilityAudit`, built from a simulated run: V at every navigation
  sample, the bound -b |v_L|^2, the realised dV/dt, the share of active-region
  samples where dV/dt <= -b |v_L|^2 holds, and the intervals where the proof's
  assumptions break (force or speed saturation, critical-region braking, a
  switch of a detour side).

Examples
--------
>>> import numpy as np
>>> w = omega_closed_form(E=[-2.5, 0.0], Edot=[0.5, 0.0], d=0.6, d_rate=-0.5, phi=0.1, phi_rate=0.0,
...                       u=[1.0, 0.0], u_psi=[0.0, 1.0], a_o=[0.0, 0.0], r2=0.8, r3=0.4,
...                       k1=3.0, k3=20.0, k5=17.0, m=4.4)
>>> round(w, 3)
259.023
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.results import OK, Result

__all__ = ["StabilityAudit", "audit_run", "omega_closed_form", "omega_printed"]


def _terms(
    E: ArrayLike,
    Edot: ArrayLike,
    d: float,
    d_rate: float,
    phi: float,
    phi_rate: float,
    u: ArrayLike,
    u_psi: ArrayLike,
    r2: float,
    r3: float,
) -> dict[str, Any]:
    E, Edot, u, u_psi = (np.asarray(v, dtype=float) for v in (E, Edot, u, u_psi))
    lam = (r2 - d) ** 2 / (d - r3)
    k_lam = (r2 - d) ** 2 / (d - r3) ** 2
    lam_rate = -k_lam * d_rate
    psi = (r2 - d) ** 2 * phi
    psi_rate = (r2 - d) ** 2 * phi_rate
    k_lam_dot = -2 * d_rate * ((r2 - d) ** 2 / (d - r3) ** 3 + (r2 - d) / (d - r3) ** 2)  # (B.2.8)
    return {
        "E": E,
        "Edot": Edot,
        "u": u,
        "u_psi": u_psi,
        "lam": lam,
        "lam_rate": lam_rate,
        "psi": psi,
        "psi_rate": psi_rate,
        "k_lam_dot": k_lam_dot,
    }


def omega_closed_form(
    *,
    E: ArrayLike,
    Edot: ArrayLike,
    d: float,
    d_rate: float,
    phi: float,
    phi_rate: float,
    u: ArrayLike,
    u_psi: ArrayLike,
    a_o: ArrayLike,
    r2: float,
    r3: float,
    k1: float,
    k3: float,
    k5: float,
    m: float,
) -> float:
    """Corrected closed-form Omega for one disc obstacle in its active region.

    Under the derivation's approximations d'' = (a_mr - a_o)^T u_Lambda and
    Phi'' = (a_o - a_mr)^T u_psi / d (B.2.4-B.2.5), with M_r = m:

    Omega = -K1 E'^T (K3 Lambda u_Lambda + K5 psi u_psi)
            - K3 Lambda'* (K1 E^T u_Lambda - m a_o^T u_Lambda)
            - K5 psi'* (K1 E^T u_psi - m a_o^T u_psi)
            - 2 K3^2 (r2-d) d' Lambda/(d-r3) - 2 K5^2 (r2-d)^3 d' Phi^2
            + m K3 K'_Lambda d'^2 / 2 + m K5 (r2-d)^2 d' Phi'^2 / 2 - m K5 d (r2-d) d' Phi'^2.

    The terms are those of ``docs/navigation.md`` (Stability); all arguments SI.

    Parameters
    ----------
    E, Edot
        Robot-to-goal vector E = P_g - P_r (m) and its rate (m/s).
    d, d_rate
        Obstacle-to-robot distance (m) and its rate (m/s).
    phi, phi_rate
        Detour angle Phi in the chosen direction (rad, in [0, 2 pi)) and its rate (rad/s).
    u, u_psi
        Unit vectors u_Lambda (away from the obstacle) and u_psi (detour direction).
    a_o
        Obstacle acceleration, m/s^2.
    r2, r3
        Active and critical radii, m (r3 < d < r2).
    k1, k3, k5
        Attractive, repulsive and detour gains.
    m
        Robot mass M_r = m_mr, kg.

    Returns
    -------
    float
        Omega in W (J/s), the residual of dV2/dt = -b |v_L|^2 - v_L^T F_L + Omega.

    Examples
    --------
    >>> kw = dict(E=(-2.0, 0.0), Edot=(0.5, 0.0), d=1.5, d_rate=-0.5, phi=0.3, phi_rate=0.1,
    ...           u=(1.0, 0.0), u_psi=(0.0, 1.0), r2=2.1, r3=0.8, k1=3.0, k3=20.0, k5=17.0,
    ...           m=4.4)
    >>> round(omega_closed_form(a_o=(0.0, 0.5), **kw), 3)
    237.228
    """
    t = _terms(E, Edot, d, d_rate, phi, phi_rate, u, u_psi, r2, r3)
    a_o = np.asarray(a_o, dtype=float)
    E, Edot, u, u_psi = t["E"], t["Edot"], t["u"], t["u_psi"]
    w = r2 - d
    return float(
        -k1 * Edot @ (k3 * t["lam"] * u + k5 * t["psi"] * u_psi)
        - k3 * t["lam_rate"] * (k1 * E @ u - m * a_o @ u)
        - k5 * t["psi_rate"] * (k1 * E @ u_psi - m * a_o @ u_psi)
        - 2 * k3**2 * w * d_rate * t["lam"] / (d - r3)
        - 2 * k5**2 * w**3 * d_rate * phi**2
        + 0.5 * m * k3 * t["k_lam_dot"] * d_rate**2
        + 0.5 * m * k5 * w**2 * d_rate * phi_rate**2
        - m * k5 * d * w * d_rate * phi_rate**2
    )


def omega_printed(
    *,
    E: ArrayLike,
    Edot: ArrayLike,
    d: float,
    d_rate: float,
    phi: float,
    phi_rate: float,
    u: ArrayLike,
    u_psi: ArrayLike,
    a_o: ArrayLike,
    r2: float,
    r3: float,
    k1: float,
    k3: float,
    k5: float,
    m: float,
) -> float:
    """Omega as printed in Zeng 2011 (5.5.8), typos included.

    The print has no M_r on a_o and ends with -K5^2 (r2-d) d' Phi^2.

    Parameters
    ----------
    E, Edot
        Robot-to-goal vector E = P_g - P_r (m) and its rate (m/s).
    d, d_rate
        Obstacle-to-robot distance (m) and its rate (m/s).
    phi, phi_rate
        Detour angle Phi in the chosen direction (rad, in [0, 2 pi)) and its rate (rad/s).
    u, u_psi
        Unit vectors u_Lambda (away from the obstacle) and u_psi (detour direction).
    a_o
        Obstacle acceleration, m/s^2.
    r2, r3
        Active and critical radii, m (r3 < d < r2).
    k1, k3, k5
        Attractive, repulsive and detour gains.
    m
        Robot mass M_r = m_mr, kg.

    Returns
    -------
    float
        The printed expression's value (its units are inconsistent when a_o != 0).

    Examples
    --------
    >>> kw = dict(E=(-2.0, 0.0), Edot=(0.5, 0.0), d=1.5, d_rate=-0.5, phi=0.3, phi_rate=0.1,
    ...           u=(1.0, 0.0), u_psi=(0.0, 1.0), r2=2.1, r3=0.8, k1=3.0, k3=20.0, k5=17.0,
    ...           m=4.4)
    >>> round(omega_printed(a_o=(0.0, 0.5), **kw), 3)   # corrected form: 237.228
    238.372
    """
    t = _terms(E, Edot, d, d_rate, phi, phi_rate, u, u_psi, r2, r3)
    a_o = np.asarray(a_o, dtype=float)
    E, Edot, u, u_psi = t["E"], t["Edot"], t["u"], t["u_psi"]
    w = r2 - d
    return float(
        -k1 * Edot @ (k3 * t["lam"] * u + k5 * t["psi"] * u_psi)
        - k3**2 * (2 * d_rate * w / (d - r3)) * t["lam"]
        + 0.5 * m * k3 * t["k_lam_dot"] * d_rate**2
        + k5 * t["psi_rate"] * (a_o @ u_psi - k1 * E @ u_psi)
        - k3 * t["lam_rate"] * (k1 * E @ u - a_o @ u)
        + 0.5 * m * k5 * w**2 * d_rate * phi_rate**2
        - m * k5 * w * d * d_rate * phi_rate**2
        - k5**2 * w * d_rate * phi**2
    )


@dataclass(frozen=True)
class StabilityAudit(Result):
    """Lyapunov audit of one run, at every navigation sample.

    Attributes
    ----------
    t
        Sample times (s).
    V
        Lyapunov function V1/V2 (B.1.4, B.2.2) at each sample.
    bound
        -b |v_L|^2, the decrease the proof guarantees (5.5.12).
    vdot
        dV/dt with the acceleration actually applied at the sample (after the
        robot's limits, or the braking of a critical region).
    vdot_hold
        (V(t_{k+1}) - V(t_k)) / T_s, the realised change over the held period.
    active
        1 where the robot is in some active region (C2) and no critical region.
    satisfied
        ``vdot <= bound`` (within 1e-9 relative), evaluated where ``active``.
    share_satisfied
        Fraction of the active samples where the condition holds (nan if none).
    share_satisfied_hold
        The same for ``vdot_hold``.
    intervals
        ``(reason, t_start, t_end)`` where an assumption of the proof breaks:
        ``"force saturation"`` (|F| > m a_mr), ``"speed saturation"``,
        ``"critical region"`` (braking), ``"detour switch"`` (u_psi changed side).
    status
        Status of the audit (``"ok"``; see :class:`designlab.results.Result`).
    warnings
        What a user should know about the audit.
    """

    t: NDArray[np.float64] = field(repr=False)
    V: NDArray[np.float64] = field(repr=False)
    bound: NDArray[np.float64] = field(repr=False)
    vdot: NDArray[np.float64] = field(repr=False)
    vdot_hold: NDArray[np.float64] = field(repr=False)
    active: NDArray[np.bool_] = field(repr=False)
    satisfied: NDArray[np.bool_] = field(repr=False)
    share_satisfied: float
    share_satisfied_hold: float
    intervals: tuple[tuple[str, float, float], ...]
    status: str = OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """One row per sample: ``t_s``, ``V``, ``bound``, ``vdot``, ``vdot_hold``, ``active``,
        ``satisfied``."""
        return pd.DataFrame(
            {
                "t_s": self.t,
                "V": self.V,
                "bound": self.bound,
                "vdot": self.vdot,
                "vdot_hold": self.vdot_hold,
                "active": self.active,
                "satisfied": self.satisfied,
            }
        )

    def intervals_frame(self) -> pd.DataFrame:
        """The assumption breaks as a table: ``reason``, ``t_start_s``, ``t_end_s``."""
        return pd.DataFrame(list(self.intervals), columns=["reason", "t_start_s", "t_end_s"])


def _intervals(
    flag: NDArray[np.bool_], t: NDArray[np.float64], period: float, reason: str
) -> list[tuple[str, float, float]]:
    out = []
    f = np.concatenate([[False], flag, [False]]).astype(int)
    starts = np.flatnonzero(np.diff(f) == 1)
    ends = np.flatnonzero(np.diff(f) == -1)
    for s, e in zip(starts, ends, strict=True):
        # rounded to the nanosecond: the sample grid, without float noise (1.1400000000000001)
        out.append((reason, round(float(t[s]), 9), round(float(t[e - 1] + period), 9)))
    return out


def _assumption_breaks(
    record: dict[str, Any],
    act: NDArray[np.bool_],
    critical: NDArray[np.bool_],
    t: NDArray[np.float64],
    period: float,
    limits: tuple[float, float, float],
    holonomic: bool,
) -> list[tuple[str, float, float]]:
    """The intervals where the proof's assumptions break (saturation, braking, a switch)."""
    mass, max_accel, max_speed = limits
    x0, F = record["x_sample"], record["F"]
    active_any = act.any(axis=1) if act.size else np.zeros(t.size, bool)
    speed = np.hypot(x0[:, 2], x0[:, 3]) if holonomic else np.abs(x0[:, 3])
    force_sat = np.hypot(F[:, 0], F[:, 1]) > mass * max_accel * (1 + 1e-9)
    speed_sat = speed >= max_speed * (1 - 1e-6)
    sig = record["sigma"]
    switch = np.zeros(t.size, bool)
    if sig.size:
        both = act[1:] & act[:-1]
        switch[1:] = np.any(both & (sig[1:] != sig[:-1]), axis=1)
    intervals: list[tuple[str, float, float]] = []
    for flag, reason in (
        (force_sat & active_any, "force saturation"),
        (speed_sat & active_any, "speed saturation"),
        (critical, "critical region"),
        (switch, "detour switch"),
    ):
        intervals.extend(_intervals(flag, t, period, reason))
    intervals.sort(key=lambda r: (r[1], r[0]))
    return intervals


def audit_run(
    record: dict[str, Any],
    *,
    b: float,
    mass: float,
    max_accel: float,
    max_speed: float,
    period: float,
    holonomic: bool,
) -> StabilityAudit:
    """Build the :class:`StabilityAudit` of a recorded run (internal to :func:`simulate`).

    Parameters
    ----------
    record
        The recorded run (time histories of the engine).
    b
        Gain b of the stabilising force.
    mass
        Robot mass in kg.
    max_accel
        Robot acceleration limit in m/s^2.
    max_speed
        Robot speed limit in m/s.
    period
        Sample time T_s in s.
    holonomic
        Whether the robot is holonomic.
    """
    t = record["t_sample"]
    V = record["V"][:, 0]
    vL2 = record["vL2"][:, 0]
    bound = -b * vL2
    act = record["active"] > 0.5
    active_any = act.any(axis=1) if act.size else np.zeros(t.size, bool)
    critical = record["critical"][:, 0] > 0.5
    active = active_any & ~critical
    F = record["F"]
    g = record["g"]
    f_unforced = F - record["FL"] * record["stab"]
    x0 = record["x_sample"]
    X = record["X"]  # column 0 is the initial state, then one column per dynamics step
    n_sub = (X.shape[1] - 1) // max(t.size, 1)
    dt = period / n_sub
    if holonomic:
        # realised acceleration at the sample instant: the first dynamics step of each hold
        v_first = X[2:4, 1 + np.arange(t.size) * n_sub]
        a_applied = ((v_first - x0[:, 2:4].T) / dt).T
    else:
        a_applied = np.clip(
            F / mass, -max_accel, max_accel
        )  # reference robot; tracking is outside the proof
    vdot = record["Vdot0"][:, 0] + np.einsum("ij,ij->i", g, a_applied - f_unforced / mass)
    vdot_hold = np.full(t.size, np.nan)
    vdot_hold[:-1] = np.diff(V) / period
    same_regions = np.zeros(t.size, bool)
    if act.size:
        same_regions[:-1] = np.all(act[1:] == act[:-1], axis=1)
    vdot_hold[~same_regions] = np.nan
    tol = 1e-9 * np.maximum(1.0, np.abs(bound))
    satisfied = active & (vdot <= bound + tol)
    n_act = int(active.sum())
    share = float(satisfied.sum() / n_act) if n_act else float("nan")
    hold_ok = active & np.isfinite(vdot_hold)
    share_hold = (
        float((vdot_hold[hold_ok] <= bound[hold_ok] + tol[hold_ok]).mean())
        if hold_ok.any()
        else float("nan")
    )
    limits = (mass, max_accel, max_speed)
    intervals = _assumption_breaks(record, act, critical, t, period, limits, holonomic)
    warnings: list[str] = []
    if not holonomic:
        warnings.append(
            "nonholonomic robot: the tracking layer is outside the Lyapunov proof "
            "(Zeng 2011, Sec. 5.5)"
        )
    if not n_act:
        warnings.append(
            "the robot never entered an active region without a critical one: the condition "
            "(5.4.9) was never in force, its share satisfied is undefined (nan)"
        )
    return StabilityAudit(
        t,
        V,
        bound,
        vdot,
        vdot_hold,
        active,
        satisfied,
        share,
        share_hold,
        tuple(intervals),
        warnings=tuple(warnings),
    )
