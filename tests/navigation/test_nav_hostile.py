"""Hostile inputs to the navigation domain (issue 18): every case a clear error naming the
parameter, a cap stated in the declarations (docs/navigation.md, "Limits"), or a finite
answer; the Python API and the study files enforce the same limits."""

from __future__ import annotations

import math
import pickle
import re
from pathlib import Path
from typing import Any

import jsonschema
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import designlab as dl
from designlab.errors import InvalidParameterError, StudyError
from designlab.params import params_of
from designlab.progress import Progress
from designlab.results import check_result
from designlab.study import RunContext, parse_study, run_study
from designlab.study.kinds import navigation_specs as specs

nav = dl.navigation
ROOT = Path(__file__).resolve().parents[2]
GAINS = nav.EXPERIMENT_GAINS

SCEN = """\
designlab: 1
kind: navigation_scenarios
name: hostile
scenarios:
  - name: corridor
    start: [4.0, 0.5]
    goal: [0.0, 0.5]
    obstacles:
      - {name: visitor, kind: disc, radius: 0.4, r2: 2.1, r3: 0.8,
         walk: {start: [0, 2], end: [4, 2], speed: 0.8}}
methods:
  - {label: "New VFF", gains: {k1: 3, b: 0.25, k3: 20, k5: 17}, stabilising: "off"}
"""


# ----------------------------------------------------------- the cases of issue 18


def test_a_robot_faster_than_light_is_refused_before_sizing() -> None:
    # was: OverflowError inside region_sizes
    with pytest.raises(InvalidParameterError, match=r"HolonomicRobot.max_speed = 1e\+300 m/s"):
        nav.region_sizes(nav.Human(), nav.HolonomicRobot(max_speed=1e300), sample_time=0.06)
    with pytest.raises(InvalidParameterError, match=r"HolonomicRobot.max_accel = 1e-300"):
        nav.HolonomicRobot(max_accel=1e-300)
    s = nav.region_sizes(nav.Human(), nav.HolonomicRobot(max_speed=5.0, max_accel=1e-3), 1.0)
    assert math.isfinite(s.r2) and s.r2 > s.r3  # at the caps: a finite, huge region


def test_a_long_horizon_and_a_big_batch_are_refused_before_computing() -> None:
    # were: hangs (nav.simulate with horizon=1e5, simulate_batch with 5000 gain sets)
    with pytest.raises(InvalidParameterError, match=r"Scenario.horizon = 100000.0 s .*<= 600"):
        nav.simulate(nav.configuration(1, horizon=1e5), GAINS)
    big = np.tile(GAINS.as_array(), (5000, 1))
    with pytest.raises(InvalidParameterError, match=r"gains \(number of gain sets\) = 5000"):
        nav.simulate_batch([nav.configuration(1)], big)
    with pytest.raises(InvalidParameterError, match=r"dynamics_step = 1e-06 s .* 1 to 1000"):
        nav.simulate(nav.configuration(1), GAINS, dynamics_step=1e-6)


def test_disc_regions_and_a_walk_of_length_zero_are_refused_by_validate_too() -> None:
    with pytest.raises(InvalidParameterError, match=r"Disc.r2 = 0.5 m .* Disc.r3 = 0.8"):
        nav.Disc("h", 0.4, r2=0.5, r3=0.8, motion=nav.Stationary((0, 0)))
    with pytest.raises(StudyError, match=r"Disc.r2 = 0.5 m .* Disc.r3 = 0.8"):
        parse_study(SCEN.replace("r2: 2.1", "r2: 0.5"))
    # a walk that ends where it starts: was blamed on Walk.ramp_time (or NaN with ramp 0)
    for ramp in (0.5, 0.0):
        with pytest.raises(InvalidParameterError, match=r"Walk.end = \(1.0, 1.0\) m .*differ"):
            nav.Walk((1.0, 1.0), (1.0, 1.0), ramp_time=ramp)
    with pytest.raises(StudyError, match=r"Walk.end"):
        parse_study(SCEN.replace("end: [4, 2]", "end: [0, 2]"))


