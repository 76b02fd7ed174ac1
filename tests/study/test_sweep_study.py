"""Sweep studies: schema errors, sampling, cache, resume after a kill, corrupt entries."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from designlab.analysis.engine import CacheIncompleteError
from designlab.analysis.store import ChunkStore, open_store
from designlab.errors import StudyError
from designlab.study import RunContext, load_study, parse_study, run_study

SWEEP = """\
designlab: 1
kind: impact_sweep
name: sweep_demo
base: {robot: MANIPULATOR_1, foam: FOAM_1, head: HEAD_MIN, impact_velocity: 1.25}
sweep:
  method: grid
  parameters:
    foam.stiffness: {low: 10e3, high: 60e3, num: 6}
    head.mass: {values: [4.4, 5.3]}
sensitivity:
  metrics: [a_h_max_g, eps_max_m]
  one_at_a_time: {deltas_pct: [-10, 10]}
"""


def _error(text: str) -> str:
    with pytest.raises(StudyError) as info:
        parse_study(text, file="s.yaml")
    return str(info.value)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("foam.stiffness:", "foam.stifness:",
         "s.yaml:8: sweep.parameters.foam.stifness: unknown field; did you mean 'foam.stiffness'?"),
        ("values: [4.4, 5.3]", "values: [-4.4, 5.3]",
         "s.yaml:9: sweep.parameters.head.mass: -4.4 kg is out of range for head mass M_h: "
         "allowed > 0 and <= 1000 kg"),
        ("method: grid", "method: gird",
         "s.yaml:6: sweep.method: Input should be 'list', 'grid', 'lhs' or 'sobol' (got 'gird'; "
         "did you mean 'grid'?)"),
        ("method: grid", "method: lhs",
         "s.yaml:5: sweep: method lhs needs samples: N"),
        ("metrics: [a_h_max_g, eps_max_m]", "metrics: [a_h_max]",
         "s.yaml:11: sensitivity.metrics[0]: Input should be 'a_h_max_g', 'eps_max_m', "
         "'peak_force_N' or 't_imp_s' (got 'a_h_max'; did you mean 'a_h_max_g'?)"),
        ("one_at_a_time: {deltas_pct: [-10, 10]}", "sobol: {samples: 100}",
         "s.yaml:12: sensitivity.sobol: samples must be a power of two (got 100; try 128)"),
        ("designlab: 1", "designlab: 2", "s.yaml:1: designlab: study format 2 is not supported"),
    ],
)  # fmt: skip
def test_schema_errors_point_at_the_line(old, new, message):
    assert message in _error(SWEEP.replace(old, new, 1))


def test_grid_points_and_tables():
    study = parse_study(SWEEP)
    result = run_study(study)
    frame = result.frame
    assert len(frame) == 12
    assert sorted(set(frame["K_c_N_per_m"])) == [10e3, 20e3, 30e3, 40e3, 50e3, 60e3]
    # a_h,max grows with foam stiffness and falls with head mass (Sec. 3.6-3.7 trends)
    light = frame[frame["M_h_kg"] == 4.4].sort_values("K_c_N_per_m")["a_h_max_g"].to_numpy()
    heavy = frame[frame["M_h_kg"] == 5.3].sort_values("K_c_N_per_m")["a_h_max_g"].to_numpy()
    assert np.all(np.diff(light) > 0) and np.all(heavy < light)
    # AD elasticity agrees with the one-at-a-time sensitivity at +-10 % to first order
    el = result.sensitivity["elasticity"].frame.set_index(["metric", "parameter"])["elasticity"]
    oat = result.sensitivity["one_at_a_time"].frame
    s = oat[(oat.metric == "a_h_max_g") & (oat.parameter == "foam.stiffness")]["S_pct"].mean()
    assert s / 100 == pytest.approx(el["a_h_max_g", "foam.stiffness"], rel=0.05)
    assert el["a_h_max_g", "impact_velocity"] == pytest.approx(1.0, abs=1e-9)  # linear in v_c


def test_seeded_samples_are_reproducible():
    text = SWEEP.replace("method: grid", "method: sobol\n  samples: 8").replace(
        "{low: 10e3, high: 60e3, num: 6}", "{low: 10e3, high: 60e3}").replace(
        "{values: [4.4, 5.3]}", "{low: 4.4, high: 5.3}")  # fmt: skip
    a = run_study(parse_study(text)).frame
    b = run_study(parse_study(text)).frame
    assert len(a) == 8 and a.equals(b)
    c = run_study(parse_study(text.replace("samples: 8", "samples: 8\n  seed: 1"))).frame
    assert not np.allclose(a["K_c_N_per_m"], c["K_c_N_per_m"])


def test_sobol_indices_rank_the_dominant_parameter():
    text = SWEEP.replace("{low: 10e3, high: 60e3, num: 6}", "{low: 10e3, high: 60e3, num: 2}")
    text = text.replace("one_at_a_time: {deltas_pct: [-10, 10]}", "sobol: {samples: 64}")
    result = run_study(parse_study(text))
    table = result.sensitivity["sobol"].ranked("a_h_max_g")
    # foam stiffness 10-60 kN/m dominates head mass 4.4-5.3 kg
    assert table["parameter"].tolist() == ["foam.stiffness", "head.mass"]
    assert table["ST"].iloc[0] > 0.8 and table["ST"].iloc[1] < 0.1


def test_store_resume_and_corrupt_chunk(tmp_path, caplog):
    study = parse_study(SWEEP)
    with open_store(tmp_path, study.name) as store:
        first = run_study(study, RunContext(store=store))
    st = first.stats
    # 21 points + the elasticity point; 3 repeats (the base, two tornado ends on the grid)
    assert (st["points"], st["distinct"], st["computed"], st["cached"]) == (22, 19, 19, 0)
    with open_store(tmp_path, study.name) as store:
        again = run_study(study, RunContext(store=store, resume=True))
    assert again.stats["computed"] == 0 and again.stats["cached"] == 19
    assert again.frame.equals(first.frame)
    # damage the sweep chunk's bytes: detected by its checksum, reported, recomputed
    import sqlite3

    path = tmp_path / "sweep_demo.sqlite"
    db = sqlite3.connect(path)
    key, n, data = max(db.execute("SELECT key, n, data FROM chunks"), key=lambda r: r[1])
    db.execute("UPDATE chunks SET data = ? WHERE key = ?", (data[:-3] + b"xyz", key))
    db.commit()
    db.close()
    with caplog.at_level("WARNING"), open_store(tmp_path, study.name) as store:
        fixed = run_study(study, RunContext(store=store, resume=True))
    assert fixed.stats["corrupt"] == 1 and fixed.stats["computed"] == n
    assert "corrupt stored chunk" in caplog.text and key in caplog.text
    assert fixed.frame.equals(first.frame)
    assert "1 corrupt stored chunks were recomputed" in fixed.warnings
    with ChunkStore(path) as store:
        assert store.get_chunk(key)[0] == "ok"
    # rebuilding from the store only: a missing chunk is an error, not a recomputation
    db = sqlite3.connect(path)
    db.execute("DELETE FROM chunks WHERE key = ?", (key,))
    db.commit()
    db.close()
    with pytest.raises(
        CacheIncompleteError, match=f"{n} points of sweep_demo are not in the store"
    ):
        with open_store(tmp_path, study.name) as store:
            run_study(study, RunContext(store=store, cache_only=True))


def test_store_refuses_foreign_and_other_study_files(tmp_path):
    from designlab.analysis.store import StoreError as ReportError

    (tmp_path / "x.sqlite").write_bytes(b"not a database at all" * 10)
    with pytest.raises(ReportError, match="is not a designlab result store"):
        ChunkStore(tmp_path / "x.sqlite").get_chunk("k")
    import sqlite3

    db = sqlite3.connect(tmp_path / "y.sqlite")
    db.execute("CREATE TABLE other (a)")
    db.commit()
    db.close()
    with pytest.raises(ReportError, match="is not a designlab result store"):
        ChunkStore(tmp_path / "y.sqlite").get_chunk("k")
    with ChunkStore(tmp_path / "z.sqlite", study="a") as store:
        store.put_chunk("k", {"y": np.array([1.0])})
    with pytest.raises(ReportError, match="holds the results of study 'a', not 'b'"):
        ChunkStore(tmp_path / "z.sqlite", study="b").get_chunk("k")


@pytest.mark.slow
def test_two_runs_at_once_share_the_store(tmp_path):
    """Two processes writing the same study's store at once: no corruption, same results."""
    script = tmp_path / "twice.py"
    script.write_text(
        textwrap.dedent(f"""\
        import sys
        from designlab.study import RunContext, parse_study, run_study
        from designlab.analysis.store import open_store
        study = parse_study({SWEEP!r})
        with open_store(sys.argv[1], study.name) as store:
            r = run_study(study, RunContext(store=store, resume=True))
        print(r.frame["a_h_max_g"].sum())
        """)
    )
    procs = [subprocess.Popen([sys.executable, str(script), str(tmp_path)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for _ in range(3)]  # fmt: skip
    outs = [p.communicate(timeout=120) for p in procs]
    assert all(p.returncode == 0 for p in procs), outs
    assert outs[0][0] == outs[1][0] == outs[2][0]
    with open_store(tmp_path, "sweep_demo") as store:
        assert store.points() == 18 + 1  # the distinct sweep points and the elasticity point
        for (key,) in store._connect().execute("SELECT key FROM chunks"):
            assert store.get_chunk(key)[0] == "ok"


SLOW_RUNNER = """\
import sys, time
import numpy as np
from designlab.impact.evaluators import impact_metrics_chunk
from designlab.study.kinds.impact_sweep import ImpactSweepStudy


def slow(points, options):
    time.sleep(0.1 * len(points["v_c"]))
    return impact_metrics_chunk(points, options)


slow.chunk_size = 2
ImpactSweepStudy.EVALUATOR = slow
from designlab.cli import app
app(sys.argv[1:], prog_name="designlab")
"""


def _stored_points(path):
    import sqlite3

    if not path.exists():
        return 0
    try:
        db = sqlite3.connect(f"file:{path}?mode=ro", uri=True, timeout=5)
        try:
            return int(db.execute("SELECT COALESCE(SUM(n), 0) FROM chunks").fetchone()[0])
        finally:
            db.close()
    except sqlite3.Error:
        return 0


@pytest.mark.slow
def test_killed_sweep_resumes_with_only_the_missing_points(tmp_path, write_study):
    study = write_study(
        SWEEP.replace("num: 6", "num: 40")
        .replace("one_at_a_time: {deltas_pct: [-10, 10]}", "local: false"),
        "killme.yaml",
    )  # fmt: skip
    script = tmp_path / "slow_designlab.py"
    script.write_text(SLOW_RUNNER)
    cache, out = tmp_path / "cache", tmp_path / "reports"
    args = [sys.executable, str(script), "run", str(study), "-o", str(out),
            "--cache-dir", str(cache)]  # fmt: skip
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    store = cache / "sweep_demo.sqlite"
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and _stored_points(store) < 10:
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=30)
    done = _stored_points(store)
    total = 1 + 80 + 4
    distinct = total - 3  # the base and two tornado ends repeat grid points
    assert 10 <= done < distinct, done
    assert not (out / "sweep_demo").exists()  # no half-written report

    resumed = subprocess.run([*args, "--resume"], capture_output=True, text=True, timeout=120)
    assert resumed.returncode == 0, resumed.stderr
    import re

    found = re.search(r"points: (\d+) \((\d+) computed, (\d+) from the store, 0 failed, "
                      r"3 duplicates merged\)", resumed.stdout)  # fmt: skip
    assert found, resumed.stdout
    points, computed, cached = map(int, found.groups())
    # every chunk finished before the kill is reused; only the rest is computed
    assert (points, cached, computed) == (total, done, distinct - done)
    import pandas as pd

    fresh = run_study(load_study(study))
    got = pd.read_csv(out / "sweep_demo" / "results.csv")
    assert np.allclose(got["a_h_max_g"], fresh.frame["a_h_max_g"], rtol=1e-6)
    # a resumed run writes the same tables as a fresh one, byte for byte
    fresh_out = tmp_path / "fresh"
    clean = subprocess.run([*args[:4], "-o", str(fresh_out), "--cache-dir",
                            str(tmp_path / "cache2")],
                           capture_output=True, text=True, timeout=120)  # fmt: skip
    assert clean.returncode == 0, clean.stderr
    for name in ("results.csv", "sensitivity_range.csv"):
        assert (out / "sweep_demo" / name).read_bytes() == (
            fresh_out / "sweep_demo" / name
        ).read_bytes()


def _default_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def test_sigint_leaves_store_and_exit_code_130(tmp_path, write_study):
    study = write_study(SWEEP.replace("num: 6", "num: 200"), "intr.yaml")
    script = tmp_path / "slow_designlab.py"
    script.write_text(SLOW_RUNNER)
    cache = tmp_path / "cache"
    args = [sys.executable, str(script), "run", str(study), "-o", str(tmp_path / "r"),
            "--cache-dir", str(cache)]  # fmt: skip
    # A shell without job control starts background jobs with SIGINT ignored, and a child
    # inherits that; give the run the default disposition, as a terminal's Ctrl-C finds it.
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "PYTHONUNBUFFERED": "1"},
                            preexec_fn=_default_sigint)  # fmt: skip
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and _stored_points(cache / "sweep_demo.sqlite") < 5:
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 130, err
    assert "interrupted: finished points are kept in" in err and "--resume" in err
    assert not (tmp_path / "r" / "sweep_demo").exists()
    assert _stored_points(cache / "sweep_demo.sqlite") >= 5


