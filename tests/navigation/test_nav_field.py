"""The force field of Zeng 2011, Sec. 5.4: formulas, direction rules and continuity."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.errors import InvalidParameterError
from designlab.navigation.field import ObstacleGeometry, build_distance, build_field

DISC = ObstacleGeometry("disc", r2=0.8, r3=0.4)
HUMAN = ObstacleGeometry("disc", r2=2.1, r3=0.8, moving=True)
RECT = ObstacleGeometry("rectangle", r2=0.8, r3=0.4, half_length=0.7, half_width=0.3)
GAINS = [3.0, 0.25, 20.0, 17.0]
M = 4.4


def _eval(geos, x, goal, obs, stab=0.0, tie=1.0, method="vff", gains=GAINS):  # type: ignore[no-untyped-def]
    f = build_field(tuple(geos), method)
    out = f(
        x=np.asarray(x, float),
        goal=np.asarray(goal, float),
        obs=np.asarray(obs, float),
        gains=gains,
        params=[M, tie, stab, 10.0],
    )
    return {k: np.array(v).ravel() for k, v in out.items()}


def _obs(p, v=(0.0, 0.0), a=(0.0, 0.0)):  # type: ignore[no-untyped-def]
    return [*p, *v, *a]


def test_free_space_is_the_pd_pull() -> None:
    x = [3.0, 2.0, 0.3, -0.2]
    out = _eval([DISC], x, [0.0, 0.0], _obs([10.0, 10.0]), stab=1.0)
    E = np.array([-3.0, -2.0])
    Edot = -np.array([0.3, -0.2])
    np.testing.assert_allclose(out["F"], 3.0 * E + 0.75 * Edot, rtol=1e-12)
    assert out["active"][0] == 0 and out["FL"].tolist() == [0.0, 0.0]


def test_disc_forces_match_hand_written_5_4_3_and_5_4_5() -> None:
    # robot above-right of a static disc, goal to the far left: detour towards the goal side
    p, v = np.array([0.5, 0.3]), np.array([-0.4, 0.1])
    goal, po = np.array([-3.0, 0.2]), np.array([0.0, 0.0])
    out = _eval([DISC], [*p, *v], goal, _obs(po))
    D = p - po
    d = np.linalg.norm(D)
    u = D / d
    d_rate = u @ v
    r2, r3 = 0.8, 0.4
    lam = (r2 - d) ** 2 / (d - r3)
    lam_rate = -d_rate * (r2 - d) ** 2 / (d - r3) ** 2
    alpha = math.atan2(goal[1] - po[1], goal[0] - po[0])
    beta = math.atan2(D[1], D[0])
    phi = alpha - beta  # in (0, pi): the shorter arc is counter-clockwise (sigma = +1)
    u_perp = np.array([-u[1], u[0]])
    beta_rate = u_perp @ v / d
    phi_rate = -beta_rate
    psi = (r2 - d) ** 2 * phi
    psi_rate = (r2 - d) ** 2 * phi_rate
    F_a = 3.0 * (goal - p) - 0.75 * v
    F = F_a + (20 * lam + 5 * lam_rate) * u + (17 * psi + 4.25 * psi_rate) * u_perp
    np.testing.assert_allclose(out["F"], F, rtol=1e-10)
    assert out["sigma"][0] == 1


def test_repulsion_is_unbounded_at_the_critical_boundary() -> None:
    mags = []
    for gap in (1e-1, 1e-2, 1e-3, 1e-4):
        out = _eval([DISC], [0.4 + gap, 0.0, 0.0, 0.0], [-3.0, 0.001], _obs([0.0, 0.0]))
        mags.append(out["F"][0] - 3.0 * (-3.0 - 0.4 - gap))
    assert all(b > 9 * a for a, b in itertools.pairwise(mags))
    out = _eval([DISC], [0.4, 0.0, 0.0, 0.0], [-3.0, 0.0], _obs([0.0, 0.0]))
    assert out["critical"][0] == 1


def _pairs_across(geo: ObstacleGeometry, eps: float):  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(3)
    for _ in range(25):
        ang = rng.uniform(-math.pi, math.pi)
        n = np.array([math.cos(ang), math.sin(ang)])
        if geo.kind == "disc":
            base = np.zeros(2)
        else:  # a point on the rectangle contour (sides and corners)
            base = np.clip(
                n * 2.0, [-geo.half_length, -geo.half_width], [geo.half_length, geo.half_width]
            )
            # outward direction from the contour point (the diagonal at a corner)
            out = np.array(
                [
                    np.sign(base[0]) * (abs(base[0]) >= geo.half_length),
                    np.sign(base[1]) * (abs(base[1]) >= geo.half_width),
                ]
            )
            n = out / np.linalg.norm(out) if np.linalg.norm(out) else n
        v = rng.normal(size=2) * 0.4
        vo = rng.normal(size=2) * 0.5 if geo.moving else np.zeros(2)
        goal = rng.normal(size=2) * 0.5 + 4.0 * np.array([math.cos(ang + 2.5), math.sin(ang + 2.5)])
        yield base + n * (geo.r2 - eps), base + n * (geo.r2 + eps), v, vo, goal


@pytest.mark.parametrize("geo", [DISC, HUMAN, RECT], ids=["disc", "human", "rectangle"])
@pytest.mark.parametrize("stab", [0.0, 1.0], ids=["off", "lyapunov"])
def test_field_is_continuous_across_every_active_boundary(
    geo: ObstacleGeometry, stab: float
) -> None:
    # (5.4.9)-(5.4.15): Lambda, Lambda'*, psi, psi'* and F_L vanish at d = r2
    for eps in (1e-4, 1e-6):
        for p_in, p_out, v, vo, goal in _pairs_across(geo, eps):
            fin = _eval([geo], [*p_in, *v], goal, _obs([0, 0], vo), stab=stab)
            fout = _eval([geo], [*p_out, *v], goal, _obs([0, 0], vo), stab=stab)
            assert fin["active"][0] == 1 and fout["active"][0] == 0
            jump = np.linalg.norm(fin["F"] - fout["F"])
            assert jump < 2e3 * eps + 1e-9, (eps, jump)
            # V is continuous too (5.5.3)-(5.5.5)
            assert abs(fin["V"][0] - fout["V"][0]) < 1e3 * eps * max(1.0, fout["V"][0])


def test_detour_rules_stationary_goes_the_short_way_round() -> None:
    # robot below the line obstacle->goal: the shorter arc is clockwise (sigma = -1)
    out = _eval([DISC], [0.6, -0.1, 0, 0], [-3.0, 0.0], _obs([0.0, 0.0]))
    assert out["sigma"][0] == -1
    out = _eval([DISC], [0.6, 0.1, 0, 0], [-3.0, 0.0], _obs([0.0, 0.0]))
    assert out["sigma"][0] == 1


def test_detour_rule_goes_behind_a_walking_human() -> None:
    # human at the origin walking +y; robot on the +x side, goal on the -x side (different sides)
    x = [1.5, 0.3, 0.0, 0.0]
    goal = [-3.0, 0.0]
    out = _eval([HUMAN], x, goal, _obs([0.0, 0.0], (0.0, 1.0)))
    u = np.array(x[:2]) / np.linalg.norm(x[:2])
    u_psi = out["sigma"][0] * np.array([-u[1], u[0]])
    assert u_psi @ np.array([0.0, 1.0]) < 0  # behind = against the walking direction
    # same side as the goal: towards the goal (the shorter arc)
    out2 = _eval([HUMAN], [-1.5, 0.3, 0, 0], [-3.0, -1.0], _obs([0.0, 0.0], (0.0, 1.0)))
    assert out2["sigma"][0] == 1  # delta = alpha - beta > 0 here


@pytest.mark.parametrize("tie, side", [(1.0, 1.0), (-1.0, -1.0)])
def test_exactly_collinear_tie_break_follows_the_chosen_y_side(tie: float, side: float) -> None:
    out = _eval([DISC], [0.6, 0.0, -0.3, 0.0], [-3.0, 0.0], _obs([0.0, 0.0]), tie=tie)
    u_psi_y = out["sigma"][0] * 1.0  # u_perp = (0, 1) for u_Lambda = (1, 0)
    assert np.sign(u_psi_y) == side
    assert np.sign(out["F"][1]) == side


def test_other_obstacles_decide_the_collinear_side_5_4_4() -> None:
    # collinear with disc 0; disc 1 (active, below-left of the robot) pushes its detour with +y
    geos = [DISC, ObstacleGeometry("disc", r2=0.8, r3=0.4)]
    x = [0.6, 0.0, 0.0, 0.0]
    obs = _obs([0.0, 0.0]) + _obs([0.75, -0.65])
    for tie in (1.0, -1.0):
        out = _eval(geos, x, [-3.0, 0.0], obs, tie=tie)
        assert out["active"].tolist() == [1, 1]
        other = _eval([geos[1]], x, [-3.0, 0.0], _obs([0.75, -0.65]))
        # the side of disc 0 agrees with the sign of u_perp . F_psi,other, whatever the tie-break
        D1 = np.array(x[:2]) - np.array([0.75, -0.65])
        u1 = D1 / np.linalg.norm(D1)
        fpsi1 = other["F"] - 3.0 * (np.array([-3.0, 0.0]) - x[:2])
        fpsi1 = fpsi1 - (fpsi1 @ u1) * u1
        assert out["sigma"][0] == np.sign(fpsi1[1])


def test_rectangle_separating_robot_and_goal_detours_around_the_near_end() -> None:
    # robot right of the rectangle, slightly above its centre line; goal straight through it
    out = _eval([RECT], [1.2, 0.1, 0, 0], [-3.0, 0.05], _obs([0.0, 0.0]))
    u_perp = np.array([0.0, 1.0])
    assert out["sigma"][0] * u_perp[1] > 0  # goes over the top (the robot's half)
    out = _eval([RECT], [1.2, -0.1, 0, 0], [-3.0, 0.05], _obs([0.0, 0.0]))
    assert out["sigma"][0] * u_perp[1] < 0


@settings(max_examples=40, deadline=None)
@given(x=st.floats(-3, 3), y=st.floats(-3, 3))
def test_rectangle_distance_is_the_contour_distance(x: float, y: float) -> None:
    d = float(build_distance((RECT,))(np.array([x, y]), np.zeros(2)))
    dx = max(abs(x) - 0.7, 0.0)
    dy = max(abs(y) - 0.3, 0.0)
    assert d == pytest.approx(math.hypot(dx, dy), abs=1e-9)


def test_masoud_field_is_discontinuous_at_r2() -> None:
    # Sec. 2.2.4: F_Lambda = K D jumps at r2 (the new VFF does not)
    inside = _eval(
        [DISC],
        [0.8 - 1e-6, 0, 0, 0],
        [-3, 0.3],
        _obs([0, 0]),
        method="masoud",
        gains=[5, 0, 24, 36],
    )
    outside = _eval(
        [DISC],
        [0.8 + 1e-6, 0, 0, 0],
        [-3, 0.3],
        _obs([0, 0]),
        method="masoud",
        gains=[5, 0, 24, 36],
    )
    assert np.linalg.norm(inside["F"] - outside["F"]) > 10.0


def test_unknown_method_is_rejected() -> None:
    with pytest.raises(InvalidParameterError, match="method"):
        build_field((DISC,), "potential")


@settings(max_examples=40, deadline=None)
@given(
    d=st.floats(0.41, 0.79),
    ang=st.floats(-math.pi, math.pi),
    speed=st.floats(-0.7, 0.0),
)
def test_repulsion_pushes_away_and_grows_towards_r3(d: float, ang: float, speed: float) -> None:
    """Radial part of F - F_a: positive (away) for a robot approaching at rest-or-closing speed,
    and larger closer to r3 (5.4.3)."""
    u = np.array([math.cos(ang), math.sin(ang)])
    goal = -4.0 * u + np.array([0.0, 1e-3])

    def radial(dist: float) -> float:
        x = [*(dist * u), *(speed * u)]
        out = _eval([DISC], x, goal, _obs([0.0, 0.0]))
        F_a = 3.0 * (goal - dist * u) - 0.75 * speed * u
        return float((out["F"] - F_a) @ u)

    assert radial(d) > 0
    assert radial(max(0.405, d - 0.02)) > radial(d)
