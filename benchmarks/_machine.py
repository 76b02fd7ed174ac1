"""The machine line every benchmark prints beside its figures (speed figures are ratios on it).

Imported by the benchmark scripts as ``from _machine import machine`` (a script's own
folder is first on ``sys.path``).
"""

from __future__ import annotations

import os


def machine() -> str:
    """CPU model, logical CPUs and load average."""
    model = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as fh:
            model = next(ln.split(":", 1)[1].strip() for ln in fh if ln.startswith("model name"))
    except (OSError, StopIteration):  # pragma: no cover - not Linux
        pass
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return f"{model}, {os.cpu_count()} logical CPUs, load average {load:.1f}"
