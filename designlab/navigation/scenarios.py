"""Scenarios: obstacles with their regions and motions, start, goal (Zeng 2011, Sec. 5.7, 6, 7).

A :class:`Scenario` holds a robot, a start, a goal and a tuple of obstacles. A
:class:`Disc` (human, circular obstacle, other robot) or a :class:`Rectangle`
carries its own active radius ``r2`` and critical radius ``r3`` (centre distance
for discs, contour distance for rectangles) and, for discs, a motion.
:func:`configuration` builds the thesis's configurations.

Examples
--------
>>> from designlab.navigation import configuration
>>> sc = configuration(1)
>>> sc.start, sc.goal, [o.name for o in sc.obstacles]
((3.9, 0.6), (0.0, 0.6), ['circle'])
>>> configuration(4).obstacle_names
('circle', 'rectangle', 'human')
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.navigation.parameters import (
    MAX_HUMAN_SPEED,
    OBSTACLES,
    SAMPLE_TIME,
    HolonomicRobot,
    NonholonomicRobot,
    declared_field,
)
from designlab.params import Param, declared, param, params_of

__all__ = [
    "ConstantVelocity",
    "Disc",
    "Rectangle",
    "SampledPath",
    "Scenario",
    "Stationary",
    "Walk",
    "configuration",
]

Array = NDArray[np.float64]

#: The longest simulated time of a scenario (s): 600 s, twenty times the thesis's 30 s
#: (a longer horizon only postpones "never arrives" and costs time and memory).
MAX_HORIZON = 600.0
#: Fastest scripted obstacle motion accepted (m/s).
_MAX_MOTION_SPEED = 50.0
#: Most samples of a :class:`SampledPath` (a measured walk at 100 Hz for 1000 s).
MAX_PATH_SAMPLES = 100_000


def _pt(doc: str, unit: str = "m") -> Any:
    """A point (x, y) field: validated by its owner (:func:`_point`)."""
    return param(None, unit, doc=doc, kind="object")


#: Largest coordinate accepted (m): a scene is at most a few hundred metres across.
_MAX_COORD = 1e4
#: Largest region radius accepted (m).
_MAX_REGION = 100.0


def _point(name: str, value: Any, unit: str = "m") -> tuple[float, float]:
    try:
        x, y = value
    except (TypeError, ValueError):
        raise InvalidParameterError(
            name, value, "must be a pair (x, y) of finite numbers", unit
        ) from None
    coord = Param(None, unit, "coordinate", ge=-_MAX_COORD, le=_MAX_COORD)
    return (coord.check(x, f"{name}[0]"), coord.check(y, f"{name}[1]"))


# ------------------------------------------------------------------------- motions


@declared
@dataclass(frozen=True)
class Stationary:
    """An obstacle that does not move.

    Examples
    --------
    >>> p, v, a = Stationary((2.45, 0.595)).state([0.0, 1.0])
    >>> p.tolist(), v.tolist()
    ([[2.45, 0.595], [2.45, 0.595]], [[0.0, 0.0], [0.0, 0.0]])
    """

    position: tuple[float, float] = _pt("position (x, y)")

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", _point("Stationary.position", self.position))

    def state(self, t: Array) -> tuple[Array, Array, Array]:
        """Position, velocity and acceleration at the times ``t``: three ``(len(t), 2)`` arrays."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        p = np.broadcast_to(np.asarray(self.position), (t.size, 2)).copy()
        return p, np.zeros_like(p), np.zeros_like(p)

    @property
    def moving(self) -> bool:
        return False


@declared
@dataclass(frozen=True)
class ConstantVelocity:
    """Straight-line motion at a constant velocity from ``start`` at t = 0.

    Examples
    --------
    >>> p, v, a = ConstantVelocity((3.0, 4.0), (0.0, -0.5)).state([2.0])
    >>> p.tolist(), v.tolist()
    ([[3.0, 3.0]], [[0.0, -0.5]])
    """

    start: tuple[float, float] = _pt("position (x, y) at t = 0")
    velocity: tuple[float, float] = _pt("velocity (v_x, v_y)", "m/s")

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", _point("ConstantVelocity.start", self.start))
        v = _point("ConstantVelocity.velocity", self.velocity, "m/s")
        if math.hypot(*v) > _MAX_MOTION_SPEED:
            raise InvalidParameterError(
                "ConstantVelocity.velocity",
                self.velocity,
                f"speed must be <= {_MAX_MOTION_SPEED:g}",
                "m/s",
            )
        object.__setattr__(self, "velocity", v)

    def state(self, t: Array) -> tuple[Array, Array, Array]:
        t = np.atleast_1d(np.asarray(t, dtype=float))[:, None]
        v = np.asarray(self.velocity)[None, :]
        p = np.asarray(self.start)[None, :] + v * t
        return p, np.broadcast_to(v, p.shape).copy(), np.zeros_like(p)

    @property
    def moving(self) -> bool:
        return any(self.velocity)


