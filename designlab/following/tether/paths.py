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
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.params import ARG, Param, check_size, declared, param

__all__ = [
    "PATHS",
    "SHAPE_PARAMETERS",
    "LeaderPath",
    "circle",
    "corridor_corner",
    "figure_eight",
    "from_array",
    "from_csv",
    "make_path",
    "slalom",
    "smooth_walk",
    "square_s",
    "straight_line",
]


def _arg(symbol: str | None, unit: str, doc: str, name: str, **kw: Any) -> Param:
    return Param(symbol, unit, doc, name=name, **kw)


#: The arguments of the path shapes, declared once: shape -> argument -> declaration. The
#: caps keep a path within 10 km and 10**6 nodes (``docs/following.md``, "Limits").
SHAPE_PARAMETERS: dict[str, dict[str, Param]] = {
    "figure_eight": {
        "a": _arg(
            "a",
            "m",
            "loop parameter: half the tip-to-tip width",
            "figure_eight.a",
            gt=0,
            le=100,
            typical=(2.0, 4.0),
            default=2.0,
        ),
        "points": _arg(
            None,
            "",
            "number of nodes",
            "figure_eight.points",
            kind="integer",
            ge=9,
            le=1_000_000,
            default=2001,
        ),
    },
    "square_s": {
        "side": _arg(None, "m", "side of each square", "square_s.side", gt=0, le=100, default=2.0),
    },
    "slalom": {
        "spacing": _arg(
            None, "m", "distance between cones", "slalom.spacing", gt=0, le=100, default=1.5
        ),
        "cones": _arg(
            None, "", "number of cones", "slalom.cones", kind="integer", ge=1, le=50, default=3
        ),
        "amplitude": _arg(
            "A",
            "m",
            "lateral distance at which the leader passes each cone",
            "slalom.amplitude",
            gt=0,
            le=10,
            default=0.5,
        ),
        "out_and_back": _arg(
            None,
            "",
            "turn around after the last cone and weave back",
            "slalom.out_and_back",
            kind="flag",
            default=False,
        ),
        "points_per_metre": _arg(
            None,
            "1/m",
            "polyline resolution",
            "slalom.points_per_metre",
            kind="integer",
            ge=1,
            le=10_000,
            default=100,
        ),
    },
    "corridor_corner": {
        "width": _arg(
            "w", "m", "corridor width", "corridor_corner.width", gt=0, le=100, default=1.0
        ),
        "leg": _arg(
            None,
            "m",
            "length of each straight leg",
            "corridor_corner.leg",
            gt=0,
            le=1000,
            default=3.0,
        ),
        "radius": _arg(
            None,
            "m",
            "radius of the corner arc",
            "corridor_corner.radius",
            gt=0,
            le=100,
            optional=True,
            none="half the width (Sec. 4.5.1)",
        ),
    },
    "straight_line": {
        "length": _arg(None, "m", "length", "straight_line.length", gt=0, le=1e4, default=10.0),
    },
    "circle": {
        "radius": _arg("R", "m", "circle radius", "circle.radius", gt=0, le=100, default=2.0),
        "turns": _arg(None, "", "number of turns", "circle.turns", gt=0, le=10, default=1.0),
        "points_per_turn": _arg(
            None,
            "",
            "polyline points per turn",
            "circle.points_per_turn",
            kind="integer",
            ge=8,
            le=100_000,
            default=720,
        ),
    },
    "smooth_walk": {
        "seed": _arg(
            None,
            "",
            "seed of the random draw",
            "smooth_walk.seed",
            kind="integer",
            ge=0,
            le=2**31 - 1,
            default=0,
        ),
        "length": _arg(None, "m", "length", "smooth_walk.length", gt=0, le=1000, default=12.0),
        "max_curvature": _arg(
            None,
            "1/m",
            "largest curvature (smallest turning radius 1/max_curvature)",
            "smooth_walk.max_curvature",
            gt=0,
            le=10,
            default=1.0,
        ),
    },
}


def _checked(shape: str, **values: Any) -> dict[str, Any]:
    """The arguments of a shape, each checked against its declaration."""
    decls = SHAPE_PARAMETERS[shape]
    return {k: decls[k].check(v) for k, v in values.items()}


