"""Hostile inputs of the accompanying robot (issue 18): clear errors, caps before allocation,
the same limits in Python and YAML, tuning results with their gains, progress."""

from __future__ import annotations

import pytest

from designlab.errors import DesignlabError, InvalidParameterError
from designlab.following import accompanying as acc
from designlab.progress import Progress
from designlab.study import parse_study


def _study(body: str) -> str:
    return f"designlab: 1\nkind: accompanying\nname: hostile\ntuning: null\n{body}"


@pytest.mark.parametrize(
    ("make", "name"),
    [
        (lambda: acc.walking_task("forward", distance=1e5), "distance"),
        (lambda: acc.walking_task("forward", speed=100.0), "speed"),
        (lambda: acc.walking_task("forward", speed=1e-9), "duration"),
        (lambda: acc.walking_task("circle_cw", radius="0.4"), "radius"),
        (lambda: acc.walking_task("circle_cw", radius=True), "radius"),
        (lambda: acc.StringPotSensor(sample_rate=1e6), "sample_rate"),
        (lambda: acc.StringPotSensor(min_range=1.0, max_range=0.5), "max_range"),
        (lambda: acc.UserFramePID(kp=0.0, ki=0.0, kd=0.0), "kp"),
        (lambda: acc.loop_analysis(n_frequencies=0), "n_frequencies"),
        (lambda: acc.loop_analysis(n_frequencies=1), "n_frequencies"),
        (lambda: acc.simulate(acc.walking_task("forward"), settle_band=-1), "settle_band"),
        (lambda: acc.tune([acc.walking_task("forward")], max_evaluations=0), "max_evaluations"),
        (lambda: acc.tune([acc.walking_task("forward")], ms_max=0.5), "ms_max"),
    ],
)
def test_bad_input_is_refused_naming_the_parameter(make, name):
    with pytest.raises(InvalidParameterError) as exc:
        make()
    assert name in str(exc.value)


def test_csv_empty_and_text_values_name_the_file(tmp_path):
    empty = tmp_path / "empty.csv"
    empty.write_text("")
    with pytest.raises(InvalidParameterError, match=r"empty\.csv"):
        acc.walking_task_from_csv(empty, target_position=(0.0, 0.5))
    bad = tmp_path / "walk.csv"
    bad.write_text("time_s,x_m,y_m,heading_deg\n0,0,0,90\n1,0,x,90\n")
    with pytest.raises(InvalidParameterError) as exc:
        acc.walking_task_from_csv(bad, target_position=(0.0, 0.5))
    assert "walk.csv line 3" in str(exc.value) and "'y_m'" in str(exc.value)


@pytest.mark.parametrize(
    ("body", "name"),
    [
        ("sensor: {min_range: 1.0, max_range: 0.5}", "max_range"),
        ("controller: {kp: 0, ki: 0, kd: 0}", "kp"),
        ("walking: {speed: 100}", "speed"),
        ("walking: {radius: '0.4'}", "radius"),
        ("walking: {radius: true}", "radius"),
        ("walking: {settle_time: 5}", "settle_time"),
        ("sensor: {sample_rate: 1.0e6}", "sample_rate"),
        ("sensor: {median_window: 4}", "odd"),
    ],
)
def test_yaml_refuses_what_the_run_refuses(body, name):
    with pytest.raises(DesignlabError) as exc:
        parse_study(_study(body))
    assert name in str(exc.value)


def test_tuning_result_frame_holds_the_gains_and_progress_is_reported():
    seen: list[Progress] = []
    res = acc.tune([acc.walking_task("forward")], progress=seen.append)
    frame = res.to_frame()
    assert frame["kp_1_s"].iloc[0] == res.controller.kp
    assert frame["ki_1_s2"].iloc[0] == res.controller.ki
    assert {"task", "rms_tuned_m", "kd", "kp_heading"} <= set(frame.columns)
    assert [p.step for p in seen] == list(range(1, res.iterations + 1))
    assert seen[-1].best == pytest.approx(res.controller.ki)
    assert isinstance(res.status, acc.PIDTuningStatus) and res.status == "ok"


