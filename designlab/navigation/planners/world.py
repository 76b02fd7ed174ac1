"""What a planner sees at one instant: the obstacles' positions and velocities, inflated.

The robot is a point in configuration space: a disc obstacle grows by the robot's
radius to rho_o + rho_r, a rectangle by rho_r. The planners of Sec. 5.7 see the
present only (the human's future motion is unpredictable, Zeng 2011 Sec. 5.2).

Examples
--------
>>> from designlab.navigation import configuration
>>> w = Snapshot.of(configuration(1), 0.0)
>>> round(float(w.clearance([[2.45, 0.0]])[0]), 3)   # 0.595 from the circle, minus 0.3
0.295
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from designlab.navigation.scenarios import Disc, Rectangle, Scenario

__all__ = ["Snapshot"]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Snapshot:
    """Obstacles at one instant, inflated by the robot radius.

    Attributes
    ----------
    centres, velocities, radii
        Discs: ``(n, 2)`` centres (m), velocities (m/s) and inflated radii rho_o + rho_r (m).
    accelerations
        Discs: ``(n, 2)`` accelerations (m/s^2), what the NLVO extrapolates with.
    rectangles
        The scenario's rectangles (static).
    robot_radius
        rho_r in m.
    """

    centres: Array
    velocities: Array
    radii: Array
    rectangles: tuple[Rectangle, ...]
    robot_radius: float
    accelerations: Array | None = None

    @classmethod
    def of(cls, scenario: Scenario, t: float) -> Snapshot:
        """The scenario's obstacles at time ``t`` (s)."""
        discs = [o for o in scenario.obstacles if isinstance(o, Disc)]
        rho = scenario.robot.radius
        c, v, a = (np.zeros((len(discs), 2)) for _ in range(3))
        for i, o in enumerate(discs):
            p, vel, acc = o.state(np.array([t]))
            c[i], v[i], a[i] = p[0], vel[0], acc[0]
        radii = np.array([o.radius + rho for o in discs])
        rects = tuple(o for o in scenario.obstacles if isinstance(o, Rectangle))
        return cls(c, v, radii, rects, rho, a)

    def clearance(self, points: Sequence[Sequence[float]] | Array) -> Array:
        """Configuration-space clearance of points ``(n, 2)`` (m; <= 0: in collision)."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        out = np.full(p.shape[0], np.inf)
        if self.radii.size:
            d = np.hypot(p[:, None, 0] - self.centres[None, :, 0],
                         p[:, None, 1] - self.centres[None, :, 1])  # fmt: skip
            out = np.minimum(out, (d - self.radii[None, :]).min(axis=1))
        for r in self.rectangles:
            out = np.minimum(out, r.contour_distance(p) - self.robot_radius)
        return out

    def segment_free(self, a: Array, b: Array, spacing: float = 0.02) -> bool:
        """Whether the straight segment from ``a`` to ``b`` keeps a positive clearance."""
        n = max(2, int(np.ceil(np.hypot(*(b - a)) / spacing)) + 1)
        s = np.linspace(0.0, 1.0, n)[:, None]
        return bool(np.all(self.clearance(a[None, :] + s * (b - a)[None, :]) > 0))
