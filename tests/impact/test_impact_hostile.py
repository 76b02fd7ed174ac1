"""Hostile inputs of the impact domain (issue 18): nothing crashes, hangs or lies.

Each case is computed here: a clear :class:`InvalidParameterError` naming the
parameter, or a finite result with its status and warnings. The fuzz test
drives every public impact constructor with random values; the schema test
checks that, for every declared impact model, the JSON Schema of its study
model and its constructor accept and refuse the same boundary values.
"""

from __future__ import annotations

import dataclasses
import math
import re

import jsonschema
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.errors import InvalidParameterError, StudyError
from designlab.impact import FOAM_1, HEAD_MIN, MANIPULATOR_1
from designlab.impact.ch3_claims import worst_impact_point
from designlab.impact.model import PARAM_NAMES, param_vector
from designlab.impact.parameters import IMPACT_VELOCITY, RATIO_POINTS
from designlab.params import params_of
from designlab.study import parse_study
from designlab.study.specs import spec_model

GEARED = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)


# --- the joint comparison with the documented ``head: null`` --------------------------------


@pytest.fixture(scope="module")
def constrained():
    return dl.impact.compare_joint_reductions(GEARED, FOAM_1, None, 1.25)


def test_constrained_comparison_says_the_foam_bottoms_out(constrained) -> None:
    """eps_max of the full joint is beyond the 20 mm linear depth: the status and a
    warning say so (they said "ok" before)."""
    eps = constrained.value("full", "eps_max")
    assert eps > FOAM_1.linear_depth  # about 32 mm
    assert constrained.status == "bottoming"
    assert any("bottoms out" in w and f"{eps:.4g}" in w for w in constrained.warnings)


def test_constrained_comparison_has_finite_errors(constrained) -> None:
    """a_h = 0 in every model of the constrained impact: its error is 0, not NaN, and
    the harm metrics' errors are the computed ones."""
    frame = constrained.to_frame()
    assert np.all(np.isfinite(frame.relative_error.to_numpy(dtype=float)))
    assert constrained.relative_error("taylor", "a_h_max") == 0.0
    for metric in ("eps_max", "f_c_max"):
        full = constrained.value("full", metric)
        red = constrained.value("taylor", metric)
        assert constrained.relative_error("taylor", metric) == pytest.approx((red - full) / full)


def test_constrained_report_has_no_nan_and_a_usable_region() -> None:
    """The joint_reduction report of ``head: null`` shows numbers, and "usable" where the
    errors are small (it said "nan %" and "usable: nowhere")."""
    from designlab.report.joint_reduction import joint_reduction_markdown
    from designlab.study import run_study

    study = parse_study(
        """
designlab: 1
kind: joint_reduction
name: hostile
joints: [{name: g, inertia: 0.059, k_mech: 2000, c_mech: 2.0, k_cont: 1500, c_cont: 30,
          lever_arm: 0.2}]
head: null
ratios: {low: 100, high: 1000, num: 2}
"""
    )
    result = run_study(study)
    sweep = result.joints[0].sweep
    errors = [sweep.errors("taylor", m) for m in ("a_h_max", "eps_max", "f_c_max")]
    assert all(np.all(np.isfinite(e)) for e in errors)
    text = joint_reduction_markdown(result)
    assert "nan" not in text.lower()
    small = all(np.all(np.abs(e) < 0.01) for e in errors)
    assert small and sweep.usable_intervals("taylor") == [(100.0, 1000.0)]
    assert "bottoming" in result.status


@pytest.mark.parametrize("fn", ["compare", "sweep"])
def test_closing_velocity_is_capped(fn) -> None:
    """1e6 m/s (eps_max 8.6 km) is refused by the one declaration of v_c (<= 20 m/s)."""
    with pytest.raises(InvalidParameterError, match=r"impact_velocity = 1000000\.0 m/s"):
        if fn == "compare":
            dl.impact.compare_joint_reductions(GEARED, FOAM_1, None, 1e6)
        else:
            dl.impact.joint_reduction_sweep(GEARED, FOAM_1, None, 1e6, [1.0])


