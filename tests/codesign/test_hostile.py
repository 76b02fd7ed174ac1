"""Hostile inputs to the co-design layer: each fails early, naming the parameter."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy import stats

import designlab as dl
from designlab.errors import DesignlabError, InvalidParameterError
from designlab.impact import FOAM_1, HEAD_MIN, MANIPULATOR_1, HeadAcceleration, LinkImpact

cd = dl.codesign
RAYLEIGH = stats.rayleigh(scale=1.0)


def _raises(name, fn, *args, **kwargs):
    with pytest.raises(InvalidParameterError) as exc:
        fn(*args, **kwargs)
    assert isinstance(exc.value, DesignlabError) and isinstance(exc.value, ValueError)
    assert name in str(exc.value)
    return exc.value


# --- speed_limit -----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"human_speed": math.nan}, "human_speed"),
        ({"human_speed": -1.0}, "human_speed"),
        ({"human_speed": math.inf}, "human_speed"),
        ({"reaction_time": -0.1}, "reaction_time"),
        ({"reaction_time": math.nan}, "reaction_time"),
        ({"deceleration": 0.0}, "deceleration"),
        ({"detection_distance": -1.0}, "detection_distance"),
        ({"detection_distance": 1e9}, "detection_distance"),
        ({"head_levels": 1}, "head_levels"),
        ({"head_levels": 10**6}, "head_levels"),
        ({"head_levels": 2.5}, "head_levels"),
        ({"head_range": (4.4, 5.3)}, "head_range"),
        ({"criteria": "a_h"}, "criteria"),
        ({"criteria": [1.0]}, "criteria"),
        ({"criteria": [dl.impact.CompressionLimit(0.02)]}, "criteria"),
    ],
)
def test_speed_limit_bad_settings(kwargs, name):
    # a bound is refused when the case is declared, a criterion or range when it is used
    _raises(name, lambda: cd.speed_limit(MANIPULATOR_1, FOAM_1, cd.SafetyCase(**kwargs)))


@pytest.mark.parametrize("case", ["ISO", {"human_speed": 1.0}, 1.0, [HeadAcceleration(10)]])
def test_the_case_is_a_safety_case(case):
    _raises("case", cd.speed_limit, MANIPULATOR_1, FOAM_1, case)
    _raises("case", cd.speed_limit_map, MANIPULATOR_1, K_c=[1e4], C_c=[50.0], case=case)
    _raises("case", cd.foam_limits, MANIPULATOR_1, [1e4], [50.0], [0.02], [0.03], case)


def test_speed_limit_bad_robot_and_foam():
    _raises("robot", cd.speed_limit, "MANIPULATOR_1", FOAM_1)
    _raises("foam", cd.speed_limit, MANIPULATOR_1, {"stiffness": 1e4})
    _raises("foam", cd.speed_limit, MANIPULATOR_1, None)


def test_contradictory_bounds():
    _raises("HeadRange.mass", dl.impact.HeadRange, mass=(5.3, 4.4))
    _raises("lever_arm_max", LinkImpact, 0.05, 1e3, 10.0, 1.0, 0.1, 0.05)


# --- speed_limit_map -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"K_c": [], "C_c": [50.0]}, "K_c"),
        ({"K_c": [1e4], "C_c": []}, "C_c"),
        ({"K_c": [math.nan], "C_c": [50.0]}, "K_c"),
        ({"K_c": [1e4], "C_c": [-1.0]}, "C_c"),
        ({"K_c": [-1e4], "C_c": [1.0]}, "K_c"),
        ({"K_c": np.linspace(1e3, 1e5, 401), "C_c": [1.0]}, "len(K_c)"),
        ({"K_c": "soft", "C_c": [1.0]}, "K_c"),
        ({"K_c": [1e4], "C_c": [1.0], "linear_depth": 0.0}, "linear_depth"),
        ({"K_c": [1e4], "C_c": [1.0], "case": "v_h = 1"}, "case"),
    ],
)
def test_map_bad_input(kwargs, name):
    _raises(name, cd.speed_limit_map, MANIPULATOR_1, **kwargs)


def test_map_refuses_a_link():
    link = LinkImpact.from_contact(MANIPULATOR_1, joint_speed=1.0, lever_arm_min=0.02,
                                   lever_arm_max=0.078)  # fmt: skip
    _raises("robot", cd.speed_limit_map, link, K_c=[1e4], C_c=[50.0])


# --- injury_probability ----------------------------------------------------------------


@pytest.mark.parametrize(
    ("speeds", "name"),
    [
        (np.array([]), "closing_speed"),
        (np.array([1.0, math.nan]), "closing_speed"),
        (np.array([1.0, math.inf]), "closing_speed"),
        (np.array([-1.0, 0.0]), "closing_speed"),
        (stats.uniform(-2.0, 1.0), "closing_speed"),
        ("fast", "closing_speed"),
        (np.array([True, False]), "closing_speed"),
    ],
)
def test_bad_closing_speeds(speeds, name):
    _raises(name, cd.injury_probability, MANIPULATOR_1, FOAM_1, speeds, samples=10)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"samples": 0}, "samples"),
        ({"samples": 10**12}, "samples"),
        ({"samples": 100.5}, "samples"),
        ({"method": "Subset"}, "method"),
        ({"confidence": 1.0}, "confidence"),
        ({"confidence": math.nan}, "confidence"),
        ({"seed": -1}, "seed"),
        ({"criterion": "a_h <= 10 g"}, "criterion"),
        ({"heads": (4.4, 5.3)}, "heads"),
        ({"points": stats.uniform(0.0, 0.1)}, "points"),
    ],
)
def test_risk_bad_settings(kwargs, name):
    _raises(name, cd.injury_probability, MANIPULATOR_1, FOAM_1, RAYLEIGH, **kwargs)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"mass": stats.norm(4.8, 0.3)}, "HeadPopulation.mass"),  # reaches M_h <= 0
        ({"mass": stats.uniform(-1.0, 6.0)}, "HeadPopulation.mass"),
        ({"mass": stats.uniform(0.0, 5.0)}, "HeadPopulation.mass"),  # M_h = 0 is in the support
        ({"mass": -4.4}, "HeadPopulation.mass"),
        ({"mass": math.nan}, "HeadPopulation.mass"),
        ({"stiffness": stats.norm(4e3, 500.0)}, "HeadPopulation.stiffness"),
        ({"damping": stats.expon(loc=-1.0)}, "HeadPopulation.damping"),
        ({"damping": "soft"}, "HeadPopulation.damping"),
    ],
)
def test_population_refuses_non_physical_support(kwargs, name):
    base = {"mass": 4.8, "stiffness": 4e3, "damping": 80.0}
    err = _raises(name, cd.HeadPopulation, **{**base, **kwargs})
    if "support" in str(err.value):
        assert "truncnorm" in str(err)


def test_points_outside_the_link():
    link = LinkImpact.from_contact(MANIPULATOR_1, joint_speed=1.0, lever_arm_min=0.02,
                                   lever_arm_max=0.078)  # fmt: skip
    _raises("points", cd.injury_probability, link, FOAM_1, RAYLEIGH,
            points=stats.uniform(0.0, 0.078), samples=10)  # fmt: skip
    _raises("points", cd.injury_probability, link, FOAM_1, RAYLEIGH, points=0.05, samples=10)


def test_a_fixed_head_with_a_criterion_far_out_gives_zero():
    risk = cd.injury_probability(MANIPULATOR_1, FOAM_1, np.array([0.1, 0.2]), heads=HEAD_MIN,
                                 criterion=HeadAcceleration(500), samples=10)  # fmt: skip
    assert risk.probability == 0.0 and risk.status == "ok"


@pytest.mark.parametrize(
    ("speeds", "name"),
    [
        ([], "speeds"),
        ([1.0, math.nan], "speeds"),
        ([0.0], "speeds"),
        ([-1.0], "speeds"),
        ([25.0], "speeds"),
        (np.ones(10_001), "len(speeds)"),
    ],
)
def test_fragility_bad_speeds(speeds, name):
    _raises(name, cd.fragility_curve, MANIPULATOR_1, FOAM_1, speeds, samples=10)


def test_fragility_speed_at_bad_probability():
    curve = cd.fragility_curve(MANIPULATOR_1, FOAM_1, [1.0], heads=HEAD_MIN, samples=10)
    _raises("probability", curve.speed_at, 0.0)
    _raises("probability", curve.speed_at, math.nan)


# --- front_sensitivity -----------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"samples": 3}, "samples"),
        ({"samples": 0}, "samples"),
        ({"samples": 2**20}, "samples"),
        ({"samples": math.nan}, "samples"),
        ({"objectives": ("speed",)}, "objectives"),
        ({"objectives": ()}, "objectives"),
        ({"measure": "fast"}, "measure"),
        ({"criterion": "10 g"}, "criterion"),
        ({"risk_samples": 1}, "risk_samples"),
        ({"space": {"speed_min": 0.5}}, "space"),
        (
            {
                "space": cd.DesignSpace(
                    **{
                        f"{n}_max": getattr(cd.DesignSpace(), f"{n}_min")
                        for n in cd.DesignSpace.NAMES[1:]
                    }
                )
            },
            "space",
        ),
    ],
)
def test_front_sensitivity_bad_settings(kwargs, name):
    import designlab.navigation as nav

    _raises(name, cd.front_sensitivity, [nav.configuration(2)], **kwargs)


def test_front_sensitivity_bad_scenarios():
    _raises("scenarios", cd.front_sensitivity, [])
    _raises("scenarios", cd.front_sensitivity, ["configuration 2"])


# --- issue 41: the braking model, designs, the search and the contacts ---------------------
@pytest.mark.parametrize(
    ("args", "name"),
    [
        ((1.0, 0.1, 0.0), "deceleration"),  # was a ZeroDivisionError
        ((1.0, -1.0, 5.0), "reaction_time"),  # was -0.9 m
        ((math.nan, 0.1, 5.0), "speed"),
        ((1e300, 0.1, 5.0), "speed"),
        ((-1.0, 0.1, 5.0), "speed"),
        (("1", 0.1, 5.0), "speed"),
        ((1.0, math.inf, 5.0), "reaction_time"),
        ((1.0, 0.1, 1e9), "deceleration"),
    ],
)
def test_stopping_distance_refuses_what_its_declarations_refuse(args, name):
    _raises(name, cd.stopping_distance, *args)


def test_stopping_distance_is_the_closed_form():
    assert cd.stopping_distance(1.0, 0.1, 5.0) == 1.0 * 0.1 + 1.0 / 10.0
    assert cd.stopping_distance(0.0, 0.1, 5.0) == 0.0


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"speed": math.nan}, "speed"),
        ({"human_speed": -1.0}, "human_speed"),
        ({"reaction_time": -0.1}, "reaction_time"),
        ({"deceleration": 0.0}, "deceleration"),
        ({"detection_distance": math.inf}, "detection_distance"),
    ],
)
def test_contact_speed_checks_every_argument(kwargs, name):
    base = {"speed": 1.0, "human_speed": 1.0, "reaction_time": 0.1, "deceleration": 5.0,
            "detection_distance": 0.6}  # fmt: skip
    _raises(name, cd.contact_speed, **{**base, **kwargs})


@pytest.mark.parametrize(
    ("u", "kwargs", "name"),
    [
        (math.nan, {}, "contact_limit"),
        (-1.0, {}, "contact_limit"),
        (1e300, {}, "contact_limit"),
        (0.5, {"deceleration": -5.0}, "deceleration"),
        (0.5, {"human_speed": math.nan}, "human_speed"),
    ],
)
def test_max_robot_speed_checks_every_argument(u, kwargs, name):
    base = {"human_speed": 1.0, "reaction_time": 0.1, "deceleration": 5.0,
            "detection_distance": 0.6}  # fmt: skip
    _raises(name, cd.max_robot_speed, u, **{**base, **kwargs})


def test_the_largest_speed_limit_is_a_braking_speed():
    """The braking speed's bound admits every speed limit the declarations allow."""
    from designlab.codesign.parameters import BRAKING_SPEED, CONTACT_LIMIT, DECELERATION
    from designlab.codesign.parameters import DETECTION_DISTANCE as D

    v = cd.max_robot_speed(CONTACT_LIMIT.le, human_speed=0.0, reaction_time=0.0,
                           deceleration=DECELERATION.le, detection_distance=D.le)  # fmt: skip
    assert v == pytest.approx(math.sqrt(CONTACT_LIMIT.le**2 + 2 * DECELERATION.le * D.le))
    assert cd.stopping_distance(v, 0.0, DECELERATION.le) == pytest.approx(D.le + 2.0)
    assert BRAKING_SPEED.within(v)


