"""``result.plot()``: the main results draw themselves on matplotlib axes.

Like python-control's responses and pymoo's results, a result has a
:meth:`~designlab.results.Result.plot` that draws it on ``ax`` (a new figure's axes when
none is given) and returns the axes, for the caller to restyle, save or show:

=====================================  ===================================================
result                                 drawn
=====================================  ===================================================
``impact.ImpactResponse``              a signal against time (``quantity=``: head
                                       acceleration in g, force, compression)
``impact.FoamEnvelope``                the feasible foam stiffness band against damping
``navigation.NavigationResult``        the robot's path, the obstacles' paths, start, goal
``navigation.PlannerResult``           the same, for a Sec. 5.7 planner
``navigation.CrowdResult``             the robot's path over the pedestrians' and walls
``following.FollowerRun``              the leader's and the robot's paths
``codesign.ParetoFront``               two objectives of every design, the front, the
                                       reference design
=====================================  ===================================================

The drawing reads the result's fields only (this module imports no domain), and matplotlib
is imported when a result is drawn, never with designlab.

Examples
--------
>>> import matplotlib
>>> matplotlib.use("Agg")
>>> import designlab as dl
>>> r = dl.impact.simulate(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, dl.impact.TEST_HEAD,
...                        impact_velocity=1.25)
>>> ax = r.plot()
>>> ax.get_xlabel(), ax.get_ylabel()
('t (ms)', 'head acceleration (g)')
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["PLOTS", "plot"]

G = 9.81


def _axes(ax: Axes | None) -> Axes:
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    return plt.subplots()[1]


#: ``quantity`` of an impact response: field, scale, axis label.
_IMPACT = {
    "head_acceleration": ("head_acceleration", 1.0 / G, "head acceleration (g)"),
    "force": ("force", 1.0, "contact force (N)"),
    "compression": ("compression", 1e3, "foam compression (mm)"),
}


def _impact_response(r: Any, ax: Axes, quantity: str = "head_acceleration", **kw: Any) -> Axes:
    if quantity not in _IMPACT:
        raise ValueError(f"quantity={quantity!r} is not one of {sorted(_IMPACT)}")
    name, scale, label = _IMPACT[quantity]
    kw.setdefault("label", f"v_c = {r.impact_velocity:g} m/s")
    ax.plot(1e3 * np.asarray(r.t), scale * np.asarray(getattr(r, name)), **kw)
    ax.set_xlabel("t (ms)")
    ax.set_ylabel(label)
    ax.legend()
    return ax


def _envelope(r: Any, ax: Axes, **kw: Any) -> Axes:
    c = np.asarray(r.damping)
    lo, hi = np.asarray(r.stiffness_min) / 1e3, np.asarray(r.stiffness_max) / 1e3
    ax.fill_between(c, lo, hi, where=lo <= hi, alpha=0.25, label="feasible foams", **kw)
    ax.plot(c, hi, lw=1.5, label="upper boundary (injury criteria)")
    ax.plot(c, lo, lw=1.5, label="lower boundary (compression)")
    ax.set_xlabel("foam damping C_c (N s/m)")
    ax.set_ylabel("foam stiffness K_c (kN/m)")
    ax.legend()
    return ax


def _start_goal(ax: Axes, start: Any, goal: Any) -> None:
    ax.plot(*np.asarray(start)[:2], "ko", ms=6, ls="none", label="start")
    ax.plot(*np.asarray(goal)[:2], "k*", ms=11, ls="none", label="goal")


def _navigation(r: Any, ax: Axes, **kw: Any) -> Axes:
    from matplotlib.patches import Circle

    sc = r.scenario
    obstacles = np.asarray(r.obstacle_positions)
    for i, o in enumerate(sc.obstacles):
        track = obstacles[i]
        ax.plot(track[:, 0], track[:, 1], ":", color="0.4", lw=1,
                label="obstacles' paths" if i == 0 else None)  # fmt: skip
        radius = getattr(o, "radius", None)
        if radius:
            ax.add_patch(Circle(tuple(track[0]), radius, color="0.5", alpha=0.5))
    kw.setdefault("label", f"robot ({r.method})")
    ax.plot(r.position[:, 0], r.position[:, 1], lw=1.8, **kw)
    _start_goal(ax, sc.start, sc.goal)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(fontsize=8)
    return ax


def _crowd(r: Any, ax: Axes, **kw: Any) -> Axes:
    for (x0, y0), (x1, y1) in r.crowd.geometry.walls:
        ax.fill([x0, x1, x1, x0], [y0, y0, y1, y1], color="0.6")
    p = np.asarray(r.pedestrian_positions)
    for i in range(p.shape[1]):
        ax.plot(p[:, i, 0], p[:, i, 1], color="0.55", lw=0.6, alpha=0.5,
                label="pedestrians" if i == 0 else None)  # fmt: skip
    kw.setdefault("label", f"robot ({r.method})")
    ax.plot(r.robot_positions[:, 0], r.robot_positions[:, 1], lw=2, **kw)
    _start_goal(ax, r.crowd.robot_start, r.crowd.robot_goal)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(fontsize=8)
    return ax


def _follower(r: Any, ax: Axes, **kw: Any) -> Axes:
    ax.plot(r.leader_xy[:, 0], r.leader_xy[:, 1], "k-", lw=1.8, label="leader")
    kw.setdefault("label", f"robot ({r.controller.name})")
    ax.plot(r.robot_xy[:, 0], r.robot_xy[:, 1], lw=1.2, **kw)
    _start_goal(ax, r.robot_xy[0], r.leader_xy[-1])
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(fontsize=8)
    return ax


def _front(r: Any, ax: Axes, x: str | None = None, y: str | None = None, **kw: Any) -> Axes:
    names = list(r.objectives)
    x, y = x or names[0], y or names[1 if len(names) > 1 else 0]
    for n in (x, y):
        if n not in names:
            raise ValueError(f"objective {n!r} is not one of the front's {names}")
    i, j = names.index(x), names.index(y)
    F, feasible, front = np.asarray(r.F), np.asarray(r.feasible), np.asarray(r.front)
    ax.scatter(F[~feasible, i], F[~feasible, j], s=10, color="0.8", label="infeasible")
    ax.scatter(F[feasible & ~front, i], F[feasible & ~front, j], s=12, color="0.5",
               label="feasible")  # fmt: skip
    kw.setdefault("label", "non-dominated")
    order = np.argsort(F[front, i])
    ax.plot(F[front, i][order], F[front, j][order], "o-", ms=5, **kw)
    ref = r.reference
    if ref is not None:
        point = np.asarray(r.reference_objectives)
        ax.plot(point[i], point[j], "*", ms=14, color="gold", mec="k", label="reference")
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    ax.legend(fontsize=8)
    return ax


#: Class name of a result -> its drawing (the first class of the result's MRO found here).
PLOTS: dict[str, Callable[..., Axes]] = {
    "ImpactResponse": _impact_response,
    "FoamEnvelope": _envelope,
    "NavigationResult": _navigation,
    "PlannerResult": _navigation,
    "CrowdResult": _crowd,
    "FollowerRun": _follower,
    "ParetoFront": _front,
}


def plot(result: Any, ax: Axes | None = None, **kwargs: Any) -> Axes:
    """Draw ``result`` on ``ax`` (a new figure's if ``None``) and return the axes.

    Parameters
    ----------
    result
        A result of one of the types of :data:`PLOTS`.
    ax
        The axes to draw on.
    **kwargs
        Options of the drawing (``quantity=`` of an impact response, ``x=``/``y=``
        objectives of a Pareto front) and line properties of the main line.

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    NotImplementedError
        For a result with no drawing (use its :meth:`~designlab.results.Result.to_frame`).
    """
    for cls in type(result).__mro__:
        if cls.__name__ in PLOTS:
            return PLOTS[cls.__name__](result, _axes(ax), **kwargs)
    raise NotImplementedError(
        f"{type(result).__name__} has no plot(); drawn are {sorted(PLOTS)} "
        "(plot the columns of result.to_frame() instead)"
    )
