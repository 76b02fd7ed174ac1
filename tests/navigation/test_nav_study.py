"""The navigation_scenarios and navigation_sweep study kinds: schema, runs, reports."""

from __future__ import annotations

import math

import pytest

from designlab.errors import StudyError
from designlab.report import write_report
from designlab.results import check_result
from designlab.study import parse_study, run_study

SCEN = """\
designlab: 1
kind: navigation_scenarios
name: tiny_nav
scenarios:
  - {configuration: 1}
  - name: corridor
    start: [4.0, 0.5]
    goal: [0.0, 0.5]
    obstacles:
      - {name: table, kind: rectangle, center: [2.0, -0.6], length: 1.0, width: 0.5,
         r2: 0.8, r3: 0.4}
      - {name: visitor, kind: disc, radius: 0.4, r2: 2.1, r3: 0.8,
         walk: {start: [0, 2], end: [4, 2], speed: 0.8}}
methods:
  - {label: "New VFF*", gains: {k1: 4.3, b: 0.68, k3: 20.3, k5: 240.7}, stabilising: "off"}
  - {label: "Masoud*", method: masoud}
references:
  - {scenario: ch6_config1, method: "New VFF*", T_arrive_s: 6.3, d_circle_min_m: 0.55, H: 0.74}
"""


def test_vff_scenarios_runs_and_reports(tmp_path) -> None:  # type: ignore[no-untyped-def]
    study = parse_study(SCEN)
    result = run_study(study)
    check_result(result)
    frame = result.to_frame()
    assert len(frame) == 4
    row = frame[(frame.scenario == "ch6_config1") & (frame.method == "New VFF*")].iloc[0]
    assert row.d_circle_min_m == pytest.approx(0.55, abs=0.03)
    assert row.ref_T_arrive_s == 6.3
    assert math.isnan(frame[frame.method == "Masoud*"].ref_H.iloc[0])
    out = write_report(result, tmp_path, study_text=SCEN, index=False)
    names = {p.name for p in out.iterdir()}
    assert {
        "summary.md",
        "results.csv",
        "stability.csv",
        "study.yaml",
        "trajectories_ch6_config1.png",
        "distances_corridor.png",
    } <= names
    text = (out / "summary.md").read_text()
    assert "Lyapunov audit" in text and "ref_T_arrive_s" in text


@pytest.mark.parametrize(
    "patch, message",
    [
        ("  - {configuration: 1}\n", "  - {configuration: 9}\n"),
        ("  - {configuration: 1}\n", "  - {configuration: 1, start: [0, 0]}\n"),
        ("gains: {k1: 4.3, b: 0.68", "gains: {k1: -4.3, b: 0.68"),
        ("gains: {k1: 4.3, b: 0.68", "gains: {k1: 4.3e12, b: 0.68"),
        ("method: masoud}", "method: masoud, gains: {k5: 1e300}}"),
        ('method: "New VFF*", T_arrive_s', 'method: "Nope", T_arrive_s'),
        ('stabilising: "off"', 'stabilising: "maybe"'),
        ("kind: disc, radius: 0.4,", "kind: disc,"),
        ("method: masoud}", "method: masoud, gains: {k1: 5, b: 0.5}}"),
        ("method: masoud}", "method: masoud, gains: {direction: 2}}"),
        ("method: masoud}", "method: masoud, cbf_gains: [4, 4]}"),
        ("method: masoud}", "method: masoud, tie_side: up}"),
        ("method: masoud}", "method: cbf, cbf_gains: [-1, 4]}"),
    ],
)
def test_bad_studies_are_rejected(patch: str, message: str) -> None:
    with pytest.raises(StudyError):
        parse_study(SCEN.replace(patch, message))


def test_goal_inside_an_obstacle_is_reported_with_the_parameter() -> None:
    # validate refuses what run refuses: the scenario is built while the file is validated
    bad = SCEN.replace("center: [2.0, -0.6]", "center: [0.0, 0.5]")
    with pytest.raises(StudyError, match=r"scenarios\[1\]: Scenario.goal"):
        parse_study(bad)


