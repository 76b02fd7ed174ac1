"""The base of the impact domain's status enums (one per result family).

Each result family of :mod:`designlab.impact` documents its statuses in a
:class:`designlab.results.Status` enum defined beside it
(:class:`~designlab.impact.metrics.ImpactStatus`,
:class:`~designlab.impact.envelope.EnvelopeStatus`, ...). A member is a ``str``
equal to its value, and it also *shows* as its value, so that printed results
(``opt.status, opt.margin``) read as before the enums.

Examples
--------
>>> class DemoStatus(ImpactDomainStatus):
...     OK = "ok"
>>> DemoStatus.OK, DemoStatus.OK == "ok"
('ok', True)
"""

from __future__ import annotations

from designlab.results import Status

__all__ = ["ImpactDomainStatus"]


class ImpactDomainStatus(Status):
    """A :class:`~designlab.results.Status` whose ``repr`` is its value's (``'ok'``)."""

    def __repr__(self) -> str:
        return repr(self.value)
