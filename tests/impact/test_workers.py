"""Batches on every core: the threaded kernel gives the single-threaded bits (issue 40.3)."""

from __future__ import annotations

import numpy as np
import pytest

from designlab.errors import InvalidParameterError
from designlab.impact.metrics import impact_metrics, matrix_metrics
from designlab.impact.model import PARAM_NAMES
from designlab.workers import map_row_blocks, thread_count

FIELDS = ("peak_head_acceleration", "max_compression", "peak_force", "impact_duration",
          "time_of_peak_acceleration", "time_of_max_compression", "time_of_peak_force")  # fmt: skip


def _designs(n: int, seed: int = 4) -> np.ndarray:
    """Thesis-range designs with a few that stress the kernel (no head stiffness, stiff foam)."""
    rng = np.random.default_rng(seed)
    p = np.empty((n, 8))
    p[:, 0] = rng.uniform(2.0, 40.0, n)
    p[:, 1] = rng.uniform(0.0, 500.0, n)
    p[:, 2] = 10 ** rng.uniform(3.0, 5.0, n)
    p[:, 3] = 10 ** rng.uniform(3.0, 5.5, n)
    p[:, 4] = rng.uniform(0.0, 300.0, n)
    p[:, 5] = rng.uniform(2.0, 8.0, n)
    p[:, 6] = rng.uniform(0.0, 60.0, n)
    p[:, 7] = np.where(rng.random(n) < 0.1, 0.0, rng.uniform(1e3, 1e4, n))
    return p


@pytest.mark.parametrize("workers", [2, 3, 7])
def test_threads_give_the_single_threaded_bits(workers: int) -> None:
    p = _designs(9_001)  # not a multiple of the lanes nor of the threads
    v = np.random.default_rng(5).uniform(-0.2, 2.0, p.shape[0])
    one = impact_metrics(p, v, columns=PARAM_NAMES, workers=1)
    many = impact_metrics(p, v, columns=PARAM_NAMES, workers=workers)
    for name in FIELDS:
        assert np.array_equal(getattr(one, name), getattr(many, name), equal_nan=True), name
    assert np.array_equal(one.design_status, many.design_status)
    assert one.warnings == many.warnings


def test_threads_give_the_single_threaded_bits_full_joint() -> None:
    rng = np.random.default_rng(6)
    n = 5_000
    p = np.empty((n, 10))
    p[:, :8] = _designs(n, seed=7)[:, [0, 1, 2, 3, 4, 5, 6, 7]]
    p[:, 7] = rng.uniform(1e3, 1e4, n)
    p[:, 8] = rng.uniform(1.0, 50.0, n)  # C_cont
    p[:, 9] = 10 ** rng.uniform(4.0, 6.0, n)  # K_cont
    one = matrix_metrics(p, 1.25, workers=1)
    two = matrix_metrics(p, 1.25, workers=2)
    for name in FIELDS:
        assert np.array_equal(getattr(one, name), getattr(two, name), equal_nan=True), name


def test_blocks_keep_row_order_and_lanes() -> None:
    rows = np.arange(100_003, dtype=float)[:, None]
    starts: list[float] = []

    def fn(b: np.ndarray) -> tuple[np.ndarray]:
        starts.append(float(b[0, 0]))
        return (b[:, 0] * 2,)

    (out,) = map_row_blocks(fn, rows, workers=3, grain=1000, align=16)
    assert np.array_equal(out, rows[:, 0] * 2)
    assert len(starts) == 3 and all(s % 16 == 0 for s in starts)
    assert thread_count(None, 10**6) >= 1


@pytest.mark.parametrize("bad", [0, -1, 2.5, "two"])
def test_workers_is_checked(bad: object) -> None:
    with pytest.raises(InvalidParameterError, match="workers"):
        impact_metrics(_designs(4), 1.0, columns=PARAM_NAMES, workers=bad)  # type: ignore[arg-type]
