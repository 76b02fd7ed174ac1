"""numba's on-disk cache of compiled kernels, loaded only as this designlab stored it.

numba stores each cached function as an index file (``.nbi``) and data files
(``.nbc``), both pickles, and unpickles them lazily, when a function is first
called with a signature: a planted or changed file would run code in the process.
:func:`verify_cache` gives a compiled kernel's cache the checks of
:mod:`designlab.sx.trust`: every index and data file is written 0600 with its
SHA-256 recorded in the directory's manifest, and read back (under the directory's
lock, the bytes checked being the bytes unpickled) only if it is a regular file of
this user, not writable by group or others, with the recorded hash. A file failing
a check is removed with a warning, and numba compiles the function again and
stores it afresh. A process that compiles a kernel missing from the cache says so once
(:data:`COMPILING`), so a first call's minute is not a mystery. Where numba's cache is
not the one this module knows (another numba version), or its directory is not
private, caching is turned off for the function (compiled in every process, said
once). Processes compiling kernels at the
same time take turns (:func:`_compile_once`): each kernel is compiled once, the others
wait and load it.

Examples
--------
>>> from designlab.sx import jit
>>> from designlab.impact.kernel_modal import shape
>>> not jit.AVAILABLE or type(shape._cache._cache_file).__name__ == "VerifiedCacheFile"
True
"""

from __future__ import annotations

import contextlib
import functools
import io
import os
import pickle
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from designlab.sx.cache import say_once
from designlab.sx.trust import Shelf, private_dir

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX: no lock, numba's own behaviour
    fcntl = None  # type: ignore[assignment]

__all__ = ["COMPILING", "compile_lock", "verify_cache"]

#: Said once (a log warning) when a process compiles a kernel that was not in the cache.
COMPILING = (
    "compiling designlab's numeric kernels (numba) for their first use with this cache: this "
    "can take a minute or more, once; later processes load them from the cache "
    "(`designlab compile` compiles everything ahead)"
)


@functools.cache
def _verified_class() -> type | None:
    """numba's ``IndexDataCacheFile`` with the checks (``None`` if numba has none)."""
    try:
        from numba.core.caching import IndexDataCacheFile
    except ImportError:  # pragma: no cover - another numba layout
        return None
    needed = ("save", "load", "_load_index", "_save_index", "_load_data", "_save_data", "_dump")
    if not all(hasattr(IndexDataCacheFile, name) for name in needed):  # pragma: no cover
        return None

    class VerifiedCacheFile(IndexDataCacheFile):  # type: ignore[misc, valid-type]
        """Index and data files stored 0600 with their hash; loaded only when they match."""

        def _shelf(self) -> Shelf:
            return Shelf(Path(self._cache_path))

        def save(self, key: Any, data: Any) -> None:
            with self._shelf().locked():
                super().save(key, data)

        def load(self, key: Any) -> Any:
            with self._shelf().locked():
                data = super().load(key)
            if data is None:  # numba compiles it now
                say_once(COMPILING)
            return data

        def _load_index(self) -> dict[Any, Any]:
            data = self._shelf().load(self._index_name, "compiled-kernel index")
            if data is None:
                return {}
            stream = io.BytesIO(data)
            if pickle.load(stream) != self._version:
                return {}
            stamp, overloads = pickle.loads(stream.read())
            return overloads if stamp == self._source_stamp else {}

        def _save_index(self, overloads: dict[Any, Any]) -> None:
            data = self._dump((self._source_stamp, overloads))
            version = pickle.dumps(self._version, protocol=-1)
            self._shelf().write(self._index_name, version + data)

        def _load_data(self, name: str) -> Any:
            data = self._shelf().load(name, "compiled-kernel")
            if data is None:
                raise OSError(f"compiled-kernel cache entry {name} is not loaded")
            return pickle.loads(data)

        def _save_data(self, name: str, data: Any) -> None:
            self._shelf().write(name, self._dump(data))

    return VerifiedCacheFile


def _private_path(root: Path, path: Path) -> None:
    """Check (and make 0700) each directory from ``root`` down to ``path``.

    Raises
    ------
    OSError
        A directory on the way is not this user's alone.
    """
    try:
        parts = path.relative_to(root).parts
    except ValueError:  # numba chose another place (next to the sources): check it alone
        private_dir(path, tighten=False)
        return
    private_dir(root, tighten=False)
    for i in range(len(parts)):
        private_dir(root.joinpath(*parts[: i + 1]))


def verify_cache(dispatcher: Any) -> None:
    """Make ``dispatcher``'s numba cache load only what this designlab stored.

    Parameters
    ----------
    dispatcher
        A ``numba.njit(cache=True)`` dispatcher.
    """
    cache = getattr(dispatcher, "_cache", None)
    cache_file = getattr(cache, "_cache_file", None)
    verified = _verified_class()
    if cache_file is None or getattr(cache_file, "_cache_path", None) is None:
        return  # no disk cache (caching off)
    try:
        if verified is None or not isinstance(cache_file, verified.__mro__[1]):
            raise OSError("numba's cache is not the one designlab knows how to check")
        from numba.core import config

        path = Path(cache_file._cache_path)
        _private_path(Path(config.CACHE_DIR or path), path)
    except OSError as exc:
        cache.disable()
        say_once(
            f"numba's disk cache is off for the compiled kernels ({exc}): they are compiled "
            "in every process"
        )
        return
    cache_file.__class__ = verified
    _compile_once(dispatcher, Path(config.CACHE_DIR or path))


#: lock files of kernels this process is compiling (re-entrant; guarded by numba's
#: compiler lock, which every compile holds first)
_HELD: dict[str, int] = {}


@contextlib.contextmanager
def _kernel_lock(path: Path) -> Iterator[None]:
    """Hold the exclusive lock of ``path`` (re-entrant in this process)."""
    key = str(path)
    if _HELD.get(key) or fcntl is None:
        _HELD[key] = _HELD.get(key, 0) + 1
        try:
            yield
        finally:
            _HELD[key] -= 1
        return
    fd = os.open(path, os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0), 0o600)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        _HELD[key] = 1
        try:
            yield
        finally:
            _HELD[key] = 0
    finally:
        os.close(fd)  # releases the lock


def compile_lock(root: Path, func: Any) -> Path:
    """The lock file in the cache ``root`` that processes compiling ``func`` take turns on.

    Parameters
    ----------
    root
        numba's cache directory.
    func
        The Python function of a kernel.

    Returns
    -------
    pathlib.Path
        ``root/.compile-<module>.<qualified name>.lock``.
    """
    name = re.sub(r"[^A-Za-z0-9_.-]", "_", f"{func.__module__}.{func.__qualname__}")
    return Path(root) / f".compile-{name}.lock"


def _compile_once(dispatcher: Any, root: Path) -> None:
    """Processes compiling a kernel take turns on its lock file in the cache (``root``).

    A second process reaching a kernel that another is compiling waits, then loads
    what the first stored instead of compiling it too; a process reaching another
    kernel goes on (one lock per kernel: two workers compile two kernels side by
    side). A kernel's lock is taken inside numba's own compiler lock (one order for
    every thread) and is re-entrant; a kernel compiled while compiling its caller takes
    its own lock after its caller's, so locks are always taken down the call graph
    (no two processes wait for each other).
    """
    from numba.core.compiler_lock import global_compiler_lock

    compile_ = dispatcher.compile
    lock = compile_lock(root, dispatcher.py_func)

    def compile(sig: Any) -> Any:
        with global_compiler_lock, _kernel_lock(lock):
            return compile_(sig)

    dispatcher.compile = compile
