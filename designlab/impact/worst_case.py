"""Does the envelope's worst case hold over the whole head-neck and speed range?

The feasible foam region (:func:`~designlab.impact.envelope.foam_envelope`)
evaluates each criterion at one head-neck set: the thesis's conservative set
(Zeng 2011, Sec. 3.6 and 3.9: the minimum set for head acceleration, the
maximum set for force and compression) unless a head range is given. The
thesis notes that the head-neck parameters affect the force and the compression
"in nearly the same way"; that is not exact. :func:`check_worst_case` tests the
claim at every boundary point of the envelope:

1. deterministically, at the 8 corners of the head-neck box at the largest
   impact velocity (the metrics rise linearly with v_c) and, for a robot
   given at joint level, at both ends of the link and at the envelope's worst
   impact point;
2. then at ``samples`` random cases (uniform heads, a quarter of them at the
   largest velocity, the others at a uniform fraction of it, uniform impact
   points).

A case that exceeds the limit that the boundary design meets is a violation.
Cases whose first lobe is *delicate* (a_h lingers near zero before the lobe
ends, so the lobe end and eps_max can jump; docs/impact.md, "Metrics") are
violations too: the foam really compresses that far. They are flagged, never
left out of the verdict. Where violations start, the damping and the foam
damping ratio xi_c = C_c / (2 sqrt(4.4 kg K_c)) at which the conservative set
stops being the worst are located by bisection on the corners.

Examples
--------
>>> import numpy as np, designlab as dl
>>> env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, 1.25, np.linspace(10, 90, 5))
>>> check = dl.impact.check_worst_case(env, samples=16)
>>> check.holds, check.status
(True, 'ok')
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.boundaries import solve_boundaries
from designlab.impact.criteria import Criterion
from designlab.impact.envelope import FoamEnvelope
from designlab.impact.parameters import (
    SEED,
    THESIS_HEAD_RANGE,
    WORST_CASE_SAMPLES,
    WORST_CASE_TOLERANCE,
    HeadRange,
)
from designlab.impact.problem import FoamProblem
from designlab.results import Result, Status

__all__ = ["WorstCaseCheck", "WorstCaseStatus", "check_worst_case"]

#: head mass of the thesis's damping-ratio convention, C_c = 2 xi_c sqrt(M_h K_c)
_XI_HEAD_MASS = 4.4


class WorstCaseStatus(Status):
    """Status of a worst-case check (:func:`check_worst_case`).

    Attributes
    ----------
    OK
        No case exceeds a limit by more than the tolerance.
    VIOLATED
        A case beyond the envelope's head set (or impact point) exceeds a limit.
    """

    OK = "ok"
    VIOLATED = "violated"


@dataclass(frozen=True)
class WorstCaseCheck(Result):
    """Result of :func:`check_worst_case`, per constraint of the envelope.

    Attributes
    ----------
    damping
        The envelope's C_c grid, N s/m.
    boundary
        Per constraint name: ``"upper"`` (safety criteria) or ``"lower"``
        (thickness constraint).
    ratio_by_point
        Per constraint, at each damping value: the largest metric / limit over
        every case checked (corners, samples, delicate lobes included); NaN
        where the boundary is not bounded.
    corner_ratio_by_point
        The same over the deterministic corners only.
    delicate_by_point
        Whether a case with a delicate first lobe exceeds the limit there.
    worst_case
        Per constraint: the parameters (``M_r ... K_h``, ``v_c``, ``C_c``) of the
        case with the largest ratio.
    onset_damping, onset_damping_ratio
        Per constraint: the C_c (N s/m) and xi_c from which the envelope's head
        set stops being the worst (first crossing, located by bisection on the
        corners); NaN if it is the worst everywhere on the grid.
    samples, tolerance
        Random cases per boundary point, and the relative tolerance on a ratio.
    status
        A :class:`WorstCaseStatus`: ``"ok"`` if no case exceeds a limit by more
        than ``tolerance``, ``"violated"`` otherwise.
    warnings
        One sentence per violated constraint.
    """

    damping: NDArray[np.float64]
    boundary: dict[str, str]
    ratio_by_point: dict[str, NDArray[np.float64]]
    corner_ratio_by_point: dict[str, NDArray[np.float64]]
    delicate_by_point: dict[str, NDArray[np.bool_]]
    worst_case: dict[str, dict[str, float]]
    onset_damping: dict[str, float]
    onset_damping_ratio: dict[str, float]
    samples: int
    tolerance: float
    status: str = WorstCaseStatus.OK
    warnings: tuple[str, ...] = ()

    @property
    def max_ratio(self) -> dict[str, float]:
        """Largest ratio per constraint over every point and case (NaN if none)."""
        return {k: _nanmax(v) for k, v in self.ratio_by_point.items()}

    @property
    def holds(self) -> bool:
        """Whether no case exceeds any limit by more than the tolerance."""
        return self.status == WorstCaseStatus.OK

    def to_frame(self) -> pd.DataFrame:
        """One row per constraint."""
        names = list(self.ratio_by_point)
        return pd.DataFrame(
            {
                "constraint": names,
                "boundary": [self.boundary[n] for n in names],
                "max_ratio": [self.max_ratio[n] for n in names],
                "max_corner_ratio": [_nanmax(self.corner_ratio_by_point[n]) for n in names],
                "n_points_violated": [
                    int(np.sum(self.ratio_by_point[n] > 1 + self.tolerance)) for n in names
                ],
                "n_points_delicate_violation": [
                    int(self.delicate_by_point[n].sum()) for n in names
                ],
                "onset_C_c_N_s_per_m": [self.onset_damping[n] for n in names],
                "onset_xi_c": [self.onset_damping_ratio[n] for n in names],
            }
        )


def _nanmax(x: NDArray) -> float:
    x = np.asarray(x, dtype=float)
    return float(np.nanmax(x)) if np.any(np.isfinite(x)) else float("nan")


def _corner_heads(prob: FoamProblem, head_range: HeadRange) -> NDArray[np.float64]:
    if prob.constrained:
        return np.array([[1.0, 0.0, 0.0]])
    return np.array([[h.mass, h.damping, h.stiffness] for h in head_range.corners()])


def _robot_cases(
    prob: FoamProblem, key: Criterion, k: NDArray, c: NDArray
) -> tuple[NDArray, NDArray, NDArray]:
    """Deterministic robot rows per boundary point: ``(n, n_r, 3)``, ``(n, n_r)`` v_c, levers."""
    n = k.size
    if prob.robot.along_link:
        _, worst_l = prob.worst(key, k, c)
        lr = prob.robot
        levers = np.column_stack(
            [np.full(n, lr.lever_arm_min), np.full(n, lr.lever_arm_max), worst_l]
        )
        rows, v = prob.robot_rows(levers.ravel())
        return rows.reshape(n, 3, rows.shape[-1]), v.reshape(n, 3), levers
    rows, v = prob.robot_rows(None)
    return (
        np.broadcast_to(rows, (n, 1, rows.shape[-1])),
        np.broadcast_to(v, (n, 1)),
        np.full((n, 1), np.nan),
    )


def _evaluate(
    prob: FoamProblem, key: Criterion, params: NDArray, v: NDArray
) -> tuple[NDArray, NDArray]:
    """Ratio metric / limit and the delicate-lobe flag of each case."""
    m = prob.contact.metrics(
        params,
        v,
        constrained=prob.constrained,
        with_force=key.needs_force,
        with_compression=key.metric == "compression",
        stop_time=prob.stop_time,
        lobe_diagnostics=not prob.constrained,
    )
    return key.from_metrics(m) / key.limit, m.delicate_lobe


def _corner_ratio(
    prob: FoamProblem, key: Criterion, heads: NDArray, k: NDArray, c: NDArray
) -> tuple[NDArray, NDArray, NDArray]:
    """Largest corner ratio per point, its delicate flag and its case parameters."""
    rows, v, _ = _robot_cases(prob, key, k, c)
    n, nr, nh = k.size, rows.shape[1], heads.shape[0]
    robot = np.repeat(rows.reshape(n * nr, rows.shape[-1]), nh, axis=0)
    vv = np.repeat(v.reshape(n * nr), nh)
    kk = np.repeat(k, nr * nh)
    cc = np.repeat(c, nr * nh)
    hh = np.tile(heads, (n * nr, 1))
    params = prob.contact.assemble(robot, kk, cc, hh, prob.foam)
    ratio, delicate = _evaluate(prob, key, params, vv)
    ratio = ratio.reshape(n, nr * nh)
    j = np.nanargmax(np.where(np.isfinite(ratio), ratio, -np.inf), axis=1)
    pick = np.arange(n) * nr * nh + j
    return (
        ratio[np.arange(n), j],
        delicate.reshape(n, nr * nh)[np.arange(n), j],
        np.column_stack([params[pick], vv[pick]]),
    )


def _sampled_ratio(
    prob: FoamProblem,
    key: Criterion,
    head_range: HeadRange,
    k: NDArray,
    c: NDArray,
    samples: int,
    rng: np.random.Generator,
) -> tuple[NDArray, NDArray, NDArray]:
    """Largest sampled ratio per point, whether a delicate sample exceeds 1, the worst case."""
    n = k.size * samples
    heads = np.tile([1.0, 0.0, 0.0], (n, 1)) if prob.constrained else head_range.sample(n, rng)
    frac = rng.random(n)
    if prob.robot.along_link:
        lr = prob.robot
        lev = lr.lever_arm_min + (lr.lever_arm_max - lr.lever_arm_min) * rng.random(n)
        rows, vmax = prob.robot_rows(lev)
    else:
        rows, vmax = prob.robot_rows(None)
        rows, vmax = np.repeat(rows, n, axis=0), np.repeat(vmax, n)
    v = vmax * np.where(frac < 0.25, 1.0, frac)
    params = prob.contact.assemble(
        rows, np.repeat(k, samples), np.repeat(c, samples), heads, prob.foam
    )
    ratio, delicate = _evaluate(prob, key, params, v)
    r = np.where(np.isfinite(ratio), ratio, -np.inf).reshape(k.size, samples)
    j = r.argmax(axis=1)
    pick = np.arange(k.size) * samples + j
    over_delicate = (delicate.reshape(k.size, samples) & (r > 1)).any(axis=1)
    return r[np.arange(k.size), j], over_delicate, np.column_stack([params[pick], v[pick]])


def _boundary_at(prob: FoamProblem, env: FoamEnvelope, key: Criterion, c: float) -> float:
    """The boundary of ``key`` at damping ``c``, solved afresh (to 1e-9)."""
    (one,) = solve_boundaries([prob], [np.array([c])], env.stiffness_bounds, 1e-9)
    k = one.stiffness_min if key.boundary == "lower" else one.upper[key.name]
    return float(k[0])


def _onset(
    prob: FoamProblem,
    env: FoamEnvelope,
    key: Criterion,
    heads: NDArray,
    ratio: NDArray,
    tolerance: float,
) -> tuple[float, float]:
    """C_c and xi_c of the first grid crossing of ``ratio`` above 1, refined on the corners."""
    bad = np.flatnonzero(ratio > 1 + tolerance)
    if bad.size == 0:
        return float("nan"), float("nan")
    j = int(bad[0])
    kb = env.stiffness_min if key.boundary == "lower" else env.upper[key.name]
    c_hi, k_hi = float(env.damping[j]), float(kb[j])
    prev = np.flatnonzero(np.isfinite(ratio[:j]) & (ratio[:j] <= 1 + tolerance))
    if prev.size and prev[-1] == j - 1:
        c_lo = float(env.damping[j - 1])
        for _ in range(30):
            if c_hi - c_lo <= 1e-6 * max(c_hi, 1.0):
                break
            mid = 0.5 * (c_lo + c_hi)
            k_mid = _boundary_at(prob, env, key, mid)
            if not np.isfinite(k_mid):
                break
            r, _, _ = _corner_ratio(prob, key, heads, np.array([k_mid]), np.array([mid]))
            if r[0] > 1 + tolerance:
                c_hi, k_hi = mid, k_mid
            else:
                c_lo = mid
    return c_hi, c_hi / (2.0 * math.sqrt(_XI_HEAD_MASS * k_hi))


def _check_constraint(
    prob: FoamProblem,
    env: FoamEnvelope,
    key: Criterion,
    heads: NDArray,
    head_range: HeadRange,
    samples: int,
    rng: np.random.Generator,
    tolerance: float,
) -> tuple[NDArray, NDArray, NDArray, dict[str, float], float, float]:
    """One constraint: ratios (all cases, corners), delicate flags, worst case, onset."""
    n = env.damping.size
    ratio_all, corner_all = np.full(n, np.nan), np.full(n, np.nan)
    flag_all = np.zeros(n, dtype=bool)
    kb = env.stiffness_min if key.boundary == "lower" else env.upper[key.name]
    ok = np.isfinite(kb)
    if not np.any(ok):
        return ratio_all, corner_all, flag_all, {}, float("nan"), float("nan")
    k, c = kb[ok], env.damping[ok]
    r_c, d_c, case_c = _corner_ratio(prob, key, heads, k, c)
    ratio, flag, case = r_c, d_c & (r_c > 1), case_c
    if samples:
        r_s, d_s, case_s = _sampled_ratio(prob, key, head_range, k, c, samples, rng)
        take = r_s > r_c
        ratio = np.where(take, r_s, r_c)
        case = np.where(take[:, None], case_s, case_c)
        flag = flag | d_s
    ratio_all[ok], corner_all[ok], flag_all[ok] = ratio, r_c, flag
    j = int(np.argmax(ratio))
    names = (*prob.contact.columns, "v_c")
    worst = dict(zip(names, case[j].tolist(), strict=True))
    onset_c, onset_xi = _onset(prob, env, key, heads, ratio_all, tolerance)
    return ratio_all, corner_all, flag_all, worst, onset_c, onset_xi


def _violation_warning(
    prob: FoamProblem,
    key: Criterion,
    ratio: NDArray,
    w: dict[str, float],
    onset_c: float,
    onset_xi: float,
    delicate: bool,
) -> str:
    """One sentence: which head set fails, from where, by how much, with which case."""
    head_set = (
        "the head-neck range's worst corner"
        if prob.head_range
        else f"the conservative head-neck set (M_h {key.conservative_head.mass:g} kg)"
    )
    return (
        f"{key.name}: {head_set} is not the worst case on the {key.boundary} boundary"
        + (
            f" from C_c = {onset_c:.1f} N s/m (xi_c = {onset_xi:.3f})"
            if np.isfinite(onset_c)
            else ""
        )
        + f": a case exceeds the limit by {100 * (np.nanmax(ratio) - 1):.2f} % "
        f"(M_h {w['M_h']:.3g} kg, K_h {w['K_h']:.4g} N/m, C_h {w['C_h']:.4g} N s/m, "
        f"v_c {w['v_c']:.3g} m/s at C_c {w['C_c']:.4g} N s/m)"
        + ("; delicate first lobes exceed it too" if delicate else "")
    )


def check_worst_case(
    env: FoamEnvelope,
    head_range: HeadRange = THESIS_HEAD_RANGE,
    samples: int = 64,
    seed: int = SEED.default,
    tolerance: float = 1e-6,
) -> WorstCaseCheck:
    """Check the envelope's worst case at every boundary point (see the module text).

    Parameters
    ----------
    env
        An envelope from :func:`~designlab.impact.envelope.foam_envelope`.
    head_range
        Head-neck ranges to check (default: the thesis's, Sec. 3.5).
    samples
        Random cases per boundary point after the corners (0: corners only).
    seed
        Seed of the random cases.
    tolerance
        Relative excess of a ratio over 1 tolerated (solver accuracy).

    Returns
    -------
    WorstCaseCheck

    Examples
    --------
    >>> import numpy as np, designlab as dl
    >>> env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, 1.25, [60.0, 150.0])
    >>> check = dl.impact.check_worst_case(env, samples=0)     # corners only
    >>> check.status, round(check.onset_damping["eps_max <= 20 mm"], 1)
    ('violated', 107.3)
    """
    if not isinstance(env, FoamEnvelope):
        raise InvalidParameterError("env", env, "must be a FoamEnvelope from foam_envelope()")
    if not isinstance(head_range, HeadRange):
        raise InvalidParameterError("head_range", head_range, "must be a HeadRange")
    samples = WORST_CASE_SAMPLES.check(samples)
    seed = SEED.check(seed)
    tolerance = WORST_CASE_TOLERANCE.check(tolerance)
    prob = env.problem
    rng = np.random.default_rng(seed)
    heads = _corner_heads(prob, head_range)
    side, by_point, corners, delicate, worst, onset_c, onset_xi = {}, {}, {}, {}, {}, {}, {}
    warnings: list[str] = []
    for key in prob.keys():
        name = key.name
        side[name] = key.boundary
        one = _check_constraint(prob, env, key, heads, head_range, samples, rng, tolerance)
        by_point[name], corners[name], delicate[name], worst[name] = one[:4]
        onset_c[name], onset_xi[name] = one[4], one[5]
        if np.any(np.isfinite(by_point[name])) and np.nanmax(by_point[name]) > 1 + tolerance:
            warnings.append(
                _violation_warning(prob, key, by_point[name], worst[name], onset_c[name],
                                   onset_xi[name], bool(np.any(delicate[name])))
            )  # fmt: skip
    return WorstCaseCheck(
        damping=env.damping,
        boundary=side,
        ratio_by_point=by_point,
        corner_ratio_by_point=corners,
        delicate_by_point=delicate,
        worst_case=worst,
        onset_damping=onset_c,
        onset_damping_ratio=onset_xi,
        samples=samples,
        tolerance=float(tolerance),
        status=WorstCaseStatus.VIOLATED if warnings else WorstCaseStatus.OK,
        warnings=tuple(warnings),
    )
