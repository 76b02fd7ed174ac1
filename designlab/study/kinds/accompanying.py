"""The ``accompanying`` study kind: the Wu et al. 2021 walking tasks, default vs tuned PID.

Every task is simulated with the study's PID (the baseline) and with the PID
tuned by convex-concave optimisation (Hast et al. 2013) on the ``tune_on``
tasks; optionally also with the derivative-free tuner of the simulated RMS
error, for comparison. The report puts the simulated Table 1 and Table 2
quantities next to the paper's (``docs/following.md``).

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: accompanying
... name: demo
... tasks: [forward, left_pivot]
... tuning: {tune_on: [forward], derivative_free: false}
... ''')
>>> result = run_study(study)
>>> result.status, list(result.to_frame()["task"].unique())
('ok', ['forward', 'left_pivot'])
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Annotated, Any, ClassVar, Literal

import pandas as pd
from pydantic import Field, model_validator

from designlab.following import (
    TASK_NAMES,
    AccompanyResult,
    LoopAnalysis,
    MecanumPlatform,
    PIDTuningResult,
    StringPotSensor,
    UserFramePID,
    accompany,
    loop_analysis,
    tune_pid,
    walking_task,
)
from designlab.results import OK, Result
from designlab.study.base import Flag, Integer, Model, NonNegative, Number, Positive, StudyBase
from designlab.study.registry import StudyKind
from designlab.study.runner import RunContext

__all__ = [
    "KIND",
    "AccompanyingResult",
    "AccompanyingStudy",
    "run",
]

logger = logging.getLogger(__name__)

TaskName = Literal[
    "forward",
    "backward",
    "left_lateral",
    "right_lateral",
    "left_pivot",
    "right_pivot",
    "rectangle",
    "circle_cw",
    "circle_ccw",
]


class WalkingSpec(Model):
    """Walking-task parameters shared by the tasks (defaults: ``walking_task``'s)."""

    speed: Positive | None = Field(None, description="cruise speed, m/s (default per task)")
    radius: Positive = Field(0.9, description="circle radius, m")
    sway_lateral: NonNegative = Field(0.0, description="pelvis sway amplitude, m")
    sway_yaw: NonNegative = Field(0.0, description="pelvis yaw sway amplitude, rad")
    settle_time: Annotated[Number, Field(ge=10.0, le=60.0)] = Field(
        10.0, description="standing time after the walk, s (>= 10 for the settled error)"
    )


class PlatformSpec(Model):
    """The mecanum platform (``MecanumPlatform``), SI units."""

    time_constant: Positive = 0.15
    yaw_time_constant: Positive | None = None
    max_speed: Positive = 1.0
    max_acceleration: Positive = 2.0
    max_yaw_rate: Positive = 3.0
    max_yaw_acceleration: Positive = 6.0
    limit_mode: Literal["norm", "per_axis"] = "norm"
    max_wheel_speed: Positive | None = None

    def build(self) -> MecanumPlatform:
        """The :class:`MecanumPlatform`."""
        return MecanumPlatform(**self.model_dump())


class SensorSpec(Model):
    """The string-pot sensor (``StringPotSensor``), SI units."""

    sample_rate: Positive = 50.0
    oversampling: Annotated[Integer, Field(ge=1, le=40)] = 4
    median_window: Annotated[Integer, Field(ge=1, le=15)] = 1
    distance_noise: NonNegative = 0.0
    angle_noise: NonNegative = 0.0
    min_range: NonNegative = 0.20
    max_range: Positive = 1.50

    def build(self) -> StringPotSensor:
        """The :class:`StringPotSensor`."""
        return StringPotSensor(**self.model_dump())


class PIDSpec(Model):
    """PID gains (``UserFramePID``); heading gains default to the linear ones."""

    kp: NonNegative = 2.0
    ki: NonNegative = 0.5
    kd: NonNegative = 0.1
    derivative_filter_time: NonNegative = 0.05
    kp_heading: NonNegative | None = None
    ki_heading: NonNegative | None = None
    kd_heading: NonNegative | None = None

    def build(self) -> UserFramePID:
        """The :class:`UserFramePID`."""
        return UserFramePID(**self.model_dump())


class TuningSpec(Model):
    """PID tuning settings."""

    tune_on: list[TaskName] = Field(
        default_factory=lambda: ["forward", "left_lateral", "circle_cw"], min_length=1
    )
    ms_max: Annotated[Number, Field(ge=1.0, le=3.0)] = 1.6
    mt_max: Annotated[Number, Field(ge=1.0, le=3.0)] = 1.3
    max_noise_gain: Positive | None = Field(
        None, description="limit of |C S|, noise to command, 1/s (none by default)"
    )
    derivative_free: Flag = Field(True, description="also run the Nelder-Mead tuner")
    max_evaluations: Annotated[Integer, Field(ge=5, le=1000)] = 150


class AccompanyingStudy(StudyBase):
    """Simulate the accompanying robot on walking tasks with the default and tuned PID."""

    kind: Literal["accompanying"]
    tasks: list[TaskName] = Field(default_factory=lambda: list(TASK_NAMES), min_length=1)
    walking: WalkingSpec = Field(default_factory=WalkingSpec)
    platform: PlatformSpec = Field(default_factory=PlatformSpec)
    sensor: SensorSpec = Field(default_factory=SensorSpec)
    controller: PIDSpec = Field(default_factory=PIDSpec)
    tuning: TuningSpec | None = Field(default_factory=TuningSpec)
    seed: Annotated[Integer, Field(ge=0)] = 0

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "metrics.csv",
        "table1.csv",
        "table2.csv",
        "tuning.csv",
        "margins.csv",
        "trajectories_*.png",
        "errors.png",
        "readings.png",
        "bode.png",
        "nyquist.png",
        "study.yaml",
    )

    def size(self) -> str:
        """The number of tasks and controllers."""
        n_ctrl = 1 + (0 if self.tuning is None else 1 + int(self.tuning.derivative_free))
        return f"{len(self.tasks)} tasks x {n_ctrl} controllers"

    @model_validator(mode="after")
    def _unique_tasks(self) -> AccompanyingStudy:
        if len(set(self.tasks)) != len(self.tasks):
            raise ValueError("a task is listed twice")
        return self

    def build_task(self, name: str) -> Any:
        """The :class:`WalkingTask` of one task name with the study's walking settings."""
        w = self.walking
        return walking_task(
            name,
            speed=w.speed,
            radius=w.radius,
            sway=(w.sway_lateral, w.sway_yaw),
            settle_time=w.settle_time,
        )


