"""Leader paths for the tether follower (Allan 2015 Sec. 2.4-2.5, 3.3-3.5, 4.5).

A :class:`LeaderPath` is a polyline in metres; the leader walks it at a
constant speed (Allan 2015 Sec. 2.4.1) and stops at its end. The thesis gives
only approximate shapes; the project fixes them (``docs/following.md``):

* :func:`figure_eight`: a Bernoulli lemniscate ``x = a cos t/(1 + sin^2 t)``,
  ``y = a sin t cos t/(1 + sin^2 t)`` from t = 0 (the right tip, heading +y,
  right lobe counter-clockwise first); a = 2 m is the "around 11 m" path of
  Fig. 2.7 and a = 4 m the "around 20 m" path of Sec. 2.5;
* :func:`square_s`: (0,0)-(2,0)-(4,0)-(4,2)-(2,2)-(2,4)-(4,4), 12 m (Fig. 2.8);
* :func:`slalom`: three cones 1.5 m apart, one way or out and back (Sec. 3.3, 3.5);
* :func:`corridor_corner`, :func:`straight_line`, :func:`circle`;
* :func:`from_array` and :func:`from_csv` for recorded walks.

Examples
--------
>>> p = figure_eight(a=2.0)
>>> round(p.length, 2), p.points[0].tolist(), p.start_heading
(10.49, [2.0, 0.0], 1.5707963267948966)
>>> round(square_s().length, 6)
12.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError, check_positive

__all__ = [
    "PATHS",
    "LeaderPath",
    "circle",
    "corridor_corner",
    "figure_eight",
    "from_array",
    "from_csv",
    "make_path",
    "slalom",
    "square_s",
    "straight_line",
]


@dataclass(frozen=True, eq=False)
class LeaderPath:
    """A leader path: an (N, 2) polyline in metres, N >= 2, finite, non-zero length.

    Consecutive duplicate points are dropped.

    Parameters
    ----------
    points
        Path nodes in m, shape (N, 2).
    name
        Label used in reports.
    obstacles
        Optional (K, 2) cone/obstacle positions in m (for plots).
    initial_heading
        Exact tangent direction at the start in rad (default: the first chord).
    """

    points: NDArray[np.float64]
    name: str = "path"
    obstacles: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 2)))
    initial_heading: float | None = None

    def __post_init__(self) -> None:
        try:
            pts = np.array(self.points, dtype=float)
        except (TypeError, ValueError):
            raise InvalidParameterError(
                "path.points", self.points, "an (N, 2) array of numbers", "m"
            ) from None
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise InvalidParameterError("path.points", f"shape {pts.shape}", "shape (N, 2)", "m")
        if pts.shape[0] < 2:
            raise InvalidParameterError(
                "path.points", f"{pts.shape[0]} point(s)", "at least 2 points", "m"
            )
        if not np.all(np.isfinite(pts)):
            bad = int(np.argwhere(~np.isfinite(pts))[0, 0])
            raise InvalidParameterError(
                f"path.points[{bad}]", pts[bad].tolist(), "finite coordinates", "m"
            )
        keep = np.ones(len(pts), bool)
        keep[1:] = np.any(np.diff(pts, axis=0) != 0.0, axis=1)
        pts = pts[keep]
        if len(pts) < 2:
            raise InvalidParameterError(
                "path.points", "all points equal", "a path of non-zero length", "m"
            )
        pts.setflags(write=False)
        obs = np.array(self.obstacles, dtype=float).reshape(-1, 2)
        obs.setflags(write=False)
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "obstacles", obs)
        s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
        s.setflags(write=False)
        object.__setattr__(self, "_s", s)

    @property
    def arc_length(self) -> NDArray[np.float64]:
        """Cumulative arc length at each node in m."""
        return self._s  # type: ignore[attr-defined,no-any-return]

    @property
    def length(self) -> float:
        """Total length in m."""
        return float(self.arc_length[-1])

    @property
    def start_heading(self) -> float:
        """Tangent direction at the start in rad (``initial_heading`` or the first chord)."""
        if self.initial_heading is not None:
            return float(self.initial_heading)
        d = self.points[1] - self.points[0]
        return float(math.atan2(d[1], d[0]))

    def position_at(self, s: Any) -> NDArray[np.float64]:
        """Points at arc length(s) ``s`` in m (clipped to the path), shape (..., 2)."""
        s = np.clip(np.asarray(s, dtype=float), 0.0, self.length)
        return np.stack(
            [
                np.interp(s, self.arc_length, self.points[:, 0]),
                np.interp(s, self.arc_length, self.points[:, 1]),
            ],
            axis=-1,
        )

    def leader_positions(
        self, speed: float, sample_time: float, duration: float
    ) -> NDArray[np.float64]:
        """Leader positions at ``t = k * sample_time`` for ``0 <= t <= duration``.

        The leader walks at ``speed`` (m/s) from the first point and stops at
        the last (Allan 2015 Sec. 2.4.1: a constant-speed leader).
        """
        n = math.floor(duration / sample_time + 1e-9) + 1
        return self.position_at(speed * sample_time * np.arange(n))

    def to_frame(self) -> Any:
        """The nodes as a DataFrame (``x_m``, ``y_m``, ``s_m``)."""
        import pandas as pd

        return pd.DataFrame(
            {"x_m": self.points[:, 0], "y_m": self.points[:, 1], "s_m": self.arc_length}
        )

    def __repr__(self) -> str:
        return f"LeaderPath({self.name!r}, {len(self.points)} points, {self.length:.2f} m)"


def figure_eight(a: float = 2.0, points: int = 2001) -> LeaderPath:
    """Bernoulli lemniscate figure-eight of loop parameter ``a`` (see ``docs/following.md``).

    Starts at the right tip (a, 0) heading +y; the right lobe is walked
    counter-clockwise first. The length is 5.2441 a (10.49 m for a = 2 m,
    20.98 m for a = 4 m; Allan 2015 Sec. 2.4 and 2.5 give "around 11 m" and
    "around 20 m").

    Parameters
    ----------
    a
        Loop parameter in m (> 0): half the tip-to-tip width.
    points
        Number of nodes (>= 9).

    Examples
    --------
    >>> round(figure_eight(a=4.0).length, 2)
    20.98
    """
    a = check_positive("figure_eight.a", a, "m")
    if isinstance(points, bool) or not isinstance(points, int) or points < 9:
        raise InvalidParameterError("figure_eight.points", points, "an integer >= 9")
    t = np.linspace(0.0, 2.0 * math.pi, points)
    d = 1.0 + np.sin(t) ** 2
    xy = np.column_stack([a * np.cos(t) / d, a * np.sin(t) * np.cos(t) / d])
    return LeaderPath(xy, name=f"figure_eight_a{a:g}", initial_heading=math.pi / 2)


def square_s(side: float = 2.0) -> LeaderPath:
    """Square-S polyline (0,0)-(2,0)-(4,0)-(4,2)-(2,2)-(2,4)-(4,4), scaled by ``side``/2 m.

    A lead-in of one side plus five sides with 90-degree left and right
    corners, 12 m for ``side = 2`` (Allan 2015 Fig. 2.8: "around 12 m").

    Parameters
    ----------
    side
        Side of each square in m (> 0).

    Examples
    --------
    >>> square_s().points.tolist()[3]
    [4.0, 2.0]
    """
    side = check_positive("square_s.side", side, "m")
    unit = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [1, 2], [2, 2]], dtype=float)
    return LeaderPath(unit * side, name="square_s")


def slalom(
    spacing: float = 1.5,
    cones: int = 3,
    amplitude: float = 0.5,
    out_and_back: bool = False,
    points_per_metre: int = 100,
) -> LeaderPath:
    """Cone slalom: weave past ``cones`` cones in a line (Allan 2015 Sec. 3.3, 3.5).

    Cones stand at x = spacing, 2 spacing, ... on y = 0. The leader walks
    ``y = -amplitude cos(pi x / spacing)`` from x = 0 to (cones + 1) spacing,
    passing each cone at ``amplitude`` on alternate sides. With
    ``out_and_back`` it turns on a half circle of radius ``amplitude`` around
    the end point and walks back past each cone on the other side (the
    thesis's "from one end to the other and back"; about 16 m with the
    defaults, the patients' 16-18 m). The weave amplitude is not in the
    thesis; it is a scenario parameter.

    Parameters
    ----------
    spacing
        Distance between cones in m (> 0).
    cones
        Number of cones (>= 1).
    amplitude
        Lateral distance at which the leader passes each cone, m (> 0).
    out_and_back
        Turn around after the last cone and weave back.
    points_per_metre
        Polyline resolution.

    Examples
    --------
    >>> round(slalom().length, 2), round(slalom(out_and_back=True).length, 2)
    (7.41, 16.38)
    """
    spacing = check_positive("slalom.spacing", spacing, "m")
    amplitude = check_positive("slalom.amplitude", amplitude, "m")
    if isinstance(cones, bool) or not isinstance(cones, int) or cones < 1:
        raise InvalidParameterError("slalom.cones", cones, "an integer >= 1")
    span = (cones + 1) * spacing
    n = max(int(span * points_per_metre), 50)
    x = np.linspace(0.0, span, n)
    y = -amplitude * np.cos(math.pi * x / spacing)
    xy = np.column_stack([x, y])
    y_end = y[-1]
    if out_and_back:
        # half circle around (span, 0) from (span, y_end) to (span, -y_end)
        sgn = 1.0 if y_end < 0 else -1.0
        ang = np.linspace(-math.pi / 2, math.pi / 2, 60)[1:-1]
        arc = np.column_stack([span + amplitude * np.cos(ang), sgn * amplitude * np.sin(ang)])
        back = np.column_stack([x[::-1], -y[::-1]])
        xy = np.vstack([xy, arc, back])
    cone_xy = np.column_stack([spacing * np.arange(1, cones + 1), np.zeros(cones)])
    name = "slalom_out_and_back" if out_and_back else "slalom"
    return LeaderPath(xy, name=name, obstacles=cone_xy, initial_heading=0.0)


def corridor_corner(
    width: float = 1.0, leg: float = 3.0, radius: float | None = None
) -> LeaderPath:
    """Centre line of a corridor with one 90-degree left corner (Allan 2015 Sec. 4.5).

    Straight ``leg`` along +x, an arc of ``radius`` (default 0.5 ``width``,
    Sec. 4.5.1) centred on the inner corner vertex, then ``leg`` along +y.

    Parameters
    ----------
    width
        Corridor width in m (> 0).
    leg
        Length of each straight leg in m (> 0).
    radius
        Radius of the corner arc in m (default: half the width).

    Examples
    --------
    >>> round(corridor_corner().length, 4)
    6.7854
    """
    width = check_positive("corridor_corner.width", width, "m")
    leg = check_positive("corridor_corner.leg", leg, "m")
    r = 0.5 * width if radius is None else check_positive("corridor_corner.radius", radius, "m")
    straight1 = np.column_stack([np.linspace(0.0, leg, 50), np.zeros(50)])
    ang = np.linspace(-math.pi / 2, 0.0, 40)
    arc = np.column_stack([leg + r * np.cos(ang), r + r * np.sin(ang)])
    straight2 = np.column_stack([np.full(50, leg + r), r + np.linspace(0.0, leg, 50)])
    return LeaderPath(np.vstack([straight1, arc[1:], straight2[1:]]), name="corridor_corner")


def straight_line(length: float = 10.0) -> LeaderPath:
    """A straight line of ``length`` m along +x from the origin.

    Parameters
    ----------
    length
        Length in m (> 0).

    Examples
    --------
    >>> straight_line(5.0).length
    5.0
    """
    length = check_positive("straight_line.length", length, "m")
    return LeaderPath(np.array([[0.0, 0.0], [length, 0.0]]), name="straight_line")


def circle(radius: float = 2.0, turns: float = 1.0, points_per_turn: int = 720) -> LeaderPath:
    """A counter-clockwise circle of ``radius`` m about the origin, from (radius, 0), heading +y.

    Parameters
    ----------
    radius
        Circle radius in m (> 0).
    turns
        Number of turns (> 0).
    points_per_turn
        Polyline points per turn.

    Examples
    --------
    >>> round(circle(1.0).length, 3)
    6.283
    """
    radius = check_positive("circle.radius", radius, "m")
    turns = check_positive("circle.turns", turns, "")
    n = max(int(points_per_turn * turns), 8) + 1
    t = np.linspace(0.0, 2.0 * math.pi * turns, n)
    return LeaderPath(
        np.column_stack([radius * np.cos(t), radius * np.sin(t)]),
        name=f"circle_r{radius:g}",
        initial_heading=math.pi / 2,
    )


def from_array(xy: Any, name: str = "recorded") -> LeaderPath:
    """A user path from an (N, 2) array of points in m.

    Parameters
    ----------
    xy
        (N, 2) points in m (or a :class:`LeaderPath`).
    name
        Name of the path in reports.

    Examples
    --------
    >>> from_array([[0, 0], [1, 0], [1, 1]]).length
    2.0
    >>> from_array([[0, 0], [float("nan"), 1]])
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: path.points[1] = [nan, 1.0] m is not allowed: ...
    """
    return LeaderPath(xy.points if isinstance(xy, LeaderPath) else xy, name=name)


def from_csv(
    file: str | Path, x: str = "x_m", y: str = "y_m", name: str | None = None
) -> LeaderPath:
    """A user path from a CSV of a recorded walk (columns ``x`` and ``y`` in m).

    Parameters
    ----------
    file
        CSV file with a header row.
    x, y
        Column names (default ``x_m``, ``y_m``).
    name
        Label (default: the file stem).
    """
    import pandas as pd

    frame = pd.read_csv(file)
    for col in (x, y):
        if col not in frame.columns:
            raise InvalidParameterError("from_csv column", col, f"one of {list(frame.columns)}")
    return LeaderPath(frame[[x, y]].to_numpy(float), name=name or Path(file).stem)


#: Path constructors by name (as used in study files).
PATHS = {
    "figure_eight": figure_eight,
    "square_s": square_s,
    "slalom": slalom,
    "corridor_corner": corridor_corner,
    "straight_line": straight_line,
    "circle": circle,
}


def make_path(spec: Any) -> LeaderPath:
    """A path from a name, ``{"type": name, **args}``, ``{"points": [...]}`` or (N, 2) points.

    Parameters
    ----------
    spec
        A path name, ``{"type": name, **args}``, ``{"points": [...]}``, (N, 2)
        points or a :class:`LeaderPath`.

    Examples
    --------
    >>> make_path({"type": "figure_eight", "a": 4.0}).name
    'figure_eight_a4'
    """
    if isinstance(spec, LeaderPath):
        return spec
    if isinstance(spec, (list, tuple, np.ndarray)):
        return from_array(spec)
    if isinstance(spec, str):
        spec = {"type": spec}
    spec = dict(spec)
    if "points" in spec:
        return from_array(spec["points"], name=spec.get("name", "recorded"))
    if "csv" in spec:
        return from_csv(spec.pop("csv"), **spec)
    kind = spec.pop("type", None)
    if kind not in PATHS:
        raise InvalidParameterError("path.type", kind, f"one of {sorted(PATHS)}")
    return PATHS[kind](**spec)  # type: ignore[operator,no-any-return]
