"""The navigation_gains study kind: a tiny run end to end, and the committed report."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from designlab.errors import StudyError
from designlab.report import write_report
from designlab.results import check_result
from designlab.study import load_study, parse_study, run_study

ROOT = Path(__file__).resolve().parents[2]

TINY = """
designlab: 1
kind: navigation_gains
name: tiny
configurations: [1]
validation: [3]
modes: [off]
popsize: 4
max_evaluations: 8
refine: false
sensitivity: false
"""


def test_tiny_study_end_to_end(tmp_path: Path) -> None:
    study = parse_study(TINY)
    assert study.modes == ["off"]  # YAML 1.1 reads a bare off as false: accepted as the mode
    result = run_study(study)
    check_result(result)
    g = result.comparison
    assert list(g["gains"]) == ["experimental", "thesis_optimum", "designlab_optimum"]
    assert list(g.columns[:7]) == ["gains", "stabilising", "k1", "b", "k3", "k5", "H_mean"]
    assert g["feasible"].all() and "H_ch6_config3" in g
    out = write_report(result, tmp_path, command="pytest", index=False)
    names = {p.name for p in out.iterdir()}
    assert {
        "summary.md",
        "gains.csv",
        "history.csv",
        "convergence.png",
        "trajectories_off.png",
    } <= names
    md = (out / "summary.md").read_text()
    assert "## Gains and H_mean" in md and "Configuration 3 (not optimised)" in md


def test_schema_errors(tmp_path: Path) -> None:
    f = tmp_path / "bad.yaml"
    f.write_text(TINY.replace("max_evaluations: 8", "max_evaluations: 2"))
    with pytest.raises(StudyError, match="max_evaluations"):
        load_study(f)
    f.write_text(TINY.replace("modes: [off]", "modes: [on]"))
    with pytest.raises(StudyError, match="modes"):
        load_study(f)
    f.write_text(TINY.replace("configurations: [1]", "configurations: [5]"))
    with pytest.raises(StudyError, match="configurations"):
        load_study(f)


def test_committed_report_matches_the_study() -> None:
    """reports/navigation_gains comes from its study: ours at least as good as (a), (b)."""
    g = pd.read_csv(ROOT / "reports" / "navigation_gains" / "gains.csv", keep_default_na=False)
    for mode in ("off", "lyapunov"):
        block = g[(g["stabilising"] == mode) & (g["robust"] == "")].set_index("gains")
        assert block.loc["designlab_optimum", "feasible"] in (True, "True")
        assert block.loc["designlab_optimum", "H_mean"] >= block.loc["experimental", "H_mean"]
        assert block.loc["designlab_optimum", "H_mean"] >= block.loc["thesis_optimum", "H_mean"]
    study = load_study(ROOT / "studies" / "navigation_gains.yaml")
    assert study.kind == "navigation_gains" and study.name == "navigation_gains"


def test_sobol_samples_must_be_a_power_of_two(tmp_path: Path) -> None:
    f = tmp_path / "bad.yaml"
    f.write_text(TINY + "sobol_samples: 12\n")
    with pytest.raises(StudyError, match="sobol_samples"):
        load_study(f)
    f.write_text(TINY + "sobol_samples: 0\n")
    assert load_study(f).sobol_samples == 0


@pytest.mark.slow
def test_bound_check_adds_a_wider_box_row(tmp_path: Path) -> None:
    # refined on Configuration 1 alone the optimum sits on the K3 and K5 bounds; the check
    # moves them 10x out
    text = TINY.replace("refine: false", "refine: true") + "bound_check: true\n"
    text += "bounds: {k1: [1.5, 2.0]}\n"
    result = run_study(parse_study(text))
    hit = result.optima["off"].on_bounds()
    assert hit, "this run's optimum lies on a bound"
    wide = result.optima["off_wider_box"].bounds
    for n, side in hit.items():
        lo, hi = result.optima["off"].bounds[n]
        assert wide[n] == ((lo / 10, hi) if side == "low" else (lo, hi * 10))
    assert "designlab_optimum_wider_box" in list(result.comparison["gains"])
    out = write_report(result, tmp_path, command="pytest", index=False)
    md = (out / "summary.md").read_text()
    assert "Bound check" in md and "wider box" in md


def test_committed_gains_table_matches_the_simulator() -> None:
    """The H values in reports/navigation_gains/gains.csv come back from today's simulator,
    on any machine within the tolerance the report states for fixed gain sets."""
    import designlab as dl
    from designlab.navigation.tuning_results import REPRO_H_FIXED

    nav = dl.navigation
    g = pd.read_csv(ROOT / "reports" / "navigation_gains" / "gains.csv", keep_default_na=False)
    sc = [nav.configuration(i) for i in (1, 2, 3)]
    for mode in ("off", "lyapunov"):
        block = g[(g["stabilising"] == mode) & (g["robust"] == "")]
        f = nav.evaluate_gains(
            sc, block[["k1", "b", "k3", "k5"]].to_numpy(), stabilising=mode
        ).frame
        for n in ("H_ch6_config1", "H_ch6_config2", "H_ch6_config3", "H_mean"):
            want = block[n].astype(float).to_numpy()
            assert f[n].to_numpy() == pytest.approx(want, abs=REPRO_H_FIXED)
        assert list(f["feasible"]) == [v in (True, "True") for v in block["feasible"]]


@pytest.mark.slow
def test_sensitivity_sections_end_to_end(tmp_path: Path) -> None:
    text = """
designlab: 1
kind: navigation_gains
name: sens
configurations: [1, 2, 3]
validation: []
modes: [off]
popsize: 8
max_evaluations: 16
refine: false
deltas_pct: [-100, 50]
sobol_samples: 8
"""
    result = run_study(parse_study(text))
    check_result(result)
    for part in [*result.sensitivities.values(), *result.global_sensitivities.values()]:
        check_result(part)
    assert set(result.sensitivities) == {"thesis_optimum_off", "designlab_optimum_off"}
    assert set(result.global_sensitivities) == set(result.sensitivities)
    a = result.appendix_c
    # only the +50 % and base rows exist here: 2 rows per (gain, quantity, configuration)
    assert set(a["delta_pct"]) == {0.0, 50.0} and set(a["parameter"]) == {"k1", "b", "k3", "k5"}
    assert (a["error"] == a["designlab"] - a["thesis"]).all()
    g = result.comparison
    assert {f"T_arrive_s_ch6_config{i}" for i in (1, 2, 3)} <= set(g.columns)
    assert {f"critical_margin_m_ch6_config{i}" for i in (1, 2, 3)} <= set(g.columns)
    out = write_report(result, tmp_path, command="pytest", index=False)
    names = {p.name for p in out.iterdir()}
    assert {
        "appendix_c_comparison.csv",
        "appendix_c_outcomes.csv",
        "global_sensitivity_thesis_optimum_off.csv",
        "sensitivity_designlab_optimum_off.csv",
    } <= names
    md = (out / "summary.md").read_text()
    for heading in (
        "## Sensitivity tables (Zeng 2011, App. C.3)",
        "## Against the thesis's Appendix C (Tables C.2-C.9)",
        "## Which gains matter when all move together",
    ):
        assert heading in md
