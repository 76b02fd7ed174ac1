"""Answers about one foam: is it safe, how fast may the arm go, how thick must it be?

* :func:`foam_verdict` -- a three-way verdict for a foam against an envelope:
  ``feasible``, ``on the boundary`` (within a stated tolerance, default 1 % in
  K_c, of the nearest boundary) or ``not feasible``, with a sentence a reader
  cannot misread ("exceeds the upper (safety) boundary by 27.5 %").
* :func:`max_safe_velocity` -- the largest impact velocity (and manipulator
  speed) at which a foam meets every constraint (metrics ~ v_c ** e, exact).
* :func:`min_foam_thickness` -- the linear depth (and thickness) a foam needs.

The boundaries are solved at the foam's own damping (not interpolated from the
envelope's grid), to a relative accuracy of 1e-9 in K_c.

Examples
--------
>>> import numpy as np, designlab as dl
>>> env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, 1.25, np.linspace(0, 200, 21))
>>> v = dl.impact.foam_verdict(env, dl.impact.FOAM_2)      # Table 3.3: 13.8 kN/m
>>> v.verdict
'on the boundary'
>>> v = dl.impact.foam_verdict(env, dl.impact.FOAM_3)
>>> v.verdict, v.statement
('not feasible', 'exceeds the upper (safety) boundary by 1.0 % (a_h,max <= 10 g)')
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from designlab.errors import InvalidParameterError
from designlab.impact.criteria import Criterion
from designlab.impact.envelope import FoamEnvelope, HeadRange, solve_envelopes
from designlab.impact.parameters import (
    HUMAN_SPEED,
    IMPACT_VELOCITY,
    VERDICT_TOLERANCE,
    ContactDynamics,
    Foam,
)
from designlab.impact.problem import make_problem
from designlab.impact.series_joint import FullJointContact
from designlab.results import OK, Result, Status

__all__ = [
    "FEASIBLE",
    "NOT_FEASIBLE",
    "ON_BOUNDARY",
    "FoamThickness",
    "FoamVerdict",
    "SafeVelocity",
    "VerdictStatus",
    "foam_verdict",
    "foam_verdicts",
    "max_safe_velocity",
    "min_foam_thickness",
]

FEASIBLE = "feasible"
ON_BOUNDARY = "on the boundary"
NOT_FEASIBLE = "not feasible"


class VerdictStatus(Status):
    """Status of the answers about one foam (:class:`FoamVerdict`, :class:`SafeVelocity`,
    :class:`FoamThickness`).

    Attributes
    ----------
    OK
        The answer is complete.
    UNSAFE_AT_REST
        No manipulator speed is safe: the person's own speed already exceeds a limit.
    """

    OK = "ok"
    UNSAFE_AT_REST = "unsafe_at_rest"


@dataclass(frozen=True)
class FoamVerdict(Result):
    """Verdict of one foam against a feasible region (:func:`foam_verdict`).

    Attributes
    ----------
    foam
        The foam judged.
    verdict
        ``"feasible"``, ``"on the boundary"`` or ``"not feasible"``.
    statement
        One sentence: where the foam is relative to the boundaries, in % of K_c.
    tolerance
        Relative distance in K_c within which a foam is "on the boundary".
    stiffness_max, stiffness_min
        The upper and lower boundaries at the foam's damping, N/m (``inf`` /
        ``0`` where unbounded, NaN where the constraint holds nowhere).
    upper_excess
        ``K_c / K_c,max - 1``: > 0 when the foam exceeds the upper boundary.
    lower_deficit
        ``1 - K_c / K_c,min``: > 0 when the foam is below the lower boundary.
    nearest
        ``"upper"`` or ``"lower"``: the boundary that decides the verdict.
    limiting
        Name of the constraint of that boundary.
    margin_decades
        Signed distance to the nearest boundary in log10(K_c) (> 0 inside).
    status
        ``"ok"``, or why the verdict is incomplete.
    warnings
        What a user should know about the verdict.
    """

    foam: Foam
    verdict: str
    statement: str
    tolerance: float
    stiffness_max: float
    stiffness_min: float
    upper_excess: float
    lower_deficit: float
    nearest: str
    limiting: str
    margin_decades: float
    status: str = OK
    warnings: tuple[str, ...] = ()

    @property
    def feasible(self) -> bool:
        """True only for the verdict ``"feasible"``."""
        return self.verdict == FEASIBLE

    def to_frame(self) -> pd.DataFrame:
        """One row: the foam, its verdict and the distances to both boundaries."""
        return pd.DataFrame(
            {
                "foam": [self.foam.name],
                "K_c_N_per_m": [self.foam.stiffness],
                "C_c_N_s_per_m": [self.foam.damping],
                "verdict": [self.verdict],
                "K_c_max_N_per_m": [self.stiffness_max],
                "K_c_min_N_per_m": [self.stiffness_min],
                "upper_excess_percent": [100 * self.upper_excess],
                "lower_deficit_percent": [100 * self.lower_deficit],
                "nearest_boundary": [self.nearest],
                "limiting": [self.limiting],
                "margin_decades": [self.margin_decades],
                "statement": [self.statement],
            }
        )


def _pct(x: float) -> str:
    """``|x|`` in percent: one decimal, two below 1 % (so "0.0 %" never hides a distance)."""
    return f"{100 * abs(x):.2f} %" if abs(x) < 0.01 else f"{100 * abs(x):.1f} %"


def _boundaries_at(one: FoamEnvelope) -> tuple[float, str, float]:
    """K_c,max, its limiting criterion and K_c,min of a one-point envelope.

    Unbounded sides become ``inf`` (upper) or ``0`` (lower); a constraint that
    holds nowhere becomes ``0`` (upper) or ``inf`` (lower).
    """
    kmax, limiting = math.inf, ""
    for name, kk in one.upper.items():
        st = str(one.upper_status[name][0])
        bound = float(kk[0]) if st == "bounded" else (math.inf if st == "unbounded" else 0.0)
        if bound < kmax:
            kmax, limiting = bound, name
    lst = str(one.lower_status[0])
    kmin = (
        float(one.stiffness_min[0])
        if lst == "bounded"
        else (0.0 if lst == "unbounded" else math.inf)
    )
    return kmax, limiting, kmin


def _judge(
    foam: Foam,
    kmax: float,
    kmin: float,
    up: float,
    low: float,
    nearest: str,
    limiting: str,
    tol: float,
) -> tuple[str, str]:
    """The three-way verdict and the sentence that states it."""
    rel = up if nearest == "upper" else low  # > 0: violated
    if kmin > kmax:
        return NOT_FEASIBLE, (
            f"no stiffness is feasible at C_c = {foam.damping:g} N s/m: the lower (thickness) "
            f"boundary {kmin / 1e3:.4g} kN/m is above the upper (safety) boundary "
            f"{kmax / 1e3:.4g} kN/m"
        )
    if abs(rel) <= tol:
        where = "above" if (rel > 0) == (nearest == "upper") else "below"
        side = "upper (safety)" if nearest == "upper" else "lower (thickness)"
        return ON_BOUNDARY, (
            f"on the {side} boundary: {_pct(rel)} {where} it, within the {100 * tol:g} % "
            f"tolerance ({limiting})"
        )
    if rel > 0:
        return NOT_FEASIBLE, (
            f"exceeds the upper (safety) boundary by {_pct(up)} ({limiting})"
            if nearest == "upper"
            else f"is {_pct(low)} below the lower (thickness) boundary ({limiting}): it "
            "compresses beyond its linear depth"
        )
    return FEASIBLE, (
        f"inside the region: {_pct(up)} below the upper (safety) boundary"
        + (f" and {_pct(low)} above the lower (thickness) boundary" if kmin > 0 else "")
    )


def foam_verdict(
    env: FoamEnvelope, foam: Foam, *, tolerance: float = VERDICT_TOLERANCE.default
) -> FoamVerdict:
    """Three-way verdict of ``foam`` against the envelope ``env`` (see the module text).

    Parameters
    ----------
    env
        The feasible region (:func:`~designlab.impact.envelope.foam_envelope`).
    foam
        The foam; its damping need not be on the envelope's grid.
    tolerance
        Relative distance in K_c to the nearest boundary within which the foam
        is "on the boundary" (default 1 %; in ``[0, 0.5)``).

    Returns
    -------
    FoamVerdict

    Examples
    --------
    >>> import numpy as np, designlab as dl
    >>> env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_2, 1.25, np.linspace(0, 200, 5))
    >>> v = dl.impact.foam_verdict(env, dl.impact.FOAM_2)
    >>> v.verdict, v.statement.split(":")[0]
    ('not feasible', 'is 28.1 % below the lower (thickness) boundary (eps_max <= 20 mm)')
    """
    return foam_verdicts([env], [foam], tolerance)[0]


def foam_verdicts(
    envs: Sequence[FoamEnvelope],
    foams: Sequence[Foam],
    tolerance: float = VERDICT_TOLERANCE.default,
) -> list[FoamVerdict]:
    """:func:`foam_verdict` of ``foams[i]`` against ``envs[i]``, solved together.

    The boundaries at the foams' damping are solved in one root-finding over
    all the foams; the envelopes must share their stiffness range.

    Parameters
    ----------
    envs
        The envelopes.
    foams
        One foam per envelope.
    tolerance
        As in :func:`foam_verdict`.

    Returns
    -------
    list of FoamVerdict
    """
    for env in envs:
        if not isinstance(env, FoamEnvelope):
            raise InvalidParameterError("env", env, "must be a FoamEnvelope from foam_envelope()")
    for foam in foams:
        if not isinstance(foam, Foam):
            raise InvalidParameterError("foam", foam, "must be a Foam")
    tol = VERDICT_TOLERANCE.check(tolerance)
    bounds = {env.stiffness_bounds for env in envs}
    if len(bounds) != 1:
        raise InvalidParameterError("envs", sorted(bounds), "must share one stiffness range")
    problems = [env.problem for env in envs]
    dampings = [np.array([foam.damping]) for foam in foams]
    ones = solve_envelopes(problems, dampings, envs[0].stiffness_bounds, 1e-9)
    return [_verdict(foam, one, tol) for foam, one in zip(foams, ones, strict=True)]


def _verdict(foam: Foam, one: FoamEnvelope, tol: float) -> FoamVerdict:
    """The verdict of ``foam`` from ``one``, its envelope solved at the foam's damping."""
    prob = one.problem
    bounds = lo_b, hi_b = one.stiffness_bounds
    k = foam.stiffness
    kmax, limiting_upper, kmin = _boundaries_at(one)
    up = k / kmax - 1.0 if kmax > 0 else math.inf
    low = (
        1.0 - k / kmin
        if math.isfinite(kmin) and kmin > 0
        else (-math.inf if kmin == 0 else math.inf)
    )
    # the deciding boundary: the violated one, else the nearest
    d_up = math.log(kmax / k) if kmax > 0 else -math.inf
    d_low = math.log(k / kmin) if 0 < kmin < math.inf else (math.inf if kmin == 0 else -math.inf)
    nearest = "upper" if d_up <= d_low else "lower"
    margin = min(d_up, d_low) / math.log(10.0)
    limiting = limiting_upper if nearest == "upper" else prob.compression.name
    verdict, statement = _judge(foam, kmax, kmin, up, low, nearest, limiting, tol)
    warnings: list[str] = []
    if not lo_b <= k <= hi_b:
        warnings.append(f"K_c = {k:g} N/m is outside the envelope's stiffness range {bounds}")
    return FoamVerdict(
        foam=foam,
        verdict=verdict,
        statement=statement,
        tolerance=tol,
        stiffness_max=kmax,
        stiffness_min=kmin,
        upper_excess=up,
        lower_deficit=low,
        nearest=nearest,
        limiting=limiting,
        margin_decades=margin,
        warnings=tuple(warnings),
    )