@pytest.mark.parametrize(
    ("make", "name"),
    [
        (lambda: cd.Design(FOAM_1, math.nan, dl.navigation.EXPERIMENT_GAINS), "Design.speed"),
        (lambda: cd.Design(FOAM_1, -1.0, dl.navigation.EXPERIMENT_GAINS), "Design.speed"),
        (lambda: cd.Design(FOAM_1, 1e300, dl.navigation.EXPERIMENT_GAINS), "Design.speed"),
        (lambda: cd.Design("foam", 0.7, dl.navigation.EXPERIMENT_GAINS), "Design.foam"),
        (lambda: cd.Design(FOAM_1, 0.7, (3.0, 0.25, 20.0, 17.0)), "Design.gains"),
        (lambda: cd.Design.from_vector([1.0, 2.0]), "x"),
        (lambda: cd.evaluate_design("thesis", [dl.navigation.configuration(2)]), "design"),
        (
            lambda: cd.evaluate_design(
                cd.THESIS_DESIGN, [dl.navigation.configuration(2)], risk_samples=10**12
            ),
            "risk_samples",
        ),
        (
            lambda: cd.evaluate_design(
                cd.THESIS_DESIGN, [dl.navigation.configuration(2)], robot="arm"
            ),
            "robot",
        ),
        (
            lambda: cd.evaluate_design(cd.THESIS_DESIGN, [dl.navigation.configuration(2)] * 101),
            "scenarios",
        ),
        (lambda: cd.pareto(dl.navigation.configuration(2), crowds="plaza"), "crowds"),
        (lambda: cd.pareto(dl.navigation.configuration(2), seed=-1), "seed"),
    ],
)
def test_designs_and_their_scores_check_their_inputs(make, name):
    _raises(name, make)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"lower": [1.0], "upper": [0.0]}, "lower[0]"),
        ({"lower": [math.nan], "upper": [1.0]}, "lower"),
        ({"lower": [0.0, 0.0], "upper": [1.0]}, "upper"),
        ({"n_obj": 0}, "n_obj"),
        ({"n_constr": -1}, "n_constr"),
        ({"evaluate": 3}, "evaluate"),
        ({"evaluate": lambda x: (np.array([math.nan]), np.zeros(0))}, "evaluate"),
        ({"evaluate": lambda x: (np.zeros(3), np.zeros(0))}, "evaluate"),
        ({"evaluate": lambda x: np.zeros(1)}, "evaluate"),
    ],
)
def test_nsga2_refuses_an_empty_box_and_wrong_answers(kwargs, name):
    base = {"evaluate": lambda x: (np.array([float(x[0])]), np.zeros(0)), "lower": [0.0],
            "upper": [1.0], "n_obj": 1, "population": 4, "generations": 1}  # fmt: skip
    args = {**base, **kwargs}
    _raises(name, cd.nsga2, args.pop("evaluate"), args.pop("lower"), args.pop("upper"), **args)


