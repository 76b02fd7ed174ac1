"""Full series joint (Zeng 2011, eq. 3.4.6) in the impact model, and the error of its reductions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.impact import FOAM_1, HEAD_MAX, HEAD_MIN, MANIPULATOR_1, TEST_HEAD
from designlab.impact.full_joint import (
    FullJointContact,
    compare_joint_reductions,
    full_joint_model,
    full_joint_params,
    joint_reduction_sweep,
    matrix_metrics,
)
from designlab.impact.metrics import impact_metrics
from designlab.impact.model import param_vector
from designlab.results import check_result

# The illustrative geared joint of tests/impact/test_joint.py (not a thesis joint) on a
# light arm: m_11 = 0.059 kg m^2 struck at l = 0.2 m.
GEARED = (2.0e3, 2.0, 1.5e3, 30.0)
ARM = FullJointContact.from_joint(0.059, *GEARED, lever_arm=0.2)


def _rel(a: float, b: float) -> float:
    return (a - b) / b


# --- the stiff-transmission limit -----------------------------------------------------------


@pytest.mark.parametrize("head", [HEAD_MIN, TEST_HEAD, None])
def test_stiff_transmission_gives_the_reduced_model(head) -> None:
    """K_mech -> infinity: the full joint is the reduced one with K_r = K_cont, C_r = C_cont.

    The difference is O(K_cont/K_mech); at K_mech = 1e7 K_cont every metric agrees to 1e-6.
    """
    m = MANIPULATOR_1
    full = FullJointContact(m.mass, 1e7 * m.stiffness, 0.0, m.stiffness, m.damping)
    a = dl.impact.simulate(full, FOAM_1, head, 1.25)
    b = dl.impact.simulate(m, FOAM_1, head, 1.25)
    pairs = [(a.peak_force, b.peak_force), (a.max_compression, b.max_compression)]
    if head is not None:
        pairs += [
            (a.peak_head_acceleration, b.peak_head_acceleration),
            (a.impact_duration, b.impact_duration),
        ]
    for x, y in pairs:
        assert abs(_rel(x, y)) < 1e-6
    # the batch engine, for (N, 10) rows, agrees as well
    rows = np.array([full_joint_params(full, FOAM_1, head)])
    mb = matrix_metrics(rows, 1.25, constrained=head is None)
    assert abs(_rel(float(mb.max_compression[0]), b.max_compression)) < 1e-6
    if head is not None:  # HIC of the batch engine, on full-joint rows
        from designlab.impact.metrics import hic_batch

        reduced = matrix_metrics(param_vector(m, FOAM_1, head)[None, :], 1.25)
        assert abs(_rel(float(hic_batch(mb)[0]), float(hic_batch(reduced)[0]))) < 1e-5
    # and the error shrinks like 1/K_mech
    errs = []
    for ratio in (1e2, 1e3, 1e4):
        f = FullJointContact(m.mass, ratio * m.stiffness, 0.0, m.stiffness, m.damping)
        errs.append(abs(_rel(dl.impact.simulate(f, FOAM_1, head, 1.25).peak_force, b.peak_force)))
    assert errs[0] / errs[1] == pytest.approx(10.0, rel=0.05)
    assert errs[1] / errs[2] == pytest.approx(10.0, rel=0.05)


# --- the time response against an independent integration -----------------------------------


def _rhs_full(p, v_c, acc=0.0, dur=0.05, feedforward=True):
    """The full-joint impact written out by hand (not the package's model).

    Absolute coordinates along the normal: arm x_r, motor node x_e, head x_h; the
    desired motion x_d(t) and the torso x_t(t) = T_u - v_h t are prescribed.
    """
    m_r, c_m, k_m, k_c, c_c, m_h, c_h, k_h, c_q, k_q = p

    def desired(t):
        tau = min(t, dur)
        a = acc if t < dur else 0.0
        return v_c * t + 0.5 * acc * tau**2 + acc * dur * max(t - dur, 0.0), v_c + acc * tau, a

    def rhs(t, z):
        x_r, v_r, x_e, x_h, v_h = z
        x_d, v_d, a_d = desired(t)
        x_t, v_t = 0.0, 0.0  # the head frame; the closing speed is all in x_d (v_h(0) = 0)
        eps = x_r - x_h
        f_c = k_c * eps + c_c * (v_r - v_h)
        f_ff = m_r * a_d if feedforward else 0.0
        # massless node: K_m(x_r - x_e) + C_m(v_r - v_e) = K_q(x_e - x_d) + C_q(v_e - v_d) - f_ff
        v_e = (k_m * (x_r - x_e) + c_m * v_r - k_q * (x_e - x_d) + c_q * v_d + f_ff) / (c_m + c_q)
        f_t = k_m * (x_r - x_e) + c_m * (v_r - v_e)
        a_r = (-f_c - f_t) / m_r
        a_h = (f_c - c_h * (v_h - v_t) - k_h * (x_h - x_t)) / m_h
        return [v_r, a_r, v_e, v_h, a_h]

    def outputs(t, z):
        x_r, v_r, _, x_h, v_h = z
        return k_c * (x_r - x_h) + c_c * (v_r - v_h), x_r - x_h

    return rhs, outputs


@pytest.mark.parametrize(
    "profile",
    [
        None,
        dl.impact.VelocityProfile(5.0, 0.02, True),
        dl.impact.VelocityProfile(-5.0, 0.02, False),
    ],
)
def test_full_joint_response_equals_dop853(profile) -> None:
    p = full_joint_params(ARM, FOAM_1, HEAD_MIN)
    v_c = 1.25
    r = dl.impact.simulate(ARM, FOAM_1, HEAD_MIN, v_c, profile=profile, duration=0.06, samples=121)
    acc = 0.0 if profile is None else profile.acceleration
    dur = 0.05 if profile is None else profile.duration
    ff = True if profile is None else profile.feedforward
    rhs, outputs = _rhs_full(p, v_c, acc, dur, ff)
    z0 = [0.0, v_c, 0.0, 0.0, 0.0]  # contact: the arm moves at v_c, node on the desired path
    sol = solve_ivp(rhs, (0.0, 0.06), z0, method="DOP853", t_eval=r.t, rtol=1e-12, atol=1e-14)
    assert sol.success
    f_ode, eps_ode = outputs(sol.t, sol.y)
    a_ode = np.array([rhs(t, z)[4] for t, z in zip(sol.t, sol.y.T, strict=True)])
    scale_f = np.abs(f_ode).max()
    assert np.max(np.abs(r.force - f_ode)) < 1e-8 * scale_f
    assert np.max(np.abs(r.compression - eps_ode)) < 1e-8 * np.abs(eps_ode).max()
    assert np.max(np.abs(r.head_acceleration - a_ode)) < 1e-8 * np.abs(a_ode).max()
    # the first-lobe maxima are the maxima of the integrated history (fine grid)
    fine = solve_ivp(
        rhs, (0.0, r.impact_duration), z0, method="DOP853", dense_output=True,
        rtol=1e-12, atol=1e-14,
    )  # fmt: skip
    tt = np.linspace(0.0, r.impact_duration, 20001)
    zz = fine.sol(tt)
    a_fine = np.array([rhs(t, z)[4] for t, z in zip(tt, zz.T, strict=True)])
    assert r.peak_head_acceleration == pytest.approx(a_fine.max(), rel=1e-7)
    assert r.peak_force == pytest.approx(outputs(tt, zz)[0].max(), rel=1e-7)


def test_full_joint_impedance_is_equation_3_4_6() -> None:
    """With the arm held (x_r given), the joint's force is (3.4.6) divided by l^2."""
    model = full_joint_model(constrained=True)
    p = full_joint_params(ARM, FOAM_1, None)
    a, _, c, _ = model.matrices(p)
    # transmission force f_t responds to delta_r through the node state only:
    # f_t = K_m (d_r - d_e) + C_m (d_r' - d_e'), C d_e' = K_m d_r + C_m d_r' - (K_m + K_q) d_e
    km, cm, kq, cq = (
        ARM.transmission_stiffness,
        ARM.transmission_damping,
        ARM.control_stiffness,
        ARM.control_damping,
    )
    assert a[2, 0] == pytest.approx(km / (cm + cq))
    assert a[2, 1] == pytest.approx(cm / (cm + cq))
    assert a[2, 2] == pytest.approx(-(km + kq) / (cm + cq))
    for w in (1.0, 30.0, 300.0):
        s = 1j * w
        node = (km + cm * s) / ((km + kq) + (cm + cq) * s)  # D_e / D_r
        f_t = (km + cm * s) * (1 - node)
        expect = (km + cm * s) * (kq + cq * s) / ((km + kq) + (cm + cq) * s)
        assert f_t == pytest.approx(expect, rel=1e-12)
        # the same from the model's own output row "transmission_force"
        row = c[model.output_names.index("transmission_force")]
        assert row[0] + row[1] * s + row[2] * node == pytest.approx(expect, rel=1e-12)


@settings(max_examples=25, deadline=None)
@given(
    ratio=st.floats(0.05, 1e3),
    c_m=st.floats(0.0, 500.0),
    c_q=st.floats(1.0, 800.0),
    k_c=st.floats(5e3, 1e5),
    head=st.booleans(),
)
def test_long_time_force_slope_is_static_series_stiffness(ratio, c_m, c_q, k_c, head) -> None:
    """At long times the force is a ramp of slope v_c / (1/K_J + 1/K_c [+ 1/K_h]).

    K_J = K_mech K_cont/(K_mech + K_cont) is exact at s = 0 for the full joint too.
    """
    from designlab.impact.metrics import ramp_responses, response_model

    k_q = 2e4
    arm = FullJointContact(5.0, ratio * k_q, c_m, k_q, c_q)
    foam = dl.impact.Foam(k_c, 60.0)
    h = HEAD_MIN if head else None
    rows = full_joint_params(arm, foam, h)[None, :]
    resp = ramp_responses(response_model(rows, h is None), rows, ("force",))["force"]
    k_j = ratio * k_q * k_q / (ratio * k_q + k_q)
    compliance = 1 / k_j + 1 / k_c + (1 / HEAD_MIN.stiffness if head else 0.0)
    assert resp.poly[0, 0] == pytest.approx(1 / compliance, rel=1e-9)


@settings(max_examples=25, deadline=None)
@given(
    ratio=st.floats(0.05, 1e4),
    c_m=st.floats(0.0, 300.0),
    c_q=st.floats(5.0, 800.0),
    mass=st.floats(0.5, 50.0),
    k_c=st.floats(5e3, 1e5),
)
def test_state_space_responses_equal_the_matrix_exponential(ratio, c_m, c_q, mass, k_c) -> None:
    """The eigen-decomposition responses equal expm of the augmented system (ramp input)."""
    from scipy.linalg import expm

    from designlab.impact.full_joint import modal_families

    arm = FullJointContact(mass, ratio * 2e4, c_m, 2e4, c_q)
    rows = full_joint_params(arm, dl.impact.Foam(k_c, 60.0), HEAD_MIN)[None, :]
    model = full_joint_model()
    a, b, c, d = model.matrices(rows[0])
    # z = [x, s_c, v_c]: s_c' = v_c, v_c' = 0, x' = A x + B [s_c, v_c, 0, 0]
    n = a.shape[0]
    aug = np.zeros((n + 2, n + 2))
    aug[:n, :n] = a
    aug[:n, n : n + 2] = b[:, :2]
    aug[n, n + 1] = 1.0
    z0 = np.zeros(n + 2)
    z0[n + 1] = 1.0
    fam = modal_families(model, rows, ("force", "head_acceleration"))["ramp"]
    for t in (0.0, 0.003, 0.011, 0.02, 0.045):
        z = expm(aug * t) @ z0
        y = c @ z[:n] + d[:, :2] @ z[n:]
        for name in ("force", "head_acceleration"):
            k = model.output_names.index(name)
            got = float(fam[name].evaluate(np.array([t]))[0, 0])
            assert got == pytest.approx(y[k], rel=1e-7, abs=1e-9 * (1 + abs(y[k])))


def test_nearly_defective_designs_fall_back_to_the_transfer_functions(monkeypatch) -> None:
    """Designs whose eigenvectors are ill-conditioned use the polynomial route; the
    splice keeps the other designs of the batch as they were."""
    import designlab.impact.state_space as fj

    other = ARM.replace(control_damping=300.0)
    rows = np.array([full_joint_params(a, FOAM_1, HEAD_MIN) for a in (ARM, other)])
    ref = matrix_metrics(rows, 1.25)
    monkeypatch.setattr(fj, "MAX_EIGVEC_CONDITION", 0.0)  # every design "defective"
    got = matrix_metrics(rows, 1.25)
    for attr in ("peak_head_acceleration", "max_compression", "peak_force", "impact_duration"):
        np.testing.assert_allclose(getattr(got, attr), getattr(ref, attr), rtol=1e-9)
    t = np.linspace(0.0, 0.05, 11)
    fam = fj.modal_families(full_joint_model(), rows, ("force",), ("ramp", "a_ff"))
    monkeypatch.setattr(fj, "MAX_EIGVEC_CONDITION", 1e8)
    eig = fj.modal_families(full_joint_model(), rows, ("force",), ("ramp", "a_ff"))
    for key in ("ramp", "a_ff"):
        a, b = fam[key]["force"].evaluate(t), eig[key]["force"].evaluate(t)
        assert np.max(np.abs(a - b)) < 1e-9 * np.abs(b).max()


# --- the error of the reductions ----------------------------------------------------------


def test_illustrative_joint_taylor_overestimates_head_acceleration() -> None:
    """The issue's check: the Taylor joint overestimates a_h,max by about 12.5 %."""
    c = compare_joint_reductions(ARM, FOAM_1, HEAD_MIN, 1.25)
    check_result(c)
    assert c.status == "ok"
    assert c.relative_error("taylor", "a_h_max") == pytest.approx(0.1253, abs=5e-4)
    assert c.conservative("taylor", "a_h_max")
    # ...but it UNDERestimates the compression and the force (non-conservative for the
    # thickness and force criteria): -10.2 % and -10.8 %
    assert c.relative_error("taylor", "eps_max") == pytest.approx(-0.1015, abs=5e-4)
    assert c.relative_error("taylor", "f_c_max") == pytest.approx(-0.1080, abs=5e-4)
    assert not c.conservative("taylor", "eps_max")
    # the comparison's values are the package's metrics of each model
    full = dl.impact.simulate(ARM, FOAM_1, HEAD_MIN, 1.25)
    assert c.value("full", "eps_max") == pytest.approx(full.max_compression, rel=1e-9)
    red = dl.impact.simulate(ARM.taylor(), FOAM_1, HEAD_MIN, 1.25)
    assert c.value("taylor", "f_c_max") == pytest.approx(red.peak_force, rel=1e-9)


def test_illustrative_joint_band_fit() -> None:
    """The band fit's error depends on the band.

    The issue quotes +8.9 % for the band fit and an rms ratio (fit/Taylor, frequency
    domain) of 0.67. Both are reproduced, but not with the same band: 0.67 is the
    ratio for omega_max = 200 rad/s, where the band fit overestimates a_h,max by
    +3.7 %; +8.9 % is the error for omega_max = 89.6 rad/s (rms ratio 0.84).
    """
    c200 = compare_joint_reductions(ARM, FOAM_1, HEAD_MIN, 1.25, omega_max=200.0)
    assert c200.band.rms_error / c200.band.taylor_rms_error == pytest.approx(0.672, abs=2e-3)
    assert c200.relative_error("band_fit", "a_h_max") == pytest.approx(0.0369, abs=5e-4)
    c90 = compare_joint_reductions(ARM, FOAM_1, HEAD_MIN, 1.25, omega_max=89.6)
    assert c90.relative_error("band_fit", "a_h_max") == pytest.approx(0.089, abs=5e-4)
    # the band sweep puts the frequency-domain and the metric errors side by side
    sweep = dl.impact.band_fit_sweep(ARM, FOAM_1, HEAD_MIN, 1.25, [89.6, 200.0, 541.7])
    check_result(sweep)
    assert sweep.errors("a_h_max")[1] == pytest.approx(
        c200.relative_error("band_fit", "a_h_max"), rel=1e-9
    )
    assert sweep.to_frame()["taylor_err_a_h_max"].iloc[0] == pytest.approx(0.1253, abs=5e-4)
    assert np.all(np.diff(sweep.rms_ratio) < 0)  # a wider band: "better" in frequency ...
    assert np.all(np.diff(sweep.errors("a_h_max")) < 0)  # ... and down to non-conservative
    # a wide band (3x the fastest impact mode) makes the fit NON-conservative on a_h,max
    wide = compare_joint_reductions(ARM, FOAM_1, HEAD_MIN, 1.25, omega_max=541.7)
    assert wide.relative_error("band_fit", "a_h_max") < 0
    assert not wide.conservative("band_fit", "a_h_max")


@settings(max_examples=12, deadline=None)
@given(
    inertia=st.floats(0.01, 1.0),
    lever=st.floats(0.05, 0.6),
    k_cont=st.floats(50.0, 5e3),
    zeta=st.floats(0.01, 0.5),
    c_mech=st.floats(0.0, 5.0),
)
def test_reductions_become_exact_for_a_stiff_transmission(inertia, lever, k_cont, zeta, c_mech):
    """For any arm and controller: at K_mech = 1e5 K_cont both reductions are within 1e-3
    on every metric. (A light, soft arm can give an overdamped pulse whose a_h peaks at
    contact: the status says so, and the metrics still agree.)"""
    c_cont = 2 * zeta * math.sqrt(k_cont * inertia)
    arm = FullJointContact.from_joint(inertia, 1e5 * k_cont, c_mech, k_cont, c_cont,
                                      lever_arm=lever)  # fmt: skip
    c = compare_joint_reductions(arm, FOAM_1, HEAD_MIN, 1.25)
    assert c.status in ("ok", "peak_at_contact")
    err = c.to_frame().relative_error.to_numpy(dtype=float)
    assert np.all(np.abs(err) < 1e-3)


def test_constrained_comparison() -> None:
    """Head against a wall (K_h -> infinity): a_h = 0 in every model, so its error is 0
    (not NaN: both are exactly zero) and eps_max and the force carry the comparison."""
    c = compare_joint_reductions(ARM, FOAM_1, None, 0.25)
    check_result(c)
    assert c.relative_error("taylor", "a_h_max") == 0.0
    assert c.value("full", "a_h_max") == 0.0 and c.conservative("taylor", "a_h_max")
    full = dl.impact.simulate(ARM, FOAM_1, None, 0.25)
    assert c.value("full", "f_c_max") == pytest.approx(full.peak_force, rel=1e-9)
    assert c.value("full", "t_imp") == 0.05  # the constrained window (stop_time)


def test_sweep_tends_to_exact_for_a_direct_drive() -> None:
    s = joint_reduction_sweep(ARM, FOAM_1, HEAD_MIN, 1.25, [0.3, 1.0, 1e4])
    check_result(s)
    err = s.errors("taylor", "a_h_max")
    assert abs(err[2]) < 1e-4 < abs(err[1])
    frame = s.to_frame()
    assert set(frame.reduction) == {"taylor", "band_fit"}
    assert len(frame) == 3 * 2 * 5
    assert s.conservative_region("taylor", "a_h_max").dtype == bool
    # Taylor: conservative on a_h,max everywhere, but not on eps_max near K_mech ~ K_cont
    assert s.conservative_intervals("taylor", ["a_h_max"]) == [(0.3, 1e4)]
    assert s.conservative_intervals("taylor") == []
    # the full model at ratio 1 agrees with compare_joint_reductions on that arm
    arm1 = FullJointContact(ARM.mass, ARM.control_stiffness, ARM.transmission_damping,
                            ARM.control_stiffness, ARM.control_damping)  # fmt: skip
    c = compare_joint_reductions(arm1, FOAM_1, HEAD_MIN, 1.25)
    assert err[1] == pytest.approx(c.relative_error("taylor", "a_h_max"), rel=1e-9)


def test_envelope_accepts_the_full_joint() -> None:
    """foam_envelope on a FullJointContact; a stiff transmission gives the reduced envelope."""
    m = MANIPULATOR_1
    stiff = FullJointContact(m.mass, 1e7 * m.stiffness, 0.0, m.stiffness, m.damping)
    damping = np.array([20.0, 80.0])
    e_full = dl.impact.foam_envelope(stiff, 1.25, damping=damping, rtol=1e-9)
    e_red = dl.impact.foam_envelope(m, 1.25, damping=damping, rtol=1e-9)
    np.testing.assert_allclose(e_full.stiffness_min, e_red.stiffness_min, rtol=1e-5)
    # the compliant illustrative joint needs a stiffer foam for the thickness limit than
    # its Taylor reduction suggests (the Taylor joint underestimates eps_max)
    e_arm = dl.impact.foam_envelope(ARM, 1.25, damping=damping)
    e_tay = dl.impact.foam_envelope(ARM.taylor(), 1.25, damping=damping)
    assert np.all(e_arm.stiffness_min > e_tay.stiffness_min)
    # the sampled worst-case check runs the full joint too, and confirms the envelope
    assert dl.impact.check_worst_case(e_arm, samples=16).holds
    # the optimiser needs exact gradients, which exist for the reduced joint only
    with pytest.raises(InvalidParameterError, match="taylor"):
        dl.impact.optimal_foam(ARM, 1.25)


def test_full_joint_link_worst_impact_point() -> None:
    """A joint struck along its link (Sec. 3.7.3): with a stiff transmission the envelope and
    its worst impact point are those of the reduced LinkImpact."""
    reduced = dl.impact.LinkImpact(0.059, 121.68, 1.521, 3.0, 0.01, 0.3)
    stiff = dl.impact.FullJointLink(0.059, 121.68, 1.521, 3.0, 0.01, 0.3,
                                    transmission_stiffness=121.68e7)  # fmt: skip
    damping = np.array([50.0])
    a = dl.impact.foam_envelope(reduced, None, damping=damping, rtol=1e-9)
    b = dl.impact.foam_envelope(stiff, None, damping=damping, rtol=1e-9)
    np.testing.assert_allclose(b.stiffness_min, a.stiffness_min, rtol=1e-6)
    np.testing.assert_allclose(b.stiffness_max, a.stiffness_max, rtol=1e-6)
    np.testing.assert_allclose(b.worst_lever_arm, a.worst_lever_arm, rtol=1e-3)
    # the manipulator at one lever arm is the FullJointContact of that arm
    arm = stiff.contact(0.1)
    assert isinstance(arm, FullJointContact)
    assert arm.mass == pytest.approx(0.059 / 0.01)
    assert arm.control_stiffness == pytest.approx(121.68 / 0.01)
    with pytest.raises(TypeError, match="transmission_stiffness"):  # a required keyword
        dl.impact.FullJointLink(0.059, 121.68, 1.521, 3.0, 0.01, 0.3)
    with pytest.raises(InvalidParameterError, match="joint_damping"):
        dl.impact.FullJointLink(0.059, 121.68, 0.0, 3.0, 0.01, 0.3, transmission_stiffness=1e3)
    with pytest.raises(InvalidParameterError, match="robot"):
        dl.impact.optimal_foam(stiff, None)


# --- bad input ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs,name",
    [
        ({"mass": -1.0}, "mass"),
        ({"mass": math.nan}, "mass"),
        ({"transmission_stiffness": 0.0}, "transmission_stiffness"),
        ({"control_stiffness": math.inf}, "control_stiffness"),
        ({"transmission_damping": -1.0}, "transmission_damping"),
        ({"transmission_damping": 0.0, "control_damping": 0.0}, "control_damping"),
        ({"lever_arm": 0.0}, "lever_arm"),
        ({"mass": "heavy"}, "mass"),
    ],
)
def test_full_joint_contact_rejects_bad_values(kwargs, name) -> None:
    base = {
        "mass": 1.0,
        "transmission_stiffness": 1e4,
        "transmission_damping": 1.0,
        "control_stiffness": 1e4,
        "control_damping": 10.0,
    }
    with pytest.raises(InvalidParameterError, match=name):
        FullJointContact(**{**base, **kwargs})


