"""VFF navigation among humans (Zeng 2011, Ch. 5-7, App. B-E)."""

from __future__ import annotations

from designlab.navigation.parameters import (
    EXPERIMENT_GAINS,
    OPTIMAL_GAINS,
    CircularObstacle,
    GeCuiGains,
    HolonomicRobot,
    Human,
    MasoudGains,
    NonholonomicRobot,
    ObstacleRobot,
    RectangularObstacle,
    VFFGains,
)
from designlab.navigation.regions import RegionSizes, region_sizes

__all__ = [
    "EXPERIMENT_GAINS",
    "OPTIMAL_GAINS",
    "CircularObstacle",
    "GeCuiGains",
    "HolonomicRobot",
    "Human",
    "MasoudGains",
    "NonholonomicRobot",
    "ObstacleRobot",
    "RectangularObstacle",
    "RegionSizes",
    "VFFGains",
    "region_sizes",
]