def test_foam_envelope_study_runs_and_explains(write_study):
    study = load_study(
        write_study(
            textwrap.dedent(
                """\
                designlab: 1
                kind: foam_envelope_sweep
                name: env
                base: {robot: MANIPULATOR_1, foam: FOAM_1, impact_velocity: 1.25, max_g: 10}
                damping: {low: 0, high: 200, num: 5}
                sweep:
                  method: list
                  parameters:
                    robot.mass: {values: [9.6, 49.4]}
                sensitivity: {metrics: [k_c_max_N_per_m], one_at_a_time: {deltas_pct: [1]}}
                """
            )
        )
    )
    result = run_study(study)
    # Foam 1 is inside the Manipulator 1 envelope (Sec. 3.9); the heavier arm shrinks it
    assert result.base["feasible"] is True and result.base["margin_decades"] > 0
    f = result.frame
    assert f["area_log"].iloc[1] < f["area_log"].iloc[0]
    el = result.sensitivity["elasticity"].frame.set_index("parameter")["elasticity"]
    # a_h,max is linear in v_c, so K_max responds to v_c and to the limit equally and oppositely
    assert el["impact_velocity"] == pytest.approx(-el["max_g"], rel=1e-9)
    s = result.sensitivity["one_at_a_time"].frame.set_index("parameter")["S_pct"]
    assert s["robot.mass"] / 100 == pytest.approx(el["robot.mass"], rel=0.05)