#: Every public impact function that takes a closing velocity, called with v_c.
_CLOSING_VELOCITY_CALLS = {
    "simulate": lambda v: dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, v),
    "simulate_constrained": lambda v: dl.impact.simulate(MANIPULATOR_1, FOAM_1, None, v),
    "simulate_full_joint": lambda v: dl.impact.simulate(GEARED, FOAM_1, HEAD_MIN, v),
    "impact_metrics": lambda v: dl.impact.impact_metrics(
        dict(zip(PARAM_NAMES, param_vector(MANIPULATOR_1, FOAM_1, HEAD_MIN), strict=True)), v
    ),
    "transfer_functions": lambda v: dl.impact.transfer_functions(
        MANIPULATOR_1, FOAM_1, HEAD_MIN, v
    ),
    "foam_envelope": lambda v: dl.impact.foam_envelope(MANIPULATOR_1, v, [50.0]),
    "optimal_foam": lambda v: dl.impact.optimal_foam(MANIPULATOR_1, v),
    "min_foam_thickness": lambda v: dl.impact.min_foam_thickness(MANIPULATOR_1, FOAM_1, v),
    "compare_joint_reductions": lambda v: dl.impact.compare_joint_reductions(
        GEARED, FOAM_1, HEAD_MIN, v
    ),
    "joint_reduction_sweep": lambda v: dl.impact.joint_reduction_sweep(
        GEARED, FOAM_1, HEAD_MIN, v, [1.0]
    ),
    "band_fit_sweep": lambda v: dl.impact.band_fit_sweep(GEARED, FOAM_1, HEAD_MIN, v, [1.0]),
}


def test_every_function_taking_a_closing_velocity_is_listed() -> None:
    import inspect

    takes_v_c = {
        name
        for name in dl.impact.__all__
        if callable(obj := getattr(dl.impact, name))
        and not inspect.isclass(obj)
        and "impact_velocity" in inspect.signature(obj).parameters
    }
    assert takes_v_c <= {
        n.split("_constrained")[0].split("_full")[0] for n in _CLOSING_VELOCITY_CALLS
    }


@pytest.mark.parametrize("fn", sorted(_CLOSING_VELOCITY_CALLS))
@pytest.mark.parametrize("v_c", [1e6, math.nextafter(IMPACT_VELOCITY.le, math.inf)])
def test_one_cap_of_the_closing_velocity_for_every_impact_function(fn, v_c) -> None:
    """Every impact function checks v_c against the one declaration, IMPACT_VELOCITY:
    ``simulate(..., 1e6)`` was accepted (status bottoming) where the others refused it."""
    with pytest.raises(InvalidParameterError) as info:
        _CLOSING_VELOCITY_CALLS[fn](v_c)
    assert f"impact_velocity = {v_c!r} m/s" in str(info.value)
    assert IMPACT_VELOCITY.allowed() in str(info.value)


@pytest.mark.parametrize("fn", ["simulate", "impact_metrics", "transfer_functions"])
def test_the_cap_itself_is_allowed_and_no_impact_stays_documented(fn) -> None:
    """v_c = 20 m/s (the cap) is computed; v_c <= 0 stays the no-impact case of a response."""
    call = _CLOSING_VELOCITY_CALLS[fn]
    call(IMPACT_VELOCITY.le)
    if fn == "simulate":
        assert call(-1.0).status == "no_impact"
    elif fn == "impact_metrics":
        assert list(call([-1.0, 0.0]).design_status) == ["no_impact", "no_impact"]
    for bad in (math.nan, math.inf):
        with pytest.raises(InvalidParameterError, match="impact_velocity"):
            call(bad)


def test_ratio_count_has_one_cap_for_api_and_yaml() -> None:
    """20,000 ratios hung the API; the cap is the declaration the YAML uses too."""
    with pytest.raises(InvalidParameterError, match=r"ratios \(number of values\) = 20000"):
        dl.impact.joint_reduction_sweep(GEARED, FOAM_1, HEAD_MIN, 1.25, np.ones(20_000))
    from designlab.study.kinds.joint_reduction import RatioGrid

    schema = RatioGrid.model_json_schema()["properties"]["num"]
    assert schema["maximum"] == RATIO_POINTS.le
    with pytest.raises(StudyError, match="num"):
        parse_study(
            "designlab: 1\nkind: joint_reduction\nname: x\njoints: [{inertia: 0.059, "
            "k_mech: 2000, c_mech: 2.0, k_cont: 1500, c_cont: 30, lever_arm: 0.2}]\n"
            f"ratios: {{low: 0.1, high: 10, num: {RATIO_POINTS.le + 1}}}\n"
        )


