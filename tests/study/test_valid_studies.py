"""No validated study crashes: every kind's run and report writer on generated valid studies.

For every kind of the registry, hypothesis draws a small valid study: the kind's fuzz
carrier (``test_fuzz_studies.BASE``, at the smallest sizes the schema allows for the heavy
kinds) with some of its fields set to other values the schema declares valid - the
corners a hand-written study rarely visits: a scenario without obstacles, Masoud's
clockwise sense, one density, a single method. Whatever ``validate`` accepts, ``run`` must
compute and the report writer must write (failed points are listed in the report, never
a traceback). Seeded (derandomised) and a few examples per kind, so the suite stays quick;
``benchmarks/fuzz_valid_studies.py`` runs many more.

The studies that crashed before: ``navigation_scenarios`` with a scenario without
obstacles (``ValueError`` in the force map of the report) and ``navigation_crowds`` with
``gains: {direction: -1}`` on VFF (every run failed, then ``KeyError: 'success'`` in the
summary); the second is now refused by ``validate`` (the gains are Masoud's).
"""

from __future__ import annotations

import copy
import itertools
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_fuzz_studies import BASE

from designlab.errors import StudyError
from designlab.report import write_report
from designlab.study import parse_study, run_study, study_kinds

#: The fuzz carriers, by kind.
CARRIERS: dict[str, dict[str, Any]] = BASE

#: Heavy kinds at the smallest sizes their schema allows (about a second each).
SMALL: dict[str, dict[str, Any]] = {
    "navigation_gains": {"popsize": 4, "max_evaluations": 4, "refine": False,
                         "sensitivity": False, "sobol_samples": 0},
    "tether_tuning": {"popsize": 2, "maxiter": 1},
    "joint_reduction": {"ratios": {"low": 0.1, "high": 100, "num": 2}},
}  # fmt: skip

_OWN_SCENARIO = {
    "name": "empty_room",
    "start": [2.0, 0.0],
    "goal": [0.0, 0.0],
    "robot": {"type": "holonomic", "max_speed": 0.7, "max_accel": 10},
    "horizon": 6,
    "obstacles": [],
}
_DISC_SCENARIO = {
    **_OWN_SCENARIO,
    "name": "one_stand",
    "obstacles": [{"kind": "disc", "name": "stand", "radius": 0.1, "position": [1.0, 0.5],
                   "r2": 0.8, "r3": 0.4}],
}  # fmt: skip
_VFF = {"k1": 4.3, "b": 0.68, "k3": 20.3, "k5": 240.7}

#: kind -> {path in the study: strategy of values its schema declares valid}.
VARIANTS: dict[str, dict[tuple[Any, ...], st.SearchStrategy[Any]]] = {
    "impact_cases": {("cases", 0, "impact_velocity"): st.floats(0.05, 3.0)},
    "impact_sweep": {("base", "impact_velocity"): st.floats(0.1, 3.0)},
    "navigation_scenarios": {
        ("scenarios",): st.sampled_from(
            [[_OWN_SCENARIO], [_DISC_SCENARIO], [{"configuration": 4}]]
        ),
        ("methods",): st.sampled_from(
            [
                [{"label": "masoud cw", "method": "masoud", "gains": {"direction": -1}}],
                [{"label": "cbf", "method": "cbf"}],
                [{"label": "ge", "method": "ge_cui"}],
                [{"label": "vff", "gains": _VFF, "stabilising": "lyapunov"}],
            ]
        ),
    },
    "navigation_crowds": {
        ("methods",): st.sampled_from(
            [
                [{"method": "masoud", "gains": {"direction": -1}}],
                [{"method": "cbf"}],
                [{"method": "vff", "tag": "thesis", "gains": _VFF, "stabilising": "off"}],
            ]
        ),
        ("scenarios",): st.sampled_from([["crossing"], ["corridor_counterflow"]]),
    },
    "navigation_regions": {("robot", "max_speed"): st.floats(0.1, 1.0)},
    "navigation_planners": {
        ("planners",): st.sampled_from([[{"method": "errt"}], [{"method": "field_dstar"}]])
    },
    "tether_snagging": {("detail_gaps",): st.sampled_from([[1.0], [2.5], []])},
    "tether_step_size": {("min_steps",): st.sampled_from([[0.01, 0.4], [0.05, 0.1, 0.4]])},
}

#: Kinds whose run and report take several seconds even at their smallest: only the
#: carrier here (``benchmarks/fuzz_valid_studies.py`` draws their variants).
HEAVY = {"navigation_gains", "tether_tuning", "accompanying", "codesign", "joint_reduction",
         "tether_step_size", "tether_snagging"}  # fmt: skip


def _set(node: Any, path: tuple[Any, ...], value: Any) -> None:
    for part in path[:-1]:
        node = node[part]
    node[path[-1]] = value