@pytest.mark.slow
def test_resume_of_a_finished_study_leaves_its_report_alone(tmp_path, write_study):
    """--resume with every point stored and an unchanged study: the report is kept as it is."""
    from typer.testing import CliRunner

    from designlab.cli import app

    runner = CliRunner()
    study = write_study(SWEEP.replace("one_at_a_time: {deltas_pct: [-10, 10]}", "local: false"))
    out, cache = tmp_path / "reports", tmp_path / "cache"
    args = ["run", str(study), "-o", str(out), "--cache-dir", str(cache)]
    first = runner.invoke(app, args)
    assert first.exit_code == 0, first.output
    report = out / "sweep_demo"
    before = {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in report.iterdir()}
    assert ".designlab-report.json" in before

    again = runner.invoke(app, [*args, "--resume"])
    assert again.exit_code == 0, again.output
    assert "report up to date" in again.output and "wrote" not in again.output
    assert {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in report.iterdir()} == before

    (report / "results.csv").write_text("tampered")  # a damaged report is rewritten
    fixed = runner.invoke(app, [*args, "--resume"])
    assert "report up to date" not in fixed.output
    assert (report / "results.csv").read_bytes() == before["results.csv"][0]

    study.write_text(study.read_text().replace("name: sweep_demo", "name: sweep_demo\n"
                                               "description: now described"))  # fmt: skip
    edited = runner.invoke(app, [*args, "--resume"])
    assert "report up to date" not in edited.output
    assert "now described" in (report / "summary.md").read_text()

    rebuilt = runner.invoke(app, ["report", str(study), "-o", str(out), "--cache-dir", str(cache)])
    assert rebuilt.exit_code == 0 and "report up to date" not in rebuilt.output


