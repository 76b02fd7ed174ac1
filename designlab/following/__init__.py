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
robot's), with every other public name of both. See ``docs/following.md``.

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

from typing import TYPE_CHECKING

from designlab._lazy import attach as _attach

if TYPE_CHECKING:  # the public names, imported on first use (designlab._lazy)
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

_attach(__name__)
