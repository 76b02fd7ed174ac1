"""A foam given by its measured quasi-static stress-strain curve, and a linear damper.

The reduced joint (3.4.9) and the head on its neck (3.5.3) as in the thesis, with the
linear foam law (3.5.1) replaced by the foam's own compression curve: for a compression
eps of a foam of thickness T and contact area A,

    f_c = A sigma(eps / T)  +  C_c eps_dot

where sigma is the measured engineering stress at the engineering strain eps / T,
interpolated by the monotone piecewise-cubic Hermite interpolant through the origin and
the measured points (PCHIP, Fritsch & Carlson 1980, "Monotone piecewise cubic
interpolation", SIAM J. Numer. Anal. 17(2); :class:`scipy.interpolate.PchipInterpolator`:
it never overshoots the data, so a rising curve gives a rising force). Written with the
contact's initial stiffness K_c = A sigma'(0) / T as its scale,

    f_c = K_c s(eps) + C_c eps_dot,    s(eps) = T sigma(eps / T) / sigma'(0)   (s'(0) = 1)

so that an envelope varies K_c (a denser grade, a larger contact area: the curve's shape
kept) and C_c like the linear foam's. Below contact (eps < 0) s(eps) = eps; the curve is
not extrapolated: a compression that reaches its last measured strain crushes the foam
(status ``bottoming``, force and a_h beyond any limit). With a linear curve
(sigma = E eps / T) the law is the Kelvin-Voigt foam of (3.5.1) with K_c = A E / T.

Not linear: its metrics come from the general response path
(:mod:`designlab.impact.general`), one design at a time (status ``"integrated"``, never
certified). The curve travels in the parameter row by name (``T_u``, the strains
``e_1..e_16`` and stresses ``s_1..s_16``, a shorter curve padded with its last point), so
sweeps and worker processes need nothing else.

Examples
--------
>>> from designlab.impact import HEAD_MIN, MANIPULATOR_1
>>> foam = StressStrainFoam(strain=(0.1, 0.5, 0.8), stress=(10e3, 30e3, 200e3),
...                         area=0.01, thickness=0.04, damping=60.0)
>>> round(foam.stiffness)                    # A sigma'(0) / T, N/m
27500
>>> law = STRESS_STRAIN.force_law_of(dict(zip(STRESS_STRAIN.columns,
...                                           STRESS_STRAIN.row(MANIPULATOR_1, foam, HEAD_MIN))))
>>> round(float(law(0.004, 0.0)[0]), 6)      # A sigma at the measured strain 0.1
100.0
"""

from __future__ import annotations

import bisect
import csv
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.contact.base import LINEAR_FOAM, REDUCED_JOINT
from designlab.impact.contact.integrated import IntegratedContact
from designlab.impact.general import ForceLaw
from designlab.impact.model import PARAM_NAMES
from designlab.impact.parameters import ContactDynamics, LinkImpact
from designlab.params import declared, param, params_of
from designlab.validation import ParamsMixin

__all__ = ["MAX_POINTS", "STRESS_STRAIN", "StressStrain", "StressStrainFoam"]

#: The most measured points a curve may have (the row carries them; a longer measurement
#: is thinned by its owner, keeping the points that matter to the shape).
MAX_POINTS = 16
#: The fewest measured points (the origin is implied): below that a curve has no shape.
MIN_POINTS = 2
_STRAINS = tuple(f"e_{i}" for i in range(1, MAX_POINTS + 1))
_STRESSES = tuple(f"s_{i}" for i in range(1, MAX_POINTS + 1))