@declared
@dataclass(frozen=True)
class Walk:
    """A straight walk with a smooth start, a cruise and a smooth stop.

    The speed rises from 0 to ``speed`` along a half-cosine over ``ramp_time``,
    cruises, and falls back to 0 so that the walker stops exactly at ``end``. Used
    for the measured human walks the thesis replays but does not publish
    (``docs/navigation.md``, "Human walks"). The end must differ from the start, and the
    two ramps must leave a cruise (``speed * ramp_time`` <= the walk's length).

    Examples
    --------
    >>> w = Walk((0.6, 0.6), (4.0, 0.6), speed=1.0, ramp_time=0.5)
    >>> round(w.duration, 2)
    3.9
    >>> p, v, a = w.state([0.0, 2.0, 10.0])
    >>> p[:, 0].round(3).tolist(), v[:, 0].round(3).tolist()
    ([0.6, 2.35, 4.0], [0.0, 1.0, 0.0])
    """

    start: tuple[float, float] = _pt("start point")
    end: tuple[float, float] = _pt("end point (not the start)")
    speed: float = param(
        "v_w", "m/s", doc="cruise speed", gt=0, le=MAX_HUMAN_SPEED, default=1.0, typical=(0.8, 1.4)
    )
    ramp_time: float = param(
        "t_ramp", "s", doc="duration of each speed ramp", ge=0, le=10.0, default=0.5
    )
    start_time: float = param(
        "t_0", "s", doc="time at which the walk starts", ge=0, le=MAX_HORIZON, default=0.0
    )

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", _point("Walk.start", self.start))
        object.__setattr__(self, "end", _point("Walk.end", self.end))
        if self.length <= 1e-9:
            raise InvalidParameterError(
                "Walk.end",
                self.end,
                f"must differ from Walk.start = {self.start} (a walk of length 0)",
                "m",
            )
        if self.length < self.speed * self.ramp_time:
            raise InvalidParameterError(
                "Walk.ramp_time",
                self.ramp_time,
                f"must leave a cruise: speed * ramp_time = {self.speed:g} m/s x "
                f"{self.ramp_time:g} s <= walk length {self.length:.3f} m",
                "s",
            )

    @property
    def length(self) -> float:
        return math.dist(self.start, self.end)

    @property
    def duration(self) -> float:
        """Walking time in s (each half-cosine ramp covers speed * ramp / 2)."""
        return self.length / self.speed + self.ramp_time

    @property
    def moving(self) -> bool:
        return True

    def _s(self, tau: Array) -> tuple[Array, Array, Array]:
        v, tr, T = self.speed, self.ramp_time, self.duration
        s = np.zeros_like(tau)
        ds = np.zeros_like(tau)
        dds = np.zeros_like(tau)
        if tr > 0:
            w = math.pi / tr
            m = (tau > 0) & (tau < tr)
            s[m] = 0.5 * v * (tau[m] - np.sin(w * tau[m]) / w)
            ds[m] = 0.5 * v * (1 - np.cos(w * tau[m]))
            dds[m] = 0.5 * v * w * np.sin(w * tau[m])
        m = (tau >= tr) & (tau <= T - tr)
        s[m] = 0.5 * v * tr + v * (tau[m] - tr)
        ds[m] = v
        if tr > 0:
            m = (tau > T - tr) & (tau < T)
            u = T - tau[m]
            w = math.pi / tr
            s[m] = self.length - 0.5 * v * (u - np.sin(w * u) / w)
            ds[m] = 0.5 * v * (1 - np.cos(w * u))
            dds[m] = -0.5 * v * w * np.sin(w * u)
        s[tau >= T] = self.length
        return s, ds, dds

    def state(self, t: Array) -> tuple[Array, Array, Array]:
        t = np.atleast_1d(np.asarray(t, dtype=float))
        s, ds, dds = self._s(t - self.start_time)
        e = (np.asarray(self.end) - np.asarray(self.start)) / self.length
        p = np.asarray(self.start)[None, :] + s[:, None] * e[None, :]
        return p, ds[:, None] * e[None, :], dds[:, None] * e[None, :]


