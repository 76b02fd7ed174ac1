"""simulate(): Sec. 3.6 and 3.8 statements, HIC, validity flags, batch agreement, errors."""

from __future__ import annotations

import numpy as np
import pytest

import designlab as dl
from designlab.errors import DesignlabError, InvalidParameterError
from designlab.impact import (
    FOAM_1,
    FOAM_3,
    HEAD_MIN,
    MANIPULATOR_1,
    MANIPULATOR_2,
    TABLE_3_2_HEADS,
    TEST_HEAD,
    VelocityProfile,
)


def _sims(q2: str) -> dict[int, dl.impact.ImpactResponse]:
    return {
        k: dl.impact.simulate(robot, FOAM_1, head, 1.25, q2=q2)
        for k, (robot, head) in TABLE_3_2_HEADS.items()
    }


def _pct(a: float, b: float) -> float:
    return 100.0 * (a / b - 1.0)


def test_section_3_6_percentages_with_printed_q2() -> None:
    """Sec. 3.6 statements reproduced within 3 percentage points (DECISIONS I1)."""
    s = _sims("printed")
    a = {k: r.peak_head_acceleration for k, r in s.items()}
    f = {k: r.peak_force for k, r in s.items()}
    assert _pct(f[2], f[1]) == pytest.approx(15, abs=3)
    assert _pct(f[1], f[3]) == pytest.approx(7, abs=3)
    assert _pct(f[4], f[2]) == pytest.approx(10, abs=3)
    assert _pct(a[2], a[1]) == pytest.approx(10, abs=3)
    assert _pct(a[1], a[3]) == pytest.approx(-13, abs=3)
    assert _pct(a[4], a[2]) == pytest.approx(-8, abs=3)


def test_section_3_6_correct_q2_same_directions() -> None:
    s = _sims("correct")
    a = {k: r.peak_head_acceleration for k, r in s.items()}
    f = {k: r.peak_force for k, r in s.items()}
    assert f[2] > f[1] > f[3] and f[4] > f[2]
    assert a[2] > a[1] and a[1] < a[3] and a[4] < a[2]
    # the printed q2 only changes results when both C_r and C_h are non-zero
    r = dl.impact.simulate(MANIPULATOR_1, FOAM_1, TEST_HEAD, 1.25, q2="printed")
    assert r.peak_head_acceleration == pytest.approx(
        dl.impact.simulate(MANIPULATOR_1, FOAM_1, TEST_HEAD, 1.25).peak_head_acceleration
    )


@pytest.mark.parametrize(
    "acc,d_force,d_acc",
    [(+0.51 * 9.80665, 5.0, 4.0), (-0.51 * 9.80665, -4.0, -3.0)],
)
def test_section_3_8_acceleration_profiles(acc: float, d_force: float, d_acc: float) -> None:
    """Fig. 3.17, reading (a) of impact.md Sec. 7 item 12: v_h = -1 m/s, with feed-forward."""
    head = TABLE_3_2_HEADS[3][1]
    base = dl.impact.simulate(MANIPULATOR_1, FOAM_1, head, 1.25)
    prof = dl.impact.simulate(
        MANIPULATOR_1, FOAM_1, head, 1.25, profile=VelocityProfile(acc, 0.05, feedforward=True)
    )
    assert _pct(prof.peak_force, base.peak_force) == pytest.approx(d_force, abs=1.0)
    assert _pct(prof.peak_head_acceleration, base.peak_head_acceleration) == pytest.approx(
        d_acc, abs=1.0
    )


def test_zero_acceleration_profile_equals_constant_velocity() -> None:
    base = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25)
    prof = dl.impact.simulate(
        MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25, profile=VelocityProfile(0.0, 0.05, False)
    )
    assert prof.peak_head_acceleration == pytest.approx(base.peak_head_acceleration, rel=1e-9)
    assert prof.impact_duration == pytest.approx(base.impact_duration, rel=1e-9)


def test_hic_standard_definition() -> None:
    # half-sine pulse of 50 g over 10 ms; oracle: exact integral, brute force over windows
    T, A = 0.01, 50.0
    t = np.linspace(0, T, 2001)
    a = A * 9.80665 * np.sin(np.pi * t / T)
    grid = np.linspace(0, T, 401)
    t1, t2 = np.meshgrid(grid, grid, indexing="ij")
    dur = t2 - t1
    integ = A * T / np.pi * (np.cos(np.pi * t1 / T) - np.cos(np.pi * t2 / T))
    with np.errstate(invalid="ignore", divide="ignore"):
        val = np.where(dur > 0, dur * (integ / np.where(dur > 0, dur, 1)) ** 2.5, 0)
    for window in (0.015, 0.003):
        oracle = val[(dur <= window + 1e-15)].max()
        assert dl.impact.hic(t, a, window) == pytest.approx(oracle, rel=2e-3)
    # whole pulse (mean 2A/pi) is not the maximising window
    assert dl.impact.hic(t, a, 0.015) > T * (2 * A / np.pi) ** 2.5
    r = dl.impact.simulate(MANIPULATOR_1, FOAM_1, TEST_HEAD, 1.25)
    assert 0 < r.hic(0.015) <= r.hic(0.036)
    # bound: HIC <= window^1 * (a_max in g)^2.5
    assert r.hic(0.015) <= 0.015 * r.peak_head_acceleration_g**2.5


