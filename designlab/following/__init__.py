"""Person-following robots: the tether follower (Allan 2015), the accompanying robot (Wu 2021).

Examples
--------
>>> import designlab as dl
>>> fol = dl.following
>>> sim = fol.simulate(fol.FollowTheLeaderConstDistance(desired_length=1.0),
...                    fol.figure_eight(a=4.0), speed=0.5)
>>> npd = fol.normal_path_deviation(sim.leader_xy, sim.robot_xy)
>>> npd.mean < 0.1
True
"""

from __future__ import annotations

__all__: list[str] = []

# --- tether follower (Allan 2015) ---
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