@dataclass(frozen=True, eq=False)
class AccompanyingResult(Result):
    """Runs of every task with each controller, the tunings and the loop analyses.

    Attributes
    ----------
    study
        The study.
    runs
        Controller label (``"default"``, ``"tuned"``, ``"derivative_free"``) ->
        task -> :class:`AccompanyResult`.
    tunings
        Label -> :class:`PIDTuningResult`.
    loops
        Label -> :class:`LoopAnalysis`.
    """

    study: AccompanyingStudy
    runs: dict[str, dict[str, AccompanyResult]]
    tunings: dict[str, PIDTuningResult]
    loops: dict[str, LoopAnalysis]

    @property
    def status(self) -> str:
        """``"ok"`` or the first non-ok status of a run, tuning or loop."""
        for runs in self.runs.values():
            for r in runs.values():
                if r.status != OK:
                    return r.status
        for t in self.tunings.values():
            if t.status not in (OK, "not_converged"):
                return t.status
        for la in self.loops.values():
            if la.status != OK:
                return la.status
        return OK

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """Every warning, prefixed with the controller and task."""
        out: list[str] = []
        for label, runs in self.runs.items():
            for task, r in runs.items():
                out.extend(f"{label} / {task}: {w}" for w in r.warnings)
        for label, t in self.tunings.items():
            out.extend(f"tuning {label}: {w}" for w in t.warnings)
        for label, la in self.loops.items():
            out.extend(f"loop {label}: {w}" for w in la.warnings)
        return tuple(out)

    def to_frame(self) -> pd.DataFrame:
        """One row per (controller, task): Table 1/2 quantities and tracking metrics."""
        frames = []
        for label, runs in self.runs.items():
            for r in runs.values():
                f = r.to_frame()
                f.insert(0, "controller", label)
                frames.append(f)
        return pd.concat(frames, ignore_index=True)

    def tuning_frame(self) -> pd.DataFrame:
        """The study's PID and every tuned PID: gains, Ms, Mt, improvement, cost."""
        rows = []
        base = self.loops["default"]
        c = self.study.controller.build()
        mean_default = float(pd.Series([r.rms_error for r in self.runs["default"].values()]).mean())
        rows.append(
            {
                "method": "default",
                "kp_1_s": c.kp,
                "ki_1_s2": c.ki,
                "kd": c.kd,
                "Tf_s": c.derivative_filter_time,
                "Ms": base.ms,
                "Mt": base.mt,
                "phase_margin_deg": float(base.to_frame()["phase_margin_deg"].min()),
                "mean_rms_all_tasks_m": mean_default,
            }
        )
        for label, t in self.tunings.items():
            row = t.gains_frame().iloc[0].to_dict()
            row["method"] = label
            row["mean_rms_all_tasks_m"] = float(
                pd.Series([r.rms_error for r in self.runs[label].values()]).mean()
            )
            row["improvement_all_tasks"] = 1.0 - row["mean_rms_all_tasks_m"] / mean_default
            rows.append(row)
        return pd.DataFrame(rows)


