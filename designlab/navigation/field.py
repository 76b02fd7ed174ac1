"""The virtual force field, written once in CasADi symbols (Zeng 2011, Sec. 5.4-5.5, App. B).

:func:`build_field` returns a ``casadi.Function`` of the robot state, the goal,
the obstacle states and the gains. It holds

* the attractive force F_a = K1 E + K2 E' (5.4.2),
* per obstacle i in its active region, the repulsive force
  F_Lambda = (K3 Lambda + K4 Lambda'*) u_Lambda (5.4.3) and the detour force
  F_psi = (K5 psi + K6 psi'*) u_psi (5.4.5) with the direction rules of
  Figs. 5.8/5.9 and (5.4.4),
* the stabilising force F_L = m max(Omega, 0) (-g)/|g|^2 where g = dV/dV_mr;
  for discs g = -m v_L and F_L = max(Omega, 0) u_L / |v_L| (5.4.6). Omega =
  b |v_L|^2 + dV/dt|_{F_L=0} comes from automatic differentiation of the
  piecewise-quadratic Lyapunov function V2 (5.5.1-5.5.2, B.2.2) along the
  unforced closed loop, so dV/dt <= -b |v_L|^2 holds exactly (without the
  saturation the proof ignores; ``docs/navigation.md``).

The baselines of Sec. 2.2.4 (Masoud 2007, Ge & Cui 2002) are built by the same
function with ``method``, and :func:`build_cbf_rows` gives the constraint rows of
the control-barrier-function filter. Distances, rates and angle rates are
derivatives of the geometry taken by CasADi, never hand-written twice.

Examples
--------
>>> import numpy as np
>>> from designlab.navigation import configuration
>>> from designlab.navigation.field import ObstacleGeometry, build_field
>>> sc = configuration(1)
>>> f = build_field(tuple(ObstacleGeometry.of(o) for o in sc.obstacles))
>>> x = np.array([3.0, 0.6, -0.5, 0.0])           # inside the circle's active region
>>> obs = np.array([2.45, 0.595, 0, 0, 0, 0])
>>> out = f(x=x, goal=[0.0, 0.6], obs=obs, gains=[3.0, 0.25, 20.0, 17.0],
...         params=[4.4, 1.0, 0.0, 10.0])
>>> np.round(np.array(out["F"]).ravel(), 2)        # stabilising force off
array([6.62, 3.46])
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import casadi as ca

from designlab.errors import InvalidParameterError

__all__ = ["METHODS", "ObstacleGeometry", "build_cbf_rows", "build_distance", "build_field"]

#: Navigation methods built by :func:`build_field` (``"cbf"`` filters the attractive field).
METHODS = ("vff", "masoud", "ge_cui", "cbf", "vff_cbf")
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


def _norm(v: ca.SX) -> ca.SX:
    return ca.sqrt(ca.sumsqr(v) + NORM_EPS**2)


def _sign_tol(x: ca.SX, tol: float | ca.SX) -> ca.SX:
    return ca.if_else(ca.fabs(x) > tol, ca.sign(x), 0)


def _reference_point(geo: ObstacleGeometry, p: ca.SX, po: ca.SX) -> ca.SX:
    """The obstacle point the regions are measured from: centre (disc), closest contour point."""
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


class _Obs:
    """Symbolic per-obstacle quantities for one obstacle (internal)."""

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
        q = _reference_point(geo, p, po)
        self.D = p - q
        self.d = _norm(self.D)
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
            speed = _norm(self.vo)
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


def _disc_collision_free(geo: ObstacleGeometry) -> None:
    if geo.kind not in ("disc", "rectangle"):
        raise InvalidParameterError(
            "ObstacleGeometry.kind", geo.kind, "must be 'disc' or 'rectangle'"
        )


@dataclass
class _Symbols:
    """The symbols a method's forces are written in."""

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
class _Forces:
    """What a method's field gives: the force, the detour sides and the Lyapunov terms
    (zero for the methods without a Lyapunov function)."""

    F: ca.SX
    sigmas: list[ca.SX]
    V: ca.SX = field(default_factory=lambda: ca.SX(0))
    vdot0: ca.SX = field(default_factory=lambda: ca.SX(0))
    omega: ca.SX = field(default_factory=lambda: ca.SX(0))
    vL: ca.SX = field(default_factory=lambda: ca.SX.zeros(2))
    FL: ca.SX = field(default_factory=lambda: ca.SX.zeros(2))
    g: ca.SX = field(default_factory=lambda: ca.SX.zeros(2))


