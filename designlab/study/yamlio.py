"""YAML reading that remembers where every key and list item came from.

PyYAML's safe loader forgets line numbers once it has built Python objects.
:func:`load_yaml_with_lines` composes the node tree once, builds the Python
data from it and records, for every mapping key and sequence item, the
1-based line on which it starts. Validation errors found later (by pydantic)
can then point at the offending line.

Two departures from plain ``yaml.safe_load``:

* floats written without a dot, such as ``20e3`` or ``1e-3``, load as floats
  (YAML 1.2 behaviour) instead of strings;
* a key repeated in the same mapping is an error, not a silent overwrite.

Examples
--------
>>> data, lines = load_yaml_with_lines("a: 1\\nb:\\n  - x: 20e3\\n")
>>> data
{'a': 1, 'b': [{'x': 20000.0}]}
>>> lines[("b", 0, "x")]
3
"""

from __future__ import annotations

import re
from collections.abc import Hashable
from typing import Any

import yaml

__all__ = [
    "MAX_CHARS",
    "MAX_DEPTH",
    "MAX_NODES",
    "YamlPath",
    "YamlSyntaxError",
    "load_yaml_with_lines",
]

#: A location in the data: mapping keys and sequence indices from the root.
YamlPath = tuple[Hashable, ...]


class YamlSyntaxError(ValueError):
    """The text is not valid YAML, or repeats a key.

    Attributes
    ----------
    line
        1-based line of the problem, if known.
    path
        Location of a duplicated key, if that is the problem.
    message
        What is wrong.
    """

    def __init__(self, message: str, line: int | None = None, path: YamlPath = ()) -> None:
        super().__init__(message)
        self.line = line
        self.path = path


#: The deepest nesting of mappings and lists a study may have (a study needs about 6).
MAX_DEPTH = 64


class _Loader(yaml.SafeLoader):
    """Safe loader with YAML 1.2-style floats (``20e3`` is a float) and a nesting limit.

    The composer is recursive, so a document nested thousands of levels deep
    would exhaust Python's stack (``RecursionError``) here or in every later
    step; the depth is counted while composing and refused beyond
    :data:`MAX_DEPTH` with the line where it happens.
    """

    _depth = 0

    def compose_node(self, parent: Any, index: Any) -> Any:
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                mark = self.peek_event().start_mark
                raise YamlSyntaxError(
                    f"the document nests lists and mappings more than {MAX_DEPTH} levels deep; "
                    "studies are shallow (a few levels)",
                    line=mark.line + 1,
                )
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(
        r"""^(?:[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+
        |[-+]?\.[0-9_]+(?:[eE][-+]?[0-9]+)?)$""",
        re.X,
    ),
    list("-+0123456789."),
)


#: The most nodes a study document may expand to (aliases counted at every use).
MAX_NODES = 200_000
#: The largest study text accepted, in characters.
MAX_CHARS = 5_000_000


def _check_size(root: yaml.Node) -> None:
    """Refuse documents whose aliases expand to more than :data:`MAX_NODES` nodes.

    A "billion laughs" document (anchors nesting aliases of aliases) is tiny as
    text but exponential once expanded; it is measured on the node graph with
    memoisation, so the check itself is linear in the text.
    """
    sizes: dict[int, int] = {}
    active: set[int] = set()

    def size(node: yaml.Node) -> int:
        key = id(node)
        if key in sizes:
            return sizes[key]
        if key in active:
            raise YamlSyntaxError(
                "the document refers to itself through an alias (a recursive structure); "
                "studies must be plain trees",
                line=node.start_mark.line + 1,
            )
        active.add(key)
        total = 1
        if isinstance(node, yaml.MappingNode):
            for k, v in node.value:
                total += size(k) + size(v)
                if total > MAX_NODES:
                    break
        elif isinstance(node, yaml.SequenceNode):
            for item in node.value:
                total += size(item)
                if total > MAX_NODES:
                    break
        active.discard(key)
        sizes[key] = total
        if total > MAX_NODES:
            raise YamlSyntaxError(
                f"the document expands to more than {MAX_NODES:,} values (nested anchors and "
                "aliases?); studies must be small",
                line=node.start_mark.line + 1,
            )
        return total

    size(root)


def _record(node: yaml.Node, path: YamlPath, lines: dict[YamlPath, int]) -> None:
    """Walk the composed node tree and record the line of each key and item."""
    if isinstance(node, yaml.MappingNode):
        seen: dict[Any, int] = {}
        for key_node, value_node in node.value:
            if not isinstance(key_node, yaml.ScalarNode) or key_node.value == "<<":
                # complex keys and merge keys: no line bookkeeping, still loaded
                continue
            key: Any = key_node.value
            line = key_node.start_mark.line + 1
            if key in seen:
                raise YamlSyntaxError(
                    f"key {key!r} appears twice in the same mapping (first on line {seen[key]})",
                    line=line,
                    path=(*path, key),
                )
            seen[key] = line
            lines[(*path, key)] = line
            _record(value_node, (*path, key), lines)
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            lines[(*path, i)] = item.start_mark.line + 1
            _record(item, (*path, i), lines)


def load_yaml_with_lines(text: str) -> tuple[Any, dict[YamlPath, int]]:
    """Parse YAML text and return ``(data, lines)``.

    Parameters
    ----------
    text
        The YAML document (a single document).

    Returns
    -------
    data
        The Python value (dicts, lists, scalars), as ``yaml.safe_load`` would
        return it except for the float rule above.
    lines
        Maps a path such as ``("cases", 0, "robot")`` to the 1-based line of
        that key or list item. Mapping keys are recorded as strings as written
        in the file.

    Raises
    ------
    YamlSyntaxError
        On a YAML syntax error or a repeated key, with the line number.

    Examples
    --------
    >>> load_yaml_with_lines("a: [1, 2")
    Traceback (most recent call last):
    ...
    designlab.study.yamlio.YamlSyntaxError: ...
    """
    if len(text) > MAX_CHARS:
        raise YamlSyntaxError(
            f"the study is {len(text):,} characters long; at most {MAX_CHARS:,} are allowed"
        )
    loader = _Loader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None, {}
        _check_size(node)
        lines: dict[YamlPath, int] = {}
        _record(node, (), lines)
        data = loader.construct_document(node)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark is not None else None
        problem = exc.problem or str(exc)
        if exc.context:
            problem = f"{exc.context}: {problem}"
        raise YamlSyntaxError(f"YAML syntax error: {problem}", line=line) from None
    except yaml.YAMLError as exc:
        raise YamlSyntaxError(f"YAML syntax error: {exc}") from None
    except RecursionError:  # pragma: no cover - MAX_DEPTH keeps the composer shallow
        raise YamlSyntaxError("the document is nested too deeply") from None
    finally:
        loader.dispose()
    # Keys were recorded by their YAML text; construct_document may have turned
    # them into ints or bools. Add the constructed forms too.
    _alias_constructed_keys(data, (), lines)
    return data, lines


def _alias_constructed_keys(data: Any, path: YamlPath, lines: dict[YamlPath, int]) -> None:
    if isinstance(data, dict):
        for key, value in data.items():
            sub = (*path, key)
            if sub not in lines:
                text_key = (*path, str(key))
                if text_key in lines:
                    lines[sub] = lines[text_key]
            _alias_constructed_keys(value, sub, lines)
    elif isinstance(data, list):
        for i, value in enumerate(data):
            _alias_constructed_keys(value, (*path, i), lines)