def test_reference_lever_arm_beyond_its_range_is_refused() -> None:
    """At l = 5 m the first lobe does not close (a NaN reference with status ok before)."""
    with pytest.raises(InvalidParameterError, match=r"reference_lever_arm = 5\.0 m"):
        worst_impact_point(0.059, 121.68, 1.521, 1.0, FOAM_1, HEAD_MIN, reference_lever_arm=5.0)
    w = worst_impact_point(0.059, 121.68, 1.521, 1.0, FOAM_1, HEAD_MIN, reference_lever_arm=1.0)
    assert w.status == "ok" and math.isfinite(w.a_h_max_reference_g)


# --- validate refuses what run refuses ----------------------------------------------------

_JOINT = "{inertia: 0.059, k_mech: 2000, c_mech: 2.0, k_cont: 1500, c_cont: 30, lever_arm: 0.2}"
_RUN_REFUSES = {
    "impact_cases": (
        "cases: [{robot: MANIPULATOR_1, foam: {preset: FOAM_1, linear_depth: 0.05}, "
        "head: HEAD_MIN, impact_velocity: 1.0}]"
    ),
    "impact_sweep": (
        "base: {robot: MANIPULATOR_1, foam: {preset: FOAM_1, linear_depth: 0.05}, "
        "head: HEAD_MIN, impact_velocity: 1.25}\n"
        "sweep: {method: grid, parameters: {foam.stiffness: {values: [2e4]}}}"
    ),
    "foam_envelope_sweep": (
        "base: {robot: MANIPULATOR_1, foam: {preset: FOAM_1, linear_depth: 0.05}}"
    ),
    "foam_design": "robots: [MANIPULATOR_1]\nfoams: [{preset: FOAM_1, linear_depth: 0.05}]",
    "joint_reduction": (
        "joints: [{inertia: 0.059, k_mech: 2000, c_mech: 0, k_cont: 1500, c_cont: 0, "
        "lever_arm: 0.2}]"
    ),
}


@pytest.mark.parametrize("kind", sorted(_RUN_REFUSES))
def test_validate_refuses_what_run_refuses(kind) -> None:
    """A foam thinner than its linear depth, an undamped motor node: the constructors refuse
    them at run, so validate (parsing the study) refuses them first, naming the field."""
    text = f"designlab: 1\nkind: {kind}\nname: hostile\n{_RUN_REFUSES[kind]}\n"
    with pytest.raises(StudyError, match=r"thickness|c_cont"):
        parse_study(text)


def test_foam_design_head_range_and_iso_rules_at_validate() -> None:
    base = "designlab: 1\nkind: foam_design\nname: h\nrobots: [MANIPULATOR_1]\n"
    with pytest.raises(StudyError, match=r"HeadRange\.mass"):
        parse_study(base + "head_range: {mass: [5.3, 4.4]}\n")
    with pytest.raises(StudyError, match="no transient-contact multiplier"):
        parse_study(
            base + "criteria: [{type: iso_ts_15066, body_region: face, contact: transient}]\n"
        )


# --- the kind-name trap ------------------------------------------------------------------


def test_kind_names_say_what_they_do(repo_root) -> None:
    from designlab.study import load_study
    from designlab.study.registry import study_kinds

    study = load_study(repo_root / "studies" / "foam_design.yaml")
    assert study.kind == "foam_design" and study.name == "foam_design"
    assert not (repo_root / "studies" / "foam_envelope.yaml").exists()
    assert "foam_envelope_sweep" in study_kinds() and "foam_envelope" not in study_kinds()
    # the kind's first name (no release was made with it) is refused, naming the kind
    with pytest.raises(StudyError, match=r"kind 'foam_envelope'.*foam_envelope_sweep"):
        parse_study(
            "designlab: 1\nkind: foam_envelope\nname: old\nbase: {robot: MANIPULATOR_1, "
            "foam: FOAM_1}\n"
        )


# --- fuzz: every public impact constructor ------------------------------------------------

_HOSTILE = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -1.0, 1e300, -1e300, 1e-300, 5e-324]),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.text(max_size=5),
    st.booleans(),
    st.none(),
)


