"""The robot's speed at contact when it detects a person and brakes (a point-mass model).

A robot driving at ``v`` detects a person at separation ``d`` (along the line
joining them), keeps its speed for the reaction time ``T_r`` and then brakes at
``a``; the person walks toward it at ``v_h`` throughout. The robot's speed when
the gap closes is

* ``v`` if the gap closes within the reaction time (``d <= (v + v_h) T_r``);
* ``v - a t`` otherwise, ``t`` the braking time to contact (0 once the robot
  has stopped: the person walks into a standing robot).

The robot's contact speed is at most ``u`` exactly when the gap closed while the
robot slows from ``v`` to ``u``, ``(v^2 - u^2) / (2a) + v_h (v - u) / a``, plus
the reaction travel ``(v + v_h) T_r``, is at most ``d``. That is a quadratic in
``v``: :func:`max_robot_speed` solves it in closed form. With ``d = 0`` (contact
without warning, the default) the answer is ``u`` itself.

Examples
--------
>>> max_robot_speed(0.5, human_speed=1.0, reaction_time=0.1, deceleration=5.0,
...                 detection_distance=0.0)
0.5
>>> v = max_robot_speed(0.5, human_speed=1.0, reaction_time=0.1, deceleration=5.0,
...                     detection_distance=0.6)
>>> round(v, 4), round(contact_speed(v, 1.0, 0.1, 5.0, 0.6), 4)
(1.4155, 0.5)
"""

from __future__ import annotations

import math

from designlab.codesign.parameters import (
    BRAKING_SPEED,
    CONTACT_LIMIT,
    DECELERATION,
    DETECTION_DISTANCE,
    REACTION_TIME,
)
from designlab.impact.parameters import HUMAN_SPEED

__all__ = ["contact_speed", "max_robot_speed", "stopping_distance"]


def contact_speed(
    speed: float,
    human_speed: float,
    reaction_time: float,
    deceleration: float,
    detection_distance: float,
) -> float:
    """The robot's speed at contact, m/s (the module text's model).

    Parameters
    ----------
    speed
        Robot speed before braking, m/s.
    human_speed
        The person's speed toward the robot, m/s.
    reaction_time
        Time the robot keeps its speed after detection, s.
    deceleration
        Braking deceleration, m/s^2.
    detection_distance
        Separation at detection, m.

    Returns
    -------
    float

    Raises
    ------
    InvalidParameterError
        For a value outside its declaration (:mod:`designlab.codesign.parameters`).
    """
    speed = BRAKING_SPEED.check(speed)
    human_speed = HUMAN_SPEED.check(human_speed)
    reaction_time = REACTION_TIME.check(reaction_time)
    deceleration = DECELERATION.check(deceleration)
    detection_distance = DETECTION_DISTANCE.check(detection_distance)
    gap = detection_distance - (speed + human_speed) * reaction_time
    if gap <= 0.0:
        return speed
    # robot: v t - a t^2 / 2 (until it stops), person: v_h t; contact when they sum to gap
    b = speed + human_speed
    disc = b * b - 2.0 * deceleration * gap
    if disc < 0.0:
        return 0.0
    t = (b - math.sqrt(disc)) / deceleration
    return max(0.0, speed - deceleration * t) if t <= speed / deceleration else 0.0


def max_robot_speed(
    contact_limit: float,
    *,
    human_speed: float,
    reaction_time: float,
    deceleration: float,
    detection_distance: float,
) -> float:
    """Largest robot speed whose contact speed is at most ``contact_limit`` (closed form).

    Parameters
    ----------
    contact_limit
        Largest allowed robot speed at contact ``u``, m/s (>= 0).
    human_speed, reaction_time, deceleration, detection_distance
        As in :func:`contact_speed`.

    Returns
    -------
    float
        ``max(u, v)`` with ``v`` the positive root of
        ``v^2/(2a) + v (v_h/a + T_r) - u^2/(2a) - v_h u/a + v_h T_r - d = 0``.

    Raises
    ------
    InvalidParameterError
        For a value outside its declaration (:mod:`designlab.codesign.parameters`).
    """
    u, a = CONTACT_LIMIT.check(contact_limit), DECELERATION.check(deceleration)
    human_speed = HUMAN_SPEED.check(human_speed)
    reaction_time = REACTION_TIME.check(reaction_time)
    detection_distance = DETECTION_DISTANCE.check(detection_distance)
    b = human_speed / a + reaction_time
    c0 = -(u * u) / (2.0 * a) - human_speed * u / a + human_speed * reaction_time
    c0 -= detection_distance
    disc = b * b - 2.0 * c0 / a
    root = a * (-b + math.sqrt(max(disc, 0.0)))
    return max(u, root)


def stopping_distance(speed: float, reaction_time: float, deceleration: float) -> float:
    """The robot's travel from detection to standstill, ``v T_r + v^2 / (2a)``, m.

    Parameters
    ----------
    speed
        Robot speed, m/s.
    reaction_time
        Reaction time, s.
    deceleration
        Braking deceleration, m/s^2.

    Returns
    -------
    float

    Raises
    ------
    InvalidParameterError
        For a value outside its declaration (:mod:`designlab.codesign.parameters`).

    Examples
    --------
    >>> stopping_distance(1.0, 0.1, 5.0)
    0.2
    >>> stopping_distance(1.0, 0.1, 0.0)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: deceleration = 0.0 m/s^2 is not allowed: ...
    """
    speed = BRAKING_SPEED.check(speed)
    reaction_time = REACTION_TIME.check(reaction_time)
    deceleration = DECELERATION.check(deceleration)
    return speed * reaction_time + speed * speed / (2.0 * deceleration)
