"""Study files: valid forms, and errors that name the file, the field and the line."""

from __future__ import annotations

import textwrap
from importlib import resources
from pathlib import Path

import pandas as pd
import pytest

from designlab.errors import DesignlabError, StudyError
from designlab.impact.parameters import FOAM_1, FOAM_2_MEASURED, MANIPULATOR_1, TEST_HEAD
from designlab.study import load_study, parse_study, study_adapter
from designlab.study.kinds.impact_cases import ImpactCasesStudy

HEADER = "designlab: 1\nkind: impact_cases\nname: s\n"


def _case(body: str) -> str:
    """A study with one case; ``body`` is the case's mapping, indented by 4."""
    return HEADER + "cases:\n  - " + textwrap.indent(textwrap.dedent(body), "    ").lstrip()


GOOD_CASE = """\
robot: MANIPULATOR_1
foam: FOAM_1
head: TEST_HEAD
impact_velocity: 1.25
"""


def test_presets_explicit_values_and_overrides(tiny_study_text):
    study = parse_study(tiny_study_text)
    assert isinstance(study, ImpactCasesStudy)
    slow, fast = study.cases
    assert slow.robot.build() == MANIPULATOR_1
    assert slow.foam.build() == FOAM_1
    assert slow.head.build() == TEST_HEAD
    assert slow.closing_velocity == 0.4
    # ``20e3`` (no dot) is a float, not a string
    robot = fast.robot.build()
    assert (robot.mass, robot.stiffness, robot.damping) == (9.6, 20000.0, 250.0)
    assert fast.closing_velocity == pytest.approx(1.25)  # v_c = v_r - v_h (I5)
    override = parse_study(
        _case(
            "robot: {preset: MANIPULATOR_1, stiffness: 10e3}\n"
            "foam: {preset: FOAM_2_MEASURED, linear_depth: 0.025}\n"
            "head: TEST_HEAD\nimpact_velocity: 0.4\n"
        )
    ).cases[0]
    assert override.robot.build() == MANIPULATOR_1.replace(stiffness=10e3)
    assert override.foam.build() == FOAM_2_MEASURED.replace(linear_depth=0.025)


def test_discriminated_union_on_kind():
    data = {
        "designlab": 1,
        "kind": "impact_cases",
        "name": "x",
        "cases": [
            {"robot": "MANIPULATOR_2", "foam": "FOAM_3", "head": "HEAD_MAX", "impact_velocity": 1.0}
        ],
    }
    assert isinstance(study_adapter().validate_python(data), ImpactCasesStudy)


# (yaml text, field path, line, words the message must contain)
ERRORS = [
    pytest.param(
        _case(GOOD_CASE.replace("head: TEST_HEAD", "haed: TEST_HEAD")),
        "cases[0].haed",
        7,
        ["unknown field", "did you mean 'head'"],
        id="unknown-field",
    ),
    pytest.param(
        _case(
            GOOD_CASE.replace(
                "robot: MANIPULATOR_1", "robot: {mass: 9.6, stifness: 2e4, damping: 250}"
            )
        ),
        "cases[0].robot.stifness",
        5,
        ["did you mean 'stiffness'"],
        id="nested-typo",
    ),
    pytest.param(
        HEADER + "descripton: x\ncases: []\n",
        "descripton",
        4,
        ["did you mean 'description'"],
        id="top-level-typo",
    ),
    pytest.param(
        _case(GOOD_CASE.replace("robot: MANIPULATOR_1", "robot: MANIPULATR_1")),
        "cases[0].robot",
        5,
        ["unknown robot preset", "did you mean 'MANIPULATOR_1'"],
        id="unknown-preset",
    ),
    pytest.param(
        _case(GOOD_CASE.replace("impact_velocity: 1.25", "impact_velocity: fast")),
        "cases[0].impact_velocity",
        8,
        ["must be a number", "'fast'"],
        id="wrong-type",
    ),
    pytest.param(
        _case(GOOD_CASE.replace("impact_velocity: 1.25", "impact_velocity: yes")),
        "cases[0].impact_velocity",
        8,
        ["boolean"],
        id="bool-is-not-a-number",
    ),
    pytest.param(
        _case(GOOD_CASE.replace("foam: FOAM_1", "foam: {stiffness: -1, damping: 7}")),
        "cases[0].foam.stiffness",
        6,
        ["greater than 0", "-1"],
        id="out-of-range",
    ),
    pytest.param(
        _case(GOOD_CASE.replace("impact_velocity: 1.25", "v_r: 0.0\nv_h: 0.4")),
        "cases[0]",
        5,
        ["v_r - v_h", "> 0"],
        id="no-impact",
    ),
    pytest.param(
        _case(GOOD_CASE.replace("impact_velocity: 1.25", "impact_velocity: 1\nv_r: 1")),
        "cases[0]",
        5,
        ["not both"],
        id="two-velocities",
    ),
    pytest.param(
        _case(GOOD_CASE.replace("head: TEST_HEAD", "head: {mass: 4.4}")),
        "cases[0].head",
        7,
        ["missing: stiffness, damping"],
        id="incomplete-head",
    ),
    pytest.param(
        _case(GOOD_CASE.replace("foam: FOAM_1\n", "")),
        "cases[0].foam",
        5,
        ["missing required field"],
        id="missing-field",
    ),
    pytest.param(
        "designlab: 1\nkind: impact_cases\ncases: [\n", None, 4, ["YAML syntax"], id="yaml-syntax"
    ),
    pytest.param(
        HEADER + "name: t\ncases: []\n",
        "name",
        4,
        ["appears twice", "lines 3 and 4"],
        id="duplicate-key",
    ),
    pytest.param(
        "designlab: 1\nkind: impact_case\nname: s\n",
        "kind",
        2,
        ["did you mean 'impact_cases'"],
        id="unknown-kind",
    ),
    pytest.param(
        "designlab: 2\nkind: impact_cases\nname: s\n",
        "designlab",
        1,
        ["not supported"],
        id="format-version",
    ),
    pytest.param(
        "kind: impact_cases\nname: s\n", "designlab", 1, ["designlab: 1"], id="no-format-version"
    ),
    pytest.param(
        HEADER.replace("name: s", "name: a/b") + "cases: []\n",
        "name",
        3,
        ["pattern"],
        id="unsafe-name",
    ),
    pytest.param(HEADER + "cases: []\n", "cases", 4, ["at least 1"], id="no-cases"),
    pytest.param("- a\n- b\n", None, 1, ["YAML mapping"], id="not-a-mapping"),
]


