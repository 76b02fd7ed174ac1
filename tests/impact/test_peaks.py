"""First local maximum of a response (the thesis's "peak", Zeng 2011, Sec. 3.6)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.impact import FOAM_1, HEAD_MIN, MANIPULATOR_1
from designlab.impact.modal import ModalResponse
from designlab.impact.peaks import first_local_maximum, first_peak


def test_first_local_maximum_exact_cases() -> None:
    # y = 1 - cos(w t) (1/(s (s^2 + w^2)) * w^2): first maximum at pi/w, value 2;
    # y = 1 - exp(-t) rises monotonically: the end point; y = exp(-t) - 1 falls: t = 0
    w = 3.0
    osc = ModalResponse.from_polynomials(np.array([[w**2]]), np.array([[1.0, 0.0, w**2]]), 1)
    t, y = first_local_maximum(osc, 10.0)
    assert t[0] == pytest.approx(math.pi / w, rel=1e-10) and y[0] == pytest.approx(2.0, rel=1e-12)
    rise = ModalResponse.from_polynomials(np.array([[1.0]]), np.array([[1.0, 1.0]]), 1)
    t, y = first_local_maximum(rise, 2.0)
    assert t[0] == 2.0 and y[0] == pytest.approx(1 - math.exp(-2.0))
    fall = ModalResponse.from_polynomials(np.array([[-1.0]]), np.array([[1.0, 1.0]]), 1)
    t, y = first_local_maximum(fall, 2.0)
    assert t[0] == 0.0 and y[0] == pytest.approx(0.0, abs=1e-15)
    # batch: several windows at once
    both = ModalResponse(
        np.vstack([osc.poles, osc.poles]), np.vstack([osc.residues] * 2), np.vstack([osc.poly] * 2)
    )
    t, _ = first_local_maximum(both, np.array([10.0, 0.5]))
    assert t[0] == pytest.approx(math.pi / w) and t[1] == pytest.approx(0.5)


def test_first_peak_of_a_simulation_is_a_stationary_point() -> None:
    r = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25)
    t, f = first_peak(r)
    ev = r._lobe["evaluate"]
    assert abs(ev(np.array([t]), 1)["force"][0]) < 1e-6 * f  # df/dt = 0
    assert f >= ev(np.array([t - 1e-4, t + 1e-4]))["force"].max()
    _, a = first_peak(r, "head_acceleration")
    assert a == pytest.approx(r.peak_head_acceleration, rel=1e-9)


def test_first_peak_special_cases_and_bad_input() -> None:
    none = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, -1.0)
    assert first_peak(none) == (0.0, 0.0)
    r = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25)
    with pytest.raises(InvalidParameterError, match="output"):
        first_peak(r, "torque")
    with pytest.raises(InvalidParameterError, match="samples"):
        first_peak(r, samples=2)
    osc = ModalResponse.from_polynomials(np.array([[1.0]]), np.array([[1.0, 0.0, 1.0]]), 1)
    with pytest.raises(InvalidParameterError, match="samples"):
        first_local_maximum(osc, 1.0, samples=2)
