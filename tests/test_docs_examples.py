"""Every example of the README and the documentation site runs as printed.

The pages are found, not listed: ``README.md`` and every ``docs/**/*.md``, so a guide that is
added is covered without an edit here. For each page:

* its ``>>>`` examples run as a doctest (the README's through pytest's own
  ``--doctest-glob=README.md``, checked below, so they are not run twice);
* its other ``python`` blocks run in order in one namespace per page, as a reader pasting
  them one after the other would run them;
* its ``yaml`` blocks that are study files (``designlab: 1``) load as ``designlab validate``
  loads them (schema, the domain models' own rules, caps);
* every ``designlab run|validate|report STUDY.yaml`` in a shell block names a study that
  exists and loads.

A block that is a sketch and cannot run (a template with ``...``) is marked in the page by
the HTML comment ``<!-- example: not run (why) -->`` on the line before its fence; the comment
does not show on the site. The examples of the generated pages are the docstrings' Examples
(the API reference), which pytest's ``--doctest-modules`` runs, and the committed studies
(the report gallery), which the study tests run.
"""

from __future__ import annotations

import doctest
import re
import shlex
from dataclasses import dataclass
from pathlib import Path

import pytest

from designlab.study import load_study, parse_study

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
FENCE = re.compile(
    r"^(?P<indent> *)```(?P<lang>[\w-]*)[^\n]*\n(?P<body>.*?)^(?P=indent)```", re.M | re.S
)
NOT_RUN = re.compile(r"<!--\s*example:\s*not run\b.*?-->\s*$")

# Blocks of pages this file's owners do not edit, kept out of the run with the reason; the
# key is (page, a line of the block). Each one is a gap to close in its page.
SKIPPED: dict[tuple[str, str], str] = {}
BROKEN: dict[tuple[str, str], str] = {}


@dataclass(frozen=True)
class Block:
    """One fenced code block of a page."""

    page: str
    line: int
    lang: str
    body: str
    marked_not_run: bool

    @property
    def where(self) -> str:
        return f"{self.page}:{self.line}"


def blocks(path: Path) -> list[Block]:
    """The fenced code blocks of a Markdown page, in order (indented ones dedented)."""
    text = path.read_text(encoding="utf-8")
    found = []
    for match in FENCE.finditer(text):
        indent = len(match["indent"])
        body = "\n".join(line[indent:] for line in match["body"].splitlines()) + "\n"
        before = text[: match.start()].rstrip("\n").rsplit("\n", 1)[-1]
        found.append(
            Block(
                page=path.relative_to(ROOT).as_posix(),
                line=text.count("\n", 0, match.start()) + 1,
                lang=match["lang"],
                body=body,
                marked_not_run=bool(NOT_RUN.search(before)),
            )
        )
    return found


def listed(table: dict[tuple[str, str], str], block: Block) -> str | None:
    """The reason a block is in ``SKIPPED`` or ``BROKEN`` (None if it is not)."""
    for (page, line), reason in table.items():
        if page == block.page and line in block.body:
            return reason
    return None


