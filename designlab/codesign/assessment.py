"""ISO/TS 15066 beside the Zeng model, and the exposure of a design (issue 36.3, 36.4).

:func:`iso_comparison` lists, per body region a contact of the robot's touching part
can meet (:func:`~designlab.codesign.injury.region_shares`), the share of contacts it
takes, the ISO/TS 15066 permissible relative speed of a transient contact (Annex A.3,
v = F_T / sqrt(mu k), :func:`~designlab.codesign.injury.iso_permissible_speed`) and the
robot speed it allows against a walker, beside the Zeng model's speed limit for the same
foam and robot (:func:`~designlab.codesign.speed_limit`, 10 g and the foam's linear
depth over the head-neck range; a head model, so given for the head regions only), and
which binds.

:func:`exposure` turns navigation runs, crowds included, into contacts per hour and per
km of operation (people only: a scenario's still disc is no person, a crowd's pedestrians
all are), with the one-sided 95 % Poisson upper bound (3 / T hours when no run touched
anybody), takes each contact's closing speed after braking (the speed limit's braking
model, :mod:`designlab.codesign.braking`), and times P(harm | closing speed) gives the
harms per hour.

Examples
--------
>>> import designlab as dl
>>> t = iso_comparison(dl.codesign.THESIS_ROBOT, dl.impact.FOAM_1)
>>> t.loc["skull_forehead", "binding"], float(t.loc["skull_forehead", "iso_robot_speed_m_per_s"])
('ISO/TS 15066', 0.0)
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import stats

from designlab.codesign.braking import contact_speed
from designlab.codesign.contacts import ContactSpeeds, contact_speeds
from designlab.codesign.injury import HEAD_REGIONS, body_regions, iso_permissible_speed
from designlab.codesign.injury import region_shares as _shares
from designlab.codesign.parameters import (
    BRAKING_SPEED,
    DECELERATION,
    DETECTION_DISTANCE,
    REACTION_TIME,
)
from designlab.codesign.robot import RobotDescription, people_names
from designlab.codesign.speed import Braking, SafetyCase, speed_limit
from designlab.errors import InvalidParameterError
from designlab.impact import Foam
from designlab.impact.parameters import HUMAN_SPEED, IMPACT_VELOCITY
from designlab.navigation import CrowdResult, NavigationResult

__all__ = ["Exposure", "exposure", "iso_comparison"]


def iso_comparison(robot: RobotDescription, foam: Foam, human_speed: float = 1.0) -> pd.DataFrame:
    """ISO/TS 15066 permissible speeds per body region beside the Zeng speed limit.

    Parameters
    ----------
    robot
        The robot (its touching part's effective mass and height band).
    foam
        The foam of the touching part (the Zeng model's speed limit).
    human_speed
        The walker's speed toward the robot, m/s.

    Returns
    -------
    pandas.DataFrame
        One row per region (index): ``share`` of contacts, ``m_H_kg``, ``k_N_per_m``,
        ``F_T_N``, ``mu_kg``, ``iso_closing_speed_m_per_s``, ``iso_robot_speed_m_per_s``,
        ``zeng_robot_speed_m_per_s`` (head regions), ``binding``.
    """
    if not isinstance(robot, RobotDescription):
        raise InvalidParameterError("robot", robot, "must be a RobotDescription")
    v_h = HUMAN_SPEED.check(human_speed, "human_speed")
    m_r = robot.contact.mass
    zeng = speed_limit(robot.contact, foam, SafetyCase(human_speed=v_h)).max_speed
    shares = _shares(robot.contact_low, robot.contact_high)
    rows = []
    for name, r in body_regions().items():
        v = iso_permissible_speed(name, m_r)
        iso_robot = max(v - v_h, 0.0)
        z = zeng if name in HEAD_REGIONS else math.nan
        bind = "ISO/TS 15066" if math.isnan(z) or iso_robot <= z else "Zeng 2011 (10 g, lambda)"
        share = float(shares.get(name, 0.0))
        rows.append({"region": name, "share": share, "m_H_kg": r.effective_mass,
                     "k_N_per_m": r.spring_constant, "F_T_N": r.transient_force,
                     "mu_kg": 1.0 / (1.0 / r.effective_mass + 1.0 / m_r),
                     "iso_closing_speed_m_per_s": v, "iso_robot_speed_m_per_s": iso_robot,
                     "zeng_robot_speed_m_per_s": z, "binding": bind})  # fmt: skip
    return pd.DataFrame(rows).set_index("region")


@dataclass(frozen=True)
class Exposure:
    """Contacts with people per hour and per km of operation, and the harm they carry.

    Attributes
    ----------
    contacts
        Contacts with people in the runs (one per person a run touched: a scenario's moving
        discs and a crowd's pedestrians; a still disc is no person).
    hours, km
        Operation simulated (s of the runs / 3600; path length / 1000).
    per_hour, per_hour_upper
        Contacts per hour and the one-sided 95 % Poisson upper bound.
    per_km, per_km_upper
        The same per km.
    runs
        The runs counted (scenario and crowd runs).
    per_hour_lower, per_km_lower
        The one-sided 95 % Poisson lower bounds per hour and per km (0 without a contact).
    closing_speeds
        The closing speed of each contact after braking (m/s).
    crowd_hours
        The share of :attr:`hours` spent in crowd runs (h).
    risk_per_hour, risk_per_hour_upper
        Expected harms per hour (the sum of P(harm | closing speed) over the contacts, per
        hour), and the Poisson upper bound on contacts per hour times the largest harm of a
        contact (the contacts' own, or at ``worst_speed``); NaN without ``harm``.
    """

    contacts: int
    hours: float
    km: float
    per_hour: float
    per_hour_upper: float
    per_km: float
    per_km_upper: float
    closing_speeds: tuple[float, ...] = ()
    crowd_hours: float = 0.0
    risk_per_hour: float = math.nan
    risk_per_hour_upper: float = math.nan
    runs: int = 0
    per_hour_lower: float = 0.0
    per_km_lower: float = 0.0


def _run_extent(run: NavigationResult | CrowdResult) -> tuple[float, float]:
    """The time (s) and path length (m) of a run."""
    if isinstance(run, CrowdResult):
        t, p = np.asarray(run.times, float), np.asarray(run.robot_positions, float)
    else:
        t, p = np.asarray(run.t, float), np.asarray(run.position, float)
    metres = float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1)))
    return float(t[-1] - t[0]), metres


def _closing_after_braking(c: ContactSpeeds, i: int, brake: Braking, v_h: float) -> float:
    """The closing speed of contact ``i`` once the robot has braked (Zeng 2011, Sec. 3.2).

    Without a detection distance the robot meets the person at the speed of the run, and
    the closing speed is the run's |v_robot - v_person|; with one, the robot's speed at
    contact is :func:`~designlab.codesign.braking.contact_speed` of its speed in the run and
    the closing speed is bounded by the head-on sum of the braked robot's and the person's
    speeds.
    """
    v_r = float(c.robot_speed[i])
    u = contact_speed(min(v_r, BRAKING_SPEED.le), v_h, brake.reaction_time, brake.deceleration,
                      brake.detection_distance)  # fmt: skip
    if u >= v_r:
        return float(c.relative_speed[i])
    return u + float(c.obstacle_speed[i])


def exposure(
    runs: Iterable[NavigationResult | CrowdResult],
    *,
    harm: Callable[[float], float] | None = None,
    worst_speed: float | None = None,
    human_speed: float = 1.0,
    reaction_time: float = REACTION_TIME.default,
    deceleration: float = DECELERATION.default,
    detection_distance: float = DETECTION_DISTANCE.default,
) -> Exposure:
    """Contacts with people per hour and per km of the runs, and the harm per hour.

    Parameters
    ----------
    runs
        Navigation results of scenarios (:class:`~designlab.navigation.NavigationResult`;
        their moving discs are people, a still disc is not) and of crowds
        (:class:`~designlab.navigation.CrowdResult`; every pedestrian is a person). A run
        touching a person counts one contact per person touched.
    harm
        P(harm | closing speed v_c), for a closing speed in m/s (e.g. the AIS3+ risk of a
        head contact at v_c); ``None``: no risk per hour.
    worst_speed
        The largest closing speed a contact of the design can have (m/s, e.g. V_mr + the
        walker); bounds the harm of the unseen contacts of :attr:`Exposure.per_hour_upper`.
    human_speed, reaction_time, deceleration, detection_distance
        The braking model of :func:`~designlab.codesign.speed_limit` that sets the closing
        speed at contact (no detection distance: the run's own closing speed).

    Returns
    -------
    Exposure

    Examples
    --------
    >>> import designlab as dl
    >>> e = exposure([dl.navigation.simulate(dl.navigation.configuration(2),
    ...                                      dl.navigation.EXPERIMENT_GAINS)])
    >>> e.contacts, round(e.per_hour_upper * e.hours, 4)   # -ln(0.05) = 2.9957
    (0, 2.9957)
    """
    items = list(runs) if isinstance(runs, Iterable) and not isinstance(runs, str) else [runs]
    if not items or not all(isinstance(r, NavigationResult | CrowdResult) for r in items):
        raise InvalidParameterError(
            "runs", runs, "must be one or more NavigationResult or CrowdResult"
        )
    if harm is not None and not callable(harm):
        raise InvalidParameterError("harm", harm, "must be a function of the closing speed or None")
    if worst_speed is not None:
        worst_speed = IMPACT_VELOCITY.check(worst_speed, "worst_speed")
    v_h = HUMAN_SPEED.check(human_speed, "human_speed")
    brake = Braking.check(reaction_time, deceleration, detection_distance)
    speeds: list[float] = []
    seconds = metres = crowd_s = 0.0
    for r in items:
        s, m = _run_extent(r)
        seconds, metres = seconds + s, metres + m
        crowd_s += s if isinstance(r, CrowdResult) else 0.0
        people = None if isinstance(r, CrowdResult) else people_names(r.scenario)
        if people == ():
            continue
        c = contact_speeds(r, obstacles=people)
        speeds += [_closing_after_braking(c, i, brake, v_h) for i in np.flatnonzero(c.contact)]
    return dataclasses.replace(_exposure(speeds, seconds, metres, crowd_s, harm, worst_speed),
                               runs=len(items))  # fmt: skip


def _exposure(speeds: list[float], seconds: float, metres: float, crowd_s: float,
              harm: Callable[[float], float] | None, worst: float | None) -> Exposure:  # fmt: skip
    """The :class:`Exposure` of contacts at ``speeds`` in ``seconds`` s and ``metres`` m."""
    if seconds <= 0 or metres <= 0:
        raise InvalidParameterError("runs", seconds, "must cover some time and distance")
    n = len(speeds)
    hours, km = seconds / 3600.0, metres / 1000.0
    upper = stats.chi2.ppf(0.95, 2 * (n + 1)) / 2.0  # one-sided 95 % Poisson bounds
    lower = stats.chi2.ppf(0.05, 2 * n) / 2.0 if n > 0 else 0.0
    risk = risk_upper = math.nan
    if harm is not None:
        hs = [float(harm(v)) for v in speeds]
        bound = max([*hs, *([float(harm(worst))] if worst is not None else [])], default=0.0)
        risk, risk_upper = sum(hs) / hours, float(upper / hours) * bound
    return Exposure(
        contacts=n, hours=hours, km=km, per_hour=n / hours, per_hour_upper=float(upper / hours),
        per_km=n / km, per_km_upper=float(upper / km), closing_speeds=tuple(speeds),
        crowd_hours=crowd_s / 3600.0, risk_per_hour=risk, risk_per_hour_upper=risk_upper,
        per_hour_lower=float(lower / hours), per_km_lower=float(lower / km),
    )  # fmt: skip
