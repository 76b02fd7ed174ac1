"""The ``tether_comparison`` study kind: tether-follower laws side by side (Allan 2015).

Every (path, law, desired tether length) is simulated
(:func:`designlab.following.tether.simulate`) and scored with the normal path
deviation of App. A and the other figures of Sec. 2.5.1
(:func:`designlab.following.tether.follower_metrics`). The report puts the mean
deviation in wheel tracks next to the measured Tables 3.2/3.3. For every
(law, l_d) it also linearises the lateral loop (python-control,
:func:`designlab.following.tether.linear_analysis`) and fits the damping ratio and
natural frequency of a simulated lateral step of the full nonlinear loop
(:func:`designlab.following.tether.lateral_step_response`), so that the
report shows the linear prediction next to the simulation.

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: tether_comparison
... name: demo
... paths: [{type: slalom}]
... controllers: [{type: PseudoJoystick}, {type: FollowTheLeaderConstDistance}]
... desired_lengths: [0.6]
... ''')
>>> r = run_study(study)
>>> str(r.status), r.to_frame()["controller"].tolist()
('ok', ['PJ', 'FTL-CD'])
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import pandas as pd
from pydantic import Field, model_validator

from designlab.errors import DesignlabError
from designlab.following.tether import (
    FollowerMetrics,
    FollowerRun,
    PseudoJoystick,
    fit_damping,
    follower_metrics,
    lateral_step_response,
    linear_analysis,
    simulate,
)
from designlab.following.tether import linear as tether_linear
from designlab.following.tether.odometry import MarkerOffset, WheelSlip, simulate_with_errors
from designlab.following.tether.parameters import DURATION, LEADER_SPEED, SEED, SETTLE_TIME
from designlab.params import params_of
from designlab.progress import Progress
from designlab.results import OK, Result
from designlab.study.base import Model, StudyBase
from designlab.study.kinds.tether_specs import (
    ControllerSpec,
    FollowerRobotSpec,
    PathSpec,
    built,
    controllers_field,
    robot_field,
)
from designlab.study.registry import StudyKind
from designlab.study.reproduction import SAME_ON_A_GENERIC_CPU
from designlab.study.runner import RunContext
from designlab.study.specs import spec_model

__all__ = ["KIND", "FollowerCase", "TetherComparisonResult", "TetherComparisonStudy", "run"]

_DESIRED_LENGTH = params_of(PseudoJoystick)["desired_length"]


#: Wheel slip of the error-source runs (:class:`WheelSlip`).
SlipSpec = spec_model(WheelSlip, name="SlipSpec")
#: Tether-tip offset from the measured marker (:class:`MarkerOffset`).
MarkerSpec = spec_model(MarkerOffset, name="MarkerSpec")
#: The error-source variants, in report order.
ERROR_VARIANTS = ("none", "slip", "marker", "both")


class ErrorSourcesSpec(Model):
    """The error sources of Allan 2015 Sec. 3.4 (wheel slip, the marker offset), per law."""

    paths: list[str] | None = Field(
        None, min_length=1, description="names of the study's paths to run (default: all)"
    )
    desired_length: _DESIRED_LENGTH.annotation() = 1.0  # type: ignore[valid-type]
    slip: SlipSpec = Field(  # type: ignore[valid-type]
        default_factory=lambda: SlipSpec(left_slip=0.02, noise_std=0.02)
    )
    marker: MarkerSpec = Field(default_factory=lambda: MarkerSpec(left=0.15))  # type: ignore[valid-type]
    seed: SEED.annotation(optional=False) = SEED.default  # type: ignore[valid-type]

    def variants(self) -> dict[str, dict[str, Any]]:
        """Variant (:data:`ERROR_VARIANTS`) -> keyword arguments of ``simulate_with_errors``."""
        slip, marker = self.slip.build(), self.marker.build()
        return {
            "none": {},
            "slip": {"slip": slip},
            "marker": {"marker": marker},
            "both": {"slip": slip, "marker": marker},
        }


class TetherComparisonStudy(StudyBase):
    """Simulate tether-follower laws on leader paths and compare their accuracy."""

    kind: Literal["tether_comparison"]
    robot: FollowerRobotSpec = robot_field()  # type: ignore[valid-type]
    speed: LEADER_SPEED.annotation() = LEADER_SPEED.default  # type: ignore[valid-type]
    settle_time: SETTLE_TIME.annotation() = SETTLE_TIME.default  # type: ignore[valid-type]
    controllers: list[ControllerSpec] = controllers_field(max_length=20)  # type: ignore[valid-type]
    paths: list[PathSpec] = Field(min_length=1, max_length=50)  # type: ignore[valid-type]
    desired_lengths: list[_DESIRED_LENGTH.annotation()] | None = Field(  # type: ignore[valid-type]
        None,
        max_length=50,
        description="l_d values (m) applied to every law; default: each law's own",
    )
    error_sources: ErrorSourcesSpec | None = Field(
        None, description="wheel slip and the marker offset (Sec. 3.4), per law and path"
    )

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "metrics.csv",
        "linear.csv",
        "npd_heuristic.csv",
        "error_sources.csv",
        "allan_tables.csv",
        "trajectories_*.png",
        "npd_profiles_*.png",
        "study.yaml",
    )
    #: s: CPU time of studies/tether_comparison.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 31

    def size(self) -> str:
        """The number of simulated runs."""
        n = len(self.paths) * len(self.controllers) * len(self.desired_lengths or [None])
        return f"{n} runs"

    def cases(self) -> list[tuple[Any, str, Any]]:
        """Every (path, label, controller) of the study, in path, l_d, law order."""
        jobs = []
        for ps in self.paths:
            path = ps.build()
            for ld in self.desired_lengths or [None]:
                for cs in self.controllers:
                    ctrl = cs.build() if ld is None else cs.build(desired_length=float(ld))
                    jobs.append((path, cs.title, ctrl))
        return jobs

    @model_validator(mode="after")
    def _runnable(self) -> TetherComparisonStudy:
        titles = [c.title for c in self.controllers]
        if len(set(titles)) != len(titles):
            raise ValueError(f"controller labels must be unique, got {titles}")
        names = [p.build().name for p in self.paths]
        if len(set(names)) != len(names):
            raise ValueError(f"path names must be unique (give `name:`), got {names}")
        robot = built(self.robot)
        e = self.error_sources
        if e is not None:
            unknown = sorted(set(e.paths or ()) - set(names))
            if unknown:
                raise ValueError(f"error_sources.paths: {unknown} are not paths of the study")
            if e.desired_length <= 0.5 * robot.body_length:
                raise ValueError(
                    f"error_sources.desired_length = {self.error_sources.desired_length:g} m "
                    f"must exceed half the robot length ({0.5 * robot.body_length:g} m)"
                )
        for path, title, ctrl in self.cases():
            if ctrl.desired_length <= 0.5 * robot.body_length:
                raise ValueError(
                    f"{title}: desired_length = {ctrl.desired_length:g} m must exceed half the "
                    f"robot length ({0.5 * robot.body_length:g} m)"
                )
            try:
                DURATION.check(
                    path.length / self.speed + self.settle_time, f"{path.name}: duration"
                )
            except DesignlabError as exc:
                raise ValueError(str(exc)) from None
        return self


@dataclass(frozen=True)
class FollowerCase:
    """One simulated (path, law, l_d).

    Attributes
    ----------
    path
        Name of the leader's path.
    controller
        Name of the law and its desired length.
    run
        The simulated run.
    metrics
        Its figures (normal path deviation, tether error, ...).
    """

    path: str
    controller: str
    run: FollowerRun
    metrics: FollowerMetrics

    def row(self) -> dict[str, Any]:
        c = self.run.controller
        return {
            "path": self.path,
            "controller": self.controller,
            "law": c.name,
            "desired_length_m": c.desired_length,
            "speed_m_per_s": self.run.speed_leader,
            **{k: v for k, v in self.metrics.as_dict().items()},
            "status": self.metrics.status,
        }


@dataclass(frozen=True)
class TetherComparisonResult(Result):
    """Results of a ``tether_comparison`` study, in path, l_d, law order.

    Attributes
    ----------
    study
        The study.
    cases
        One case per (path, l_d, law).
    linear
        Linearised loop next to the simulated step, per law and l_d (if asked for).
    errors
        Mean NPD per path, law and error-source variant (:func:`error_sources_table`),
        or None.
    """

    study: TetherComparisonStudy
    cases: tuple[FollowerCase, ...]
    linear: pd.DataFrame | None = None
    errors: pd.DataFrame | None = None

    @property
    def status(self) -> str:  # type: ignore[override]
        for c in self.cases:
            if c.metrics.status != OK:
                return str(c.metrics.status)
        return OK

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        return tuple(
            f"{c.path} / {c.controller} / l_d {c.run.controller.desired_length:g} m: {w}"
            for c in self.cases
            for w in c.metrics.warnings
        )

    def to_frame(self) -> pd.DataFrame:
        """One row per run: NPD statistics (m and /b), tether, smoothness, path-length ratio."""
        return pd.DataFrame([c.row() for c in self.cases])


def run(study: TetherComparisonStudy, context: RunContext) -> TetherComparisonResult:
    """Simulate every (path, l_d, law) in this process (each run takes milliseconds).

    Parameters
    ----------
    study
        The tether comparison study.
    context
        How to run it (its progress bar).
    """
    robot = study.robot.build()
    jobs = study.cases()
    cases = []
    with context.bar(f"{study.kind}: simulate", total=len(jobs)) as hook:
        for i, (path, title, ctrl) in enumerate(jobs):
            r = simulate(ctrl, path, speed=study.speed, robot=robot, settle_time=study.settle_time)
            cases.append(FollowerCase(path.name, title, r, follower_metrics(r)))
            hook(Progress(i + 1, len(jobs), label="run", note=f"{path.name} {title}"))
    errors = error_sources_table(study, robot, context)
    return TetherComparisonResult(study, tuple(cases), linear_table(study, robot), errors)


def error_sources_table(
    study: TetherComparisonStudy, robot: Any, context: RunContext
) -> pd.DataFrame | None:
    """Each law on each chosen path with no error, slip, the marker offset and both.

    One row per (path, law, variant): mean and maximum NPD (App. A, against the
    marker's path) in m and in wheel tracks, and the final odometry drift.

    Parameters
    ----------
    study
        The comparison study (its ``error_sources``; None: no table).
    robot
        The robot.
    context
        How to run it (its progress bar).
    """
    e = study.error_sources
    if e is None:
        return None
    chosen = set(e.paths) if e.paths is not None else None
    paths = [p.build() for p in study.paths]
    paths = [p for p in paths if chosen is None or p.name in chosen]
    jobs = [
        (p, cs.title, cs.build(desired_length=float(e.desired_length)), v, kw)
        for p in paths
        for cs in study.controllers
        for v, kw in e.variants().items()
    ]
    rows = []
    with context.bar(f"{study.kind}: error sources", total=len(jobs)) as hook:
        for i, (path, title, ctrl, variant, kw) in enumerate(jobs):
            res = simulate_with_errors(
                ctrl, path, study.speed, robot, settle_time=study.settle_time, seed=e.seed, **kw
            )
            npd = follower_metrics(res.run).npd
            rows.append(
                {
                    "path": path.name,
                    "controller": title,
                    "variant": variant,
                    "desired_length_m": float(e.desired_length),
                    "npd_mean_m": npd.mean,
                    "npd_max_m": npd.max,
                    "npd_mean_over_b": npd.mean / robot.wheel_track,
                    "odometry_drift_m": float(res.odometry_drift[-1]),
                }
            )
            hook(Progress(i + 1, len(jobs), label="run", note=f"{path.name} {title} {variant}"))
    return pd.DataFrame(rows)


#: Lateral offset (m) and fitted window (s) of the simulated step in :func:`linear_table`.
STEP_OFFSET = float(tether_linear.STEP_OFFSET.default)
STEP_WINDOW = 10.0


def linear_table(study: TetherComparisonStudy, robot: Any) -> pd.DataFrame:
    """Linear lateral loop of every (law, l_d) next to a simulated lateral step.

    The linear columns come from :func:`designlab.following.tether.linear_analysis`;
    ``sim_damping_ratio`` and ``sim_natural_frequency_rad_per_s`` come from the
    two poles identified (:func:`designlab.following.tether.linear.identify_poles`,
    :func:`designlab.following.tether.fit_damping`) in the robot's
    lateral offset after a ``STEP_OFFSET`` m sideways start on a straight path
    at the study's leader speed (the full nonlinear loop with its buffers).
    """
    rows = []
    n_fit = round(STEP_WINDOW / robot.sample_time)
    for ld in study.desired_lengths or [None]:
        for cs in study.controllers:
            ctrl = cs.build() if ld is None else cs.build(desired_length=float(ld))
            lin = linear_analysis(ctrl, speed=study.speed, robot=robot)
            row = {"controller": cs.title, "desired_length_m": ctrl.desired_length}
            row.update(lin.to_frame().iloc[0].to_dict())
            t, e = lateral_step_response(
                ctrl,
                offset=STEP_OFFSET,
                speed=study.speed,
                duration=STEP_WINDOW + 2.0,
                robot=robot,
            )
            zeta, wn = fit_damping(t[:n_fit], e[:n_fit])
            zl, wl = lin.damping_ratio, lin.natural_frequency
            row["slow_pole_per_s"] = -wl * (zl - math.sqrt(zl * zl - 1)) if zl > 1 else -zl * wl
            row["sim_slow_pole_per_s"] = float(
                tether_linear.identify_poles(t[:n_fit], e[:n_fit])[0].real
            )
            row["sim_damping_ratio"] = zeta
            row["sim_natural_frequency_rad_per_s"] = wn
            row["damping_ratio_error"] = zeta - lin.damping_ratio
            row["overshoot"] = max(0.0, -float(e.min()) / STEP_OFFSET)
            rows.append(row)
    return pd.DataFrame(rows)


KIND = StudyKind(
    name="tether_comparison",
    schema=TetherComparisonStudy,
    run=run,
    report="designlab.report.tether",
    reproduction=SAME_ON_A_GENERIC_CPU,
)
