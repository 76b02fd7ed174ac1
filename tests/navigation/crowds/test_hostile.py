"""Hostile inputs to the crowd simulator: a clear error naming the parameter."""

from __future__ import annotations

import math

import numpy as np
import pytest

import designlab as dl
from designlab.errors import InvalidParameterError

nav = dl.navigation
GAINS = nav.VFFGains(4.3, 0.68, 20.3, 240.7)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"pedestrians": 0}, "pedestrians"),
        ({"pedestrians": -3}, "pedestrians"),
        ({"pedestrians": 2.5}, "pedestrians"),
        ({"pedestrians": "many"}, "pedestrians"),
        ({"pedestrians": 10**6}, "pedestrians"),
        ({"density": 5.0}, "density"),  # more than the corridor holds
        ({"density": -0.1}, "density"),
        ({"density": math.nan}, "density"),
        ({"density": 1e-6}, "density"),  # no pedestrian at all
        ({"pedestrians": 300}, "pedestrians"),  # 30 m x 4 m holds about 230
        ({"model": "boids"}, "model"),
        ({"width": math.nan}, "width"),
        ({"length": math.inf}, "length"),
        ({"width": -4.0}, "width"),
        ({"seed": -1}, "seed"),
        ({"react_to_robot": "yes"}, "react_to_robot"),
        ({"goal": (1.5, 0.1)}, "goal"),  # inside the south wall's critical region
        ({"goal": (50.0, 2.0)}, "goal"),  # outside the corridor
        ({"goal": (math.nan, 2.0)}, "goal"),
        ({"start": "here"}, "start"),
        ({"pedestrian_step": 0.025}, "pedestrian_step"),  # does not divide 0.06 s
        ({"desired_speed": 2.0, "max_desired_speed": 1.5}, "max_desired_speed"),
        ({"neighbours": 0}, "neighbours"),
        ({"horizon": 1e9}, "horizon"),
        ({"critical_radius": 3.0, "active_radius": 2.0}, "active_radius"),
        ({"paths": (((1.0, 1.0), (5.0, 1.0)),)}, "pedestrians"),  # 40 pedestrians, 1 path
        ({"paths": "nowhere", "pedestrians": 1}, "paths"),
        ({"robot": "R2D2"}, "robot"),
    ],
)
def test_bad_crowds_name_the_parameter(kwargs, name):
    kw = {"pedestrians": 40, **kwargs}
    if "density" in kw:
        kw.pop("pedestrians")
    with pytest.raises(InvalidParameterError, match=name):
        nav.crowd("corridor_counterflow", **kw)


def test_unknown_layout_and_both_counts():
    with pytest.raises(InvalidParameterError, match="layout"):
        nav.crowd("stadium", 10)
    with pytest.raises(InvalidParameterError, match="density"):
        nav.crowd("open_plaza", 10, density=0.2, width=10.0, length=10.0)


def test_bottleneck_narrower_than_two_critical_distances_is_refused():
    with pytest.raises(InvalidParameterError, match="bottleneck_width"):
        nav.crowd("bottleneck", 10, bottleneck_width=0.5)


def test_bad_run_arguments():
    c = nav.crowd("corridor_counterflow", 5, length=10.0, horizon=0.12)
    with pytest.raises(InvalidParameterError, match="order"):
        nav.crowds.simulate_crowd(c, GAINS, order="sideways")
    with pytest.raises(InvalidParameterError, match="method"):
        nav.simulate(c, GAINS, method="teleport")
    with pytest.raises(InvalidParameterError, match="gains"):
        nav.simulate(c, nav.MasoudGains())
    with pytest.raises(InvalidParameterError, match="dynamics_step"):
        nav.simulate(c, GAINS, dynamics_step=0.004)  # does not divide the 0.01 s step
    with pytest.raises(InvalidParameterError, match="crowd"):
        nav.simulate_pedestrians("corridor")
    with pytest.raises(InvalidParameterError, match="crowd"):
        nav.crowds.simulate_crowd(nav.configuration(1), GAINS)


def test_paths_refused_by_jupedsim_name_the_path():
    with pytest.raises(InvalidParameterError, match=r"paths\[1\]"):
        nav.simulate_pedestrians(
            nav.crowd(
                "open_plaza",
                2,
                width=10.0,
                length=10.0,
                horizon=0.1,
                paths=(((5.0, 5.0), (8.0, 5.0)), ((5.1, 5.0), (8.0, 6.0))),
            )
        )


