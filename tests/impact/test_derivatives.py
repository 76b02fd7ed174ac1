"""Exact metric gradients (CasADi AD + envelope theorem) against finite differences."""

from __future__ import annotations

import numpy as np
import pytest

import designlab as dl
from designlab.impact.derivatives import metric_gradients, response_function

P = np.array([9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 46.0, 3e3])


def test_symbolic_response_equals_modal_solution() -> None:
    r = dl.impact.simulate(
        dl.impact.MANIPULATOR_1,
        dl.impact.FOAM_1,
        dl.impact.HEAD_MIN,
        1.25,
        duration=0.08,
        samples=9,
    )
    f = response_function()
    for k, t in enumerate(r.t):
        y = np.asarray(f(t, P, 1.25)).ravel()
        assert y[0] == pytest.approx(r.force[k], rel=1e-9, abs=1e-8)
        assert y[1] == pytest.approx(r.head_acceleration[k], rel=1e-9, abs=1e-8)
        assert y[2] == pytest.approx(r.compression[k], rel=1e-9, abs=1e-12)


@pytest.mark.parametrize(
    "metric", ["peak_head_acceleration", "max_compression", "peak_force", "impact_duration"]
)
def test_gradients_match_central_differences(metric: str) -> None:
    g = metric_gradients(np.atleast_2d(P), 1.25, columns=dl.impact.PARAM_NAMES).gradients[metric][0]
    for j in range(8):
        h = P[j] * 1e-5
        up, dn = P.copy(), P.copy()
        up[j] += h
        dn[j] -= h
        fd = (
            getattr(dl.impact.impact_metrics(up, 1.25, columns=dl.impact.PARAM_NAMES), metric)[0]
            - getattr(dl.impact.impact_metrics(dn, 1.25, columns=dl.impact.PARAM_NAMES), metric)[0]
        ) / (2 * h)
        assert g[j] == pytest.approx(fd, rel=1e-4, abs=1e-12 * max(1.0, abs(fd)))


#: Relative accuracy of the lobe end t_imp: its Newton solve stops at a step below 1e-11 t
#: (designlab/impact/kernel_lobe.py, ``lobe_end``); 10x that bounds the error of the last step.
T_IMP_RTOL = 1e-10


def test_elasticity_of_linear_metrics_in_velocity_is_one() -> None:
    v = np.array([0.4, 1.25])
    g = metric_gradients(np.vstack([P, P]), v, columns=dl.impact.PARAM_NAMES)
    for metric in ("peak_head_acceleration", "max_compression", "peak_force"):
        np.testing.assert_allclose(g.elasticities(metric)["v_c"], 1.0, rtol=1e-8)
    # exactly 0 (t_imp does not depend on v_c); computed as -(da_h/dv)/(da_h/dt) at the
    # computed t_imp, with da_h/dv = a_h(t_imp)/v, it is (t_exact - t_imp)/v to first order:
    # the lobe end's error over v_c, not a rounding error of a few ulps
    t_imp = dl.impact.impact_metrics(np.vstack([P, P]), v, columns=dl.impact.PARAM_NAMES)
    bound = T_IMP_RTOL * t_imp.impact_duration / v
    assert np.all(np.abs(g.gradients["impact_duration"][:, 8]) <= bound)
    assert set(g.to_frame()["variable"]) >= {"K_c", "C_c", "v_c"}
