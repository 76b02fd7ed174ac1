"""Deprecated: the result store lives beside the sweep engine, in
:mod:`designlab.analysis.store`.

This module re-exports its names for one release.
"""

from __future__ import annotations

from designlab.analysis.store import STORE_FORMAT, ChunkStore, StoreError, open_store

__all__ = ["STORE_FORMAT", "ChunkStore", "StoreError", "open_store"]