@dataclass(frozen=True)
class SafeVelocity(Result):
    """Largest impact velocity for which a foam satisfies every constraint.

    Attributes
    ----------
    impact_velocity
        Largest v_c, m/s.
    manipulator_speed
        ``impact_velocity - human_speed``: the largest manipulator speed when the
        person moves toward it at ``human_speed`` (negative: unsafe even at rest;
        then ``status`` is ``"unsafe_at_rest"``).
    per_constraint
        Largest v_c allowed by each constraint alone.
    limiting
        Name of the constraint that sets the answer.
    human_speed
        Speed of the person toward the robot in m/s, subtracted to get the manipulator speed.
    status
        ``"ok"``, or why no velocity is safe.
    warnings
        What a user should know.
    """

    impact_velocity: float
    manipulator_speed: float
    human_speed: float
    per_constraint: dict[str, float]
    limiting: str
    status: str = OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """One row per constraint."""
        return pd.DataFrame(
            {
                "constraint": list(self.per_constraint),
                "v_c_max_m_per_s": list(self.per_constraint.values()),
            }
        )


def _check_robot_foam(robot: object, foam: object) -> None:
    """The robot (reduced or full joint) and the foam of a one-foam answer."""
    if not isinstance(robot, (ContactDynamics, FullJointContact)):
        raise InvalidParameterError(
            "robot", robot, "must be a ContactDynamics or a FullJointContact"
        )
    if not isinstance(foam, Foam):
        raise InvalidParameterError("foam", foam, "must be a Foam")


