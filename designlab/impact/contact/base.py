"""The face of an impact contact model: what engines ask of a variant.

A contact model is one way of writing the manipulator-foam-head impact (Zeng 2011,
Sec. 3.4-3.5): the manipulator's model (the reduced joint of (3.4.9) or the full series
joint of (3.4.6)) and the foam's force law (the linear Kelvin-Voigt spring and damper of
(3.5.1), or a non-linear law). Each variant is one object of a subclass of
:class:`ContactModel`, declared in its own module with

* the parameter classes it serves (``robots``, ``foam``) and the names of its parameter
  row (``columns``): the row is built, and read, by name here and nowhere else outside
  the kernels;
* its equations (``equations``, one line for the docs) and how its first-lobe metrics are
  computed (:meth:`ContactModel.metrics`: an exact kernel, or the general response path
  of :mod:`designlab.impact.general`);
* its label and capabilities: ``linear`` (an exact closed-form kernel exists; otherwise
  the adaptive integrator), ``batched`` (many designs per compiled call), ``gradients``
  (exact metric gradients, :mod:`designlab.impact.derivatives`), ``profiles`` (velocity
  profiles in :func:`~designlab.impact.simulate`).

Engines (simulate, the worst-case problem behind the envelope, the worst-case check, the
co-design callers) look the variant of a (robot, foam) pair up in
:data:`~designlab.impact.contact.CONTACTS` and ask it; they never test its class.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.parameters import STOP_TIME

__all__ = [
    "HEAD_COLUMNS",
    "ContactModel",
    "reduced_joint_labels",
    "reduced_joint_values",
]

#: The head-neck columns of every parameter row, in the order of ``head_rows``.
HEAD_COLUMNS: tuple[str, ...] = ("M_h", "C_h", "K_h")


def reduced_joint_values(robot: Any, levers: NDArray | None) -> dict[str, Any]:
    """M_r, C_r, K_r of the reduced joint: a fixed manipulator, or a link at ``levers`` (3.4.17).

    Parameters
    ----------
    robot
        A :class:`~designlab.impact.parameters.ContactDynamics` or a
        :class:`~designlab.impact.parameters.LinkImpact` (``robot.along_link``).
    levers
        Lever arms, m (a link only).
    """
    if robot.along_link:
        l2 = np.asarray(levers, dtype=float) ** 2
        return {"M_r": robot.inertia / l2, "C_r": robot.joint_damping / l2,
                "K_r": robot.joint_stiffness / l2}  # fmt: skip
    return {"M_r": robot.mass, "C_r": robot.damping, "K_r": robot.stiffness}


def reduced_joint_labels(along_link: bool) -> dict[str, str]:
    """The arguments behind M_r, C_r, K_r: a fixed manipulator's, or a link's joint values.

    Parameters
    ----------
    along_link
        The robot is a link (``robot.inertia``, ``robot.joint_damping``, ...).
    """
    if along_link:
        return {"M_r": "robot.inertia", "C_r": "robot.joint_damping",
                "K_r": "robot.joint_stiffness"}  # fmt: skip
    return {"M_r": "robot.mass", "C_r": "robot.damping", "K_r": "robot.stiffness"}


@dataclass(frozen=True)
class ContactModel:
    """One impact contact model (see the module text).

    Attributes
    ----------
    name, label, doc
        Public name, report label and one-line description.
    robots
        The manipulator classes it serves (a robot struck along a link included).
    foam
        The foam class it serves.
    columns
        Names of its parameter row, in order.
    robot_columns
        Names of the manipulator's columns (a subset of ``columns``).
    foam_columns
        Names of the foam's columns beyond K_c and C_c (its fixed shape).
    equations
        The force law or state space, one line.
    linear, batched, gradients, profiles
        Capabilities (see the module text).
    printed_q2
        The thesis's printed q2 of (3.5.14) applies (the reduced joint's model).
    response_form
        How :func:`~designlab.impact.simulate` builds the exact time histories of a linear
        model: ``"transfer_function"`` (closed-form ramp numerators) or ``"state_space"``
        (modal families of the state space, with a feed-forward input at the motor);
        ``""`` for a non-linear model (integrated).
    """

    name: str
    label: str
    doc: str
    robots: tuple[type, ...]
    foam: type
    columns: tuple[str, ...]
    robot_columns: tuple[str, ...]
    foam_columns: tuple[str, ...] = ()
    equations: str = ""
    linear: bool = True
    batched: bool = True
    gradients: bool = False
    profiles: bool = True
    printed_q2: bool = False
    response_form: str = "transfer_function"

    #: the constrained head's placeholder row (its entries do not enter the equations)
    NO_HEAD: ClassVar[tuple[float, float, float]] = (1.0, 0.0, 0.0)

    # ---------------------------------------------------------------- rows
    def serves(self, robot: object, foam: object | None) -> bool:
        """Whether this model is the one of ``robot`` (its exact class) and ``foam``."""
        return type(robot) in self.robots and (foam is None or type(foam) is self.foam)

    def robot_row(self, robot: Any, levers: NDArray | None = None) -> NDArray[np.float64]:
        """``(n, len(robot_columns))`` manipulator rows: the robot, or a link at ``levers``.

        Parameters
        ----------
        robot
            A manipulator of :attr:`robots`.
        levers
            Lever arms (m) of a robot struck along its link; ignored for a fixed robot.
        """
        values = self._robot_values(robot, levers)
        return np.column_stack([np.atleast_1d(values[c]) for c in self.robot_columns])

    def _robot_values(self, robot: Any, levers: NDArray | None) -> Mapping[str, Any]:
        raise NotImplementedError  # pragma: no cover - every variant implements it

    def foam_values(self, foam: Any) -> dict[str, float]:
        """The foam's shape columns (beyond K_c and C_c) by name."""
        return {}

    def assemble(
        self,
        robot_rows: NDArray,
        stiffness: NDArray,
        damping: NDArray,
        heads: NDArray,
        foam: Any = None,
    ) -> NDArray[np.float64]:
        """Parameter rows from paired robot rows, foam (K_c, C_c) and head rows (``(n, 3)``).

        Parameters
        ----------
        robot_rows
            ``(n, len(robot_columns))`` as :meth:`robot_row`.
        stiffness, damping
            ``(n,)`` K_c and C_c.
        heads
            ``(n, 3)`` rows of :data:`HEAD_COLUMNS`.
        foam
            The foam whose shape columns are kept (a non-linear law's), or ``None``.
        """
        n = np.asarray(stiffness).size
        by_name: dict[str, Any] = dict(
            zip(self.robot_columns, np.asarray(robot_rows).T, strict=True)
        )
        by_name.update(zip(HEAD_COLUMNS, np.asarray(heads).T, strict=True))
        by_name.update({"K_c": stiffness, "C_c": damping})
        by_name.update(self.foam_values(foam) if foam is not None else {})
        missing = [c for c in self.columns if c not in by_name]
        if missing:
            raise InvalidParameterError(
                "foam", foam, f"is needed by the {self.label} contact (its {missing})"
            )
        return np.column_stack([np.broadcast_to(by_name[c], (n,)) for c in self.columns])

    def row(self, robot: Any, foam: Any, head: Any | None) -> NDArray[np.float64]:
        """The ``(len(columns),)`` parameter row of one impact (``head=None``: constrained)."""
        h = self.NO_HEAD if head is None else (head.mass, head.damping, head.stiffness)
        return self.assemble(
            self.robot_row(robot),
            np.array([foam.stiffness]),
            np.array([foam.damping]),
            np.array([h]),
            foam,
        )[0]

    def column(self, rows: NDArray, name: str) -> NDArray[np.float64]:
        """The column ``name`` of parameter rows (``(n, len(columns))``)."""
        return np.atleast_2d(rows)[:, self.columns.index(name)]

    def head_values(self, row: NDArray) -> dict[str, float]:
        """``{"mass", "damping", "stiffness"}`` of the head of one parameter row."""
        m, c, k = (float(self.column(row, n)[0]) for n in HEAD_COLUMNS)
        return {"mass": m, "damping": c, "stiffness": k}

    def input_labels(
        self, head: object | None, *, along_link: bool = False
    ) -> tuple[str | None, ...]:
        """The argument behind each column (``robot.mass``, ...; ``None``: no head given).

        Parameters
        ----------
        head
            The head (``None``: the constrained head, or the columns of a head grid).
        along_link
            The robot is a link: its columns come from its joint values (``robot.inertia``).
        """
        labels = dict(self._labels(along_link))
        for c, attr in zip(HEAD_COLUMNS, ("mass", "damping", "stiffness"), strict=True):
            labels[c] = None if head is None else f"head.{attr}"
        return tuple(labels[c] for c in self.columns)

    def _labels(self, along_link: bool) -> Mapping[str, str]:
        raise NotImplementedError  # pragma: no cover - every variant implements it

    # ---------------------------------------------------------------- responses
    def model(self, constrained: bool) -> Any:
        """The linear model (:class:`~designlab.impact.model.LinearImpactModel`) of a
        linear contact; the constrained one (head against a wall) if ``constrained``."""
        raise InvalidParameterError(
            "contact", self.name, "has no linear model: its responses are integrated"
        )

    def valid_depth(self, foam: Any) -> float:
        """The compression beyond which the foam's law is not valid (bottoming), m."""
        return float(foam.linear_depth)

    def integrate(
        self, robot: Any, foam: Any, head: Any, impact_velocity: float, **options: Any
    ) -> tuple[Any, Any]:
        """First-lobe metrics and time histories of one impact by the general path."""
        raise InvalidParameterError(
            "contact", self.name, "is linear: its responses come from the exact kernels"
        )

    def metrics(self, rows: NDArray, impact_velocity: Any, **options: Any) -> Any:
        """First-lobe metrics (:class:`~designlab.impact.metrics.ImpactMetrics`) of rows."""
        raise NotImplementedError  # pragma: no cover - every variant implements it

    def values(
        self,
        key: Any,
        rows: NDArray,
        impact_velocity: NDArray,
        *,
        constrained: bool = False,
        stop_time: float = STOP_TIME.default,
    ) -> NDArray[np.float64]:
        """The metric of criterion ``key`` for rows (the exact kernel's path by default)."""
        return key.values(rows, impact_velocity, constrained=constrained, stop_time=stop_time)

    def check_foam(self, foam: Any, robot: Any) -> None:
        """Refuse a foam this model cannot take with ``robot`` (``foam`` must be :attr:`foam`)."""
        if type(foam) is not self.foam:
            raise InvalidParameterError(
                "foam", foam, f"must be a {self.foam.__name__} for a {type(robot).__name__} robot"
            )
