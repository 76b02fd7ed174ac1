"""Atomic file and directory writes.

Every file designlab writes goes through :func:`atomic_write_bytes`: the data
are written to a temporary file in the destination directory, flushed to disk
(``fsync``) and moved over the destination with :func:`os.replace`, so a
reader sees either the old file or the new one, never half of one.

A report directory is built with :func:`report_directory`: files are written
into a hidden temporary sibling directory, which replaces the previous
report only when everything has been written. An exception (or Ctrl-C)
while writing removes the temporary directory and leaves the previous
report untouched. The swap (and the tidying up after a run killed mid-swap)
holds an exclusive lock on the parent directory (``flock``, released by the
system if the process dies), so that runs writing the same report at once,
in any number of processes, replace it one after the other and leave no
``.NAME.old-*`` directory behind.

Examples
--------
>>> import tempfile, pathlib
>>> root = pathlib.Path(tempfile.mkdtemp())
>>> with report_directory(root / "demo") as tmp:
...     _ = atomic_write_text(tmp / "a.txt", "hello")
>>> sorted(p.name for p in root.iterdir())
['demo']
>>> (root / "demo" / "a.txt").read_text()
'hello'
>>> import shutil; shutil.rmtree(root)
"""

from __future__ import annotations

import contextlib
import logging
import os
import shutil
import tempfile
import uuid
from collections.abc import Iterator
from pathlib import Path

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows: swaps are not serialised across processes
    fcntl = None  # type: ignore[assignment]

from designlab.errors import DesignlabError

__all__ = [
    "ReportError",
    "atomic_write_bytes",
    "atomic_write_text",
    "current_umask",
    "report_directory",
]

logger = logging.getLogger(__name__)


class ReportError(DesignlabError, OSError):
    """A report could not be written (permissions, disk full, a file in the way)."""


def _fsync_dir(path: Path) -> None:
    """Flush a directory entry to disk (best effort; not all systems allow it)."""
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:  # pragma: no cover - e.g. Windows
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover
        pass
    finally:
        os.close(fd)


def current_umask() -> int:
    """The process's file mode creation mask (``umask``), read without changing it.

    Temporary files and directories are created private (0600 / 0700); reports are then
    given the mode a plain ``open()`` or ``mkdir`` would give them: 0666 or 0777 without
    the bits of the user's umask (with umask 077 a report is readable by its owner only).

    Examples
    --------
    >>> 0 <= current_umask() <= 0o777
    True
    """
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)  # no /proc: read it by setting it (and put it back at once)
    os.umask(mask)
    return mask


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; return the path.

    Parameters
    ----------
    path
        Destination file. Its directory must exist.
    data
        The complete new content.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "x.bin"
    >>> atomic_write_bytes(p, b"abc").read_bytes()
    b'abc'
    >>> import shutil; shutil.rmtree(p.parent)
    """
    target = Path(path)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    tmp = Path(tmp_name)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o666 & ~current_umask())  # as open() would create it
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
        raise
    _fsync_dir(target.parent)
    return target


def atomic_write_text(path: str | os.PathLike[str], text: str, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically (see :func:`atomic_write_bytes`).

    Line endings are written as given (``\\n``), on every platform.

    Parameters
    ----------
    path
        The file.
    text
        Its new content.
    encoding
        Text encoding.
    """
    return atomic_write_bytes(path, text.encode(encoding))


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # pragma: no cover - someone else's process
        return True
    return True


@contextlib.contextmanager
def _directory_lock(directory: Path) -> Iterator[None]:
    """Hold an exclusive lock on ``directory`` (no lock file: the directory itself)."""
    if fcntl is None:  # pragma: no cover
        yield
        return
    fd = os.open(directory, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock


def _owner_gone(path: Path, marker: str) -> bool:
    """Whether the process named in ``.<name><marker><pid>-<random>`` has exited."""
    try:
        pid = int(path.name.rsplit(marker, 1)[1].split("-", 1)[0])
    except (IndexError, ValueError):
        return True  # an old name without a pid: no live owner can be known
    return pid != os.getpid() and not _pid_alive(pid)


def _mtime(path: Path) -> float | None:
    """Modification time, or ``None`` for a directory its owner has just removed."""
    try:
        return path.stat().st_mtime
    except FileNotFoundError:
        return None


def _recover(final: Path) -> None:
    """Tidy up after runs killed (SIGKILL, power loss) mid-write or mid-swap.

    Called with the directory lock held: no other swap is under way, so an
    ``.old-*`` directory belongs to a run that died between its two renames.
    """
    parent = final.parent
    for stale in parent.glob(f".{final.name}.tmp-*"):
        # .<name>.tmp-<pid>-<random>: remove it only if its writer is gone
        if _owner_gone(stale, ".tmp-"):
            logger.info("removing stale temporary report directory %s", stale)
            shutil.rmtree(stale, ignore_errors=True)
    dated = [(_mtime(p), p) for p in parent.glob(f".{final.name}.old-*")]
    olds = [p for m, p in sorted((m, p) for m, p in dated if m is not None)]
    if not final.exists() and olds:
        logger.warning("restoring the previous report %s from %s", final, olds[-1])
        os.rename(olds.pop(), final)
    for old in olds:
        if _owner_gone(old, ".old-"):
            shutil.rmtree(old, ignore_errors=True)


def _swap_into_place(new: Path, final: Path) -> Path | None:
    """Move ``new`` to ``final``; return the previous report's directory, to remove."""
    if not final.exists():
        os.rename(new, final)
        return None
    if not final.is_dir() or final.is_symlink():
        raise ReportError(f"{final} exists and is not a report directory; remove it first")
    old = final.parent / f".{final.name}.old-{os.getpid()}-{uuid.uuid4().hex[:8]}"
    os.rename(final, old)
    try:
        os.rename(new, final)
    except BaseException:
        os.rename(old, final)
        raise
    return old


@contextlib.contextmanager
def report_directory(final: str | os.PathLike[str]) -> Iterator[Path]:
    """Build a report directory atomically.

    Yields a temporary directory next to ``final``; write every file of the
    report into it. When the ``with`` block ends normally, the temporary
    directory replaces ``final`` (the previous report, if any, is removed).
    If the block raises, the temporary directory is deleted and ``final`` is
    left as it was.

    Parameters
    ----------
    final
        The report directory, e.g. ``reports/zeng_ch4_validation``. Its
        parent is created if needed.

    Raises
    ------
    ReportError
        If the directory cannot be created or replaced.
    """
    final = Path(final)
    try:
        final.parent.mkdir(parents=True, exist_ok=True)
        with _directory_lock(final.parent):
            _recover(final)
        tmp = Path(tempfile.mkdtemp(prefix=f".{final.name}.tmp-{os.getpid()}-", dir=final.parent))
        os.chmod(tmp, 0o777 & ~current_umask())  # as mkdir would create it
    except OSError as exc:
        raise ReportError(f"cannot create the report directory {final}: {exc}") from exc
    try:
        yield tmp
        _fsync_dir(tmp)
        try:
            with _directory_lock(final.parent):
                _recover(final)
                old = _swap_into_place(tmp, final)
                _fsync_dir(final.parent)
        except ReportError:
            raise
        except OSError as exc:
            raise ReportError(f"cannot move the new report into {final}: {exc}") from exc
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