def test_bad_calls() -> None:
    with pytest.raises(InvalidParameterError, match="robot"):
        compare_joint_reductions(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25)
    with pytest.raises(InvalidParameterError, match="impact_velocity"):
        compare_joint_reductions(ARM, FOAM_1, HEAD_MIN, -1.0)
    with pytest.raises(InvalidParameterError, match="ratios"):
        joint_reduction_sweep(ARM, FOAM_1, HEAD_MIN, 1.25, [1.0, -2.0])
    with pytest.raises(InvalidParameterError, match="ratios"):
        joint_reduction_sweep(ARM, FOAM_1, HEAD_MIN, 1.25, [np.nan])
    with pytest.raises(InvalidParameterError, match="omega_max"):
        dl.impact.band_fit_sweep(ARM, FOAM_1, HEAD_MIN, 1.25, [0.0])
    with pytest.raises(InvalidParameterError, match="q2"):
        dl.impact.simulate(ARM, FOAM_1, HEAD_MIN, 1.25, q2="printed")
    with pytest.raises(InvalidParameterError, match="metric"):
        compare_joint_reductions(ARM, FOAM_1, HEAD_MIN, 1.25).conservative("taylor", "t_imp")
    rows = full_joint_params(ARM, FOAM_1, HEAD_MIN)[None, :].copy()
    rows[0, 1] = rows[0, 8] = 0.0
    with pytest.raises(InvalidParameterError, match="C_mech"):
        matrix_metrics(rows, 1.25)
    rows = full_joint_params(ARM, FOAM_1, HEAD_MIN)[None, :].copy()
    rows[0, 9] = -1.0
    with pytest.raises(InvalidParameterError, match="K_cont"):
        matrix_metrics(rows, 1.25)


