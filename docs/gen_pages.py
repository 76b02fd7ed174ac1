"""Generate the reference pages, the report gallery and the navigation of the site.

Run by mkdocs-gen-files at build time (``mkdocs build``/``mkdocs serve``), so every page
follows the live package: the API reference walks ``designlab`` with :mod:`pkgutil`, the
study-file reference reads :func:`designlab.study.registry.study_json_schema`, the CLI
reference formats the typer app's click help, and the gallery lists ``reports/*/``.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
import shutil
from pathlib import Path
from typing import Any

import mkdocs_gen_files
import typer
import yaml

import designlab
import designlab.cli
from designlab.params import Param, parameter_table
from designlab.study.registry import study_json_schema

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
REPORTS = ROOT / "reports"
EXAMPLES = ROOT / "examples"
#: Pages placed by hand in the navigation; every other ``docs/*.md`` is a guide.
USING_PAGES = {"python.md": "From Python", "studies.md": "Studies", "cli.md": "Command line"}
FIXED_PAGES = ("index.md", "getting-started.md", *USING_PAGES, "developers.md")
#: The guides' order (one domain after another); a guide not listed follows, by file name.
GUIDE_ORDER = (
    "impact.md",
    "impact_joint.md",
    "navigation.md",
    "navigation_scenarios.md",
    "navigation_planners.md",
    "navigation_gains.md",
    "navigation_crowds.md",
    "following.md",
    "tether_modes.md",
    "accompanying.md",
    "codesign.md",
    "sweeps.md",
)


# --------------------------------------------------------------------------- API reference
def public_modules() -> list[str]:
    """Every public module of designlab (no ``_private`` part, no ``__main__``), sorted."""
    names = ["designlab"]
    for info in pkgutil.walk_packages(designlab.__path__, prefix="designlab."):
        parts = info.name.split(".")
        if any(part.startswith("_") for part in parts):
            continue
        names.append(info.name)
    return sorted(names)


def write_api() -> list[str]:
    """One page per public module under reference/api/; returns the nav lines."""
    nav = []
    for name in public_modules():
        path = Path("reference", "api", *name.split(".")).with_suffix(".md")
        with mkdocs_gen_files.open(path, "w") as fd:
            # the title names the package's own page in the navigation (not "Impact")
            fd.write(
                f"---\ntitle: {name}\n---\n\n::: {name}\n    options:\n      heading_level: 1\n"
            )
        depth = name.count(".")
        target = path.relative_to("reference/api").as_posix()
        nav.append(f"{'    ' * depth}* [{name.rsplit('.', 1)[-1]}]({target})")
    with mkdocs_gen_files.open("reference/api/SUMMARY.md", "w") as fd:
        fd.write("\n".join(nav) + "\n")
    return nav


# --------------------------------------------------------------------------- study files
def resolve(schema: dict[str, Any], node: dict[str, Any]) -> dict[str, Any]:
    """The definition a ``$ref`` points to (or the node itself)."""
    ref = node.get("$ref")
    if ref:
        return schema["$defs"][ref.rsplit("/", 1)[-1]]
    return node


def model_title(name: str) -> str:
    """A readable heading for a ``$defs`` name (the anchor keeps the name itself).

    pydantic names a model that two modules define by its module path
    (``designlab__study__kinds__accompanying__TuningSpec``) and a generic model by its
    parameters (``SensitivitySpec_Literal__a_h_max_g____eps_max_m___``): shown as
    ``TuningSpec (accompanying)`` and ``SensitivitySpec (a_h_max_g, eps_max_m)``.
    """
    if name.startswith("designlab__"):
        parts = name.split("__")
        return f"{parts[-1]} ({parts[-2]})"
    match = re.match(r"^([A-Za-z0-9]+)_Literal__(.+?)_*$", name)
    if match:
        return f"{match.group(1)} ({', '.join(match.group(2).split('____'))})"
    return name


def type_text(node: dict[str, Any]) -> str:
    """A short type description: refs link to their section, unions join with ``|``."""
    if "$ref" in node:
        name = node["$ref"].rsplit("/", 1)[-1]
        return f"[{model_title(name)}](#{name.lower()})"
    for key in ("anyOf", "oneOf"):
        if key in node:
            return " \\| ".join(type_text(sub) for sub in node[key])
    if "const" in node:
        return f"`{node['const']!r}`"
    if "enum" in node:
        return "one of " + ", ".join(f"`{v}`" for v in node["enum"])
    if node.get("type") == "array":
        return f"list of {type_text(node.get('items', {}))}"
    if node.get("type") == "object" and "additionalProperties" in node:
        extra = node["additionalProperties"]
        if isinstance(extra, dict):
            return f"mapping to {type_text(extra)}"
    return f"`{node.get('type', 'any')}`"


BOUND_KEYS = {
    "minimum": ">=",
    "exclusiveMinimum": ">",
    "maximum": "<=",
    "exclusiveMaximum": "<",
    "minItems": "items >=",
    "maxItems": "items <=",
    "minLength": "length >=",
    "maxLength": "length <=",
}


def bounds_text(node: dict[str, Any]) -> str:
    """Numeric bounds of a field (of every branch of a union)."""
    found = []
    for sub in [node, *node.get("anyOf", []), *node.get("oneOf", [])]:
        for key, symbol in BOUND_KEYS.items():
            if key in sub:
                found.append(
                    f"{symbol} {sub[key]:g}"
                    if isinstance(sub[key], float)
                    else f"{symbol} {sub[key]}"
                )
    return ", ".join(dict.fromkeys(found))


def cell(text: Any) -> str:
    """Text safe inside a Markdown table cell."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def plain_cell(text: Any) -> str:
    """Plain text (a study's description) in a table cell: a star stays a star ("Masoud*, Ge &
    Cui*" was set in italics)."""
    return cell(str(text).replace("\\", "\\\\").replace("*", "\\*"))


