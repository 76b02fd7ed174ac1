"""Deprecated alias (kept for one release): the impact status enums subclass
:class:`designlab.results.Status` directly.

``ImpactDomainStatus`` only repeated :class:`~designlab.results.Status` (whose
members already show as their values); import :class:`designlab.results.Status`.

Examples
--------
>>> from designlab.results import Status
>>> ImpactDomainStatus is Status
True
"""

from __future__ import annotations

from designlab.results import Status

__all__ = ["ImpactDomainStatus"]

#: Deprecated: :class:`designlab.results.Status`.
ImpactDomainStatus = Status
