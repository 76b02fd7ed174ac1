"""The row-by-row account of the thesis (docs/navigation.md, "How close to the thesis")."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.navigation.account import (
    TABLE_5_1_FITTED,
    account_markdown,
    thesis_account,
    thesis_rows,
)
from designlab.report.navigation_account import BEGIN, END

nav = dl.navigation
ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"


def test_every_thesis_row_is_in_the_account() -> None:
    ch6 = pd.read_csv(DATA / "nav_results_ch6.csv")
    ch7 = pd.read_csv(DATA / "nav_results_ch7.csv")
    rows = thesis_rows()
    assert len(rows) == len(ch6) + len(ch7)
    assert set(rows["table"]) == {"5.1", "6.2", "6.3", "6.4", "6.5", "7.1", "7.2", "7.3", "7.4"}
    assert (rows["configuration"] == "unpredictable").sum() == (ch6["table"] == 5.1).sum()


def test_a_cause_is_named_only_when_its_run_removes_the_difference() -> None:
    acc = thesis_account(tables=("6.4",), methods=("New VFF*",))
    f = acc.frame.set_index("quantity")
    t = f.loc["T_arrive_s"]
    # independent runs: the default, then each cause removed
    base = nav.simulate(nav.configuration(3), nav.OPTIMAL_GAINS, stabilising="off")
    tol = nav.simulate(
        nav.configuration(3), nav.OPTIMAL_GAINS, stabilising="off", arrival_tolerance=0.05
    )
    start = nav.simulate(
        nav.configuration(3).replace(start=(3.99, 0.6)), nav.OPTIMAL_GAINS, stabilising="off"
    )
    assert t["ours"] == base.arrival_time and abs(base.arrival_time / 6.2 - 1) > 0.07
    assert t["cause"] == "tolerance or start"
    assert t["cause_value"] == tol.arrival_time and abs(tol.arrival_time / 6.2 - 1) <= 0.07
    assert abs(start.arrival_time / 6.2 - 1) <= 0.07
    for q, name in (("d_cir_min_m", "circle"), ("d_rect_min_m", "rectangle")):
        assert f.loc[q, "ours"] == base.min_distance[name]
        assert f.loc[q, "within"] == (abs(base.min_distance[name] - f.loc[q, "thesis"]) <= 0.03)
        assert f.loc[q, "cause"] == "-"


@pytest.mark.parametrize(
    ("label", "method", "thesis"),
    [("Masoud", "masoud", (14.0, 1.8)), ("Ge & Cui", "ge_cui", (10.5, 1.1))],
)
def test_table_5_1_baselines_are_their_law_with_unstated_gains(
    label: str, method: str, thesis: tuple[float, float]
) -> None:
    sc = nav.configuration("unpredictable")
    table_c1 = nav.simulate(sc, method=method, stabilising="off")
    fitted = nav.simulate(sc, TABLE_5_1_FITTED[method], method=method, stabilising="off")
    t, d = thesis
    # the fitted set gives both numbers of the row; Table C.1's gains miss the distance
    assert abs(fitted.arrival_time / t - 1) <= 0.07
    assert abs(fitted.min_distance["human"] - d) <= 0.03
    assert abs(table_c1.min_distance["human"] - d) > 0.4
    acc = thesis_account(tables=("5.1",), methods=(label,)).frame.set_index("quantity")
    row = acc.loc["d_h_min_m"]
    assert row["ours"] == table_c1.min_distance["human"]
    assert "baseline_gains" in row["cause"]
    assert row["cause_value"] == fitted.min_distance["human"]
    if method == "masoud":  # Table C.1's robot is caught by the turning human
        assert table_c1.entered_critical and not fitted.entered_critical
        assert table_c1.min_distance["human"] < sc.obstacles[0].r3


def test_docs_table_is_the_generated_one() -> None:
    text = (ROOT / "docs" / "navigation.md").read_text()
    table = text[text.index(BEGIN) + len(BEGIN) : text.index(END)]
    acc = thesis_account(tables=("6.4",), methods=("New VFF*",))
    for line in account_markdown(acc).splitlines()[2:]:
        assert line in table
    assert table.count("\n| ") - 1 == len(thesis_account_rows_expected())  # minus the header


def test_docs_table_is_the_committed_report() -> None:
    """Every line of the docs table is the committed report's (reports/navigation_account):
    a regenerated report with a stale docs table fails here."""
    from designlab.navigation.account import AccountResult

    text = (ROOT / "docs" / "navigation.md").read_text()
    table = text[text.index(BEGIN) + len(BEGIN) : text.index(END)].strip()
    frame = pd.read_csv(ROOT / "reports" / "navigation_account" / "account.csv")
    for column in ("cause", "tried", "note"):
        frame[column] = frame[column].fillna("")
    want = account_markdown(AccountResult(frame)).splitlines()
    got = table.splitlines()
    assert len(got) == len(want)
    number = re.compile(r"[-+]?\d+\.?\d*(?:e[-+]?\d+)?")
    for a, b in zip(got, want, strict=True):
        # the CSV keeps 7 significant digits: a 3-digit rounding may differ in its last digit
        assert number.sub("#", a) == number.sub("#", b), (a, b)
        x = [float(v) for v in number.findall(a)]
        y = [float(v) for v in number.findall(b)]
        assert np.allclose(x, y, rtol=6e-3, atol=1e-12), (a, b)


def thesis_account_rows_expected() -> list[tuple[str, str]]:
    """(row, quantity) pairs with a thesis value: one line each in the docs table."""
    rows = thesis_rows()
    out = []
    for _, r in rows.iterrows():
        for q in ("T_arrive_s", "d_h_min_m", "d_cir_min_m", "d_rect_min_m"):
            if not math.isnan(r[q]):
                out.append((r["table"], q))
    return out


@pytest.mark.parametrize("bad", [0.0, -0.1, float("nan"), 2.0, "x"])
def test_account_bands_are_checked(bad: object) -> None:
    with pytest.raises(InvalidParameterError, match="time_band"):
        thesis_account(tables=("6.2",), time_band=bad)  # type: ignore[arg-type]


def test_the_walk_is_named_only_with_a_walk_that_reproduces_the_row() -> None:
    acc = thesis_account(tables=("6.3",), methods=("New VFF",))
    f = acc.frame
    d = f[f["sim_or_exp"] == "sim"].set_index("quantity").loc["d_h_min_m"]
    assert d["cause"] == "walk" and abs(d["cause_value"] - 1.1) <= 0.03
    # an independent run of the walks tried finds the value the row names
    found = [
        nav.simulate(
            nav.configuration(2, human_speed=v, human_ramp_time=r), nav.EXPERIMENT_GAINS,
            stabilising="off",
        ).min_distance["human"]
        for v in (0.8, 1.0, 1.2) for r in (0.5, 1.5) if (v, r) != (1.0, 0.5)
    ]  # fmt: skip
    assert d["cause_value"] in found


def test_thesis_text_is_named_when_the_text_gives_our_value() -> None:
    # Table 6.2 prints 0.54 m for the New VFF; Sec. 6.4.1 says 0.49 m in simulation
    acc = thesis_account(tables=("6.2",), methods=("New VFF",))
    f = acc.frame
    d = f[f["sim_or_exp"] == "sim"].set_index("quantity").loc["d_cir_min_m"]
    run = nav.simulate(nav.configuration(1), nav.EXPERIMENT_GAINS, stabilising="off")
    assert d["ours"] == run.min_distance["circle"]
    assert abs(run.min_distance["circle"] - 0.54) > 0.03 >= abs(run.min_distance["circle"] - 0.49)
    assert d["cause"] == "thesis text" and d["cause_value"] == 0.49


def test_a_seeded_cause_counts_by_its_median_not_its_luckiest_seed() -> None:
    """Table 6.2's New VFF experiment arrives in 7.4 s; one vision-noise seed of ten gives
    an arrival inside the 7 % band, their median does not: no cause (issue 37: a cause must
    be demonstrated, not drawn)."""
    from designlab.navigation.account import CAUSE_SEEDS as SEEDS

    acc = thesis_account(tables=("6.2",), methods=("New VFF",))
    f = acc.frame
    t = f[f["sim_or_exp"] == "exp"].set_index("quantity").loc["T_arrive_s"]
    runs = [
        nav.simulate(nav.configuration(1), nav.EXPERIMENT_GAINS, stabilising="off",
                     noise=nav.SensorNoise(seed=k)).arrival_time
        for k in range(SEEDS)
    ]  # fmt: skip
    inside = sum(abs(x / 7.4 - 1) <= 0.07 for x in runs)
    median = float(np.median(runs))
    assert inside >= 1 and abs(median / 7.4 - 1) > 0.07
    assert t["cause"] == "experiment: not found"
    assert (
        f"noise: {min(runs):.3g}-{max(runs):.3g} (median {median:.3g}, {inside}/{SEEDS} "
        in (t["tried"])
    )


def test_the_walk_start_and_timing_move_the_human_only() -> None:
    """The ``walk_start`` cause: the human's walk starts 1 m further along and 0.5 s later;
    an independent run with that walk gives the same numbers (issue 37: Config 4's d_rect
    equalled Config 3's for every method while the thesis's differ)."""
    from designlab.navigation.account import RunSetup

    setup = RunSetup("4", 6, "vff", nav.EXPERIMENT_GAINS, True, human_head_start=1.0,
                     human_delay=0.5)  # fmt: skip
    sc = nav.configuration(4, robot=nav.HolonomicRobot())
    human = next(o for o in sc.obstacles if o.name == "human")
    walk = setup._shifted(human).motion
    assert walk.start == (human.motion.start[0] + 1.0, human.motion.start[1])
    assert walk.end == human.motion.end and walk.start_time == human.motion.start_time + 0.5
    moved = sc.replace(obstacles=tuple(setup._shifted(o) for o in sc.obstacles))
    ref = nav.simulate(moved, nav.EXPERIMENT_GAINS, stabilising="off")
    out = setup.run()
    assert out["T_arrive_s"] == ref.arrival_time
    assert out["d_rect_min_m"] == ref.min_distance["rectangle"]
    circle = next(o for o in sc.obstacles if o.name == "circle")
    assert setup._shifted(circle) is circle


def test_every_walking_row_is_tried_against_the_walks_noise_and_start() -> None:
    """Simulated rows with a walking human are tried against the measured walk's velocity
    noise (up to the thesis's amplitude, +-0.8 m/s) and the walk's start and timing, with the
    values each gave."""
    from designlab.navigation.account import CAUSES, WALK_NOISE_SD

    names = [c.name for c in CAUSES]
    assert {"walk_start", "walk_noise"} <= set(names)
    assert max(WALK_NOISE_SD) >= 0.8
    acc = thesis_account(tables=("6.3",), methods=("New VFF*",))
    f = acc.frame.set_index("quantity")
    for q in ("T_arrive_s", "d_h_min_m"):
        if not f.loc[q, "within"]:
            assert "walk_start: " in f.loc[q, "tried"] and "walk_noise: " in f.loc[q, "tried"]


def test_the_wider_timing_delays_or_moves_the_walk_and_nothing_else() -> None:
    """The ``walk_timing`` cause (issue 37: Config 4's human timing): 1.5-4 s late or 1.5-2 m
    along the walk; a 3 s-late run equals an independent run with the walk started 3 s later,
    and it applies only where a human walks."""
    from designlab.navigation.account import (
        CAUSES,
        WIDE_DELAYS,
        WIDE_HEAD_STARTS,
        RunSetup,
        _wide_timings,
    )

    cause = next(c for c in CAUSES if c.name == "walk_timing")
    setup = RunSetup("4", 6, "vff", nav.OPTIMAL_GAINS, True)
    runs = _wide_timings(setup)
    assert [r.human_delay for r in runs[: len(WIDE_DELAYS)]] == list(WIDE_DELAYS)
    assert [r.human_head_start for r in runs[len(WIDE_DELAYS) :]] == list(WIDE_HEAD_STARTS)
    assert cause.applies(setup, "d_h_min_m")
    assert not cause.applies(RunSetup("3", 6, "vff", nav.OPTIMAL_GAINS, True), "d_h_min_m")
    sc = nav.configuration(4, robot=nav.HolonomicRobot())
    late = RunSetup("4", 6, "vff", nav.OPTIMAL_GAINS, True, human_delay=3.0)
    moved = sc.replace(obstacles=tuple(late._shifted(o) for o in sc.obstacles))
    human = next(o for o in moved.obstacles if o.name == "human")
    original = next(o for o in sc.obstacles if o.name == "human")
    assert human.motion.start_time == original.motion.start_time + 3.0
    assert human.motion.start == original.motion.start
    ref = nav.simulate(moved, nav.OPTIMAL_GAINS, stabilising="off")
    assert late.run()["d_h_min_m"] == ref.min_distance["human"]
