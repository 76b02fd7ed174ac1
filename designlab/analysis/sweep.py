"""Deprecated: the sweep engine is :mod:`designlab.analysis.engine` (keys in
:mod:`designlab.analysis.keys`, column helpers in :mod:`designlab.analysis.columns`).

This module re-exports the old names for one release; import them from their
new homes.
"""

from __future__ import annotations

from designlab.analysis.engine import (
    DEFAULT_CHUNK_SIZE,
    STATUS_ERROR,
    CacheIncompleteError,
    Columns,
    Evaluator,
    ResultStore,
    StoredRows,
    SweepRun,
    as_columns,
    evaluate_chunk,
    run_points,
)
from designlab.analysis.keys import (
    KEY_FORMAT,
    chunk_key,
    code_version,
    evaluator_id,
    package_hash,
    source_files,
)

__all__ = [
    "DEFAULT_CHUNK_SIZE",
    "KEY_FORMAT",
    "STATUS_ERROR",
    "CacheIncompleteError",
    "Columns",
    "Evaluator",
    "ResultStore",
    "StoredRows",
    "SweepRun",
    "as_columns",
    "chunk_key",
    "code_version",
    "evaluate_chunk",
    "evaluator_id",
    "run_points",
]

# the old private spellings, for code written against them (one release)
_package_hash = package_hash
_source_files = source_files
