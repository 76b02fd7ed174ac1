"""The disk cache of compiled code, shared by every process and every run.

A compiled artefact is stored under a key, the hash of everything its machine code
depends on (the generated source, the compiler and its version, the flags, the CPU),
in ``compiled/`` of the cache directory: ``$DESIGNLAB_CACHE_DIR`` if set, else the
user cache directory (``$XDG_CACHE_HOME/designlab`` or ``~/.cache/designlab``; on
macOS ``~/Library/Caches/designlab``; on Windows ``%LOCALAPPDATA%\\designlab\\Cache``).
A second process or run loads the stored file instead of compiling. Clear it with
:func:`clear_cache` or ``python -m designlab.sx clear``; deleting the directory is
equally safe.

Each entry is one file ``<key>.<content hash>.so``, written 0600 to a temporary name
then renamed (atomic), so a reader never sees half a file; concurrent processes
building the same key take turns on a lock file, and the later ones load what the
first stored. The cache trusts only itself (:mod:`designlab.sx.trust`): the directory
is created 0700 and must be this user's alone (else a private temporary cache of the
process is used, with a warning), and an entry is loaded only if it is this user's,
not writable by group or others, and its bytes have the SHA-256 recorded in the
directory's manifest when this designlab stored it; an entry failing a check (a
damaged, truncated, planted or changed file) is removed and rebuilt, with a warning.
The checked bytes are the ones loaded (copied to a private file of the process, so
the entry cannot change between check and load). Where no directory can be written,
code is compiled to a temporary directory, loaded and the directory removed (nothing
is cached; said once in the log).

Examples
--------
>>> import os
>>> cache_dir() == Path(os.environ[ENV]) if os.environ.get(ENV) else cache_dir().name == "designlab"
True
"""

from __future__ import annotations

import atexit
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

from designlab.sx.trust import Shelf, private_dir

try:  # POSIX: processes building the same entry take turns
    import fcntl
except ImportError:  # pragma: no cover - Windows: concurrent builds then both rename
    fcntl = None  # type: ignore[assignment]

__all__ = [
    "ENV", "cache_dir", "cache_key", "clear_cache", "load_or_build", "private_cache_dir",
    "private_cache_subdir",
]  # fmt: skip

#: The environment variable naming the cache directory.
ENV = "DESIGNLAB_CACHE_DIR"
_SUFFIX = ".so"
_LOG = logging.getLogger("designlab.sx")
_SAID: set[str] = set()
_FALLBACK: Path | None = None


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


def _fallback() -> Path | None:
    """A private temporary cache for this process (removed at exit), or ``None``."""
    global _FALLBACK
    if _FALLBACK is None:
        try:
            _FALLBACK = Path(tempfile.mkdtemp(prefix="designlab-cache-"))
        except OSError as exc:
            say_once(f"no private temporary cache directory ({exc}); compiling uncached")
            return None
        atexit.register(shutil.rmtree, _FALLBACK, ignore_errors=True)
    return _FALLBACK


def private_cache_dir() -> Path | None:
    """:func:`cache_dir`, created 0700 and checked to be this user's alone.

    A directory owned by another user, or that group or others may write (a
    ``$DESIGNLAB_CACHE_DIR`` such as ``/tmp``), is not used: a private temporary
    cache of this process replaces it, with a warning. The default directory
    (``~/.cache/designlab``) of this user is made 0700 if it was not.

    Returns
    -------
    Path or None
        ``None`` where not even a temporary directory can be made.
    """
    root = cache_dir()
    try:
        return private_dir(root, tighten=not os.environ.get(ENV))
    except OSError as exc:
        say_once(
            f"compile cache directory {root} is not used ({exc}): compiled code is cached in a "
            "private temporary directory for this process only (give DESIGNLAB_CACHE_DIR a "
            "directory of your own that only you can write)"
        )
    return _fallback()


def private_cache_subdir(name: str) -> Path | None:
    """``<private_cache_dir()>/name``, created 0700 and checked (or ``None``).

    Parameters
    ----------
    name
        The subdirectory's name (one path component).
    """
    root = private_cache_dir()
    if root is None:
        return None
    try:
        return private_dir(root / name)
    except OSError as exc:
        say_once(f"compile cache directory {root / name} is not used ({exc}); compiling uncached")
        return None


def _stored(shelf: Shelf, key: str) -> bytes | None:
    """The checked bytes of the entry of ``key`` (entries failing a check are removed)."""
    for path in sorted(shelf.directory.glob(f"{key}.*{_SUFFIX}")):
        data = shelf.load(path.name, "compiled-code")
        if data is not None:
            return data
    return None


@contextlib.contextmanager
def _turn(root: Path, key: str) -> Iterator[None]:
    """Hold the lock of ``key`` (other processes building it wait)."""
    if fcntl is None:  # pragma: no cover
        yield
        return
    fd = os.open(root / f"{key}.lock", os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0), 0o600)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)


def _store(shelf: Shelf, key: str, build: Callable[[Path], None]) -> bytes:
    """Build the entry of ``key`` in a private directory and store it (0600, recorded)."""
    work = Path(tempfile.mkdtemp(prefix=".build-", dir=shelf.directory))
    try:
        tmp = work / f"entry{_SUFFIX}"
        build(tmp)
        data = tmp.read_bytes()
    finally:
        shutil.rmtree(work, ignore_errors=True)
    digest = hashlib.sha256(data).hexdigest()[:16]
    shelf.write(f"{key}.{digest}{_SUFFIX}", data)
    return data


def _dlopen(directory: Path, data: bytes) -> ctypes.CDLL:
    """Load the checked bytes ``data`` from a file of this process (nothing read twice)."""
    fd, path = tempfile.mkstemp(prefix=".load-", suffix=_SUFFIX, dir=directory)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        return ctypes.CDLL(path)
    finally:
        os.unlink(path)  # the code stays mapped


def _uncached(build: Callable[[Path], None]) -> ctypes.CDLL:
    """Build in a temporary directory, load, remove the directory (the code stays mapped)."""
    work = tempfile.mkdtemp(prefix="designlab_so_")
    try:
        path = Path(work) / f"entry{_SUFFIX}"
        build(path)
        return ctypes.CDLL(str(path))
    finally:
        shutil.rmtree(work, ignore_errors=True)


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
    root = private_cache_subdir("compiled")
    if root is None:
        return _uncached(build)
    shelf = Shelf(root)
    for _attempt in range(2):
        data = _stored(shelf, key)
        if data is None:
            with _turn(root, key):
                data = _stored(shelf, key) or _store(shelf, key, build)
        try:
            return _dlopen(root, data)
        except OSError as exc:  # stored but not loadable: rebuilt once
            say_once(f"compiled-code cache entry of {key} does not load ({exc}); it is rebuilt")
            for path in root.glob(f"{key}.*{_SUFFIX}"):
                shelf.discard(path.name)
    return _uncached(build)