def test_full_joint_rows_by_name() -> None:
    from designlab.impact.full_joint import FULL_PARAM_NAMES

    row = full_joint_params(ARM, FOAM_1, HEAD_MIN)
    by_name = impact_metrics(dict(zip(FULL_PARAM_NAMES, row, strict=True)), 1.25)
    by_row = matrix_metrics(row, 1.25)
    assert by_name.peak_force[0] == by_row.peak_force[0]
    assert list(by_row.to_frame().columns[:10]) == list(FULL_PARAM_NAMES)
    with pytest.raises(InvalidParameterError, match="missing"):
        impact_metrics({k: v for k, v in zip(FULL_PARAM_NAMES[:-1], row, strict=False)}, 1.25)


def test_reduced_rows_are_unchanged() -> None:
    """Eight-column rows still use the reduced model (same numbers as simulate)."""
    m = matrix_metrics(param_vector(MANIPULATOR_1, FOAM_1, TEST_HEAD), 1.25)
    r = dl.impact.simulate(MANIPULATOR_1, FOAM_1, TEST_HEAD, 1.25)
    assert float(m.peak_head_acceleration[0]) == pytest.approx(r.peak_head_acceleration, rel=1e-12)
    assert list(m.to_frame().columns[:8]) == list(dl.impact.PARAM_NAMES)


