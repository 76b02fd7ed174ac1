"""No function of the package is over 100 lines, docstring included (the developers' guide)."""

from __future__ import annotations

import ast
from pathlib import Path

import designlab

LIMIT = 100


def test_no_function_is_over_100_lines() -> None:
    root = Path(designlab.__file__).parent
    long = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                lines = node.end_lineno - node.lineno + 1
                if lines > LIMIT:
                    long.append(f"{path.relative_to(root)}:{node.lineno} {node.name} ({lines})")
    assert not long, "functions over 100 lines:\n" + "\n".join(long)


def test_the_check_sees_a_long_function() -> None:
    body = "\n".join(f"    x{i} = {i}" for i in range(LIMIT))
    (node,) = ast.parse(f"def f():\n{body}\n").body
    assert node.end_lineno - node.lineno + 1 == LIMIT + 1
