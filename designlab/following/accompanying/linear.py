"""Linear analysis of the accompanying robot's per-axis loops (python-control).

Away from saturation each axis of the closed loop is a sampled loop: the
PID of eq. (9) (with its derivative filter, see
:mod:`designlab.following.accompanying.model`) drives a velocity command held over
one sensor period (zero-order hold) into a first-order lag whose output
integrates to the position (or heading) measured by the string-pot at the
next sample:

``P(s) = 1 / (s (tau s + 1))``,  ``P_d(z) = ZOH{P}``,
``C(z) = K_p + K_i T_s z/(z-1) + K_d (z-1)/((T_f+T_s) z - T_f)``,
``L(z) = C(z) P_d(z)``.

The error transform of eqs. (1)-(8) is a rotation and does not change the
loop. The median filter's delay ((window - 1)/2 raw samples) is included
as a pure delay rounded to whole control periods (none for the default
window of 1). For each axis this module gives python-control's gain and
phase margins and the peaks Ms = max |S|, Mt = max |T| of the sensitivity
``S = 1/(1+L)`` and complementary sensitivity ``T = L/(1+L)`` over
frequencies up to the Nyquist frequency.

Examples
--------
>>> la = loop_analysis()
>>> row = la.to_frame().set_index("axis").loc["forward"]
>>> bool(row["stable"]), round(float(row["Ms"]), 2)
(True, 1.14)
>>> loop_analysis(n_frequencies=1)
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: n_frequencies = 1 is not allowed: must be an integer ...
"""

from __future__ import annotations

import math
import warnings as warnings_module
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.following.accompanying.parameters import (
    AXES,
    N_FREQUENCIES,
    MecanumPlatform,
    StringPotSensor,
    UserFramePID,
    loop_parts,
)
from designlab.results import Result, Status

__all__ = [
    "LoopAnalysis",
    "LoopStatus",
    "axis_loop",
    "delay_periods",
    "frequency_grid",
    "loop_analysis",
    "pid_basis",
    "plant_response",
    "refined_peak",
]


class LoopStatus(Status):
    """Status of the loop analysis of the three PIDs.

    ``OK``: every closed loop is stable. ``UNSTABLE``: a closed loop has a pole
    on or outside the unit circle.
    """

    OK = "ok"
    UNSTABLE = "unstable"


def frequency_grid(sample_time: float, n: int = 400, w_min: float = 1e-2) -> NDArray[np.float64]:
    """Log-spaced frequencies (rad/s) from ``w_min`` to just below the Nyquist frequency.

    Parameters
    ----------
    sample_time
        Controller sample time T_s (s); the grid ends just below pi / T_s.
    n
        Number of frequencies.
    w_min
        Lowest frequency (rad/s).
    """
    return np.logspace(math.log10(w_min), math.log10(0.999 * math.pi / sample_time), n)


def refined_peak(
    fn: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    omega: NDArray[np.float64],
    candidates: int = 3,
) -> tuple[float, float]:
    """The largest value of ``fn`` over [omega[0], omega[-1]], refined between grid points.

    The ``candidates`` largest local maxima of ``fn`` on the grid are each
    refined by a bounded scalar search (scipy) between their neighbouring grid
    frequencies, so the peak does not depend on the grid (a peak between two
    grid points is found, not missed).

    Parameters
    ----------
    fn
        Vectorised function of the frequency (rad/s), e.g. ``|S(e^{i w T_s})|``.
    omega
        Increasing frequency grid (rad/s).
    candidates
        How many grid maxima to refine.

    Returns
    -------
    (peak value, frequency in rad/s)

    Examples
    --------
    >>> w = np.linspace(0.0, 10.0, 11)
    >>> v, at = refined_peak(lambda x: 1.0 / (1.0 + (x - 3.3) ** 2), w)
    >>> round(v, 9), round(at, 4)
    (1.0, 3.3)
    """
    from scipy.optimize import minimize_scalar

    vals = fn(omega)
    n = len(omega)
    is_max = np.ones(n, bool)
    is_max[1:] &= vals[1:] >= vals[:-1]
    is_max[:-1] &= vals[:-1] >= vals[1:]
    idx = np.flatnonzero(is_max)
    idx = idx[np.argsort(vals[idx])[::-1][:candidates]]
    best, at = float(vals[idx[0]]), float(omega[idx[0]])
    for i in idx:
        lo, hi = omega[max(i - 1, 0)], omega[min(i + 1, n - 1)]
        if hi <= lo:
            continue
        res = minimize_scalar(
            lambda w: -float(fn(np.array([w]))[0]),
            bounds=(lo, hi),
            method="bounded",
            options={"xatol": 1e-10 * hi},
        )
        if -res.fun > best:
            best, at = float(-res.fun), float(res.x)
    return best, at