@declared
@dataclass(frozen=True, eq=False)
class LeaderPath:
    """A leader path: an (N, 2) polyline in metres, N >= 2, finite, non-zero length.

    Consecutive duplicate points are dropped.
    """

    points: NDArray[np.float64] = param(  # noqa: RUF009
        kind="object", doc="path nodes in m, shape (N, 2), at most 10**6"
    )
    name: str = param(
        kind="text", doc="label used in reports", default="path", min_length=1, max_length=60
    )
    obstacles: NDArray[np.float64] = param(  # noqa: RUF009
        kind="object",
        doc="cone/obstacle positions in m, shape (K, 2), for plots",
        default_factory=lambda: np.zeros((0, 2)),
    )
    initial_heading: float | None = param(
        None,
        "rad",
        doc="exact tangent direction at the start",
        ge=-100,
        le=100,
        optional=True,
        none="the direction of the first chord",
        default=None,
    )

    def __post_init__(self) -> None:
        pts = _polyline("path.points", self.points, limit=1_000_000)
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
    args = _checked("figure_eight", a=a, points=points)
    a, points = args["a"], args["points"]
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
    side = _checked("square_s", side=side)["side"]
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
    args = _checked(
        "slalom",
        spacing=spacing,
        cones=cones,
        amplitude=amplitude,
        out_and_back=out_and_back,
        points_per_metre=points_per_metre,
    )
    spacing, cones, amplitude = args["spacing"], args["cones"], args["amplitude"]
    span = (cones + 1) * spacing
    n = max(int(span * args["points_per_metre"]), 50)
    check_size("slalom.points_per_metre", points_per_metre, 4 * n, what="the slalom's nodes")
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
    args = _checked("corridor_corner", width=width, leg=leg, radius=radius)
    width, leg = args["width"], args["leg"]
    r = 0.5 * width if args["radius"] is None else args["radius"]
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
    length = _checked("straight_line", length=length)["length"]
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
    args = _checked("circle", radius=radius, turns=turns, points_per_turn=points_per_turn)
    radius, turns, points_per_turn = args["radius"], args["turns"], args["points_per_turn"]
    n = max(int(points_per_turn * turns), 8) + 1
    t = np.linspace(0.0, 2.0 * math.pi * turns, n)
    return LeaderPath(
        np.column_stack([radius * np.cos(t), radius * np.sin(t)]),
        name=f"circle_r{radius:g}",
        initial_heading=math.pi / 2,
    )


def smooth_walk(
    seed: int = ARG.seed.default, length: float = 12.0, max_curvature: float = 1.0
) -> LeaderPath:
    """A random smooth walk: seeded straight pieces and arcs, |curvature| <= ``max_curvature``.

    Pieces of 1-3 m, each straight (one in three) or an arc of curvature drawn
    uniformly in [-max_curvature, max_curvature], from
    ``numpy.random.default_rng(seed)``; the curvature is smoothed over 0.5 m
    (continuous, as a walker turns) and integrated (100 nodes per metre) from
    the origin, in a start direction also drawn from the seed. The seed names
    the walk (``smooth_walk_s<seed>``), so tuning and validation draws can be
    kept apart.

    Parameters
    ----------
    seed
        Seed of the draw (>= 0).
    length
        Length in m.
    max_curvature
        Largest curvature in 1/m.

    Examples
    --------
    >>> w = smooth_walk(seed=3)
    >>> w.name, round(w.length, 3)
    ('smooth_walk_s3', 12.0)
    """
    args = _checked("smooth_walk", seed=seed, length=length, max_curvature=max_curvature)
    rng = np.random.default_rng(args["seed"])
    n = max(int(100 * args["length"]), 10) + 1
    s = np.linspace(0.0, args["length"], n)
    kappa = np.zeros(n)
    start = 0.0
    while start < args["length"]:  # pieces of 1-3 m: straight (1 in 3) or an arc
        stop = start + rng.uniform(1.0, 3.0)
        turn = 0.0 if rng.uniform() < 1 / 3 else rng.uniform(-1.0, 1.0)
        kappa[(s >= start) & (s < stop)] = turn * args["max_curvature"]
        start = stop
    box = np.ones(51) / 51  # a 0.5 m moving average: continuous curvature
    kappa = np.convolve(np.pad(kappa, 25, mode="edge"), box, mode="valid")
    ds = np.diff(s)
    start_heading = rng.uniform(-math.pi, math.pi)
    heading = start_heading + np.concatenate(
        [[0.0], np.cumsum(0.5 * (kappa[1:] + kappa[:-1]) * ds)]
    )
    mid = 0.5 * (heading[1:] + heading[:-1])
    xy = np.vstack(
        [[0.0, 0.0], np.cumsum(np.column_stack([np.cos(mid), np.sin(mid)]) * ds[:, None], axis=0)]
    )
    return LeaderPath(xy, name=f"smooth_walk_s{args['seed']}", initial_heading=start_heading)


