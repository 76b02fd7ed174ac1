"""Lyapunov conditions of Zeng 2011, Sec. 5.5 / App. B.

Gain structure, Omega, the dV/dt bound and the stability audit.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.navigation.field import ObstacleGeometry, build_field
from designlab.results import check_result

nav = dl.navigation
DISC = ObstacleGeometry("disc", r2=0.8, r3=0.4)
HUMAN = ObstacleGeometry("disc", r2=2.1, r3=0.8, moving=True)
M = 4.4


def _field(geos, stab):  # type: ignore[no-untyped-def]
    f = build_field(tuple(geos), "vff")

    def ev(x, obs, goal, gains):  # type: ignore[no-untyped-def]
        out = f(x=x, goal=goal, obs=obs, gains=gains, params=[M, 1.0, stab, 10.0])
        return {k: np.array(v).ravel() for k, v in out.items()}

    return ev


# ------------------------------------------------------------------ gain structure


def test_gain_structure_is_built_in() -> None:
    g = nav.VFFGains(k1=4.3, b=0.68, k3=20.3, k5=240.7)
    assert (g.k2, g.k4, g.k6) == pytest.approx((4.3 * 0.68, 20.3 * 0.68, 240.7 * 0.68))
    assert nav.VFFGains.from_full(k1=2, k2=1, k3=4, k4=2, k5=6, k6=3).b == 0.5


@pytest.mark.parametrize(
    "kw",
    [
        dict(k1=2, k2=1, k3=4, k4=2.1, k5=6, k6=3),
        dict(k1=2, k2=1, k3=4, k4=2, k5=6, k6=2.9),
        dict(k1=2, k2=-1, k3=4, k4=-2, k5=6, k6=-3),
    ],
)
def test_gains_violating_the_structure_are_rejected(kw: dict) -> None:
    with pytest.raises(InvalidParameterError, match="VFFGains"):
        nav.VFFGains.from_full(**kw)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf, "x", None, True, [3.0]])
def test_bad_gain_values(bad: object) -> None:
    with pytest.raises(InvalidParameterError, match=r"VFFGains\.k5"):
        nav.VFFGains(k1=3, b=0.25, k3=20, k5=bad)  # type: ignore[arg-type]


def test_absurdly_large_gains_are_refused_not_simulated() -> None:
    # k1 = 1e300 overflowed the field's norm: the robot stood still and H_E read 1.
    with pytest.raises(InvalidParameterError, match=r"VFFGains\.k1 = 1e\+300 N/m .*<= 1e\+09"):
        nav.VFFGains(k1=1e300, b=0.25, k3=20, k5=17)
    assert nav.VFFGains(k1=1e9, b=0.25, k3=20, k5=17).k1 == 1e9
    with pytest.raises(InvalidParameterError, match=r"gains\[1, 3\] = 1000000000000.0 .*<= 1e\+09"):
        nav.simulate_batch([nav.configuration(1)], [[3, 0.25, 20, 17], [3, 0.25, 20, 1e12]])
    with pytest.raises(InvalidParameterError, match=r"bounds\['k1'\]"):
        nav.optimise_gains([nav.configuration(1)], bounds={"k1": (1.0, 1e10)})


# ---------------------------------------------- AD Omega vs the corrected closed form


def _state_radial(rng: np.random.Generator):  # type: ignore[no-untyped-def]
    """A state whose relative velocity is radial and a static obstacle: the derivation's
    approximations (B.2.4)-(B.2.5) are then exact, so AD and closed form must agree."""
    beta = rng.uniform(-math.pi, math.pi)
    d = rng.uniform(0.45, 0.78)
    u = np.array([math.cos(beta), math.sin(beta)])
    p = d * u
    v = rng.uniform(-0.7, 0.7) * u
    goal = (
        p + rng.normal(size=2) * 2.0 + 2.5 * np.array([math.cos(beta + 2.0), math.sin(beta + 2.0)])
    )
    return p, v, goal, u, d


def test_ad_omega_matches_the_corrected_closed_form() -> None:
    rng = np.random.default_rng(7)
    ev = _field([DISC], 0.0)
    gains = [3.0, 0.25, 20.0, 17.0]
    checked = 0
    for _ in range(40):
        p, v, goal, u, d = _state_radial(rng)
        if np.linalg.norm(goal) < 1.0:
            continue
        out = ev([*p, *v], [0, 0, 0, 0, 0, 0], goal, gains)
        sigma = out["sigma"][0]
        alpha = math.atan2(goal[1], goal[0])
        beta = math.atan2(p[1], p[0])
        delta = math.atan2(math.sin(alpha - beta), math.cos(alpha - beta))
        phi = (sigma * delta) % (2 * math.pi)
        u_psi = sigma * np.array([-u[1], u[0]])
        omega = nav.omega_closed_form(
            E=goal - p,
            Edot=-v,
            d=d,
            d_rate=float(u @ v),
            phi=phi,
            phi_rate=0.0,
            u=u,
            u_psi=u_psi,
            a_o=[0, 0],
            r2=0.8,
            r3=0.4,
            k1=3.0,
            k3=20.0,
            k5=17.0,
            m=M,
        )
        assert out["Omega"][0] == pytest.approx(omega, rel=1e-9, abs=1e-9)
        checked += 1
    assert checked > 20


def test_printed_omega_typos_change_the_value() -> None:
    # (5.5.8) as printed (no M_r on a_o, -K5^2 (r2-d) d' Phi^2) differs from the corrected form
    kw = dict(
        E=[-2.5, 0.3],
        Edot=[0.5, 0.1],
        d=0.6,
        d_rate=-0.5,
        phi=1.0,
        phi_rate=0.4,
        u=[1.0, 0.0],
        u_psi=[0.0, 1.0],
        a_o=[0.3, 0.2],
        r2=0.8,
        r3=0.4,
        k1=3.0,
        k3=20.0,
        k5=17.0,
        m=M,
    )
    assert abs(nav.omega_printed(**kw) - nav.omega_closed_form(**kw)) > 1.0


def test_dv_dvr_is_minus_m_vl_for_discs() -> None:
    rng = np.random.default_rng(2)
    ev = _field([DISC, HUMAN], 1.0)
    for _ in range(30):
        x = [*rng.uniform(-1.5, 1.5, 2), *rng.normal(size=2) * 0.4]
        obs = [0.0, 0.0, 0, 0, 0, 0, 1.2, 0.8, *rng.normal(size=2) * 0.6, *rng.normal(size=2)]
        out = ev(x, obs, [-4.0, 1.0], [3.0, 0.25, 20.0, 17.0])
        assert np.dot(out["g"], out["g"]) == pytest.approx(
            M**2 * out["vL2"][0], rel=1e-9, abs=1e-12
        )


def _rk4(ev, z, goal, gains, h, ao):  # type: ignore[no-untyped-def]
    """Integrate robot (p, v) and a constant-acceleration obstacle with the unsaturated field."""

    def rhs(z):  # type: ignore[no-untyped-def]
        x, po, vo = z[:4], z[4:6], z[6:8]
        F = ev(x, [*po, *vo, *ao], goal, gains)["F"]
        return np.concatenate([x[2:4], F / M, vo, ao])

    k1 = rhs(z)
    k2 = rhs(z + h / 2 * k1)
    k3 = rhs(z + h / 2 * k2)
    k4 = rhs(z + h * k3)
    return z + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10_000), b=st.floats(0.05, 2.0), k5=st.floats(1.0, 300.0))
def test_stabilising_force_gives_vdot_below_minus_b_vl2(seed: int, b: float, k5: float) -> None:
    """Without saturation, dV/dt <= -b |v_L|^2 (5.5.12), checked by integrating the closed
    loop with RK4 and differencing V: independent of the AD used to build F_L."""
    rng = np.random.default_rng(seed)
    ev = _field([HUMAN], 1.0)
    gains = [3.0, b, 20.0, k5]
    beta = rng.uniform(-math.pi, math.pi)
    d = rng.uniform(0.9, 2.0)
    p = d * np.array([math.cos(beta), math.sin(beta)])
    z = np.concatenate([p, rng.normal(size=2) * 0.4, [0.0, 0.0], rng.normal(size=2) * 0.7])
    ao = rng.normal(size=2) * 0.5
    goal = np.array([-4.0, 0.5])
    out = ev(z[:4], [*z[4:8], *ao], goal, gains)
    # F_L can be large (it is unbounded as v_L -> 0, Sec. 5.5): keep the velocity change in the
    # difference step small so the RK4 difference measures dV/dt, not the step error
    h = min(1e-5, 1e-4 / max(float(np.linalg.norm(out["F"])) / M, 1e-9))
    zp = _rk4(ev, z, goal, gains, h, ao)
    zm = _rk4(ev, z, goal, gains, -h, ao)
    vp = ev(zp[:4], [*zp[4:8], *ao], goal, gains)["V"][0]
    vm = ev(zm[:4], [*zm[4:8], *ao], goal, gains)["V"][0]
    vdot = (vp - vm) / (2 * h)
    bound = -b * out["vL2"][0]
    scale = max(1.0, abs(bound), abs(out["Vdot0"][0]))
    assert vdot <= bound + 1e-5 * scale
    if out["Omega"][0] > 0:  # then the bound holds with equality
        assert vdot == pytest.approx(bound, abs=1e-3 * scale)  # FD + RK4 error


# ------------------------------------------------------------------------- audit


def test_audit_of_a_stabilised_run_fails_only_where_the_proof_does_not_apply() -> None:
    res = nav.simulate(nav.configuration(1), nav.OPTIMAL_GAINS, stabilising="lyapunov")
    a = res.stability
    check_result(a)
    assert 0.0 < a.share_satisfied <= 1.0
    broken = np.zeros(a.t.size, bool)
    period = a.t[1] - a.t[0]
    for _reason, t0, t1 in a.intervals:
        broken |= (a.t >= t0 - 1e-9) & (a.t < t1 - 1e-9)
    violations = a.active & ~a.satisfied
    assert violations.any()  # the saturation the proof ignores does occur
    assert not (violations & ~broken).any()
    assert {r for r, *_ in a.intervals} <= {
        "force saturation",
        "speed saturation",
        "critical region",
        "detour switch",
    }
    assert a.intervals_frame().shape[1] == 3
    assert period == pytest.approx(0.06)


def test_audit_with_the_stabilising_force_off_shows_violations_outside_saturation() -> None:
    res = nav.simulate(nav.configuration(1), nav.OPTIMAL_GAINS, stabilising="off")
    on = nav.simulate(nav.configuration(1), nav.OPTIMAL_GAINS, stabilising="lyapunov")
    assert res.stability.share_satisfied < 1.0
    assert (
        on.arrival_time > res.arrival_time
    )  # the finding of docs/navigation.md: F_L slows the robot
