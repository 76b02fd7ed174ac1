"""Compile ahead what designlab compiles on first use (``designlab compile``).

The numeric kernels (numba) and the navigation step (C) are compiled the first time a
process needs them and cached on disk (:mod:`designlab.sx.cache`); a fresh
installation therefore pays the compilation in its first call. :func:`compile_all`
pays it at a time of the user's choosing (after installing, or in an image build):
each step runs the smallest call that compiles its code, and says what it compiles,
why, and how long it took (a step whose code is in the cache only loads it).

The crowd layer's bookkeeping kernels are not compiled ahead (they need a JuPedSim
crowd); the first crowd run compiles them.

Examples
--------
>>> [name for name, _, _ in STEPS]
['impact', 'sampling', 'navigation']
"""

from __future__ import annotations

import time
from collections.abc import Callable

__all__ = ["STEPS", "compile_all"]


def _impact() -> None:
    import numpy as np

    import designlab as dl
    from designlab.impact.metrics import metrics_of_matrix

    p8 = np.array([[9.6, 250.0, 20e3, 24.25e3, 71.9, 4.4, 46.0, 3e3]])
    metrics_of_matrix(p8, 1.25)
    metrics_of_matrix(p8, 1.25, constrained=True)
    p10 = np.array([[9.6, 10.0, 5e5, 24.25e3, 71.9, 4.4, 46.0, 3e3, 251.0, 20e3]])
    metrics_of_matrix(p10, 1.25)
    robot = dl.impact.ContactDynamics(mass=9.6, stiffness=20e3, damping=250.0)
    foam = dl.impact.Foam(stiffness=24.25e3, damping=71.9, linear_depth=0.02)
    head = dl.impact.HeadNeck(mass=4.4, stiffness=4e3, damping=0.0)
    dl.impact.simulate(robot, foam, head, impact_velocity=1.25)
    from designlab.impact.passfail import head_acceleration_exceeds
    from designlab.impact.single import impact_metrics_one

    impact_metrics_one(p8[0].tolist(), 1.25)  # the scalar fast path (its own compiled entry)
    head_acceleration_exceeds(p8, 1.25, 10.0)  # the pass/fail path


def _sampling() -> None:
    from designlab.analysis.sampling import COMPILED_FROM, LatinHypercubePoints

    box = {"a": (0.0, 1.0), "b": (1.0, 2.0)}
    LatinHypercubePoints(box, COMPILED_FROM, seed=1).columns()  # the compiled path


def _navigation() -> None:
    import numpy as np

    import designlab as dl
    from designlab.navigation import engine

    nav = dl.navigation
    gains = nav.OPTIMAL_GAINS.as_array()[None, :] * np.ones((1, 1))
    for k in (1, 2, 3, 4):
        engine.run(nav.configuration(k), gains, stabilising=False, jit=True)


#: ``(name, what is compiled and why, the call that compiles it)``, in order.
STEPS: tuple[tuple[str, str, Callable[[], None]], ...] = (
    (
        "impact",
        "the impact kernels (impact_metrics and its scalar path, the full joint, simulate, "
        "pass/fail; numba)",
        _impact,
    ),
    ("sampling", "the Latin hypercube sampler of sweeps (numba)", _sampling),
    ("navigation", "the navigation step of configurations 1-4 (C, 4 members a pass)", _navigation),
)


def compile_all(
    names: tuple[str, ...] | None = None, say: Callable[[str], None] = print
) -> dict[str, float]:
    """Compile (or load from the cache) every step of :data:`STEPS`, or those in ``names``.

    Parameters
    ----------
    names
        The steps to run (default: all).
    say
        Called with one progress line before and after each step.

    Returns
    -------
    dict
        Wall seconds of each step.

    Raises
    ------
    ValueError
        An unknown step name.
    """
    from designlab.sx.cache import cache_dir

    known = [name for name, _, _ in STEPS]
    unknown = sorted(set(names or ()) - set(known))
    if unknown:
        raise ValueError(f"unknown compile step(s) {unknown}: known are {known}")
    took: dict[str, float] = {}
    for name, what, step in STEPS:
        if names and name not in names:
            continue
        say(
            f"compiling {what}: compiled on first use, so done now once for every later "
            f"process (cached in {cache_dir()}; loaded if already there)..."
        )
        wall, cpu = time.perf_counter(), time.process_time()
        step()
        took[name] = time.perf_counter() - wall
        say(f"  {name}: {took[name]:.1f} s ({time.process_time() - cpu:.1f} CPU s)")
    return took
