"""MkDocs hook: typeset the site's maths as MathML at build time, so it renders offline.

``pymdownx.arithmatex`` (generic mode) finds the TeX of every page and docstring
(``$...$``, ``$$...$$``, ``\\(...\\)``, ``\\[...\\]``) and wraps it as
``<span class="arithmatex">\\(...\\)</span>`` or ``<div class="arithmatex">\\[...\\]</div>``.
This hook replaces each of those by the MathML that :mod:`latex2mathml` (pure Python) makes
of it, which every current browser draws natively: the built site needs no script and no
network to show the equations. A formula that latex2mathml cannot convert is logged as a
warning naming the page and the TeX (so is a command it does not know, which it would print
as text), so ``mkdocs build --strict`` fails on it, and it is left as TeX in the page.
"""

from __future__ import annotations

import html
import logging
import re
from typing import Any

from latex2mathml.converter import convert

LOG = logging.getLogger("mkdocs.hooks.mathml")

INLINE = re.compile(r'<span class="arithmatex">\\\((?P<tex>.*?)\\\)</span>', re.DOTALL)
BLOCK = re.compile(r'<div class="arithmatex">\\\[(?P<tex>.*?)\\\]</div>', re.DOTALL)


UNKNOWN_COMMAND = re.compile(r"<m[ion][^>]*>(\\[A-Za-z]+)")


def tex_to_mathml(tex: str, display: str) -> str:
    """The MathML of a TeX formula (``display`` is ``"inline"`` or ``"block"``).

    Raises ``ValueError`` for a command latex2mathml does not know (it would print it as text).
    """
    mathml = convert(html.unescape(tex).strip(), display=display)
    unknown = UNKNOWN_COMMAND.search(mathml)
    if unknown:
        raise ValueError(f"unknown TeX command {unknown.group(1)}")
    return mathml


def typeset(text: str, where: str = "") -> str:
    """Every arithmatex span/div of an HTML fragment replaced by its MathML."""

    def replacer(display: str) -> Any:
        def replace(match: re.Match[str]) -> str:
            try:
                mathml = tex_to_mathml(match.group("tex"), display)
            except Exception as exc:  # latex2mathml raises several types on bad TeX
                LOG.warning("%s: cannot typeset $%s$ as MathML: %s", where, match["tex"], exc)
                return match.group(0)
            tag = "div" if display == "block" else "span"
            return f'<{tag} class="arithmatex">{mathml}</{tag}>'

        return replace

    text = BLOCK.sub(replacer("block"), text)
    return INLINE.sub(replacer("inline"), text)


def on_page_content(html_text: str, page: Any, **kwargs: Any) -> str:
    """MkDocs event: the rendered body of a page, with its maths as MathML."""
    return typeset(html_text, page.file.src_uri)
