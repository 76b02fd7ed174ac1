"""A taut tether that snags on obstacle corners and keeps its history (Allan 2015 Sec. 4.5).

:func:`designlab.following.tether.snag.string` is the shortest string around one
convex corner. A real tether also keeps the way it was laid: a leader who walks
once round a pillar leaves the tether wrapped round it until the leader (or the
robot) walks back. :class:`WrappedTether` models that for any set of corner
points (the convex vertices of the obstacles): the string runs from the winch
through the corners it is wrapped on (snag points) to the tip; each control
period

* a corner swept over by the first or the last segment (inside the triangle
  between the segment's fixed end and the moving end's old and new positions)
  becomes a snag point, wrapped in the turning direction of the string there;
* a snag point whose turning direction has reversed (the string has come straight
  and would leave the corner) is released.

The moving ends should move less per period than the corners are apart (the
sweep catches the first corner it meets); the Sec. 4.5 steps are millimetres.
The measured length is the string's, the measured angle that of its first
segment, as in the corridor model (``docs/tether_modes.md``).

Examples
--------
>>> t = WrappedTether([(0.0, 0.0)], robot=(-1.0, -0.5), tip=(-0.2, -0.5))
>>> for y in (-0.3, 0.0, 0.3, 0.6):           # the tip goes round the corner
...     _ = t.update(robot=(-1.0, -0.5), tip=(0.5, y))
>>> t.snag_points, round(t.length, 6)
([(0.0, 0.0)], 1.899059)
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError

__all__ = ["WrappedTether", "convex_corners"]


def _cross(ax: float, ay: float, bx: float, by: float) -> float:
    return ax * by - ay * bx


def _turn(a: tuple[float, float], w: tuple[float, float], b: tuple[float, float]) -> float:
    """Turning direction of the path a -> w -> b (> 0: left)."""
    return _cross(w[0] - a[0], w[1] - a[1], b[0] - w[0], b[1] - w[1])


def convex_corners(polygon: Sequence[Sequence[float]]) -> list[tuple[float, float]]:
    """The convex vertices of a simple polygon (either orientation): where a tether can snag.

    Parameters
    ----------
    polygon
        Vertices ``[(x, y), ...]`` in m (at least 3).

    Examples
    --------
    >>> convex_corners([(0, 0), (2, 0), (2, 2), (1, 1), (0, 2)])
    [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)]
    """
    try:
        p = np.asarray(polygon, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameterError(
            "polygon", polygon, "at least 3 finite (x, y) vertices"
        ) from None
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 3 or not np.all(np.isfinite(p)):
        raise InvalidParameterError("polygon", polygon, "at least 3 finite (x, y) vertices")
    x, y = p[:, 0], p[:, 1]
    area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    if area == 0.0:
        raise InvalidParameterError("polygon", polygon, "a polygon with an area")
    out = []
    for i in range(len(p)):
        t = _turn(tuple(p[i - 1]), tuple(p[i]), tuple(p[(i + 1) % len(p)]))
        if t * area > 0.0:
            out.append((float(p[i, 0]), float(p[i, 1])))
    return out


def _inside(c: NDArray[np.float64], a: tuple[float, float], b: tuple[float, float],
            d: tuple[float, float]) -> NDArray[np.bool_]:  # fmt: skip
    """Corners strictly inside the triangle a, b, d."""
    area = _cross(b[0] - a[0], b[1] - a[1], d[0] - a[0], d[1] - a[1])
    if abs(area) < 1e-15:
        return np.zeros(len(c), dtype=bool)
    s = np.sign(area)
    e1 = s * ((b[0] - a[0]) * (c[:, 1] - a[1]) - (b[1] - a[1]) * (c[:, 0] - a[0]))
    e2 = s * ((d[0] - b[0]) * (c[:, 1] - b[1]) - (d[1] - b[1]) * (c[:, 0] - b[0]))
    e3 = s * ((a[0] - d[0]) * (c[:, 1] - d[1]) - (a[1] - d[1]) * (c[:, 0] - d[0]))
    return (e1 > 1e-12) & (e2 > 1e-12) & (e3 > 1e-12)


class WrappedTether:
    """A taut tether from a winch to a tip, wrapping corner points (its snag points).

    Parameters
    ----------
    corners
        Corner points ``[(x, y), ...]`` in m where the tether can snag (e.g. from
        :func:`convex_corners`).
    robot, tip
        Initial winch and tip positions in m (the straight line between them is
        taken to be free).
    """

    def __init__(
        self,
        corners: Sequence[Sequence[float]],
        robot: Sequence[float],
        tip: Sequence[float],
    ) -> None:
        try:
            c = np.asarray(corners, dtype=float).reshape(-1, 2)
        except (TypeError, ValueError):
            raise InvalidParameterError("corners", corners, "finite (x, y) points") from None
        if not np.all(np.isfinite(c)):
            raise InvalidParameterError("corners", corners, "finite (x, y) points")
        self.corners = c
        self.robot = self._point("robot", robot)
        self.tip = self._point("tip", tip)
        self._wraps: list[tuple[float, float, float]] = []  # (x, y, turning sign)

    @staticmethod
    def _point(name: str, p: Sequence[float]) -> tuple[float, float]:
        try:
            x, y = (float(v) for v in p)
        except (TypeError, ValueError):
            raise InvalidParameterError(name, p, "a point (x, y)") from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise InvalidParameterError(name, p, "a point (x, y) of finite numbers")
        return x, y

    @property
    def snag_points(self) -> list[tuple[float, float]]:
        """The corners the tether is wrapped on, from the winch to the tip."""
        return [(x, y) for x, y, _ in self._wraps]

    @property
    def nodes(self) -> list[tuple[float, float]]:
        """Winch, snag points, tip."""
        return [self.robot, *self.snag_points, self.tip]

    @property
    def length(self) -> float:
        """Length of the string in m (what the winch measures)."""
        n = self.nodes
        return float(sum(math.dist(a, b) for a, b in itertools.pairwise(n)))

    @property
    def direction(self) -> float:
        """Direction (rad) of the first segment, from the winch (what the angle sensor sees)."""
        a, b = self.nodes[0], self.nodes[1]
        return math.atan2(b[1] - a[1], b[0] - a[0])

    def _sweep(self, fixed: tuple[float, float], old: tuple[float, float],
               new: tuple[float, float]) -> tuple[float, float] | None:  # fmt: skip
        """The first corner the segment from ``fixed`` meets moving from ``old`` to ``new``."""
        hit = _inside(self.corners, fixed, old, new)
        if not hit.any():
            return None
        c = self.corners[hit]
        base = math.atan2(old[1] - fixed[1], old[0] - fixed[0])
        ang = np.abs(
            np.angle(np.exp(1j * (np.arctan2(c[:, 1] - fixed[1], c[:, 0] - fixed[0]) - base)))
        )
        k = int(np.argmin(ang))
        return float(c[k, 0]), float(c[k, 1])

    def _release(self) -> None:
        """Drop snag points where the string has come straight (turn reversed)."""
        changed = True
        while changed and self._wraps:
            changed = False
            nodes = self.nodes
            for i, (x, y, sign) in enumerate(self._wraps):
                if _turn(nodes[i], (x, y), nodes[i + 2]) * sign <= 0.0:
                    del self._wraps[i]
                    changed = True
                    break

    def update(self, robot: Sequence[float], tip: Sequence[float]) -> tuple[float, float]:
        """Move the winch and the tip; return the measured length (m) and direction (rad).

        Parameters
        ----------
        robot, tip
            New winch and tip positions in m.
        """
        robot, tip = self._point("robot", robot), self._point("tip", tip)
        first = self.nodes[1]
        c = self._sweep(first, self.robot, robot)
        self.robot = robot
        if c is not None:
            self._wraps.insert(0, (*c, _turn(robot, c, first)))
        last = self.nodes[-2]
        c = self._sweep(last, self.tip, tip)
        self.tip = tip
        if c is not None:
            self._wraps.append((*c, _turn(last, c, tip)))
        self._release()
        return self.length, self.direction
