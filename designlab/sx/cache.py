"""The disk cache of compiled code, shared by every process and every run.

A compiled artefact is stored under a key, the hash of everything its machine code
depends on (the generated source, the compiler and its version, the flags, the CPU),
in ``compiled/`` of the cache directory: ``$DESIGNLAB_CACHE_DIR`` if set, else the
user cache directory (``$XDG_CACHE_HOME/designlab`` or ``~/.cache/designlab``; on
macOS ``~/Library/Caches/designlab``; on Windows ``%LOCALAPPDATA%\\designlab\\Cache``).
A second process or run loads the stored file instead of compiling. Clear it with
:func:`clear_cache` or ``python -m designlab.sx clear``; deleting the directory is
equally safe.

Each entry is one file ``<key>.<content hash>.so``, written to a temporary name then
renamed (atomic), so a reader never sees half a file; concurrent processes building
the same key take turns on a lock file, and the later ones load what the first
stored. An entry whose content no longer matches the hash in its name (a damaged or
truncated file) is removed and rebuilt. Where the directory cannot be written, code
is compiled to a temporary directory, loaded and the directory removed (nothing is
cached; said once in the log).

Examples
--------
>>> import os
>>> cache_dir() == Path(os.environ[ENV]) if os.environ.get(ENV) else cache_dir().name == "designlab"
True
"""

from __future__ import annotations

import contextlib
import ctypes
import hashlib
import logging
import os
import shutil
import sys
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

try:  # POSIX: processes building the same entry take turns
    import fcntl
except ImportError:  # pragma: no cover - Windows: concurrent builds then both rename
    fcntl = None  # type: ignore[assignment]

__all__ = ["ENV", "cache_dir", "cache_key", "clear_cache", "load_or_build"]

#: The environment variable naming the cache directory.
ENV = "DESIGNLAB_CACHE_DIR"
_SUFFIX = ".so"
_LOG = logging.getLogger("designlab.sx")
_SAID: set[str] = set()


def say_once(message: str, level: int = logging.WARNING) -> None:
    """Log ``message`` the first time only (per process)."""
    if message not in _SAID:
        _SAID.add(message)
        _LOG.log(level, message)


def cache_dir() -> Path:
    """The cache directory: ``$DESIGNLAB_CACHE_DIR``, else the user cache directory."""
    if os.environ.get(ENV):
        return Path(os.environ[ENV])
    if sys.platform == "win32":  # pragma: no cover - not run on this project's machines
        base = Path(os.environ.get("LOCALAPPDATA", Path.home() / "AppData" / "Local"))
        return base / "designlab" / "Cache"
    if sys.platform == "darwin":  # pragma: no cover
        return Path.home() / "Library" / "Caches" / "designlab"
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "designlab"


def clear_cache() -> int:
    """Remove every compiled entry (the loaded ones stay usable); return how many files.

    Examples
    --------
    >>> isinstance(clear_cache(), int)
    True
    """
    root = cache_dir() / "compiled"
    if not root.is_dir():
        return 0
    n = sum(1 for p in root.iterdir() if p.suffix == _SUFFIX)
    shutil.rmtree(root, ignore_errors=True)
    return n


def cache_key(*parts: str) -> str:
    """The key of an entry: a hash of everything its machine code depends on."""
    h = hashlib.sha256()
    for part in parts:
        h.update(len(part).to_bytes(8, "little") + part.encode())
    return h.hexdigest()[:40]


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()[:16]


def _stored(root: Path, key: str) -> Path | None:
    """The intact entry of ``key``, removing damaged ones."""
    for path in sorted(root.glob(f"{key}.*{_SUFFIX}")):
        try:
            if _digest(path) == path.name.split(".")[1]:
                return path
        except OSError:
            continue
        say_once(f"damaged compiled-code cache entry {path} removed; it is rebuilt")
        path.unlink(missing_ok=True)
    return None


@contextlib.contextmanager
def _turn(root: Path, key: str) -> Iterator[None]:
    """Hold the lock of ``key`` (other processes building it wait)."""
    if fcntl is None:  # pragma: no cover
        yield
        return
    with open(root / f"{key}.lock", "a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def _store(root: Path, key: str, build: Callable[[Path], None]) -> Path:
    """Build the entry of ``key`` in a private directory of ``root`` and rename it in place."""
    work = Path(tempfile.mkdtemp(prefix=".build-", dir=root))
    try:
        tmp = work / f"entry{_SUFFIX}"
        build(tmp)
        final = root / f"{key}.{_digest(tmp)}{_SUFFIX}"
        os.replace(tmp, final)
        return final
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _uncached(build: Callable[[Path], None]) -> ctypes.CDLL:
    """Build in a temporary directory, load, remove the directory (the code stays mapped)."""
    work = tempfile.mkdtemp(prefix="designlab_so_")
    try:
        path = Path(work) / f"entry{_SUFFIX}"
        build(path)
        return ctypes.CDLL(str(path))
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _writable_root() -> Path | None:
    root = cache_dir() / "compiled"
    try:
        root.mkdir(parents=True, exist_ok=True)
        probe = tempfile.mkstemp(prefix=".probe-", dir=root)
        os.close(probe[0])
        os.unlink(probe[1])
    except OSError as exc:
        say_once(f"compiled-code cache {root} cannot be written ({exc}); compiling uncached")
        return None
    return root


def load_or_build(key: str, build: Callable[[Path], None]) -> ctypes.CDLL:
    """Load the shared object stored under ``key``, building and storing it if needed.

    Parameters
    ----------
    key
        From :func:`cache_key`.
    build
        Writes the shared object to the path it is given (raises if it cannot).

    Returns
    -------
    ctypes.CDLL
        The loaded library.
    """
    root = _writable_root()
    if root is None:
        return _uncached(build)
    for _attempt in range(2):
        path = _stored(root, key)
        if path is None:
            with _turn(root, key):
                path = _stored(root, key) or _store(root, key, build)
        try:
            return ctypes.CDLL(str(path))
        except OSError as exc:  # stored but not loadable: rebuilt once
            say_once(f"compiled-code cache entry {path} does not load ({exc}); it is rebuilt")
            path.unlink(missing_ok=True)
    return _uncached(build)