def test_nondominated_refuses_text_and_an_unbounded_comparison():
    _raises("F", cd.nondominated, "ab")
    _raises("F", cd.nondominated, np.zeros((10**5, 2)))  # 2e10 comparisons
    assert cd.nondominated([[0.0, math.inf], [1.0, 0.0]]).tolist() == [True, True]


def test_navigation_contacts_name_unknown_obstacles_and_options():
    """An obstacle name that is none of the scenarios' discs gave an empty answer; an
    unknown simulate option was a TypeError after the first run."""
    sc = dl.navigation.configuration(1)
    gains = dl.navigation.EXPERIMENT_GAINS
    e = _raises("obstacles", cd.navigation_contacts, sc, gains, obstacles="human")
    assert "circle" in str(e)
    e = _raises("simulate_options", cd.navigation_contacts, sc, gains, stabilize="off")
    assert "stabilising" in str(e)
    _raises("scenarios", cd.navigation_contacts, "configuration 1", gains)
    _raises("measure", cd.navigation_contacts, sc, gains, measure="speed")


def test_design_sobol_names_a_metric_that_is_not_a_finite_number():
    space = cd.DesignSpace()
    _raises("metric", cd.design_sobol, 3, space, samples=2)
    _raises("metric['a']", cd.design_sobol, lambda d: {"a": math.nan}, space, samples=2)
    _raises("metric", cd.design_sobol, lambda d: [1.0], space, samples=2)


