"""The per-axis PID of the accompanying robot (Wu et al. 2021, eq. 9, Fig. 3).

Three discrete PIDs at the sensor rate act on the errors of eq. (8):
(e_x, e_y) in the robot frame give the lateral and forward velocity commands
(V_x, V_y), the heading error e_theta gives the yaw-rate command omega_z. The
two linear axes share one set of gains (the platform is isotropic); the yaw
axis has its own. The paper reports neither gains nor loop details; this
module adds what a practical PID needs (``docs/following.md``):

* backward-Euler integral ``I_k = I_{k-1} + K_i T_s e_k``;
* derivative on the error through a first-order filter of time constant
  ``T_f``: ``D_k = T_f/(T_f+T_s) D_{k-1} + K_d/(T_f+T_s) (e_k - e_{k-1})``;
* anti-windup by conditional integration (clamping): while the command is
  saturated, the integrator of an axis whose error pushes further into the
  saturation is frozen.

So ``C(z) = K_p + K_i T_s z/(z-1) + K_d (z-1)/((T_f+T_s) z - T_f)``, which
:mod:`designlab.following.accompany_linear` uses.

Examples
--------
>>> pid = UserFramePID()
>>> pid.kp, pid.ki, pid.kd
(2.0, 0.5, 0.1)
>>> pid.gains("heading")
(2.0, 0.5, 0.1, 0.05)
>>> UserFramePID(kp=1.0, ki=0.0, kd=0.0).is_p_only
True
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace
from typing import Any

from designlab.errors import InvalidParameterError, check_nonnegative

__all__ = ["AXES", "UserFramePID", "sx_pid_axis"]

#: The controlled axes: lateral (X_R), forward (Y_R) and heading.
AXES = ("lateral", "forward", "heading")


@dataclass(frozen=True)
class UserFramePID:
    """Gains of the three user-frame PIDs (eq. 9).

    Parameters
    ----------
    kp
        Proportional gain of the linear axes, (m/s)/m = 1/s (>= 0).
    ki
        Integral gain of the linear axes, 1/s^2 (>= 0).
    kd
        Derivative gain of the linear axes, dimensionless (m/s)/(m/s) (>= 0).
    derivative_filter_time
        Time constant T_f of the derivative filter of the linear axes in s (>= 0).
    kp_heading, ki_heading, kd_heading, heading_filter_time
        The same for the yaw axis ((rad/s)/rad etc.); ``None`` copies the linear value.

    Examples
    --------
    >>> UserFramePID(kp=-1.0)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: UserFramePID.kp = -1.0 1/s is not allowed: ...
    """

    kp: float = 2.0
    ki: float = 0.5
    kd: float = 0.1
    derivative_filter_time: float = 0.05
    kp_heading: float | None = None
    ki_heading: float | None = None
    kd_heading: float | None = None
    heading_filter_time: float | None = None

    def __post_init__(self) -> None:
        c = "UserFramePID."
        units = {"kp": "1/s", "ki": "1/s^2", "kd": "", "derivative_filter_time": "s"}
        for name, unit in units.items():
            object.__setattr__(self, name, check_nonnegative(c + name, getattr(self, name), unit))
        for name, base in (
            ("kp_heading", "kp"),
            ("ki_heading", "ki"),
            ("kd_heading", "kd"),
            ("heading_filter_time", "derivative_filter_time"),
        ):
            v = getattr(self, name)
            if v is None:
                object.__setattr__(self, name, getattr(self, base))
            else:
                object.__setattr__(self, name, check_nonnegative(c + name, v, units[base]))
        if self.kp + self.ki == 0.0 or self.kp_heading + self.ki_heading == 0.0:  # type: ignore[operator]
            raise InvalidParameterError(
                c + "kp", self.kp, "kp or ki must be > 0 on every axis (else nothing moves)"
            )

    def gains(self, axis: str) -> tuple[float, float, float, float]:
        """(K_p, K_i, K_d, T_f) of one axis: ``"lateral"``, ``"forward"`` or ``"heading"``."""
        if axis in ("lateral", "forward"):
            return (self.kp, self.ki, self.kd, self.derivative_filter_time)
        if axis == "heading":
            return (self.kp_heading, self.ki_heading, self.kd_heading, self.heading_filter_time)  # type: ignore[return-value]
        raise InvalidParameterError("axis", axis, f"one of {AXES}")

    @property
    def is_p_only(self) -> bool:
        """True if every axis has K_i = K_d = 0."""
        return self.ki == self.kd == self.ki_heading == self.kd_heading == 0.0

    def vector(self) -> list[float]:
        """The 12 numbers (K_p, K_i, K_d, T_f) for lateral, forward, heading."""
        return [v for a in AXES for v in self.gains(a)]

    def as_dict(self) -> dict[str, Any]:
        """Return the fields as a plain ``dict``."""
        return asdict(self)

    def replace(self, **changes: Any) -> UserFramePID:
        """Return a copy with some fields changed (validated again)."""
        return replace(self, **changes)


def sx_pid_axis(e, e_prev, i_prev, d_prev, kp, ki, kd, tf, ts):
    """One PID update before saturation (symbolic): returns (u, I_candidate, D).

    ``u = K_p e + I + D`` with the backward-Euler integral and the filtered
    derivative described in the module docstring. The caller saturates ``u``
    and decides (anti-windup) whether to keep ``I_candidate``.

    Parameters
    ----------
    e
        Error at this sample.
    e_prev
        Error at the previous sample.
    i_prev
        Integral state at the previous sample.
    d_prev
        Filtered derivative at the previous sample.
    kp
        Proportional gain K_p.
    ki
        Integral gain K_i (1/s).
    kd
        Derivative gain K_d (s).
    tf
        Derivative filter time constant T_f (s).
    ts
        Sample time T_s (s).
    """
    i_new = i_prev + ki * ts * e
    d_new = (tf * d_prev + kd * (e - e_prev)) / (tf + ts)
    return kp * e + i_new + d_new, i_new, d_new
