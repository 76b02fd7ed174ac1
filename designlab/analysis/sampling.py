"""Design-of-experiments samples: lists, grids, Latin hypercubes, Sobol sequences.

A grid, a Latin hypercube and a Sobol sequence are
:class:`~designlab.analysis.points.PointSource` objects: they produce any range
of their points on demand, as point *columns* ``{name: 1-D float array}`` in a
deterministic order, so a million-point sweep never holds its sample
(``.columns()`` gives them all). Seeded methods give the same points for the
same seed on every platform, however the points are split into chunks.

Examples
--------
>>> g = GridPoints({"a": [1.0, 2.0], "b": [10.0, 20.0, 30.0]}).columns()
>>> g["a"].tolist(), g["b"].tolist()
([1.0, 1.0, 1.0, 2.0, 2.0, 2.0], [10.0, 20.0, 30.0, 10.0, 20.0, 30.0])
>>> pts = LatinHypercubePoints({"k": (1e4, 6e4), "c": (10.0, 200.0)}, 4, seed=1).columns()
>>> sorted(((pts["k"] - 1e4) // 12500).astype(int).tolist())     # one point per stratum
[0, 1, 2, 3]
>>> lhs = LatinHypercubePoints({"k": (1e4, 6e4)}, 1_000_000, seed=1)
>>> bool((lhs.take(500_000, 500_004)["k"] == lhs.columns()["k"][500_000:500_004]).all())
True
"""

from __future__ import annotations

import math
import warnings
from abc import abstractmethod
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from designlab.analysis.points import PointSource, source_identity
from designlab.errors import InvalidParameterError
from designlab.params import ARG

__all__ = [
    "MAX_SALTELLI_SAMPLES",
    "GridPoints",
    "LatinHypercubePoints",
    "SobolPoints",
    "list_points",
    "saltelli",
]

Bounds = Mapping[str, tuple[float, float]]
Columns = dict[str, NDArray[np.float64]]

#: The largest Saltelli base sample N: SALib's Sobol analysis bootstraps 100 resamples of
#: N values in several arrays at once (about 4 kB per unit of N per metric), so N = 2**20
#: needs over 4 GB where 2**16 needs about 300 MB.
MAX_SALTELLI_SAMPLES = 1 << 16


def list_points(values: Mapping[str, Sequence[float]]) -> Columns:
    """Point i takes the i-th value of every list (all lists the same length).

    Parameters
    ----------
    values
        Name -> list of values.
    """
    lengths = {len(v) for v in values.values()}
    if len(lengths) > 1:
        raise ValueError(f"lists of different lengths: { {k: len(v) for k, v in values.items()} }")
    return {k: np.asarray(v, dtype=float) for k, v in values.items()}


class GridPoints(PointSource):
    """The Cartesian product of value lists (last name varies fastest), point by index.

    Parameters
    ----------
    values
        Name -> list of values.
    """

    def __init__(self, values: Mapping[str, Sequence[float]]) -> None:
        self.names = tuple(values)
        self._axes = [np.asarray(values[k], dtype=float).ravel() for k in self.names]
        self._shape = tuple(a.size for a in self._axes)

    def __len__(self) -> int:
        return math.prod(self._shape) if self._shape else 0

    def identity(self) -> str:
        """A hash of the axes' names and values.

        See :meth:`~designlab.analysis.points.PointSource.identity`.
        """
        axes = {f"axis {k}": a for k, a in zip(self.names, self._axes, strict=True)}
        return source_identity(self, {"names": list(self.names), **axes})

    def _take(self, start: int, stop: int) -> Columns:
        idx = np.unravel_index(np.arange(start, stop), self._shape)
        return {k: a[i] for k, a, i in zip(self.names, self._axes, idx, strict=True)}


