"""Compiled Latin-hypercube columns (numba; :class:`.sampling.LatinHypercubePoints`).

The keyed permutation (a six-round Feistel network on ``2 half`` bits with
SplitMix64 rounds, cycle-walked into ``[0, n)``) and the in-stratum position of
:class:`~designlab.analysis.sampling.LatinHypercubePoints`, one point at a time:
the same integer and floating-point operations as its numpy path, so the same
points bit for bit, without the numpy path's temporaries and repeated
cycle-walking passes over masked subsets (which cost more than the impact
kernel on the points they produce).

Examples
--------
>>> import numpy as np
>>> out = np.empty(4)
>>> keys = np.arange(1, 8, dtype=np.uint64)
>>> lhs_column(0, keys, np.uint64(1), np.uint64(1), 4, out)
>>> sorted(np.floor(out * 4).astype(int).tolist())       # one point per stratum
[0, 1, 2, 3]
"""

from __future__ import annotations

import numpy as np

from designlab.sx.jit import AVAILABLE, kernel

__all__ = ["AVAILABLE", "lhs_column", "mix"]

_M1, _M2 = np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB)
_S30, _S27, _S31, _S11 = np.uint64(30), np.uint64(27), np.uint64(31), np.uint64(11)


@kernel(inline=True)
def mix(x):  # type: ignore[no-untyped-def]
    """SplitMix64's finaliser of one ``uint64`` (wrapping products)."""
    x = (x ^ (x >> _S30)) * _M1
    x = (x ^ (x >> _S27)) * _M2
    return x ^ (x >> _S31)


@kernel(inline=True)
def _feistel(x, keys, rounds, half, mask):  # type: ignore[no-untyped-def]
    left = x >> half
    right = x & mask
    for k in range(rounds):
        left, right = right, left ^ (mix(right ^ keys[k]) & mask)
    return (left << half) | right


@kernel
def lhs_column(start, keys, half, mask, n, out):  # type: ignore[no-untyped-def]
    """Unit-cube coordinates of points ``start .. start + len(out) - 1`` in one dimension.

    ``keys``: the dimension's Feistel round keys then its position key (uint64);
    ``half``, ``mask``: half the permutation's bits and ``2^half - 1``; ``n``: samples.
    """
    rounds = keys.shape[0] - 1
    bound = np.uint64(n)
    scale = 2.0**-53
    for j in range(out.shape[0]):
        i = np.uint64(start + j)
        x = _feistel(i, keys, rounds, half, mask)
        while x >= bound:  # cycle walking: a bijection of [0, 2^bits) restricted to [0, n)
            x = _feistel(x, keys, rounds, half, mask)
        u = float(mix(mix(i ^ keys[rounds])) >> _S11) * scale
        out[j] = (float(x) + u) / n