# --------------------------------------------------------------------------- issue 41
def test_a_walk_file_is_read_only_when_it_is_a_bounded_regular_file(tmp_path):
    """/dev/zero as a walk file was read whole until the machine ran out of memory."""
    import os
    from pathlib import Path

    for path in (Path("/dev/zero"), tmp_path):
        if path.exists():
            with pytest.raises(InvalidParameterError, match="regular file"):
                acc.walking_task_from_csv(path, target_position=(0.0, 0.6))
    if hasattr(os, "mkfifo"):
        fifo = tmp_path / "walk.csv"
        os.mkfifo(fifo)
        with pytest.raises(InvalidParameterError, match="regular file"):
            acc.walking_task_from_csv(fifo, target_position=(0.0, 0.6))
    with pytest.raises(InvalidParameterError, match="file not found"):
        acc.walking_task_from_csv(tmp_path / "missing.csv", target_position=(0.0, 0.6))
    nul = tmp_path / "nul.csv"
    nul.write_bytes(b"time_s,x_m,y_m,heading_rad\n0,0,0,0\x00\n")
    with pytest.raises(InvalidParameterError, match="NUL"):
        acc.walking_task_from_csv(nul, target_position=(0.0, 0.6))


def test_user_frame_functions_refuse_nan_and_mismatched_shapes():
    import math

    import numpy as np

    with pytest.raises(InvalidParameterError, match="target_gamma"):
        acc.robot_frame_error((0.0, 0.6), math.nan, [1.0], [0.0], [0.0])  # was a NaN row
    with pytest.raises(InvalidParameterError, match="d, theta_u, theta_r"):
        acc.robot_frame_error((0.0, 0.6), 0.0, [1.0, 2.0], [0.0], [0.0])
    with pytest.raises(InvalidParameterError, match="p_c"):
        acc.string_pot_readings([math.nan, 0.0], 0.0)  # was NaN readings
    with pytest.raises(InvalidParameterError, match="p_c, gamma_c"):
        acc.string_pot_readings(np.zeros((2, 2)), [0.0])
    with pytest.raises(InvalidParameterError, match="user_pose, robot_pose"):
        acc.robot_in_user_frame(np.zeros((3, 2)), np.zeros((3, 3)))
    readings = acc.string_pot_readings([0.2, 0.6], 0.3)
    err = acc.robot_frame_error((0.2, 0.6), 0.3, *readings)  # the robot on its target
    assert np.abs(err).max() < 1e-12


def test_accompany_metrics_refuse_a_walk_that_stops_before_it_starts():
    import math

    import numpy as np

    t, pose = np.arange(3.0), np.zeros((3, 3))
    with pytest.raises(InvalidParameterError, match="walk_stop"):
        acc.accompany_metrics(t, pose, pose, (0.0, 0.6), 0.0, 2.0, 1.0)  # was accepted
    with pytest.raises(InvalidParameterError, match="walk_stop"):
        acc.accompany_metrics(t, pose, pose, (0.0, 0.6), 0.0, 0.0, math.nan)  # a traceback
    with pytest.raises(InvalidParameterError, match="target_position"):
        acc.accompany_metrics(t, pose, pose, (math.inf, 0.6), 0.0, 0.0, 1.0)


def test_a_settle_band_never_met_says_so():
    """settle_band=1e-6 gave settling_time NaN with status ok and no word about it."""
    import math

    r = acc.simulate(acc.walking_task("forward"), settle_band=1e-6)
    assert math.isnan(r.metrics.settling_time)
    assert any("settle_band" in w for w in r.warnings)
    assert not any("settle_band" in w for w in acc.simulate(acc.walking_task("forward")).warnings)
