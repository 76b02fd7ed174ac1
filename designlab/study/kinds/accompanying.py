"""The ``accompanying`` study kind: the Wu et al. 2021 walking tasks, default vs tuned PID.

Every task is simulated with the study's PID (the baseline) and with the PID
tuned by convex-concave optimisation (Hast et al. 2013) on the ``tune_on``
tasks; optionally also with the derivative-free tuner of the simulated RMS
error, for comparison. The report puts the simulated Table 1 and Table 2
quantities next to the paper's (``docs/following.md``). The platform, sensor
and PID fields, their bounds and defaults are the domain's declarations
(:mod:`designlab.following.accompanying.parameters`); every model is built
while the study is validated, so ``designlab validate`` refuses what the run
would refuse. Progress bars show the tuners and the simulations.

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
>>> str(result.status), list(result.to_frame()["task"].unique())
('ok', ['forward', 'left_pivot'])
"""

from __future__ import annotations

import dataclasses
import logging
from dataclasses import dataclass, field
from typing import Any, ClassVar, Literal

import numpy as np
import pandas as pd
from pydantic import Field, create_model, model_validator

from designlab.errors import DesignlabError
from designlab.following.accompanying import (
    TASK_NAMES,
    AccompanyResult,
    LoopAnalysis,
    MecanumPlatform,
    MotionFilter,
    PIDTuningResult,
    SensorMount,
    StringPotSensor,
    TargetAdaptation,
    UserFramePID,
    loop_analysis,
    simulate,
    tune,
    walking_task,
)
from designlab.following.accompanying.metrics import command_rate
from designlab.following.accompanying.parameters import (
    MAX_EVALUATIONS,
    MAX_NOISE_GAIN,
    MS_MAX,
    MT_MAX,
    RADIUS,
    SEED,
    SETTLE_TIME,
    SWAY_LATERAL,
    SWAY_YAW,
    WALKING_SPEED,
)
from designlab.params import Param, params_of
from designlab.progress import Progress
from designlab.results import OK, Result
from designlab.study.base import Flag, Model, StudyBase
from designlab.study.registry import StudyKind
from designlab.study.reproduction import TUNED_GAINS
from designlab.study.runner import RunContext
from designlab.study.specs import Buildable, spec_model

__all__ = [
    "KIND",
    "AccompanyingResult",
    "AccompanyingStudy",
    "run",
]

logger = logging.getLogger(__name__)

#: One of the nine tasks of Wu et al. 2021, Sec. 3 (:data:`designlab.following.TASK_NAMES`).
TaskName = Literal[TASK_NAMES]  # type: ignore[valid-type]

#: The settled error is taken 10 s after the user stops: the walk must stand that long.
MIN_SETTLE_TIME = 10.0


def _of_params(name: str, doc: str, decls: dict[str, Param], base: type[Model]) -> Any:
    """A model whose fields are declared arguments (type, bounds and default derived)."""
    fields = {n: (d.annotation(), d.default) for n, d in decls.items()}
    return create_model(name, __base__=base, __doc__=doc, **fields)


class _WalkingFields(Model):
    def build(self, name: str = "forward") -> Any:
        """The :class:`WalkingTask` of one task with these settings.

        Parameters
        ----------
        name
            The task.
        """
        return walking_task(
            name,
            speed=self.speed,  # type: ignore[attr-defined]
            radius=self.radius,  # type: ignore[attr-defined]
            sway=(self.sway_lateral, self.sway_yaw),  # type: ignore[attr-defined]
            settle_time=self.settle_time,  # type: ignore[attr-defined]
        )

    @model_validator(mode="after")
    def _settles(self) -> _WalkingFields:
        if self.settle_time < MIN_SETTLE_TIME:  # type: ignore[attr-defined]
            raise ValueError(
                f"settle_time = {self.settle_time:g} s: at least {MIN_SETTLE_TIME:g} s, so that "  # type: ignore[attr-defined]
                "the settled error 10 s after the stop is defined"
            )
        return self


