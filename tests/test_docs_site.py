"""The documentation site builds strictly and holds its key pages, with its maths typeset.

``mkdocs build --strict`` turns every warning into an error: a broken link, a page missing
from the navigation's targets, a docstring section griffe cannot parse, a formula that
cannot be typeset. The reference pages are generated from the live package by
``docs/gen_pages.py``, so a module, a study kind or a CLI command that is added or moved
appears without an edit to the site. The examples of the pages run in
``tests/test_docs_examples.py``.

``.ci/run`` builds the site strictly as its own step and passes its directory in
``DESIGNLAB_DOCS_SITE``: these tests then read that build instead of building again, so CI
builds the site once.
"""

from __future__ import annotations

import html
import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

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
    "reference/parameters/index.html",
    "reference/api/designlab/index.html",
    "reference/api/designlab/impact/index.html",
    "reference/api/designlab/study/registry/index.html",
    "gallery/index.html",
    "python/index.html",
    "studies/index.html",
    "cli/index.html",
    "developers/index.html",
    "search/search_index.json",
]


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The site built with ``mkdocs build --strict`` (or the build ``.ci/run`` made)."""
    prebuilt = os.environ.get("DESIGNLAB_DOCS_SITE")
    if prebuilt and (Path(prebuilt) / "index.html").is_file():
        return Path(prebuilt)
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
def test_every_docs_page_is_built_and_in_the_navigation(site: Path) -> None:
    """A guide added to docs/ needs no edit of the site: it is built and in the navigation."""
    home = (site / "index.html").read_text(encoding="utf-8")
    for page in sorted((ROOT / "docs").glob("*.md")):
        target = "index.html" if page.stem == "index" else f"{page.stem}/index.html"
        assert (site / target).is_file(), page.name
        if page.stem != "index":
            assert f'href="{page.stem}/"' in home, f"{page.name} is not in the navigation"


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
def test_parameter_tables_cover_every_declared_class(site: Path) -> None:
    """One table per @declared class, generated from its declarations (parameter_table)."""
    import importlib
    import inspect
    import pkgutil

    import designlab
    from designlab.impact import Foam
    from designlab.params import params_of

    page = (site / "reference/parameters/index.html").read_text(encoding="utf-8")
    for info in pkgutil.walk_packages(designlab.__path__, "designlab."):
        if any(part.startswith("_") for part in info.name.split(".")):
            continue
        for obj in vars(importlib.import_module(info.name)).values():
            if (
                inspect.isclass(obj)
                and obj.__module__ == info.name
                and "__params__" in obj.__dict__
            ):
                assert f"{info.name}.{obj.__name__}" in page
    stiffness = params_of(Foam)["stiffness"]
    assert stiffness.allowed() in page.replace("&gt;", ">").replace("&lt;", "<")
    assert "<code>K_c</code>" in page and stiffness.doc in page


@pytest.mark.slow
def test_gallery_lists_every_report(site: Path) -> None:
    for report in sorted(p for p in (ROOT / "reports").iterdir() if p.is_dir()):
        page = site / "gallery" / report.name / "index.html"
        assert page.is_file(), report.name
        for png in report.glob("*.png"):
            assert (site / "gallery" / report.name / png.name).is_file()
        text = re.sub(r"<[^>]+>", "", html.unescape(page.read_text(encoding="utf-8")))
        for markdown in report.glob("*.md"):  # the report's own text is on its gallery page
            headings = re.findall(r"^## (.+)$", markdown.read_text(encoding="utf-8"), re.M)
            assert all(h.replace("`", "").strip() in text for h in headings[:3]), markdown


@pytest.mark.slow
def test_maths_is_typeset_as_mathml(site: Path) -> None:
    """Every formula of the site is MathML in the built HTML: no TeX left, no script needed."""
    home = (site / "index.html").read_text(encoding="utf-8")
    assert home.count('<math xmlns="http://www.w3.org/1998/Math/MathML"') >= 5
    assert 'display="block"' in home and "<mover>" in home  # the impact equation, x-double-dot
    assert "mathjax" not in home.lower() and "cdn." not in home
    leftover = []
    for page in site.rglob("*.html"):
        text = page.read_text(encoding="utf-8")
        for match in re.finditer(r'class="arithmatex">(?!<math)', text):
            leftover.append(f"{page.relative_to(site)}: {text[match.end() : match.end() + 60]}")
    assert not leftover


@pytest.mark.slow
def test_pages_load_nothing_from_the_network(site: Path) -> None:
    """No script, stylesheet or font comes from another host: the site works offline."""
    external = re.compile(r'<(?:script|link|img)\b[^>]*(?:src|href)="(?:https?:)?//', re.I)
    for page in ["index.html", "reference/api/designlab/impact/index.html", "gallery/index.html"]:
        text = (site / page).read_text(encoding="utf-8")
        assert not external.search(text), f"{page}: {external.search(text).group(0)}"
        assert "fonts.googleapis" not in text


@pytest.mark.slow
def test_the_api_pages_link_their_cross_references(site: Path) -> None:
    """No role is left as text anywhere on the site; the API pages hold the links."""
    left = re.compile(r":(?:func|class|mod|meth|attr|data|obj|exc|const):<code>")
    for page in site.rglob("*.html"):
        text = page.read_text(encoding="utf-8")
        assert not left.search(text), page.relative_to(site)
    page = (site / "reference/api/designlab/impact/problem/index.html").read_text(encoding="utf-8")
    assert re.search(r'<a class="autorefs autorefs-internal"[^>]*href="[^"]*boundaries/#', page)
    links = 0
    for page in (site / "reference/api").rglob("*.html"):
        links += page.read_text(encoding="utf-8").count('class="autorefs autorefs-internal"')
    assert links > 500


def test_mathml_hook_converts_arithmatex_output() -> None:
    hook = load_hook("mathml")
    text = (
        '<p>a <span class="arithmatex">\\(K_c &lt; 10^{4}\\)</span> b</p>'
        '<div class="arithmatex">\\[\n\\frac{a}{b}\n\\]</div>'
    )
    out = hook.typeset(text, "page.md")
    assert '<span class="arithmatex"><math' in out and 'display="inline"' in out
    assert '<div class="arithmatex"><math' in out and 'display="block"' in out
    assert "<mfrac>" in out and "&#x0003C;" in out and "\\(" not in out and "\\[" not in out


@pytest.mark.parametrize("tex", ["a^", "\\left( x", "\\notacommand x"])
def test_mathml_hook_warns_on_bad_tex(tex: str, caplog: pytest.LogCaptureFixture) -> None:
    """Bad TeX is a warning (so the strict build fails) naming the page, and stays as TeX."""
    hook = load_hook("mathml")
    text = f'<span class="arithmatex">\\({tex}\\)</span>'
    with caplog.at_level("WARNING", logger="mkdocs.hooks.mathml"):
        out = hook.typeset(text, "page.md")
    assert out == text
    assert "page.md" in caplog.text and tex in caplog.text


def load_hook(name: str):
    spec = importlib.util.spec_from_file_location(f"{name}_hook", ROOT / f"docs/hooks/{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_griffe_extension_shows_declared_defaults() -> None:
    griffe = pytest.importorskip("griffe")
    hook = load_hook("griffe_params")
    extensions = griffe.load_extensions(hook.DeclaredFieldDefaults())
    module = griffe.load("designlab.impact.parameters", extensions=extensions)
    defaults = {p.name: p.default for p in module["Foam"].parameters if p.name != "self"}
    assert defaults == {
        "stiffness": None,
        "damping": None,
        "linear_depth": "0.02",
        "thickness": "None",
        "name": "''",
    }
    # a field reusing a module-level declaration: as_field(K_MECH), as_field(C_MECH, default=0.0)
    module = griffe.load("designlab.impact.series_joint", extensions=extensions)
    defaults = {p.name: p.default for p in module["FullJointLink"].parameters}
    assert defaults["transmission_stiffness"] is None
    assert defaults["transmission_damping"] == "0.0"
    assert not any("as_field" in str(d) for d in defaults.values())


def test_griffe_extension_reads_comment_docstrings() -> None:
    """A constant documented by ``#:`` lines has them as its docstring (so an API entry)."""
    griffe = pytest.importorskip("griffe")
    hook = load_hook("griffe_params")
    module = griffe.load(
        "designlab.codesign.front", extensions=griffe.load_extensions(hook.CommentDocstrings())
    )
    doc = module["THESIS_DESIGNS"].docstring
    assert doc is not None and doc.value.startswith("The thesis's designs placed against a front")
    model = griffe.load(
        "designlab.impact.model", extensions=griffe.load_extensions(hook.CommentDocstrings())
    )
    assert model["INPUT_NAMES"].docstring is None  # no comment above it: nothing invented


