"""Crowd study summaries: rates and intervals counted from the runs, worst and typical runs."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from designlab.errors import DesignlabError
from designlab.navigation.crowds.metrics import wilson_interval
from designlab.navigation.crowds.study import (
    CrowdStudy,
    decode_gains,
    encode_gains,
    representative_run,
    run_row,
    worst_run,
)
from designlab.navigation.parameters import GeCuiGains, MasoudGains, VFFGains


def _runs(rng: np.random.Generator, n: int = 40) -> pd.DataFrame:
    outcome = rng.choice(["success", "collision", "timeout"], size=n, p=[0.6, 0.2, 0.2])
    return pd.DataFrame({
        "scenario": rng.choice(["corridor", "plaza"], size=n),
        "density": rng.choice([0.1, 0.3], size=n),
        "seed": np.arange(n),
        "method": rng.choice(["vff", "cbf"], size=n),
        "outcome": outcome,
        "success": (outcome == "success").astype(float),
        "collided": (outcome == "collision").astype(float),
        "timeout": (outcome == "timeout").astype(float),
        "critical": rng.integers(0, 2, size=n).astype(float),
        "arrival_time_s": np.where(outcome == "success", rng.uniform(5, 20, size=n), np.inf),
        "min_centre_distance_m": rng.uniform(0.2, 2.0, size=n),
        "personal_space_s": rng.uniform(0, 3, size=n),
        "ped_delay_mean_s": rng.uniform(0, 1, size=n),
        "ped_deviation_mean_m": rng.uniform(0, 1, size=n),
        "status": np.where(rng.uniform(size=n) < 0.1, "error", "ok"),
    })  # fmt: skip


@pytest.mark.parametrize("seed", range(5))
def test_summary_counts_every_group(seed: int) -> None:
    runs = _runs(np.random.default_rng(seed))
    summary = CrowdStudy(runs=runs).to_frame()
    assert summary["runs"].sum() + summary["failed"].sum() == len(runs)
    for _, row in summary.iterrows():
        g = runs[(runs.scenario == row.scenario) & (runs.density == row.density)
                 & (runs.method == row.method) & (runs.status == "ok")]  # fmt: skip
        assert row.runs == len(g)
        k = int(g.collided.sum())
        assert (
            row.collision_rate == pytest.approx(k / len(g))
            if len(g)
            else math.isnan(row.collision_rate)
        )
        if len(g):
            assert (row.collision_low, row.collision_high) == pytest.approx(
                wilson_interval(k, len(g))
            )
            assert row.success_rate + row.collision_rate + row.timeout_rate == pytest.approx(1.0)
            ok = g[g.success > 0]
            want = ok.arrival_time_s.mean() if len(ok) else math.nan
            assert row.time_to_goal_mean_s == pytest.approx(want, nan_ok=True)
            assert row.clearance_min_m == g.min_centre_distance_m.min()


def test_worst_and_representative() -> None:
    runs = pd.DataFrame({
        "method": ["vff"] * 4,
        "collided": [0.0, 0.0, 1.0, 0.0],
        "critical": [1.0, 0.0, 0.0, 0.0],
        "timeout": [0.0, 0.0, 0.0, 0.0],
        "success": [1.0, 1.0, 0.0, 1.0],
        "arrival_time_s": [9.0, 10.0, np.inf, 30.0],
        "min_centre_distance_m": [0.5, 1.0, 0.1, 2.0],
        "status": ["ok"] * 4,
    })  # fmt: skip
    assert worst_run(runs, "vff").name == 2
    assert representative_run(runs, "vff").name == 1
    with pytest.raises(DesignlabError):
        worst_run(runs, "cbf")


def test_run_row_of_a_synthetic_run() -> None:
    t = np.arange(4) * 0.5
    robot = np.stack([t, np.zeros(4)], axis=1)
    peds = np.array([[[3.0, 0.0]], [[2.0, 0.0]], [[1.5, 0.5]], [[np.nan, np.nan]]])
    res = SimpleNamespace(
        times=t, robot_positions=robot, pedestrian_positions=peds, collided=False,
        arrival_time=1.5, entered_critical=True, min_distance=0.4, status="ok",
    )  # fmt: skip
    alone = SimpleNamespace(
        pedestrian_positions=np.array([[[3.0, 0.0]], [[2.0, 0.0]], [[np.nan] * 2], [[np.nan] * 2]])
    )
    row = run_row(res, alone)
    assert row["outcome"] == "success" and row["critical"] == 1.0
    assert row["min_centre_distance_m"] == pytest.approx(math.sqrt(0.5))  # (1, 0) to (1.5, 0.5)
    assert row["personal_space_s"] == pytest.approx(0.5)  # only t = 1.0 s is inside 1.2 m
    assert row["ped_delay_mean_s"] == pytest.approx(0.5)  # leaves at 1.5 s instead of 1.0 s
    assert row["ped_deviation_max_m"] == pytest.approx(
        math.sqrt(0.5)
    )  # (1.5, 0.5) to the end (2, 0)
    timeout = run_row(SimpleNamespace(**{**vars(res), "arrival_time": math.inf}))
    assert timeout["outcome"] == "timeout" and math.isnan(timeout["ped_delay_mean_s"])


@pytest.mark.parametrize(
    "gains", [VFFGains(4.3, 0.68, 20.3, 240.7), MasoudGains(), GeCuiGains(), None]
)
def test_gains_round_trip(gains: object) -> None:
    assert decode_gains(encode_gains(gains)) == gains


def test_gains_bad() -> None:
    with pytest.raises(DesignlabError):
        encode_gains("fast")
    with pytest.raises(DesignlabError):
        decode_gains({"type": "pid"})


SHORT = {"length": 8.0, "horizon": 1.5}


def test_crowd_study_runs_every_combination_and_stores_them(tmp_path) -> None:
    from designlab.analysis.store import open_store
    from designlab.navigation.crowds.study import crowd_study

    args = (["corridor_counterflow"], [0.1, 0.2], [0, 1], ["vff", "masoud"])
    with open_store(tmp_path, "crowds") as store:
        st = crowd_study(*args, crowd_options={**SHORT, "react_to_robot": True}, store=store)
        again = crowd_study(*args, crowd_options={**SHORT, "react_to_robot": True}, store=store,
                            cache_only=True)  # fmt: skip
    runs = st.runs
    assert len(runs) == 8 and st.status == "ok"
    assert set(zip(runs.density, runs.seed, runs.method, strict=True)) == {
        (d, s, m) for d in (0.1, 0.2) for s in (0, 1) for m in ("vff", "masoud")
    }
    pd.testing.assert_frame_equal(runs, again.runs)
    summary = st.to_frame()
    assert len(summary) == 4 and (summary["runs"] == 2).all()
    assert np.isfinite(runs["ped_delay_mean_s"]).all() or runs["ped_beyond_window"].notna().all()


def test_pedestrians_that_ignore_the_robot_are_not_delayed() -> None:
    from designlab.navigation.crowds.study import crowd_study

    st = crowd_study("open_plaza", [0.1], [3], ["vff"], crowd_options=SHORT)
    assert st.runs["ped_delay_mean_s"].tolist() == [0.0]
    assert st.runs["ped_deviation_max_m"].tolist() == [0.0]


@pytest.mark.parametrize(
    "kwargs",
    [
        {"scenarios": ["hallway"]},
        {"scenarios": []},
        {"densities": [0.1, 0.1]},
        {"densities": [-0.1]},
        {"densities": [50.0]},
        {"seeds": [-1]},
        {"seeds": [1.5]},
        {"methods": ["teleport"]},
        {"methods": "vff"},
        {"methods": ["vff", "vff"]},
        {"gains": {"cbf": VFFGains(3.0, 0.25, 20.0, 17.0)}},
        {"gains": {"vff": "fast"}},
        {"seeds": range(100_001)},
        {"crowd_options": {"model": "teleport"}},
        {"stabilising": "sometimes"},
        {"personal_space": 0.0},
    ],
)
def test_crowd_study_bad_input(kwargs: dict) -> None:
    from designlab.navigation.crowds.study import crowd_study

    args = {"scenarios": ["crossing"], "densities": [0.1], "seeds": [0], "methods": ["vff"],
            "crowd_options": SHORT}  # fmt: skip
    args.update(kwargs)
    with pytest.raises(DesignlabError):
        crowd_study(**args)


def test_the_report_is_written_from_its_tables(tmp_path) -> None:
    """The kind runs, the writer writes every file, and each finding's counts are the table's."""
    import re

    from designlab.report import write_report
    from designlab.study import parse_study, run_study

    study = parse_study(
        "designlab: 1\nkind: navigation_crowds\nname: demo\nscenarios: [corridor_counterflow]\n"
        "densities: [0.1]\nseeds: [0, 1]\nmethods: [{method: vff}, {method: masoud}]\n"
        "crowd: {length: 8.0, horizon: 0.5}\nanimations: false\n"
    )
    result = run_study(study)
    out = write_report(result, tmp_path, index=False)
    written = {p.name for p in out.iterdir()}
    assert {
        "summary.md",
        "rates.csv",
        "runs.csv",
        "rates_vs_density.png",
        "trajectories.png",
        "stalls.csv",
    } <= written
    assert not any(name.endswith(".gif") for name in written)  # animations: false
    text = (out / "summary.md").read_text()
    runs = pd.read_csv(out / "runs.csv")
    for method in ("vff", "masoud"):
        got = re.search(rf"- {method}: (\d+) of (\d+) runs arrived, (\d+) collided", text)
        sub = runs[runs["method"] == method]
        assert got is not None
        assert [int(g) for g in got.groups()] == [
            int(sub.success.sum()),
            len(sub),
            int(sub.collided.sum()),
        ]
    stalls = pd.read_csv(out / "stalls.csv")
    for method, g in stalls.groupby("method"):
        line = re.search(rf"- {method}: slow (\d+)% and receding (\d+)%", text)
        assert line is not None
        assert [int(x) for x in line.groups()] == [
            round(100 * g["slow"].mean()),
            round(100 * g["receding"].mean()),
        ]


def test_stabilising_per_method_label() -> None:
    from designlab.navigation.crowds.study import crowd_study, encode_gains, simulate_run

    g = encode_gains(VFFGains(4.3, 0.68, 20.3, 240.7))
    options = {"crowd": {"length": 8.0, "horizon": 0.12}, "stabilising": {"vff:off": "off"},
               "gains": {"vff": g, "vff:off": g}}  # fmt: skip
    assert simulate_run(options, "crossing", 0.1, 0, "vff:off").stabilising == "off"
    assert simulate_run(options, "crossing", 0.1, 0, "vff").stabilising == "lyapunov"
    args = {"scenarios": ["crossing"], "densities": [0.1], "seeds": [0],
            "methods": ["vff", "vff:off"], "crowd_options": SHORT}  # fmt: skip
    for bad in ({"vff:on": "off"}, {"vff:off": "sometimes"}):
        with pytest.raises(DesignlabError, match="stabilising"):
            crowd_study(**args, stabilising=bad)


def test_an_interrupted_crowd_study_resumes_from_its_store(tmp_path, monkeypatch) -> None:
    """`designlab run` keeps a crowd study's finished crowds in the result store, so a rerun
    with --resume (and `designlab report`) computes none of them again."""
    from typer.testing import CliRunner

    import designlab.navigation.crowds.study as crowd_mod
    from designlab.cli import app

    study = tmp_path / "tiny_crowds.yaml"
    study.write_text("designlab: 1\nkind: navigation_crowds\nname: tiny_crowds\n"
                     "scenarios: [corridor_counterflow]\ndensities: [0.1]\nseeds: [0]\n"
                     "methods: [{method: vff}]\ncrowd: {length: 8.0, horizon: 0.5}\n"
                     "animations: false\n")  # fmt: skip
    cache, out = tmp_path / "cache", tmp_path / "reports"
    args = ["run", str(study), "-o", str(out), "--cache-dir", str(cache)]
    first = CliRunner().invoke(app, args)
    assert first.exit_code == 0, first.output
    assert (cache / "tiny_crowds.sqlite").is_file()
    calls = []
    real = crowd_mod.simulate_run

    def counted(*a, **k):
        calls.append(a)
        return real(*a, **k)

    monkeypatch.setattr(crowd_mod, "simulate_run", counted)  # the grid's runs go through it
    again = CliRunner().invoke(app, [*args, "--resume"])
    assert again.exit_code == 0, again.output
    assert calls == []  # the crowd came from the store
    fresh = CliRunner().invoke(app, ["run", str(study), "-o", str(out), "--cache-dir",
                                     str(tmp_path / "other")])  # fmt: skip
    assert fresh.exit_code == 0, fresh.output
    assert len(calls) == 1  # without the store, the run is simulated (the counter counts)