def _pd_attraction(s: _Symbols) -> ca.SX:
    """F_a = K1 E + K2 E' with K2 = b K1 (5.4.2)."""
    return s.k1 * s.E + s.b * s.k1 * s.Edot


def _vff_sides(items: list[_Obs], s: _Symbols) -> list[ca.SX]:
    """Side of each detour force: the rules, then (5.4.4), then the tie-break (+/- y)."""
    zeros2 = ca.SX.zeros(2)

    def psi_force(it: _Obs, sigma: ca.SX) -> ca.SX:
        phi, phi_rate, u_psi = it.detour_terms(sigma)
        w2 = (it.r2 - it.dd) ** 2
        return (s.k5 * w2 * phi + s.b * s.k5 * w2 * phi_rate) * u_psi

    rule_forces = [ca.if_else(it.c, psi_force(it, it.sigma_rule), zeros2) for it in items]
    sigmas = []
    for i, it in enumerate(items):
        others = zeros2
        for j in range(len(items)):
            if j != i:
                others = others + rule_forces[j]
        t = ca.dot(it.u_perp, others)
        tie_side = ca.if_else(ca.fabs(it.u_perp[1]) > 1e-9, ca.sign(it.u_perp[1]) * s.tie, s.tie)
        resolved = ca.if_else(ca.fabs(t) > 1e-9, ca.sign(t), tie_side)
        sigmas.append(ca.if_else(it.sigma_rule != 0, it.sigma_rule, resolved))
    return sigmas


def _vff_forces(items: list[_Obs], s: _Symbols) -> _Forces:
    """The new VFF with V, dV/dt, Omega and the stabilising force F_L (B.2.2, B.3, (5.4.6))."""
    zeros2 = ca.SX.zeros(2)
    k1, b, k3, k5, m = s.k1, s.b, s.k3, s.k5, s.m
    sigmas = _vff_sides(items, s)
    # --- forces and the Lyapunov function V (B.2.2, B.3), with the sides held fixed
    F_unf = _pd_attraction(s)
    V = 0.5 * k1**2 * ca.dot(s.E, s.E) + 0.5 * m * k1 * ca.dot(s.Edot, s.Edot)
    vL = k1 * s.Edot
    for it, sigma in zip(items, sigmas, strict=True):
        r2, r3 = it.r2, it.geo.r3
        dd = it.dd
        lam = (r2 - dd) ** 2 / (dd - r3)
        k_lam = (r2 - dd) ** 2 / (dd - r3) ** 2
        lam_rate = -k_lam * it.d_rate
        phi, phi_rate, u_psi = it.detour_terms(sigma)
        w2 = (r2 - dd) ** 2
        psi = w2 * phi
        psi_rate = w2 * phi_rate
        c = it.c
        F_i = (k3 * lam + b * k3 * lam_rate) * it.u + (k5 * psi + b * k5 * psi_rate) * u_psi
        F_unf = F_unf + ca.if_else(c, F_i, zeros2)
        V_i = (
            0.5 * k3**2 * lam**2
            + 0.5 * m * k3 * k_lam * it.d_rate**2
            + 0.5 * k5**2 * psi**2
            + 0.5 * m * k5 * dd * w2 * phi_rate**2
        )
        V = V + ca.if_else(c, V_i, 0)
        vL = vL + ca.if_else(c, k3 * lam_rate * it.u + k5 * psi_rate * u_psi, zeros2)
    z = ca.vertcat(s.p, s.v, *[ca.vertcat(it.po, it.vo) for it in items])
    zdot = ca.vertcat(s.v, F_unf / m, *[ca.vertcat(it.vo, it.ao) for it in items])
    vdot0 = ca.jtimes(V, z, zdot)
    g = ca.gradient(V, s.v)
    omega = b * ca.dot(vL, vL) + vdot0
    any_active = ca.SX(0)
    for it in items:
        any_active = ca.logic_or(any_active, it.c)
    g2 = ca.dot(g, g)
    FL = ca.if_else(
        ca.logic_and(any_active, g2 > 1e-18),
        m * ca.fmax(omega, 0) * (-g) / ca.fmax(g2, 1e-18),
        zeros2,
    )
    return _Forces(F_unf + s.stab * FL, sigmas, V, vdot0, omega, vL, FL, g)


