"""Every following parameter is declared once: the constructors, the JSON Schema of the study
models and hostile values agree (issues 18 and 19)."""

from __future__ import annotations

import math
import sys

import jsonschema
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from designlab.errors import InvalidParameterError
from designlab.following import accompanying as acc
from designlab.following import tether
from designlab.following.tether.paths import PATHS, SHAPE_PARAMETERS
from designlab.params import params_of
from designlab.study.kinds import accompanying as acc_kind
from designlab.study.kinds import tether_sweep
from designlab.study.specs import spec_model

MODELS = [
    tether.FollowerRobot,
    tether.PseudoJoystick,
    tether.FollowTheLeader,
    tether.FollowTheLeaderConstDistance,
    tether.CostWeights,
    acc.MecanumPlatform,
    acc.StringPotSensor,
    acc.UserFramePID,
]

#: Cross-field rules of the constructors (a value that breaks one is refused by the
#: constructor only; the schema checks each field alone).
RULES = {
    ("StringPotSensor", "median_window"): lambda v: v % 2 == 1,
    ("StringPotSensor", "min_range"): lambda v: v < 1.5,
    ("StringPotSensor", "max_range"): lambda v: v > 0.2,
}


def _boundary_values(decl) -> list:
    out = []
    for b in (decl.gt, decl.ge, decl.lt, decl.le):
        if b is None:
            continue
        if decl.kind == "integer":
            out += [int(b) - 1, int(b), int(b) + 1]
        else:
            out += [b, math.nextafter(b, -math.inf), math.nextafter(b, math.inf)]
    return out


def _cases():
    for cls in MODELS:
        for name, decl in params_of(cls).items():
            if decl.kind in ("real", "integer"):
                yield pytest.param(cls, name, decl, id=f"{cls.__name__}.{name}")


@pytest.mark.parametrize(("cls", "name", "decl"), list(_cases()))
def test_schema_and_constructor_accept_the_same_boundary_values(cls, name, decl):
    schema = spec_model(cls).model_json_schema()
    rule = RULES.get((cls.__name__, name), lambda v: True)
    for value in _boundary_values(decl):
        if not rule(value):
            continue
        try:
            jsonschema.validate({name: value}, schema)
            schema_ok = True
        except jsonschema.ValidationError:
            schema_ok = False
        try:
            cls(**{name: value})
            ctor_ok = True
        except InvalidParameterError:
            ctor_ok = False
        assert schema_ok == ctor_ok, (cls.__name__, name, value, schema_ok, ctor_ok)


def test_no_kind_restates_a_domain_field():
    """The YAML models take their fields from the declarations (same bounds and defaults)."""
    platform = acc_kind.PlatformSpec.model_json_schema()["properties"]
    for name, decl in params_of(acc.MecanumPlatform).items():
        assert platform[name].get("default") == decl.default
    sensor = acc_kind.SensorSpec()
    assert sensor.build() == acc.StringPotSensor()
    assert acc_kind.PIDSpec().build() == acc.UserFramePID()
    for path, (key, decl) in tether_sweep.TETHER_PARAMETERS.items():
        where, _, field = path.rpartition(".")
        assert key == decl.symbol
        if where:
            assert decl is params_of(decl.owner and getattr(tether, decl.owner))[field]


HOSTILE = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0, -1, 1, 1e300, -1e300, 1e-300, sys.float_info.max]),
    st.integers(-(10**12), 10**12),
    st.text(max_size=5),
    st.booleans(),
    st.none(),
    st.just([1.0, 2.0]),
)


def _finite_fields(obj) -> bool:
    for value in vars(obj).values():
        if isinstance(value, float) and math.isnan(value):
            return False
    return True


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(MODELS), st.data(), HOSTILE)
def test_fuzz_model_constructors(cls, data, value):
    name = data.draw(st.sampled_from(list(params_of(cls))))
    try:
        obj = cls(**{name: value})
    except InvalidParameterError as exc:
        assert name in exc.name or name in str(exc)
        return
    assert _finite_fields(obj)


SHAPES = [(shape, arg) for shape, decls in SHAPE_PARAMETERS.items() for arg in decls]


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(SHAPES), HOSTILE)
def test_fuzz_path_constructors(shape_arg, value):
    shape, arg = shape_arg
    try:
        path = PATHS[shape](**{arg: value})
    except InvalidParameterError as exc:
        assert arg in str(exc)
        return
    assert np.all(np.isfinite(path.points)) and math.isfinite(path.length)


WALK_ARGS = ["speed", "yaw_rate", "distance", "turn_angle", "radius", "ramp_time", "pause"]
WALK_ARGS += ["stand_before", "settle_time", "pivot_offset", "step_frequency", "start_heading"]


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(["forward", "left_pivot", "circle_cw"]), st.sampled_from(WALK_ARGS), HOSTILE)
def test_fuzz_walking_tasks(task, arg, value):
    try:
        t = acc.walking_task(task, **{arg: value})
    except InvalidParameterError as exc:
        assert arg in str(exc) or "duration" in str(exc)
        return
    assert np.all(np.isfinite(t.x)) and np.all(np.isfinite(t.heading))