def _constructors() -> dict[str, tuple[type, dict]]:
    """Each public parameter class of designlab.impact with valid arguments."""
    i = dl.impact
    return {
        "HeadNeck": (i.HeadNeck, {"mass": 4.4, "stiffness": 3e3, "damping": 46.0}),
        "ContactDynamics": (i.ContactDynamics, {"mass": 9.6, "stiffness": 2e4, "damping": 250.0}),
        "Foam": (i.Foam, {"stiffness": 2.4e4, "damping": 71.9}),
        "LinkImpact": (
            i.LinkImpact,
            {"inertia": 0.059, "joint_stiffness": 121.7, "joint_damping": 1.5,
             "joint_speed": 3.0, "lever_arm_min": 0.01, "lever_arm_max": 0.078},
        ),
        "HeadRange": (i.HeadRange, {"mass": (4.4, 5.3)}),
        "FullJointContact": (
            i.FullJointContact,
            {"mass": 1.5, "transmission_stiffness": 5e4, "transmission_damping": 50.0,
             "control_stiffness": 3.75e4, "control_damping": 750.0},
        ),
        "SeriesJoint": (
            i.SeriesJoint,
            {"inertia": 0.059, "k_mech": 2e3, "c_mech": 2.0, "k_cont": 1.5e3, "c_cont": 30.0,
             "lever_arm": 0.2},
        ),
        "FullJointLink": (
            i.FullJointLink,
            {"inertia": 0.059, "joint_stiffness": 1.5e3, "joint_damping": 30.0,
             "joint_speed": 1.0, "lever_arm_min": 0.05, "lever_arm_max": 0.3,
             "transmission_stiffness": 2e3},
        ),
        "VelocityProfile": (i.VelocityProfile, {"acceleration": 5.0}),
        "HeadAcceleration": (i.HeadAcceleration, {"max_g": 10.0}),
        "ImpactForce": (i.ImpactForce, {"max_force": 660.0}),
        "HeadInjuryCriterion": (i.HeadInjuryCriterion, {"max_hic": 650.0}),
        "CompressionLimit": (i.CompressionLimit, {"max_compression": 0.02}),
        "IsoQuasiStaticForce": (i.IsoQuasiStaticForce, {"body_region": "face"}),
        "IsoTransientForce": (i.IsoTransientForce, {"body_region": "chest"}),
        "ImpactPlane": (i.ImpactPlane, {"robot": MANIPULATOR_1, "normal": (1.0, 0.0)}),
    }  # fmt: skip


CONSTRUCTORS = _constructors()


def _finite(obj) -> bool:
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        vals = v if isinstance(v, tuple) else (v,)
        for x in vals:
            if isinstance(x, float) and not math.isfinite(x):
                return False
    return True


@pytest.mark.parametrize("name", sorted(CONSTRUCTORS))
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_fuzz_constructors(name, data) -> None:
    """Random values in one field (or a pair's end): a clear error naming the field, or a
    valid object with finite numbers."""
    cls, valid = CONSTRUCTORS[name]
    field = data.draw(st.sampled_from([f.name for f in dataclasses.fields(cls) if f.init]))
    value = data.draw(_HOSTILE)
    if field in ("mass", "stiffness", "damping") and cls is dl.impact.HeadRange:
        value = data.draw(st.tuples(_HOSTILE, _HOSTILE) | _HOSTILE)
    kwargs = {**valid, field: value}
    try:
        obj = cls(**kwargs)
    except InvalidParameterError as exc:
        assert field in str(exc) or exc.name.split(".")[-1] in {
            f.name for f in dataclasses.fields(cls)
        }, str(exc)
        return
    assert _finite(obj)


# --- the JSON Schema and the constructor agree on every boundary --------------------------


def _boundaries(decl) -> list[float]:
    out = []
    for bound in (decl.gt, decl.ge, decl.lt, decl.le):
        if bound is not None:
            out += [bound, float(np.nextafter(bound, -np.inf)), float(np.nextafter(bound, np.inf))]
    return out


