"""The compile caches trust only themselves: a planted, foreign-owned, group-writable or
changed entry is rebuilt (never run), with a warning; the directories are 0700 and the
entries 0600 whatever the umask; a cache directory another user owns, or that group or
others may write, is not used.

Each cache is checked for real: the SX lanes' shared objects (designlab.sx.cache), numba's
pickled index and data files (designlab.sx.jit_cache, with a tiny kernel) and CasADi's
serialised functions (designlab.sx.functions). The planted payloads would create a marker
file if they ran.
"""

from __future__ import annotations

import importlib.util
import logging
import os
import pickle
import shutil
import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import casadi as ca
import pytest
from test_compiler import _check, needs_cc, wrapped_cc

from designlab.sx import compile_lanes, jit
from designlab.sx.functions import cached_function
from designlab.sx.trust import MANIFEST

X, P = ca.SX.sym("x", 2), ca.SX.sym("p")
NOBODY = 65534
as_root = pytest.mark.skipif(
    not hasattr(os, "geteuid") or os.geteuid() != 0, reason="chown to another user needs root"
)


def _foreign(path: Path) -> None:
    os.chown(path, NOBODY, NOBODY)


def _group_writable(path: Path) -> None:
    os.chmod(path, 0o664)


def _changed(path: Path) -> None:
    """Same name, owner and mode; other content (written in place)."""
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0x01
    with open(path, "r+b") as fh:
        fh.write(bytes(data))


HARM: dict[str, Callable[[Path], None]] = {
    "foreign-owned": _foreign,
    "group-writable": _group_writable,
    "changed": _changed,
}
REASON = {
    "foreign-owned": f"owned by uid {NOBODY}, not by this user",
    "group-writable": "writable by group or others (mode 0664)",
    "changed": "differs from what this designlab stored",
}


def _harms() -> list:  # type: ignore[type-arg]
    return [pytest.param(k, marks=as_root) if k == "foreign-owned" else k for k in HARM]


def _warned(caplog: pytest.LogCaptureFixture, *parts: str) -> bool:
    return any(all(p in r.getMessage() for p in parts) for r in caplog.records)


@pytest.fixture
def loose_umask() -> Iterator[None]:
    old = os.umask(0o002)
    try:
        yield
    finally:
        os.umask(old)


def _modes(root: Path) -> dict[str, str]:
    return {
        str(p.relative_to(root)): oct(p.stat().st_mode & 0o777)
        for p in [root, *root.rglob("*")]
        if not p.name.endswith(".lock")
    }


# --- the SX lanes' shared objects ----------------------------------------------------------


def _lanes(name: str):  # type: ignore[no-untyped-def]
    return compile_lanes(ca.Function(name, [X, P], [X * P - 1]), shared=[1])


@needs_cc
def test_lanes_cache_is_private_whatever_the_umask(_private_cache: Path, loose_umask) -> None:
    _check(_lanes("private"))
    modes = _modes(_private_cache)
    assert {m for p, m in modes.items() if p.endswith(".so") or MANIFEST in p} == {"0o600"}
    assert modes["."] == modes["compiled"] == "0o700"


@needs_cc
@pytest.mark.parametrize("harm", _harms())
def test_an_untrusted_lanes_entry_is_rebuilt(
    harm: str,
    tmp_path: Path,
    _private_cache: Path,
    monkeypatch: pytest.MonkeyPatch,
    caplog: pytest.LogCaptureFixture,
) -> None:
    log = wrapped_cc(tmp_path, monkeypatch)
    _check(_lanes(f"harm_{harm.replace('-', '_')}"))
    (entry,) = (_private_cache / "compiled").glob("*.so")
    HARM[harm](entry)
    with caplog.at_level(logging.WARNING, logger="designlab.sx"):
        _check(_lanes(f"harm_{harm.replace('-', '_')}"))
    assert len(log.read_text().splitlines()) == 2  # built again, not loaded
    assert _warned(caplog, "not loaded", str(entry), REASON[harm], "rebuilt")
    (rebuilt,) = (_private_cache / "compiled").glob("*.so")
    st = rebuilt.stat()
    assert (st.st_uid, st.st_mode & 0o777) == (os.geteuid(), 0o600)


PAYLOAD = """
#include <stdio.h>
__attribute__((constructor)) static void planted(void) {
    FILE *f = fopen("%s", "w");
    if (f) fclose(f);
}
"""