@pytest.mark.parametrize("value, ok", [(10.0, False), (1.0, True), (0.5, True), (0.0, False)])
def test_sample_time_has_one_declaration_for_python_and_yaml(value: float, ok: bool) -> None:
    def python() -> None:
        nav.Scenario("x", (0.0, 0.0), (3.0, 0.0), sample_time=value)
        nav.region_sizes(nav.Human(), nav.HolonomicRobot(), sample_time=value)

    def yaml() -> None:
        parse_study(
            SCEN.replace(
                "    goal: [0.0, 0.5]\n", f"    goal: [0.0, 0.5]\n    sample_time: {value}\n"
            )
        )

    for attempt in (python, yaml):
        if ok:
            attempt()
        else:
            with pytest.raises((InvalidParameterError, StudyError), match="sample_time"):
                attempt()


def test_a_bare_off_is_the_stabilising_mode_off_in_every_navigation_kind() -> None:
    # YAML 1.1 reads an unquoted off as false; the navigation kinds read it as "off" (stated in
    # docs/navigation.md, "Study files"); any other boolean is refused naming the field
    study = parse_study(SCEN.replace('stabilising: "off"', "stabilising: off"))
    assert study.methods[0].stabilising == "off"
    with pytest.raises(StudyError, match="stabilising"):
        parse_study(SCEN.replace('stabilising: "off"', "stabilising: on"))
    sweep = parse_study(
        "designlab: 1\nkind: navigation_sweep\nname: s\nbase: {gains: {k1: 3, b: 0.25, k3: 20, "
        "k5: 17}, stabilising: off}\nsweep: {method: grid, parameters: {gains.k1: {values: [3]}}}\n"
    )
    assert sweep.base.stabilising == "off"
    gains = parse_study("designlab: 1\nkind: navigation_gains\nname: g\nmodes: [off]\n")
    assert gains.modes == ["off"]
    with pytest.raises(InvalidParameterError, match="stabilising = False"):
        nav.simulate(nav.configuration(1), GAINS, stabilising=False)  # type: ignore[arg-type]


class _Recording(RunContext):
    """A run context whose bars record what the solver reports."""

    def bar(self, desc: str, total: int | None = None):  # type: ignore[no-untyped-def,override]
        import contextlib

        seen = self.__dict__.setdefault("seen", [])

        @contextlib.contextmanager
        def hook():  # type: ignore[no-untyped-def]
            yield lambda info: seen.append((desc, info))

        return hook()


def test_navigation_gains_reports_generations_and_the_best_objective() -> None:
    seen: list[Progress] = []
    nav.optimise_gains([nav.configuration(1)], stabilising="off", popsize=4, max_evaluations=8,
                       refine=False, progress=seen.append)  # fmt: skip
    assert [p.label for p in seen] == ["generation", "generation"]
    assert seen[-1].step == 8 and seen[-1].total == 8 and seen[-1].best is not None
    study = parse_study(
        "designlab: 1\nkind: navigation_gains\nname: g\nmodes: [off]\nconfigurations: [1]\n"
        "validation: []\npopsize: 4\nmax_evaluations: 8\nrefine: false\nsensitivity: false\n"
    )
    ctx = _Recording()
    run_study(study, ctx)
    bars = {d for d, _ in ctx.seen}  # type: ignore[attr-defined]
    assert bars == {"navigation_gains: optimise (off)"}
    assert all(isinstance(p.best, float) for _, p in ctx.seen)  # type: ignore[attr-defined]


def test_ctrl_c_in_a_study_that_keeps_nothing_says_so(monkeypatch, tmp_path) -> None:  # type: ignore[no-untyped-def]
    from typer.testing import CliRunner

    import designlab.study as study_mod
    from designlab.cli import app

    def interrupted(*args: Any, **kw: Any) -> Any:
        raise KeyboardInterrupt

    monkeypatch.setattr(study_mod, "run_study", interrupted)
    path = tmp_path / "g.yaml"
    path.write_text("designlab: 1\nkind: navigation_gains\nname: g\nmodes: [off]\n")
    out = CliRunner().invoke(app, ["run", str(path), "--cache-dir", str(tmp_path / "c")])
    text = out.stderr if hasattr(out, "stderr") else out.output
    assert "nothing was kept" in text and "--resume" not in text