def unit_text(description: str) -> str:
    """The unit a parameter description states (``"foam stiffness K_c, N/m; allowed ..."``)."""
    match = re.match(r"^[^;]*?,\s*([^,;]+?)\s*(;|$)", description)
    if match and "allowed" in description and len(match.group(1)) <= 12:
        return match.group(1)
    return ""


def model_table(schema: dict[str, Any], model: dict[str, Any]) -> tuple[str, list[str]]:
    """The field table of one model and the names of the models it refers to."""
    rows = ["| field | type | description | unit | bounds | default |", "|---|---|---|---|---|---|"]
    refs: list[str] = []
    required = set(model.get("required", []))
    for field, node in model.get("properties", {}).items():
        refs += re.findall(r"#/\$defs/([A-Za-z0-9_]+)", repr(node))
        description = node.get("description", "")
        default = (
            "required"
            if field in required
            else f"`{node['default']!r}`"
            if "default" in node
            else ""
        )
        rows.append(
            f"| `{field}` | {cell(type_text(node))} | {cell(description)} | "
            f"{cell(unit_text(description))} | {cell(bounds_text(node))} | {cell(default)} |"
        )
    return "\n".join(rows), refs


def model_section(schema: dict[str, Any], name: str, level: str) -> tuple[str, list[str]]:
    """A heading, the description and the field table(s) of one ``$defs`` entry."""
    model = schema["$defs"][name]
    lines = [f"{level} {model_title(name)}", ""]
    if model.get("description"):
        lines += [model["description"], ""]
    refs: list[str] = []
    branches = [model, *model.get("anyOf", []), *model.get("oneOf", [])]
    for branch in branches:
        branch = resolve(schema, branch) if "$ref" in branch else branch
        if "properties" in branch:
            table, found = model_table(schema, branch)
            lines += [table, ""]
            refs += found
        elif branch is not model and ("enum" in branch or "type" in branch):
            lines += [f"Or: {type_text(branch)}.", ""]
    return "\n".join(lines), refs


