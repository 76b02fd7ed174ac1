"""designlab: design and sizing of robots that work next to people.

Three model families, from Zeng 2011 (impact safety of foam-covered
manipulators; navigation among people), Allan 2015 and Wu et al. 2021
(robots that follow or accompany a person).

Examples
--------
>>> import designlab as dl
>>> r = dl.impact.simulate(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1,
...                        dl.impact.TEST_HEAD, impact_velocity=1.25)
>>> round(r.peak_head_acceleration_g, 2)
6.57
"""

from __future__ import annotations

from designlab import errors, following, impact, navigation
from designlab._version import __version__

__all__ = ["__version__", "errors", "following", "impact", "navigation"]