@needs_cc
def test_a_planted_shared_object_is_never_loaded(
    tmp_path: Path,
    _private_cache: Path,
    monkeypatch: pytest.MonkeyPatch,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """A shared object whose name carries its own content hash (all the old check
    wanted) is not run: it is not what this designlab stored."""
    import hashlib

    _check(_lanes("planted"))
    (entry,) = (_private_cache / "compiled").glob("*.so")
    marker = tmp_path / "ran"
    src = tmp_path / "planted.c"
    src.write_text(PAYLOAD % marker)
    evil = tmp_path / "planted.so"
    cc = shutil.which("cc") or "gcc"
    subprocess.run([cc, "-shared", "-fPIC", "-o", str(evil), str(src)], check=True)
    data = evil.read_bytes()
    key = entry.name.split(".")[0]
    planted = entry.with_name(f"{key}.{hashlib.sha256(data).hexdigest()[:16]}.so")
    entry.unlink()
    planted.write_bytes(data)
    os.chmod(planted, 0o600)
    with caplog.at_level(logging.WARNING, logger="designlab.sx"):
        _check(_lanes("planted"))
    assert not marker.exists()
    assert _warned(caplog, str(planted), "was not stored by this designlab")


# --- numba's pickled index and data files --------------------------------------------------

TINY = """
from designlab.sx.jit import kernel


@kernel
def tiny(x):
    return 2.0 * x + 1.0
"""
needs_jit = pytest.mark.skipif(not jit.AVAILABLE, reason=f"no compiled kernels: {jit.reason()}")


class _Planted:
    """Unpickling it creates the marker file."""

    def __init__(self, marker: Path) -> None:
        self.marker = str(marker)

    def __reduce__(self):  # type: ignore[no-untyped-def]
        return (open, (self.marker, "w"))


@pytest.fixture
def tiny_kernel(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):  # type: ignore[no-untyped-def]
    """A fresh dispatcher of a one-line kernel at each call, cached under tmp_path/numba."""
    import numba

    source = tmp_path / "src" / "dl_tiny_kernel.py"
    source.parent.mkdir()
    source.write_text(TINY)
    (tmp_path / "numba").mkdir(mode=0o700)  # as jit_cache_dir() makes it
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(tmp_path / "numba"))

    def fresh():  # type: ignore[no-untyped-def]
        sys.modules.pop("dl_tiny_kernel", None)
        spec = importlib.util.spec_from_file_location("dl_tiny_kernel", source)
        module = importlib.util.module_from_spec(spec)  # type: ignore[arg-type]
        spec.loader.exec_module(module)  # type: ignore[union-attr]
        assert module.tiny(3.0) == 7.0
        return module.tiny

    yield fresh
    sys.modules.pop("dl_tiny_kernel", None)


def _hits(f) -> int:  # type: ignore[no-untyped-def]
    return sum(f.stats.cache_hits.values())


@needs_jit
def test_kernel_cache_is_private_and_loads_what_it_stored(
    tmp_path: Path,
    tiny_kernel,
    loose_umask,
    monkeypatch: pytest.MonkeyPatch,
    caplog: pytest.LogCaptureFixture,
) -> None:
    from designlab.sx import cache as sx_cache
    from designlab.sx.jit_cache import COMPILING

    monkeypatch.setattr(sx_cache, "_SAID", set())
    with caplog.at_level(logging.WARNING, logger="designlab.sx"):
        first = tiny_kernel()
    assert _hits(first) == 0 and [r.getMessage() for r in caplog.records] == [COMPILING]
    caplog.clear()
    monkeypatch.setattr(sx_cache, "_SAID", set())
    with caplog.at_level(logging.WARNING, logger="designlab.sx"):
        assert _hits(tiny_kernel()) == 1  # a new dispatcher loads it from disk
    assert caplog.records == []  # loading says nothing
    modes = _modes(tmp_path / "numba")
    assert {m for p, m in modes.items() if Path(p).suffix in (".nbi", ".nbc")} == {"0o600"}
    assert {m for p, m in modes.items() if (tmp_path / "numba" / p).is_dir()} == {"0o700"}


@needs_jit
@pytest.mark.parametrize("suffix", [".nbi", ".nbc"])
@pytest.mark.parametrize("harm", _harms())
def test_an_untrusted_kernel_cache_file_is_rebuilt(
    harm: str, suffix: str, tmp_path: Path, tiny_kernel, caplog: pytest.LogCaptureFixture
) -> None:
    tiny_kernel()
    (entry,) = (tmp_path / "numba").rglob(f"*{suffix}")
    HARM[harm](entry)
    with caplog.at_level(logging.WARNING, logger="designlab.sx"):
        again = tiny_kernel()
    assert _hits(again) == 0  # compiled again, not loaded
    assert _warned(caplog, "not loaded", str(entry), REASON[harm], "rebuilt")
    st = entry.stat()  # stored afresh
    assert (st.st_uid, st.st_mode & 0o777) == (os.geteuid(), 0o600)
    assert _hits(tiny_kernel()) == 1


@needs_jit
def test_a_planted_kernel_index_is_never_unpickled(
    tmp_path: Path, tiny_kernel, caplog: pytest.LogCaptureFixture
) -> None:
    import numba

    tiny_kernel()
    (index,) = (tmp_path / "numba").rglob("*.nbi")
    marker = tmp_path / "ran"
    payload = pickle.dumps(numba.__version__) + pickle.dumps(_Planted(marker))
    index.write_bytes(payload)  # same name, owner and mode 0600
    with caplog.at_level(logging.WARNING, logger="designlab.sx"):
        assert _hits(tiny_kernel()) == 0
    assert not marker.exists()
    assert _warned(caplog, str(index), "differs from what this designlab stored")