def delay_periods(sensor: StringPotSensor) -> int:
    """The median filter's delay, (window - 1)/2 raw samples, in whole control periods.

    Parameters
    ----------
    sensor
        The string-pot sensor.
    """
    return round((sensor.median_window - 1) / 2 / sensor.oversampling)


def plant_response(tau: float, sample_time: float, omega: NDArray, delay: int = 0) -> NDArray:
    """Frequency response of ZOH{1/(s(tau s+1))} (times z^-delay) at ``omega`` (exact formula).

    Parameters
    ----------
    tau
        Lag time constant in s.
    sample_time
        Controller sample time T_s (s).
    omega
        Frequencies (rad/s).
    delay
        Extra delay in control periods.
    """
    a = math.exp(-sample_time / tau)
    z = np.exp(1j * omega * sample_time)
    # ZOH of 1/(s (tau s + 1)): (b1 z + b0) / ((z - 1)(z - a))
    b1 = sample_time - tau * (1 - a)
    b0 = tau * (1 - a) - a * sample_time
    return (b1 * z + b0) / ((z - 1) * (z - a)) * z ** (-delay)


def pid_basis(
    derivative_filter_time: float, sample_time: float, omega: NDArray
) -> NDArray[np.complex128]:
    """Columns [1, T_s z/(z-1), (z-1)/((T_f+T_s) z - T_f)] so that C = basis @ (K_p, K_i, K_d).

    Parameters
    ----------
    derivative_filter_time
        Derivative filter time constant T_f (s).
    sample_time
        Controller sample time T_s (s).
    omega
        Frequencies (rad/s).
    """
    z = np.exp(1j * omega * sample_time)
    tf = derivative_filter_time
    return np.stack(
        [np.ones_like(z), sample_time * z / (z - 1), (z - 1) / ((tf + sample_time) * z - tf)],
        axis=1,
    )


def axis_loop(
    controller: UserFramePID,
    platform: MecanumPlatform,
    sensor: StringPotSensor,
    axis: str,
) -> Any:
    """The discrete loop L(z) of one axis as a python-control ``TransferFunction``.

    Parameters
    ----------
    controller, platform, sensor
        The models.
    axis
        ``"lateral"``, ``"forward"`` or ``"heading"``.
    """
    import control as ct

    kp, ki, kd, tf = controller.gains(axis)
    tau = platform.yaw_tau if axis == "heading" else platform.time_constant
    ts = sensor.period
    plant = ct.c2d(ct.tf([1.0], [tau, 1.0, 0.0]), ts, method="zoh")
    z = ct.tf([1.0, 0.0], [1.0], ts)
    c = kp + ki * ts * z / (z - 1) + kd * (z - 1) / ((tf + ts) * z - tf)
    delay = delay_periods(sensor)
    loop = c * plant
    if delay:
        loop = loop * ct.tf([1.0], [1.0] + [0.0] * delay, ts)
    return ct.minreal(loop, verbose=False)


@dataclass(frozen=True, eq=False)
class LoopAnalysis(Result):
    """Margins and sensitivity peaks of the three loops.

    Attributes
    ----------
    rows
        One dict per axis (see :meth:`to_frame`).
    omega
        Frequency grid in rad/s.
    loops
        Axis -> complex L(e^{i omega T_s}) on ``omega``.
    transfer_functions
        Axis -> python-control ``TransferFunction`` L(z).
    status
        ``"ok"`` or ``"unstable"`` (:class:`LoopStatus`).
    warnings
        What a user should know about the margins (e.g. a loop below the margin targets).
    """

    rows: tuple[dict[str, Any], ...]
    omega: NDArray[np.float64]
    loops: dict[str, NDArray[np.complex128]]
    transfer_functions: dict[str, Any]
    status: LoopStatus = LoopStatus.OK
    warnings: tuple[str, ...] = field(default=())

    def to_frame(self) -> pd.DataFrame:
        """Per axis: gain and phase margins, crossover (rad/s), Ms, Mt, max |C S| (1/s), stable."""
        return pd.DataFrame(list(self.rows))

    def axis(self, name: str) -> dict[str, Any]:
        """The row of one axis."""
        for r in self.rows:
            if r["axis"] == name:
                return r
        raise InvalidParameterError("axis", name, f"one of {AXES}")

    @property
    def ms(self) -> float:
        """Largest sensitivity peak over the axes."""
        return max(r["Ms"] for r in self.rows)

    @property
    def mt(self) -> float:
        """Largest complementary sensitivity peak over the axes."""
        return max(r["Mt"] for r in self.rows)


