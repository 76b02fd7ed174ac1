"""Linearised lateral-error loop of the tether follower laws (python-control).

On a straight leader path at speed v, with lateral offset e and heading
error psi of the robot, ``e' = v psi`` and ``psi' = Omega``. Every law steers
toward a point ahead at an effective distance L, ``phi ~ -psi - e/L``, with
``Omega = K phi``:

======================  ======================  =====================
law                     K (1/s)                 L (m)
======================  ======================  =====================
Pseudo-Joystick coded   k_O                     l = l_d + v/k_V
Pseudo-Joystick printed 2v/b (eq. 2.2)          l = l_d + v/k_V
Follow the Leader       K_Omega                 delta
FTL constant distance   K_b                     l - l_d = v/K_p
======================  ======================  =====================

so the loop ``L(s) = K (s + v/L)/s^2`` closes to ``s^2 + K s + K v/L``:
``omega_n = sqrt(K v/L)``, ``zeta = sqrt(K L/v)/2`` (a small look-ahead
weaves, Allan 2015 Sec. 2.5.4). The tether length obeys
``l' = v - k_V (l - l_d)``: one real pole at ``-k_V`` and the steady state
``l_d + v/k_V``. Poles, margins and the poles of the sampled loop (zero-order
hold at the control period) come from python-control. See ``docs/following.md``.

Examples
--------
>>> from designlab.following.tether import FollowTheLeader
>>> lin = linear_analysis(FollowTheLeader(lookahead=0.5), speed=0.5)
>>> round(lin.damping_ratio, 4), round(lin.natural_frequency, 4)
(0.866, 1.7321)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.following.tether.laws.base import TetherController, checked_law
from designlab.following.tether.parameters import DURATION, LEADER_SPEED, WHEEL_TRACK, FollowerRobot
from designlab.following.tether.paths import straight_line
from designlab.following.tether.simulate import simulate
from designlab.params import Param
from designlab.results import Result, Status
from designlab.validation import real_array

__all__ = [
    "STEP_OFFSET",
    "LinearLoop",
    "LinearLoopStatus",
    "effective_loop",
    "fit_damping",
    "identify_poles",
    "lateral_step_response",
    "linear_analysis",
]


def effective_loop(
    controller: TetherController, speed: float, wheel_track: float = WHEEL_TRACK.default
) -> tuple[Any, Any, Any]:
    """Turn gain K (1/s), effective look-ahead L (m) and steady tether length (m).

    Works on numbers or numpy arrays of gains (for batches of gain sets).

    Parameters
    ----------
    controller
        The tether controller (its gains may be numpy arrays).
    speed
        Leader speed in m/s.
    wheel_track
        Wheel track b in m (the printed Pseudo-Joystick law uses it).
    """
    return checked_law(controller).effective_loop(speed, wheel_track)


def damping_ratio(
    controller: TetherController, speed: float, wheel_track: float = WHEEL_TRACK.default
) -> float:
    """Damping ratio ``sqrt(K L / v)/2`` of the lateral loop (see the module notes)."""
    k, look, _ = effective_loop(controller, speed, wheel_track)
    return 0.5 * math.sqrt(k * look / speed)


class LinearLoopStatus(Status):
    """Status of a linearised lateral loop.

    ``OK``: the loop sampled at the control period is stable. ``UNSTABLE``: a
    pole of the sampled loop is on or outside the unit circle.
    """

    OK = "ok"
    UNSTABLE = "unstable"


#: Initial lateral offset of the simulated step of :func:`lateral_step_response`.
STEP_OFFSET = Param(
    "e_0", "m", "initial lateral offset of the robot", ge=-1, le=1, default=0.05, name="offset"
)


@dataclass(frozen=True, eq=False)
class LinearLoop(Result):
    """Linearised lateral loop of one law at one speed.

    Attributes
    ----------
    turn_gain, lookahead
        K (1/s) and the effective look-ahead L (m).
    poles
        Closed-loop poles (1/s).
    damping_ratio, natural_frequency
        zeta and omega_n (rad/s) of ``s^2 + 2 zeta omega_n s + omega_n^2``
        (zeta > 1: two real poles).
    phase_margin, gain_margin
        Of the loop broken at Omega (deg; the gain margin is infinite).
    crossover_frequency
        Gain-crossover frequency in rad/s.
    length_pole
        Pole of the tether-length loop (-k_V), 1/s.
    steady_length
        Steady tether length ``l_d + v/k_V`` in m.
    discrete_poles
        Poles of the loop sampled at the control period (zero-order hold).
    discrete_stable
        True when every sampled pole is inside the unit circle.
    controller
        The law analysed.
    speed
        Leader speed in m/s.
    sample_time
        Control period in s (for the discrete poles).
    matrices
        ``(A, B, C, D)`` of the closed lateral loop (states psi, e); the
        python-control model is :attr:`system` (rebuilt from them, so that the
        result pickles).
    status
        ``"ok"``, or ``"unstable"`` when a pole of the sampled loop is outside
        the unit circle.
    warnings
        What a user should know about the loop.
    """

    controller: TetherController
    speed: float
    sample_time: float
    turn_gain: float
    lookahead: float
    poles: NDArray[np.complex128]
    damping_ratio: float
    natural_frequency: float
    phase_margin: float
    gain_margin: float
    crossover_frequency: float
    length_pole: float
    steady_length: float
    discrete_poles: NDArray[np.complex128]
    discrete_stable: bool
    matrices: tuple[NDArray[np.float64], ...]
    status: LinearLoopStatus = LinearLoopStatus.OK
    warnings: tuple[str, ...] = ()

    @property
    def system(self) -> Any:
        """The python-control state-space model of the closed lateral loop."""
        import control

        return control.ss(*self.matrices)

    def to_frame(self) -> pd.DataFrame:
        """One row of the loop's figures."""
        return pd.DataFrame(
            [
                {
                    "law": self.controller.name,
                    "speed_m_per_s": self.speed,
                    "turn_gain_per_s": self.turn_gain,
                    "lookahead_m": self.lookahead,
                    "damping_ratio": self.damping_ratio,
                    "natural_frequency_rad_per_s": self.natural_frequency,
                    "phase_margin_deg": self.phase_margin,
                    "crossover_rad_per_s": self.crossover_frequency,
                    "length_pole_per_s": self.length_pole,
                    "steady_length_m": self.steady_length,
                    "discrete_stable": self.discrete_stable,
                }
            ]
        )