BAD_DOCSTRING = '''
def area(width, height):
    """The area.

    Parameters
    ----------
    width : float
        The width.
    depth : float
        Not a parameter of the function.
    """
    return width * height
'''


@pytest.mark.slow
def test_a_docstring_that_does_not_parse_fails_the_strict_build(tmp_path: Path) -> None:
    """With the site's own mkdocstrings options, a wrong Parameters entry is an error."""
    import yaml

    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"))
    (plugin,) = [p for p in config["plugins"] if isinstance(p, dict) and "mkdocstrings" in p]
    handler = plugin["mkdocstrings"]["handlers"]["python"]
    handler["options"] = {k: v for k, v in handler["options"].items() if k != "extensions"}
    handler["paths"] = [str(tmp_path)]
    (tmp_path / "badpkg.py").write_text(BAD_DOCSTRING, encoding="utf-8")
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs/index.md").write_text("::: badpkg\n", encoding="utf-8")
    tiny = {"site_name": "tiny", "strict": True, "plugins": [plugin]}
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
    assert "'depth' does not appear in the function signature" in proc.stderr


def load_tool(name: str):
    spec = importlib.util.spec_from_file_location(f"{name}_tool", ROOT / f"docs/tools/{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow
def test_rendered_pages_in_chromium(site: Path, tmp_path: Path) -> None:
    """Home, an API page and a gallery page in headless Chromium: maths, navigation, search.

    ``docs/tools/screenshots.py`` serves the built site on localhost, saves the screenshots
    (look at them when changing the site's layout) and checks the rendered DOM: MathML, every
    navigation link answering 200, images loaded and within the page, no page scrolling
    sideways, no script error, and a search that returns results.
    """
    tool = load_tool("screenshots")
    chromium = tool.find_chromium()
    required = os.environ.get("DESIGNLAB_REQUIRE_BROWSER") == "1"  # .ci/run: never skipped
    if chromium is None:
        assert not required, "no Chromium (.ci/run installs Debian's chromium when missing)"
        pytest.skip("no Chromium on this machine (chromium, $DESIGNLAB_CHROMIUM): not rendered")
    if required:
        import playwright.sync_api  # noqa: F401  (a dev dependency: its absence is a failure)
    pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
    # the screenshots are CI's artefact when DESIGNLAB_SCREENSHOTS names a directory
    out = Path(os.environ.get("DESIGNLAB_SCREENSHOTS") or tmp_path)
    report = tool.render(site, out, chromium)
    assert not report["problems"], report["problems"]
    for name in (*tool.PAGES, "search"):
        assert (out / f"{name}.png").stat().st_size > 10_000, name
    assert report["pages"]["home"]["math"] >= 5
    assert report["pages"]["gallery"]["images"] and report["pages"]["gallery"]["tables"]
    assert len(report["nav"]) > 20 and set(report["nav"].values()) == {200}
    assert report["links"] and set(report["links"].values()) == {200}
    assert report["search"]["results"] > 0 and report["search_index"]["docs"] > 100


@pytest.mark.slow
def test_the_gallery_groups_every_report_by_its_study_kind(site: Path) -> None:
    """A report added under reports/ appears in the gallery with no edit (its section from its
    study's kind, an unknown kind under "Other studies")."""
    index = (site / "gallery/index.html").read_text(encoding="utf-8")
    for report in (p for p in (ROOT / "reports").iterdir() if p.is_dir() and any(p.glob("*.md"))):
        assert f'href="{report.name}/"' in index, report.name
    assert "Impact safety" in index and "Tether follower" in index


def test_gallery_sections_follow_the_kind() -> None:
    pytest.importorskip("mkdocs_gen_files")
    spec = importlib.util.spec_from_file_location("gen_pages", ROOT / "docs/gen_pages.py")
    gen_pages = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen_pages)  # imported, it writes nothing
    assert gen_pages.gallery_section("impact_cases") == "Impact safety"
    assert gen_pages.gallery_section("foam_envelope_sweep") == "Impact safety"
    assert gen_pages.gallery_section("navigation_gains") == "Navigation among people"
    assert gen_pages.gallery_section("tether_modes") == "Tether follower"
    assert gen_pages.gallery_section("codesign") == "Co-design"
    assert gen_pages.gallery_section("my_own_kind") == "Other studies"
    assert gen_pages.first_sentence("Does it work? It does.") == "Does it work?"


