"""MkDocs hook: Sphinx roles in docstrings (``:func:`name```) read as plain code.

The numpydoc docstrings use Sphinx's cross-reference roles, which Markdown renders as the
role's text followed by the name in code (``:func:<code>simulate</code>``). This hook drops
the role's text, and Sphinx's ``~`` shorthand (``:class:`~designlab.impact.Foam``` shows
``Foam``), so the API reference reads ``simulate`` and ``Foam``.
"""

from __future__ import annotations

import re
from typing import Any

ROLE = re.compile(r":(?:py:)?(?:func|class|mod|meth|attr|data|obj|exc|const):(?=<code>)")
TILDE = re.compile(r"<code>~(?:[\w.]*\.)?(\w+)</code>")


def strip_roles(html_text: str) -> str:
    """The HTML with every role prefix before a code span removed."""
    if ":" not in html_text:
        return html_text
    text = ROLE.sub("", html_text)
    return TILDE.sub(r"<code>\1</code>", text)


def on_page_content(html_text: str, **kwargs: Any) -> str:
    """MkDocs event: the rendered body of a page without role prefixes."""
    return strip_roles(html_text)