def write_studies() -> None:
    """The study-file reference: every kind, then every model a kind refers to."""
    schema = study_json_schema()
    mapping = schema["discriminator"]["mapping"]
    out = [
        "# Study-file reference",
        "",
        "Generated from `designlab.study.registry.study_json_schema()` at build time. A study",
        "file is YAML with `designlab: 1`, a `kind` (one of the sections below) and a `name`;",
        "each parameter's description gives its symbol and SI unit, and the value is",
        "checked against the bounds shown before anything runs.",
        "",
        "## Kinds",
        "",
    ]
    out += [f"- [`{kind}`](#kind-{kind})" for kind in sorted(mapping)] + [""]
    nested: list[str] = []
    for kind in sorted(mapping):
        name = mapping[kind].rsplit("/", 1)[-1]
        text, refs = model_section(schema, name, "###")
        out += [f"## Kind `{kind}` {{#kind-{kind}}}", "", text.split("\n", 1)[1]]
        nested += refs
    out += ["## Nested models", ""]
    seen: set[str] = set(m.rsplit("/", 1)[-1] for m in mapping.values())
    while nested:
        name = nested.pop(0)
        if name in seen:
            continue
        seen.add(name)
        text, refs = model_section(schema, name, "###")
        title = model_title(name)
        out += [text.replace(f"### {title}", f"### {title} {{#{name.lower()}}}", 1)]
        nested += refs
    with mkdocs_gen_files.open("reference/studies.md", "w") as fd:
        fd.write("\n".join(out) + "\n")


# --------------------------------------------------------------------------- CLI
def command_help(command: Any, path: list[str]) -> list[str]:
    """The click help of a command and of its subcommands, each in a section.

    Duck-typed: recent typer releases ship their own copy of click, whose classes are not
    ``click.Group``.
    """
    ctx = command.context_class(command, info_name=" ".join(path), terminal_width=100)
    ctx.max_content_width = 100
    lines = [
        f"{'#' * min(len(path) + 1, 4)} `{' '.join(path)}`",
        "",
        "```text",
        command.get_help(ctx),
        "```",
        "",
    ]
    if hasattr(command, "list_commands"):
        for name in command.list_commands(ctx):
            sub = command.get_command(ctx, name)
            if sub is not None and not sub.hidden:
                lines += command_help(sub, [*path, name])
    return lines


def write_cli() -> None:
    """The CLI reference from the typer app."""
    command = typer.main.get_command(designlab.cli.app)
    out = [
        "# CLI reference",
        "",
        "Generated from the typer app `designlab.cli.app` at build time.",
        "",
    ]
    out += command_help(command, ["designlab"])
    with mkdocs_gen_files.open("reference/cli.md", "w") as fd:
        fd.write("\n".join(out))


# --------------------------------------------------------------------------- parameters
def declared_classes() -> dict[str, list[type]]:
    """Every ``@declared`` class of the package, by the module that defines it."""
    found: dict[str, list[type]] = {}
    for name in public_modules():
        module = importlib.import_module(name)
        for obj in vars(module).values():
            if inspect.isclass(obj) and obj.__module__ == name and "__params__" in obj.__dict__:
                found.setdefault(name, []).append(obj)
    return found


def argument_params() -> dict[str, list[Param]]:
    """The module-level declarations (function arguments) of each domain ``parameters`` module."""
    found: dict[str, list[Param]] = {}
    for name in public_modules():
        if not name.endswith(".parameters"):
            continue
        module = importlib.import_module(name)
        decls = [obj for key, obj in vars(module).items() if isinstance(obj, Param)]
        if decls:
            found[name] = decls
    return found


def table_markdown(frame: Any) -> list[str]:
    """A ``parameter_table`` frame as a Markdown table (names and symbols as code)."""
    code = {"name", "symbol"}
    lines = ["| " + " | ".join(frame.columns) + " |", "|" + "---|" * len(frame.columns)]
    for row in frame.itertuples(index=False):
        cells = [
            f"`{value}`" if column in code and value != "" else cell(value)
            for column, value in zip(frame.columns, row, strict=True)
        ]
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def domain_of(module: str) -> str:
    """``designlab.following.tether.controllers`` -> ``designlab.following.tether``."""
    parts = module.split(".")
    return ".".join(parts[:3] if parts[1] == "following" and len(parts) > 3 else parts[:2])


