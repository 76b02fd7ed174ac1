"""The new VFF (Zeng 2011, Sec. 5.4-5.5, App. B): the method this project is about.

The attractive PD force (5.4.2), per obstacle in its active region the repulsive force
(5.4.3) and the detour force (5.4.5) on the side of the rules (Figs. 5.8/5.9, (5.4.4)),
and the stabilising force F_L = m max(Omega, 0) (-g)/|g|^2 of (5.4.6), Omega from the
automatic derivative of the piecewise-quadratic Lyapunov function V2 (5.5.1-5.5.2, B.2.2)
along the unforced closed loop (``docs/navigation.md``, "The force field").

Examples
--------
>>> from designlab.navigation.methods import METHODS
>>> m = METHODS.get("vff")
>>> m.label, m.stabilised, m.batched, m.gains_required
('New VFF', True, True, True)
"""

from __future__ import annotations

from typing import Any

import casadi as ca

from designlab.navigation.field_terms import Forces, Obs, Symbols, pd_attraction
from designlab.navigation.methods.base import NavigationMethod

__all__ = ["VFF", "VFFMethod"]


def _vff_sides(items: list[Obs], s: Symbols) -> list[ca.SX]:
    """Side of each detour force: the rules, then (5.4.4), then the tie-break (+/- y)."""
    zeros2 = ca.SX.zeros(2)

    def psi_force(it: Obs, sigma: ca.SX) -> ca.SX:
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


def _vff_forces(items: list[Obs], s: Symbols) -> Forces:
    """The new VFF with V, dV/dt, Omega and the stabilising force F_L (B.2.2, B.3, (5.4.6))."""
    zeros2 = ca.SX.zeros(2)
    k1, b, k3, k5, m = s.k1, s.b, s.k3, s.k5, s.m
    sigmas = _vff_sides(items, s)
    # --- forces and the Lyapunov function V (B.2.2, B.3), with the sides held fixed
    F_unf = pd_attraction(s)
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
    return Forces(F_unf + s.stab * FL, sigmas, V, vdot0, omega, vL, FL, g)


class VFFMethod(NavigationMethod):
    """The new VFF: gains required (:class:`~designlab.navigation.parameters.VFFGains`),
    stabilising force and its audit."""

    stabilised = True

    def default_gains(self) -> Any:
        return None

    def forces(self, items: list[Obs], s: Symbols) -> Forces:
        return _vff_forces(items, s)


#: The new VFF (``method="vff"``).
VFF = VFFMethod("vff", "New VFF", "the new virtual force field (Zeng 2011, Sec. 5.4-5.5)")
