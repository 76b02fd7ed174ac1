"""The machinery of the hostile-input harness (benchmarks/hostile.py), on known cases.

The harness is a benchmark (minutes per domain); these tests keep its parts from rotting:
the classification of each kind of outcome in a forked worker with a timeout, the values
generated from a declaration, and the 40-digit impact reference against a closed form.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import math
import sys
import time
from pathlib import Path

import pytest

from designlab.errors import InvalidParameterError
from designlab.impact import HeadNeck
from designlab.params import Param

pytest.importorskip("mpmath")

_PATH = Path(__file__).resolve().parents[1] / "benchmarks" / "hostile.py"
_spec = importlib.util.spec_from_file_location("hostile_harness", _PATH)
assert _spec is not None and _spec.loader is not None
hostile = importlib.util.module_from_spec(_spec)
sys.modules["hostile_harness"] = hostile
_spec.loader.exec_module(hostile)


def _raise(exc: BaseException) -> None:
    raise exc


@dataclasses.dataclass
class _Answer:
    peak: float
    status: str = "ok"


def test_each_outcome_is_classified_in_a_worker_with_a_timeout() -> None:
    Case = hostile.Case
    oracle = hostile.finite_oracle(nonneg=("peak",))
    cases = [
        Case("t", "clear", lambda: HeadNeck(mass=-1.0, stiffness=3e3, damping=46.0),
             ("mass",), -1.0, "refuse"),
        Case("t", "unclear", lambda: _raise(InvalidParameterError("other", 2, "no")),
             ("mass",), -1.0, "refuse"),
        Case("t", "traceback", lambda: 1 / 0, ("mass",), 0.0),
        Case("t", "hang", lambda: time.sleep(30)),
        Case("t", "silent", lambda: _Answer(-3.0), oracle=oracle),
        Case("t", "accepted", lambda: _Answer(2.0), oracle=oracle),
        Case("t", "silent refusal", lambda: _Answer(2.0), ("mass",), math.nan, "refuse",
             oracle=oracle),
    ]  # fmt: skip
    rows = hostile.run_cases(cases, timeout=2.0)
    got = {r["name"]: r["outcome"] for r in rows}
    assert got == {
        "clear": "clear",
        "unclear": "unclear",
        "traceback": "traceback",
        "hang": "hang",
        "silent": "silent",
        "accepted": "accepted",
        "silent refusal": "silent",
    }
    assert "ZeroDivisionError" in next(r["detail"] for r in rows if r["name"] == "traceback")
    table = hostile.table(rows)
    assert "| t | 7 | 1 | 1 | 1 | 1 | 2 | 1 |" in table
    assert "repro" in hostile.findings(rows)


def test_values_come_from_the_declaration() -> None:
    decl = Param("k", "N/m", "stiffness", gt=0, le=1e9, name="stiffness")
    values = dict(hostile.hostile_values(decl, 1e3))
    assert values["at >0"] == 0.0 and values["at <=1e+09"] == 1e9
    assert values["outside <=1e+09"] > 1e9
    assert 1e6 in values.values() and 1e13 not in values.values()  # the admitted ladder only
    assert hostile.expectation(decl, 1e9) == "accept"
    assert hostile.expectation(decl, 2e9) == "refuse"
    assert hostile.expectation(decl, -1.0) == "refuse"
    assert hostile.expectation(decl, math.nan) == "refuse"


def test_the_impact_reference_equals_the_undamped_closed_form() -> None:
    # No damping, no robot or neck spring: eps = v/w sin(w t), w^2 = K_c (1/M_r + 1/M_h);
    # the lobe ends at pi/w, eps_max = v/w, a_h,max = K_c v/(w M_h), f_c,max = K_c v/w.
    m_r, k_c, m_h, v = 9.6, 24.25e3, 4.4, 1.25
    w = math.sqrt(k_c * (1 / m_r + 1 / m_h))
    ref = hostile.impact_reference([m_r, 0.0, 0.0, k_c, 0.0, m_h, 0.0, 0.0], v)
    assert ref is not None
    assert ref["impact_duration"] == pytest.approx(math.pi / w, rel=1e-12)
    assert ref["max_compression"] == pytest.approx(v / w, rel=1e-12)
    assert ref["peak_head_acceleration"] == pytest.approx(k_c * v / (w * m_h), rel=1e-12)
    assert ref["peak_force"] == pytest.approx(k_c * v / w, rel=1e-12)
