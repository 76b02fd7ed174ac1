"""The general response path (adaptive integrator with events) against the exact kernel.

With its non-linear terms set to zero (n = p = 0) the Hunt-Crossley foam is the
Kelvin-Voigt foam of (3.5.1), so the integrated first-lobe metrics must equal the exact
kernel's (closed form, certified maxima). Tolerance: the integrator runs DOP853 at
rtol = 1e-12 with the absolute tolerance 1e-3 x rtol of the impact's own length and speed;
its global error over a lobe of some tens of steps is a few 1e-11 relative, and the events
(lobe end, maxima) are located on its 7th-order dense output to the same order (a maximum's
value is insensitive, to first order, to its time). 1e-8 leaves two decades of margin and
still catches any difference in the equations (a wrong sign or term moves the metrics by
percents).
"""

from __future__ import annotations

import numpy as np
import pytest

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.impact.contact import CONTACTS
from designlab.impact.metrics import metrics_of_matrix
from designlab.impact.model import PARAM_NAMES

HC = CONTACTS.get("hunt_crossley")
METRICS = (
    "peak_head_acceleration",
    "max_compression",
    "peak_force",
    "impact_duration",
    "time_of_peak_acceleration",
    "time_of_max_compression",
    "time_of_peak_force",
)

#: typical ranges of the reduced model's parameters (the presets' and Table 3.1-3.3's)
LOW = {"M_r": 2.0, "C_r": 50.0, "K_r": 5e3, "K_c": 8e3, "C_c": 20.0, "M_h": 4.0, "C_h": 0.0,
       "K_h": 2e3}  # fmt: skip
HIGH = {"M_r": 50.0, "C_r": 400.0, "K_r": 40e3, "K_c": 80e3, "C_c": 150.0, "M_h": 5.5,
        "C_h": 150.0, "K_h": 6e3}  # fmt: skip


