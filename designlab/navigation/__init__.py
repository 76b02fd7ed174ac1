"""VFF navigation among humans (Zeng 2011, Ch. 5-7, App. B-E)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from designlab._lazy import attach as _attach

if TYPE_CHECKING:  # the public names, imported on first use (designlab._lazy)
    from designlab.navigation.criteria import Criteria, criteria
    from designlab.navigation.crowds import (
        CrowdResult,
        CrowdScenario,
        CrowdStatus,
        PedestrianRun,
        crowd,
        simulate_pedestrians,
    )
    from designlab.navigation.lyapunov import StabilityAudit, omega_closed_form, omega_printed
    from designlab.navigation.merge import merge_critical_regions
    from designlab.navigation.noise import SensorNoise
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
    from designlab.navigation.sensitivity import (
        GainGlobalSensitivity,
        GainSensitivity,
        gain_global_sensitivity,
        gain_sensitivity,
    )
    from designlab.navigation.simulate import (
        BatchResult,
        NavigationResult,
        simulate,
        simulate_batch,
    )
    from designlab.navigation.tuning import GainOptimum, RandomWalks, evaluate_gains, optimise_gains

__all__ = [
    "EXPERIMENT_GAINS",
    "OPTIMAL_GAINS",
    "BatchResult",
    "CircularObstacle",
    "ConstantVelocity",
    "Criteria",
    "CrowdResult",
    "CrowdScenario",
    "CrowdStatus",
    "Disc",
    "GainGlobalSensitivity",
    "GainOptimum",
    "GainSensitivity",
    "GeCuiGains",
    "HolonomicRobot",
    "Human",
    "MasoudGains",
    "NavigationResult",
    "NonholonomicRobot",
    "ObstacleRobot",
    "PedestrianRun",
    "RandomWalks",
    "Rectangle",
    "RectangularObstacle",
    "RegionSizes",
    "SampledPath",
    "Scenario",
    "SensorNoise",
    "StabilityAudit",
    "Stationary",
    "VFFGains",
    "Walk",
    "configuration",
    "criteria",
    "crowd",
    "evaluate_gains",
    "gain_global_sensitivity",
    "gain_sensitivity",
    "merge_critical_regions",
    "omega_closed_form",
    "omega_printed",
    "optimise_gains",
    "region_sizes",
    "simulate",
    "simulate_batch",
    "simulate_pedestrians",
]

_attach(__name__)
