"""Cross-references: the Sphinx roles and ``See Also`` entries of the docs become links.

This file is both a griffe extension (for the docstrings) and a MkDocs hook (for the pages).

The numpydoc docstrings of designlab cross-reference with Sphinx roles
(``:func:`simulate```, ``:class:`~designlab.impact.Foam```) and numpydoc ``See Also``
sections, which is what ``help()`` and Sphinx users read. mkdocstrings does not know either:
it links Markdown cross-references, ``[`Foam`][designlab.impact.parameters.Foam]``, through
mkdocs-autorefs. This extension, loaded by mkdocstrings (``extensions`` in ``mkdocs.yml``),
rewrites the docstrings it has loaded (never the source) once the package is loaded:

* each role's target is resolved as Sphinx would: a dotted path from ``designlab``, else a
  name in the scope of the documented object (its members, its module's names and imports,
  its parents'), else the one designlab object of that name (the nearest to the documented
  object when several share it); ``~`` shows the last part, ``title <target>`` a title,
  ``!target`` no link;
* the target becomes an autorefs cross-reference to its canonical path, which the API pages
  render (one page per public module); autorefs also knows the re-exported paths;
* a name outside designlab (``math``, ``numpy.ndarray``, ``scipy.optimize``) is shown as
  code without a link: the site is built offline, without the other projects' inventories;
* a private designlab object, or one without a docstring (the API pages render neither), is
  shown as code without a link; so is a value griffe cannot see statically
  (``BEGIN, END = ...``) but the imported module has;
* a target that names nothing is a warning naming the object and the role, so
  ``mkdocs build --strict`` fails on a broken reference (as autorefs does for a Markdown
  cross-reference whose target is not rendered).

``See Also`` entries (``name : description``, ``name_a, name_b``) become a list of links.

As a MkDocs hook (``hooks`` in ``mkdocs.yml``) it does the same for the roles written in a
Markdown page (a guide, or a generated page such as the study-file reference, whose field
descriptions come from the docstrings): there is no scope, so the target is a full dotted
path, checked by importing it; one that names nothing is a warning. The link is an
*optional* autorefs reference: a constant that the API pages do not render shows as code.
Last, a role still left as text in a rendered page (``:func:<code>x</code>``) is a warning.
"""

from __future__ import annotations

import builtins
import html
import importlib
import importlib.util
import logging
import re
from collections.abc import Iterator
from typing import Any

import griffe

LOG = logging.getLogger("mkdocs.hooks.crossrefs")

PACKAGE = "designlab"


def inside(path: str, package: str = PACKAGE) -> bool:
    """Whether a dotted path is the package or under it."""
    return path == package or path.startswith(package + ".")


ROLE = re.compile(
    r":(?:py:)?(?P<role>func|class|mod|meth|attr|data|obj|exc|const|type):`(?P<text>[^`]+)`"
)
EXPLICIT_TITLE = re.compile(r"^(?P<title>.+?)\s*<(?P<target>[^<>]+)>$")
SEE_ALSO = re.compile(r"^See Also\n-+\n", re.MULTILINE)
SECTION = re.compile(r"^\S.*\n-{3,}$", re.MULTILINE)


def walk(obj: griffe.Object) -> Iterator[griffe.Object]:
    """The object and every member defined under it (aliases skipped)."""
    yield obj
    for member in obj.members.values():
        if not member.is_alias:
            yield from walk(member)  # type: ignore[arg-type]


