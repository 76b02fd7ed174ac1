"""Built CasADi functions cached on disk, so that a second process loads instead of rebuilding.

Building a large SX function (a navigation step: field, hold and distances over
60 sub-steps) and eliminating its common subexpressions takes a large part of a
second, in every process, before the compiled lanes can even be looked up by
their source (:mod:`designlab.sx.cache`). :func:`cached_function` stores the
built function (``casadi.Function.serialize``) under a key made of the caller's
description of what it builds and a hash of the source files it is built from,
in ``functions/`` of the designlab cache directory; a later process or run
deserialises it (milliseconds). A change of any of those source files, of CasADi's
version or of the description gives a new key. A serialised function can name a
library to load, so an entry is loaded only as this designlab stored it (owner, mode
and recorded SHA-256, :mod:`designlab.sx.trust`); an entry failing a check or not
loading is removed and rebuilt; where the directory cannot be written, nothing is
cached.

Examples
--------
>>> import casadi as ca
>>> def build():
...     x = ca.SX.sym("x")
...     return ca.Function("twice", [x], [2 * x])
>>> f = cached_function("doc example twice", build, sources=(__file__,))
>>> float(f(1.5))
3.0
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable, Sequence
from functools import cache
from pathlib import Path

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from designlab.sx.cache import cache_key, private_cache_subdir, say_once
from designlab.sx.trust import Shelf

__all__ = ["BufferedFunction", "cached_function", "source_hash"]

_SUFFIX = ".casadi"


@cache
def source_hash(paths: tuple[str, ...]) -> str:
    """Hash of the contents of ``paths`` (files; a directory stands for its ``*.py`` files).

    Parameters
    ----------
    paths
        Files or directories.

    Returns
    -------
    str
    """
    h = hashlib.sha256()
    for name in paths:
        p = Path(name)
        files = sorted(p.glob("*.py")) if p.is_dir() else [p]
        for f in files:
            h.update(f.name.encode() + b"\0" + f.read_bytes())
    return h.hexdigest()[:32]


def cached_function(
    description: str, build: Callable[[], ca.Function], sources: Sequence[str]
) -> ca.Function:
    """The function ``build()`` makes, from the disk cache when an equal one was stored.

    Parameters
    ----------
    description
        Everything the function depends on besides the source files (a repr of the
        arguments of ``build``), as a string.
    build
        Builds the function.
    sources
        The source files (or directories of them) the function is built from.

    Returns
    -------
    casadi.Function
    """
    key = cache_key("sx-function", ca.__version__, description, source_hash(tuple(sources)))
    root = private_cache_subdir("functions")
    name = f"{key}{_SUFFIX}"
    shelf = None if root is None else Shelf(root)
    data = None if shelf is None else shelf.load(name, "built-function")
    if data is not None:
        try:
            return ca.Function.deserialize(data.decode())
        except (UnicodeDecodeError, RuntimeError) as exc:
            say_once(f"cached function {root / name} does not load ({exc}); it is rebuilt")
            shelf.discard(name)  # type: ignore[union-attr]
    f = build()
    if shelf is not None:
        try:
            shelf.write(name, f.serialize().encode())
        except OSError as exc:
            say_once(f"function cache {root} cannot be written ({exc}); functions are rebuilt")
    return f


class BufferedFunction:
    """A casadi.Function evaluated through its buffer interface on preallocated numpy arrays.

    ``inp[i]`` and ``out[i]`` are the flat (column-major) arrays of input and output ``i``;
    write the inputs, call, read the outputs: no allocation per call.

    Parameters
    ----------
    f
        The function.

    Examples
    --------
    >>> import casadi as ca
    >>> x = ca.SX.sym("x", 2)
    >>> g = BufferedFunction(ca.Function("g", [x], [ca.vertcat(x[0] + x[1], x[0] * x[1])]))
    >>> g.inp[0][:] = (2.0, 3.0)
    >>> g()
    >>> g.out[0].tolist(), g.view_out(0).shape
    ([5.0, 6.0], (2, 1))
    """

    def __init__(self, f: ca.Function) -> None:
        self.f = f
        self._buf, self._trigger = f.buffer()
        self.inp = [np.zeros(f.nnz_in(i)) for i in range(f.n_in())]
        self.out = [np.zeros(f.nnz_out(i)) for i in range(f.n_out())]
        for i, a in enumerate(self.inp):
            self._buf.set_arg(i, memoryview(a))
        for i, a in enumerate(self.out):
            self._buf.set_res(i, memoryview(a))
        self.shape_in = [(f.size1_in(i), f.size2_in(i)) for i in range(f.n_in())]
        self.shape_out = [(f.size1_out(i), f.size2_out(i)) for i in range(f.n_out())]

    def view_in(self, i: int) -> NDArray[np.float64]:
        """Input ``i`` as its matrix (a column-major view of :attr:`inp`).

        Parameters
        ----------
        i
            Index of the input.
        """
        r, c = self.shape_in[i]
        return self.inp[i].reshape((c, r)).T

    def view_out(self, i: int) -> NDArray[np.float64]:
        """Output ``i`` as its matrix (a column-major view of :attr:`out`).

        Parameters
        ----------
        i
            Index of the output.
        """
        r, c = self.shape_out[i]
        return self.out[i].reshape((c, r)).T

    def __call__(self) -> None:
        self._trigger()
