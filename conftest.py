"""Repository-wide pytest hooks: the CPU time of each test, for keeping the test command fast.

With ``DESIGNLAB_TEST_CPU_LOG=<file>`` set, every test (the tests, the modules' examples and
the README's) appends a line ``<CPU s>\\t<wall s>\\t<node id>`` to the file, from whichever
xdist worker ran it (setup, call and teardown; a module or session fixture counts in the
first test that needs it; CPU of child processes counts once they have ended), and the run
ends with the CPU seconds per file. On a machine shared with other jobs CPU time, not wall
time, says which files the README's test command spends its time in (docs/developers.md).
"""

from __future__ import annotations

import os
import resource
import time
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

CPU_LOG = os.environ.get("DESIGNLAB_TEST_CPU_LOG")

#: Module examples run in the slow step only (``-m slow``), with why. Each compiles a second
#: copy of a compiled kernel for the argument types of a call from Python (the library calls
#: it from other kernels, with other types), about a CPU minute on a cold cache; the kernels
#: themselves run in the README's command through the tests of their callers.
SLOW_EXAMPLES = {
    "designlab.impact.kernel_lobe": "march and maximum called from Python: 61 CPU s cold",
}
_started: dict[str, tuple[float, float]] = {}
_runs_tests = [True]  # False in pytest-xdist's controller (the workers run the tests)


def pytest_configure(config: Any) -> None:
    distributed = getattr(config.option, "dist", "no") != "no"
    _runs_tests[0] = bool(os.environ.get("PYTEST_XDIST_WORKER")) or not distributed


def _cpu() -> float:
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


@pytest.hookimpl(tryfirst=True)  # before -m "not slow" deselects
def pytest_collection_modifyitems(items: list[Any]) -> None:
    for item in items:
        if item.nodeid.rsplit("::", 1)[-1] in SLOW_EXAMPLES:
            item.add_marker(pytest.mark.slow)


def pytest_runtest_logstart(nodeid: str, location: Any) -> None:
    if CPU_LOG and _runs_tests[0]:
        _started[nodeid] = (_cpu(), time.perf_counter())


def pytest_runtest_logfinish(nodeid: str, location: Any) -> None:
    if CPU_LOG and nodeid in _started:
        cpu, wall = _started.pop(nodeid)
        line = f"{_cpu() - cpu:.3f}\t{time.perf_counter() - wall:.3f}\t{nodeid}\n"
        with open(CPU_LOG, "a", encoding="utf-8") as log:  # one short append per test
            log.write(line)


def cpu_by_file(path: Path) -> Counter[str]:
    """CPU seconds per file of a log written by these hooks (the last line of each test)."""
    tests: dict[str, float] = {}
    for line in path.read_text(encoding="utf-8").splitlines():
        cpu, _, nodeid = line.split("\t", 2)
        tests[nodeid] = float(cpu)
    totals: Counter[str] = Counter()
    for nodeid, cpu in tests.items():
        totals[nodeid.split("::")[0]] += cpu
    return totals


def pytest_terminal_summary(terminalreporter: Any) -> None:
    if not CPU_LOG or not Path(CPU_LOG).is_file() or os.environ.get("PYTEST_XDIST_WORKER"):
        return
    totals = cpu_by_file(Path(CPU_LOG))
    terminalreporter.section(f"CPU seconds per file ({sum(totals.values()):.1f} in all)")
    for name, cpu in totals.most_common(40):
        terminalreporter.write_line(f"{cpu:9.1f}  {name}")
