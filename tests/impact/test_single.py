"""The scalar fast path: row 0 of impact_metrics, to the bit, and its errors (issue 40.2)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from designlab.errors import InvalidParameterError
from designlab.impact.metrics import impact_metrics
from designlab.impact.model import PARAM_NAMES
from designlab.impact.single import ImpactPoint, impact_metrics_one

BASE = [9.6, 250.0, 20e3, 24.25e3, 71.9, 4.4, 0.0, 4e3]


def _batch_row(q: list[float], v: float, **options: object) -> ImpactPoint:
    m = impact_metrics([q], v, columns=PARAM_NAMES, **options)  # type: ignore[arg-type]
    return ImpactPoint(*(float(getattr(m, f)[0]) for f in ImpactPoint._fields[:-1]),
                       str(m.design_status[0]))  # fmt: skip


def _same(a: ImpactPoint, b: ImpactPoint) -> bool:
    return all(
        (x == y) or (isinstance(x, float) and math.isnan(x) and math.isnan(y))
        for x, y in zip(a, b, strict=True)
    )


def test_one_design_equals_the_batch_row_to_the_bit() -> None:
    rng = np.random.default_rng(40)
    for _ in range(300):
        q = [
            rng.uniform(2, 40), rng.uniform(0, 500), 10 ** rng.uniform(3, 5),
            10 ** rng.uniform(3, 5.5), rng.uniform(0, 300), rng.uniform(2, 8),
            rng.uniform(0, 60), 0.0 if rng.random() < 0.2 else rng.uniform(1e3, 1e4),
        ]  # fmt: skip
        v = float(rng.choice([-0.3, 0.0, rng.uniform(0.1, 3.0)]))
        assert _same(impact_metrics_one(q, v), _batch_row(q, v)), (q, v)


def test_a_mapping_and_options_go_the_same_way() -> None:
    named = dict(zip(PARAM_NAMES, BASE, strict=True))
    one = impact_metrics_one(named, 1.25, stop_time=0.2, max_lobe_steps=500)
    assert _same(one, _batch_row(BASE, 1.25, stop_time=0.2, max_lobe_steps=500))
    assert one.status == "ok" and one.peak_head_acceleration_g == pytest.approx(6.568, abs=5e-4)


def test_a_design_the_batch_settles_goes_through_the_batch() -> None:
    """A lobe not closed within the search is tried again by the batch (at 40 digits)."""
    one = impact_metrics_one(BASE, 1.25, max_lobe_steps=3)
    assert _same(one, _batch_row(BASE, 1.25, max_lobe_steps=3))


@pytest.mark.parametrize(
    ("column", "value"),
    [(0, -1.0), (3, 0.0), (4, math.nan), (5, math.inf), (1, -0.5), (0, 3e13)],
)
def test_bad_values_raise_the_batch_error(column: int, value: float) -> None:
    q = list(BASE)
    q[column] = value
    with pytest.raises(InvalidParameterError) as fast:
        impact_metrics_one(q, 1.25)
    with pytest.raises(InvalidParameterError) as batch:
        impact_metrics([q], 1.25, columns=PARAM_NAMES)
    assert str(fast.value) == str(batch.value)


@pytest.mark.parametrize("options", [{"stop_time": 0.0}, {"max_lobe_steps": 0}])
def test_bad_options_raise(options: dict[str, float]) -> None:
    with pytest.raises(InvalidParameterError):
        impact_metrics_one(BASE, 1.25, **options)  # type: ignore[arg-type]


def test_wrong_length_and_velocity_raise() -> None:
    with pytest.raises(InvalidParameterError, match="shape"):
        impact_metrics_one(BASE[:7], 1.25)
    with pytest.raises(InvalidParameterError, match="impact_velocity"):
        impact_metrics_one(BASE, 50.0)
    with pytest.raises(InvalidParameterError):
        impact_metrics_one({"M_r": 9.6}, 1.25)
