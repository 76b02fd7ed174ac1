"""Walking tasks of Wu et al. 2021, Sec. 3 (synthetic and from CSV)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

import designlab as dl
from designlab.errors import InvalidParameterError

fol = dl.following


def test_nine_tasks():
    assert fol.TASK_NAMES == (
        "forward",
        "backward",
        "left_lateral",
        "right_lateral",
        "left_pivot",
        "right_pivot",
        "rectangle",
        "circle_cw",
        "circle_ccw",
    )


@pytest.mark.parametrize(
    ("name", "dx", "dy"),
    [
        ("forward", 0.0, 1.95),
        ("backward", 0.0, -1.98),
        ("left_lateral", -1.52, 0.0),
        ("right_lateral", 1.56, 0.0),
    ],
)
def test_straight_tasks_displacement(name, dx, dy):
    """The paper's walked distances (Sec. 4.1), user facing +Y without turning."""
    t = fol.walking_task(name)
    assert t.x[-1] - t.x[0] == pytest.approx(dx, abs=2e-3)
    assert t.y[-1] - t.y[0] == pytest.approx(dy, abs=2e-3)
    assert np.ptp(t.heading) == pytest.approx(0.0, abs=1e-12)
    # stands still 10 s after the stop
    late = t.time >= t.walk_stop
    assert np.ptp(t.y[late]) < 1e-9 and t.duration == pytest.approx(t.walk_stop + 10.0, abs=2e-3)


@pytest.mark.parametrize(("name", "sign"), [("left_pivot", 1.0), ("right_pivot", -1.0)])
def test_pivots(name, sign):
    t = fol.walking_task(name, pivot_offset=0.25)
    assert t.heading[-1] - t.heading[0] == pytest.approx(sign * math.pi / 2, abs=1e-3)
    # origin 0.25 m ahead of the turning centre: displacement 0.25 (-/+ sin 90, cos 90 - 1)
    assert t.x[-1] == pytest.approx(-sign * 0.25, abs=1e-3)
    assert t.y[-1] == pytest.approx(-0.25, abs=1e-3)
    # Table 1 left pivot user displacement (-266, -222) mm for a 73.7 deg turn
    t2 = fol.walking_task("left_pivot", turn_angle=math.radians(73.7), pivot_offset=0.28)
    assert (t2.x[-1], t2.y[-1]) == pytest.approx((-0.266, -0.202), abs=0.025)


@pytest.mark.parametrize(("name", "sign"), [("circle_cw", -1.0), ("circle_ccw", 1.0)])
def test_circles_close_with_the_radius(name, sign):
    r = 0.9
    t = fol.walking_task(name, radius=r)
    assert (t.x[-1], t.y[-1]) == pytest.approx((0.0, 0.0), abs=5e-3)
    assert t.heading[-1] - t.heading[0] == pytest.approx(sign * 2 * math.pi, abs=5e-3)
    centre = np.array([-sign * r, 0.0])
    radius = np.hypot(t.x - centre[0], t.y - centre[1])
    assert radius == pytest.approx(r, abs=5e-3)


def test_rectangle_returns_facing_forward():
    t = fol.walking_task("rectangle", rectangle=(2.5, 1.8))
    assert (t.x[-1], t.y[-1]) == pytest.approx((0.0, 0.0), abs=2e-3)
    assert t.x.max() == pytest.approx(1.8, abs=2e-3)
    assert t.y.max() == pytest.approx(2.5, abs=2e-3)
    assert np.ptp(t.heading) == 0.0
    assert t.distance == pytest.approx(8.6, abs=1e-2)


def test_sway_only_while_walking():
    t = fol.walking_task("forward", sway=(0.02, math.radians(3.0)))
    walking = (t.time > t.walk_start + 0.7) & (t.time < t.walk_stop - 0.7)
    assert np.ptp(t.x[walking]) == pytest.approx(0.04, abs=0.005)
    assert np.ptp(t.heading[walking]) == pytest.approx(math.radians(6.0), abs=math.radians(0.5))
    assert np.ptp(t.x[t.time < t.walk_start]) == 0.0


def test_default_targets_are_the_papers():
    t = fol.walking_task("left_lateral")
    assert t.target_position == (0.292, 0.550)  # Table 2
    assert math.degrees(t.target_heading) == pytest.approx(95.7 - 97.4)  # Table 1 robot - user
    assert fol.walking_task("rectangle").target_position == (-0.121, 0.384)


def test_csv_walk(tmp_path):
    t = np.arange(0.0, 8.0, 0.01)
    y = np.clip(0.5 * (t - 1.0), 0.0, 2.0)
    frame = pd.DataFrame({"time_s": t + 5.0, "x_m": 0.0, "y_m": y, "heading_rad": math.pi / 2})
    path = tmp_path / "walk.csv"
    frame.to_csv(path, index=False)
    task = fol.walking_task_from_csv(path, target_position=(0.0, 0.45))
    assert task.name == "walk" and task.time[0] == 0.0
    assert task.walk_start == pytest.approx(1.0, abs=0.02)
    assert task.walk_stop == pytest.approx(5.0, abs=0.02)
    res = fol.accompany(task)
    assert res.ok and res.settled_error < 0.02


def test_csv_bad_points(tmp_path):
    frame = pd.DataFrame(
        {"time_s": [0.0, 0.1, 0.2], "x_m": [0.0, np.nan, 0.0], "y_m": 0.0, "heading_deg": 90.0}
    )
    path = tmp_path / "bad.csv"
    frame.to_csv(path, index=False)
    with pytest.raises(InvalidParameterError, match=r"line 3 .*column .x_m."):
        fol.walking_task_from_csv(path, target_position=(0.0, 0.45))
    frame.drop(columns="heading_deg").to_csv(path, index=False)
    with pytest.raises(InvalidParameterError, match="heading"):
        fol.walking_task_from_csv(path, target_position=(0.0, 0.45))


def test_bad_tasks():
    with pytest.raises(InvalidParameterError, match="inside the user") as exc:
        fol.walking_task("forward", target_position=(0.05, 0.1))
    assert exc.value.name.endswith("target_position")
    with pytest.raises(InvalidParameterError) as exc:
        fol.walking_task("forward", speed=-0.5)
    assert exc.value.name == "speed"
    with pytest.raises(InvalidParameterError) as exc:
        fol.walking_task("circle_cw", radius=float("inf"))
    assert exc.value.name == "radius"
    with pytest.raises(InvalidParameterError):
        fol.walking_task("moonwalk")
    t = np.linspace(0, 1, 5)
    x = np.zeros(5)
    x[2] = np.inf
    with pytest.raises(InvalidParameterError, match=r"x\[2\]"):
        fol.WalkingTask("bad", t, x, np.zeros(5), np.zeros(5), 0.0, 1.0, (0.0, 0.5))
    with pytest.raises(InvalidParameterError, match="increasing"):
        fol.WalkingTask("bad", t[::-1], np.zeros(5), np.zeros(5), np.zeros(5), 0.0, 1.0, (0, 0.5))
    with pytest.raises(InvalidParameterError, match="target_position"):
        fol.WalkingTask("bad", t, np.zeros(5), np.zeros(5), np.zeros(5), 0.0, 1.0, (np.nan, 0.5))
