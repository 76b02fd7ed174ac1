"""Deprecated: the navigation specs, now :mod:`designlab.study.kinds.navigation_specs`."""

from designlab.study.kinds.navigation_specs import *  # noqa: F403
from designlab.study.kinds.navigation_specs import __all__  # noqa: F401