_MODELS = [
    (dl.impact.HeadNeck, {"mass": 4.4, "stiffness": 3e3, "damping": 46.0}),
    (dl.impact.ContactDynamics, {"mass": 9.6, "stiffness": 2e4, "damping": 250.0}),
    (dl.impact.Foam, {"stiffness": 2.4e4, "damping": 71.9, "linear_depth": 0.02,
                      "thickness": 1.0}),
    (dl.impact.SeriesJoint, {"inertia": 0.059, "k_mech": 2e3, "c_mech": 2.0, "k_cont": 1.5e3,
                             "c_cont": 30.0, "lever_arm": 0.2}),
    (dl.impact.FullJointContact, {"mass": 1.5, "transmission_stiffness": 5e4,
                                  "transmission_damping": 50.0, "control_stiffness": 3.75e4,
                                  "control_damping": 750.0}),
    (dl.impact.LinkImpact, {"inertia": 0.059, "joint_stiffness": 121.7, "joint_damping": 1.5,
                            "joint_speed": 3.0, "lever_arm_min": 0.01, "lever_arm_max": 100.0}),
    (dl.impact.HeadAcceleration, {"max_g": 10.0}),
    (dl.impact.ImpactForce, {"max_force": 660.0}),
    (dl.impact.HeadInjuryCriterion, {"max_hic": 650.0, "window": 0.015}),
    (dl.impact.CompressionLimit, {"max_compression": 0.02}),
    (dl.impact.VelocityProfile, {"acceleration": 5.0, "duration": 0.05}),
]  # fmt: skip


@pytest.mark.parametrize("cls,valid", _MODELS, ids=[c.__name__ for c, _ in _MODELS])
def test_schema_and_constructor_agree_on_boundaries(cls, valid) -> None:
    """For each real field: the bound itself and its float neighbours are accepted or
    refused alike by the JSON Schema of the study model and by the constructor."""
    schema = spec_model(cls).model_json_schema()
    for name, decl in params_of(cls).items():
        if decl.kind != "real" or name not in schema["properties"]:
            continue
        prop = schema["properties"][name]
        for x in _boundaries(decl):
            data = {**valid, name: x}
            # keep the class's cross-field rules out of the way of the field's own bounds
            if cls is dl.impact.Foam and name == "linear_depth":
                data["thickness"] = None
            if cls is dl.impact.Foam and name == "thickness" and x > 0:
                data["linear_depth"] = min(x, 0.02)  # thickness >= linear_depth
            if cls is dl.impact.LinkImpact and name == "lever_arm_max" and x > 0:
                data["lever_arm_min"] = min(x, 0.01)  # lever_arm_max >= lever_arm_min
            by_schema = jsonschema.Draft202012Validator(schema).is_valid(
                {k: v for k, v in data.items() if k in schema["properties"]}
            )
            try:
                cls(**data)
                by_constructor = True
            except InvalidParameterError:
                by_constructor = False
            assert by_schema == by_constructor, (cls.__name__, name, x, prop)


# --- issue 41: declared domains the arithmetic can serve ------------------------------------

_BASE = dict(zip(PARAM_NAMES, [9.6, 250, 2e4, 24.25e3, 71.9, 4.4, 46, 3e3], strict=True))


def _design(**changes: float) -> list[float]:
    return [changes.get(k, v) for k, v in _BASE.items()]


def test_a_3e13_kg_manipulator_is_refused_where_it_was_silently_wrong() -> None:
    """eps_max was 0.01987 m with status ok; 50 digits give 0.015092 m. Refused, by name."""
    from designlab.impact.metrics import impact_metrics

    with pytest.raises(InvalidParameterError) as err:
        impact_metrics([_design(M_r=3e13)], 1.25, columns=PARAM_NAMES)
    text = str(err.value)
    assert "params[0]" in text and "M_r = 3e+13 kg" in text
    assert "time scales span a ratio of 2.86e+06" in text and "at most 10000" in text


@pytest.mark.parametrize("mass", [3e13, 1e17, 1e18])
def test_simulate_refuses_what_it_cannot_serve_and_never_blames_duration(mass) -> None:
    """From 1e17 kg simulate complained about a ``duration`` never passed, from 1e18 kg it
    returned -7,268 g."""
    robot = dl.impact.ContactDynamics(mass, 2e4, 250.0)
    with pytest.raises(InvalidParameterError) as err:
        dl.impact.simulate(robot, FOAM_1, HEAD_MIN, 1.25)
    assert err.value.name == "robot.mass" and err.value.value == mass
    assert "duration" not in str(err.value) and "M_r" in str(err.value)


_IMPACT_DEFAULTS = {"robot": MANIPULATOR_1, "foam": FOAM_1, "head": HEAD_MIN}


