"""Deprecated: the sweep evaluator, now :mod:`designlab.navigation.evaluators` (one release)."""

from designlab.navigation.evaluators import VFF_METRICS, VFF_POINT_KEYS, vff_metrics_chunk

__all__ = ["VFF_METRICS", "VFF_POINT_KEYS", "vff_metrics_chunk"]