def write_parameters() -> None:
    """The parameter tables of every declared class and of the domains' argument declarations."""
    out = [
        "# Parameters",
        "",
        "Every parameter of the models, generated at build time with",
        "`designlab.params.parameter_table` from its single declaration (`designlab.params.param`",
        "on a `@declared` class, or a module-level `Param` for a function argument). The same",
        "declaration checks the value in the Python API and in a study file, writes the",
        "docstring's Parameters section and the JSON Schema, so the ranges below are the ones",
        "enforced. Units are SI.",
        "",
    ]
    by_domain: dict[str, list[str]] = {}
    for module, classes in declared_classes().items():
        api = "api/" + module.replace(".", "/") + ".md"
        for cls in classes:
            section = [f"### {cls.__name__}", ""]
            section += [f"[`{module}.{cls.__name__}`]({api}#{module}.{cls.__name__})", ""]
            section += [*table_markdown(parameter_table(cls)), ""]
            by_domain.setdefault(domain_of(module), []).extend(section)
    for module, decls in argument_params().items():
        api = "api/" + module.replace(".", "/") + ".md"
        section = [f"### Function arguments ({module.rsplit('.', 1)[-1]})", ""]
        section += [f"Module-level declarations of [`{module}`]({api}).", ""]
        section += [*table_markdown(parameter_table(decls)), ""]
        by_domain.setdefault(domain_of(module), []).extend(section)
    for domain in sorted(by_domain):
        out += [f"## `{domain}`", "", *by_domain[domain]]
    with mkdocs_gen_files.open("reference/parameters.md", "w") as fd:
        fd.write("\n".join(out))


# --------------------------------------------------------------------------- gallery
def first_heading(path: Path) -> str:
    """The first Markdown heading of a file (its file name if none)."""
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("# "):
            return line[2:].strip()
    return path.stem


def copy_binary(source: Path, target: str) -> None:
    """Copy a file into the generated site."""
    with source.open("rb") as src, mkdocs_gen_files.open(target, "wb") as dst:
        shutil.copyfileobj(src, dst)


def escape_tags(markdown: str) -> str:
    """``<word`` outside code spans and fences as text (``sensitivity_<base>.csv``), not HTML."""
    out, fenced = [], False
    for line in markdown.splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
        if not fenced:
            parts = line.split("`")
            parts[::2] = [re.sub(r"<(?=[A-Za-z/!])", "&lt;", part) for part in parts[::2]]
            line = "`".join(parts)
        out.append(line)
    return "\n".join(out)


def report_markdown(report: Path) -> tuple[str, list[str], set[str]]:
    """The title, the body lines and the files referred to of a report's Markdown pages."""
    pages = sorted(report.glob("*.md"), key=lambda p: (p.name != "summary.md", p.name))
    title, lines, linked = report.name, [], set()
    for index, page in enumerate(pages):
        text = page.read_text(encoding="utf-8")
        linked |= set(re.findall(r"\]\(([^)\s]+)\)", text))
        head, _, body = text.partition("\n")
        if head.startswith("# ") and index == 0:
            title, text = head[2:].strip(), body
        lines += [escape_tags(text).strip("\n"), ""]
    return title, lines, linked


#: Gallery sections: a report goes to the first whose kind prefix its study's kind has; a
#: report of any other kind goes to "Other studies", so a new report needs no edit here.
GALLERY_SECTIONS = (
    ("Impact safety", ("impact", "foam", "joint", "zeng")),
    ("Navigation among people", ("navigation", "vff", "crowd")),
    ("Tether follower", ("tether", "follower")),
    ("Accompanying robot", ("accompanying",)),
    ("Co-design", ("codesign",)),
)
OTHER_SECTION = "Other studies"


