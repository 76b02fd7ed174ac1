"""A non-linear foam: Hunt-Crossley damping and a densification (stiffening) spring.

The reduced joint (3.4.9) and the head on its neck (3.5.3) as in the thesis, with the
linear foam law (3.5.1) replaced by, for a compression eps (eps+ = max(eps, 0))::

    f_c = K_c eps (1 - eps+ / x_d)^(-n)  +  C_c (eps+ / x_d)^p eps_dot

* the spring stiffens as the cells collapse and the foam densifies: its stress rises
  without bound as the compression approaches the densification depth x_d (Gibson &
  Ashby, *Cellular Solids*, 2nd ed. 1997, Sec. 5.3, the densification strain
  eps_D ~ 1 - 1.4 rho*/rho_s); ``n`` sets how sharply (n = 0: a linear spring);
* the damping is Hunt & Crossley's (1975, "Coefficient of restitution interpreted as
  damping in vibroimpact", J. Appl. Mech. 42(2)): proportional to a power p of the
  indentation, so the force starts at zero on contact and the damper does not pull the
  head back at separation (p = 0: the linear damper). C_c is the damping at eps = x_d,
  so it keeps the unit N s/m; p must be 0 or at least 1 (the force's rate is then finite
  at contact).

With n = p = 0 the law is the Kelvin-Voigt foam of (3.5.1). Not linear: its metrics come
from the general response path (:mod:`designlab.impact.general`: an adaptive integrator
with event location), one design at a time; they are integrator results with stated
tolerances, not certified (status ``"integrated"``). A compression can never reach x_d;
the compression limit of an envelope (lambda) stays the designer's.

Examples
--------
>>> from designlab.impact import HEAD_MIN, MANIPULATOR_1
>>> foam = HuntCrossleyFoam(24.25e3, 71.9, densification_depth=0.02, stiffening=1.0,
...                         damping_exponent=1.0)
>>> HUNT_CROSSLEY.row(MANIPULATOR_1, foam, HEAD_MIN).tolist()[-3:]
[0.02, 1.0, 1.0]
>>> f, _, _ = HUNT_CROSSLEY.force_law(foam.stiffness, foam.damping, 0.02, 1.0, 1.0)(
...     np.array([0.01]), np.array([1.0]))
>>> round(float(f[0]), 2)                # 24.25e3 * 0.01 / 0.5 + 71.9 * 0.5
520.95
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.contact.base import LINEAR_FOAM, REDUCED_JOINT
from designlab.impact.contact.integrated import IntegratedContact
from designlab.impact.general import ForceLaw
from designlab.impact.model import PARAM_NAMES
from designlab.impact.parameters import ContactDynamics, Foam, LinkImpact, as_field
from designlab.params import declared, param, params_of
from designlab.validation import ParamsMixin

__all__ = ["HUNT_CROSSLEY", "HuntCrossley", "HuntCrossleyFoam"]

_FOAM = params_of(Foam)
#: the columns of the force law, in the order of :meth:`HuntCrossley.force_law`
_LAW = ("K_c", "C_c", "x_d", "n_d", "p_c")


@declared
@dataclass(frozen=True)
class HuntCrossleyFoam(ParamsMixin):
    """A foam with Hunt-Crossley damping and a densification spring (see the module text).

    Examples
    --------
    >>> HuntCrossleyFoam(24.25e3, 71.9, densification_depth=0.02).stiffening
    1.0
    >>> HuntCrossleyFoam(24.25e3, 71.9, densification_depth=0.03, thickness=0.0254)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: HuntCrossleyFoam.densification_depth = 0.03 m ...
    """

    stiffness: float = as_field(_FOAM["stiffness"])
    damping: float = param(
        "C_c", "N s/m", doc="foam damping at eps = x_d", ge=0, le=1e10, typical=(43.8, 113.6)
    )
    densification_depth: float = param(
        "x_d", "m", doc="densification depth: the compression at which the spring locks up",
        gt=0, le=1, typical=(0.015, 0.025),
    )  # fmt: skip
    stiffening: float = param(
        "n", "", doc="densification exponent (0: a linear spring)", ge=0, le=10, default=1.0,
        typical=(0.0, 2.0),
    )  # fmt: skip
    damping_exponent: float = param(
        "p", "", doc="Hunt-Crossley damping exponent (0: a linear damper; else >= 1)", ge=0,
        le=3, default=1.0, typical=(0.0, 1.5),
    )  # fmt: skip
    thickness: float | None = param(
        "T_u", "m", doc="uncompressed thickness (>= densification_depth)", gt=0, le=1,
        optional=True, none="the densification depth scaled as the Ch. 4 foam, x 0.0254/0.02",
        default=None,
    )  # fmt: skip
    name: str = param(kind="text", default="", doc="optional label used in reports")

    def __post_init__(self) -> None:
        if 0.0 < self.damping_exponent < 1.0:
            raise InvalidParameterError(
                "HuntCrossleyFoam.damping_exponent", self.damping_exponent, "must be 0 or >= 1"
            )
        if self.thickness is None:
            object.__setattr__(self, "thickness", self.densification_depth * 0.0254 / 0.02)
        elif self.thickness < self.densification_depth:
            raise InvalidParameterError(
                "HuntCrossleyFoam.densification_depth",
                self.densification_depth,
                f"must be <= HuntCrossleyFoam.thickness = {self.thickness} m",
                "m",
            )


def _force_law(k: float, c: float, x_d: float, n: float, p: float) -> ForceLaw:
    """``f_c(eps, eps_dot)`` and its partial derivatives (see the module text).

    A scalar (one state of the integrator) is served by plain float arithmetic, an array
    (the samples of the histories) by numpy; both by the same formulas.
    """

    def scalar(x: float, xd: float) -> tuple[float, float, float]:
        xp = min(max(x / x_d, 0.0), 1.0 - 1e-15)
        spring = (1.0 - xp) ** -n
        d_spring = n / x_d * (1.0 - xp) ** (-n - 1.0) if x > 0 else 0.0
        damp = xp**p if p > 0 else 1.0
        d_damp = p / x_d * xp ** (p - 1.0) if p > 0 and x > 0 else 0.0
        return (
            k * x * spring + c * damp * xd,
            k * (spring + x * d_spring) + c * d_damp * xd,
            c * damp,
        )

    def law(x: NDArray, xd: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        if np.ndim(x) == 0:
            return scalar(float(x), float(xd))  # type: ignore[return-value]
        f = [
            scalar(a, b)
            for a, b in zip(np.ravel(x), np.ravel(np.broadcast_to(xd, np.shape(x))), strict=True)
        ]
        return tuple(np.reshape([r[i] for r in f], np.shape(x)) for i in range(3))  # type: ignore[return-value]

    return law


@dataclass(frozen=True)
class HuntCrossley(IntegratedContact):
    """The reduced joint with the non-linear foam (see the module text).

    Attributes
    ----------
    name, label, doc, robots, foam, columns, robot_attributes, foam_attributes
        As in :class:`~designlab.impact.contact.base.ContactModel`.
    linear_model, equations
        As there (no linear model: ``None``).
    linear, batched, gradients, profiles, printed_q2, response_form
        Its capabilities, as in :class:`~designlab.impact.contact.base.ContactModel`.
    """

    def force_law(self, k: float, c: float, x_d: float, n: float, p: float) -> ForceLaw:
        """The force law of one design (``K_c, C_c, x_d, n, p``)."""
        return _force_law(k, c, x_d, n, p)

    def force_law_of(self, values: Mapping[str, float]) -> ForceLaw:
        """The force law of one design from its row by name (K_c, C_c, x_d, n, p)."""
        return _force_law(*(values[c] for c in _LAW))

    def crush_depth_of(self, values: Mapping[str, float]) -> float | None:
        """x_d, where the spring locks up; ``None`` for a linear spring (n = 0)."""
        return values["x_d"] if values["n_d"] > 0 else None

    def valid_depth(self, foam: Any) -> float:
        """The densification depth x_d: the law's compression can never reach it."""
        return float(foam.densification_depth)


HUNT_CROSSLEY = HuntCrossley(
    name="hunt_crossley",
    label="Reduced joint, stiffening foam",
    doc="Hunt-Crossley damping and a densification spring; general path (integrated)",
    robots=(ContactDynamics, LinkImpact),
    foam=HuntCrossleyFoam,
    columns=(*PARAM_NAMES, "x_d", "n_d", "p_c"),
    robot_attributes=REDUCED_JOINT,
    foam_attributes=(
        *LINEAR_FOAM,
        ("x_d", "densification_depth"),
        ("n_d", "stiffening"),
        ("p_c", "damping_exponent"),
    ),
    equations="f_c = K_c eps (1 - eps+/x_d)^-n + C_c (eps+/x_d)^p eps_dot",
    linear=False,
    batched=False,
    gradients=False,
    profiles=False,
    response_form="",
)
