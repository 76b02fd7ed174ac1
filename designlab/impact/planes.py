"""Combined impact planes: closing speeds from vectors, and the head accelerations added.

Zeng 2011, Sec. 3.3-3.4: an impact on link 2 or 3 of an articulated arm is split
into a horizontal plane (scenario 1, joint 1) and a vertical plane (scenarios 2
and 3, joints 2 and 3), each with its own single-DOF manipulator, and "the head
accelerations in the horizontal and vertical planes are added". In each plane
the closing speed is the normal component of the relative velocity,

    (3.4.13)  v_c = v_r(0) - v_h(0) cos(gamma_c)
    (3.4.21)  v_c = v_r(0) cos(gamma_r) - v_h(0) cos(gamma_c)

where gamma_r (gamma_c) is the angle between the manipulator's (head's) velocity
and the plane's contact normal. Here the user gives the vectors -- the velocity
of the impact point, the head's velocity and each plane's contact normal -- and
:func:`combined_impact` projects them, runs the impact model in each plane and
combines the metrics:

* ``a_h_max_sum`` -- the thesis's rule, the sum of the planes' a_h,max. The
  peaks need not be simultaneous, so the sum bounds the head's acceleration
  magnitude from above (|a_1 n_1 + a_2 n_2| <= |a_1| + |a_2|).
* ``a_h_max_vector`` -- an extension: the largest magnitude over time of the
  head's acceleration vector ``sum_i a_i(t) n_i``, with every plane's contact
  starting at t = 0 and each plane's a_h taken as zero after its first lobe.

Velocity sign convention (docs/impact.md, "Impact velocity", in vector form): the
normal ``n`` points from the manipulator towards the head; ``v_c = (v_r - v_h) . n``, and a plane
with ``v_c <= 0`` has no impact.

Examples
--------
>>> import designlab as dl
>>> horizontal = ImpactPlane(dl.impact.MANIPULATOR_1, normal=(1.0, 0.0, 0.0), name="horizontal")
>>> vertical = ImpactPlane(dl.impact.MANIPULATOR_2, normal=(0.0, 0.0, -1.0), name="vertical")
>>> c = combined_impact([horizontal, vertical], dl.impact.FOAM_1, dl.impact.HEAD_MIN,
...                     robot_velocity=(0.25, 0.0, -0.2), head_velocity=(-1.0, 0.0, 0.0))
>>> [round(v.closing_speed, 3) for v in c.closing]
[1.25, 0.2]
>>> round(c.a_h_max_sum_g, 2), round(c.a_h_max_vector_g, 2)
(7.23, 6.22)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.parameters import (
    HEAD_VELOCITY,
    ROBOT_VELOCITY,
    ContactDynamics,
    Foam,
    HeadNeck,
)
from designlab.impact.peaks import first_peak
from designlab.impact.series_joint import FullJointContact
from designlab.impact.simulate import simulate
from designlab.params import Param, declared, param
from designlab.results import Result
from designlab.units import STANDARD_GRAVITY

__all__ = [
    "ClosingSpeed",
    "CombinedImpact",
    "ImpactPlane",
    "closing_speed",
    "combined_impact",
]


#: Points on which the vector combination of the planes is evaluated.
VECTOR_SAMPLES = Param(
    None, "", "points of the vector combination", kind="integer", ge=2, le=1_000_000,
    name="samples",
)  # fmt: skip


def _vector(name: str, value: Any, unit: str, size: int | None = None) -> NDArray[np.float64]:
    try:
        v = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameterError(name, value, "must be a vector of real numbers", unit) from None
    if v.ndim != 1 or v.size not in (2, 3) or (size is not None and v.size != size):
        allowed = f"must be a vector of length {size}" if size else "must be a 2- or 3-vector"
        raise InvalidParameterError(name, value, allowed, unit)
    if not np.all(np.isfinite(v)):
        raise InvalidParameterError(name, value, "must contain only finite numbers", unit)
    return v


def _unit_normal(name: str, value: Any, size: int | None = None) -> NDArray[np.float64]:
    n = _vector(name, value, "", size)
    scale = float(np.max(np.abs(n)))  # scaled first: a norm of 1e-300 or 1e300 is no 0 or inf
    if scale == 0.0:
        raise InvalidParameterError(name, value, "must be a non-zero vector (the contact normal)")
    n = n / scale
    return n / float(np.linalg.norm(n))


@dataclass(frozen=True)
class ClosingSpeed(Result):
    """Closing speed of one plane, (3.4.13)/(3.4.21) (:func:`closing_speed`).

    Attributes
    ----------
    closing_speed
        v_c = v_r(0) cos(gamma_r) - v_h(0) cos(gamma_c), m/s.
    robot_speed, head_speed
        |v_r(0)| and |v_h(0)|, m/s.
    gamma_r, gamma_c
        Angles (rad) between the manipulator's (head's) velocity and the normal;
        NaN for a zero velocity.
    status
        ``"ok"`` (a closing speed is always defined).
    warnings
        Empty.
    """

    closing_speed: float
    robot_speed: float
    head_speed: float
    gamma_r: float
    gamma_c: float
    status: str = "ok"
    warnings: tuple[str, ...] = ()

    @property
    def impact(self) -> bool:
        """Whether the bodies close in along the normal (v_c > 0; docs/impact.md)."""
        return self.closing_speed > 0.0

    def to_frame(self) -> pd.DataFrame:
        """One row: v_c, the speeds and the angles.

        Returns
        -------
        pandas.DataFrame
            ``v_c_m_per_s, v_r_m_per_s, v_h_m_per_s, gamma_r_deg, gamma_c_deg``.
        """
        return pd.DataFrame(
            {
                "v_c_m_per_s": [self.closing_speed],
                "v_r_m_per_s": [self.robot_speed],
                "v_h_m_per_s": [self.head_speed],
                "gamma_r_deg": [math.degrees(self.gamma_r)],
                "gamma_c_deg": [math.degrees(self.gamma_c)],
            }
        )


def _angle(v: NDArray[np.float64], n: NDArray[np.float64], sign: float) -> float:
    speed = float(np.linalg.norm(v))
    if speed == 0.0:
        return math.nan
    return math.acos(max(-1.0, min(1.0, sign * float(v @ n) / speed)))


def _closing_inputs(robot_velocity: Any, head_velocity: Any, normal: Any) -> tuple[NDArray, ...]:
    """The checked vectors of :func:`closing_speed`: the one whose length differs from the
    other two named; speeds within the declared bounds of v_r and v_h (Sec. 3.4)."""
    given = {"robot_velocity": robot_velocity, "head_velocity": head_velocity, "normal": normal}
    vecs = {k: _vector(k, v, "" if k == "normal" else "m/s") for k, v in given.items()}
    sizes = [v.size for v in vecs.values()]
    if len(set(sizes)) > 1:
        odd = next(k for k, v in vecs.items() if sizes.count(v.size) == 1)
        size = next(s for s in sizes if sizes.count(s) == 2)
        raise InvalidParameterError(
            odd, given[odd], f"must be a vector of length {size}, as the other two of "
            "robot_velocity, head_velocity and normal", "" if odd == "normal" else "m/s",
        )  # fmt: skip
    for key, decl in (("robot_velocity", ROBOT_VELOCITY), ("head_velocity", HEAD_VELOCITY)):
        with np.errstate(over="ignore"):
            speed = float(np.linalg.norm(vecs[key]))
        if not speed <= decl.le:  # also an overflow to inf
            raise InvalidParameterError(
                key, given[key], f"its magnitude ({speed:g} m/s) must be <= {decl.le:g} m/s "
                f"(the declared bound of the {decl.doc}, {decl.symbol})", "m/s",
            )  # fmt: skip
    return vecs["robot_velocity"], vecs["head_velocity"], _unit_normal("normal", normal)


def closing_speed(
    robot_velocity: ArrayLike, head_velocity: ArrayLike, normal: ArrayLike
) -> ClosingSpeed:
    """Closing speed along a contact normal, (3.4.13) and (3.4.21), from velocity vectors.

    Parameters
    ----------
    robot_velocity
        Velocity of the impact point P_c just before impact, m/s (2- or 3-vector).
    head_velocity
        Velocity of the head, m/s (same length).
    normal
        Contact normal pointing from the manipulator towards the head (any
        non-zero length; it is normalised).

    Returns
    -------
    ClosingSpeed
        ``v_c = (v_r - v_h) . n``; ``gamma_r`` is the angle between ``v_r`` and
        ``n``, ``gamma_c`` the angle between the head's velocity and the normal
        pointing back at the manipulator (``-n``), so that v_c = |v_r| cos gamma_r
        + |v_h| cos gamma_c with the head moving towards the manipulator. The
        thesis writes the head term as ``- v_h(0) cos gamma_c`` with a signed
        v_h(0) along the normal (negative towards the manipulator; docs/impact.md,
        "Impact velocity").

    Examples
    --------
    Scenario 1 at the thesis's worst case (gamma_c = 0): 0.25 m/s arm, 1 m/s head.

    >>> c = closing_speed((0.25, 0.0), (-1.0, 0.0), (1.0, 0.0))
    >>> c.closing_speed, c.gamma_r, c.gamma_c
    (1.25, 0.0, 0.0)

    A head approaching at 60 degrees to the normal adds only half its speed:

    >>> round(closing_speed((0.25, 0.0), (-0.5, 0.866), (1.0, 0.0)).closing_speed, 3)
    0.75
    """
    v_r, v_h, n = _closing_inputs(robot_velocity, head_velocity, normal)
    v_c = float((v_r - v_h) @ n)
    return ClosingSpeed(
        closing_speed=v_c,
        robot_speed=float(np.linalg.norm(v_r)),
        head_speed=float(np.linalg.norm(v_h)),
        gamma_r=_angle(v_r, n, 1.0),
        gamma_c=_angle(v_h, n, -1.0),
    )


@declared
@dataclass(frozen=True)
class ImpactPlane:
    """One impact plane: the manipulator reduced in that plane and its contact normal.

    The robot is the single-DOF manipulator of the plane (e.g. scenario 1's
    joint 1 in the horizontal plane, scenario 3's joints 2-3 in the vertical
    plane), reduced (:class:`~designlab.impact.parameters.ContactDynamics`) or
    with its full series joint (:class:`~designlab.impact.series_joint.FullJointContact`).

    Examples
    --------
    >>> import designlab as dl
    >>> ImpactPlane(dl.impact.MANIPULATOR_1, normal=(2.0, 0.0)).normal
    (1.0, 0.0)
    """

    robot: ContactDynamics | FullJointContact = param(  # noqa: RUF009 (a declaration)
        kind="object", doc="the manipulator of the plane (ContactDynamics or FullJointContact)"
    )
    normal: tuple[float, ...] = param(
        kind="object", doc="contact normal from the manipulator towards the head (2 or 3 numbers)"
    )
    name: str = param(kind="text", default="", doc="label for reports")

    def __post_init__(self) -> None:
        if not isinstance(self.robot, (ContactDynamics, FullJointContact)):
            raise InvalidParameterError(
                "ImpactPlane.robot", self.robot, "must be a ContactDynamics or FullJointContact"
            )
        n = _unit_normal("ImpactPlane.normal", self.normal)
        object.__setattr__(self, "normal", tuple(float(x) for x in n))


@dataclass(frozen=True, eq=False)
class CombinedImpact(Result):
    """Impact metrics of several planes and their combination (:func:`combined_impact`).

    Attributes
    ----------
    planes
        The planes.
    closing
        The :class:`ClosingSpeed` of each plane.
    responses
        The :class:`~designlab.impact.simulate.ImpactResponse` of each plane
        (``None`` for a plane without impact).
    a_h_max_sum
        The thesis's combination (Sec. 3.4): the sum of the planes' a_h,max, m/s^2.
    a_h_max_vector
        The largest magnitude of the head's acceleration vector over time, m/s^2
        (an extension; <= ``a_h_max_sum``).
    status
        ``"ok"``, or the first status of a plane's impact that is not.
    warnings
        The planes' warnings.
    """

    planes: tuple[ImpactPlane, ...]
    closing: tuple[ClosingSpeed, ...]
    responses: tuple[Any, ...]
    a_h_max_sum: float
    a_h_max_vector: float
    status: str
    warnings: tuple[str, ...]
    _rows: list[dict[str, Any]] = field(repr=False, default_factory=list)

    @property
    def a_h_max_sum_g(self) -> float:
        """The thesis's combined a_h,max in g (standard gravity)."""
        return self.a_h_max_sum / STANDARD_GRAVITY

    @property
    def a_h_max_vector_g(self) -> float:
        """The vector combination in g."""
        return self.a_h_max_vector / STANDARD_GRAVITY

    def to_frame(self) -> pd.DataFrame:
        """One row per plane and a last row ``combined``.

        Returns
        -------
        pandas.DataFrame
            Per plane: closing speed, angles and the metrics (a_h,max in g, eps_max,
            the lobe and first-peak forces, t_imp, status); ``combined``: the
            thesis's sum ``a_h_max_g`` and the vector ``a_h_max_vector_g``.
        """
        return pd.DataFrame(self._rows)


