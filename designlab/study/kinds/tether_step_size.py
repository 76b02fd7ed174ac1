"""The ``tether_step_size`` study kind: FTL's recording step Delta s_min (Allan 2015 Sec. 2.5.5).

The thesis ran FTL on the 4 m figure-eight with non-dimensional steps 0.02 and
0.8 (0.01 m and 0.4 m under the 0.5 m unit of Sec. 2.5, A4): 0.02 tracks closely;
0.8 deviates significantly more and cuts corners, with a larger variation of
l_m at large steps; the effect on V_r is negligible. Each (path, step) is
simulated (:func:`designlab.following.tether.simulate`) and scored
(:func:`designlab.following.tether.follower_metrics`); the path memory the
buffer holds, ``(buffer_size - 1) Delta s_min``, is reported beside it (the
thesis's trade-off: a small step needs more memory).

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> r = run_study(parse_study('''
... designlab: 1
... kind: tether_step_size
... name: demo
... paths: [{type: figure_eight, a: 2.0}]
... min_steps: [0.01, 0.4]
... '''))
>>> str(r.status), r.to_frame()["min_step_m"].tolist()
('ok', [0.01, 0.4])
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import pandas as pd
from pydantic import Field, TypeAdapter, model_validator

from designlab.following.tether import (
    LAWS,
    FollowerMetrics,
    FollowerRun,
    FollowTheLeader,
    follower_metrics,
    simulate,
)
from designlab.following.tether.parameters import LEADER_SPEED, SETTLE_TIME
from designlab.params import params_of
from designlab.progress import Progress
from designlab.results import OK, Result
from designlab.study.base import StudyBase
from designlab.study.kinds.tether_specs import (
    ControllerSpec,
    FollowerRobotSpec,
    PathSpec,
    robot_field,
)
from designlab.study.registry import StudyKind
from designlab.study.reproduction import SAME_ON_A_GENERIC_CPU
from designlab.study.runner import RunContext

__all__ = ["KIND", "StepSizeCase", "TetherStepSizeResult", "TetherStepSizeStudy", "run"]

_MIN_STEP = params_of(FollowTheLeader)["min_step"]

#: Start-up from rest (s) left out of the l_m and V_r variations (they are taken from then
#: until the leader stops).
TRANSIENT = 5.0


def _default_paths() -> list[Any]:
    return TypeAdapter(list[PathSpec]).validate_python([{"type": "figure_eight", "a": 4.0}])


def _default_controller() -> Any:
    return TypeAdapter(ControllerSpec).validate_python({"type": FollowTheLeader.name})


class TetherStepSizeStudy(StudyBase):
    """FTL (or FTL-CD) with several recording steps Delta s_min on leader paths."""

    kind: Literal["tether_step_size"]
    robot: FollowerRobotSpec = robot_field()  # type: ignore[valid-type]
    speed: LEADER_SPEED.annotation() = LEADER_SPEED.default  # type: ignore[valid-type]
    settle_time: SETTLE_TIME.annotation() = SETTLE_TIME.default  # type: ignore[valid-type]
    controller: ControllerSpec = Field(default_factory=_default_controller)  # type: ignore[valid-type]
    paths: list[PathSpec] = Field(default_factory=_default_paths, min_length=1, max_length=10)  # type: ignore[valid-type]
    min_steps: list[_MIN_STEP.annotation()] = Field(  # type: ignore[valid-type]
        default_factory=lambda: [0.01, 0.4],
        min_length=2,
        max_length=40,
        description="Delta s_min values (m); the first is the reference",
    )

    TYPICAL_DURATION: ClassVar[float] = 2  # s, the committed study, serial, this machine
    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "step_size.csv",
        "step_size_*.png",
        "study.yaml",
    )

    def size(self) -> str:
        """Paths x steps."""
        return f"{len(self.paths) * len(self.min_steps)} runs"

    @model_validator(mode="after")
    def _runnable(self) -> TetherStepSizeStudy:
        if not LAWS.get(self.controller.type).target_finder.records_path:
            raise ValueError(
                f"controller.type = {self.controller.type!r}: the step size is FTL's or FTL-CD's "
                "(a Pseudo-Joystick records no path)"
            )
        names = [p.build().name for p in self.paths]
        if len(set(names)) != len(names):
            raise ValueError(f"path names must be unique (give `name:`), got {names}")
        return self


@dataclass(frozen=True)
class StepSizeCase:
    """One (path, Delta s_min) run and its figures.

    Attributes
    ----------
    path
        The path's name.
    min_step
        Delta s_min in m.
    run
        The run.
    metrics
        Its figures.
    """

    path: str
    min_step: float
    run: FollowerRun
    metrics: FollowerMetrics

    def row(self) -> dict[str, Any]:
        c = self.run.controller
        t = self.run.t
        walking = (t >= TRANSIENT) & (t <= self.run.path.length / self.run.speed_leader)
        return {
            "path": self.path,
            "min_step_m": self.min_step,
            "memory_m": (c.buffer_size - 1) * self.min_step,  # type: ignore[attr-defined]
            **self.metrics.as_dict(),
            "tether_range_m": self.metrics.tether_max - self.metrics.tether_min,
            "tether_std_m": float(self.run.tether_length[walking].std()),
            "speed_std_m_per_s": float(self.run.speed[walking].std()),
            "status": self.metrics.status,
        }


@dataclass(frozen=True)
class TetherStepSizeResult(Result):
    """Results of a ``tether_step_size`` study, in path, step order.

    Attributes
    ----------
    study
        The study.
    cases
        One case per (path, step).
    """

    study: TetherStepSizeStudy
    cases: tuple[StepSizeCase, ...]

    @property
    def status(self) -> str:  # type: ignore[override]
        return next((str(c.metrics.status) for c in self.cases if c.metrics.status != OK), OK)

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        return tuple(
            f"{c.path} / ds_min {c.min_step:g} m: {w}"
            for c in self.cases
            for w in c.metrics.warnings
        )

    def to_frame(self) -> pd.DataFrame:
        """One row per run."""
        return pd.DataFrame([c.row() for c in self.cases])


def run(study: TetherStepSizeStudy, context: RunContext) -> TetherStepSizeResult:
    """Simulate every (path, step).

    Parameters
    ----------
    study, context
        The study, and how to run it (its progress bar: one step a (path, step) run).
    """
    robot = study.robot.build()
    base = study.controller.build()
    jobs = [(p.build(), float(ds)) for p in study.paths for ds in study.min_steps]
    cases = []
    with context.bar(f"{study.kind}: simulate", total=len(jobs)) as hook:
        for i, (path, ds) in enumerate(jobs):
            r = simulate(base.replace(min_step=ds), path, speed=study.speed, robot=robot,
                         settle_time=study.settle_time)  # fmt: skip
            cases.append(StepSizeCase(path.name, ds, r, follower_metrics(r)))
            hook(Progress(i + 1, len(jobs), label="run", note=f"{path.name} {ds:g} m"))
    return TetherStepSizeResult(study, tuple(cases))


KIND = StudyKind(
    name="tether_step_size",
    schema=TetherStepSizeStudy,
    run=run,
    report="designlab.report.tether_step_size",
    reproduction=SAME_ON_A_GENERIC_CPU,
)