SWEEP = """\
designlab: 1
kind: navigation_sweep
name: tiny_sweep
base:
  gains: {k1: 4.3, b: 0.68, k3: 20.3, k5: 240.7}
  scenarios: [[1, 6], [3, 6]]
  stabilising: "off"
sweep:
  method: grid
  parameters:
    gains.k5: {values: [120.0, 240.7]}
    robot.max_speed: {values: [0.5, 0.7]}
sensitivity:
  metrics: [H_mean, T_mean_s]
  one_at_a_time: {deltas_pct: [-20, 20], parameters: [gains.k1, gains.b]}
"""


@pytest.mark.slow
def test_vff_sweep_runs_through_the_shared_machinery(tmp_path) -> None:  # type: ignore[no-untyped-def]
    study = parse_study(SWEEP)
    result = run_study(study)
    check_result(result)
    frame = result.to_frame()
    assert len(frame) == 4
    assert (frame["collisions"] == 0).all()
    slow = frame[frame["v_max_m_per_s"] == 0.5] if "v_max_m_per_s" in frame else frame.iloc[:2]
    fast = frame[frame["v_max_m_per_s"] == 0.7] if "v_max_m_per_s" in frame else frame.iloc[2:]
    assert slow["T_mean_s"].min() > fast["T_mean_s"].max()  # a slower robot arrives later
    out = write_report(result, tmp_path, study_text=SWEEP, index=False)
    assert (out / "summary.md").exists()
    # jit: true compiles the step to four gain sets per pass: the same table to the bit
    fast = run_study(
        parse_study(SWEEP.replace('stabilising: "off"', 'stabilising: "off"\n  jit: true'))
    )
    assert fast.to_frame().equals(frame)
    with pytest.raises(StudyError, match=r"gains.k5: 2.4e\+12 N/m\^2 .* <= 1e\+09"):
        parse_study(SWEEP.replace("values: [120.0, 240.7]", "values: [120.0, 2.4e12]"))


TOL_SWEEP = """
designlab: 1
kind: navigation_sweep
name: tolerance
base: {gains: {k1: 3.0, b: 0.25, k3: 20.0, k5: 17.0}, scenarios: [[1, 6]]}
sweep:
  method: grid
  parameters:
    arrival_tolerance: {values: [0.05, 0.15]}
"""


def test_vff_sweep_varies_the_arrival_tolerance() -> None:
    frame = run_study(parse_study(TOL_SWEEP)).to_frame()
    t = dict(zip(frame.filter(like="tol").iloc[:, 0], frame["T_mean_s"], strict=True))
    # the same run, first passage at 0.15 m then at 0.05 m of the goal (6.48 s and 6.63 s)
    assert t[0.05] > t[0.15]
    assert t[0.15] == pytest.approx(6.483, abs=1e-3)
    with pytest.raises(ValueError, match="arrival_tolerance"):
        parse_study(TOL_SWEEP.replace("[0.05, 0.15]", "[0.05, 2.0]"))


def test_vff_metrics_take_the_walk_ramp_and_default_the_optional_keys() -> None:
    import numpy as np

    from designlab.navigation.evaluators import vff_metrics_chunk

    base = {k: np.array([v, v]) for k, v in dict(k1=3.0, b=0.25, k3=20.0, k5=17.0).items()}
    base |= {"v_max": np.array([0.7, 0.7]), "a_max": np.array([10.0, 10.0])}
    base |= {"v_h": np.array([1.0, 1.0])}
    opts = {"scenarios": [[2, 6]], "stabilising": "off"}
    plain = vff_metrics_chunk(base, opts)  # no ramp / tol columns: defaults 0.5 s, 0.15 m
    ramps = vff_metrics_chunk(base | {"ramp": np.array([0.5, 2.0])}, opts)
    assert plain["T_mean_s"][0] == ramps["T_mean_s"][0]
    assert ramps["T_mean_s"][1] != ramps["T_mean_s"][0]  # a slower-starting walker


def test_baseline_gains_tie_side_and_cbf_gains_from_yaml() -> None:
    text = SCEN.replace(
        "method: masoud}",
        "method: masoud, gains: {direction: -1}}\n"
        "  - {label: CBF soft, method: cbf, cbf_gains: [1.0, 2.0]}\n"
        "  - {label: GC, method: ge_cui, gains: {k3: 20.0}}",
    )
    study = parse_study(text)
    by = {m.label: m for m in study.methods}
    assert by["Masoud*"].gains.build().direction == -1
    assert by["CBF soft"].cbf_gains == (1.0, 2.0)
    assert by["GC"].gains.build().k3 == 20.0 and by["GC"].gains.build().b == 0.75
