"""The ``foam_design`` study kind: the foam covering design report (Zeng 2011, Sec. 3.9).

For every robot of the study it computes the feasible foam region
(:func:`designlab.impact.foam_envelope`), the verdict and margin of every foam,
the largest safe speed and the thickness each foam needs, the optimal foam
(:func:`designlab.impact.optimal_foam`) and a sampled worst-case check.

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: foam_design
... name: demo
... robots: [MANIPULATOR_1]
... foams: [FOAM_1]
... damping: {low: 20, high: 100, num: 5}
... optimal: false
... worst_case_samples: 0
... ''')
>>> result = run_study(study)
>>> result.verdicts()[["robot", "foam", "feasible"]]
           robot    foam  feasible
0  Manipulator 1  Foam 1      True
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from designlab.impact import (
    FoamEnvelope,
    HeadRange,
    OptimalFoam,
    SafeVelocity,
    WorstCaseCheck,
    check_worst_case,
    foam_envelope,
    max_safe_velocity,
    min_foam_thickness,
    optimal_foam,
)
from designlab.impact.parameters import ContactDynamics, Foam
from designlab.study.schema import FoamDesignStudy

__all__ = ["FoamDesignResult", "FoamDesignStudy", "run_foam_design"]


@dataclass(frozen=True)
class RobotDesign:
    """Everything the study computed for one robot."""

    robot: ContactDynamics
    label: str
    envelope: FoamEnvelope
    safe: list[SafeVelocity]
    thickness: list[float]
    optimal: OptimalFoam | None
    check: WorstCaseCheck | None


@dataclass(frozen=True)
class FoamDesignResult:
    """Result of a ``foam_design`` study."""

    study: FoamDesignStudy
    foams: list[Foam]
    designs: list[RobotDesign]

    def envelope_frame(self) -> pd.DataFrame:
        """All boundaries, one row per (robot, damping)."""
        frames = []
        for d in self.designs:
            df = d.envelope.to_frame()
            df.insert(0, "robot", d.label)
            frames.append(df)
        return pd.concat(frames, ignore_index=True)

    def verdicts(self) -> pd.DataFrame:
        """One row per (robot, foam): feasibility, margin, safe speeds, thickness."""
        rows = []
        for d in self.designs:
            for foam, sv, th in zip(self.foams, d.safe, d.thickness, strict=True):
                margin = float(d.envelope.margin(foam.stiffness, foam.damping))
                rows.append(
                    {
                        "robot": d.label,
                        "foam": foam.name,
                        "K_c_N_per_m": foam.stiffness,
                        "C_c_N_s_per_m": foam.damping,
                        "feasible": bool(d.envelope.is_feasible(foam.stiffness, foam.damping)),
                        "margin_decades": margin,
                        "margin_percent": 100 * (10**margin - 1)
                        if math.isfinite(margin)
                        else margin,
                        "v_c_max_m_per_s": sv.impact_velocity,
                        "v_r_max_m_per_s": sv.manipulator_speed,
                        "limiting": sv.limiting,
                        "lambda_needed_m": th,
                    }
                )
        return pd.DataFrame(rows)

    def to_frame(self) -> pd.DataFrame:
        """The foam verdicts (:meth:`verdicts`)."""
        return self.verdicts()


def run_foam_design(study: FoamDesignStudy) -> FoamDesignResult:
    """Compute the ``foam_design`` study."""
    criteria = [c.build() for c in study.criteria]
    foams = []
    for i, spec in enumerate(study.foams):
        f = spec.build()
        foams.append(f if f.name else f.replace(name=f"foam {i + 1}"))
    head_range = study.head_range.build() if study.head_range else None
    damping = np.asarray(study.damping.values())
    designs = []
    for i, spec in enumerate(study.robots):
        robot = spec.build()
        label = robot.name or f"robot {i + 1}"
        env = foam_envelope(
            robot,
            study.impact_velocity,
            damping,
            criteria,
            study.max_compression,
            head_range=head_range,
        )
        safe = [
            max_safe_velocity(
                robot,
                f,
                criteria,
                max_compression=study.max_compression,
                human_speed=study.human_speed,
                head_range=head_range,
            )
            for f in foams
        ]
        thick = [
            min_foam_thickness(robot, f, study.impact_velocity, head_range=head_range).linear_depth
            for f in foams
        ]
        opt = (
            optimal_foam(
                robot,
                study.impact_velocity,
                criteria,
                study.max_compression,
                damping_bounds=(float(damping.min()), float(damping.max())),
                head_range=head_range,
            )
            if study.optimal
            else None
        )
        check = (
            check_worst_case(env, head_range or HeadRange(), samples=study.worst_case_samples)
            if study.worst_case_samples
            else None
        )
        designs.append(RobotDesign(robot, label, env, safe, thick, opt, check))
    return FoamDesignResult(study, foams, designs)
