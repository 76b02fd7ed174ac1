"""The symbolic model: transfer functions, time-domain agreement, limits, invariants."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import designlab as dl
from designlab.impact import FOAM_1, HEAD_MIN, MANIPULATOR_1, MANIPULATOR_2, TEST_HEAD
from designlab.impact.model import param_vector, unconstrained_model


def thesis_q(mr, cr, kr, kc, cc, mh, ch, kh, printed=False):
    """(3.5.14) coefficients, typed from the thesis (test oracle, not library code)."""
    q1 = (cr + cc) / mr + (cc + ch) / mh
    q2 = (
        (kr + kc) / mr
        + (kh + kc) / mh
        + (cc * cr + cc * ch + (0 if printed else cr * ch)) / (mr * mh)
    )
    q3 = (kr * (cc + ch) + kc * (cr + ch) + kh * (cc + cr)) / (mr * mh)
    q4 = (kr * kh + kc * kh + kr * kc) / (mr * mh)
    return np.array([1.0, q1, q2, q3, q4])


@pytest.mark.parametrize("robot,head", [(MANIPULATOR_1, HEAD_MIN), (MANIPULATOR_2, TEST_HEAD)])
def test_denominator_is_3_5_14(robot, head) -> None:
    p = param_vector(robot, FOAM_1, head)
    den = unconstrained_model().denominator(p)[0]
    np.testing.assert_allclose(den, thesis_q(*p), rtol=1e-12)


def test_transfer_functions_match_3_5_14_and_3_9_2() -> None:
    p = param_vector(MANIPULATOR_1, FOAM_1, HEAD_MIN)
    mr, cr, kr, kc, cc, mh, ch, kh = p
    v = 1.25
    tfs = dl.impact.transfer_functions(MANIPULATOR_1, FOAM_1, HEAD_MIN, v)
    den = thesis_q(*p)
    for s in (0.3 + 2j, 10j, 55.0 + 40j, 300j):
        a_h = (kc + cc * s) * v * (s**2 + cr / mr * s + kr / mr) / (mh * np.polyval(den, s))
        eps = (
            v
            * (s**2 + cr / mr * s + kr / mr)
            * (s**2 + ch / mh * s + kh / mh)
            / (s**2 * np.polyval(den, s))
        )
        zc, zr, zh = kc + cc * s, mr * s**2 + cr * s + kr, mh * s**2 + ch * s + kh
        f_c = zc * v / (s**2 * (1 + zc / zr + zc / zh))  # (3.5.11)
        assert tfs["head_acceleration"](s) == pytest.approx(a_h, rel=1e-9)
        assert tfs["compression"](s) == pytest.approx(eps, rel=1e-9)
        assert tfs["force"](s) == pytest.approx(f_c, rel=1e-9)


def test_constrained_transfer_functions_3_6_1_and_3_9_4() -> None:
    p = param_vector(MANIPULATOR_1, FOAM_1, None)
    mr, cr, kr, kc, cc = p[:5]
    tfs = dl.impact.transfer_functions(MANIPULATOR_1, FOAM_1, None, 0.25)
    for s in (1 + 1j, 20j, 100.0):
        zc, zr = kc + cc * s, mr * s**2 + cr * s + kr
        assert tfs["force"](s) == pytest.approx(zc * 0.25 / (s**2 * (1 + zc / zr)), rel=1e-9)
        eps = 0.25 * zr / (s**2 * (mr * s**2 + (cr + cc) * s + kr + kc))
        assert tfs["compression"](s) == pytest.approx(eps, rel=1e-9)


def test_time_domain_route_equals_ode_of_casadi_model() -> None:
    """Exact modal solution vs a tight ODE integration of the CasADi state derivative."""
    model = unconstrained_model()
    p = param_vector(MANIPULATOR_2, FOAM_1, HEAD_MIN)
    v = 1.25
    ode = model.ode

    def f(t, x):
        return np.asarray(ode(x, [v * t, v, 0.0], p)).ravel()

    t = np.linspace(0, 0.06, 61)
    sol = solve_ivp(f, (0, 0.06), np.zeros(4), t_eval=t, rtol=1e-11, atol=1e-14, method="DOP853")
    y = np.column_stack(
        [
            np.asarray(model.outputs(sol.y[:, k], [v * tk, v, 0.0], p)).ravel()
            for k, tk in enumerate(t)
        ]
    )
    r = dl.impact.simulate(MANIPULATOR_2, FOAM_1, HEAD_MIN, v, duration=0.06, samples=61)
    np.testing.assert_allclose(r.force, y[0], rtol=1e-7, atol=1e-6)
    np.testing.assert_allclose(r.head_acceleration, y[1], rtol=1e-7, atol=1e-6)
    np.testing.assert_allclose(r.compression, y[2], rtol=1e-7, atol=1e-10)


def test_casadi_functions_are_exported_and_differentiable() -> None:
    model = unconstrained_model()
    assert isinstance(model.ode, ca.Function) and isinstance(model.state_space, ca.Function)
    p = ca.MX.sym("p", 8)
    den = model.ramp_tf(p)[0]
    jac = ca.Function("j", [p], [ca.jacobian(den, p)])
    val = np.asarray(jac(param_vector(MANIPULATOR_1, FOAM_1, HEAD_MIN)))
    # d q1 / d C_c = 1/M_r + 1/M_h
    assert val[1, 4] == pytest.approx(1 / 9.6 + 1 / 4.4)


def test_force_steps_to_cc_vc() -> None:
    r = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25)
    assert r.force[0] == pytest.approx(FOAM_1.damping * 1.25, rel=1e-10)
    assert r.head_acceleration[0] == pytest.approx(FOAM_1.damping * 1.25 / 4.4, rel=1e-10)
    assert r.compression[0] == pytest.approx(0.0, abs=1e-15)


def test_stiff_neck_tends_to_constrained_impact() -> None:
    """K_h -> infinity: the coupled model tends to the constrained model (3.6.1, 3.9.4)."""
    con = dl.impact.simulate(MANIPULATOR_1, FOAM_1, None, 0.25, duration=0.02, samples=201)
    errs = []
    for kh in (1e7, 1e9):
        head = dl.impact.HeadNeck(mass=4.4, stiffness=kh, damping=2 * 0.3 * np.sqrt(4.4 * kh))
        r = dl.impact.simulate(MANIPULATOR_1, FOAM_1, head, 0.25, duration=0.02, samples=201)
        errs.append(np.max(np.abs(r.force - con.force)) / np.max(np.abs(con.force)))
    assert errs[1] < errs[0] and errs[1] < 2e-3


def test_constrained_force_much_larger_fig_3_12() -> None:
    free = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 0.25)
    wall = dl.impact.simulate(MANIPULATOR_1, FOAM_1, None, 0.25)
    assert wall.peak_force > 2 * free.peak_force


@settings(max_examples=40, deadline=None)
@given(
    mr=st.floats(1.0, 80.0),
    kr=st.floats(1e3, 1e5),
    cr=st.floats(0.0, 800.0),
    kc=st.floats(2e3, 1.5e5),
    xi=st.floats(0.02, 0.3),
    mh=st.floats(3.0, 6.0),
    kh=st.floats(0.0, 8e3),
    ch=st.floats(0.0, 150.0),
    v=st.floats(0.05, 3.0),
    k=st.floats(0.1, 5.0),
)
def test_linear_in_vc_and_zero_without_closing_speed(mr, kr, cr, kc, xi, mh, kh, ch, v, k) -> None:
    p = [mr, cr, kr, kc, 2 * xi * np.sqrt(4.4 * kc), mh, ch, kh]
    m = dl.impact.impact_metrics(p, np.array([v, k * v, 0.0, -v]), columns=dl.impact.PARAM_NAMES)
    ok = m.design_status[:2]
    assert ok[0] == ok[1]
    if ok[0] in ("ok", "peak_at_contact"):
        assert m.peak_head_acceleration[1] == pytest.approx(
            k * m.peak_head_acceleration[0], rel=1e-9
        )
        assert m.max_compression[1] == pytest.approx(k * m.max_compression[0], rel=1e-9)
        assert m.peak_force[1] == pytest.approx(k * m.peak_force[0], rel=1e-9)
        assert m.impact_duration[1] == pytest.approx(m.impact_duration[0], rel=1e-9)
    assert list(m.design_status[2:]) == ["no_impact", "no_impact"]
    assert np.all(m.peak_head_acceleration[2:] == 0) and np.all(m.max_compression[2:] == 0)
    r = dl.impact.simulate(
        dl.impact.ContactDynamics(mr, kr, cr),
        dl.impact.Foam(kc, p[4]),
        dl.impact.HeadNeck(mh, kh, ch),
        -v,
    )
    assert r.status == "no_impact" and not np.any(r.force)


def test_transfer_functions_cancel_the_ramp_poles_exactly() -> None:
    """a_h tends to 0 under the ramp (the neck carries the load): no pole at the origin;
    the force and the compression keep growing (the double pole stays)."""
    tfs = dl.impact.transfer_functions(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25)
    origin = {k: int(np.sum(np.abs(v.poles()) < 1e-9)) for k, v in tfs.items()}
    assert origin == {"force": 2, "head_acceleration": 0, "compression": 2}
    # the other poles are the model's four, untouched
    assert all(np.sum(np.abs(v.poles()) >= 1e-9) == 4 for v in tfs.values())


def test_impact_response_repr_is_short() -> None:
    r = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, impact_velocity=1.0)
    text = repr(r)
    assert len(text) < 200 and "a_h,max=" in text and "status='ok'" in text
    assert r.metrics()["peak_force_N"] == pytest.approx(r.peak_force)
    dl.results.check_result(r)
    assert "a_h_max_g" in r.summary()


def test_every_impact_result_honours_the_result_contract() -> None:

    from designlab.impact.derivatives import metric_gradients

    env = dl.impact.foam_envelope(MANIPULATOR_1, 1.25, [50.0])
    p = [[9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 46.0, 3e3]]
    results = [
        env,
        dl.impact.foam_verdict(env, FOAM_1),
        dl.impact.check_worst_case(env, samples=0),
        dl.impact.max_safe_velocity(MANIPULATOR_1, FOAM_1),
        dl.impact.min_foam_thickness(MANIPULATOR_1, FOAM_1),
        dl.impact.impact_metrics(p, 1.25, columns=dl.impact.PARAM_NAMES),
        metric_gradients(p, 1.25, columns=dl.impact.PARAM_NAMES),
        dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, impact_velocity=1.0),
        dl.impact.effective_contact([[0.059]], [121.68], [1.521], [0.078]),
        dl.impact.impact_point_sweep(0.059, 121.68, 1.521, 0.5, [0.01, 0.078]),
    ]
    for r in results:
        dl.results.check_result(r)
