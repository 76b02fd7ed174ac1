"""The crowd the robot met, measured by pedpy (issue 23, item 3): exact on a walking lattice,
the band inside the walkable area, the columns of a run and of the study table."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from shapely.geometry import box

import designlab as dl
import designlab.navigation.crowds.faced as faced_module
from designlab.errors import DesignlabError
from designlab.navigation.crowds.faced import (
    FRAME_RATE,
    FacedStatus,
    faced_by,
    faced_by_runs,
    faced_crowd,
    faced_crowds,
    measurement_band,
)
from designlab.navigation.crowds.study import crowd_study, run_row, simulate_run

nav = dl.navigation


def _lattice(a, b, rows, cols, v, phase, T, dt):
    """Pedestrians on a lattice of spacing a (x) by b (y), all walking +x at speed v."""
    t = np.arange(T) * dt
    i, j = np.meshgrid(np.arange(cols), np.arange(rows))
    x0 = (phase + i * a).ravel()
    y0 = (0.5 * b + j * b).ravel()
    P = np.empty((T, x0.size, 2))
    P[:, :, 0] = x0[None, :] + v * t[:, None]
    P[:, :, 1] = y0[None, :]
    return t, P


@settings(max_examples=25, deadline=None)
@given(
    a=st.floats(0.4, 2.0),
    b=st.floats(0.4, 2.0),
    k=st.integers(1, 6),
    m=st.integers(1, 3),
    v=st.floats(0.2, 2.0),
    phase=st.floats(0.0, 1.0),
)
def test_lattice_walking_at_a_fixed_speed_gives_the_exact_density_and_speed(a, b, k, m, v, phase):
    """rho = 1 / (a b) in a band k a long and m b wide (no one on its edge), speed v."""
    T, dt = 201, 0.01  # 2 s, thinned to 10 Hz
    x_band = 3.0 * a + v * T * dt  # the lattice covers the band over the whole run
    cols = math.ceil((x_band + k * a + 3 * v * T * dt) / a) + 6
    t, P = _lattice(a, b, m, cols, v, -phase * a - v * T * dt - a, T, dt)
    band = measurement_band((x_band, m * b / 2), (x_band + k * a, m * b / 2), half_width=m * b / 2)
    sampled = P[:: round(1 / (FRAME_RATE * dt)), :, 0]
    edge = np.minimum(np.abs(sampled - x_band), np.abs(sampled - x_band - k * a))
    assume(edge.min() > 1e-6)  # nobody exactly on the band's ends at a sampled frame
    f = faced_crowd(t, P, band)
    assert f.status == FacedStatus.OK
    assert f.frames["density_per_m2"].to_numpy() == pytest.approx(1 / (a * b), rel=1e-9)
    assert f.measured_density_per_m2 == pytest.approx(1 / (a * b), rel=1e-9)
    assert f.mean_ped_speed_m_per_s == pytest.approx(v, rel=1e-9)
    assert f.band_area_m2 == pytest.approx(k * a * m * b, rel=1e-12)


def test_density_counts_the_frames_with_nobody_and_speed_only_those_with_someone():
    """One pedestrian at 1 m/s crosses a 2 m band in the first half of a 4 s record."""
    t = np.arange(401) * 0.01
    P = np.stack([-1.05 + t, np.zeros_like(t)], axis=1)[:, None, :]  # in (0, 2) from 1.05 s
    P[t > 2.0] = np.nan  # it leaves the simulation at 2 s
    f = faced_crowd(t, P, measurement_band((0.0, 0.0), (2.0, 0.0), half_width=0.5))
    inside = ((t[::10] > 1.05) & (t[::10] <= 2.0)).sum()  # frames with it in the band
    assert f.measured_density_per_m2 == pytest.approx(inside / 41 / 2.0, rel=1e-12)
    assert f.mean_ped_speed_m_per_s == pytest.approx(1.0, rel=1e-9)


def test_band_lies_in_the_walkable_area():
    corridor = box(0.0, 0.0, 30.0, 4.0)
    assert measurement_band((1.5, 2.0), (28.5, 2.0), corridor).bounds == (1.5, 1.0, 28.5, 3.0)
    c = nav.crowd("bottleneck", 10, length=10.0, width=4.0, bottleneck_width=1.2)
    band = measurement_band(c.robot_start, c.robot_goal, c.geometry.area, 2.0)
    assert c.geometry.area.covers(band)
    assert band.bounds[1] == pytest.approx(2.0 - 0.6) and band.bounds[3] == pytest.approx(2.6)
    plaza = nav.crowd("open_plaza", 10, length=10.0, width=6.0)
    diag = measurement_band(plaza.robot_start, plaza.robot_goal, plaza.geometry.area)
    assert plaza.geometry.area.covers(diag)
    assert diag.area == pytest.approx(2.0 * math.hypot(7.0, 3.0), rel=1e-12)


@pytest.mark.parametrize(
    "call",
    [
        lambda: measurement_band((1.0, 1.0), (1.0, 1.0)),
        lambda: measurement_band((0.0, 0.0), (1.0, 0.0), half_width=math.nan),
        lambda: measurement_band((0.0, 0.0), (1.0, 0.0), half_width=-1.0),
        lambda: measurement_band((0.0, 0.0), (1.0, 0.0), half_width=math.inf),
        lambda: measurement_band((-1.0, 1.0), (5.0, 1.0), box(0, 0, 4, 2)),  # leaves the area
        lambda: measurement_band((0.0, 0.0), (4.0, 0.0), box(0, 0, 4, 2)),  # on its edge
        lambda: faced_crowd(np.arange(3.0), np.zeros((4, 1, 2)), box(0, 0, 1, 1)),
        lambda: faced_crowd(np.arange(3.0), np.zeros((3, 2)), box(0, 0, 1, 1)),
    ],
)
def test_bad_input_is_a_clear_error(call):
    with pytest.raises(DesignlabError):
        call()


def test_empty_and_too_short_records():
    band = measurement_band((0.0, 0.0), (2.0, 0.0))
    t = np.arange(101) * 0.01
    none = faced_crowd(t, np.full((101, 3, 2), np.nan), band)
    assert none.status == FacedStatus.NO_PEDESTRIANS and none.measured_density_per_m2 == 0.0
    assert math.isnan(none.mean_ped_speed_m_per_s)
    away = faced_crowd(t, np.full((101, 1, 2), 50.0), band)
    assert away.status == FacedStatus.NO_PEDESTRIANS and away.measured_density_per_m2 == 0.0
    one = faced_crowd(t[:1], np.zeros((1, 1, 2)), band)
    assert one.status == FacedStatus.TOO_SHORT and math.isnan(one.measured_density_per_m2)


def test_a_path_around_a_corner_has_no_band_and_says_so():
    """A start and goal whose straight path crosses a wall: NaN measures, not an error."""
    c = nav.crowd("crossing", 4, length=12.0, width=4.0, seed=0, horizon=0.5,
                  start=(5.0, 1.0), goal=(1.0, 5.0))  # fmt: skip
    res = nav.simulate(c, nav.OPTIMAL_GAINS)
    f = res.faced()
    assert f.status == FacedStatus.NO_BAND and "no measurement band" in f.warnings[0]
    assert math.isnan(f.measured_density_per_m2) and math.isnan(
        run_row(res)["mean_ped_speed_m_per_s"]
    )
    with pytest.raises(DesignlabError):
        res.faced(half_width=-1.0)


def test_a_run_and_the_study_table_report_the_crowd_met():
    """The per-run columns equal faced_by of the same run; the table averages them."""
    opts = {"length": 10.0, "horizon": 1.0}
    st_ = crowd_study(["corridor_counterflow"], [0.5], [3], ["vff"], crowd_options=opts)
    res = nav.simulate(nav.crowd("corridor_counterflow", density=0.5, seed=3, **opts),
                       nav.OPTIMAL_GAINS)  # fmt: skip
    f = faced_by(res)
    row = run_row(res)
    frame = res.to_frame().iloc[0]
    for col, want in (("measured_density_per_m2", f.measured_density_per_m2),
                      ("mean_ped_speed_m_per_s", f.mean_ped_speed_m_per_s)):  # fmt: skip
        assert row[col] == want == frame[col] == st_.runs[col].iloc[0] == st_.to_frame()[col][0]
    assert 0.0 < f.measured_density_per_m2 < 3.0 and 0.2 < f.mean_ped_speed_m_per_s < 2.0


def _same(f, g):
    """Two FacedCrowd measures and series agree to 1e-12 (NaN where the other is NaN)."""
    assert f.status == g.status
    for x, y in ((f.measured_density_per_m2, g.measured_density_per_m2),
                 (f.mean_ped_speed_m_per_s, g.mean_ped_speed_m_per_s),
                 (f.band_area_m2, g.band_area_m2)):  # fmt: skip
        assert (math.isnan(x) and math.isnan(y)) or abs(x - y) <= 1e-12
    np.testing.assert_allclose(
        f.frames.to_numpy(float), g.frames.to_numpy(float), rtol=0, atol=1e-12
    )


@settings(max_examples=8, deadline=None)
@given(
    runs=st.lists(st.tuples(st.floats(0.4, 2.0), st.floats(0.2, 2.0), st.integers(2, 201),
                            st.sampled_from([0.01, 0.02, 0.1]), st.floats(-3.0, 3.0)),
                  min_size=1, max_size=5),
    seed=st.integers(0, 2**16),
)  # fmt: skip
def test_runs_measured_together_are_measured_as_alone(runs, seed):
    """faced_crowds == faced_crowd of each run (lattices of random spacing, speed, length,
    record step and offset; some pedestrians leave, one run empty, one a single record)."""
    band = measurement_band((0.0, 1.0), (4.0, 1.0), half_width=1.0)
    rng = np.random.default_rng(seed)
    recs = []
    for a, v, T, dt, x in runs:
        t, P = _lattice(a, 0.5, 4, 12, v, x - 6.0, T, dt)
        P[rng.random(P.shape[:2]) < 0.05] = np.nan  # gaps: pedestrians out of the simulation
        recs.append((t, P))
    t = np.arange(101) * 0.01
    recs += [(t, np.full((101, 3, 2), np.nan)), (t[:1], np.zeros((1, 1, 2)))]
    together = faced_crowds(recs, band)
    assert len(together) == len(recs)
    for (t, P), f in zip(recs, together, strict=True):
        _same(f, faced_crowd(t, P, band))
    assert together[-2].status == FacedStatus.NO_PEDESTRIANS
    assert together[-1].status == FacedStatus.TOO_SHORT


def test_a_studys_runs_measured_together_equal_faced_by_of_each():
    """faced_by_runs (bands shared, a path around a corner among them) == faced_by of each
    run, and a study's columns == faced_by of its runs (several seeds and methods)."""
    opts = {"length": 10.0, "horizon": 1.0}
    res = [nav.simulate(nav.crowd("corridor_counterflow", density=d, seed=s, **opts),
                        nav.OPTIMAL_GAINS) for d, s in ((0.5, 3), (0.8, 4), (0.5, 5))]  # fmt: skip
    corner = nav.crowd("crossing", 4, length=12.0, width=4.0, seed=0, horizon=0.5,
                       start=(5.0, 1.0), goal=(1.0, 5.0))  # fmt: skip
    res.append(nav.simulate(corner, nav.OPTIMAL_GAINS))
    for half_width in (1.0, 0.5):
        for r, f in zip(res, faced_by_runs(res, half_width), strict=True):
            _same(f, faced_by(r, half_width))
    study = crowd_study(["corridor_counterflow"], [0.5], [3, 5], ["vff", "cbf"], crowd_options=opts)
    for _, row in study.runs.iterrows():
        run = simulate_run(study.settings["options"], "corridor_counterflow", 0.5,
                           int(row["seed"]), str(row["method"]))  # fmt: skip
        f = faced_by(run)
        assert row["measured_density_per_m2"] == f.measured_density_per_m2
        assert row["mean_ped_speed_m_per_s"] == f.mean_ped_speed_m_per_s