@dataclass(frozen=True)
class SampledPath:
    """A path given by samples (e.g. a measured walk), linearly interpolated.

    Velocity and acceleration are finite differences of the samples; the obstacle
    stays at the last sample afterwards.

    Parameters
    ----------
    times
        Increasing sample times in s.
    positions
        ``(len(times), 2)`` positions in m.

    Examples
    --------
    >>> path = SampledPath((0.0, 1.0, 2.0), ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0)))
    >>> path.state([0.5, 5.0])[0].tolist()
    [[0.5, 0.0], [1.0, 1.0]]
    """

    times: tuple[float, ...]
    positions: tuple[tuple[float, float], ...]

    def __post_init__(self) -> None:
        try:
            t = np.asarray(self.times, dtype=float)
            p = np.asarray(self.positions, dtype=float)
        except (TypeError, ValueError):
            raise InvalidParameterError(
                "SampledPath", (self.times, self.positions), "must be numbers: times, (x, y)"
            ) from None
        if t.ndim != 1 or t.size < 2 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
            raise InvalidParameterError(
                "SampledPath.times", self.times, "must be >= 2 increasing finite times", "s"
            )
        if t.size and (t[0] < 0 or t[-1] > MAX_HORIZON):
            raise InvalidParameterError(
                "SampledPath.times", self.times, f"must lie within 0 to {MAX_HORIZON:g} s", "s"
            )
        if p.shape != (t.size, 2) or not np.all(np.abs(p) <= _MAX_COORD):
            raise InvalidParameterError(
                "SampledPath.positions",
                self.positions,
                f"must be finite, within +-{_MAX_COORD:g} m, shape (len(times), 2)",
                "m",
            )
        if t.size > MAX_PATH_SAMPLES:
            raise InvalidParameterError(
                "SampledPath.times", f"{t.size} samples", f"must have <= {MAX_PATH_SAMPLES:,}"
            )
        object.__setattr__(self, "times", tuple(t.tolist()))
        object.__setattr__(self, "positions", tuple(map(tuple, p.tolist())))

    @classmethod
    def through(
        cls,
        waypoints: Sequence[Sequence[float]],
        speed: float = 1.0,
        start_time: float = 0.0,
    ) -> SampledPath:
        """A walk through ``waypoints`` at a constant ``speed`` (m/s), starting at ``start_time``.

        The walker waits at the first waypoint until ``start_time``, walks each leg in a
        straight line (turning on the spot at a waypoint, as the Sec. 5.7 human does) and
        stays at the last one.

        Examples
        --------
        >>> path = SampledPath.through([(0, 0), (2, 0), (2, 1)], speed=1.0, start_time=1.0)
        >>> path.times, path.state([2.0, 3.5, 9.0])[0].tolist()
        ((0.0, 1.0, 3.0, 4.0), [[1.0, 0.0], [2.0, 0.5], [2.0, 1.0]])
        """
        w = np.asarray(waypoints, dtype=float)
        if w.ndim != 2 or w.shape[1] != 2 or w.shape[0] < 2 or not np.all(np.isfinite(w)):
            raise InvalidParameterError(
                "route.waypoints", waypoints, "must be >= 2 finite (x, y) points", "m"
            )
        v = params_of(Walk)["speed"].check(speed, "route.speed")
        t0 = params_of(Walk)["start_time"].check(start_time, "route.start_time")
        legs = np.hypot(*np.diff(w, axis=0).T)
        if np.any(legs <= 1e-9):
            raise InvalidParameterError(
                "route.waypoints", waypoints, "consecutive waypoints must differ", "m"
            )
        times = t0 + np.concatenate([[0.0], np.cumsum(legs) / v])
        points = w
        if t0 > 0:
            times, points = np.concatenate([[0.0], times]), np.vstack([w[:1], w])
        return cls(tuple(times.tolist()), tuple(map(tuple, points.tolist())))

    @property
    def moving(self) -> bool:
        return True

    def state(self, t: Array) -> tuple[Array, Array, Array]:
        t = np.atleast_1d(np.asarray(t, dtype=float))
        ts = np.asarray(self.times)
        ps = np.asarray(self.positions)
        vs = np.gradient(ps, ts, axis=0)
        acc = np.gradient(vs, ts, axis=0)
        inside = (t >= ts[0]) & (t <= ts[-1])
        p = np.stack([np.interp(t, ts, ps[:, i]) for i in range(2)], axis=1)
        v = np.stack([np.interp(t, ts, vs[:, i]) for i in range(2)], axis=1) * inside[:, None]
        a = np.stack([np.interp(t, ts, acc[:, i]) for i in range(2)], axis=1) * inside[:, None]
        return p, v, a


Motion = Stationary | ConstantVelocity | Walk | SampledPath


# ----------------------------------------------------------------------- obstacles


@declared
@dataclass(frozen=True)
class Disc:
    """A disc obstacle (human, circular obstacle, other robot) with its regions.

    The radii r2 and r3 are centre-to-centre (Minkowski sums with the robot included),
    r2 > r3; a collision is a centre distance below rho_o + rho_r.

    Examples
    --------
    >>> h = Disc("human", 0.4, r2=2.1, r3=0.8, motion=Walk((0.6, 0.6), (4.0, 0.6)))
    >>> h.name, h.r3
    ('human', 0.8)
    """

    name: str = param(
        kind="text", doc="label used in results (circle, human, robot)", min_length=1, max_length=60
    )
    radius: float = param("rho_o", "m", doc="model radius", gt=0, le=5.0)
    r2: float = param("r_2", "m", doc="active radius (centre distance, > r3)", gt=0, le=_MAX_REGION)
    r3: float = param("r_3", "m", doc="critical radius (centre distance)", gt=0, le=_MAX_REGION)
    motion: Motion = param(doc="Stationary, ConstantVelocity, Walk or SampledPath", kind="object")  # noqa: RUF009

    def __post_init__(self) -> None:
        _check_regions(self)
        if not isinstance(self.motion, Stationary | ConstantVelocity | Walk | SampledPath):
            raise InvalidParameterError(
                f"{self.name}.motion", self.motion, "must be a motion object"
            )

    @property
    def kind(self) -> str:
        return "disc"

    def state(self, t: Array) -> tuple[Array, Array, Array]:
        return self.motion.state(t)

    def contour_distance(self, p: Array, t: float = 0.0) -> Array:
        """Centre distance d from points ``p`` ``(n, 2)`` at time ``t``."""
        c = self.state(np.array([t]))[0][0]
        return np.hypot(p[:, 0] - c[0], p[:, 1] - c[1])

    def collision_distance(self, robot_radius: float) -> float:
        return self.radius + robot_radius