def test_study_reference_headings_are_readable() -> None:
    """pydantic's ``$defs`` names (module paths, generic parameters) are not headings."""
    pytest.importorskip("mkdocs_gen_files")
    from designlab.study.registry import study_json_schema

    spec = importlib.util.spec_from_file_location("gen_pages", ROOT / "docs/gen_pages.py")
    gen_pages = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen_pages)  # imported, it writes nothing
    title = gen_pages.model_title
    assert title("designlab__study__kinds__accompanying__TuningSpec") == "TuningSpec (accompanying)"
    assert title("SensitivitySpec_Literal__a_h_max_g____eps_max_m___") == (
        "SensitivitySpec (a_h_max_g, eps_max_m)"
    )
    assert title("RobotSpec") == "RobotSpec"
    titles = [title(name) for name in study_json_schema()["$defs"]]
    assert not [t for t in titles if "__" in t or "Literal" in t], titles
    assert len(set(titles)) == len(titles)  # still one heading per model


@pytest.mark.slow
def test_gallery_descriptions_are_whole(site: Path) -> None:
    """Each report's description stands whole in the gallery's index (issue 39: 17 of 25 were
    cut at an abbreviation such as "Zeng 2011 Ch." or "Wu et al.")."""
    import yaml

    index = re.sub(r"<[^>]+>", "", html.unescape((site / "gallery/index.html").read_text("utf-8")))
    index = " ".join(index.split())
    for study in sorted((ROOT / "reports").glob("*/study.yaml")):
        description = yaml.safe_load(study.read_text(encoding="utf-8")).get("description")
        if description:
            assert " ".join(str(description).split()) in index, study.parent.name


