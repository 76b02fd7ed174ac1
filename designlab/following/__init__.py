"""Robots that follow or accompany a person.

* The accompanying robot of Wu et al. 2021 (Sensors 21:3889): a mecanum
  robot that keeps a pose chosen in the user's own frame, measured by a
  string-pot, with one PID per axis (``docs/following.md``).

Examples
--------
>>> import designlab as dl
>>> fol = dl.following
>>> res = fol.accompany(fol.walking_task("circle_cw"))
>>> res.settled_error < 0.02
True
"""

from __future__ import annotations

__all__: list[str] = []

# --- accompanying robot (Wu et al. 2021) ---
from designlab.following.accompany_linear import LoopAnalysis, loop_analysis
from designlab.following.accompany_metrics import AccompanyMetrics, accompany_metrics
from designlab.following.accompany_model import MecanumPlatform, StringPotSensor, mecanum_matrix
from designlab.following.accompany_simulate import AccompanyResult, accompany
from designlab.following.pid_tuning import PIDTuningResult, tune_pid
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
