"""Every test of designlab.sx compiles into a cache directory of its own."""

from __future__ import annotations

from pathlib import Path

import pytest


@pytest.fixture(autouse=True)
def _private_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    root = tmp_path / "sx cache; dir"  # a space and a shell metacharacter
    monkeypatch.setenv("DESIGNLAB_CACHE_DIR", str(root))
    return root
