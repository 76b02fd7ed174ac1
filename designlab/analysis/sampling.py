"""Design-of-experiments samples: lists, grids, Latin hypercubes, Sobol sequences.

Every function returns point *columns*: ``{name: 1-D float array}``, one entry
per point, in a deterministic order; seeded methods give the same points for the
same seed on every platform. Columns scale to millions of points (no Python
object per point).

Examples
--------
>>> g = grid({"a": [1.0, 2.0], "b": [10.0, 20.0, 30.0]})
>>> g["a"].tolist(), g["b"].tolist()
([1.0, 1.0, 1.0, 2.0, 2.0, 2.0], [10.0, 20.0, 30.0, 10.0, 20.0, 30.0])
>>> pts = latin_hypercube({"k": (1e4, 6e4), "c": (10.0, 200.0)}, 4, seed=1)
>>> sorted(((pts["k"] - 1e4) // 12500).astype(int).tolist())     # one point per stratum
[0, 1, 2, 3]
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

__all__ = ["grid", "latin_hypercube", "list_points", "saltelli", "sobol_sequence"]

Bounds = Mapping[str, tuple[float, float]]
Columns = dict[str, NDArray[np.float64]]


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


def grid(values: Mapping[str, Sequence[float]]) -> Columns:
    """The Cartesian product of the value lists (last name varies fastest).

    Parameters
    ----------
    values
        Name -> list of values.
    """
    names = list(values)
    if not names:
        return {}
    mesh = np.meshgrid(*[np.asarray(values[k], dtype=float) for k in names], indexing="ij")
    return {k: m.ravel() for k, m in zip(names, mesh, strict=True)}


def _scale(unit: NDArray, bounds: Bounds, log: Mapping[str, bool] | None) -> Columns:
    out: Columns = {}
    for j, name in enumerate(bounds):
        lo, hi = bounds[name]
        if log and log.get(name):
            out[name] = np.exp(math.log(lo) + unit[:, j] * (math.log(hi) - math.log(lo)))
        else:
            out[name] = lo + unit[:, j] * (hi - lo)
    return out


def latin_hypercube(
    bounds: Bounds, samples: int, *, seed: int = 0, log: Mapping[str, bool] | None = None
) -> Columns:
    """``samples`` Latin-hypercube points in the box ``bounds`` (scipy.stats.qmc).

    Parameters
    ----------
    bounds
        Name -> (low, high).
    samples
        Number of points.
    seed
        Seed of the generator.
    log
        ``log[name]`` samples that parameter uniformly in its logarithm.
    """
    from scipy.stats import qmc

    unit = qmc.LatinHypercube(d=len(bounds), rng=np.random.default_rng(seed)).random(samples)
    return _scale(unit, bounds, log)


def sobol_sequence(
    bounds: Bounds, samples: int, *, seed: int = 0, log: Mapping[str, bool] | None = None
) -> Columns:
    """``samples`` (a power of two) scrambled Sobol points in the box ``bounds``.

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
    from scipy.stats import qmc

    m = round(math.log2(samples))
    if 2**m != samples:
        raise ValueError(f"samples must be a power of two, got {samples}")
    engine = qmc.Sobol(d=len(bounds), scramble=True, rng=np.random.default_rng(seed))
    return _scale(engine.random_base2(m), bounds, log)


def saltelli(bounds: Bounds, samples: int, *, seed: int = 0) -> Columns:
    """SALib's Saltelli sample for first- and total-order Sobol indices.

    ``samples * (D + 2)`` points (D parameters), in the order
    :func:`SALib.analyze.sobol.analyze` expects.

    Parameters
    ----------
    bounds
        Name -> (low, high).
    samples
        Base sample size N (a power of two).
    seed
        Seed of the sample.
    """
    from SALib.sample import sobol as sobol_sample

    problem = {
        "num_vars": len(bounds),
        "names": list(bounds),
        "bounds": [list(b) for b in bounds.values()],
    }
    x = sobol_sample.sample(problem, samples, calc_second_order=False, seed=seed)
    return {k: np.ascontiguousarray(x[:, j]) for j, k in enumerate(bounds)}