def max_safe_velocity(
    robot: ContactDynamics,
    foam: Foam,
    criteria: Sequence[Criterion] | None = None,
    *,
    max_compression: float | None = None,
    human_speed: float = 1.0,
    head_range: HeadRange | None = None,
    constrained: bool = False,
) -> SafeVelocity:
    """Largest impact velocity (and manipulator speed) for which ``foam`` is safe.

    The metrics scale as v_c ** exponent (1 for a_h,max, force and eps_max, 2.5
    for HIC), so the answer is exact: ``v_i = v_0 (limit_i / metric_i(v_0))^(1/e_i)``.

    Parameters
    ----------
    robot
        Effective manipulator at the impact point.
    foam
        The foam.
    criteria
        Safety criteria (default: a_h,max <= 10 g).
    max_compression
        lambda, m; defaults to the foam's linear depth.
    human_speed
        The head's speed toward the robot, m/s (>= 0).
    head_range
        ``None``: each criterion's conservative head-neck set; a
        :class:`~designlab.impact.envelope.HeadRange`: the worst of its corners.
    constrained
        Constrained impact (head against a wall); force criteria only.

    Returns
    -------
    SafeVelocity

    Examples
    --------
    >>> import designlab as dl
    >>> sv = dl.impact.max_safe_velocity(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1)
    >>> sv.limiting, round(sv.impact_velocity, 2)
    ('eps_max <= 20 mm', 1.81)
    """
    _check_robot_foam(robot, foam)
    human_speed = HUMAN_SPEED.check(human_speed)
    lam = foam.linear_depth if max_compression is None else max_compression
    prob = make_problem(robot, 1.0, criteria, lam, head_range, constrained, human_speed, 0.05)
    k = np.array([foam.stiffness])
    c = np.array([foam.damping])
    per: dict[str, float] = {}
    for key in prob.keys():
        vals, _ = prob.worst(key, k, c)
        per[key.name] = float(
            np.inf if vals[0] <= 0 else (key.limit / vals[0]) ** (1 / key.velocity_exponent)
        )
    limiting = min(per, key=lambda n: per[n])
    v = per[limiting]
    status, warnings = VerdictStatus.OK, ()
    if v - human_speed < 0:
        status = VerdictStatus.UNSAFE_AT_REST
        warnings = (
            f"the foam is unsafe even with the manipulator at rest: a person moving at "
            f"{human_speed:g} m/s alone exceeds {limiting}",
        )
    return SafeVelocity(v, v - human_speed, human_speed, per, limiting, status, warnings)