#: Walking-task settings shared by the tasks (:func:`designlab.following.walking_task`).
WalkingSpec = _of_params(
    "WalkingSpec",
    "Walking-task settings shared by the tasks (defaults: walking_task's), SI units.",
    {
        "speed": WALKING_SPEED,
        "radius": RADIUS,
        "sway_lateral": SWAY_LATERAL,
        "sway_yaw": SWAY_YAW,
        "settle_time": SETTLE_TIME,
    },
    _WalkingFields,
)


def _buildable_spec(cls: type, name: str) -> Any:
    return create_model(name, __base__=(spec_model(cls, name=f"{name}Fields"), Buildable))


#: The mecanum platform (:class:`designlab.following.MecanumPlatform`), SI units.
PlatformSpec = _buildable_spec(MecanumPlatform, "PlatformSpec")
#: The string-pot sensor (:class:`designlab.following.StringPotSensor`), SI units.
SensorSpec = _buildable_spec(StringPotSensor, "SensorSpec")
#: PID gains (:class:`designlab.following.UserFramePID`); heading gains default to the linear.
PIDSpec = _buildable_spec(UserFramePID, "PIDSpec")
#: The sensor's offset from the rotation centre (:class:`SensorMount`); both
#: settings of ``compensate`` are run, so it is not a field here.
MountSpec = create_model(
    "MountSpec",
    __base__=(
        spec_model(SensorMount, name="MountSpecFields", exclude=("compensate",)),
        Buildable,
    ),
)
#: Target-distance adaptation (:class:`TargetAdaptation`).
AdaptationSpec = _buildable_spec(TargetAdaptation, "AdaptationSpec")
#: Motion filter (:class:`MotionFilter`).
MotionFilterSpec = _buildable_spec(MotionFilter, "MotionFilterSpec")

#: The runs of the Sec. 6 section, in report order.
EXTRA_OPTIONS = ("none", "mount", "mount_compensated", "adaptation", "motion_filter")


class _ExtrasFields(Model):
    tasks: list[TaskName] = Field(  # type: ignore[valid-type]
        default_factory=lambda: ["forward", "backward", "left_pivot", "circle_cw"], min_length=1
    )
    mount: MountSpec = Field(default_factory=lambda: MountSpec(offset_y=0.25))  # type: ignore[valid-type]
    adaptation: AdaptationSpec = Field(default_factory=AdaptationSpec)  # type: ignore[valid-type]
    motion_filter: MotionFilterSpec = Field(default_factory=MotionFilterSpec)  # type: ignore[valid-type]

    def options(self) -> dict[str, dict[str, Any]]:
        """Option label -> keyword arguments of :func:`simulate` (:data:`EXTRA_OPTIONS`)."""
        mount = self.mount.build()
        return {
            "none": {},
            "mount": {"mount": mount},
            "mount_compensated": {
                "mount": SensorMount(mount.offset_x, mount.offset_y, compensate=True)
            },
            "adaptation": {"adaptation": self.adaptation.build()},
            "motion_filter": {"motion_filter": self.motion_filter.build()},
        }


#: The Sec. 6 options (Wu et al. 2021): each task with the default PID and each option
#: alone, the user's pelvis sway as given here (the motion filter acts on it).
ExtrasSpec = _of_params(
    "ExtrasSpec",
    "The Sec. 6 options run one by one with the default PID, with their own pelvis sway.",
    {"sway_lateral": SWAY_LATERAL, "sway_yaw": SWAY_YAW},
    _ExtrasFields,
)


class _TuningFields(Model):
    tune_on: list[TaskName] = Field(  # type: ignore[valid-type]
        default_factory=lambda: ["forward", "left_lateral", "circle_cw"], min_length=1
    )
    derivative_free: Flag = Field(True, description="also run the Nelder-Mead tuner")


#: PID tuning settings (:func:`designlab.following.tune_pid`).
TuningSpec = _of_params(
    "TuningSpec",
    "PID tuning settings: the tasks tuned on, the limits, the derivative-free tuner.",
    {
        "ms_max": MS_MAX,
        "mt_max": MT_MAX,
        "max_noise_gain": MAX_NOISE_GAIN,
        "max_evaluations": MAX_EVALUATIONS,
    },
    _TuningFields,
)


