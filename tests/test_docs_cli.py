"""``designlab docs``: builds (strictly) or serves the documentation site with mkdocs.

The command only hands over to mkdocs, so these tests check what it hands over (the
strict build itself is tests/test_docs_site.py's, and CI's own step).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest
from typer.testing import CliRunner

import designlab.cli as cli

runner = CliRunner()


@pytest.fixture
def calls(monkeypatch: pytest.MonkeyPatch) -> list[dict]:
    """The subprocess.run calls the command makes (nothing is run)."""
    made: list[dict] = []

    def fake_run(command, **kwargs):
        made.append({"command": command, **kwargs})
        return SimpleNamespace(returncode=0)

    monkeypatch.setattr(subprocess, "run", fake_run)
    return made


def test_docs_serves_the_site_and_opens_it(calls: list[dict]) -> None:
    result = runner.invoke(cli.app, ["docs"])
    assert result.exit_code == 0, result.output
    (call,) = calls
    assert call["command"][:4] == [sys.executable, "-m", "mkdocs", "serve"]
    assert "--open" in call["command"] and "127.0.0.1:8000" in call["command"]
    assert call["command"][-2:] == ["--config-file", str(cli.MKDOCS_CONFIG)]
    assert call["cwd"] == cli.MKDOCS_CONFIG.parent
    assert cli.MKDOCS_CONFIG == Path(__file__).resolve().parent.parent / "mkdocs.yml"


def test_docs_build_is_strict(calls: list[dict], tmp_path: Path) -> None:
    result = runner.invoke(cli.app, ["docs", "--build", "--site-dir", str(tmp_path / "s")])
    assert result.exit_code == 0, result.output
    command = calls[0]["command"]
    assert command[3:5] == ["build", "--strict"]
    assert command[command.index("--site-dir") + 1] == str((tmp_path / "s").resolve())


def test_docs_passes_on_mkdocs_exit_code(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(subprocess, "run", lambda *a, **k: SimpleNamespace(returncode=1))
    assert runner.invoke(cli.app, ["docs", "--build"]).exit_code == 1


def test_docs_without_a_checkout_says_so(
    calls: list[dict], monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setattr(cli, "MKDOCS_CONFIG", tmp_path / "mkdocs.yml")
    result = runner.invoke(cli.app, ["docs", "--no-open"])
    assert result.exit_code == cli.EXIT_DESIGNLAB_ERROR
    assert "checkout" in result.output
    assert not calls