def _polyline(name: str, xy: Any, *, limit: int) -> NDArray[np.float64]:
    """``xy`` as a finite (N, 2) float array, 2 <= N <= ``limit``, or raise naming ``name``."""
    n = int(np.size(xy)) if isinstance(xy, np.ndarray) else None
    if n is not None and n > 2 * limit:
        raise InvalidParameterError(name, f"{n // 2} points", f"at most {limit} points", "m")
    try:
        pts = np.array(xy, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameterError(name, xy, "an (N, 2) array of numbers", "m") from None
    if pts.ndim != 2 or pts.shape[1] != 2:
        shown = pts.tolist() if pts.size <= 8 else f"shape {pts.shape}"
        raise InvalidParameterError(name, shown, f"shape (N, 2), not {pts.shape}", "m")
    if not 2 <= pts.shape[0] <= limit:
        raise InvalidParameterError(
            name, f"{pts.shape[0]} point(s)", f"at least 2 and at most {limit} points", "m"
        )
    if not np.all(np.isfinite(pts)):
        bad = int(np.argwhere(~np.isfinite(pts))[0, 0])
        raise InvalidParameterError(f"{name}[{bad}]", pts[bad].tolist(), "finite coordinates", "m")
    return pts


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


def _read_csv(file: str | Path) -> Any:
    """The CSV as a DataFrame, or an error naming the file."""
    import pandas as pd

    try:
        return pd.read_csv(file)
    except pd.errors.EmptyDataError:
        raise InvalidParameterError("file", str(file), "a CSV file with a header row") from None
    except (pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise InvalidParameterError("file", str(file), f"a readable CSV file ({exc})") from None


def _numeric_column(frame: Any, column: str, file: str | Path) -> NDArray[np.float64]:
    """One column of numbers, or an error naming the file, line and column of the first bad cell."""
    import pandas as pd

    values = pd.to_numeric(frame[column], errors="coerce").to_numpy(float)
    bad = np.flatnonzero(~np.isfinite(values))
    if len(bad):
        i = int(bad[0])
        where = f"{Path(file).name} line {i + 2} (data row {i + 1}), column {column!r}"
        raise InvalidParameterError(where, frame[column].iloc[i], "a finite number", "m")
    return values


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

    Examples
    --------
    >>> import os, tempfile
    >>> f = os.path.join(tempfile.mkdtemp(), "walk.csv")
    >>> _ = open(f, "w").write(chr(10).join(["x_m,y_m", "0,0", "1,0", "far,1"]))
    >>> from_csv(f)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: walk.csv line 4 (data row 3), column 'x_m' = 'far' m ...
    """
    frame = _read_csv(file)
    for col in (x, y):
        if col not in frame.columns:
            raise InvalidParameterError(
                f"{Path(file).name} column", col, f"one of {list(frame.columns)}"
            )
    xy = np.column_stack([_numeric_column(frame, c, file) for c in (x, y)])
    return LeaderPath(xy, name=name or Path(file).stem)


#: Path constructors by name (as used in study files).
PATHS = {
    "figure_eight": figure_eight,
    "square_s": square_s,
    "slalom": slalom,
    "corridor_corner": corridor_corner,
    "straight_line": straight_line,
    "circle": circle,
    "smooth_walk": smooth_walk,
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
    if not isinstance(spec, dict):
        raise InvalidParameterError("path", spec, "a LeaderPath, a path name, a dict or points")
    spec = dict(spec)
    if "points" in spec:
        return from_array(spec["points"], name=spec.get("name", "recorded"))
    if "csv" in spec:
        return from_csv(spec.pop("csv"), **spec)
    kind = spec.pop("type", None)
    if kind not in PATHS:
        raise InvalidParameterError("path.type", kind, f"one of {sorted(PATHS)}")
    unknown = sorted(set(spec) - set(SHAPE_PARAMETERS[kind]))
    if unknown:
        raise InvalidParameterError(
            f"path.{unknown[0]}",
            spec[unknown[0]],
            f"an argument of {kind}: {list(SHAPE_PARAMETERS[kind])}",
        )
    return PATHS[kind](**spec)  # type: ignore[operator,no-any-return]
