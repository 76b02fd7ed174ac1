"""The result store of a study: one SQLite file holding every finished chunk.

A sweep's points are evaluated in chunks (see :mod:`designlab.analysis.engine`);
each finished chunk is one row of ``<cache dir>/<study name>.sqlite``, keyed by
the hash of its points, the evaluator, its options and the evaluator's source.
The row holds the chunk's result columns, packed column by column (floats as
IEEE doubles, strings as JSON) and zlib-compressed, with a SHA-256 checksum.

* **Nothing lost, nothing torn.** Each chunk is written in its own transaction
  (WAL journal) as soon as it comes back: a kill loses at most the chunks in
  flight, and a half-written chunk never becomes visible.
* **Never silently reused.** A file that is not a designlab store (not SQLite,
  or without the store's ``meta`` table, or of another format) is refused with
  a :class:`StoreError`, and so is the store of another study, or of a study
  of another kind with the same name. A chunk whose checksum does not match is
  reported as corrupt (the engine recomputes it on ``--resume``).
* **Damage is repaired, not fatal.** When SQLite finds the file damaged
  (random bytes over a page: "database disk image is malformed"), the store
  reads every chunk that is still readable straight from the file's pages
  (:mod:`designlab.analysis.salvage`), checks each against its checksum,
  rewrites the store with them and logs what it kept; the chunks that were
  lost are simply missing, so ``--resume`` recomputes them and ``designlab
  report`` names them. A damaged store that cannot be rewritten (a read-only
  directory) is repaired in memory for reading.
* **Read-only stores are read.** A store in a directory (or a file) this
  process may not write is opened read-only: everything stored can be read;
  writing a chunk raises :class:`StoreError` saying so.
* **Concurrent runs.** Two runs of the same study at once wait for each other's
  transactions (``busy_timeout``); identical chunks have identical keys and
  contents, so the second write is a no-op.

Examples
--------
>>> import tempfile, pathlib, numpy as np
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> store = ChunkStore(d / "demo.sqlite")
>>> store.get_chunk("k")
('missing', None)
>>> ok = np.array(["ok", "ok"], dtype=object)
>>> store.put_chunk("k", {"y": np.array([1.0, 2.0]), "status": ok})
>>> state, cols = store.get_chunk("k")
>>> state, cols["y"].tolist(), cols["status"].tolist()
('ok', [1.0, 2.0], ['ok', 'ok'])
>>> len(store), store.points()
(1, 2)
>>> store.close()
>>> import shutil; shutil.rmtree(d)
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import sqlite3
import struct
import zlib
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TypeVar
from urllib.parse import quote

import numpy as np

from designlab.analysis.salvage import salvage_rows
from designlab.errors import DesignlabError

__all__ = ["STORE_FORMAT", "ChunkStore", "StoreError", "open_store"]

logger = logging.getLogger(__name__)

#: Version of the store layout (``meta.format``).
STORE_FORMAT = "designlab-chunk-store-2"

#: Seconds a store operation waits for another run's transaction.
BUSY_TIMEOUT = 60.0

# A rowid table: a chunk of a slow evaluator packs to a kilobyte or two, which a
# WITHOUT ROWID table would spill to an overflow page of its own (4 KiB each).
_SCHEMA = """
CREATE TABLE meta (name TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE chunks (
    key TEXT PRIMARY KEY,
    n INTEGER NOT NULL,
    data BLOB NOT NULL,
    sha256 BLOB NOT NULL
);
"""

# What a resumed run needs of a finished chunk without unpacking it: its point count and a
# JSON summary (points per status, result columns and their kinds, a hash of its points).
# Written in the chunk's own transaction; a store without it (older, or repaired) still works.
_SUMMARIES = """
CREATE TABLE IF NOT EXISTS summaries (key TEXT PRIMARY KEY, n INTEGER NOT NULL,
                                      summary TEXT NOT NULL)
"""

#: Chunk keys per query when reading summaries (SQLite's bound-variable limit is higher).
_KEYS_PER_QUERY = 500

T = TypeVar("T")


class StoreError(DesignlabError, OSError):
    """The result store cannot be opened, read or written (or belongs to another study)."""


def _is_damage(exc: BaseException) -> bool:
    """Whether SQLite says the file is damaged (as opposed to locked, read-only, full).

    Text that is not UTF-8 (random bytes over a table name or a meta value) is damage too.
    """
    if isinstance(exc, UnicodeDecodeError):
        return True
    name = str(getattr(exc, "sqlite_errorname", ""))
    text = str(exc)
    return name.startswith(("SQLITE_CORRUPT", "SQLITE_NOTADB")) or (
        "malformed" in text or "not a database" in text or "Could not decode to UTF-8" in text
    )


def _is_read_only(exc: BaseException) -> bool:
    name = str(getattr(exc, "sqlite_errorname", ""))
    text = str(exc)
    return (
        isinstance(exc, PermissionError)
        or name.startswith(("SQLITE_READONLY", "SQLITE_CANTOPEN", "SQLITE_PERM"))
        or "readonly" in text
        or "unable to open" in text
        or "Read-only file system" in text
    )


def _writable(path: Path) -> bool:
    """Whether this process may write ``path`` (a file or, if missing, its directory)."""
    parent = path.parent
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent
    if not os.access(parent, os.W_OK | os.X_OK):
        return False
    return not path.exists() or os.access(path, os.W_OK)


#: The error raised when an index lookup returns the row of another key (random bytes over
#: an index cell's row number): SQLite's own words, so that the store is repaired.
_MISDIRECTED = "database disk image is malformed (an index entry points at another chunk's row)"


def _check_rows(db: sqlite3.Connection, table: str, keys: dict[int, str]) -> None:
    """Raise SQLite's "malformed" error unless the rows ``rowid -> key`` hold those keys.

    A lookup by key reads the key from the index and the rest from the row the index
    names: random bytes over an index cell's row number give another chunk's data under
    the asked key, checksum intact. The keys are read again from the table itself.
    """
    if not keys:
        return
    marks = ",".join("?" * len(keys))
    found = dict(db.execute(
        f"SELECT rowid, key FROM {table} NOT INDEXED WHERE rowid IN ({marks})", list(keys)
    ).fetchall())  # fmt: skip
    if found != keys:
        raise sqlite3.DatabaseError(_MISDIRECTED)


def _check_structure(db: sqlite3.Connection) -> None:
    """Raise SQLite's "malformed" error if an existing store is damaged where no query looked.

    Random bytes over a page that the run's queries never walk (an index page, a leaf of
    chunks already done) go unnoticed by SQLite: a chunk key missing from a damaged index
    is then inserted a second time and ``PRAGMA integrity_check`` fails, though results
    stay right. ``PRAGMA quick_check`` (every page's structure, one pass over the file) and
    the keys and row numbers of each table read with and without its index (the part of
    ``PRAGMA integrity_check`` that ``quick_check`` leaves out, for the two small indexes)
    find that damage when the store is opened; the store is then repaired as for any
    damage (:meth:`ChunkStore._repair`).
    """
    problems = [r[0] for r in db.execute("PRAGMA quick_check(5)").fetchall()]
    if problems != ["ok"]:
        raise sqlite3.DatabaseError(f"database disk image is malformed ({'; '.join(problems)})")
    tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type='table'")}
    for table in ("chunks", "summaries"):
        if table not in tables:
            continue
        rows = sorted(db.execute(f"SELECT key, rowid FROM {table} NOT INDEXED").fetchall())
        index = sorted(db.execute(
            f"SELECT key, rowid FROM {table} INDEXED BY sqlite_autoindex_{table}_1 "
            "WHERE key IS NOT NULL"
        ).fetchall())  # fmt: skip
        keys = [r[0] for r in rows]
        if rows != index or len(set(keys)) != len(keys):
            raise sqlite3.DatabaseError(
                f"database disk image is malformed (the {table} index does not match its "
                "rows, or a key is stored twice)"
            )


def _has_summaries(db: sqlite3.Connection) -> bool:
    return bool(
        db.execute(
            "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = 'summaries'"
        ).fetchall()
    )


def _sha256(data: bytes) -> bytes:
    return hashlib.sha256(data).digest()


#: Types that :func:`_pack` writes to JSON as they are.
_JSON_TYPES = frozenset({str, bool, int, float, type(None)})


def _pack(columns: dict[str, Any]) -> tuple[int, bytes]:
    """Columns -> ``(n, compressed bytes)``."""
    header: list[list[Any]] = []
    blobs: list[bytes] = []
    n = 0
    for name, values in columns.items():
        arr = np.asarray(values)
        n = len(arr)
        if arr.dtype.kind == "f" or arr.dtype.kind in "iu":
            blob = np.ascontiguousarray(arr, dtype="<f8").tobytes()
            header.append([name, "f8", len(blob)])
        elif arr.dtype.kind == "b":
            blob = np.ascontiguousarray(arr, dtype=np.uint8).tobytes()
            header.append([name, "b1", len(blob)])
        else:
            values = arr.tolist()
            if not set(map(type, values)) <= _JSON_TYPES:  # else kept as they are (fast)
                values = [None if v is None else v if isinstance(v, (bool, int, float, str))
                          else str(v) for v in values]  # fmt: skip
            blob = json.dumps(values, allow_nan=True, separators=(",", ":")).encode()
            header.append([name, "json", len(blob)])
        blobs.append(blob)
    head = json.dumps({"n": n, "columns": header}, separators=(",", ":")).encode()
    raw = struct.pack("<I", len(head)) + head + b"".join(blobs)
    return n, zlib.compress(raw, 1)


def _unpack(data: bytes) -> dict[str, np.ndarray]:
    raw = zlib.decompress(data)
    (hlen,) = struct.unpack_from("<I", raw, 0)
    head = json.loads(raw[4 : 4 + hlen])
    pos = 4 + hlen
    out: dict[str, np.ndarray] = {}
    for name, kind, size in head["columns"]:
        blob = raw[pos : pos + size]
        pos += size
        if kind == "f8":
            out[name] = np.frombuffer(blob, dtype="<f8").copy()
        elif kind == "b1":
            out[name] = np.frombuffer(blob, dtype=np.uint8).astype(bool)
        else:
            values = json.loads(blob)
            arr = np.empty(len(values), dtype=object)
            arr[:] = values
            out[name] = arr
    if pos != len(raw):
        raise ValueError("trailing bytes")
    return out


class ChunkStore:
    """Finished chunks of one study, in one SQLite file.

    The file is opened on first use (a study that never stores a chunk
    leaves no file).

    Parameters
    ----------
    path
        The store file (created with its directory when missing).
    study
        The study name, recorded in the store; a store of another study is
        refused.
    kind
        The study kind, recorded in the store; a store written by a study of
        another kind (with the same name) is refused.

    Attributes
    ----------
    read_only
        Whether the store can only be read (known once it is opened).
    repairs
        What each repair of a damaged file kept (also logged as warnings).
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        *,
        study: str | None = None,
        kind: str | None = None,
    ) -> None:
        self.path = Path(path)
        self.study = study
        self.kind = kind
        self.read_only = False
        self.repairs: list[str] = []
        self._db: sqlite3.Connection | None = None

    # -- opening ------------------------------------------------------------------

    def _connect(self) -> sqlite3.Connection:
        if self._db is not None:
            return self._db
        try:
            db = self._open()
        except (sqlite3.DatabaseError, UnicodeDecodeError) as exc:
            if not _is_damage(exc):
                raise self._error("open", exc) from exc
            db = self._repair(exc)
        self._db = db
        return db

    def _check_path(self) -> None:
        """Refuse a store path that is a symbolic link or not a regular file."""
        if self.path.is_symlink():
            raise StoreError(
                f"{self.path} is a symbolic link; a result store must be a regular file "
                "(give the directory it is in as --cache-dir, or move the link away)"
            )
        if self.path.exists() and not self.path.is_file():
            raise StoreError(
                f"{self.path} is not a regular file, so not a designlab result store; move it "
                "away or choose another --cache-dir"
            )

    def _open(self) -> sqlite3.Connection:
        self._check_path()
        if self.path.exists() and not _writable(self.path):
            return self._open_read_only()
        try:
            return self._open_writable()
        except (OSError, sqlite3.OperationalError) as exc:
            if isinstance(exc, StoreError):
                raise
            if self.path.exists() and _is_read_only(exc):
                return self._open_read_only()
            if isinstance(exc, OSError):
                raise StoreError(f"cannot create the result store {self.path}: {exc}") from exc
            raise

    def _open_writable(self) -> sqlite3.Connection:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        created = not self.path.exists()
        db = sqlite3.connect(self.path, timeout=BUSY_TIMEOUT, isolation_level=None)
        try:
            db.execute(f"PRAGMA busy_timeout = {int(BUSY_TIMEOUT * 1000)}")
            # set up a new store in one exclusive step, so that a second run starting at the
            # same moment sees either nothing or a complete store
            db.execute("BEGIN IMMEDIATE")
            try:
                if not db.execute("SELECT name FROM sqlite_master").fetchall():
                    for statement in _SCHEMA.split(";"):
                        if statement.strip():
                            db.execute(statement)
                    db.executemany("INSERT INTO meta VALUES (?, ?)", self._own_meta().items())
                db.execute("COMMIT")
            finally:
                if db.in_transaction:
                    db.execute("ROLLBACK")
            if db.execute("PRAGMA journal_mode").fetchone()[0] != "wal":
                db.execute("PRAGMA journal_mode = WAL")
            self._check(db)
            if not created:
                _check_structure(db)
            db.execute(_SUMMARIES)
            db.execute("PRAGMA synchronous = NORMAL")
        except BaseException:
            db.close()
            raise
        self.read_only = False
        logger.info("result store %s (%s)", self.path, "new" if created else "existing")
        return db

    def _open_read_only(self) -> sqlite3.Connection:
        uri = f"file:{quote(str(self.path.resolve()))}?mode=ro"
        for extra in ("", "&immutable=1"):  # no WAL index can be made in a read-only directory
            db = sqlite3.connect(uri + extra, uri=True, timeout=BUSY_TIMEOUT, isolation_level=None)
            try:
                db.execute("SELECT name FROM sqlite_master").fetchall()
                self.read_only = True
                self._check(db)
                _check_structure(db)
            except sqlite3.OperationalError as exc:
                db.close()
                if extra or not _is_read_only(exc):
                    raise
                continue
            except BaseException:
                db.close()
                raise
            logger.info("result store %s (read-only)", self.path)
            return db
        raise AssertionError("unreachable")  # pragma: no cover

    def _own_meta(self) -> dict[str, str]:
        meta = {"format": STORE_FORMAT}
        if self.study is not None:
            meta["study"] = self.study
        if self.kind is not None:
            meta["kind"] = self.kind
        return meta

    def _check(self, db: sqlite3.Connection) -> None:
        tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type='table'")}
        if not {"meta", "chunks"} <= tables:
            raise StoreError(
                f"{self.path} is not a designlab result store (tables: "
                f"{', '.join(sorted(tables)) or 'none'}); move it away or choose another "
                "--cache-dir"
            )
        meta = dict(db.execute("SELECT name, value FROM meta").fetchall())
        self._check_meta(meta)
        recorded = meta.get("kind")
        if self.kind is not None and recorded != self.kind and not self.read_only:
            db.execute("INSERT OR REPLACE INTO meta VALUES ('kind', ?)", (self.kind,))

    def _check_meta(self, meta: dict[str, str]) -> None:
        if meta.get("format") != STORE_FORMAT:
            raise StoreError(
                f"{self.path} is a result store of format {meta.get('format')!r}, this "
                f"designlab reads {STORE_FORMAT!r}; move it away or choose another --cache-dir"
            )
        if self.study is not None and meta.get("study") not in (None, self.study):
            raise StoreError(
                f"{self.path} holds the results of study {meta.get('study')!r}, not "
                f"{self.study!r}; study names must be unique per cache directory"
            )
        recorded = meta.get("kind")
        if self.kind is not None and recorded not in (None, self.kind):
            raise StoreError(
                f"{self.path} holds the results of a study {meta.get('study', self.study)!r} "
                f"of kind {recorded!r}, not of kind {self.kind!r}: two studies of different "
                "kinds with one name cannot share a result store; rename one of them or "
                "choose another --cache-dir"
            )

    def _error(self, what: str, exc: BaseException) -> StoreError:
        text = str(exc)
        if "locked" in text or "busy" in text:
            return StoreError(
                f"cannot {what} the result store {self.path}: another run holds it "
                f"(waited {BUSY_TIMEOUT:g} s): {exc}"
            )
        if self.read_only or _is_read_only(exc):
            return StoreError(self._read_only_message(str(exc)))
        return StoreError(f"cannot {what} the result store {self.path}: {exc}")

    def _read_only_message(self, why: str) -> str:
        return (
            f"cannot write the result store {self.path}: it is read-only ({why}); what it "
            "holds can still be read (designlab report, or --resume when every chunk is "
            "stored): give a writable --cache-dir to compute"
        )

    # -- damage ---------------------------------------------------------------------

    def _salvage(self) -> tuple[dict[str, str], dict[str, tuple[int, bytes, bytes]]]:
        """The meta rows and the intact chunks (checksum and layout verified) of the file."""
        meta: dict[str, str] = {}
        chunks: dict[str, tuple[int, bytes, bytes]] = {}
        for row in salvage_rows(self.path):
            if len(row) == 2 and all(isinstance(v, str) for v in row):
                if row[0] in ("format", "study", "kind"):
                    meta.setdefault(row[0], row[1])
                continue
            if len(row) != 4 or row[0] in chunks:
                continue
            key, n, data, digest = row
            if not (isinstance(key, str) and isinstance(n, int) and isinstance(data, bytes)):
                continue
            if hashlib.sha256(data).digest() != digest:
                continue
            try:
                if any(len(v) != n for v in _unpack(data).values()):
                    continue
            except (ValueError, zlib.error, struct.error, KeyError, TypeError):
                continue
            chunks[key] = (n, data, digest)
        return meta, chunks

    def _repaired_copy(self, chunks: dict[str, tuple[int, bytes, bytes]]) -> sqlite3.Connection:
        """An in-memory store holding ``chunks``, with this store's page size."""
        with open(self.path, "rb") as fh:
            head = fh.read(100)
        size = struct.unpack_from(">H", head, 16)[0] if len(head) == 100 else 0
        mem = sqlite3.connect(":memory:", isolation_level=None)
        if head.startswith(b"SQLite format 3\x00") and size in (512, 1024, 2048, 4096, 8192):
            mem.execute(f"PRAGMA page_size = {size}")
        mem.execute("BEGIN")
        for statement in _SCHEMA.split(";"):
            if statement.strip():
                mem.execute(statement)
        mem.executemany("INSERT INTO meta VALUES (?, ?)", self._own_meta().items())
        mem.executemany(
            "INSERT INTO chunks VALUES (?, ?, ?, ?)", ((k, *v) for k, v in chunks.items())
        )
        mem.execute("COMMIT")
        return mem

    def _write_back(self, mem: sqlite3.Connection) -> None:
        """Replace the damaged file's content by ``mem`` (through SQLite, so under its locks)."""
        dest = sqlite3.connect(self.path, timeout=BUSY_TIMEOUT, isolation_level=None)
        try:
            dest.execute(f"PRAGMA busy_timeout = {int(BUSY_TIMEOUT * 1000)}")
            mem.backup(dest)
            return
        except sqlite3.DatabaseError as exc:
            if not _is_damage(exc):
                raise
        finally:
            dest.close()
        # the file header itself is damaged: a new file takes its place
        tmp = self.path.with_name(f".{self.path.name}.repair-{os.getpid()}")
        tmp.unlink(missing_ok=True)
        out = sqlite3.connect(tmp)
        try:
            mem.backup(out)
        finally:
            out.close()
        for suffix in ("-wal", "-shm"):
            Path(str(self.path) + suffix).unlink(missing_ok=True)
        os.replace(tmp, self.path)

    def _repair(self, exc: BaseException) -> sqlite3.Connection:
        """Keep every readable chunk of a damaged file; return a connection to the result."""
        self.close()
        meta, chunks = self._salvage()
        if not chunks and meta.get("format") is None:
            raise StoreError(
                f"{self.path} is not a designlab result store ({exc}); move it away or "
                "choose another --cache-dir"
            ) from exc
        self._check_meta({"format": STORE_FORMAT, **meta})
        mem = self._repaired_copy(chunks)
        how = "reading a repaired copy in memory: the store is read-only"
        db = mem
        if _writable(self.path):
            try:
                self._write_back(mem)
                db = self._open_writable()
                mem.close()
                how = "rewrote the store with them"
            except (OSError, sqlite3.Error) as err:
                how = f"reading a repaired copy in memory: rewriting the store failed ({err})"
        if db is mem:
            self.read_only = True
        message = (
            f"the result store {self.path} was damaged ({exc}): kept its "
            f"{len(chunks)} readable chunks ({sum(v[0] for v in chunks.values())} points), "
            f"{how}; the chunks lost to the damage are missing and `designlab run --resume` "
            "recomputes them"
        )
        logger.warning("%s", message)
        self.repairs.append(message)
        return db

    def _run(self, what: str, op: Callable[[sqlite3.Connection], T]) -> T:
        """``op(connection)``; a damaged file is repaired once and ``op`` tried again."""
        try:
            return op(self._connect())
        except (sqlite3.DatabaseError, UnicodeDecodeError) as exc:
            if not _is_damage(exc):
                raise self._error(what, exc) from exc
            self._db = self._repair(exc)
        try:
            return op(self._db)
        except (sqlite3.DatabaseError, UnicodeDecodeError) as exc:
            raise self._error(what, exc) from exc

    # -- life cycle -------------------------------------------------------------------

    def close(self) -> None:
        """Close the connection (idempotent)."""
        if self._db is not None:
            self._db.close()
            self._db = None

    def __enter__(self) -> ChunkStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __getstate__(self) -> dict[str, Any]:  # pragma: no cover - stores stay on the client
        raise TypeError("a ChunkStore stays with the client: workers never write it")

    # -- chunks -----------------------------------------------------------------------

    def get_chunk(self, key: str) -> tuple[str, Any]:
        """``("ok", columns)``, ``("missing", None)`` or ``("corrupt", reason)``.

        Parameters
        ----------
        key
            The chunk key.
        """

        def select(db: sqlite3.Connection) -> Any:
            row = db.execute(
                "SELECT rowid, n, data, sha256 FROM chunks WHERE key = ?", (key,)
            ).fetchone()
            if row is None:
                return None
            _check_rows(db, "chunks", {row[0]: key})
            return row[1:]

        row = self._run("read", select)
        if row is None:
            return "missing", None
        n, data, digest = row
        if not isinstance(data, bytes) or hashlib.sha256(data).digest() != digest:
            return "corrupt", "checksum mismatch"
        try:
            cols = _unpack(data)
        except (ValueError, zlib.error, struct.error, KeyError, TypeError) as exc:
            return "corrupt", f"undecodable ({type(exc).__name__})"
        if any(len(v) != n for v in cols.values()):
            return "corrupt", "column lengths differ from the recorded count"
        return "ok", cols

    def put_chunk(
        self, key: str, columns: dict[str, Any], summary: dict[str, Any] | None = None
    ) -> None:
        """Store a finished chunk (and its summary) in its own transaction.

        Parameters
        ----------
        key
            The chunk key.
        columns
            The chunk's result columns (numbers, booleans or strings).
        summary
            What a resumed run reads instead of the chunk (:meth:`summaries`);
            JSON-serialisable.

        Raises
        ------
        StoreError
            If the store is read-only, or the disk full.
        """
        n, data = _pack(columns)
        digest = hashlib.sha256(data).digest()
        self._connect()
        if self.read_only:
            raise StoreError(self._read_only_message("opened read-only"))

        def insert(db: sqlite3.Connection) -> None:
            db.execute("BEGIN IMMEDIATE")
            try:
                db.execute("INSERT OR REPLACE INTO chunks VALUES (?, ?, ?, ?)",
                           (key, n, data, digest))  # fmt: skip
                if summary is not None:
                    db.execute("INSERT OR REPLACE INTO summaries VALUES (?, ?, ?)",
                               (key, n, json.dumps(summary, separators=(",", ":"))))  # fmt: skip
                else:
                    db.execute("DELETE FROM summaries WHERE key = ?", (key,))
                db.execute("COMMIT")
            finally:
                if db.in_transaction:
                    db.execute("ROLLBACK")

        self._run("write", insert)

    def discard(self, key: str) -> None:
        """Remove a chunk (e.g. a corrupt one); a no-op on a read-only store.

        Parameters
        ----------
        key
            The chunk key.
        """
        self._connect()
        if self.read_only:
            return

        def delete(db: sqlite3.Connection) -> None:
            db.execute("BEGIN IMMEDIATE")
            try:
                db.execute("DELETE FROM chunks WHERE key = ?", (key,))
                if _has_summaries(db):
                    db.execute("DELETE FROM summaries WHERE key = ?", (key,))
                db.execute("COMMIT")
            finally:
                if db.in_transaction:
                    db.execute("ROLLBACK")

        self._run("write", delete)

    def summaries(self, keys: Sequence[str]) -> dict[str, tuple[int, dict[str, Any]]]:
        """``{key: (n, summary)}`` of the chunks ``keys`` that are stored intact with a summary.

        A chunk counts only when its checksum matches (its data is read and
        hashed, not unpacked); a chunk stored without a summary, or damaged,
        is left out (the engine then reads it with :meth:`get_chunk`).

        Parameters
        ----------
        keys
            Chunk keys.
        """
        if not keys or (self._db is None and not self.path.exists()):
            return {}
        out: dict[str, tuple[int, dict[str, Any]]] = {}

        def select(db: sqlite3.Connection) -> None:
            if not _has_summaries(db):
                return
            for i in range(0, len(keys), _KEYS_PER_QUERY):
                part = list(keys[i : i + _KEYS_PER_QUERY])
                marks = ",".join("?" * len(part))
                rows = db.execute(
                    "SELECT c.rowid, s.rowid, c.key, c.n, c.data, c.sha256, s.n, s.summary "
                    f"FROM chunks c JOIN summaries s ON s.key = c.key WHERE c.key IN ({marks})",
                    part,
                ).fetchall()
                _check_rows(db, "chunks", {r[0]: r[2] for r in rows})
                _check_rows(db, "summaries", {r[1]: r[2] for r in rows})
                for _, _, key, n, data, digest, sn, text in rows:
                    if n == sn and isinstance(data, bytes) and _sha256(data) == digest:
                        out[key] = (int(n), json.loads(text))

        self._run("read", select)
        return out

    def keys(self) -> list[str]:
        """The keys of every stored chunk."""
        if self._db is None and not self.path.exists():
            return []
        rows = self._run("read", lambda db: db.execute("SELECT key FROM chunks").fetchall())
        return [r[0] for r in rows]

    def __len__(self) -> int:
        if self._db is None and not self.path.exists():
            return 0
        return int(
            self._run("read", lambda db: db.execute("SELECT COUNT(*) FROM chunks").fetchone()[0])
        )

    def points(self) -> int:
        """Points stored, over all chunks."""
        if self._db is None and not self.path.exists():
            return 0
        row = self._run(
            "read", lambda db: db.execute("SELECT COALESCE(SUM(n), 0) FROM chunks").fetchone()
        )
        return int(row[0])

    def size_bytes(self) -> int:
        """Bytes on disk (the database and its WAL)."""
        total = 0
        for suffix in ("", "-wal", "-shm"):
            p = Path(str(self.path) + suffix)
            if p.exists():
                total += p.stat().st_size
        return total

    def checkpoint(self) -> None:
        """Fold the WAL into the database file (at the end of a run; best effort)."""
        if self._db is not None and not self.read_only:
            try:
                self._db.execute("PRAGMA wal_checkpoint(TRUNCATE)")
            except sqlite3.Error as exc:
                logger.warning("result store %s: checkpoint failed: %s", self.path, exc)


def open_store(
    cache_dir: str | os.PathLike[str],
    study: str,
    kind: str | None = None,
) -> ChunkStore:
    """The store of ``study`` under ``cache_dir``: ``<cache_dir>/<study>.sqlite``.

    Parameters
    ----------
    cache_dir
        The directory of stores (``--cache-dir``).
    study
        The study name.
    kind
        The study's kind (recorded; a store of another kind is refused).
    """
    return ChunkStore(Path(cache_dir) / f"{study}.sqlite", study=study, kind=kind)
