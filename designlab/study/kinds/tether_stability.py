"""The ``tether_stability`` study kind: the convergence map of Allan 2015 Figs. 2.9-2.10.

For every law, a static leader is placed at each ``(l_0, theta_0)`` of a grid
around a robot at rest and the time the robot takes to come to rest facing it is
recorded (:func:`designlab.following.tether.stability.convergence_map`; the
reconstruction of Sec. 2.4.5 and its criterion are in ``docs/tether_modes.md``).

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> r = run_study(parse_study('''
... designlab: 1
... kind: tether_stability
... name: demo
... controllers: [{type: PseudoJoystick}]
... lengths: {low: 0.5, high: 3.0, num: 3}
... angles: 5
... max_time: 10
... '''))
>>> str(r.status), len(r.to_frame())
('ok', 15)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Literal

import numpy as np
import pandas as pd
from pydantic import Field, model_validator

from designlab.following.tether import FollowTheLeader, PseudoJoystick
from designlab.following.tether.stability import (
    GRID_LENGTH,
    GRID_POINTS,
    HOLD,
    MAX_GRID,
    MAX_TIME,
    TOL_ANGLE,
    TOL_LENGTH,
    TOL_SPEED,
    ConvergenceMap,
    convergence_map,
)
from designlab.progress import Progress
from designlab.results import OK, Result
from designlab.study.base import Grid, StudyBase
from designlab.study.kinds.tether_specs import (
    ControllerSpec,
    FollowerRobotSpec,
    controllers_field,
    robot_field,
)
from designlab.study.registry import StudyKind
from designlab.study.reproduction import CONVERGENCE_MAP
from designlab.study.runner import RunContext

__all__ = ["KIND", "LengthGrid", "TetherStabilityResult", "TetherStabilityStudy", "run"]


class LengthGrid(Grid):
    """Evenly spaced initial tether lengths: ``num`` of them from ``low`` to ``high`` (m)."""

    low: GRID_LENGTH.annotation() = 0.25  # type: ignore[valid-type]
    high: GRID_LENGTH.annotation() = 10.0  # type: ignore[valid-type]
    num: GRID_POINTS.annotation() = 40  # type: ignore[valid-type]


class TetherStabilityStudy(StudyBase):
    """Convergence time over initial tether readings, static leader (Figs. 2.9-2.10)."""

    kind: Literal["tether_stability"]
    robot: FollowerRobotSpec = robot_field()  # type: ignore[valid-type]
    controllers: list[ControllerSpec] = controllers_field(  # type: ignore[valid-type]
        PseudoJoystick, FollowTheLeader, max_length=8
    )
    lengths: LengthGrid = Field(default_factory=LengthGrid)
    angles: GRID_POINTS.annotation() = Field(  # type: ignore[valid-type]
        73, description="angles from -pi to pi (both ends)"
    )
    max_time: MAX_TIME.annotation() = MAX_TIME.default  # type: ignore[valid-type]
    hold: HOLD.annotation() = HOLD.default  # type: ignore[valid-type]
    tol_angle: TOL_ANGLE.annotation() = TOL_ANGLE.default  # type: ignore[valid-type]
    tol_speed: TOL_SPEED.annotation() = TOL_SPEED.default  # type: ignore[valid-type]
    tol_length: TOL_LENGTH.annotation() = TOL_LENGTH.default  # type: ignore[valid-type]

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "convergence.csv",
        "convergence_*.png",
        "study.yaml",
    )
    TYPICAL_DURATION: ClassVar[float] = 53  # s, the committed study, serial, this machine

    def size(self) -> str:
        """Laws x grid points."""
        return f"{len(self.controllers)} law(s) x {self.lengths.num * self.angles} grid points"

    def angle_values(self) -> list[float]:
        """The angle grid in rad."""
        grid = (float(f"{x:.12g}") for x in np.linspace(-math.pi, math.pi, self.angles))
        return [min(max(x, -math.pi), math.pi) for x in grid]

    @model_validator(mode="after")
    def _runnable(self) -> TetherStabilityStudy:
        titles = [c.title for c in self.controllers]
        if len(set(titles)) != len(titles):
            raise ValueError(f"controller labels must be unique, got {titles}")
        if self.lengths.num * self.angles > MAX_GRID:
            raise ValueError(
                f"lengths.num x angles = {self.lengths.num * self.angles} grid points; "
                f"at most {MAX_GRID}"
            )
        if not self.hold < self.max_time:
            raise ValueError(f"hold = {self.hold:g} s must be < max_time = {self.max_time:g} s")
        return self


@dataclass(frozen=True)
class TetherStabilityResult(Result):
    """Results of a ``tether_stability`` study: one map per law.

    Attributes
    ----------
    study
        The study.
    titles
        The laws' labels.
    maps
        One :class:`ConvergenceMap` per law.
    """

    study: TetherStabilityStudy
    titles: tuple[str, ...]
    maps: tuple[ConvergenceMap, ...]

    @property
    def status(self) -> str:  # type: ignore[override]
        return next((str(m.status) for m in self.maps if m.status != OK), OK)

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        return tuple(
            f"{t}: {w}" for t, m in zip(self.titles, self.maps, strict=True) for w in m.warnings
        )

    def to_frame(self) -> pd.DataFrame:
        """One row per law and grid point."""
        frames = []
        for t, m in zip(self.titles, self.maps, strict=True):
            f = m.to_frame()
            f.insert(0, "controller", t)
            frames.append(f)
        return pd.concat(frames, ignore_index=True)


def run(study: TetherStabilityStudy, context: RunContext) -> TetherStabilityResult:
    """Compute every law's map (one batch run each).

    Parameters
    ----------
    study, context
        The study, and how to run it (its progress bar: one step a law).
    """
    robot = study.robot.build()
    maps = []
    with context.bar(f"{study.kind}: laws", total=len(study.controllers)) as hook:
        for i, cs in enumerate(study.controllers):
            maps.append(
                convergence_map(
                    cs.build(),
                    study.lengths.values(),
                    study.angle_values(),
                    robot=robot,
                    max_time=study.max_time,
                    hold=study.hold,
                    tol_angle=study.tol_angle,
                    tol_speed=study.tol_speed,
                    tol_length=study.tol_length,
                )
            )
            hook(Progress(i + 1, len(study.controllers), label="law", note=cs.title))
    return TetherStabilityResult(study, tuple(c.title for c in study.controllers), tuple(maps))


KIND = StudyKind(
    name="tether_stability",
    schema=TetherStabilityStudy,
    run=run,
    report="designlab.report.tether_stability",
    reproduction=CONVERGENCE_MAP,
)