class Resolver:
    """Resolves role targets to designlab objects, the way Sphinx's Python domain does."""

    def __init__(self, package: griffe.Module, collection: Any) -> None:
        self.package = package.name
        self.collection = collection
        self.by_name: dict[str, list[griffe.Object]] = {}
        for obj in walk(package):
            self.by_name.setdefault(obj.name, []).append(obj)

    def lookup(self, path: str) -> griffe.Object | None:
        """The object a dotted path names (aliases followed), or None."""
        try:
            found = self.collection[path]
            return found.final_target if found.is_alias else found
        except (KeyError, griffe.AliasResolutionError, griffe.CyclicAliasError):
            return None

    def in_scope(self, scope: griffe.Object, target: str) -> str | None:
        """The full path of ``target`` resolved in ``scope`` (first part by scope), or None."""
        first, _, rest = target.partition(".")
        try:
            base = scope.resolve(first)
        except griffe.NameResolutionError:
            return None
        return f"{base}.{rest}" if rest else base

    def nearest(self, scope: griffe.Object, target: str) -> list[griffe.Object]:
        """The designlab objects whose path ends with ``target``, nearest to ``scope`` first."""
        last = target.rsplit(".", 1)[-1]
        found = [o for o in self.by_name.get(last, []) if f".{o.path}".endswith(f".{target}")]

        def shared(obj: griffe.Object) -> int:
            common = 0
            for a, b in zip(obj.path.split("."), scope.path.split("."), strict=False):
                if a != b:
                    break
                common += 1
            return common

        if not found:
            return []
        best = max(shared(o) for o in found)
        return inherited([o for o in found if shared(o) == best])

    def at_runtime(self, scope: griffe.Object, target: str) -> griffe.Object | str | None:
        """What ``target`` names when imported (griffe cannot see ``A, B = ...``).

        The object it finds is looked up by its defining module and qualified name; a value
        (a constant) without one is ``"value"``.
        """
        module = scope.module.path
        for base in (target, f"{module}.{target}"):
            value = runtime_value(base, self.package)
            if value is None:
                continue
            owner, name = getattr(value, "__module__", None), getattr(value, "__qualname__", None)
            if isinstance(owner, str) and isinstance(name, str) and inside(owner, self.package):
                found = self.lookup(f"{owner}.{name}")
                if found is not None:
                    return found
            return "value"
        return None

    def resolve(self, scope: griffe.Object, target: str) -> griffe.Object | str | None:
        """The object ``target`` names from ``scope``, ``"external"``, or None (broken).

        Raises ``LookupError`` when several designlab objects are equally near.
        """
        target = target.lstrip(".")
        if inside(target, self.package):
            return self.lookup(target)
        path = self.in_scope(scope, target)
        if path is not None:
            if inside(path, self.package):
                found = self.lookup(path)
                if found is not None:
                    return found
            else:
                return "external"
        first = target.split(".", 1)[0]
        if hasattr(builtins, first) or importlib.util.find_spec(first) is not None:
            return "external"
        candidates = self.nearest(scope, target)
        if len(candidates) > 1:
            raise LookupError(", ".join(sorted(o.path for o in candidates)))
        return candidates[0] if candidates else self.at_runtime(scope, target)


MISSING = object()


def runtime_value(path: str, package: str = PACKAGE) -> Any:
    """The object a dotted path of the package names once imported, or None."""
    if not inside(path, package):
        return None
    parts = path.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            value: Any = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for part in parts[cut:]:
            value = getattr(value, part, MISSING)
            if value is MISSING:
                return None
        return value
    return None


def inherited(candidates: list[griffe.Object]) -> list[griffe.Object]:
    """Methods of one class hierarchy reduced to the base class's (``law_function``)."""
    methods = all(c.parent is not None and c.parent.is_class for c in candidates)
    if len(candidates) < 2 or not methods:
        return candidates
    for candidate in candidates:
        base = candidate.parent
        try:
            if all(base is c.parent or base in c.parent.mro() for c in candidates):  # type: ignore[union-attr]
                return [candidate]
        except (ValueError, griffe.AliasResolutionError):
            continue
    return candidates


def literal_marker(line: str) -> str:
    """A line ending in reST's ``::`` as Sphinx shows it (``a::`` -> ``a:``, ``a ::`` -> ``a``)."""
    stripped = line.rstrip()
    if not stripped.endswith("::") or stripped.endswith(":::"):
        return line
    if stripped.strip() == "::":
        return ""
    return stripped[:-3] if stripped.endswith(" ::") else stripped[:-1]


def rendered(obj: griffe.Object) -> bool:
    """Whether the API pages render ``obj``: public, and a module or documented."""
    return not private(obj) and (obj.is_module or obj.has_docstring)


def split_role(text: str) -> tuple[str, str, bool]:
    """``(display, target, link)`` of a role's text (``~``, ``title <target>``, ``!``)."""
    text = text.strip()
    explicit = EXPLICIT_TITLE.match(text)
    if explicit:
        return explicit["title"], explicit["target"].strip(), True
    if text.startswith("!"):
        return text[1:], text[1:], False
    if text.startswith("~"):
        target = text[1:]
        return target.removesuffix("()").rsplit(".", 1)[-1], target, True
    return text, text, True


