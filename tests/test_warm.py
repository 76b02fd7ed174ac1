"""``designlab compile``: compiles ahead, saying what and why; unknown steps are refused."""

from __future__ import annotations

from typer.testing import CliRunner

from designlab.cli import EXIT_STUDY_ERROR, app
from designlab.warm import STEPS

runner = CliRunner()


def test_compile_says_what_it_compiles_and_why() -> None:
    result = runner.invoke(app, ["compile", "--only", "sampling"])
    assert result.exit_code == 0, result.output
    first, second = result.stdout.splitlines()
    assert first.startswith("compiling the Latin hypercube sampler of sweeps (numba): ")
    assert "compiled on first use" in first and "cached in" in first
    assert second.startswith("  sampling: ") and second.endswith(" CPU s)")


def test_an_unknown_step_is_refused() -> None:
    result = runner.invoke(app, ["compile", "--only", "impakt"])
    assert result.exit_code == EXIT_STUDY_ERROR
    known = [name for name, _, _ in STEPS]
    assert f"unknown compile step(s) ['impakt']: known are {known}" in result.stderr