def test_results_pickle() -> None:
    sweep = run_study(
        parse_study(
            "designlab: 1\nkind: navigation_sweep\nname: s\nbase: {gains: {k1: 3, b: 0.25, "
            "k3: 20, k5: 17}, scenarios: [[1, 6]], stabilising: off}\n"
            "sweep: {method: grid, parameters: {gains.k1: {values: [3, 4.3]}}}\n"
        )
    )
    scen = run_study(parse_study(SCEN))
    batch = nav.simulate_batch([nav.configuration(1)], [GAINS.as_array()], stabilising="off")
    evaluation = nav.evaluate_gains([nav.configuration(1)], GAINS, stabilising="off")
    sizes = nav.region_sizes(nav.Human(), nav.HolonomicRobot(), 0.06)
    for r in (sweep, scen, batch, evaluation, sizes, scen.runs[0].result):
        back = pickle.loads(pickle.dumps(r))
        assert type(back) is type(r)
        assert back.to_frame().equals(r.to_frame())


def test_evaluate_gains_is_a_result_with_status_and_warnings() -> None:
    e = nav.evaluate_gains([nav.configuration(1)], [GAINS, nav.VFFGains(1e-3, 1e-3, 1e-3, 1e-3)],
                           stabilising="off")  # fmt: skip
    check_result(e)
    assert e.status == "ok" and e.warnings and "[1]" in e.warnings[0]
    assert list(e.to_frame()["feasible"]) == [True, False]


def test_the_docs_examples_run() -> None:
    # docs/navigation.md used an undefined gains_array_N_by_4
    for page in ("navigation.md", "navigation_gains.md"):
        text = (ROOT / "docs" / page).read_text()
        for block in re.findall(r"```python\n(.*?)```", text, re.S):
            exec(compile(block, page, "exec"), {})


# ------------------------------------------------------------------- fuzzing

CONSTRUCTORS: dict[type, dict[str, Any]] = {
    nav.HolonomicRobot: {},
    nav.NonholonomicRobot: {},
    nav.Human: {},
    nav.CircularObstacle: {},
    nav.ObstacleRobot: {},
    nav.RectangularObstacle: {},
    nav.VFFGains: {"k1": 3.0, "b": 0.25, "k3": 20.0, "k5": 17.0},
    nav.MasoudGains: {},
    nav.GeCuiGains: {},
    nav.Stationary: {"position": (1.0, 2.0)},
    nav.ConstantVelocity: {"start": (0.0, 0.0), "velocity": (0.5, 0.0)},
    nav.Walk: {"start": (0.0, 0.0), "end": (4.0, 0.0)},
    nav.Disc: {"name": "d", "radius": 0.1, "r2": 0.8, "r3": 0.4, "motion": nav.Stationary((2, 2))},
    nav.Rectangle: {
        "name": "r",
        "center": (2.0, 2.0),
        "length": 1.0,
        "width": 0.5,
        "r2": 0.8,
        "r3": 0.4,
    },
    nav.Scenario: {"name": "s", "start": (4.0, 0.0), "goal": (0.0, 0.0)},
    nav.RandomWalks: {},
}
HOSTILE = st.one_of(
    st.sampled_from([math.nan, math.inf, -math.inf, 1e300, -1e300, -1.0, 0.0, 1e-300, True,
                     False, None, "0.4", "", [], (1.0,), (math.nan, 0.0), (1e300, 1e300)]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-(10**12), 10**12),
)  # fmt: skip


@settings(max_examples=300, deadline=None)
@given(cls=st.sampled_from(list(CONSTRUCTORS)), data=st.data())
def test_every_constructor_refuses_clearly_or_gives_finite_values(cls: type, data: Any) -> None:
    field = data.draw(st.sampled_from(list(params_of(cls))))
    value = data.draw(HOSTILE)
    kw = {**CONSTRUCTORS[cls], field: value}
    try:
        obj = cls(**kw)
    except InvalidParameterError as exc:
        assert exc.name.split(".")[0] in (cls.__name__, "Scenario") or field in exc.name
        assert field in str(exc) or exc.name.startswith(cls.__name__)
        return
    for name, decl in params_of(cls).items():
        v = getattr(obj, name)
        if decl.kind == "real" and v is not None:
            assert isinstance(v, float) and math.isfinite(v) and decl.within(v), (name, v)


# ------------------------------------------- JSON Schema and constructor agree

