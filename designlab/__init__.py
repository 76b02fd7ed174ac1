"""designlab: design and sizing of robots that work next to people.

Three model families, from Zeng 2011 (impact safety of foam-covered
manipulators; navigation among people), Allan 2015 and Wu et al. 2021
(robots that follow or accompany a person). The domain packages are imported
on first use (``dl.impact``, ``dl.navigation``, ``dl.following``; the co-design layer
``dl.codesign`` above them), so that a command touching
one domain does not pay for loading the others.

Examples
--------
>>> import designlab as dl
>>> r = dl.impact.simulate(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1,
...                        dl.impact.TEST_HEAD, impact_velocity=1.25)
>>> round(r.peak_head_acceleration_g, 2)
6.57
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from designlab._version import __version__

if TYPE_CHECKING:
    from designlab import codesign as codesign
    from designlab import errors as errors
    from designlab import following as following
    from designlab import impact as impact
    from designlab import navigation as navigation

#: Subpackages imported on first attribute access.
SUBPACKAGES: tuple[str, ...] = ("codesign", "errors", "following", "impact", "navigation")

__all__ = ["__version__", "codesign", "errors", "following", "impact", "navigation"]


def __getattr__(name: str) -> Any:
    if name in SUBPACKAGES:
        return importlib.import_module(f"designlab.{name}")
    raise AttributeError(f"module 'designlab' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *SUBPACKAGES})
