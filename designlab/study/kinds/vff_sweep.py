"""Deprecated: the kind ``vff_sweep``, now ``navigation_sweep``.

Kept for one release so that imports of the old module keep working; study files with
``kind: vff_sweep`` are read as the new kind (``RENAMED_KINDS``).
"""

from designlab.study.kinds.navigation_sweep import *  # noqa: F403
from designlab.study.kinds.navigation_sweep import (  # noqa: F401
    NAVIGATION_PARAMETERS as VFF_PARAMETERS,
)
from designlab.study.kinds.navigation_sweep import (  # noqa: F401
    NavigationDesign as VffDesign,
)
from designlab.study.kinds.navigation_sweep import (  # noqa: F401
    NavigationSweepStudy as VffSweepStudy,
)
from designlab.study.kinds.navigation_sweep import __all__  # noqa: F401
