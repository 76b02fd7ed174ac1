"""Simulate one impact: exact time histories and first-lobe metrics.

:func:`simulate` evaluates the closed-form (modal) solution of the linear model
of :mod:`designlab.impact.model`, so the time histories are exact at every
sample and the metrics are located to machine precision, not on a grid.

Manipulator acceleration or deceleration during the impact (Zeng 2011, Sec. 3.8)
is a :class:`VelocityProfile`: the desired manipulator speed changes linearly
over ``duration`` and stays constant after. With ``feedforward=True`` the
controller compensates the desired acceleration (the term M_r x_d_dd in
(3.5.2)); without it, the desired acceleration loads the manipulator's
deflection. The response is then a superposition of delayed ramp, step and
parabola responses, all exact.

Examples
--------
>>> import designlab as dl
>>> r = dl.impact.simulate(dl.impact.ContactDynamics(mass=9.6, stiffness=20e3, damping=250.0),
...                        dl.impact.Foam(stiffness=24.25e3, damping=71.9, linear_depth=0.02),
...                        dl.impact.HeadNeck(mass=4.4, stiffness=4e3, damping=0.0),
...                        impact_velocity=1.25)
>>> round(r.peak_head_acceleration_g, 2), round(r.impact_duration, 4), r.bottoming
(6.57, 0.0332, False)
>>> round(float(r.force[0]), 3)        # f_c(0+) = C_c v_c
89.875
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError, check_finite
from designlab.impact.conditioning import check_conditioning
from designlab.impact.contact import CONTACTS, ContactModel, contact_of
from designlab.impact.general import GENERAL_RTOL, GeneralStatus, integrator_note
from designlab.impact.metrics import (
    STATUS_OK,
    STATUS_PEAK_AT_CONTACT,
    ImpactStatus,
    metrics_of_matrix,
)
from designlab.impact.modal import ModalResponse, poles_of
from designlab.impact.model import printed_q2_correction
from designlab.impact.parameters import (
    HIC_WINDOW,
    SIMULATION_DURATION,
    SIMULATION_SAMPLES,
    STOP_TIME,
    ContactDynamics,
    Foam,
    HeadNeck,
    check_closing_velocity,
)
from designlab.impact.series_joint import FullJointContact
from designlab.impact.state_space import modal_families
from designlab.params import declared, param
from designlab.results import Result
from designlab.units import STANDARD_GRAVITY

__all__ = ["ImpactResponse", "VelocityProfile", "hic", "simulate"]

_OUTPUTS = ("force", "head_acceleration", "compression", "head_velocity", "robot_deflection")
_METRIC_OUTPUTS = ("force", "head_acceleration", "compression")


@declared
@dataclass(frozen=True)
class VelocityProfile:
    """Manipulator acceleration during the impact (Sec. 3.8, Fig. 3.17).

    The desired manipulator speed changes at ``acceleration`` (m/s^2, negative to
    decelerate) for ``duration`` s from the instant of contact, then stays constant.

    Examples
    --------
    >>> round(VelocityProfile(acceleration=0.51 * 9.80665, duration=0.05).delta_v, 4)
    0.25
    """

    acceleration: float = param(
        "a_d", "m/s^2", doc="manipulator acceleration during the impact (negative: braking)",
        ge=-1e3, le=1e3, typical=(-5.0, 5.0),
    )  # fmt: skip
    duration: float = param(
        "T_a", "s", doc="how long the acceleration lasts from contact", gt=0, le=1.0,
        default=0.05, typical=(0.05, 0.05),
    )  # fmt: skip
    feedforward: bool = param(
        kind="flag", default=True, doc="the controller feeds the acceleration forward (Sec. 3.8)"
    )

    @property
    def delta_v(self) -> float:
        """Change of manipulator speed over the profile, m/s."""
        return self.acceleration * self.duration


def hic(t: NDArray, head_acceleration: NDArray, window: float = HIC_WINDOW.default) -> float:
    """Head Injury Criterion by the standard definition (docs/impact.md, "HIC").

    ``HIC = max (t2 - t1) [ (1/(t2 - t1)) int_{t1}^{t2} a dt ]^2.5`` over
    ``0 < t2 - t1 <= window``, with ``a`` in g. The integral is taken with the
    trapezoid rule on the samples given; segments with a non-positive mean are
    skipped.

    Parameters
    ----------
    t
        Sample times, s (1-D, increasing).
    head_acceleration
        Head acceleration at ``t``, m/s^2 (converted to g with standard gravity).
    window
        Largest window t2 - t1, s: 0.015 (HIC15) or 0.036 (HIC36).

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 0.03, 3001)
    >>> a = np.full_like(t, 10 * 9.80665)   # 10 g held for 30 ms
    >>> round(hic(t, a, 0.015), 2)          # 0.015 * 10**2.5
    4.74
    """
    t = np.asarray(t, dtype=float)
    a = np.asarray(head_acceleration, dtype=float) / STANDARD_GRAVITY
    if t.ndim != 1 or t.shape != a.shape or t.size < 2:
        raise InvalidParameterError("t", t.shape, "t and head_acceleration need the same 1-D shape")
    if not window > 0:
        raise InvalidParameterError("window", window, "must be > 0", "s")
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * np.diff(t))])
    best = 0.0
    n = t.size
    dt_min = float(np.min(np.diff(t)))
    max_lag = min(n - 1, math.ceil(window / max(dt_min, 1e-12)) + 1)
    for lag in range(1, max_lag + 1):
        dur = t[lag:] - t[:-lag]
        ok = dur <= window * (1 + 1e-12)
        if not np.any(ok):
            break
        mean = (cum[lag:] - cum[:-lag])[ok] / dur[ok]
        pos = mean > 0
        if np.any(pos):
            best = max(best, float(np.max(dur[ok][pos] * mean[pos] ** 2.5)))
    return best


@dataclass(frozen=True)
class ImpactResponse(Result):
    """Time histories and first-lobe metrics of one impact (SI units).

    Attributes
    ----------
    t
        Sample times, s, from the instant of contact.
    force, head_acceleration, compression
        f_c (N), a_h (m/s^2) and eps (m) at ``t``.
    head_velocity, robot_deflection
        Head velocity relative to the torso (m/s) and manipulator deflection
        x_r - x_d (m) at ``t``.
    peak_head_acceleration, max_compression, peak_force, impact_duration
        First-lobe metrics (docs/impact.md, "Metrics") in m/s^2, m, N, s.
    bottoming
        ``max_compression > foam.linear_depth``: the linear foam model is used
        outside its valid range and the numbers are not to be trusted (I7).
    status
        An :class:`~designlab.impact.metrics.ImpactStatus`: ``"ok"``, ``"no_impact"``,
        ``"peak_at_contact"`` (overdamped pulse),
        ``"bottoming"`` or ``"lobe_not_closed"``.
    warnings
        Human-readable notes on the validity of the result.
    robot
        The effective manipulator.
    foam
        The foam.
    head
        The head-neck (``None``: constrained head).
    impact_velocity
        Closing speed v_c in m/s.
    time_of_peak_acceleration
        Time of the peak head acceleration in s.
    time_of_max_compression
        Time of the largest compression in s.
    time_of_peak_force
        Time of the peak contact force in s.
    profile
        The manipulator's velocity profile during the impact, if any (Sec. 3.8).
    q2
        The q2 option of the model (``"correct"`` or ``"printed"``; docs/impact.md).
    """

    robot: ContactDynamics | FullJointContact
    foam: Foam
    head: HeadNeck | None
    impact_velocity: float
    t: NDArray[np.float64]
    force: NDArray[np.float64]
    head_acceleration: NDArray[np.float64]
    compression: NDArray[np.float64]
    head_velocity: NDArray[np.float64]
    robot_deflection: NDArray[np.float64]
    peak_head_acceleration: float
    max_compression: float
    peak_force: float
    impact_duration: float
    time_of_peak_acceleration: float
    time_of_max_compression: float
    time_of_peak_force: float
    status: str
    warnings: tuple[str, ...] = ()
    profile: VelocityProfile | None = None
    q2: str = "correct"
    _lobe: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def peak_head_acceleration_g(self) -> float:
        """a_h,max in g (standard gravity, 9.80665 m/s^2)."""
        return self.peak_head_acceleration / STANDARD_GRAVITY

    def __repr__(self) -> str:
        return (
            f"ImpactResponse(v_c={self.impact_velocity:g} m/s, "
            f"a_h,max={self.peak_head_acceleration_g:.4g} g, "
            f"eps_max={1e3 * self.max_compression:.4g} mm, f_c,max={self.peak_force:.4g} N, "
            f"t_imp={1e3 * self.impact_duration:.4g} ms, status={self.status!r}, "
            f"{self.t.size} samples)"
        )

    @property
    def bottoming(self) -> bool:
        """Whether the foam is compressed beyond the depth where its law holds (I7): the
        linear depth lambda of a linear foam."""
        return bool(self.max_compression > contact_of(self.robot, self.foam).valid_depth(self.foam))

    @property
    def constrained(self) -> bool:
        """Whether the head was against a wall (K_h -> infinity)."""
        return self.head is None

    def hic(self, window: float = HIC_WINDOW.default, samples: int = 3001) -> float:
        """HIC over the first impact lobe (HIC15 by default, 0.036 for HIC36).

        The head acceleration is re-sampled exactly on ``samples`` points of
        ``[0, impact_duration]``; the model has no meaning after the first lobe.
        """
        if self.constrained or self.impact_duration <= 0:
            return 0.0
        t = np.linspace(0.0, self.impact_duration, samples)
        a = self._lobe["evaluate"](t)["head_acceleration"]
        return hic(t, a, window)

    def summary(self, max_rows: int = 10) -> str:
        """A short text: status, warnings and the scalar metrics (:meth:`metrics`).

        Parameters
        ----------
        max_rows
            Unused (the scalar metrics are always shown); kept for the
            :class:`~designlab.results.Result` interface.
        """
        head = f"ImpactResponse: status {self.status}, {len(self.warnings)} warning(s)"
        lines = [head, *(f"  warning: {w}" for w in self.warnings)]
        for key, value in self.metrics().items():
            text = f"{value:.6g}" if isinstance(value, float) else str(value)
            lines.append(f"  {key}: {text}")
        return "\n".join(lines)

    def metrics(self) -> dict[str, float | str | bool]:
        """The scalar metrics as a flat dict (column names of :mod:`.metric_names`)."""
        return {
            "v_c_m_per_s": self.impact_velocity,
            "a_h_max_g": self.peak_head_acceleration_g,
            "a_h_max_m_per_s2": self.peak_head_acceleration,
            "t_imp_s": self.impact_duration,
            "eps_max_m": self.max_compression,
            "peak_force_N": self.peak_force,
            "hic15": self.hic(0.015),
            "hic36": self.hic(0.036),
            "bottoming": self.bottoming,
            "status": self.status,
        }

    def to_frame(self) -> pd.DataFrame:
        """Time histories, one row per sample, columns with units."""
        return pd.DataFrame(
            {
                "t_s": self.t,
                "f_c_N": self.force,
                "a_h_m_per_s2": self.head_acceleration,
                "a_h_g": self.head_acceleration / STANDARD_GRAVITY,
                "eps_m": self.compression,
                "v_h_rel_m_per_s": self.head_velocity,
                "delta_r_m": self.robot_deflection,
            }
        )


def _responses(
    robot: ContactDynamics | FullJointContact,
    foam: Foam,
    head: HeadNeck | None,
    q2: str,
    keys: tuple[str, ...] = ("ramp", "accel", "a_d"),
) -> dict[str, dict[str, ModalResponse]]:
    """Unit responses to the inputs: closing ramp, closing step, closing parabola, a_d step.

    A :class:`FullJointContact` (full series joint, (3.4.6)) is evaluated from
    its state space and adds the ``a_ff`` step: a desired acceleration
    compensated by feed-forward at the motor.
    """
    contact = contact_of(robot, foam)
    model, p = _model_and_params(robot, foam, head)
    if contact.response_form == "state_space":  # with the feed-forward input at the motor
        fams = (*keys, "a_ff") if "a_d" in keys else keys
        return modal_families(model, p, _OUTPUTS, fams)
    den, num = model.tf_coefficients(p)
    if q2 == "printed" and head is not None:
        den = den.copy()
        den[:, 2] -= printed_q2_correction(p)
    exact = _exact_ramp(p, q2) if head is not None else None
    if exact is not None:
        den = exact[0]
    poles = poles_of(den)
    zero = np.zeros((1, 1))

    def shift(c: NDArray, k: int) -> NDArray:  # multiply a polynomial by s^k
        return np.concatenate([c, np.zeros((c.shape[0], k))], axis=1) if k else c

    def padd(a: NDArray, b: NDArray) -> NDArray:
        n = max(a.shape[1], b.shape[1])
        out = np.zeros((a.shape[0], n))
        out[:, n - a.shape[1] :] += a
        out[:, n - b.shape[1] :] += b
        return out

    # closing motion s_c(t) with v_c(t) = s_c'(t):
    #   unit ramp speed   v_c = 1:     S_c = 1/s^2, V_c = 1/s   -> (N_sc + s N_vc) / s^2
    #   unit speed ramp   v_c = t:     S_c = 1/s^3, V_c = 1/s^2 -> (N_sc + s N_vc) / s^3
    #   a_d step          a_d = 1:     A_d = 1/s               -> N_ad / s
    families = {}
    for key, m in (("ramp", 2), ("accel", 3), ("a_d", 1)):
        if key not in keys:
            continue
        nums = {}
        for name in _OUTPUTS:
            nm = num[name][:, :, :]
            if key == "a_d":
                c = nm[:, 2, :]
            else:
                c = padd(nm[:, 0, :], shift(nm[:, 1, :], 1))
            if key == "ramp" and exact is not None and name in exact[1]:
                c = exact[1][name]
            nums[name] = c if np.any(c) else zero
        families[key] = ModalResponse.family(nums, den, m, poles)
    return families


def _exact_ramp(p: NDArray, q2: str) -> tuple[NDArray, dict[str, NDArray]]:
    """The reduced model's characteristic polynomial and ramp numerators of the force, the
    head acceleration and the compression in closed form (:mod:`designlab.impact.kernel_poles`,
    the batch engine's): sums of products of the parameters, without the cancellations of the
    symbolic Faddeev-LeVerrier coefficients, which for extreme (admitted) designs lose every
    digit of the small terms."""
    from designlab.impact.kernel_poles import coefficients

    den, num = np.zeros(5), np.zeros((3, 6))
    coefficients(*(float(x) for x in p[0]), q2 == "printed", den, num)
    outputs = ("force", "head_acceleration", "compression")
    return den[None, :], {k: num[None, i] for i, k in enumerate(outputs)}


def _model_and_params(robot, foam, head):  # type: ignore[no-untyped-def]
    """The linear model and its ``(1, n_p)`` parameters (the contact model's)."""
    contact = contact_of(robot, foam)
    return contact.model(head is None), contact.row(robot, foam, head)[None, :]


def _superpose(
    families: dict[str, dict[str, ModalResponse]],
    v_c: float,
    profile: VelocityProfile | None,
) -> _Superposition:
    """Return a function t -> {output: values} (and derivative) for the whole input."""
    terms: list[tuple[str, float, float]] = [("ramp", v_c, 0.0)]
    if profile is not None:
        a, d = profile.acceleration, profile.duration
        terms += [("accel", a, 0.0), ("accel", -a, d)]
        if not profile.feedforward:
            terms += [("a_d", a, 0.0), ("a_d", -a, d)]
        elif "a_ff" in families:  # full joint: the feed-forward acts at the motor
            terms += [("a_ff", a, 0.0), ("a_ff", -a, d)]
    return _Superposition(families, tuple(terms))


@dataclass(frozen=True, eq=False)
class _Superposition:
    """The response to the whole input, a sum of delayed modal responses (picklable, unlike a
    closure, so an :class:`ImpactResponse` that keeps it can be pickled)."""

    families: dict[str, dict[str, ModalResponse]]
    terms: tuple[tuple[str, float, float], ...]

    def __call__(self, t: NDArray, derivative: int = 0) -> dict[str, NDArray]:
        t = np.asarray(t, dtype=float)
        out = {name: np.zeros(t.shape) for name in _OUTPUTS}
        for key, gain, delay in self.terms:
            if gain == 0.0:
                continue
            tau = t - delay
            on = tau >= 0 if delay > 0 else np.ones(t.shape, dtype=bool)
            if not np.any(on):
                continue
            vals = ModalResponse.evaluate_family(self.families[key], tau[on], derivative)
            for name in _OUTPUTS:
                out[name][on] += gain * vals[name][0]
        return out


def _no_head_acceleration(t: NDArray) -> dict[str, NDArray]:
    """The head acceleration of no impact: zero (a module-level function: picklable)."""
    return {"head_acceleration": np.zeros_like(t)}


def simulate(
    robot: ContactDynamics | FullJointContact,
    foam: Foam,
    head: HeadNeck | None,
    impact_velocity: float,
    *,
    profile: VelocityProfile | None = None,
    duration: float | None = None,
    samples: int = 2001,
    q2: str = "correct",
    stop_time: float = STOP_TIME.default,
) -> ImpactResponse:
    """Simulate the impact of a foam-covered manipulator on a head (Zeng 2011, Sec. 3.5).

    Parameters
    ----------
    robot
        Effective manipulator at the impact point: the reduced joint
        (:class:`ContactDynamics`) or the full series joint of (3.4.6)
        (:class:`~designlab.impact.full_joint.FullJointContact`).
    foam
        Foam covering: a linear :class:`Foam`, or a non-linear one (docs/impact_contact.md).
    head
        Head on its neck; ``None`` for the constrained impact (head against a
        wall, (3.6.1)/(3.9.4)).
    impact_velocity
        v_c = v_r(0) - v_h(0) in m/s, at most 20 (the cap of ``IMPACT_VELOCITY``);
        no impact (zero response) if v_c <= 0 (I5).
    profile
        Optional manipulator acceleration during the impact (Sec. 3.8).
    duration
        Length of the returned time histories, s. Default: twice the impact
        period (``stop_time`` for the constrained impact).
    samples
        Number of samples of the time histories.
    q2
        ``"correct"`` (default) or ``"printed"`` q2 of (3.5.14) (docs/impact.md, "q2").
    stop_time
        Window of the constrained impact's metrics, s.

    Returns
    -------
    ImpactResponse

    Examples
    --------
    >>> import designlab as dl
    >>> r = dl.impact.simulate(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, None, 0.25)
    >>> r.constrained, round(r.peak_force, 1)
    (True, 158.3)
    """
    v_c, contact = _check_inputs(robot, foam, head, impact_velocity, profile, samples, q2)
    duration = SIMULATION_DURATION.check(duration)
    stop_time = STOP_TIME.check(stop_time)
    if not contact.linear:
        return _integrated(contact, robot, foam, head, v_c, duration, samples, stop_time)
    keys = ("ramp",) if profile is None else ("ramp", "accel", "a_d")
    families = _responses(robot, foam, head, q2, keys)
    evaluate = _superpose(families, max(v_c, 0.0), profile)
    if v_c <= 0 and profile is None:
        return _no_impact(robot, foam, head, v_c, duration, samples, q2)
    if v_c <= 0:
        raise InvalidParameterError(
            "impact_velocity", v_c, "must be > 0 when a velocity profile is given", "m/s"
        )
    t_imp, metrics, status = _lobe_metrics(
        families, evaluate, robot, foam, head, v_c, profile, stop_time, q2
    )
    warnings, status = _response_warnings(status, t_imp, metrics, foam, contact)

    t = np.linspace(0.0, _t_end(duration, t_imp), int(samples))
    with np.errstate(all="ignore"):
        y = evaluate(t)
    _check_histories(robot, y)

    return ImpactResponse(
        robot=robot,
        foam=foam,
        head=head,
        impact_velocity=v_c,
        t=t,
        force=y["force"],
        head_acceleration=y["head_acceleration"],
        compression=y["compression"],
        head_velocity=y["head_velocity"],
        robot_deflection=y["robot_deflection"],
        peak_head_acceleration=metrics["head_acceleration"][1],
        max_compression=metrics["compression"][1],
        peak_force=metrics["force"][1],
        impact_duration=t_imp,
        time_of_peak_acceleration=metrics["head_acceleration"][0],
        time_of_max_compression=metrics["compression"][0],
        time_of_peak_force=metrics["force"][0],
        status=ImpactStatus(status),
        warnings=tuple(warnings),
        profile=profile,
        q2=q2,
        _lobe={"evaluate": evaluate},
    )


def _integrated(
    contact: ContactModel,
    robot: ContactDynamics,
    foam: object,
    head: HeadNeck | None,
    v_c: float,
    duration: float | None,
    samples: int,
    stop_time: float,
) -> ImpactResponse:
    """:func:`simulate` of a non-linear contact: the general response path, integrated."""
    if v_c <= 0:
        return _no_impact(robot, foam, head, v_c, duration, samples, "correct")  # type: ignore[arg-type]
    lobe, evaluate = contact.integrate(robot, foam, head, v_c, t_end=duration, stop_time=stop_time)
    metrics = {
        "head_acceleration": (lobe.time_of_peak_acceleration, lobe.peak_head_acceleration),
        "compression": (lobe.time_of_max_compression, lobe.max_compression),
        "force": (lobe.time_of_peak_force, lobe.peak_force),
    }
    t_imp = lobe.impact_duration
    if lobe.status == "bottoming":
        status, warnings = (
            lobe.status,
            [
                f"the foam is crushed at t = {lobe.time_of_max_compression:.4g} s: eps reached its "
                "densification depth, the force and a_h are beyond any limit (the histories end "
                "there)"
            ],
        )
    else:
        warnings, status = _response_warnings(lobe.status, t_imp, metrics, foam, contact)  # type: ignore[arg-type]
    t = np.linspace(0.0, min(_t_end(duration, t_imp), evaluate.end), int(samples))
    y = evaluate(t)
    return ImpactResponse(
        robot, foam, head, v_c, t, y["force"], y["head_acceleration"], y["compression"],  # type: ignore[arg-type]
        y["head_velocity"], y["robot_deflection"], lobe.peak_head_acceleration,
        lobe.max_compression, lobe.peak_force, t_imp, lobe.time_of_peak_acceleration,
        lobe.time_of_max_compression, lobe.time_of_peak_force,
        GeneralStatus.INTEGRATED if status == STATUS_OK else ImpactStatus(status),
        (*warnings, integrator_note(GENERAL_RTOL.default)), None, "correct",
        {"evaluate": evaluate},
    )  # fmt: skip


def _check_histories(robot: object, y: dict[str, NDArray]) -> None:
    """Refuse, by name, a design whose time histories double precision could not evaluate.

    The full joint's histories come from the eigen-decomposition of its state matrix; with a
    transmission so stiff that the motor node's mode is about 1e12 times faster than the
    slowest one, the decomposition breaks down (its metrics, from the closed form, do not).
    """
    if all(np.all(np.isfinite(v)) for v in y.values()):
        return
    raise InvalidParameterError(
        "robot",
        robot,
        "gives time histories beyond double precision: the full joint's motor-node mode "
        "(K_mech + K_cont) / (C_mech + C_cont) is too far from its slowest mode for the "
        "eigen-decomposition of its state matrix; its metrics are given by impact_metrics "
        '(docs/impact.md, "Limits")',
    )


def _t_end(duration: float | None, t_imp: float) -> float:
    """The length of the time histories: ``duration`` or, by default, twice the impact
    period (the constrained impact's is ``stop_time``; 0.1 s if the lobe did not close)."""
    if duration is not None:
        return duration
    return 2.0 * t_imp if np.isfinite(t_imp) and t_imp > 0 else 0.1


def _no_impact(
    robot: ContactDynamics | FullJointContact,
    foam: Foam,
    head: HeadNeck | None,
    v_c: float,
    duration: float | None,
    samples: int,
    q2: str,
) -> ImpactResponse:
    """The response when v_c <= 0: the bodies do not close in, every value is 0."""
    t = np.linspace(0.0, duration or 0.05, int(samples))
    zeros = np.zeros_like(t)
    return ImpactResponse(
        robot, foam, head, v_c, t, zeros, zeros, zeros, zeros, zeros,
        0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, ImpactStatus.NO_IMPACT,
        ("v_c <= 0: the head and the manipulator do not close in; no impact",),
        None, q2, {"evaluate": _no_head_acceleration},
    )  # fmt: skip


def input_labels(robot: object, head: object) -> tuple[str | None, ...]:
    """The names of simulate's inputs in the order of the model's parameter row (``None``
    for the constrained head's placeholders): the names of a conditioning refusal.

    Examples
    --------
    >>> import designlab as dl
    >>> input_labels(dl.impact.MANIPULATOR_1, None)[:2]
    ('robot.mass', 'robot.damping')
    """
    return contact_of(robot).input_labels(head)


def _check_inputs(
    robot: object,
    foam: object,
    head: object,
    impact_velocity: object,
    profile: object,
    samples: object,
    q2: object,
) -> float:
    """Validate the arguments of :func:`simulate`; returns v_c and the contact model."""
    contact = contact_of(robot, foam)
    if robot.along_link:  # type: ignore[attr-defined]
        raise InvalidParameterError(
            "robot", robot, "must be a manipulator at one impact point (robot.contact(l))"
        )
    if head is not None and not isinstance(head, HeadNeck):
        raise InvalidParameterError("head", head, "must be a HeadNeck or None")
    v_c = check_closing_velocity(check_finite("impact_velocity", impact_velocity, "m/s"))
    if q2 not in ("correct", "printed"):
        raise InvalidParameterError("q2", q2, "must be 'correct' or 'printed'")
    if q2 == "printed" and not contact.printed_q2:
        raise InvalidParameterError("q2", q2, "the printed q2 belongs to the reduced joint")
    SIMULATION_SAMPLES.check(samples)
    if profile is not None and not isinstance(profile, VelocityProfile):
        raise InvalidParameterError("profile", profile, "must be a VelocityProfile or None")
    if profile is not None and not contact.profiles:
        raise InvalidParameterError(
            "profile", profile, f"is not available with the {contact.name} contact "
            f"({contact.label}); velocity profiles serve {list(CONTACTS.choices(profiles=True))}",
        )  # fmt: skip
    if contact.linear:
        model, p = _model_and_params(robot, foam, head)
        check_conditioning(
            p, model.param_names, constrained=head is None, labels=contact.input_labels(head)
        )
    return v_c, contact


def _lobe_metrics(
    families: dict,
    evaluate: Callable,
    robot: ContactDynamics,
    foam: Foam,
    head: HeadNeck | None,
    v_c: float,
    profile: VelocityProfile | None,
    stop_time: float,
    q2: str = "correct",
) -> tuple[float, dict[str, tuple[float, float]], str]:
    """Impact period, ``{output: (time, value)}`` of the maxima, and the design status.

    The batch engine for the constant-velocity impact; a dense exact
    evaluation with Newton polishing for a velocity profile.
    """
    constrained = head is None
    p = _model_and_params(robot, foam, head)[1]
    # the batch engine (its closed-form coefficients are sums of positive terms): the same
    # metrics as impact_metrics for the same design
    base = metrics_of_matrix(p, v_c, constrained=constrained, q2=q2, stop_time=stop_time)
    status = str(base.design_status[0])
    t_imp = float(base.impact_duration[0])
    metrics = {
        "head_acceleration": (
            float(base.time_of_peak_acceleration[0]),
            float(base.peak_head_acceleration[0]),
        ),
        "compression": (float(base.time_of_max_compression[0]), float(base.max_compression[0])),
        "force": (float(base.time_of_peak_force[0]), float(base.peak_force[0])),
    }
    if profile is not None:
        t_imp, metrics, status = _profile_metrics(evaluate, t_imp, constrained, stop_time)
    return t_imp, metrics, status


def _response_warnings(
    status: str,
    t_imp: float,
    metrics: dict[str, tuple[float, float]],
    foam: Foam,
    contact: ContactModel,
) -> tuple[list[str], str]:
    """Warnings of one response, and its status (``bottoming`` if the foam bottoms out)."""
    warnings: list[str] = []
    if status == STATUS_PEAK_AT_CONTACT:
        warnings.append(
            "a_h peaks at t = 0+ (overdamped pulse, foam damping far above xi_c ~ 0.05-0.2): "
            "a_h,max = C_c v_c / M_h and the impact period is delicate"
        )
    if not np.isfinite(t_imp):
        warnings.append("the first impact lobe did not close; metrics are NaN")
    if metrics["compression"][1] > contact.valid_depth(foam):
        warnings.append(
            f"eps_max = {metrics['compression'][1]:.4g} m exceeds the foam's linear depth "
            f"lambda = {foam.linear_depth:.4g} m: the foam bottoms out and the linear model "
            'is not valid (docs/impact.md, "Foam bottoming")'
        )
        if status == STATUS_OK:
            status = "bottoming"
    return warnings, status


def _profile_metrics(evaluate, t_guess: float, constrained: bool, stop_time: float):
    """First-lobe metrics of a superposed response: dense exact samples + Brent polish."""
    from scipy.optimize import brentq, minimize_scalar

    horizon = stop_time if constrained else max(4.0 * t_guess, 0.2) if np.isfinite(t_guess) else 0.5
    t = np.linspace(0.0, horizon, 8001)
    y = evaluate(t)
    if constrained:
        t_imp = stop_time
        k = t.size
    else:
        a = y["head_acceleration"]
        nonpos = np.flatnonzero((a <= 0) & (t > 0))
        if nonpos.size == 0:
            return np.nan, {k: (np.nan, np.nan) for k in _OUTPUTS}, "lobe_not_closed"
        k = int(nonpos[0])

        def ah(x: float) -> float:
            return float(evaluate(np.array([x]))["head_acceleration"][0])

        t_imp = brentq(ah, t[k - 1], t[k], xtol=1e-14, rtol=1e-12)
    metrics = {}
    status = STATUS_OK
    for name in ("head_acceleration", "compression", "force"):
        vals = y[name][:k]
        j = int(np.argmax(vals))
        lo, hi = t[max(j - 1, 0)], min(t[min(j + 1, k - 1)], t_imp)
        best_t, best_y = float(t[j]), float(vals[j])
        if hi > lo:

            def neg(x: float, name: str = name) -> float:
                return -float(evaluate(np.array([x]))[name][0])

            res = minimize_scalar(neg, bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
            if -res.fun > best_y:
                best_t, best_y = float(res.x), float(-res.fun)
        end = float(evaluate(np.array([t_imp]))[name][0])
        if end > best_y:
            best_t, best_y = t_imp, end
        metrics[name] = (best_t, best_y)
        if name == "head_acceleration" and best_t == 0.0:
            status = STATUS_PEAK_AT_CONTACT
    return float(t_imp), metrics, status
