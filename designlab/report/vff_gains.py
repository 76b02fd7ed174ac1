"""Deprecated: the report of the ``navigation_gains`` kind, now
:mod:`designlab.report.navigation_gains` (kept for one release)."""

from designlab.report.navigation_gains import *  # noqa: F403
from designlab.report.navigation_gains import __all__  # noqa: F401