@pytest.mark.parametrize(
    ("where", "field", "value"),
    [
        ("robot", "damping", 1e300),
        ("robot", "mass", 1e300),
        ("foam", "damping", 1e6),
        ("head", "mass", 1e-6),
        ("head", "damping", 1e6),
    ],
)
def test_the_conditioning_refusal_names_the_farthest_parameter_and_its_value(
    where, field, value
) -> None:
    """It named ``robot, foam and head`` (or ``params[0]``) with all the values; now the
    input farthest from its typical range is the parameter, as the caller spelled it."""
    args = dict(_IMPACT_DEFAULTS)
    args[where] = dataclasses.replace(args[where], **{field: value})
    with pytest.raises(InvalidParameterError) as err:
        dl.impact.simulate(args["robot"], args["foam"], args["head"], 1.25)
    assert (err.value.name, err.value.value) == (f"{where}.{field}", value)
    assert str(err.value).startswith(f"{where}.{field} = {value!r} ")
    assert "at most 10000" in str(err.value)
    if where == "head":
        return
    symbol = params_of(type(args[where]))[field].symbol
    with pytest.raises(InvalidParameterError) as err:
        dl.impact.max_safe_velocity(args["robot"], args["foam"])
    assert (err.value.name, err.value.value) == (f"params[0].{symbol}", value)
    assert field in str(err.value)  # the declaration's meaning: "foam damping C_c"


@pytest.mark.parametrize(
    ("field", "value"),
    [("control_damping", 1e9), ("transmission_damping", 1e300), ("mass", 1e18),
     ("mass", 1e-200), ("transmission_stiffness", 1e300)],
)  # fmt: skip
def test_the_full_joints_conditioning_refusal_names_the_robots_field(field, value) -> None:
    arm = dataclasses.replace(GEARED, **{field: value})
    with pytest.raises(InvalidParameterError) as err:
        dl.impact.simulate(arm, FOAM_1, HEAD_MIN, 1.25)
    assert (err.value.name, err.value.value) == (f"robot.{field}", value)


@pytest.mark.parametrize("column", ["K_h", "K_c", "C_h", "C_c"])
def test_matrix_columns_have_their_models_declared_bounds(column) -> None:
    """K_h = 1e20 in an (N, 8) row was accepted (HeadNeck refuses it); now the row's column
    is checked against the same declaration."""
    from designlab.impact.metrics import impact_metrics

    decl = {"K_h": dl.impact.HeadNeck, "C_h": dl.impact.HeadNeck}.get(column, dl.impact.Foam)
    field = {"K_h": "stiffness", "C_h": "damping", "K_c": "stiffness", "C_c": "damping"}[column]
    upper = re.escape(f"{params_of(decl)[field].le:g}")
    with pytest.raises(InvalidParameterError, match=rf"{column}\[0\].*<= {upper}"):
        impact_metrics([_design(**{column: 1e20})], 1.25, columns=PARAM_NAMES)


@pytest.mark.parametrize("index", [1, 3, 6, 8])  # C_mech, K_c, C_h, C_cont
def test_full_joint_at_1e20_is_refused_not_negative(index) -> None:
    """The full joint with C_mech, C_cont, K_c or C_h at 1e20 gave a negative duration and
    peak."""
    from designlab.impact.full_joint_model import full_joint_params
    from designlab.impact.metrics import matrix_metrics

    row = full_joint_params(GEARED, FOAM_1, HEAD_MIN)
    row[index] = 1e20
    with pytest.raises(InvalidParameterError, match=r"params\[0\]|\[0\] = 1e\+20"):
        matrix_metrics(row[None, :], 1.25)


@pytest.mark.parametrize("field", ["transmission_damping", "control_damping"])
def test_simulate_full_joint_with_a_1e20_damping_is_refused(field) -> None:
    arm = dataclasses.replace(GEARED, **{field: 1e20})
    with pytest.raises(InvalidParameterError, match="time scales span"):
        dl.impact.simulate(arm, FOAM_1, HEAD_MIN, 1.25)


def test_speed_limit_of_a_1e14_kg_manipulator_is_refused_not_zero() -> None:
    """It said 0 m/s where the answer is 0.375 m/s: double precision cannot serve the design,
    and the refusal says which parameter is extreme."""
    robot = dl.impact.ContactDynamics(mass=1e14, stiffness=2e4, damping=250)
    with pytest.raises(InvalidParameterError, match=r"time scales span.*M_r = 1e\+14 kg"):
        dl.codesign.speed_limit(robot, FOAM_1)


