"""YAML reading for study files: the core's safe loader (:mod:`designlab.yamlio`).

Kept so that ``designlab.study.yamlio`` imports keep working; everything lives in
:mod:`designlab.yamlio`, which the domains (scenario files) use too.

Examples
--------
>>> data, lines = load_yaml_with_lines("a: 1\\nb:\\n  - x: 20e3\\n")
>>> data
{'a': 1, 'b': [{'x': 20000.0}]}
>>> lines[("b", 0, "x")]
3
"""

from __future__ import annotations

from typing import Any

from designlab.yamlio import MAX_BYTES, MAX_DEPTH, MAX_NODES, YamlError, YamlPath, load_yaml

__all__ = [
    "MAX_CHARS",
    "MAX_DEPTH",
    "MAX_NODES",
    "YamlPath",
    "YamlSyntaxError",
    "load_yaml_with_lines",
]

#: The largest study text accepted, in characters (:data:`designlab.yamlio.MAX_BYTES`).
MAX_CHARS = MAX_BYTES
#: The error of a study's YAML text (:class:`designlab.yamlio.YamlError`).
YamlSyntaxError = YamlError


def load_yaml_with_lines(text: str) -> tuple[Any, dict[YamlPath, int]]:
    """Parse YAML text and return ``(data, lines)`` (:func:`designlab.yamlio.load_yaml`).

    Parameters
    ----------
    text
        The YAML document (a single document).

    Returns
    -------
    data, lines
        The Python value and the 1-based line of every key and list item.

    Examples
    --------
    >>> load_yaml_with_lines("a: [1, 2")
    Traceback (most recent call last):
    ...
    designlab.yamlio.YamlError: YAML syntax error: ...
    """
    return load_yaml(text)
