"""Co-design of a robot that moves among people: foam, speed limit and injury probability.

A layer above the domains: it imports the impact (and navigation) packages, and no
domain imports it (an import-linter contract in ``pyproject.toml``). See
``docs/codesign.md``.

The API (stable: names are added, never renamed)::

    cd = dl.codesign
    case = cd.SafetyCase(criteria=[...], head_range=dl.impact.THESIS_HEAD_RANGE,
                         human_speed=1.0, reaction_time=0.0, deceleration=10.0,
                         detection_distance=0.0, head_levels=3)   # every field optional
    speed = cd.speed_limit(robot, foam, case, refine=True)
    # -> cd.SpeedLimit: max_speed (robot, m/s), closing_speed, robot_speed / head_speed
    #    (the Sec. 3.4 split), joint_speed (a LinkImpact), limiting_criterion,
    #    per_criterion, worst_heads, worst_lever_arm, unit_metric, stopping_distance,
    #    status, warnings, to_frame()
    smap = cd.speed_limit_map(robot, K_c=[...], C_c=[...], linear_depth=0.02, case=case,
                              refine=True)
    # -> cd.SpeedLimitMap: stiffness, damping, max_speed[i, j], closing_speed[i, j],
    #    limiting[i, j] (index into criteria), per_criterion, grid_closing_speed (the head
    #    grid's alone; refine=True searches off it), to_frame() (one row per foam)
    risk = cd.injury_probability(robot, foam, closing_speed=<scipy frozen dist or samples>,
                                 heads=<None | HeadPopulation | HeadRange | HeadNeck>,
                                 criterion=dl.impact.HeadAcceleration(10), points=None,
                                 samples=100_000, method="crude" | "importance" | "subset",
                                 confidence=0.95, seed=0, progress=None)
    # -> cd.InjuryRisk: probability, interval, standard_error, samples, method,
    #    failed_samples, contact_fraction, status, warnings, to_frame()
    curve = cd.fragility_curve(robot, foam, speeds=[...], heads=..., criterion=..., samples=...)
    # -> cd.FragilityCurve: P(exceeded | contact at v) per speed, Wilson low/high,
    #    thresholds, speed_at(p), to_frame()
    cd.HeadPopulation(mass=<number or dist>, stiffness=..., damping=...)  # .uniform(), .fixed()
    cd.ClosingSpeeds.of(dist_or_samples)      # P(v_c > v | contact), conditional sampling
    cd.contact_speed(...), cd.max_robot_speed(...), cd.stopping_distance(...)  # braking model
    speeds = cd.navigation_contacts(scenarios, gains)   # or cd.contact_speeds(runs)
    # -> cd.ContactSpeeds: encounters (closest approach or first contact) per run and disc,
    #    an empirical closing-speed distribution (rvs, cdf, sf, ppf), to_frame()
    front = cd.pareto(scenarios, space=cd.DesignSpace(...), objectives=(...), seed=0,
                      crowds=None)  # crowds: for the objective crowd_injury_probability
    # -> cd.ParetoFront: to_frame() (non-dominated designs), designs_frame(),
    #    reference_frame() (the thesis's design and its distance from the front)
    sens = cd.front_sensitivity(scenarios, space=..., objectives=(...), samples=16, seed=0)
    # -> designlab.analysis.sensitivity.SensitivityTable: Sobol S1, ST and their 95 %
    #    half-widths of each objective (and ``infeasible``) per design variable

What the model does not cover: head rotation (the head is a point mass on a linear
neck), the torso and the rest of the body, clamping (a head pinned against a wall),
foam beyond its linear depth, correlated head-neck parameters.

Examples
--------
>>> import designlab as dl
>>> s = dl.codesign.speed_limit(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1)
>>> s.limiting_criterion, round(s.max_speed, 3)
('eps_max <= 20 mm', 0.807)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from designlab._lazy import attach as _attach

if TYPE_CHECKING:  # the public names, imported on first use (designlab._lazy)
    from designlab.codesign.braking import contact_speed, max_robot_speed, stopping_distance
    from designlab.codesign.contacts import (
        ContactSpeeds,
        ContactStatus,
        contact_speeds,
        navigation_contacts,
    )
    from designlab.codesign.crowd_encounters import CrowdEncounters
    from designlab.codesign.fragility import FragilityCurve, fragility_curve
    from designlab.codesign.front import (
        OBJECTIVES,
        THESIS_DESIGN,
        THESIS_DESIGNS,
        Design,
        DesignScore,
        DesignSpace,
        FrontStatus,
        ParetoFront,
        evaluate_design,
        knee_point,
        nondominated,
        nsga2,
        pareto,
        preference_pick,
    )
    from designlab.codesign.limits import FoamLimits, foam_limits
    from designlab.codesign.population import ClosingSpeeds, HeadPopulation
    from designlab.codesign.risk import (
        InjuryRisk,
        RiskStatus,
        exceedance_probability,
        injury_probability,
    )
    from designlab.codesign.robot import (
        BUMPER_BASE,
        THESIS_ROBOT,
        RobotDescription,
        people_names,
        sized_scenario,
    )
    from designlab.codesign.sensitivity import design_sobol, front_sensitivity
    from designlab.codesign.speed import SafetyCase, SpeedLimit, SpeedLimitStatus, speed_limit
    from designlab.codesign.speed_map import SpeedLimitMap, speed_limit_map

__all__ = [
    "BUMPER_BASE",
    "OBJECTIVES",
    "THESIS_DESIGN",
    "THESIS_DESIGNS",
    "THESIS_ROBOT",
    "ClosingSpeeds",
    "ContactSpeeds",
    "ContactStatus",
    "CrowdEncounters",
    "Design",
    "DesignScore",
    "DesignSpace",
    "FoamLimits",
    "FragilityCurve",
    "FrontStatus",
    "HeadPopulation",
    "InjuryRisk",
    "ParetoFront",
    "RiskStatus",
    "RobotDescription",
    "SafetyCase",
    "SpeedLimit",
    "SpeedLimitMap",
    "SpeedLimitStatus",
    "contact_speed",
    "contact_speeds",
    "design_sobol",
    "evaluate_design",
    "exceedance_probability",
    "foam_limits",
    "fragility_curve",
    "front_sensitivity",
    "injury_probability",
    "knee_point",
    "max_robot_speed",
    "navigation_contacts",
    "nondominated",
    "nsga2",
    "pareto",
    "people_names",
    "preference_pick",
    "sized_scenario",
    "speed_limit",
    "speed_limit_map",
    "stopping_distance",
]

_attach(__name__)