@pytest.mark.parametrize(
    ("call", "name", "shown"),
    [
        (
            lambda: cd.fragility_curve(
                MANIPULATOR_1, FOAM_1, [[1.0, 2.0], [3.0, 4.0]], samples=100
            ),
            "speeds",
            "flat",
        ),  # was accepted
        (
            lambda: cd.fragility_curve(MANIPULATOR_1, FOAM_1, [True, False], samples=100),
            "speeds",
            "booleans",
        ),  # named 0.0, not the booleans
        (lambda: cd.speed_limit_map(MANIPULATOR_1, K_c=None, C_c=[50.0]), "K_c", "None"),
        (lambda: cd.speed_limit_map(MANIPULATOR_1, K_c=[True], C_c=[50.0]), "K_c", "True"),
        (lambda: cd.speed_limit_map(MANIPULATOR_1, K_c=[[1e4]], C_c=[50.0]), "K_c", "flat"),
        (
            lambda: cd.injury_probability(MANIPULATOR_1, FOAM_1, -1.0, samples=100),
            "closing_speed",
            "[-1.0]",
        ),  # named '1 samples', not the value
    ],
)
def test_errors_show_the_value_given(call, name, shown):
    e = _raises(name, call)
    assert shown in str(e)


# --- issue 41: sample counts that run in reasonable time ---------------------------------


