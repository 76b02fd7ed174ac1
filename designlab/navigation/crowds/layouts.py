"""The four crowd layouts: walkable area, walls, pedestrian streams, robot start and goal.

Every layout is axis-aligned and built from its ``length`` L (along x) and ``width`` W
(across), with its lower-left corner at the origin:

``corridor_counterflow``
    A corridor [0, L] x [0, W] between two walls, closed at its ends; half the pedestrians
    walk +x, half -x. The robot goes from (1.5, W/2) to (L - 1.5, W/2).
``crossing``
    Two corridors of width W crossing at right angles in a square of side L (a plus
    shape; the four corner blocks and the four arms' ends are the walls); one stream walks
    -x (against the robot), one +y (across its path). The robot goes from (1.5, L/2) to
    (L - 1.5, L/2).
``bottleneck``
    The closed corridor with a 1 m long constriction of width ``bottleneck_width`` at x = L/2
    (two blocks against the walls); every pedestrian walks +x through it and the robot
    comes the other way, from (L - 1.5, W/2) to (1.5, W/2).
``open_plaza``
    A walled plaza [0, L] x [0, W] crossed by four streams (+x, -x, +y, -y); the robot
    crosses it diagonally from (1.5, 1.5) to (L - 1.5, W - 1.5).

The arena is sealed: every layout's walkable area is closed by walls, its ends too (the
robot cannot leave it through an end; a run whose robot leaves the area all the same ends
there with the outcome ``left_area``). Pedestrians leave through their exit strips, inside
the area, as if through a door the robot cannot take.

Pedestrians are placed over the whole walkable area at t = 0 (outside the robot's
clearance disc and the exits); a pedestrian reaching its exit strip (0.4 m deep, at the
far end of its stream) leaves the simulation and a new one enters its stream's spawn
strip (1 m deep, at the near end), so the crowd keeps its size.

Examples
--------
>>> lay = build_layout("corridor_counterflow", length=30.0, width=4.0)
>>> lay.area.area, len(lay.walls), lay.start, lay.goal
(120.0, 4, (1.5, 2.0), (28.5, 2.0))
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from shapely.geometry import Polygon, box
from shapely.ops import unary_union

__all__ = ["LAYOUTS", "Layout", "Stream", "build_layout"]

#: Depth of the strip where a stream's pedestrians leave, m.
EXIT_DEPTH = 0.4
#: Depth of the strip where a stream's replacements enter, m.
SPAWN_DEPTH = 1.0
#: Distance of the robot's start and goal from the ends of its path, m.
END_MARGIN = 1.5
#: Thickness of the walls modelled for the robot (outside the walkable area), m.
WALL_THICKNESS = 0.2


@dataclass(frozen=True)
class Stream:
    """A pedestrian stream: where it enters and where it leaves.

    Attributes
    ----------
    spawn
        Where replacements enter (a polygon inside the walkable area).
    exit
        Where its pedestrians leave (a polygon inside the walkable area).
    share
        Fraction of the crowd in this stream.
    """

    spawn: Polygon
    exit: Polygon
    share: float


@dataclass(frozen=True)
class Layout:
    """The geometry of a crowd scenario.

    Attributes
    ----------
    area
        The walkable area (a shapely polygon) given to the pedestrian simulator.
    walls
        Axis-aligned wall blocks ``((x_min, y_min), (x_max, y_max))``: the robot's static
        rectangular obstacles, outside (or bounding) the walkable area.
    streams
        The pedestrian streams.
    start, goal
        The robot's start and goal, m.
    """

    area: Polygon
    walls: tuple[tuple[tuple[float, float], tuple[float, float]], ...]
    streams: tuple[Stream, ...]
    start: tuple[float, float]
    goal: tuple[float, float]


def _strip(x0: float, y0: float, x1: float, y1: float) -> Polygon:
    return box(min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1))


def _long_walls(L: float, W: float) -> tuple:
    t = WALL_THICKNESS
    return (((-t, -t), (L + t, 0.0)), ((-t, W), (L + t, W + t)))


def _end_walls(L: float, y0: float, y1: float) -> tuple:
    """The walls closing the ends x = 0 and x = L of a corridor spanning [y0, y1]."""
    t = WALL_THICKNESS
    return (((-t, y0), (0.0, y1)), ((L, y0), (L + t, y1)))


def _x_streams(L: float, W: float, y0: float = 0.0) -> tuple[Stream, Stream]:
    """A +x and a -x stream along [0, L] x [y0, y0 + W]."""
    east = Stream(_strip(0.0, y0, SPAWN_DEPTH, y0 + W), _strip(L - EXIT_DEPTH, y0, L, y0 + W), 0.5)
    west = Stream(_strip(L - SPAWN_DEPTH, y0, L, y0 + W), _strip(0.0, y0, EXIT_DEPTH, y0 + W), 0.5)
    return east, west


def corridor_counterflow(length: float, width: float, bottleneck_width: float = 0.0) -> Layout:
    """A corridor with two opposing streams."""
    L, W = length, width
    return Layout(
        box(0.0, 0.0, L, W),
        (*_long_walls(L, W), *_end_walls(L, 0.0, W)),
        _x_streams(L, W),
        (END_MARGIN, W / 2),
        (L - END_MARGIN, W / 2),
    )


def crossing(length: float, width: float, bottleneck_width: float = 0.0) -> Layout:
    """Two corridors crossing at right angles; the robot meets one stream and crosses the other."""
    L, W, t = length, width, WALL_THICKNESS
    c0, c1 = L / 2 - W / 2, L / 2 + W / 2
    area = unary_union([box(0.0, c0, L, c1), box(c0, 0.0, c1, L)])
    walls = (
        ((0.0, 0.0), (c0, c0)),
        ((c1, 0.0), (L, c0)),
        ((0.0, c1), (c0, L)),
        ((c1, c1), (L, L)),
        *_end_walls(L, c0 - t, c1 + t),  # over the corners too: no gap at an arm's end
        ((c0 - t, -t), (c1 + t, 0.0)),
        ((c0 - t, L), (c1 + t, L + t)),
    )
    _east, west = _x_streams(L, W, c0)
    north = Stream(_strip(c0, 0.0, c1, SPAWN_DEPTH), _strip(c0, L - EXIT_DEPTH, c1, L), 0.5)
    west = Stream(west.spawn, west.exit, 0.5)
    return Layout(area, walls, (west, north), (END_MARGIN, L / 2), (L - END_MARGIN, L / 2))


def bottleneck(length: float, width: float, bottleneck_width: float = 1.2) -> Layout:
    """A corridor with a constriction at mid-length; the robot goes against the stream."""
    L, W, b = length, width, bottleneck_width
    x0, x1 = L / 2 - 0.5, L / 2 + 0.5
    lower, upper = box(x0, 0.0, x1, (W - b) / 2), box(x0, (W + b) / 2, x1, W)
    area = box(0.0, 0.0, L, W).difference(unary_union([lower, upper]))
    walls = (
        *_long_walls(L, W),
        *_end_walls(L, 0.0, W),
        ((x0, 0.0), (x1, (W - b) / 2)),
        ((x0, (W + b) / 2), (x1, W)),
    )
    east, _west = _x_streams(L, W)
    return Layout(
        area,
        walls,
        (Stream(east.spawn, east.exit, 1.0),),
        (L - END_MARGIN, W / 2),
        (END_MARGIN, W / 2),
    )


def open_plaza(length: float, width: float, bottleneck_width: float = 0.0) -> Layout:
    """A walled plaza crossed by four streams; the robot crosses it diagonally."""
    L, W = length, width
    walls = (*_long_walls(L, W), *_end_walls(L, 0.0, W))
    east, west = _x_streams(L, W)
    north = Stream(_strip(0.0, 0.0, L, SPAWN_DEPTH), _strip(0.0, W - EXIT_DEPTH, L, W), 0.25)
    south = Stream(_strip(0.0, W - SPAWN_DEPTH, L, W), _strip(0.0, 0.0, L, EXIT_DEPTH), 0.25)
    streams = (Stream(east.spawn, east.exit, 0.25), Stream(west.spawn, west.exit, 0.25))
    return Layout(
        box(0.0, 0.0, L, W),
        walls,
        (*streams, north, south),
        (END_MARGIN, END_MARGIN),
        (L - END_MARGIN, W - END_MARGIN),
    )


#: The layouts by name.
LAYOUTS: dict[str, Callable[..., Layout]] = {
    "corridor_counterflow": corridor_counterflow,
    "crossing": crossing,
    "bottleneck": bottleneck,
    "open_plaza": open_plaza,
}


def build_layout(
    name: str, *, length: float, width: float, bottleneck_width: float = 1.2
) -> Layout:
    """The layout ``name`` for a length and width (checked by the caller).

    Parameters
    ----------
    name
        One of :data:`LAYOUTS`.
    length, width
        L and W in m.
    bottleneck_width
        Width of the bottleneck's constriction in m (``"bottleneck"`` only).
    """
    return LAYOUTS[name](length, width, bottleneck_width)