def _study(kind: str, data: Any) -> tuple[str, dict[str, Any]]:
    body = copy.deepcopy({**CARRIERS[kind], **SMALL.get(kind, {})})
    for path, values in VARIANTS.get(kind, {}).items():
        if data.draw(st.booleans(), label=f"set {path}"):
            _set(body, path, data.draw(values, label=str(path)))
    study = {"designlab": 1, "kind": kind, "name": f"valid_{kind}", **body}
    return yaml.safe_dump(study, sort_keys=False), study


def test_every_kind_is_exercised() -> None:
    assert set(study_kinds()) <= set(CARRIERS)
    assert set(VARIANTS) | set(SMALL) | HEAVY <= set(CARRIERS)


def _check(kind: str, data: Any, tmp: Path) -> None:
    text, _ = _study(kind, data)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        try:
            study = parse_study(text, file="valid.yaml")
        except StudyError as exc:  # the variants are valid by declaration: a test defect
            pytest.fail(f"a variant of {kind} meant to be valid is refused: {exc}\n{text}")
    result = run_study(study)
    out = write_report(result, tmp, command="designlab run valid.yaml", study_text=text)
    written = {p.name for p in out.iterdir()}
    assert "study.yaml" in written and len(written) >= 2, written


def _examples(kind: str) -> int:
    """The carrier, then (for a kind with variants) one seeded variant."""
    return 1 if kind in HEAVY or kind not in VARIANTS else 2


@pytest.mark.parametrize("kind", sorted(study_kinds()))
def test_a_validated_study_runs_and_its_report_is_written(kind: str, tmp_path: Path) -> None:
    @settings(max_examples=_examples(kind), derandomize=True, database=None, deadline=None,
              suppress_health_check=list(HealthCheck))  # fmt: skip
    @given(data=st.data())
    def check(data: Any) -> None:
        _check(kind, data, tmp_path / f"r{next(runs)}")

    runs = itertools.count()

    check()


def test_masoud_gains_given_to_vff_are_refused_by_validate() -> None:
    """``{direction: -1}`` is Masoud's gains: on VFF every run failed, then the summary."""
    for kind in ("navigation_crowds", "navigation_scenarios"):
        body = copy.deepcopy(CARRIERS[kind])
        body["methods"] = [{"method": "vff", "label": "v", "gains": {"direction": -1}}]
        if kind == "navigation_crowds":
            del body["methods"][0]["label"]
        text = yaml.safe_dump({"designlab": 1, "kind": kind, "name": "x", **body})
        with pytest.raises(StudyError, match=r"methods\[0\]: gains: \{'direction': -1\} are not "
                           r"vff gains \(vff takes k1, b, k3, k5\)"):  # fmt: skip
            parse_study(text, file="s.yaml")


def test_the_force_map_of_a_scenario_without_obstacles_is_the_attraction() -> None:
    import dataclasses

    import designlab as dl
    from designlab.navigation.force_map import force_map

    nav = dl.navigation
    room = dataclasses.replace(nav.configuration(1), obstacles=())
    x, y = np.linspace(0, 4, 9), np.linspace(-0.4, 1.6, 5)
    m = force_map(room, nav.EXPERIMENT_GAINS, x, y)
    X, Y = np.meshgrid(x, y)
    E = np.stack([room.goal[0] - X, room.goal[1] - Y], axis=2)
    assert np.array_equal(m.force, nav.EXPERIMENT_GAINS.k1 * E)  # K1 E alone, exactly
    assert np.isnan(m.minimum).all()  # no active region: no local minimum to point at
    obstacles = force_map(room, nav.EXPERIMENT_GAINS, x, y, part="obstacles")
    assert np.array_equal(obstacles.force, np.zeros_like(E))


def test_a_scenario_without_obstacles_runs_and_its_report_is_written(tmp_path: Path) -> None:
    """It validated, then the report's force map raised ``ValueError`` (no obstacle)."""
    body = {"scenarios": [_OWN_SCENARIO], "methods": [{"label": "vff", "gains": _VFF}]}
    text = yaml.safe_dump({"designlab": 1, "kind": "navigation_scenarios", "name": "empty",
                           **body})  # fmt: skip
    result = run_study(parse_study(text, file="empty.yaml"))
    out = write_report(result, tmp_path, command="designlab run empty.yaml", study_text=text)
    assert (out / "force_empty_room.png").is_file()
    row = result.to_frame().iloc[0]
    assert row["status"] == "ok" and not row["collided"] and not row["entered_critical"]
    assert 0 < row["T_arrive_s"] < 6  # nothing in the way: it arrives within the horizon


def test_a_crowd_grid_whose_every_run_failed_is_summarised_not_a_key_error() -> None:
    import pandas as pd

    from designlab.navigation.crowds.study import summarise_runs

    runs = pd.DataFrame([{"scenario": "crossing", "density": 0.1, "seed": 0, "method": "vff",
                          "status": "error", "error": "InvalidParameterError: ..."}])  # fmt: skip
    row = summarise_runs(runs).iloc[0]
    assert (row["runs"], row["failed"]) == (0.0, 1.0)
    assert np.isnan(row["success_rate"]) and np.isnan(row["time_to_goal_mean_s"])
