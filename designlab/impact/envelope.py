"""Feasible foam stiffness-damping region (Zeng 2011, Sec. 3.9, Figs. 3.18-3.20).

For each foam damping C_c the envelope solves two boundaries in the foam
stiffness K_c:

* the **upper** (safety) boundary: the largest K_c for which every criterion
  (head acceleration, force, HIC, ISO/TS 15066 force) holds, using the
  criterion's conservative head-neck set (Sec. 3.9.1), and
* the **lower** (thickness) boundary: the smallest K_c for which the foam is
  not compressed beyond its linear depth, eps_max < lambda (3.9.3), using the
  maximum head-neck set (Sec. 3.9.2).

Each boundary is a bracketed root in log K_c: a scan over the whole stiffness
range finds every sign change (so a root cannot be missed silently, and more
than one is reported), then vectorised Illinois iterations polish the brackets
to ``rtol`` (:mod:`designlab.impact.boundaries`). Every point carries a status:
``bounded``, ``unbounded`` (the constraint holds over the whole range) or
``no_solution`` (it holds nowhere).

The worst case is searched where it is, not assumed: the response is linear in
the impact velocity (so the largest velocity is the worst), the head-neck set
can be the thesis's conservative one or the worst corner of a range
(:class:`~designlab.impact.parameters.HeadRange`), and for a robot given at
joint level (:class:`~designlab.impact.parameters.LinkImpact`) the worst impact
point along the link is found by a grid and golden-section search at every
evaluation (Sec. 3.7.3; :mod:`designlab.impact.problem`).
:func:`~designlab.impact.worst_case.check_worst_case` samples the ranges to
confirm it.

Examples
--------
>>> import numpy as np
>>> import designlab as dl
>>> env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, impact_velocity=1.25,
...                               damping=np.linspace(0, 200, 41),
...                               criteria=[dl.impact.HeadAcceleration(max_g=10)],
...                               max_compression=0.02)
>>> env.is_feasible(24.3e3, 71.9)
True
>>> foam2 = dl.impact.FOAM_2_MEASURED          # 13.48 kN/m: just below the thickness boundary
>>> bool(env.is_feasible(foam2.stiffness, foam2.damping))
False
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.boundaries import BoundarySolution, BoundaryStatus, solve_boundaries
from designlab.impact.criteria import Criterion
from designlab.impact.parameters import (
    DAMPING_GRID,
    DAMPING_POINTS,
    RTOL,
    STOP_TIME,
    THESIS_HEAD_RANGE,
    ContactDynamics,
    HeadRange,
    LinkImpact,
    check_grid,
    check_pair,
)
from designlab.impact.parameters import Foam as Foam
from designlab.impact.problem import FoamProblem, make_problem
from designlab.params import params_of
from designlab.results import Result, Status

__all__ = [
    "THESIS_HEAD_RANGE",
    "Design",
    "EnvelopeStatus",
    "FoamEnvelope",
    "HeadRange",
    "envelope_warnings",
    "foam_envelope",
    "foam_envelopes",
    "solve_envelopes",
]

log = logging.getLogger(__name__)

_FOAM = params_of(Foam)
BOUNDED, UNBOUNDED = BoundaryStatus.BOUNDED, BoundaryStatus.UNBOUNDED


class EnvelopeStatus(Status):
    """Status of a foam envelope (:func:`foam_envelope`).

    Attributes
    ----------
    OK
        Some damping value of the grid has a feasible stiffness.
    EMPTY
        No foam of the grid meets every constraint.
    """

    OK = "ok"
    EMPTY = "empty"


@dataclass(frozen=True)
class FoamEnvelope(Result):
    """Feasible foam region: boundaries in K_c over a damping grid (SI units).

    Attributes
    ----------
    damping
        C_c grid, N s/m.
    stiffness_max
        Upper (safety) boundary, N/m: the smallest of the criteria's bounds.
        NaN where no bound exists (see ``upper_status``).
    stiffness_min
        Lower (thickness) boundary, N/m; NaN where no bound exists.
    upper, upper_status
        Per criterion name: its bound and status
        (:class:`~designlab.impact.boundaries.BoundaryStatus`: ``bounded``,
        ``unbounded``, ``no_solution``).
    lower_status
        Status of the thickness boundary.
    multiple_roots
        Points where a constraint changes sign more than once over the
        stiffness range (the feasible K_c set is not an interval there).
    overdamped
        Points where the head acceleration peaks at contact on the upper
        boundary (an overdamped pulse; the impact period is delicate).
    delicate
        Points where a boundary design's first lobe is delicate (a_h lingers
        near zero before the lobe ends, or peaks at contact): the thesis's
        first-lobe metrics can jump there (docs/impact.md, "Metrics").
    worst_lever_arm
        For a robot at joint level, the worst impact point on the upper
        boundary of the first criterion (NaN otherwise).
    robot
        The manipulator (effective contact dynamics or a link struck anywhere).
    impact_velocity
        Closing speed v_c in m/s.
    criteria
        The safety criteria of the upper boundary.
    max_compression
        Usable foam depth lambda in m (the lower boundary).
    stiffness_bounds
        ``(low, high)`` K_c search range in N/m.
    constrained
        Whether the head is constrained (no neck; Sec. 3.4).
    head_range
        The head-neck ranges the boundaries hold for (``None``: one head).
    warnings
        What a user should know (several roots, delicate lobes, ...).
    status
        An :class:`EnvelopeStatus`: ``"ok"``, or ``"empty"`` when no foam is feasible.
    """

    robot: ContactDynamics | LinkImpact
    impact_velocity: float
    criteria: tuple[Criterion, ...]
    max_compression: float
    damping: NDArray[np.float64]
    stiffness_min: NDArray[np.float64]
    stiffness_max: NDArray[np.float64]
    upper: dict[str, NDArray[np.float64]]
    upper_status: dict[str, NDArray[np.str_]]
    lower_status: NDArray[np.str_]
    multiple_roots: NDArray[np.bool_]
    overdamped: NDArray[np.bool_]
    delicate: NDArray[np.bool_]
    worst_lever_arm: NDArray[np.float64]
    stiffness_bounds: tuple[float, float]
    constrained: bool
    head_range: HeadRange | None
    warnings: tuple[str, ...] = ()
    status: str = EnvelopeStatus.OK
    _problem: FoamProblem | None = field(default=None, repr=False, compare=False)

    # -- effective bounds (unbounded sides clipped to the search range) ----------
    def _effective(self) -> tuple[NDArray, NDArray]:
        lo, hi = self.stiffness_bounds
        kmax = np.full(self.damping.size, hi)
        for name, k in self.upper.items():
            st = self.upper_status[name]
            kk = np.where(st == BOUNDED, k, np.where(st == UNBOUNDED, hi, -np.inf))
            kmax = np.minimum(kmax, kk)
        kmin = np.where(
            self.lower_status == BOUNDED,
            self.stiffness_min,
            np.where(self.lower_status == UNBOUNDED, lo, np.inf),
        )
        return kmin, kmax

    @property
    def region_status(self) -> NDArray[np.str_]:
        """Per damping value: ``feasible`` or ``empty``."""
        kmin, kmax = self._effective()
        return np.where(kmin <= kmax, "feasible", "empty").astype(str)

    @property
    def is_empty(self) -> bool:
        """True if no damping value of the grid has a feasible stiffness."""
        return bool(np.all(self.region_status == "empty"))

    def is_feasible(self, stiffness: ArrayLike, damping: ArrayLike) -> bool | NDArray[np.bool_]:
        """Whether foams ``(K_c, C_c)`` satisfy every criterion and the thickness limit.

        Evaluated exactly with the model and the envelope's worst case, at any
        damping (not interpolated from the grid).

        Parameters
        ----------
        stiffness, damping
            K_c (N/m) and C_c (N s/m) of the foams (broadcast together).

        Returns
        -------
        bool or numpy.ndarray
        """
        prob = self.problem
        k, c = np.broadcast_arrays(np.asarray(stiffness, float), np.asarray(damping, float))
        ok = np.ones(k.shape, dtype=bool)
        for key in prob.keys():
            vals, _ = prob.worst(key, k.ravel(), c.ravel())
            ok &= (vals <= prob.limit(key)).reshape(k.shape)
        return bool(ok) if ok.ndim == 0 else ok

    def margin(self, stiffness: ArrayLike, damping: ArrayLike) -> float | NDArray[np.float64]:
        """Signed distance to the nearest boundary in log10(K_c), decades.

        Positive inside the region, negative outside; ``-inf`` where no
        stiffness is feasible at that damping.

        Parameters
        ----------
        stiffness, damping
            K_c (N/m) and C_c (N s/m) of the foams (broadcast together).

        Returns
        -------
        float or numpy.ndarray
        """
        prob = self.problem
        k, c = np.broadcast_arrays(np.asarray(stiffness, float), np.asarray(damping, float))
        cu, inv = np.unique(c.ravel(), return_inverse=True)
        (env,) = solve_envelopes([prob], [cu], self.stiffness_bounds, 1e-9)
        kmin, kmax = env._effective()
        kk = k.ravel()
        kx, kn = kmax[inv], kmin[inv]
        with np.errstate(divide="ignore", invalid="ignore"):
            up = np.where(kx > 0, np.log10(np.where(kx > 0, kx, 1.0) / kk), -np.inf)
            dn = np.where(
                np.isfinite(kn), np.log10(kk / np.where(np.isfinite(kn), kn, 1.0)), -np.inf
            )
        m = np.minimum(up, dn)
        m = np.where(kmin[inv] > kmax[inv], np.minimum(m, -np.inf), m)
        m = m.reshape(k.shape)
        return float(m) if m.ndim == 0 else m

    def area(self, log: bool = False) -> float:
        """Area of the feasible region over the damping grid.

        ``log=False``: in (N/m)(N s/m), the integral of ``K_max - K_min``;
        ``log=True``: in decades x N s/m, the integral of ``log10(K_max/K_min)``.
        Unbounded sides are clipped to the stiffness search range.
        """
        kmin, kmax = self._effective()
        if log:
            with np.errstate(divide="ignore", invalid="ignore"):
                w = np.log10(kmax) - np.log10(kmin)
        else:
            w = kmax - kmin
        w = np.where(np.isfinite(w) & (w > 0), w, 0.0)
        if self.damping.size < 2:
            return 0.0
        return float(np.sum(0.5 * (w[1:] + w[:-1]) * np.diff(self.damping)))

    def to_frame(self) -> pd.DataFrame:
        """One row per damping value, columns with units."""
        df = pd.DataFrame(
            {
                "C_c_N_s_per_m": self.damping,
                "K_c_min_N_per_m": self.stiffness_min,
                "K_c_max_N_per_m": self.stiffness_max,
                "lower_status": self.lower_status,
                "region": self.region_status,
            }
        )
        for name in self.upper:
            df[f"K_c_max[{name}]_N_per_m"] = self.upper[name]
            df[f"status[{name}]"] = self.upper_status[name]
        df["multiple_roots"] = self.multiple_roots
        df["overdamped_pulse"] = self.overdamped
        df["delicate_lobe"] = self.delicate
        if np.any(np.isfinite(self.worst_lever_arm)):
            df["worst_lever_arm_m"] = self.worst_lever_arm
        return df

    @property
    def problem(self) -> FoamProblem:
        """The worst-case problem the envelope was solved for (:mod:`designlab.impact.problem`)."""
        if self._problem is None:  # pragma: no cover - only for hand-built objects
            raise InvalidParameterError("FoamEnvelope", None, "was not built by foam_envelope")
        return self._problem


def envelope_warnings(
    empty: bool, multiple: NDArray, overdamped: NDArray, delicate: NDArray
) -> list[str]:
    """What a user should know about an envelope (empty region, several roots, flags).

    Parameters
    ----------
    empty
        Whether no damping value has a feasible stiffness.
    multiple, overdamped, delicate
        The flags per damping value (see :class:`FoamEnvelope`).

    Returns
    -------
    list of str
    """
    warnings = []
    if empty:
        warnings.append(
            "the feasible region is empty at every damping value of the grid: reduce the "
            'impact velocity (docs/impact.md, "Foam design")'
        )
    if np.any(multiple):
        warnings.append(
            f"{int(multiple.sum())} damping value(s) have a constraint that changes sign more "
            "than once over the stiffness range; the boundary reported is the one nearest the "
            "feasible side"
        )
    if np.any(delicate & ~overdamped):
        warnings.append(
            f"{int((delicate & ~overdamped).sum())} boundary point(s) have a delicate first lobe "
            "(a_h lingers near zero before the lobe ends), so eps_max and the impact period "
            'can jump with small parameter changes (docs/impact.md, "Metrics")'
        )
    if np.any(overdamped):
        warnings.append(
            f"{int(overdamped.sum())} upper-boundary point(s) are overdamped pulses (a_h peaks "
            "at contact, a_h,max = C_c v_c / M_h): outside the thesis's foam range xi_c 0.05-0.2"
        )
    return warnings


def solve_envelopes(
    problems: Sequence[FoamProblem],
    dampings: Sequence[NDArray],
    bounds: tuple[float, float],
    rtol: float,
) -> list[FoamEnvelope]:
    """The envelopes of ``problems[i]`` over ``dampings[i]``, solved together.

    The boundaries come from :func:`~designlab.impact.boundaries.solve_boundaries`
    (one root-finding over every problem and damping value); each envelope
    gets its warnings and status. Several problems must differ only in a fixed
    robot, v_c and limits.

    Parameters
    ----------
    problems
        Problems of :func:`~designlab.impact.problem.make_problem`.
    dampings
        C_c values of each problem, N s/m.
    bounds
        ``(low, high)`` stiffness search range, N/m.
    rtol
        Relative accuracy of the boundaries in K_c.

    Returns
    -------
    list of FoamEnvelope
    """
    out = []
    for sol in solve_boundaries(problems, dampings, bounds, rtol):
        p = sol.problem
        env = FoamEnvelope(
            robot=p.robot,
            impact_velocity=p.impact_velocity,
            criteria=p.criteria,
            max_compression=p.max_compression,
            damping=sol.damping,
            stiffness_min=sol.stiffness_min,
            stiffness_max=sol.stiffness_max,
            upper=sol.upper,
            upper_status=sol.upper_status,
            lower_status=sol.lower_status,
            multiple_roots=sol.multiple_roots,
            overdamped=sol.overdamped,
            delicate=sol.delicate,
            worst_lever_arm=sol.worst_lever_arm,
            stiffness_bounds=bounds,
            constrained=p.constrained,
            head_range=p.head_range,
            _problem=p,
        )
        empty = env.is_empty
        warnings = envelope_warnings(empty, sol.multiple_roots, sol.overdamped, sol.delicate)
        _log_solution(sol)
        status = EnvelopeStatus.EMPTY if empty else EnvelopeStatus.OK
        out.append(replace(env, warnings=tuple(warnings), status=status))
    return out


def _log_solution(sol: BoundarySolution) -> None:
    # one-point solves (verdicts, margins, the worst-case onset) are debug detail
    n = sol.damping.size
    log.log(
        logging.INFO if n > 1 else logging.DEBUG,
        "foam_envelope: %d damping values, %d-point scan in K_c: upper bounded at %d, "
        "lower bounded at %d, %d delicate, %d with several roots",
        n, 48, int(np.isfinite(sol.stiffness_max).sum()),
        int(np.isfinite(sol.stiffness_min).sum()), int(sol.delicate.sum()),
        int(sol.multiple_roots.sum()),
    )  # fmt: skip


def foam_envelope(
    robot: ContactDynamics | LinkImpact,
    impact_velocity: float | None = 1.25,
    damping: ArrayLike | None = None,
    criteria: Sequence[Criterion] | None = None,
    max_compression: float = 0.02,
    *,
    head_range: HeadRange | None = None,
    constrained: bool = False,
    stiffness_bounds: tuple[float, float] = (1e2, 1e7),
    rtol: float = 1e-6,
    human_speed: float = 1.0,
    stop_time: float = STOP_TIME.default,
    foam: object | None = None,
) -> FoamEnvelope:
    """Feasible region of foam stiffness and damping (Zeng 2011, Sec. 3.9).

    Parameters
    ----------
    robot
        Effective manipulator at the worst impact point, or a
        :class:`~designlab.impact.parameters.LinkImpact` to search the impact
        point along the link.
    impact_velocity
        Maximum v_c, m/s (the response is linear in v_c, so the maximum is the
        worst case). ``None`` for a ``LinkImpact`` (its speed comes from the joint).
    damping
        C_c grid, N s/m (default: 41 points over 0-200 N s/m; each value in
        0-1e5 N s/m, at most 2001 values).
    criteria
        Safety criteria for the upper boundary (default: a_h,max <= 10 g).
    max_compression
        lambda, the linear depth of the foam, m (lower boundary, (3.9.3)).
    head_range
        ``None`` (default) uses each criterion's conservative head-neck set as
        the thesis does; a :class:`HeadRange` takes the worst of its corners.
    constrained
        Constrained impact (head against a wall; (3.6.1) and (3.9.4)); force
        criteria only.
    stiffness_bounds
        Search range of K_c, N/m.
    rtol
        Relative accuracy of the boundaries in K_c.
    human_speed
        Head speed toward the robot for a ``LinkImpact``, m/s.
    stop_time
        Window of the constrained impact's metrics, s.
    foam
        ``None`` (default): the linear foam of (3.5.1). A foam of a non-linear law
        (:class:`~designlab.impact.contact.HuntCrossleyFoam`): the region is in its own
        K_c and C_c, its other parameters kept, solved by the general response path
        (:mod:`designlab.impact.general`; slower, integrator results). The K_c and C_c of
        ``foam`` itself are not used.

    Returns
    -------
    FoamEnvelope

    Examples
    --------
    >>> import designlab as dl
    >>> env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, 1.25, [0.0, 100.0])
    >>> (env.stiffness_max / 1e3).round(2).tolist(), (env.stiffness_min / 1e3).round(2).tolist()
    ([46.04, 58.77], [16.67, 11.92])
    """
    design = (robot, impact_velocity, criteria, max_compression)
    return foam_envelopes(
        [design],
        damping,
        head_range=head_range,
        constrained=constrained,
        stiffness_bounds=stiffness_bounds,
        rtol=rtol,
        human_speed=human_speed,
        stop_time=stop_time,
        foam=foam,
    )[0]


#: One design of :func:`foam_envelopes`: robot, impact velocity, criteria, max_compression.
Design = tuple[ContactDynamics | LinkImpact, float | None, Sequence[Criterion] | None, float]


def foam_envelopes(
    designs: Sequence[Design], damping: ArrayLike | None, **settings: Any
) -> list[FoamEnvelope]:
    """:func:`foam_envelope` of several designs over one damping grid, solved together.

    Parameters
    ----------
    designs
        ``(robot, impact_velocity, criteria, max_compression)`` of each design.
        Several designs must have fixed robots and criteria differing in their
        limits only.
    damping
        The C_c grid, N s/m (default: 41 points over 0-200 N s/m; at most 2001 values).
    **settings
        Keyword arguments of :func:`foam_envelope` (its defaults where not given).

    Returns
    -------
    list of FoamEnvelope
    """
    s = {**(foam_envelope.__kwdefaults__ or {}), **settings}
    c = (
        np.linspace(0.0, 200.0, 41)
        if damping is None
        else check_grid(DAMPING_GRID, DAMPING_POINTS, damping, "damping")
    )
    lo, hi = check_pair(_FOAM["stiffness"], s["stiffness_bounds"], "stiffness_bounds")
    rtol = RTOL.check(s["rtol"])
    setting = (s["head_range"], s["constrained"], s["human_speed"], s["stop_time"], s["foam"])
    problems = [make_problem(r, v, crit, lam, *setting) for r, v, crit, lam in designs]
    return solve_envelopes(problems, [c] * len(problems), (lo, hi), rtol)
