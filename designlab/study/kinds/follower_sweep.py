"""The ``follower_sweep`` study kind: tether-follower metrics over a sweep of gains and settings.

The shared sweep and sensitivity machinery (grid, LHS, one-at-a-time, Sobol,
tornado; executors and the result store) over the tether follower: the law's
desired length and gains, the leader speed and the robot's wheel limit,
control period and sensor noise. Each point is one closed-loop run on the
base path (:func:`designlab.following.tether_sweep.follower_metrics_chunk`).

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: follower_sweep
... name: demo
... base: {controller: {type: FollowTheLeader}, path: {type: slalom}}
... sweep:
...   method: grid
...   parameters:
...     controller.lookahead: {values: [0.1, 0.5]}
... ''')
>>> r = run_study(study)
>>> r.status, r.to_frame()["damping_ratio"].round(3).tolist()
('ok', [0.387, 0.866])
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from pydantic import Field, model_validator

from designlab.following.tether_sweep import FOLLOWER_METRICS, follower_metrics_chunk, sweep_options
from designlab.study.base import Integer, Model, Positive
from designlab.study.kinds.follower_specs import ControllerSpec, FollowerRobotSpec, PathSpec
from designlab.study.registry import StudyKind
from designlab.study.sweep_runner import run_sweep_study
from designlab.study.sweeps import ParameterInfo, SweepStudyBase, parameter_model

__all__ = ["FOLLOWER_PARAMETERS", "KIND", "FollowerDesign", "FollowerSweepStudy"]

#: What a follower sweep can vary: dotted path -> (point key, info).
FOLLOWER_PARAMETERS: dict[str, tuple[str, ParameterInfo]] = {
    "controller.desired_length": (
        "l_d",
        ParameterInfo("desired tether length l_d", "m", gt=0, le=10),
    ),
    "controller.speed_gain": ("k_V", ParameterInfo("speed gain k_V (K_p for FTL-CD)", "1/s", gt=0)),
    "controller.turn_gain": ("k_O", ParameterInfo("turn gain k_O (K_Omega, K_b)", "1/s", gt=0)),
    "controller.lookahead": ("delta", ParameterInfo("FTL look-ahead delta", "m", gt=0, le=10)),
    "controller.angle_gain": ("K_a", ParameterInfo("FTL-CD angle gain K_a", "1/rad", ge=0)),
    "speed": ("v", ParameterInfo("leader speed", "m/s", gt=0, le=5)),
    "robot.max_wheel_speed": ("w_max", ParameterInfo("wheel speed limit", "rad/s", gt=0)),
    "robot.sample_time": ("dt", ParameterInfo("control period", "s", gt=0, le=1)),
    "robot.length_noise_std": ("sigma_l", ParameterInfo("tether length noise", "m", ge=0)),
    "robot.angle_noise_std": ("sigma_theta", ParameterInfo("tether angle noise", "rad", ge=0)),
}

_LAW_FIELDS = {
    "PseudoJoystick": {"controller.lookahead", "controller.angle_gain"},
    "FollowTheLeader": {"controller.angle_gain"},
    "FollowTheLeaderConstDistance": {"controller.lookahead"},
}

FollowerSweepParameters = parameter_model(
    "FollowerSweepParameters", {path: info for path, (_, info) in FOLLOWER_PARAMETERS.items()}
)
FollowerMetricName = Literal[
    "npd_mean_m",
    "npd_mean_over_b",
    "npd_std_m",
    "length_error_rms_m",
    "tether_max_m",
    "accel_rms_m_per_s2",
    "path_length_ratio",
    "damping_ratio",
]


class FollowerDesign(Model):
    """The nominal follower of a sweep: law, leader path, leader speed and robot."""

    controller: ControllerSpec
    path: PathSpec
    speed: Positive = Field(0.5, le=5.0, description="leader speed, m/s")
    robot: FollowerRobotSpec = Field(default_factory=lambda: FollowerRobotSpec(preset="DEFAULT"))
    seed: Integer = Field(0, ge=0, description="seed of the sensor noise")


class FollowerSweepStudy(SweepStudyBase[FollowerSweepParameters, FollowerMetricName]):  # type: ignore[valid-type]
    """Tether-follower metrics over a sweep of gains and settings, with sensitivity tables."""

    kind: Literal["follower_sweep"]
    base: FollowerDesign = Field(description="nominal follower; the sweep varies some of it")

    PARAMETERS: ClassVar[dict[str, tuple[str, ParameterInfo]]] = FOLLOWER_PARAMETERS
    METRICS: ClassVar[dict[str, str]] = FOLLOWER_METRICS
    DEFAULT_METRICS: ClassVar[tuple[str, ...]] = (
        "npd_mean_m",
        "length_error_rms_m",
        "accel_rms_m_per_s2",
    )
    EVALUATOR: ClassVar[Any] = follower_metrics_chunk
    NEEDS_SWEEP_OR_SENSITIVITY: ClassVar[bool] = True

    @model_validator(mode="after")
    def _law_has_parameters(self) -> FollowerSweepStudy:
        swept = {p for p, _ in self.sweep.parameters.items()} if self.sweep is not None else set()
        sens = self.sensitivity
        for block in (sens.one_at_a_time, sens.sobol) if sens is not None else ():
            if block is not None and block.parameters:
                swept |= set(block.parameters)
        bad = swept & _LAW_FIELDS[self.base.controller.type]
        if bad:
            raise ValueError(f"{self.base.controller.type} has no {', '.join(sorted(bad))}")
        return self

    def base_point(self) -> dict[str, float]:
        """The base follower as point columns (``l_d, k_V, k_O, ..., v, dt, ...``)."""
        c = self.base.controller.build()
        r = self.base.robot.build()
        pt = {
            "l_d": c.desired_length,
            "k_V": c.speed_gain,
            "k_O": c.turn_gain,
            "v": float(self.base.speed),
            "w_max": r.max_wheel_speed,
            "dt": r.sample_time,
            "sigma_l": r.length_noise_std,
            "sigma_theta": r.angle_noise_std,
        }
        if hasattr(c, "lookahead"):
            pt["delta"] = c.lookahead  # type: ignore[attr-defined]
        if hasattr(c, "angle_gain"):
            pt["K_a"] = c.angle_gain  # type: ignore[attr-defined]
        return {k: float(v) for k, v in pt.items()}

    def evaluator_options(self) -> dict[str, Any]:
        return sweep_options(
            self.base.controller.build(),
            self.base.path.build(),
            self.base.robot.build(),
            self.base.seed,
        )


KIND = StudyKind(
    name="follower_sweep",
    schema=FollowerSweepStudy,
    run=run_sweep_study,
    report="designlab.report.sweep",
)
