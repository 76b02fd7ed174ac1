"""Zeng 2011 Ch. 3 statements, recomputed: what the model and the text support.

Four statements of Ch. 3 need restating (``docs/impact_joint.md``, Sec. 5):

* **Sec. 3.8 (Fig. 3.17).** The manipulator accelerating or decelerating at
  0.51 g changes the "peak" force by about +5/-4 % and a_h,max by +4/-3 %. The
  head speed and the feed-forward are not stated. :func:`profile_change` gives
  the changes of a_h,max, of the force's first local maximum (the thesis's
  "peak", Sec. 3.6) and of its first-lobe maximum (docs/impact.md, "Metrics") for any
  reading.
* **Fig. 3.16.** The worst impact point along Manipulator 1's link and the
  change of a_h,max as l -> 0. Since v_c = v_h (1 + (theta_dot / v_h) l) and the
  model is linear in v_c, both depend only on the joint-speed/head-speed ratio:
  :func:`worst_impact_point` searches the worst point continuously.
* **The printed q2 (docs/impact.md, "q2").** :func:`q2_effect` shows that the printed
  q2 changes the common denominator, so the force and the compression change as
  well as a_h.
* **Table 3.1, Manipulator 1**, recomputed from its joint data (App. A.2) by
  :func:`manipulator_1_recomputed`: M_r = 9.70 kg (printed 9.6), K_r = 20.0 kN/m,
  C_r = 250 N s/m.

Examples
--------
>>> import designlab as dl
>>> from designlab.units import STANDARD_GRAVITY
>>> head = dl.impact.TABLE_3_2_HEADS[3][1]
>>> c = profile_change(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, head, 0.25,
...                    0.51 * STANDARD_GRAVITY, feedforward=False)
>>> round(c.force_first_peak_pct, 1), round(c.a_h_max_pct, 1), round(c.force_lobe_max_pct)
(5.0, 3.4, 90)
>>> w = worst_impact_point(0.059, 121.68, 1.521, 1.0, dl.impact.FOAM_1, dl.impact.HEAD_MIN)
>>> round(w.lever_arm, 3), round(w.change_at_zero_pct, 2)
(0.016, -0.69)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.effective import impact_point_sweep, scenario_single_joint
from designlab.impact.joint import joint_from_pd_gains
from designlab.impact.parameters import (
    HEAD_SPEED,
    IMPACT_VELOCITY,
    ContactDynamics,
    Foam,
    HeadNeck,
    LinkImpact,
    check_pair,
)
from designlab.impact.peaks import first_peak
from designlab.impact.simulate import ImpactResponse, VelocityProfile, simulate
from designlab.params import Param, params_of
from designlab.results import OK, Result, Status
from designlab.units import STANDARD_GRAVITY

__all__ = [
    "LEVER_SAMPLES",
    "MANIPULATOR_1_JOINT_DATA",
    "REFERENCE_LEVER_ARM",
    "SPEED_RATIO",
    "ProfileChange",
    "Q2Effect",
    "WorstImpactPoint",
    "WorstPointStatus",
    "manipulator_1_recomputed",
    "profile_change",
    "q2_effect",
    "worst_impact_point",
]

#: Manipulator 1's joint data (Zeng 2011, App. A.2 and Sec. 4.3.1): inertia m_11 (kg m^2,
#: (A.2.5)), lever arm l_1 (m, Table 3.1), PD gains K_p (V/rad) and K_d (V s/rad), K_t K_amp
#: (N m/V) and the viscous friction B (N m s/rad).
MANIPULATOR_1_JOINT_DATA: dict[str, float] = {
    "inertia": 0.059,
    "lever_arm": 0.078,
    "k_p": 433.8,
    "k_d": 5.4,
    "torque_constant": 0.2807,
    "viscous_friction": 0.0079,
}


#: The joint-speed/head-speed ratio of Fig. 3.16, (rad/s)/(m/s) = 1/m.
SPEED_RATIO = Param(
    "theta_dot/v_h", "1/m", "joint-speed/head-speed ratio", ge=0, le=100,
    typical=(0.5, 2.3), name="speed_ratio",
)  # fmt: skip
#: The point compared with l -> 0 (the thesis's 0.01 m). Above 1 m the effective
#: manipulator of a thesis-sized link is so light that the first lobe need not close.
REFERENCE_LEVER_ARM = Param(
    "l_ref", "m", "the point compared with l -> 0", gt=0, le=1, typical=(0.01, 0.01),
    name="reference_lever_arm",
)  # fmt: skip
#: Grid points of the worst-impact-point search.
LEVER_SAMPLES = Param(
    None, "", "grid points of the lever-arm search", kind="integer", ge=3, le=100_000,
    name="samples",
)  # fmt: skip

_LINK = params_of(LinkImpact)


class WorstPointStatus(Status):
    """Status of :func:`worst_impact_point`.

    Attributes
    ----------
    OK
        The worst point is inside the range and every a_h,max is finite.
    AT_BOUND
        The worst point is an end of the lever-arm range: widen it.
    LOBE_NOT_CLOSED
        At the reference point or at l -> 0 the first lobe did not close: that
        a_h,max is NaN.
    """

    OK = "ok"
    AT_BOUND = "at_bound"
    LOBE_NOT_CLOSED = "lobe_not_closed"


def _pct(new: float, base: float) -> float:
    return 100.0 * (new / base - 1.0) if base != 0 else float("nan")


def _check_types(robot: Any, foam: Any, head: Any) -> None:
    if not isinstance(robot, ContactDynamics):
        raise InvalidParameterError("robot", robot, "must be a ContactDynamics")
    if not isinstance(foam, Foam):
        raise InvalidParameterError("foam", foam, "must be a Foam")
    if not isinstance(head, HeadNeck):
        raise InvalidParameterError("head", head, "must be a HeadNeck (the head moves)")


# --- Sec. 3.8: acceleration profiles -------------------------------------------------------


class _TwoImpacts(Result):
    """A result made of two impacts (the fields named in ``_impacts``): their status and
    warnings are its own."""

    _impacts: ClassVar[tuple[str, str]]

    @property
    def status(self) -> str:  # type: ignore[override]
        """``"ok"``, or the first status of the two impacts that is not."""
        responses = [getattr(self, name) for name in self._impacts]
        return next((str(r.status) for r in responses if r.status != OK), OK)

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """The two impacts' warnings, each once, in order."""
        responses = [getattr(self, name) for name in self._impacts]
        return tuple(dict.fromkeys(w for r in responses for w in r.warnings))


