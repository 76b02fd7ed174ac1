"""Animations: a GIF with the frames asked for, from crowd runs and thesis runs alike."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import designlab as dl
from designlab.errors import DesignlabError
from designlab.navigation.crowds.animation import animate, run_tracks


def _tracks(n: int = 30) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    t = np.linspace(0.0, 3.0, n)
    robot = np.stack([t, np.zeros(n)], axis=1)
    peds = np.full((n, 2, 2), np.nan)
    peds[:, 0] = np.stack([3.0 - t, np.full(n, 0.8)], axis=1)
    peds[: n // 2, 1] = [1.0, -1.0]  # leaves half-way
    return t, robot, peds


def test_gif_has_the_subsampled_frames(tmp_path: Path) -> None:
    t, robot, peds = _tracks()
    wall = [[-1, -2], [4, -2], [4, -1.8], [-1, -1.8]]
    out = animate(t, robot, peds, tmp_path / "sub" / "run.gif", goal=(3.0, 0.0), walls=[wall],
                  max_frames=7, title="demo")  # fmt: skip
    with Image.open(out) as im:
        assert im.format == "GIF"
        assert im.n_frames == 7


def test_every_sample_when_the_run_is_short(tmp_path: Path) -> None:
    t, robot, peds = _tracks(4)
    with Image.open(animate(t, robot, peds, tmp_path / "a.gif", max_frames=50)) as im:
        assert im.n_frames == 4


def test_thesis_run_tracks() -> None:
    nav = dl.navigation
    res = nav.simulate(nav.configuration(2), nav.OPTIMAL_GAINS)
    _t, robot, people = run_tracks(res)
    assert np.array_equal(robot, res.position)
    assert np.array_equal(people[:, 0], res.obstacle_positions[0])


@pytest.mark.parametrize(
    ("change", "value"),
    [
        ("times", [0.0, math.nan]),
        ("robot", np.ones((2, 3))),
        ("others", np.ones((2, 2))),
        ("max_frames", 1),
        ("max_frames", 10**6),
        ("fps", 0),
        ("robot_radius", -0.1),
    ],
)
def test_bad_input(tmp_path: Path, change: str, value: object) -> None:
    args = {"times": [0.0, 1.0], "robot": np.zeros((2, 2)), "others": np.ones((2, 1, 2)),
            "path": tmp_path / "x.gif"}  # fmt: skip
    args[change] = value
    with pytest.raises(DesignlabError):
        animate(**args)  # type: ignore[arg-type]
    with pytest.raises(DesignlabError):
        run_tracks(object())
