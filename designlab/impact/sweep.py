"""Deprecated alias of :mod:`designlab.impact.evaluators` (kept for one release).

The chunk evaluators of the impact domain moved to :mod:`designlab.impact.evaluators`
(``designlab.impact.sweep.impact_metrics_chunk`` was named in the README).

Examples
--------
>>> from designlab.impact import evaluators, sweep
>>> sweep.impact_metrics_chunk is evaluators.impact_metrics_chunk
True
"""

from __future__ import annotations

from designlab.impact.evaluators import (
    ENVELOPE_METRICS,
    IMPACT_METRICS,
    envelope_elasticities_chunk,
    foam_envelope_chunk,
    impact_elasticities_chunk,
    impact_metrics_chunk,
)

__all__ = [
    "ENVELOPE_METRICS",
    "IMPACT_METRICS",
    "envelope_elasticities_chunk",
    "foam_envelope_chunk",
    "impact_elasticities_chunk",
    "impact_metrics_chunk",
]
