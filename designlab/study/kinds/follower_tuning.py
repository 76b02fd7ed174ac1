"""The ``follower_tuning`` study kind: tuned tether-follower gains against the thesis defaults.

For each law, :func:`designlab.following.tune` searches the gains over the
tuning paths and speeds (seeded differential evolution, damping-ratio floor,
tether range, the robot's wheel limits) and reports the improvement over the
App. C defaults on validation paths it was not tuned on. The scenarios of a
generation run through the study's executor (``designlab run --executor``).

Examples
--------
>>> from designlab.study import parse_study
>>> study = parse_study('''
... designlab: 1
... kind: follower_tuning
... name: demo
... laws: [FollowTheLeader]
... paths: [{type: slalom}]
... validation_paths: [{type: square_s}]
... ''')
>>> study.size()
'1 law x 1 path x 1 speed'
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import Annotated, ClassVar, Literal

import pandas as pd
from pydantic import Field, model_validator
from tqdm.auto import tqdm

from designlab.following import TuningResult, controller_from_dict, tune
from designlab.following.tether_tuning import DEFAULT_WEIGHTS
from designlab.results import OK, Result
from designlab.study.base import Integer, Model, NonNegative, Number, Positive, StudyBase
from designlab.study.kinds.follower_specs import FollowerRobotSpec, PathSpec
from designlab.study.registry import StudyKind
from designlab.study.runner import RunContext

__all__ = ["KIND", "FollowerTuningResult", "FollowerTuningStudy", "run"]

Law = Literal["PseudoJoystick", "FollowTheLeader", "FollowTheLeaderConstDistance"]


class CostWeights(Model):
    """Weights of the tuning cost (see :mod:`designlab.following.tether_tuning`)."""

    deviation: NonNegative = DEFAULT_WEIGHTS["deviation"]
    length: NonNegative = DEFAULT_WEIGHTS["length"]
    smoothness: NonNegative = DEFAULT_WEIGHTS["smoothness"]


class FollowerTuningStudy(StudyBase):
    """Tune the gains of tether-follower laws and measure the improvement on unseen paths."""

    kind: Literal["follower_tuning"]
    laws: list[Law] = Field(min_length=1)
    desired_length: Positive | None = Field(None, le=10.0, description="l_d for every law, m")
    robot: FollowerRobotSpec = Field(default_factory=lambda: FollowerRobotSpec(preset="OXYDOG"))
    paths: list[PathSpec] = Field(min_length=1)
    speeds: list[Annotated[Number, Field(gt=0, le=5.0, allow_inf_nan=False)]] = Field(
        [0.5], min_length=1
    )
    validation_paths: list[PathSpec] = Field(min_length=1)
    weights: CostWeights = Field(default_factory=CostWeights)
    damping_floor: NonNegative = Field(0.5, le=5.0)
    tether_range: tuple[Positive, Positive] = (0.2, 2.0)
    seed: Annotated[Integer, Field(ge=0)] = 0
    popsize: Annotated[Integer, Field(ge=2, le=100)] = 6
    maxiter: Annotated[Integer, Field(ge=1, le=1000)] = 12

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "gains.csv",
        "scenarios.csv",
        "tuning_*.png",
        "study.yaml",
    )

    def size(self) -> str:
        n_l, n_p, n_s = len(self.laws), len(self.paths), len(self.speeds)
        laws, paths = f"{n_l} law{'s' * (n_l > 1)}", f"{n_p} path{'s' * (n_p > 1)}"
        return f"{laws} x {paths} x {n_s} speed{'s' * (n_s > 1)}"

    @model_validator(mode="after")
    def _check(self) -> FollowerTuningStudy:
        if self.tether_range[1] <= self.tether_range[0]:
            raise ValueError("tether_range must be (min, max) with min < max, m")
        train = {p.build().name for p in self.paths}
        overlap = train & {p.build().name for p in self.validation_paths}
        if overlap:
            raise ValueError(
                f"validation paths must differ from the tuning paths: {sorted(overlap)}"
            )
        return self


@dataclass(frozen=True)
class FollowerTuningResult(Result):
    """Results of a ``follower_tuning`` study: one :class:`TuningResult` per law.

    Attributes
    ----------
    study
        The study.
    results
        One tuning result per law.
    """

    study: FollowerTuningStudy
    results: tuple[TuningResult, ...]

    @property
    def status(self) -> str:  # type: ignore[override]
        for r in self.results:
            if r.status != OK:
                return str(r.status)
        return OK

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        return tuple(
            f"{type(r.controller).__name__}: {w}" for r in self.results for w in r.warnings
        )

    def to_frame(self) -> pd.DataFrame:
        """One row per law and gain: default and tuned values, and the improvements."""
        rows = []
        for r in self.results:
            law = type(r.controller).__name__
            for k, v in r.controller.gains.items():
                rows.append(
                    {
                        "law": law,
                        "gain": k,
                        "default": r.default.gains[k],
                        "tuned": v,
                        "improvement_validation": r.improvement,
                        "npd_improvement_validation": r.npd_improvement,
                        "training_improvement": r.training_improvement,
                        "min_damping_ratio": min(r.damping_ratios.values()),
                        "status": r.status,
                    }
                )
        return pd.DataFrame(rows)


def run(study: FollowerTuningStudy, context: RunContext) -> FollowerTuningResult:
    """Tune each law (its scenarios through ``context.executor``).

    Parameters
    ----------
    study
        The follower tuning study.
    context
        How to run it (the executor evaluates the candidate gain sets).
    """
    robot = study.robot.build()
    paths = [p.build() for p in study.paths]
    val = [p.build() for p in study.validation_paths]
    out = []
    for law in tqdm(
        study.laws, desc=study.name, unit="law", file=sys.stderr, disable=not context.progress
    ):
        base = {"type": law}
        if study.desired_length is not None:
            base["desired_length"] = study.desired_length  # type: ignore[assignment]
        out.append(
            tune(
                controller_from_dict(base),
                paths=paths,
                speeds=study.speeds,
                robot=robot,
                weights=study.weights.model_dump(),
                damping_floor=study.damping_floor,
                tether_range=study.tether_range,
                validation_paths=val,
                seed=study.seed,
                popsize=study.popsize,
                maxiter=study.maxiter,
                executor=context.executor,
            )
        )
    return FollowerTuningResult(study, tuple(out))


KIND = StudyKind(
    name="follower_tuning",
    schema=FollowerTuningStudy,
    run=run,
    report="designlab.report.following",
)
