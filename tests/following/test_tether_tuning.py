"""Gain tuning of the tether follower (seeded differential evolution with a damping floor)."""

from __future__ import annotations

import pytest

import designlab as dl
from designlab.analysis.executors import make_executor
from designlab.errors import InvalidParameterError
from designlab.following.tether.linear import damping_ratio
from designlab.results import check_result

fol = dl.following

SMALL = {"popsize": 3, "maxiter": 2}


@pytest.fixture(scope="module")
def tuned():
    return fol.tune(
        fol.FollowTheLeader,
        paths=[fol.figure_eight(a=2.0)],
        speeds=[0.5, 0.8],
        validation_paths=[fol.slalom()],
        seed=7,
        **SMALL,
    )


def test_tuning_result_contract(tuned):
    check_result(tuned)
    assert isinstance(tuned.controller, fol.FollowTheLeader)
    assert tuned.default == fol.FollowTheLeader()
    # the defaults are in the initial population: never worse on the tuning scenarios
    assert tuned.cost <= tuned.default_cost + 1e-12
    assert tuned.training_improvement >= 0.0
    assert set(tuned.scenarios["set"]) == {"tuning", "validation"}
    assert set(tuned.scenarios["path"]) == {"figure_eight_a2", "slalom"}
    assert len(tuned.history) >= 1 and tuned.evaluations >= 9


def test_damping_floor_holds(tuned):
    for v, z in tuned.damping_ratios.items():
        assert z == pytest.approx(damping_ratio(tuned.controller, v))
        assert z >= 0.5


def test_bounds_are_respected(tuned):
    for k, (lo, hi) in fol.FollowTheLeader.BOUNDS.items():
        assert lo <= tuned.controller.gains[k] <= hi
    assert 0.28 <= tuned.controller.lookahead <= 0.56  # the thesis rule b < delta < 2b


def test_seeded_and_executor_independent(tuned):
    with make_executor("serial") as ex:
        again = fol.tune(
            fol.FollowTheLeader,
            paths=[fol.figure_eight(a=2.0)],
            speeds=[0.5, 0.8],
            validation_paths=[fol.slalom()],
            seed=7,
            executor=ex,
            **SMALL,
        )
    assert again.controller == tuned.controller
    assert again.improvement == pytest.approx(tuned.improvement)


def test_high_floor_forces_long_lookahead():
    """zeta = sqrt(K delta / v)/2 >= 1.2 at v = 0.5 m/s needs K delta >= 2.88 m/s."""
    res = fol.tune(
        fol.FollowTheLeader,
        paths=[fol.slalom()],
        speeds=[0.5],
        validation_paths=[],
        damping_floor=1.2,
        bounds={"turn_gain": (0.5, 4.0), "lookahead": (0.3, 1.0)},
        seed=1,
        **SMALL,
    )
    c = res.controller
    assert c.turn_gain * c.lookahead >= 4 * 1.2**2 * 0.5 - 1e-9
    assert any("validation" in w for w in res.warnings)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"speeds": [-0.5]}, "speeds"),
        ({"paths": []}, "paths"),
        ({"bounds": {"lookahead": (0.5, 0.1)}}, "bounds.lookahead"),
        ({"bounds": {"angle_gain": (0.0, 1.0)}}, "bounds.angle_gain"),
        ({"weights": {"jerk": 1.0}}, "weights.jerk"),
        ({"weights": {"length": -1.0}}, "length"),
        ({"tether_range": (1.0, 0.5)}, "tether_range"),
        ({"damping_floor": float("nan")}, "damping_floor"),
    ],
)
def test_bad_tuning_input(kwargs, name):
    args = {"paths": [fol.slalom()], "speeds": [0.5], **kwargs}
    with pytest.raises(InvalidParameterError, match=name):
        fol.tune(fol.FollowTheLeader, **args)
