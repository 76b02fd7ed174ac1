"""Read the rows of a damaged SQLite file page by page, without SQLite.

When a result store's file is damaged (random bytes over a b-tree page, a torn
disk write), SQLite refuses every query that walks through the damaged page.
:func:`salvage_rows` reads the file (and its write-ahead log) as the SQLite
file format describes it (https://www.sqlite.org/fileformat2.html): it looks
at every page, takes the cells of every table leaf page, follows their
overflow chains and decodes the records. Nothing is trusted: a cell that does
not decode is skipped, and the caller checks each row it keeps (the store
keeps a chunk only if its SHA-256 checksum matches its data).

Examples
--------
>>> import sqlite3, tempfile, pathlib
>>> path = pathlib.Path(tempfile.mkdtemp()) / "demo.sqlite"
>>> db = sqlite3.connect(path)
>>> _ = db.execute("CREATE TABLE t (name TEXT, size INTEGER, data BLOB)")
>>> _ = db.execute("INSERT INTO t VALUES ('a', 3, ?)", (b"x" * 9000,))
>>> db.commit(); db.close()
>>> rows = [r for r in salvage_rows(path) if len(r) == 3]
>>> [(r[0], r[1], len(r[2])) for r in rows]
[('a', 3, 9000)]
>>> import shutil; shutil.rmtree(path.parent)
"""

from __future__ import annotations

import os
import struct
from collections.abc import Iterator
from pathlib import Path
from typing import Any

__all__ = ["salvage_rows"]

_MAGIC = b"SQLite format 3\x00"
_TABLE_LEAF = 0x0D
_PAGE_SIZES = (4096, 1024, 2048, 8192, 16384, 32768, 65536, 512)
_WAL_HEADER, _FRAME_HEADER = 32, 24


def _varint(buf: bytes, pos: int) -> tuple[int, int]:
    """A SQLite varint at ``pos``: ``(value, position after it)``."""
    value = 0
    for i in range(8):
        byte = buf[pos + i]
        value = (value << 7) | (byte & 0x7F)
        if byte < 0x80:
            return value, pos + i + 1
    return (value << 8) | buf[pos + 8], pos + 9


def _geometry(data: bytes) -> tuple[int, int] | None:
    """``(page size, usable size)`` from an intact file header, else ``None``."""
    if not data.startswith(_MAGIC) or len(data) < 100:
        return None
    size = struct.unpack_from(">H", data, 16)[0]
    size = 65536 if size == 1 else size
    if size not in _PAGE_SIZES:
        return None
    return size, size - data[20]


def _pages(path: Path, size: int) -> dict[int, bytes]:
    """Page number (from 1) -> content: the file's pages, then the WAL's frames over them."""
    data = path.read_bytes()
    pages = {i // size + 1: data[i : i + size] for i in range(0, len(data) - size + 1, size)}
    wal = Path(str(path) + "-wal")
    if wal.is_file():
        log = wal.read_bytes()
        step = _FRAME_HEADER + size
        for at in range(_WAL_HEADER, len(log) - step + 1, step):
            number = struct.unpack_from(">I", log, at)[0]
            if number:
                pages[number] = log[at + _FRAME_HEADER : at + step]
    return pages


def _payload(pages: dict[int, bytes], page: bytes, at: int, usable: int) -> bytes:
    """The payload of the table-leaf cell at offset ``at``, overflow pages included."""
    total, pos = _varint(page, at)
    _, pos = _varint(page, pos)  # the rowid
    most = usable - 35
    if total <= most:
        local = total
    else:
        least = (usable - 12) * 32 // 255 - 23
        local = least + (total - least) % (usable - 4)
        local = local if local <= most else least
    out = bytearray(page[pos : pos + local])
    if local < total:
        nxt = struct.unpack_from(">I", page, pos + local)[0]
        seen: set[int] = set()
        while nxt and len(out) < total:
            if nxt in seen or nxt not in pages:
                raise ValueError("broken overflow chain")
            seen.add(nxt)
            over = pages[nxt]
            out += over[4:usable][: total - len(out)]
            nxt = struct.unpack_from(">I", over, 0)[0]
    if len(out) != total:
        raise ValueError("short payload")
    return bytes(out)


def _record(payload: bytes) -> tuple[Any, ...]:
    """The values of a record (SQLite's record format)."""
    header, pos = _varint(payload, 0)
    types = []
    while pos < header:
        t, pos = _varint(payload, pos)
        types.append(t)
    if pos != header:
        raise ValueError("bad record header")
    values: list[Any] = []
    for t in types:
        if t == 0:
            values.append(None)
        elif t in (8, 9):
            values.append(t - 8)
        elif 1 <= t <= 6:
            width = (1, 2, 3, 4, 6, 8)[t - 1]
            values.append(int.from_bytes(payload[pos : pos + width], "big", signed=True))
            pos += width
        elif t == 7:
            values.append(struct.unpack_from(">d", payload, pos)[0])
            pos += 8
        elif t >= 12:
            width = (t - 12) // 2
            raw = payload[pos : pos + width]
            values.append(raw.decode("utf-8") if t % 2 else raw)
            pos += width
        else:
            raise ValueError(f"reserved serial type {t}")
    if pos != len(payload):
        raise ValueError("record length mismatch")
    return tuple(values)


def _leaf_rows(pages: dict[int, bytes], number: int, usable: int) -> Iterator[tuple[Any, ...]]:
    page = pages[number]
    start = 100 if number == 1 else 0
    if len(page) < start + 8 or page[start] != _TABLE_LEAF:
        return
    cells = struct.unpack_from(">H", page, start + 3)[0]
    for c in range(cells):
        try:
            at = struct.unpack_from(">H", page, start + 8 + 2 * c)[0]
            yield _record(_payload(pages, page, at, usable))
        except (ValueError, IndexError, struct.error, UnicodeDecodeError):
            continue


def salvage_rows(path: str | os.PathLike[str]) -> Iterator[tuple[Any, ...]]:
    """Every row that decodes from the table leaf pages of a SQLite file (and its WAL).

    Rows of every table come out mixed, in no particular order; a row may
    come out twice (an old copy of a page in the WAL). With the file header
    damaged, the common page sizes are tried in turn (4 KiB first), and the
    first that yields any row is used.

    Parameters
    ----------
    path
        The database file.

    Yields
    ------
    tuple
        A row's values (``None``, ``int``, ``float``, ``str`` or ``bytes``).
    """
    path = Path(path)
    with open(path, "rb") as fh:
        geometry = _geometry(fh.read(100))
    candidates = [geometry] if geometry else [(s, s) for s in _PAGE_SIZES]
    for size, usable in candidates:
        pages = _pages(path, size)
        found = False
        for number in sorted(pages):
            for row in _leaf_rows(pages, number, usable):
                found = True
                yield row
        if found:
            return