@pytest.mark.slow
def test_every_example_has_a_page(site: Path) -> None:
    """The examples gallery: a page per script of ``examples/`` with its code, and an index."""
    index = (site / "examples/index.html").read_text(encoding="utf-8")
    for script in sorted((ROOT / "examples").glob("*.py")):
        page = site / "examples" / script.stem / "index.html"
        assert page.is_file() and f'href="{script.stem}/"' in index, script.name
        assert "import designlab as dl" in html.unescape(
            re.sub(r"<[^>]+>", "", page.read_text(encoding="utf-8"))
        )


@pytest.mark.slow
def test_no_navigation_file_is_a_page(site: Path) -> None:
    """literate-nav's SUMMARY.md files make the navigation, not pages of the site."""
    assert not [p for p in site.rglob("SUMMARY/index.html")], "a SUMMARY page was built"


#: How the README and the guides name designlab's modules in their code (``nav = dl.navigation``).
_ALIAS = re.compile(r"\b([a-z_]+) = (?:dl|designlab)\.([\w.]+)\s*$", re.M)
_IMPORT_AS = re.compile(r"import (designlab[\w.]*) as (\w+)")
_FROM_IMPORT = re.compile(r"^\s*(?:>>> )?from (designlab[\w.]*) import ([\w, ]+)$", re.M)