def test_usable_intervals_agree_with_single_comparisons() -> None:
    """Usable = on every harm metric conservative or underestimating by <= tolerance; each
    sampled ratio is checked against its own compare_joint_reductions."""
    ratios = [0.03, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0]
    s = joint_reduction_sweep(ARM, FOAM_1, HEAD_MIN, 1.25, ratios)
    assert s.usable_intervals("taylor", 0.0) == s.conservative_intervals("taylor")
    assert s.usable_intervals("taylor", 0.5) == [(0.03, 100.0)]
    singles = {}
    for r in ratios:
        arm = FullJointContact(ARM.mass, r * ARM.control_stiffness, ARM.transmission_damping,
                               ARM.control_stiffness, ARM.control_damping)  # fmt: skip
        singles[r] = compare_joint_reductions(arm, FOAM_1, HEAD_MIN, 1.25)
    for tol in (0.01, 0.05):
        iv = s.usable_intervals("taylor", tol)
        for r, c in singles.items():
            ok = all(
                c.relative_error("taylor", m) >= -tol for m in ("a_h_max", "eps_max", "f_c_max")
            )
            assert any(lo <= r <= hi for lo, hi in iv) == ok, (tol, r)
    for bad in (-0.1, 1.0, True, "1 %"):
        with pytest.raises(InvalidParameterError, match="tolerance"):
            s.usable_intervals("taylor", bad)
    with pytest.raises(InvalidParameterError, match="metric"):
        s.usable_intervals("taylor", 0.01, ["t_imp"])