def _checked_curve(strain: object, stress: object) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The measured points, checked: finite, strains rising in (0, 1), stresses rising > 0."""
    pts = []
    for name, values in (("strain", strain), ("stress", stress)):
        try:
            arr = np.asarray(values, dtype=float)
        except (TypeError, ValueError):
            raise InvalidParameterError(
                f"StressStrainFoam.{name}", values, "must be a sequence of numbers"
            ) from None
        if arr.ndim != 1 or not MIN_POINTS <= arr.size <= MAX_POINTS:
            raise InvalidParameterError(
                f"StressStrainFoam.{name}", values,
                f"must be {MIN_POINTS} to {MAX_POINTS} measured points (the origin implied)",
            )  # fmt: skip
        if not np.all(np.isfinite(arr)):
            raise InvalidParameterError(f"StressStrainFoam.{name}", values, "must be finite")
        pts.append(arr)
    e, s = pts
    if e.size != s.size:
        raise InvalidParameterError(
            "StressStrainFoam.stress", stress, f"must have one value per strain ({e.size})"
        )
    if not (e[0] > 0 and np.all(np.diff(e) > 0) and e[-1] < 1):
        raise InvalidParameterError(
            "StressStrainFoam.strain", strain, "must rise strictly within (0, 1) (engineering "
            "strain of the compression; the origin is implied)",
        )  # fmt: skip
    if not (s[0] > 0 and np.all(np.diff(s) > 0) and s[-1] <= 1e9):
        raise InvalidParameterError(
            "StressStrainFoam.stress", stress, "must rise strictly from > 0 to <= 1e9 Pa (a "
            "monotone loading curve: a foam whose stress falls is not served)",
        )  # fmt: skip
    return tuple(float(x) for x in e), tuple(float(x) for x in s)


class _Curve:
    """The PCHIP curve through the origin and the points, evaluated with plain floats."""

    def __init__(self, strain: NDArray, stress: NDArray) -> None:
        from scipy.interpolate import PchipInterpolator

        self.x = [0.0, *map(float, strain)]
        self.c = PchipInterpolator(self.x, [0.0, *map(float, stress)]).c.T.tolist()
        self.slope0 = float(self.c[0][2])

    def __call__(self, u: float) -> tuple[float, float]:
        """sigma(u) and sigma'(u), 0 <= u <= the last strain."""
        i = min(max(bisect.bisect_right(self.x, u) - 1, 0), len(self.c) - 1)
        a, b, c, d = self.c[i]
        h = u - self.x[i]
        return ((a * h + b) * h + c) * h + d, (3.0 * a * h + 2.0 * b) * h + c


def _curve_of(strain: Any, stress: Any) -> _Curve:
    curve = _Curve(np.asarray(strain), np.asarray(stress))
    if not curve.slope0 > 0:
        raise InvalidParameterError(
            "StressStrainFoam.strain", tuple(strain), "must start closer to the origin: the "
            "interpolant's initial slope sigma'(0) is 0 (the first segment is too flat "
            "against the second)",
        )  # fmt: skip
    return curve


