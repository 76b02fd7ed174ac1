"""Region sizes of Zeng 2011, Sec. 6.3, 7.4 and 7.5.5 (tests/data/nav_region_sizes.csv).

Each printed value is recomputed with the same inputs the thesis fed into its printed
expression (its *adopted* upstream values, e.g. r3 = 0.8 m, Delta t2 = 1.18 s). Printed
values that do not follow from their own expressions are the thesis's arithmetic slips;
the tests name them and check the correct value instead.
"""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.results import check_result

nav = dl.navigation
DATA = Path(__file__).resolve().parents[1] / "data"
TABLE = pd.read_csv(DATA / "nav_region_sizes.csv")
TS = 0.06
HOLO = nav.HolonomicRobot(radius=0.2, max_speed=0.7, max_accel=10.0)
NH = nav.NonholonomicRobot(radius=0.2, max_speed=0.7, max_accel=10.0, max_angular_accel=70.0)
HUMAN = nav.Human(radius=0.4, max_speed=1.0)
CIRCLE = nav.CircularObstacle(radius=0.1)
RECT = nav.RectangularObstacle(length=1.4, width=0.6, offset=0.3)
MOB = nav.ObstacleRobot(radius=0.2, max_speed=0.5)


def _computed() -> dict[str, float]:
    """Every sized quantity, fed with the thesis's adopted upstream values."""
    h = nav.region_sizes(HUMAN, HOLO, TS, critical_radius=0.8, sidestep_time=1.18)
    c = nav.region_sizes(CIRCLE, HOLO, TS, critical_radius=0.4, sidestep_time=0.61)
    r = nav.region_sizes(RECT, HOLO, TS, critical_radius=0.4, sidestep_time=1.04)
    h_nh = nav.region_sizes(HUMAN, NH, TS, critical_radius=0.8, sidestep_time=1.18, turn_time=0.22)
    c_nh = nav.region_sizes(CIRCLE, NH, TS, critical_radius=0.4, sidestep_time=0.61, turn_time=0.22)
    r_nh = nav.region_sizes(RECT, NH, TS, critical_radius=0.3, sidestep_time=0.93, turn_time=0.22)
    m = nav.region_sizes(MOB, NH, TS, critical_radius=0.55, sidestep_time=0.83, turn_time=0.23)
    h_min = nav.region_sizes(HUMAN, HOLO, TS, critical_radius=0.8)
    c_min = nav.region_sizes(CIRCLE, HOLO, TS, critical_radius=0.4)
    r_min = nav.region_sizes(RECT, HOLO, TS, critical_radius=0.4)
    r_nh_min = nav.region_sizes(RECT, NH, TS, critical_radius=0.3)
    m_min = nav.region_sizes(MOB, NH, TS, critical_radius=0.55)
    return {
        "Delta_t1": h.stopping_time,
        "t_a": h.accel_time,
        "delta_r1_bar": h.robot_stopping_distance,
        "delta_h1_bar": h.obstacle_advance,
        "r3_hat": h.r3_hat,
        # (6.3.3) uses the adopted r3_hat = 0.2: 0.2 + rho_h + rho_r
        "r3": 0.2 + HUMAN.radius + HOLO.radius,
        "Delta_t2": h_min.sidestep_time,
        "r2": h.r2,
        "r3_cir": c.r3_min,
        "Delta_t2_circular": c_min.sidestep_time,
        "r2_cir": c.r2,
        "r3_hat_rect": r.r3_hat,
        # (6.3.11) uses the adopted r3_hat_rect = 0.2
        "r3_rect": 0.2 + HOLO.radius,
        "B": r.offset,
        "Delta_t2_rect": r_min.sidestep_time,
        "r2_rect": r.r2,
        "t_turn": NH.turn_time,
        "r2_nh": h_nh.r2,
        "r2_cir_nh": c_nh.r2,
        "r3_hat_rect_nh": r_nh.r3_hat,
        "r3_rect_nh": 0.1 + NH.radius,
        "Delta_t2_rect_nh": r_nh_min.sidestep_time,
        "r2_rect_nh": r_nh.r2,
        "delta_mob_bar": m.obstacle_advance,
        "r3_mob": m.r3_min,
        "Delta_t2_mob": m_min.sidestep_time,
        "r2_mob": m.r2,
    }


