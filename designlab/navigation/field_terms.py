"""The symbols a navigation method's force is written in (Zeng 2011, Sec. 5.4, App. B).

The obstacle geometry baked into a field (:class:`ObstacleGeometry`), the per-obstacle
symbolic quantities (:class:`Obs`: distance, its rate, the angle to the goal, the detour
rules of Figs. 5.8/5.9), the robot's symbols (:class:`Symbols`) and what a method's force
builder returns (:class:`Forces`). Each method of :mod:`designlab.navigation.methods`
writes its force in these terms; :func:`designlab.navigation.field.build_field` turns it
into a ``casadi.Function``. Distances, rates and angle rates are derivatives of the
geometry taken by CasADi, never hand-written twice.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import casadi as ca

from designlab.errors import InvalidParameterError

__all__ = [
    "NORM_EPS",
    "Forces",
    "Obs",
    "ObstacleGeometry",
    "Symbols",
    "check_geometry",
    "norm",
    "pd_attraction",
    "reference_point",
]

#: The epsilon of the smoothed norm sqrt(|v|^2 + eps^2) used by every field term (no 0/0 at v = 0).
NORM_EPS = 1e-12
_TIE_ANGLE = 1e-6


@dataclass(frozen=True)
class ObstacleGeometry:
    """The constants of one obstacle baked into the field (hashable, picklable).

    ``kind`` is ``"disc"`` or ``"rectangle"``; rectangles carry half sizes and the
    rotation; ``moving`` switches on the walking-human direction rule.

    Attributes
    ----------
    kind
        ``"disc"`` or ``"rectangle"``.
    r2
        Active-region radius in m.
    r3
        Critical-region radius in m.
    half_length
        Rectangle half length in m.
    half_width
        Rectangle half width in m.
    angle
        Rectangle rotation in rad.
    moving
        Whether the walking-human direction rule applies.
    r2_input
        Whether the active radius is an input of the field, set at every sample (the
        closing-speed sizing of a crowd, :mod:`designlab.navigation.crowds.regions`); ``r2``
        is then its largest value.
    """

    kind: str
    r2: float
    r3: float
    half_length: float = 0.0
    half_width: float = 0.0
    angle: float = 0.0
    moving: bool = False
    r2_input: bool = False

    @classmethod
    def of(cls, obstacle: Any) -> ObstacleGeometry:
        """Geometry of a :class:`~designlab.navigation.scenarios.Disc` or ``Rectangle``."""
        if obstacle.kind == "rectangle":
            return cls(
                "rectangle",
                obstacle.r2,
                obstacle.r3,
                obstacle.length / 2,
                obstacle.width / 2,
                obstacle.angle,
                False,
            )
        return cls("disc", obstacle.r2, obstacle.r3, moving=bool(obstacle.motion.moving))


def _rot90(u: ca.SX) -> ca.SX:
    return ca.vertcat(-u[1], u[0])


def _cross(a: ca.SX, b: ca.SX) -> ca.SX:
    return a[0] * b[1] - a[1] * b[0]


def norm(v: ca.SX) -> ca.SX:
    """The smoothed norm sqrt(|v|^2 + eps^2) of every field term (no 0/0 at v = 0).

    Parameters
    ----------
    v
        A CasADi vector.
    """
    return ca.sqrt(ca.sumsqr(v) + NORM_EPS**2)


def _sign_tol(x: ca.SX, tol: float | ca.SX) -> ca.SX:
    return ca.if_else(ca.fabs(x) > tol, ca.sign(x), 0)


def reference_point(geo: ObstacleGeometry, p: ca.SX, po: ca.SX) -> ca.SX:
    """The obstacle point the regions are measured from: centre (disc), closest contour point.

    Parameters
    ----------
    geo
        The obstacle's geometry.
    p, po
        Robot position and obstacle position (or rectangle centre), CasADi 2-vectors.
    """
    if geo.kind == "disc":
        return po
    c, s = math.cos(geo.angle), math.sin(geo.angle)
    rel = p - po
    lx = c * rel[0] + s * rel[1]
    ly = -s * rel[0] + c * rel[1]
    qx = ca.fmin(ca.fmax(lx, -geo.half_length), geo.half_length)
    qy = ca.fmin(ca.fmax(ly, -geo.half_width), geo.half_width)
    return po + ca.vertcat(c * qx - s * qy, s * qx + c * qy)


def _segment_blocked(geo: ObstacleGeometry, a: ca.SX, b: ca.SX, po: ca.SX) -> ca.SX:
    """1 if the segment a->b crosses the rectangle (Liang-Barsky slab test), else 0."""
    c, s = math.cos(geo.angle), math.sin(geo.angle)

    def local(v: ca.SX) -> ca.SX:
        return ca.vertcat(c * v[0] + s * v[1], -s * v[0] + c * v[1])

    o = local(a - po)
    e = local(b - a)
    t_in, t_out = ca.SX(0), ca.SX(1)
    for k, h in ((0, geo.half_length), (1, geo.half_width)):
        ek = ca.if_else(ca.fabs(e[k]) < 1e-12, 1e-12, e[k])
        t1 = (-h - o[k]) / ek
        t2 = (h - o[k]) / ek
        t_in = ca.fmax(t_in, ca.fmin(t1, t2))
        t_out = ca.fmin(t_out, ca.fmax(t1, t2))
    return t_in <= t_out


class Obs:
    """The symbolic quantities of one obstacle that the methods' forces are written in.

    ``D``, ``d``, ``u``: robot minus reference point, its length and direction; ``u_perp``
    its left normal; ``c``: inside the active region (r3 < d < r2); ``critical``: d <= r3;
    ``dd``: d inside the active region, r2 outside (every term vanishes there);
    ``d_rate``: the rate of d; ``delta``: the signed angle from D to the goal;
    ``sigma_rule``: the detour side the rules give (Figs. 5.8, 5.9), 0 where they leave
    it open.

    Parameters
    ----------
    geo
        The obstacle's geometry.
    p, v
        Robot position and velocity symbols.
    goal
        Goal position symbol.
    po, vo, ao
        Obstacle position (or rectangle centre), velocity and acceleration symbols.
    r2
        The active radius: ``geo.r2``, or the field's input for an ``r2_input`` obstacle.
    """

    def __init__(
        self,
        geo: ObstacleGeometry,
        p: ca.SX,
        v: ca.SX,
        goal: ca.SX,
        po: ca.SX,
        vo: ca.SX,
        ao: ca.SX,
        r2: float | ca.SX,
    ) -> None:
        self.geo, self.p, self.v, self.goal, self.po, self.vo, self.ao = geo, p, v, goal, po, vo, ao
        self.r2 = r2  # geo.r2, or the field's input for an r2_input obstacle
        self.z = ca.vertcat(p, po)
        self.zdot = ca.vertcat(v, vo)
        q = reference_point(geo, p, po)
        self.D = p - q
        self.d = norm(self.D)
        self.u = self.D / self.d
        self.u_perp = _rot90(self.u)
        self.W = goal - q
        self.c = ca.logic_and(self.d > geo.r3, self.d < r2)
        self.critical = self.d <= geo.r3
        self.dd = ca.if_else(self.c, self.d, r2)  # safe distance: every term vanishes outside C2
        self.d_rate = ca.jtimes(self.d, self.z, self.zdot)
        alpha = ca.atan2(self.W[1], self.W[0])
        beta = ca.atan2(self.D[1], self.D[0])
        self.delta = ca.atan2(ca.sin(alpha - beta), ca.cos(alpha - beta))  # in (-pi, pi]
        self.sigma_rule = self._rule()

    def _rule(self) -> ca.SX:
        """Detour side from the verbal rules (Figs. 5.8, 5.9); 0 when they leave it open."""
        toward_goal = ca.if_else(
            ca.fabs(self.delta) < math.pi - _TIE_ANGLE, _sign_tol(self.delta, 1e-12), 0
        )
        geo = self.geo
        if geo.kind == "disc" and geo.moving:
            speed = norm(self.vo)
            moving = speed > 1e-3
            side_r = _sign_tol(_cross(self.vo, self.p - self.po), 1e-6 * speed)
            side_g = _sign_tol(_cross(self.vo, self.goal - self.po), 1e-6 * speed)
            behind = -_sign_tol(ca.dot(self.u_perp, self.vo), 1e-9)
            different = ca.logic_and(moving, side_r * side_g < 0)
            return ca.if_else(different, behind, toward_goal)
        if geo.kind == "rectangle":
            blocked = _segment_blocked(geo, self.p, self.goal, self.po)
            wc = self.goal - self.po
            side = _sign_tol(_cross(wc, self.p - self.po), 1e-9)
            n = side * _rot90(wc)
            outward = _sign_tol(ca.dot(self.u_perp, n), 1e-9)
            return ca.if_else(blocked, outward, toward_goal)
        return toward_goal

    def detour_terms(self, sigma: ca.SX) -> tuple[ca.SX, ca.SX, ca.SX]:
        """(Phi, Phi', u_psi) for the side ``sigma`` (project convention, docs/navigation.md)."""
        x = sigma * self.delta
        phi = ca.if_else(x < 0, x + 2 * math.pi, x)
        phi_rate = ca.jtimes(phi, self.z, self.zdot)
        return phi, phi_rate, sigma * self.u_perp


def check_geometry(geo: ObstacleGeometry) -> None:
    """Refuse a geometry the field does not know (a kind other than disc or rectangle).

    Parameters
    ----------
    geo
        The obstacle's geometry.
    """
    if geo.kind not in ("disc", "rectangle"):
        raise InvalidParameterError(
            "ObstacleGeometry.kind", geo.kind, "must be 'disc' or 'rectangle'"
        )


@dataclass
class Symbols:
    """The symbols a method's forces are written in.

    Attributes
    ----------
    p, v
        Robot position and velocity.
    E, Edot
        Goal error goal - p and its rate -v.
    k1, b, k3, k5
        The gains (a row of the gain array).
    m
        Robot mass.
    tie
        Detour side (+1 / -1) where the rules leave it open (Masoud's fixed sense).
    stab
        1 with the stabilising force F_L, else 0.
    amax
        The robot's acceleration limit a_mr (Ge & Cui's (2.2.12)).
    """

    p: ca.SX
    v: ca.SX
    E: ca.SX
    Edot: ca.SX
    k1: ca.SX
    b: ca.SX
    k3: ca.SX
    k5: ca.SX
    m: ca.SX
    tie: ca.SX
    stab: ca.SX
    amax: ca.SX


@dataclass
class Forces:
    """What a method's field gives: the force, the detour sides and the Lyapunov terms
    (zero for the methods without a Lyapunov function).

    Attributes
    ----------
    F
        The virtual force (2).
    sigmas
        The detour side of each obstacle.
    V, vdot0, omega
        The Lyapunov function, its rate without F_L and Omega of (5.4.6).
    vL
        v_L of (5.4.6) (2).
    FL
        The stabilising force (2).
    g
        dV/dV_mr (2).
    """

    F: ca.SX
    sigmas: list[ca.SX]
    V: ca.SX = field(default_factory=lambda: ca.SX(0))
    vdot0: ca.SX = field(default_factory=lambda: ca.SX(0))
    omega: ca.SX = field(default_factory=lambda: ca.SX(0))
    vL: ca.SX = field(default_factory=lambda: ca.SX.zeros(2))
    FL: ca.SX = field(default_factory=lambda: ca.SX.zeros(2))
    g: ca.SX = field(default_factory=lambda: ca.SX.zeros(2))


def pd_attraction(s: Symbols) -> ca.SX:
    """F_a = K1 E + K2 E' with K2 = b K1 (5.4.2).

    Parameters
    ----------
    s
        The robot's symbols.
    """
    return s.k1 * s.E + s.b * s.k1 * s.Edot
