"""Honest tuning: validation paths share no stretch with the tuning paths; penalties count."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.following.tether.overlap import overlapping_paths, shared_stretch
from designlab.following.tether.paths import LeaderPath, from_array, smooth_walk
from designlab.following.tether.tuning import (
    VALIDATION_WALK_SEEDS,
    default_validation,
    scenario_costs,
)
from designlab.study import parse_study

fol = dl.following
ROOT = Path(__file__).resolve().parents[2]


def _moved(path: LeaderPath, angle: float, scale: float, shift, mirror: bool = False):
    xy = path.points * ([1.0, -1.0] if mirror else [1.0, 1.0])
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    return from_array(scale * xy @ rot.T + shift, name="moved")


def test_the_issue_s_overlaps_are_caught():
    """The out-and-back slalom starts with the one-way slalom; the a = 2 m figure-eight is
    the a = 4 m one scaled by one half (issue 20)."""
    st = shared_stretch(fol.slalom(out_and_back=True), fol.slalom())
    assert st.shared and st.in_place == pytest.approx(fol.slalom().length, abs=0.05)
    st = shared_stretch(fol.figure_eight(a=2.0), fol.figure_eight(a=4.0))
    assert st.shared and st.normalised > 0.99
    pairs = overlapping_paths(
        [fol.figure_eight(a=2.0), fol.slalom(out_and_back=True), fol.square_s()],
        [fol.figure_eight(a=4.0), fol.slalom()],
    )
    assert {(v, t) for v, t, _ in pairs} == {
        ("figure_eight_a2", "figure_eight_a4"),
        ("slalom_out_and_back", "slalom"),
    }


@pytest.mark.parametrize(
    ("angle", "scale", "mirror"), [(0.7, 1.0, False), (-2.0, 0.37, False), (1.1, 2.5, True)]
)
def test_moved_scaled_and_mirrored_copies_overlap(angle, scale, mirror):
    walk = smooth_walk(seed=5)
    assert shared_stretch(_moved(walk, angle, scale, (3.0, -2.0), mirror), walk).shared


def _planted(scale: float, angle: float, mirror: bool) -> tuple[LeaderPath, float]:
    """A path whose middle is the 4 m stretch of the a = 4 m figure-eight that turns most,
    moved, rotated, scaled and mirrored, between two 4 m straights."""
    f8 = fol.figure_eight(a=4.0)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(f8.points, axis=0).T))])
    piece = f8.points[(s >= 8.5) & (s <= 12.5)]
    piece = _moved(from_array(piece - piece[0]), angle, scale, (0.0, 0.0), mirror).points
    d, e = piece[1] - piece[0], piece[-1] - piece[-2]
    d, e = d / np.linalg.norm(d), e / np.linalg.norm(e)
    run = np.linspace(0.01, 4.0, 200)[:, None]
    xy = np.vstack([piece[0] - d * run[::-1], piece, piece[-1] + e * run])
    return from_array(xy + np.array([5.0, -3.0]), name="planted"), float(
        np.hypot(*np.diff(piece, axis=0).T).sum()
    )


@pytest.mark.parametrize(
    ("scale", "angle", "mirror"), [(1.0, 0.0, False), (1.3, 0.9, True), (0.8, -2.2, False)]
)
def test_a_copy_planted_mid_path_is_found(scale, angle, mirror):
    """Issue 37: a 4 m exact copy of the figure-eight placed mid-path (moved, rotated, scaled,
    mirrored) was missed by the start-anchored measures; the sliding windows find it."""
    path, length = _planted(scale, angle, mirror)
    st = shared_stretch(path, fol.figure_eight(a=4.0))
    assert st.shared
    assert st.sliding == pytest.approx(length, abs=0.25)  # the whole copy, window by window
    assert st.in_place < 0.5 and st.normalised < 0.2  # what the old measures saw
    assert overlapping_paths([path], [fol.figure_eight(a=4.0), fol.slalom()])[0][1] == (
        "figure_eight_a4"
    )
    assert not shared_stretch(path, fol.slalom()).shared


def test_a_crossing_is_not_a_shared_stretch():
    a = from_array([[0.0, 0.0], [4.0, 0.0]])
    b = from_array([[2.0, -2.0], [2.2, 2.0]])  # crosses at about 87 degrees
    assert not shared_stretch(a, b).shared
    c = from_array([[1.0, 0.01], [3.0, 0.01]])  # runs along it, 1 cm off, for 2 m
    assert shared_stretch(c, a).in_place == pytest.approx(2.0, abs=0.02)
    # two paths that both start straight are not copies of each other once normalised
    bent = from_array([[0.0, 0.0], [3.0, 0.0], [3.0, 2.0]])
    assert shared_stretch(bent, from_array([[0.0, 0.0], [8.0, 0.0], [8.0, -1.0]])).normalised == 0
    assert shared_stretch(bent, _moved(bent, 0.3, 1.7, (1.0, 1.0))).normalised > 0.99


def test_the_committed_tuning_study_validates_on_paths_it_did_not_see():
    """A geometric check of studies/tether_tuning.yaml: no validation path shares a stretch
    with a tuning path (in place, or moved, scaled or mirrored as a whole)."""
    study = parse_study((ROOT / "studies" / "tether_tuning.yaml").read_text())
    tuning = [p.build() for p in study.paths]
    validation = [p.build() for p in study.validation_paths]
    assert overlapping_paths(validation, tuning) == []
    # random walks: the validation seeds are not tuning seeds
    seeds = {p.seed for p in study.validation_paths if getattr(p, "type", "") == "smooth_walk"}
    tseeds = {p.seed for p in study.paths if getattr(p, "type", "") == "smooth_walk"}
    assert seeds and not seeds & tseeds
    names = {p.name for p in validation}
    assert {"square_s", "corridor_corner", "circle_r1.5"} <= names


def test_default_validation_leaves_out_what_the_tuning_saw():
    tuning = [fol.figure_eight(a=4.0), fol.slalom(), smooth_walk(seed=VALIDATION_WALK_SEEDS[0])]
    val = default_validation(tuning)
    assert overlapping_paths(val, tuning) == []
    assert f"smooth_walk_s{VALIDATION_WALK_SEEDS[0]}" not in {p.name for p in val}
    assert f"smooth_walk_s{VALIDATION_WALK_SEEDS[1]}" in {p.name for p in val}
    # the square S itself is left out, and so is the corridor corner, whose first leg runs
    # along the square S's first side
    assert [p.name for p in default_validation([fol.square_s()])] == [
        "circle_r1.5",
        "smooth_walk_s101",
        "smooth_walk_s102",
    ]


def test_smooth_walk_is_seeded_smooth_and_bounded():
    a, b = smooth_walk(seed=9), smooth_walk(seed=9)
    assert np.array_equal(a.points, b.points) and a.length == pytest.approx(12.0, abs=1e-6)
    assert not np.array_equal(a.points, smooth_walk(seed=10).points)
    heading = np.unwrap(np.arctan2(*np.diff(a.points, axis=0).T[::-1]))
    kappa = np.diff(heading) / 0.01
    assert np.max(np.abs(kappa)) <= 1.0 + 1e-6  # |curvature| <= max_curvature
    assert np.max(np.abs(np.diff(kappa))) < 0.05  # continuous (smoothed over 0.5 m)
    with pytest.raises(InvalidParameterError, match=r"smooth_walk\.seed"):
        smooth_walk(seed=-1)


def _task(robot, gains, max_saturation):
    ctrl = fol.FollowTheLeader()
    return {
        "law": "FollowTheLeader",
        "base": ctrl.as_dict(),
        "gains": gains,
        "path": fol.circle(radius=1.0).points,
        "path_name": "circle",
        "speed": 0.8,
        "robot": robot.as_dict(),
        "weights": {"deviation": 1.0, "length": 0.5, "smoothness": 0.05},
        "tether_range": (0.0001, 100.0),
        "max_saturation": max_saturation,
    }


def test_wheel_saturation_is_a_constraint_with_a_stated_bound():
    robot = fol.OXYDOG.replace(max_wheel_speed=5.0)  # 0.625 m/s: a 0.8 m/s leader saturates
    gains = [{"speed_gain": 8.0, "turn_gain": 6.0, "lookahead": 0.4}]
    loose = scenario_costs(_task(robot, gains, 1.0))
    tight = scenario_costs(_task(robot, gains, 0.05))
    sat = float(loose["saturation"][0])
    assert 0.05 < sat <= 1.0
    assert loose["penalty"][0] == pytest.approx(0.0)
    assert tight["penalty"][0] == pytest.approx(10.0 * (sat - 0.05))
    assert tight["cost"][0] - loose["cost"][0] == pytest.approx(10.0 * (sat - 0.05))


@pytest.fixture(scope="module")
def tuned():
    return fol.tune(
        fol.FollowTheLeader,
        paths=[fol.figure_eight(a=4.0)],
        speeds=[0.8],
        validation_paths=[fol.slalom(), fol.figure_eight(a=2.0)],
        seed=3,
        popsize=3,
        maxiter=2,
    )


def test_headline_includes_the_penalties_and_the_unpenalised_figure_is_beside_it(tuned):
    tab = tuned.scenarios
    val = tab[tab["set"] == "validation"]
    mean = val.groupby("controller")[["cost", "cost_unpenalised", "wheel_saturation"]].mean()
    assert tuned.improvement == pytest.approx(
        1 - mean.loc["tuned", "cost"] / mean.loc["default", "cost"]
    )
    assert tuned.improvement_unpenalised == pytest.approx(
        1 - mean.loc["tuned", "cost_unpenalised"] / mean.loc["default", "cost_unpenalised"]
    )
    assert np.allclose(val["cost"] - val["cost_unpenalised"], val["penalty"])
    assert tuned.saturation["validation"]["tuned"] == pytest.approx(
        val[val["controller"] == "tuned"]["wheel_saturation"].max()
    )
    assert tuned.max_saturation == 0.05


def test_an_overlapping_validation_path_is_reported(tuned):
    assert any("figure_eight_a2 shares a stretch" in w for w in tuned.warnings)


def test_the_wheel_limit_is_a_hard_constraint_of_the_search(monkeypatch):
    """FTL on the slalom at 0.8 m/s with the OxyDog wheels: the defaults hold a wheel at its
    limit for 15 % of the run. With the soft penalty alone the search settles beyond the 5 %
    bound (issue 37: 10.6 % in the committed tuning); with the hard constraint every set
    beyond it ranks below every set within it, and the tuned gains keep it."""
    import designlab.following.tether.tuning as tuning

    def run():
        return tuning.tune(
            fol.FollowTheLeader,
            paths=[fol.slalom()],
            speeds=[0.8],
            robot=fol.OXYDOG,
            validation_paths=[],
            popsize=4,
            maxiter=3,
            seed=3,
        )

    res = run()
    assert res.saturation["tuning"]["default"] > 0.05
    assert res.saturation["tuning"]["tuned"] <= 0.05
    assert (res.evaluated["cost"] >= tuning.WHEEL_LIMIT_INFEASIBLE).any()
    assert str(res.status) != "infeasible"
    # the same search with the soft penalty only ends beyond the bound, and says so
    monkeypatch.setattr(tuning, "wheel_limit_barrier", lambda parts, bound: 0.0)
    soft = run()
    assert soft.saturation["tuning"]["tuned"] > 0.05
    assert str(soft.status) == "infeasible"
    assert any("keeps a wheel at its limit" in w for w in soft.warnings)
