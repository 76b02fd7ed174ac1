"""Table C.1 like for like: the ranking sentence follows its table (report first lines)."""

from __future__ import annotations

from types import SimpleNamespace

import pandas as pd

from designlab.report.navigation_gains import like_for_like_label, like_for_like_lines


def _optimum(best: float, half: float, status: str = "not_converged") -> SimpleNamespace:
    best_h = [half - 0.01, half, best - 0.001, best]
    history = pd.DataFrame({"evaluations": [16, 32, 48, 64], "best_H_mean": best_h})
    return SimpleNamespace(history=history, evaluations=64, status=status, objective=best)


def _result(h: dict[str, float], half: dict[str, float]) -> SimpleNamespace:
    rows = [
        {"method": m, "gains": "designlab_optimum", "H_mean": v, "feasible": v > 0}
        for m, v in h.items()
    ]
    rows += [{"method": m, "gains": "table_C1", "H_mean": 0.1, "feasible": True} for m in h]
    return SimpleNamespace(
        baselines=pd.DataFrame(rows),
        study=SimpleNamespace(baseline_configurations=[1, 2, 4]),
        baseline_optima={m: _optimum(h[m], half[m]) for m in h if m != "vff"},
        optima={"off": _optimum(h["vff"], half["vff"])},
    )


def test_the_reversal_of_table_c1_is_said_plainly():
    lines = like_for_like_lines(
        _result(
            {"vff": 0.636, "masoud": 0.653, "ge_cui": 0.4},
            {"vff": 0.62, "masoud": 0.64, "ge_cui": 0.3},
        )
    )
    assert lines[0].endswith("Masoud 0.653 > New VFF 0.636 > Ge & Cui 0.400.")
    assert "Table C.1 (App. C.2): New VFF 0.69 > Masoud 0.66 > Ge & Cui 0.52" in lines[2]
    assert "**The thesis's order is reversed here**: Masoud ranks above New VFF." in lines[2]
    assert "after half of them 0.6200" in lines[4] and "give the same ranking" in lines[4]


def test_the_thesis_order_and_a_changed_half_budget_ranking():
    lines = like_for_like_lines(
        _result(
            {"vff": 0.70, "masoud": 0.65, "ge_cui": 0.5},
            {"vff": 0.60, "masoud": 0.64, "ge_cui": 0.3},
        )
    )
    assert lines[0].endswith("New VFF 0.700 > Masoud 0.650 > Ge & Cui 0.500.")
    assert lines[2].endswith("The thesis's order holds here.")
    assert "give a different ranking" in lines[4]


def test_an_infeasible_method_ranks_last_and_is_named():
    lines = like_for_like_lines(
        _result(
            {"vff": 0.70, "masoud": 0.65, "ge_cui": -1.0},
            {"vff": 0.6, "masoud": 0.6, "ge_cui": 0.3},
        )
    )
    assert lines[0].endswith("New VFF 0.700 > Masoud 0.650 > Ge & Cui (none feasible).")
    assert like_for_like_label("vff") == "vff like for like"