def combined_impact(
    planes: Sequence[ImpactPlane],
    foam: Foam,
    head: HeadNeck,
    robot_velocity: ArrayLike,
    head_velocity: ArrayLike,
    *,
    samples: int = 2001,
) -> CombinedImpact:
    """Impact in several planes from the velocity vectors, with the planes combined.

    Parameters
    ----------
    planes
        One :class:`ImpactPlane` per plane (typically horizontal and vertical).
    foam, head
        The covering and the head-neck model (the same in every plane).
    robot_velocity, head_velocity
        Velocity vectors of the impact point and of the head, m/s.
    samples
        Points on which the vector combination is evaluated.

    Returns
    -------
    CombinedImpact

    Raises
    ------
    InvalidParameterError
        For no planes, vectors of different lengths, a zero normal.

    Examples
    --------
    >>> import designlab as dl
    >>> h = ImpactPlane(dl.impact.MANIPULATOR_1, normal=(1, 0, 0), name="horizontal")
    >>> v = ImpactPlane(dl.impact.MANIPULATOR_2, normal=(0, 0, -1), name="vertical")
    >>> c = combined_impact([h, v], dl.impact.FOAM_1, dl.impact.HEAD_MIN,
    ...                     robot_velocity=(0.25, 0, -0.2), head_velocity=(-1, 0, 0))
    >>> bool(c.a_h_max_vector_g <= c.a_h_max_sum_g)
    True
    """
    planes = tuple(planes)
    v_r, v_h = _check_combined(planes, foam, head, robot_velocity, head_velocity, samples)
    closing = tuple(closing_speed(v_r, v_h, p.normal) for p in planes)
    responses = tuple(
        simulate(p.robot, foam, head, c.closing_speed) if c.impact else None
        for p, c in zip(planes, closing, strict=True)
    )
    rows, peaks, status, warnings = _plane_rows(planes, closing, responses)
    total = float(np.nansum(peaks))
    vector = _vector_peak(planes, responses, int(samples))
    rows.append(
        {"plane": "combined", "a_h_max_g": total / STANDARD_GRAVITY,
         "a_h_max_vector_g": vector / STANDARD_GRAVITY}
    )  # fmt: skip
    if all(r is None for r in responses):
        status = "no_impact"
    return CombinedImpact(
        planes=planes,
        closing=closing,
        responses=responses,
        a_h_max_sum=total,
        a_h_max_vector=vector,
        status=status,
        warnings=tuple(warnings),
        _rows=rows,
    )


