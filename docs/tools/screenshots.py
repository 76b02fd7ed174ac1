"""Render pages of the built documentation site in headless Chromium, and check them.

Usage::

    python docs/tools/screenshots.py OUT_DIR [--site SITE_DIR] [--chromium PATH]

The site (``mkdocs build --strict``, built into a temporary directory when ``--site`` is not
given) is served on localhost; four pages (the home page, a guide, an API page, a gallery page) are
opened in headless Chromium through Playwright (``executable_path``: no browser download)
at 1280 x 2000 and saved as ``OUT_DIR/<page>.png``, with a search for "foam stiffness" on the
home page saved as ``search.png``. Look at them: that is what a reader sees. The DOM of each
page is checked and ``OUT_DIR/report.json`` holds what was found; the exit code is 1 when a
check fails:

* the maths is MathML (``<math>`` elements, no TeX left in the page);
* every link of the navigation and of the pages' text resolves (HTTP 200 from the served
  site);
* every image loads, and no page scrolls sideways as a whole;
* the search index is built and a search returns results;
* no script error in the console.

Chromium is ``--chromium``, ``$DESIGNLAB_CHROMIUM`` or the first of ``chromium``,
``chromium-browser``, ``google-chrome`` on the ``PATH``.
"""

from __future__ import annotations

import argparse
import functools
import http.server
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import urllib.request
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
PAGES = {
    "home": "",
    "guide": "impact/",
    "api": "reference/api/designlab/impact/model/",
    "gallery": "gallery/zeng_ch4_validation/",
}
QUERY = "foam stiffness"
WINDOW = {"width": 1280, "height": 2000}
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
#: Seconds the browser's search worker may take to build its index (2 shared cores).
SEARCH_TIMEOUT = 120


def find_chromium(explicit: str | None = None) -> str | None:
    """The Chromium executable to use, or None when there is none."""
    if explicit:
        return explicit
    if os.environ.get("DESIGNLAB_CHROMIUM"):
        return os.environ["DESIGNLAB_CHROMIUM"]
    for name in ("chromium", "chromium-browser", "google-chrome"):
        found = shutil.which(name)
        if found:
            return found
    return None


def build_site(target: Path) -> Path:
    """``mkdocs build --strict`` of the repository into ``target``."""
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1", "DISABLE_MKDOCS_2_WARNING": "true"}
    command = [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(target)]
    subprocess.run(command, cwd=ROOT, env=env, check=True)
    return target


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    """A static file handler that does not log every request."""

    def log_message(self, format: str, *args: Any) -> None:
        pass


class QuietServer(http.server.ThreadingHTTPServer):
    """A server that does not print a traceback when the browser drops a request."""

    def handle_error(self, request: Any, client_address: Any) -> None:
        if not isinstance(sys.exc_info()[1], ConnectionError):
            super().handle_error(request, client_address)


@contextmanager
def serve(site: Path) -> Iterator[str]:
    """Serve ``site`` on a free localhost port; yields the base URL."""
    handler = functools.partial(QuietHandler, directory=str(site))
    server = QuietServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()
        server.server_close()


def status(url: str) -> int:
    """The HTTP status of a GET of ``url``."""
    try:
        with urllib.request.urlopen(url, timeout=30) as response:
            return int(response.status)
    except urllib.error.HTTPError as exc:
        return int(exc.code)


DOM_FACTS = """() => ({
  math: document.querySelectorAll("math").length,
  tex_left: [...document.querySelectorAll(".arithmatex")]
      .filter(e => !e.querySelector("math")).map(e => e.textContent.slice(0, 60)),
  nav: [...new Set([...document.querySelectorAll("nav.md-nav a.md-nav__link[href]")]
      .map(a => a.href.split("#")[0]))],
  links: [...new Set([...document.querySelectorAll("article a[href]")]
      .map(a => a.href.split("#")[0]).filter(h => h.startsWith(location.origin)))],
  images: [...document.querySelectorAll("article img")].map(i => ({
      src: i.getAttribute("src"), loaded: i.complete && i.naturalWidth > 0,
      width: i.getBoundingClientRect().width,
      content: i.closest("article").getBoundingClientRect().width})),
  sideways: document.documentElement.scrollWidth > window.innerWidth + 1,
  tables: document.querySelectorAll("article table").length,
  title: document.title,
})"""


def page_facts(browser: Any, url: str, shot: Path) -> dict[str, Any]:
    """Open ``url``, screenshot it into ``shot`` and read its DOM facts."""
    page = browser.new_page(viewport=WINDOW)
    errors: list[str] = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.on("console", lambda msg: errors.append(msg.text) if msg.type == "error" else None)
    page.goto(url, wait_until="networkidle")
    page.screenshot(path=str(shot))
    facts = page.evaluate(DOM_FACTS)
    page.close()
    return {**facts, "errors": errors, "screenshot": shot.name}