_SENSOR = params_of(StringPotSensor)
_WINDOW = _SENSOR["median_window"].annotation(optional=False)


class _NoiseFields(Model):
    max_noise_gains: list[MAX_NOISE_GAIN.annotation(optional=False)] = Field(  # type: ignore[valid-type]
        default_factory=lambda: [20.0, 10.0, 5.0],
        min_length=1,
        max_length=10,
        description="limits of |C S| (1/s) the PID is tuned again with, one tuning each",
    )
    median_windows: list[_WINDOW] = Field(  # type: ignore[valid-type]
        default_factory=lambda: [5],
        max_length=5,
        description="median windows (raw samples) run with the tuned PID's gains and noise",
    )


#: Sensor noise and the noise-gain limits of the noise table (``noise.csv``): the study's
#: PID, the tuned PID and a PID tuned with each limit, simulated on every task without and
#: with white noise on the raw string-pot samples.
NoiseSpec = _of_params(
    "NoiseSpec",
    "White noise on the raw samples and the |C S| limits tuned with (noise.csv).",
    {
        "distance_noise": _SENSOR["distance_noise"].but(default=0.005),
        "angle_noise": _SENSOR["angle_noise"].but(default=0.005),
    },
    _NoiseFields,
)


class AccompanyingStudy(StudyBase):
    """Simulate the accompanying robot on walking tasks with the default and tuned PID."""

    kind: Literal["accompanying"]
    tasks: list[TaskName] = Field(default_factory=lambda: list(TASK_NAMES), min_length=1)  # type: ignore[valid-type]
    walking: WalkingSpec = Field(default_factory=WalkingSpec)  # type: ignore[valid-type]
    platform: PlatformSpec = Field(default_factory=PlatformSpec)  # type: ignore[valid-type]
    sensor: SensorSpec = Field(default_factory=SensorSpec)  # type: ignore[valid-type]
    controller: PIDSpec = Field(default_factory=PIDSpec)  # type: ignore[valid-type]
    tuning: TuningSpec | None = Field(default_factory=TuningSpec)  # type: ignore[valid-type]
    extras: ExtrasSpec | None = Field(  # type: ignore[valid-type]
        None, description="the Sec. 6 options (sensor offset, target adaptation, motion filter)"
    )
    noise: NoiseSpec | None = Field(  # type: ignore[valid-type]
        None,
        description="the noise table: PIDs tuned with limits on |C S|, run with sensor noise "
        "(needs tuning)",
    )
    seed: SEED.annotation(optional=False) = SEED.default  # type: ignore[valid-type]

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "metrics.csv",
        "table1.csv",
        "table2.csv",
        "tuning.csv",
        "extras.csv",
        "noise.csv",
        "margins.csv",
        "baseline_sensitivity.csv",
        "trajectories_*.png",
        "errors.png",
        "readings.png",
        "bode.png",
        "nyquist.png",
        "study.yaml",
    )
    #: s: CPU time of studies/accompanying.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 23

    def size(self) -> str:
        """The number of tasks and controllers."""
        return f"{len(self.tasks)} tasks x {self.n_controllers} controllers"

    @property
    def n_controllers(self) -> int:
        """The default PID and the tuned ones."""
        return 1 + (0 if self.tuning is None else 1 + int(self.tuning.derivative_free))

    @model_validator(mode="after")
    def _runnable(self) -> AccompanyingStudy:
        if len(set(self.tasks)) != len(self.tasks):
            raise ValueError("a task is listed twice")
        if self.noise is not None and self.tuning is None:
            raise ValueError("noise needs tuning: its rows are PIDs tuned with |C S| limits")
        names = set(self.tasks) | set(self.tuning.tune_on if self.tuning is not None else ())
        names |= set(self.extras.tasks if self.extras is not None else ())
        for name in sorted(names):
            try:
                self.build_task(name)
            except DesignlabError as exc:
                raise ValueError(f"task {name}: {exc}") from None
        return self

    def build_task(self, name: str) -> Any:
        """The :class:`WalkingTask` of one task name with the study's walking settings.

        Parameters
        ----------
        name
            The task.
        """
        return self.walking.build(name)

    def build_extras_task(self, name: str) -> Any:
        """The :class:`WalkingTask` of a Sec. 6 run: the walking settings, the extras' sway.

        Parameters
        ----------
        name
            The task.
        """
        w, e = self.walking, self.extras
        return walking_task(
            name,
            speed=w.speed,
            radius=w.radius,
            sway=(e.sway_lateral, e.sway_yaw),
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
    extras
        Option (:data:`EXTRA_OPTIONS`) -> task -> :class:`AccompanyResult`
        (empty without the study's ``extras``).
    noise
        The noise table (``noise.csv``; empty without the study's ``noise``): one row per
        PID (``controller``, ``max_noise_gain_1_s``, gains, ``noise_gain_1_s`` = max |C S|
        over the axes), the mean over the tasks of the RMS error without
        (``rms_clean_m``) and with (``rms_noisy_m``) sensor noise and of the command's
        rate of change with noise (``command_rate_m_s2``, :func:`command_rate`), and the
        status of each k_s row's tuning (``tuning_status``).
    """

    study: AccompanyingStudy
    runs: dict[str, dict[str, AccompanyResult]]
    tunings: dict[str, PIDTuningResult]
    loops: dict[str, LoopAnalysis]
    extras: dict[str, dict[str, AccompanyResult]] = field(default_factory=dict)
    noise: pd.DataFrame = field(default_factory=pd.DataFrame, repr=False)

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
        for label, runs in self.extras.items():
            for task, r in runs.items():
                out.extend(f"Sec. 6 {label} / {task}: {w}" for w in r.warnings)
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


def _tunings(study: AccompanyingStudy, context: RunContext) -> dict[str, PIDTuningResult]:
    """The convex-concave tuning and, if asked, the derivative-free one, with progress bars."""
    if study.tuning is None:
        return {}
    t = study.tuning
    baseline = study.controller.build()
    common = {
        "baseline": baseline,
        "platform": study.platform.build(),
        "sensor": study.sensor.build(),
        "ms_max": t.ms_max,
        "mt_max": t.mt_max,
        "derivative_filter_time": baseline.derivative_filter_time,
        "max_noise_gain": t.max_noise_gain,
    }
    tune_tasks = [study.build_task(n) for n in t.tune_on]
    out = {}
    with context.bar(f"{study.kind}: convex-concave tuning") as hook:
        out["tuned"] = tune(tune_tasks, method="convex", progress=hook, **common)
    if t.derivative_free:
        logger.info("derivative-free tuning on %d tasks", len(tune_tasks))
        with context.bar(f"{study.kind}: derivative-free tuning", t.max_evaluations) as hook:
            out["derivative_free"] = tune(
                tune_tasks,
                method="simulation",
                max_evaluations=t.max_evaluations,
                progress=hook,
                **common,
            )
    return out


def run(study: AccompanyingStudy, context: RunContext) -> AccompanyingResult:
    """Simulate the tasks with the default PID, tune, and simulate again (in this process).

    Parameters
    ----------
    study
        The accompanying study.
    context
        How to run it (its progress bars; the tasks are simulated in this process).
    """
    platform = study.platform.build()
    sensor = study.sensor.build()
    tasks = {name: study.build_task(name) for name in study.tasks}
    tunings = _tunings(study, context)
    controllers = {"default": study.controller.build()}
    controllers.update({label: t.controller for label, t in tunings.items()})
    runs: dict[str, dict[str, AccompanyResult]] = {label: {} for label in controllers}
    total = len(tasks) * len(controllers)
    with context.bar(f"{study.kind}: simulate", total) as hook:
        for label, c in controllers.items():
            for name, task in tasks.items():
                runs[label][name] = simulate(
                    task, c, platform=platform, sensor=sensor, seed=study.seed
                )
                step = sum(len(r) for r in runs.values())
                hook(Progress(step, total, label="run", note=f"{label} {name}"))
    loops = {label: loop_analysis(c, platform, sensor) for label, c in controllers.items()}
    extras = _extras(study, controllers["default"], context)
    noise = _noise_table(study, controllers, runs, context)
    return AccompanyingResult(study, runs, tunings, loops, extras, noise)


def _noise_table(
    study: AccompanyingStudy,
    controllers: dict[str, UserFramePID],
    runs: dict[str, dict[str, AccompanyResult]],
    context: RunContext,
) -> pd.DataFrame:
    """The study's and the tuned PIDs and one tuned with each |C S| limit, with noise."""
    if study.noise is None or study.tuning is None:
        return pd.DataFrame()
    nz, t = study.noise, study.tuning
    platform, sensor = study.platform.build(), study.sensor.build()
    noisy = study.sensor.model_copy(
        update={"distance_noise": nz.distance_noise, "angle_noise": nz.angle_noise}
    ).build()
    base = controllers["default"]
    pids: list[tuple[str, float | None, UserFramePID]] = [
        ("default", None, base),
        ("tuned", t.max_noise_gain, controllers["tuned"]),
    ]
    tune_tasks = [study.build_task(n) for n in t.tune_on]
    status: dict[str, str] = {}  # the tuning's status of each k_s row (a solver says so)
    for ks in nz.max_noise_gains:
        with context.bar(f"{study.kind}: tuning with |C S| <= {ks:g}") as hook:
            r = tune(tune_tasks, method="convex", baseline=base, platform=platform,
                     sensor=sensor, ms_max=t.ms_max, mt_max=t.mt_max,
                     derivative_filter_time=base.derivative_filter_time,
                     max_noise_gain=ks, progress=hook)  # fmt: skip
        pids.append((f"tuned, k_s = {ks:g} 1/s", ks, r.controller))
        status[pids[-1][0]] = str(r.status)
    runs_of = [(label, ks, c, sensor.median_window) for label, ks, c in pids]
    runs_of += [(f"tuned, median of {m}", t.max_noise_gain, controllers["tuned"], m)
                for m in nz.median_windows]  # fmt: skip
    rows = []
    for label, ks, c, window in runs_of:
        row = {"controller": label, "max_noise_gain_1_s": ks, "kp_1_s": c.kp, "ki_1_s2": c.ki,
               "kd": c.kd, "median_window": window,
               "noise_gain_1_s": float(loop_analysis(c, platform, sensor).to_frame()[
                   "noise_gain_1_s"].max())}  # fmt: skip
        if window == sensor.median_window:
            clean = [runs[label][n] if label in runs else
                     simulate(study.build_task(n), c, platform=platform, sensor=sensor)
                     for n in study.tasks]  # fmt: skip
            row["rms_clean_m"] = float(np.mean([r.rms_error for r in clean]))
        noisy_w = dataclasses.replace(noisy, median_window=window)
        dirty = [simulate(study.build_task(n), c, platform=platform, sensor=noisy_w,
                          seed=study.seed) for n in study.tasks]  # fmt: skip
        row["rms_noisy_m"] = float(np.mean([r.rms_error for r in dirty]))
        row["command_rate_m_s2"] = float(np.mean([command_rate(r.time, r.command) for r in dirty]))
        row["tuning_status"] = status.get(label, "")
        rows.append(row)
    return pd.DataFrame(rows)


def _extras(
    study: AccompanyingStudy, controller: UserFramePID, context: RunContext
) -> dict[str, dict[str, AccompanyResult]]:
    """Each Sec. 6 option alone on the extras' tasks, with the default PID."""
    if study.extras is None:
        return {}
    common = {
        "platform": study.platform.build(),
        "sensor": study.sensor.build(),
        "seed": study.seed,
    }
    tasks = {name: study.build_extras_task(name) for name in study.extras.tasks}
    options = study.extras.options()
    out: dict[str, dict[str, AccompanyResult]] = {label: {} for label in options}
    total = len(tasks) * len(options)
    with context.bar(f"{study.kind}: Sec. 6 options", total) as hook:
        for label, kwargs in options.items():
            for name, task in tasks.items():
                out[label][name] = simulate(task, controller, **common, **kwargs)
                step = sum(len(r) for r in out.values())
                hook(Progress(step, total, label="run", note=f"{label} {name}"))
    return out


KIND = StudyKind(
    name="accompanying",
    schema=AccompanyingStudy,
    run=run,
    report="designlab.report.accompanying",
    reproduction=TUNED_GAINS,
)
