"""The face of a navigation method: what engines, kinds and reports may ask of it.

A method is one object registered by its public name in
:data:`designlab.navigation.methods.METHODS`. It says

* its ``name``, report ``label`` and one-line ``doc``;
* its gains (``gains_type``, ``used_gains``, the default, the row of the simulator's gain
  array, the gains of a row, the tie side it implies);
* its capabilities: ``force_field`` (a virtual force, simulated by the engine) or
  ``planner`` (a Sec. 5.7 planner commanding a velocity, :class:`Planner`),
  ``batched`` (many gain sets at once), ``stabilised`` (the Lyapunov stabilising force
  F_L of (5.4.6) and its audit), ``filtered`` (one CBF QP per period corrects its
  force), ``crowds`` (simulated among pedestrians), ``baseline`` (a Sec. 2.2.4 baseline
  of Table C.1), ``fixed_sense`` (its gains carry a fixed detour sense);
* its computation: the force builder :meth:`NavigationMethod.forces` written in the terms
  of :mod:`designlab.navigation.field_terms`.

Engines never test a method's name; they look the method up and ask it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from designlab.errors import InvalidParameterError
from designlab.navigation.field_terms import Forces, Obs, Symbols
from designlab.navigation.parameters import VFFGains
from designlab.params import Param

__all__ = [
    "GAIN_COLUMNS",
    "STABILISING",
    "TIE_SIDE",
    "CrowdController",
    "Filtered",
    "NavigationMethod",
    "Planner",
    "goal_velocity",
]

#: The columns of the simulator's gain array (k1, b, k3, k5).
GAIN_COLUMNS = ("k1", "b", "k3", "k5")

#: The stabilising force F_L of (5.4.6): ``"lyapunov"`` (on) or ``"off"`` (how the thesis's
#: tables come back, docs/navigation.md).
STABILISING = Param(
    doc="stabilising force F_L of (5.4.6)",
    kind="choice",
    choices=("lyapunov", "off"),
    name="stabilising",
)
#: The detour side where the direction rules leave it open (``"+y"`` or ``"-y"``).
TIE_SIDE = Param(
    doc="detour side where the rules leave it open (docs/navigation.md, 'The force field')",
    kind="choice",
    choices=("+y", "-y"),
    name="tie_side",
)


class NavigationMethod:
    """One force-field navigation method: its gains, capabilities and force.

    Parameters
    ----------
    name
        The public name (``method="vff"``).
    label
        The label in reports and docs tables.
    doc
        One line: what the method is, with its source.
    """

    #: The gains class of the method (``None``: it takes settings, not gains).
    gains_type: Any = VFFGains
    #: The gain columns the method reads (Masoud's has no b).
    used_gains: tuple[str, ...] = GAIN_COLUMNS
    #: A virtual force simulated by the engine (not a planner).
    force_field: bool = True
    #: A Sec. 5.7 planner commanding a velocity.
    planner: bool = False
    #: Whether many gain sets can be simulated together.
    batched: bool = True
    #: Whether the method has the Lyapunov stabilising force (and an audit).
    stabilised: bool = False
    #: Whether one CBF QP per period corrects its force.
    filtered: bool = False
    #: Whether the CBF barrier is tightened by the sampled-data margin a_max T_s^2 / 2.
    sampled_margin: bool = False
    #: Whether it is simulated among a crowd of pedestrians.
    crowds: bool = True
    #: Whether it is a Sec. 2.2.4 baseline (Table C.1).
    baseline: bool = False
    #: Whether its gains carry a fixed detour sense (the tie side is theirs).
    fixed_sense: bool = False

    def __init__(self, name: str, label: str, doc: str = "") -> None:
        self.name = name
        self.label = label
        self.doc = doc

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r})"

    # ------------------------------------------------------------------ gains
    def default_gains(self) -> Any:
        """The gains used when none are given (``None``: gains are required)."""
        return self.gains_type()

    @property
    def gains_required(self) -> bool:
        """Whether gains must be given (the method has no default)."""
        return self.default_gains() is None

    def gains(self, gains: Any) -> Any:
        """The gains checked for this method (the default if ``None``).

        Parameters
        ----------
        gains
            The gains given, or ``None``.
        """
        g = self.default_gains() if gains is None else gains
        if not isinstance(g, self.gains_type):
            raise InvalidParameterError(
                "gains", gains, f"must be a {self.gains_type.__name__} for method {self.name!r}"
            )
        return g

    def gain_row(self, gains: Any) -> np.ndarray:
        """The gains as one row (k1, b, k3, k5) of the simulator's gain array.

        Parameters
        ----------
        gains
            The gains given, or ``None`` (the default).
        """
        g = self.gains(gains)
        return np.array([getattr(g, k) if k in self.used_gains else 0.0 for k in GAIN_COLUMNS])

    def gains_dict(self, row: np.ndarray) -> dict[str, float]:
        """The gains of a row, by name, as results report them.

        Parameters
        ----------
        row
            A row (k1, b, k3, k5) of the gain array.
        """
        return {k: float(v) for k, v in zip(GAIN_COLUMNS, row, strict=True) if k in self.used_gains}

    def gains_of_row(self, row: Any, tie_side: str = "+y") -> Any:
        """The gains object of a row (k1, b, k3, k5), as the gain tuner returns it.

        Parameters
        ----------
        row
            A row of the gain array.
        tie_side
            The tie side (a method with a fixed sense takes it as its sense).
        """
        values = dict(zip(GAIN_COLUMNS, (float(v) for v in row), strict=True))
        return self.gains_type(**{k: values[k] for k in self.used_gains})

    def tie(self, gains: Any, tie_side: str) -> int:
        """The tie side +1 / -1 the field uses.

        Parameters
        ----------
        gains
            The gains given.
        tie_side
            ``"+y"`` or ``"-y"``.
        """
        return 1 if tie_side == "+y" else -1

    # ------------------------------------------------------------------ force
    def forces(self, items: list[Obs], s: Symbols) -> Forces:
        """The method's force (and Lyapunov terms) in the field's symbols.

        Parameters
        ----------
        items
            The obstacles' symbolic quantities.
        s
            The robot's symbols.
        """
        raise NotImplementedError(f"{type(self).__name__} does not define its force")


class Filtered(NavigationMethod):
    """A method whose force one CBF QP per period corrects (the same field, filtered).

    Its gains, force and stabilising force are the nominal method's; it is not batched
    nor run among crowds, and its barrier is tightened by the sampled-data margin.

    Parameters
    ----------
    name, label, doc
        As for :class:`NavigationMethod`.
    nominal
        The force-field method whose force is filtered.
    """

    batched = False
    filtered = True
    sampled_margin = True
    crowds = False

    def __init__(self, name: str, label: str, doc: str = "", *, nominal: Any) -> None:
        if not isinstance(nominal, NavigationMethod) or not nominal.force_field:
            raise InvalidParameterError(
                "Filtered.nominal", nominal, "must be a force-field NavigationMethod"
            )
        super().__init__(name, label, doc)
        self.nominal = nominal
        self.gains_type = nominal.gains_type
        self.used_gains = nominal.used_gains
        self.stabilised = nominal.stabilised
        self.fixed_sense = nominal.fixed_sense

    def default_gains(self) -> Any:
        return self.nominal.default_gains()

    def gains_of_row(self, row: Any, tie_side: str = "+y") -> Any:
        return self.nominal.gains_of_row(row, tie_side)

    def tie(self, gains: Any, tie_side: str) -> int:
        return self.nominal.tie(gains, tie_side)

    def forces(self, items: list[Obs], s: Symbols) -> Forces:
        return self.nominal.forces(items, s)


class Planner(NavigationMethod):
    """A Sec. 5.7 planner: it commands a velocity each period (no force field, no gains).

    :func:`designlab.navigation.planners.simulate_planner` runs it: the robot tracks the
    commanded velocity at its acceleration limit (``docs/navigation_planners.md``).

    Parameters
    ----------
    name, label, doc
        As for :class:`NavigationMethod`.
    """

    gains_type = None
    used_gains = ()
    force_field = False
    planner = True
    batched = False
    crowds = False
    gains_required = False  # type: ignore[assignment]
    #: Its settings class (each default from its paper).
    settings_type: Any = None
    #: Whether it is randomised (runs differ by their settings' seed).
    seeded = False

    def default_gains(self) -> Any:
        raise InvalidParameterError(
            "gains", None, f"do not apply to {self.name!r}, a Sec. 5.7 planner: it takes settings"
        )

    def gains(self, gains: Any) -> Any:
        return self.default_gains()

    def settings(self, settings: Any) -> Any:
        """The settings checked for this planner (its defaults if ``None``).

        Parameters
        ----------
        settings
            The settings given, or ``None``.
        """
        cls = self.settings_type
        out = cls() if settings is None else settings
        if not isinstance(out, cls):
            raise InvalidParameterError("settings", settings, f"must be a {cls.__name__}")
        return out

    def check_run(self, scenario: Any, settings: Any, steps: int, step: float) -> None:
        """Refuse a run too large for the planner before it starts (none is, by default).

        Parameters
        ----------
        scenario
            The scenario.
        settings
            The planner's settings.
        steps
            Dynamics steps of the run.
        step
            The dynamics step in s.
        """

    def commander(
        self, scenario: Any, settings: Any, toward: Callable[[Any, Any], Any]
    ) -> Callable[..., Any]:
        """The planner as ``command(world, position, velocity) -> velocity``.

        Parameters
        ----------
        scenario
            The scenario (goal, robot limits, navigation period).
        settings
            The planner's settings.
        toward
            ``toward(position, waypoint) -> velocity``: toward a waypoint at the robot's
            speed, braking to stop at the goal.
        """
        raise NotImplementedError(f"{type(self).__name__} does not define its commander")

    def forces(self, items: list[Obs], s: Symbols) -> Forces:
        raise InvalidParameterError("method", self.name, "is a Sec. 5.7 planner: no force field")


class CrowdController(NavigationMethod):
    """A robot controller among crowds from the field's baselines: it commands a velocity
    each navigation period from the pedestrians' positions and velocities (no force field,
    no gains: settings, each default from its source).

    :func:`designlab.navigation.crowds.simulate_crowd` runs it: the robot (holonomic) tracks
    the commanded velocity at its acceleration and speed limits (``docs/navigation_crowds.md``).

    Parameters
    ----------
    name, label, doc
        As for :class:`NavigationMethod`.
    """

    used_gains = ()
    force_field = False
    batched = False
    crowds = True
    #: Its settings class (each default from its source), given as ``gains``.
    gains_type: Any = None

    def default_gains(self) -> Any:
        return self.gains_type()

    def gain_row(self, gains: Any) -> np.ndarray:
        self.gains(gains)  # checked; the settings go to the controller, not the field
        return np.zeros(len(GAIN_COLUMNS))

    def gains_dict(self, row: np.ndarray) -> dict[str, float]:
        return {}

    def controller(self, crowd: Any, settings: Any) -> Callable[..., np.ndarray]:
        """The controller of one run as ``command(p, v, P, V) -> velocity``.

        Parameters
        ----------
        crowd
            The crowd scenario (its robot, goal, walls, pedestrian radius, sample time).
        settings
            The method's settings (checked).

        Returns
        -------
        callable
            ``command(p, v, P, V)``: the robot's position and velocity ``(2,)``, the
            pedestrians' positions and velocities ``(n, 2)`` -> the commanded velocity.
        """
        raise NotImplementedError(f"{type(self).__name__} does not define its controller")

    def forces(self, items: list[Obs], s: Symbols) -> Forces:
        raise InvalidParameterError("method", self.name, "commands a velocity: no force field")


def goal_velocity(
    p: np.ndarray, goal: np.ndarray, max_speed: float, max_accel: float
) -> np.ndarray:
    """The preferred velocity: straight to the goal at the speed limit, slowing to stop at it
    (speed min(V_mr, sqrt(2 a_mr d)) at distance d).

    Parameters
    ----------
    p, goal
        The robot's position and goal ``(2,)``, m.
    max_speed, max_accel
        V_mr (m/s) and a_mr (m/s^2).

    Examples
    --------
    >>> goal_velocity(np.zeros(2), np.array([3.0, 4.0]), 0.7, 1.0).tolist()
    [0.42, 0.56]
    """
    e = goal - p
    d = float(np.hypot(*e))
    if d <= 1e-12:
        return np.zeros(2)
    return e / d * min(max_speed, (2.0 * max_accel * d) ** 0.5)
