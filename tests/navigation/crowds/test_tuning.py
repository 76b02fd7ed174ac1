"""Gains for crowds: disjoint validation, the robust cost and rates, the optimise_gains entry."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import designlab as dl
from designlab.errors import DesignlabError
from designlab.navigation.crowds.metrics import cvar
from designlab.navigation.crowds.tuning import (
    CrowdSet,
    check_disjoint,
    optimise_crowd_gains,
    validate_gains,
)
from designlab.navigation.crowds.tuning import score_runs as score
from designlab.navigation.tuning import DEFAULT_BOUNDS

SHORT = {"length": 8.0, "horizon": 1.0}


@pytest.mark.parametrize(
    ("seeds", "densities"), [((1, 5), (0.4,)), ((7,), (0.2, 0.4)), ((0,), (0.2,))]
)
def test_validation_sharing_a_seed_or_density_is_refused(seeds: tuple, densities: tuple) -> None:
    train = CrowdSet(("crossing",), (0.2,), (0, 1))
    with pytest.raises(DesignlabError, match="share nothing"):
        check_disjoint(train, CrowdSet(("crossing",), densities, seeds))
    with pytest.raises(DesignlabError):
        validate_gains(
            {"x": dl.navigation.OPTIMAL_GAINS}, CrowdSet(("crossing",), densities, seeds), train
        )


def test_disjoint_sets_pass() -> None:
    check_disjoint(
        CrowdSet(("crossing",), (0.2,), range(3)), CrowdSet(("bottleneck",), (0.5,), range(3, 6))
    )


def _runs(arrival: list[float], collided: list[int], critical: list[int]) -> pd.DataFrame:
    a = np.asarray(arrival)
    ok = np.isfinite(a) & (np.asarray(collided) == 0)
    return pd.DataFrame(
        {"arrival_time_s": a, "success": ok, "collided": collided, "critical": critical}
    )


def test_score_mean_cvar_and_rates() -> None:
    train = CrowdSet(("crossing",), (0.2,), (0, 1, 2, 3), critical_rate=0.25)
    runs = _runs([10.0, 12.0, np.inf, 20.0], [0, 0, 0, 0], [0, 1, 0, 0])
    costs = [10.0, 12.0, 60.0, 20.0]  # a run that did not arrive costs twice the 30 s horizon
    mean = score(runs, train, 30.0, "mean", 0.8)
    assert mean["cost_s"] == pytest.approx(np.mean(costs)) and mean["feasible"]
    assert mean["fitness"] == mean["cost_s"]
    assert (
        score(runs, train, 30.0, "cvar", 0.5)["cost_s"] == pytest.approx(cvar(costs, 0.5)) == 40.0
    )
    bad = score(
        _runs([10.0, 12.0, 9.0, 20.0], [0, 1, 0, 0], [1, 1, 0, 0]), train, 30.0, "mean", 0.8
    )
    assert not bad["feasible"]
    # infeasible ranks below anything feasible (cost <= 2 horizons), by its violation 0.25 + 0.25
    assert bad["fitness"] == pytest.approx(4 * 30.0 * 1.5)


def test_bad_sets_and_options() -> None:
    with pytest.raises(DesignlabError):
        CrowdSet(("crossing",), (0.2,), (0,), critical_rate=1.5)
    with pytest.raises(DesignlabError):
        CrowdSet("crossing", (0.2,), (0,))
    train = CrowdSet(("corridor_counterflow",), (0.1,), (0,), SHORT)
    for bad in ({"robust": "worst"}, {"alpha": 1.0}, {"popsize": 2}, {"generations": 0},
                {"bounds": {**DEFAULT_BOUNDS, "k1": (5.0, 1.0)}}):  # fmt: skip
        with pytest.raises(DesignlabError):
            optimise_crowd_gains(train, **{"bounds": DEFAULT_BOUNDS, **bad})
    with pytest.raises(DesignlabError, match="CrowdSet takes only"):
        dl.navigation.optimise_gains(train, refine=False)


def test_optimise_gains_over_a_crowd_set() -> None:
    """One generation of four candidates on one short crowd: a result with its history."""
    train = CrowdSet(
        ("corridor_counterflow",), (0.1,), (0,), SHORT, critical_rate=1.0, collision_rate=1.0
    )
    opt = dl.navigation.optimise_gains(train, robust="cvar", popsize=4, generations=1, seed=3)
    assert opt.evaluations == 4 and len(opt.to_frame()) == 4
    assert opt.status == "ok" and opt.robust == "cvar"
    lo = {k: v[0] for k, v in DEFAULT_BOUNDS.items()}
    hi = {k: v[1] for k, v in DEFAULT_BOUNDS.items()}
    assert all(lo[k] <= getattr(opt.gains, k) <= hi[k] for k in lo)
    # every horizon-1 s run times out: the cost is twice the horizon
    assert opt.cost == pytest.approx(2.0)
