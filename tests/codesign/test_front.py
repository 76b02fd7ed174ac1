"""The Pareto front (issue 24, item 4): the non-dominated filter, the search, the design space."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as hst

import designlab as dl
import designlab.navigation as nav
from designlab.codesign import (
    THESIS_DESIGN,
    Design,
    DesignSpace,
    evaluate_design,
    nondominated,
    nsga2,
    pareto,
)
from designlab.errors import DesignlabError


def _brute_force(F: list[list[float]]) -> list[bool]:
    keep = []
    for i, a in enumerate(F):
        dominated = False
        for j, b in enumerate(F):
            pairs = list(zip(a, b, strict=True))
            if j != i and all(y <= x for x, y in pairs) and any(y < x for x, y in pairs):
                dominated = True
        keep.append(not dominated)
    return keep


@settings(max_examples=200, deadline=None)
@given(
    hst.integers(1, 4).flatmap(
        lambda m: hst.lists(
            hst.lists(hst.integers(0, 4).map(float), min_size=m, max_size=m),
            min_size=1,
            max_size=25,
        )
    )
)
def test_nondominated_equals_brute_force(F: list[list[float]]) -> None:
    # small integers make ties and duplicates frequent
    assert nondominated(np.array(F)).tolist() == _brute_force(F)


def _two_parabolas(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return np.array([x[0] ** 2, (x[0] - 2.0) ** 2]), np.array([1.0 - x[0]])


def test_search_finds_the_known_front() -> None:
    # min (x^2, (x-2)^2) s.t. x >= 1 on [-5, 5]: the front is x in [1, 2], where
    # f2 = (2 - sqrt(f1))^2 with f1 in [1, 4].
    out = nsga2(_two_parabolas, [-5.0], [5.0], n_obj=2, n_constr=1, population=16,
                generations=12, seed=3)  # fmt: skip
    ok = out.feasible
    assert ok.any() and (out.X[ok, 0] >= 1.0).all() and not (out.X[~ok, 0] >= 1.0).any()
    front = out.F[ok][nondominated(out.F[ok])]
    x = out.X[ok][nondominated(out.F[ok]), 0]
    assert (x >= 1.0).all() and (x <= 2.0 + 1e-9).all()
    np.testing.assert_allclose(front[:, 1], (2.0 - np.sqrt(front[:, 0])) ** 2, atol=1e-12)
    assert front[:, 0].min() < 1.1 and front[:, 0].max() > 3.5  # spread over the front
    again = nsga2(_two_parabolas, [-5.0], [5.0], n_obj=2, n_constr=1, population=16,
                  generations=12, seed=3)  # fmt: skip
    np.testing.assert_array_equal(out.X, again.X)  # seeded


def test_a_fixed_variable_is_not_searched() -> None:
    seen = []

    def f(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        seen.append(x[1])
        return np.array([x[0], 1.0 - x[0]]), np.zeros(0)

    out = nsga2(f, [0.0, 0.25], [1.0, 0.25], n_obj=2, population=6, generations=2, seed=0)
    assert set(seen) == {0.25} and out.X.shape == (12, 2)
    one = nsga2(f, [0.5, 0.25], [0.5, 0.25], n_obj=2, population=6, generations=2)
    assert one.X.tolist() == [[0.5, 0.25]]


def test_design_space_bounds_come_from_the_domains() -> None:
    space = DesignSpace()
    assert (space.lower < space.upper).all()
    with pytest.raises(DesignlabError, match=r"DesignSpace\.damping_min"):
        DesignSpace(damping_min=300.0, damping_max=100.0)
    with pytest.raises(DesignlabError, match=r"DesignSpace\.speed_max"):
        DesignSpace(speed_max=1e6)  # above the robot's declared speed cap
    with pytest.raises(DesignlabError, match=r"DesignSpace\.stiffness_min"):
        DesignSpace(stiffness_min=-1.0)
    v = THESIS_DESIGN.vector()
    assert Design.from_vector(v).vector().tolist() == v.tolist()
    with pytest.raises(DesignlabError, match=r"Design\.speed"):
        Design.from_vector([*v[:3], -1.0, *v[4:]])


def test_the_thesis_design_scores_as_its_runs() -> None:
    sc = nav.configuration(4)
    s = evaluate_design(THESIS_DESIGN, [sc])
    # V_mr = 0.7 m/s is the thesis's robot; the regions grow to the minimum for it
    run = nav.simulate(dl.codesign.sized_scenario(sc, sc.robot, 1.0), nav.EXPERIMENT_GAINS)
    assert s.arrival_time == run.arrival_time
    assert s.collisions == 0 and s.critical_entries == 0 and s.not_arrived == 0
    assert s.closing_speed == pytest.approx(s.contacts.relative_speed.max())
    assert 0.0 < s.required_thickness < THESIS_DESIGN.foam.thickness and s.feasible
    assert math.isnan(s.injury_probability)  # not asked for


def test_injury_objective_counts_the_encounters_above_the_limit() -> None:
    # A fixed head: the model is linear in v_c, so the criterion is exceeded exactly by the
    # encounters whose closing speed is above v* = limit / a_h,max(1 m/s); the exceedance
    # probability is their share (the closing speeds are the encounters' empirical law).
    # People only: the two scenarios' walking humans (the pole of configuration 4 is no
    # person), with the limit set between their two closing speeds.
    head = dl.impact.HEAD_MIN
    fixed = dl.impact.HeadRange(mass=(head.mass, head.mass),
                                stiffness=(head.stiffness, head.stiffness),
                                damping=(head.damping, head.damping))  # fmt: skip
    design = Design(dl.impact.FOAM_1, 0.7, nav.EXPERIMENT_GAINS)
    scs = [nav.configuration(2), nav.configuration(4)]
    met = evaluate_design(design, scs, heads=fixed, measure="approach").contacts
    assert met.obstacle == ("human", "human")
    lo, hi = sorted(met.samples)
    assert hi > 1.05 * lo  # the test means something: one encounter on each side
    unit = dl.impact.impact_metrics(
        {"M_r": 9.6, "C_r": 250.0, "K_r": 20.0e3, "K_c": 24.25e3, "C_c": 71.9,
         "M_h": head.mass, "C_h": head.damping, "K_h": head.stiffness}, 1.0,
    ).peak_head_acceleration_g[0]  # fmt: skip
    crit = dl.impact.HeadAcceleration(max_g=float(unit * (lo + hi) / 2))
    s = evaluate_design(design, scs, heads=fixed, measure="approach", criterion=crit,
                        risk_samples=20_000, seed=1)  # fmt: skip
    assert abs(s.exceedance_probability - 0.5) < 0.02


def test_pareto_front_is_feasible_and_non_dominated() -> None:
    seen = []
    front = pareto([nav.configuration(2)], objectives=("arrival_time", "foam_thickness"),
                   population=4, generations=2, seed=0, progress=seen.append)  # fmt: skip
    assert [p.step for p in seen] == [1, 2] and len(front.X) == 8
    assert front.front.any() and (front.feasible[front.front]).all()
    F = front.F[front.front]
    assert nondominated(F).all()
    for f in front.F[front.feasible]:  # every feasible design is matched or beaten on the front
        assert ((F <= f).all(axis=1)).any()
    table = front.to_frame()
    assert len(table) == front.front.sum() and table["arrival_time_s"].is_monotonic_increasing
    ref = front.reference_frame()
    assert ref["feasible"][0] and ref["distance_to_front"][0] >= 0.0
    assert front.reference_dominated_by == int(
        ((F <= front.reference_objectives).all(axis=1)
         & (F < front.reference_objectives).any(axis=1)).sum()
    )  # fmt: skip
    assert math.isnan(pareto([nav.configuration(2)], population=4, generations=1,
                             reference={}).reference_distance)  # fmt: skip


def test_bad_input_names_the_parameter() -> None:
    sc = [nav.configuration(2)]
    for kwargs, name in [
        ({"objectives": ("arrival_time",)}, "objectives"),
        ({"objectives": ("arrival_time", "beauty")}, "objectives"),
        ({"measure": "fast"}, "measure"),
        ({"population": 2}, "population"),
        ({"generations": 0}, "generations"),
        ({"seed": -1}, "seed"),
        ({"space": {"speed_min": 1}}, "space"),
        ({"reference": "thesis"}, "reference"),
    ]:
        with pytest.raises(DesignlabError, match=name):
            pareto(sc, **kwargs)
    with pytest.raises(DesignlabError, match="scenarios"):
        pareto([])
    with pytest.raises(DesignlabError, match="F"):
        nondominated([[np.nan, 1.0]])


@settings(max_examples=30, deadline=None)
@given(
    hst.sampled_from([n for n in DesignSpace.NAMES]).flatmap(
        lambda n: hst.tuples(
            hst.just(n),
            hst.sampled_from(["min", "max"]),
            hst.one_of(
                hst.sampled_from([math.nan, math.inf, -math.inf, -1.0, 0.0, 1e300]),
                hst.text(max_size=3),
                hst.none(),
            ),
        )
    )
)
def test_hostile_bounds_name_their_field(case: tuple[str, str, object]) -> None:
    name, end, value = case
    field = f"{name}_{end}"
    try:
        space = DesignSpace(**{field: value})
    except DesignlabError as exc:
        assert f"DesignSpace.{name}_" in str(exc)
        return
    assert np.isfinite(space.lower).all() and np.isfinite(space.upper).all()
    assert (space.lower <= space.upper).all()


def test_a_snapped_search_evaluates_and_keeps_only_snapped_points() -> None:
    # f(x) = ((x0 - 0.123)^2, (x0 - 0.5)^2) with x0 evaluated on a 0.01 grid: every point kept
    # is on the grid, and the grid point nearest 0.123 (0.12) is found
    from designlab.codesign.front import nsga2

    seen = []

    def f(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        seen.append(float(x[0]))
        return np.array([(x[0] - 0.123) ** 2, (x[0] - 0.5) ** 2]), np.zeros(0)

    out = nsga2(f, [0.0, 0.0], [1.0, 1.0], n_obj=2, population=12, generations=6, seed=3,
                snap=lambda X: np.c_[np.round(X[:, 0], 2), X[:, 1]])  # fmt: skip
    assert all(v == round(v, 2) for v in seen)
    assert np.array_equal(out.X[:, 0], np.round(out.X[:, 0], 2))
    assert out.X[np.argmin(out.F[:, 0]), 0] == 0.12


def test_the_design_space_snaps_the_speed_limit_to_a_hundredth_inside_the_box() -> None:
    box = dl.codesign.DesignSpace(speed_min=0.304, speed_max=1.5)
    X = np.array([[2e4, 50.0, 0.02, 0.3041, 3.0, 0.3, 20.0, 20.0],
                  [2e4, 50.0, 0.02, 0.7049, 3.0, 0.3, 20.0, 20.0]])  # fmt: skip
    got = box.snap(X)
    assert got[:, 3].tolist() == [0.304, 0.7]  # 0.30 would leave the box: clipped to its end
    assert np.array_equal(np.delete(got, 3, axis=1), np.delete(X, 3, axis=1))