COMPUTED = _computed()

# The thesis's arithmetic slips: printed value -> what its own expression gives.
SLIPS = {
    "r2": 2.108,  # (6.3.5): 1.7 * 1.24 = 2.108, printed 2.09
    "r2_rect": 0.77,  # (6.3.13): 0.7 * (1.04 + 0.06) = 0.77; the thesis used 0.07 for T_s -> 0.78
    "t_turn": 0.2118,  # (7.4.2b): sqrt(pi/70) = 0.2118, printed 0.22
    "r2_nh": 2.482,  # (7.4.3): 1.7 * 1.46 = 2.482, printed 2.47
    "Delta_t2_rect_nh": 0.8921,  # (7.4.5): 0.5755/0.7 + 0.07 = 0.892, printed 0.92
    "r3_mob": 0.5315,  # (7.5.1): 0.065 + 0.0665 + 0.4 = 0.5315, printed 0.54
}


ROWS = [(row.quantity, row) for row in TABLE.itertuples() if row.quantity in COMPUTED]


def test_every_sized_row_is_checked() -> None:
    sized = set(TABLE.quantity) - {"r2 (conventional VFFs)"}
    assert sized <= set(COMPUTED), sized - set(COMPUTED)


@pytest.mark.parametrize("quantity", [q for q, _ in ROWS])
def test_printed_region_values(quantity: str) -> None:
    row = TABLE[TABLE.quantity == quantity].iloc[0]
    printed = float(row.thesis_printed_value)
    value = COMPUTED[quantity]
    if quantity in SLIPS:
        # The printed value does not follow from the printed expression; the code gives
        # the expression's value, which is at least 0.005 away from the print.
        assert value == pytest.approx(SLIPS[quantity], abs=6e-4)
        assert abs(value - printed) > 0.005
    else:
        # Half a unit of the last printed decimal; 3-decimal prints get 2e-3 because the
        # thesis rounds intermediates (0.0665 -> 0.067, so 1.1779 prints as 1.179).
        text = str(row.thesis_printed_value)
        decimals = len(text.split(".")[1]) if "." in text else 0
        tol = 0.5 * 10.0**-decimals + 1e-9 if decimals <= 2 else 2.1e-3
        assert value == pytest.approx(printed, abs=tol), (quantity, value, printed)


@pytest.mark.parametrize("quantity", [q for q, r in ROWS if not pd.isna(r.adopted_value)])
def test_adopted_values_respect_the_minimum_except_where_the_thesis_says(quantity: str) -> None:
    row = TABLE[TABLE.quantity == quantity].iloc[0]
    adopted = float(row.adopted_value)
    minimum = COMPUTED[quantity]
    if quantity == "r2":
        # Finding: the adopted 2.1 m is below the 2.108 m the expression requires; the
        # print slip 2.09 hid it.
        assert adopted < minimum
    elif quantity == "r2_rect_nh":
        # 0.55 m chosen for lab space, below the 0.85 m minimum (Sec. 7.4)
        assert adopted < minimum
    elif quantity == "t_turn":
        assert adopted >= minimum
    else:
        assert adopted >= minimum - 2e-3, (quantity, adopted, minimum)


def test_conventional_vff_regions_equal_new_vff_regions() -> None:
    row = TABLE[TABLE.quantity == "r2 (conventional VFFs)"].iloc[0]
    assert [float(x) for x in row.adopted_value.split("/")] == [2.1, 0.8, 0.8]


def test_result_contract_and_frame() -> None:
    s = nav.region_sizes(HUMAN, HOLO, TS)
    check_result(s)
    frame = s.to_frame()
    assert set(frame.quantity) >= {"r2", "r3", "sidestep_time", "robot_stopping_distance"}


def test_independent_closed_form_human() -> None:
    # (5.3.1)-(5.3.7) written out by hand for V=0.7, a=10, Vh=1, Ts=0.06
    d_r1 = 0.7 * 0.06 + 0.5 * 10 * 0.07**2
    r3 = 0.13 + d_r1 + 0.6
    dt2 = (r3 - 0.5 * 10 * 0.07**2) / 0.7 + 0.07
    s = nav.region_sizes(HUMAN, HOLO, TS)
    assert s.r3 == pytest.approx(r3)
    assert s.r2 == pytest.approx(1.7 * (dt2 + 0.06))


