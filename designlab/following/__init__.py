"""Robots that follow or accompany a person.

* The accompanying robot of Wu et al. 2021 (Sensors 21:3889): a mecanum
  robot that keeps a pose chosen in the user's own frame, measured by a
  string-pot, with one PID per axis (``docs/following.md``).
* The tether follower of Allan 2015 (doctoral thesis, Tokyo Tech): a
  differential-drive robot led on a short tether, with the Pseudo-Joystick,
  Follow the Leader and Follow the Leader with Constant Distance laws and the
  normal path deviation of App. A (``docs/following.md``).

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

__all__: list[str] = []

# Both robots (tether follower, Allan 2015; accompanying robot, Wu et al. 2021), sorted.
from designlab.following.accompany_linear import LoopAnalysis, loop_analysis
from designlab.following.accompany_metrics import AccompanyMetrics, accompany_metrics
from designlab.following.accompany_model import MecanumPlatform, StringPotSensor, mecanum_matrix
from designlab.following.accompany_simulate import AccompanyResult, accompany
from designlab.following.path_deviation import PathDeviation, normal_path_deviation
from designlab.following.paths import (
    LeaderPath,
    circle,
    corridor_corner,
    figure_eight,
    from_array,
    from_csv,
    make_path,
    slalom,
    square_s,
    straight_line,
)
from designlab.following.pid_tuning import PIDTuningResult, tune_pid
from designlab.following.tether_controllers import (
    FollowTheLeader,
    FollowTheLeaderConstDistance,
    PseudoJoystick,
    TetherController,
    controller_from_dict,
)
from designlab.following.tether_linear import LinearLoop, linear_analysis
from designlab.following.tether_metrics import FollowerMetrics, follower_metrics
from designlab.following.tether_model import OXYDOG, FollowerRobot
from designlab.following.tether_reference import allan_tables, measured_ratio
from designlab.following.tether_simulate import FollowerBatch, FollowerRun, simulate, simulate_batch
from designlab.following.tether_tuning import TuningResult, tune
from designlab.following.user_frame import (
    robot_frame_error,
    robot_in_user_frame,
    string_pot_readings,
)
from designlab.following.user_frame_pid import UserFramePID
from designlab.following.walking_tasks import (
    TASK_NAMES,
    WalkingTask,
    paper_table1,
    paper_table2,
    walking_task,
    walking_task_from_csv,
)

__all__ += [
    "TASK_NAMES",
    "AccompanyMetrics",
    "AccompanyResult",
    "LoopAnalysis",
    "MecanumPlatform",
    "PIDTuningResult",
    "StringPotSensor",
    "UserFramePID",
    "WalkingTask",
    "accompany",
    "accompany_metrics",
    "loop_analysis",
    "mecanum_matrix",
    "paper_table1",
    "paper_table2",
    "robot_frame_error",
    "robot_in_user_frame",
    "string_pot_readings",
    "tune_pid",
    "walking_task",
    "walking_task_from_csv",
]
# --- end accompanying robot ---

# --- tether follower exports ---
__all__ += [
    "OXYDOG",
    "FollowTheLeader",
    "FollowTheLeaderConstDistance",
    "FollowerBatch",
    "FollowerMetrics",
    "FollowerRobot",
    "FollowerRun",
    "LeaderPath",
    "LinearLoop",
    "PathDeviation",
    "PseudoJoystick",
    "TetherController",
    "TuningResult",
    "allan_tables",
    "circle",
    "controller_from_dict",
    "corridor_corner",
    "figure_eight",
    "follower_metrics",
    "from_array",
    "from_csv",
    "linear_analysis",
    "make_path",
    "measured_ratio",
    "normal_path_deviation",
    "simulate",
    "simulate_batch",
    "slalom",
    "square_s",
    "straight_line",
    "tune",
]
# --- end tether follower ---
