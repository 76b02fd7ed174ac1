"""One table of the impact model's column names, meanings and units.

Every impact result's ``to_frame()`` and ``summary()``, the sweep evaluators
and the report plots name their columns from here, so that a column means the
same thing everywhere. Column names carry their SI unit (``_m``, ``_N``, ``_s``,
``_g`` for standard gravity).

Examples
--------
>>> METRICS["peak_force_N"].label
'peak contact force f_c,max (N)'
>>> PARAMETERS["K_c"].unit
'N/m'
>>> label("K_c"), label("eps_max_m")
('foam stiffness K_c (N/m)', 'max. foam compression eps_max (m)')
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import NamedTuple

from designlab.units import STANDARD_GRAVITY

__all__ = [
    "ENVELOPE_COLUMNS",
    "LIMITS",
    "METRICS",
    "PARAMETERS",
    "ColumnInfo",
    "ImpactPoint",
    "label",
]


@dataclass(frozen=True)
class ColumnInfo:
    """A column: its symbol, a readable name and its unit.

    Attributes
    ----------
    symbol
        The symbol (e.g. ``"a_h,max"``).
    name
        A readable name.
    unit
        Its SI unit (or ``g``).
    """

    symbol: str
    name: str
    unit: str

    @property
    def label(self) -> str:
        """``"name symbol (unit)"`` for axes and tables."""
        unit = f" ({self.unit})" if self.unit else ""
        return f"{self.name} {self.symbol}{unit}"


#: The model parameters, ordered as :data:`designlab.impact.model.PARAM_NAMES`.
PARAMETERS = MappingProxyType(
    {
        "M_r": ColumnInfo("M_r", "effective robot mass", "kg"),
        "C_r": ColumnInfo("C_r", "effective robot damping", "N s/m"),
        "K_r": ColumnInfo("K_r", "effective robot stiffness", "N/m"),
        "K_c": ColumnInfo("K_c", "foam stiffness", "N/m"),
        "C_c": ColumnInfo("C_c", "foam damping", "N s/m"),
        "M_h": ColumnInfo("M_h", "head mass", "kg"),
        "C_h": ColumnInfo("C_h", "neck damping", "N s/m"),
        "K_h": ColumnInfo("K_h", "neck stiffness", "N/m"),
        "v_c": ColumnInfo("v_c", "impact velocity", "m/s"),
        "lambda": ColumnInfo("lambda", "foam linear depth", "m"),
        "l_1": ColumnInfo("l_1", "lever arm", "m"),
    }
)

#: First-lobe metrics (Zeng 2011, Sec. 3.5-3.9; docs/impact.md, "Metrics").
METRICS = MappingProxyType(
    {
        "v_c_m_per_s": ColumnInfo("v_c", "impact velocity", "m/s"),
        "a_h_max_g": ColumnInfo("a_h,max", "peak head acceleration", "g"),
        "a_h_max_m_per_s2": ColumnInfo("a_h,max", "peak head acceleration", "m/s^2"),
        "eps_max_m": ColumnInfo("eps_max", "max. foam compression", "m"),
        "peak_force_N": ColumnInfo("f_c,max", "peak contact force", "N"),
        "t_imp_s": ColumnInfo("Delta t_imp", "impact period", "s"),
        "t_a_h_max_s": ColumnInfo("t(a_h,max)", "time of peak head acceleration", "s"),
        "t_eps_max_s": ColumnInfo("t(eps_max)", "time of max. compression", "s"),
        "t_peak_force_s": ColumnInfo("t(f_c,max)", "time of peak force", "s"),
        "hic15": ColumnInfo("HIC15", "head injury criterion, 15 ms", ""),
        "hic36": ColumnInfo("HIC36", "head injury criterion, 36 ms", ""),
        "bottoming": ColumnInfo("eps_max > lambda", "foam bottoms out", ""),
        "status": ColumnInfo("", "status", ""),
    }
)

#: Metrics of a foam envelope evaluated at one foam (the ``foam_envelope`` sweeps).
ENVELOPE_COLUMNS = MappingProxyType(
    {
        "k_c_max_N_per_m": ColumnInfo(
            "K_c,max", "upper (safety) boundary at the foam's damping", "N/m"
        ),
        "k_c_min_N_per_m": ColumnInfo(
            "K_c,min", "lower (thickness) boundary at the foam's damping", "N/m"
        ),
        "margin_decades": ColumnInfo(
            "", "margin of the foam to the nearest boundary", "decades of K_c"
        ),
        "area_log": ColumnInfo("", "feasible area over the damping grid", "decades x N s/m"),
    }
)

#: The thesis's design limits on the metrics (Zeng 2011, Sec. 3.9): 10 g and 20 mm.
LIMITS = MappingProxyType({"a_h_max_g": 10.0, "eps_max_m": 0.02})


def label(column: str) -> str:
    """Readable axis label of a parameter or metric column (the column itself if unknown).

    Parameters
    ----------
    column
        A parameter or metric column name (e.g. ``"K_c_N_per_m"``).
    """
    info = PARAMETERS.get(column) or METRICS.get(column) or ENVELOPE_COLUMNS.get(column)
    return info.label if info is not None else column


class ImpactPoint(NamedTuple):
    """First-lobe metrics of one design (SI units; the fields of
    :class:`~designlab.impact.metrics.ImpactMetrics` as floats): what the one-design fast
    path (:mod:`designlab.impact.single`) and the general path
    (:mod:`designlab.impact.general`) return.

    Attributes
    ----------
    peak_head_acceleration, max_compression, peak_force, impact_duration
        m/s^2, m, N, s (the constrained impact: a_h = 0, the window ``stop_time``).
    time_of_peak_acceleration, time_of_max_compression, time_of_peak_force
        s.
    status
        The design's status (:class:`~designlab.impact.metrics.ImpactStatus` value; the
        general path's also ``"bottoming"``).

    Examples
    --------
    >>> ImpactPoint(9.80665, 0.01, 100.0, 0.05, 0.01, 0.02, 0.02, "ok").peak_head_acceleration_g
    1.0
    """

    peak_head_acceleration: float
    max_compression: float
    peak_force: float
    impact_duration: float
    time_of_peak_acceleration: float
    time_of_max_compression: float
    time_of_peak_force: float
    status: str

    @property
    def peak_head_acceleration_g(self) -> float:
        """a_h,max in g (standard gravity)."""
        return self.peak_head_acceleration / STANDARD_GRAVITY
