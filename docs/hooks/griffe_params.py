"""Griffe extension: a declared field's default is its ``default=``, not the ``param(...)`` call.

A field of a ``@declared`` data class is written ``mass: float = param("M_h", "kg", ...)``;
read from the source, its default (in the class signature and the attribute's entry) would be
that whole call (as ``as_field(C_MECH, default=0.0)`` would be, a field reusing a module-level
declaration). This extension, loaded by mkdocstrings (``extensions`` in ``mkdocs.yml``),
replaces it by the value of the call's ``default=`` (or ``default_factory=``, shown called),
or by nothing when the field is required, so the API reference shows
``HeadNeck(mass, stiffness, damping, name='')``. The declaration itself is documented by the
generated Parameters section of the class and by the parameter tables.
"""

from __future__ import annotations

from typing import Any

import griffe

#: ``param(...)`` declares a field; ``as_field(decl, default=...)`` reuses a declaration
DECLARATION_FUNCTIONS = {
    "param", "params.param", "designlab.params.param",
    "as_field", "parameters.as_field", "designlab.impact.parameters.as_field",
}  # fmt: skip


def keyword(call: griffe.ExprCall, name: str) -> Any:
    """The value of keyword argument ``name`` of a call expression (None if absent)."""
    for argument in call.arguments:
        if isinstance(argument, griffe.ExprKeyword) and argument.name == name:
            return argument.value
    return None


class DeclaredFieldDefaults(griffe.Extension):
    """Show a declared field's default value instead of its ``param(...)`` declaration."""

    def on_attribute_instance(self, *, attr: griffe.Attribute, **kwargs: Any) -> None:
        value = attr.value
        if not isinstance(value, griffe.ExprCall):
            return
        if str(value.function) not in DECLARATION_FUNCTIONS:
            return
        default = keyword(value, "default")
        factory = keyword(value, "default_factory")
        if default is not None:
            attr.value = default
        elif factory is not None:
            attr.value = f"{factory}()"
        else:
            attr.value = None


class CommentDocstrings(griffe.Extension):
    """A module attribute documented by ``#:`` comment lines above it gets them as docstring.

    The package documents its constants Sphinx's way (``#: The reductions compared.`` over
    ``REDUCTIONS = ...``), which ``help()`` and Sphinx read but griffe does not: without this
    extension such a constant, an alias such as ``THESIS_DESIGNS`` or a registry such as
    ``METHODS`` had no entry on its API page (``show_if_no_docstring: false``).
    """

    def on_attribute_instance(self, *, attr: griffe.Attribute, **kwargs: Any) -> None:
        if attr.docstring is not None or attr.lineno is None or not attr.parent:
            return
        if not attr.parent.is_module:
            return
        try:
            lines = attr.lines_collection[attr.filepath]
        except (KeyError, TypeError):
            return
        comment: list[str] = []
        index = attr.lineno - 2  # the line above (line numbers start at 1)
        while index >= 0 and lines[index].lstrip().startswith("#:"):
            comment.insert(0, lines[index].lstrip()[2:].strip())
            index -= 1
        if comment:
            attr.docstring = griffe.Docstring(
                "\n".join(comment), lineno=index + 2, endlineno=attr.lineno - 1, parent=attr
            )
