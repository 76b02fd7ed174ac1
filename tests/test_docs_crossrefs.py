"""The docs' cross-references: Sphinx roles and See Also entries become links, broken ones fail.

``docs/hooks/crossrefs.py`` is a griffe extension (the docstrings, rewritten in griffe's copy
only: ``help()`` keeps the roles) and a MkDocs hook (the roles written in Markdown pages). The
unit tests run the extension on a small package written here; the slow one builds a tiny
strict site with a broken reference. ``tests/test_docs_site.py`` checks the links of the
built site.
"""

from __future__ import annotations

import importlib.util
import logging
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

griffe = pytest.importorskip("griffe")


def load_hook():
    spec = importlib.util.spec_from_file_location(
        "crossrefs_hook", ROOT / "docs/hooks/crossrefs.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


PACKAGE = {
    "__init__.py": '''
        """The package: see :func:`xrefpkg.solve.run` and :mod:`~xrefpkg.solve`."""
        from xrefpkg.solve import run

        __all__ = ["run"]
    ''',
    "solve.py": '''
        """Solvers.

        :func:`run` runs, :class:`Plant` is what it runs, :func:`math.sqrt` is not ours,
        :data:`UNDOCUMENTED` has no docstring, :func:`!run` is not linked and
        :func:`the runner <run>` has a title.

        See Also
        --------
        run : one run.
        Plant, other.helper
            Two names, and a description
            on two lines.
        """
        import math

        UNDOCUMENTED = 1


        class Plant:
            """A plant; its :meth:`step` is a method, :meth:`helper` is found by name."""

            def step(self):
                """One step (:meth:`Plant.step`)."""


        def run(plant: Plant) -> float:
            """Run ``plant`` (:class:`Plant`); :func:`_private` is not on the site.

            >>> ":func:`doctest` lines are code"
            """
            return math.sqrt(2.0)


        def _private():
            """Private."""
    ''',
    "other.py": '''
        """Other."""


        def helper():
            """Help: :func:`~xrefpkg.solve.run` and :func:`nowhere` (broken)."""
    ''',
}


@pytest.fixture
def package(tmp_path: Path, caplog: pytest.LogCaptureFixture):
    """The test package loaded by griffe with the extension, and the warnings it logged."""
    root = tmp_path / "xrefpkg"
    root.mkdir()
    for name, text in PACKAGE.items():
        (root / name).write_text(textwrap.dedent(text).lstrip(), encoding="utf-8")
    hook = load_hook()
    extensions = griffe.load_extensions(hook.SphinxCrossReferences(package="xrefpkg"))
    with caplog.at_level(logging.WARNING, logger="mkdocs.hooks.crossrefs"):
        pkg = griffe.load("xrefpkg", search_paths=[str(tmp_path)], extensions=extensions)
    return pkg, caplog.text


def test_roles_become_autorefs_links_to_canonical_paths(package) -> None:
    pkg, _ = package
    top = pkg.docstring.value
    assert "[`xrefpkg.solve.run`][xrefpkg.solve.run]" in top
    assert "[`solve`][xrefpkg.solve]" in top  # ~ shows the last part
    solve = pkg["solve"].docstring.value
    assert "[`run`][xrefpkg.solve.run]" in solve
    assert "[`Plant`][xrefpkg.solve.Plant]" in solve
    assert "[`the runner`][xrefpkg.solve.run]" in solve
    assert ":func:" not in solve and ":class:" not in solve and ":data:" not in solve


def test_names_that_cannot_be_links_are_code(package) -> None:
    """Outside the package, undocumented, private, or ``!``: code without a link."""
    pkg, _ = package
    solve = pkg["solve"].docstring.value
    assert "`math.sqrt`" in solve and "][math" not in solve
    assert "`UNDOCUMENTED` has" in solve
    assert "`run` is not linked" in solve
    run = pkg["solve.run"].docstring.value
    assert "`_private` is not" in run
    assert '>>> ":func:`doctest` lines are code"' in run  # doctests are left alone


def test_scope_and_nearest_name(package) -> None:
    """A method by its class scope; a name not in scope is the package's one object of it."""
    pkg, _ = package
    plant = pkg["solve.Plant"].docstring.value
    assert "[`step`][xrefpkg.solve.Plant.step]" in plant
    assert "[`helper`][xrefpkg.other.helper]" in plant
    assert "[`Plant.step`][xrefpkg.solve.Plant.step]" in pkg["solve.Plant.step"].docstring.value


def test_see_also_becomes_a_list_of_links(package) -> None:
    pkg, _ = package
    solve = pkg["solve"].docstring.value
    assert "- [`run`][xrefpkg.solve.run]: one run." in solve
    assert (
        "- [`Plant`][xrefpkg.solve.Plant], [`other.helper`][xrefpkg.other.helper]: "
        "Two names, and a description on two lines."
    ) in solve


def test_a_broken_role_is_a_warning_naming_the_object(package) -> None:
    pkg, warnings = package
    assert "xrefpkg.other.helper" in warnings and ":func:`nowhere`" in warnings
    assert warnings.count("broken cross-reference") == 1
    assert "`nowhere`" in pkg["other.helper"].docstring.value


def test_the_source_keeps_its_roles() -> None:
    """help() shows the numpydoc roles: only griffe's copy is rewritten."""
    import designlab.report.impact as module

    assert ":meth:`designlab.study.kinds.impact_cases.ImpactCasesResult.to_frame`" in (
        module.__doc__ or ""
    )


def test_page_roles_link_full_paths_and_warn_on_broken(caplog: pytest.LogCaptureFixture) -> None:
    hook = load_hook()
    text = (
        "A :func:`designlab.impact.foam_envelope` and :class:`~designlab.impact.HeadNeck`.\n"
        "```python\n:func:`not.touched`\n```\n"
        ":data:`math.pi` and :func:`designlab.impact.nothing_here`.\n"
        "Quoted: ``:func:`simulate` `` stays as written."
    )
    with caplog.at_level(logging.WARNING, logger="mkdocs.hooks.crossrefs"):
        out = hook.page_roles(text, "page.md")
    assert (
        '<autoref identifier="designlab.impact.envelope.foam_envelope" optional>'
        "<code>designlab.impact.foam_envelope</code></autoref>"
    ) in out
    assert ">HeadNeck</code></autoref>" in out
    assert ":func:`not.touched`" in out and "<code>math.pi</code>" in out
    assert "``:func:`simulate` ``" in out
    assert "page.md" in caplog.text and "designlab.impact.nothing_here" in caplog.text


def test_a_role_left_as_text_in_a_page_is_a_warning(caplog: pytest.LogCaptureFixture) -> None:
    hook = load_hook()

    class Page:
        class file:
            src_uri = "guide.md"

    with caplog.at_level(logging.WARNING, logger="mkdocs.hooks.crossrefs"):
        hook.on_page_content("<p>:func:<code>simulate</code> and 1:2</p>", page=Page)
    assert "guide.md" in caplog.text and ":func:<code>simulate</code>" in caplog.text


BROKEN = '''
"""A module.

It calls :func:`solve`, which does not exist.
"""


def area(width: float) -> float:
    """The area (:func:`area`)."""
    return width
'''


@pytest.mark.slow
def test_a_broken_cross_reference_fails_the_strict_build(tmp_path: Path) -> None:
    """With the site's own mkdocstrings options and hooks, a broken role is an error."""
    import yaml

    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"))
    (plugin,) = [p for p in config["plugins"] if isinstance(p, dict) and "mkdocstrings" in p]
    handler = plugin["mkdocstrings"]["handlers"]["python"]
    hook = str(ROOT / "docs/hooks/crossrefs.py")
    handler["options"]["extensions"] = [{f"{hook}:SphinxCrossReferences": {"package": "badxref"}}]
    handler["paths"] = [str(tmp_path)]
    (tmp_path / "badxref.py").write_text(BROKEN, encoding="utf-8")
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs/index.md").write_text("::: badxref\n", encoding="utf-8")
    tiny = {"site_name": "tiny", "strict": True, "plugins": [plugin], "hooks": [hook]}
    (tmp_path / "mkdocs.yml").write_text(yaml.safe_dump(tiny), encoding="utf-8")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1", "DISABLE_MKDOCS_2_WARNING": "true"}
    proc = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(tmp_path / "site")],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env=env,
        check=False,
    )
    assert proc.returncode != 0
    assert "broken cross-reference :func:`solve`" in proc.stderr
    assert "badxref" in proc.stderr


def test_rest_literal_markers_read_as_sphinx_shows_them() -> None:
    hook = load_hook()
    assert hook.literal_marker("Every quantity is a symbol::") == "Every quantity is a symbol:"
    assert hook.literal_marker("    ::") == ""
    assert hook.literal_marker("A table ::") == "A table"
    assert hook.literal_marker("::: designlab.impact") == "::: designlab.impact"
    assert hook.literal_marker("a::b") == "a::b"
