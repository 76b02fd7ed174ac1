"""The closed-form snagging limits of the constant-speed follower (Allan 2015 Sec. 4.5)."""

from __future__ import annotations

import math

import mpmath as mp
import pytest

from designlab.errors import InvalidParameterError
from designlab.following.tether.snag import SnagScenario, simulate_snag
from designlab.following.tether.snag_geometry import constant_speed_d_col, constant_speed_limits


def _mp_d_col(gap: float) -> mp.mpf:
    """d_col over w at 30 digits: the tip's largest x where its derivative vanishes."""
    mp.mp.dps = 30
    big = mp.mpf(gap) - mp.pi / 4
    y1, y2 = (big - mp.sqrt(big**2 - 1)) / 2, (big + mp.sqrt(big**2 - 1)) / 2

    def tip(y: mp.mpf) -> mp.mpf:
        q = big - y
        return -q + (mp.sqrt(mp.mpf(1) / 4 + y**2) + mp.sqrt(q**2 + mp.mpf(1) / 4)) * q / mp.sqrt(
            q**2 + mp.mpf(1) / 4
        )

    grid = [y1 + (y2 - y1) * k / 200 for k in range(1, 200)]
    y0 = max(grid, key=tip)
    ystar = mp.findroot(lambda y: mp.diff(tip, y), y0)
    return 1 - tip(ystar)


@pytest.mark.parametrize("gap", [2.0, 2.3, 2.55])
def test_d_col_equals_the_30_digit_maximum(gap: float) -> None:
    assert constant_speed_d_col(gap) == pytest.approx(float(_mp_d_col(gap)), abs=1e-9)


def test_the_limits_are_where_the_30_digit_d_col_crosses() -> None:
    lim = constant_speed_limits()
    assert lim["first_snag"] == pytest.approx(1 + math.pi / 4, abs=1e-15)
    assert float(_mp_d_col(lim["collision"])) == pytest.approx(0.2, abs=1e-9)
    assert float(_mp_d_col(lim["wall"])) == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("gap", [2.0, 2.3, 2.55])
def test_the_simulation_converges_to_the_closed_form(gap: float) -> None:
    """The simulated d_col at the users' settings (5 mm, 5 ms) within 5e-4 w: the recording
    lags the leader by under one 5 mm step."""
    run = simulate_snag(SnagScenario(gap=gap))
    assert run.d_col == pytest.approx(constant_speed_d_col(gap), abs=5e-4)


def test_a_winch_behind_the_centre_shifts_every_limit_by_its_offset() -> None:
    base, moved = constant_speed_limits(), constant_speed_limits(winch_offset=-0.03)
    for key in base:
        assert moved[key] == pytest.approx(base[key] - 0.03, abs=1e-9)
    run = simulate_snag(SnagScenario(gap=2.3, winch_offset=-0.03))
    assert run.d_col == pytest.approx(constant_speed_d_col(2.3, winch_offset=-0.03), abs=5e-4)


def test_a_tether_height_lengthens_the_estimate_and_keeps_the_first_snag() -> None:
    base, high = constant_speed_limits(), constant_speed_limits(tether_height=0.3)
    assert high["first_snag"] == base["first_snag"]
    assert high["collision"] < base["collision"] and high["wall"] < base["wall"]
    run = simulate_snag(SnagScenario(gap=2.3, tether_height=0.3))
    assert run.d_col == pytest.approx(constant_speed_d_col(2.3, tether_height=0.3), abs=5e-4)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"r_col": float("nan")}, "r_col"),
        ({"r_col": 0.5}, "r_col"),
        ({"winch_offset": float("inf")}, "winch_offset"),
        ({"tether_height": -0.1}, "tether_height"),
        ({"tether_height": "0.3"}, "tether_height"),
    ],
)
def test_hostile_arguments_name_the_parameter(kwargs: dict, name: str) -> None:
    with pytest.raises(InvalidParameterError, match=name):
        constant_speed_limits(**kwargs)


@pytest.mark.parametrize("field", ["winch_offset", "tether_height"])
@pytest.mark.parametrize("value", [float("nan"), 1e9, True])
def test_hostile_scenario_fields_are_refused(field: str, value: object) -> None:
    with pytest.raises(InvalidParameterError, match=field):
        SnagScenario(**{field: value})


def test_d_col_below_the_first_snag_is_the_centre_line() -> None:
    assert constant_speed_d_col(1.0) == 0.5
    with pytest.raises(InvalidParameterError, match="gap"):
        constant_speed_d_col(-1.0)
