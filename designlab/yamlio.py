"""Reading YAML files safely, with errors that name the file and the line.

Every YAML file designlab reads (study files, scenario files) goes through this module,
part of the shared core so that the domains can use it too. It guards against what a
hostile or mistaken file can do to a plain ``yaml.safe_load(open(path).read())``:

* only a **regular file** is opened: a FIFO (which would block forever), a device
  (``/dev/zero`` never ends), a socket or a directory is refused before it is read;
* the file is read in bounded chunks and refused beyond :data:`MAX_BYTES`, so a huge file
  never fills the memory;
* the text must be UTF-8 without NUL bytes or other control characters (YAML forbids them);
* a key repeated in one mapping is an error naming the key and both lines, not a silent
  overwrite;
* nesting deeper than :data:`MAX_DEPTH` (a recursion bomb), aliases expanding to more than
  :data:`MAX_NODES` values (a "billion laughs") and numbers longer than
  :data:`MAX_NUMBER_CHARS` characters (a 5,000-digit integer) are refused with their line;
* floats written without a dot, such as ``20e3`` or ``1e-3``, load as floats (YAML 1.2)
  instead of strings.

Every problem raises :class:`YamlError` (a :class:`~designlab.errors.DesignlabError` and a
``ValueError``) whose message starts with ``<file>:<line>:``.

Examples
--------
>>> data, lines = load_yaml("a: 1\\nb:\\n  - x: 20e3\\n")
>>> data
{'a': 1, 'b': [{'x': 20000.0}]}
>>> lines[("b", 0, "x")]
3
>>> load_yaml("a: 1\\nb: 2\\na: 3\\n", file="room.yaml")
Traceback (most recent call last):
...
designlab.yamlio.YamlError: room.yaml:3: key 'a' appears twice in the same mapping, on
    lines 1 and 3
"""

from __future__ import annotations

import os
import re
import stat
from collections.abc import Hashable
from os import PathLike
from typing import Any

import yaml

from designlab.errors import DesignlabError

__all__ = [
    "MAX_BYTES",
    "MAX_DEPTH",
    "MAX_NODES",
    "MAX_NUMBER_CHARS",
    "YamlError",
    "YamlPath",
    "load_yaml",
    "load_yaml_file",
    "read_text_file",
]

#: A location in the data: mapping keys and sequence indices from the root.
YamlPath = tuple[Hashable, ...]

#: The largest YAML file read, in bytes (and text, in characters): studies and scenarios
#: are a few kB.
MAX_BYTES = 5_000_000
#: The deepest nesting of mappings and lists (a study needs about 6).
MAX_DEPTH = 64
#: The most values a document may expand to (aliases counted at every use).
MAX_NODES = 200_000
#: The longest number read, in characters (a double has 17 significant digits and an
#: exponent; an integer of int64 has 19 digits).
MAX_NUMBER_CHARS = 40

_CHUNK = 1 << 16


class YamlError(DesignlabError, ValueError):
    """A YAML file cannot be read, is not valid YAML, or is hostile (see the module).

    Parameters
    ----------
    message
        What is wrong and what is allowed.
    file
        The file, if known.
    line
        1-based line of the problem, if known.
    path
        The keys and indices of the value at fault (a repeated key), if known.

    Examples
    --------
    >>> str(YamlError("not valid YAML", file="s.yaml", line=3))
    's.yaml:3: not valid YAML'
    """

    def __init__(
        self, message: str, *, file: str | None = None, line: int | None = None,
        path: YamlPath = (),
    ) -> None:  # fmt: skip
        self.message = message
        self.file = file
        self.line = line
        self.path = path
        where = f"{file}: " if file else ""  # without a file, the message alone (see .line)
        if line is not None and file:
            where = f"{file}:{line}: "
        super().__init__(f"{where}{message}")


