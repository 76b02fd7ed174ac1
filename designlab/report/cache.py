"""On-disk cache of sweep points: one small JSON file per finished point.

A point's key is the SHA-256 of its evaluator name, the evaluator options,
the point itself (a plain dict) and the *code version*
(:func:`code_version`: the designlab version and a hash of the model and
evaluator sources), so changing a parameter or the physics never returns a
stale result. Entries are written atomically (temporary file + rename) as
points finish, and carry a checksum of their content: a truncated or edited
entry is detected on reading, reported and recomputed.

Layout: ``<cache dir>/<study name>/<key[:2]>/<key>.json``.

Examples
--------
>>> import tempfile, pathlib
>>> cache = PointCache(pathlib.Path(tempfile.mkdtemp()))
>>> key = cache.key("demo", {}, {"x": 1.0})
>>> cache.get(key)
('missing', None)
>>> _ = cache.put(key, {"x": 1.0}, {"y": 2.0})
>>> cache.get(key)
('ok', {'y': 2.0})
>>> _ = cache.path(key).write_text("{not json")
>>> cache.get(key)[0]
'corrupt'
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from functools import cache
from pathlib import Path
from typing import Any

from designlab.report.atomic import ReportError

__all__ = ["CACHE_FORMAT", "PointCache", "code_version"]

#: Version of the entry layout; part of every key.
CACHE_FORMAT = 1


@cache
def code_version() -> str:
    """designlab's version plus a short hash of the sources that compute points."""
    import designlab

    root = Path(designlab.__file__).parent
    h = hashlib.sha256(designlab.__version__.encode())
    files = [*sorted((root / "impact").glob("*.py")), root / "analysis" / "sweep.py"]
    for path in files:
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return f"{designlab.__version__}+{h.hexdigest()[:12]}"


def _canonical(obj: Any) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=True)


class PointCache:
    """Finished points of one study, on disk.

    Parameters
    ----------
    root
        Directory of this study's entries (created when the first is written).
    fsync
        Flush every entry to disk before renaming it into place (slower; the
        checksum catches the rare torn entry after a power loss anyway).
    """

    def __init__(self, root: str | os.PathLike[str], *, fsync: bool = False) -> None:
        self.root = Path(root)
        self.fsync = fsync

    def key(self, evaluator: str, options: dict[str, Any], point: dict[str, Any]) -> str:
        """The content hash of a point (hex SHA-256)."""
        text = _canonical(
            {
                "format": CACHE_FORMAT,
                "code": code_version(),
                "evaluator": evaluator,
                "options": options,
                "point": point,
            }
        )
        return hashlib.sha256(text.encode()).hexdigest()

    def path(self, key: str) -> Path:
        """File of an entry."""
        return self.root / key[:2] / f"{key}.json"

    def get(self, key: str) -> tuple[str, Any]:
        """``("ok", result)``, ``("missing", None)`` or ``("corrupt", reason)``."""
        path = self.path(key)
        try:
            text = path.read_text(encoding="utf-8")
        except FileNotFoundError:
            return "missing", None
        except (OSError, UnicodeDecodeError) as exc:
            return "corrupt", f"unreadable ({exc})"
        try:
            entry = json.loads(text)
            result = entry["result"]
            ok = entry["key"] == key and entry["sha256"] == _digest(result)
        except (ValueError, KeyError, TypeError) as exc:
            return "corrupt", f"not a cache entry ({type(exc).__name__})"
        if not ok:
            return "corrupt", "checksum mismatch"
        return "ok", result

    def put(self, key: str, point: dict[str, Any], result: Any) -> Path:
        """Store a finished point (atomically)."""
        path = self.path(key)
        entry = {"key": key, "point": point, "result": result, "sha256": _digest(result)}
        data = json.dumps(entry, sort_keys=True, allow_nan=True).encode()
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=".", suffix=".tmp", dir=path.parent)
            try:
                with os.fdopen(fd, "wb") as fh:
                    fh.write(data)
                    if self.fsync:
                        fh.flush()
                        os.fsync(fh.fileno())
                os.replace(tmp, path)
            except BaseException:
                Path(tmp).unlink(missing_ok=True)
                raise
        except OSError as exc:
            raise ReportError(f"cannot write the sweep cache {self.root}: {exc}") from exc
        return path

    def discard(self, key: str) -> None:
        """Remove an entry (e.g. a corrupt one)."""
        self.path(key).unlink(missing_ok=True)

    def __len__(self) -> int:
        return sum(1 for _ in self.root.glob("??/*.json")) if self.root.is_dir() else 0


def _digest(result: Any) -> str:
    return hashlib.sha256(_canonical(result).encode()).hexdigest()