@declared
@dataclass(frozen=True)
class Rectangle:
    """A stationary rectangle; ``r2`` and ``r3`` are distances from its contour (r2 > r3).

    Examples
    --------
    >>> r = Rectangle.from_corners("rectangle", [(1.6, -0.3), (3, -0.3), (3, 0.3), (1.6, 0.3)],
    ...                            r2=0.8, r3=0.4)
    >>> r.center, r.length, r.width
    ((2.3, 0.0), 1.4, 0.6)
    """

    name: str = param(kind="text", doc="label used in results", min_length=1, max_length=60)
    center: tuple[float, float] = _pt("centroid")
    length: float = param("L", "m", doc="side along the local x axis", gt=0, le=_MAX_REGION)
    width: float = param("W", "m", doc="side along the local y axis", gt=0, le=_MAX_REGION)
    r2: float = param(
        "r_2", "m", doc="active distance from the contour (> r3)", gt=0, le=_MAX_REGION
    )
    r3: float = param("r_3", "m", doc="critical distance from the contour", gt=0, le=_MAX_REGION)
    angle: float = param(
        "theta",
        "rad",
        doc="rotation of the local x axis from world x",
        ge=-10.0,
        le=10.0,
        default=0.0,
    )

    def __post_init__(self) -> None:
        _check_regions(self)
        object.__setattr__(self, "center", _point("Rectangle.center", self.center))

    @classmethod
    def from_corners(
        cls, name: str, corners: Sequence[Sequence[float]], *, r2: float, r3: float
    ) -> Rectangle:
        """Axis-aligned rectangle from its four corner points (m), in any order.

        The points must be the corners of one axis-aligned rectangle (within 1e-9 of its
        size): any other four points are refused, not replaced by their bounding box.

        Examples
        --------
        >>> Rectangle.from_corners("r", [(0, 0), (2, 0), (2, 1), (0, 1)], r2=1, r3=0.5).center
        (1.0, 0.5)
        >>> Rectangle.from_corners("r", [(0, 0), (1, 2), (3, 1), (2, 5)], r2=1, r3=0.5)
        Traceback (most recent call last):
        ...
        designlab.errors.InvalidParameterError: r.corners = ... is not allowed: must be the ...
        """
        try:
            c = np.asarray(corners, dtype=float)
        except (TypeError, ValueError):
            c = np.empty((0,))
        if c.shape != (4, 2) or not np.all(np.isfinite(c)):
            raise InvalidParameterError(
                f"{name}.corners", corners, "must be four finite (x, y) points", "m"
            )
        lo, hi = c.min(axis=0), c.max(axis=0)
        tol = 1e-9 * max(1.0, float(np.abs(c).max()))
        at = [
            np.where(
                np.abs(c[:, k] - lo[k]) <= tol, 0, np.where(np.abs(c[:, k] - hi[k]) <= tol, 1, -1)
            )
            for k in (0, 1)
        ]
        if (
            (at[0] < 0).any()
            or (at[1] < 0).any()
            or len(set(zip(at[0].tolist(), at[1].tolist(), strict=True))) != 4
        ):
            raise InvalidParameterError(
                f"{name}.corners", corners,
                "must be the four corners of one axis-aligned rectangle (for a rotated one give "
                "center, length, width and angle)", "m",
            )  # fmt: skip
        return cls(
            name,
            (round(float(lo[0] + hi[0]) / 2, 12), round(float(lo[1] + hi[1]) / 2, 12)),
            round(float(hi[0] - lo[0]), 12),
            round(float(hi[1] - lo[1]), 12),
            r2=r2,
            r3=r3,
        )

    @classmethod
    def wall(
        cls,
        name: str,
        start: Sequence[float],
        end: Sequence[float],
        thickness: float,
        *,
        r2: float,
        r3: float,
    ) -> Rectangle:
        """A straight wall from ``start`` to ``end`` (m), ``thickness`` thick: a rotated rectangle.

        Its regions are measured from the wall's contour, as for any rectangle (Sec. 5.3.5).

        Examples
        --------
        >>> w = Rectangle.wall("wall", (0.0, 2.0), (4.0, 2.0), 0.1, r2=0.8, r3=0.4)
        >>> w.center, w.length, w.width, w.angle
        ((2.0, 2.0), 4.0, 0.1, 0.0)
        >>> float(w.contour_distance(np.array([[1.0, 1.0]]))[0])
        0.95
        """
        a = _point(f"{name}.start", start)
        b = _point(f"{name}.end", end)
        length = math.dist(a, b)
        if length <= 1e-9:
            raise InvalidParameterError(
                f"{name}.end", end, f"must differ from {name}.start = {a} (a wall of length 0)", "m"
            )
        return cls(
            name,
            ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2),
            length,
            params_of(cls)["width"].check(thickness, f"{name}.thickness"),
            r2=r2,
            r3=r3,
            angle=math.atan2(b[1] - a[1], b[0] - a[0]),
        )

    @property
    def kind(self) -> str:
        return "rectangle"

    @property
    def motion(self) -> Stationary:
        return Stationary(self.center)

    def state(self, t: Array) -> tuple[Array, Array, Array]:
        return self.motion.state(t)

    def contour_distance(self, p: Array, t: float = 0.0) -> Array:
        """Distance from points ``p`` ``(n, 2)`` to the rectangle (0 inside)."""
        c, s = math.cos(self.angle), math.sin(self.angle)
        rel = np.asarray(p, dtype=float) - np.asarray(self.center)
        lx = c * rel[:, 0] + s * rel[:, 1]
        ly = -s * rel[:, 0] + c * rel[:, 1]
        dx = np.maximum(np.abs(lx) - self.length / 2, 0.0)
        dy = np.maximum(np.abs(ly) - self.width / 2, 0.0)
        return np.hypot(dx, dy)

    def collision_distance(self, robot_radius: float) -> float:
        return robot_radius

    def corners(self) -> Array:
        """The four corners, ``(4, 2)`` in m, counter-clockwise."""
        c, s = math.cos(self.angle), math.sin(self.angle)
        hl, hw = self.length / 2, self.width / 2
        local = np.array([(-hl, -hw), (hl, -hw), (hl, hw), (-hl, hw)])
        rot = np.array([[c, -s], [s, c]])
        return np.asarray(self.center) + local @ rot.T