#: (domain class, its spec model, the other fields of a valid object)
SPECS: list[tuple[type, Any, dict[str, Any], dict[str, Any]]] = [
    (nav.VFFGains, specs.GainsSpec, dict(k1=3.0, b=0.25, k3=20.0, k5=17.0),
     dict(k1=3.0, b=0.25, k3=20.0, k5=17.0)),
    (nav.MasoudGains, specs.MasoudGainsSpec, {}, {}),
    (nav.GeCuiGains, specs.GeCuiGainsSpec, {}, {}),
    (nav.Walk, specs.WalkSpec, {"start": (0.0, 0.0), "end": (200.0, 0.0)},
     {"start": [0.0, 0.0], "end": [200.0, 0.0]}),
    (nav.HolonomicRobot, specs.RobotSpec, {}, {"type": "holonomic"}),
    (nav.NonholonomicRobot, specs.RobotSpec, {}, {"type": "nonholonomic"}),
]  # fmt: skip


def _edges(decl: Any) -> list[float]:
    out = []
    for b in (decl.gt, decl.ge, decl.lt, decl.le):
        if b is not None:
            out += [b, math.nextafter(b, -math.inf), math.nextafter(b, math.inf)]
    return out


@pytest.mark.parametrize(
    "cls, spec, base, yaml_base", SPECS, ids=lambda x: getattr(x, "__name__", "")
)
def test_json_schema_and_constructor_accept_and_refuse_the_same_edges(
    cls: type, spec: Any, base: dict[str, Any], yaml_base: dict[str, Any]
) -> None:
    schema = spec.model_json_schema()
    schema = schema["anyOf"][1] if "anyOf" in schema else schema
    for name, decl in params_of(cls).items():
        if decl.kind not in ("real", "integer"):
            continue
        for value in _edges(decl):
            if decl.kind == "integer" and not float(value).is_integer():
                continue
            try:
                cls(**{**base, name: value})
                built = True
            except InvalidParameterError:
                built = False
            try:
                jsonschema.validate({**yaml_base, name: value}, schema)
                valid = True
            except jsonschema.ValidationError:
                valid = False
            assert built == valid == decl.within(value) or (
                decl.kind == "integer" and name == "direction"  # +1 / -1: a rule between them
            ), (cls.__name__, name, value, built, valid)


@pytest.mark.parametrize("popsize", [0, 3, 300, 4.5, True, "16"])
def test_python_and_yaml_refuse_the_same_population(popsize: object) -> None:
    with pytest.raises(InvalidParameterError, match="popsize"):
        nav.optimise_gains([nav.configuration(1)], popsize=popsize)  # type: ignore[arg-type]
    text = f"designlab: 1\nkind: navigation_gains\nname: g\npopsize: {popsize!r}\n"
    with pytest.raises(StudyError, match="popsize"):
        parse_study(text.replace("'", '"') if isinstance(popsize, str) else text)


def test_text_is_not_a_number_in_python_nor_in_yaml() -> None:
    # was: radius='0.4' coerced by the constructor while the YAML refused True
    with pytest.raises(InvalidParameterError, match=r"Human.radius = '0.4'"):
        nav.Human(radius="0.4")  # type: ignore[arg-type]
    with pytest.raises(StudyError, match="radius"):
        parse_study(SCEN.replace("radius: 0.4", 'radius: "0.4"'))


def test_a_ten_million_point_navigation_sweep_is_refused_by_validate() -> None:
    text = (
        "designlab: 1\nkind: navigation_sweep\nname: big\nbase: {gains: {k1: 3, b: 0.25, k3: 20, "
        "k5: 17}}\nsweep: {method: lhs, samples: SAMPLES, parameters: {gains.k1: {low: 1, "
        "high: 5}}}\n"
    )
    with pytest.raises(StudyError, match=r"10,000,001 points .* at most 100,000"):
        parse_study(text.replace("SAMPLES", "10000000"))
    # the cap counts the base point too: 99,999 samples + the base = 100,000 points
    assert parse_study(text.replace("SAMPLES", "99999")).sweep.count() == 99_999


@given(gap=st.floats(min_value=0.0, max_value=0.05))
@settings(max_examples=20, deadline=None)
def test_an_active_region_inside_contact_is_refused_naming_r2(gap: float) -> None:
    # r2 at or below radius + robot radius leaves no clearance to score (was a ZeroDivisionError)
    nav = dl.navigation
    robot = nav.HolonomicRobot()
    r2 = 0.2 + robot.radius - gap
    human = nav.Disc(name="h", radius=0.2, r2=r2, r3=r2 / 2, motion=nav.Stationary((2.0, 1.0)))
    with pytest.raises(InvalidParameterError, match=r"Disc\.r2.*contact distance"):
        nav.Scenario(name="x", start=(0.0, 0.0), goal=(5.0, 0.0), obstacles=(human,), robot=robot)
