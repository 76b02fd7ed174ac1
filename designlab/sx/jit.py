"""Compiled numeric kernels (numba) cached on disk in the one designlab cache.

:func:`kernel` decorates a function written in the numba subset of Python with
``numba.njit(cache=True)``; numba's cache (keyed by the source file, its
contents' timestamp and size, the function and the CPU) lives in ``numba/`` of the
designlab cache directory (:func:`designlab.sx.cache.cache_dir`:
``$DESIGNLAB_CACHE_DIR`` or ``~/.cache/designlab``), next to the compiled SX
lanes, so worker processes and later runs load the machine code instead of
compiling it again. ``NUMBA_CACHE_DIR``, if set, wins.

numba checks only the file that defines a cached function, not the files of
the functions it calls (inlined into it): a kernel whose helper in another
module changed would load stale machine code. The cache therefore lives in a
subdirectory named by a hash of every module that defines kernels
(:data:`KERNEL_MODULES`, :func:`sources_key`): changing any of them compiles
afresh.

Where numba is not installed (or ``DESIGNLAB_NO_JIT`` is set to a non-empty
value) :data:`AVAILABLE` is False and :func:`kernel` returns the Python function
unchanged: callers check :data:`AVAILABLE`, keep their numpy path and say so once
in the log (:func:`say_no_jit`).

Examples
--------
>>> from designlab.impact.kernel_modal import shape
>>> shape(-1.0, -2.0, 1.0, 1.0)        # y'' < 0 on a cell of width 1 with |y'''| <= 1
-1
>>> isinstance(AVAILABLE, bool) and jit_cache_dir().endswith(sources_key())
True
"""

from __future__ import annotations

import hashlib
import logging
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from designlab.sx.cache import private_cache_subdir, say_once
from designlab.sx.jit_cache import verify_cache
from designlab.sx.trust import private_dir

__all__ = [
    "AVAILABLE", "KERNEL_MODULES", "NO_JIT_ENV", "jit_cache_dir", "kernel", "reason",
    "say_no_jit", "sources_key",
]  # fmt: skip

#: Set to a non-empty value to disable the compiled kernels (numpy paths only).
NO_JIT_ENV = "DESIGNLAB_NO_JIT"


#: the modules (relative to the package) whose functions are compiled by :func:`kernel`
KERNEL_MODULES = (
    "analysis/lhs_kernel.py",
    "impact/kernel.py",
    "impact/kernel_dd.py",
    "impact/kernel_exp.py",
    "impact/kernel_full.py",
    "impact/kernel_lobe.py",
    "impact/kernel_modal.py",
    "impact/kernel_poles.py",
    "impact/kernel_single.py",
    "navigation/crowds/bookkeeping.py",
    "sx/jit.py",
)


def sources_key(root: Path | None = None) -> str:
    """Hash (16 hex digits) of the :data:`KERNEL_MODULES` sources under ``root``.

    Parameters
    ----------
    root
        The package directory (default: this installation's ``designlab/``).

    Returns
    -------
    str
        Changes whenever one of the kernel modules changes.

    Examples
    --------
    >>> len(sources_key())
    16
    """
    base = Path(__file__).resolve().parent.parent if root is None else Path(root)
    digest = hashlib.sha256()
    for rel in KERNEL_MODULES:
        digest.update(rel.encode())
        try:
            digest.update((base / rel).read_bytes())
        except OSError:
            digest.update(b"missing")
    return digest.hexdigest()[:16]


def jit_cache_dir() -> str:
    """Where numba stores compiled kernels, checked to be this user's alone.

    ``$NUMBA_CACHE_DIR``, else ``<cache_dir>/numba/<sources_key()>``; a directory
    owned by another user or writable by group or others is replaced by one in a
    private temporary cache of the process, with a warning
    (:func:`designlab.sx.cache.private_cache_dir`).
    """
    given = os.environ.get("NUMBA_CACHE_DIR")
    if given:
        try:
            return str(private_dir(Path(given), tighten=False))
        except OSError as exc:
            say_once(f"NUMBA_CACHE_DIR {given} is not used ({exc}); using designlab's cache")
    root = private_cache_subdir("numba")
    if root is None:
        root = Path(tempfile.mkdtemp(prefix="designlab-numba-"))
    return str(private_dir(root / sources_key()))


def _load() -> tuple[Any, str]:
    if os.environ.get(NO_JIT_ENV):
        return None, f"{NO_JIT_ENV} is set"
    os.environ["NUMBA_CACHE_DIR"] = jit_cache_dir()
    try:
        import numba
    except ImportError as exc:  # pragma: no cover - numba is a declared dependency
        return None, f"numba is not installed ({exc})"
    # numba reads its configuration when first imported: a program that imported it
    # before designlab would otherwise cache next to the sources, keyed by each
    # file's own time stamp only (stale code after a change in another module)
    numba.config.CACHE_DIR = os.environ["NUMBA_CACHE_DIR"]
    return numba, ""


_NUMBA, _REASON = _load()

#: Whether compiled kernels are available in this process.
AVAILABLE: bool = _NUMBA is not None


def reason() -> str:
    """Why compiled kernels are not available ('' when they are).

    Examples
    --------
    >>> isinstance(reason(), str)
    True
    """
    return _REASON


def kernel(
    func: Callable[..., Any] | None = None, *, inline: bool = False, borrows: bool = False
) -> Any:
    """``numba.njit(cache=True, error_model="numpy")`` of ``func`` (``func`` without numba).

    IEEE semantics (division by zero gives inf/NaN), no fast-math: the compiled
    function computes what its Python source says, operation by operation.

    Parameters
    ----------
    func
        A function in numba's nopython subset.
    inline
        Inline the function into its callers (small helpers of hot loops).
    borrows
        The function allocates nothing and only borrows the arrays it is given
        (its caller owns them for the whole call): compile it without numba's
        reference counting (``_nrt=False``). Every array argument of a compiled
        call otherwise costs two atomic reference-count updates; per design of
        the impact kernel they took about a quarter of the time. A function
        that allocates (``np.empty``, ``np.linalg``) does not compile this way.

    Returns
    -------
    callable
        Or, without ``func``, the decorator (``@kernel(inline=True)``).
    """
    if func is None:
        return lambda f: kernel(f, inline=inline, borrows=borrows)
    if _NUMBA is None:
        return func
    options: dict[str, Any] = {"inline": "always"} if inline else {}
    if borrows:
        options["_nrt"] = False
    dispatcher = _NUMBA.njit(cache=True, error_model="numpy", nogil=True, **options)(func)
    verify_cache(dispatcher)
    return dispatcher


def say_no_jit(what: str) -> None:
    """Log once that ``what`` runs its numpy path (no compiled kernels), with the reason.

    Parameters
    ----------
    what
        The computation that falls back.
    """
    say_once(
        f"{what}: compiled kernels unavailable ({_REASON}); using the numpy path "
        "(the same results, slower)",
        logging.WARNING,
    )