def report_study(report: Path) -> dict[str, Any]:
    """The study a report was made from: its copy ``study.yaml`` (else ``studies/<name>.yaml``)."""
    for path in (report / "study.yaml", ROOT / "studies" / f"{report.name}.yaml"):
        if path.is_file():
            loaded = yaml.safe_load(path.read_text(encoding="utf-8"))
            if isinstance(loaded, dict):
                return {**loaded, "_path": path}
    return {}


def gallery_section(kind: str) -> str:
    """The gallery section of a study kind (``OTHER_SECTION`` for an unknown one)."""
    for title, prefixes in GALLERY_SECTIONS:
        if kind.startswith(prefixes):
            return title
    return OTHER_SECTION


def first_sentence(text: str) -> str:
    """The first sentence of a description (the whole text if it has one sentence)."""
    text = " ".join(str(text).split())
    match = re.match(r"^(.+?[.?!])(\s|$)", text)
    return match.group(1) if match else text


def gallery_page(report: Path, study: dict[str, Any]) -> tuple[str, list[str]]:
    """The title and the Markdown of one report's gallery page (files copied alongside)."""
    name = report.name
    title, body, linked = report_markdown(report)
    for source in sorted(report.iterdir()):
        if source.suffix in (".png", ".gif", ".csv") and source.is_file():
            copy_binary(source, f"gallery/{name}/{source.name}")
    # the table of contents on the right is hidden: report tables need the width
    page = ["---", "hide:", "  - toc", "---", "", f"# {title}", ""]
    page += ['<div class="dl-report" markdown>', "", *body]
    csvs = sorted(report.glob("*.csv"))
    if csvs:
        page += ["## Tables (CSV)", "", *(f"- [{c.name}]({c.name})" for c in csvs), ""]
    figures = [png for png in sorted(report.glob("*.png")) if png.name not in linked]
    if figures:
        page += ["## Figures", ""]
        for png in figures:
            page += [f"### {png.stem}", "", f"![{png.stem}]({png.name})", ""]
    page += ["</div>", ""]
    path = study.get("_path")
    if path is not None:
        text = path.read_text(encoding="utf-8").rstrip()
        shown = path.relative_to(ROOT).as_posix()
        page += [f'??? note "Study file `{shown}`"', "", "    ```yaml"]
        page += [f"    {line}".rstrip() for line in text.splitlines()]
        page += ["    ```", ""]
    return title, page


def write_gallery() -> list[str]:
    """One gallery page per report directory under ``reports/``, grouped, and an index.

    Every directory of ``reports/`` with a Markdown page is a report: a report another study
    adds appears on the next build, in the section of its study's kind.
    """
    sections: dict[str, list[tuple[str, str, int, int]]] = {}
    for report in sorted(p for p in REPORTS.iterdir() if p.is_dir() and any(p.glob("*.md"))):
        study = report_study(report)
        _, page = gallery_page(report, study)
        with mkdocs_gen_files.open(f"gallery/{report.name}/index.md", "w") as fd:
            fd.write("\n".join(page))
        what = " ".join(str(study.get("description", "")).split()) or report.name
        counts = (len(list(report.glob("*.png"))), len(list(report.glob("*.csv"))))
        section = gallery_section(str(study.get("kind", "")))
        sections.setdefault(section, []).append((report.name, what, *counts))
    order = [title for title, _ in GALLERY_SECTIONS] + [OTHER_SECTION]
    index = [
        "# Report gallery",
        "",
        "The committed reports under `reports/`, one per study, generated from that directory",
        "at build time: each page shows the report's text, tables and figures and the study",
        "file that made it (`designlab run` regenerates it).",
        "",
    ]
    nav = ["* [Overview](index.md)"]
    for title in [t for t in order if t in sections]:
        index += [f"## {title}", "", "| report | what it asks | figures | tables |"]
        index.append("|---|---|---|---|")
        nav.append(f"* {title}")
        for name, what, pngs, csvs in sections[title]:
            index.append(f"| [{name}]({name}/index.md) | {plain_cell(what)} | {pngs} | {csvs} |")
            nav.append(f"    * [{name}]({name}/index.md)")
        index.append("")
    with mkdocs_gen_files.open("gallery/index.md", "w") as fd:
        fd.write("\n".join(index) + "\n")
    with mkdocs_gen_files.open("gallery/SUMMARY.md", "w") as fd:
        fd.write("\n".join(nav) + "\n")
    return nav


