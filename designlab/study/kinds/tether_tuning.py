"""The ``tether_tuning`` study kind: tuned tether-follower gains against the thesis defaults.

For each law, :func:`designlab.following.tether.tune` searches the gains over the
tuning paths and speeds (seeded differential evolution, damping-ratio floor,
tether range, the robot's wheel limits) and reports the improvement over the
App. C defaults on validation paths it was not tuned on. The scenarios of a
generation run through the study's executor (``designlab run --executor``); a
progress bar shows the generation and the best cost.

Examples
--------
>>> from designlab.study import parse_study
>>> study = parse_study('''
... designlab: 1
... kind: tether_tuning
... name: demo
... laws: [FollowTheLeader]
... paths: [{type: slalom}]
... validation_paths: [{type: square_s}]
... ''')
>>> study.size()
'1 law x 1 path x 1 speed'
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import pandas as pd
from pydantic import Field, model_validator

from designlab.following.tether import (
    LAWS,
    CostWeights,
    PseudoJoystick,
    TuningResult,
    controller_from_dict,
    tune,
)
from designlab.following.tether.parameters import (
    DAMPING_FLOOR,
    LEADER_SPEED,
    MAXITER,
    POPSIZE,
    SEED,
    TETHER_LIMIT,
)
from designlab.following.tether.tuning import TUNERS
from designlab.params import params_of
from designlab.results import OK, Result
from designlab.study.base import StudyBase
from designlab.study.kinds.tether_specs import FollowerRobotSpec, PathSpec, robot_field
from designlab.study.registry import StudyKind
from designlab.study.runner import RunContext
from designlab.study.specs import spec_model

__all__ = ["KIND", "TetherTuningResult", "TetherTuningStudy", "run"]

#: A law the tuner takes: one with a linear lateral loop (its damping floor).
Law = LAWS.literal(linear=True)
#: A tuner name (:data:`designlab.following.tether.tuning.TUNERS`).
Tuner = Literal[tuple(TUNERS)]  # type: ignore[valid-type]

#: Weights of the tuning cost (:class:`designlab.following.tether.CostWeights`).
CostWeightsSpec = spec_model(CostWeights, name="CostWeightsSpec")

_DESIRED_LENGTH = params_of(PseudoJoystick)["desired_length"]


class TetherTuningStudy(StudyBase):
    """Tune the gains of tether-follower laws and measure the improvement on unseen paths."""

    kind: Literal["tether_tuning"]
    laws: list[Law] = Field(min_length=1, max_length=len(LAWS.choices(linear=True)))  # type: ignore[valid-type]
    desired_length: _DESIRED_LENGTH.annotation(optional=True) = Field(  # type: ignore[valid-type]
        None, description="l_d for every law, m (default: each law's own)"
    )
    robot: FollowerRobotSpec = robot_field("OXYDOG")  # type: ignore[valid-type]
    paths: list[PathSpec] = Field(min_length=1, max_length=100)  # type: ignore[valid-type]
    speeds: list[LEADER_SPEED.annotation()] = Field([0.5], min_length=1, max_length=100)  # type: ignore[valid-type]
    validation_paths: list[PathSpec] = Field(min_length=1, max_length=100)  # type: ignore[valid-type]
    weights: CostWeightsSpec = Field(default_factory=CostWeightsSpec)  # type: ignore[valid-type]
    damping_floor: DAMPING_FLOOR.annotation() = DAMPING_FLOOR.default  # type: ignore[valid-type]
    tether_range: tuple[TETHER_LIMIT.annotation(), TETHER_LIMIT.annotation()] = (0.2, 2.0)  # type: ignore[valid-type]
    method: Tuner = Field(  # type: ignore[valid-type]
        "differential_evolution", description="the search (designlab.following.tether.TUNERS)"
    )
    seed: SEED.annotation(optional=False) = SEED.default  # type: ignore[valid-type]
    popsize: POPSIZE.annotation() = POPSIZE.default  # type: ignore[valid-type]
    maxiter: MAXITER.annotation() = MAXITER.default  # type: ignore[valid-type]

    PRODUCES: ClassVar[tuple[str, ...]] = (
        "summary.md",
        "gains.csv",
        "scenarios.csv",
        "improvement.csv",
        "tuning_*.png",
        "study.yaml",
    )
    #: s: CPU time of studies/tether_tuning.yaml run serially (fresh store), measured.
    TYPICAL_DURATION: ClassVar[float] = 194

    def size(self) -> str:
        """Laws, paths and speeds."""
        n_l, n_p, n_s = len(self.laws), len(self.paths), len(self.speeds)
        laws, paths = f"{n_l} law{'s' * (n_l > 1)}", f"{n_p} path{'s' * (n_p > 1)}"
        return f"{laws} x {paths} x {n_s} speed{'s' * (n_s > 1)}"

    def base(self, law: str) -> Any:
        """The law with the study's desired length (the tuner starts from its gains).

        Parameters
        ----------
        law
            The law's class name.
        """
        fields: dict[str, Any] = {"type": law}
        if self.desired_length is not None:
            fields["desired_length"] = self.desired_length
        return controller_from_dict(fields)

    @model_validator(mode="after")
    def _check(self) -> TetherTuningStudy:
        if self.tether_range[1] <= self.tether_range[0]:
            raise ValueError("tether_range must be (min, max) with min < max, m")
        train = {p.build().name for p in self.paths}
        overlap = train & {p.build().name for p in self.validation_paths}
        if overlap:
            raise ValueError(
                f"validation paths must differ from the tuning paths: {sorted(overlap)}"
            )
        robot = self.robot.build()
        for law in self.laws:
            ld = self.base(law).desired_length
            if ld <= 0.5 * robot.body_length:
                raise ValueError(
                    f"{law}: desired_length = {ld:g} m must exceed half the robot length "
                    f"({0.5 * robot.body_length:g} m)"
                )
        return self


@dataclass(frozen=True)
class TetherTuningResult(Result):
    """Results of a ``tether_tuning`` study: one :class:`TuningResult` per law.

    Attributes
    ----------
    study
        The study.
    results
        One tuning result per law.

    Examples
    --------
    One generation of two candidates is ``not_converged``, and says so:

    >>> from designlab.study import parse_study, run_study
    >>> r = run_study(parse_study('''
    ... designlab: 1
    ... kind: tether_tuning
    ... name: demo
    ... laws: [FollowTheLeader]
    ... paths: [{type: figure_eight, a: 2.0}]
    ... speeds: [0.5]
    ... validation_paths: [{type: slalom}]
    ... popsize: 2
    ... maxiter: 1
    ... '''))
    >>> type(r).__name__, r.status, len(r.results)
    ('TetherTuningResult', 'not_converged', 1)
    """

    study: TetherTuningStudy
    results: tuple[TuningResult, ...]

    @property
    def status(self) -> str:  # type: ignore[override]
        for r in self.results:
            if r.status != OK:
                return str(r.status)
        return OK

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        return tuple(f"{r.controller.name}: {w}" for r in self.results for w in r.warnings)

    def to_frame(self) -> pd.DataFrame:
        """One row per law and gain: default and tuned values, and the improvements."""
        rows = []
        for r in self.results:
            law = r.controller.name
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
                        "status": str(r.status),
                    }
                )
        return pd.DataFrame(rows)


def run(study: TetherTuningStudy, context: RunContext) -> TetherTuningResult:
    """Tune each law (its scenarios through ``context.executor``), with a progress bar.

    Parameters
    ----------
    study
        The tether tuning study.
    context
        How to run it (the executor evaluates the candidate gain sets).
    """
    robot = study.robot.build()
    paths = [p.build() for p in study.paths]
    val = [p.build() for p in study.validation_paths]
    out = []
    tuner = TUNERS[study.method]
    for law in study.laws:
        total = tuner.steps(study.maxiter, study.popsize, len(study.base(law).gains))
        with context.bar(f"{study.kind}: {law}", total=total) as hook:
            out.append(
                tune(
                    study.base(law),
                    paths=paths,
                    speeds=study.speeds,
                    robot=robot,
                    weights=study.weights.model_dump(),
                    damping_floor=study.damping_floor,
                    tether_range=study.tether_range,
                    validation_paths=val,
                    method=study.method,
                    seed=study.seed,
                    popsize=study.popsize,
                    maxiter=study.maxiter,
                    executor=context.executor,
                    progress=hook,
                )
            )
    return TetherTuningResult(study, tuple(out))


KIND = StudyKind(
    name="tether_tuning",
    schema=TetherTuningStudy,
    run=run,
    report="designlab.report.tether",
)
