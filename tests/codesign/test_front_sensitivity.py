"""Sensitivity of the front (issue 24, item 5): Sobol indices against closed forms."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as hst

import designlab.navigation as nav
from designlab.codesign import DesignSpace, design_sobol, front_sensitivity

_FIXED = {"damping": 70.0, "speed": 0.7, "k1": 3.0, "b": 0.5, "k3": 20.0, "k5": 100.0}


def _space(free: dict[str, tuple[float, float]]) -> DesignSpace:
    """A space with only ``free`` varied; the rest fixed at thesis-like values."""
    kw: dict[str, float] = {}
    for name in DesignSpace.NAMES:
        lo, hi = free.get(name, (_FIXED.get(name), _FIXED.get(name)))
        if lo is None:  # a variable neither free nor listed: its default middle
            d = DesignSpace()
            lo = hi = 0.5 * (getattr(d, f"{name}_min") + getattr(d, f"{name}_max"))
        kw[f"{name}_min"], kw[f"{name}_max"] = lo, hi
    return DesignSpace(**kw)


def _unit(x: float, lo: float, hi: float) -> float:
    return (x - lo) / (hi - lo)


BOX = {"stiffness": (1e4, 5e4), "thickness": (0.01, 0.05), "k5": (10.0, 300.0)}


@settings(max_examples=6, deadline=None)
@given(hst.lists(hst.floats(0.2, 5.0), min_size=3, max_size=3))
def test_additive_objective_has_closed_form_first_order_indices(a: list[float]) -> None:
    # y = sum a_j u_j with u_j uniform on [0, 1]: Var = sum a_j^2 / 12, so
    # S1_j = ST_j = a_j^2 / sum a^2 (no interaction).
    names = ("K_c", "T_u", "k5")

    def metric(d):
        u = (_unit(d.foam.stiffness, *BOX["stiffness"]), _unit(d.foam.thickness, *BOX["thickness"]),
             _unit(d.gains.k5, *BOX["k5"]))  # fmt: skip
        return {"y": float(np.dot(a, u))}

    table = design_sobol(metric, _space(BOX), samples=1024, seed=3)
    got = table.frame.set_index("parameter")
    exact = np.square(a) / np.square(a).sum()
    for name, s in zip(names, exact, strict=True):
        assert got.loc[name, "S1"] == pytest.approx(s, abs=0.06)
        assert got.loc[name, "ST"] == pytest.approx(s, abs=0.06)
        # the exact value lies within a few of the reported 95 % half-widths
        assert abs(got.loc[name, "ST"] - s) <= 4 * got.loc[name, "ST_conf"] + 1e-3


def test_ignored_variable_has_zero_total_index_and_interaction_splits() -> None:
    # y = u_K * u_T (k5 ignored): Var = 7/144, V_K = V_T = 1/48, so S1 = 3/7 and
    # ST = 4/7 each; k5 gets exactly zero total index.
    def metric(d):
        uk = _unit(d.foam.stiffness, *BOX["stiffness"])
        ut = _unit(d.foam.thickness, *BOX["thickness"])
        return {"y": uk * ut, "flat": 2.0}

    table = design_sobol(metric, _space(BOX), samples=2048, seed=0)
    y = table.frame[table.frame["metric"] == "y"].set_index("parameter")
    assert y.loc["k5", "ST"] == 0.0
    for name in ("K_c", "T_u"):
        assert y.loc[name, "S1"] == pytest.approx(3 / 7, abs=0.05)
        assert y.loc[name, "ST"] == pytest.approx(4 / 7, abs=0.05)
    flat = table.frame[table.frame["metric"] == "flat"]
    assert flat["ST"].isna().all()  # a constant metric has no variance to share
    assert table.ranked("y")["parameter"].iloc[-1] == "k5"
    assert set(table.frame["parameter"]) == {"K_c", "T_u", "k5"}  # fixed variables: no row


def test_front_sensitivity_of_the_real_model_has_exact_zeros() -> None:
    # The foam does not steer the robot: arrival_time has ST = 0 for K_c and T_u; the
    # foam_thickness objective is T_u itself: ST = 0 for K_c and V_mr.
    space = _space({"stiffness": (2e4, 3e4), "thickness": (0.02, 0.04), "speed": (0.5, 0.9)})
    t = front_sensitivity([nav.configuration(2)], space=space, samples=2, seed=1,
                          objectives=("arrival_time", "foam_thickness"))  # fmt: skip
    f = t.frame.set_index(["metric", "parameter"])
    assert f.loc[("arrival_time", "K_c"), "ST"] == 0.0
    assert f.loc[("arrival_time", "T_u"), "ST"] == 0.0
    assert f.loc[("arrival_time", "V_mr"), "ST"] > 0.0
    assert f.loc[("foam_thickness", "K_c"), "ST"] == 0.0
    assert f.loc[("foam_thickness", "V_mr"), "ST"] == 0.0
    assert f.loc[("foam_thickness", "T_u"), "ST"] > 0.0
    assert set(t.metrics) == {"arrival_time", "foam_thickness", "infeasible"}
