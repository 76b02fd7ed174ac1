"""The tether follower of Allan 2015 (doctoral thesis, Tokyo Tech).

A differential-drive robot led on a short tether by a person (a home-oxygen
patient: the robot carries the oxygen), with the Pseudo-Joystick, Follow the
Leader and Follow the Leader with Constant Distance laws, the thesis's leader
paths, and the normal path deviation of App. A (``docs/following.md``).

=========================  ==========================================================
module                     holds
=========================  ==========================================================
``parameters``             :class:`FollowerRobot`, :data:`OXYDOG` and the declared
                           arguments of the simulation and the tuner
``laws``                   the control laws, one module each, and their registry
                           :data:`LAWS` (PJ, FTL, FTL-CD; Ch. 4's side, front and
                           Brake modes)
``paths``                  the leader paths and :class:`LeaderPath`
``model``                  kinematics, tether sensor and closed-loop step in CasADi
``buffer``                 the FTL path buffer and its target points
``closed_loop``            the control-period loop (one run, a batch)
``simulate``               :func:`simulate`, :func:`simulate_batch` and their results
``path_deviation``         :func:`normal_path_deviation` (App. A)
``metrics``                :func:`follower_metrics` (Sec. 2.5.1)
``linear``                 :func:`linear_analysis` (python-control)
``tuning``                 :func:`tune` (differential evolution)
``evaluators``             the sweep engine's chunk evaluator
``reference``              Allan 2015 Tables 3.2 and 3.3
``stepwise``               the loop of the modes with memory
``odometry``               dead reckoning with wheel slip, the marker-to-tip offset
``snag``                   tether snagging on a corridor corner (Sec. 4.5)
``wrap``                   a tether wrapping obstacle corners, with its history
``stability``              the convergence map of Figs. 2.9-2.10
=========================  ==========================================================

Examples
--------
>>> from designlab.following import tether
>>> sim = tether.simulate(tether.FollowTheLeaderConstDistance(desired_length=1.0),
...                       tether.figure_eight(a=4.0), speed=0.5)
>>> npd = tether.normal_path_deviation(sim.leader_xy, sim.robot_xy)
>>> npd.mean < 0.1
True
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from designlab._lazy import attach as _attach

if TYPE_CHECKING:  # the public names, imported on first use (designlab._lazy)
    from designlab.following.tether.laws.base import TetherController
    from designlab.following.tether.laws.brake import BrakeMode, brake_timeline
    from designlab.following.tether.laws.constant_distance import FollowTheLeaderConstDistance
    from designlab.following.tether.laws.follow_the_leader import FollowTheLeader
    from designlab.following.tether.laws.front_joystick import FrontJoystick
    from designlab.following.tether.laws.front_vel_joystick import FrontVelJoystick
    from designlab.following.tether.laws.pseudo_joystick import PseudoJoystick
    from designlab.following.tether.laws.registry import LAWS, controller_from_dict
    from designlab.following.tether.laws.side_joystick import SideJoystick
    from designlab.following.tether.laws.side_tracking import SideTracking
    from designlab.following.tether.linear import (
        LinearLoop,
        LinearLoopStatus,
        fit_damping,
        lateral_step_response,
        linear_analysis,
    )
    from designlab.following.tether.metrics import FollowerMetrics, follower_metrics
    from designlab.following.tether.odometry import (
        ErrorRun,
        MarkerOffset,
        WheelSlip,
        simulate_with_errors,
    )
    from designlab.following.tether.parameters import OXYDOG, FollowerRobot
    from designlab.following.tether.path_deviation import (
        DeviationStatus,
        PathDeviation,
        normal_path_deviation,
        normal_path_deviations,
    )
    from designlab.following.tether.paths import (
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
    from designlab.following.tether.reference import allan_tables, measured_ratio
    from designlab.following.tether.simulate import (
        FollowerBatch,
        FollowerRun,
        FollowerStatus,
        simulate,
        simulate_batch,
    )
    from designlab.following.tether.tuning import CostWeights, TuningResult, TuningStatus, tune

__all__ = [
    "LAWS",
    "OXYDOG",
    "BrakeMode",
    "CostWeights",
    "DeviationStatus",
    "ErrorRun",
    "FollowTheLeader",
    "FollowTheLeaderConstDistance",
    "FollowerBatch",
    "FollowerMetrics",
    "FollowerRobot",
    "FollowerRun",
    "FollowerStatus",
    "FrontJoystick",
    "FrontVelJoystick",
    "LeaderPath",
    "LinearLoop",
    "LinearLoopStatus",
    "MarkerOffset",
    "PathDeviation",
    "PseudoJoystick",
    "SideJoystick",
    "SideTracking",
    "TetherController",
    "TuningResult",
    "TuningStatus",
    "WheelSlip",
    "allan_tables",
    "brake_timeline",
    "circle",
    "controller_from_dict",
    "corridor_corner",
    "figure_eight",
    "fit_damping",
    "follower_metrics",
    "from_array",
    "from_csv",
    "lateral_step_response",
    "linear_analysis",
    "make_path",
    "measured_ratio",
    "normal_path_deviation",
    "normal_path_deviations",
    "simulate",
    "simulate_batch",
    "simulate_with_errors",
    "slalom",
    "square_s",
    "straight_line",
    "tune",
]

_attach(__name__)
