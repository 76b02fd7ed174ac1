"""Every public impact function, and the impact report writers, document every parameter
(numpydoc ``Parameters`` section) and carry a runnable ``Examples`` section (run as doctests).

In the manner of python-control's ``control/tests/docstrings_test.py``.
"""

from __future__ import annotations

import inspect
import re

import pytest

import designlab.impact as impact
import designlab.report.envelope as report_envelope
import designlab.report.impact as report_impact


def _public_functions() -> list[tuple[str, object]]:
    out = []
    for name in impact.__all__:
        obj = getattr(impact, name)
        if inspect.isfunction(obj):
            out.append((f"designlab.impact.{name}", obj))
    for mod in (report_envelope, report_impact):
        for name in getattr(mod, "__all__", []):
            obj = getattr(mod, name)
            if inspect.isfunction(obj):
                out.append((f"{mod.__name__}.{name}", obj))
    return out


def _section(doc: str, title: str) -> str | None:
    m = re.search(rf"^\s*{title}\n\s*-+\n(.*?)(?=^\s*\w[\w ]*\n\s*-+\n|\Z)", doc, re.S | re.M)
    return m.group(1) if m else None


def _documented(section: str) -> set[str]:
    names: set[str] = set()
    for line in section.splitlines():
        m = re.match(r"^    (\*{0,2}[A-Za-z_][\w, *]*?)(\s*:.*)?$", line)
        if m and not line.startswith("        "):
            names |= {n.strip().lstrip("*") for n in m.group(1).split(",")}
    return names


@pytest.mark.parametrize(
    ("name", "fn"), _public_functions(), ids=lambda x: x if isinstance(x, str) else "fn"
)
def test_every_parameter_is_documented_with_an_example(name: str, fn) -> None:
    doc = inspect.getdoc(fn) or ""
    doc = "\n".join("    " + ln if ln else ln for ln in doc.splitlines())
    params = [
        p.name
        for p in inspect.signature(fn).parameters.values()
        if p.name not in ("self", "cls") and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
    ]
    if params:
        section = _section(doc, "Parameters")
        assert section is not None, f"{name}: no Parameters section"
        missing = [p for p in params if p not in _documented(section)]
        assert not missing, f"{name}: parameters not documented: {missing}"
    examples = _section(doc, "Examples")
    assert examples is not None and ">>>" in examples, f"{name}: no runnable Examples section"
