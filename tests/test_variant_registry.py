"""The shared registry of a family of variants (designlab.registry)."""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from pathlib import Path

import pytest
import tomllib
from pydantic import TypeAdapter, ValidationError

from designlab.errors import InvalidParameterError
from designlab.registry import Registry


@dataclass(frozen=True)
class _V:
    name: str
    label: str
    doc: str = ""
    batched: bool = True


def _reg() -> Registry[_V]:
    return Registry("method", "toy methods", [_V("a", "A", "first"), _V("b", "B", batched=False)])


def test_lookup_and_choices_follow_declaration_order() -> None:
    r = _reg()
    assert r.choices() == ("a", "b")
    assert r.choices(batched=False) == ("b",)
    assert r.get("b").label == "B"
    assert "a" in r and "z" not in r and 3 not in r
    assert [v.name for v in r] == ["a", "b"] and len(r) == 2
    assert r.labels() == {"a": "A", "b": "B"}


def test_unknown_name_names_parameter_value_and_choices() -> None:
    with pytest.raises(InvalidParameterError) as e:
        _reg().get("zz", parameter="crowd.method")
    assert e.value.name == "crowd.method" and e.value.value == "zz"
    assert "['a', 'b']" in str(e.value)


def test_a_variant_without_the_capability_is_refused_with_what_is_allowed() -> None:
    allowed = r"\['a'\] \(the toy methods with batched=True\)"
    with pytest.raises(InvalidParameterError, match=allowed):
        _reg().get("b", batched=True)


def test_duplicate_and_nameless_variants_are_refused() -> None:
    r = _reg()
    with pytest.raises(InvalidParameterError, match="already registered"):
        r.register(_V("a", "again"))
    with pytest.raises(InvalidParameterError, match="non-empty str name"):
        r.register(_V("", "empty"))


def test_param_literal_and_schema_derive_from_the_table() -> None:
    r = _reg()
    p = r.param("toy method", default="a")
    assert p.check("b") == "b" and p.default == "a" and p.choices == ("a", "b")
    with pytest.raises(InvalidParameterError):
        p.check("c")
    t = TypeAdapter(r.literal(batched=True))
    assert t.validate_python("a") == "a"
    with pytest.raises(ValidationError):
        t.validate_python("b")
    assert r.json_schema(batched=True)["enum"] == ["a"]
    assert TypeAdapter(r.literal()).json_schema()["enum"] == ["a", "b"] == r.json_schema()["enum"]


def test_docs_table_has_one_row_per_variant_and_extra_columns() -> None:
    text = _reg().table({"batched": lambda v: v.batched})
    assert text.splitlines() == [
        "| name | label | description | batched |",
        "|---|---|---|---|",
        "| `a` | A | first | yes |",
        "| `b` | B |  | no |",
    ]


# --- the import contracts list every variant module of each family --------------------

_FAMILIES = {
    "designlab.navigation.methods": "navigation method",
    "designlab.impact.contact": "impact contact model",
    "designlab.following.tether.laws": "tether law",
}
#: Modules of a family's folder that are not variants (shared base, registry, integrator).
_NOT_VARIANTS = {"__init__", "base", "registry", "integrated"}


def _contracts() -> list[dict]:
    root = Path(__file__).resolve().parents[1]
    config = tomllib.loads((root / "pyproject.toml").read_text(encoding="utf-8"))
    return config["tool"]["importlinter"]["contracts"]


@pytest.mark.parametrize("package", sorted(_FAMILIES))
def test_each_variant_module_is_in_its_familys_contracts(package: str) -> None:
    """A new variant module is listed in its family's independence contract and in the list
    the engines may not import (pyproject.toml); otherwise import-linter cannot keep it alone."""
    folder = Path(importlib.import_module(package).__file__).parent
    variants = {f"{package}.{p.stem}" for p in folder.glob("*.py") if p.stem not in _NOT_VARIANTS}
    listed = [
        set(c.get("modules", c.get("forbidden_modules", ())))
        for c in _contracts()
        if any(
            m.startswith(package + ".") for m in c.get("modules", c.get("forbidden_modules", ()))
        )
    ]
    assert len(listed) == 2, f"{_FAMILIES[package]}: an independence and a forbidden contract"
    for modules in listed:
        assert modules == variants, sorted(modules ^ variants)
