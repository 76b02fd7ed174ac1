"""Every result type pickles with what it computed (issue 39, item 6).

Process executors and users' own multiprocessing send results between processes, so
every subclass of :class:`designlab.results.Result` must pickle. The types are discovered
(every module of designlab imported, ``Result``'s subclasses walked), and the instances
are the ones the examples create, of each type's own module and of the modules that construct
it (their doctests, run here with every new result recorded): a new result type is covered by
an example, and a type no example creates fails this test until one does. A base class that
no module constructs (only its subclasses) is covered by its subclasses.
"""

from __future__ import annotations

import doctest
import importlib
import inspect
import pickle
import pkgutil
import re
import sys
from typing import Any

import pytest

import designlab
from designlab.results import Result

pytestmark = pytest.mark.slow  # the examples of every result module: a few minutes


def _modules() -> list[str]:
    """Every module of designlab (``__main__`` left out)."""
    return [
        info.name
        for info in pkgutil.walk_packages(designlab.__path__, "designlab.")
        if not info.name.endswith("__main__")
    ]


def result_types() -> list[type[Result]]:
    """Every subclass of :class:`Result` in designlab, discovered."""
    for name in _modules():
        importlib.import_module(name)
    found: set[type[Result]] = set()
    todo = [Result]
    while todo:
        for sub in todo.pop().__subclasses__():
            if sub.__module__.startswith("designlab.") and sub not in found:
                found.add(sub)
                todo.append(sub)
    return sorted(found, key=lambda t: f"{t.__module__}.{t.__qualname__}")


def _examples_results(modules: set[str]) -> dict[type, Any]:
    """The first result of each type that the doctests of ``modules`` create."""
    import matplotlib

    matplotlib.use("Agg")
    seen: dict[type, Any] = {}
    own_new = Result.__dict__.get("__new__")  # None: inherited from object (restored by deleting)

    def recording_new(cls: type, *args: Any, **kwargs: Any) -> Any:
        obj = object.__new__(cls)
        seen.setdefault(cls, obj)
        return obj

    Result.__new__ = recording_new  # type: ignore[method-assign,assignment]
    try:
        runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
        for name in sorted(modules):
            for test in doctest.DocTestFinder().find(importlib.import_module(name)):
                runner.run(test, out=lambda _: None)
    finally:
        # Neither deleting the patch nor assigning object.__new__ back restores CPython's slot
        # (object.__new__ then refuses the constructor's arguments): a plain __new__ does.
        Result.__new__ = own_new or _plain_new  # type: ignore[method-assign,assignment]
    return seen


TYPES = result_types()

#: Types known not to pickle: each must fail (strict), so fixing one fails this test until it
#: leaves this table. Every result type pickles now.
KNOWN: dict[str, str] = {}


def _sources() -> dict[str, str]:
    return {name: inspect.getsource(sys.modules[name]) for name in _modules()}


def _constructor(kind: type) -> re.Pattern[str]:
    """A call of ``kind`` (its ``class`` statement left out)."""
    return re.compile(rf"(?<!\w)(?<!class ){kind.__name__}\(")


def base_only(types: list[type[Result]]) -> list[type[Result]]:
    """The types no module constructs, only subclasses (covered by their subclasses)."""
    sources = _sources().values()
    return [
        t for t in types
        if t.__subclasses__() and not any(_constructor(t).search(s) for s in sources)
    ]  # fmt: skip


def _plain_new(cls: type, *args: Any, **kwargs: Any) -> Any:
    return object.__new__(cls)


def example_modules(types: list[type[Result]]) -> set[str]:
    """The modules whose examples may create ``types``: where each is defined or constructed.

    A result is usually built by the function that computes it, in another module than its
    class (``evaluate_gains`` in ``navigation.tuning`` builds a ``GainEvaluation``): that
    function's example is the type's example too.
    """
    calls = [_constructor(t) for t in types]
    found = {t.__module__ for t in types}
    for name, source in _sources().items():
        if ">>>" in source and any(call.search(source) for call in calls):
            found.add(name)
    return found


@pytest.fixture(scope="module")
def instances() -> dict[type, Any]:
    return _examples_results(example_modules(TYPES))


def test_result_types_are_discovered() -> None:
    names = {t.__name__ for t in TYPES}
    assert {"ImpactResponse", "NavigationResult", "CrowdResult", "FollowerRun",
            "ParetoFront", "AccompanyResult"} <= names  # fmt: skip
    assert set(KNOWN) <= names, sorted(set(KNOWN) - names)


BASES = base_only(TYPES)


def test_base_types_are_covered_by_their_subclasses(instances: dict[type, Any]) -> None:
    """A base no module constructs (``ReductionResult``) is pickled as its subclasses."""
    assert "ReductionResult" in {t.__name__ for t in BASES}
    for base in BASES:
        subs = [t for t in TYPES if issubclass(t, base) and t not in BASES]
        assert subs and all(t in instances for t in subs), base


def _cases() -> list[Any]:
    return [
        pytest.param(t, id=t.__qualname__, marks=pytest.mark.xfail(reason=KNOWN[t.__name__],
                                                                  strict=True))
        if t.__name__ in KNOWN else pytest.param(t, id=t.__qualname__)
        for t in TYPES if t not in BASES
    ]  # fmt: skip


@pytest.mark.parametrize("kind", _cases())
def test_every_result_type_pickles(kind: type, instances: dict[type, Any]) -> None:
    assert kind in instances, (
        f"no example of {kind.__module__} creates a {kind.__qualname__}: give it a doctest"
    )
    r = instances[kind]
    back = pickle.loads(pickle.dumps(r))
    assert type(back) is kind
    assert not _differences(r, back), _differences(r, back)[:5]


def _differences(a: Any, b: Any, where: str = "result", depth: int = 0) -> list[str]:
    """Where ``b`` (unpickled) differs from ``a``: fields, items and array values, NaN = NaN."""
    import numpy as np
    import pandas as pd

    if depth > 12 or a is b:
        return []
    if type(a) is not type(b):
        return [f"{where}: {type(a).__name__} came back as {type(b).__name__}"]
    if isinstance(a, np.ndarray):
        pairs = zip(a.flat, b.flat, strict=True) if a.shape == b.shape else ()
        same = a.shape == b.shape and (
            np.array_equal(a, b, equal_nan=a.dtype.kind in "fc") if a.dtype != object
            else all(not _differences(x, y, where, depth + 1) for x, y in pairs)
        )  # fmt: skip
        return [] if same else [f"{where}: array differs"]
    if isinstance(a, pd.DataFrame | pd.Series):
        return [] if a.equals(b) else [f"{where}: table differs"]
    if isinstance(a, float):
        return [] if a == b or (a != a and b != b) else [f"{where}: {a!r} != {b!r}"]
    if isinstance(a, dict):
        if list(a) != list(b):
            return [f"{where}: keys differ"]
        return [d for k in a for d in _differences(a[k], b[k], f"{where}[{k!r}]", depth + 1)]
    if isinstance(a, list | tuple):
        if len(a) != len(b):
            return [f"{where}: length {len(a)} != {len(b)}"]
        return [d for i, (x, y) in enumerate(zip(a, b, strict=True)) for d in
                _differences(x, y, f"{where}[{i}]", depth + 1)]  # fmt: skip
    state = getattr(a, "__dict__", None)
    if state is not None:
        return _differences(state, b.__dict__, where, depth + 1)
    try:
        return [] if a == b else [f"{where}: {a!r} != {b!r}"]
    except ValueError:  # an object whose == is elementwise
        return []