def test_safe_velocity_and_thickness_take_the_full_joint() -> None:
    """The metrics are linear in v_c: at the largest safe speed the limiting metric of the
    full joint, computed directly, sits on its limit; the needed linear depth is eps_max."""
    from designlab.impact.full_joint import FULL_PARAM_NAMES
    from designlab.impact.full_joint import full_joint_params as fjp

    s = dl.impact.max_safe_velocity(ARM, FOAM_1)
    assert s.ok
    row = dict(zip(FULL_PARAM_NAMES, fjp(ARM, FOAM_1, HEAD_MAX), strict=True))
    m = impact_metrics(row, s.impact_velocity)
    limits = {"a_h,max <= 10 g": float(m.peak_head_acceleration_g[0]) / 10.0,
              "eps_max <= 20 mm": float(m.max_compression[0]) / 0.020}  # fmt: skip
    # HEAD_MAX is the compression design set; a_h,max uses HEAD_MIN
    row_min = dict(zip(FULL_PARAM_NAMES, fjp(ARM, FOAM_1, HEAD_MIN), strict=True))
    limits["a_h,max <= 10 g"] = float(impact_metrics(row_min, s.impact_velocity)
                                      .peak_head_acceleration_g[0]) / 10.0  # fmt: skip
    assert limits[s.limiting] == pytest.approx(1.0, rel=1e-6)
    assert max(limits.values()) == pytest.approx(1.0, rel=1e-6)
    t = dl.impact.min_foam_thickness(ARM, FOAM_1, 1.25)
    eps = impact_metrics(row, 1.25).max_compression[0]
    assert t.linear_depth == pytest.approx(float(eps), rel=1e-6)
