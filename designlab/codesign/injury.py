"""Injury risk a safety reviewer recognises: cited curves, ISO/TS 15066 and body regions.

Three cited sources, each kept as a data file in ``designlab/data`` with its citation:

* ``iso_ts_15066_body_regions.csv``: per body region the maximum permissible
  quasi-static force and the transient multiplier (ISO/TS 15066:2016, Annex A,
  Table A.2), the effective spring constant (Table A.2) and the effective mass
  (Table A.3). :func:`iso_permissible_speed` is the standard's energy-transfer model of
  a transient contact (Annex A.3): the body region is a spring k and a mass m_H, the
  robot a mass m_R; the contact force is F = v sqrt(mu k) with mu = (1/m_H + 1/m_R)^-1,
  so the permissible relative speed is v = F_max / sqrt(mu k).
* ``hic_injury_risk_curves.csv``: head-injury risk from HIC: the Prasad-Mertz (1985)
  AIS3+ curve, P = Phi((ln HIC - mu) / sigma) (mu = 7.45231, sigma = 0.73998: the HIC15
  form of Eppinger et al. 1999, Sec. 2), and the NHTSA (1995) logistic AIS2+ and AIS3+
  curves, P = 1 / (1 + exp(a + b / HIC - c HIC)) (:func:`head_injury_risk`). The primary
  documents could not be checked here: the coefficients are taken from secondary sources
  that reproduce them and agree with each other (the robot-safety literature after
  Haddadin et al. 2007-2009 and public injury-risk code; the file's ``source`` column says
  so per curve). They were
  fitted to adult heads in vehicle crashes (HIC in the hundreds to thousands): a gentle
  foam contact's HIC of a few units lies far below their data, and a risk below
  :data:`CURVE_FLOOR` is reported as "below the curve's data", not as a number.
* ``anthropometry_heights.csv`` and ``anthropometry_stature.csv``: landmark heights as
  fractions of stature (Drillis and Contini 1966) and an adult stature population
  (Pheasant and Haslegrave 2006): :func:`region_shares` gives which body region a
  contact at a given height meets (a base's bumper meets shins, knees, thighs and
  hands; a link at 1.4-1.8 m meets chests, necks, faces and heads).

Examples
--------
>>> round(iso_permissible_speed("skull_forehead", 9.6), 4)   # 130 / sqrt(mu 150e3)
0.1932
>>> head_injury_risk(4.7, "prasad_mertz_ais3") < 1e-15
True
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from functools import cache
from importlib.resources import files

import numpy as np
import pandas as pd
from scipy import special, stats

from designlab.errors import InvalidParameterError

__all__ = [
    "CURVE_FLOOR",
    "BodyRegion",
    "HicCurve",
    "StatureGroup",
    "body_regions",
    "head_injury_risk",
    "hic_curves",
    "iso_permissible_speed",
    "region_shares",
    "stature_population",
]

#: Risks below this are outside every curve's data (reported as "below the curve's data").
CURVE_FLOOR = 1e-6

#: Body regions at the head, for which ISO/TS 15066 gives no transient multiplier.
HEAD_REGIONS = ("skull_forehead", "face")


def _rows(name: str) -> list[dict[str, str]]:
    with (files("designlab") / "data" / name).open() as fh:
        return list(csv.DictReader(fh))


@dataclass(frozen=True)
class BodyRegion:
    """One body region of ISO/TS 15066:2016, Annex A.

    Attributes
    ----------
    name
        The region (``"skull_forehead"``, ...).
    quasi_static_force
        Maximum permissible quasi-static force, N (Table A.2).
    transient_factor
        Multiplier of that force for a transient contact (Table A.2; ``nan`` for the head
        regions, where transient contact is to be avoided).
    spring_constant
        Effective spring constant k, N/m (Table A.2, given there in N/mm).
    effective_mass
        Effective mass m_H, kg (Table A.3).
    source
        The citation.
    """

    name: str
    quasi_static_force: float
    transient_factor: float
    spring_constant: float
    effective_mass: float
    source: str

    @property
    def transient_force(self) -> float:
        """The permissible transient force F_T, N (the quasi-static one at the head)."""
        f = self.transient_factor
        return self.quasi_static_force * (1.0 if math.isnan(f) else f)


@cache
def body_regions() -> dict[str, BodyRegion]:
    """The ISO/TS 15066 body regions (``designlab/data/iso_ts_15066_body_regions.csv``).

    Examples
    --------
    >>> r = body_regions()["lower_leg"]
    >>> r.transient_force, r.spring_constant, r.effective_mass
    (260.0, 60000.0, 75.0)
    """
    return {
        r["region"]: BodyRegion(
            r["region"],
            float(r["quasi_static_force_N"]),
            float(r["transient_factor"]) if r["transient_factor"] else math.nan,
            1e3 * float(r["spring_constant_N_per_mm"]),
            float(r["effective_mass_kg"]),
            r["source"],
        )
        for r in _rows("iso_ts_15066_body_regions.csv")
    }


def _region(name: object) -> BodyRegion:
    regions = body_regions()
    if not isinstance(name, str) or name not in regions:
        raise InvalidParameterError("region", name, f"must be one of {tuple(regions)}")
    return regions[name]


def iso_permissible_speed(region: str, robot_mass: float) -> float:
    """ISO/TS 15066 permissible relative speed of a transient contact, m/s.

    v = F_T / sqrt(mu k), mu = (1/m_H + 1/m_R)^-1 (ISO/TS 15066:2016, Annex A.3,
    energy transfer; F_T, k from Table A.2, m_H from Table A.3). For the head regions the
    standard gives no transient multiplier (transient contact is to be avoided): the
    quasi-static force is used.

    Parameters
    ----------
    region
        A body region of :func:`body_regions`.
    robot_mass
        The robot's effective mass m_R at the contact, kg.

    Returns
    -------
    float

    Examples
    --------
    >>> round(iso_permissible_speed("abdomen", 40.0), 4)   # 220 / sqrt(20 x 10e3)
    0.4919
    """
    r = _region(region)
    if not (isinstance(robot_mass, (int, float)) and math.isfinite(robot_mass) and robot_mass > 0):
        raise InvalidParameterError("robot_mass", robot_mass, "must be a positive mass", "kg")
    mu = 1.0 / (1.0 / r.effective_mass + 1.0 / robot_mass)
    return r.transient_force / math.sqrt(mu * r.spring_constant)


@dataclass(frozen=True)
class HicCurve:
    """A head-injury risk curve of HIC (``designlab/data/hic_injury_risk_curves.csv``).

    Attributes
    ----------
    name, severity, form
        Its key, the AIS level (``"AIS3+"``) and ``"lognormal"`` or ``"logistic"``.
    a, b, c, mu, sigma
        Its coefficients (logistic: a, b, c; lognormal: mu, sigma of ln HIC).
    window_ms
        The HIC window of the curve's data (15 or 36 ms).
    source
        The citation.
    """

    name: str
    severity: str
    form: str
    a: float
    b: float
    c: float
    mu: float
    sigma: float
    window_ms: int
    source: str

    def risk(self, hic: float) -> float:
        """P(AIS >= level | HIC) (0 at HIC 0)."""
        if hic <= 0:
            return 0.0
        if self.form == "lognormal":
            return float(special.ndtr((math.log(hic) - self.mu) / self.sigma))
        return float(special.expit(-(self.a + self.b / hic - self.c * hic)))


@cache
def hic_curves() -> dict[str, HicCurve]:
    """The cited HIC risk curves, by name."""

    def num(x: str) -> float:
        return float(x) if x else math.nan

    return {
        r["curve"]: HicCurve(
            r["curve"],
            r["severity"],
            r["form"],
            num(r["a"]),
            num(r["b"]),
            num(r["c"]),
            num(r["mu"]),
            num(r["sigma"]),
            int(r["hic_window_ms"]),
            r["source"],
        )
        for r in _rows("hic_injury_risk_curves.csv")
    }


def head_injury_risk(hic: float, curve: str = "prasad_mertz_ais3") -> float:
    """P(AIS >= level) of a head contact of the given HIC, from a cited curve.

    Parameters
    ----------
    hic
        The contact's HIC (>= 0).
    curve
        A key of :func:`hic_curves`.

    Returns
    -------
    float

    Examples
    --------
    >>> round(head_injury_risk(1000.0), 4), round(head_injury_risk(1000.0, "nhtsa_ais2"), 4)
    (0.2309, 0.8947)
    """
    curves = hic_curves()
    if curve not in curves:
        raise InvalidParameterError("curve", curve, f"must be one of {tuple(curves)}")
    if not (isinstance(hic, (int, float)) and math.isfinite(hic) and hic >= 0):
        raise InvalidParameterError("hic", hic, "must be a finite HIC >= 0")
    return curves[curve].risk(float(hic))


@dataclass(frozen=True)
class StatureGroup:
    """A normal stature distribution with its share of the population.

    Attributes
    ----------
    name
        The group (``"men"``, ``"women"``).
    share
        Its share of the population.
    mean, sd
        Mean and standard deviation of the stature, m.
    source
        The citation.
    """

    name: str
    share: float
    mean: float
    sd: float
    source: str


@cache
def stature_population() -> tuple[StatureGroup, ...]:
    """The adult stature mixture of ``designlab/data/anthropometry_stature.csv``."""
    return tuple(StatureGroup(r["group"], float(r["share"]), float(r["mean_mm"]) / 1e3,
                              float(r["sd_mm"]) / 1e3, r["source"])
                 for r in _rows("anthropometry_stature.csv"))  # fmt: skip


#: The frontal body region between two landmarks (fractions of stature, Drillis and
#: Contini 1966), arms hanging: hands beside the hips, between knuckle and hip height.
_BANDS = (
    ("lower_leg", "sole", "knee"),
    ("thigh_knee", "knee", "knuckle"),
    ("hand_finger", "knuckle", "hip"),
    ("pelvis", "hip", "elbow"),
    ("abdomen", "elbow", "chest"),
    ("chest", "chest", "shoulder"),
    ("neck", "shoulder", "chin"),
    ("face", "chin", "eye"),
    ("skull_forehead", "eye", "vertex"),
)


@cache
def _landmarks() -> dict[str, float]:
    return {r["landmark"]: float(r["fraction_of_stature"])
            for r in _rows("anthropometry_heights.csv")}  # fmt: skip


def region_shares(low: float, high: float, points: int = 401) -> pd.Series:
    """Which frontal body region a contact between ``low`` and ``high`` above the floor meets.

    The contact height is uniform over [low, high] (one height when equal) and the
    person's stature follows :func:`stature_population`; a height above the person's
    stature meets nobody (``"above the head"``). The band of each region is between two
    landmarks of ``designlab/data/anthropometry_heights.csv`` (arms hanging, a frontal
    contact: the back and the arms' upper and lower segments are not assigned).

    Parameters
    ----------
    low, high
        Heights of the touching part, m (0 <= low <= high <= 3).
    points
        Gauss-Legendre points over the height range.

    Returns
    -------
    pandas.Series
        Share per region (summing to 1 with ``"above the head"``).

    Examples
    --------
    >>> s = region_shares(0.1, 0.1)
    >>> s.idxmax(), round(float(s.max()), 6)
    ('lower_leg', 1.0)
    """
    for name, v in (("low", low), ("high", high)):
        if not (isinstance(v, (int, float)) and 0.0 <= v <= 3.0):
            raise InvalidParameterError(name, v, "must be a height in [0, 3]", "m")
    if low > high:
        raise InvalidParameterError("low", low, f"must be <= high = {high:g}", "m")
    if high > low:
        x, w = np.polynomial.legendre.leggauss(points)
        h, w = low + (x + 1) * (high - low) / 2, w / 2
    else:
        h, w = np.array([low]), np.array([1.0])
    marks = _landmarks()

    def cdf(s: np.ndarray) -> np.ndarray:  # P(stature <= s)
        return sum(g.share * stats.norm.cdf(s, g.mean, g.sd) for g in stature_population())

    with np.errstate(divide="ignore"):
        out = {}
        for region, lo, hi in _BANDS:
            # h / H in [f_lo, f_hi)  <=>  H in (h / f_hi, h / f_lo]
            top = np.where(marks[lo] > 0, cdf(h / max(marks[lo], 1e-300)), 1.0)
            out[region] = float(np.sum(w * (top - cdf(h / marks[hi]))))
    out["above the head"] = float(np.sum(w * cdf(h)))
    return pd.Series(out)