Obstacle = Disc | Rectangle


def _contact_terms(o: Obstacle, robot_radius: float) -> str:
    """The terms of an obstacle's contact distance, for error messages."""
    if isinstance(o, Disc):
        return f"radius {o.radius:g} m + robot radius {robot_radius:g} m"
    return f"robot radius {robot_radius:g} m from the rectangle's contour"


def _shape(o: Obstacle) -> str:
    """An obstacle's name and size, for error messages."""
    if isinstance(o, Disc):
        return f"{o.name}: disc of radius {o.radius:g} m"
    return f"{o.name}: rectangle of length {o.length:g} m, width {o.width:g} m at {o.center}"


def _where(o: Obstacle) -> str:
    """Where a stationary obstacle is, as its declaration spells it, for error messages."""
    if isinstance(o, Rectangle):
        return f"center = {o.center}"
    return f"position = {getattr(o.motion, 'position', getattr(o.motion, 'start', '?'))}"


def _overlap(a: Rectangle, b: Rectangle) -> bool:
    """Separating-axis test: True if the two rectangles intersect."""
    ca, cb = a.corners(), b.corners()
    for ang in (a.angle, b.angle):
        for axis in ((math.cos(ang), math.sin(ang)), (-math.sin(ang), math.cos(ang))):
            pa, pb = ca @ np.asarray(axis), cb @ np.asarray(axis)
            if pa.max() < pb.min() or pb.max() < pa.min():
                return False
    return True


def _static_gap(a: Obstacle, b: Obstacle) -> float:
    """Distance between two static obstacles' reference sets minus r3_a + r3_b (< 0: the
    critical regions intersect). Discs are their centres, rectangles their areas."""

    def points(o: Obstacle) -> Array:
        if isinstance(o, Rectangle):
            return o.corners()
        return np.asarray([o.motion.state(np.zeros(1))[0][0]])

    if isinstance(a, Disc) and isinstance(b, Disc):
        d = float(np.hypot(*(points(a)[0] - points(b)[0])))
    else:
        # disjoint convex sets are closest at a vertex of one of them (a disc is a point)
        d = min(
            float(b.contour_distance(points(a)).min()), float(a.contour_distance(points(b)).min())
        )
        if isinstance(a, Rectangle) and isinstance(b, Rectangle) and _overlap(a, b):
            d = 0.0  # crossing edges with no vertex inside the other
    return d - (a.r3 + b.r3)


def _check_regions(o: Any) -> None:
    cls = type(o).__name__
    if o.r2 <= o.r3:
        raise InvalidParameterError(
            f"{cls}.r2", o.r2, f"must exceed {cls}.r3 = {o.r3} m (obstacle {o.name!r})", "m"
        )


# ------------------------------------------------------------------------ scenario


