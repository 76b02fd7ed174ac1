"""Animations of navigation runs: the robot and the people around it, as a GIF.

:func:`run_tracks` takes the trajectories out of any navigation run (a crowd run's
``times, robot_positions, pedestrian_positions``, or a
:class:`~designlab.navigation.NavigationResult`'s ``t, position, obstacle_positions``);
:func:`animate` draws them frame by frame and writes a GIF through matplotlib's
:class:`~matplotlib.animation.PillowWriter`.

Examples
--------
>>> import tempfile, pathlib
>>> t = np.linspace(0.0, 2.0, 21)
>>> robot = np.stack([t, 0 * t], axis=1)
>>> peds = np.stack([2.0 - t, 0.5 + 0 * t], axis=1)[:, None, :]
>>> with tempfile.TemporaryDirectory() as d:
...     out = animate(t, robot, peds, pathlib.Path(d) / "run.gif", max_frames=5)
...     out.stat().st_size > 0
True
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.animation import FuncAnimation, PillowWriter
from matplotlib.figure import Figure
from matplotlib.patches import Circle
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.params import Param

__all__ = ["MAX_FRAMES", "animate", "run_tracks"]

logger = logging.getLogger(__name__)
Array = NDArray[np.float64]

#: Frames of a GIF at most (the run is sub-sampled evenly to fit).
MAX_FRAMES = Param("max_frames", "", "frames of an animation at most", kind="integer", ge=2,
                   le=2000, default=120, name="max_frames")  # fmt: skip


def run_tracks(result: Any) -> tuple[Array, Array, Array]:
    """``(times (T,), robot (T, 2), others (T, N, 2))`` of a navigation run.

    Parameters
    ----------
    result
        A crowd run (``times``, ``robot_positions``, ``pedestrian_positions``) or a
        :class:`~designlab.navigation.NavigationResult` (``t``, ``position``,
        ``obstacle_positions`` of shape ``(N, T, 2)``).

    Returns
    -------
    tuple of ndarray
        Times, robot positions and the positions of the people (NaN where absent).

    Examples
    --------
    >>> import designlab as dl
    >>> res = dl.navigation.simulate(dl.navigation.configuration(1), dl.navigation.OPTIMAL_GAINS)
    >>> t, robot, people = run_tracks(res)
    >>> robot.shape == (t.size, 2), people.shape == (t.size, 1, 2)
    (True, True)
    """
    if hasattr(result, "pedestrian_positions"):
        t, r, p = result.times, result.robot_positions, result.pedestrian_positions
    elif hasattr(result, "obstacle_positions") and hasattr(result, "position"):
        t, r = result.t, result.position
        p = np.transpose(np.asarray(result.obstacle_positions, dtype=float), (1, 0, 2))
    else:
        raise InvalidParameterError("result", type(result).__name__, "must be a navigation run")
    return np.asarray(t, dtype=float), np.asarray(r, dtype=float), np.asarray(p, dtype=float)


def animate(
    times: ArrayLike,
    robot: ArrayLike,
    others: ArrayLike,
    path: str | Path,
    *,
    goal: Sequence[float] | None = None,
    walls: Sequence[ArrayLike] = (),
    robot_radius: float = 0.3,
    person_radius: float = 0.25,
    title: str = "",
    max_frames: int = MAX_FRAMES.default,
    fps: int = 10,
) -> Path:
    """Write a GIF of a run: the robot (blue, with its trail), the people (orange), walls.

    Parameters
    ----------
    times, robot, others
        As returned by :func:`run_tracks`: ``(T,)`` s, ``(T, 2)`` m, ``(T, N, 2)`` m.
    path
        The GIF to write (its folder is created).
    goal
        The robot's goal ``(x, y)`` (m), drawn as a cross.
    walls
        Polygons ``(K, 2)`` (m) drawn filled grey.
    robot_radius, person_radius
        Radii of the drawn discs (m).
    title
        Title above the frames (the time is appended).
    max_frames
        Frames at most (:data:`MAX_FRAMES`); the run is sub-sampled evenly.
    fps
        Frames per second of the GIF (1-50).

    Returns
    -------
    Path
        The written file.
    """
    t, r, p = _checked(times, robot, others)
    frames = _frames(t.size, MAX_FRAMES.check(max_frames))
    if isinstance(fps, bool) or not isinstance(fps, int) or not 1 <= fps <= 50:
        raise InvalidParameterError("fps", fps, "must be an integer in 1-50")
    fig = Figure(figsize=(6.0, 3.6), dpi=70)  # no pyplot: the user's backend is left alone
    ax = fig.add_subplot()
    _background(ax, r, p, goal, walls)
    art = _artists(ax, p.shape[1], robot_radius, person_radius)

    def draw(k: int) -> list[Any]:
        art["robot"].center = tuple(r[k])
        art["trail"].set_data(r[: k + 1, 0], r[: k + 1, 1])
        for i, disc in enumerate(art["people"]):
            present = not np.isnan(p[k, i]).any()
            disc.set_visible(present)
            if present:
                disc.center = tuple(p[k, i])
        ax.set_title(f"{title}  t = {t[k]:.1f} s".strip(), fontsize=9)
        return [art["robot"], art["trail"], *art["people"]]

    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    anim = FuncAnimation(fig, draw, frames=frames, blit=False)
    anim.save(out, writer=PillowWriter(fps=fps))
    logger.info("animation %s: %d frames", out, len(frames))
    return out


def _checked(times: ArrayLike, robot: ArrayLike, others: ArrayLike) -> tuple[Array, Array, Array]:
    t = np.asarray(times, dtype=float)
    r = np.asarray(robot, dtype=float)
    p = np.asarray(others, dtype=float)
    if t.ndim != 1 or t.size < 1 or not np.isfinite(t).all():
        raise InvalidParameterError(
            "times", t.shape, "must be a non-empty 1-D array of finite times"
        )
    if r.shape != (t.size, 2) or not np.isfinite(r).all():
        raise InvalidParameterError("robot", r.shape, f"must be finite, shape ({t.size}, 2)")
    if p.ndim != 3 or p.shape[0] != t.size or p.shape[2] != 2:
        raise InvalidParameterError("others", p.shape, f"must have shape ({t.size}, N, 2)")
    return t, r, p


def _frames(n: int, most: int) -> list[int]:
    """At most ``most`` evenly spaced sample indices, the first and last included."""
    return sorted(set(np.linspace(0, n - 1, min(n, most)).round().astype(int).tolist()))


def _background(ax: Any, r: Array, p: Array, goal: Any, walls: Sequence[ArrayLike]) -> None:
    pts = np.concatenate([r, p.reshape(-1, 2)[~np.isnan(p.reshape(-1, 2)).any(axis=1)]])
    for w in walls:
        poly = np.asarray(w, dtype=float)
        ax.fill(poly[:, 0], poly[:, 1], color="0.6", zorder=1)
        pts = np.concatenate([pts, poly])
    if goal is not None:
        ax.plot(goal[0], goal[1], "x", color="green", ms=9, mew=2, zorder=3)
        pts = np.concatenate([pts, [np.asarray(goal, dtype=float)]])
    lo, hi = pts.min(axis=0) - 0.5, pts.max(axis=0) + 0.5
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def _artists(ax: Any, n: int, robot_radius: float, person_radius: float) -> dict[str, Any]:
    for name, v in (("robot_radius", robot_radius), ("person_radius", person_radius)):
        if not (np.isfinite(v) and 0 < v <= 10):
            raise InvalidParameterError(name, v, "must be in (0, 10] m")
    robot = Circle((0, 0), robot_radius, color="tab:blue", zorder=4)
    ax.add_patch(robot)
    (trail,) = ax.plot([], [], "-", color="tab:blue", lw=1, zorder=3)
    people = [
        Circle((0, 0), person_radius, color="tab:orange", alpha=0.8, zorder=2) for _ in range(n)
    ]
    for c in people:
        ax.add_patch(c)
    return {"robot": robot, "trail": trail, "people": people}
