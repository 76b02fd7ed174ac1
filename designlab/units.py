"""Physical constants and unit conversions used across designlab.

Examples
--------
>>> STANDARD_GRAVITY
9.80665
>>> round(to_g(98.0665), 6)
10.0
"""

from __future__ import annotations

from typing import Any

__all__ = ["STANDARD_GRAVITY", "from_g", "to_g"]

#: Standard gravity g_n in m/s^2 (CGPM 1901, ISO 80000-3); every ``*_g`` value uses it.
STANDARD_GRAVITY = 9.80665


def to_g(acceleration: Any) -> Any:
    """Convert an acceleration in m/s^2 to g (standard gravity).

    Parameters
    ----------
    acceleration
        Acceleration in m/s^2 (scalar or array).
    """
    return acceleration / STANDARD_GRAVITY


def from_g(value: Any) -> Any:
    """Convert an acceleration in g (standard gravity) to m/s^2.

    Parameters
    ----------
    value
        Acceleration in g (scalar or array).
    """
    return value * STANDARD_GRAVITY
