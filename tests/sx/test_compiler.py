"""Compilation without a shell: $CC honoured, hostile temporary paths harmless, nothing left
behind, and CasADi's own evaluation (same results) where no compiler exists."""

from __future__ import annotations

import logging
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from designlab.sx import CompilerError, compile_lanes, compiler_missing_reason, try_compile_lanes

HAVE_CC = compiler_missing_reason() is None
needs_cc = pytest.mark.skipif(
    not HAVE_CC, reason=f"needs a C compiler: {compiler_missing_reason()}"
)
X, P = ca.SX.sym("x", 2), ca.SX.sym("p")
WRAPPER = """import os, subprocess, sys
if "-shared" in sys.argv:
    with open(os.environ["SX_CC_LOG"], "a") as fh:
        fh.write(repr(sys.argv[1:]) + "\\n")
sys.exit(subprocess.call([{cc!r}, *sys.argv[1:]]))
"""


def wrapped_cc(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Set CC to a recording wrapper of the real compiler; return its log (one line a build)."""
    real = shutil.which("cc") or shutil.which("gcc")
    script = tmp_path / "cc_wrapper.py"
    script.write_text(WRAPPER.format(cc=real))
    log = tmp_path / "cc.log"
    log.touch()
    monkeypatch.setenv("CC", f"{shlex.quote(sys.executable)} {shlex.quote(str(script))} -O1")
    monkeypatch.setenv("SX_CC_LOG", str(log))
    return log


def _check(lanes, n: int = 3) -> None:  # type: ignore[no-untyped-def]
    call = lanes.bind(n)
    call.inp[0][:] = np.arange(2.0 * n)
    call.inp[1][:] = 2.0
    call()
    np.testing.assert_array_equal(call.out[0], 2.0 * np.arange(2.0 * n) - 1.0)


@needs_cc
def test_a_hostile_tmpdir_and_cache_dir_run_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    hostile = tmp_path / "a b;touch X;$(touch Y)`touch Z`"
    hostile.mkdir()
    monkeypatch.setenv("TMPDIR", str(hostile))
    monkeypatch.setattr(tempfile, "tempdir", str(hostile))
    monkeypatch.setenv("DESIGNLAB_CACHE_DIR", str(tmp_path / "c d;touch X;"))
    monkeypatch.chdir(tmp_path)
    log = wrapped_cc(tmp_path, monkeypatch)
    _check(compile_lanes(ca.Function("hostile", [X, P], [X * P - 1]), shared=[1]))
    assert len(log.read_text().splitlines()) == 1  # compiled once, by $CC with its option
    assert "-O1" in log.read_text()
    created = {p.name for p in tmp_path.rglob("*")} & {"X", "Y", "Z"}
    assert not created
    assert list(hostile.iterdir()) == []  # the temporary directory is gone


@needs_cc
def test_a_failing_compilation_leaves_nothing_behind(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(tmp))
    cache = tmp_path / "cache"
    monkeypatch.setenv("DESIGNLAB_CACHE_DIR", str(cache))
    cc = shutil.which("cc") or "gcc"
    monkeypatch.setenv("CC", f"{cc} -Wl,--no-such-linker-option")
    f = ca.Function("broken", [X, P], [X * P - 1])
    with pytest.raises(CompilerError, match="compiling 'broken' failed"):
        compile_lanes(f, shared=[1])
    assert list(tmp.iterdir()) == []
    assert [p.name for p in (cache / "compiled").iterdir() if not p.name.endswith(".lock")] == []


def test_no_compiler_is_a_clear_error_and_a_single_log_line(
    monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    monkeypatch.setenv("CC", "/nonexistent/cc")
    assert "no C compiler found" in compiler_missing_reason()  # type: ignore[operator]
    f = ca.Function("nocc", [X, P], [X * P])
    with pytest.raises(CompilerError, match=r"no C compiler found \(CC = '/nonexistent/cc'"):
        compile_lanes(f, shared=[1])
    with caplog.at_level(logging.WARNING, logger="designlab.sx"):
        assert try_compile_lanes(f, shared=[1]) is None
        assert try_compile_lanes(ca.Function("nocc2", [X, P], [X + P]), shared=[1]) is None
    said = [r.getMessage() for r in caplog.records if "CasADi's own evaluation" in r.getMessage()]
    assert len(said) <= 1  # once per process (it may have been said by an earlier test)


def test_navigation_without_a_compiler_uses_casadi_with_the_same_results(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import designlab as dl
    from designlab.navigation import engine

    nav = dl.navigation
    monkeypatch.setenv("CC", "/nonexistent/cc")
    engine._lane_step.cache_clear()
    sc = nav.configuration(1)
    gains = nav.OPTIMAL_GAINS.as_array()[None, :] * np.array([[1.0], [0.8], [1.2]])
    try:
        jit = engine.run(sc, gains, stabilising=False, jit=True)
    finally:
        engine._lane_step.cache_clear()
    vm = engine.run(sc, gains, stabilising=False)
    np.testing.assert_array_equal(jit.arrival_time, vm.arrival_time)
    np.testing.assert_array_equal(jit.min_distance, vm.min_distance)
    np.testing.assert_array_equal(jit.energy, vm.energy)


def test_the_compiled_code_tests_skip_with_the_reason_without_a_compiler(tmp_path: Path) -> None:
    env = {**os.environ, "CC": "/nonexistent/cc", "DESIGNLAB_CACHE_DIR": str(tmp_path)}
    test = Path(__file__).with_name("test_lanes.py")
    out = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-rs", "-p", "no:cacheprovider", str(test)],
        capture_output=True,
        text=True,
        env=env,
        cwd=Path(__file__).parents[2],
    )
    assert out.returncode == 0, out.stdout[-2000:]
    assert "skipped" in out.stdout and "failed" not in out.stdout
    assert "needs a C compiler: no C compiler found (CC = '/nonexistent/cc'" in out.stdout
