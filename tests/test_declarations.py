"""Each fact said once: the declarations of the domain models, checked across the package.

* For every :func:`designlab.params.declared` class in designlab, the JSON Schema
  of its study spec (:func:`designlab.study.specs.spec_model`) and its
  constructor accept and refuse the same boundary values: each bound, one ulp
  either side, NaN, +-inf, a boolean and a number written as text.
* No study-kind module re-declares a field of the domain class its spec builds
  (a pydantic field restating the name, and so the unit, bound and default, of a
  dataclass field): kinds derive their specs from the declarations.
"""

from __future__ import annotations

import ast
import dataclasses
import doctest
import functools
import importlib
import inspect
import math
import pkgutil
import typing
from collections.abc import Callable
from pathlib import Path
from typing import Any

import jsonschema
import pytest

import designlab
from designlab.errors import InvalidParameterError
from designlab.params import ARG, Param, params_of
from designlab.study.specs import spec_model

_MISSING: Any = dataclasses.MISSING


def _modules() -> list[Any]:
    out = []
    for info in pkgutil.walk_packages(designlab.__path__, "designlab."):
        if info.name.startswith(("designlab.cli", "designlab.__main__")):
            continue
        out.append(importlib.import_module(info.name))
    return out


MODULES = _modules()
DECLARED = {
    f"{obj.__module__}.{obj.__qualname__}": obj
    for mod in MODULES
    for obj in vars(mod).values()
    if inspect.isclass(obj) and "__params__" in vars(obj) and obj.__module__ == mod.__name__
}


#: Valid instances of the classes whose required fields no rule below can fill (a controller
#: to wrap, arrays that must agree), each built by the package's own factory.
EXAMPLES: dict[str, Callable[[], Any]] = {
    "BrakeMode": lambda: designlab.following.tether.BrakeMode(
        designlab.following.tether.PseudoJoystick()
    ),
    "LeaderPath": lambda: designlab.following.tether.straight_line(2.0),
    "WalkingTask": lambda: designlab.following.accompanying.walking_task("forward"),
}


def _preset(cls: type) -> Any:
    """An instance of ``cls`` kept in its module (a named preset such as ``OXYDOG``)."""
    for value in vars(importlib.import_module(cls.__module__)).values():
        if type(value) is cls:
            return value
    return None


def _documented(cls: type) -> Any:
    """The first instance of ``cls`` that its docstring's examples make (bound or not)."""
    namespace = dict(vars(importlib.import_module(cls.__module__)))
    for example in doctest.DocTestParser().get_examples(cls.__doc__ or ""):
        if example.exc_msg is not None:
            continue
        try:
            exec(compile(example.source, f"<{cls.__name__} docstring>", "exec"), namespace)
            calls = [n for n in ast.walk(ast.parse(example.source)) if isinstance(n, ast.Call)]
            made = [eval(compile(ast.Expression(c), "<call>", "eval"), namespace) for c in calls]
        except Exception:  # an example that needs what came before it in a module doctest
            return None
        found = [v for v in [*namespace.values(), *made] if type(v) is cls]
        if found:
            return found[0]
    return None


def _field_value(cls: type, name: str, decl: Param) -> Any:
    """A valid value of a required field from its declaration alone (``_MISSING``: none)."""
    if decl.kind == "choice":
        return decl.choices[0]
    if decl.kind == "flag":
        return False
    if decl.kind == "text":
        return "x" * (decl.min_length or 1)
    if decl.kind == "object":
        nested = typing.get_type_hints(cls).get(name)
        if inspect.isclass(nested) and "__params__" in vars(nested):
            return _example(nested)  # a required nested model: its own example
        return _MISSING
    if decl.typical is not None:
        return sum(decl.typical) / 2
    lo = decl.ge if decl.ge is not None else decl.gt
    hi = decl.le if decl.le is not None else decl.lt
    return ((lo or 0.0) + (hi if hi is not None else (lo or 0.0) + 2.0)) / 2


def _built(cls: type) -> Any:
    """An instance built from the declarations (defaults kept), or ``None``."""
    values = {}
    for name, decl in params_of(cls).items():
        if decl.default is not None or decl.optional:
            continue
        field = next(f for f in dataclasses.fields(cls) if f.name == name)
        if field.default is not _MISSING or field.default_factory is not _MISSING:
            continue
        value = _field_value(cls, name, decl)
        if value is _MISSING:
            return None
        values[name] = value
    try:
        return cls(**values)
    except (TypeError, ValueError):
        return None


