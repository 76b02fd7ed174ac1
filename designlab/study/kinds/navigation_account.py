"""The ``navigation_account`` study kind: every thesis row against the model, with causes.

Runs :func:`designlab.navigation.account.thesis_account` (Zeng 2011, Tables 5.1, 6.2-6.5,
7.1-7.4): for each row and quantity the thesis's value, ours, the difference and its cause,
each cause demonstrated by a run that removes it (``docs/navigation.md``, "How close to the
thesis").

Examples
--------
>>> from designlab.study import parse_study, run_study
>>> study = parse_study('''
... designlab: 1
... kind: navigation_account
... name: demo
... tables: ["6.4"]
... methods: ["New VFF*"]
... ''')
>>> r = run_study(study)
>>> r.to_frame().loc[0, ["quantity", "cause"]].tolist()
['T_arrive_s', 'tolerance or start']
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Annotated, ClassVar, Literal

import pandas as pd
from pydantic import Field

from designlab.navigation.account import (
    DISTANCE_BAND,
    TIME_BAND,
    AccountResult,
    noise_ordering,
    thesis_account,
)
from designlab.results import OK, Result
from designlab.study.base import Integer, StudyBase
from designlab.study.registry import StudyKind
from designlab.study.reproduction import SAME_ON_A_GENERIC_CPU
from designlab.study.runner import RunContext

__all__ = ["KIND", "NavigationAccountResult", "NavigationAccountStudy", "run"]

_Table = Literal["5.1", "6.2", "6.3", "6.4", "6.5", "7.1", "7.2", "7.3", "7.4"]
_Method = Literal["New VFF", "New VFF*", "Masoud*", "Ge & Cui*", "Masoud", "Ge & Cui"]


class NavigationAccountStudy(StudyBase):
    """Compare the thesis's simulated and experimental rows with the model."""

    kind: Literal["navigation_account"]
    tables: list[_Table] | None = Field(None, min_length=1, description="default: all")
    methods: list[_Method] | None = Field(None, min_length=1, description="default: all")
    time_band: TIME_BAND.annotation() = 0.07  # type: ignore[valid-type]
    distance_band: DISTANCE_BAND.annotation() = 0.03  # type: ignore[valid-type]
    noise_seeds: Annotated[Integer, Field(ge=0, le=1000)] = Field(
        0,
        description="seeded sensor-noise draws per configuration and gain set for the "
        "Config 2/4 ordering of the two gain sets (0: not run)",
    )

    TYPICAL_DURATION: ClassVar[float] = 9  # s, the committed study, serial, this machine
    PRODUCES: ClassVar[tuple[str, ...]] = ("summary.md", "account.csv", "noise.csv", "study.yaml")

    def size(self) -> str:
        """What the study runs."""
        return "one run per thesis row, plus one per candidate cause tried"


@dataclass(frozen=True)
class NavigationAccountResult(Result):
    """The account of a ``navigation_account`` study.

    Attributes
    ----------
    study
        The study.
    account
        The :class:`~designlab.navigation.account.AccountResult`.
    noise
        The gain sets' H in Configurations 2 and 4 without and with sensor noise
        (:func:`~designlab.navigation.account.noise_ordering`; empty if not run).
    status, warnings
        ``"ok"``; how many simulated quantities have no cause found.
    """

    study: NavigationAccountStudy
    account: AccountResult
    noise: pd.DataFrame = field(default_factory=pd.DataFrame, repr=False)
    status: str = OK
    warnings: tuple[str, ...] = ()

    def to_frame(self) -> pd.DataFrame:
        """One row per (thesis row, quantity)."""
        return self.account.to_frame()


def run(study: NavigationAccountStudy, context: RunContext) -> NavigationAccountResult:
    """Run the account with a progress bar.

    Parameters
    ----------
    study
        The validated study.
    context
        How to run it.
    """
    with context.bar(f"{study.kind}: thesis rows", None) as hook:
        acc = thesis_account(
            tables=study.tables,
            methods=study.methods,
            time_band=study.time_band,
            distance_band=study.distance_band,
            progress=hook,
        )
    noise = pd.DataFrame()
    if study.noise_seeds:
        with context.bar(f"{study.kind}: sensor noise", None) as hook:
            noise = noise_ordering(seeds=study.noise_seeds, progress=hook)
    missing = int((acc.frame["cause"] == "not found").sum()) if len(acc.frame) else 0
    warnings = (
        (f"{missing} simulated quantities lie outside the band with no cause found",)
        if missing
        else ()
    )
    return NavigationAccountResult(study, acc, noise, warnings=warnings)


KIND = StudyKind(
    name="navigation_account",
    schema=NavigationAccountStudy,
    run=run,
    report="designlab.report.navigation_account",
    reproduction=SAME_ON_A_GENERIC_CPU,
)
