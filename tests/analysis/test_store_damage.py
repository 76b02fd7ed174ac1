"""The result store survives damage: real page corruption, read-only directories, name clashes.

Pages are damaged by writing random bytes over them in the SQLite file, as a bad disk
or a stray write would; results are checked against the evaluator called directly.
"""

from __future__ import annotations

import os
import random
import shutil
import sqlite3
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from designlab.analysis.engine import CacheIncompleteError, run_points
from designlab.analysis.store import ChunkStore, StoreError
from designlab.cli import app

POINTS = {"x": np.arange(600.0)}


def cubic(points, options):
    """y = x^3 + c, and a label: cheap, so that a store of many chunks is quick to build."""
    x = points["x"]
    return {"y": x**3 + options["c"], "sign": np.where(x % 2 == 0, "even", "odd")}


def _build(path: Path) -> None:
    with ChunkStore(path) as store:
        run_points(POINTS, cubic, {"c": 1.0}, store=store, chunk_size=5)  # 120 chunks
        store.checkpoint()


def _damage(path: Path, pages: list[int], seed: int = 0) -> None:
    """Random bytes over whole pages (numbered from 1) of the SQLite file."""
    size = 4096
    data = bytearray(path.read_bytes())
    rng = random.Random(seed)
    for page in pages:
        start = (page - 1) * size + (100 if page == 1 else 0)
        data[start : page * size] = bytes(rng.randrange(256) for _ in range(page * size - start))
    path.write_bytes(bytes(data))


def _layout(path: Path) -> tuple[int, list[int]]:
    """The root page of the chunks table and its leaf pages (from SQLite's dbstat)."""
    db = sqlite3.connect(path)
    root = db.execute("SELECT rootpage FROM sqlite_master WHERE name = 'chunks'").fetchone()[0]
    try:
        leaves = [r[0] for r in db.execute(
            "SELECT pageno FROM dbstat WHERE name = 'chunks' AND pagetype = 'leaf'")]  # fmt: skip
    except sqlite3.OperationalError:  # SQLite built without dbstat
        leaves = []
    db.close()
    return root, leaves


def _want() -> list[float]:
    return [x**3 + 1.0 for x in range(600)]


