"""What the compile caches load: only what this user's designlab stored there.

Compiled code is machine code (a shared object) or a pickle (numba's index and data
files, CasADi's serialised functions can name a library to load): loading an entry
runs it. An entry is therefore loaded only when

* its directory is private (:func:`private_dir`: owned by this user, created 0700,
  not writable by group or others),
* the entry is a regular file (not a symbolic link, FIFO or device) owned by this
  user and not writable by group or others, and
* the SHA-256 of the bytes read matches the one recorded when designlab stored the
  entry, in the directory's manifest (:data:`MANIFEST`, itself 0600 and owned by
  this user). The bytes checked are the bytes used: nothing is read twice.

Entries are written 0600 whatever the umask, to a temporary name then renamed, the
manifest first (so a reader never finds an entry the manifest does not know); writers
and readers of one directory take turns on a lock file. An entry failing a check is
removed and rebuilt, with a warning naming it and why.

Examples
--------
>>> import tempfile
>>> tmp = tempfile.TemporaryDirectory()
>>> shelf = Shelf(private_dir(Path(tmp.name) / "cache"))
>>> _ = shelf.write("entry", b"data")
>>> shelf.read("entry")
b'data'
>>> [oct(os.stat(p).st_mode & 0o777) for p in (shelf.directory, shelf.directory / "entry")]
['0o700', '0o600']
>>> os.chmod(shelf.directory / "entry", 0o664)
>>> shelf.load("entry", "example") is None     # refused (and removed), with a warning
True
>>> tmp.cleanup()
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import logging
import os
import stat
import tempfile
import threading
from collections.abc import Iterator
from pathlib import Path

try:  # POSIX: writers and readers of a directory take turns
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]

__all__ = ["MANIFEST", "Shelf", "UntrustedError", "private_dir", "untrusted_reason"]

#: The file, in each cache directory, recording the SHA-256 of every entry designlab wrote.
MANIFEST = ".designlab-manifest"
_LOG = logging.getLogger("designlab.sx")
_GUARD = threading.RLock()
_HELD: dict[str, int] = {}


class UntrustedError(OSError):
    """A cache directory or entry that this user's designlab did not write (or that
    someone else could have changed since)."""


def _uid() -> int | None:
    return os.geteuid() if hasattr(os, "geteuid") else None


def untrusted_reason(st: os.stat_result) -> str:
    """``""`` if ``st`` is owned by this user and not writable by group or others, else why not.

    Parameters
    ----------
    st
        The ``os.stat`` (or ``os.lstat``/``os.fstat``) result of the file or directory.

    Examples
    --------
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     untrusted_reason(os.stat(tmp))
    ''
    """
    uid = _uid()
    if uid is None:  # pragma: no cover - no POSIX owners and modes (Windows): the hash decides
        return ""
    if st.st_uid != uid:
        return f"owned by uid {st.st_uid}, not by this user (uid {uid})"
    if st.st_mode & 0o022:
        return f"writable by group or others (mode {stat.S_IMODE(st.st_mode):04o})"
    return ""


def private_dir(path: Path, *, tighten: bool = True) -> Path:
    """``path`` as a directory only this user can change: created 0700 when missing.

    Parameters
    ----------
    path
        The directory (its parents are created with the usual modes when missing).
    tighten
        An existing directory of this user that group or others may write is made
        0700 (for directories only designlab uses); otherwise it is refused.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    UntrustedError
        Not a directory, owned by another user, or writable by group or others.
    OSError
        It cannot be created.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        os.mkdir(path, 0o700)
        os.chmod(path, 0o700)  # whatever the umask
    except FileExistsError:
        pass
    st = os.stat(path)
    if not stat.S_ISDIR(st.st_mode):
        raise UntrustedError(f"{path} is not a directory")
    reason = untrusted_reason(st)
    if reason and tighten and st.st_uid == _uid():
        os.chmod(path, 0o700)
        reason = untrusted_reason(os.stat(path))
    if reason:
        raise UntrustedError(f"{path} is {reason}")
    return path


