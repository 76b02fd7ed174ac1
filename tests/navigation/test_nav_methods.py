"""The navigation methods: one module each behind one registry (issue 38).

Every table of method names derives from :data:`designlab.navigation.methods.METHODS`, no
module outside ``designlab/navigation/methods/`` compares a method's name, and a filtered
method is filtered wherever it runs (``method="vff_cbf"`` once ran plain VFF among a crowd).
"""

from __future__ import annotations

import ast
import typing
from pathlib import Path

import numpy as np
import pytest

import designlab
from designlab import navigation as nav
from designlab.errors import InvalidParameterError
from designlab.navigation import engine
from designlab.navigation.methods import (
    CROWD_METHOD,
    METHOD,
    METHODS,
    PLANNER,
    NavigationMethod,
    method_of,
)
from designlab.navigation.methods.base import Filtered
from designlab.navigation.methods.masoud import MASOUD
from designlab.navigation.methods.vo import VO

PACKAGE = Path(designlab.__file__).parent


def _literal_names(node: ast.AST) -> set[str]:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return {node.value}
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return set().union(*(_literal_names(e) for e in node.elts)) if node.elts else set()
    return set()


def test_no_module_outside_the_methods_compares_a_method_name():
    """Engines, kinds and reports ask a method's capabilities; they never test its name."""
    names = set(METHODS.choices())
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if path.is_relative_to(PACKAGE / "navigation" / "methods"):
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Compare):
                if any(_literal_names(n) & names for n in (node.left, *node.comparators)):
                    found.append(f"{path.relative_to(PACKAGE)}:{node.lineno}")
    assert found == []


def test_every_choice_of_a_method_is_the_registry_s():
    from designlab.study.kinds.navigation_crowds import CrowdMethodSpec
    from designlab.study.kinds.navigation_gains import NavigationGainsStudy
    from designlab.study.kinds.navigation_specs import MethodSpec

    assert METHOD.choices == ("vff", "masoud", "ge_cui", "cbf", "vff_cbf")
    assert PLANNER.choices == ("vo", "nlvo", "errt", "field_dstar")
    crowd_baselines = ("orca", "social_force")  # velocity commands among crowds (issue 35)
    assert METHODS.choices() == METHOD.choices + PLANNER.choices + crowd_baselines
    assert CROWD_METHOD.choices == ("vff", "masoud", "ge_cui", "cbf", *crowd_baselines)
    assert typing.get_args(MethodSpec.model_fields["method"].annotation) == (
        METHOD.choices + PLANNER.choices
    )
    assert typing.get_args(CrowdMethodSpec.model_fields["method"].annotation) == (
        CROWD_METHOD.choices
    )
    (baseline,) = typing.get_args(NavigationGainsStudy.model_fields["baselines"].annotation)
    assert typing.get_args(baseline) == ("masoud", "ge_cui") == METHODS.choices(baseline=True)


def test_the_capabilities_of_each_method():
    caps = {
        m.name: (m.force_field, m.batched, m.stabilised, m.filtered, m.crowds, m.gains_required)
        for m in METHODS
    }
    assert caps == {
        "vff": (True, True, True, False, True, True),
        "masoud": (True, True, False, False, True, False),
        "ge_cui": (True, True, False, False, True, False),
        "cbf": (True, False, False, True, True, False),
        "vff_cbf": (True, False, True, True, False, True),
        "vo": (False, False, False, False, False, False),
        "nlvo": (False, False, False, False, False, False),
        "errt": (False, False, False, False, False, False),
        "field_dstar": (False, False, False, False, False, False),
        "orca": (False, False, False, False, True, False),
        "social_force": (False, False, False, False, True, False),
    }
    assert [m.name for m in METHODS.variants(planner=True, seeded=True)] == ["errt"]


def test_vff_cbf_runs_its_filter_every_period_and_crowds_refuse_it():
    """The filtered methods solve one QP per period (recorded); a crowd refuses vff_cbf
    as the study file does, naming what it runs."""
    sc = nav.configuration(1).replace(horizon=0.3)
    row = METHODS.get("vff_cbf").gain_row(nav.EXPERIMENT_GAINS)[None, :]
    raw = engine.run(sc, row, method="vff_cbf", stabilising=True, tie=1, record=True)
    status = raw.record["qp_status"]
    assert len(status) == 5 and all(s.startswith("solved") for s in status)
    plain = engine.run(sc, row, method="vff", stabilising=True, tie=1, record=True)
    assert set(plain.record["qp_status"]) == {""}
    c = nav.crowd("corridor_counterflow", 4, length=10.0, seed=1, horizon=1.0)
    with pytest.raises(
        InvalidParameterError, match=r"\['vff', 'masoud', 'ge_cui', 'cbf', 'orca', 'social_force'\]"
    ):
        nav.simulate(c, nav.EXPERIMENT_GAINS, method="vff_cbf")


def test_a_filtered_method_takes_its_nominal_s_gains_and_force():
    f = Filtered("masoud_cbf", "Masoud + CBF", nominal=MASOUD)
    assert f.filtered and not f.batched and f.sampled_margin and not f.crowds
    assert f.gain_row(None).tolist() == MASOUD.gain_row(None).tolist() == [5.0, 0.0, 24.0, 36.0]
    assert f.tie(nav.MasoudGains(direction=-1), "+y") == -1 and f.fixed_sense
    with pytest.raises(InvalidParameterError, match=r"Filtered\.nominal"):
        Filtered("vo_cbf", "VO + CBF", nominal=VO)


def test_a_planner_takes_settings_not_gains_and_is_no_force_field_method():
    with pytest.raises(InvalidParameterError, match=r"planner.*simulate"):
        method_of("vo")
    with pytest.raises(InvalidParameterError, match="takes settings"):
        METHODS.get("errt").gain_row(None)
    with pytest.raises(InvalidParameterError, match="must be a VOSettings"):
        METHODS.get("nlvo").settings(nav.planners.ERRTSettings())
    assert isinstance(METHODS.get("vff"), NavigationMethod)


def test_the_gains_of_a_row_round_trip_for_every_batched_method():
    row = np.array([2.0, 0.5, 10.0, 12.0])
    for m in METHODS.variants(batched=True):
        g = m.gains_of_row(row, "-y")
        assert isinstance(g, m.gains_type)
        back = m.gain_row(g)
        assert [back[i] for i, k in enumerate(("k1", "b", "k3", "k5")) if k in m.used_gains] == [
            row[i] for i, k in enumerate(("k1", "b", "k3", "k5")) if k in m.used_gains
        ]
    assert METHODS.get("masoud").gains_of_row(row, "-y").direction == -1


def test_the_docs_table_of_the_methods_is_the_registry_s():
    from designlab.navigation.methods import docs_table

    page = (PACKAGE.parent / "docs" / "navigation.md").read_text(encoding="utf-8")
    assert docs_table() in page