def test_a_damaged_page_is_detected_readable_chunks_kept_the_rest_recomputed(tmp_path):
    path = tmp_path / "s.sqlite"
    _build(path)
    root, leaves = _layout(path)
    hit = [root, leaves[len(leaves) // 2]]
    _damage(path, hit)
    with sqlite3.connect(path) as db, pytest.raises(sqlite3.DatabaseError):
        db.execute("SELECT SUM(n) FROM chunks").fetchone()  # SQLite itself gives up

    # rebuilding from the store only: the lost points are named, nothing is computed
    with ChunkStore(path) as store:
        with pytest.raises(CacheIncompleteError, match=r"points of x are not in the store") as e:
            run_points(POINTS, cubic, {"c": 1.0}, store=store, chunk_size=5, cache_only=True,
                       desc="x")  # fmt: skip
        assert "--resume" in str(e.value)
        assert store.repairs and "kept its" in store.repairs[0]
        kept = len(store)
    assert 0 < kept < 120  # the damaged leaf's chunks are lost, the others kept
    # --resume computes only what was lost; the table is right
    with ChunkStore(path) as store:
        run = run_points(POINTS, cubic, {"c": 1.0}, store=store, chunk_size=5, resume=True)
    assert (run.cached, run.computed) == (5 * kept, 600 - 5 * kept)
    assert run.frame["y"].tolist() == _want()
    with sqlite3.connect(path) as db:
        assert db.execute("PRAGMA integrity_check").fetchone() == ("ok",)
        assert db.execute("SELECT COUNT(*) FROM chunks").fetchone() == (120,)


def test_a_damaged_file_header_is_repaired_too(tmp_path):
    path = tmp_path / "s.sqlite"
    _build(path)
    _damage(path, [1], seed=3)
    with ChunkStore(path) as store:
        run = run_points(POINTS, cubic, {"c": 1.0}, store=store, chunk_size=5, resume=True)
    assert run.computed < 600 and run.frame["y"].tolist() == _want()


def test_a_file_that_is_not_a_store_is_still_refused(tmp_path):
    path = tmp_path / "s.sqlite"
    path.write_bytes(os.urandom(3 * 4096))
    with pytest.raises(StoreError, match="is not a designlab result store"):
        ChunkStore(path).get_chunk("k")
    assert len(path.read_bytes()) == 3 * 4096  # left as it was


def test_two_kinds_with_one_name_never_share_a_store(tmp_path):
    path = tmp_path / "a.sqlite"
    with ChunkStore(path, study="a", kind="impact_sweep") as store:
        store.put_chunk("k", {"y": np.array([1.0])})
    with pytest.raises(StoreError, match="of kind 'impact_sweep', not of kind 'tether_sweep'"):
        ChunkStore(path, study="a", kind="tether_sweep").get_chunk("k")


def _unprivileged() -> list[str]:
    """A command prefix under which directory permissions apply (root ignores them)."""
    if os.name != "posix":
        pytest.skip("POSIX permissions")
    if os.geteuid() != 0:
        return []
    if shutil.which("setpriv") is None:
        pytest.skip("running as root without setpriv: permissions cannot be enforced")
    return ["setpriv", "--bounding-set=-dac_override,-dac_read_search"]


READ_ONLY = """\
import sys
import numpy as np
sys.path.insert(0, {here!r})
from test_store_damage import POINTS, cubic
from designlab.analysis.engine import run_points
from designlab.analysis.store import ChunkStore, StoreError
with ChunkStore({path!r}) as store:
    run = run_points(POINTS, cubic, {{"c": 1.0}}, store=store, chunk_size=5, cache_only=True)
    assert store.read_only
    assert run.frame["y"].tolist() == [x**3 + 1.0 for x in range(600)]
    try:
        store.put_chunk("new", {{"y": np.array([1.0])}})
    except StoreError as exc:
        print("refused:", exc)
"""


def test_a_valid_store_in_a_read_only_directory_is_read(tmp_path):
    prefix = _unprivileged()
    cache = tmp_path / "cache"
    cache.mkdir()
    _build(cache / "s.sqlite")
    script = tmp_path / "read.py"
    script.write_text(READ_ONLY.format(here=str(Path(__file__).parent),
                                       path=str(cache / "s.sqlite")))  # fmt: skip
    cache.chmod(0o555)
    try:
        out = subprocess.run([*prefix, sys.executable, str(script)], capture_output=True,
                             text=True, timeout=300)  # fmt: skip
    finally:
        cache.chmod(0o755)
    assert out.returncode == 0, out.stderr
    assert "refused: cannot write the result store" in out.stdout
    assert "it is read-only" in out.stdout
    assert sorted(p.name for p in cache.iterdir()) == ["s.sqlite"]


STUDY = """\
designlab: 1
kind: impact_sweep
name: demo
base: {robot: MANIPULATOR_1, foam: FOAM_1, head: HEAD_MIN, impact_velocity: 1.25}
sweep:
  method: grid
  parameters:
    foam.stiffness: {low: 10.0e+3, high: 60.0e+3, num: 5}
    head.mass: {values: [4.4, 5.3]}
"""

CASES = """\
designlab: 1
kind: impact_cases
name: cases
cases:
  - {robot: MANIPULATOR_1, foam: FOAM_1, head: TEST_HEAD, impact_velocity: 0.4}
"""


def test_cli_report_and_resume_after_damage_and_a_same_size_edit(tmp_path):
    runner = CliRunner()
    study = tmp_path / "demo.yaml"
    study.write_text(STUDY)
    out, cache = tmp_path / "out", tmp_path / "cache"
    args = ["run", str(study), "-o", str(out), "--cache-dir", str(cache)]
    first = runner.invoke(app, args)
    assert first.exit_code == 0, first.output
    table = (out / "demo" / "results.csv").read_bytes()
    root, _ = _layout(cache / "demo.sqlite")
    _damage(cache / "demo.sqlite", [root])

    report = runner.invoke(app, ["report", str(study), "-o", str(out), "--cache-dir", str(cache)])
    assert report.exit_code == 4, report.output
    assert "11 points of demo are not in the store" in report.output
    assert "--resume" in report.output and "recomputing" not in report.output

    resumed = runner.invoke(app, [*args, "--resume"])
    assert resumed.exit_code == 0, resumed.output
    assert "(11 computed, 0 from the store" in resumed.output
    assert (out / "demo" / "results.csv").read_bytes() == table

    # a results.csv changed in place, size unchanged: not "up to date", rewritten
    edited = table.replace(b"ok", b"ko", 1)
    assert len(edited) == len(table) and edited != table
    (out / "demo" / "results.csv").write_bytes(edited)
    again = runner.invoke(app, [*args, "--resume"])
    assert again.exit_code == 0 and "report up to date" not in again.output
    assert (out / "demo" / "results.csv").read_bytes() == table


def test_cli_report_of_a_kind_without_store_recomputes_and_says_so(tmp_path):
    runner = CliRunner()
    study = tmp_path / "cases.yaml"
    study.write_text(CASES)
    out, cache = tmp_path / "out", tmp_path / "cache"
    ran = runner.invoke(app, ["-v", "run", str(study), "-o", str(out), "--cache-dir", str(cache)])
    assert ran.exit_code == 0, ran.output
    assert ".sqlite" not in ran.output and not cache.exists()  # -v names no unused store
    rebuilt = runner.invoke(app, ["report", str(study), "-o", str(out), "--cache-dir", str(cache)])
    assert rebuilt.exit_code == 0, rebuilt.output
    assert "kind impact_cases keeps no result store" in rebuilt.output
    assert (out / "cases" / "summary.md").exists()


def test_a_sweep_above_its_kinds_cap_is_refused_when_validated():
    import yaml
    from pydantic import ValidationError

    from designlab.study.kinds.impact_sweep import ImpactSweepStudy

    class Capped(ImpactSweepStudy):
        MAX_POINTS = 100

    text = (
        STUDY.replace("method: grid", "method: lhs\n  samples: 1000")
        .replace("num: 5}", "scale: log}")
        .replace("{values: [4.4, 5.3]}", "{low: 4.4, high: 5.3}")
    )
    data = yaml.safe_load(text)
    with pytest.raises(ValidationError, match=r"sweep.samples: the study has 1,001 points"):
        Capped.model_validate(data)
    msg = "evaluates at most 100"
    with pytest.raises(ValidationError, match=msg):
        Capped.model_validate(data)
    assert ImpactSweepStudy.model_validate(data).size() == "1001 points"


def _sound(path: Path) -> None:
    """SQLite's full check passes and no chunk key is stored twice."""
    with sqlite3.connect(path) as db:
        assert db.execute("PRAGMA integrity_check").fetchall() == [("ok",)]
        keys = [r[0] for r in db.execute("SELECT key FROM chunks NOT INDEXED")]
    assert len(keys) == len(set(keys)) == 120


def test_200_random_bytes_on_any_page_leave_right_results_and_a_sound_store(tmp_path):
    """200 random bytes at a seeded place of every page: even where no query of the run walks
    (an index page, a finished leaf) the store is found damaged when opened and repaired, so
    it ends with no repeated chunk row and a passing ``integrity_check``."""
    orig = tmp_path / "orig.sqlite"
    _build(orig)
    pages = orig.stat().st_size // 4096
    rng = random.Random(200)
    for page in range(1, pages + 1):
        path = tmp_path / f"p{page}.sqlite"
        data = bytearray(orig.read_bytes())
        at = (page - 1) * 4096 + rng.randrange(4096 - 200)
        data[at : at + 200] = bytes(rng.randrange(256) for _ in range(200))
        path.write_bytes(bytes(data))
        with ChunkStore(path) as store:
            run = run_points(POINTS, cubic, {"c": 1.0}, store=store, chunk_size=5, resume=True)
            store.checkpoint()
        assert run.frame["y"].tolist() == _want(), page
        _sound(path)


def _index_entry(path: Path, key: str) -> int:
    """The file offset of ``key``'s entry in the chunk key index (the byte after is its rowid)."""
    data = path.read_bytes()
    with sqlite3.connect(path) as db:
        rowid = db.execute("SELECT rowid FROM chunks NOT INDEXED WHERE key = ?", (key,)).fetchone()
    hits = [i for i in range(len(data)) if data.startswith(key.encode(), i)]
    entries = [i for i in hits if data[i + len(key)] == rowid[0]]  # (key, rowid): the index cell
    assert len(entries) == 1, (hits, rowid)
    return entries[0]


def test_an_index_entry_naming_another_row_is_damage_not_another_chunks_result(tmp_path):
    """The row number of one key's index entry changed to another chunk's: a lookup by key
    would return the other chunk's data, checksum intact (a silent wrong result)."""
    path = tmp_path / "s.sqlite"
    _build(path)
    with sqlite3.connect(path) as db:
        (k29, r29), (_, r50) = db.execute(
            "SELECT key, rowid FROM chunks NOT INDEXED WHERE rowid IN (30, 51) ORDER BY rowid"
        ).fetchall()
    at = _index_entry(path, k29) + len(k29)
    data = bytearray(path.read_bytes())
    assert data[at] == r29
    data[at] = r50
    path.write_bytes(bytes(data))
    with sqlite3.connect(path) as db:  # what a plain lookup now gives: chunk 50's data
        assert db.execute("SELECT rowid FROM chunks WHERE key = ?", (k29,)).fetchone() == (r50,)
    with ChunkStore(path) as store:
        run = run_points(POINTS, cubic, {"c": 1.0}, store=store, chunk_size=5, resume=True)
        assert store.repairs and "damaged" in store.repairs[0]
    assert run.frame["y"].tolist() == _want()
    _sound(path)


def test_an_index_key_changed_in_place_never_leads_to_a_second_row(tmp_path):
    """One character of an index entry's key changed: a lookup of that key misses, and an
    ``INSERT OR REPLACE`` would add a second row for it (a failing integrity_check)."""
    path = tmp_path / "s.sqlite"
    _build(path)
    with sqlite3.connect(path) as db:
        key = db.execute("SELECT key FROM chunks NOT INDEXED WHERE rowid = 30").fetchone()[0]
    at = _index_entry(path, key) + len(key) - 1
    data = bytearray(path.read_bytes())
    data[at] = ord("0") if data[at] != ord("0") else ord("1")
    path.write_bytes(bytes(data))
    with ChunkStore(path) as store:
        run = run_points(POINTS, cubic, {"c": 1.0}, store=store, chunk_size=5, resume=True)
        store.checkpoint()
    assert run.frame["y"].tolist() == _want()
    _sound(path)


def test_a_symlinked_or_empty_store_is_refused_not_turned_into_a_store(tmp_path):
    runner = CliRunner()
    study = tmp_path / "demo.yaml"
    study.write_text(STUDY)
    cache, elsewhere = tmp_path / "cache", tmp_path / "elsewhere"
    cache.mkdir()
    elsewhere.mkdir()
    target = elsewhere / "notes.txt"
    target.write_bytes(b"")
    (cache / "demo.sqlite").symlink_to(target)
    args = ["report", str(study), "-o", str(tmp_path / "out"), "--cache-dir", str(cache)]
    result = runner.invoke(app, args)
    assert result.exit_code == 1, result.output
    assert "demo.sqlite is a symbolic link; a result store must be a regular file" in result.output
    assert target.read_bytes() == b""  # not turned into a store
    with pytest.raises(StoreError, match="is a symbolic link"):
        ChunkStore(cache / "demo.sqlite").put_chunk("k", {"y": np.array([1.0])})
    assert target.read_bytes() == b""
    (cache / "demo.sqlite").unlink()
    (cache / "demo.sqlite").write_bytes(b"")
    result = runner.invoke(app, args)
    assert result.exit_code == 1, result.output
    assert "demo.sqlite is an empty file, not a designlab result store" in result.output
    assert (cache / "demo.sqlite").read_bytes() == b""