def read_text_file(path: str | PathLike[str], *, max_bytes: int = MAX_BYTES) -> str:
    """The UTF-8 text of a regular file of at most ``max_bytes`` bytes.

    The file is checked to be a regular file before it is opened (and again once open,
    without blocking), then read in chunks: a FIFO, a device such as ``/dev/zero``, a
    directory or a file over ``max_bytes`` is refused without reading it whole.

    Parameters
    ----------
    path
        The file.
    max_bytes
        The largest size accepted.

    Returns
    -------
    str
        Its text.

    Raises
    ------
    YamlError
        If the file is missing, not a regular file, too large, unreadable or not UTF-8.

    Examples
    --------
    >>> read_text_file("/dev/zero")
    Traceback (most recent call last):
    ...
    designlab.yamlio.YamlError: /dev/zero: is a character device, not a regular file; ...
    """
    name = os.fspath(path)
    try:
        _check_regular(os.stat(name), name)
        fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)
                     | getattr(os, "O_NOCTTY", 0))  # fmt: skip
    except FileNotFoundError:
        raise YamlError("file not found", file=name) from None
    except OSError as exc:
        raise YamlError(f"cannot read the file: {exc.strerror}", file=name) from None
    try:
        _check_regular(os.fstat(fd), name)  # the same file, swapped since the stat or not
        data = _read_bounded(fd, name, max_bytes)
    except OSError as exc:
        raise YamlError(f"cannot read the file: {exc.strerror}", file=name) from None
    finally:
        os.close(fd)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise YamlError(
            f"not UTF-8 text ({exc.reason} at byte {exc.start:,}); save the file as UTF-8",
            file=name,
            line=line,
        ) from None
    nul = text.find("\0")
    if nul >= 0:
        raise YamlError(
            f"a NUL byte at character {nul + 1:,}: a text file cannot contain NUL bytes (is "
            "it a binary file?)",
            file=name,
            line=text.count("\n", 0, nul) + 1,
        )
    return text


_KINDS = (
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def _check_regular(st: os.stat_result, name: str) -> None:
    if stat.S_ISREG(st.st_mode):
        return
    what = next((text for test, text in _KINDS if test(st.st_mode)), "not a regular file")
    raise YamlError(f"is {what}, not a regular file; give the path of a text file", file=name)


def _read_bounded(fd: int, name: str, max_bytes: int) -> bytes:
    chunks: list[bytes] = []
    total = 0
    while True:
        chunk = os.read(fd, min(_CHUNK, max_bytes + 1 - total))
        if not chunk:
            return b"".join(chunks)
        chunks.append(chunk)
        total += len(chunk)
        if total > max_bytes:
            raise YamlError(
                f"the file is larger than {max_bytes:,} bytes, the most read (a study or a "
                "scenario is a few kB)",
                file=name,
            )


class _Loader(yaml.SafeLoader):
    """Safe loader with YAML 1.2-style floats, a nesting limit and a number-length limit.

    The composer is recursive, so a document nested thousands of levels deep would exhaust
    Python's stack (``RecursionError``) here or in every later step; the depth is counted
    while composing and refused beyond :data:`MAX_DEPTH` with the line where it happens.
    """

    _depth = 0

    def compose_node(self, parent: Any, index: Any) -> Any:
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                mark = self.peek_event().start_mark
                raise YamlError(
                    f"the document nests lists and mappings more than {MAX_DEPTH} levels "
                    "deep; studies and scenarios are shallow (a few levels)",
                    line=mark.line + 1,
                )
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def construct_object(self, node: yaml.Node, deep: bool = False) -> Any:
        try:
            return super().construct_object(node, deep=deep)
        except (YamlError, yaml.YAMLError):
            raise
        except (ValueError, TypeError, OverflowError) as exc:  # e.g. a date 2020-13-45
            raise YamlError(
                f"cannot read the value {str(node.value)[:60]!r} ({node.tag}): {exc}",
                line=node.start_mark.line + 1,
            ) from None

    def construct_yaml_int(self, node: yaml.ScalarNode) -> int:
        _check_number(node)
        return int(super().construct_yaml_int(node))

    def construct_yaml_float(self, node: yaml.ScalarNode) -> float:
        _check_number(node)
        return float(super().construct_yaml_float(node))


def _check_number(node: yaml.ScalarNode, path: YamlPath = ()) -> None:
    """Refuse a number written with more than :data:`MAX_NUMBER_CHARS` characters, with its
    place (``path``, named by the callers' errors: ``cases[0].impact_velocity``) if known."""
    text = str(node.value)
    if len(text) > MAX_NUMBER_CHARS:
        raise YamlError(
            f"the number {text[:12]}...{text[-4:]} is not allowed: it is written with "
            f"{len(text):,} characters (digits); at most {MAX_NUMBER_CHARS} are read (write a "
            "large or precise value in scientific notation, e.g. 1.5e300)",
            line=node.start_mark.line + 1,
            path=path,
        )


_NUMBER_TAGS = ("tag:yaml.org,2002:int", "tag:yaml.org,2002:float")
_Loader.add_constructor("tag:yaml.org,2002:int", _Loader.construct_yaml_int)
_Loader.add_constructor("tag:yaml.org,2002:float", _Loader.construct_yaml_float)
_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(
        r"""^(?:[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+
        |[-+]?\.[0-9_]+(?:[eE][-+]?[0-9]+)?)$""",
        re.X,
    ),
    list("-+0123456789."),
)


