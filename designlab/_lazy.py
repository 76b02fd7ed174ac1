"""Packages whose public names are imported on first use (PEP 562), declared once.

A domain package lists its public names as ordinary import statements under
``if TYPE_CHECKING:`` -- the one declaration that type checkers, IDEs and the API
documentation read -- and calls :func:`attach` at its end. At run time nothing behind
those statements is imported with the package: the first access of a name imports the
module that defines it (``dl.impact.simulate`` imports :mod:`designlab.impact.simulate`
and nothing of the navigation layer, pandas or matplotlib). ``import designlab.impact``
therefore costs milliseconds, and a call pays for the modules it needs (issue 39).

Two habits of eager packages are kept:

* a name that is also the name of its module (``designlab.impact.simulate`` the function,
  ``designlab.impact.simulate`` the module) stays the function when the module is imported
  by another path (the import system sets the package's attribute to the module);
* ``package.submodule`` works for every submodule, imported on access.

Examples
--------
>>> import sys, designlab
>>> impact = designlab.impact
>>> callable(impact.simulate), impact.simulate.__module__
(True, 'designlab.impact.simulate')
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
import sys
import types
from pathlib import Path
from typing import Any

__all__ = ["LazyPackage", "attach", "declared_imports"]


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def declared_imports(source: str, package: str) -> dict[str, tuple[str, str | None]]:
    """The names imported under ``if TYPE_CHECKING:`` in ``source``: ``name -> (module, attr)``.

    Parameters
    ----------
    source
        The text of a package's ``__init__``.
    package
        The package's dotted name: ``from package import sub`` declares the submodule
        ``sub``, whose ``attr`` is then ``None`` (the name is the module itself).

    Returns
    -------
    dict
        Each declared name and where it is defined.

    Examples
    --------
    >>> src = "if TYPE_CHECKING:\\n    from p.a import f, G as H\\n    from p import sub\\n"
    >>> declared_imports(src, "p")
    {'f': ('p.a', 'f'), 'H': ('p.a', 'G'), 'sub': ('p.sub', None)}
    """
    names: dict[str, tuple[str, str | None]] = {}
    for node in ast.parse(source).body:
        if not (isinstance(node, ast.If) and _is_type_checking(node.test)):
            continue
        for statement in node.body:
            if not isinstance(statement, ast.ImportFrom) or statement.level or not statement.module:
                continue
            for alias in statement.names:
                name = alias.asname or alias.name
                if statement.module == package:
                    names[name] = (f"{package}.{alias.name}", None)
                else:
                    names[name] = (statement.module, alias.name)
    return names


class LazyPackage(types.ModuleType):
    """A package module whose declared names are imported on first access."""

    _lazy_names: dict[str, tuple[str, str | None]]

    def _lazy_resolve(self, name: str) -> Any:
        module, attr = self._lazy_names[name]
        loaded = importlib.import_module(module)
        return loaded if attr is None else getattr(loaded, attr)

    def __getattr__(self, name: str) -> Any:
        lazy = self.__dict__.get("_lazy_names", {})
        if name in lazy:
            value = self._lazy_resolve(name)
        elif not name.startswith("__") and importlib.util.find_spec(f"{self.__name__}.{name}"):
            value = importlib.import_module(f"{self.__name__}.{name}")
        else:
            raise AttributeError(f"module {self.__name__!r} has no attribute {name!r}")
        types.ModuleType.__setattr__(self, name, value)
        return value

    def __setattr__(self, name: str, value: Any) -> None:
        # The import system binds a freshly imported submodule to its package's attribute;
        # where a public name (a function) shares the submodule's name, the name wins.
        lazy = self.__dict__.get("_lazy_names", {})
        if (
            name in lazy
            and lazy[name][1] is not None
            and isinstance(value, types.ModuleType)
            and value.__name__ == f"{self.__name__}.{name}"
        ):
            value = self._lazy_resolve(name)
        types.ModuleType.__setattr__(self, name, value)

    def __dir__(self) -> list[str]:
        return sorted({*self.__dict__, *self.__dict__.get("_lazy_names", {})})


def attach(package: str) -> None:
    """Make ``package`` (being imported) a :class:`LazyPackage` of its ``TYPE_CHECKING`` names.

    Parameters
    ----------
    package
        The dotted name of the package whose ``__init__`` is running (``__name__``): call
        this at the end of it. Names bound there already (a constant, a submodule the
        ``__init__`` imports itself) are kept as they are.
    """
    module = sys.modules[package]
    source = Path(module.__file__ or "").read_text(encoding="utf-8")
    declared = declared_imports(source, package)
    module.__class__ = LazyPackage
    lazy = {name: target for name, target in declared.items() if name not in module.__dict__}
    types.ModuleType.__setattr__(module, "_lazy_names", lazy)