def _axis_row(
    controller: UserFramePID,
    platform: MecanumPlatform,
    sensor: StringPotSensor,
    axis: str,
    omega: NDArray,
) -> tuple[dict[str, Any], NDArray, Any]:
    """Margins (python-control) and the Ms, Mt and noise-gain peaks of one axis on ``omega``."""
    import control as ct

    loop = axis_loop(controller, platform, sensor, axis)
    kp, ki, kd, tf = controller.gains(axis)
    tau = platform.yaw_tau if axis == "heading" else platform.time_constant
    ts = sensor.period
    # factored response (accurate near z = 1, where the polynomial form cancels)
    gains = np.array([kp, ki, kd])
    delay = delay_periods(sensor)

    def parts(w: NDArray) -> tuple[NDArray, NDArray]:
        c = pid_basis(tf, ts, w) @ gains
        return c, c * plant_response(tau, ts, w, delay)

    c_w, lw = parts(omega)
    s = 1.0 / (1.0 + lw)
    # peaks refined between grid points: they hold on any grid
    ms, _ = refined_peak(lambda w: np.abs(1.0 / (1.0 + parts(w)[1])), omega)
    mt, _ = refined_peak(lambda w: np.abs(parts(w)[1] / (1.0 + parts(w)[1])), omega)
    noise, _ = refined_peak(lambda w: np.abs(parts(w)[0] / (1.0 + parts(w)[1])), omega)
    with warnings_module.catch_warnings():
        # the polynomial method agrees with python-control's frequency-response
        # method here (tests check the crossover against the factored L) and is 10x faster
        warnings_module.simplefilter("ignore", UserWarning)
        gm, pm, _sm, wpc, wgc, _wms = ct.stability_margins(loop, method="poly")
    cl_poles = ct.poles(ct.feedback(loop, 1))
    row = {
        "axis": axis,
        "kp": kp,
        "ki": ki,
        "kd": kd,
        "gain_margin": float(gm),
        "gain_margin_dB": float(20 * np.log10(gm)) if np.isfinite(gm) and gm > 0 else math.inf,
        "phase_margin_deg": float(pm),
        "crossover_rad_s": float(wgc),
        "phase_crossover_rad_s": float(wpc),
        "Ms": max(ms, float(np.max(np.abs(s)))),
        "Mt": max(mt, float(np.max(np.abs(lw * s)))),
        "noise_gain_1_s": max(noise, float(np.max(np.abs(c_w * s)))),
        "stable": bool(np.all(np.abs(cl_poles) < 1.0 - 1e-12)),
    }
    return row, lw, loop


def loop_analysis(
    controller: UserFramePID | None = None,
    platform: MecanumPlatform | None = None,
    sensor: StringPotSensor | None = None,
    *,
    n_frequencies: int = N_FREQUENCIES.default,
) -> LoopAnalysis:
    """Margins, Ms and Mt of the lateral, forward and heading loops.

    Parameters
    ----------
    controller, platform, sensor
        The models (defaults as :func:`designlab.following.accompanying.simulate`).
    n_frequencies
        Points of the log frequency grid for Ms and Mt (:data:`N_FREQUENCIES`:
        at least 50, so that the peaks are on the grid).

    Returns
    -------
    LoopAnalysis
        ``status`` ``"ok"``, or ``"unstable"`` if a closed loop has a pole on
        or outside the unit circle.

    Examples
    --------
    >>> la = loop_analysis(UserFramePID(kp=2.0, ki=0.0, kd=0.0))
    >>> r = la.axis("lateral")
    >>> round(r["phase_margin_deg"], 1) > 45, r["stable"]
    (True, True)
    """
    n_frequencies = N_FREQUENCIES.check(n_frequencies)
    controller, platform, sensor = loop_parts(controller, platform, sensor)
    omega = frequency_grid(sensor.period, n_frequencies, 1e-3)
    rows, loops, tfs, warnings = [], {}, {}, []
    done: dict[tuple[float, ...], tuple[dict[str, Any], NDArray, Any]] = {}
    for axis in AXES:
        tau = platform.yaw_tau if axis == "heading" else platform.time_constant
        key = (*controller.gains(axis), tau)
        if key not in done:
            done[key] = _axis_row(controller, platform, sensor, axis, omega)
        row, lw, loop = done[key]
        rows.append({**row, "axis": axis})
        loops[axis], tfs[axis] = lw, loop
        if not row["stable"]:
            warnings.append(f"the {axis} loop is unstable in closed loop")
    status = LoopStatus.OK if all(r["stable"] for r in rows) else LoopStatus.UNSTABLE
    return LoopAnalysis(tuple(rows), omega, loops, tfs, status, tuple(warnings))
