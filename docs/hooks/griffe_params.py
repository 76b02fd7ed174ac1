"""Griffe extension: a declared field's default is its ``default=``, not the ``param(...)`` call.

A field of a ``@declared`` data class is written ``mass: float = param("M_h", "kg", ...)``;
read from the source, its default (in the class signature and the attribute's entry) would be
that whole call. This extension, loaded by mkdocstrings (``extensions`` in ``mkdocs.yml``),
replaces it by the value of the call's ``default=`` (or ``default_factory=``, shown called),
or by nothing when the field is required, so the API reference shows
``HeadNeck(mass, stiffness, damping, name='')``. The declaration itself is documented by the
generated Parameters section of the class and by the parameter tables.
"""

from __future__ import annotations

from typing import Any

import griffe

DECLARATION_FUNCTIONS = {"param", "params.param", "designlab.params.param"}


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