def _check_combined(
    planes: tuple[Any, ...],
    foam: Any,
    head: Any,
    robot_velocity: ArrayLike,
    head_velocity: ArrayLike,
    samples: Any,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Validate the arguments of :func:`combined_impact`; returns the two velocities."""
    if not planes or not all(isinstance(p, ImpactPlane) for p in planes):
        raise InvalidParameterError("planes", planes, "must be a non-empty sequence of ImpactPlane")
    if not isinstance(foam, Foam):
        raise InvalidParameterError("foam", foam, "must be a Foam")
    if not isinstance(head, HeadNeck):
        raise InvalidParameterError("head", head, "must be a HeadNeck")
    v_r = _vector("robot_velocity", robot_velocity, "m/s")
    v_h = _vector("head_velocity", head_velocity, "m/s", v_r.size)
    for p in planes:
        if len(p.normal) != v_r.size:
            raise InvalidParameterError(
                "planes",
                p.name or p.normal,
                f"normals must have the length {v_r.size} of the velocities",
            )
    VECTOR_SAMPLES.check(samples)
    return v_r, v_h


def _plane_rows(
    planes: tuple[ImpactPlane, ...],
    closing: tuple[ClosingSpeed, ...],
    responses: tuple[Any, ...],
) -> tuple[list[dict[str, Any]], list[float], str, list[str]]:
    """One row per plane, the planes' a_h,max, the first status that is not ok, the warnings."""
    rows: list[dict[str, Any]] = []
    warnings: list[str] = []
    status = "ok"
    peaks = []
    for i, (p, c, r) in enumerate(zip(planes, closing, responses, strict=True)):
        row = {"plane": p.name or f"plane {i + 1}", **c.to_frame().iloc[0].to_dict()}
        if r is None:
            row.update(a_h_max_g=0.0, eps_max_m=0.0, f_c_max_N=0.0, f_c_first_peak_N=0.0,
                       t_imp_s=0.0, status="no_impact")  # fmt: skip
            peaks.append(0.0)
        else:
            row.update(
                a_h_max_g=r.peak_head_acceleration / STANDARD_GRAVITY,
                eps_max_m=r.max_compression,
                f_c_max_N=r.peak_force,
                f_c_first_peak_N=first_peak(r)[1],
                t_imp_s=r.impact_duration,
                status=r.status,
            )
            peaks.append(r.peak_head_acceleration)
            warnings.extend(f"{row['plane']}: {w}" for w in r.warnings)
            if r.status != "ok" and status == "ok":
                status = r.status
        rows.append(row)
    return rows, peaks, status, warnings


def _vector_peak(
    planes: tuple[ImpactPlane, ...], responses: tuple[Any, ...], samples: int
) -> float:
    """max_t |sum_i a_i(t) n_i| with a_i = 0 after plane i's first lobe."""
    ends = [r.impact_duration for r in responses if r is not None]
    if not ends or not np.all(np.isfinite(ends)):
        return math.nan if ends else 0.0
    peaks_t = [r.time_of_peak_acceleration for r in responses if r is not None]
    t = np.union1d(np.linspace(0.0, max(ends), samples), peaks_t)
    acc = np.zeros((t.size, len(planes[0].normal)))
    for p, r in zip(planes, responses, strict=True):
        if r is None:
            continue
        a = r._lobe["evaluate"](t)["head_acceleration"]
        a = np.where(t <= r.impact_duration, a, 0.0)
        acc += a[:, None] * np.asarray(p.normal)[None, :]
    return float(np.linalg.norm(acc, axis=1).max())
