"""Fuzz: every study kind's YAML with one value replaced by a random one.

The loader must either refuse the file with a :class:`StudyError` that names
the file (and a line and a field where the value is), or accept it; for the
quick kinds an accepted study is also run and its metrics must be finite or
the result must say why not (its status and warnings).
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from designlab.errors import DesignlabError, InvalidParameterError, StudyError
from designlab.study import parse_study, run_study, study_kinds

#: One small valid study of each kind (the carriers of the hostile corpus).
BASE: dict[str, dict[str, Any]] = {
    "impact_cases": {"cases": [{"robot": "MANIPULATOR_1", "foam": "FOAM_1", "head": "TEST_HEAD",
                                "impact_velocity": 0.4}]},
    "impact_sweep": {"base": {"robot": "MANIPULATOR_1", "foam": "FOAM_1", "head": "HEAD_MIN",
                              "impact_velocity": 1.25},
                     "sweep": {"method": "grid",
                               "parameters": {"foam.stiffness": {"values": [2.0e4, 4.0e4]}}}},
    "foam_envelope_sweep": {"base": {"robot": "MANIPULATOR_1", "foam": "FOAM_1"},
                      "damping": {"low": 0, "high": 200, "num": 5}},
    "foam_design": {"robots": ["MANIPULATOR_1"], "foams": ["FOAM_1"],
                    "damping": {"low": 20, "high": 100, "num": 3}, "optimal": False,
                    "worst_case_check": False},
    "joint_reduction": {"joints": [{"name": "geared", "inertia": 0.059, "k_mech": 2000,
                                    "c_mech": 2.0, "k_cont": 1500, "c_cont": 30,
                                    "lever_arm": 0.2}],
                        "ratios": {"low": 0.1, "high": 100, "num": 4}},
    "zeng_ch3_claims": {"readings": [{"name": "b", "impact_velocity": 0.25,
                                      "feedforward": False}], "speed_ratios": [1.0]},
    "tether_comparison": {"paths": [{"type": "slalom"}],
                            "controllers": [{"type": "PseudoJoystick"}],
                            "desired_lengths": [0.6]},
    "tether_tuning": {"laws": ["FollowTheLeader"], "paths": [{"type": "slalom"}],
                        "validation_paths": [{"type": "square_s"}]},
    "tether_sweep": {"base": {"controller": {"type": "FollowTheLeader"},
                                "path": {"type": "slalom"}},
                       "sweep": {"method": "grid",
                                 "parameters": {"controller.lookahead": {"values": [0.1, 0.5]}}}},
    "navigation_scenarios": {"scenarios": [{"configuration": 1}],
                      "methods": [{"label": "vff", "gains": {"k1": 4.3, "b": 0.68, "k3": 20.3,
                                                             "k5": 240.7},
                                   "stabilising": "off"}]},
    "navigation_sweep": {"base": {"gains": {"k1": 4.3, "b": 0.68, "k3": 20.3, "k5": 240.7},
                           "scenarios": [[1, 6]], "stabilising": "off"},
                  "sweep": {"method": "grid",
                            "parameters": {"gains.k1": {"values": [3.0, 4.3]}}}},
    "navigation_gains": {"modes": ["off"], "max_evaluations": 32},
    "navigation_account": {"tables": ["6.2"], "methods": ["New VFF*"]},
    "navigation_planners": {"scenarios": [{"configuration": 1}], "mirror": False,
                            "planners": [{"method": "vo", "settings": {"horizon": 2.0}}],
                            "methods": []},
    "navigation_regions": {"robot": {"type": "holonomic", "max_speed": 1.0},
                           "obstacles": [{"name": "h", "type": "human", "max_speed": 1.4},
                                         {"name": "b", "type": "rectangle", "offset": 0.3,
                                          "critical_radius": 0.5, "active_radius": 1.0}]},
    "accompanying": {"tasks": ["forward"],
                     "tuning": {"tune_on": ["forward"], "derivative_free": False}},
    "tether_stability": {"controllers": [{"type": "PseudoJoystick"}],
                         "lengths": {"low": 0.5, "high": 2.0, "num": 2}, "angles": 3,
                         "max_time": 5},
    "tether_step_size": {"paths": [{"type": "square_s"}], "min_steps": [0.01, 0.4]},
    "tether_snagging": {"gaps": {"low": 1.0, "high": 2.5, "num": 3}, "detail_gaps": [2.5]},
    "tether_modes": {"paths": [{"type": "straight_line", "length": 3.0}],
                     "modes": ["SideJoystick"], "side_offsets": [0.5],
                     "brake_laws": ["PseudoJoystick"]},
    "codesign": {"scenarios": [{"configuration": 2}],
                 "front": {"objectives": ["arrival_time", "foam_thickness"], "population": 4,
                           "generations": 1},
                 "speed_map": {"stiffness": {"num": 3}, "damping": {"num": 3}},
                 "risk": {"foams": ["FOAM_1"], "speeds": {"num": 3}, "samples": 1000}},
    "navigation_crowds": {"scenarios": ["corridor_counterflow"], "densities": [0.1],
                          "seeds": [0], "methods": [{"method": "vff"}],
                          "crowd": {"length": 8.0, "horizon": 0.5}, "animations": False},
}  # fmt: skip

#: Kinds quick enough to run on every accepted example: what ``run`` refuses as input
#: (a StudyError or an InvalidParameterError) ``validate`` must have refused.
RUN = {"impact_cases", "impact_sweep", "navigation_regions", "foam_envelope_sweep",
       "tether_stability", "navigation_sweep"}  # fmt: skip

VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0, -1, 1, 10**9, 10**30, 1e-300, 1e300, -0.0]),
    st.integers(min_value=-(10**12), max_value=10**12),
    st.booleans(),
    st.none(),
    st.text(max_size=8),
    st.lists(st.floats(allow_nan=False, allow_infinity=False, width=32), max_size=3),
    st.dictionaries(st.sampled_from(["low", "high", "x", "preset"]), st.integers(), max_size=2),
)


def _leaves(node: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    if isinstance(node, dict):
        return [p for k, v in node.items() for p in _leaves(v, (*path, k))] + [path]
    if isinstance(node, list):
        return [p for i, v in enumerate(node) for p in _leaves(v, (*path, i))] + [path]
    return [path]


def _replace(node: Any, path: tuple[Any, ...], value: Any) -> Any:
    if not path:
        return value
    head, rest = path[0], path[1:]
    if isinstance(node, dict):
        return {**node, head: _replace(node[head], rest, value)}
    out = list(node)
    out[head] = _replace(out[head], rest, value)
    return out


def test_every_kind_has_a_fuzz_carrier() -> None:
    assert set(study_kinds()) <= set(BASE)


def _finite_or_explained(result: Any) -> None:
    frame = result.to_frame()
    computed = [c for c in frame.columns if not c.startswith(("ref_", "err_", "exp_"))]
    numbers = frame[computed].select_dtypes("number").to_numpy(dtype=float)  # not references
    if not np.isfinite(numbers).all():
        assert result.status != "ok" or result.warnings, "a non-finite metric with status ok"


@pytest.mark.parametrize("kind", sorted(BASE))
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_random_values_give_a_clear_error_or_a_finite_result(kind: str, data: Any) -> None:
    base = {"designlab": 1, "kind": kind, "name": "fuzz", **BASE[kind]}
    paths = [p for p in _leaves(base) if p and p[0] not in ("designlab", "kind")]
    path = data.draw(st.sampled_from(paths), label="path")
    value = data.draw(VALUES, label="value")
    text = yaml.safe_dump(_replace(base, path, value), sort_keys=False)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            study = parse_study(text, file="fuzz.yaml")
    except StudyError as exc:
        message = str(exc)
        assert message.startswith("fuzz.yaml"), message
        assert "Traceback" not in message and len(message) < 20_000
        return
    if kind in RUN:
        try:
            result = run_study(study)
        except (StudyError, InvalidParameterError) as exc:  # bad input: validate's to refuse
            pytest.fail(f"validate accepted what run refuses as input: {exc}\n{text}")
        except DesignlabError as exc:  # a model or solver failure: still a clear error
            assert str(exc), exc
            return
        _finite_or_explained(result)
    assert not (isinstance(value, float) and math.isnan(value) and path[-1] == "name")