@functools.cache
def _example(cls: type) -> Any:
    """A valid instance to start from: the registry, a preset, the declarations, the docstring."""
    make = EXAMPLES.get(cls.__name__)
    for candidate in (
        make() if make is not None else None,
        _preset(cls),
        _built(cls),
        _documented(cls),
    ):
        if type(candidate) is cls:
            return candidate
    raise AssertionError(
        f"no valid {cls.__name__} to start from: add a preset, a docstring example that "
        "binds one, or an entry of EXAMPLES"
    )


def test_every_declared_class_has_an_example() -> None:
    missing = []
    for name, cls in DECLARED.items():
        try:
            _example(cls)
        except AssertionError:
            missing.append(name)
    assert not missing


def _boundary_values(decl: Param) -> list[Any]:
    values: list[Any] = [math.nan, math.inf, -math.inf, True, "1"]
    for bound in (decl.gt, decl.ge, decl.lt, decl.le):
        if bound is not None:
            b = float(bound)
            values += [b, math.nextafter(b, -math.inf), math.nextafter(b, math.inf)]
    return values


CASES = [
    (name, field)
    for name, cls in DECLARED.items()
    for field, decl in params_of(cls).items()
    if decl.kind in ("real", "integer")
]


def _start(name: str, field: str) -> tuple[Param, Any, Any]:
    """A field's declaration, a valid instance to vary, the field's JSON Schema validator."""
    cls = DECLARED[name]
    schema = spec_model(cls).model_json_schema()["properties"][field]
    return params_of(cls)[field], _example(cls), jsonschema.Draft202012Validator(schema)


def test_declared_classes_are_found() -> None:
    assert "designlab.impact.parameters.Foam" in DECLARED


@pytest.mark.parametrize(
    ("name", "field"), CASES, ids=[f"{n.split('.')[-1]}.{f}" for n, f in CASES]
)
def test_schema_and_constructor_agree_on_the_boundaries(name: str, field: str) -> None:
    decl, base, validator = _start(name, field)
    disagree = []
    for value in _boundary_values(decl):
        by_schema = validator.is_valid(value)  # JSON has no NaN/inf: the schema says "number"
        if isinstance(value, float) and not math.isfinite(value):
            # JSON has no NaN/inf: YAML's .inf is allowed only where the declaration allows it
            by_schema = not math.isnan(value) and decl.within(value)
        try:
            decl.check(value)
            own_rule_accepts = True
        except InvalidParameterError:
            own_rule_accepts = False
        try:
            dataclasses.replace(base, **{field: value})
            by_constructor = True
        except ValueError:  # InvalidParameterError included
            if own_rule_accepts:
                continue  # refused by a rule between fields (__post_init__), not by the bound
            by_constructor = False
        if by_schema != by_constructor:
            disagree.append(f"{value!r}: schema {by_schema}, constructor {by_constructor}")
    assert not disagree, f"{name}.{field}: " + "; ".join(disagree)


TEXT_CASES = [
    (name, field)
    for name, cls in DECLARED.items()
    for field, decl in params_of(cls).items()
    if decl.kind == "text"
]


def test_text_lengths_are_declared_somewhere() -> None:
    assert ("designlab.following.tether.paths.LeaderPath", "name") in TEXT_CASES


@pytest.mark.parametrize(
    ("name", "field"), TEXT_CASES, ids=[f"{n.split('.')[-1]}.{f}" for n, f in TEXT_CASES]
)
def test_schema_and_constructor_agree_on_text_lengths(name: str, field: str) -> None:
    decl, base, validator = _start(name, field)
    lengths = {0, 1}
    for bound in (decl.min_length, decl.max_length):
        if bound is not None:
            lengths |= {max(bound - 1, 0), bound, bound + 1}
    for n in sorted(lengths):
        value = "x" * n
        try:
            dataclasses.replace(base, **{field: value})
            by_constructor = True
        except InvalidParameterError as exc:
            assert field in str(exc) and "characters" in str(exc)
            by_constructor = False
        assert validator.is_valid(value) == by_constructor, f"{name}.{field}: length {n}"


# --- kinds do not restate domain fields ----------------------------------------------

KINDS_DIR = Path(designlab.__file__).parent / "study" / "kinds"
KIND_MODULES = sorted(p.stem for p in KINDS_DIR.glob("*.py") if p.stem != "__init__")