@dataclass(frozen=True)
class ProfileChange(_TwoImpacts):
    """Change of the impact metrics when the manipulator accelerates (Sec. 3.8).

    Attributes
    ----------
    base, profiled
        The impacts at constant velocity and with the acceleration profile.
    acceleration
        The manipulator's acceleration during the profile, m/s^2.
    feedforward
        Whether the controller compensates the acceleration by feed-forward.
    force_first_peak
        ``(base, profiled)`` first local maxima of the force, N (:func:`first_peak`).
    force_first_peak_time
        ``(base, profiled)`` times of those maxima, s.
    """

    base: ImpactResponse = field(repr=False)
    profiled: ImpactResponse = field(repr=False)
    acceleration: float
    feedforward: bool
    force_first_peak: tuple[float, float]
    force_first_peak_time: tuple[float, float]
    _impacts: ClassVar[tuple[str, str]] = ("base", "profiled")

    @property
    def a_h_max_pct(self) -> float:
        """Change of a_h,max, %."""
        return _pct(self.profiled.peak_head_acceleration, self.base.peak_head_acceleration)

    @property
    def force_first_peak_pct(self) -> float:
        """Change of the force's first local maximum (the thesis's "peak"), %."""
        return _pct(self.force_first_peak[1], self.force_first_peak[0])

    @property
    def force_lobe_max_pct(self) -> float:
        """Change of the force's first-lobe maximum (docs/impact.md, "Metrics"), %."""
        return _pct(self.profiled.peak_force, self.base.peak_force)

    def to_frame(self) -> pd.DataFrame:
        """One row: the inputs, both impacts' values and the changes in %."""
        return pd.DataFrame(
            {
                "v_c_m_per_s": [self.base.impact_velocity],
                "acceleration_g": [self.acceleration / STANDARD_GRAVITY],
                "feedforward": [self.feedforward],
                "a_h_max_g": [self.base.peak_head_acceleration_g],
                "a_h_max_profiled_g": [self.profiled.peak_head_acceleration_g],
                "f_c_first_peak_N": [self.force_first_peak[0]],
                "f_c_first_peak_profiled_N": [self.force_first_peak[1]],
                "f_c_lobe_max_N": [self.base.peak_force],
                "f_c_lobe_max_profiled_N": [self.profiled.peak_force],
                "d_a_h_max_pct": [self.a_h_max_pct],
                "d_f_c_first_peak_pct": [self.force_first_peak_pct],
                "d_f_c_lobe_max_pct": [self.force_lobe_max_pct],
                "status": [self.status],
            }
        )


