"""The documentation site builds strictly and holds its key pages; its examples run.

``mkdocs build --strict`` turns every warning into an error: a broken link, a page missing
from the navigation's targets, a docstring section griffe cannot parse. The reference pages
are generated from the live package by ``docs/gen_pages.py``, so a module, a study kind or
a CLI command that is added or moved appears without an edit to the site.
"""

from __future__ import annotations

import doctest
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

pytest.importorskip("mkdocs")
pytest.importorskip("mkdocstrings_handlers.python")
pytest.importorskip("mkdocs_gen_files")
pytest.importorskip("material")

KEY_PAGES = [
    "index.html",
    "getting-started/index.html",
    "impact/index.html",
    "reference/studies/index.html",
    "reference/cli/index.html",
    "reference/api/designlab/index.html",
    "reference/api/designlab/impact/index.html",
    "reference/api/designlab/study/registry/index.html",
    "gallery/index.html",
    "search/search_index.json",
]


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The site built with ``mkdocs build --strict`` into a temporary directory."""
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1", "DISABLE_MKDOCS_2_WARNING": "true"}
    proc = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=env,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr[-4000:]
    return out


@pytest.mark.slow
def test_key_pages_exist(site: Path) -> None:
    missing = [page for page in KEY_PAGES if not (site / page).is_file()]
    assert not missing


@pytest.mark.slow
def test_reference_pages_follow_the_package(site: Path) -> None:
    from designlab.study.registry import study_json_schema

    studies = (site / "reference/studies/index.html").read_text(encoding="utf-8")
    for kind in study_json_schema()["discriminator"]["mapping"]:
        assert f"kind-{kind}" in studies
    cli = (site / "reference/cli/index.html").read_text(encoding="utf-8")
    assert "designlab run" in cli and "Usage:" in cli
    api = (site / "reference/api/designlab/impact/index.html").read_text(encoding="utf-8")
    assert "simulate" in api


@pytest.mark.slow
def test_gallery_lists_every_report(site: Path) -> None:
    for report in sorted(p for p in (ROOT / "reports").iterdir() if p.is_dir()):
        page = site / "gallery" / report.name / "index.html"
        assert page.is_file(), report.name
        for png in report.glob("*.png"):
            assert (site / "gallery" / report.name / png.name).is_file()


@pytest.mark.parametrize("page", ["index.md", "getting-started.md"])
def test_site_page_examples_run(page: str) -> None:
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    result = doctest.testfile(str(ROOT / "docs" / page), module_relative=False, optionflags=flags)
    assert result.failed == 0
