"""ISO/TS 15066 beside the Zeng model, and the exposure of a design (issue 36.3, 36.4).

:func:`iso_comparison` lists, per body region a contact of the robot's touching part
can meet (:func:`~designlab.codesign.injury.region_shares`), the share of contacts it
takes, the ISO/TS 15066 permissible relative speed of a transient contact (Annex A.3,
v = F_T / sqrt(mu k), :func:`~designlab.codesign.injury.iso_permissible_speed`) and the
robot speed it allows against a walker, beside the Zeng model's speed limit for the same
foam and robot (:func:`~designlab.codesign.speed_limit`, 10 g and the foam's linear
depth over the head-neck range; a head model, so given for the head regions only), and
which binds.

:func:`exposure` turns navigation runs into contacts per hour of operation (people only:
a still disc is no person), with the one-sided 95 % Poisson upper bound (3 / T hours
when no run touched anybody), and times P(harm | contact) gives the risk per hour.

Examples
--------
>>> import designlab as dl
>>> t = iso_comparison(dl.codesign.THESIS_ROBOT, dl.impact.FOAM_1)
>>> t.loc["skull_forehead", "binding"], float(t.loc["skull_forehead", "iso_robot_speed_m_per_s"])
('ISO/TS 15066', 0.0)
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import stats

from designlab.codesign.injury import HEAD_REGIONS, body_regions, iso_permissible_speed
from designlab.codesign.injury import region_shares as _shares
from designlab.codesign.robot import RobotDescription, people_names
from designlab.codesign.speed import speed_limit
from designlab.errors import InvalidParameterError
from designlab.impact import Foam
from designlab.impact.parameters import HUMAN_SPEED
from designlab.navigation import NavigationResult

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
    zeng = speed_limit(robot.contact, foam, human_speed=v_h).max_speed
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
    """Contacts with people per hour of operation, from navigation runs.

    Attributes
    ----------
    contacts
        Contacts with people in the runs (one per person a run touched; a still disc is no
        person).
    hours, km
        Operation simulated (s of the runs / 3600; path length / 1000).
    per_hour, per_hour_upper
        Contacts per hour and the one-sided 95 % Poisson upper bound.
    per_km_upper
        The upper bound per km.
    """

    contacts: int
    hours: float
    km: float
    per_hour: float
    per_hour_upper: float
    per_km_upper: float


def exposure(runs: Iterable[NavigationResult]) -> Exposure:
    """Contacts with people per hour and per km of the runs (95 % Poisson upper bound).

    Parameters
    ----------
    runs
        Navigation results (a run touching a person counts one contact).

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
    items = list(runs)
    if not items or not all(isinstance(r, NavigationResult) for r in items):
        raise InvalidParameterError("runs", items, "must be one or more NavigationResult")
    n = 0
    seconds = 0.0
    metres = 0.0
    for r in items:
        people = set(people_names(r.scenario))
        n += sum(bool(hit) for name, hit in r.collisions.items() if name in people)
        seconds += float(r.t[-1])
        metres += float(np.sum(np.linalg.norm(np.diff(r.position, axis=0), axis=1)))
    hours, km = seconds / 3600.0, metres / 1000.0
    upper = stats.chi2.ppf(0.95, 2 * (n + 1)) / 2.0  # one-sided 95 % Poisson bound
    return Exposure(n, hours, km, n / hours, float(upper / hours), float(upper / km))
