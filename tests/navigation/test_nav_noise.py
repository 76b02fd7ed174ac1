"""The seeded sensor-noise model (designlab.navigation.noise)."""

from __future__ import annotations

import numpy as np
import pytest

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.navigation import engine
from designlab.navigation.account import noise_ordering

nav = dl.navigation
EXP = nav.EXPERIMENT_GAINS


def test_noise_is_seeded_and_zero_noise_is_the_exact_run() -> None:
    sc = nav.configuration(4)
    quiet = nav.simulate(sc, EXP, stabilising="off")
    zero = nav.simulate(sc, EXP, stabilising="off", noise=nav.SensorNoise(0.0, 0.0, seed=5))
    assert np.array_equal(zero.position, quiet.position)
    a = nav.simulate(sc, EXP, stabilising="off", noise=nav.SensorNoise(seed=1))
    b = nav.simulate(sc, EXP, stabilising="off", noise=nav.SensorNoise(seed=1))
    c = nav.simulate(sc, EXP, stabilising="off", noise=nav.SensorNoise(seed=2))
    assert np.array_equal(a.position, b.position)
    assert not np.array_equal(a.position, c.position)
    # the robot is scored on the true state: distances are the true ones
    d_true = min(np.hypot(*(a.position - a.obstacle_positions[2]).T))
    assert a.min_distance["human"] == pytest.approx(d_true, abs=1e-9)


def test_measurement_shifts_everything_by_the_robot_error() -> None:
    noise = nav.SensorNoise(position_sd=0.01, velocity_sd=0.0, seed=0)
    obs = np.arange(12.0)
    moved, goal = noise.measure(
        noise.generator(), obs, np.array([0.0, 0.6]), np.array([1, 0], bool)
    )
    rng = noise.generator()
    e_r = rng.normal(0, 0.01, 2)
    e_o = rng.normal(0, 0.01, (2, 2))
    assert np.allclose(goal, [0.0, 0.6] - e_r)
    assert np.allclose(moved.reshape(2, 6)[:, :2], obs.reshape(2, 6)[:, :2] + e_o - e_r)
    assert np.array_equal(moved.reshape(2, 6)[:, 2:], obs.reshape(2, 6)[:, 2:])


@pytest.mark.parametrize(
    "kw",
    [
        {"position_sd": -0.1},
        {"position_sd": float("nan")},
        {"velocity_sd": 1e9},
        {"seed": -1},
        {"seed": 1.5},
    ],
)
def test_noise_parameters_are_checked(kw: dict) -> None:
    with pytest.raises(InvalidParameterError):
        nav.SensorNoise(**kw)


def test_noise_is_refused_where_it_cannot_apply() -> None:
    sc = nav.configuration(1)
    with pytest.raises(InvalidParameterError, match="noise"):
        engine.run(sc, np.tile(EXP.as_array(), (2, 1)), noise=nav.SensorNoise())
    with pytest.raises(InvalidParameterError, match="noise"):
        nav.simulate(sc, EXP, noise=0.01)  # type: ignore[arg-type]


def test_noise_ordering_reports_both_gain_sets() -> None:
    f = noise_ordering((4,), seeds=2)
    assert list(f["gains"]) == ["New VFF", "New VFF*"]
    assert list(f["thesis_H"]) == [0.55, 0.53]
    assert (f["H_noise_sd"] >= 0).all() and (f["collisions"] <= 2).all()
