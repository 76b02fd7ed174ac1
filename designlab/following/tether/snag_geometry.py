"""Closed-form snagging limits of the constant-speed follower (Allan 2015 Sec. 4.5, Table 4.1).

With the thesis's follower (constant ``v_F`` along the recorded path, the leader at the same
speed) the robot is still on the undistorted straight before the corner while the string
is wrapped: it is exactly ``g_F`` behind the leader along the true path. The distorted
recorded path is then geometry alone, and so are the limits. Coordinates over ``w``, the
inner vertex at the origin: the leader at ``(1/2, y)`` on the second leg, the winch at
``(-q, -1/2)`` on the first with ``q = g_F - e - pi/4 - y`` (``e``: the winch ahead of the
robot centre). The string wraps the vertex exactly when ``q y > 1/4``; while it does, the
estimated tip (winch + ``l_m`` along the first segment, eq. 2.14) lies at

``x_tip(y) = -q + l_m q / sqrt(q^2 + 1/4)``,  ``l_m = sqrt(L^2 + h^2)``,
``L = sqrt(1/4 + y^2) + sqrt(q^2 + 1/4)``

(``h``: the tether's height difference, 0 in a planar model). The robot later drives
through these points, so its least distance to the outer wall is ``d_col = 1 - max x_tip``
(at most 1/2, the centre line). The first snag needs ``g_F - e >= 1 + pi/4``. With
``h > 0`` the estimate also overshoots a little where the string is straight (by about
``h^2 / 2 l``, and by at least ``h`` near a stopped leader); that part is not in the closed
form, which holds at the collision and wall limits (the hump of the wrapped part).

The kinematic simulation (:func:`designlab.following.tether.snag.simulate_snag`) converges
to these values, so the time step, the follower's step, the straight lengths and the
release criterion cannot move its limits (``docs/tether_modes.md``, Snagging).

Examples
--------
>>> lim = constant_speed_limits()
>>> round(lim["first_snag"], 4), round(lim["collision"], 4), round(lim["wall"], 4)
(1.7854, 2.294, 2.5871)
"""

from __future__ import annotations

import math

from scipy.optimize import brentq, minimize_scalar

from designlab.errors import InvalidParameterError
from designlab.params import Param

__all__ = ["SNAG_GEOMETRY_RADIUS", "constant_speed_d_col", "constant_speed_limits"]

_QUARTER = 0.25 * math.pi
#: Winch offset and tether height over w (the closed form's range).
_OFFSET = Param(
    "e/w", "", "winch ahead of the robot centre, over w", ge=-1, le=1, name="winch_offset"
)
_HEIGHT = Param("h/w", "", "tether height difference, over w", ge=0, le=2, name="tether_height")
_GAP = Param("g_F/w", "", "following gap along the path, over w", gt=0, le=50, name="gap")
#: Bounding-circle radius over w at which the collision limit is taken (Sec. 4.5.4).
SNAG_GEOMETRY_RADIUS = Param(
    "r_col/w", "", "bounding-circle radius over w", ge=0, lt=0.5, default=0.2, name="r_col"
)


def _max_tip(g: float, e: float, h: float) -> float:
    big = g - e - _QUARTER
    if big <= 1.0:  # the chord never reaches the vertex
        return 0.5
    root = math.sqrt(big * big - 1.0)
    y1, y2 = 0.5 * (big - root), 0.5 * (big + root)

    def tip(y: float) -> float:
        q = big - y
        arm = math.hypot(q, 0.5)
        lm = math.hypot(math.hypot(0.5, y) + arm, h)
        return -q + lm * q / arm

    best = minimize_scalar(lambda y: -tip(y), bounds=(y1, y2), method="bounded",
                           options={"xatol": 1e-13})  # fmt: skip
    return max(0.5, -float(best.fun))


def constant_speed_d_col(
    gap: float, winch_offset: float = 0.0, tether_height: float = 0.0
) -> float:
    """The robot's least wall distance over a run of the constant-speed follower, over w.

    Parameters
    ----------
    gap
        Following gap along the path over w (> 0).
    winch_offset
        Winch ahead of the robot centre over w (negative: behind).
    tether_height
        Height difference of the tether's ends over w (0: planar).

    Examples
    --------
    >>> constant_speed_d_col(1.0), round(constant_speed_d_col(2.5), 4)
    (0.5, 0.0609)
    """
    g, e, h = _GAP.check(gap), _OFFSET.check(winch_offset), _HEIGHT.check(tether_height)
    return min(0.5, 1.0 - _max_tip(g, e, h))


def constant_speed_limits(
    r_col: float = SNAG_GEOMETRY_RADIUS.default,
    winch_offset: float = 0.0,
    tether_height: float = 0.0,
) -> dict[str, float]:
    """First snagging gap, collision limit and wall limit of the constant-speed follower, over w.

    ``first_snag``: the least gap at which the string wraps; ``collision``: the gap at which
    ``d_col`` falls to ``r_col`` (eq. 4.7); ``wall``: the gap at which the robot centre
    reaches the wall (``d_col = 0``, the constant of eq. 4.6). Allan 2015 gives 1.75, 2.25
    (eq. 4.8: 2.258) and 2.565.

    Parameters
    ----------
    r_col
        Bounding-circle radius over w (half the vehicle length: 0.2).
    winch_offset
        Winch ahead of the robot centre over w (negative: behind).
    tether_height
        Height difference of the tether's ends over w (0: planar).

    Examples
    --------
    >>> lim = constant_speed_limits(winch_offset=-0.03)
    >>> round(lim["first_snag"], 4), round(lim["collision"], 4), round(lim["wall"], 4)
    (1.7554, 2.264, 2.5571)
    >>> constant_speed_limits(r_col=0.7)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: r_col = 0.7 is not allowed: must be ...
    """
    r = SNAG_GEOMETRY_RADIUS.check(r_col)
    e, h = _OFFSET.check(winch_offset), _HEIGHT.check(tether_height)
    first = 1.0 + _QUARTER + e
    lo, hi = first + 1e-9, first + 10.0

    def crossing(level: float) -> float:
        f = lambda g: 1.0 - _max_tip(g, e, h) - level  # noqa: E731
        if f(lo) <= 0.0 or f(hi) > 0.0:
            raise InvalidParameterError("r_col", r_col, "a distance the robot passes through")
        return float(brentq(f, lo, hi, xtol=1e-13, rtol=1e-13))

    return {"first_snag": first, "collision": crossing(r), "wall": crossing(0.0)}