# --------------------------------------------------------------------------- examples
def example_page(script: Path) -> tuple[str, str, list[str]]:
    """The title, the description and the Markdown page of one example script."""
    import ast

    source = script.read_text(encoding="utf-8")
    tree = ast.parse(source)
    doc = ast.get_docstring(tree) or script.stem
    title, _, text = doc.partition("\n\n")
    body = source.splitlines()[tree.body[0].end_lineno :]  # the code after the docstring
    shown = script.relative_to(ROOT).as_posix()
    page = [f"# {title.strip()}", "", text.strip(), "", f"The script `{shown}` (run it with "
            f"`python {shown}`; the tests run every example):", "", "```python",
            *"\n".join(body).strip().splitlines(), "```", ""]  # fmt: skip
    return title.strip(), " ".join(text.split()), page


def write_examples() -> list[str]:
    """One page per script of ``examples/`` and an index (a new script appears on its own)."""
    index = ["# Examples", "", "Short scripts, one question each, that draw what they compute "
             "(`result.plot()`); every one of them runs in the tests.", "",
             "| example | what it shows |", "|---|---|"]  # fmt: skip
    nav = ["* [Overview](index.md)"]
    for script in sorted(EXAMPLES.glob("*.py")):
        title, what, page = example_page(script)
        with mkdocs_gen_files.open(f"examples/{script.stem}.md", "w") as fd:
            fd.write("\n".join(page))
        index.append(f"| [{title}]({script.stem}.md) | {plain_cell(what)} |")
        nav.append(f"* [{title}]({script.stem}.md)")
    with mkdocs_gen_files.open("examples/index.md", "w") as fd:
        fd.write("\n".join(index) + "\n")
    with mkdocs_gen_files.open("examples/SUMMARY.md", "w") as fd:
        fd.write("\n".join(nav) + "\n")
    return nav


# --------------------------------------------------------------------------- navigation
def guide_pages() -> list[Path]:
    """Every ``docs/*.md`` that is not a fixed page, in ``GUIDE_ORDER`` then by name."""
    pages = [p for p in DOCS.glob("*.md") if p.name not in FIXED_PAGES]
    rank = {name: i for i, name in enumerate(GUIDE_ORDER)}
    return sorted(pages, key=lambda p: (rank.get(p.name, len(rank)), p.name))


def write_nav() -> None:
    """The site navigation (literate-nav): fixed pages, every guide, the generated pages."""
    nav = ["* [Home](index.md)", "* [Getting started](getting-started.md)", "* Using designlab"]
    nav += [f"    * [{title}]({name})" for name, title in USING_PAGES.items()]
    nav += ["* Guides"]
    nav += [f"    * [{first_heading(p)}]({p.name})" for p in guide_pages()]
    nav += [
        "* Reference",
        "    * [Study files](reference/studies.md)",
        "    * [Command line](reference/cli.md)",
        "    * [Parameters](reference/parameters.md)",
        "    * [API](reference/api/)",
        "* [Examples](examples/)",
        "* [Report gallery](gallery/)",
        "* [Developers](developers.md)",
    ]
    with mkdocs_gen_files.open("SUMMARY.md", "w") as fd:
        fd.write("\n".join(nav) + "\n")


def main() -> None:
    """Write every generated page of the site."""
    write_api()
    write_studies()
    write_cli()
    write_parameters()
    write_gallery()
    write_examples()
    write_nav()


# mkdocs-gen-files runs this file with runpy.run_path (module name "<run_path>"); importing
# it (the tests do) writes nothing.
if __name__ in ("__main__", "<run_path>"):
    main()