class _Box(PointSource):
    """Points of the unit cube scaled to a box (uniform or logarithmic per name)."""

    def __init__(self, bounds: Bounds, samples: int, log: Mapping[str, bool] | None) -> None:
        self.names = tuple(bounds)
        self._bounds = {k: (float(lo), float(hi)) for k, (lo, hi) in bounds.items()}
        self._log = {k: bool(log and log.get(k)) for k in self.names}
        self._n = int(samples)

    def __len__(self) -> int:
        return self._n

    def _fields(self) -> dict[str, object]:
        """What determines the points besides the class: names, bounds, scales, count."""
        return {"names": list(self.names), "bounds": self._bounds, "log": self._log, "n": self._n}

    @abstractmethod
    def _unit(self, start: int, stop: int) -> NDArray[np.float64]:
        """Points ``start .. stop - 1`` of the unit cube, shape ``(stop - start, d)``."""

    def _take(self, start: int, stop: int) -> Columns:
        unit = self._unit(start, stop)
        out: Columns = {}
        for j, name in enumerate(self.names):
            lo, hi = self._bounds[name]
            if self._log[name]:
                out[name] = np.exp(math.log(lo) + unit[:, j] * (math.log(hi) - math.log(lo)))
            else:
                out[name] = lo + unit[:, j] * (hi - lo)
        return out


#: Latin-hypercube ranges of at least this many points use the compiled kernel; smaller ones
#: (a resumed run's check of a few points) the numpy path, which gives the same points and
#: spares a process numba's start-up (about 0.6 CPU s on the first compiled call).
COMPILED_FROM = 64

_M1, _M2 = np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB)
_FEISTEL_ROUNDS = 6


def _mix(x: NDArray[np.uint64]) -> NDArray[np.uint64]:
    """SplitMix64's finaliser: a bijective 64-bit mix (Steele, Lea and Flood 2014)."""
    with np.errstate(over="ignore"):
        x = (x ^ (x >> np.uint64(30))) * _M1
        x = (x ^ (x >> np.uint64(27))) * _M2
    return x ^ (x >> np.uint64(31))