def _masoud_forces(items: list[_Obs], s: _Symbols) -> _Forces:
    """Masoud (2007): F_a = K1 E, repulsion K3 D, detour K5 |D| in a fixed sense (the tie)."""
    F = s.k1 * s.E
    for it in items:
        rot = s.tie * it.u_perp  # fixed rotational sense (+1 counter-clockwise)
        F = F + ca.if_else(it.c, s.k3 * it.D + s.k5 * it.d * rot, ca.SX.zeros(2))
    return _Forces(F, [s.tie] * len(items))


def _ge_cui_forces(items: list[_Obs], s: _Symbols) -> _Forces:
    """Ge & Cui (2002): (2.2.12)-(2.2.13) on the PD attraction."""
    F = _pd_attraction(s)
    sigmas = []
    for it in items:
        r3 = it.geo.r3
        gap2 = (it.dd - r3) ** 2
        beta_rate = ca.dot(it.u_perp, s.v - it.vo) / it.dd
        rep = (s.k3 - it.d_rate / s.amax) / gap2
        det = ca.fabs(s.k5 * it.d_rate * beta_rate * it.dd) / gap2
        side = ca.sign(beta_rate)
        sigmas.append(side)
        F = F + ca.if_else(it.c, rep * it.u + det * side * it.u_perp, ca.SX.zeros(2))
    return _Forces(F, sigmas)


def _cbf_forces(items: list[_Obs], s: _Symbols) -> _Forces:
    """The CBF filter's nominal field: the PD attraction alone (filtered by the simulator)."""
    return _Forces(_pd_attraction(s), [ca.SX(0)] * len(items))


#: The force of each navigation method (the registry of :data:`METHODS`).
_FORCES = {
    "vff": _vff_forces,
    "masoud": _masoud_forces,
    "ge_cui": _ge_cui_forces,
    "cbf": _cbf_forces,
    "vff_cbf": _vff_forces,  # the new VFF; the simulator's CBF filter corrects its force
}


@lru_cache(maxsize=64)
def build_field(geometries: tuple[ObstacleGeometry, ...], method: str = "vff") -> ca.Function:
    """The force field for a set of obstacles as a ``casadi.Function``.

    Parameters
    ----------
    geometries
        One :class:`ObstacleGeometry` per obstacle, in scenario order.
    method
        ``"vff"`` (Zeng 2011), ``"masoud"``, ``"ge_cui"``, ``"cbf"`` (the
        attractive field alone; the CBF filter is applied by the simulator) or ``"vff_cbf"``
        (the new VFF, whose force the simulator's CBF filter corrects).

    Returns
    -------
    casadi.Function
        Inputs ``x`` (p_x, p_y, v_x, v_y), ``goal`` (2), ``obs`` (6 per obstacle:
        position or rectangle centre, velocity, acceleration), ``gains`` (k1, b, k3,
        k5; for Masoud k1, -, k3, k5), ``params`` (mass m, tie side +1/-1,
        stabilising 1/0, acceleration limit a_mr used by Ge & Cui's (2.2.12)) and, if an
        obstacle has ``r2_input``, ``r2`` (one active radius per obstacle, m; read for those
        obstacles only). Outputs
        ``F`` (2, the virtual force before the robot's limits), ``critical`` (1 if the
        robot is in any critical region), ``V``, ``Vdot0`` (dV/dt without F_L),
        ``Omega``, ``vL2`` (|v_L|^2), ``FL`` (2), ``g`` (dV/dV_mr, 2),
        ``active`` (one flag per obstacle), ``d`` (distances), ``sigma`` (detour sides).
    """
    if method not in METHODS:
        raise InvalidParameterError("method", method, f"must be one of {METHODS}")
    for g in geometries:
        _disc_collision_free(g)
    n = len(geometries)
    x = ca.SX.sym("x", 4)
    goal = ca.SX.sym("goal", 2)
    obs = ca.SX.sym("obs", 6 * n)
    gains = ca.SX.sym("gains", 4)
    params = ca.SX.sym("params", 4)
    r2 = ca.SX.sym("r2", n)  # an input only if some obstacle's active radius is
    extra = [r2] if any(g.r2_input for g in geometries) else []
    p, v = x[0:2], x[2:4]
    k1, b, k3, k5 = gains[0], gains[1], gains[2], gains[3]
    m, tie, stab, amax = params[0], params[1], params[2], params[3]
    E = goal - p
    items = [
        _Obs(
            g,
            p,
            v,
            goal,
            obs[6 * i : 6 * i + 2],
            obs[6 * i + 2 : 6 * i + 4],
            obs[6 * i + 4 : 6 * i + 6],
            r2[i] if g.r2_input else g.r2,
        )
        for i, g in enumerate(geometries)
    ]
    critical = ca.SX(0)
    for it in items:
        critical = ca.logic_or(critical, it.critical)
    sym = _Symbols(p, v, E, -v, k1, b, k3, k5, m, tie, stab, amax)
    out = _FORCES[method](items, sym)
    F, sigmas = out.F, out.sigmas
    active = ca.vertcat(*[it.c for it in items]) if n else ca.SX(0, 1)
    dist = ca.vertcat(*[it.d for it in items]) if n else ca.SX(0, 1)
    sig = ca.vertcat(*sigmas) if n else ca.SX(0, 1)
    return ca.Function(
        f"field_{method}_{n}",
        [x, goal, obs, gains, params, *extra],
        [
            F,
            critical,
            out.V,
            out.vdot0,
            out.omega,
            ca.dot(out.vL, out.vL),
            out.FL,
            out.g,
            active,
            dist,
            sig,
        ],
        ["x", "goal", "obs", "gains", "params"] + ["r2"] * len(extra),
        ["F", "critical", "V", "Vdot0", "Omega", "vL2", "FL", "g", "active", "d", "sigma"],
    )