def test_simulate_sample_count_is_bounded_by_its_declaration() -> None:
    """``samples=10**9`` ended in MemoryError."""
    from designlab.impact.parameters import SIMULATION_SAMPLES

    with pytest.raises(InvalidParameterError, match=r"samples = 1000000000 .*<= 1e\+06"):
        dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25, samples=10**9)
    r = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25, samples=SIMULATION_SAMPLES.ge)
    assert r.t.size == 2
    with pytest.raises(InvalidParameterError, match="duration"):
        dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25, duration=-1.0)


@pytest.mark.parametrize(
    "value", [np.complex128(4.4 + 0j), np.complex64(4.4 + 1j), np.array([4.4 + 1j]), 4.4 + 0j]
)
def test_complex_numbers_are_refused_never_cast_to_real(value) -> None:
    """numpy casts np.complex128(4.4) to 4.4 with only a warning: every check refuses it."""
    from pydantic import TypeAdapter, ValidationError

    from designlab.errors import check_finite, check_positive
    from designlab.impact.metrics import impact_metrics
    from designlab.validation import real_array

    scalar = value if np.ndim(value) == 0 else value[0]
    for check in (check_finite, check_positive, real_array):
        with pytest.raises(InvalidParameterError, match="real"):
            check("x", value)
    with pytest.raises(InvalidParameterError, match=r"HeadNeck\.mass"):
        dl.impact.HeadNeck(mass=scalar, stiffness=3e3, damping=46.0)
    adapter = TypeAdapter(params_of(dl.impact.HeadNeck)["mass"].annotation())
    with pytest.raises(ValidationError, match="real number"):
        adapter.validate_python(scalar)
    with pytest.raises(InvalidParameterError, match="impact_velocity"):
        dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, scalar)
    with pytest.raises(InvalidParameterError):
        impact_metrics({**_BASE, "M_r": value}, 1.25)


def _extremes():
    """Each impact parameter at the ends of its declared range (1e20 where it has no upper
    bound; 0 where 0 is allowed, else a millionth of its typical low)."""
    decls = {d.symbol: d for c in (dl.impact.ContactDynamics, dl.impact.Foam, dl.impact.HeadNeck)
             for d in params_of(c).values() if d.symbol in PARAM_NAMES}  # fmt: skip
    out = []
    for name in PARAM_NAMES:
        d = decls[name]
        out.append((name, d.le if d.le is not None else 1e20))
        out.append((name, 0.0 if d.ge == 0 else 1e-6 * d.typical[0]))
    return out


@pytest.mark.parametrize(("name", "value"), _extremes())
def test_each_parameter_at_its_extreme_is_right_or_refused(name, value) -> None:
    """Siblings of the issue's cases: the named refusal, or the 50-digit answer."""
    from mp_reference import MpImpact

    from designlab.errors import ModelError
    from designlab.impact.conditioning import time_scale_ratio
    from designlab.impact.metrics import impact_metrics
    from designlab.impact.parameters import TIME_SCALE_RATIO

    p = _design(**{name: value})
    try:
        m = impact_metrics([p], 1.25, columns=PARAM_NAMES)
    except InvalidParameterError as err:
        assert "time scales span" in str(err)
        assert time_scale_ratio(np.array([p]))[0] > TIME_SCALE_RATIO.le
        return
    except ModelError as err:
        assert "no restoring stiffness" in str(err)
        return
    ref = MpImpact(p, 1.25)
    exact = ref.metrics()
    tol = ref.tolerances(exact, 1e-8, 1e-12)
    got = {"t_imp": m.impact_duration[0], "a_max": m.peak_head_acceleration[0],
           "eps_max": m.max_compression[0], "f_max": m.peak_force[0]}  # fmt: skip
    for key, v in got.items():
        assert abs(float(v) - exact[key]) <= tol[key], (key, v, exact[key])


# --- issue 41, the last silent and unclear impact answers ------------------------------------


@pytest.mark.parametrize("which", ["robot_velocity", "head_velocity"])
def test_closing_speed_refuses_speeds_beyond_their_declaration(which) -> None:
    """[1e300, 0, 0] gave an infinite speed with status ok; the declared bound is 20 m/s."""
    from designlab.impact.parameters import ROBOT_VELOCITY

    args = {"robot_velocity": [1.0, 0.0, 0.0], "head_velocity": [-0.5, 0.0, 0.0]}
    args[which] = [1e300, 0.0, 0.0]
    with pytest.raises(InvalidParameterError, match=rf"{which} = \[1e\+300, 0\.0, 0\.0\] m/s"):
        dl.impact.closing_speed(args["robot_velocity"], args["head_velocity"], [1.0, 0, 0])
    args[which] = [ROBOT_VELOCITY.le, 0.0, 0.0]  # at the bound: answered
    c = dl.impact.closing_speed(args["robot_velocity"], args["head_velocity"], [1.0, 0, 0])
    assert math.isfinite(c.closing_speed)


