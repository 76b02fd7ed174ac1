"""docs/studies.md lists every committed study, and nothing that is not one."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def test_the_studies_page_lists_every_committed_study() -> None:
    text = (ROOT / "docs" / "studies.md").read_text(encoding="utf-8")
    listed = set(re.findall(r"^\| `studies/([a-z0-9_]+)\.yaml` \|", text, flags=re.M))
    committed = {p.stem for p in (ROOT / "studies").glob("*.yaml")}
    assert listed == committed, (sorted(committed - listed), sorted(listed - committed))