def profile_change(
    robot: ContactDynamics,
    foam: Foam,
    head: HeadNeck,
    impact_velocity: float,
    acceleration: float,
    *,
    duration: float = 0.05,
    feedforward: bool = False,
) -> ProfileChange:
    """Changes of a_h,max and of the peak force under an acceleration profile (Sec. 3.8).

    The manipulator accelerates at ``acceleration`` for ``duration`` from the
    moment of contact (:class:`~designlab.impact.simulate.VelocityProfile`). The
    force is compared both at its first local maximum (the thesis's "peak",
    Sec. 3.6) and at its first-lobe maximum (docs/impact.md, "Metrics"): under acceleration
    the force can keep rising into its ramp after its peak, and the two differ.

    Parameters
    ----------
    robot
        Effective manipulator at the impact point (reduced joint).
    foam
        Foam covering.
    head
        Head-neck set (the head is free; the constrained case has no head speed).
    impact_velocity
        Closing velocity at contact v_c, m/s (> 0).
    acceleration
        The manipulator's acceleration during the profile, m/s^2 (negative: it
        decelerates).
    duration
        How long the acceleration lasts from contact, s (> 0).
    feedforward
        True if the controller compensates the acceleration (no tracking force).

    Returns
    -------
    ProfileChange

    Examples
    --------
    >>> import designlab as dl
    >>> head = dl.impact.TABLE_3_2_HEADS[3][1]
    >>> c = profile_change(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, head, 1.25,
    ...                    -0.51 * 9.80665, feedforward=True)        # reading (a), -0.51 g
    >>> round(c.force_first_peak_pct, 1), round(c.a_h_max_pct, 1)
    (-4.4, -3.8)
    """
    _check_types(robot, foam, head)
    v_c = IMPACT_VELOCITY.check(impact_velocity)
    if not isinstance(feedforward, bool):
        raise InvalidParameterError("feedforward", feedforward, "must be True or False")
    profile = VelocityProfile(acceleration, duration, feedforward)  # checks both
    a = profile.acceleration
    base = simulate(robot, foam, head, v_c)
    prof = simulate(robot, foam, head, v_c, profile=profile)
    (t0, f0), (t1, f1) = first_peak(base), first_peak(prof)
    return ProfileChange(base, prof, a, feedforward, (f0, f1), (t0, t1))


# --- Fig. 3.16: the worst impact point -----------------------------------------------------


