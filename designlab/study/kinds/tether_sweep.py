"""The ``tether_sweep`` study kind: tether-follower metrics over a sweep of gains and settings.

The shared sweep and sensitivity machinery (grid, LHS, one-at-a-time, Sobol,
tornado; executors and the result store) over the tether follower: the law's
desired length and gains, the leader speed and the robot's wheel limit,
control period and sensor noise. Each point is one closed-loop run on the
base path (:func:`designlab.following.tether.evaluators.follower_metrics_chunk`). The
sweepable parameters and their ranges are the domain's declarations
(:func:`designlab.params.sweepable`). A sweep of more than :attr:`TetherSweepStudy.MAX_POINTS`
points (each a closed-loop run of about 0.1 s) is refused.

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: tether_sweep
... name: demo
... base: {controller: {type: FollowTheLeader}, path: {type: slalom}}
... sweep:
...   method: grid
...   parameters:
...     controller.lookahead: {values: [0.1, 0.5]}
... ''')
>>> r = run_study(study)
>>> str(r.status), r.to_frame()["damping_ratio"].round(3).tolist()
('ok', [0.387, 0.866])
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from pydantic import Field, model_validator

from designlab.following.tether import (
    LAWS,
    FollowerRobot,
    FollowTheLeader,
    FollowTheLeaderConstDistance,
    PseudoJoystick,
)
from designlab.following.tether.evaluators import (
    FOLLOWER_METRICS,
    follower_metrics_chunk,
    sweep_options,
)
from designlab.following.tether.parameters import LEADER_SPEED, SEED
from designlab.params import Param, params_of, sweepable
from designlab.study.base import Model
from designlab.study.kinds.tether_specs import ControllerSpec, FollowerRobotSpec, PathSpec
from designlab.study.registry import StudyKind
from designlab.study.reproduction import SAME_ON_A_GENERIC_CPU
from designlab.study.sweep_runner import run_sweep_study
from designlab.study.sweeps import SweepStudyBase, parameter_model

__all__ = ["KIND", "TETHER_PARAMETERS", "TetherDesign", "TetherSweepStudy"]

#: What a tether sweep can vary: dotted path -> (point key, declaration). The declarations
#: are the domain's: l_d, k_V and k_O as the Pseudo-Joystick names them (the same field of
#: every law), delta of FTL, K_a of FTL-CD, the leader speed and the robot's fields.
TETHER_PARAMETERS: dict[str, tuple[str, Param]] = {
    **sweepable(PseudoJoystick, "controller", names=("desired_length", "speed_gain", "turn_gain")),
    **sweepable(FollowTheLeader, "controller", names=("lookahead",)),
    **sweepable(FollowTheLeaderConstDistance, "controller", names=("angle_gain",)),
    "speed": (str(LEADER_SPEED.symbol), LEADER_SPEED),
    **sweepable(
        FollowerRobot,
        "robot",
        names=("max_wheel_speed", "sample_time", "length_noise_std", "angle_noise_std"),
    ),
}

TetherSweepParameters = parameter_model(
    "TetherSweepParameters", {path: info for path, (_, info) in TETHER_PARAMETERS.items()}
)
TetherMetricName = Literal[tuple(FOLLOWER_METRICS)]  # type: ignore[valid-type]


class TetherDesign(Model):
    """The nominal follower of a sweep: law, leader path, leader speed and robot."""

    controller: ControllerSpec  # type: ignore[valid-type]
    path: PathSpec  # type: ignore[valid-type]
    speed: LEADER_SPEED.annotation() = LEADER_SPEED.default  # type: ignore[valid-type]
    robot: FollowerRobotSpec = Field(  # type: ignore[valid-type]
        default_factory=lambda: FollowerRobotSpec(preset="DEFAULT")
    )
    seed: SEED.annotation(optional=False) = SEED.default  # type: ignore[valid-type]


class TetherSweepStudy(SweepStudyBase[TetherSweepParameters, TetherMetricName]):  # type: ignore[valid-type]
    """Tether-follower metrics over a sweep of gains and settings, with sensitivity tables."""

    kind: Literal["tether_sweep"]
    base: TetherDesign = Field(description="nominal follower; the sweep varies some of it")

    PARAMETERS: ClassVar[dict[str, tuple[str, Param]]] = TETHER_PARAMETERS
    METRICS: ClassVar[dict[str, str]] = FOLLOWER_METRICS
    DEFAULT_METRICS: ClassVar[tuple[str, ...]] = (
        "npd_mean_m",
        "length_error_rms_m",
        "accel_rms_m_per_s2",
    )
    EVALUATOR: ClassVar[Any] = follower_metrics_chunk
    NEEDS_SWEEP_OR_SENSITIVITY: ClassVar[bool] = True
    #: The most points of a sweep or sensitivity block: each point is a closed-loop run
    #: (0.05-0.5 s of CPU), so 100,000 points are hours on a laptop (docs/following.md).
    MAX_POINTS: ClassVar[int] = 100_000
    #: s: CPU time of studies/tether_sensitivity.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 51

    @model_validator(mode="after")
    def _law_has_parameters(self) -> TetherSweepStudy:
        swept = {p for p, _ in self.sweep.parameters.items()} if self.sweep is not None else set()
        sens = self.sensitivity
        for block in (sens.one_at_a_time, sens.sobol) if sens is not None else ():
            if block is not None and block.parameters:
                swept |= set(block.parameters)
        fields = params_of(LAWS.get(self.base.controller.type))
        bad = {p for p in swept if p.startswith("controller.") and p[11:] not in fields}
        if bad:
            raise ValueError(f"{self.base.controller.type} has no {', '.join(sorted(bad))}")
        return self

    def base_point(self) -> dict[str, float]:
        """The base follower as point columns (``l_d, k_V, k_O, ..., v, dt, ...``)."""
        objects = {"controller": self.base.controller.build(), "robot": self.base.robot.build()}
        point = {}
        for path, (key, _) in TETHER_PARAMETERS.items():
            where, _, name = path.rpartition(".")
            if not where:
                point[key] = float(self.base.speed)
            elif hasattr(objects[where], name):
                point[key] = float(getattr(objects[where], name))
        return point

    def evaluator_options(self) -> dict[str, Any]:
        """The plain options of the chunk evaluator (base law, path, robot, seed)."""
        return sweep_options(
            self.base.controller.build(),
            self.base.path.build(),
            self.base.robot.build(),
            self.base.seed,
        )


KIND = StudyKind(
    name="tether_sweep",
    schema=TetherSweepStudy,
    run=run_sweep_study,
    report="designlab.report.sweep",
    reproduction=SAME_ON_A_GENERIC_CPU,
)
