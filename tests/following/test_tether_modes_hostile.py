"""Hostile inputs of the Ch. 4 modes, the snagging simulation and their study kinds."""

from __future__ import annotations

import math
import pickle

import pytest

from designlab.errors import InvalidParameterError
from designlab.following import tether as T
from designlab.following.tether.snag import SnagScenario, simulate_snag

BAD_NUMBERS = [math.nan, math.inf, -math.inf, -1.0, 1e300, "1.0", None, True]


@pytest.mark.parametrize("value", BAD_NUMBERS)
@pytest.mark.parametrize(
    "make",
    [
        lambda v: T.SideJoystick(desired_length=v),
        lambda v: T.SideJoystick(speed_gain=v),
        lambda v: T.SideTracking(offset_length=v),
        lambda v: T.SideTracking(lookahead=v),
        lambda v: T.FrontJoystick(turn_gain=v),
        lambda v: T.FrontVelJoystick(turn_gain=v),
        lambda v: SnagScenario(gap=v),
        lambda v: SnagScenario(step=v),
        lambda v: T.BrakeMode(T.PseudoJoystick(), release_margin=v),
    ],
)
def test_bad_numbers_name_the_parameter(make, value):
    with pytest.raises(InvalidParameterError, match=" is not allowed: "):
        make(value)


@pytest.mark.parametrize("value", [1.5, -3, 0, 10**9, "4"])
def test_bad_counts(value):
    with pytest.raises(InvalidParameterError):
        T.SideTracking(tip_buffer_size=value)
    with pytest.raises(InvalidParameterError):
        T.FrontVelJoystick(samples=value)


@pytest.mark.parametrize(
    "mode", [None, "PseudoJoystick", 3, T.FrontJoystick(), T.FrontVelJoystick()]
)
def test_brake_refuses_what_it_cannot_wrap(mode):
    with pytest.raises(InvalidParameterError, match=r"BrakeMode\.mode"):
        T.BrakeMode(mode)


def test_brake_refuses_itself_and_inverted_hysteresis():
    with pytest.raises(InvalidParameterError, match=r"BrakeMode\.mode"):
        T.BrakeMode(T.BrakeMode(T.PseudoJoystick()))
    with pytest.raises(InvalidParameterError, match="release_margin"):
        T.BrakeMode(T.PseudoJoystick(), engage_margin=0.05, release_margin=0.05)


def test_side_offset_inside_the_robot_is_refused_by_simulate():
    with pytest.raises(InvalidParameterError, match="half the robot length"):
        T.simulate(T.SideJoystick(desired_length=0.2), T.straight_line(2.0))


def test_mixed_stepwise_batch_is_refused():
    with pytest.raises(InvalidParameterError, match="all of one law"):
        T.simulate_batch([T.SideTracking(), T.FrontVelJoystick()], T.straight_line(2.0))


def test_snag_needs_a_scenario_and_caps_its_size():
    with pytest.raises(InvalidParameterError, match="scenario"):
        simulate_snag({"gap": 2.0})  # type: ignore[arg-type]
    with pytest.raises(InvalidParameterError, match="is not allowed"):
        simulate_snag(
            SnagScenario(exit=200.0, approach=200.0, step=1e-6, sample_time=1e-6, speed=1e-3)
        )


def test_results_pickle_and_stepwise_batch_with_noise_is_finite():
    robot = T.FollowerRobot(length_noise_std=0.02, angle_noise_std=0.1, max_wheel_speed=8.0)
    batch = T.simulate_batch(
        [T.SideTracking(), T.SideTracking(turn_gain=5.0)], T.figure_eight(a=4.0), robot=robot
    )
    assert str(batch.status) == "ok"
    pickle.loads(pickle.dumps(batch.run(1)))
    pickle.loads(pickle.dumps(simulate_snag(SnagScenario(gap=1.0))))


# ----------------------------------------------------------- issue 41: snagging's functions
@pytest.mark.parametrize("width", [-1, 0, math.nan, math.inf, 1e300, "1", True, None])
def test_first_snag_gap_refuses_what_is_not_a_corridor_width(width):
    """first_snag_gap(-1) was -1.785 m; a width outside its declaration is refused."""
    from designlab.following.tether.snag import first_snag_gap

    with pytest.raises(InvalidParameterError, match="width"):
        first_snag_gap(width)
    assert first_snag_gap(2.0) == 2.0 * (1.0 + math.pi / 4)


def test_snagging_building_blocks_refuse_non_finite_inputs():
    import numpy as np

    from designlab.following.tether.snag import (
        corridor_leader,
        snag_limits,
        string,
        wall_distance,
    )

    with pytest.raises(InvalidParameterError, match="lx"):
        string(-1.0, -0.5, math.nan, 1.0)
    with pytest.raises(InvalidParameterError, match="width"):
        wall_distance(np.zeros(2), np.zeros(2), -1.0)
    with pytest.raises(InvalidParameterError, match="x"):
        wall_distance(np.array([math.inf]), np.zeros(1), 1.0)
    with pytest.raises(InvalidParameterError, match="s"):
        corridor_leader(SnagScenario(), np.array([-1.0]))
    with pytest.raises(InvalidParameterError, match="sc"):
        corridor_leader("corner", np.array([1.0]))  # type: ignore[arg-type]
    d = np.linspace(0.0, 0.5, 6)
    with pytest.raises(InvalidParameterError, match="r_col"):
        snag_limits(d, 2.0 - d, -0.2)
    with pytest.raises(InvalidParameterError, match="d_col"):
        snag_limits(d[:2], (2.0 - d)[:2], 0.2)  # a quadratic needs 3 runs
    with pytest.raises(InvalidParameterError, match="gaps"):
        snag_limits(d, np.full(6, math.nan), 0.2)


