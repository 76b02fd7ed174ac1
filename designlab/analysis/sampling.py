"""Design-of-experiments samples: lists, grids, Latin hypercubes, Sobol sequences.

Every function returns a list of ``{name: value}`` dictionaries (plain floats)
in a deterministic order; seeded methods give the same points for the same
seed on every platform.

Examples
--------
>>> grid({"a": [1.0, 2.0], "b": [10.0, 20.0, 30.0]})[:4]
[{'a': 1.0, 'b': 10.0}, {'a': 1.0, 'b': 20.0}, {'a': 1.0, 'b': 30.0}, {'a': 2.0, 'b': 10.0}]
>>> pts = latin_hypercube({"k": (1e4, 6e4), "c": (10.0, 200.0)}, 4, seed=1)
>>> sorted(int((p["k"] - 1e4) // 12500) for p in pts)       # one point per stratum
[0, 1, 2, 3]
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

__all__ = ["grid", "latin_hypercube", "list_points", "saltelli", "sobol_sequence"]

Bounds = Mapping[str, tuple[float, float]]


def list_points(values: Mapping[str, Sequence[float]]) -> list[dict[str, float]]:
    """Point i takes the i-th value of every list (all lists the same length)."""
    lengths = {len(v) for v in values.values()}
    if len(lengths) != 1:
        raise ValueError(f"lists of different lengths: { {k: len(v) for k, v in values.items()} }")
    names = list(values)
    return [
        {k: float(v) for k, v in zip(names, row, strict=True)}
        for row in zip(*values.values(), strict=True)
    ]


def grid(values: Mapping[str, Sequence[float]]) -> list[dict[str, float]]:
    """The Cartesian product of the value lists (last name varies fastest)."""
    names = list(values)
    return [
        {k: float(v) for k, v in zip(names, row, strict=True)}
        for row in itertools.product(*values.values())
    ]


def _scale(unit: NDArray, bounds: Bounds, log: Mapping[str, bool] | None) -> list[dict[str, float]]:
    names = list(bounds)
    cols = []
    for j, name in enumerate(names):
        lo, hi = bounds[name]
        if log and log.get(name):
            cols.append(np.exp(math.log(lo) + unit[:, j] * (math.log(hi) - math.log(lo))))
        else:
            cols.append(lo + unit[:, j] * (hi - lo))
    arr = np.column_stack(cols) if cols else np.empty((unit.shape[0], 0))
    return [{k: float(v) for k, v in zip(names, row, strict=True)} for row in arr]


def latin_hypercube(
    bounds: Bounds, samples: int, *, seed: int = 0, log: Mapping[str, bool] | None = None
) -> list[dict[str, float]]:
    """``samples`` Latin-hypercube points in the box ``bounds`` (scipy.stats.qmc).

    ``log[name]`` samples that parameter uniformly in its logarithm.
    """
    from scipy.stats import qmc

    unit = qmc.LatinHypercube(d=len(bounds), seed=np.random.default_rng(seed)).random(samples)
    return _scale(unit, bounds, log)


def sobol_sequence(
    bounds: Bounds, samples: int, *, seed: int = 0, log: Mapping[str, bool] | None = None
) -> list[dict[str, float]]:
    """``samples`` (a power of two) scrambled Sobol points in the box ``bounds``."""
    from scipy.stats import qmc

    m = round(math.log2(samples))
    if 2**m != samples:
        raise ValueError(f"samples must be a power of two, got {samples}")
    engine = qmc.Sobol(d=len(bounds), scramble=True, seed=np.random.default_rng(seed))
    return _scale(engine.random_base2(m), bounds, log)


def saltelli(bounds: Bounds, samples: int, *, seed: int = 0) -> list[dict[str, float]]:
    """SALib's Saltelli sample for first- and total-order Sobol indices.

    ``samples * (D + 2)`` points (D parameters), in the order
    :func:`SALib.analyze.sobol.analyze` expects.
    """
    from SALib.sample import sobol as sobol_sample

    problem = {
        "num_vars": len(bounds),
        "names": list(bounds),
        "bounds": [list(b) for b in bounds.values()],
    }
    x = sobol_sample.sample(problem, samples, calc_second_order=False, seed=seed)
    names = list(bounds)
    return [{k: float(v) for k, v in zip(names, row, strict=True)} for row in x]