class CrossReferences:
    """Rewrites one docstring's roles and See Also entries as autorefs cross-references."""

    def __init__(self, resolver: Resolver) -> None:
        self.resolver = resolver
        self.broken: list[str] = []

    def link(self, scope: griffe.Object, text: str, role: str = "obj") -> str:
        """The Markdown of one reference (a link, or code when it cannot be one)."""
        display, target, link = split_role(text)
        code = f"`{display}`"
        if not link:
            return code
        try:
            found = self.resolver.resolve(scope, target.removesuffix("()"))
        except LookupError as exc:
            self.warn(scope, f":{role}:`{text}` is ambiguous (one of {exc})")
            return code
        if found is None:
            self.warn(scope, f":{role}:`{text}` names nothing in designlab")
            return code
        if isinstance(found, str) or not rendered(found):  # outside designlab, or not rendered
            return code
        return f"[{code}][{found.canonical_path}]"  # type: ignore[union-attr]

    def warn(self, scope: griffe.Object, message: str) -> None:
        """A broken reference: a warning, so the strict build fails."""
        where = scope.filepath if isinstance(scope.filepath, str) else scope.relative_filepath
        LOG.warning("%s (%s): broken cross-reference %s", scope.path, where, message)
        self.broken.append(f"{scope.path}: {message}")

    def roles(self, scope: griffe.Object, text: str) -> str:
        """Every role of a docstring as a link (doctest lines kept as written).

        A reST literal-block marker is read as Sphinx does: ``text::`` shows ``text:`` and a
        line ``::`` alone shows nothing (the indented block after it is code either way).
        """
        lines = []
        for line in text.split("\n"):
            if not line.lstrip().startswith((">>>", "...")):
                line = ROLE.sub(lambda m: self.link(scope, m["text"], m["role"]), line)
                line = literal_marker(line)
            lines.append(line)
        return "\n".join(lines)

    def see_also(self, scope: griffe.Object, text: str) -> str:
        """The numpydoc ``See Also`` section as a Markdown list of links."""
        header = SEE_ALSO.search(text)
        if header is None:
            return text
        body = text[header.end() :]
        following = SECTION.search(body)
        section, rest = (body, "") if following is None else body.split(following[0], 1)
        rest = "" if following is None else following[0] + rest
        items: list[str] = []
        for line in section.rstrip("\n").split("\n"):
            if not line.strip():
                continue
            if line[0].isspace() and items:  # a description's continuation line
                items[-1] += " " + line.strip()
                continue
            names, _, description = line.partition(" : ")
            links = ", ".join(self.link(scope, n.strip()) for n in names.split(",") if n.strip())
            items.append(f"- {links}" + (f": {description.strip()}" if description else ":"))
        items = [item.removesuffix(":") for item in items]
        listing = "\n".join(items)
        return f"{text[: header.end()]}\n{listing}\n\n{rest}".rstrip("\n") + "\n"

    def rewrite(self, scope: griffe.Object) -> None:
        """Rewrite the docstring of ``scope`` in place (griffe's copy, not the source)."""
        docstring = scope.docstring
        if docstring is None or ("`" not in docstring.value and "See Also" not in docstring.value):
            return
        docstring.value = self.roles(scope, self.see_also(scope, docstring.value))


class SphinxCrossReferences(griffe.Extension):
    """Convert the docstrings' Sphinx roles and See Also entries to autorefs links.

    ``package`` is the package whose docstrings are converted (and whose objects are linked).
    """

    def __init__(self, package: str = PACKAGE) -> None:
        super().__init__()
        self.package = package

    def on_package(self, *, pkg: griffe.Module, loader: griffe.GriffeLoader, **kwargs: Any) -> None:
        if pkg.name != self.package:
            return
        converter = CrossReferences(Resolver(pkg, loader.modules_collection))
        for obj in walk(pkg):
            if not private(obj):  # the site renders no private object
                converter.rewrite(obj)


def private(obj: griffe.Object) -> bool:
    """Whether a part of the object's path is private (``_name``, not ``__init__``)."""
    return any(p.startswith("_") and not p.endswith("__") for p in obj.path.split("."))


# --------------------------------------------------------------------------- MkDocs hook
FENCE = re.compile(r"^\s*(```|~~~)")
DOUBLE_CODE = re.compile(r"(``.+?``)")
LEFTOVER = re.compile(
    r":(?:py:)?(?:func|class|mod|meth|attr|data|obj|exc|const|type):<code>[^<]*</code>"
)


def page_link(text: str, role: str, where: str) -> str:
    """The HTML of a role written in a Markdown page (an optional autorefs link, or code)."""
    display, target, link = split_role(text)
    code = f"<code>{html.escape(display)}</code>"
    target = target.removesuffix("()")
    if not link or not inside(target):
        return code
    value = runtime_value(target)
    if value is None:
        LOG.warning(
            "%s: broken cross-reference :%s:`%s` names nothing in designlab", where, role, text
        )
        return code
    identifier = target
    owner, name = getattr(value, "__module__", None), getattr(value, "__qualname__", None)
    if isinstance(owner, str) and isinstance(name, str) and inside(owner):
        identifier = f"{owner}.{name}"
    return f'<autoref identifier="{identifier}" optional>{code}</autoref>'


def page_roles(markdown: str, where: str) -> str:
    """Every role of a Markdown page (outside code fences) as a link."""
    lines, fenced = [], False
    for line in markdown.split("\n"):
        if FENCE.match(line):
            fenced = not fenced
        elif not fenced and ":`" in line:
            # a role quoted in a ``double-backtick`` code span is text, not a reference
            parts = DOUBLE_CODE.split(line)
            parts[::2] = [
                ROLE.sub(lambda m: page_link(m["text"], m["role"], where), part)
                for part in parts[::2]
            ]
            line = "".join(parts)
        lines.append(line)
    return "\n".join(lines)


def on_page_markdown(markdown: str, page: Any, **kwargs: Any) -> str:
    """MkDocs event: the roles of a page's Markdown as links."""
    return page_roles(markdown, page.file.src_uri)


def on_page_content(html_text: str, page: Any, **kwargs: Any) -> str:
    """MkDocs event: a role left as text in the rendered page is a warning."""
    for role in LEFTOVER.findall(html_text):
        LOG.warning("%s: Sphinx role left as text (not a link): %s", page.file.src_uri, role)
    return html_text