@pytest.mark.parametrize("samples", [10**8, 2_000_001])
def test_sample_counts_beyond_the_declared_cap_are_refused(samples) -> None:
    """``samples=1e8`` was admitted and ran far beyond 20 s; the cap is 2e6 (about 6 s)."""
    from designlab.codesign.parameters import RISK_SAMPLES

    assert RISK_SAMPLES.le == 2_000_000
    with pytest.raises(InvalidParameterError, match=rf"samples = {samples} .*<= 2e\+06"):
        dl.codesign.injury_probability(MANIPULATOR_1, FOAM_1, 1.0, samples=samples)
    with pytest.raises(InvalidParameterError, match=rf"samples = {samples} .*<= 2e\+06"):
        dl.codesign.fragility_curve(MANIPULATOR_1, FOAM_1, speeds=[0.5, 1.0], samples=samples)


def test_subset_simulation_has_its_own_cap_per_level() -> None:
    """Up to 20 levels of ``samples`` evaluations each: 1e5 per level is about 10 s."""
    from designlab.codesign.parameters import SUBSET_SAMPLES

    with pytest.raises(InvalidParameterError, match=r"samples \(per level .*\) = 100001"):
        dl.codesign.injury_probability(
            MANIPULATOR_1, FOAM_1, 1.0, samples=SUBSET_SAMPLES.le + 1, method="subset"
        )


def test_long_runs_report_progress_between_blocks() -> None:
    """The blocks are Python-level steps: a progress callback (or Ctrl-C) acts between them."""
    from designlab.codesign.risk import BLOCK

    steps: list[int] = []
    dl.codesign.fragility_curve(MANIPULATOR_1, FOAM_1, speeds=[1.0], samples=BLOCK + 10,
                                progress=lambda p: steps.append(p.step))  # fmt: skip
    assert steps == [1, 2]


@pytest.mark.parametrize(
    ("where", "field", "value"),
    [("robot", "damping", 1e6), ("foam", "damping", 1e6), ("robot", "damping", 1e300)],
)
def test_speed_limit_refuses_what_double_precision_cannot_serve_by_name(
    where, field, value
) -> None:
    """A damping of 1e6 N s/m gave NaN metrics, then ``contact_limit = nan`` was refused;
    now the robot's or the foam's parameter is named up front with its value."""
    import dataclasses

    args = {"robot": MANIPULATOR_1, "foam": FOAM_1}
    args[where] = dataclasses.replace(args[where], **{field: value})
    with pytest.raises(InvalidParameterError) as err:
        dl.codesign.speed_limit(args["robot"], args["foam"])
    assert (err.value.name, err.value.value) == (f"{where}.{field}", value)
    assert "nan" not in str(err.value) and "at most 10000" in str(err.value)


@pytest.mark.parametrize(
    ("field", "value", "effective"),
    [("joint_damping", 1e7, "C_J/l^2 = 1e+13"), ("joint_damping", 1e6, "C_J/l^2 = 1e+14")],
)
def test_speed_limit_of_a_link_names_the_links_own_parameter(field, value, effective) -> None:
    """A link's conditioning refusal named ``params[0].C_r`` (the effective row of the
    kernel batch); it names the link's own field with the value given, and the lever arm."""
    base = {"inertia": 0.5, "joint_stiffness": 100.0, "joint_damping": 10.0,
            "joint_speed": 3.0, "lever_arm_min": 0.001, "lever_arm_max": 0.5}  # fmt: skip
    link = LinkImpact(**{**base, field: value})
    if value == 1e6:
        link = dataclasses.replace(link, lever_arm_min=1e-4)
    with pytest.raises(InvalidParameterError) as err:
        dl.codesign.speed_limit(link, FOAM_1)
    assert (err.value.name, err.value.value) == (f"robot.{field}", value)
    text = str(err.value)
    assert "params[" not in text and f"l = {link.lever_arm_min:g} m" in text and effective in text
    assert "at most 10000" in text