#: Kind modules that still restate some domain fields, with what is left to convert.
UNCONVERTED: dict[str, str] = {}


def _domain_fields(obj: Any) -> set[str]:
    if not inspect.isclass(obj) or not obj.__module__.startswith("designlab."):
        return set()
    if obj.__module__.startswith(("designlab.study", "designlab.report")):
        return set()
    if "__params__" in vars(obj):
        return set(params_of(obj))
    if dataclasses.is_dataclass(obj):
        return {f.name for f in dataclasses.fields(obj)}
    return set()


def restated_fields(module_name: str) -> list[str]:
    """``Spec.field (Domain)`` for each pydantic field written by hand that a domain class
    built in the same class (a call in its methods) also has."""
    module = importlib.import_module(f"designlab.study.kinds.{module_name}")
    tree = ast.parse(Path(module.__file__).read_text(encoding="utf-8"))
    found = []
    for node in tree.body:
        if not isinstance(node, ast.ClassDef):
            continue
        annotated = {
            s.target.id
            for s in node.body
            if isinstance(s, ast.AnnAssign) and isinstance(s.target, ast.Name)
        }
        built = {
            call.func.id
            for call in ast.walk(node)
            if isinstance(call, ast.Call) and isinstance(call.func, ast.Name)
        }
        for name in sorted(built):
            fields = _domain_fields(getattr(module, name, None))
            for field in sorted(annotated & fields):
                found.append(f"{node.name}.{field} ({name})")
    return found


def test_the_converted_impact_specs_restate_nothing() -> None:
    assert restated_fields("impact_specs") == []
    assert restated_fields("impact_sweep") == []


@pytest.mark.parametrize("module_name", KIND_MODULES)
def test_kind_modules_do_not_restate_domain_fields(module_name: str) -> None:
    found = restated_fields(module_name)
    if found and module_name in UNCONVERTED:
        pytest.xfail(f"{UNCONVERTED[module_name]}: restates {', '.join(found)}")
    assert not found, f"{module_name} restates domain fields: {', '.join(found)}"


# --- signatures read argument defaults from their declarations ----------------------

PACKAGE = Path(designlab.__file__).parent


def _argument_defaults() -> dict[str, list[Any]]:
    """Argument name -> the defaults declared for it: the standalone declarations (module-level
    :class:`~designlab.params.Param` objects with a default) and :data:`designlab.params.ARG`."""
    found: dict[str, list[Any]] = {}
    seen: set[int] = set()
    decls = [v for mod in MODULES for v in vars(mod).values() if isinstance(v, Param)]
    for decl in [*decls, *ARG]:
        if decl.name and decl.default is not None and id(decl) not in seen:
            seen.add(id(decl))
            found.setdefault(decl.name, []).append(decl.default)
    return found


def _same(literal: Any, declared: Any) -> bool:
    if isinstance(literal, bool) or isinstance(declared, bool):
        return type(literal) is type(declared) and literal == declared
    if isinstance(literal, str) or isinstance(declared, str):
        return literal == declared
    return (
        isinstance(literal, int | float)
        and isinstance(declared, int | float)
        and (literal == declared)
    )


def restated_defaults(sources: dict[str, str], declared: dict[str, list[Any]]) -> list[str]:
    """``file:line name=value`` for each function argument whose default is a literal equal to
    a default declared for an argument of the same name."""
    found = []
    for where, text in sources.items():
        for fn in ast.walk(ast.parse(text)):
            if not isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef):
                continue
            a = fn.args
            positional = [*a.posonlyargs, *a.args]
            with_default = positional[len(positional) - len(a.defaults) :]
            pairs = list(zip(with_default, a.defaults, strict=True))
            kw = zip(a.kwonlyargs, a.kw_defaults, strict=True)
            pairs += [(x, d) for x, d in kw if d is not None]
            for arg, default in pairs:
                if not isinstance(default, ast.Constant) or default.value is None:
                    continue
                if any(_same(default.value, d) for d in declared.get(arg.arg, ())):
                    found.append(f"{where}:{default.lineno} {arg.arg}={default.value!r}")
    return found


def test_no_signature_restates_a_declared_default() -> None:
    """``seed: int = 0`` where ``seed`` is declared restates its default: read it from the
    declaration (``seed: int = ARG.seed.default``, ``stop_time: float = STOP_TIME.default``)."""
    sources = {
        str(p.relative_to(PACKAGE.parent)): p.read_text(encoding="utf-8")
        for p in sorted(PACKAGE.rglob("*.py"))
    }
    assert restated_defaults(sources, _argument_defaults()) == []


