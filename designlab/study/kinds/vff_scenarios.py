"""Deprecated: the kind ``vff_scenarios``, now ``navigation_scenarios``.

Kept for one release so that imports of the old module keep working; study files with
``kind: vff_scenarios`` are read as the new kind (``RENAMED_KINDS``).
"""

from designlab.study.kinds.navigation_scenarios import *  # noqa: F403
from designlab.study.kinds.navigation_scenarios import (  # noqa: F401
    VffReference,
    VffRun,
    VffScenariosResult,
    VffScenariosStudy,
    __all__,
)
