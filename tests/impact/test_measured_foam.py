"""The measured-curve foam (stress_strain) and the integrated models' HIC and gradients.

Exact answers only:

* a linear curve sigma = E eps is the Kelvin-Voigt foam with K_c = A E / T, whose metrics
  the exact kernel gives in closed form; the integrated ones must agree to 1e-8 (the
  integrator's own error is a few 1e-11 relative, see tests/impact/test_general_path.py);
* the force law passes through the measured points exactly (A sigma_i at eps = T e_i);
* energy balance: a mass M struck into the foam alone (no manipulator spring or damper,
  no foam damper, a wall behind) stops where the work of the law, the integral of the
  interpolant (a piecewise cubic, integrated exactly), equals M v^2 / 2;
* HIC from the integrated head velocity and the linear kernel's (exact velocity) run the
  same window search on the same grid: they agree to the integrator's error;
* finite-difference gradients of a linear curve against the exact (CasADi) gradients:
  their error is the integrator's error over the step (about 1e-6 relative), so 1e-4.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.impact.contact import CONTACTS
from designlab.impact.contact.measured import MAX_POINTS
from designlab.impact.derivatives import metric_gradients
from designlab.impact.metrics import hic_batch, metrics_of_matrix
from designlab.impact.model import PARAM_NAMES

SS = CONTACTS.get("stress_strain")
HC = CONTACTS.get("hunt_crossley")
ARM, HEAD = dl.impact.MANIPULATOR_1, dl.impact.HEAD_MIN
#: a stiffening curve: elastic, plateau, densification (shape of Gibson & Ashby, Sec. 5.3)
STRAIN = (0.05, 0.1, 0.3, 0.5, 0.7, 0.8)
STRESS = (5e3, 8e3, 11e3, 16e3, 60e3, 200e3)
LOW = {"M_r": 2.0, "C_r": 50.0, "K_r": 5e3, "K_c": 8e3, "C_c": 20.0, "M_h": 4.0, "C_h": 0.0,
       "K_h": 2e3}  # fmt: skip
HIGH = {"M_r": 50.0, "C_r": 400.0, "K_r": 40e3, "K_c": 80e3, "C_c": 150.0, "M_h": 5.5,
        "C_h": 150.0, "K_h": 6e3}  # fmt: skip


def _foam(**kw: object) -> dl.impact.StressStrainFoam:
    args = {"strain": STRAIN, "stress": STRESS, "area": 0.01, "thickness": 0.04,
            "damping": 60.0, **kw}  # fmt: skip
    return dl.impact.StressStrainFoam(**args)  # type: ignore[arg-type]


def _linear_rows(p: np.ndarray, seed: int) -> np.ndarray:
    """Rows of the designs ``p`` with a linear curve of random points (K_c from the row)."""
    rng = np.random.default_rng(seed)
    strains = np.append(np.sort(rng.uniform(0.05, 0.9, 4)), 0.98)  # crushed beyond 98 mm
    foam = _foam(strain=tuple(strains), stress=tuple(1e5 * strains), thickness=0.1)
    shape = SS.foam_values(foam)
    named = dict(zip(PARAM_NAMES, p.T, strict=True))
    return np.column_stack([np.broadcast_to({**named, **shape}[c], len(p)) for c in SS.columns])


def _designs(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    lo, hi = (np.array([d[k] for k in PARAM_NAMES]) for d in (LOW, HIGH))
    return lo + (hi - lo) * rng.random((n, len(PARAM_NAMES)))


@pytest.mark.parametrize("constrained", [False, True])
def test_a_linear_curve_is_the_kelvin_voigt_foam(constrained: bool) -> None:
    p = _designs(6, seed=380 + constrained)
    v = np.random.default_rng(2).uniform(0.3, 1.2, len(p))
    exact = metrics_of_matrix(p, v, constrained=constrained)
    general = SS.metrics(_linear_rows(p, seed=3), v, constrained=constrained)
    assert general.status == "integrated" and general.contact == "stress_strain"
    for name in ("peak_head_acceleration", "max_compression", "peak_force", "impact_duration"):
        if constrained and name == "peak_head_acceleration":
            continue
        np.testing.assert_allclose(getattr(general, name), getattr(exact, name), rtol=1e-8,
                                   err_msg=name)  # fmt: skip


def test_the_law_passes_through_the_measured_points_and_is_linear_below_contact() -> None:
    foam = _foam()
    law = SS.force_law_of(dict(zip(SS.columns, SS.row(ARM, foam, HEAD), strict=True)))
    for e, s in zip(STRAIN, STRESS, strict=True):
        assert law(0.04 * e, 0.0)[0] == pytest.approx(0.01 * s, rel=1e-12)
    f, f_x, f_xd = law(-0.001, 2.0)
    assert f == pytest.approx(-0.001 * foam.stiffness + 2.0 * 60.0, rel=1e-12)
    assert (f_x, f_xd) == (foam.stiffness, 60.0)
    assert foam.stiffness == pytest.approx(
        0.01 * PchipInterpolator((0.0, *STRAIN), (0.0, *STRESS)).derivative()(0.0) / 0.04
    )


def test_the_stop_is_where_the_work_of_the_curve_equals_the_kinetic_energy() -> None:
    mass, v = 9.6, 0.5
    foam = _foam(damping=0.0)
    row = SS.row(ARM, foam, None)
    row[[SS.columns.index(c) for c in ("M_r", "C_r", "K_r")]] = (mass, 0.0, 0.0)
    m = SS.metrics(row, v, constrained=True, stop_time=0.2)
    work = PchipInterpolator((0.0, *STRAIN), (0.0, *STRESS)).antiderivative()
    eps = brentq(lambda x: 0.01 * 0.04 * work(x / 0.04) - 0.5 * mass * v**2, 1e-9, 0.032,
                 xtol=1e-15)  # fmt: skip
    assert m.max_compression[0] == pytest.approx(eps, rel=1e-8)
    assert m.peak_force[0] == pytest.approx(
        0.01 * PchipInterpolator((0.0, *STRAIN), (0.0, *STRESS))(eps / 0.04), rel=1e-7
    )


def test_a_crushed_foam_is_bottoming_and_its_force_beyond_any_limit() -> None:
    m = dl.impact.impact_metrics(
        dict(zip(SS.columns, SS.row(ARM, _foam(), HEAD), strict=True)), 3.0
    )
    assert m.design_status[0] == "bottoming" and math.isinf(m.peak_force[0])
    assert m.max_compression[0] == pytest.approx(0.04 * 0.8)


@pytest.mark.parametrize("model", ["hunt_crossley", "stress_strain"])
def test_hic_of_the_integrated_path_is_the_kernels_for_a_linear_law(model: str) -> None:
    p = _designs(3, seed=11)
    v = np.array([0.8, 1.25, 1.6])
    if model == "stress_strain":
        rows = _linear_rows(p, seed=5)
    else:
        shape = {"x_d": 0.05, "n_d": 0.0, "p_c": 0.0}
        named = {**dict(zip(PARAM_NAMES, p.T, strict=True)), **shape}
        rows = np.column_stack([np.broadcast_to(named[c], 3) for c in HC.columns])
    general = hic_batch(CONTACTS.get(model).metrics(rows, v), 0.015)
    exact = hic_batch(metrics_of_matrix(p, v), 0.015)
    np.testing.assert_allclose(general, exact, rtol=1e-7)
    assert np.all(general > 0)


def test_finite_difference_gradients_of_a_linear_curve_are_the_exact_ones() -> None:
    p = _designs(2, seed=21)
    rows = _linear_rows(p, seed=7)
    g = metric_gradients(rows, 1.25, columns=SS.columns)
    exact = metric_gradients(p, 1.25, columns=PARAM_NAMES)
    assert g.method == "finite_differences" and "finite differences" in g.warnings[-1]
    assert g.variables == (*SS.columns, "v_c")
    cols = [SS.columns.index(c) for c in PARAM_NAMES] + [len(SS.columns)]
    for metric in ("peak_head_acceleration", "max_compression", "peak_force"):
        a, b = g.gradients[metric][:, cols], exact.gradients[metric]
        scale = np.abs(b).max(axis=1, keepdims=True)
        np.testing.assert_allclose(a / scale, b / scale, atol=1e-4, err_msg=metric)


def test_a_linear_model_without_exact_gradients_is_refused_by_its_capability() -> None:
    sj = CONTACTS.get("series_joint")
    with pytest.raises(InvalidParameterError, match=r"series_joint contact's columns.*exact"):
        metric_gradients(np.ones((1, len(sj.columns))), 1.0, columns=sj.columns)


def test_a_sweep_chunk_and_simulate_take_the_measured_foam() -> None:
    from designlab.impact.evaluators import impact_metrics_chunk

    foam = _foam()
    r = dl.impact.simulate(ARM, foam, HEAD, 1.0)
    assert r.status == "integrated" and r.force[0] == pytest.approx(60.0 * 1.0)
    points = {c: np.full(2, x) for c, x in zip(SS.columns, SS.row(ARM, foam, HEAD), strict=True)}
    points["v_c"] = np.array([1.0, 1.0])
    out = impact_metrics_chunk(points, {})
    np.testing.assert_allclose(out["a_h_max_g"], r.peak_head_acceleration_g, rtol=1e-9)


# ------------------------------------------------------------------ hostile inputs
@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"strain": (0.1, float("nan"))}, "strain .* must be finite"),
        ({"stress": (1e3, float("inf"))}, "stress .* must be finite"),
        ({"strain": (-0.1, 0.2), "stress": (1e3, 2e3)}, "strain .* rise strictly"),
        ({"strain": (0.1, 0.2), "stress": (-1e3, 2e3)}, "stress .* rise strictly"),
        ({"strain": (0.1, 0.3, 0.2), "stress": (1e3, 2e3, 3e3)}, "strain .* rise strictly"),
        ({"strain": (0.1, 0.2, 0.3), "stress": (1e3, 3e3, 2e3)}, "monotone loading curve"),
        ({"strain": (0.1,), "stress": (1e3,)}, "2 to 16 measured points"),
        (
            {
                "strain": tuple(np.linspace(0.01, 0.9, MAX_POINTS + 1)),
                "stress": tuple(np.linspace(1e3, 1e5, MAX_POINTS + 1)),
            },
            "2 to 16",
        ),
        ({"strain": (0.1, 1.5), "stress": (1e3, 2e3)}, "within \\(0, 1\\)"),
        ({"strain": (0.1, 0.2), "stress": (1e3, 1e300)}, "<= 1e9 Pa"),
        ({"strain": (0.1, 0.2, 0.3), "stress": (1e3, 2e3)}, "one value per strain"),
        ({"strain": "0.1, 0.2"}, "strain"),
        ({"strain": (0.1, None)}, "StressStrainFoam.strain"),
        ({"strain": [[0.1, 0.2]]}, "StressStrainFoam.strain"),
        ({"area": 0.0}, "area"),
        ({"thickness": float("nan")}, "thickness"),
        ({"damping": -1.0}, "damping"),
        ({"stiffness": float("inf")}, "stiffness"),
        ({"thickness": 1e-12}, "thickness = 1e-12 m .* stiffness"),
    ],
)
def test_hostile_curves_and_fields_are_refused_by_name(kw: dict, match: str) -> None:
    with pytest.raises(InvalidParameterError, match=match):
        _foam(**kw)


def test_a_curve_whose_interpolant_starts_flat_is_refused() -> None:
    with pytest.raises(InvalidParameterError, match="initial slope"):
        _foam(strain=(0.5, 0.51), stress=(1.0, 1e6))


def test_a_csv_without_the_columns_is_refused(tmp_path: object) -> None:
    import pathlib

    path = pathlib.Path(str(tmp_path)) / "curve.csv"
    path.write_text("# source: test\nstrain,stress\n0.1,1000\n")
    with pytest.raises(InvalidParameterError, match="strain and stress_Pa"):
        dl.impact.StressStrainFoam.from_csv(path, area=0.01, thickness=0.04, damping=60.0)
    path.write_text("# source: test\nstrain,stress_Pa\n0.1,1000\n0.2,3000\n")
    foam = dl.impact.StressStrainFoam.from_csv(path, area=0.01, thickness=0.04, damping=60.0)
    assert foam.strain == (0.1, 0.2) and foam.stress == (1000.0, 3000.0)


# ------------------------------------------------------------------ co-design
def test_the_speed_limit_of_a_linear_curve_is_the_closed_form_one() -> None:
    """Linear: v_c allowed = (limit / metric at 1 m/s)^(1/e) on the same head grid; the
    integrated answer is a Brent root to 1e-6 relative."""
    e = (0.2, 0.5, 0.9)
    curve = _foam(strain=e, stress=tuple(1e5 * np.array(e)), damping=71.9)
    depth = 0.04 * 0.9 * (1.0 - 1e-4)  # the crushed margin (designlab.impact.general.CRUSHED)
    linear = dl.impact.Foam(curve.stiffness, 71.9, linear_depth=depth, thickness=0.04)
    a = dl.codesign.speed_limit(ARM, curve, dl.codesign.SafetyCase(head_levels=2, human_speed=0.0))
    b = dl.codesign.speed_limit(
        ARM, linear, dl.codesign.SafetyCase(head_levels=2, human_speed=0.0), refine=False
    )
    assert list(a.per_criterion) == list(b.per_criterion)
    for name, v in b.per_criterion.items():
        assert a.per_criterion[name] == pytest.approx(v, rel=1e-5), name
        assert a.unit_metric[name] == pytest.approx(b.unit_metric[name], rel=1e-8), name
    assert a.limiting_criterion == b.limiting_criterion


def test_co_design_answers_without_an_integrated_path_refuse_by_capability() -> None:
    link = dl.impact.LinkImpact(1.0, 10.0, 1.0, 1.0, 0.1, 0.5)
    with pytest.raises(InvalidParameterError, match=r"stress_strain contact .* fixed robot"):
        dl.codesign.speed_limit(link, _foam())
    with pytest.raises(InvalidParameterError, match="only a linear contact"):
        dl.codesign.injury_probability(ARM, _foam(), 1.0)
