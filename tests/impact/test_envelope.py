"""Foam envelope (Zeng 2011, Sec. 3.9, Figs. 3.13-3.19): thesis statements and solver checks."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import designlab as dl
from designlab.impact import (
    FOAM_1,
    FOAM_2,
    FOAM_3,
    HEAD_MAX,
    HEAD_MIN,
    MANIPULATOR_1,
    MANIPULATOR_2,
    HeadAcceleration,
    ImpactForce,
)

C_GRID = np.linspace(0, 200, 41)
TEN_G = [HeadAcceleration(max_g=10)]


@pytest.fixture(scope="module")
def env1() -> dl.impact.FoamEnvelope:
    return dl.impact.foam_envelope(MANIPULATOR_1, 1.25, C_GRID, TEN_G, 0.02)


@pytest.fixture(scope="module")
def env2() -> dl.impact.FoamEnvelope:
    return dl.impact.foam_envelope(MANIPULATOR_2, 1.25, C_GRID, TEN_G, 0.02)


def _metric(robot, foam_k, foam_c, head, v=1.25):
    p = [
        robot.mass,
        robot.damping,
        robot.stiffness,
        foam_k,
        foam_c,
        head.mass,
        head.damping,
        head.stiffness,
    ]
    return dl.impact.impact_metrics(p, v, columns=dl.impact.PARAM_NAMES)


def test_foam_1_feasible_on_both_manipulators(env1, env2) -> None:
    assert env1.is_feasible(24.3e3, 71.9)
    assert env1.is_feasible(FOAM_1.stiffness, FOAM_1.damping)
    assert env2.is_feasible(FOAM_1.stiffness, FOAM_1.damping)
    assert env1.margin(FOAM_1.stiffness, FOAM_1.damping) > 0.1


def test_foams_1_and_2_below_the_safety_boundary(env1, env2) -> None:
    for env in (env1, env2):
        for foam in (FOAM_1, FOAM_2):
            a = _metric(env.robot, foam.stiffness, foam.damping, HEAD_MIN)
            assert a.peak_head_acceleration_g[0] < 10


def test_foam_2_on_the_thickness_boundary_for_m1_far_below_for_m2(env1, env2) -> None:
    # Manipulator 1: Foam 2 lies within 2 % of the lower boundary (thesis: "almost on it")
    m1 = env1.margin(FOAM_2.stiffness, FOAM_2.damping)
    assert abs(m1) < math.log10(1.02)
    # with the App. A.1 measured stiffness it violates the thickness limit
    assert not env1.is_feasible(13.48e3, FOAM_2.damping)
    # Manipulator 2: far below the lower boundary (more than 20 % in stiffness)
    assert env2.margin(FOAM_2.stiffness, FOAM_2.damping) < -math.log10(1.2)
    eps = _metric(MANIPULATOR_2, FOAM_2.stiffness, FOAM_2.damping, HEAD_MAX).max_compression[0]
    assert eps > 0.02


def test_foam_3_not_safe_on_m2(env2) -> None:
    assert not env2.is_feasible(FOAM_3.stiffness, FOAM_3.damping)
    j = np.argmin(np.abs(C_GRID - 115))
    upper = dl.impact.foam_envelope(MANIPULATOR_2, 1.25, [FOAM_3.damping], TEN_G).stiffness_max[0]
    assert FOAM_3.stiffness > upper
    assert np.isfinite(env2.stiffness_max[j])


def test_region_of_m2_smaller(env1, env2) -> None:
    assert env2.area() < env1.area()
    assert env2.area(log=True) < env1.area(log=True)
    # pointwise: higher lower boundary and lower upper boundary over the physical foam range
    sl = slice(1, 20)
    assert np.all(env2.stiffness_min[sl] > env1.stiffness_min[sl])


def test_boundaries_are_roots_to_1e4(env1) -> None:
    ok = np.isfinite(env1.stiffness_max)
    p = np.column_stack(
        [np.tile([9.6, 250, 20e3], (ok.sum(), 1)), env1.stiffness_max[ok], C_GRID[ok],
         np.tile([HEAD_MIN.mass, HEAD_MIN.damping, HEAD_MIN.stiffness], (ok.sum(), 1))]
    )  # fmt: skip
    a = dl.impact.impact_metrics(p, 1.25, columns=dl.impact.PARAM_NAMES).peak_head_acceleration_g
    np.testing.assert_allclose(a, 10.0, rtol=1e-4)
    ok = np.isfinite(env1.stiffness_min)
    p = np.column_stack(
        [np.tile([9.6, 250, 20e3], (ok.sum(), 1)), env1.stiffness_min[ok], C_GRID[ok],
         np.tile([HEAD_MAX.mass, HEAD_MAX.damping, HEAD_MAX.stiffness], (ok.sum(), 1))]
    )  # fmt: skip
    eps = dl.impact.impact_metrics(p, 1.25, columns=dl.impact.PARAM_NAMES).max_compression
    # where the first lobe is delicate, eps_max jumps across the limit at the boundary
    # (the lobe end jumps): the boundary is the jump, reported on its feasible side
    jump = env1.delicate[ok]
    np.testing.assert_allclose(eps[~jump], 0.02, rtol=1e-4)
    assert np.all(eps[jump] <= 0.02 * (1 + 1e-6))
    below = p[jump].copy()
    below[:, 3] *= 1 - 1e-5
    eps_below = dl.impact.impact_metrics(below, 1.25, columns=dl.impact.PARAM_NAMES).max_compression
    assert np.all(eps_below > 0.02)
    assert set(env1.lower_status) == {"bounded"}


def test_velocity_closes_the_region() -> None:
    envs = [
        dl.impact.foam_envelope(MANIPULATOR_2, v, C_GRID[:21], TEN_G) for v in (1.25, 1.5, 1.75)
    ]
    for a, b in itertools.pairwise(envs):
        assert np.all(b.stiffness_max < a.stiffness_max)
        assert np.all(b.stiffness_min > a.stiffness_min)
        assert b.area() < a.area()
    closed = dl.impact.foam_envelope(MANIPULATOR_2, 3.0, C_GRID[:21], TEN_G)
    assert closed.is_empty
    assert set(closed.region_status) == {"empty"}


def test_status_reports_unbounded_and_no_solution() -> None:
    # a huge limit is never reached: unbounded; a tiny one is never met: no solution
    env = dl.impact.foam_envelope(
        MANIPULATOR_1, 1.25, [10.0, 60.0], [HeadAcceleration(max_g=500)], 0.5,
        stiffness_bounds=(1e3, 1e5),
    )  # fmt: skip
    assert list(env.upper_status["a_h,max <= 500 g"]) == ["unbounded", "unbounded"]
    assert np.all(np.isnan(env.stiffness_max))
    assert list(env.lower_status) == ["unbounded", "unbounded"]
    env = dl.impact.foam_envelope(MANIPULATOR_1, 1.25, [10.0], [HeadAcceleration(max_g=0.1)])
    assert env.upper_status["a_h,max <= 0.1 g"][0] == "no_solution"
    assert env.is_empty and env.margin(24e3, 10.0) == -np.inf


def test_criteria_force_hic_iso_and_constrained() -> None:
    crit = [HeadAcceleration(10), ImpactForce(660), dl.impact.HeadInjuryCriterion(650, 0.015),
            dl.impact.IsoQuasiStaticForce("skull_forehead")]  # fmt: skip
    env = dl.impact.foam_envelope(MANIPULATOR_1, 1.25, [40.0, 80.0], crit)
    # ISO/TS 15066 Table A.2 skull/forehead force (130 N) is the tightest of the four
    iso = env.upper[crit[3].name]
    assert np.all(env.stiffness_max == iso)
    for c in crit[:3]:
        st = env.upper_status[c.name]
        assert np.all((env.upper[c.name] >= iso) | (st == "unbounded"))
    assert set(env.upper_status[crit[2].name]) == {"unbounded"}  # HIC15 never near 650 here
    # f_c at the ISO boundary equals 130 N with the maximum head set (conservative for force)
    f = _metric(MANIPULATOR_1, iso[0], 40.0, HEAD_MAX).peak_force[0]
    assert f == pytest.approx(130.0, rel=1e-4)
    # constrained impact: force much larger, so a lower safe stiffness
    con = dl.impact.foam_envelope(MANIPULATOR_1, 1.25, [40.0], [ImpactForce(660)], constrained=True)
    assert con.stiffness_max[0] < env.upper["f_c,max <= 660 N"][0]
    with pytest.raises(dl.errors.InvalidParameterError, match="constrained"):
        dl.impact.foam_envelope(MANIPULATOR_1, 1.25, [40.0], TEN_G, constrained=True)


def test_thesis_head_sets_are_the_worst_case_in_the_foam_range(env1) -> None:
    """Sampled check: heads in the thesis ranges and velocities up to v_max never do worse.

    Holds over elastomeric foams (xi_c <= 0.2, impact.md Sec. 5); above it the first
    lobe becomes delicate and the envelope flags those points.
    """
    check = dl.impact.check_worst_case(env1, samples=48)
    xi = C_GRID / (2 * np.sqrt(4.4 * env1.stiffness_min))
    phys = xi <= 0.2
    for name, ratios in check.ratio_by_point.items():
        assert np.all(ratios[phys & np.isfinite(ratios)] <= 1 + 1e-6), name
    assert np.any(env1.delicate[~phys]) and not np.any(env1.delicate[phys])


def test_head_range_takes_the_worst_case_everywhere() -> None:
    env = dl.impact.foam_envelope(
        MANIPULATOR_1, 1.25, np.linspace(0, 200, 9), TEN_G, head_range=dl.impact.THESIS_HEAD_RANGE
    )
    check = dl.impact.check_worst_case(env, samples=48)
    assert check.holds, check.max_ratio
    base = dl.impact.foam_envelope(MANIPULATOR_1, 1.25, np.linspace(0, 200, 9), TEN_G)
    assert np.all(env.stiffness_max <= base.stiffness_max * (1 + 1e-5))
    assert np.all(env.stiffness_min >= base.stiffness_min * (1 - 1e-5))


def test_impact_point_along_the_link_worst_case_interior() -> None:
    link = dl.impact.LinkImpact.from_contact(
        MANIPULATOR_1, joint_speed=0.25 / 0.078, lever_arm_min=0.005, lever_arm_max=0.078
    )
    env = dl.impact.foam_envelope(link, None, [40.0, 70.0], TEN_G)
    lev = env.worst_lever_arm
    assert np.all((lev > 0.006) & (lev < 0.077))  # not at an end of the link
    # the worst impact point is a maximum: a dense sweep of lever arms never does worse
    ls = np.linspace(0.005, 0.078, 200)
    for i, c in enumerate([40.0, 70.0]):
        l2 = ls**2
        n = ls.size
        p = np.column_stack(
            [link.inertia / l2, link.joint_damping / l2, link.joint_stiffness / l2]
            + [np.full(n, x) for x in (env.stiffness_max[i], c, 4.4, 46.0, 3e3)]
        )
        a = dl.impact.impact_metrics(
            p, link.joint_speed * ls + 1.0, columns=dl.impact.PARAM_NAMES
        ).peak_head_acceleration_g
        assert a.max() <= 10 * (1 + 1e-6)
    assert dl.impact.check_worst_case(env, samples=32).holds


def test_mass_and_stiffness_trends_figs_3_13_3_14() -> None:
    head = HEAD_MIN
    masses = np.array([2.5, 5, 10, 20, 40, 60, 100])
    a = np.array([_metric(dl.impact.ContactDynamics(m, 20e3, 250), 24.25e3, 71.9, head)
                  .peak_head_acceleration_g[0] for m in masses])  # fmt: skip
    assert np.all(np.diff(a) > 0)  # a_h,max falls with M_r
    slope_small = (a[2] - a[1]) / 5
    slope_large = (a[6] - a[5]) / 40
    assert slope_small > 5 * slope_large  # mass matters below ~20 kg, little above 40 kg
    heavy = dl.impact.ContactDynamics(100.0, 20e3, 250)
    for foam, safe in ((FOAM_1, True), (FOAM_2, True), (FOAM_3, False)):
        assert (
            _metric(heavy, foam.stiffness, foam.damping, head).peak_head_acceleration_g[0] < 10
        ) == safe
    # K_r: falls with K_r, less than with M_r; vanishes above ~40 K_c
    base = _metric(
        dl.impact.ContactDynamics(9.6, 20e3, 250), 24.25e3, 71.9, head
    ).peak_head_acceleration[0]
    half_k = _metric(
        dl.impact.ContactDynamics(9.6, 10e3, 250), 24.25e3, 71.9, head
    ).peak_head_acceleration[0]
    half_m = _metric(
        dl.impact.ContactDynamics(4.8, 20e3, 250), 24.25e3, 71.9, head
    ).peak_head_acceleration[0]
    assert half_k < base and (base - half_k) < (base - half_m)
    k1 = _metric(
        dl.impact.ContactDynamics(9.6, 40 * 24.25e3, 250), 24.25e3, 71.9, head
    ).peak_head_acceleration[0]
    k2 = _metric(
        dl.impact.ContactDynamics(9.6, 80 * 24.25e3, 250), 24.25e3, 71.9, head
    ).peak_head_acceleration[0]
    assert abs(k2 / k1 - 1) < 0.01
    c2 = _metric(
        dl.impact.ContactDynamics(9.6, 20e3, 500), 24.25e3, 71.9, head
    ).peak_head_acceleration[0]
    assert abs(c2 / base - 1) < 0.05  # C_r doubled: minor effect


def test_max_safe_velocity_and_min_thickness_are_exact() -> None:
    sv = dl.impact.max_safe_velocity(MANIPULATOR_1, FOAM_1, TEN_G)
    assert sv.limiting == "eps_max <= 20 mm"
    eps = _metric(MANIPULATOR_1, FOAM_1.stiffness, FOAM_1.damping, HEAD_MAX, sv.impact_velocity)
    assert eps.max_compression[0] == pytest.approx(0.02, rel=1e-9)
    a = _metric(MANIPULATOR_1, FOAM_1.stiffness, FOAM_1.damping, HEAD_MIN,
                sv.per_constraint["a_h,max <= 10 g"])  # fmt: skip
    assert a.peak_head_acceleration_g[0] == pytest.approx(10.0, rel=1e-9)
    assert sv.manipulator_speed == pytest.approx(sv.impact_velocity - 1.0)
    th = dl.impact.min_foam_thickness(MANIPULATOR_1, FOAM_1, 1.25)
    eps = _metric(MANIPULATOR_1, FOAM_1.stiffness, FOAM_1.damping, HEAD_MAX).max_compression[0]
    assert th.linear_depth == pytest.approx(eps)
    assert th.thickness == pytest.approx(eps * 0.0254 / 0.02)
    hic = dl.impact.max_safe_velocity(MANIPULATOR_1, FOAM_3, [dl.impact.HeadInjuryCriterion(650)])
    assert hic.per_constraint["HIC15 <= 650"] > 3.0  # HIC is far from binding for these foams


def test_optimal_foam_matches_dense_grid_search() -> None:
    opt = dl.impact.optimal_foam(MANIPULATOR_1, 1.25, TEN_G, 0.02)
    assert opt.status == "ok"
    # dense grid over the same feasible set (xi_c in [0.05, 0.2])
    k = np.geomspace(1e3, 2e5, 160)
    c = np.linspace(0, 200, 161)
    kk, cc = np.meshgrid(k, c, indexing="ij")
    xi = cc / (2 * np.sqrt(4.4 * kk))
    sel = (xi >= 0.05) & (xi <= 0.2)
    kk, cc = kk[sel], cc[sel]
    n = kk.size
    pa = np.column_stack(
        [np.tile([9.6, 250, 20e3], (n, 1)), kk, cc, np.tile([4.4, 46.0, 3e3], (n, 1))]
    )
    pe = np.column_stack(
        [np.tile([9.6, 250, 20e3], (n, 1)), kk, cc, np.tile([5.3, 130.2, 5e3], (n, 1))]
    )
    ga = np.log(
        10
        * 9.80665
        / dl.impact.impact_metrics(
            pa, 1.25, with_force=False, columns=dl.impact.PARAM_NAMES
        ).peak_head_acceleration
    )
    ge = np.log(
        0.02
        / dl.impact.impact_metrics(
            pe, 1.25, with_force=False, columns=dl.impact.PARAM_NAMES
        ).max_compression
    )
    best = np.max(np.minimum(ga, ge))
    assert opt.margin >= best - 1e-6
    assert opt.margin <= best + 0.01  # the grid is fine: the optimum cannot be much better
    j = np.argmax(np.minimum(ga, ge))
    assert opt.stiffness == pytest.approx(kk[j], rel=0.05)
    assert opt.damping == pytest.approx(cc[j], abs=5.0)
    assert opt.margins["eps_max <= 20 mm"] == pytest.approx(
        opt.margins["a_h,max <= 10 g"], abs=1e-6
    )


def test_optimal_foam_reports_empty_region_and_reopening_velocity() -> None:
    opt = dl.impact.optimal_foam(MANIPULATOR_2, 2.5, TEN_G, 0.02)
    assert opt.status == "empty" and opt.margin < 0
    assert opt.reopen_velocity < 2.5
    again = dl.impact.optimal_foam(MANIPULATOR_2, opt.reopen_velocity * 0.999, TEN_G, 0.02)
    assert again.status == "ok" and again.margin >= 0
    closed = dl.impact.optimal_foam(MANIPULATOR_2, opt.reopen_velocity * 1.01, TEN_G, 0.02)
    assert closed.status == "empty"


def test_thinnest_foam() -> None:
    opt = dl.impact.optimal_foam(
        MANIPULATOR_1,
        1.25,
        TEN_G,
        thickness_bounds=(0.005, 0.03),
        objective="thinnest",
        min_margin=0.05,
    )
    assert opt.status == "ok"
    assert 0.005 < opt.linear_depth < 0.02
    assert min(opt.margins.values()) == pytest.approx(0.05, abs=1e-6)


def test_bad_envelope_input() -> None:
    with pytest.raises(dl.errors.InvalidParameterError, match="damping"):
        dl.impact.foam_envelope(MANIPULATOR_1, 1.25, [-1.0])
    with pytest.raises(dl.errors.InvalidParameterError, match="impact_velocity"):
        dl.impact.foam_envelope(MANIPULATOR_1, -1.0)
    with pytest.raises(dl.errors.InvalidParameterError, match="max_compression"):
        dl.impact.foam_envelope(MANIPULATOR_1, 1.25, max_compression=0.0)
    with pytest.raises(dl.errors.InvalidParameterError, match="body_region"):
        dl.impact.IsoTransientForce("elbow")
    # Table A.2 gives no transient multiplier for the head regions: refused unless given
    for region in ("skull_forehead", "face"):
        with pytest.raises(dl.errors.InvalidParameterError, match="no transient-contact"):
            dl.impact.IsoTransientForce(region)
    assert dl.impact.IsoTransientForce("face", transient_factor=1.5).limit == 97.5
    assert dl.impact.IsoTransientForce("chest").limit == 280.0
    assert dl.impact.IsoQuasiStaticForce("face").limit == 65.0
    with pytest.raises(dl.errors.InvalidParameterError, match="transient_factor"):
        dl.impact.IsoTransientForce("chest", transient_factor=-2.0)


def test_impact_point_sweep_fig_3_16() -> None:
    """Fig. 3.16 (Foam 1, minimum head set), one reading of the unstated speeds
    (docs/impact.md, "Unstated inputs"): joint speed 0.5 rad/s, head speed 1 m/s.

    Manipulator 1: the worst impact is close to the joint (l ~ 0.01 m) and a_h,max
    decreases farther out; Manipulator 2: the worst impact is at the distal end.
    """
    m11 = 9.6 * 0.078**2
    l1 = np.array([1e-4, 0.005, 0.01, 0.02, 0.04, 0.078])
    s1 = dl.impact.impact_point_sweep(m11, 20e3 * 0.078**2, 250 * 0.078**2, 0.5, l1)
    a1 = s1.evaluate(FOAM_1, HEAD_MIN)["a_h_max_g"].to_numpy()
    j = int(np.argmax(a1))
    assert l1[j] == pytest.approx(0.01)
    assert np.all(np.diff(a1[j:]) < 0)
    l2 = np.linspace(0.05, 0.5, 10)
    s2 = dl.impact.impact_point_sweep(49.4 * 0.25, 14.4e3 * 0.25, 111 * 0.25, 0.5, l2)
    a2 = s2.evaluate(FOAM_1, HEAD_MIN)["a_h_max_g"].to_numpy()
    assert int(np.argmax(a2)) == l2.size - 1 and np.all(np.diff(a2) > 0)