@declared
@dataclass(frozen=True)
class Scenario:
    """A navigation task: robot, start, goal, obstacles.

    A run that has not arrived by the horizon has ``arrival_time = inf``.

    Raises
    ------
    InvalidParameterError
        If the goal lies inside an obstacle's critical region, or an obstacle
        overlaps the robot at the start, or names repeat.

    Examples
    --------
    >>> sc = Scenario("corridor", start=(4.0, 0.5), goal=(0.0, 0.5),
    ...               obstacles=(Disc("pillar", 0.1, r2=0.8, r3=0.4,
    ...                               motion=Stationary((2.0, 0.6))),))
    >>> sc.obstacle_names
    ('pillar',)
    >>> Scenario("bad", start=(4.0, 0.5), goal=(2.0, 0.6), obstacles=sc.obstacles)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: Scenario.goal = (2.0, 0.6) m is not allowed: ...
    """

    name: str = param(kind="text", doc="label")
    start: tuple[float, float] = _pt("robot start (at rest)")
    goal: tuple[float, float] = _pt("goal")
    obstacles: tuple[Obstacle, ...] = param(
        doc="discs and rectangles (unique names)", kind="object", default=()
    )
    robot: HolonomicRobot | NonholonomicRobot = param(  # noqa: RUF009
        doc="HolonomicRobot or NonholonomicRobot", kind="object", default_factory=HolonomicRobot
    )
    horizon: float = param(
        "T_max", "s", doc="simulated time limit", gt=0, le=MAX_HORIZON, default=30.0
    )
    sample_time: float = declared_field(SAMPLE_TIME, 0.06)
    initial_heading: float | None = param(
        "phi_0",
        "rad",
        doc="heading of a nonholonomic robot at the start",
        ge=-10.0,
        le=10.0,
        optional=True,
        none="faces the goal",
        default=None,
    )
    description: str = param(kind="text", doc="free text for reports", default="")

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", _point("Scenario.start", self.start))
        object.__setattr__(self, "goal", _point("Scenario.goal", self.goal))
        if isinstance(self.obstacles, (str, bytes)) or not hasattr(self.obstacles, "__iter__"):
            raise InvalidParameterError(
                "Scenario.obstacles", self.obstacles, "must be a sequence of Disc or Rectangle"
            )
        object.__setattr__(self, "obstacles", tuple(self.obstacles))
        OBSTACLES.check(len(self.obstacles), "Scenario.obstacles (how many)")
        if self.horizon < self.sample_time:
            raise InvalidParameterError(
                "Scenario.horizon", self.horizon,
                f"must hold at least one navigation period (sample_time = {self.sample_time} s)",
                "s",
            )  # fmt: skip
        if not isinstance(self.robot, HolonomicRobot | NonholonomicRobot):
            raise InvalidParameterError(
                "Scenario.robot", self.robot, "must be a HolonomicRobot or NonholonomicRobot"
            )
        for o in self.obstacles:
            if not isinstance(o, Disc | Rectangle):
                raise InvalidParameterError(
                    "Scenario.obstacles", o, "must contain Disc or Rectangle objects"
                )
        names = [o.name for o in self.obstacles]
        if len(set(names)) != len(names):
            raise InvalidParameterError(
                "Scenario.obstacles", names, "obstacle names must be unique"
            )
        for o in self.obstacles:
            contact = o.collision_distance(self.robot.radius)
            if o.r2 <= contact:
                raise InvalidParameterError(
                    f"{type(o).__name__}.r2",
                    o.r2,
                    f"must exceed the contact distance {contact:.3f} m of {o.name!r} and the"
                    f" robot ({_contact_terms(o, self.robot.radius)}; an active region inside"
                    " contact has no clearance to score, Sec. 5.6)",
                    "m",
                )
            d_start = float(o.contour_distance(np.array([self.start]), 0.0)[0])
            if d_start <= o.collision_distance(self.robot.radius):
                raise InvalidParameterError(
                    f"Scenario.obstacles[{o.name}]",
                    _shape(o),
                    f"overlaps the robot at the start {self.start} (distance {d_start:.3f} m <= "
                    f"{o.collision_distance(self.robot.radius):.3f} m)",
                )
            if not o.motion.moving:
                d_goal = float(o.contour_distance(np.array([self.goal]), 0.0)[0])
                if d_goal <= o.r3:
                    raise InvalidParameterError(
                        "Scenario.goal",
                        self.goal,
                        f"lies inside the critical region of {o.name!r} (Scenario.obstacles"
                        f"[{self.obstacles.index(o)}], {_where(o)}; distance {d_goal:.3f} m "
                        f"<= r3 = {o.r3} m): move the goal or the obstacle, or shrink its r3",
                        "m",
                    )

    @property
    def obstacle_names(self) -> tuple[str, ...]:
        return tuple(o.name for o in self.obstacles)

    def intersecting_critical_regions(self) -> tuple[tuple[str, str, float], ...]:
        """Pairs of static obstacles whose critical regions intersect, with the overlap (m).

        Zeng 2011 (Sec. 6.4.3) merges such obstacles into one; designlab keeps them
        apart, and :func:`~designlab.navigation.simulate` warns: no path between them
        stays outside both critical regions.

        Examples
        --------
        >>> pillar = lambda n, x: Disc(n, 0.1, r2=0.8, r3=0.4, motion=Stationary((x, 1.0)))
        >>> sc = Scenario("gate", start=(4.0, 0.0), goal=(0.0, 0.0),
        ...               obstacles=(pillar("a", 2.0), pillar("b", 2.7)))
        >>> [(a, b, round(o, 3)) for a, b, o in sc.intersecting_critical_regions()]
        [('a', 'b', 0.1)]
        """
        static = [o for o in self.obstacles if isinstance(o, Rectangle) or not o.motion.moving]
        out = []
        for i, a in enumerate(static):
            for b in static[i + 1 :]:
                gap = _static_gap(a, b)
                if gap < 0:
                    out.append((a.name, b.name, -gap))
        return tuple(out)

    def with_robot(self, robot: HolonomicRobot | NonholonomicRobot) -> Scenario:
        """The same scenario with another robot."""
        return replace(self, robot=robot)

    def without_obstacles(self) -> Scenario:
        """The nominal run of the criteria (Sec. 5.6): same robot, start, goal, no obstacles."""
        return replace(self, obstacles=(), name=f"{self.name} (no obstacles)")

    def replace(self, **changes: Any) -> Scenario:
        """Copy with fields changed (validated again)."""
        return replace(self, **changes)

    @property
    def heading0(self) -> float:
        if self.initial_heading is not None:
            return float(self.initial_heading)
        return math.atan2(self.goal[1] - self.start[1], self.goal[0] - self.start[0])