def _margins(a: NDArray, b: NDArray, kx: NDArray) -> tuple[float, float, float]:
    """Gain margin, phase margin (deg) and crossover (rad/s) of the loop broken at Omega."""
    import control

    loop = control.ss(a, b, kx, np.zeros((1, 1)))  # Omega -> K(psi + e/L)
    gm, pm, _, wcp = control.margin(loop)
    return (float(gm) if gm is not None else math.inf), float(pm), float(wcp)


def _sampled_poles(a: NDArray, b: NDArray, kx: NDArray, dt: float) -> NDArray[np.complex128]:
    """Poles of the loop sampled at ``dt`` with a zero-order hold."""
    import control

    plant = control.ss(a, b, np.eye(2), np.zeros((2, 1)))
    sampled = control.sample_system(plant, dt, method="zoh")
    return np.linalg.eigvals(sampled.A - sampled.B @ kx)


def linear_analysis(
    controller: TetherController,
    speed: float = LEADER_SPEED.default,
    robot: FollowerRobot | None = None,
) -> LinearLoop:
    """Linearise the lateral-error loop of ``controller`` at leader speed ``speed``.

    Parameters
    ----------
    controller
        A :class:`PseudoJoystick`, :class:`FollowTheLeader` or
        :class:`FollowTheLeaderConstDistance`.
    speed
        Leader (and steady robot) speed in m/s.
    robot
        Gives the wheel track (printed PJ law) and the control period.

    Returns
    -------
    LinearLoop
    """
    import control  # lazily: python-control is slow to import

    speed = LEADER_SPEED.check(speed)
    robot = robot or FollowerRobot()
    k, look, l_ss = effective_loop(controller, speed, robot.wheel_track)
    # plant: states (psi, e), input Omega; closed loop Omega = -K(psi + e/L)
    a = np.array([[0.0, 0.0], [speed, 0.0]])
    b = np.array([[1.0], [0.0]])
    kx = np.array([[k, k / look]])
    matrices = (a - b @ kx, b, np.eye(2), np.zeros((2, 1)))
    poles = np.sort_complex(control.poles(control.ss(*matrices)))
    # s^2 + 2 zeta wn s + wn^2 from the poles (zeta > 1 when the poles are real)
    wn = float(np.sqrt(np.real(np.prod(poles))))
    zeta_min = float(-np.real(np.sum(poles)) / (2.0 * wn))
    gm, pm, wcp = _margins(a, b, kx)
    dpoles = _sampled_poles(a, b, kx, robot.sample_time)
    warns = []
    stable_d = bool(np.all(np.abs(dpoles) < 1.0))
    if not stable_d:
        warns.append(f"the sampled loop is unstable at dt = {robot.sample_time:g} s")
    if zeta_min < 0.3:
        warns.append(f"lightly damped lateral loop (zeta = {zeta_min:.2f}): the robot weaves")
    return LinearLoop(
        controller=controller,
        speed=speed,
        sample_time=robot.sample_time,
        turn_gain=float(k),
        lookahead=float(look),
        poles=poles,
        damping_ratio=zeta_min,
        natural_frequency=wn,
        phase_margin=pm,
        gain_margin=gm,
        crossover_frequency=wcp,
        length_pole=-float(controller.speed_gain),  # type: ignore[attr-defined]
        steady_length=float(l_ss),
        discrete_poles=dpoles,
        discrete_stable=stable_d,
        matrices=matrices,
        status=LinearLoopStatus.OK if stable_d else LinearLoopStatus.UNSTABLE,
        warnings=tuple(warns),
    )