def test_resume_regenerates_the_same_random_sample(tmp_path):
    """An LHS sweep's resume draws the same points again (nothing to keep) and computes none."""
    study = parse_study(
        SWEEP.replace("method: grid", "method: lhs\n  samples: 50\n  seed: 4")
        .replace("{low: 10e3, high: 60e3, num: 6}", "{low: 10e3, high: 60e3, scale: log}")
        .replace("{values: [4.4, 5.3]}", "{low: 4.4, high: 5.3}")
    )  # fmt: skip
    with open_store(tmp_path, "sweep_demo") as store:
        first = run_study(study, RunContext(store=store))
    with open_store(tmp_path, "sweep_demo") as store:
        again = run_study(study, RunContext(store=store, resume=True))
        assert store.points() == first.stats["distinct"]
    assert again.stats["computed"] == 0
    assert again.frame.equals(first.frame)
    assert again.fingerprint == first.fingerprint
    reseeded = parse_study(
        SWEEP.replace("method: grid", "method: lhs\n  samples: 50\n  seed: 5")
        .replace("{low: 10e3, high: 60e3, num: 6}", "{low: 10e3, high: 60e3, scale: log}")
        .replace("{values: [4.4, 5.3]}", "{low: 4.4, high: 5.3}")
    )  # fmt: skip
    with open_store(tmp_path, "sweep_demo") as store:
        other = run_study(reseeded, RunContext(store=store, resume=True))
    assert other.stats["computed"] == other.stats["distinct"] - 1  # all but the base point
    assert not np.array_equal(
        other.frame["K_c_N_per_m"].to_numpy(), first.frame["K_c_N_per_m"].to_numpy()
    )