@dataclass(frozen=True)
class WorstImpactPoint(Result):
    """The worst impact point along a link for one joint-speed/head-speed ratio (Fig. 3.16).

    Attributes
    ----------
    speed_ratio
        Joint speed (rad/s) over head speed (m/s), 1/m.
    head_speed
        Head speed toward the link, m/s.
    lever_arm
        Worst impact point l, m (continuous search).
    a_h_max_g
        a_h,max at the worst point, g.
    reference_lever_arm, a_h_max_reference_g
        The reference point (the thesis's 0.01 m) and its a_h,max, m and g.
    a_h_max_zero_g
        a_h,max as l -> 0 (v_c -> head speed, M_r, K_r, C_r -> infinity), g.
    grid, grid_a_h_max_g
        The search grid, m, and a_h,max on it, g.
    status
        A :class:`WorstPointStatus`: ``"ok"``, ``"at_bound"`` when the worst
        point is an end of the range, ``"lobe_not_closed"`` when a_h,max is NaN
        at the reference point or at l -> 0.
    warnings
        Notes (a worst point at an end of the range).
    """

    speed_ratio: float
    head_speed: float
    lever_arm: float
    a_h_max_g: float
    reference_lever_arm: float
    a_h_max_reference_g: float
    a_h_max_zero_g: float
    grid: NDArray[np.float64] = field(repr=False)
    grid_a_h_max_g: NDArray[np.float64] = field(repr=False)
    status: str = OK
    warnings: tuple[str, ...] = ()

    @property
    def change_at_zero_pct(self) -> float:
        """a_h,max at l -> 0 against the reference point, %."""
        return _pct(self.a_h_max_zero_g, self.a_h_max_reference_g)

    def to_frame(self) -> pd.DataFrame:
        """One row: the ratio, the worst point and the changes."""
        return pd.DataFrame(
            {
                "speed_ratio_per_m": [self.speed_ratio],
                "head_speed_m_per_s": [self.head_speed],
                "worst_l_m": [self.lever_arm],
                "a_h_max_worst_g": [self.a_h_max_g],
                "l_ref_m": [self.reference_lever_arm],
                "a_h_max_ref_g": [self.a_h_max_reference_g],
                "a_h_max_l0_g": [self.a_h_max_zero_g],
                "d_a_h_max_l0_vs_ref_pct": [self.change_at_zero_pct],
                "status": [self.status],
            }
        )


#: Lever arm standing in for l -> 0, m (a_h,max converges to its limit well before it).
_ZERO_LEVER = 1e-7