def lateral_step_response(
    controller: TetherController,
    offset: float = STEP_OFFSET.default,
    speed: float = LEADER_SPEED.default,
    duration: float = 12.0,
    robot: FollowerRobot | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Simulated lateral response of the full nonlinear loop on a straight path.

    The leader walks +x at ``speed``; the robot starts at the steady tether
    length behind it, parallel, ``offset`` m to the side, with the leader's
    earlier straight path already recorded. Returns ``(t, e)``: time (s) and
    the robot's lateral offset (m).

    Parameters
    ----------
    controller
        The tether controller.
    offset
        Initial lateral offset of the robot in m.
    speed
        Leader speed in m/s.
    duration
        Simulated time in s.
    robot
        The robot (default :class:`FollowerRobot`).
    """
    offset = STEP_OFFSET.check(offset)
    speed = LEADER_SPEED.check(speed)
    duration = DURATION.check(duration)
    robot = robot or FollowerRobot()
    _, _, l_ss = effective_loop(controller, speed, robot.wheel_track)
    run = simulate(
        controller,
        straight_line(speed * duration + 5.0),
        speed=speed,
        robot=robot,
        duration=duration,
        lead_in=l_ss + 2.0,
        initial_pose=(-math.sqrt(max(l_ss**2 - offset**2, 0.0)), offset, 0.0),
    )
    return run.t, run.robot_xy[:, 1]


#: Samples :func:`identify_poles` leaves out at the start.
_SKIP = Param(None, "", "samples left out at the start", kind="integer", ge=0, le=10**6,
              name="skip")  # fmt: skip


def identify_poles(t: Any, e: Any, skip: int = 5) -> NDArray[np.complex128]:
    """The two poles (1/s) of a sampled free response, by a second-order autoregressive fit.

    A free response of a second-order linear system sampled every T obeys
    ``e[k] = a1 e[k-1] + a2 e[k-2]`` exactly; (a1, a2) are fitted by linear least
    squares, the roots z of ``z^2 - a1 z - a2`` are the sampled poles and
    ``s = log(z) / T`` the continuous ones. No initial condition is assumed.

    Parameters
    ----------
    t
        Equally spaced times in s.
    e
        The response at those times.
    skip
        Samples left out at the start (the first steps of a sampled controller).

    Returns
    -------
    ndarray
        The two poles, slowest first.

    Examples
    --------
    >>> t = np.arange(0.0, 5.0, 0.01)
    >>> p = identify_poles(t, 2.0 * np.exp(-0.5 * t) - np.exp(-4.0 * t))
    >>> np.round(p.real, 6).tolist()
    [-0.5, -4.0]
    """
    t, e = real_array("t", t, "s"), real_array("e", e)
    skip = _SKIP.check(skip)
    if t.ndim != 1 or e.shape != t.shape or t.size < skip + 4:
        raise InvalidParameterError(
            "e", e.shape, f"must be one value per time of t {t.shape}, at least skip + 4 = "
            f"{skip + 4} samples",
        )  # fmt: skip
    dt = float(t[1] - t[0])
    if not dt > 0 or np.abs(np.diff(t) - dt).max() > 1e-6 * dt:
        raise InvalidParameterError("t", t[:3].tolist(), "must be increasing and equally spaced")
    e = e[skip:]
    a = np.column_stack([e[1:-1], e[:-2]])
    (a1, a2), *_ = np.linalg.lstsq(a, e[2:], rcond=None)
    z = np.roots([1.0, -a1, -a2]).astype(complex)
    s = np.log(z) / dt
    return s[np.argsort(np.abs(s))]


def fit_damping(t: Any, e: Any) -> tuple[float, float]:
    """Damping ratio and natural frequency of the two poles identified in a free response.

    ``zeta = -(s1 + s2) / (2 sqrt(s1 s2))`` and ``omega_n = sqrt(s1 s2)`` of the
    poles of :func:`identify_poles` (real for an overdamped loop, a complex pair
    otherwise): the damping ratio *from the identified poles*, not a curve fit.

    Parameters
    ----------
    t
        Times in s (equally spaced).
    e
        Lateral offset in m at those times.

    Returns
    -------
    (zeta, omega_n)
    """
    s = identify_poles(t, e)
    wn = float(np.sqrt(abs((s[0] * s[1]).real)))
    return float(-(s[0] + s[1]).real / (2.0 * wn)), wn
