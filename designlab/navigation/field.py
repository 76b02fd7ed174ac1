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

Each method's force is written by its module of :mod:`designlab.navigation.methods` (the
new VFF above, the baselines of Sec. 2.2.4: Masoud 2007, Ge & Cui 2002) in the terms of
:mod:`designlab.navigation.field_terms`; this function looks the method up by name and
builds it. :func:`build_cbf_rows` gives the constraint rows of the
control-barrier-function filter. Distances, rates and angle rates are derivatives of
the geometry taken by CasADi, never hand-written twice.

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

from functools import lru_cache

import casadi as ca

from designlab.errors import InvalidParameterError
from designlab.navigation.field_terms import (
    NORM_EPS,
    Obs,
    ObstacleGeometry,
    Symbols,
    check_geometry,
    norm,
    reference_point,
)
from designlab.navigation.methods import METHOD, METHODS

__all__ = ["NORM_EPS", "ObstacleGeometry", "build_cbf_rows", "build_distance", "build_field"]


@lru_cache(maxsize=64)
def build_field(
    geometries: tuple[ObstacleGeometry, ...], method: str = METHOD.default
) -> ca.Function:
    """The force field for a set of obstacles as a ``casadi.Function``.

    Parameters
    ----------
    geometries
        One :class:`ObstacleGeometry` per obstacle, in scenario order.
    method
        A force-field method of :data:`~designlab.navigation.methods.METHODS` (``"vff"``,
        Zeng 2011; ``"masoud"``, ``"ge_cui"``; ``"cbf"``: the attractive field alone, which
        the simulator's CBF filter corrects; ``"vff_cbf"``: the new VFF, corrected by it).

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
    variant = METHODS.get(method, force_field=True)
    for g in geometries:
        check_geometry(g)
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
        Obs(
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
    sym = Symbols(p, v, E, -v, k1, b, k3, k5, m, tie, stab, amax)
    out = variant.forces(items, sym)
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
    rel = [p - reference_point(g, p, op[2 * i : 2 * i + 2]) for i, g in enumerate(geometries)]
    d = [ca.sumsqr(r) if squared else norm(r) for r in rel]
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
        d = norm(p - reference_point(g, p, po))
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
