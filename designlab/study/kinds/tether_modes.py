"""The ``tether_modes`` study kind: Allan 2015 Ch. 4 side, front and Brake modes in simulation.

* Side and front following (Sec. 4.2-4.3, Figs. 4.5-4.12): each mode walks each
  path with the leader; the side modes at every side offset l_H (the thesis's
  figures use 2.0 b and 1.5 b), the front modes at the code's l_d. The figures:
  the normal deviation from the leader's path (for a side mode: the side
  offset), its spread, the tether range and whether the robot lost the leader.
* Brake mode (Sec. 4.4): a leader walks a straight line and stops; with a noisy
  tether sensor each law runs without and with Brake mode; the figures are the
  robot's turning and travel after the leader stopped, and the time braked
  while the leader walked (a false brake).

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> r = run_study(parse_study('''
... designlab: 1
... kind: tether_modes
... name: demo
... paths: [{type: straight_line, length: 4.0}]
... modes: [SideJoystick]
... side_offsets: [0.56]
... brake_laws: [PseudoJoystick]
... '''))
>>> r.to_frame()["mode"].tolist(), r.brake_frame()["brake"].tolist()
(['SideJoystick'], [False, True])
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np
import pandas as pd
from pydantic import Field, TypeAdapter, model_validator

from designlab.following.tether import (
    LAWS,
    BrakeMode,
    FollowerRobot,
    FollowerRun,
    SideJoystick,
    brake_timeline,
    normal_path_deviation,
    simulate,
    straight_line,
)
from designlab.following.tether.parameters import LEADER_SPEED
from designlab.params import params_of
from designlab.progress import Progress
from designlab.results import OK, Result
from designlab.study.base import StudyBase
from designlab.study.kinds.tether_specs import FollowerRobotSpec, PathSpec, robot_field
from designlab.study.registry import StudyKind
from designlab.study.reproduction import NOISE_AROUND_ZERO
from designlab.study.runner import RunContext

__all__ = ["KIND", "BrakeCase", "ModeCase", "TetherModesResult", "TetherModesStudy", "run"]

#: The modes of the study: every registered law that walks beside or ahead of the leader.
MODES = LAWS.choices(placement="side") + LAWS.choices(placement="front")
#: The laws Brake mode may wrap here: those that follow from behind.
BRAKE_LAWS = LAWS.choices(placement="behind", brakeable=True)
_OFFSET = params_of(SideJoystick)["desired_length"]
_ENGAGE = params_of(BrakeMode)["engage_margin"]
_RELEASE = params_of(BrakeMode)["release_margin"]
_LNOISE = params_of(FollowerRobot)["length_noise_std"]
_ANOISE = params_of(FollowerRobot)["angle_noise_std"]
#: Leader curvature (1/m) above which a path segment counts as a turn (inside or outside).
TURN_CURVATURE = 0.1
#: The Brake runs' start-up (s) left out of ``braked_while_walking_pct``: the leader must
#: walk longer than this before it stops (``brake_walk / speed``), or the share has no sample.
BRAKE_SETTLE = 2.0
#: A robot farther than this many side offsets (or l_d) from the leader at the end has lost it.
LOST_FACTOR = 3.0


def _default_paths() -> list[Any]:
    shapes = [{"type": "straight_line", "length": 10.0}, {"type": "figure_eight", "a": 4.0}]
    return TypeAdapter(list[PathSpec]).validate_python(shapes)


class TetherModesStudy(StudyBase):
    """Side, front and Brake modes of Allan 2015 Ch. 4 on leader paths."""

    kind: Literal["tether_modes"]
    robot: FollowerRobotSpec = robot_field()  # type: ignore[valid-type]
    speed: LEADER_SPEED.annotation() = LEADER_SPEED.default  # type: ignore[valid-type]
    paths: list[PathSpec] = Field(default_factory=_default_paths, min_length=1, max_length=10)  # type: ignore[valid-type]
    modes: list[Literal[MODES]] = Field(  # type: ignore[valid-type]
        default_factory=lambda: list(MODES), min_length=1, max_length=len(MODES)
    )
    side_offsets: list[_OFFSET.annotation()] = Field(  # type: ignore[valid-type]
        default_factory=lambda: [0.56, 0.42],
        min_length=1,
        max_length=6,
        description="l_H (m); the thesis's figures use 2.0 b and 1.5 b",
    )
    brake_laws: list[Literal[BRAKE_LAWS]] = Field(  # type: ignore[valid-type]
        default_factory=lambda: list(BRAKE_LAWS), min_length=1, max_length=len(BRAKE_LAWS)
    )
    brake_walk: float = Field(
        4.0, gt=0, le=100, description="leader's straight walk before it stops (m)"
    )
    brake_wait: float = Field(20.0, gt=0, le=600, description="time the leader stands still (s)")
    brake_length_noise: _LNOISE.annotation() = Field(0.01, description="Brake runs: sigma_l (m)")  # type: ignore[valid-type]
    brake_angle_noise: _ANOISE.annotation() = Field(
        0.05, description="Brake runs: sigma_theta (rad)"
    )  # type: ignore[valid-type]
    engage_margin: _ENGAGE.annotation() = _ENGAGE.default  # type: ignore[valid-type]
    release_margin: _RELEASE.annotation() = _RELEASE.default  # type: ignore[valid-type]

    TYPICAL_DURATION: ClassVar[float] = 8  # s, the committed study, serial, this machine
    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "modes.csv",
        "brake.csv",
        "modes_*.png",
        "brake.png",
        "study.yaml",
    )

    def size(self) -> str:
        """Runs."""
        n = sum(len(self.offsets(m)) for m in self.modes) * len(self.paths)
        return f"{n} mode runs, {2 * len(self.brake_laws)} brake runs"

    def offsets(self, mode: str) -> list[float]:
        """The side offsets l_H (m) a mode runs at (a front mode: NaN, its own l_d).

        Parameters
        ----------
        mode
            The mode's name.
        """
        side = LAWS.get(mode).placement == "side"
        return [float(lh) for lh in self.side_offsets] if side else [math.nan]

    def mode_jobs(self) -> list[tuple[Any, str, float, Any]]:
        """Every (path, mode, offset, controller)."""
        jobs = []
        for ps in self.paths:
            path = ps.build()
            for m in self.modes:
                law = LAWS.get(m)
                jobs += [
                    (path, m, lh, law.holding(lh) if math.isfinite(lh) else law())
                    for lh in self.offsets(m)
                ]
        return jobs

    def brake_robot(self, robot: FollowerRobot) -> FollowerRobot:
        """The robot of the Brake runs (the study's, with the Brake runs' sensor noise)."""
        return robot.replace(
            length_noise_std=self.brake_length_noise, angle_noise_std=self.brake_angle_noise
        )

    @model_validator(mode="after")
    def _runnable(self) -> TetherModesStudy:
        if not self.release_margin > self.engage_margin:
            raise ValueError(
                f"release_margin = {self.release_margin:g} m must exceed engage_margin = "
                f"{self.engage_margin:g} m"
            )
        if not self.brake_walk / self.speed > BRAKE_SETTLE:
            raise ValueError(
                f"brake_walk = {self.brake_walk:g} m must exceed {BRAKE_SETTLE:g} s x speed "
                f"({BRAKE_SETTLE * self.speed:g} m): the Brake runs' share braked while walking "
                f"leaves out the first {BRAKE_SETTLE:g} s"
            )
        robot = self.robot.build()
        self.brake_robot(robot)
        for i, lh in enumerate(self.side_offsets):
            if lh <= 0.5 * robot.body_length:
                raise ValueError(
                    f"side_offsets[{i}] = {lh:g} m is not allowed: a side offset must exceed "
                    f"half the robot length (robot.body_length / 2 = "
                    f"{0.5 * robot.body_length:g} m)"
                )
        names = [p.build().name for p in self.paths]
        if len(set(names)) != len(names):
            raise ValueError(f"path names must be unique (give `name:`), got {names}")
        return self


def turn_errors(path: Any, npd: Any, offset: float) -> tuple[float, float]:
    """Mean |side offset - l_H| (m) where the robot is inside and outside the leader's turns.

    The robot walks on the leader's right (the modes' defaults), so it is inside a
    right turn (curvature < -TURN_CURVATURE) and outside a left one. NaN without turns.

    Parameters
    ----------
    path
        The leader's :class:`~designlab.following.tether.LeaderPath`.
    npd
        The run's normal path deviation (its segment midpoints and profile).
    offset
        l_H in m.
    """
    pts = path.points
    d = np.diff(pts, axis=0)
    heading = np.arctan2(d[:, 1], d[:, 0])
    ds = np.hypot(d[:, 0], d[:, 1])
    kappa = np.angle(np.exp(1j * np.diff(heading))) / np.maximum(0.5 * (ds[1:] + ds[:-1]), 1e-12)
    if len(kappa) == 0 or len(npd.profile) == 0:
        return math.nan, math.nan
    mid = npd.midpoints
    node = np.argmin(((mid[:, None, :] - pts[None, 1:-1, :]) ** 2).sum(axis=2), axis=1)
    k = kappa[node]
    err = np.abs(np.asarray(npd.profile) - offset)
    inside, outside = err[k < -TURN_CURVATURE], err[k > TURN_CURVATURE]
    return (
        float(inside.mean()) if inside.size else math.nan,
        float(outside.mean()) if outside.size else math.nan,
    )


@dataclass(frozen=True)
class ModeCase:
    """One side or front run.

    Attributes
    ----------
    path, mode
        Names of the path and the mode.
    offset
        The side offset l_H in m (NaN for a front mode).
    run
        The run.
    """

    path: str
    mode: str
    offset: float
    run: FollowerRun

    def row(self) -> dict[str, Any]:
        r = self.run
        npd = normal_path_deviation(r.leader_xy, r.robot_xy)
        hold = self.offset if math.isfinite(self.offset) else r.controller.desired_length
        gap = np.hypot(*(r.robot_xy - r.leader_xy).T)
        robot_len = float(np.hypot(*np.diff(r.robot_xy, axis=0).T).sum())
        side = math.isfinite(self.offset)
        inside, outside = turn_errors(r.path, npd, self.offset) if side else (math.nan, math.nan)
        return {
            "path": self.path,
            "mode": self.mode,
            "side_offset_m": self.offset,
            "npd_mean_m": npd.mean,
            "npd_std_m": npd.std,
            "npd_max_m": npd.max,
            "offset_error_mean_m": npd.mean - self.offset if side else math.nan,
            "offset_error_inside_turns_m": inside,
            "offset_error_outside_turns_m": outside,
            "tether_min_m": float(np.nanmin(r.tether_length)),
            "tether_max_m": float(np.nanmax(r.tether_length)),
            "final_distance_m": float(gap[-1]),
            "lost": bool(gap[-1] > LOST_FACTOR * hold),
            "path_length_ratio": robot_len / r.path.length,
            "status": str(r.status),
        }


@dataclass(frozen=True)
class BrakeCase:
    """One law with or without Brake mode behind a leader who stops.

    Attributes
    ----------
    law
        The wrapped law's name.
    brake
        Brake mode on.
    run
        The run.
    stop_time
        When the leader stopped (s).
    engage, release
        The margins (m).
    """

    law: str
    brake: bool
    run: FollowerRun
    stop_time: float
    engage: float
    release: float

    def row(self) -> dict[str, Any]:
        r = self.run
        after = r.t >= self.stop_time + 1.0
        walking = r.t < self.stop_time
        ld = r.controller.desired_length
        braked = brake_timeline(r.tether_length, ld, self.engage, self.release)
        start = int(np.argmax(after))
        step = np.hypot(*np.diff(r.robot_xy[start:], axis=0).T)
        return {
            "law": self.law,
            "brake": self.brake,
            "turned_after_stop_rad": float(np.abs(np.diff(r.heading[after])).sum()),
            "travel_after_stop_m": float(step.sum()),
            "braked_while_walking_pct": 100.0 * float(braked[walking & (r.t > BRAKE_SETTLE)].mean())
            if self.brake
            else 0.0,
            "braked_after_stop_pct": 100.0 * float(braked[after].mean()) if self.brake else 0.0,
            "status": str(r.status),
        }


@dataclass(frozen=True)
class TetherModesResult(Result):
    """Results of a ``tether_modes`` study.

    Attributes
    ----------
    study
        The study.
    cases
        The side and front runs.
    brakes
        The Brake runs.
    """

    study: TetherModesStudy
    cases: tuple[ModeCase, ...]
    brakes: tuple[BrakeCase, ...]

    @property
    def status(self) -> str:  # type: ignore[override]
        runs = [c.run for c in self.cases] + [b.run for b in self.brakes]
        return next((str(r.status) for r in runs if r.status != OK), OK)

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        out = [f"{c.path} / {c.mode}: {w}" for c in self.cases for w in c.run.warnings]
        for c in self.cases:
            if c.row()["lost"]:
                where = f" l_H {c.offset:g} m" if math.isfinite(c.offset) else ""
                out.append(f"{c.path} / {c.mode}{where}: the robot lost the leader")
        return tuple(out)

    def to_frame(self) -> pd.DataFrame:
        """One row per side or front run."""
        return pd.DataFrame([c.row() for c in self.cases])

    def brake_frame(self) -> pd.DataFrame:
        """One row per Brake run."""
        return pd.DataFrame([b.row() for b in self.brakes])


def _brakes(study: TetherModesStudy, robot: FollowerRobot) -> list[BrakeCase]:
    noisy = study.brake_robot(robot)
    path = straight_line(study.brake_walk)
    stop = study.brake_walk / study.speed
    out = []
    for name in study.brake_laws:
        law = LAWS.get(name)()
        for on in (False, True):
            c = (
                BrakeMode(
                    law, engage_margin=study.engage_margin, release_margin=study.release_margin
                )
                if on
                else law
            )
            r = simulate(
                c, path, speed=study.speed, robot=noisy, settle_time=study.brake_wait, seed=7
            )
            out.append(BrakeCase(name, on, r, stop, study.engage_margin, study.release_margin))
    return out


def run(study: TetherModesStudy, context: RunContext) -> TetherModesResult:
    """Simulate every mode on every path, then the Brake runs.

    Parameters
    ----------
    study, context
        The study, and how to run it (its progress bar: a step a mode run, one for Brake).
    """
    robot = study.robot.build()
    jobs = study.mode_jobs()
    cases = []
    with context.bar(f"{study.kind}: simulate", total=len(jobs) + 1) as hook:
        for i, (path, mode, lh, ctrl) in enumerate(jobs):
            cases.append(
                ModeCase(path.name, mode, lh, simulate(ctrl, path, speed=study.speed, robot=robot))
            )
            hook(Progress(i + 1, len(jobs) + 1, label="run", note=f"{path.name} {mode}"))
        brakes = _brakes(study, robot)
        hook(Progress(len(jobs) + 1, len(jobs) + 1, label="run", note="brake"))
    return TetherModesResult(study, tuple(cases), tuple(brakes))


KIND = StudyKind(
    name="tether_modes",
    schema=TetherModesStudy,
    run=run,
    report="designlab.report.tether_modes",
    reproduction=NOISE_AROUND_ZERO,
)