@pytest.mark.parametrize(("text", "field", "line", "words"), ERRORS)
def test_study_errors_name_file_field_and_line(write_study, text, field, line, words):
    path = write_study(text, "bad.yaml")
    with pytest.raises(StudyError) as info:
        load_study(path)
    err = info.value
    assert isinstance(err, DesignlabError) and isinstance(err, ValueError)
    assert (err.file, err.field, err.line) == (str(path), field, line)
    first = str(err).splitlines()[0]
    expected_prefix = f"{path}:{line}: " + (f"{field}: " if field else "")
    assert first.startswith(expected_prefix), first
    for word in words:
        assert word in str(err)


def test_all_errors_are_listed_in_line_order(write_study):
    text = _case(
        GOOD_CASE.replace(
            "robot: MANIPULATOR_1", "robot: {mass: 0, stiffness: 2e4, damping: 1}"
        ).replace("impact_velocity: 1.25", "impact_velocity: -1")
    )
    with pytest.raises(StudyError) as info:
        load_study(write_study(text))
    message = str(info.value)
    assert info.value.line == 5 and info.value.field == "cases[0].robot.mass"
    assert "and 1 more" in message and ":8: cases[0].impact_velocity:" in message


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(StudyError, match=r"nope\.yaml: study file not found"):
        load_study(tmp_path / "nope.yaml")
    with pytest.raises(StudyError, match="is a directory"):
        load_study(tmp_path)


def test_duplicate_case_labels_are_rejected():
    text = (
        HEADER
        + "cases:\n"
        + "".join(
            f"  - {{label: a, robot: MANIPULATOR_1, foam: FOAM_1, head: TEST_HEAD, "
            f"impact_velocity: {v}}}\n"
            for v in (0.4, 1.25)
        )
    )
    with pytest.raises(StudyError, match="label 'a' is used twice"):
        parse_study(text, file="x.yaml")


def test_default_study_matches_packaged_thesis_tables(repo_root):
    """Every (foam, K_r, C_r, v_c) group of Tables 4.1/4.2 is a case, with the thesis values."""
    study = load_study(repo_root / "studies" / "zeng_ch4_validation.yaml")
    data = resources.files("designlab") / "data"
    with (data / "impact_experiments_table4_1.csv").open() as fh:
        t41 = pd.read_csv(fh)
    with (data / "impact_experiments_table4_2.csv").open() as fh:
        t42 = pd.read_csv(fh)
    t41["K_r"], t41["C_r"], t41["M_r"] = t41.K_r_kN_per_m * 1e3, t41.C_r_N_s_per_m, 9.6
    t42["K_r"], t42["C_r"], t42["M_r"], t42["foam_no"] = 14.4e3, 111.0, 49.4, 1
    foams = {1: FOAM_1, 2: FOAM_2_MEASURED}  # DECISIONS I3 (Foam 1: App. A.1 values)
    keys = ["M_r", "K_r", "C_r", "foam_no", "v_c_m_per_s"]
    groups = pd.concat([t41, t42]).groupby(keys, sort=False)
    assert len(study.cases) == groups.ngroups == 10
    for case in study.cases:
        robot, foam, head = case.robot.build(), case.foam.build(), case.head.build()
        assert head == TEST_HEAD  # C_h = 0, K_h = 4 kN/m, M_h = 4.4 kg (I3)
        foam_no = next(n for n, f in foams.items() if f == foam)
        key = (robot.mass, robot.stiffness, robot.damping, foam_no, case.closing_velocity)
        rows = groups.get_group(key)
        ref = case.reference
        assert ref is not None and ref.exp_trials == len(rows)
        assert ref.a_h_max_g == rows.sim_a_h_max_g.iloc[0]
        assert ref.t_imp_s == rows.sim_t_imp_s.iloc[0]
        assert ref.eps_max_m == rows.sim_eps_max_m.iloc[0]
        assert ref.exp_a_h_max_g == pytest.approx(rows.exp_a_h_max_g.mean(), rel=1e-3)
        assert ref.exp_t_imp_s == pytest.approx(rows.exp_t_imp_s.mean(), rel=1e-3)
        assert ref.exp_eps_max_m == pytest.approx(rows.exp_eps_max_m.mean(), rel=1e-3)