def worst_impact_point(
    inertia: float,
    joint_stiffness: float,
    joint_damping: float,
    speed_ratio: float,
    foam: Foam,
    head: HeadNeck,
    *,
    head_speed: float = 1.0,
    lever_range: tuple[float, float] = (0.001, 0.1),
    reference_lever_arm: float = 0.01,
    samples: int = 100,
) -> WorstImpactPoint:
    """Search the worst impact point along one joint's link (Sec. 3.7.3, Fig. 3.16).

    The head moves toward the link at ``head_speed`` and the joint turns at
    ``speed_ratio * head_speed`` rad/s, so v_c = head_speed (1 + speed_ratio l)
    (3.4.11). a_h,max is evaluated on a grid of ``samples`` lever arms and the
    best grid point is polished by a bounded scalar search. Because the model
    is linear in v_c, the worst point depends on ``speed_ratio`` only, and
    a_h,max scales with ``head_speed``.

    Parameters
    ----------
    inertia
        Joint inertia m_ii, kg m^2.
    joint_stiffness
        K_J, N m/rad.
    joint_damping
        C_J, N m s/rad.
    speed_ratio
        Joint speed over head speed, (rad/s)/(m/s) = 1/m (>= 0).
    foam
        Foam covering.
    head
        Head-neck set.
    head_speed
        Head speed toward the link, m/s (> 0).
    lever_range
        ``(low, high)`` lever arms searched, m (0 < low < high).
    reference_lever_arm
        Point compared with l -> 0, m (> 0 and <= 1; the thesis's 0.01 m).
    samples
        Grid points (>= 3).

    Returns
    -------
    WorstImpactPoint
        ``status`` is ``"at_bound"`` when the worst point is an end of the range.

    Examples
    --------
    >>> import designlab as dl
    >>> w = worst_impact_point(0.059, 121.68, 1.521, 0.5, dl.impact.FOAM_1, dl.impact.HEAD_MIN)
    >>> round(w.lever_arm, 3), round(w.change_at_zero_pct, 2)
    (0.008, -0.19)
    """
    m, k, c, ratio, v_h, lo, hi, l_ref, n = _worst_point_inputs(dict(locals()))

    def a_h(levers: NDArray[np.float64]) -> NDArray[np.float64]:
        sweep = impact_point_sweep(m, k, c, ratio * v_h, levers)
        return sweep.evaluate(foam, head, v_h)["a_h_max_g"].to_numpy()

    grid = np.linspace(lo, hi, n)
    values = a_h(grid)
    best_l, best, status = _polish_worst(a_h, grid, values)
    a_zero, a_ref = a_h(np.array([_ZERO_LEVER, l_ref]))
    warnings: tuple[str, ...] = ()
    if status == WorstPointStatus.AT_BOUND:
        warnings = (
            f"the worst point is at an end of the range {lo:g}-{hi:g} m; widen lever_range",
        )
    if not (np.isfinite(a_zero) and np.isfinite(a_ref)):
        status = WorstPointStatus.LOBE_NOT_CLOSED
        warnings = (
            *warnings,
            f"the first lobe did not close at l = {l_ref:g} m or l -> 0: a_h,max is NaN there",
        )
    return WorstImpactPoint(
        ratio, v_h, best_l, best, l_ref, float(a_ref), float(a_zero), grid, values, status,
        warnings,
    )  # fmt: skip


def _worst_point_inputs(
    args: dict[str, Any],
) -> tuple[float, float, float, float, float, float, float, float, int]:
    """The checked arguments of :func:`worst_impact_point` (``args``: its arguments by name),
    each against its declaration."""
    if not isinstance(args["foam"], Foam):
        raise InvalidParameterError("foam", args["foam"], "must be a Foam")
    if not isinstance(args["head"], HeadNeck):
        raise InvalidParameterError("head", args["head"], "must be a HeadNeck (the head moves)")
    lo, hi = check_pair(_LINK["lever_arm_min"], args["lever_range"], "lever_range")
    m, k, c = (_LINK[n].check(args[n], n) for n in ("inertia", "joint_stiffness", "joint_damping"))
    return (
        m,
        k,
        c,
        SPEED_RATIO.check(args["speed_ratio"]),
        HEAD_SPEED.check(args["head_speed"]),
        lo,
        hi,
        REFERENCE_LEVER_ARM.check(args["reference_lever_arm"]),
        LEVER_SAMPLES.check(args["samples"]),
    )


def _polish_worst(
    a_h: Any, grid: NDArray[np.float64], values: NDArray[np.float64]
) -> tuple[float, float, WorstPointStatus]:
    """The best grid point polished by a bounded scalar search (or an end of the range)."""
    from scipy.optimize import minimize_scalar

    j = int(np.nanargmax(values))
    if j in (0, grid.size - 1):
        return float(grid[j]), float(values[j]), WorstPointStatus.AT_BOUND
    res = minimize_scalar(
        lambda x: -float(a_h(np.array([x]))[0]),
        bounds=(float(grid[j - 1]), float(grid[j + 1])),
        method="bounded",
        options={"xatol": 1e-8},
    )
    best_l, best = (float(res.x), float(-res.fun))
    if best < values[j]:
        best_l, best = float(grid[j]), float(values[j])
    return best_l, best, WorstPointStatus.OK


# --- the printed q2 of (3.5.14) ----------------------------------------------------------