@pytest.mark.parametrize("odd", [0, 1, 2])
def test_closing_speed_blames_the_vector_whose_length_differs(odd) -> None:
    """A 2-vector robot_velocity was reported as a wrong head_velocity."""
    names = ("robot_velocity", "head_velocity", "normal")
    vectors = [[1.0, 0.0, 0.0], [-0.5, 0.0, 0.0], [1.0, 0.0, 0.0]]
    vectors[odd] = vectors[odd][:2]
    with pytest.raises(InvalidParameterError) as err:
        dl.impact.closing_speed(*vectors)
    assert (err.value.name, err.value.value) == (names[odd], vectors[odd])
    assert "length 3" in str(err.value)


def test_foam_envelope_needs_the_impact_velocity_of_a_fixed_robot() -> None:
    """``impact_velocity=None`` silently meant 1.25 m/s; None is for a LinkImpact only."""
    with pytest.raises(InvalidParameterError, match=r"impact_velocity = None .*LinkImpact"):
        dl.impact.foam_envelope(MANIPULATOR_1, impact_velocity=None, damping=[0.0, 60.0])


@pytest.mark.parametrize(
    ("field", "value"),
    [("inertia", 1e300), ("inertia", 2e4), ("inertia", "text"), ("joint_damping", 1e300),
     ("joint_damping", "text"), ("joint_stiffness", 2e9), ("joint_speed", 1e300),
     ("joint_speed", -1.0)],
)  # fmt: skip
def test_impact_point_sweep_checks_through_the_links_declarations(field, value) -> None:
    """Values LinkImpact refuses (1e300, text, a negative speed) were answered."""
    decl = params_of(dl.impact.LinkImpact)[field]
    args = {"inertia": 0.059, "joint_stiffness": 100.0, "joint_damping": 2.0, "joint_speed": 3.0}
    args[field] = value
    with pytest.raises(InvalidParameterError) as err:
        dl.impact.impact_point_sweep(**args, lever_arms=[0.05, 0.1])
    assert (err.value.name, err.value.value) == (field, value)
    assert f"<= {decl.le:g}" in str(err.value)


@pytest.mark.parametrize(
    ("arms", "shown"), [([True, False], "[True, False]"), ([0.1, 1e3], "lever_arms[1] = 1000.0")]
)
def test_impact_point_sweep_names_the_lever_arms_as_given(arms, shown) -> None:
    with pytest.raises(InvalidParameterError, match=re.escape(shown)):
        dl.impact.impact_point_sweep(0.059, 100.0, 2.0, 3.0, arms)


@pytest.mark.parametrize(
    ("omega", "shown"),
    [([], "omega_max = []"), ([True, False], "omega_max[0] = True"),
     (list(range(1, 1100)), "omega_max (number of values) = 1099")],
)  # fmt: skip
def test_band_fit_sweep_names_the_grid_as_given(omega, shown) -> None:
    """``[]`` was shown as ``0``, ``[True, False]`` as ``0.0``."""
    with pytest.raises(InvalidParameterError, match=re.escape(shown)):
        dl.impact.band_fit_sweep(GEARED, FOAM_1, HEAD_MIN, 1.25, omega)


@pytest.mark.parametrize("scale", [1e-300, 1e300])
def test_a_normal_of_any_finite_length_is_normalised(scale) -> None:
    """[1e-300, 0, 0] was refused as a zero vector (its norm underflowed); [1e300, 1e300, 0]
    overflowed to inf. The answer is (v_r - v_h) . n / |n|: 1.5 and 1.5 cos 45 deg."""
    c = dl.impact.closing_speed([1.0, 0.0, 0.0], [-0.5, 0.0, 0.0], [scale, 0.0, 0.0])
    assert c.closing_speed == 1.5
    c = dl.impact.closing_speed([1.0, 0.0, 0.0], [-0.5, 0.0, 0.0], [scale, scale, 0.0])
    assert c.closing_speed == pytest.approx(1.5 / math.sqrt(2.0), rel=1e-15)
