"""Batches on every core: blocks of rows in threads (the compiled kernels release the GIL).

The compiled kernels (:mod:`designlab.sx.jit`, ``nogil=True``) compute each design on
its own, so a batch cut into contiguous blocks and evaluated in threads gives, row for
row, the bits of the single-threaded call, provided each cut falls on a multiple of the
kernel's lane width (designs computed side by side, :data:`designlab.impact.kernel_poles.LANES`).
:func:`map_row_blocks` does that; :data:`WORKERS` declares the ``workers=`` argument of
every caller (``None``: every core this process may run on).

Examples
--------
>>> import numpy as np
>>> rows = np.arange(10.0).reshape(5, 2)
>>> map_row_blocks(lambda b: (b.sum(axis=1), b[:, 0] > 3), rows, workers=2, grain=2)
[array([ 1.,  5.,  9., 13., 17.]), array([False, False,  True,  True,  True])]
>>> WORKERS.check(0)
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: workers = 0 is not allowed: must be an integer >= 1 ...
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from numpy.typing import NDArray

from designlab.params import Param

__all__ = ["DEFAULT_GRAIN", "WORKERS", "core_count", "map_row_blocks", "thread_count"]

#: The ``workers=`` argument of the batch evaluators: threads that share a batch.
WORKERS = Param(
    None, "", "threads that evaluate a batch, each on a contiguous block of its rows",
    kind="integer", ge=1, le=1024, optional=True,
    none="every core this process may run on (os.sched_getaffinity)", name="workers",
)  # fmt: skip

#: Fewest rows a thread is given: below, a thread's start (tens of microseconds) would
#: cost more than the rows (about 1.5 us each through the impact kernel).
DEFAULT_GRAIN = 2048


def core_count() -> int:
    """The cores this process may run on (its affinity mask; ``os.cpu_count()`` elsewhere).

    Returns
    -------
    int

    Examples
    --------
    >>> core_count() >= 1
    True
    """
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def thread_count(workers: int | None, rows: int, grain: int = DEFAULT_GRAIN) -> int:
    """Threads for ``rows`` rows: ``workers`` (checked; ``None``: every core), at most one
    per ``grain`` rows.

    Parameters
    ----------
    workers
        :data:`WORKERS`.
    rows
        The batch's rows.
    grain
        Fewest rows per thread.

    Returns
    -------
    int

    Examples
    --------
    >>> thread_count(4, 10_000, grain=2048), thread_count(4, 100), thread_count(1, 10**6)
    (4, 1, 1)
    """
    wanted = core_count() if workers is None else WORKERS.check(workers)
    return max(1, min(int(wanted), rows // max(grain, 1)))


def map_row_blocks(
    fn: Callable[[NDArray], Sequence[NDArray]],
    rows: NDArray,
    *,
    workers: int | None = None,
    grain: int = DEFAULT_GRAIN,
    align: int = 16,
) -> list[NDArray]:
    """``fn(rows)`` computed block by block in threads, its outputs joined in row order.

    Parameters
    ----------
    fn
        Takes a block of rows and returns a sequence of arrays, each with one entry
        (first axis) per row; it must release the GIL to run in parallel (a compiled
        kernel) and compute every row on its own.
    rows
        The batch, rows along the first axis.
    workers
        :data:`WORKERS`.
    grain
        Fewest rows per thread (:data:`DEFAULT_GRAIN`).
    align
        Every block but the last starts at a multiple of this (the kernel's lanes),
        so that each row is computed with the same neighbours as in one call.

    Returns
    -------
    list of ndarray
        ``fn``'s outputs over the whole batch: equal, bit for bit, to ``fn(rows)``
        for a row-wise ``fn``.
    """
    n = rows.shape[0]
    threads = thread_count(workers, n, grain)
    if threads == 1:
        return list(fn(rows))
    size = math.ceil(n / threads / align) * align
    cuts = list(range(0, n, size))
    with ThreadPoolExecutor(max_workers=len(cuts), thread_name_prefix="designlab") as pool:
        parts = list(pool.map(fn, [rows[a : a + size] for a in cuts]))
    return [np.concatenate([p[k] for p in parts]) for k in range(len(parts[0]))]