@dataclass(frozen=True)
class Q2Effect(_TwoImpacts):
    """The impact with the correct and with the printed q2 of (3.5.14) (docs/impact.md, "q2").

    Attributes
    ----------
    correct, printed
        The two simulated impacts.
    """

    correct: ImpactResponse = field(repr=False)
    printed: ImpactResponse = field(repr=False)
    _impacts: ClassVar[tuple[str, str]] = ("correct", "printed")

    def to_frame(self) -> pd.DataFrame:
        """One row per metric: correct and printed values and the change in %."""
        pairs = {
            "a_h_max_g": ("peak_head_acceleration_g", 1.0),
            "eps_max_m": ("max_compression", 1.0),
            "f_c_max_N": ("peak_force", 1.0),
            "t_imp_s": ("impact_duration", 1.0),
        }
        rows = []
        for name, (attr, _) in pairs.items():
            a, b = float(getattr(self.correct, attr)), float(getattr(self.printed, attr))
            rows.append({"metric": name, "correct": a, "printed": b, "change_pct": _pct(b, a)})
        return pd.DataFrame(rows)


def q2_effect(
    robot: ContactDynamics, foam: Foam, head: HeadNeck, impact_velocity: float
) -> Q2Effect:
    """Simulate one impact with the correct and with the printed q2 (docs/impact.md, "q2").

    The printed q2 of (3.5.14) lacks C_r C_h / (M_r M_h). It sits in the common
    denominator of every response, so the force and the compression change as
    well as a_h, although Fig. 3.10 cites the force of (3.5.11), which has no q2.

    Parameters
    ----------
    robot
        Effective manipulator at the impact point.
    foam
        Foam covering.
    head
        Head-neck set (q2 belongs to the free-head model).
    impact_velocity
        Closing velocity v_c, m/s (> 0).

    Returns
    -------
    Q2Effect

    Examples
    --------
    >>> import designlab as dl
    >>> e = q2_effect(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, dl.impact.HEAD_MIN, 1.25)
    >>> df = e.to_frame().set_index("metric")
    >>> bool(abs(df.loc["f_c_max_N", "change_pct"]) > 0.1)
    True
    """
    _check_types(robot, foam, head)
    v_c = IMPACT_VELOCITY.check(impact_velocity)
    return Q2Effect(
        simulate(robot, foam, head, v_c), simulate(robot, foam, head, v_c, q2="printed")
    )


# --- Table 3.1: Manipulator 1 from its joint data ------------------------------------------


def manipulator_1_recomputed() -> ContactDynamics:
    """Manipulator 1 of Table 3.1 recomputed from its joint data (App. A.2, (A.2.20)).

    K_J = K_t K_amp K_p, C_J = K_t K_amp K_d + B, then (3.4.17) at l_1 = 0.078 m.
    The result, M_r = 9.70 kg, K_r = 20.0 kN/m and C_r = 250 N s/m, differs from
    the printed M_r = 9.6 kg by 1 %: an error in the thesis's own arithmetic
    (0.059 / 0.078^2 = 9.70). The preset :data:`~designlab.impact.MANIPULATOR_1`
    keeps the printed values so that the thesis's tables are reproduced.

    Returns
    -------
    ContactDynamics
        Effective values at l_1, named ``"Manipulator 1 (recomputed)"``.

    Examples
    --------
    >>> r = manipulator_1_recomputed()
    >>> round(r.mass, 2), round(r.stiffness / 1e3, 1), round(r.damping)
    (9.7, 20.0, 250)
    """
    d = MANIPULATOR_1_JOINT_DATA
    k_j, c_j = joint_from_pd_gains(
        d["k_p"], d["k_d"], d["torque_constant"], viscous_friction=d["viscous_friction"]
    )
    e = scenario_single_joint(d["inertia"], k_j, c_j, d["lever_arm"])
    return ContactDynamics(
        e.mass, e.stiffness, e.damping, lever_arm=d["lever_arm"], name="Manipulator 1 (recomputed)"
    )
