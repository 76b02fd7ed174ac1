"""The general response path: first-lobe metrics of a non-linear contact by an adaptive integrator.

The exact kernels (:mod:`designlab.impact.metrics`) serve linear contacts only: they
evaluate the closed-form modal solution. A contact whose force is a non-linear function of
the compression eps and its rate (:mod:`designlab.impact.contact.hunt_crossley`) is
integrated instead, with the same equations of motion (Zeng 2011, (3.5.2)-(3.5.3); the
relative coordinates of docs/impact.md) and its force law ``f_c(eps, eps_dot)`` in place
of (3.5.1)::

    M_r delta_r_dd = -f_c - C_r delta_r_dot - K_r delta_r
    M_h delta_h_dd =  f_c - C_h delta_h_dot - K_h delta_h,     a_h = delta_h_dd
    eps = delta_r - delta_h + v_c t,   eps_dot = delta_r_dot - delta_h_dot + v_c

by :func:`scipy.integrate.solve_ivp` (DOP853, ``rtol`` :data:`GENERAL_RTOL`, the
absolute tolerance scaled to the impact's own length and speed), with event location for
the metrics of docs/impact.md, "Metrics": the lobe end is the first zero of a_h falling
(a terminal event), and the maxima of a_h, eps and f_c are the zeros, falling, of their
time derivatives (a_h_dot, eps_dot, f_c_dot, all written from the state), compared with
the window's ends. The constrained impact (head against a wall) has no lobe; its window
is ``[0, stop_time]``.

The numbers are integrator results with the stated tolerances: the batch's ``status`` is
``"integrated"`` and its warnings say how they were obtained; nothing here is certified as
the linear kernels' maxima are. With a linear force law the path agrees with the exact
kernel to about 1e-10 relative (tests/impact/test_general_path.py checks 1e-8).

Examples
--------
>>> import numpy as np
>>> law = lambda x, xd: (24.25e3 * x + 71.9 * xd, np.full_like(x, 24.25e3), np.full_like(x, 71.9))
>>> lobe = first_lobe(law, (9.6, 250.0, 20e3), (4.4, 0.0, 4e3), 1.25)
>>> round(lobe.peak_head_acceleration / 9.80665, 3), round(lobe.impact_duration * 1e3, 2)
(6.568, 33.22)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.impact.metric_names import ImpactPoint
from designlab.impact.parameters import STOP_TIME
from designlab.params import Param
from designlab.results import Status

__all__ = [
    "GENERAL_RTOL",
    "ForceLaw",
    "GeneralStatus",
    "Histories",
    "first_lobe",
    "histories",
    "integrator_note",
]

#: Relative tolerance of the general response path (scipy ``solve_ivp``, DOP853).
GENERAL_RTOL = Param(
    None, "", "relative tolerance of the adaptive integrator of a non-linear contact",
    gt=1e-14, le=1e-3, typical=(1e-12, 1e-12), default=1e-12, name="rtol",
)  # fmt: skip

#: ``force(eps, eps_dot) -> (f_c, d f_c / d eps, d f_c / d eps_dot)``, arrays of equal shape.
ForceLaw = Callable[[NDArray, NDArray], tuple[NDArray, NDArray, NDArray]]

#: the integrator's method (8th-order Dormand-Prince, 7th-order dense output for the events)
METHOD = "DOP853"
#: absolute tolerance, as a fraction of the impact's length v_c T0 and speed v_c
_ATOL_SCALE = 1e-3
#: the fraction of the crush depth left when a densifying foam counts as crushed (its spring
#: has then stiffened 1e4-fold for n = 1)
CRUSHED = 1e-4
#: lobe-end search horizon, in contact time scales T0 = pi sqrt(mu / K_c)
_HORIZON = 400.0


class GeneralStatus(Status):
    """Status of a batch of metrics from the general response path.

    Attributes
    ----------
    INTEGRATED
        Every design's first lobe closed; the metrics are integrator results with the
        stated tolerances (not certified).
    LOBE_NOT_CLOSED
        Some first lobe did not close within the horizon (those metrics are NaN).
    """

    INTEGRATED = "integrated"
    LOBE_NOT_CLOSED = "lobe_not_closed"


def integrator_note(rtol: float) -> str:
    """The sentence that says how general-path numbers were obtained.

    Parameters
    ----------
    rtol
        The integrator's relative tolerance.

    Returns
    -------
    str
    """
    return (
        f"integrator results (scipy solve_ivp {METHOD}, rtol={rtol:.0e}, atol "
        f"{_ATOL_SCALE:.0e} x rtol of the impact's length and speed, events located on the "
        "dense output): accurate to about the tolerance, not certified"
    )


class _Impact:
    """The equations of one impact: state derivative and outputs (with their rates)."""

    def __init__(self, force: ForceLaw, robot: tuple, head: tuple | None, v: float) -> None:
        self.force, self.v = force, v
        self.m_r, self.c_r, self.k_r = robot
        self.head = head

    def outputs(self, t: NDArray, y: NDArray) -> dict[str, NDArray]:
        """f_c, a_h, eps, eps_dot and the rates of f_c and a_h at states ``y`` (columns)."""
        v = self.v
        if np.ndim(t) == 0:  # one state of the integrator: plain floats
            t, y = float(t), [float(e) for e in y]
        dr, vr = y[0], y[1]
        dh, vh = (y[2], y[3]) if self.head is not None else (0.0 * dr, 0.0 * vr)
        x, xd = dr - dh + v * t, vr - vh + v
        f, f_x, f_xd = self.force(x, xd)
        a_r = (-f - self.c_r * vr - self.k_r * dr) / self.m_r
        if self.head is None:
            a_h = 0.0 * f
            a_h_dot = 0.0 * f
            f_dot = f_x * xd + f_xd * a_r
        else:
            m_h, c_h, k_h = self.head
            a_h = (f - c_h * vh - k_h * dh) / m_h
            f_dot = f_x * xd + f_xd * (a_r - a_h)
            a_h_dot = (f_dot - c_h * a_h - k_h * vh) / m_h
        return {"force": f, "head_acceleration": a_h, "compression": x, "rate": xd,
                "robot_acceleration": a_r, "force_rate": f_dot, "head_jerk": a_h_dot,
                "head_velocity": vh, "robot_deflection": dr}  # fmt: skip

    def rhs(self, t: float, y: NDArray) -> NDArray:
        o = self.outputs(t, y)
        if self.head is None:
            return np.array([y[1], o["robot_acceleration"]])
        return np.array([y[1], o["robot_acceleration"], y[3], o["head_acceleration"]])


def _time_scale(force: ForceLaw, robot: tuple, head: tuple | None, v: float) -> float:
    """T0 = pi sqrt(mu / k0): half a period of the two masses on the foam's initial stiffness
    (or, for a foam without one, on the stiffer of the manipulator and the neck)."""
    m_r = robot[0]
    mu = m_r if head is None else m_r * head[0] / (m_r + head[0])
    k0 = float(force(np.array([0.0]), np.array([0.0]))[1][0])
    if not k0 > 0.0:
        k0 = max(robot[2], 0.0 if head is None else head[2])
    return math.pi * math.sqrt(mu / k0) if k0 > 0.0 else 1.0


def _events(imp: _Impact, constrained: bool, crush_depth: float | None) -> list[Callable]:
    def event(key: str) -> Callable:
        def g(t: float, y: NDArray) -> float:
            return float(imp.outputs(t, y)[key])

        g.direction = -1.0  # type: ignore[attr-defined]
        return g

    evs = [event("rate"), event("force_rate")]
    if not constrained:
        lobe_end, peak = event("head_acceleration"), event("head_jerk")
        lobe_end.terminal = True  # type: ignore[attr-defined]
        evs = [lobe_end, peak, *evs]
    if crush_depth is not None:
        depth = crush_depth * (1.0 - CRUSHED)

        def crushed(t: float, y: NDArray) -> float:
            return depth - float(imp.outputs(t, y)["compression"])

        crushed.terminal = True  # type: ignore[attr-defined]
        crushed.direction = -1.0  # type: ignore[attr-defined]
        evs = [*evs, crushed]
    return evs


def first_lobe(
    force: ForceLaw,
    robot: tuple[float, float, float],
    head: tuple[float, float, float] | None,
    impact_velocity: float,
    *,
    stop_time: float = STOP_TIME.default,
    rtol: float = GENERAL_RTOL.default,
    crush_depth: float | None = None,
) -> ImpactPoint:
    """First-lobe metrics of one impact with a (non-linear) contact force law, integrated.

    Parameters
    ----------
    force
        The contact force law :data:`ForceLaw` (zero compression at contact).
    robot
        ``(M_r, C_r, K_r)`` of the effective manipulator, SI.
    head
        ``(M_h, C_h, K_h)`` of the head-neck, or ``None`` for the constrained impact.
    impact_velocity
        v_c, m/s (<= 0: no impact, every metric 0).
    stop_time
        Window of the constrained impact, s.
    rtol
        Relative tolerance of the integrator (:data:`GENERAL_RTOL`).
    crush_depth
        The compression the law cannot pass (a densifying foam's x_d), m, or ``None``.
        Reaching ``(1 - CRUSHED)`` of it ends the integration: the foam is crushed, the
        status is ``"bottoming"``, the force and a_h are infinite (beyond any limit) and
        eps_max is ``crush_depth``.

    Returns
    -------
    ImpactPoint
    """
    v = float(impact_velocity)
    if v <= 0.0:
        return ImpactPoint(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, "no_impact")
    imp = _Impact(force, robot, head, v)
    constrained = head is None
    horizon = stop_time if constrained else _HORIZON * _time_scale(force, robot, head, v)
    sol = _solve(imp, horizon, rtol, _events(imp, constrained, crush_depth))
    if sol.status == -1:
        return _open_lobe()
    if crush_depth is not None and sol.t_events[-1].size:
        t_c, inf = float(sol.t_events[-1][0]), float("inf")
        return ImpactPoint(inf, crush_depth, inf, float("nan"), t_c, t_c, t_c, "bottoming")
    if constrained:
        t_end = float(stop_time)
        times = {"compression": sol.t_events[0], "force": sol.t_events[1]}
    else:
        if sol.t_events[0].size == 0:
            return _open_lobe()
        t_end = float(sol.t_events[0][0])
        times = {"head_acceleration": sol.t_events[1], "compression": sol.t_events[2],
                 "force": sol.t_events[3]}  # fmt: skip
    return _maxima(imp, sol.sol, times, t_end, constrained)


def _solve(imp: _Impact, t_end: float, rtol: float, events: list | None) -> Any:
    """``solve_ivp`` of one impact from rest (relative coordinates) over ``[0, t_end]``."""
    from scipy.integrate import solve_ivp

    t0 = _time_scale(imp.force, (imp.m_r, imp.c_r, imp.k_r), imp.head, imp.v)
    n = 2 if imp.head is None else 4
    scale = np.tile([imp.v * t0, imp.v], n // 2)
    return solve_ivp(
        imp.rhs, (0.0, t_end), np.zeros(n), method=METHOD, rtol=rtol,
        atol=rtol * _ATOL_SCALE * scale, events=events, dense_output=True,
    )  # fmt: skip


@dataclass(frozen=True, eq=False)
class Histories:
    """The time histories of one integrated impact: ``t -> {output: values}`` (picklable).

    Outputs: ``force``, ``head_acceleration``, ``compression``, ``head_velocity``,
    ``robot_deflection`` (the names of :func:`~designlab.impact.simulate`), at times within
    the integrated span.

    Attributes
    ----------
    impact
        The equations of the impact (force law, manipulator, head, v_c).
    dense
        The integrator's dense output, ``t -> state``.
    end
        The end of the integrated span, s.
    """

    impact: _Impact
    dense: Any
    end: float

    def __call__(self, t: NDArray, derivative: int = 0) -> dict[str, NDArray]:
        t = np.atleast_1d(np.asarray(t, dtype=float))
        out = self.impact.outputs(t, np.atleast_2d(self.dense(t)).reshape(-1, t.size))
        keys = ("force", "head_acceleration", "compression", "head_velocity", "robot_deflection")
        return {k: np.broadcast_to(np.asarray(out[k], dtype=float), t.shape).copy() for k in keys}


def histories(
    force: ForceLaw,
    robot: tuple[float, float, float],
    head: tuple[float, float, float] | None,
    impact_velocity: float,
    t_end: float,
    *,
    rtol: float = GENERAL_RTOL.default,
    crush_depth: float | None = None,
) -> Histories:
    """The time histories of one impact over ``[0, t_end]`` (arguments as :func:`first_lobe`).

    Parameters
    ----------
    force, robot, head, impact_velocity, rtol, crush_depth
        As for :func:`first_lobe` (v_c > 0); the histories end where the foam is crushed.
    t_end
        End of the histories, s.

    Returns
    -------
    Histories
    """
    imp = _Impact(force, robot, head, float(impact_velocity))
    events = _events(imp, True, crush_depth)[2:] if crush_depth is not None else None
    sol = _solve(imp, float(t_end), rtol, events)
    return Histories(imp, sol.sol, float(sol.t[-1]))


def _open_lobe() -> ImpactPoint:
    nan = float("nan")
    return ImpactPoint(nan, nan, nan, nan, nan, nan, nan, "lobe_not_closed")


def _maxima(
    imp: _Impact, dense: Callable, times: dict, t_end: float, constrained: bool
) -> ImpactPoint:
    """The largest value of each output over ``[0+, t_end]``: its falling-rate zeros and ends."""
    out: dict[str, tuple[float, float]] = {"head_acceleration": (0.0, 0.0)}
    for key, ts in times.items():
        cand = np.concatenate([[0.0, t_end], ts[ts < t_end]])
        ys = np.column_stack([np.zeros(dense(0.0).shape)] + [dense(t) for t in cand[1:]])
        vals = imp.outputs(cand, ys)[key]
        j = int(np.argmax(vals))
        out[key] = (float(cand[j]), float(vals[j]))
    status = "ok"
    if not constrained and out["head_acceleration"][0] == 0.0:
        status = "peak_at_contact"
    (ta, a), (tx, x), (tf, f) = (out[k] for k in ("head_acceleration", "compression", "force"))
    return ImpactPoint(a, x, f, t_end, ta, tx, tf, status)