def test_brake_walk_shorter_than_the_settling_time_is_refused_by_the_study():
    """brake_walk: 1.0 at 0.5 m/s gave a NaN braked-while-walking share (no sample after the
    2 s start-up): refused by the study's validation, naming brake_walk."""
    from designlab.errors import StudyError
    from designlab.study import parse_study
    from designlab.study.kinds.tether_modes import BRAKE_SETTLE

    head = "designlab: 1\nkind: tether_modes\nname: m\nspeed: 0.5\n"
    with pytest.raises(StudyError, match="brake_walk"):
        parse_study(head + "brake_walk: 1.0\n")
    ok = parse_study(head + "brake_walk: 1.1\n")
    assert ok.brake_walk / ok.speed > BRAKE_SETTLE


@pytest.mark.parametrize(
    ("args", "name"),
    [
        (([1.0, math.nan], 1.0, 0.02, 0.05), "tether_length"),
        (("abc", 1.0, 0.02, 0.05), "tether_length"),
        (([1.0], math.nan, 0.02, 0.05), "desired_length"),  # was all False, silently
        (([1.0], 1.0, 0.1, 0.05), "release_margin"),  # inverted hysteresis: was accepted
        (([1.0], 1.0, -1e300, 0.05), "engage_margin"),
    ],
)
def test_brake_timeline_checks_its_arguments_as_brake_mode_does(args, name):
    with pytest.raises(InvalidParameterError, match=name):
        T.brake_timeline(*args)


def test_brake_timeline_is_the_selector_of_a_brake_run():
    """The timeline of a Brake run's own tether lengths is the run's braking record."""
    import numpy as np

    c = T.BrakeMode(T.PseudoJoystick(), engage_margin=0.02, release_margin=0.05)
    run = T.simulate(c, T.straight_line(2.0), settle_time=3.0)
    on = T.brake_timeline(run.tether_length, 1.0, 0.02, 0.05)
    assert on.dtype == bool and on.shape == run.tether_length.shape
    assert on.any()  # the leader stops: the robot brakes
    stopped = np.hypot(*np.diff(run.robot_xy, axis=0).T)[on[1:]]
    assert stopped.max() < 0.05  # braking periods do not drive on


@pytest.mark.parametrize(
    ("spec", "name"),
    [
        ([1], "controller"),
        ({"type": "FollowTheLeader", "lookahed": 0.3}, r"controller\.lookahed"),  # TypeError
        ({"type": 3}, r"controller\.type"),
    ],
)
def test_controller_from_dict_names_the_key(spec, name):
    with pytest.raises(InvalidParameterError, match=name):
        T.controller_from_dict(spec)


@pytest.mark.parametrize(
    ("t", "e", "name"),
    [
        ([0.0, 1.0, 2.0], [1.0, math.nan, 0.1], "e"),  # was (nan, nan)
        ([0.0], [1.0], "e"),  # was an IndexError
        ([0.0, 0.1, 0.2], [1.0, 0.5], "e"),
        ([0.0, 0.1, 0.3, 0.4] * 3, [1.0] * 12, "t"),  # not equally spaced
    ],
)
def test_fit_damping_refuses_what_is_not_a_sampled_response(t, e, name):
    with pytest.raises(InvalidParameterError, match=f"^{name} "):
        T.fit_damping(t, e)


def test_fit_damping_of_a_two_pole_response():
    import numpy as np

    zeta, wn = 0.6, 2.0
    t = np.arange(0.0, 8.0, 0.01)
    wd = wn * math.sqrt(1 - zeta**2)
    e = np.exp(-zeta * wn * t) * np.cos(wd * t)
    z, w = T.fit_damping(t, e)
    assert z == pytest.approx(zeta, rel=1e-8) and w == pytest.approx(wn, rel=1e-8)


def test_follower_metrics_needs_a_run():
    with pytest.raises(InvalidParameterError, match="run"):
        T.follower_metrics("run")  # type: ignore[arg-type]


@pytest.mark.parametrize("body", ["modes: []\n", "brake_laws: []\n"])
def test_tether_modes_refuses_empty_lists_its_report_needs(body):
    """modes: [] and brake_laws: [] validated, then the report writer raised KeyError."""
    from designlab.errors import StudyError
    from designlab.study import parse_study

    with pytest.raises(StudyError, match=body.split(":")[0]):
        parse_study("designlab: 1\nkind: tether_modes\nname: m\n" + body)


def test_tether_length_noise_is_bounded_below_a_negative_length():
    """sigma_l up to 1 m gave negative measured tether lengths (-3.8 m)."""
    with pytest.raises(InvalidParameterError, match="length_noise_std"):
        T.FollowerRobot(length_noise_std=0.5)
    robot = T.FollowerRobot(length_noise_std=0.1, max_wheel_speed=8.0)
    run = T.simulate(T.PseudoJoystick(), T.straight_line(3.0), robot=robot)
    assert (run.tether_length > 0).all()
