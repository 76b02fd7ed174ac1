"""The face of an impact contact model: what engines ask of a variant.

A contact model is one way of writing the manipulator-foam-head impact (Zeng 2011,
Sec. 3.4-3.5): the manipulator's model (the reduced joint of (3.4.9) or the full series
joint of (3.4.6)) and the foam's force law (the linear Kelvin-Voigt spring and damper of
(3.5.1), or a non-linear law). Each variant is one :class:`ContactModel` (a linear one
with an exact kernel), or one object of a subclass (a non-linear one, which brings its
force law), declared in its own module with

* the parameter classes it serves (``robots``, ``foam``), the names of its parameter row
  (``columns``) and the attributes each column is read from (``robot_attributes``,
  ``foam_attributes``): the row is built, labelled and read by name here and nowhere
  else outside the kernels;
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

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.metrics import metrics_of_matrix
from designlab.impact.parameters import STOP_TIME, HeadNeck
from designlab.params import params_of

__all__ = [
    "HEAD_COLUMNS",
    "LINEAR_FOAM",
    "REDUCED_JOINT",
    "ContactModel",
]

#: The head-neck columns of every parameter row, in the order of ``head_rows``.
HEAD_COLUMNS: tuple[str, ...] = ("M_h", "C_h", "K_h")
#: The :class:`~designlab.impact.parameters.HeadNeck` fields of :data:`HEAD_COLUMNS`.
_HEAD_FIELDS = ("mass", "damping", "stiffness")


#: The reduced joint's manipulator columns (3.4.9): (column, a fixed manipulator's attribute,
#: a link's attribute; a link's value is divided by its lever arm squared, (3.4.17)).
REDUCED_JOINT: tuple[tuple[str, str, str], ...] = (
    ("M_r", "mass", "inertia"),
    ("C_r", "damping", "joint_damping"),
    ("K_r", "stiffness", "joint_stiffness"),
)

#: The linear foam's columns (3.5.1): (column, the foam's attribute).
LINEAR_FOAM: tuple[tuple[str, str], ...] = (("K_c", "stiffness"), ("C_c", "damping"))


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
    robot_attributes
        The manipulator's columns (a subset of ``columns``) as ``(column, a fixed
        manipulator's attribute, a link's attribute)``; a link's value is divided by its
        lever arm squared (3.4.17). :data:`REDUCED_JOINT` for the reduced joint.
    foam_attributes
        The foam's columns as ``(column, attribute)``: :data:`LINEAR_FOAM` (K_c, C_c)
        and, for a non-linear law, its shape columns after them.
    linear_model
        ``linear_model(constrained)``: the linear model
        (:class:`~designlab.impact.model.LinearImpactModel`) of a linear contact; ``None``
        for a non-linear one.
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
    robot_attributes: tuple[tuple[str, str, str], ...]
    foam_attributes: tuple[tuple[str, str], ...] = LINEAR_FOAM
    linear_model: Callable[[bool], Any] | None = None
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
    @property
    def robot_columns(self) -> tuple[str, ...]:
        """Names of the manipulator's columns (a subset of :attr:`columns`)."""
        return tuple(c for c, _, _ in self.robot_attributes)

    @property
    def foam_columns(self) -> tuple[str, ...]:
        """Names of the foam's columns beyond K_c and C_c (its fixed shape)."""
        return tuple(c for c, _ in self.foam_attributes if c not in ("K_c", "C_c"))

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
        if robot.along_link:
            l2 = np.asarray(levers, dtype=float) ** 2
            values = [getattr(robot, link) / l2 for _, _, link in self.robot_attributes]
        else:
            values = [getattr(robot, fixed) for _, fixed, _ in self.robot_attributes]
        return np.column_stack([np.atleast_1d(v) for v in values])

    def foam_values(self, foam: Any) -> dict[str, float]:
        """The foam's shape columns (beyond K_c and C_c) by name."""
        shape = [(c, a) for c, a in self.foam_attributes if c in self.foam_columns]
        if shape and type(foam) is not self.foam:
            raise InvalidParameterError("foam", foam, f"must be a {self.foam.__name__}")
        return {c: getattr(foam, a) for c, a in shape}

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

    def check_rows(self, rows: NDArray, constrained: bool) -> None:
        """Refuse a row entry outside its declaration (the robot's, foam's or head's field
        the column is read from), naming the column and the design: ``M_r[3] = -1.0 kg``.

        Parameters
        ----------
        rows
            ``(n, len(columns))`` parameter rows.
        constrained
            The head is constrained: its placeholder columns are not checked.
        """
        robot, foam = params_of(self.robots[0]), params_of(self.foam)
        decls = {c: robot[fixed] for c, fixed, _ in self.robot_attributes}
        decls.update({c: foam[a] for c, a in self.foam_attributes})
        if not constrained:
            head = params_of(HeadNeck)
            decls.update({c: head[a] for c, a in zip(HEAD_COLUMNS, _HEAD_FIELDS, strict=True)})
        for c, decl in decls.items():
            for j, x in enumerate(self.column(rows, c)):
                decl.check(float(x), f"{c}[{j}]")

    def head_values(self, row: NDArray) -> dict[str, float]:
        """``{"mass", "damping", "stiffness"}`` of the head of one parameter row."""
        return {
            a: float(self.column(row, c)[0])
            for c, a in zip(HEAD_COLUMNS, _HEAD_FIELDS, strict=True)
        }

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
        labels: dict[str, str | None] = {
            c: f"robot.{link if along_link else fixed}" for c, fixed, link in self.robot_attributes
        }
        labels.update({c: f"foam.{a}" for c, a in self.foam_attributes})
        for c, attr in zip(HEAD_COLUMNS, _HEAD_FIELDS, strict=True):
            labels[c] = None if head is None else f"head.{attr}"
        return tuple(labels[c] for c in self.columns)

    # ---------------------------------------------------------------- responses
    def model(self, constrained: bool) -> Any:
        """The linear model (:class:`~designlab.impact.model.LinearImpactModel`) of a
        linear contact; the constrained one (head against a wall) if ``constrained``."""
        if self.linear_model is None:
            raise InvalidParameterError(
                "contact", self.name, "has no linear model: its responses are integrated"
            )
        return self.linear_model(constrained)

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
        """First-lobe metrics (:class:`~designlab.impact.metrics.ImpactMetrics`) of rows:
        the exact kernel of a linear model (:func:`~designlab.impact.metrics.metrics_of_matrix`).
        """
        return metrics_of_matrix(rows, impact_velocity, **options)

    def values(
        self,
        key: Any,
        rows: NDArray,
        impact_velocity: NDArray,
        *,
        constrained: bool = False,
        stop_time: float = STOP_TIME.default,
    ) -> NDArray[np.float64]:
        """The metric of criterion ``key`` for rows: the exact kernel's path of a linear model;
        of a non-linear one, its first-lobe metrics (:meth:`metrics`, the general path), which
        serve a_h,max, the peak force and eps_max (HIC needs a linear model's closed form)."""
        if self.linear:
            return key.values(rows, impact_velocity, constrained=constrained, stop_time=stop_time)
        if key.metric not in ("head_acceleration", "force", "compression"):
            raise InvalidParameterError(
                "criteria", key.name, f"the {self.label} contact serves a_h,max, the peak force "
                "and eps_max (HIC needs the closed-form response of a linear contact)",
            )  # fmt: skip
        m = self.metrics(rows, impact_velocity, constrained=constrained, stop_time=stop_time)
        return key.from_metrics(m)

    def check_foam(self, foam: Any, robot: Any) -> None:
        """Refuse a foam this model cannot take with ``robot`` (``foam`` must be :attr:`foam`)."""
        if type(foam) is not self.foam:
            raise InvalidParameterError(
                "foam", foam, f"must be a {self.foam.__name__} for a {type(robot).__name__} robot"
            )
