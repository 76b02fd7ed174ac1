"""Every public function and class documents every parameter (numpydoc), in the manner of
python-control's ``control/tests/docstrings_test.py``.

Public means: listed in a module's ``__all__`` (or, without ``__all__``, not starting with
``_``) and defined in that module. A class documents its constructor's parameters under
``Parameters`` or, for data classes and models, ``Attributes``.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import pkgutil
import warnings

import pytest

numpydoc = pytest.importorskip("numpydoc.docscrape", reason="numpydoc is in the dev extra")

import designlab  # noqa: E402

SKIP_PARAMS = {"self", "cls"}


def _modules():
    for info in pkgutil.walk_packages(designlab.__path__, "designlab."):
        if info.name.endswith("__main__"):
            continue
        yield importlib.import_module(info.name)


def _public(module):
    names = getattr(module, "__all__", None)
    if names is None:
        names = [n for n in vars(module) if not n.startswith("_")]
    for name in names:
        obj = getattr(module, name, None)
        if (inspect.isfunction(obj) or inspect.isclass(obj)) and obj.__module__ == module.__name__:
            yield f"{module.__name__}.{name}", obj


def _documented_list(obj) -> list[str]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if inspect.isclass(obj):
            doc = numpydoc.ClassDoc(obj, config={"show_class_members": False})
        else:
            doc = numpydoc.FunctionDoc(obj)
    names: list[str] = []
    for section in ("Parameters", "Other Parameters", "Attributes"):
        for p in doc[section]:
            names += [part.strip() for part in p.name.replace("*", "").split(",")]
    return names


def _documented(obj) -> set[str]:
    return set(_documented_list(obj))


def _signature_params(obj) -> list[str]:
    if inspect.isclass(obj):
        if "__init__" not in vars(obj) and not dataclasses.is_dataclass(obj):
            return []  # inherits its constructor (documented where it is defined)
        try:
            sig = inspect.signature(obj)
        except (TypeError, ValueError):
            return []
        if dataclasses.is_dataclass(obj):
            init = {
                f.name for f in dataclasses.fields(obj) if f.init and not f.name.startswith("_")
            }
            return [p for p in sig.parameters if p in init]
    else:
        sig = inspect.signature(obj)
    return [
        name
        for name, p in sig.parameters.items()
        if name not in SKIP_PARAMS and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
    ]


def _cases():
    seen = set()
    for module in _modules():
        for qualname, obj in _public(module):
            if id(obj) in seen:
                continue
            seen.add(id(obj))
            if inspect.isclass(obj) and _is_pydantic(obj):
                continue  # schema models: fields are described in the JSON Schema
            yield pytest.param(obj, id=qualname)


def _is_pydantic(cls) -> bool:
    return any(c.__module__.startswith("pydantic") for c in cls.__mro__[1:])


@pytest.mark.parametrize("obj", list(_cases()))
def test_every_parameter_is_documented(obj):
    assert inspect.getdoc(obj), f"{obj.__qualname__} has no docstring"
    missing = [p for p in _signature_params(obj) if p not in _documented(obj)]
    assert not missing, f"{obj.__module__}.{obj.__qualname__}: undocumented {missing}"
    listed = _documented_list(obj)
    twice = sorted({p for p in listed if listed.count(p) > 1})
    assert not twice, f"{obj.__module__}.{obj.__qualname__}: documented twice {twice}"
