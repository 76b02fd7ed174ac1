"""Deprecated alias of :mod:`designlab.sx.lanes` (kept for one release).

The four-lane compiler now lives in :mod:`designlab.sx`, the one symbolic back end
(with its disk cache and CasADi's evaluation where no C compiler exists); import it
from there.

Examples
--------
>>> LANES
4
"""

from designlab.sx.lanes import LANES, CompiledLanes, LaneCall, compile_lanes
from designlab.sx.program import UnsupportedOperation

__all__ = ["LANES", "CompiledLanes", "LaneCall", "UnsupportedOperation", "compile_lanes"]