def test_bottoming_flag_and_warning() -> None:
    soft = dl.impact.Foam(stiffness=3e3, damping=10.0, linear_depth=0.02)
    r = dl.impact.simulate(MANIPULATOR_2, soft, HEAD_MIN, 1.25)
    assert r.bottoming and r.status == "bottoming"
    assert any("linear depth" in w for w in r.warnings)
    ok = dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.25)
    assert not ok.bottoming and ok.warnings == ()


def test_overdamped_pulse_is_flagged() -> None:
    foam = dl.impact.Foam(stiffness=5e3, damping=600.0)
    r = dl.impact.simulate(MANIPULATOR_1, foam, HEAD_MIN, 1.25)
    assert r.status == "peak_at_contact"
    assert r.peak_head_acceleration == pytest.approx(600.0 * 1.25 / 4.4, rel=1e-9)


def test_batch_equals_dense_reference() -> None:
    """Batch metrics vs a dense exact sampling (1e-6 s) polished by hand, random designs."""
    rng = np.random.default_rng(7)
    n = 25
    p = np.column_stack(
        [
            rng.uniform(2, 60, n),
            rng.uniform(0, 600, n),
            rng.uniform(5e3, 5e4, n),
            rng.uniform(5e3, 8e4, n),
            rng.uniform(10, 200, n),
            rng.uniform(4.4, 5.3, n),
            rng.uniform(0, 130, n),
            rng.uniform(3e3, 5e3, n),
        ]
    )
    m = dl.impact.impact_metrics(p, 1.25, columns=dl.impact.PARAM_NAMES)
    for i in range(n):
        robot = dl.impact.ContactDynamics(p[i, 0], p[i, 2], p[i, 1])
        foam = dl.impact.Foam(p[i, 3], p[i, 4])
        head = dl.impact.HeadNeck(p[i, 5], p[i, 7], p[i, 6])
        r = dl.impact.simulate(robot, foam, head, 1.25, duration=0.15, samples=150_001)
        a = r.head_acceleration
        k = int(np.flatnonzero((a <= 0) & (r.t > 0))[0])
        assert m.impact_duration[i] == pytest.approx(r.t[k], abs=2e-6)
        assert m.peak_head_acceleration[i] == pytest.approx(a[:k].max(), rel=1e-6)
        assert m.max_compression[i] == pytest.approx(r.compression[: k + 1].max(), rel=1e-5)
        assert m.peak_force[i] == pytest.approx(r.force[: k + 1].max(), rel=1e-5)


@pytest.mark.parametrize(
    "make,field",
    [
        (lambda: dl.impact.HeadNeck(mass=0.0, stiffness=3e3, damping=46.0), "HeadNeck.mass"),
        (lambda: dl.impact.HeadNeck(mass=4.4, stiffness=-1.0, damping=46.0), "HeadNeck.stiffness"),
        (lambda: dl.impact.Foam(stiffness=float("nan"), damping=1.0), "Foam.stiffness"),
        (lambda: dl.impact.Foam(stiffness=1e4, damping=-1.0), "Foam.damping"),
        (
            lambda: dl.impact.ContactDynamics(mass=float("inf"), stiffness=1.0, damping=1.0),
            "ContactDynamics.mass",
        ),
        (
            lambda: dl.impact.Foam(stiffness=1e4, damping=1.0, linear_depth=0.02, thickness=0.01),
            "Foam.thickness",
        ),
        (
            lambda: dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, float("nan")),
            "impact_velocity",
        ),
        (lambda: dl.impact.simulate(MANIPULATOR_1, FOAM_1, HEAD_MIN, 1.0, q2="typo"), "q2"),
        (lambda: dl.impact.impact_metrics({"M_r": 1.0}, 1.0), "params"),
    ],
)
def test_bad_input_names_the_parameter(make, field) -> None:
    with pytest.raises(InvalidParameterError) as exc:
        make()
    assert field in str(exc.value)
    assert isinstance(exc.value, ValueError) and isinstance(exc.value, DesignlabError)


def test_to_frame_and_summary() -> None:
    r = dl.impact.simulate(MANIPULATOR_1, FOAM_3, HEAD_MIN, 1.25, samples=101)
    df = r.to_frame()
    assert list(df.columns)[:4] == ["t_s", "f_c_N", "a_h_m_per_s2", "a_h_g"]
    assert len(df) == 101
    s = r.metrics()
    assert s["a_h_max_g"] == pytest.approx(r.peak_head_acceleration / 9.80665)
    m = dl.impact.impact_metrics(
        [9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 0, 4e3], [0.4, 1.25], columns=dl.impact.PARAM_NAMES
    )
    assert m.to_frame()["a_h_max_g"].round(2).tolist() == [2.10, 6.57]
