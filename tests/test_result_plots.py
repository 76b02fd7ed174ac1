"""``result.plot()`` on the main results returns matplotlib axes with what it drew (issue 39,
item 6): labelled axes with units, a legend, the lines of the result's own numbers."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest
from matplotlib.axes import Axes
from matplotlib.figure import Figure

import designlab as dl
from designlab.plots import PLOTS
from designlab.results import Result


def _axes() -> Axes:
    return Figure().subplots()


def test_an_impact_response_draws_its_signal_in_the_asked_unit() -> None:
    imp = dl.impact
    r = imp.simulate(imp.MANIPULATOR_1, imp.FOAM_1, imp.TEST_HEAD, impact_velocity=1.25)
    ax = r.plot(_axes())
    assert isinstance(ax, Axes) and ax.get_ylabel() == "head acceleration (g)"
    line = ax.get_lines()[0]
    assert np.array_equal(line.get_xdata(), 1e3 * r.t)
    assert np.array_equal(line.get_ydata(), (1.0 / 9.81) * r.head_acceleration)
    ax = r.plot(_axes(), quantity="compression")
    assert np.array_equal(ax.get_lines()[0].get_ydata(), 1e3 * r.compression)
    with pytest.raises(ValueError, match="quantity='speed'"):
        r.plot(_axes(), quantity="speed")


def test_a_foam_envelope_draws_its_band() -> None:
    env = dl.impact.foam_envelope(dl.impact.MANIPULATOR_1, damping=np.linspace(0, 200, 5))
    ax = env.plot(_axes())
    upper = ax.get_lines()[0]
    assert np.allclose(upper.get_ydata(), env.stiffness_max / 1e3)
    assert "(N s/m)" in ax.get_xlabel() and "(kN/m)" in ax.get_ylabel()


def _legend(ax: Axes) -> set[str]:
    return {t.get_text() for t in ax.get_legend().get_texts()}


def test_a_navigation_run_draws_its_path_start_and_goal() -> None:
    nav = dl.navigation
    r = nav.simulate(nav.configuration(1), nav.OPTIMAL_GAINS)
    ax = r.plot(_axes())
    assert {"start", "goal", "robot (vff)"} <= _legend(ax)
    robot = next(line for line in ax.get_lines() if line.get_label() == "robot (vff)")
    assert np.array_equal(robot.get_xydata(), r.position[:, :2])
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("x (m)", "y (m)")


def test_a_tether_run_draws_leader_and_robot() -> None:
    fol = dl.following
    run = fol.simulate(fol.FollowTheLeader(), fol.slalom(), speed=0.5)
    ax = run.plot(_axes())
    assert {"leader", "start", "goal"} <= _legend(ax)
    assert np.array_equal(ax.get_lines()[1].get_xydata(), run.robot_xy)


@pytest.mark.slow  # a JuPedSim crowd: a minute under load
def test_a_crowd_run_draws_robot_and_pedestrians() -> None:
    pytest.importorskip("jupedsim")
    nav = dl.navigation
    crowd = nav.crowd("corridor_counterflow", pedestrians=4, length=12.0, seed=0, horizon=1.0)
    r = nav.simulate(crowd, nav.VFFGains(4.3, 0.68, 20.3, 240.7))
    ax = r.plot(_axes())
    assert {"pedestrians", "robot (vff)", "start", "goal"} <= _legend(ax)


@pytest.mark.slow  # a search of 4 designs: half a minute under load
def test_a_pareto_front_draws_the_front_and_the_reference() -> None:
    cd = dl.codesign
    front = cd.pareto(dl.navigation.configuration(2), objectives=("arrival_time",
                      "foam_thickness"), population=4, generations=1, risk_samples=200)  # fmt: skip
    ax = front.plot(_axes())
    assert "non-dominated" in _legend(ax)
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("arrival_time", "foam_thickness")
    with pytest.raises(ValueError, match="'speed'"):
        front.plot(_axes(), x="speed")


@pytest.mark.slow  # imports every module of designlab
def test_every_drawing_is_of_a_result_type_and_the_others_say_so() -> None:
    from test_pickle_results import result_types  # every Result subclass, discovered

    names = {t.__name__ for t in result_types()}
    assert set(PLOTS) <= names
    r = dl.impact.closing_speed((0.25, 0.0), (-1.0, 0.0), (1.0, 0.0))
    assert isinstance(r, Result)
    with pytest.raises(NotImplementedError, match="ClosingSpeed has no plot"):
        r.plot(_axes())
