"""A user's own scenario as plain data (a YAML file, a dict): robot, obstacles, start, goal.

:func:`scenario_from_dict` builds a :class:`~designlab.navigation.Scenario` from the
structure a study file uses (``docs/navigation_scenarios.md``), and
:func:`load_scenario` reads it from a YAML file. Every value is checked by the
domain object it builds (:class:`~designlab.navigation.HolonomicRobot`,
:class:`~designlab.navigation.Disc`, :class:`~designlab.navigation.Walk`, ...), so the
errors name the parameter, its value and what is allowed.

Obstacles (``kind``):

* ``disc`` / ``human``: ``name``, ``radius`` (a human defaults to rho_h = 0.4 m),
  ``r2``, ``r3`` and one motion: ``position`` (fixed, or with a constant
  ``velocity``), ``walk`` (a straight walk with smooth start and stop), ``route``
  (``waypoints`` at a ``speed``, turning on the spot) or ``path`` (sampled
  ``times`` and ``positions``, e.g. a measured walk);
* ``rectangle``: ``center``, ``length``, ``width`` (and ``angle``), or ``corners``;
* ``wall``: ``start``, ``end`` and ``thickness`` (a rotated rectangle).

Examples
--------
>>> sc = scenario_from_dict({
...     "name": "corridor", "start": [5, 1], "goal": [0, 1],
...     "robot": {"type": "holonomic", "max_speed": 0.5},
...     "obstacles": [
...         {"kind": "wall", "name": "north", "start": [0, 2], "end": [5, 2],
...          "thickness": 0.1, "r2": 0.6, "r3": 0.3},
...         {"kind": "human", "name": "visitor", "r2": 2.1, "r3": 0.8,
...          "route": {"waypoints": [[0, 0.2], [2, 0.2], [2, -3]], "speed": 0.8}}]})
>>> sc.robot.max_speed, sc.obstacle_names, sc.obstacles[1].radius
(0.5, ('north', 'visitor'), 0.4)
>>> scenario_from_dict({"name": "x", "start": [0, 0], "goal": [1, 0], "obstacles": [
...     {"kind": "tree", "name": "t"}]})
Traceback (most recent call last):
...
designlab.errors.InvalidParameterError: obstacles[0].kind = 'tree' is not allowed: ...
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from designlab.errors import InvalidParameterError, StudyError
from designlab.navigation.parameters import OBSTACLES, HolonomicRobot, Human, NonholonomicRobot
from designlab.navigation.scenarios import (
    MAX_PATH_SAMPLES,
    ConstantVelocity,
    Disc,
    Motion,
    Obstacle,
    Rectangle,
    SampledPath,
    Scenario,
    Stationary,
    Walk,
)
from designlab.params import Param

__all__ = [
    "OBSTACLE_KINDS",
    "ROBOT_TYPES",
    "load_scenario",
    "mirrored",
    "obstacle_from_dict",
    "robot_from_dict",
    "scenario_from_dict",
    "with_limits",
]

#: Robot ``type`` -> class.
ROBOT_TYPES: dict[str, type] = {"holonomic": HolonomicRobot, "nonholonomic": NonholonomicRobot}
#: The motions of a disc: key -> builder from its value.
_MOTIONS = ("position", "walk", "route", "path")
#: Largest scenario file read (bytes): a scenario is a few kB.
MAX_FILE_BYTES = 5_000_000


def _mapping(name: str, value: Any) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise InvalidParameterError(name, value, "must be a mapping (key: value)")
    return value


def _known(name: str, data: Mapping[str, Any], allowed: set[str]) -> None:
    unknown = sorted(set(data) - allowed)
    if unknown:
        raise InvalidParameterError(
            name, unknown[0], f"is not a key here; allowed: {', '.join(sorted(allowed))}"
        )


def robot_from_dict(data: Mapping[str, Any] | None) -> HolonomicRobot | NonholonomicRobot:
    """The robot of ``{type: holonomic | nonholonomic, <its fields>}`` (default holonomic).

    Parameters
    ----------
    data
        ``type`` (``"holonomic"``, the default, or ``"nonholonomic"``) and fields of that
        robot class in SI units (``None`` or empty: the default holonomic robot).

    Examples
    --------
    >>> robot_from_dict({"type": "nonholonomic", "max_angular_accel": 50}).turn_time > 0.25
    True
    """
    data = dict(_mapping("robot", data or {}))
    kind = data.pop("type", "holonomic")
    if kind not in ROBOT_TYPES:
        raise InvalidParameterError("robot.type", kind, f"must be one of {tuple(ROBOT_TYPES)}")
    cls = ROBOT_TYPES[kind]
    _known(f"robot ({kind})", data, set(cls.__dataclass_fields__))
    return cls(**data)  # type: ignore[no-any-return]


def _motion(where: str, data: Mapping[str, Any]) -> Motion:
    given = [k for k in _MOTIONS if data.get(k) is not None]
    if len(given) != 1:
        raise InvalidParameterError(
            where, given or None, f"give exactly one motion of {', '.join(_MOTIONS)}"
        )
    key = given[0]
    value = data[key]
    if key == "position":
        if data.get("velocity") is not None:
            return ConstantVelocity(value, data["velocity"])
        return Stationary(value)
    if data.get("velocity") is not None:
        raise InvalidParameterError(f"{where}.velocity", data["velocity"], "goes with position")
    body = dict(_mapping(f"{where}.{key}", value))
    if key == "walk":
        _known(f"{where}.walk", body, set(Walk.__dataclass_fields__))
        return Walk(**body)
    if key == "route":
        _known(f"{where}.route", body, {"waypoints", "speed", "start_time"})
        if "waypoints" not in body:
            raise InvalidParameterError(f"{where}.route", None, "needs waypoints")
        return SampledPath.through(**body)
    _known(f"{where}.path", body, {"times", "positions"})
    return SampledPath(body.get("times", ()), body.get("positions", ()))  # type: ignore[arg-type]


def _disc(where: str, data: Mapping[str, Any], human: bool) -> Disc:
    _known(where, data, {"kind", "name", "radius", "r2", "r3", "velocity", *_MOTIONS})
    radius = data.get("radius", Human().radius if human else None)
    if radius is None:
        raise InvalidParameterError(f"{where}.radius", None, "give the disc's radius (m)")
    return Disc(data.get("name", ""), radius, data.get("r2"), data.get("r3"), _motion(where, data))


def _rectangle(where: str, data: Mapping[str, Any], _: bool) -> Rectangle:
    keys = {"kind", "name", "center", "length", "width", "angle", "corners", "r2", "r3"}
    _known(where, data, keys)
    regions = {"r2": data.get("r2"), "r3": data.get("r3")}
    if data.get("corners") is not None:
        if any(data.get(k) is not None for k in ("center", "length", "width", "angle")):
            raise InvalidParameterError(
                f"{where}.corners", data["corners"], "give corners or center/length/width"
            )
        return Rectangle.from_corners(data.get("name", ""), data["corners"], **regions)
    for key in ("center", "length", "width"):
        if data.get(key) is None:
            raise InvalidParameterError(
                f"{where}.{key}", None, "is required (or give the four corners)"
            )
    given = {k: data[k] for k in ("length", "width", "angle") if data.get(k) is not None}
    return Rectangle(data.get("name", ""), data.get("center"), **given, **regions)


def _wall(where: str, data: Mapping[str, Any], _: bool) -> Rectangle:
    _known(where, data, {"kind", "name", "start", "end", "thickness", "r2", "r3"})
    return Rectangle.wall(
        data.get("name", ""),
        data.get("start"),  # type: ignore[arg-type]
        data.get("end"),  # type: ignore[arg-type]
        data.get("thickness"),  # type: ignore[arg-type]
        r2=data.get("r2"),  # type: ignore[arg-type]
        r3=data.get("r3"),  # type: ignore[arg-type]
    )


#: Obstacle ``kind`` -> builder ``(where, data, is_human) -> obstacle``.
_BUILDERS: dict[str, tuple[Callable[[str, Mapping[str, Any], bool], Obstacle], bool]] = {
    "disc": (_disc, False),
    "human": (_disc, True),
    "rectangle": (_rectangle, False),
    "wall": (_wall, False),
}
#: The obstacle kinds of a scenario file.
OBSTACLE_KINDS = tuple(_BUILDERS)


def obstacle_from_dict(data: Mapping[str, Any], where: str = "obstacle") -> Obstacle:
    """One obstacle of a scenario file (see the module's documentation).

    Parameters
    ----------
    data
        The obstacle's ``kind`` (``disc``, ``human``, ``rectangle`` or ``wall``) and the
        keys of that kind (lengths in m, speeds in m/s, times in s).
    where
        Where the obstacle is in the file (e.g. ``"obstacles[0]"``): the prefix of the
        key names in errors.
    """
    data = _mapping(where, data)
    kind = data.get("kind")
    if kind not in _BUILDERS:
        raise InvalidParameterError(f"{where}.kind", kind, f"must be one of {OBSTACLE_KINDS}")
    build, human = _BUILDERS[kind]
    return build(where, data, human)


_SCENARIO_KEYS = {
    "name", "start", "goal", "obstacles", "robot", "horizon", "sample_time",
    "initial_heading", "description",
}  # fmt: skip


def scenario_from_dict(data: Mapping[str, Any]) -> Scenario:
    """A :class:`~designlab.navigation.Scenario` from plain data (a study file's ``scenario``).

    Parameters
    ----------
    data
        ``name``, ``start``, ``goal``, ``obstacles`` (a list, see the module's
        documentation), ``robot`` (``{type, <limits>}``), and optionally ``horizon``,
        ``sample_time``, ``initial_heading`` and ``description``.

    Raises
    ------
    InvalidParameterError
        Naming the key or parameter that is missing, unknown or out of range.
    """
    data = _mapping("scenario", data)
    _known("scenario", data, _SCENARIO_KEYS)
    for key in ("name", "start", "goal"):
        if data.get(key) is None:
            raise InvalidParameterError(f"scenario.{key}", None, "is required")
    items = data.get("obstacles") or []
    if not isinstance(items, list | tuple):
        raise InvalidParameterError("scenario.obstacles", items, "must be a list")
    OBSTACLES.check(len(items), "scenario.obstacles (how many)")
    obstacles = tuple(obstacle_from_dict(o, f"obstacles[{i}]") for i, o in enumerate(items))
    extra = {
        k: data[k]
        for k in ("horizon", "sample_time", "initial_heading", "description")
        if data.get(k) is not None
    }
    return Scenario(
        data["name"],
        data["start"],
        data["goal"],
        obstacles,
        robot_from_dict(data.get("robot")),
        **extra,
    )


def load_scenario(path: str | Path) -> Scenario:
    """Read a scenario from a YAML file (the structure of :func:`scenario_from_dict`).

    The file is read as a study is (:func:`designlab.yamlio.load_yaml`): a
    repeated key, a YAML syntax error or nesting deeper than
    :data:`~designlab.yamlio.MAX_DEPTH` is refused with the file and the line; only a
    regular file of at most :data:`MAX_FILE_BYTES` bytes of UTF-8 text without NUL bytes is
    read (in bounded chunks: a FIFO or a device is refused, never waited on).

    Parameters
    ----------
    path
        The YAML file (at most :data:`MAX_FILE_BYTES` bytes).

    Returns
    -------
    Scenario

    Raises
    ------
    StudyError
        For a file that is missing, not a regular file (a FIFO, a device), too large, not
        UTF-8 text, not YAML, repeats a key or nests too deeply (with the file and line;
        :func:`designlab.yamlio.load_yaml_file`).
    InvalidParameterError
        For the scenario's content (as :func:`scenario_from_dict`).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "room.yaml"
    >>> _ = f.write_text("name: room\\nstart: [3, 0]\\ngoal: [0, 0]\\n")
    >>> load_scenario(f).obstacle_names
    ()
    >>> _ = f.write_text("name: room\\nstart: [3, 0]\\ngoal: [0, 0]\\nname: hall\\n")
    >>> load_scenario(f)
    Traceback (most recent call last):
    ...
    designlab.errors.StudyError: ...room.yaml:4: name: key 'name' appears twice ...
    """
    from designlab.yamlio import YamlError, load_yaml_file

    p = Path(path)
    try:
        data, _ = load_yaml_file(p, max_bytes=MAX_FILE_BYTES)
    except YamlError as exc:
        raise StudyError(exc.message, file=str(p), line=exc.line, path=exc.path or None) from None
    return scenario_from_dict(data)


def with_limits(
    scenario: Scenario,
    max_speed: float,
    max_accel: float,
    walk_speed: float | None = None,
    walk_ramp_time: float | None = None,
) -> Scenario:
    """The scenario with other robot limits and, for every :class:`Walk`, another cruise speed
    and ramp time (``None``: unchanged): what a sweep point of a user's scenario varies.

    Parameters
    ----------
    scenario
        The scenario to change.
    max_speed
        The robot's speed limit V_mr (m/s).
    max_accel
        The robot's acceleration limit a_mr (m/s^2).
    walk_speed
        Cruise speed v_w of every :class:`Walk` (m/s; ``None``: unchanged).
    walk_ramp_time
        Duration t_ramp of each speed ramp of every :class:`Walk` (s; ``None``: unchanged).

    Examples
    --------
    >>> sc = scenario_from_dict({"name": "x", "start": [4, 0], "goal": [0, 0], "obstacles": [
    ...     {"kind": "human", "name": "h", "r2": 2.1, "r3": 0.8,
    ...      "walk": {"start": [0, 0], "end": [4, 0]}}]})
    >>> s2 = with_limits(sc, 1.0, 5.0, walk_speed=1.2)
    >>> s2.robot.max_speed, s2.robot.max_accel, s2.obstacles[0].motion.speed
    (1.0, 5.0, 1.2)
    """
    robot = replace(scenario.robot, max_speed=max_speed, max_accel=max_accel)
    walk = {
        k: v for k, v in (("speed", walk_speed), ("ramp_time", walk_ramp_time)) if v is not None
    }
    obstacles = tuple(
        replace(o, motion=replace(o.motion, **walk))
        if walk and isinstance(o, Disc) and isinstance(o.motion, Walk)
        else o
        for o in scenario.obstacles
    )
    return replace(scenario, robot=robot, obstacles=obstacles)


#: The sampling interval of a mirrored scenario's moving discs (:func:`mirrored`).
MIRROR_STEP = Param(None, "s", "sampling interval of the mirrored paths", gt=0, le=1.0, name="dt")


def mirrored(scenario: Scenario, dt: float = 0.02) -> Scenario:
    """The scenario with every obstacle reflected about the line through start and goal.

    The robot's task is unchanged; a human who turned to one side now turns to the other
    (how a planner's choice of side decides whether the Sec. 5.7 human walks into it).
    Moving discs become :class:`SampledPath` motions sampled every ``dt`` s.

    Parameters
    ----------
    scenario
        The scenario to mirror (its start and goal must differ).
    dt
        Sampling interval of the mirrored paths of moving discs (s), up to the horizon.

    Examples
    --------
    >>> from designlab.navigation import configuration
    >>> m = mirrored(configuration("unpredictable"))
    >>> m.obstacles[0].state([5.0])[0].round(3).tolist()
    [[2.1, -2.5]]
    """
    if not isinstance(scenario, Scenario):
        raise InvalidParameterError("scenario", scenario, "must be a Scenario")
    dt = MIRROR_STEP.check(dt)
    samples = scenario.horizon / dt + 1
    if samples > MAX_PATH_SAMPLES:
        raise InvalidParameterError(
            "dt", dt, f"gives {samples:.3g} samples over the {scenario.horizon:g} s horizon; "
            f"a path holds at most {MAX_PATH_SAMPLES:,}", "s",
        )  # fmt: skip
    if scenario.start == scenario.goal:
        raise InvalidParameterError(
            "scenario", scenario.name, "must have a goal apart from its start (the mirror line)"
        )
    a, b = np.asarray(scenario.start), np.asarray(scenario.goal)
    u = (b - a) / np.hypot(*(b - a))

    def reflect(p: Any) -> Any:
        q = np.asarray(p, dtype=float) - a
        return a + 2 * (q @ u)[..., None] * u - q

    out: list[Obstacle] = []
    for o in scenario.obstacles:
        if isinstance(o, Rectangle):
            line = math.atan2(u[1], u[0])
            c = tuple(reflect(o.center).tolist())
            out.append(replace(o, center=c, angle=math.remainder(2 * line - o.angle, 2 * math.pi)))
        elif not o.motion.moving:
            out.append(replace(o, motion=Stationary(tuple(reflect(o.state([0.0])[0][0]).tolist()))))
        else:
            t = np.arange(0.0, scenario.horizon + dt / 2, dt)
            pts = reflect(o.state(t)[0])
            path = SampledPath(tuple(t.tolist()), tuple(map(tuple, pts.tolist())))
            out.append(replace(o, motion=path))
    return replace(scenario, obstacles=tuple(out), name=f"{scenario.name} (mirrored)")