class LatinHypercubePoints(_Box):
    """A seeded Latin hypercube whose points are computed from their index.

    In each dimension point i falls in stratum pi(i) of ``samples`` equal
    strata, at a uniform position inside it: pi is a keyed pseudo-random
    permutation of ``0 .. samples - 1`` (a six-round Feistel network on the
    next even power of two, cycle-walked into range; Black and Rogaway 2002)
    and the position a counter-based uniform (SplitMix64 of the index and a
    key). Both come from the seed through :class:`numpy.random.SeedSequence`,
    so any chunk of points is computed on its own, in memory proportional to
    the chunk, and equals the same rows of the whole sample.

    Parameters
    ----------
    bounds
        Name -> (low, high).
    samples
        Number of points.
    seed
        Seed of the sample.
    log
        ``log[name]`` samples that parameter uniformly in its logarithm.
    """

    code_modules = ("designlab.analysis.lhs_kernel",)

    def __init__(
        self,
        bounds: Bounds,
        samples: int,
        *,
        seed: int = ARG.seed.default,
        log: Mapping[str, bool] | None = None,
    ) -> None:
        super().__init__(bounds, samples, log)
        self._seed = int(seed)
        d = len(self.names)
        keys = np.random.SeedSequence(int(seed)).generate_state(d * (_FEISTEL_ROUNDS + 1), "u8")
        self._keys = keys.reshape(d, _FEISTEL_ROUNDS + 1)
        bits = max(2, math.ceil(math.log2(max(self._n, 2))))
        self._half = np.uint64((bits + 1) // 2)
        self._mask = np.uint64((1 << int(self._half)) - 1)

    def identity(self) -> str:
        """A hash of the box, the sample count and the seed.

        See :meth:`~designlab.analysis.points.PointSource.identity`.
        """
        return source_identity(self, {**self._fields(), "seed": self._seed})

    def _feistel(self, x: NDArray[np.uint64], keys: NDArray[np.uint64]) -> NDArray[np.uint64]:
        left, right = x >> self._half, x & self._mask
        for key in keys:
            left, right = right, left ^ (_mix(right ^ key) & self._mask)
        return (left << self._half) | right

    def _permute(self, i: NDArray[np.uint64], keys: NDArray[np.uint64]) -> NDArray[np.uint64]:
        x = self._feistel(i, keys)
        out = x >= np.uint64(self._n)
        while out.any():  # cycle walking: a bijection of [0, 2^bits) restricted to [0, n)
            x[out] = self._feistel(x[out], keys)
            out[out] = x[out] >= np.uint64(self._n)
        return x

    def _unit(self, start: int, stop: int) -> NDArray[np.float64]:
        if stop - start >= COMPILED_FROM:  # the same points, bit for bit
            # numba imported here, not with the module: a resumed run draws a few points
            from designlab.analysis import lhs_kernel

            if lhs_kernel.AVAILABLE:
                cols = np.empty((len(self.names), stop - start))
                for j, keys in enumerate(self._keys):
                    lhs_kernel.lhs_column(start, keys, self._half, self._mask, self._n, cols[j])
                return cols.T
        i = np.arange(start, stop, dtype=np.uint64)
        unit = np.empty((i.size, len(self.names)))
        for j, keys in enumerate(self._keys):
            stratum = self._permute(i, keys[:-1]).astype(float)
            u = (_mix(_mix(i ^ keys[-1])) >> np.uint64(11)).astype(float) * 2.0**-53
            unit[:, j] = (stratum + u) / self._n
        return unit


class SobolPoints(_Box):
    """``samples`` (a power of two) scrambled Sobol points (scipy.stats.qmc), by range.

    A range is drawn by fast-forwarding the seeded engine to its first point,
    so any chunk equals the same rows of the whole sequence.

    Parameters
    ----------
    bounds
        Name -> (low, high).
    samples
        Number of points, a power of two.
    seed
        Seed of the scrambling.
    log
        ``log[name]`` samples that parameter uniformly in its logarithm.
    """

    def __init__(
        self,
        bounds: Bounds,
        samples: int,
        *,
        seed: int = ARG.seed.default,
        log: Mapping[str, bool] | None = None,
    ) -> None:
        from scipy.stats import qmc

        m = round(math.log2(samples)) if samples > 0 else -1
        if m < 0 or 2**m != samples:
            raise ValueError(f"samples must be a power of two, got {samples}")
        super().__init__(bounds, samples, log)
        self._seed = int(seed)
        self._engine = qmc.Sobol(d=len(self.names), scramble=True, rng=np.random.default_rng(seed))

    def identity(self) -> str:
        """A hash of the box, the count, the seed and scipy's version (its scrambling)."""
        import scipy

        return source_identity(
            self, {**self._fields(), "seed": self._seed, "scipy": scipy.__version__}
        )

    def _unit(self, start: int, stop: int) -> NDArray[np.float64]:
        self._engine.reset()
        if start:  # scipy cannot fast-forward by zero points
            self._engine.fast_forward(start)
        with warnings.catch_warnings():  # a chunk is not a power of two: the whole sample is
            warnings.simplefilter("ignore", UserWarning)
            return self._engine.random(stop - start)


def saltelli(bounds: Bounds, samples: int, *, seed: int = ARG.seed.default) -> Columns:
    """SALib's Saltelli sample for first- and total-order Sobol indices.

    ``samples * (D + 2)`` points (D parameters), in the order
    :func:`SALib.analyze.sobol.analyze` expects.

    Parameters
    ----------
    bounds
        Name -> (low, high).
    samples
        Base sample size N (a power of two, at most :data:`MAX_SALTELLI_SAMPLES`).
    seed
        Seed of the sample.

    Examples
    --------
    >>> saltelli({"a": (0, 1), "b": (0, 1)}, 2**17)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: samples = 131072 is not allowed: must be a power
    of two from 2 to 65536 ...
    """
    from SALib.sample import sobol as sobol_sample

    n = samples if isinstance(samples, int | np.integer) and not isinstance(samples, bool) else 0
    if not (2 <= n <= MAX_SALTELLI_SAMPLES and n & (n - 1) == 0):
        raise InvalidParameterError(
            "samples", samples, f"must be a power of two from 2 to {MAX_SALTELLI_SAMPLES} (the "
            "Sobol analysis holds 100 bootstrap resamples of N values)",
        )  # fmt: skip

    problem = {
        "num_vars": len(bounds),
        "names": list(bounds),
        "bounds": [list(b) for b in bounds.values()],
    }
    x = sobol_sample.sample(problem, samples, calc_second_order=False, seed=seed)
    return {k: np.ascontiguousarray(x[:, j]) for j, k in enumerate(bounds)}
