"""The disk cache of compiled code: a second process loads instead of compiling, concurrent
processes build an entry once, a damaged entry is rebuilt, the cache can be cleared."""

from __future__ import annotations

import logging
import os
import subprocess
import sys
from pathlib import Path

import casadi as ca
import pytest
from test_compiler import _check, needs_cc, wrapped_cc

from designlab.sx import cache_dir, clear_cache, compile_lanes
from designlab.sx.__main__ import main

X, P = ca.SX.sym("x", 2), ca.SX.sym("p")
CHILD = """
import casadi as ca, numpy as np
from designlab.sx import compile_lanes
x, p = ca.SX.sym("x", 2), ca.SX.sym("p")
call = compile_lanes(ca.Function({name!r}, [x, p], [x * p - 1]), shared=[1]).bind(3)
call.inp[0][:] = np.arange(6.0); call.inp[1][:] = 2.0; call()
assert (call.out[0] == 2.0 * np.arange(6.0) - 1.0).all()
"""


def _replace(path: Path, data: bytes) -> None:
    tmp = path.with_suffix(".tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def _builds(log: Path) -> int:
    return len(log.read_text().splitlines())


def _children(name: str, n: int) -> None:
    procs = [
        subprocess.Popen([sys.executable, "-c", CHILD.format(name=name)], env=dict(os.environ))
        for _ in range(n)
    ]
    assert [p.wait(timeout=300) for p in procs] == [0] * n


@needs_cc
def test_other_processes_load_what_one_compiled(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    log = wrapped_cc(tmp_path, monkeypatch)
    f = ca.Function("cached", [X, P], [X * P - 1])
    _check(compile_lanes(f, shared=[1]))
    _check(compile_lanes(f, shared=[1]))
    assert _builds(log) == 1
    _children("cached", 1)  # a second process (a later run) loads it
    assert _builds(log) == 1
    _children("fresh", 2)  # two processes at once: one builds, the other waits and loads
    assert _builds(log) == 2
    entries = sorted((cache_dir() / "compiled").glob("*.so"))
    assert len(entries) == 2 and not list((cache_dir() / "compiled").glob(".build-*"))


@needs_cc
def test_a_damaged_entry_is_detected_and_rebuilt(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    log = wrapped_cc(tmp_path, monkeypatch)
    f = ca.Function("damaged", [X, P], [X * P - 1])
    compile_lanes(f, shared=[1])
    (entry,) = (cache_dir() / "compiled").glob("*.so")
    data = bytearray(entry.read_bytes())
    data[len(data) // 2] ^= 0xFF  # one flipped byte (a new file: the loaded one stays mapped)
    _replace(entry, bytes(data))
    with caplog.at_level(logging.WARNING, logger="designlab.sx"):
        _check(compile_lanes(f, shared=[1]))
    assert _builds(log) == 2
    assert any("differs from what this designlab stored" in r.getMessage() for r in caplog.records)
    _replace(entry, data[:100])  # truncated
    _children("damaged", 1)
    assert _builds(log) == 3


@needs_cc
def test_the_cache_is_cleared(capsys: pytest.CaptureFixture[str]) -> None:
    compile_lanes(ca.Function("cleared", [X, P], [X * P - 1]), shared=[1])
    assert main(["clear"]) == 0
    assert "removed 1 compiled entries" in capsys.readouterr().out
    assert clear_cache() == 0
    main(["info"])
    assert str(cache_dir()) in capsys.readouterr().out


@needs_cc
def test_an_unwritable_cache_uses_a_private_temporary_one(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    blocker = tmp_path / "a file"
    blocker.write_text("")
    monkeypatch.setenv("DESIGNLAB_CACHE_DIR", str(blocker / "cache"))  # cannot be created
    log = wrapped_cc(tmp_path, monkeypatch)
    f = ca.Function("uncached", [X, P], [X * P - 1])
    with caplog.at_level(logging.WARNING, logger="designlab.sx"):
        _check(compile_lanes(f, shared=[1]))
        _check(compile_lanes(f, shared=[1]))
    assert _builds(log) == 1  # the second call loads from the process's temporary cache
    assert blocker.read_text() == ""
    said = " ".join(r.getMessage() for r in caplog.records)
    assert f"compile cache directory {blocker / 'cache'} is not used" in said