def _check_size(root: yaml.Node) -> None:
    """Refuse documents whose aliases expand to more than :data:`MAX_NODES` nodes.

    A "billion laughs" document (anchors nesting aliases of aliases) is tiny as text but
    exponential once expanded; it is measured on the node graph with memoisation, so the
    check itself is linear in the text.
    """
    sizes: dict[int, int] = {}
    active: set[int] = set()

    def size(node: yaml.Node) -> int:
        key = id(node)
        if key in sizes:
            return sizes[key]
        if key in active:
            raise YamlError(
                "the document refers to itself through an alias (a recursive structure); "
                "it must be a plain tree",
                line=node.start_mark.line + 1,
            )
        active.add(key)
        total = 1
        children: list[yaml.Node] = []
        if isinstance(node, yaml.MappingNode):
            children = [n for pair in node.value for n in pair]
        elif isinstance(node, yaml.SequenceNode):
            children = list(node.value)
        for child in children:
            total += size(child)
            if total > MAX_NODES:
                break
        active.discard(key)
        sizes[key] = total
        if total > MAX_NODES:
            raise YamlError(
                f"the document expands to more than {MAX_NODES:,} values (nested anchors and "
                "aliases?); studies and scenarios are small",
                line=node.start_mark.line + 1,
            )
        return total

    size(root)


def _record(loader: _Loader, node: yaml.Node, path: YamlPath, lines: dict[YamlPath, int]) -> None:
    """Walk the composed node tree, record the line of each key and item, refuse repeats.

    Keys are compared as constructed (``1``, ``01`` and ``1.0`` are one key, as they would
    be in the loaded mapping).
    """
    if isinstance(node, yaml.MappingNode):
        seen: dict[Any, int] = {}
        for key_node, value_node in node.value:
            if not isinstance(key_node, yaml.ScalarNode) or key_node.value == "<<":
                continue  # complex keys and merge keys: no line bookkeeping, still loaded
            key: Any = key_node.value
            line = key_node.start_mark.line + 1
            value = loader.construct_object(key_node)
            same = value if isinstance(value, Hashable) else key
            if same in seen:
                raise YamlError(
                    f"key {key!r} appears twice in the same mapping, on lines {seen[same]} "
                    f"and {line}",
                    line=line,
                    path=(*path, key),
                )
            seen[same] = line
            lines[(*path, key)] = line
            _record(loader, value_node, (*path, key), lines)
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            lines[(*path, i)] = item.start_mark.line + 1
            _record(loader, item, (*path, i), lines)
    elif isinstance(node, yaml.ScalarNode) and node.tag in _NUMBER_TAGS:
        _check_number(node, path)  # here, where its path is known