@lru_cache(maxsize=64)
def build_distance(geometries: tuple[ObstacleGeometry, ...], squared: bool = False) -> ca.Function:
    """Distances from robot positions to each obstacle (centre or contour distance).

    Inputs ``p`` (2) and ``obs_p`` (2 per obstacle: position or centre); output
    ``d`` (one per obstacle). With ``squared=True`` the output is the argument of the
    square root, ``d**2 - eps**2``: minima over many steps are taken on it and the root
    is drawn once (the root is monotone, so the minimum is the same to the last bit).
    """
    p = ca.SX.sym("p", 2)
    n = len(geometries)
    op = ca.SX.sym("obs_p", 2 * n)
    rel = [p - _reference_point(g, p, op[2 * i : 2 * i + 2]) for i, g in enumerate(geometries)]
    d = [ca.sumsqr(r) if squared else _norm(r) for r in rel]
    return ca.Function(
        "distance", [p, op], [ca.vertcat(*d) if n else ca.SX(0, 1)], ["p", "obs_p"], ["d"]
    )


@lru_cache(maxsize=64)
def build_cbf_rows(
    geometries: tuple[ObstacleGeometry, ...], safety: str = "critical"
) -> ca.Function:
    """Rows of the exponential-CBF constraints A a >= lb for a double integrator.

    With h_i = d_i - r3_i (``safety="critical"``) the constraint
    h'' + k_1 h' + k_0 h >= 0 is affine in the robot acceleration a; h' and h'' are
    derivatives of the same geometry as the field (CasADi AD).

    Inputs ``x`` (4), ``obs`` (6 per obstacle), ``k`` (k_0, k_1); outputs ``A``
    (n x 2) and ``lb`` (n).
    """
    if safety not in ("critical", "collision"):
        raise InvalidParameterError("safety", safety, "must be 'critical' or 'collision'")
    n = len(geometries)
    x = ca.SX.sym("x", 4)
    obs = ca.SX.sym("obs", 6 * n)
    kk = ca.SX.sym("k", 2)
    a = ca.SX.sym("a", 2)
    p, v = x[0:2], x[2:4]
    rows, lbs = [], []
    for i, g in enumerate(geometries):
        po, vo, ao = obs[6 * i : 6 * i + 2], obs[6 * i + 2 : 6 * i + 4], obs[6 * i + 4 : 6 * i + 6]
        d = _norm(p - _reference_point(g, p, po))
        h = d - g.r3
        z = ca.vertcat(p, po)
        hdot = ca.jtimes(h, z, ca.vertcat(v, vo))
        zz = ca.vertcat(p, v, po, vo)
        hddot = ca.jtimes(hdot, zz, ca.vertcat(v, a, vo, ao))
        A = ca.jacobian(hddot, a)
        drift = ca.substitute(hddot, a, ca.SX.zeros(2))
        rows.append(A)
        lbs.append(-drift - kk[1] * hdot - kk[0] * h)
    A_all = ca.vertcat(*rows) if n else ca.SX(0, 2)
    lb_all = ca.vertcat(*lbs) if n else ca.SX(0, 1)
    return ca.Function("cbf_rows", [x, obs, kk], [A_all, lb_all], ["x", "obs", "k"], ["A", "lb"])