def page_id(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


def test_the_examples_are_found() -> None:
    """The parser sees the README's and the guides' blocks (a guard against a silent regex)."""
    readme = blocks(ROOT / "README.md")
    assert {b.lang for b in readme} >= {"bash", "python"}
    assert any(">>>" in b.body for b in readme)
    assert len(PAGES) >= 5


README_RUN = (
    "python3 -m venv .venv && .venv/bin/pip install -e . && "
    ".venv/bin/designlab run studies/zeng_ch4_validation.yaml"
)
README_TEST = (
    "python3 -m venv .venv && .venv/bin/pip install -e '.[dev]' && "
    ".venv/bin/python -m pytest -n auto"
)


def test_readme_starts_with_the_two_commands() -> None:
    """Install and run the default study (writing reports/zeng_ch4_validation/); install
    and run the tests, exactly as ``.ci/run`` does."""
    shell = [b.body.strip() for b in blocks(ROOT / "README.md") if b.lang == "bash"]
    assert shell[:2] == [README_RUN, README_TEST]
    assert load_study(ROOT / "studies/zeng_ch4_validation.yaml").name == "zeng_ch4_validation"
    ci = (ROOT / ".ci/run").read_text(encoding="utf-8")
    assert "-m venv" in ci and "pip install --quiet -e '.[dev]'" in ci
    assert '"$VENV/bin/python" -m pytest -n auto </dev/null' in ci


def test_readme_links_exist() -> None:
    """The README's relative links (into docs/) point at files that exist."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    targets = re.findall(r"\]\(([^)#:\s]+)(?:#[^)]*)?\)", text)
    assert targets
    missing = [t for t in targets if not (ROOT / t).exists()]
    assert not missing


def test_readme_doctests_run_through_pytest() -> None:
    """The README's ``>>>`` examples are collected by pytest itself (not repeated here)."""
    config = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    assert re.search(r'^testpaths = \[[^]]*"README.md"', config, re.M)
    assert re.search(r'^addopts = "[^"]*--doctest-glob=README.md', config, re.M)


DOCTEST_PAGES = [
    p for p in PAGES if p.name != "README.md" and any(">>>" in b.body for b in blocks(p))
]


@pytest.mark.parametrize("path", DOCTEST_PAGES, ids=page_id)
def test_page_doctests(path: Path, tmp_path: Path, monkeypatch) -> None:
    """The page's ``>>>`` blocks run as one doctest session (a fence may close right after
    the last output line: each block is parsed on its own)."""
    monkeypatch.chdir(tmp_path)
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    parser = doctest.DocTestParser()
    runner = doctest.DocTestRunner(optionflags=flags)
    globs: dict[str, object] = {"__name__": "__docs_example__"}
    failures: list[str] = []
    for block in blocks(path):
        if ">>>" not in block.body or block.marked_not_run:
            continue
        test = parser.get_doctest(block.body, globs, block.where, str(path), block.line)
        runner.run(test, out=failures.append, clear_globs=False)
        globs.update(test.globs)  # a DocTest holds a copy: carry its names to the next block
    assert not failures, "".join(failures)
    assert runner.summarize(verbose=False).attempted > 0


def script_blocks(path: Path) -> list[Block]:
    """The ``python`` blocks of a page that are scripts (no ``>>>``)."""
    return [b for b in blocks(path) if b.lang in ("python", "py") and ">>>" not in b.body]


#: Pages whose script blocks take over a CPU minute together (whole studies and fronts):
#: marked slow, so the README's test command leaves them to ``.ci/run``'s slow step.
SLOW_SCRIPT_PAGES = {"codesign.md", "following.md", "studies.md"}
SCRIPT_PAGES = [
    pytest.param(p, marks=pytest.mark.slow) if p.name in SLOW_SCRIPT_PAGES else p
    for p in PAGES
    if script_blocks(p)
]


@pytest.mark.parametrize("path", SCRIPT_PAGES, ids=page_id)
def test_page_python_blocks_run(path: Path, tmp_path: Path, monkeypatch) -> None:
    """The page's script blocks run in order, in one namespace, from an empty directory."""
    monkeypatch.chdir(tmp_path)
    namespace: dict[str, object] = {"__name__": "__docs_example__"}
    broken: list[str] = []
    for block in script_blocks(path):
        if block.marked_not_run or listed(SKIPPED, block):
            continue
        try:
            exec(compile(block.body, block.where, "exec"), namespace)
        except Exception as exc:
            if listed(BROKEN, block) is None:
                raise AssertionError(f"{block.where}: {type(exc).__name__}: {exc}") from exc
            broken.append(f"{block.where}: {listed(BROKEN, block)}")
    if broken:
        pytest.xfail("known broken example(s): " + "; ".join(broken))


def study_blocks() -> list[Block]:
    return [
        b
        for p in PAGES
        for b in blocks(p)
        if b.lang in ("yaml", "yml")
        and re.match(r"designlab:\s*1\b", b.body)
        and not b.marked_not_run
    ]


@pytest.mark.parametrize("block", study_blocks(), ids=lambda b: b.where)
def test_page_study_files_load(block: Block) -> None:
    """A study file printed on a page loads as ``designlab validate`` loads it."""
    study = parse_study(block.body)
    assert study.kind and study.name


def shell_study_commands() -> list[tuple[str, str]]:
    """``(where, study)`` of each ``designlab run|validate|report X.yaml`` of a shell block."""
    found = []
    for path in PAGES:
        for block in blocks(path):
            if block.lang not in ("bash", "sh", "console", "shell"):
                continue
            for line in block.body.splitlines():
                words = shlex.split(line.split("#", 1)[0].replace("&&", ";"))
                for i, word in enumerate(words[:-1]):
                    if word.endswith("designlab") and words[i + 1] in ("run", "validate", "report"):
                        found += [(block.where, w) for w in words[i + 2 :] if w.endswith(".yaml")]
    return found


@pytest.mark.parametrize(("where", "study"), shell_study_commands(), ids=lambda x: str(x))
def test_page_commands_name_studies_that_load(where: str, study: str) -> None:
    assert (ROOT / study).is_file(), f"{where}: {study} does not exist"
    assert load_study(ROOT / study).name == Path(study).stem
