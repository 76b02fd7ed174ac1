"""Randomised human walks for the robust gain optimisation (Zeng 2011, App. C; moved from
:mod:`designlab.navigation.tuning`, which still exports it).

Examples
--------
>>> from designlab.navigation import configuration
>>> len(RandomWalks(n=3).expand(configuration(2)))
3
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from designlab.errors import InvalidParameterError
from designlab.navigation.scenarios import Disc, Scenario, Walk
from designlab.params import ARG, declared, param

__all__ = ["RandomWalks"]


@declared
@dataclass(frozen=True)
class RandomWalks:
    """Randomised human walks for the robust mode.

    Every obstacle that walks (a :class:`~designlab.navigation.Walk`) is replaced by
    ``n`` walks with the cruise speed, the start time and a lateral offset (normal
    to the walking direction) drawn uniformly from the given ranges with ``seed``.
    Scenarios without a walking obstacle are left as they are.

    Examples
    --------
    >>> from designlab.navigation import configuration
    >>> walks = RandomWalks(n=3, seed=0).expand(configuration(2))
    >>> len(walks), sorted({round(s.obstacles[0].motion.speed, 2) for s in walks}) != [1.0]
    (3, True)
    >>> len(RandomWalks(n=3).expand(configuration(1)))
    1
    """

    n: int = param(doc="walks per scenario", kind="integer", ge=1, le=64, default=8)
    speed: tuple[float, float] = param(
        unit="m/s", doc="range (low, high) of the cruise speed, low > 0", kind="object",
        default=(0.8, 1.2),
    )  # fmt: skip
    start_time: tuple[float, float] = param(
        unit="s", doc="range of the time the walk starts, low >= 0", kind="object",
        default=(0.0, 0.5),
    )  # fmt: skip
    lateral_offset: tuple[float, float] = param(
        unit="m", doc="range of the offset of the whole walk to the left of its direction",
        kind="object", default=(-0.1, 0.1),
    )  # fmt: skip
    seed: int = ARG.seed.field(doc="seed of the draws")

    def __post_init__(self) -> None:
        for name, unit, lo_min in (
            ("speed", "m/s", 1e-9),
            ("start_time", "s", 0.0),
            ("lateral_offset", "m", -math.inf),
        ):
            rng = getattr(self, name)
            try:
                lo, hi = (float(v) for v in rng)
            except (TypeError, ValueError):
                raise InvalidParameterError(
                    f"RandomWalks.{name}", rng, "must be a pair (low, high)", unit
                ) from None
            if not (math.isfinite(lo) and math.isfinite(hi) and lo <= hi and lo >= lo_min):
                raise InvalidParameterError(
                    f"RandomWalks.{name}",
                    rng,
                    f"must be finite with low <= high{' and low > 0' if lo_min > 0 else ''}"
                    f"{' and low >= 0' if lo_min == 0 else ''}",
                    unit,
                )
            object.__setattr__(self, name, (lo, hi))

    def expand(self, scenario: Scenario) -> list[Scenario]:
        """The scenario with its walks randomised (``[scenario]`` if nothing walks)."""
        walking = [
            i
            for i, o in enumerate(scenario.obstacles)
            if isinstance(o, Disc) and isinstance(o.motion, Walk)
        ]
        if not walking:
            return [scenario]
        rng = np.random.default_rng(self.seed)
        out = []
        for k in range(self.n):
            obs = list(scenario.obstacles)
            for i in walking:
                o = obs[i]
                assert isinstance(o, Disc) and isinstance(o.motion, Walk)
                w = o.motion
                speed = rng.uniform(*self.speed)
                t0 = rng.uniform(*self.start_time)
                off = rng.uniform(*self.lateral_offset)
                d = np.subtract(w.end, w.start) / w.length
                n = np.array([-d[1], d[0]]) * off
                ramp = min(w.ramp_time, w.length / speed)
                walk = Walk(
                    tuple(np.add(w.start, n)),
                    tuple(np.add(w.end, n)),
                    speed=speed,
                    ramp_time=ramp,
                    start_time=t0,
                )
                obs[i] = replace(o, motion=walk)
            out.append(scenario.replace(obstacles=tuple(obs), name=f"{scenario.name}_walk{k}"))
        return out
