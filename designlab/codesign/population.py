"""The random inputs of an injury probability: head-neck populations, closing speeds, impact points.

* :class:`HeadPopulation` -- the head mass, neck stiffness and neck damping, each a
  number or any scipy frozen distribution (independent); by default uniform over the
  thesis's ranges (Zeng 2011, Sec. 3.5). A distribution whose support leaves the
  parameter's declared range (a normal mass reaches non-positive masses) is refused:
  use a truncated one (``scipy.stats.truncnorm``).
* :class:`ClosingSpeeds` -- the closing speed v_c at contact: a scipy frozen
  distribution or samples (for instance from navigation runs). The injury probability
  is conditional on a contact, so the part of the distribution at ``v_c <= 0`` (no
  impact, docs/impact.md, "Impact velocity") is left out and its share reported.
* :func:`lever_sampler` -- impact points along a link (:class:`~designlab.impact.LinkImpact`).

Examples
--------
>>> import numpy as np
>>> from scipy import stats
>>> pop = HeadPopulation.uniform()
>>> pop.sample(2, np.random.default_rng(0)).shape
(2, 3)
>>> HeadPopulation(mass=stats.norm(4.8, 0.3), stiffness=4e3, damping=80.0)
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: HeadPopulation.mass = ... reaches outside ...
>>> v = ClosingSpeeds.of(stats.uniform(-1.0, 3.0))   # v_c uniform on [-1, 2] m/s
>>> round(v.contact_fraction, 3), round(float(v.sf(np.array([1.0]))[0]), 3)
(0.667, 0.5)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import stats

from designlab.errors import InvalidParameterError
from designlab.impact import THESIS_HEAD_RANGE, HeadNeck, HeadRange, LinkImpact
from designlab.params import Param, params_of
from designlab.validation import real_array

__all__ = ["ClosingSpeeds", "HeadPopulation", "is_distribution", "lever_sampler"]

_HEAD = params_of(HeadNeck)
_LINK = params_of(LinkImpact)


def is_distribution(value: object) -> bool:
    """Whether ``value`` looks like a scipy frozen distribution (``rvs``, ``sf``, ``support``).

    Parameters
    ----------
    value
        Any object.

    Returns
    -------
    bool
    """
    return all(hasattr(value, a) for a in ("rvs", "sf", "isf", "support"))


def _check_support(decl: Param, dist: Any, name: str, lo_ok: float | None = None,
                   hi_ok: float | None = None) -> None:  # fmt: skip
    """Refuse a distribution whose support reaches outside the declared range."""
    lo, hi = (float(x) for x in dist.support())
    inside = decl.within(lo) and decl.within(hi)
    if lo_ok is not None and hi_ok is not None:
        inside = inside and lo_ok <= lo and hi <= hi_ok
    if not inside:
        rng = decl.allowed() if lo_ok is None else f">= {lo_ok:g} and <= {hi_ok:g}"
        raise InvalidParameterError(
            name,
            f"a distribution with support [{lo:g}, {hi:g}]",
            f"reaches outside the allowed range {rng} {decl.unit} (a normal distribution "
            "reaches non-positive values: use a truncated one, e.g. scipy.stats.truncnorm)",
        )


def _entry(decl: Param, value: Any, name: str) -> Any:
    """A number checked against ``decl``, or a distribution whose support is inside it."""
    if is_distribution(value):
        _check_support(decl, value, name)
        return value
    return decl.check(value, name)


@dataclass(frozen=True)
class HeadPopulation:
    """Independent distributions of the head-neck parameters (a number fixes one).

    Attributes
    ----------
    mass
        M_h, kg: a number or a scipy frozen distribution with support in (0, 1000].
    stiffness
        K_h, N/m: a number or a distribution with support in [0, 1e9].
    damping
        C_h, N s/m: a number or a distribution with support in [0, 1e7].
    """

    mass: Any
    stiffness: Any
    damping: Any

    def __post_init__(self) -> None:
        for name in ("mass", "stiffness", "damping"):
            value = _entry(_HEAD[name], getattr(self, name), f"HeadPopulation.{name}")
            object.__setattr__(self, name, value)

    @classmethod
    def uniform(cls, head_range: HeadRange = THESIS_HEAD_RANGE) -> HeadPopulation:
        """Uniform over a head-neck range (default: the thesis's ranges, Sec. 3.5).

        Parameters
        ----------
        head_range
            The ranges.

        Returns
        -------
        HeadPopulation
        """
        if not isinstance(head_range, HeadRange):
            raise InvalidParameterError("heads", head_range, "must be a HeadRange")

        def one(pair: tuple[float, float]) -> Any:
            lo, hi = pair
            return lo if hi == lo else stats.uniform(lo, hi - lo)

        return cls(one(head_range.mass), one(head_range.stiffness), one(head_range.damping))

    @classmethod
    def fixed(cls, head: HeadNeck) -> HeadPopulation:
        """One head-neck set.

        Parameters
        ----------
        head
            The set.

        Returns
        -------
        HeadPopulation
        """
        return cls(head.mass, head.stiffness, head.damping)

    @classmethod
    def of(cls, heads: object) -> HeadPopulation:
        """A population from ``None`` (the thesis's ranges), a HeadRange, a HeadNeck or itself.

        Parameters
        ----------
        heads
            What the user gave.

        Returns
        -------
        HeadPopulation
        """
        if heads is None:
            return cls.uniform()
        if isinstance(heads, HeadPopulation):
            return heads
        if isinstance(heads, HeadRange):
            return cls.uniform(heads)
        if isinstance(heads, HeadNeck):
            return cls.fixed(heads)
        raise InvalidParameterError(
            "heads", heads, "must be None, a HeadPopulation, a HeadRange or a HeadNeck"
        )

    def sample(self, n: int, rng: np.random.Generator) -> NDArray[np.float64]:
        """``(n, 3)`` samples ``[M_h, C_h, K_h]`` (the impact model's column order).

        Parameters
        ----------
        n
            Number of samples.
        rng
            The random generator.

        Returns
        -------
        numpy.ndarray
        """
        cols = [_draw(getattr(self, name), n, rng) for name in ("mass", "damping", "stiffness")]
        return np.column_stack(cols)

    @property
    def dimension(self) -> int:
        """How many parameters are random (a distribution, not a number)."""
        return sum(is_distribution(getattr(self, n)) for n in ("mass", "damping", "stiffness"))

    def from_normal(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """``(n, 3)`` heads ``[M_h, C_h, K_h]`` from ``(n, dimension)`` standard normals.

        Each random parameter is ``isf(Phi(-u))`` of its distribution (the Rosenblatt
        transform of independent parameters, exact in the upper tail); a fixed one keeps
        its number. Used by subset simulation (:mod:`designlab.codesign.subset`).

        Parameters
        ----------
        u
            Standard normal coordinates, one column per random parameter (in the order
            mass, damping, stiffness).

        Returns
        -------
        numpy.ndarray
        """
        cols, j = [], 0
        for name in ("mass", "damping", "stiffness"):
            entry = getattr(self, name)
            if is_distribution(entry):
                cols.append(np.asarray(entry.isf(stats.norm.sf(u[:, j])), dtype=float))
                j += 1
            else:
                cols.append(np.full(u.shape[0], float(entry)))
        return np.column_stack(cols)


def _draw(entry: Any, n: int, rng: np.random.Generator) -> NDArray[np.float64]:
    if is_distribution(entry):
        return np.asarray(entry.rvs(size=n, random_state=rng), dtype=float).reshape(n)
    return np.full(n, float(entry))


@dataclass(frozen=True)
class ClosingSpeeds:
    """The closing speed at contact: a distribution or samples, conditioned on ``v_c > 0``.

    Build it with :meth:`of`. ``sample`` draws from the conditional distribution
    (``v = isf(u)``, ``u`` uniform on ``(0, P(v_c > 0))``, exact in the upper tail);
    ``sf`` is ``P(v_c > v | v_c > 0)``.

    Attributes
    ----------
    dist
        The scipy frozen distribution, or ``None`` for samples.
    values
        The sorted positive samples (empty for a distribution).
    contact_fraction
        ``P(v_c > 0)`` of what was given (the share of contacts).
    """

    dist: Any
    values: NDArray[np.float64]
    contact_fraction: float

    @classmethod
    def of(cls, closing_speed: object) -> ClosingSpeeds:
        """Check and wrap a scipy frozen distribution or an array of samples (m/s).

        Parameters
        ----------
        closing_speed
            The distribution or the samples.

        Returns
        -------
        ClosingSpeeds
        """
        if is_distribution(closing_speed):
            p0 = float(closing_speed.sf(0.0))
            if not p0 > 0.0 or not math.isfinite(p0):
                raise InvalidParameterError(
                    "closing_speed", closing_speed, "has no probability at v_c > 0 (no contact)"
                )
            return cls(closing_speed, np.empty(0), p0)
        v = real_array("closing_speed", closing_speed, "m/s").ravel()
        if v.size == 0:
            raise InvalidParameterError("closing_speed", [], "needs at least one sample", "m/s")
        pos = np.sort(v[v > 0])
        if pos.size == 0:
            raise InvalidParameterError(
                "closing_speed",
                v.tolist() if v.size <= 8 else f"{v.size} samples (all <= 0)",
                "has no sample with v_c > 0 (no contact)",
            )
        return cls(None, pos, pos.size / v.size)

    def sample(self, n: int, rng: np.random.Generator) -> NDArray[np.float64]:
        """``n`` closing speeds given a contact, m/s.

        Parameters
        ----------
        n
            Number of samples.
        rng
            The random generator.

        Returns
        -------
        numpy.ndarray
        """
        if self.dist is None:
            return self.values[rng.integers(0, self.values.size, n)]
        u = rng.random(n) * self.contact_fraction
        return np.asarray(self.dist.isf(u), dtype=float)

    def from_normal(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """Closing speeds given a contact from standard normals ``u`` (the transform of
        :meth:`sample`: ``isf(Phi(-u) P(v_c > 0))``; samples: their empirical quantile).

        Parameters
        ----------
        u
            Standard normal coordinates.

        Returns
        -------
        numpy.ndarray
        """
        tail = stats.norm.sf(np.asarray(u, dtype=float))
        if self.dist is None:
            k = np.floor((1.0 - tail) * self.values.size).astype(int)
            return self.values[np.clip(k, 0, self.values.size - 1)]
        return np.asarray(self.dist.isf(tail * self.contact_fraction), dtype=float)

    def sf(self, v: NDArray[np.float64]) -> NDArray[np.float64]:
        """``P(v_c > v | v_c > 0)`` for an array of speeds ``v >= 0``.

        Parameters
        ----------
        v
            Speeds, m/s.

        Returns
        -------
        numpy.ndarray
        """
        if self.dist is None:
            above = self.values.size - np.searchsorted(self.values, v, side="right")
            return above / self.values.size
        out = np.asarray(self.dist.sf(np.maximum(v, 0.0)), dtype=float) / self.contact_fraction
        return np.minimum(out, 1.0)


def lever_sampler(robot: object, points: object) -> Any:
    """The distribution of impact points along a link (uniform over its lever arms by default).

    Parameters
    ----------
    robot
        The robot; only a :class:`~designlab.impact.LinkImpact` has impact points.
    points
        ``None`` or a scipy frozen distribution of the lever arm l, m, with support inside
        ``[lever_arm_min, lever_arm_max]``.

    Returns
    -------
    scipy frozen distribution or float or None
        ``None`` for a robot with one impact point.
    """
    if not isinstance(robot, LinkImpact):
        if points is not None:
            raise InvalidParameterError(
                "points", points, "needs a LinkImpact robot (the others have one impact point)"
            )
        return None
    lo, hi = robot.lever_arm_min, robot.lever_arm_max
    if points is None:
        return lo if hi == lo else stats.uniform(lo, hi - lo)
    if not is_distribution(points):
        raise InvalidParameterError("points", points, "must be None or a scipy distribution")
    _check_support(_LINK["lever_arm_max"], points, "points", lo, hi)
    return points