# ----------------------------------------------------------- thesis configurations

_CH6 = {"human": (2.1, 0.8), "circle": (0.8, 0.4), "rectangle": (0.8, 0.4)}
_CH7 = {"human": (2.5, 0.8), "circle": (0.65, 0.4), "rectangle": (0.55, 0.3), "robot": (1.35, 0.55)}
RHO_H, RHO_CIR, RHO_MOB = 0.4, 0.1, 0.2


def _human(regions: dict[str, tuple[float, float]], motion: Motion) -> Disc:
    return Disc("human", RHO_H, *regions["human"], motion=motion)


def _circle(regions: dict[str, tuple[float, float]], at: tuple[float, float]) -> Disc:
    return Disc("circle", RHO_CIR, *regions["circle"], motion=Stationary(at))


def unpredictable_human_path(duration: float = 30.0, dt: float = 0.01) -> SampledPath:
    """The Sec. 5.7 human: [1, 0] m/s from [0.6, 0]; after 1 s it brakes at 1 m/s^2 to a stop,
    then accelerates at 1 m/s^2 along +y to 1 m/s and keeps that velocity."""
    t = np.arange(0.0, duration + dt / 2, dt)
    x = np.where(t <= 1, 0.6 + t, np.where(t <= 2, 1.6 + (t - 1) - 0.5 * (t - 1) ** 2, 2.1))
    ty = np.clip(t - 2.0, 0.0, None)
    y = np.where(ty <= 1, 0.5 * ty**2, 0.5 + (ty - 1))
    return SampledPath(tuple(t.tolist()), tuple(zip(x.tolist(), y.tolist(), strict=True)))