def search_facts(browser: Any, url: str, shot: Path) -> dict[str, Any]:
    """Type ``QUERY`` in the search box of ``url``; the results and the console's warnings."""
    page = browser.new_page(viewport={"width": WINDOW["width"], "height": 1000})
    errors: list[str] = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.on("console", lambda msg: errors.append(msg.text) if "Error" in msg.text else None)
    page.goto(url, wait_until="networkidle")
    page.click(".md-search__input")
    page.keyboard.type(QUERY, delay=20)
    results = 0
    try:
        page.wait_for_selector(".md-search-result__item", timeout=SEARCH_TIMEOUT * 1000)
        results = page.locator(".md-search-result__item").count()
    except Exception as exc:  # playwright's TimeoutError
        errors.append(f"no search result for {QUERY!r}: {type(exc).__name__}")
    meta = page.locator(".md-search-result__meta").inner_text()
    page.screenshot(path=str(shot))
    page.close()
    return {"query": QUERY, "results": results, "meta": meta, "errors": errors}


def problems_of(report: dict[str, Any]) -> list[str]:
    """What a reader would find broken, from the facts of ``render``."""
    found = []
    home = report["pages"]["home"]
    if home["math"] == 0:
        found.append("home: no MathML")
    for name, facts in report["pages"].items():
        found += [f"{name}: TeX left: {t}" for t in facts["tex_left"]]
        found += [
            f"{name}: image does not load: {i['src']}" for i in facts["images"] if not i["loaded"]
        ]
        found += [
            f"{name}: image wider than the page: {i['src']}"
            for i in facts["images"]
            if i["width"] > i["content"] + 1
        ]
        if facts["sideways"]:
            found.append(f"{name}: the page scrolls sideways")
        found += [f"{name}: console: {e}" for e in facts["errors"]]
    found += [
        f"navigation link {url}: HTTP {code}" for url, code in report["nav"].items() if code != 200
    ]
    found += [
        f"link in a page {url}: HTTP {code}"
        for url, code in report.get("links", {}).items()
        if code != 200
    ]
    if not report["search_index"]["docs"]:
        found.append("search index empty")
    if report["search"]["results"] == 0:
        found.append(f"search for {QUERY!r} found nothing: {report['search']['errors']}")
    return found


def render(site: Path, out: Path, chromium: str) -> dict[str, Any]:
    """Screenshots of ``PAGES`` and the search into ``out``; the facts and the problems found."""
    from playwright.sync_api import sync_playwright

    out.mkdir(parents=True, exist_ok=True)
    report: dict[str, Any] = {"pages": {}, "nav": {}}
    with serve(site) as base, sync_playwright() as driver:
        browser = driver.chromium.launch(
            executable_path=chromium, headless=True, args=CHROMIUM_ARGS
        )
        try:
            for name, path in PAGES.items():
                report["pages"][name] = page_facts(browser, base + path, out / f"{name}.png")
            report["search"] = search_facts(browser, base, out / "search.png")
        finally:
            browser.close()
        links = sorted({url for facts in report["pages"].values() for url in facts.pop("nav")})
        report["nav"] = {url: status(url) for url in links if url.startswith(base)}
        content = sorted({url for facts in report["pages"].values() for url in facts.pop("links")})
        report["links"] = {url: status(url) for url in content if url.startswith(base)}
        with urllib.request.urlopen(base + "search/search_index.json", timeout=30) as response:
            index = json.load(response)
        report["search_index"] = {"docs": len(index.get("docs", [])), "config": index.get("config")}
    report["problems"] = problems_of(report)
    (out / "report.json").write_text(json.dumps(report, indent=2) + "\n", encoding="utf-8")
    return report


def main(argv: list[str] | None = None) -> int:
    """Command line: screenshots and checks of the built site (exit 1 on a problem)."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", type=Path, help="directory for the PNGs and report.json")
    parser.add_argument("--site", type=Path, help="a built site (default: build one)")
    parser.add_argument("--chromium", help="the Chromium executable")
    args = parser.parse_args(argv)
    chromium = find_chromium(args.chromium)
    if chromium is None:
        print("no Chromium found (--chromium, $DESIGNLAB_CHROMIUM or chromium on the PATH)")
        return 2
    with tempfile.TemporaryDirectory() as tmp:
        site = args.site or build_site(Path(tmp) / "site")
        report = render(site, args.out, chromium)
    for name, facts in report["pages"].items():
        print(f"{name}: {facts['screenshot']}, {facts['math']} formulas, {facts['tables']} tables")
    print(
        f"search {QUERY!r}: {report['search']['results']} results; {len(report['nav'])} nav links"
    )
    for problem in report["problems"]:
        print("PROBLEM:", problem)
    return 1 if report["problems"] else 0


if __name__ == "__main__":
    sys.exit(main())
