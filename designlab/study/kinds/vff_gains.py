"""Deprecated: the kind ``vff_gains``, now ``navigation_gains``.

Kept for one release so that imports of the old module keep working; study files with
``kind: vff_gains`` are read as the new kind (``RENAMED_KINDS``).
"""

from designlab.study.kinds.navigation_gains import *  # noqa: F403
from designlab.study.kinds.navigation_gains import (  # noqa: F401
    VffGainsResult,
    VffGainsStudy,
    __all__,
)