def test_runs_split_into_pedpy_calls_are_measured_as_alone(monkeypatch):
    """Runs beyond the rows of one pedpy call are split into consecutive parts (each run in
    one part, a run with more rows alone) and measured as alone."""
    assert faced_module._parts([3, 3, 3]) == [[0, 1, 2]]
    monkeypatch.setattr(faced_module, "_BATCH_ROWS", 5)
    assert faced_module._parts([2, 3, 1, 9, 4, 4]) == [[0, 1], [2], [3], [4], [5]]
    assert faced_module._parts([]) == [[]]
    band = measurement_band((0.0, 1.0), (4.0, 1.0), half_width=1.0)
    recs = [_lattice(a, 0.5, 4, 12, v, -6.0, 101, 0.01) for a, v in ((0.5, 1.0), (0.9, 0.4))]
    rows = [faced_module._thinned(t, P, band.bounds).ped.size for t, P in recs]
    monkeypatch.setattr(faced_module, "_BATCH_ROWS", sum(rows))  # two calls of two runs
    calls = []
    measured = faced_module._measured
    monkeypatch.setattr(
        faced_module, "_measured", lambda th, *a: calls.append(len(th)) or measured(th, *a)
    )
    for (t, P), f in zip(recs * 2, faced_crowds(recs * 2, band), strict=True):
        _same(f, faced_crowd(t, P, band))
    assert calls[:2] == [2, 2]