def test_speed_limit_refuses_an_impact_lobe_that_does_not_end() -> None:
    """A nearly undamped, very stiff robot: its metrics are NaN (``lobe_not_closed``); the
    link's Brent search raised scipy's 'function value at x=0.0 is NaN' and a fixed robot
    'contact_limit = nan'; both now name the robot's inputs and the status."""
    fixed = dl.impact.ContactDynamics(mass=2.0, damping=40.0, stiffness=4e9)
    link = LinkImpact(0.5, 1e9, 10.0, 3.0, 0.001, 0.5)
    cases = ((fixed, "robot.stiffness = 4e+09"), (link, "robot.joint_stiffness = 1e+09"))
    for robot, shown in cases:
        with pytest.raises(dl.errors.ModelError) as err:
            dl.codesign.speed_limit(robot, FOAM_1)
        assert shown in str(err.value) and "lobe_not_closed" in str(err.value)


# --- the robot description and the ISO/TS 15066 comparison (issue 36.1, 36.4) -----------


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"radius": math.nan}, "radius"), ({"radius": -0.2}, "radius"),
        ({"radius": math.inf}, "radius"), ({"max_speed": 1e9}, "max_speed"),
        ({"max_speed": "fast"}, "max_speed"), ({"max_accel": -1.0}, "max_accel"),
        ({"mass": math.nan}, "mass"), ({"mass": 0.0}, "mass"), ({"mass": 1e300}, "mass"),
        ({"mass": True}, "mass"), ({"part": "elbow"}, "part"),
        ({"contact_low": -0.1}, "contact_low"), ({"contact_high": math.inf}, "contact_high"),
        ({"contact_low": 1.0, "contact_high": 0.5}, "contact_low"),
        ({"contact": None}, "contact"), ({"contact": FOAM_1}, "contact"),
        ({"contact": dataclasses.replace(MANIPULATOR_1, mass=50.0)}, "contact"),
    ],
)  # fmt: skip
def test_robot_description_refuses_hostile_fields_by_name(kwargs, name):
    err = _raises(name, cd.RobotDescription, "robot", **kwargs)
    shown = next(iter(kwargs.values())) if len(kwargs) == 1 else 1.0
    if isinstance(shown, float) and math.isfinite(shown):
        assert f"{shown:g}" in str(err) or repr(shown) in str(err)


def test_robot_description_refuses_a_name_that_is_no_text():
    _raises("name", cd.RobotDescription, 3.0)
    _raises("name", cd.RobotDescription, "")


@pytest.mark.parametrize(
    ("args", "name"),
    [
        (("robot", FOAM_1), "robot"), ((MANIPULATOR_1, FOAM_1), "robot"),
        ((cd.THESIS_ROBOT, FOAM_1, math.nan), "human_speed"),
        ((cd.THESIS_ROBOT, FOAM_1, -1.0), "human_speed"),
        ((cd.THESIS_ROBOT, FOAM_1, math.inf), "human_speed"),
        ((cd.THESIS_ROBOT, FOAM_1, "1"), "human_speed"),
        ((cd.THESIS_ROBOT, None), "foam"), ((cd.THESIS_ROBOT, "FOAM_1"), "foam"),
    ],
)  # fmt: skip
def test_iso_comparison_refuses_hostile_inputs_by_name(args, name):
    from designlab.codesign.assessment import iso_comparison

    _raises(name, iso_comparison, *args)


def test_iso_comparison_of_a_bumper_is_the_closed_form_per_region():
    # ISO/TS 15066 Annex A.3: v = F_T / sqrt(mu k), mu = (1/m_H + 1/m_R)^-1, for the 20 kg base
    from designlab.codesign.assessment import iso_comparison

    t = iso_comparison(cd.BUMPER_BASE, FOAM_1, human_speed=0.5)
    for name, r in t.iterrows():
        mu = 1.0 / (1.0 / r["m_H_kg"] + 1.0 / 20.0)
        assert r["iso_closing_speed_m_per_s"] == pytest.approx(
            r["F_T_N"] / math.sqrt(mu * r["k_N_per_m"]), rel=1e-14
        ), name
        assert r["iso_robot_speed_m_per_s"] == max(r["iso_closing_speed_m_per_s"] - 0.5, 0.0)
    assert t.loc["lower_leg", "share"] > 0.5  # a bumper at 0.1-0.5 m meets shins
