"""The tether tuners are strategy objects in a registry (no method chains)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from designlab.errors import InvalidParameterError
from designlab.following.accompanying import tuning as acc_tuning
from designlab.following.tether import FollowTheLeader, figure_eight, slalom, tune
from designlab.following.tether.tuning import TUNERS

ROOT = Path(__file__).resolve().parents[2]


def test_registry_holds_strategy_objects_named_as_registered():
    assert set(TUNERS) == {"differential_evolution", "nelder_mead"}
    for name, cls in TUNERS.items():
        assert cls.name == name
        tuner = cls()
        assert callable(tuner.search) and tuner.steps(3, 4, 2) >= 3
    # the accompanying tuners build themselves from the options, one code path for all
    for name, cls in acc_tuning.TUNERS.items():
        assert cls.name == name and cls.from_options(150).name == name


@pytest.mark.parametrize("method", sorted(TUNERS))
def test_each_tuner_never_ends_worse_than_the_defaults_it_starts_from(method):
    seen = []
    res = tune(
        FollowTheLeader,
        paths=[figure_eight(a=2.0)],
        speeds=[0.5],
        validation_paths=[slalom()],
        popsize=4,
        maxiter=1,
        seed=1,
        method=method,
        progress=seen.append,
    )
    assert res.cost <= res.default_cost + 1e-12
    assert seen and seen[-1].label == TUNERS[method].step_label
    # the same simulation budget: popsize x gains x (maxiter + 1) evaluations at most
    assert res.evaluations <= 4 * 3 * 2


@pytest.mark.parametrize("method", ["simplex", "", None, 3, "Differential_Evolution"])
def test_unknown_method_is_refused_naming_the_parameter(method):
    with pytest.raises(InvalidParameterError) as exc:
        tune(FollowTheLeader, paths=[figure_eight(a=2.0)], method=method)
    assert "method" in str(exc.value)


def test_no_method_name_chains_in_the_following_package():
    chain = re.compile(r"\bif\s+\w*method\w*\s*==")
    for path in (ROOT / "designlab" / "following").rglob("*.py"):
        assert not chain.search(path.read_text()), path


def test_the_tuning_study_takes_a_registered_method_only():
    from designlab.errors import DesignlabError
    from designlab.study import parse_study

    body = (
        "designlab: 1\nkind: tether_tuning\nname: t\nlaws: [FollowTheLeader]\n"
        "paths: [{type: figure_eight, a: 2.0}]\nvalidation_paths: [{type: slalom}]\n"
    )
    assert parse_study(body).method == "differential_evolution"
    assert parse_study(body + "method: nelder_mead\n").method == "nelder_mead"
    with pytest.raises(DesignlabError, match="method"):
        parse_study(body + "method: simplex\n")
