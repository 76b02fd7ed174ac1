"""What identifies a chunk of results: the evaluator, its code, its options and the points.

The sweep engine (:mod:`designlab.analysis.engine`) keys every chunk it stores
by :func:`chunk_key`, a SHA-256 over

* the evaluator's qualified name (:func:`evaluator_id`, also how workers find it),
* :func:`code_version`: designlab's version and a hash of the source of the
  package that holds the evaluator (:func:`package_hash`), so that editing the
  navigation code invalidates navigation results and nothing else,
* the evaluator options and the point values, bit for bit.

Reports use :func:`package_hash` too: a changed report writer makes every
report stale.

Examples
--------
>>> import numpy as np
>>> evaluator_id(chunk_key)
'designlab.analysis.keys.chunk_key'
>>> len(package_hash("designlab.analysis.keys"))
16
"""

from __future__ import annotations

import hashlib
import importlib
import json
import sys
from collections.abc import Callable, Mapping
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from designlab._version import __version__

__all__ = [
    "KEY_FORMAT",
    "chunk_key",
    "code_version",
    "evaluator_id",
    "indexed_chunk_keys",
    "package_hash",
    "source_files",
]

#: Version of the chunk key layout; part of every key.
KEY_FORMAT = 2


def evaluator_id(fn: Callable[..., Any]) -> str:
    """The qualified name ``module.function`` by which workers find an evaluator.

    Parameters
    ----------
    fn
        A module-level function.

    Examples
    --------
    >>> evaluator_id(evaluator_id)
    'designlab.analysis.keys.evaluator_id'
    """
    module, qualname = getattr(fn, "__module__", None), getattr(fn, "__qualname__", None)
    if not module or not qualname or "<" in qualname:
        raise TypeError(
            f"an evaluator must be a module-level function (got {fn!r}): workers import it "
            "by its qualified name"
        )
    return f"{module}.{qualname}"


def source_files(module_name: str) -> list[Path]:
    """The sources that define a module's results: its whole ``designlab`` subpackage.

    For a module outside ``designlab`` (a user's evaluator, a test), its own file.

    Parameters
    ----------
    module_name
        A module's dotted name, e.g. ``"designlab.impact.evaluators"``.
    """
    module = sys.modules.get(module_name) or importlib.import_module(module_name)
    parts = module_name.split(".")
    if len(parts) >= 2 and parts[0] == "designlab":
        package = importlib.import_module(".".join(parts[:2]))
        root = Path(getattr(package, "__file__", "") or "")
        if root.name == "__init__.py":
            return sorted(root.parent.rglob("*.py"))
    path = getattr(module, "__file__", None)
    return [Path(path)] if path else []


@cache
def package_hash(module_name: str) -> str:
    """A 16-hex-digit hash of the sources of a module's package (:func:`source_files`).

    Cached per process (``package_hash.cache_clear()`` after editing sources
    in a running process).

    Parameters
    ----------
    module_name
        A module's dotted name; ``"designlab.report"`` hashes every report writer.
    """
    h = hashlib.sha256()
    files = source_files(module_name)
    base = files[0].parent if files else Path()
    for path in files:
        try:
            rel = path.relative_to(base).as_posix()
        except ValueError:
            rel = path.name
        h.update(rel.encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def code_version(fn: Callable[..., Any]) -> str:
    """designlab's version and a hash of the source of the package holding ``fn``.

    For an evaluator in ``designlab.impact.evaluators`` the hash covers every module
    of ``designlab/impact/``; for one defined elsewhere (a user's module, a
    test), that module's file.

    Parameters
    ----------
    fn
        The evaluator.
    """
    return f"{__version__}+{package_hash(fn.__module__)}"


def _canonical(obj: Any) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=True, default=float)


def chunk_key(
    fn: Callable[..., Any], options: Mapping[str, Any], points: Mapping[str, np.ndarray]
) -> str:
    """The content hash of a chunk: evaluator, its code, options and the point values.

    Parameters
    ----------
    fn
        The evaluator.
    options
        The evaluator options.
    points
        The chunk's point columns.

    Examples
    --------
    >>> import numpy as np
    >>> a = chunk_key(evaluator_id, {}, {"x": np.array([1.0, 2.0])})
    >>> b = chunk_key(evaluator_id, {}, {"x": np.array([1.0, 2.0 + 1e-15])})
    >>> len(a), a == b
    (64, False)
    """
    h = hashlib.sha256()
    header = {
        "format": KEY_FORMAT,
        "evaluator": evaluator_id(fn),
        "code": code_version(fn),
        "options": options,
        "columns": sorted(points),
    }
    h.update(_canonical(header).encode())
    for name in sorted(points):
        h.update(np.ascontiguousarray(points[name], dtype="<f8").tobytes())
    return h.hexdigest()


def indexed_chunk_keys(
    fn: Callable[..., Any], options: Mapping[str, Any], identity: str, n: int, size: int
) -> list[str]:
    """Keys of the chunks of ``n`` points whose values are fixed by ``identity``, by index.

    Chunk ``i`` holds points ``[i size, min((i + 1) size, n))``; its key hashes
    the evaluator, its code, its options, the source's identity
    (:meth:`~designlab.analysis.points.PointSource.identity`), ``n``, ``size``
    and ``i``, so it is known without drawing the chunk's points.

    Parameters
    ----------
    fn
        The evaluator.
    options
        The evaluator options.
    identity
        The identity of the point source.
    n
        The number of points.
    size
        Points per chunk.

    Examples
    --------
    >>> keys = indexed_chunk_keys(evaluator_id, {}, "a sampler", 5, 2)
    >>> len(keys), len(set(keys)), keys == indexed_chunk_keys(evaluator_id, {}, "other", 5, 2)
    (3, 3, False)
    """
    header = {
        "format": KEY_FORMAT,
        "indexed": True,
        "evaluator": evaluator_id(fn),
        "code": code_version(fn),
        "options": options,
        "points": identity,
        "n": int(n),
        "size": int(size),
    }
    run = hashlib.sha256(_canonical(header).encode()).hexdigest()
    return [
        hashlib.sha256(f"{run}:{i}".encode()).hexdigest() for i in range(-(-int(n) // int(size)))
    ]
