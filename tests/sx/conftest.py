"""Every test of designlab.sx compiles into a cache directory of its own session."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True)
def _private_cache(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch):
    root = tmp_path_factory.getbasetemp() / "sx cache; dir"  # a space and a metacharacter
    monkeypatch.setenv("DESIGNLAB_CACHE_DIR", str(root))
    yield root
