"""Crowd encounters of each candidate design: its own gains and speed limit in the crowds.

A design's navigation (its VFF gains and speed limit V_mr) decides how fast it meets the
pedestrians of a crowd; the foam does not. :class:`CrowdEncounters` drives a design
through a small set of crowd scenarios (:func:`designlab.navigation.crowd`) with the
design's gains and speed limit, and keeps the encounters
(:func:`~designlab.codesign.contact_speeds`) per ``(V_mr, K1, b, K3, K5)``: designs
that differ only in their foam (in a Sobol sample, a third of them) reuse the runs.
:func:`~designlab.codesign.evaluate_design` uses it for the objective
``crowd_injury_probability``: P(criterion exceeded | contact) over the design's own
crowd encounters.

Cost: one crowd run per crowd scenario and new ``(V_mr, gains)``; a 12 m corridor with a
handful of pedestrians takes seconds per run (JuPedSim plus the robot), so a search with
crowds costs about (crowd runs x their time) per design on top of the scenarios. Keep the
crowd set small.

Examples
--------
>>> import designlab.navigation as nav
>>> enc = CrowdEncounters([nav.crowd("corridor_counterflow", 4, length=10.0, horizon=4.0)])
>>> a = enc.of(0.7, nav.EXPERIMENT_GAINS)
>>> b = enc.of(0.7, nav.EXPERIMENT_GAINS)
>>> a is b, enc.runs, enc.hits
(True, 1, 1)
"""

from __future__ import annotations

import dataclasses
from collections import OrderedDict
from collections.abc import Sequence
from typing import Any

from designlab.codesign.contacts import MEASURES, ContactSpeeds, contact_speeds
from designlab.errors import InvalidParameterError
from designlab.navigation import CrowdScenario, VFFGains, simulate

__all__ = ["CrowdEncounters"]

#: Designs' encounters kept (least recently used dropped first).
MAX_ENTRIES = 4096


class CrowdEncounters:
    """The crowd encounters of designs, run once per ``(speed limit, gains)``.

    Parameters
    ----------
    crowds
        One or more :class:`~designlab.navigation.CrowdScenario` (their robot's speed limit
        is replaced by each design's).
    measure
        Which closing speed of the encounters counts (:func:`contact_speeds`).

    Attributes
    ----------
    runs, hits
        Crowd-set runs made, and requests answered from the cache.
    """

    def __init__(self, crowds: CrowdScenario | Sequence[CrowdScenario], measure: str = "relative"):
        items = (crowds,) if isinstance(crowds, CrowdScenario) else tuple(crowds)
        if not items or not all(isinstance(c, CrowdScenario) for c in items):
            raise InvalidParameterError(
                "crowds", crowds, "must be one or more CrowdScenario objects"
            )
        if measure not in MEASURES:
            raise InvalidParameterError("measure", measure, f"must be one of {MEASURES}")
        self.crowds = items
        self.measure = measure
        self.runs = 0
        self.hits = 0
        self._cache: OrderedDict[tuple[float, ...], ContactSpeeds] = OrderedDict()

    def of(self, speed: float, gains: VFFGains) -> ContactSpeeds:
        """The encounters of a robot with speed limit ``speed`` (m/s) and ``gains``.

        Parameters
        ----------
        speed
            The design's speed limit V_mr, m/s.
        gains
            The design's VFF gains.

        Returns
        -------
        ContactSpeeds
        """
        key = (float(speed), *(float(g) for g in gains.as_array()))
        hit = self._cache.get(key)
        if hit is not None:
            self.hits += 1
            self._cache.move_to_end(key)
            return hit
        runs: list[Any] = [
            simulate(dataclasses.replace(c, robot=dataclasses.replace(c.robot, max_speed=speed)),
                     gains)
            for c in self.crowds
        ]  # fmt: skip
        self.runs += 1
        out = contact_speeds(runs, measure=self.measure)
        self._cache[key] = out
        if len(self._cache) > MAX_ENTRIES:
            self._cache.popitem(last=False)
        return out