def _read_checked(path: Path) -> bytes:
    """The bytes of ``path`` if it is a regular file of this user that only it can write."""
    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    try:
        fd = os.open(path, flags | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        if isinstance(exc, FileNotFoundError):
            raise
        raise UntrustedError(f"{path} cannot be opened safely ({exc})") from None
    with os.fdopen(fd, "rb") as fh:
        st = os.fstat(fh.fileno())
        if not stat.S_ISREG(st.st_mode):
            raise UntrustedError(f"{path} is not a regular file")
        reason = untrusted_reason(st)
        if reason:
            raise UntrustedError(f"{path} is {reason}")
        return fh.read()


def _write_private(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path``, mode 0600, through a temporary name and a rename."""
    fd, tmp = tempfile.mkstemp(prefix=".tmp-", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            if hasattr(os, "fchmod"):
                os.fchmod(fh.fileno(), 0o600)
            fh.write(data)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


class Shelf:
    """The entries of one cache directory, loaded only as this designlab stored them.

    Parameters
    ----------
    directory
        A private directory (:func:`private_dir`).
    """

    def __init__(self, directory: Path) -> None:
        self.directory = Path(directory)

    @contextlib.contextmanager
    def locked(self) -> Iterator[None]:
        """Hold the directory's lock (re-entrant in this process)."""
        key = str(self.directory)
        with _GUARD:
            if _HELD.get(key) or fcntl is None:
                _HELD[key] = _HELD.get(key, 0) + 1
                try:
                    yield
                finally:
                    _HELD[key] -= 1
                return
            flags = os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0)
            fd = os.open(self.directory / f"{MANIFEST}.lock", flags, 0o600)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX)
                _HELD[key] = 1
                try:
                    yield
                finally:
                    _HELD[key] = 0
            finally:
                os.close(fd)  # releases the lock

    def _manifest(self) -> dict[str, str]:
        try:
            text = _read_checked(self.directory / MANIFEST)
            entries = json.loads(text)["entries"]
        except FileNotFoundError:
            return {}
        except (OSError, ValueError, KeyError, TypeError) as exc:
            _LOG.warning(
                "compile cache manifest %s is not trusted (%s): every entry of %s is rebuilt",
                self.directory / MANIFEST, exc, self.directory,
            )  # fmt: skip
            return {}
        if not isinstance(entries, dict):
            return {}
        return {str(k): str(v) for k, v in entries.items()}

    def read(self, name: str) -> bytes:
        """The bytes of entry ``name``, checked (owner, mode, recorded hash).

        Raises
        ------
        FileNotFoundError
            No such entry.
        UntrustedError
            It fails a check.
        """
        with self.locked():
            data = _read_checked(self.directory / name)
            recorded = self._manifest().get(name)
        if recorded is None:
            raise UntrustedError(f"{self.directory / name} was not stored by this designlab")
        if hashlib.sha256(data).hexdigest() != recorded:
            raise UntrustedError(
                f"{self.directory / name} differs from what this designlab stored (changed since)"
            )
        return data

    def load(self, name: str, what: str) -> bytes | None:
        """:meth:`read`, or ``None`` (the entry removed, with a warning) where it fails a check.

        Parameters
        ----------
        name
            The entry.
        what
            What the entry is, for the warning ("compiled code").
        """
        try:
            return self.read(name)
        except FileNotFoundError:
            return None
        except OSError as exc:
            _LOG.warning("%s cache entry not loaded: %s; it is rebuilt", what, exc)
            self.discard(name)
            return None

    def write(self, name: str, data: bytes) -> Path:
        """Store ``data`` as entry ``name`` (0600), its SHA-256 recorded first."""
        path = self.directory / name
        with self.locked():
            entries = self._manifest()
            present = set(os.listdir(self.directory))
            entries = {k: v for k, v in entries.items() if k in present}
            entries[name] = hashlib.sha256(data).hexdigest()
            manifest = json.dumps({"version": 1, "entries": entries}, sort_keys=True)
            _write_private(self.directory / MANIFEST, manifest.encode())
            _write_private(path, data)
        return path

    def discard(self, name: str) -> None:
        """Remove entry ``name`` (if it is there)."""
        with contextlib.suppress(OSError):
            (self.directory / name).unlink()
