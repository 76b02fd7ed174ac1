"""The control-period loop of the tether follower (Allan 2015 Sec. 2.3-2.4, App. C).

Each period: the target finder of the law (:mod:`designlab.following.tether.buffer`)
gives the path target, the compiled closed-loop step
(:func:`designlab.following.tether.model.step_compiled`: sensor, law, wheel
limits, exact arc) moves the robot, and the state is stored. :func:`run_single`
runs one noise-free member on Python floats (the fast path of
:func:`designlab.following.tether.simulate`); :func:`run_batch` runs many gain
sets of one law on numpy arrays. Both return the histories ``x, y, g, v, om``
(B, N) and the measured tether ``l, th`` (B, N).

Examples
--------
>>> import numpy as np
>>> from designlab.following.tether import FollowerRobot, PseudoJoystick
>>> leader = np.column_stack([0.5 * 0.01 * np.arange(200), np.zeros(200)])
>>> hist = run_single(PseudoJoystick(), leader, (-1.0, 0.0, 0.0), FollowerRobot(), None)
>>> hist["x"].shape, round(float(hist["l"][0, -1]), 3)
((1, 200), 1.1)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from designlab.following.tether.buffer import MemberBuffers, NoTarget
from designlab.following.tether.laws.base import TetherController
from designlab.following.tether.model import sensor_step, step_compiled, tip_step
from designlab.following.tether.parameters import FollowerRobot

__all__ = ["Buffering", "run_batch", "run_single"]

_HISTORY = ("x", "y", "g", "v", "om")


@dataclass(frozen=True)
class Buffering:
    """How the law's path buffer is kept for a run.

    Attributes
    ----------
    window
        Points searched (``buffer_size - 1``; 0 for Pseudo-Joystick).
    min_step
        Delta s_min in m.
    prefill
        Points recorded before t = 0 (the lead-in), (M, 2).
    shared
        The shared recording ``(points, path distance, counts)`` when every
        member records the leader's positions (no noise, planar), else ``None``.
    """

    window: int
    min_step: float
    prefill: NDArray[np.float64]
    shared: tuple[NDArray, NDArray, NDArray] | None


def _robot_inputs(robot: FollowerRobot) -> tuple[float, ...]:
    """``b, r, dt, max_wheel_speed, max_wheel_step, off_x, off_y`` of the step."""
    dt = robot.sample_time
    return (
        robot.wheel_track,
        robot.wheel_radius,
        dt,
        robot.max_wheel_speed,
        robot.max_wheel_acceleration * dt,
        robot.winch_offset_x,
        robot.winch_offset_y,
    )


def _sensed(
    hist: dict[str, NDArray[np.float64]],
    leader: NDArray[np.float64],
    robot: FollowerRobot,
    noise: tuple[NDArray[np.float64], NDArray[np.float64]] | None,
) -> None:
    """Add the measured tether length and angle (one vectorised call over the run)."""
    lm, th = sensor_step(True)(
        hist["x"],
        hist["y"],
        hist["g"],
        leader[None, :, 0],
        leader[None, :, 1],
        robot.winch_offset_x,
        robot.winch_offset_y,
        robot.tip_height,
    )
    if noise is not None:
        lm = lm + noise[0]
        th = th + noise[1]
    hist["l"] = np.asarray(lm, dtype=float)
    hist["th"] = np.asarray(th, dtype=float)


def run_single(
    c: TetherController,
    leader: NDArray[np.float64],
    pose: tuple[float, float, float],
    robot: FollowerRobot,
    buf: Buffering | None,
) -> dict[str, NDArray[np.float64]]:
    """One noise-free run on Python floats.

    Parameters
    ----------
    c
        The controller.
    leader
        Leader (tether tip) positions per period in m, (N, 2).
    pose
        Initial ``(x, y, heading)`` in m, m, rad.
    robot
        The robot (noise-free).
    buf
        The shared buffer (``None`` for Pseudo-Joystick).
    """
    offsets = robot.winch_offset_x != 0.0 or robot.winch_offset_y != 0.0
    law = type(c).law_function(c.law_key())
    finder = c.target_finder
    step = step_compiled(law, finder.records_path, robot.limited, offsets, False, False)
    b, r, dt, wmax, astep, ox, oy = _robot_inputs(robot)
    params = c.law_values()
    find = NoTarget() if buf is None else finder.single(buf.shared, buf.window, c.search_distance())
    x, y, g = pose
    wl = wr = 0.0
    out = np.empty((len(leader), 5))
    txs, tys = leader[:, 0].tolist(), leader[:, 1].tolist()
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for k in range(len(leader)):
            jx, jy = find(k, x, y)
            xn, yn, gn, v, om, wl, wr = step(
                x,
                y,
                g,
                txs[k],
                tys[k],
                jx,
                jy,
                wl,
                wr,
                0.0,
                0.0,
                b,
                r,
                dt,
                wmax,
                astep,
                ox,
                oy,
                0.0,
                *params,
            )
            out[k] = (x, y, g, v, om)
            x, y, g = xn, yn, gn
    hist = {k: out[:, i][None, :] for i, k in enumerate(_HISTORY)}
    _sensed(hist, leader, robot, None)
    return hist


def _batch_target(
    controllers: tuple[TetherController, ...], buf: Buffering | None, n: int, robot: FollowerRobot
) -> Any:
    finder = controllers[0].target_finder
    nb = len(controllers)
    if buf is None or not finder.records_path:
        return NoTarget(np.zeros(nb))
    per = np.array([c.search_distance() for c in controllers])
    if buf.shared is not None:
        return finder.batch(buf.shared, buf.window, per)
    offsets = (robot.winch_offset_x, robot.winch_offset_y, robot.tip_height)
    return MemberBuffers(
        finder,
        nb,
        n,
        buf.window,
        buf.min_step,
        buf.prefill,
        per,
        sensor_step(True),
        tip_step(True),
        offsets,
    )


def run_batch(
    controllers: tuple[TetherController, ...],
    leader: NDArray[np.float64],
    pose: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    robot: FollowerRobot,
    buf: Buffering | None,
    rng: np.random.Generator,
) -> dict[str, NDArray[np.float64]]:
    """A batch of runs of one law on numpy arrays (one member per gain set).

    Parameters
    ----------
    controllers
        The members (one law, one variant).
    leader
        Leader positions per period in m, (N, 2).
    pose
        Initial ``(x, y, heading)`` of each member, three (B,) arrays.
    robot
        The robot (its noise is drawn from ``rng``).
    buf
        The buffer settings (``None`` for Pseudo-Joystick).
    rng
        Random numbers of the sensor noise.
    """
    c0, nb, n = controllers[0], len(controllers), len(leader)
    offsets = not robot.planar
    law = type(c0).law_function(c0.law_key())
    step = step_compiled(
        law, c0.target_finder.records_path, robot.limited, offsets, robot.noisy, True
    )
    b, r, dt, wmax, astep, ox, oy = _robot_inputs(robot)
    hh = robot.tip_height
    noise = None
    if robot.noisy:
        noise = (
            rng.normal(0.0, 1.0, (nb, n)) * robot.length_noise_std,
            rng.normal(0.0, 1.0, (nb, n)) * robot.angle_noise_std,
        )
    params = [np.array(v) for v in zip(*(c.law_values() for c in controllers), strict=True)]
    x, y, g = (np.array(v, dtype=float) for v in pose)
    wl, wr = np.zeros(nb), np.zeros(nb)
    nl = nth = 0.0
    find = _batch_target(controllers, buf, n, robot)
    out = np.empty((n, 5, nb))
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for k in range(n):
            tx, ty = leader[k]
            if noise is not None:
                nl, nth = noise[0][:, k], noise[1][:, k]
            jx, jy = find(k, x, y, g, tx, ty, nl, nth)
            xn, yn, gn, v, om, wl, wr = step(
                x, y, g, tx, ty, jx, jy, wl, wr, nl, nth, b, r, dt, wmax, astep, ox, oy, hh, *params
            )
            o = out[k]
            o[0], o[1], o[2], o[3], o[4] = x, y, g, v, om
            x, y, g = xn, yn, gn
    hist = {k: out[:, i, :].T.copy() for i, k in enumerate(_HISTORY)}
    _sensed(hist, leader, robot, noise)
    return hist