@declared
@dataclass(frozen=True)
class StressStrainFoam(ParamsMixin):
    """A foam given by its measured quasi-static compression curve (see the module text).

    Examples
    --------
    >>> foam = StressStrainFoam(strain=(0.05, 0.3, 0.6), stress=(5e3, 2e4, 8e4), area=0.01,
    ...                         thickness=0.04, damping=60.0)
    >>> round(foam.crush_depth, 3)   # m: the law is not extrapolated past the last strain
    0.024
    >>> StressStrainFoam(strain=(0.1, 0.05), stress=(1e3, 2e3), area=0.01, thickness=0.04,
    ...                  damping=60.0)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: StressStrainFoam.strain = (0.1, 0.05) is not ...
    """

    strain: tuple[float, ...] = param(
        doc="measured engineering strains, rising in (0, 1), the origin implied", kind="object"
    )
    stress: tuple[float, ...] = param(
        unit="Pa", doc="measured engineering stresses at those strains, rising", kind="object"
    )
    area: float = param("A_c", "m^2", doc="contact area of the foam", gt=0, le=1,
                        typical=(1e-3, 1e-2))  # fmt: skip
    thickness: float = param("T_u", "m", doc="uncompressed thickness", gt=0, le=1,
                             typical=(0.02, 0.05))  # fmt: skip
    damping: float = param("C_c", "N s/m", doc="foam damping (a linear damper)", ge=0, le=1e10,
                           typical=(43.8, 113.6))  # fmt: skip
    stiffness: float | None = param(
        "K_c", "N/m", doc="initial contact stiffness (the curve's shape kept)", gt=0, le=1e10,
        optional=True, none="the curve's own, A sigma'(0) / T", default=None,
    )  # fmt: skip
    name: str = param(kind="text", default="", doc="optional label used in reports")

    def __post_init__(self) -> None:
        e, s = _checked_curve(self.strain, self.stress)
        object.__setattr__(self, "strain", e)
        object.__setattr__(self, "stress", s)
        if self.stiffness is None:
            own = self.area * _curve_of(e, s).slope0 / self.thickness
            top = params_of(StressStrainFoam)["stiffness"].le
            if not own <= top:  # the curve's stiffness is checked as a given one would be
                raise InvalidParameterError(
                    "StressStrainFoam.thickness", self.thickness, f"gives the contact stiffness "
                    f"A sigma'(0) / T = {own:.4g} N/m with area = {self.area:g} m^2, beyond "
                    f"{top:g} N/m: a thicker foam, a smaller area or a softer curve is served",
                    "m",
                )  # fmt: skip
            object.__setattr__(self, "stiffness", own)
        else:
            _curve_of(e, s)

    @property
    def crush_depth(self) -> float:
        """The compression at the last measured strain, m: the law is not extrapolated."""
        return self.thickness * self.strain[-1]

    @classmethod
    def from_csv(cls, path: str | Path, **fields: Any) -> StressStrainFoam:
        """The foam whose curve is the file's ``strain`` and ``stress_Pa`` columns.

        Lines starting with ``#`` (the source and its citation) are skipped.

        Parameters
        ----------
        path
            A CSV file with the columns ``strain`` and ``stress_Pa``.
        **fields
            The other fields (``area``, ``thickness``, ``damping``, ...).
        """
        with open(path, newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
        if not rows or not {"strain", "stress_Pa"} <= set(rows[0]):
            raise InvalidParameterError(
                "path", str(path), "must be a CSV with the columns strain and stress_Pa"
            )
        return cls(strain=tuple(float(r["strain"]) for r in rows),
                   stress=tuple(float(r["stress_Pa"]) for r in rows), **fields)  # fmt: skip


def _force_law(k: float, c: float, thickness: float, curve: _Curve) -> ForceLaw:
    """``f_c(eps, eps_dot)`` and its partial derivatives (see the module text)."""
    scale = k * thickness / curve.slope0  # K_c T / sigma'(0), per unit of sigma(eps / T)
    end = curve.x[-1]

    def scalar(x: float, xd: float) -> tuple[float, float, float]:
        if x <= 0.0:
            return k * x + c * xd, k, c
        sig, dsig = curve(min(x / thickness, end))
        return scale * sig + c * xd, scale * dsig / thickness, c

    def law(x: Any, xd: Any) -> tuple[Any, Any, Any]:
        if np.ndim(x) == 0:
            return scalar(float(x), float(xd))
        pairs = zip(np.ravel(x), np.ravel(np.broadcast_to(xd, np.shape(x))), strict=True)
        f = [scalar(float(a), float(b)) for a, b in pairs]
        return tuple(np.reshape([r[i] for r in f], np.shape(x)) for i in range(3))

    return law


@dataclass(frozen=True)
class StressStrain(IntegratedContact):
    """The reduced joint with a measured-curve foam (see the module text).

    Attributes
    ----------
    name, label, doc, robots, foam, columns, robot_attributes, foam_attributes
        As in :class:`~designlab.impact.contact.base.ContactModel`.
    linear_model, equations, linear, batched, gradients, profiles, printed_q2, response_form
        As in :class:`~designlab.impact.contact.base.ContactModel` (``linear_model`` is
        ``None``: the responses are integrated).
    """

    def foam_values(self, foam: Any) -> dict[str, float]:
        """T_u and the curve, padded to :data:`MAX_POINTS` with its last point."""
        if type(foam) is not self.foam:
            raise InvalidParameterError("foam", foam, "must be a StressStrainFoam")
        pad = MAX_POINTS - len(foam.strain)
        e = (*foam.strain, *[foam.strain[-1]] * pad)
        s = (*foam.stress, *[foam.stress[-1]] * pad)
        return {"T_u": foam.thickness, **dict(zip(_STRAINS, e, strict=True)),
                **dict(zip(_STRESSES, s, strict=True))}  # fmt: skip

    @staticmethod
    def _curve_points(values: Mapping[str, float]) -> tuple[list[float], list[float]]:
        e, s = [values[_STRAINS[0]]], [values[_STRESSES[0]]]
        for ce, cs in zip(_STRAINS[1:], _STRESSES[1:], strict=True):
            if values[ce] == e[-1] and values[cs] == s[-1]:
                break  # the padding: the last point repeated
            e.append(values[ce])
            s.append(values[cs])
        return e, s

    def force_law_of(self, values: Mapping[str, float]) -> ForceLaw:
        """The force law of one design from its row by name (K_c, C_c, T_u and the curve)."""
        e, s = _checked_curve(*self._curve_points(values))
        return _force_law(values["K_c"], values["C_c"], values["T_u"], _curve_of(e, s))

    def crush_depth_of(self, values: Mapping[str, float]) -> float | None:
        """T_u times the last measured strain."""
        return values["T_u"] * self._curve_points(values)[0][-1]

    def valid_depth(self, foam: Any) -> float:
        """The compression at the last measured strain, m."""
        return float(foam.crush_depth)


STRESS_STRAIN = StressStrain(
    name="stress_strain",
    label="Reduced joint, measured-curve foam",
    doc="a measured quasi-static stress-strain curve (PCHIP) and a linear damper; general path",
    robots=(ContactDynamics, LinkImpact),
    foam=StressStrainFoam,
    columns=(*PARAM_NAMES, "T_u", *_STRAINS, *_STRESSES),
    robot_attributes=REDUCED_JOINT,
    foam_attributes=(
        *LINEAR_FOAM,
        ("T_u", "thickness"),
        *((c, "strain") for c in _STRAINS),
        *((c, "stress") for c in _STRESSES),
    ),
    equations="f_c = K_c T sigma(eps/T) / sigma'(0) + C_c eps_dot (sigma: PCHIP of the curve)",
    linear=False,
    batched=False,
    gradients=False,
    profiles=False,
    response_form="",
)
