"""Performance criteria H_T, H_D, H_E and H (Zeng 2011, Sec. 5.6).

H = k (H_T + H_D + H_E) / 3 with H_T = T*_arrive / T_arrive (5.6.1), H_D the mean
over obstacles of d_s,min / (r2 - rho_r - rho_o) capped at 1 (5.6.3), H_E =
L*_energy / L_energy (5.6.5), k = 0 on collision (5.6.6). The starred values come
from the nominal run: same robot, gains, start and goal, no obstacles.

Examples
--------
>>> c = criteria(arrival_time=8.0, nominal_arrival_time=6.0, energy=2.0, nominal_energy=1.5,
...              surface_clearance={"human": 0.5}, nominal_clearance={"human": 1.5})
>>> round(c.H_T, 3), round(c.H_D, 3), round(c.H_E, 3), round(c.H, 3)
(0.75, 0.333, 0.75, 0.611)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from designlab.errors import InvalidParameterError
from designlab.results import OK, Result

__all__ = ["EQUAL_WEIGHTS", "UNDEFINED", "Criteria", "check_weights", "criteria"]


@dataclass(frozen=True)
class Criteria(Result):
    """The Sec. 5.6 criteria of one run.

    Attributes
    ----------
    H_T, H_D, H_E, H
        Arrival-time, avoidance and energy criteria and their weighted total.
    k
        1, or 0 if any surface distance reached 0 (collision).
    arrival_time, nominal_arrival_time
        T_arrive and T*_arrive (s).
    energy, nominal_energy
        L_energy and L*_energy as the integral of the squared feed-forward wheel
        currents (A^2 s = J per ohm of winding resistance).
    status
        ``"ok"``, or :data:`UNDEFINED` when the run arrived and its nominal run did not
        (H_T, H_E and H are then NaN; the warnings say why).
    warnings
        What a user should know about the scores.
    """

    H_T: float
    H_D: float
    H_E: float
    H: float
    k: int
    arrival_time: float
    nominal_arrival_time: float
    energy: float
    nominal_energy: float
    status: str = OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """One row: the criteria and their inputs (units in the column names)."""
        return pd.DataFrame(
            [
                {
                    "H_T": self.H_T,
                    "H_D": self.H_D,
                    "H_E": self.H_E,
                    "H": self.H,
                    "k": self.k,
                    "T_arrive_s": self.arrival_time,
                    "T_star_s": self.nominal_arrival_time,
                    "L_energy_J_per_ohm": self.energy,
                    "L_star_J_per_ohm": self.nominal_energy,
                }
            ]
        )


#: ``Criteria.status`` when the run arrived but its obstacle-free nominal run did not: T* = inf,
#: so H_T = T*/T (5.6.1) and H_E = L*/L (5.6.5) are undefined and H is NaN.
UNDEFINED = "undefined"

_UNDEFINED_NOTE = (
    "the obstacle-free nominal run never arrived (T* = inf) while the run did (T = {t:.3f} s): "
    "H_T = T*/T and H_E = L*/L are undefined and H is NaN (an unstable sampled attraction loop "
    "or an arrival tolerance the nominal run never meets; docs/navigation.md, Criteria)"
)

#: The equal weights of the thesis's H (5.6.6).
EQUAL_WEIGHTS = (1 / 3, 1 / 3, 1 / 3)


def check_weights(weights: Any) -> tuple[float, float, float]:
    """The criterion weights (w_T, w_D, w_E) checked: three finite numbers >= 0 summing to 1.

    Parameters
    ----------
    weights
        The weights of H_T, H_D and H_E in H (5.6.6).

    Examples
    --------
    >>> check_weights([0.5, 0.25, 0.25])
    (0.5, 0.25, 0.25)
    >>> check_weights([1, 1, 1])
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: weights = [1, 1, 1] is not allowed: ...
    """
    try:
        w = tuple(float(x) for x in weights)
    except (TypeError, ValueError):
        w = ()
    if len(w) != 3 or not all(math.isfinite(x) and x >= 0 for x in w) or abs(sum(w) - 1) > 1e-9:
        raise InvalidParameterError(
            "weights", weights, "must be three finite non-negative numbers summing to 1"
        )
    return (w[0], w[1], w[2])


def _number(name: str, value: Any, unit: str) -> float:
    if (
        isinstance(value, bool | np.bool_)
        or not isinstance(value, int | float | np.number)
        or (isinstance(value, complex | np.complexfloating))
    ):
        raise InvalidParameterError(name, value, "must be a real number", unit)
    return float(value)


def _check_run_figures(
    arrival_time: Any, nominal_arrival_time: Any, energy: Any, nominal_energy: Any
) -> tuple[float, float, float, float]:
    """T_arrive > 0 (inf: never arrived), T*_arrive > 0 (inf: the nominal run never arrived),
    energies finite >= 0."""
    t = _number("arrival_time", arrival_time, "s")
    if not t > 0:  # NaN too
        raise InvalidParameterError("arrival_time", arrival_time, "must be > 0 (inf: never "
                                    "arrived)", "s")  # fmt: skip
    t0 = _number("nominal_arrival_time", nominal_arrival_time, "s")
    if not t0 > 0:  # NaN too
        raise InvalidParameterError(
            "nominal_arrival_time", nominal_arrival_time, "must be > 0 (inf: the obstacle-free "
            "run never arrived)", "s",
        )  # fmt: skip
    out = []
    for name, v in (("energy", energy), ("nominal_energy", nominal_energy)):
        e = _number(name, v, "")
        if not (math.isfinite(e) and e >= 0):
            raise InvalidParameterError(name, v, "must be finite and >= 0")
        out.append(e)
    return t, t0, out[0], out[1]


def _check_clearances(surface: Any, nominal: Any) -> tuple[dict[str, float], dict[str, float]]:
    """d_s,min and d*_s,min per obstacle: the same names, finite, the nominal ones > 0."""
    for name, m in (("surface_clearance", surface), ("nominal_clearance", nominal)):
        if not isinstance(m, Mapping):
            raise InvalidParameterError(name, m, "must map obstacle names to distances (m)")
    if set(surface) != set(nominal):
        raise InvalidParameterError(
            "nominal_clearance", dict(nominal),
            f"must name the same obstacles as surface_clearance = {dict(surface)!r} (obstacles "
            f"{sorted(map(str, surface))} there, {sorted(map(str, nominal))} here)",
        )  # fmt: skip
    s = {k: _number(f"surface_clearance[{k!r}]", v, "m") for k, v in surface.items()}
    n = {k: _number(f"nominal_clearance[{k!r}]", v, "m") for k, v in nominal.items()}
    for k in s:
        if not math.isfinite(s[k]):
            raise InvalidParameterError(f"surface_clearance[{k!r}]", s[k], "must be finite", "m")
        if not (math.isfinite(n[k]) and n[k] > 0):
            raise InvalidParameterError(
                f"nominal_clearance[{k!r}]", n[k], "must be finite and > 0", "m"
            )
    return s, n


def criteria(
    *,
    arrival_time: float,
    nominal_arrival_time: float,
    energy: float,
    nominal_energy: float,
    surface_clearance: Mapping[str, float],
    nominal_clearance: Mapping[str, float],
    weights: tuple[float, float, float] = EQUAL_WEIGHTS,
) -> Criteria:
    """Compute H from a run and its nominal run (Zeng 2011, (5.6.1)-(5.6.6)).

    Parameters
    ----------
    arrival_time, nominal_arrival_time
        T_arrive and T*_arrive in s (``inf`` if never arrived). A run that never arrived has
        H_T = 0; a run that arrived while its nominal run did not has H_T, H_E and H undefined
        (NaN, status :data:`UNDEFINED`, a warning naming the cause).
    energy, nominal_energy
        L_energy and L*_energy (same units).
    surface_clearance
        d_s,min per obstacle (m): surface-to-surface minimum distance.
    nominal_clearance
        d*_s,min per obstacle: r2 - rho_r - rho_o (discs) or r2 - rho_r (rectangles).
    weights
        w1, w2, w3 (non-negative, sum 1).

    Returns
    -------
    Criteria
        H_T, H_D, H_E, H and the collision indicator k.

    Examples
    --------
    >>> c = criteria(arrival_time=6.0, nominal_arrival_time=5.4, energy=2.0,
    ...              nominal_energy=1.0, surface_clearance={"circle": 0.25},
    ...              nominal_clearance={"circle": 0.5})
    >>> round(c.H_T, 3), c.H_D, c.H_E, round(c.H, 3)
    (0.9, 0.5, 0.5, 0.633)
    >>> c = criteria(arrival_time=6.0, nominal_arrival_time=float("inf"), energy=2.0,
    ...              nominal_energy=9.0, surface_clearance={"circle": 0.25},
    ...              nominal_clearance={"circle": 0.5})
    >>> c.status, c.H_T, c.H_D, c.H
    ('undefined', nan, 0.5, nan)
    """
    w = check_weights(weights)
    arrival_time, nominal_arrival_time, energy, nominal_energy = _check_run_figures(
        arrival_time, nominal_arrival_time, energy, nominal_energy
    )
    surface_clearance, nominal_clearance = _check_clearances(surface_clearance, nominal_clearance)
    warnings: list[str] = []
    h_t = 0.0 if not math.isfinite(arrival_time) else nominal_arrival_time / arrival_time
    if not math.isfinite(arrival_time):
        warnings.append("the robot never arrived: H_T = 0")
    if surface_clearance:
        ratios = [
            min(1.0, max(0.0, surface_clearance[n]) / nominal_clearance[n])
            for n in surface_clearance
        ]
        h_d = sum(ratios) / len(ratios)
    else:
        h_d = 1.0
    h_e = nominal_energy / energy if energy > 0 else 1.0
    k = 0 if any(v <= 0.0 for v in surface_clearance.values()) else 1
    if k == 0:
        warnings.append("collision: k = 0, H = 0")
    for name, ratio, what in (("H_T", h_t, "arrived sooner"), ("H_E", h_e, "used less energy")):
        if ratio > 1.0:
            warnings.append(
                f"{name} = {ratio:.3f} > 1: the run {what} than its obstacle-free nominal run, "
                "which (5.6.1)/(5.6.5) do not cap; H can exceed 1 (docs/navigation.md, Criteria)"
            )
    status = OK
    if math.isfinite(arrival_time) and math.isinf(nominal_arrival_time):
        h_t = h_e = math.nan
        status = UNDEFINED
        warnings.append(_UNDEFINED_NOTE.format(t=arrival_time))
    w1, w2, w3 = w
    h = k * (w1 * h_t + w2 * h_d + w3 * h_e)
    return Criteria(
        h_t,
        h_d,
        h_e,
        h,
        k,
        float(arrival_time),
        float(nominal_arrival_time),
        float(energy),
        float(nominal_energy),
        status=status,
        warnings=tuple(warnings),
    )