# --- CasADi's serialised functions ---------------------------------------------------------


def _built(counter: list[int]):  # type: ignore[no-untyped-def]
    def build() -> ca.Function:
        counter.append(1)
        x = ca.SX.sym("x")
        return ca.Function("f", [x], [3 * x])

    return build


@pytest.mark.parametrize("harm", _harms())
def test_an_untrusted_built_function_is_rebuilt(
    harm: str, tmp_path: Path, _private_cache: Path, caplog: pytest.LogCaptureFixture
) -> None:
    built: list[int] = []
    cached_function(f"trust {harm}", _built(built), (str(tmp_path),))
    (entry,) = (_private_cache / "functions").glob("*.casadi")
    HARM[harm](entry)
    with caplog.at_level(logging.WARNING, logger="designlab.sx"):
        f = cached_function(f"trust {harm}", _built(built), (str(tmp_path),))
    assert len(built) == 2 and float(f(2.0)) == 6.0
    assert _warned(caplog, "not loaded", str(entry), REASON[harm], "rebuilt")


# --- the cache directory itself ------------------------------------------------------------


@pytest.mark.parametrize("harm", ["foreign-owned", "group-writable"])
def test_a_cache_directory_not_ours_alone_is_not_used(
    harm: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """A DESIGNLAB_CACHE_DIR another user owns (or that others may write) is left alone; a
    private temporary cache serves the process."""
    from designlab.sx.cache import private_cache_dir

    if harm == "foreign-owned" and (not hasattr(os, "geteuid") or os.geteuid() != 0):
        pytest.skip("chown to another user needs root")
    shared = tmp_path / "shared"
    shared.mkdir()
    if harm == "foreign-owned":
        _foreign(shared)
    else:
        os.chmod(shared, 0o777)
    before = shared.stat()
    monkeypatch.setenv("DESIGNLAB_CACHE_DIR", str(shared))
    with caplog.at_level(logging.WARNING, logger="designlab.sx"):
        root = private_cache_dir()
    assert root is not None and root != shared and (root.stat().st_mode & 0o777) == 0o700
    assert _warned(caplog, f"compile cache directory {shared} is not used")
    assert list(shared.iterdir()) == []
    after = shared.stat()  # left as it was
    assert (after.st_uid, after.st_mode) == (before.st_uid, before.st_mode)


CHILD = """
import sys
sys.path.insert(0, {src!r})
import dl_tiny_kernel
assert dl_tiny_kernel.tiny(3.0) == 7.0
f = dl_tiny_kernel.tiny
print(sum(f.stats.cache_hits.values()), sum(f.stats.cache_misses.values()))
"""


@needs_jit
@pytest.mark.skipif(not hasattr(os, "fork"), reason="flock is POSIX")
def test_processes_starting_together_compile_a_kernel_once(tmp_path: Path) -> None:
    """Two processes reach a kernel while a third holds its compile lock: when it is
    released, one compiles and stores, the other waits and loads."""
    import fcntl
    from types import SimpleNamespace

    from designlab.sx.jit_cache import compile_lock

    src = tmp_path / "src"
    src.mkdir()
    (src / "dl_tiny_kernel.py").write_text(TINY)
    cache = tmp_path / "numba"
    cache.mkdir(mode=0o700)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    code = CHILD.format(src=str(src))
    tiny = SimpleNamespace(__module__="dl_tiny_kernel", __qualname__="tiny")
    with open(compile_lock(cache, tiny), "a") as held:
        fcntl.flock(held, fcntl.LOCK_EX)
        procs = [
            subprocess.Popen(
                [sys.executable, "-c", code], env=env, stdout=subprocess.PIPE, text=True
            )
            for _ in range(2)
        ]
        try:
            procs[0].wait(timeout=3)  # it cannot finish: it waits for the lock
            raise AssertionError("a process compiled while another held the lock")
        except subprocess.TimeoutExpired:
            pass
        # one lock per kernel: another kernel compiles meanwhile, without waiting
        (src / "dl_other_kernel.py").write_text(TINY.replace("tiny", "other"))
        other = CHILD.format(src=str(src)).replace("tiny", "other")
        done = subprocess.run(
            [sys.executable, "-c", other],
            env=env, capture_output=True, text=True, timeout=300,
        )  # fmt: skip
        assert done.stdout.split() == ["0", "1"], done.stderr
        assert all(p.poll() is None for p in procs)  # still waiting for tiny's lock
    outs = sorted(p.communicate(timeout=300)[0].split() for p in procs)
    assert outs == [["0", "1"], ["1", "0"]]  # one compiled (a miss), the other loaded (a hit)
