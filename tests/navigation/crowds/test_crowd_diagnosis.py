"""The force breakdown of a crowd run (designlab.navigation.crowds.diagnosis)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import designlab as dl
from designlab.navigation.crowds.diagnosis import force_breakdown, stall_summary

nav = dl.navigation
GAINS = nav.VFFGains(4.3, 0.68, 20.3, 240.7)


def _run(paths, **kw):
    c = nav.crowd("open_plaza", len(paths), width=10.0, length=12.0, start=(2.0, 5.0),
                  goal=(10.0, 5.0), paths=paths, horizon=3.0, **kw)  # fmt: skip
    return nav.simulate(c, GAINS)


def test_attraction_alone_far_from_everything():
    res = _run((((11.5, 9.5), (11.5, 9.5)),))  # stands far beyond every active region
    f = force_breakdown(res)
    per = round(res.crowd.sample_time / res.crowd.pedestrian_step)
    p, v = res.robot_positions[::per], res.robot_velocities[::per]
    E = np.asarray(res.crowd.robot_goal) - p
    u = E / np.hypot(E[:, 0], E[:, 1])[:, None]
    expected = np.einsum("ij,ij->i", 4.3 * E - 0.68 * 4.3 * v, u)  # K1 E + K2 E', E' = -v
    assert f["attraction_n"].to_numpy() == pytest.approx(expected, rel=1e-9, abs=1e-9)
    assert (f[["walls_n", "pedestrians_n", "stabilising_n"]].to_numpy() == 0).all()
    assert f["progress_mps"].to_numpy() == pytest.approx(np.einsum("ij,ij->i", v, u))


def test_an_oncoming_pedestrian_pushes_back():
    res = _run((((7.0, 5.0), (1.0, 5.0)),))  # walks head-on at the robot
    f = force_breakdown(res)
    active = f[f["active_pedestrians"] > 0]
    assert len(active) and (active["pedestrians_n"] < 0).any()
    assert (f.loc[f["active_pedestrians"] == 0, "pedestrians_n"] == 0).all()


def test_stall_summary_counts():
    frame = pd.DataFrame({
        "speed_mps": [0.0, 0.1, 0.7, 0.7], "progress_mps": [0.0, -0.1, 0.7, 0.1],
        "critical": [True, False, False, False], "attraction_n": [1.0] * 4,
        "walls_n": [0.0, -1.0, 0.0, 0.0], "pedestrians_n": [0.0, -2.0, 0.0, 0.5],
        "stabilising_n": [0.0, -0.5, 0.0, 0.0],
    })  # fmt: skip
    s = stall_summary(frame, max_speed=0.7)
    assert s["stopped"] == 0.25 and s["slow"] == 0.75 and s["receding"] == 0.25
    assert s["slow_by_critical"] == pytest.approx(1 / 3)
    assert s["slow_by_pedestrians"] == pytest.approx(1 / 3)
    assert s["slow_by_none"] == pytest.approx(1 / 3)
    assert s["slow_by_walls"] == 0.0 and s["slow_by_stabilising"] == 0.0