def _line_at(text: str, position: int) -> int:
    return text.count("\n", 0, max(position, 0)) + 1


def load_yaml(text: str, *, file: str | None = None) -> tuple[Any, dict[YamlPath, int]]:
    """Parse YAML text and return ``(data, lines)``.

    Parameters
    ----------
    text
        The YAML document (a single document).
    file
        The file it came from, for error messages.

    Returns
    -------
    data
        The Python value (dicts, lists, scalars), as ``yaml.safe_load`` would return it
        except for the float rule of the module.
    lines
        Maps a path such as ``("cases", 0, "robot")`` to the 1-based line of that key or
        list item. Mapping keys are recorded as written in the file, and as constructed.

    Raises
    ------
    YamlError
        On a YAML syntax error, a repeated key or a hostile document, with the line.

    Examples
    --------
    >>> load_yaml("a: [1, 2", file="s.yaml")
    Traceback (most recent call last):
    ...
    designlab.yamlio.YamlError: s.yaml:1: YAML syntax error: ...
    """
    if len(text) > MAX_BYTES:
        raise YamlError(f"the text is {len(text):,} characters long; at most {MAX_BYTES:,} "
                        "are read", file=file)  # fmt: skip
    try:
        data, lines = _parse(text)
    except YamlError as exc:
        raise YamlError(exc.message, file=file, line=exc.line, path=exc.path) from None
    except yaml.reader.ReaderError as exc:
        code = ord(exc.character) if isinstance(exc.character, str) else int(exc.character)
        what = "a NUL byte" if code == 0 else f"the control character #x{code:04x}"
        raise YamlError(
            f"{what} at character {exc.position + 1:,}: YAML text cannot contain control "
            "characters (is it a binary file?)",
            file=file,
            line=_line_at(text, exc.position),
        ) from None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        problem = exc.problem or str(exc)
        if exc.context:
            problem = f"{exc.context}: {problem}"
        line = mark.line + 1 if mark is not None else None
        raise YamlError(f"YAML syntax error: {problem}", file=file, line=line) from None
    except yaml.YAMLError as exc:
        raise YamlError(f"YAML syntax error: {exc}", file=file) from None
    except RecursionError:  # pragma: no cover - MAX_DEPTH keeps the composer shallow
        raise YamlError("the document is nested too deeply", file=file) from None
    return data, lines


def _parse(text: str) -> tuple[Any, dict[YamlPath, int]]:
    loader = _Loader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None, {}
        _check_size(node)
        lines: dict[YamlPath, int] = {}
        _record(loader, node, (), lines)
        data = loader.construct_document(node)
    finally:
        loader.dispose()
    # Keys were recorded by their YAML text; construct_document may have turned them into
    # ints or bools. Add the constructed forms too.
    _alias_constructed_keys(data, (), lines)
    return data, lines


def load_yaml_file(
    path: str | PathLike[str], *, max_bytes: int = MAX_BYTES
) -> tuple[Any, dict[YamlPath, int]]:
    """Read a YAML file safely (:func:`read_text_file`, then :func:`load_yaml`).

    Parameters
    ----------
    path
        The file.
    max_bytes
        The largest size accepted.

    Returns
    -------
    data, lines
        As :func:`load_yaml`.

    Raises
    ------
    YamlError
        As :func:`read_text_file` and :func:`load_yaml`, naming the file and the line.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "room.yaml"
    >>> _ = f.write_text("goal: [4.0, 0.6]\\n")
    >>> load_yaml_file(f)[0]
    {'goal': [4.0, 0.6]}
    """
    return load_yaml(read_text_file(path, max_bytes=max_bytes), file=os.fspath(path))


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
