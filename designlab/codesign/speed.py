"""Speed limit from safety: the fastest a robot may move so that any contact stays within limits.

For a foam-covered robot and a head-neck range, :func:`speed_limit` finds the
largest robot speed for which a contact with any head of the range meets every
criterion (head acceleration, force, HIC, ISO/TS 15066 force limits) and the
foam's thickness limit (eps_max <= lambda, so the foam never bottoms out). It
uses the impact package's worst-case evaluation
(:func:`designlab.impact.max_safe_velocity`'s problem: the worst head of a grid
over the range and, for a robot at joint level, the worst impact point along
the link), polishes a fixed robot's worst head off the grid with a bounded local
search (:mod:`designlab.codesign.worst_head`), and uses the linearity of the
model: every peak metric scales exactly as ``v_c ** e`` (``e = 1`` for acceleration,
force and compression, 2.5 for HIC), so the closing speed allowed by criterion
``i`` is ``(limit_i / metric_i(1 m/s)) ** (1/e)``.

The closing speed is split into the robot's and the head's parts (Zeng 2011,
Sec. 3.4, (3.4.13) at the worst angle gamma_c = 0): ``v_c = v_r + v_h``. With a
detection distance, a reaction time and a braking deceleration, the robot's
speed limit is the largest speed whose speed *at contact* stays within
``v_c - v_h`` (:mod:`designlab.codesign.braking`); without one (the default) a
contact comes without warning and the limit is ``v_c - v_h``.

What the model does not cover: head rotation (the head is a point mass on a
linear neck), the torso and the rest of the body, clamping (a head pinned
against a wall: use the impact package's ``constrained`` impact for force
criteria), nonlinear foam beyond its linear depth, and heads outside the range.

Examples
--------
>>> import designlab as dl
>>> s = dl.codesign.speed_limit(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1)
>>> s.limiting_criterion, round(s.closing_speed, 3), round(s.max_speed, 3)
('eps_max <= 20 mm', 1.807, 0.807)
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray
from scipy.optimize import brentq

from designlab.codesign.braking import max_robot_speed, stopping_distance
from designlab.codesign.parameters import (
    DECELERATION,
    DETECTION_DISTANCE,
    REACTION_TIME,
)
from designlab.codesign.worst_head import refine_link_worst, worst_heads
from designlab.errors import InvalidParameterError, ModelError
from designlab.impact import (
    THESIS_HEAD_RANGE,
    ContactDynamics,
    Criterion,
    Foam,
    FullJointContact,
    HeadNeck,
    HeadRange,
    LinkImpact,
)
from designlab.impact.conditioning import check_conditioning, time_scale_ratio
from designlab.impact.contact import CONTACTS, ContactModel, contact_of
from designlab.impact.criteria import CompressionLimit
from designlab.impact.general import CRUSHED
from designlab.impact.parameters import HEAD_LEVELS, HUMAN_SPEED, TIME_SCALE_RATIO
from designlab.impact.problem import FoamProblem, make_problem
from designlab.params import declared, param, params_of
from designlab.results import Result, Status

__all__ = ["SafetyCase", "SpeedLimit", "SpeedLimitStatus", "speed_limit"]

#: Largest closing speed the impact model takes, m/s (its declaration's cap).
_MAX_CLOSING_SPEED = 20.0


class SpeedLimitStatus(Status):
    """Status of :func:`speed_limit` and :func:`~designlab.codesign.speed_limit_map`.

    Attributes
    ----------
    OK
        A positive robot speed limit was found.
    UNSAFE_AT_REST
        No robot speed is safe: the person's own speed already exceeds a limit
        (``max_speed`` is 0).
    """

    OK = "ok"
    UNSAFE_AT_REST = "unsafe_at_rest"


@dataclass(frozen=True)
class SpeedLimit(Result):
    """Result of :func:`speed_limit`.

    Attributes
    ----------
    max_speed
        The robot's speed limit, m/s (for a :class:`~designlab.impact.LinkImpact`
        the speed of its farthest impact point, ``joint_speed * lever_arm_max``).
    closing_speed
        The largest closing speed v_c at contact, m/s (at the worst impact point).
    robot_speed, head_speed
        The split of ``closing_speed`` (Sec. 3.4): the robot's speed at contact
        ``v_c - v_h`` and the head's speed toward the robot ``v_h``, m/s.
    joint_speed
        For a LinkImpact, the largest joint speed, rad/s (NaN otherwise).
    limiting_criterion
        Name of the constraint that sets the limit.
    per_criterion
        Per constraint name: the largest closing speed it allows alone, m/s.
    worst_heads
        Per constraint name: the head-neck set at which it is worst.
    worst_lever_arm
        Per constraint name: the worst impact point, m (NaN for a fixed robot).
    unit_metric
        Per constraint name: its worst-case metric at v_c = 1 m/s (SI).
    reaction_time, deceleration, detection_distance
        The braking model (s, m/s^2, m; :mod:`designlab.codesign.braking`).
    stopping_distance
        Robot travel from detection to standstill at ``max_speed``, m.
    head_range
        The head-neck range searched.
    status
        A :class:`SpeedLimitStatus`.
    warnings
        What a user should know.
    """

    max_speed: float
    closing_speed: float
    robot_speed: float
    head_speed: float
    joint_speed: float
    limiting_criterion: str
    per_criterion: dict[str, float]
    worst_heads: dict[str, HeadNeck]
    worst_lever_arm: dict[str, float]
    unit_metric: dict[str, float]
    reaction_time: float
    deceleration: float
    detection_distance: float
    stopping_distance: float
    head_range: HeadRange
    status: str = SpeedLimitStatus.OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """One row per constraint: the closing speed it allows and its worst case.

        Returns
        -------
        pandas.DataFrame
        """
        names = list(self.per_criterion)
        heads = [self.worst_heads[n] for n in names]
        return pd.DataFrame(
            {
                "criterion": names,
                "v_c_max_m_per_s": [self.per_criterion[n] for n in names],
                "limiting": [n == self.limiting_criterion for n in names],
                "metric_at_1_m_per_s": [self.unit_metric[n] for n in names],
                "worst_M_h_kg": [h.mass for h in heads],
                "worst_K_h_N_per_m": [h.stiffness for h in heads],
                "worst_C_h_N_s_per_m": [h.damping for h in heads],
                "worst_lever_arm_m": [self.worst_lever_arm[n] for n in names],
            }
        )


@dataclass(frozen=True)
class Braking:
    """The checked braking model of a speed limit (:mod:`designlab.codesign.braking`)."""

    reaction_time: float
    deceleration: float
    detection_distance: float

    @classmethod
    def check(cls, reaction_time: float, deceleration: float, detection_distance: float) -> Braking:
        """Each value against its declaration."""
        return cls(
            REACTION_TIME.check(reaction_time),
            DECELERATION.check(deceleration),
            DETECTION_DISTANCE.check(detection_distance),
        )

    def notes(self) -> tuple[str, ...]:
        """A warning when the reaction time cannot act (no detection distance)."""
        if self.reaction_time > 0 and self.detection_distance == 0:
            return (
                "reaction_time has no effect without a detection_distance: the contact comes "
                "without warning and the robot meets the person at its full speed",
            )
        return ()

    def robot_limit(self, contact_limit: float, human_speed: float) -> float:
        """The robot speed whose contact speed is ``contact_limit`` (0 if negative)."""
        if contact_limit <= 0.0:
            return 0.0
        return max_robot_speed(
            contact_limit,
            human_speed=human_speed,
            reaction_time=self.reaction_time,
            deceleration=self.deceleration,
            detection_distance=self.detection_distance,
        )


@declared
@dataclass(frozen=True)
class SafetyCase:
    """What a speed limit answers for: the criteria, the people and the robot's braking.

    One declaration of the conditions shared by :func:`speed_limit`,
    :func:`~designlab.codesign.speed_limit_map` and :func:`~designlab.codesign.foam_limits`:
    the criteria every contact must meet (the foam's thickness limit is always added), the
    head-neck range and the head's speed toward the robot (Zeng 2011, Sec. 3.4), the
    robot's braking (:mod:`designlab.codesign.braking`) and how finely the worst head is
    sought.

    Examples
    --------
    >>> import designlab as dl
    >>> case = dl.codesign.SafetyCase(criteria=[dl.impact.HeadAcceleration(10)],
    ...                               human_speed=0.0)
    >>> case.human_speed, case.head_levels, case.braking.deceleration
    (0.0, 3, 10.0)
    """

    criteria: Sequence[Criterion] | None = param(
        kind="object", optional=True, default=None,
        doc="safety criteria (the foam's thickness limit is always added)",
        none="a_h,max <= 10 g",
    )  # fmt: skip
    head_range: HeadRange | None = param(  # noqa: RUF009 (a declaration)
        kind="object", optional=True, default=None,
        doc="head-neck range whose worst head sets the limit",
        none="the thesis's ranges (Sec. 3.5)",
    )  # fmt: skip
    human_speed: float = HUMAN_SPEED.field(default=1.0)
    reaction_time: float = REACTION_TIME.field()
    deceleration: float = DECELERATION.field()
    detection_distance: float = DETECTION_DISTANCE.field()
    head_levels: int = HEAD_LEVELS.field()

    @property
    def braking(self) -> Braking:
        """The robot's braking model."""
        return Braking(self.reaction_time, self.deceleration, self.detection_distance)

    @classmethod
    def of(cls, case: object) -> SafetyCase:
        """``case`` itself, or the default case for ``None``; anything else is refused.

        Parameters
        ----------
        case
            The object given as the case.
        """
        if case is None:
            return cls()
        if not isinstance(case, SafetyCase):
            raise InvalidParameterError(
                "case", case, "must be a dl.codesign.SafetyCase (or None: the default case)"
            )
        return case


def check_robot_foam(robot: object, foam: object, *, scaling: bool = False) -> ContactModel:
    """The contact model of the robot (fixed, full joint or a link) and the foam of a co-design
    answer; a pair whose speed limit is not served is refused by the model's capabilities.

    A linear contact's metrics scale as a power of v_c (its speed limits are closed form); an
    integrated (non-linear) one's are found on the general path, for a fixed robot.

    Parameters
    ----------
    robot
        The object given as the robot.
    foam
        The object given as the foam.
    scaling
        The caller scales the metrics with v_c (a linear contact's closed form) and has no
        integrated path: a non-linear contact is refused.

    Returns
    -------
    ContactModel
    """
    if foam is None:  # contact_of reads None as "the linear foam, not known yet"
        raise InvalidParameterError("foam", foam, "must be a foam (e.g. dl.impact.FOAM_1)")
    contact = contact_of(robot, foam)
    if not contact.linear and scaling:
        raise InvalidParameterError(
            "foam", type(foam).__name__, f"this answer scales the metrics with v_c, which only "
            f"a linear contact {list(CONTACTS.choices(linear=True))} allows; the "
            f"{contact.name} contact ({contact.label}) is served by speed_limit, the impact "
            "package's envelope and simulate",
        )  # fmt: skip
    if not contact.linear and robot.along_link:  # type: ignore[attr-defined]
        raise InvalidParameterError(
            "robot", type(robot).__name__, f"a robot struck along its link is served with a "
            f"linear contact {list(CONTACTS.choices(linear=True))}; the {contact.name} contact "
            f"({contact.label}) serves a fixed robot (ContactDynamics)",
        )  # fmt: skip
    return contact


def problem_for(
    robot: ContactDynamics | FullJointContact | LinkImpact,
    case: SafetyCase,
    max_compression: float,
    foam: object | None = None,
) -> FoamProblem:
    """The impact package's worst-case problem at v_c = 1 m/s (a link: at its joint speed).

    Parameters
    ----------
    robot
        As in :func:`speed_limit`.
    case
        The criteria, head range, walker's speed and worst-head grid (:class:`SafetyCase`).
    max_compression
        lambda, m.
    foam
        A non-linear foam (its law's other parameters kept), or ``None``: the linear foam.

    Returns
    -------
    FoamProblem
    """
    head_range = THESIS_HEAD_RANGE if case.head_range is None else case.head_range
    v = None if robot.along_link else 1.0
    prob = make_problem(
        robot, v, case.criteria, max_compression, head_range, False, case.human_speed, 0.05, foam
    )
    prob.head_levels = case.head_levels
    return prob


def _check_served(prob: FoamProblem, foam: Foam) -> None:
    """Refuse up front, naming the robot's or the foam's parameter, a fixed robot and foam
    whose impact with a head of the worst-head grid double precision cannot serve (a damping
    of 1e6 N s/m gave NaN metrics and ``contact_limit = nan``; docs/impact.md, "Limits")."""
    if prob.robot.along_link:
        _check_link_served(prob, foam)
        return
    k, c = np.array([foam.stiffness]), np.array([foam.damping])
    for key in prob.keys():
        params = prob.designs(key, k, c)[0]
        check_conditioning(params, prob.contact.columns,
                           labels=prob.contact.input_labels(None))  # fmt: skip


#: Lever arms (geometric, ends included) at which a link's conditioning is checked up front:
#: the ratio of its time scales changes smoothly with the lever arm (every robot value
#: scales as 1/l^2), and the search's lever grid has 17.
_LINK_CHECK_LEVERS = 65


def link_labels(robot: LinkImpact) -> tuple[str | None, ...]:
    """The names of a link's inputs in the order of the model's row at a lever arm (``None``
    for the worst-head grid's columns, never blamed): a conditioning refusal names them.

    Examples
    --------
    >>> import designlab as dl
    >>> link_labels(dl.impact.LinkImpact(1.0, 10.0, 1.0, 1.0, 0.1, 0.5))[:3]
    ('robot.inertia', 'robot.joint_damping', 'robot.joint_stiffness')
    """
    return contact_of(robot).input_labels(None, along_link=True)


def _check_link_served(prob: FoamProblem, foam: Foam) -> None:
    """Refuse a link whose effective manipulator, at some lever arm of its range, double
    precision cannot serve with a head of the worst-head grid, naming the link's own
    parameter (``robot.joint_damping``) and its value, not the effective ``C_J/l^2``."""
    robot = prob.robot
    levers = np.geomspace(robot.lever_arm_min, robot.lever_arm_max, _LINK_CHECK_LEVERS)
    k, c = np.full(levers.size, foam.stiffness), np.full(levers.size, foam.damping)
    for key in prob.keys():
        params, _, nh = prob.designs(key, k, c, levers)
        bad = ~(time_scale_ratio(params, prob.constrained) <= TIME_SCALE_RATIO.le)
        if not np.any(bad):
            continue
        j = int(np.flatnonzero(bad)[0])
        try:
            check_conditioning(params[j : j + 1], prob.contact.columns,
                               constrained=prob.constrained, labels=link_labels(robot))  # fmt: skip
        except InvalidParameterError as exc:
            lever = float(levers[j // nh])
            owner, field = exc.name.split(".", 1)
            at = (
                f"at the lever arm l = {lever:.4g} m (of robot.lever_arm_min = "
                f"{robot.lever_arm_min:g} .. robot.lever_arm_max = {robot.lever_arm_max:g} m)"
            )
            if owner != "robot":
                raise InvalidParameterError(exc.name, exc.value, f"{at}: {exc.allowed}",
                                            exc.unit) from None  # fmt: skip
            decl = params_of(type(robot))[field]
            raise InvalidParameterError(
                exc.name, getattr(robot, field),
                f"{at} its effective value {decl.symbol}/l^2 = {exc.value:.4g} {exc.unit} "
                f"(Sec. 3.4.3), {exc.allowed}; a larger robot.lever_arm_min or a smaller "
                f"{exc.name} is served",
                decl.unit,
            ) from None  # fmt: skip
        raise AssertionError("time_scale_ratio and check_conditioning disagree")  # pragma: no cover


def _worst_head(prob: FoamProblem, key: Criterion, foam: Foam, lever: float) -> HeadNeck:
    """The head of the grid at which ``key`` is worst (for a link, at ``lever``)."""
    k, c = np.array([foam.stiffness]), np.array([foam.damping])
    levers = None if math.isnan(lever) else np.array([lever])
    params, vv, _ = prob.designs(key, k, c, levers)
    j = int(np.argmax(prob.contact.values(key, params, vv)))
    return HeadNeck(**prob.contact.head_values(params[j]))


def allowed_closing_speeds(
    prob: FoamProblem, k: NDArray[np.float64], c: NDArray[np.float64],
    depth: NDArray[np.float64], refine: bool,
) -> list[tuple[Criterion, NDArray[np.float64], list[HeadNeck], NDArray[np.float64]]]:  # fmt: skip
    """Per constraint of a fixed robot, for foams ``(k[i], c[i])`` in one lock-step search:
    the worst metric at v_c = 1 m/s, its head, and the closing speed allowed.

    Every metric scales as ``v_c ** e``, so the closing speed allowed is
    ``(limit / metric(1 m/s)) ** (1/e)`` (infinite where the metric is 0 or NaN); the
    compression limit is each foam's own linear depth ``depth[i]``.

    Parameters
    ----------
    prob
        The worst-case problem (:func:`problem_for`).
    k, c, depth
        Foam stiffnesses, dampings and linear depths, paired.
    refine
        Polish the worst heads off the grid (:func:`~designlab.codesign.worst_head.worst_heads`).

    Returns
    -------
    list
        ``(criterion, metric, heads, v_c allowed)`` per constraint.
    """
    out = []
    for key in prob.keys():
        vals, heads = worst_heads(prob, key, k, c, refine)
        vals = np.asarray(vals, dtype=float)
        limit = depth if isinstance(key, CompressionLimit) else key.limit
        pos = vals > 0
        v = np.full(vals.shape, math.inf)
        v[pos] = (np.broadcast_to(limit, vals.shape)[pos] / vals[pos]) ** (
            1.0 / key.velocity_exponent
        )
        out.append((key, vals, heads, v))
    return out


def _fixed_limits(
    prob: FoamProblem, foam: Foam, refine: bool
) -> dict[str, tuple[float, float, HeadNeck]]:
    """Per constraint of a fixed robot: (v_c allowed, metric at 1 m/s, worst head)."""
    k, c = np.array([foam.stiffness]), np.array([foam.damping])
    out = {}
    for key, vals, heads, v in allowed_closing_speeds(
        prob, k, c, np.array([foam.linear_depth]), refine
    ):
        if math.isnan(vals[0]):
            _refuse_open_lobe(prob, foam, key)
        out[key.name] = (float(v[0]), float(vals[0]), heads[0])
    return out


def integrated_limits(prob: FoamProblem, foam: object) -> dict[str, tuple[float, float, HeadNeck]]:
    """Per constraint of a fixed robot with an integrated (non-linear) contact: (v_c allowed,
    metric at 1 m/s, worst head at that v_c).

    The metrics of a non-linear law do not scale with v_c, so the allowed v_c is the root
    (Brent, to 1e-6 relative) of ``log(worst metric / limit)`` over ``(0, 20]`` m/s, the
    worst taken over the head grid at each v_c (no off-grid polish); the metric is taken to
    rise with v_c, as an impact's a_h, force and compression do.

    Parameters
    ----------
    prob
        The problem (:func:`problem_for` with the foam).
    foam
        The non-linear foam.

    Returns
    -------
    dict
    """
    k, c = np.array([foam.stiffness]), np.array([foam.damping])  # type: ignore[attr-defined]
    out = {}
    for key in prob.keys():
        params, _, _ = prob.designs(key, k, c)

        def worst(v: float, key: Criterion = key, params: NDArray = params) -> tuple[float, int]:
            vals = prob.contact.values(key, params, np.full(len(params), v))
            if np.any(np.isnan(vals)):
                _refuse_open_lobe(prob, foam, key)  # type: ignore[arg-type]
            j = int(np.argmax(vals))
            return float(vals[j]), j

        def excess(v: float, key: Criterion = key, worst: Any = worst) -> float:
            return float(np.clip(np.log(max(worst(v)[0], 1e-300) / key.limit), -50.0, 50.0))

        m1 = worst(1.0)[0]
        lo, top = 1e-3, _MAX_CLOSING_SPEED
        if excess(lo) > 0:
            v = 0.0
        elif excess(top) <= 0:
            v = math.inf
        else:
            v = float(brentq(excess, lo, top, xtol=1e-9, rtol=1e-6))
        j = worst(v if math.isfinite(v) and v > 0 else 1.0)[1]
        out[key.name] = (v, m1, HeadNeck(**prob.contact.head_values(params[j])))
    return out


def _link_excess(
    prob: FoamProblem, key: Criterion, foam: Foam, omega: float
) -> tuple[float, float]:
    """``log(worst metric / limit)`` of a link at joint speed ``omega``, and the worst lever."""
    robot = dataclasses.replace(prob.robot, joint_speed=omega)
    at = dataclasses.replace(prob, robot=robot)
    vals, lev = at.worst(key, np.array([foam.stiffness]), np.array([foam.damping]))
    return math.log(max(float(vals[0]), 1e-300) / key.limit), float(lev[0])


def _refuse_open_lobe(prob: FoamProblem, foam: Foam, key: Criterion) -> None:
    """Refuse, naming the robot's inputs, a robot and foam whose first impact lobe's end the
    model does not find (metrics NaN, status ``lobe_not_closed``, docs/impact.md) for a head
    of the grid: no speed limit can be derived from a metric the model cannot give."""
    shown = ", ".join(
        f"robot.{name} = {getattr(prob.robot, name):g}"
        for name, d in params_of(type(prob.robot)).items()
        if d.kind != "text" and isinstance(getattr(prob.robot, name), (int, float))
    )
    raise ModelError(
        f"robot ({shown}) with foam.stiffness = {foam.stiffness:g} N/m and foam.damping = "
        f"{foam.damping:g} N s/m: the impact model finds no end of the first impact lobe "
        f"within its search for a head of the worst-head grid (status lobe_not_closed, "
        f"{key.name} is NaN; docs/impact.md, "
        '"Metrics"), so no speed limit follows from it; served are the robots and foams '
        "whose impact_metrics status is ok for every head of the head_range"
    )


def _link_joint_speed(prob: FoamProblem, key: Criterion, foam: Foam, top_speed: float) -> float:
    """The largest joint speed at which the grid's worst case of a link meets ``key``.

    The worst metric rises with the joint speed (``v_c = theta_dot l + v_h`` at every
    point), so it is a root of ``log(metric / limit)`` (Brent).
    """
    at_rest, _ = _link_excess(prob, key, foam, 0.0)
    top, _ = _link_excess(prob, key, foam, top_speed)
    if math.isnan(at_rest) or math.isnan(top):
        _refuse_open_lobe(prob, foam, key)
    if at_rest > 0:
        return 0.0
    if top <= 0:
        return top_speed
    return float(brentq(lambda w: _link_excess(prob, key, foam, w)[0], 0.0, top_speed,
                        xtol=1e-12, rtol=1e-10))  # fmt: skip


#: Rounds of the off-grid correction of a link's joint speed (each lowers it).
_LINK_ROUNDS = 8


def _link_limits(
    prob: FoamProblem, foam: Foam, refine: bool
) -> dict[str, tuple[float, float, float, HeadNeck | None]]:
    """Per constraint of a link: (joint speed allowed, v_c at its worst point, lever, head).

    With ``refine``, the worst impact point and head are then sought off the grids together
    (:func:`~designlab.codesign.worst_head.refine_link_worst`); at a fixed point and head
    the metric scales exactly as ``v_c ** e``, so a worse case found lowers the joint speed
    in closed form, and the search repeats at the lower speed until it finds none.
    """
    out = {}
    v_h = prob.human_speed
    top_speed = (_MAX_CLOSING_SPEED - v_h) / prob.robot.lever_arm_max
    for key in prob.keys():
        omega = _link_joint_speed(prob, key, foam, top_speed)
        _, lever = _link_excess(prob, key, foam, omega)
        head = None
        for _ in range(_LINK_ROUNDS if refine and omega > 0 else 0):
            at = dataclasses.replace(prob, robot=dataclasses.replace(prob.robot, joint_speed=omega))
            vals, lev = at.worst(key, np.array([foam.stiffness]), np.array([foam.damping]))
            m, lv, h = refine_link_worst(at, key, foam, float(lev[0]), float(vals[0]))
            if h is None or m <= key.limit * (1.0 + 1e-12):
                break
            allowed = (omega * lv + v_h) * (key.limit / m) ** (1.0 / key.velocity_exponent)
            omega, lever, head = max((allowed - v_h) / lv, 0.0), lv, h
        out[key.name] = (omega, omega * lever + v_h, lever, head)
    return out


def speed_limit(
    robot: ContactDynamics | FullJointContact | LinkImpact,
    foam: Foam,
    case: SafetyCase | None = None,
    *,
    refine: bool = True,
) -> SpeedLimit:
    """The largest robot speed for which any contact meets every criterion.

    Parameters
    ----------
    robot
        The effective manipulator at the impact point (a
        :class:`~designlab.impact.ContactDynamics` or
        :class:`~designlab.impact.FullJointContact`), or a
        :class:`~designlab.impact.LinkImpact` struck anywhere along its link.
    foam
        The foam covering; its linear depth is the thickness limit. A non-linear foam
        (:class:`~designlab.impact.HuntCrossleyFoam`,
        :class:`~designlab.impact.StressStrainFoam`) takes the general response path: the
        depth its law holds to (less :data:`~designlab.impact.general.CRUSHED`: a crushed
        foam exceeds it) is the limit, each criterion's v_c a root on the head grid
        (:func:`integrated_limits`; a fixed robot only).
    case
        The criteria, the head-neck range and the head's speed toward the robot, the
        robot's braking and the worst-head grid (:class:`SafetyCase`; ``None``: its
        defaults, a_h,max <= 10 g for the thesis's heads walking at 1 m/s, no warning).
        For ISO/TS 15066 transient contact with the head, state the factor:
        ``IsoTransientForce("skull_forehead", transient_factor=2.0)``.
    refine
        Polish each criterion's worst head off the grid with a bounded local search
        (:mod:`designlab.codesign.worst_head`; for a link, the head and the impact point
        together, lowering the joint speed when a worse case is found).

    Returns
    -------
    SpeedLimit

    Examples
    --------
    >>> import designlab as dl
    >>> crit = [dl.impact.HeadAcceleration(10), dl.impact.HeadInjuryCriterion(650)]
    >>> case = dl.codesign.SafetyCase(criteria=crit, human_speed=0.0)
    >>> s = dl.codesign.speed_limit(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, case)
    >>> s.limiting_criterion, round(s.max_speed, 3)
    ('eps_max <= 20 mm', 1.807)
    """
    contact = check_robot_foam(robot, foam)
    case = SafetyCase.of(case)
    # a non-linear law (the general path) is held to the depth it is valid to; a crushed
    # foam exceeds it
    depth = foam.linear_depth if contact.linear else contact.valid_depth(foam) * (1 - CRUSHED)
    prob = problem_for(robot, case, depth, None if contact.linear else foam)
    brake = case.braking
    if not isinstance(refine, (bool, np.bool_)):
        raise InvalidParameterError("refine", refine, "must be True or False")
    if not contact.linear:  # no scaling with v_c: a root per criterion
        return _summarise_fixed(prob, foam, brake, integrated_limits(prob, foam))
    _check_served(prob, foam)
    if robot.along_link:
        return _summarise_link(prob, foam, brake, _link_limits(prob, foam, bool(refine)))
    return _summarise_fixed(prob, foam, brake, _fixed_limits(prob, foam, bool(refine)))


def _link_heads(
    prob: FoamProblem, foam: Foam, lim: dict[str, tuple[float, float, float, HeadNeck | None]]
) -> dict[str, HeadNeck]:
    """The worst head of each constraint of a link: off the grid, or the grid's at its lever."""
    out = {}
    for key in prob.keys():
        omega, _, lever, head = lim[key.name]
        if head is None:
            at = dataclasses.replace(prob, robot=dataclasses.replace(prob.robot, joint_speed=omega))
            head = _worst_head(at, key, foam, lever)
        out[key.name] = head
    return out


def _summarise_fixed(
    prob: FoamProblem, foam: Foam, brake: Braking, lim: dict[str, tuple[float, float, HeadNeck]]
) -> SpeedLimit:
    """The speed limit of a fixed robot from the per-constraint closing speeds."""
    per = {n: v for n, (v, _, _) in lim.items()}
    limiting = min(per, key=lambda n: per[n])
    v_c = per[limiting]
    v_h = prob.human_speed
    robot_speed = v_c - v_h
    status, warnings = _status(robot_speed, v_h, limiting)
    warnings += brake.notes()
    speed = brake.robot_limit(robot_speed, v_h)
    return SpeedLimit(
        max_speed=speed, closing_speed=v_c, robot_speed=robot_speed, head_speed=v_h,
        joint_speed=math.nan, limiting_criterion=limiting, per_criterion=per,
        worst_heads={n: h for n, (_, _, h) in lim.items()},
        worst_lever_arm={n: math.nan for n in per},
        unit_metric={n: m for n, (_, m, _) in lim.items()},
        reaction_time=brake.reaction_time, deceleration=brake.deceleration,
        detection_distance=brake.detection_distance,
        stopping_distance=stopping_distance(speed, brake.reaction_time, brake.deceleration),
        head_range=prob.head_range, status=status, warnings=warnings,
    )  # fmt: skip


def _summarise_link(
    prob: FoamProblem,
    foam: Foam,
    brake: Braking,
    lim: dict[str, tuple[float, float, float, HeadNeck | None]],
) -> SpeedLimit:
    """The speed limit of a link from the per-constraint joint speeds."""
    omegas = {n: w for n, (w, _, _, _) in lim.items()}
    limiting = min(omegas, key=lambda n: omegas[n])
    omega, v_c, _, _ = lim[limiting]
    v_h = prob.human_speed
    levers = {n: lv for n, (_, _, lv, _) in lim.items()}
    status, warnings = _status(omega, v_h, limiting)
    if brake.detection_distance > 0:
        warnings += ("the braking model is not applied to a LinkImpact (a joint speed limit)",)
    speed = omega * prob.robot.lever_arm_max
    return SpeedLimit(
        max_speed=speed, closing_speed=v_c, robot_speed=v_c - v_h, head_speed=v_h,
        joint_speed=omega, limiting_criterion=limiting,
        per_criterion={n: v for n, (_, v, _, _) in lim.items()},
        worst_heads=_link_heads(prob, foam, lim), worst_lever_arm=levers,
        unit_metric={n: math.nan for n in omegas},
        reaction_time=brake.reaction_time, deceleration=brake.deceleration,
        detection_distance=brake.detection_distance,
        stopping_distance=stopping_distance(speed, brake.reaction_time, brake.deceleration),
        head_range=prob.head_range, status=status, warnings=warnings,
    )  # fmt: skip


def _status(robot_part: float, human_speed: float, limiting: str) -> tuple[str, tuple[str, ...]]:
    """``unsafe_at_rest`` when the robot may not move at all."""
    if robot_part > 0:
        return SpeedLimitStatus.OK, ()
    return SpeedLimitStatus.UNSAFE_AT_REST, (
        f"no robot speed is safe: a person moving at {human_speed:g} m/s into the robot at "
        f"rest alone exceeds {limiting}",
    )