def _designs(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    lo, hi = (np.array([d[k] for k in PARAM_NAMES]) for d in (LOW, HIGH))
    return lo + (hi - lo) * rng.random((n, len(PARAM_NAMES)))


def _linear_rows(p: np.ndarray) -> np.ndarray:
    """The Hunt-Crossley rows of the linear designs: n = p = 0 (x_d only scales them out)."""
    shape = {"x_d": np.full(len(p), 0.05), "n_d": np.zeros(len(p)), "p_c": np.zeros(len(p))}
    named = dict(zip(PARAM_NAMES, p.T, strict=True))
    return np.column_stack([{**named, **shape}[c] for c in HC.columns])


@pytest.mark.parametrize("constrained", [False, True])
def test_without_its_nonlinear_terms_the_general_path_is_the_exact_kernel(
    constrained: bool,
) -> None:
    p = _designs(8, seed=38 + constrained)
    v = np.random.default_rng(1).uniform(0.3, 2.0, len(p))
    exact = metrics_of_matrix(p, v, constrained=constrained)
    general = HC.metrics(_linear_rows(p), v, constrained=constrained)
    assert general.status == "integrated" and "not certified" in general.warnings[0]
    assert list(general.design_status) == list(exact.design_status)
    for name in METRICS:
        a, b = getattr(general, name), getattr(exact, name)
        if constrained and name in ("peak_head_acceleration", "time_of_peak_acceleration"):
            assert np.all(a == 0.0)
            continue
        np.testing.assert_allclose(a, b, rtol=1e-8, err_msg=name)


def test_impact_metrics_and_simulate_take_the_nonlinear_foam() -> None:
    foam = dl.impact.HuntCrossleyFoam(24.25e3, 71.9, densification_depth=0.02, stiffening=0.0,
                                      damping_exponent=0.0)  # fmt: skip
    r = dl.impact.simulate(dl.impact.MANIPULATOR_1, foam, dl.impact.HEAD_MIN, 1.25)
    lin = dl.impact.simulate(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25)
    assert r.status == "integrated" and lin.status == "ok"
    assert r.peak_head_acceleration == pytest.approx(lin.peak_head_acceleration, rel=1e-8)
    assert r.impact_duration == pytest.approx(lin.impact_duration, rel=1e-8)
    j = np.searchsorted(r.t, lin.time_of_peak_force)
    assert r.force[j] == pytest.approx(float(lin.force[j]), rel=1e-7)
    named = dict(
        zip(HC.columns, HC.row(dl.impact.MANIPULATOR_1, foam, dl.impact.HEAD_MIN), strict=True)
    )
    m = dl.impact.impact_metrics(named, 1.25)
    assert m.status == "integrated"
    assert m.peak_force[0] == pytest.approx(lin.peak_force, rel=1e-8)


def test_stiffening_holds_the_compression_below_densification_and_raises_the_peak() -> None:
    """Physics: a densifying foam cannot be compressed to x_d (its force diverges there);
    with Hunt-Crossley damping the force starts at zero at contact."""
    common = {"densification_depth": 0.012}
    lin = dl.impact.simulate(dl.impact.MANIPULATOR_2, dl.impact.FOAM_1, dl.impact.HEAD_MAX, 1.5)
    hc = dl.impact.simulate(
        dl.impact.MANIPULATOR_2,
        dl.impact.HuntCrossleyFoam(24.25e3, 71.9, stiffening=1.0, damping_exponent=1.0, **common),
        dl.impact.HEAD_MAX,
        1.5,
    )
    assert lin.max_compression > 0.012 > hc.max_compression
    assert hc.peak_force > lin.peak_force
    assert hc.force[0] == 0.0 and lin.force[0] == pytest.approx(71.9 * 1.5)


def test_profiles_are_refused_by_capability() -> None:
    foam = dl.impact.HuntCrossleyFoam(24.25e3, 71.9, densification_depth=0.02)
    prof = dl.impact.VelocityProfile(acceleration=-5.0)
    with pytest.raises(InvalidParameterError, match=r"hunt_crossley contact .* serve \['kel"):
        dl.impact.simulate(dl.impact.MANIPULATOR_1, foam, dl.impact.HEAD_MIN, 1.0, profile=prof)
    with pytest.raises(InvalidParameterError, match="damping_exponent"):
        dl.impact.HuntCrossleyFoam(24.25e3, 71.9, densification_depth=0.02, damping_exponent=0.5)


def test_a_sweep_chunk_with_the_foam_shape_columns_takes_the_general_path() -> None:
    from designlab.impact.evaluators import impact_metrics_chunk

    p = _designs(3, seed=7)
    points = dict(zip(HC.columns, _linear_rows(p).T, strict=True))
    points["v_c"] = np.array([0.5, 1.0, 1.5])
    linear = impact_metrics_chunk({k: points[k] for k in (*PARAM_NAMES, "v_c")}, {})
    general = impact_metrics_chunk(points, {})
    np.testing.assert_allclose(general["a_h_max_g"], linear["a_h_max_g"], rtol=1e-8)
    np.testing.assert_allclose(general["eps_max_m"], linear["eps_max_m"], rtol=1e-8)


def test_the_envelope_of_a_stiffening_foam_is_in_its_own_parameters_and_checked() -> None:
    """The upper boundary is where the worst head (HEAD_MIN, Sec. 3.9) reaches 10 g with
    the stiffening law at that K_c; the worst-case check's corners include that head, so its
    ratio there is 1 (to the boundary's rtol), never below."""
    foam = dl.impact.HuntCrossleyFoam(20e3, 60.0, densification_depth=0.03, thickness=0.04)
    env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, 1.25, [60.0], max_compression=0.025,
                                  foam=foam, rtol=1e-6)  # fmt: skip
    k_max = float(env.stiffness_max[0])
    at = dl.impact.simulate(dl.impact.MANIPULATOR_1, foam.replace(stiffness=k_max),
                            dl.impact.HEAD_MIN, 1.25)  # fmt: skip
    assert at.peak_head_acceleration_g == pytest.approx(10.0, rel=1e-5)
    linear = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, 1.25, [60.0], max_compression=0.025)
    assert k_max < 0.6 * float(linear.stiffness_max[0])  # the stiffening law caps K_c
    check = dl.impact.check_worst_case(env, samples=0)
    ratio = check.to_frame()
    assert ratio.filter(like="ratio").max().max() >= 1.0 - 1e-5
