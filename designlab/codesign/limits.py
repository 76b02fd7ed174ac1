"""The impact limits of many foams at once: speed limit and thickness needed (issue 36).

A design of the front (:mod:`designlab.codesign.front`) must not break a limit another
part of designlab reports: its speed limit V_mr may not exceed what
:func:`~designlab.codesign.speed_limit` allows for its foam (for the walker speed the
study states), and its thickness must hold the worst head's compression at the closing
speed it can meet. :func:`foam_limits` gives both for many foams (paired stiffness,
damping and linear depth) in one lock-step search of the worst heads: it is
:func:`~designlab.codesign.speed_limit`'s own setup and per-constraint closing speeds
(:func:`~designlab.codesign.speed.problem_for`,
:func:`~designlab.codesign.speed.allowed_closing_speeds`, with the off-grid refinement)
over many foams, so one foam gives exactly ``speed_limit``'s answer.

Both metrics of the linear model scale with the closing speed (velocity exponent 1):
the worst compression at v_c is v_c times the worst compression at 1 m/s, so the
linear depth a foam needs at v_c is ``eps_1 v_c``, and its thickness
``eps_1 v_c T_u / lambda`` (Zeng 2011, Sec. 3.9.3; docs/codesign.md).

Examples
--------
>>> import designlab as dl
>>> lim = foam_limits(dl.impact.MANIPULATOR_1, [24250.0], [71.9], [0.02], [0.0254])
>>> s = dl.codesign.speed_limit(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1)
>>> bool(abs(lim.max_speed[0] - s.max_speed) < 1e-12), lim.limiting[0]
(True, 'eps_max <= 20 mm')
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.codesign.speed import SafetyCase, allowed_closing_speeds, problem_for
from designlab.errors import InvalidParameterError
from designlab.impact import ContactDynamics, Foam, FullJointContact
from designlab.impact.criteria import CompressionLimit
from designlab.params import params_of
from designlab.results import Result
from designlab.validation import real_array

__all__ = ["FoamLimits", "foam_limits"]

Array = NDArray[np.float64]
_FOAM = params_of(Foam)

#: Most foams of one :func:`foam_limits` call (one lock-step search; about 5 ms each).
MAX_FOAMS = 10_000


@dataclass(frozen=True)
class FoamLimits(Result):
    """The speed limit and the compression per closing speed of many foams.

    Attributes
    ----------
    stiffness, damping, linear_depth, thickness
        The foams (N/m, N s/m, m, m), paired.
    unit_metric
        Per constraint name: its worst metric over the head range at v_c = 1 m/s, per foam.
    closing_speed
        The largest closing speed every constraint allows, per foam (m/s).
    max_speed
        The robot's speed limit, per foam (m/s; :func:`~designlab.codesign.speed_limit`).
    limiting
        The constraint that sets each foam's limit.
    human_speed
        The walker's speed toward the robot the limit assumes (m/s).
    compression_key
        The name under which :attr:`unit_metric` holds the compression (m per m/s).
    """

    stiffness: Array = field(repr=False)
    damping: Array = field(repr=False)
    linear_depth: Array = field(repr=False)
    thickness: Array = field(repr=False)
    unit_metric: dict[str, Array] = field(repr=False)
    closing_speed: Array = field(repr=False)
    max_speed: Array = field(repr=False)
    limiting: tuple[str, ...] = field(repr=False)
    human_speed: float = 1.0
    compression_key: str = "eps_max"

    def required_thickness(self, closing_speed: ArrayLike) -> Array:
        """The thickness T_u each foam needs not to bottom out at ``closing_speed`` (m).

        Parameters
        ----------
        closing_speed
            A closing speed per foam (or one for all), m/s.

        Returns
        -------
        numpy.ndarray
        """
        v = np.broadcast_to(real_array("closing_speed", closing_speed), self.stiffness.shape)
        eps1 = self.unit_metric[self.compression_key]
        return np.where(v > 0, eps1 * v * self.thickness / self.linear_depth, 0.0)

    def row(self, i: int) -> FoamLimits:
        """The limits of foam ``i`` alone.

        Parameters
        ----------
        i
            Index of the foam.
        """
        sl = slice(i, i + 1)
        return FoamLimits(
            stiffness=self.stiffness[sl], damping=self.damping[sl],
            linear_depth=self.linear_depth[sl], thickness=self.thickness[sl],
            unit_metric={k: v[sl] for k, v in self.unit_metric.items()},
            closing_speed=self.closing_speed[sl], max_speed=self.max_speed[sl],
            limiting=self.limiting[sl], human_speed=self.human_speed,
            compression_key=self.compression_key,
        )  # fmt: skip

    def to_frame(self) -> pd.DataFrame:
        """One row per foam: the foam, its limits and the limiting constraint."""
        frame = pd.DataFrame(
            {
                "K_c_N_per_m": self.stiffness,
                "C_c_N_s_per_m": self.damping,
                "linear_depth_m": self.linear_depth,
                "T_u_m": self.thickness,
                "v_c_max_m_per_s": self.closing_speed,
                "max_speed_m_per_s": self.max_speed,
                "limiting": list(self.limiting),
            }
        )
        for name, vals in self.unit_metric.items():
            frame[f"at_1_m_per_s: {name}"] = vals
        return frame


def _foams(stiffness: ArrayLike, damping: ArrayLike, linear_depth: ArrayLike,
           thickness: ArrayLike) -> tuple[Array, Array, Array, Array]:  # fmt: skip
    """The paired foam arrays, each value checked against the Foam declaration."""
    names = ("stiffness", "damping", "linear_depth", "thickness")
    given = (stiffness, damping, linear_depth, thickness)
    arrs = [np.atleast_1d(real_array(n, v)).astype(float).ravel()
            for n, v in zip(names, given, strict=True)]  # fmt: skip
    n = arrs[0].size
    if n == 0 or n > MAX_FOAMS or any(a.size != n for a in arrs):
        raise InvalidParameterError(
            "stiffness", n, f"must pair with damping, linear_depth, thickness (1 to {MAX_FOAMS})"
        )
    for name, arr in zip(names, arrs, strict=True):
        for x in arr:
            _FOAM[name].check(float(x), name)
    if (arrs[3] < arrs[2]).any():
        i = int(np.argmax(arrs[3] < arrs[2]))
        raise InvalidParameterError(f"thickness[{i}]", float(arrs[3][i]),
                                    f"must be >= linear_depth = {arrs[2][i]:g} m", "m")  # fmt: skip
    return arrs[0], arrs[1], arrs[2], arrs[3]


def foam_limits(
    robot: ContactDynamics | FullJointContact,
    stiffness: ArrayLike,
    damping: ArrayLike,
    linear_depth: ArrayLike,
    thickness: ArrayLike,
    case: SafetyCase | None = None,
) -> FoamLimits:
    """The speed limit of each foam and its worst compression per m/s of closing speed.

    Parameters
    ----------
    robot
        The effective robot at the contact point (a fixed point).
    stiffness, damping, linear_depth, thickness
        The foams, paired (N/m, N s/m, m, m).
    case
        The criteria, people, braking and worst-head grid
        (:class:`~designlab.codesign.SafetyCase`; ``None``: its defaults); the worst heads
        are always refined off the grid.

    Returns
    -------
    FoamLimits
    """
    if not isinstance(robot, (ContactDynamics, FullJointContact)):
        raise InvalidParameterError("robot", robot, "must be a ContactDynamics or FullJointContact")
    k, c, lam, t = _foams(stiffness, damping, linear_depth, thickness)
    case = SafetyCase.of(case)
    prob, v_h, brake = problem_for(robot, case, float(lam[0])), case.human_speed, case.braking
    unit: dict[str, Array] = {}
    allowed = []
    comp = ""
    for key, vals, _, v in allowed_closing_speeds(prob, k, c, lam, True):
        if isinstance(key, CompressionLimit):
            comp = key.name if np.all(lam == lam[0]) else "eps_max <= linear depth"
        unit[comp if isinstance(key, CompressionLimit) else key.name] = vals
        allowed.append(v)
    stack = np.stack(allowed)
    v_c = stack.min(axis=0)
    names = list(unit)
    speed = np.array([brake.robot_limit(u - v_h, v_h) for u in v_c], dtype=float)
    return FoamLimits(
        stiffness=k, damping=c, linear_depth=lam, thickness=t, unit_metric=unit,
        closing_speed=v_c, max_speed=speed,
        limiting=tuple(names[i] for i in np.argmin(stack, axis=0)), human_speed=v_h,
        compression_key=comp,
    )  # fmt: skip