def configuration(
    which: int | str,
    chapter: int = 6,
    *,
    robot: HolonomicRobot | NonholonomicRobot | None = None,
    human_speed: float = 1.0,
    human_ramp_time: float = 0.5,
    horizon: float = 30.0,
) -> Scenario:
    """A configuration of Zeng 2011 as a :class:`Scenario`.

    Parameters
    ----------
    which
        1-4 (Ch. 6 Sec. 6.4, or Ch. 7 Sec. 7.5 with ``chapter=7``), ``"parallel"``
        (the human walking parallel to the robot, Sec. 6.4.5), ``"unpredictable"``
        (the human who stops and turns, Sec. 5.7) or ``"multi"`` (human, circle and
        another robot, Sec. 7.5.5; ``chapter=7`` only).
    chapter
        6 (holonomic robot, Ch. 6 regions) or 7 (nonholonomic robot, Ch. 7 regions:
        r2 = 2.5 m for the human, 0.65 m for the circle, rectangle 0.55/0.3 m).
    robot
        Override the robot (e.g. the holonomic comparison runs of Ch. 7).
    human_speed, human_ramp_time
        The synthetic walk replacing the thesis's measured walk in Configurations 2
        and 4 (``docs/navigation.md``): cruise speed (m/s) and ramp duration (s).
    horizon
        Simulated time limit (s).

    Notes
    -----
    The thesis does not state the start and goal of the Ch. 6 Configurations 3-4
    (assumed as Configuration 1) nor those of Sec. 7.5.5 (assumed here:
    start [5.5, 0.2], goal [1.0, 3.5]; the human walks towards +x, the direction the
    text states in words).

    Examples
    --------
    >>> sc = configuration(2, chapter=7)
    >>> type(sc.robot).__name__, sc.obstacles[0].r2
    ('NonholonomicRobot', 2.5)
    """
    if chapter not in (6, 7):
        raise InvalidParameterError("chapter", chapter, "must be 6 or 7")
    params_of(Walk)["speed"].check(human_speed, "human_speed")
    params_of(Walk)["ramp_time"].check(human_ramp_time, "human_ramp_time")
    rb = robot if robot is not None else (HolonomicRobot() if chapter == 6 else NonholonomicRobot())
    key = str(which)
    walk = (human_speed, human_ramp_time)
    if chapter == 6 and key == "unpredictable":
        human = _human(_CH6, unpredictable_human_path(horizon))
        text = "Sec. 5.7: a human who stops and turns"
        return Scenario("unpredictable", (4.0, 0.0), (0.0, 0.0), (human,), rb, horizon,
                        description=text)  # fmt: skip
    if chapter == 7 and key == "multi":
        return Scenario("multi", (5.5, 0.2), (1.0, 3.5), _multi(), rb, horizon,
                        description="Sec. 7.5.5: human, circle and an obstacle robot "
                        "(start/goal assumed)")  # fmt: skip
    builds = _chapter6(walk) if chapter == 6 else _chapter7(walk)
    if key not in builds:
        allowed = (
            "1, 2, 3, 4, 'parallel', 'unpredictable'" if chapter == 6 else "1, 2, 3, 4, 'multi'"
        )
        raise InvalidParameterError(
            "configuration", which, f"must be one of {allowed} for chapter {chapter}"
        )
    obstacles, text = builds[key]
    start = (3.9, 0.6) if chapter == 6 else (3.99, 0.6)
    name = f"ch{chapter}_config{key}" if key.isdigit() else f"ch{chapter}_{key}"
    return Scenario(name, start, (0.0, 0.6), obstacles, rb, horizon, description=text)


_Builds = dict[str, tuple[tuple[Obstacle, ...], str]]


def _chapter6(walk: tuple[float, float]) -> _Builds:
    """The Ch. 6 configurations (holonomic robot, Ch. 6 regions)."""
    reg, (v, ramp) = _CH6, walk
    head_on = Walk((0.6, 0.6), (4.0, 0.6), speed=v, ramp_time=ramp)
    rect = Rectangle.from_corners(
        "rectangle", [(1.6, -0.3), (3, -0.3), (3, 0.3), (1.6, 0.3)], r2=0.8, r3=0.4
    )
    circle3 = _circle(reg, (2.45, 1.4))
    parallel = _human(reg, Walk((0.6, 1.2), (4.0, 1.2), speed=v, ramp_time=ramp))
    return {
        "1": ((_circle(reg, (2.45, 0.595)),), "Sec. 6.4.1: a near-collinear circular obstacle"),
        "2": ((_human(reg, head_on),), "Sec. 6.4.2: a human walking head-on (synthetic walk)"),
        "3": ((circle3, rect), "Sec. 6.4.3: a passage between a circle and a rectangle"),
        "4": (
            (circle3, rect, _human(reg, head_on)),
            "Sec. 6.4.4: Configuration 3 plus the walking human",
        ),
        "parallel": (
            (parallel,),
            "Sec. 6.4.5: a human walking parallel to the robot, 0.6 m to the side",
        ),
    }


def _chapter7(walk: tuple[float, float]) -> _Builds:
    """The Ch. 7 configurations (nonholonomic robot, Ch. 7 regions)."""
    reg, (v, ramp) = _CH7, walk
    rect = Rectangle.from_corners(
        "rectangle",
        [(1.6, -0.1), (1.6, 0.5), (3.0, 0.5), (3.0, -0.1)],
        r2=reg["rectangle"][0],
        r3=reg["rectangle"][1],
    )
    circle3 = _circle(reg, (2.16, 1.5))
    human4 = _human(reg, Walk((0.2, 0.6), (3.9, 0.6), speed=v, ramp_time=ramp))
    human2 = _human(reg, Walk((0.2, 0.6), (4.0, 0.6), speed=v, ramp_time=ramp))
    return {
        "1": ((_circle(reg, (2.16, 0.6)),), "Sec. 7.5.1: an exactly collinear circular obstacle"),
        "2": ((human2,), "Sec. 7.5.2: a human walking head-on (synthetic walk)"),
        "3": ((circle3, rect), "Sec. 7.5.3: circle and rectangle"),
        "4": ((circle3, rect, human4), "Sec. 7.5.4: Configuration 3 plus the walking human"),
    }


def _multi() -> tuple[Obstacle, ...]:
    """Sec. 7.5.5: a circle, a human and another robot (start and goal assumed)."""
    reg = _CH7
    return (
        Disc("circle", RHO_CIR, *reg["circle"], motion=Stationary((4.1, 2.0))),
        _human(reg, ConstantVelocity((0.0, 0.6), (1.0, 0.0))),
        Disc("robot", RHO_MOB, *reg["robot"], motion=ConstantVelocity((3.0, 4.0), (0.0, -0.5))),
    )
