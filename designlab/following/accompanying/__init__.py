"""The accompanying robot of Wu et al. 2021 (Sensors 21:3889).

A mecanum robot that keeps a pose chosen in the user's own frame, measured by
a string-pot, with one PID per axis (``docs/following.md``).

=========================  ==========================================================
module                     holds
=========================  ==========================================================
``parameters``             :class:`MecanumPlatform`, :class:`StringPotSensor`,
                           :class:`UserFramePID` and the declared arguments
``user_frame``             the user-frame error transform, eqs. (1)-(8)
``extras``                 Sec. 6: :class:`SensorMount`, :class:`TargetAdaptation`,
                           :class:`MotionFilter`
``model``                  the control period in CasADi, eq. (10)
``tasks``                  the nine walking tasks and recorded walks
``simulate``               :func:`simulate` (``accompany``) and its result
``metrics``                the Table 1 and Table 2 quantities, error, lag, overshoot
``linear``                 :func:`loop_analysis` (python-control)
``tuning``                 :func:`tune` (``tune_pid``): convex-concave and simulation tuners
=========================  ==========================================================

Examples
--------
>>> from designlab.following import accompanying as acc
>>> res = acc.simulate(acc.walking_task("circle_cw"))
>>> res.settled_error < 0.02
True
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from designlab._lazy import attach as _attach

if TYPE_CHECKING:  # the public names, imported on first use (designlab._lazy)
    from designlab.following.accompanying.extras import MotionFilter, SensorMount, TargetAdaptation
    from designlab.following.accompanying.linear import LoopAnalysis, LoopStatus, loop_analysis
    from designlab.following.accompanying.metrics import AccompanyMetrics, accompany_metrics
    from designlab.following.accompanying.model import mecanum_matrix
    from designlab.following.accompanying.parameters import (
        AXES,
        LIMIT_MODES,
        MecanumPlatform,
        StringPotSensor,
        UserFramePID,
    )
    from designlab.following.accompanying.simulate import (
        AccompanyResult,
        AccompanyStatus,
        accompany,
        simulate,
    )
    from designlab.following.accompanying.tasks import (
        PAPER_TEST_NAMES,
        TASK_NAMES,
        WalkingTask,
        paper_table1,
        paper_table2,
        walking_task,
        walking_task_from_csv,
    )
    from designlab.following.accompanying.tuning import (
        TUNERS,
        PIDTuningResult,
        PIDTuningStatus,
        tune,
        tune_pid,
    )
    from designlab.following.accompanying.user_frame import (
        robot_frame_error,
        robot_in_user_frame,
        string_pot_readings,
    )

__all__ = [
    "AXES",
    "LIMIT_MODES",
    "PAPER_TEST_NAMES",
    "TASK_NAMES",
    "TUNERS",
    "AccompanyMetrics",
    "AccompanyResult",
    "AccompanyStatus",
    "LoopAnalysis",
    "LoopStatus",
    "MecanumPlatform",
    "MotionFilter",
    "PIDTuningResult",
    "PIDTuningStatus",
    "SensorMount",
    "StringPotSensor",
    "TargetAdaptation",
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
    "simulate",
    "string_pot_readings",
    "tune",
    "tune_pid",
    "walking_task",
    "walking_task_from_csv",
]

_attach(__name__)
