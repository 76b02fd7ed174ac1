"""The tether law registry: one module per law, one table, engines that ask the law (issue 38)."""

from __future__ import annotations

import importlib
import inspect
import math
import pkgutil
from dataclasses import dataclass
from functools import cache
from typing import ClassVar

import casadi as ca
import numpy as np
import pytest
from pydantic import TypeAdapter, ValidationError

from designlab.errors import InvalidParameterError
from designlab.following import tether
from designlab.following.tether import LAWS, FollowTheLeader, controller_from_dict
from designlab.following.tether.buffer import LOOKAHEAD, TargetFinder
from designlab.following.tether.laws import base
from designlab.params import declared, params_of
from designlab.study.kinds.tether_comparison import TetherComparisonStudy
from designlab.study.kinds.tether_modes import TetherModesStudy
from designlab.study.kinds.tether_specs import ControllerSpec


def _law_modules() -> list[str]:
    skip = {"base", "registry"}
    return [m.name for m in pkgutil.iter_modules(tether.laws.__path__) if m.name not in skip]


def test_one_registered_law_per_module():
    """Each law module defines exactly one law, and the registry holds exactly those."""
    defined = []
    for name in _law_modules():
        module = importlib.import_module(f"designlab.following.tether.laws.{name}")
        own = [
            c
            for _, c in inspect.getmembers(module, inspect.isclass)
            if issubclass(c, base.TetherController) and c.__module__ == module.__name__
        ]
        assert len(own) == 1, (name, own)
        defined.append(own[0])
    assert sorted(c.name for c in defined) == sorted(LAWS.choices())
    assert all(LAWS.get(c.name) is c for c in defined)


def test_the_length_held_has_one_bound():
    """Every law's tether length (l_d, or the side offset l_H) is bounded as DESIRED_LENGTH."""
    for law in LAWS.variants():
        decl = params_of(law).get(law.LENGTH_FIELD)
        if decl is None:  # Brake mode: the wrapped law's
            continue
        assert (decl.gt, decl.le, decl.unit) == (
            base.DESIRED_LENGTH.gt,
            base.DESIRED_LENGTH.le,
            base.DESIRED_LENGTH.unit,
        ), law.name


def test_the_comparison_compares_every_law_that_follows_from_behind():
    """The comparison's default law list and the laws its file accepts are the registry's."""
    behind = LAWS.variants(placement="behind")
    study = TetherComparisonStudy(
        designlab=1, kind="tether_comparison", name="t", paths=[{"type": "slalom"}]
    )
    assert [c.type for c in study.controllers] == [law.name for law in behind]
    assert [c.title for c in study.controllers] == [law.short for law in behind]
    accepted = set()
    for name in LAWS.choices():
        try:
            TypeAdapter(ControllerSpec).validate_python({"type": name})
            accepted.add(name)
        except ValidationError:
            pass
    assert accepted == {law.name for law in behind}


def test_the_modes_study_lists_the_registry_modes():
    study = TetherModesStudy(designlab=1, kind="tether_modes", name="t")
    side_front = LAWS.choices(placement="side") + LAWS.choices(placement="front")
    assert study.modes == list(side_front)
    assert study.brake_laws == list(LAWS.choices(placement="behind", brakeable=True))


def test_controller_from_dict_refuses_a_law_not_behind():
    with pytest.raises(InvalidParameterError, match=r"controller\.type"):
        controller_from_dict({"type": "SideJoystick"})
    assert controller_from_dict({"type": "FollowTheLeader"}) == FollowTheLeader()


