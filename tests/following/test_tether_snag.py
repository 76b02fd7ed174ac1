"""Tether snagging on a corridor corner (Allan 2015 Sec. 4.5): geometry, limits, detection."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designlab.errors import StudyError
from designlab.following.tether.snag import (
    SnagScenario,
    corridor_leader,
    first_snag_gap,
    simulate_snag,
    snag_limits,
    string,
    wall_distance,
)

coords = st.floats(-5.0, 5.0)


def _blocked(px, py, lx, ly, n=4001):
    t = np.linspace(0.0, 1.0, n)
    x, y = px + t * (lx - px), py + t * (ly - py)
    return bool(np.any((x < -1e-9) & (y > 1e-9)))


@settings(max_examples=200, deadline=None)
@given(coords, coords, coords, coords)
def test_string_wraps_exactly_when_the_chord_is_blocked(px, py, lx, ly):
    if (px < 0 and py > 0) or (lx < 0 and ly > 0):
        return  # an end inside the wall block
    length, direction, wrapped = string(px, py, lx, ly)
    straight = math.hypot(lx - px, ly - py)
    if wrapped:
        assert _blocked(px, py, lx, ly, 20001) or length - straight < 1e-6
        assert length == pytest.approx(math.hypot(px, py) + math.hypot(lx, ly))
        assert length >= straight - 1e-12
        assert direction == pytest.approx(math.atan2(-py, -px))
    else:
        assert not _blocked(px, py, lx, ly)
        assert length == pytest.approx(straight)


def test_wall_distance_exact_points():
    x = np.array([-3.0, 0.5, 0.5, -0.1, 0.2, 1.2, -0.5])
    y = np.array([-0.5, 3.0, -0.5, -0.1, -0.9, 2.0, 0.2])
    expect = [0.5, 0.5, 0.5, 0.1, 0.1, -0.2, -0.2]
    assert wall_distance(x, y, 1.0).tolist() == pytest.approx(expect)


def test_leader_walks_the_centre_line_at_constant_speed():
    sc = SnagScenario()
    s = np.linspace(0.0, sc.approach + 0.25 * math.pi + sc.exit, 2001)
    xy = corridor_leader(sc, s)
    steps = np.hypot(*np.diff(xy, axis=0).T)
    assert steps == pytest.approx(np.diff(s), abs=1e-6)
    assert wall_distance(xy[:, 0], xy[:, 1], 1.0) == pytest.approx(0.5)


def test_no_snag_below_the_geometric_limit_and_snag_above():
    g0 = first_snag_gap(1.0)
    assert g0 == pytest.approx(1.0 + math.pi / 4)
    calm = simulate_snag(SnagScenario(gap=g0 - 0.02))
    assert not calm.snagged.any() and calm.d_col == pytest.approx(0.5, abs=1e-5)  # 5 mm chords
    assert calm.detections == ()
    assert simulate_snag(SnagScenario(gap=g0 + 0.02)).snagged.any()


@pytest.mark.parametrize("gap", [2.5, 5.0])
def test_snag_starts_where_the_chord_touches_the_vertex(gap):
    # robot d_r before the arc and leader d_L after it: d_r + d_L = g - pi w/4, d_r d_L = w^2/4
    sc = SnagScenario(gap=gap)
    total = gap - math.pi / 4
    d_l = 0.5 * (total - math.sqrt(total**2 - 1.0))
    expect = sc.approach + math.pi / 4 + d_l
    run = simulate_snag(sc)
    assert run.snag_span[0] == pytest.approx(expect, abs=0.01)
    assert run.detections[0] == pytest.approx(expect, abs=0.06)  # a chord of 4 steps later


def test_distortion_grows_with_the_gap_and_compensation_removes_it():
    d = [simulate_snag(SnagScenario(gap=g)).d_col for g in (1.8, 2.0, 2.25, 2.5)]
    assert all(a > b for a, b in itertools.pairwise(d))
    # the gap-keeping robot (ours) ends g_F behind the leader; the thesis's constant-speed
    # robot (the default) drives on to the newest recorded point
    fixed = simulate_snag(SnagScenario(gap=2.5, compensate=True, follower="gap"))
    assert fixed.d_col == pytest.approx(0.5, abs=0.01)  # the straight join after the unsnag
    assert len(fixed.detections) == 2  # snag and unsnag
    end = fixed.robot_xy[-1]
    assert end.tolist() == pytest.approx([0.5, fixed.leader_xy[-1, 1] - 2.5], abs=0.02)


def test_snag_limits_recovers_a_quadratic():
    rng = np.random.default_rng(1)
    d = rng.uniform(0.0, 0.5, 20)
    a, b, c = -0.5, -1.0, 2.4
    fit = snag_limits(d, a * d**2 + b * d + c, 0.2)
    assert (fit["a"], fit["b"], fit["c"]) == pytest.approx((a, b, c))
    assert fit["gap_limit"] == pytest.approx(a * 0.04 + b * 0.2 + c)
    assert fit["rms"] < 1e-9


def test_feature_rates_table():
    run = simulate_snag(SnagScenario(gap=3.0))
    rates = run.feature_rates()
    assert list(rates.columns) == [
        "s_leader_m",
        "dtheta_ds_rad_per_m",
        "dl_ds",
        "dbeta_ds_rad_per_m",
    ]
    assert len(rates) == len(run.tracked_xy)


def test_snagging_study_report_and_limits(tmp_path):
    from designlab.report import write_report
    from designlab.study import parse_study, run_study

    study = parse_study(
        "designlab: 1\nkind: tether_snagging\nname: sn\ngaps: {low: 1.6, high: 2.6, num: 11}\n"
        "detail_gaps: [2.5]"
    )
    result = run_study(study)
    lim = result.limits()
    frame = result.to_frame()
    # the grid's first snag is the first grid gap above 1 + pi/4
    assert lim["first_snag_gap_over_w"] == pytest.approx(1.8)
    d = frame["d_col_over_w"].to_numpy()
    i = int(np.argmax(d < 0.2))
    g = frame["gap_over_w"].to_numpy()
    expect = g[i - 1] + (0.2 - d[i - 1]) * (g[i] - g[i - 1]) / (d[i] - d[i - 1])
    assert lim["collision_gap_over_w"] == pytest.approx(expect)
    assert (frame["compensated_status"] == "ok").all()
    prom = result.feature_prominence()
    assert len(prom) == 3 and (prom["ratio"] == prom["near_max"] / prom["elsewhere_max"]).all()
    assert prom.set_index("feature")["ratio"]["d beta_path / d s_L (4.12)"] > 1.0
    assert result.followers == ("constant_speed", "gap")
    table = result.limits_frame().set_index("follower")
    assert table.loc["constant_speed", "collision_gap_over_w"] == lim["collision_gap_over_w"]
    ours = result.limits("gap")
    assert ours["collision_gap_over_w"] < lim["collision_gap_over_w"]  # it speeds up in the snag
    out = write_report(result, tmp_path, index=False)
    assert {
        "snagging.csv",
        "limits.csv",
        "snagging_paths.png",
        "snagging_limits.png",
        "summary.md",
    } <= {p.name for p in out.iterdir()}
    text = (out / "summary.md").read_text()
    assert (
        "constant v_F (Table 4.1; the thesis's follower)" in text and "gap-keeping (ours)" in text
    )


@pytest.mark.parametrize(
    "body",
    [
        "gaps: {low: 3, high: 1}",
        "gaps: {num: 1}",
        "gaps: {low: -1}",
        "scenario: {width: .nan}",
        "scenario: {gap: 2.0}",
        "detail_gaps: [1, 2, 3, 4, 5, 6, 7]",
        "compare_followers: [slow]",
        "scenario: {follower: slow}",
    ],
)
def test_snagging_study_refuses(body):
    from designlab.study import parse_study

    with pytest.raises(StudyError, match=r"<string>:\d+: "):
        parse_study(f"designlab: 1\nkind: tether_snagging\nname: sn\n{body}")


@settings(max_examples=40, deadline=None)
@given(st.floats(0.5, 5.0), st.floats(0.01, 1.0))
def test_thesis_gap_limits_scale_with_the_width(w, frac):
    from designlab.following.tether.snag import thesis_gap_limits

    lim = thesis_gap_limits(w, frac * w)
    r = 0.5 * frac
    assert lim["no_snag"] == pytest.approx(1.75 * w)
    assert lim["no_collision"] == pytest.approx(w * (-0.664 * r * r - 1.4 * r + 2.565))


@pytest.mark.parametrize("args", [(0.0, 0.4), (1.0, -1.0), (1.0, 1.5), (math.nan, 0.4), (1.0, "x")])
def test_thesis_gap_limits_refuses(args):
    from designlab.errors import InvalidParameterError
    from designlab.following.tether.snag import thesis_gap_limits

    with pytest.raises(InvalidParameterError):
        thesis_gap_limits(*args)