@pytest.mark.parametrize("method", ["vff", "masoud", "ge_cui", "cbf"])
def test_every_method_runs_in_a_crowd_and_reports_its_outcome(method):
    c = nav.crowd("crossing", 8, width=4.0, length=12.0, seed=2, horizon=0.6)
    gains = {"vff": GAINS, "cbf": GAINS}.get(method)
    res = nav.simulate(c, gains, method=method)
    assert res.method == method and res.status in ("ok", "not_arrived")
    assert math.isfinite(res.min_wall_distance) and res.robot_positions.shape == (61, 2)
    assert res.to_frame().shape[0] == 1


def test_scenario_options_that_do_not_apply_to_a_crowd_are_refused():
    c = nav.crowd("corridor_counterflow", 5, length=10.0, horizon=0.12)
    for kw in ({"jit": True}, {"noise": nav.SensorNoise()}, {"weights": (0.5, 0.5, 0.0)}):
        with pytest.raises(InvalidParameterError, match=next(iter(kw))):
            nav.simulate(c, GAINS, **kw)
    assert nav.simulate(c, GAINS, jit=False).status == "not_arrived"  # defaults pass


def test_a_density_that_does_not_match_the_number_is_refused():
    c = nav.crowd("open_plaza", density=0.2, width=10.0, length=10.0)
    with pytest.raises(InvalidParameterError, match="pedestrians"):
        c.replace(width=12.0)  # the area changed, the number did not
    assert c.replace(seed=3).pedestrians == 20


# --------------------------------------------------------------------------- issue 41
from designlab.navigation.crowds.study import crowd_study  # noqa: E402

SMALL = {"length": 10.0, "seed": 2, "horizon": 0.3}


@pytest.mark.parametrize(
    ("cbf_gains", "match"),
    [
        ((math.nan, 4.0), r"cbf_gains\[0\]"),
        ((-4.0, 4.0), r"cbf_gains\[0\]"),
        ((1e300, 4.0), r"cbf_gains\[0\]"),
        ((4.0, math.inf), r"cbf_gains\[1\]"),
        ((4.0, "4"), r"cbf_gains\[1\]"),
        ("ab", "cbf_gains"),
        ((4.0,), "cbf_gains"),
        (None, "cbf_gains"),
    ],
)
@pytest.mark.parametrize("method", ["cbf", "vff"])
def test_crowd_runs_check_cbf_gains_as_simulate_does(cbf_gains, match, method):
    """Crowd runs accepted NaN, -4 and 1e300 (and 'ab' was a traceback): the same
    declarations as plain simulate refuse them, before any pedestrian moves."""
    c = nav.crowd("corridor_counterflow", 4, **SMALL)
    with pytest.raises(InvalidParameterError, match=match):
        nav.simulate(c, GAINS, method=method, cbf_gains=cbf_gains)
    with pytest.raises(InvalidParameterError, match=match):  # the same as without a crowd
        nav.simulate(nav.configuration(1), GAINS, method=method, cbf_gains=cbf_gains)


@pytest.mark.parametrize("method", ["vff_cbf", "vo", "field_dstar", "VFF", "", 3, None])
def test_crowd_runs_refuse_a_method_they_do_not_simulate(method):
    """method="vff_cbf" ran plain VFF among a crowd, silently: every method a crowd does not
    simulate is refused naming the allowed ones (as the navigation_crowds study file does)."""
    from designlab.navigation.crowds.simulate import CROWD_METHOD

    c = nav.crowd("corridor_counterflow", 4, **SMALL)
    with pytest.raises(InvalidParameterError, match="method") as exc:
        nav.simulate(c, GAINS, method=method)
    assert all(m in str(exc.value) for m in CROWD_METHOD.choices)
    with pytest.raises(InvalidParameterError, match="method"):
        crowd_study(["corridor_counterflow"], [0.1], [0], [f"{method}:x"])


def test_the_study_file_and_python_allow_the_same_crowd_methods():
    import typing

    from designlab.navigation.crowds.simulate import CROWD_METHOD
    from designlab.study.kinds.navigation_crowds import CrowdMethodSpec

    assert set(typing.get_args(CrowdMethodSpec.model_fields["method"].annotation)) == set(
        CROWD_METHOD.choices
    )


def test_one_neighbour_slot_runs_among_a_dense_crowd():
    """neighbours=1 raised ValueError (unpacking the pairs of one slot) once two pedestrians
    were inside r2: with one slot no pair of slots can overlap, the run goes on."""
    c = nav.crowd("corridor_counterflow", 20, length=10.0, seed=2, horizon=3.0, neighbours=1)
    res = nav.simulate(c, GAINS)
    assert res.robot_positions.shape == (301, 2)  # 3 s at the 10 ms pedestrian step
    assert np.isfinite(res.robot_positions).all()
    assert res.critical_overlaps >= 0 and res.status in ("arrived", "not_arrived", "collision")


