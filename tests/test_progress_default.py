"""A long solver shows progress on a terminal by default and is silent otherwise (issue 39,
item 6): :func:`designlab.progress.report` without a hook."""

from __future__ import annotations

import io

import pytest

from designlab import progress
from designlab.progress import ENV, Progress, report


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def _run(steps: int = 3) -> None:
    for i in range(steps):
        report(None, Progress(step=i + 1, total=steps, best=1.0 / (i + 1), label="generation"))


@pytest.mark.parametrize(("stream", "mode", "shown"), [
    (_Terminal(), None, True), (io.StringIO(), None, False), (_Terminal(), "off", False),
    (io.StringIO(), "on", True),
])  # fmt: skip
def test_the_default_bar_follows_the_terminal_and_the_variable(
    stream: io.StringIO, mode: str | None, shown: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr("sys.stderr", stream)
    if mode is None:
        monkeypatch.delenv(ENV, raising=False)
    else:
        monkeypatch.setenv(ENV, mode)
    _run()
    text = stream.getvalue()
    assert ("generation" in text and "/3 [" in text) is shown, text
    assert progress._TERMINAL.bar is None  # the bar of a finished run is closed


def test_a_hook_of_the_caller_replaces_the_bar(monkeypatch: pytest.MonkeyPatch) -> None:
    stream = _Terminal()
    monkeypatch.setattr("sys.stderr", stream)
    seen: list[Progress] = []
    report(seen.append, Progress(step=1, total=1))
    assert [p.step for p in seen] == [1] and stream.getvalue() == ""