def test_rectangle_worst_case_offset_is_half_length() -> None:
    worst = nav.region_sizes(nav.RectangularObstacle(1.4, 0.6), HOLO, TS)
    assert worst.offset == pytest.approx(0.7)
    assert worst.r2 > nav.region_sizes(RECT, HOLO, TS).r2


@settings(max_examples=60, deadline=None)
@given(
    v=st.floats(0.05, 3.0),
    a=st.floats(0.5, 50.0),
    vh=st.floats(0.0, 3.0),
    ts=st.floats(1e-3, 0.5),
    rho=st.floats(0.01, 1.0),
)
def test_invariants(v: float, a: float, vh: float, ts: float, rho: float) -> None:
    robot = nav.HolonomicRobot(radius=0.2, max_speed=v, max_accel=a)
    s = nav.region_sizes(nav.Human(radius=rho, max_speed=vh), robot, ts)
    # the robot must sidestep by r3 and the lateral travel covers it exactly at Delta t2
    lateral = v * (s.sidestep_time - s.accel_time) + 0.5 * a * s.accel_time**2
    assert lateral == pytest.approx(s.r3, rel=1e-9)
    assert s.r2 > s.r3 > rho + 0.2
    # nonholonomic regions are never smaller; a faster obstacle needs bigger regions
    nh = nav.NonholonomicRobot(radius=0.2, max_speed=v, max_accel=a)
    assert nav.region_sizes(nav.Human(rho, vh), nh, ts).r2 > s.r2
    assert nav.region_sizes(nav.Human(rho, vh + 0.1), robot, ts).r2 > s.r2


@pytest.mark.parametrize("bad", [0.0, -0.06, math.nan, math.inf, "x", None])
def test_bad_sample_time(bad: object) -> None:
    with pytest.raises(InvalidParameterError, match="sample_time"):
        nav.region_sizes(HUMAN, HOLO, bad)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "make",
    [
        lambda: nav.Human(radius=-0.4),
        lambda: nav.Human(radius=math.nan),
        lambda: nav.HolonomicRobot(max_speed=0.0),
        lambda: nav.HolonomicRobot(max_accel=math.inf),
        lambda: nav.RectangularObstacle(length=-1),
        lambda: nav.NonholonomicRobot(xi=1.5),
        lambda: nav.region_sizes(HUMAN, HOLO, TS, critical_radius=0.5),
        lambda: nav.region_sizes(HUMAN, HOLO, TS, sidestep_time=0.1),
        lambda: nav.region_sizes(HUMAN, HOLO, TS, turn_time=0.2),
        lambda: nav.region_sizes("human", HOLO, TS),
    ],
)
def test_bad_inputs_name_the_parameter(make) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidParameterError):
        make()


def test_an_absurd_human_speed_is_refused():
    import pytest

    import designlab as dl
    from designlab.errors import InvalidParameterError

    with pytest.raises(InvalidParameterError, match=r"Human.max_speed = 1e\+300 m/s"):
        dl.navigation.Human(radius=0.4, max_speed=1e300)


def test_region_sizes_warnings_are_filled() -> None:
    import designlab as dl

    nav = dl.navigation
    robot = nav.HolonomicRobot()
    adopted = dict(critical_radius=0.8, sidestep_time=1.18)  # the thesis's (6.3.5)
    ok = nav.region_sizes(nav.Human(), robot, 0.06, active_radius=2.2, **adopted)
    assert ok.warnings == () and ok.r2 < 2.2
    low = nav.region_sizes(nav.Human(), robot, 0.06, active_radius=2.1, **adopted)
    assert len(low.warnings) == 1 and "below the minimum" in low.warnings[0]
    # a loop slower than the stopping time: the reaction delay dominates
    slow = nav.region_sizes(nav.Human(), robot, robot.max_speed / robot.max_accel * 2.0)
    assert any("exceeds the stopping time" in w for w in slow.warnings)
    assert any("twice the thesis" in w for w in slow.warnings)
    with pytest.raises(dl.errors.InvalidParameterError, match="active_radius"):
        nav.region_sizes(nav.Human(), robot, 0.06, active_radius=-1.0)