# --- issue 18: what the shared layers refuse, clearly -------------------------------


@pytest.mark.parametrize("depth", [65, 500, 5000])
def test_deeply_nested_lists_are_refused_with_the_line(depth):
    text = "designlab: 1\nkind: impact_cases\nname: x\ncases: " + "[" * depth + "]" * depth
    with pytest.raises(StudyError, match=r"deep.yaml:4: .*more than 64 levels deep"):
        parse_study(text, file="deep.yaml")


@pytest.mark.parametrize("name", ["index.md", "INDEX.md", "nul", "com1"])
def test_reserved_study_names_are_refused(name):
    text = f"designlab: 1\nkind: impact_cases\nname: {name}\ncases: []\n"
    with pytest.raises(StudyError, match=r"s.yaml:3: name: .*reserved"):
        parse_study(text, file="s.yaml")


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        ("'1'", r"the number 1, not the text '1'; write 'designlab: 1' without quotes"),
        ("true", r"must be the number 1 \(got True\)"),
        ("2", r"study format 2 is not supported; this designlab reads format 1 only"),
    ],
)
def test_format_version_is_explained(value, expected):
    text = f"name: x\nkind: impact_cases\ndesignlab: {value}\ncases: []\n"
    with pytest.raises(StudyError, match=rf"s.yaml:3: designlab: .*{expected}"):
        parse_study(text, file="s.yaml")


def test_a_domain_rule_broken_is_refused_at_validation_with_the_spec_line():
    # every field is in range; the domain class's own rule (__post_init__) refuses the set
    from dataclasses import dataclass

    from designlab.params import declared, param
    from designlab.study.base import build_every_spec
    from designlab.study.specs import spec_model

    @declared
    @dataclass(frozen=True)
    class Band:
        """A band."""

        low: float = param("a", "m", doc="low end", ge=0, le=10)
        high: float = param("b", "m", doc="high end", ge=0, le=10)

        def __post_init__(self):
            if self.low >= self.high:
                raise ValueError(f"Band.low = {self.low} m must be < Band.high = {self.high} m")

    from pydantic import create_model

    from designlab.study.base import Model

    spec = spec_model(Band).model_validate({"low": 3, "high": 2})
    holder = create_model("Holder", __base__=Model, band=(type(spec), ...))(band=spec)
    with pytest.raises(StudyError, match=r"band: Band.low = 3.0 m must be < Band.high") as info:
        build_every_spec(holder)
    assert info.value.path == ("band",)


# --- the shipped studies read the same in every YAML parser -------------------------

STUDY_FILES = sorted((Path(__file__).resolve().parents[2] / "studies").glob("*.yaml"))


def _yaml12(text: str):
    from ruamel.yaml import YAML

    return YAML(typ="safe", pure=True).load(text)


def _yaml11(text: str):
    import yaml

    return yaml.safe_load(text)


@pytest.fixture(scope="module")
def schema_validator():
    import jsonschema

    from designlab.study import study_json_schema

    return jsonschema.Draft202012Validator(study_json_schema())


@pytest.mark.parametrize("reader", [_yaml12, _yaml11], ids=["yaml1.2-ruamel", "yaml1.1-pyyaml"])
@pytest.mark.parametrize("path", STUDY_FILES, ids=lambda p: p.stem)
def test_shipped_studies_pass_the_exported_json_schema_in_any_yaml_parser(
    path, reader, schema_validator
):
    from designlab.study.yamlio import load_yaml_with_lines

    text = path.read_text(encoding="utf-8")
    data = reader(text)
    assert data == load_yaml_with_lines(text)[0]  # the same values as designlab reads
    schema_validator.validate(data)
