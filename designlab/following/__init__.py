"""Robots that follow or accompany a person: two subpackages that share nothing.

* :mod:`designlab.following.tether` -- the tether follower of Allan 2015
  (doctoral thesis, Tokyo Tech): a differential-drive robot led on a short
  tether, with the Pseudo-Joystick, Follow the Leader and Follow the Leader with
  Constant Distance laws and the normal path deviation of App. A
  (``fol.tether.simulate``, ``fol.tether.tune``, ``fol.tether.linear_analysis``);
* :mod:`designlab.following.accompanying` -- the accompanying robot of Wu et
  al. 2021 (Sensors 21:3889): a mecanum robot that keeps a pose chosen in the
  user's own frame, measured by a string-pot, with one PID per axis
  (``fol.accompanying.simulate``, ``fol.accompanying.tune``,
  ``fol.accompanying.loop_analysis``).

The flat names of the API contract keep working: ``fol.simulate``,
``fol.tune``, ``fol.linear_analysis`` (the tether follower's) and
``fol.accompany``, ``fol.tune_pid``, ``fol.loop_analysis`` (the accompanying
robot's), with every other public name of both. The modules of the former flat
layout (``designlab.following.tether_simulate``, ``...walking_tasks``, ...)
still import, with a ``DeprecationWarning``, for one release. See
``docs/following.md``.

Examples
--------
>>> import designlab as dl
>>> fol = dl.following
>>> res = fol.accompany(fol.walking_task("circle_cw"))
>>> res.settled_error < 0.02
True
>>> sim = fol.simulate(fol.FollowTheLeaderConstDistance(desired_length=1.0),
...                    fol.figure_eight(a=4.0), speed=0.5)
>>> npd = fol.normal_path_deviation(sim.leader_xy, sim.robot_xy)
>>> npd.mean < 0.1
True
"""

from __future__ import annotations

import importlib
import sys
import types
import warnings
from typing import Any

from designlab.following import accompanying, tether
from designlab.following.accompanying import (
    TASK_NAMES,
    AccompanyMetrics,
    AccompanyResult,
    LoopAnalysis,
    MecanumPlatform,
    PIDTuningResult,
    StringPotSensor,
    UserFramePID,
    WalkingTask,
    accompany,
    accompany_metrics,
    loop_analysis,
    mecanum_matrix,
    paper_table1,
    paper_table2,
    robot_frame_error,
    robot_in_user_frame,
    string_pot_readings,
    tune_pid,
    walking_task,
    walking_task_from_csv,
)
from designlab.following.tether import (
    OXYDOG,
    FollowerBatch,
    FollowerMetrics,
    FollowerRobot,
    FollowerRun,
    FollowTheLeader,
    FollowTheLeaderConstDistance,
    LeaderPath,
    LinearLoop,
    PathDeviation,
    PseudoJoystick,
    TetherController,
    TuningResult,
    allan_tables,
    circle,
    controller_from_dict,
    corridor_corner,
    figure_eight,
    follower_metrics,
    from_array,
    from_csv,
    linear_analysis,
    make_path,
    measured_ratio,
    normal_path_deviation,
    simulate,
    simulate_batch,
    slalom,
    square_s,
    straight_line,
    tune,
)

__all__ = [
    "OXYDOG",
    "TASK_NAMES",
    "AccompanyMetrics",
    "AccompanyResult",
    "FollowTheLeader",
    "FollowTheLeaderConstDistance",
    "FollowerBatch",
    "FollowerMetrics",
    "FollowerRobot",
    "FollowerRun",
    "LeaderPath",
    "LinearLoop",
    "LoopAnalysis",
    "MecanumPlatform",
    "PIDTuningResult",
    "PathDeviation",
    "PseudoJoystick",
    "StringPotSensor",
    "TetherController",
    "TuningResult",
    "UserFramePID",
    "WalkingTask",
    "accompany",
    "accompany_metrics",
    "accompanying",
    "allan_tables",
    "circle",
    "controller_from_dict",
    "corridor_corner",
    "figure_eight",
    "follower_metrics",
    "from_array",
    "from_csv",
    "linear_analysis",
    "loop_analysis",
    "make_path",
    "measured_ratio",
    "mecanum_matrix",
    "normal_path_deviation",
    "paper_table1",
    "paper_table2",
    "robot_frame_error",
    "robot_in_user_frame",
    "simulate",
    "simulate_batch",
    "slalom",
    "square_s",
    "straight_line",
    "string_pot_readings",
    "tether",
    "tune",
    "tune_pid",
    "walking_task",
    "walking_task_from_csv",
]

#: Modules of the former flat layout -> the modules that now hold their names.
MOVED_MODULES: dict[str, tuple[str, ...]] = {
    "tether_model": ("tether.model", "tether.parameters"),
    "tether_controllers": ("tether",),
    "tether_simulate": ("tether.simulate", "tether.buffer", "tether.closed_loop"),
    "tether_linear": ("tether.linear",),
    "tether_metrics": ("tether.metrics",),
    "tether_reference": ("tether.reference",),
    "tether_sweep": ("tether.evaluators",),
    "tether_tuning": ("tether.tuning",),
    "paths": ("tether.paths",),
    "path_deviation": ("tether.path_deviation",),
    "accompany_model": ("accompanying.parameters", "accompanying.model"),
    "accompany_simulate": ("accompanying.simulate", "accompanying.model"),
    "accompany_linear": ("accompanying.linear",),
    "accompany_metrics": ("accompanying.metrics",),
    "pid_tuning": ("accompanying.tuning",),
    "user_frame": ("accompanying.user_frame",),
    "user_frame_pid": ("accompanying.parameters", "accompanying.model"),
    "walking_tasks": ("accompanying.tasks",),
}


class MovedModule(types.ModuleType):
    """A module of the former flat layout: its names, looked up where they now live.

    Parameters
    ----------
    name
        The old module's full name.
    targets
        Full names of the modules that now hold its names.
    """

    def __init__(self, name: str, targets: tuple[str, ...]) -> None:
        super().__init__(name, f"Moved to {', '.join(targets)} (deprecated).")
        self._targets = targets

    def __getattr__(self, attr: str) -> Any:
        if attr.startswith("__"):
            raise AttributeError(attr)
        for target in self._targets:
            module = importlib.import_module(target)
            if hasattr(module, attr):
                warnings.warn(
                    f"{self.__name__} is deprecated: import {attr} from {target}",
                    DeprecationWarning,
                    stacklevel=2,
                )
                return getattr(module, attr)
        raise AttributeError(f"module {self.__name__!r} has no attribute {attr!r}")


for _old, _new in MOVED_MODULES.items():
    sys.modules.setdefault(
        f"{__name__}.{_old}",
        MovedModule(f"{__name__}.{_old}", tuple(f"{__name__}.{n}" for n in _new)),
    )
del _old, _new


def __getattr__(name: str) -> Any:
    if name in MOVED_MODULES:
        return sys.modules[f"{__name__}.{name}"]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