@dataclass(frozen=True)
class FoamThickness(Result):
    """Thickness a foam needs so that it does not bottom out.

    ``linear_depth`` (lambda) is the worst-case eps_max; ``thickness`` scales it by the
    foam's ratio T_u / lambda (0.0254/0.02 for the thesis's foam).

    Attributes
    ----------
    linear_depth
        Linear depth lambda the foam needs in m.
    thickness
        Total thickness in m (lambda over the linear fraction).
    impact_velocity
        Closing speed v_c in m/s.
    status
        ``"ok"``, or why no thickness suffices.
    warnings
        What a user should know.
    """

    linear_depth: float
    thickness: float
    impact_velocity: float
    status: str = OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """One row: v_c, lambda and T_u."""
        return pd.DataFrame(
            {
                "v_c_m_per_s": [self.impact_velocity],
                "lambda_m": [self.linear_depth],
                "T_u_m": [self.thickness],
            }
        )


def min_foam_thickness(
    robot: ContactDynamics,
    foam: Foam,
    impact_velocity: float = 1.25,
    *,
    head_range: HeadRange | None = None,
    constrained: bool = False,
) -> FoamThickness:
    """Smallest linear depth (and total thickness) for ``foam`` at ``impact_velocity``.

    Parameters
    ----------
    robot
        Effective manipulator at the impact point.
    foam
        The foam (its stiffness and damping; its thickness ratio T_u / lambda).
    impact_velocity
        v_c, m/s.
    head_range
        ``None``: the maximum head-neck set; a
        :class:`~designlab.impact.envelope.HeadRange`: the worst of its corners.
    constrained
        Constrained impact (head against a wall).

    Returns
    -------
    FoamThickness

    Examples
    --------
    >>> import designlab as dl
    >>> t = dl.impact.min_foam_thickness(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, 1.25)
    >>> round(t.linear_depth * 1000, 1)     # mm, maximum head-neck set
    13.8
    """
    _check_robot_foam(robot, foam)
    v = IMPACT_VELOCITY.check(impact_velocity)
    prob = make_problem(robot, v, (), 1.0, head_range, constrained, 1.0, 0.05)
    vals, _ = prob.worst(prob.compression, np.array([foam.stiffness]), np.array([foam.damping]))
    lam = float(vals[0])
    assert foam.thickness is not None
    return FoamThickness(lam, lam * foam.thickness / foam.linear_depth, v)
