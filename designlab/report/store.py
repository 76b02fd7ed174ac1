"""The result store of a study: one SQLite file holding every finished chunk.

A sweep's points are evaluated in chunks (see :mod:`designlab.analysis.sweep`);
each finished chunk is one row of ``<cache dir>/<study name>.sqlite``, keyed by
the hash of its points, the evaluator, its options and the evaluator's source.
The row holds the chunk's result columns, packed column by column (floats as
IEEE doubles, strings as JSON) and zlib-compressed, with a SHA-256 checksum.

* **Nothing lost, nothing torn.** Each chunk is written in its own transaction
  (WAL journal) as soon as it comes back: a kill loses at most the chunks in
  flight, and a half-written chunk never becomes visible.
* **Never silently reused.** A file that is not a designlab store (not SQLite,
  or without the store's ``meta`` table, or of another format) is refused with
  a :class:`~designlab.report.atomic.ReportError`; a chunk whose checksum does
  not match is reported as corrupt and recomputed.
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
import os
import sqlite3
import struct
import zlib
from pathlib import Path
from typing import Any

import numpy as np

from designlab.report.atomic import ReportError

__all__ = ["STORE_FORMAT", "ChunkStore", "open_store"]

#: Version of the store layout (``meta.format``).
STORE_FORMAT = "designlab-chunk-store-2"

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
            blob = json.dumps(
                [None if v is None else v if isinstance(v, (bool, int, float, str)) else str(v)
                 for v in arr.tolist()],
                allow_nan=True, separators=(",", ":"),
            ).encode()  # fmt: skip
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

    Parameters
    ----------
    path
        The store file (created with its directory when missing).
    study
        The study name, recorded in the store; a store of another study is
        refused.
    """

    def __init__(self, path: str | os.PathLike[str], *, study: str | None = None) -> None:
        self.path = Path(path)
        self.study = study
        self._db: sqlite3.Connection | None = None

    # -- connection ---------------------------------------------------------------

    def _connect(self) -> sqlite3.Connection:
        if self._db is not None:
            return self._db
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            db = sqlite3.connect(self.path, timeout=60.0, isolation_level=None)
        except (OSError, sqlite3.Error) as exc:
            raise ReportError(f"cannot open the result store {self.path}: {exc}") from exc
        try:
            db.execute("PRAGMA busy_timeout = 60000")
            # set up a new store in one exclusive step, so that a second run starting at the
            # same moment sees either nothing or a complete store
            db.execute("BEGIN IMMEDIATE")
            tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master")}
            if not tables:
                for statement in _SCHEMA.split(";"):
                    if statement.strip():
                        db.execute(statement)
                db.execute("INSERT INTO meta VALUES ('format', ?)", (STORE_FORMAT,))
                if self.study is not None:
                    db.execute("INSERT INTO meta VALUES ('study', ?)", (self.study,))
            db.execute("COMMIT")
            if db.execute("PRAGMA journal_mode").fetchone()[0] != "wal":
                db.execute("PRAGMA journal_mode = WAL")
            self._check(db)
            db.execute("PRAGMA synchronous = NORMAL")
        except sqlite3.DatabaseError as exc:
            db.close()
            raise ReportError(
                f"{self.path} is not a designlab result store ({exc}); move it away or "
                "choose another --cache-dir"
            ) from exc
        except ReportError:
            db.close()
            raise
        self._db = db
        return db

    def _check(self, db: sqlite3.Connection) -> None:
        tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type='table'")}
        if not {"meta", "chunks"} <= tables:
            raise ReportError(
                f"{self.path} is not a designlab result store (tables: "
                f"{', '.join(sorted(tables)) or 'none'}); move it away or choose another "
                "--cache-dir"
            )
        meta = dict(db.execute("SELECT name, value FROM meta").fetchall())
        if meta.get("format") != STORE_FORMAT:
            raise ReportError(
                f"{self.path} is a result store of format {meta.get('format')!r}, this "
                f"designlab reads {STORE_FORMAT!r}; move it away or choose another --cache-dir"
            )
        if self.study is not None and meta.get("study") not in (None, self.study):
            raise ReportError(
                f"{self.path} holds the results of study {meta.get('study')!r}, not "
                f"{self.study!r}; study names must be unique per cache directory"
            )

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

    # -- rows of the chunks table -------------------------------------------

    def _read(self, key: str) -> tuple[str, Any]:
        """``("ok", columns)``, ``("missing", None)`` or ``("corrupt", reason)``."""
        row = (
            self._connect()
            .execute("SELECT n, data, sha256 FROM chunks WHERE key = ?", (key,))
            .fetchone()
        )
        if row is None:
            return "missing", None
        n, data, digest = row
        if hashlib.sha256(data).digest() != digest:
            return "corrupt", "checksum mismatch"
        try:
            cols = _unpack(data)
        except (ValueError, zlib.error, struct.error, KeyError, TypeError) as exc:
            return "corrupt", f"undecodable ({type(exc).__name__})"
        if any(len(v) != n for v in cols.values()):
            return "corrupt", "column lengths differ from the recorded count"
        return "ok", cols

    def _write(self, key: str, columns: dict[str, Any]) -> None:
        """Store ``columns`` under ``key`` in one transaction."""
        n, data = _pack(columns)
        digest = hashlib.sha256(data).digest()
        db = self._connect()
        try:
            db.execute("BEGIN IMMEDIATE")
            db.execute("INSERT OR REPLACE INTO chunks VALUES (?, ?, ?, ?)", (key, n, data, digest))
            db.execute("COMMIT")
        except sqlite3.Error as exc:
            if db.in_transaction:
                db.execute("ROLLBACK")
            raise ReportError(f"cannot write the result store {self.path}: {exc}") from exc

    # -- chunks -----------------------------------------------------------------------

    def get_chunk(self, key: str) -> tuple[str, Any]:
        """``("ok", columns)``, ``("missing", None)`` or ``("corrupt", reason)``.

        Parameters
        ----------
        key
            The chunk key.
        """
        return self._read(key)

    def put_chunk(self, key: str, columns: dict[str, Any]) -> None:
        """Store a finished chunk in its own transaction.

        Parameters
        ----------
        key
            The chunk key.
        columns
            The chunk's result columns (numbers, booleans or strings).
        """
        self._write(key, columns)

    def discard(self, key: str) -> None:
        """Remove a chunk (e.g. a corrupt one).

        Parameters
        ----------
        key
            The chunk key.
        """
        db = self._connect()
        db.execute("DELETE FROM chunks WHERE key = ?", (key,))

    def __len__(self) -> int:
        if not self.path.exists():
            return 0
        return int(self._connect().execute("SELECT COUNT(*) FROM chunks").fetchone()[0])

    def points(self) -> int:
        """Points stored, over all chunks."""
        if not self.path.exists():
            return 0
        row = self._connect().execute("SELECT COALESCE(SUM(n), 0) FROM chunks").fetchone()
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
        """Fold the WAL into the database file (at the end of a run)."""
        if self._db is not None:
            self._db.execute("PRAGMA wal_checkpoint(TRUNCATE)")


def open_store(cache_dir: str | os.PathLike[str], study: str) -> ChunkStore:
    """The store of ``study`` under ``cache_dir``: ``<cache_dir>/<study>.sqlite``.

    Parameters
    ----------
    cache_dir
        The directory of stores (``--cache-dir``).
    study
        The study name.
    """
    return ChunkStore(Path(cache_dir) / f"{study}.sqlite", study=study)
