"""VFF navigation among humans (Zeng 2011, Ch. 5-7, App. B-E)."""

from __future__ import annotations

from designlab.navigation.criteria import Criteria, criteria
from designlab.navigation.lyapunov import StabilityAudit, omega_closed_form, omega_printed
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
from designlab.navigation.scenarios import (
    ConstantVelocity,
    Disc,
    Rectangle,
    SampledPath,
    Scenario,
    Stationary,
    Walk,
    configuration,
)
from designlab.navigation.simulate import BatchResult, NavigationResult, simulate, simulate_batch
from designlab.navigation.tuning import GainOptimum, RandomWalks, evaluate_gains, optimise_gains
from designlab.navigation.sensitivity import GainSensitivity, gain_sensitivity

__all__ = [
    "GainOptimum",
    "GainSensitivity",
    "RandomWalks",
    "evaluate_gains",
    "gain_sensitivity",
    "optimise_gains",
    "EXPERIMENT_GAINS",
    "OPTIMAL_GAINS",
    "BatchResult",
    "CircularObstacle",
    "ConstantVelocity",
    "Criteria",
    "Disc",
    "GeCuiGains",
    "HolonomicRobot",
    "Human",
    "MasoudGains",
    "NavigationResult",
    "NonholonomicRobot",
    "ObstacleRobot",
    "Rectangle",
    "RectangularObstacle",
    "RegionSizes",
    "SampledPath",
    "Scenario",
    "StabilityAudit",
    "Stationary",
    "VFFGains",
    "Walk",
    "configuration",
    "criteria",
    "omega_closed_form",
    "omega_printed",
    "region_sizes",
    "simulate",
    "simulate_batch",
]