@pytest.mark.parametrize(
    ("options", "key"),
    [({"lenght": 8.0}, "lenght"), ({"seed": 3}, "seed"), ({"density": 0.2}, "density")],
)
def test_crowd_study_names_an_unknown_or_grid_crowd_option(options, key):
    """crowd_options={'lenght': 8} was a TypeError: the key is named with the allowed ones."""
    with pytest.raises(InvalidParameterError, match="crowd_options") as exc:
        crowd_study(["corridor_counterflow"], [0.1], [0], ["vff"], crowd_options=options)
    assert repr(key) in str(exc.value) and "length" in str(exc.value)
    with pytest.raises(InvalidParameterError, match="crowd_options"):
        crowd_study(["corridor_counterflow"], [0.1], [0], ["vff"], crowd_options=[1])


def test_crowd_names_an_unknown_keyword():
    with pytest.raises(InvalidParameterError, match=r"'lenght'.*allowed: .*length"):
        nav.crowd("corridor_counterflow", 4, lenght=8.0)


def test_crowd_study_checks_its_confidence_before_any_run():
    """confidence=2 ran the whole study and then failed in the summary."""
    for conf in (2.0, 0.0, math.nan, "0.9"):
        with pytest.raises(InvalidParameterError, match="confidence"):
            crowd_study(["bottleneck"], [0.1], [0], confidence=conf)


def test_crowd_measures_name_a_bad_track():
    from designlab.navigation.crowds import metrics as M

    with pytest.raises(InvalidParameterError, match="robot"):
        M.clearance([[math.nan, 0.0]], [[[1.0, 0.0]]])  # was inf, silently
    with pytest.raises(InvalidParameterError, match="pedestrians"):
        M.clearance([[0.0, 0.0]], [[[math.inf, 0.0]]])
    assert M.clearance([[0.0, 0.0]], [[[3.0, 4.0], [math.nan, math.nan]]]).tolist() == [5.0]
    with pytest.raises(InvalidParameterError, match="path"):
        M.point_to_path([[0.0, 0.0]], [[0.0, 0.0], [math.nan, 1.0]])  # was nan, silently
    with pytest.raises(InvalidParameterError, match="path"):
        M.point_to_path([[0.0, 0.0]], np.zeros((0, 2)))


@pytest.mark.parametrize("frame", ["runs", {"method": ["vff"]}])
def test_run_tables_name_what_is_missing(frame):
    import pandas as pd

    from designlab.navigation.crowds.study import representative_run, summarise_runs, worst_run

    runs = pd.DataFrame(frame) if isinstance(frame, dict) else frame
    for call in (
        lambda: summarise_runs(runs),
        lambda: worst_run(runs, "vff"),
        lambda: representative_run(runs, "vff"),
    ):
        with pytest.raises(InvalidParameterError, match="runs"):
            call()


def test_diagnosis_and_faced_crowd_need_a_crowd_run():
    import pandas as pd

    from designlab.navigation.crowds.diagnosis import force_breakdown, stall_summary
    from designlab.navigation.crowds.faced import faced_by

    for call in (lambda: force_breakdown("run"), lambda: faced_by("run")):
        with pytest.raises(InvalidParameterError, match="result"):
            call()
    with pytest.raises(InvalidParameterError, match="frame"):
        stall_summary(pd.DataFrame({"x": [1.0]}), 0.7)
    c = nav.crowd("corridor_counterflow", 4, **SMALL)
    frame = force_breakdown(nav.simulate(c, GAINS))
    with pytest.raises(InvalidParameterError, match="max_speed"):
        stall_summary(frame, math.nan)
    assert 0.0 <= stall_summary(frame, 0.7)["stopped"] <= 1.0


@pytest.mark.parametrize("horizon", [1e-300, 0.01, 0.059])
def test_a_crowd_horizon_shorter_than_a_period_is_refused(horizon):
    """horizon: 1e-300 gave a run of no period and a NaN measured density with status ok."""
    with pytest.raises(InvalidParameterError, match="horizon"):
        nav.crowd("corridor_counterflow", 4, length=10.0, horizon=horizon)
    nav.crowd("corridor_counterflow", 4, length=10.0, horizon=0.06)


def test_an_audit_that_never_applies_says_so():
    """A run that never enters an active region has an undefined share (nan) and a warning."""
    sc = nav.configuration(1).replace(obstacles=())
    res = nav.simulate(sc, GAINS)
    assert math.isnan(res.stability.share_satisfied)
    assert any("never entered an active region" in w for w in res.stability.warnings)