@declared
@dataclass(frozen=True)
class _SlowFTL(base.TetherController):
    """A new law written in one place: FTL's target with half its speed command."""

    desired_length: float = base.tether_length(1.0)
    speed_gain: float = base.gain("K_V", "1/s", "speed gain", 1.0)
    turn_gain: float = base.gain("K_O", "1/s", "turn gain", 3.0)
    lookahead: float = base.length("delta", "look-ahead", 0.5)
    min_step: float = base.min_step()
    buffer_size: int = base.buffer_size()

    label: ClassVar[str] = "slow FTL"
    target_finder: ClassVar[TargetFinder] = LOOKAHEAD
    linear: ClassVar[bool] = True
    LAW_PARAMS: ClassVar[tuple[str, ...]] = ("desired_length", "speed_gain", "turn_gain")

    @classmethod
    @cache
    def law_function(cls, variant: str = "") -> ca.Function:
        lm, phi, b, ld, kv, ko = base.symbols("l_m", "phi", "b", "l_d", "k_V", "k_O")
        return ca.Function("slow", [lm, phi, b, ld, kv, ko], [kv * (lm - ld), ko * phi + 0 * b])

    def effective_loop(self, speed, wheel_track):
        return self.turn_gain, self.lookahead, self.desired_length + speed / self.speed_gain


def test_a_new_law_runs_in_the_engines_without_touching_them():
    """A law the engines never heard of: the same law as FTL gives FTL's run, bit for bit."""
    path = tether.straight_line(3.0)
    new = tether.simulate(_SlowFTL(), path)
    ftl = tether.simulate(FollowTheLeader(), path)
    np.testing.assert_array_equal(new.robot_xy, ftl.robot_xy)
    noisy = tether.OXYDOG.replace(length_noise_std=0.01)
    a = tether.simulate_batch([_SlowFTL(), _SlowFTL(lookahead=0.3)], path, robot=noisy, seed=3)
    b = tether.simulate_batch(
        [FollowTheLeader(), FollowTheLeader(lookahead=0.3)], path, robot=noisy, seed=3
    )
    np.testing.assert_array_equal(a.robot_xy, b.robot_xy)
    assert tether.linear_analysis(_SlowFTL()).damping_ratio == pytest.approx(
        tether.linear_analysis(FollowTheLeader()).damping_ratio, rel=0, abs=0
    )
    assert math.isfinite(new.tether_length[-1])


def test_the_comparison_table_ratios_cover_every_law_behind():
    """The summary's ratio columns: the reference law against every other law behind."""
    from designlab.report.tether import _RATIO_LAWS, _REFERENCE

    behind = LAWS.variants(placement="behind")
    assert _REFERENCE is behind[0]
    assert {_REFERENCE, *_RATIO_LAWS} == set(behind)
    assert [law.measured for law in _RATIO_LAWS] == sorted(
        (law.measured for law in _RATIO_LAWS), reverse=True
    )


def test_the_docs_table_of_the_laws_is_the_registry():
    from pathlib import Path

    from designlab.following.tether.laws.registry import TABLE_COLUMNS

    docs = (Path(__file__).resolve().parents[2] / "docs" / "following.md").read_text()
    assert LAWS.table(TABLE_COLUMNS) in docs


_NEW_LAW_SCRIPT = """
from dataclasses import dataclass
from typing import ClassVar

from designlab.following.tether import LAWS, FollowTheLeader
from designlab.params import declared


@declared
@dataclass(frozen=True)
class NewLaw(FollowTheLeader):
    '''A law registered by one line, after the package's own.'''

    label: ClassVar[str] = "a new law"
    short: ClassVar[str] = "NEW"


LAWS.register(NewLaw)

from designlab.report.tether import comparison_markdown  # noqa: E402
from designlab.study import parse_study, run_study  # noqa: E402

study = parse_study('''
designlab: 1
kind: tether_comparison
name: new_law
paths: [{type: straight_line, length: 2.0}]
desired_lengths: [1.0]
''')
result = run_study(study)
print(result.to_frame()["controller"].tolist())
table = comparison_markdown(result, figures={}).split("## Mean normal path deviation")[1]
print(table.splitlines()[2])
"""


def test_a_registered_law_appears_in_the_comparison_report():
    """One registry line: the comparison study runs the new law and its table has its columns."""
    import subprocess
    import sys

    out = subprocess.run(
        [sys.executable, "-c", _NEW_LAW_SCRIPT], capture_output=True, text=True, check=True
    ).stdout.splitlines()
    assert out[0] == str([law.short for law in LAWS.variants(placement="behind")] + ["NEW"])
    header = out[1]
    assert "NEW mean/b" in header and "PJ / NEW" in header and "FTL-CD mean/b" in header