def test_a_restated_default_is_found() -> None:
    declared = _argument_defaults()
    text = (
        "def f(n, seed: int = 0, *, confidence=0.95, stop_time=0.05, other=0.95):\n"
        "    return ARG.seed.default\n"
        "def g(seed=ARG.seed.default, confidence=0.9, stop_time=None): ...\n"
    )
    assert restated_defaults({"x.py": text}, declared) == [
        "x.py:1 seed=0",
        "x.py:1 confidence=0.95",
        "x.py:1 stop_time=0.05",
    ]


def test_every_seed_is_the_shared_declaration() -> None:
    """A seed is declared once (``ARG.seed``); a use only narrows what it says (its meaning,
    ``None`` allowed, JuPedSim's 31-bit seeds), never the kind, lower bound or default."""
    seeds = [v for mod in MODULES for v in vars(mod).values() if isinstance(v, Param)]
    seeds += [d for cls in DECLARED.values() for d in params_of(cls).values()]
    seeds = [d for d in seeds if d.name in ("seed", "seeds")]
    assert len(seeds) > 5
    for decl in seeds:
        same = (decl.kind, decl.ge, decl.default) == ("integer", 0, ARG.seed.default)
        assert same and decl.le <= ARG.seed.le, decl.qualname


def restated_field_defaults(sources: dict[str, str], declared: dict[str, list[Any]]) -> list[str]:
    """``file:line Class.name=value`` for each class field whose default is a literal equal to
    a default declared for an argument of the same name (a result or spec restating it)."""
    found = []
    for where, text in sources.items():
        for cls in ast.walk(ast.parse(text)):
            if not isinstance(cls, ast.ClassDef):
                continue
            for s in cls.body:
                if not (
                    isinstance(s, ast.AnnAssign)
                    and isinstance(s.target, ast.Name)
                    and isinstance(s.value, ast.Constant)
                    and s.value.value is not None
                ):
                    continue
                if any(_same(s.value.value, d) for d in declared.get(s.target.id, ())):
                    found.append(f"{where} {cls.name}.{s.target.id}={s.value.value!r}")
    return found


#: Class fields that still restate a declared default, with what is left to convert.
FIELDS_LEFT: dict[str, str] = {
    "designlab/codesign/front.py DesignScore.risk_bound=1.0": "RISK_BOUND is declared below it",
    **{
        f"designlab/study/kinds/{k}": "a study spec's field: read the declaration (kinds owners)"
        for k in (
            "navigation_crowds.py CrowdMethodSpec.method='vff'",
            "navigation_crowds.py TuningSpec.robust='mean'",
            "navigation_crowds.py TuningSpec.alpha=0.8",
            "navigation_crowds.py TuningSpec.popsize=6",
            "navigation_crowds.py NavigationCrowdsStudy.personal_space=1.2",
            "navigation_crowds.py NavigationCrowdsStudy.confidence=0.95",
            "navigation_scenarios.py NavigationScenariosStudy.arrival_tolerance=0.15",
            "navigation_specs.py MethodSpec.method='vff'",
            "navigation_sweep.py NavigationDesign.arrival_tolerance=0.15",
            "tether_comparison.py ErrorSourcesSpec.desired_length=1.0",
        )
    },
}


def test_no_class_field_restates_a_declared_default() -> None:
    """A result's or spec's ``seed: int = 0`` restates the declaration as a signature would
    (``ParetoFront.seed``, ``GainOptimum.method``, ``FoamProblem.head_levels`` were)."""
    sources = {
        str(p.relative_to(PACKAGE.parent)): p.read_text(encoding="utf-8")
        for p in sorted(PACKAGE.rglob("*.py"))
    }
    found = set(restated_field_defaults(sources, _argument_defaults()))
    assert found - set(FIELDS_LEFT) == set()
    assert set(FIELDS_LEFT) - found == set(), "converted: remove from FIELDS_LEFT"


def test_a_restated_field_default_is_found() -> None:
    text = "class R:\n    seed: int = 0\n    confidence: float = ARG.confidence.default\n"
    assert restated_field_defaults({"x.py": text}, _argument_defaults()) == ["x.py R.seed=0"]
