"""Parameter objects of the full series joint (Zeng 2011, eq. 3.4.6).

A position-controlled joint is a transmission (K_mech, C_mech) in series with
the PD controller (K_cont, C_cont). Three views of it:

* :class:`SeriesJoint`, the joint at joint level (N m/rad, N m s/rad) struck at
  lever arm ``l``: the inputs of the ``joint_reduction`` study;
* :class:`FullJointContact`, the same joint at the impact point: every value
  divided by l^2 (3.4.17), the manipulator of the impact model with the full
  joint (:mod:`designlab.impact.full_joint_model`);
* :class:`FullJointLink`, a link struck anywhere along it (Sec. 3.7.3), with
  its transmission kept.

Examples
--------
>>> joint = SeriesJoint(0.059, k_mech=2e3, c_mech=2.0, k_cont=1.5e3, c_cont=30.0, lever_arm=0.2)
>>> arm = joint.contact()
>>> round(arm.mass, 3), round(arm.stiffness_ratio, 3)
(1.475, 1.333)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.joint import JointFit, fit_joint_band, reduced_joint
from designlab.impact.parameters import (
    C_CONT,
    C_MECH,
    K_CONT,
    K_MECH,
    ContactDynamics,
    LinkImpact,
    as_field,
)
from designlab.params import declared, param, params_of
from designlab.validation import ParamsMixin

__all__ = ["FullJointContact", "FullJointLink", "SeriesJoint"]

_LINK = params_of(LinkImpact)
_CONTACT = params_of(ContactDynamics)


def _damped(owner: str, field: str, c_a: float, c_b: float, unit: str) -> None:
    if c_a + c_b <= 0.0:
        raise InvalidParameterError(
            f"{owner}.{field}",
            c_b,
            "the transmission and control dampings must not both be 0 (a massless motor "
            "node between two undamped springs has no dynamics)",
            unit,
        )


@declared
@dataclass(frozen=True)
class FullJointContact(ParamsMixin):
    """A single-joint manipulator with the full series joint (3.4.6), at the impact point.

    All values are effective (prismatic, along the impact normal): joint values
    divided by l^2, (3.4.17). Use :meth:`from_joint` (or :class:`SeriesJoint`)
    for joint-level data. The two dampings must not both be zero (the massless
    motor node then has no dynamics of its own).

    Examples
    --------
    >>> arm = FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    >>> round(arm.mass, 3), round(arm.taylor().stiffness, 1), round(arm.taylor().damping, 1)
    (1.475, 21428.6, 254.1)
    """

    # effective values have no upper bound: near the joint they grow as 1/l^2 (3.4.17)
    mass: float = as_field(_CONTACT["mass"])
    transmission_stiffness: float = param(
        "K_mech/l^2", "N/m", doc="effective transmission stiffness", gt=0
    )
    transmission_damping: float = param(
        "C_mech/l^2", "N s/m", doc="effective transmission damping", ge=0
    )
    control_stiffness: float = param(
        "K_cont/l^2", "N/m", doc="effective control stiffness (P gain)", gt=0
    )
    control_damping: float = param("C_cont/l^2", "N s/m", doc="effective control damping", ge=0)
    lever_arm: float | None = as_field(_CONTACT["lever_arm"], default=None)
    name: str = param(kind="text", default="", doc="optional label used in reports")

    #: a fixed manipulator: struck at one point, at a given v_c
    along_link: ClassVar[bool] = False

    def __post_init__(self) -> None:
        _damped(
            "FullJointContact",
            "control_damping",
            self.transmission_damping,
            self.control_damping,
            "N s/m",
        )

    @classmethod
    def from_joint(
        cls,
        inertia: float,
        k_mech: float,
        c_mech: float,
        k_cont: float,
        c_cont: float,
        *,
        lever_arm: float,
        name: str = "",
    ) -> FullJointContact:
        """Build from joint-level values (kg m^2, N m/rad, N m s/rad) at lever arm ``l`` (m).

        Scenario 1/2 reduction (3.4.17): every value is divided by ``l^2``
        (:meth:`SeriesJoint.contact`).

        Parameters
        ----------
        inertia, k_mech, c_mech, k_cont, c_cont, lever_arm, name
            The fields of :class:`SeriesJoint`.

        Returns
        -------
        FullJointContact
        """
        return SeriesJoint(inertia, k_mech, c_mech, k_cont, c_cont, lever_arm, name).contact()

    @property
    def stiffness_ratio(self) -> float:
        """K_mech / K_cont: large for a direct drive, where the reduction is exact in the limit."""
        return self.transmission_stiffness / self.control_stiffness

    @property
    def corner_frequency(self) -> float:
        """(K_mech + K_cont) / (C_mech + C_cont), rad/s: the pole of (3.4.6)."""
        return (self.transmission_stiffness + self.control_stiffness) / (
            self.transmission_damping + self.control_damping
        )

    def joint_values(self) -> tuple[float, float, float, float]:
        """The joint's values at the impact point.

        Returns
        -------
        tuple of float
            ``(K_mech, C_mech, K_cont, C_cont)`` in N/m and N s/m.
        """
        return (
            self.transmission_stiffness,
            self.transmission_damping,
            self.control_stiffness,
            self.control_damping,
        )

    def with_ratio(self, ratio: float) -> FullJointContact:
        """This arm with the transmission stiffness ``ratio * K_cont`` (all else kept).

        Parameters
        ----------
        ratio
            K_mech / K_cont (> 0).

        Returns
        -------
        FullJointContact
        """
        return self.replace(transmission_stiffness=float(ratio) * self.control_stiffness)

    def taylor(self) -> ContactDynamics:
        """The reduced manipulator of the thesis: K_r, C_r from (3.4.9) (Taylor truncation).

        Returns
        -------
        ContactDynamics
            M_r of this arm with the Taylor K_J, C_J (effective values).
        """
        k, c = reduced_joint(*self.joint_values())
        return ContactDynamics(self.mass, k, c, lever_arm=self.lever_arm, name=self.name)

    def band_fit(self, omega_max: float, **kwargs: Any) -> tuple[ContactDynamics, JointFit]:
        """The reduced manipulator fitted over ``[omega_max/1000, omega_max]`` rad/s.

        An extension of the thesis (:func:`~designlab.impact.joint.fit_joint_band`).

        Parameters
        ----------
        omega_max
            Upper end of the band, rad/s (> 0).
        **kwargs
            Further arguments of :func:`~designlab.impact.joint.fit_joint_band`
            (``n``, ``omega_min``, ``weights``).

        Returns
        -------
        tuple
            The manipulator (``None`` if the fit failed) and the
            :class:`~designlab.impact.joint.JointFit` (check ``fit.success``).
        """
        fit = fit_joint_band(*self.joint_values(), omega_max=omega_max, **kwargs)
        contact = None
        if fit.success:
            contact = ContactDynamics(
                self.mass, fit.stiffness, fit.damping, lever_arm=self.lever_arm, name=self.name
            )
        return contact, fit  # type: ignore[return-value]


@declared
@dataclass(frozen=True)
class SeriesJoint(ParamsMixin):
    """One joint at joint level, struck at ``lever_arm`` (scenarios 1/2, Sec. 3.4.3).

    The transmission (K_mech, C_mech) in series with the PD controller
    (K_cont, C_cont), (3.4.6). The two dampings must not both be zero.

    Examples
    --------
    >>> SeriesJoint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2).contact().control_stiffness
    37500.0...
    """

    inertia: float = as_field(_LINK["inertia"])
    k_mech: float = as_field(K_MECH)
    c_mech: float = as_field(C_MECH)
    k_cont: float = as_field(K_CONT)
    c_cont: float = as_field(C_CONT)
    lever_arm: float = param(
        "l", "m", doc="distance from the joint axis to the impact point", ge=1e-6, le=100
    )
    name: str = param(kind="text", default="", doc="optional label used in reports")

    def __post_init__(self) -> None:
        _damped("SeriesJoint", "c_cont", self.c_mech, self.c_cont, "N m s/rad")

    def contact(self) -> FullJointContact:
        """The joint at the impact point: every value divided by ``lever_arm**2`` (3.4.17).

        Returns
        -------
        FullJointContact
        """
        l2 = self.lever_arm * self.lever_arm
        return FullJointContact(
            self.inertia / l2,
            self.k_mech / l2,
            self.c_mech / l2,
            self.k_cont / l2,
            self.c_cont / l2,
            lever_arm=self.lever_arm,
            name=self.name,
        )


@declared
@dataclass(frozen=True, kw_only=True)
class FullJointLink(LinkImpact):
    """A joint with its full series joint (3.4.6), struck anywhere along its link (Sec. 3.7.3).

    The :class:`~designlab.impact.parameters.LinkImpact` of the thesis's
    scenarios 1 and 2, with the transmission kept: ``joint_stiffness`` and
    ``joint_damping`` are the controller's K_cont (> 0) and C_cont (N m/rad,
    N m s/rad), ``transmission_stiffness`` and ``transmission_damping`` the
    transmission's K_mech and C_mech (keyword arguments). At lever arm ``l``
    the manipulator is :meth:`contact` ``(l)``, every value divided by ``l^2``
    (3.4.17). :func:`~designlab.impact.envelope.foam_envelope` searches the
    worst impact point with the full joint.

    Examples
    --------
    >>> link = FullJointLink(0.059, 1.5e3, 30.0, 1.0, 0.05, 0.3,
    ...                      transmission_stiffness=2e3, transmission_damping=2.0)
    >>> arm = link.contact(0.2)
    >>> round(arm.mass, 3), round(arm.stiffness_ratio, 3)
    (1.475, 1.333)
    """

    transmission_stiffness: float = as_field(K_MECH)
    transmission_damping: float = as_field(C_MECH, default=0.0)

    def __post_init__(self) -> None:
        super().__post_init__()
        K_CONT.check(self.joint_stiffness, "FullJointLink.joint_stiffness")
        _damped(
            "FullJointLink",
            "joint_damping",
            self.transmission_damping,
            self.joint_damping,
            "N m s/rad",
        )

    def contact(self, lever_arm: float) -> FullJointContact:  # type: ignore[override]
        """The full-joint manipulator at ``lever_arm`` (m), (3.4.17).

        Parameters
        ----------
        lever_arm
            l, m (> 0).

        Returns
        -------
        FullJointContact
            Every value divided by ``l^2``.
        """
        return SeriesJoint(
            self.inertia,
            self.transmission_stiffness,
            self.transmission_damping,
            self.joint_stiffness,
            self.joint_damping,
            lever_arm=lever_arm,
            name=self.name,
        ).contact()

    def effective_rows(self, levers: ArrayLike) -> NDArray[np.float64]:
        """``(n, 5)`` rows ``[M_r, C_mech, K_mech, C_cont, K_cont]`` at the lever arms.

        Parameters
        ----------
        levers
            Lever arms, m.

        Returns
        -------
        numpy.ndarray
            Effective values (joint values divided by ``l^2``), SI units.
        """
        l2 = np.asarray(levers, dtype=float) ** 2
        return np.column_stack(
            [
                self.inertia / l2,
                self.transmission_damping / l2,
                self.transmission_stiffness / l2,
                self.joint_damping / l2,
                self.joint_stiffness / l2,
            ]
        )