def run(study: AccompanyingStudy, context: RunContext) -> AccompanyingResult:
    """Simulate the tasks with the default PID, tune, and simulate again (in this process).

    Parameters
    ----------
    study
        The accompanying study.
    context
        How to run it (unused: the tasks are simulated in this process).
    """
    platform = study.platform.build()
    sensor = study.sensor.build()
    baseline = study.controller.build()
    tasks = {name: study.build_task(name) for name in study.tasks}
    controllers: dict[str, UserFramePID] = {"default": baseline}
    tunings: dict[str, PIDTuningResult] = {}
    if study.tuning is not None:
        tune_tasks = [study.build_task(n) for n in study.tuning.tune_on]
        common = {
            "baseline": baseline,
            "platform": platform,
            "sensor": sensor,
            "ms_max": study.tuning.ms_max,
            "mt_max": study.tuning.mt_max,
            "derivative_filter_time": baseline.derivative_filter_time,
            "max_noise_gain": study.tuning.max_noise_gain,
        }
        tunings["tuned"] = tune_pid(tune_tasks, method="convex", **common)
        controllers["tuned"] = tunings["tuned"].controller
        if study.tuning.derivative_free:
            logger.info("derivative-free tuning on %d tasks", len(tune_tasks))
            tunings["derivative_free"] = tune_pid(
                tune_tasks,
                method="simulation",
                max_evaluations=study.tuning.max_evaluations,
                **common,
            )
            controllers["derivative_free"] = tunings["derivative_free"].controller
    runs = {
        label: {
            name: accompany(task, c, platform=platform, sensor=sensor, seed=study.seed)
            for name, task in tasks.items()
        }
        for label, c in controllers.items()
    }
    loops = {label: loop_analysis(c, platform, sensor) for label, c in controllers.items()}
    return AccompanyingResult(study, runs, tunings, loops)


KIND = StudyKind(
    name="accompanying",
    schema=AccompanyingStudy,
    run=run,
    report="designlab.report.accompanying",
)