def used_names() -> dict[str, str]:
    """Every ``designlab...`` name the README and the guides write: full path -> first page.

    ``dl.impact.simulate``, ``fol.accompany`` (with ``fol = dl.following`` on the page),
    ``from designlab.x import a, b as c`` and ``designlab.x.y`` written out (not a file's
    path: ``benchmarks/full_joint.py``).
    """
    found: dict[str, str] = {}
    for page in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        text = page.read_text(encoding="utf-8")
        aliases = {"dl": "designlab", "designlab": "designlab"}
        aliases |= {m[2]: m[1] for m in _IMPORT_AS.finditer(text)}
        aliases |= {m[1]: f"designlab.{m[2]}" for m in _ALIAS.finditer(text)}
        for m in _FROM_IMPORT.finditer(text):
            for item in m[2].split(","):
                name, _, alias = item.strip().partition(" as ")
                if name:
                    found.setdefault(f"{m[1]}.{name}", page.name)
                    aliases[alias or name] = f"{m[1]}.{name}"
        prefix = "|".join(re.escape(a) for a in aliases)
        for m in re.finditer(rf"(?<![\w./])({prefix})((?:\.[A-Za-z_]\w*)+)", text):
            found.setdefault(aliases[m[1]] + m[2], page.name)
    return found


def _module_and_name(path: str) -> tuple[Any, str] | None:
    """The module a dotted name is an attribute of, and the name (``None``: a module itself,
    or an attribute of a class or object, documented on its class's entry)."""
    parts = path.split(".")
    for cut in range(len(parts), 0, -1):
        module = _module(".".join(parts[:cut]))
        if module is None:
            continue
        return (module, parts[cut]) if cut == len(parts) - 1 else None
    return None


def _module(name: str) -> Any:
    """The module ``name`` (``None`` if it is not one: a class's path)."""
    import importlib

    try:
        return importlib.import_module(name)
    except ImportError:
        return None


@pytest.mark.slow
def test_every_name_the_guides_use_has_an_api_entry(site: Path) -> None:
    """``fol.accompany`` and every other name of the README and the guides has an entry (an
    anchor ``<module>.<name>`` on a module's API page) under the name the text uses."""

    anchors: dict[str, set[str]] = {}  # name -> modules whose page holds <module>.<name>
    for page in (site / "reference/api").rglob("index.html"):
        for anchor in re.findall(r'id="(designlab(?:\.\w+)+)"', page.read_text(encoding="utf-8")):
            module, _, name = anchor.rpartition(".")
            anchors.setdefault(name, set()).add(module)
    missing, unknown = [], []
    for path, page in sorted(used_names().items()):
        found = _module_and_name(path)
        if found is None:
            continue
        module, name = found
        if not hasattr(module, name):
            if not name.startswith("_"):
                unknown.append(f"{path} ({page})")
            continue
        obj = getattr(module, name)
        if isinstance(obj, type(module)):
            continue  # a module: its own page
        holders = anchors.get(name, set())
        if not any(getattr(_module(m), name, None) is obj for m in holders):
            missing.append(f"{path} ({page})")
    assert not unknown, f"names the pages use that designlab does not have: {unknown}"
    assert not missing, f"names the pages use without an API entry: {missing}"
