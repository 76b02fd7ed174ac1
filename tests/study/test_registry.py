"""One module per study kind: the registry, a kind defined here end to end, the layers.

The kind below lives in this test file only: it is registered, validated from
YAML and the JSON Schema, run through the shared sweep machinery and its store,
and reported by a writer registered here, without editing any designlab file.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any, ClassVar, Literal

import jsonschema
import numpy as np
import pandas as pd
import pytest
import yaml
from pydantic import Field

from designlab.analysis.keys import chunk_key, code_version, package_hash, source_files
from designlab.analysis.store import open_store
from designlab.params import Param
from designlab.report import register_writer, write_report
from designlab.study import (
    RunContext,
    StudyKind,
    parse_study,
    register_kind,
    run_study,
    study_json_schema,
    study_kinds,
    unregister_kind,
)
from designlab.study.base import Model, Positive
from designlab.study.sweep_runner import SweepStudyResult, run_sweep_study
from designlab.study.sweeps import SweepStudyBase, parameter_model

REPO = Path(__file__).resolve().parents[2]


# --- a small kind: a damped oscillator's peak overshoot, defined entirely here -------


def overshoot_chunk(points: dict[str, np.ndarray], options: dict[str, Any]) -> dict[str, Any]:
    """Percent overshoot of a second-order step response, exp(-pi z / sqrt(1 - z^2))."""
    z = points["zeta"]
    if np.any(z >= 1):
        raise ValueError("zeta must be < 1 for an overshoot")
    return {"overshoot_pct": 100 * np.exp(-np.pi * z / np.sqrt(1 - z**2)) * options["gain"]}


OSC_PARAMETERS = {"zeta": ("zeta", Param(None, "", "damping ratio zeta", gt=0, le=5))}
OscParameters = parameter_model("OscParameters", {"zeta": OSC_PARAMETERS["zeta"][1]})


class OscDesign(Model):
    zeta: Positive = 0.5


class OscStudy(SweepStudyBase[OscParameters, Literal["overshoot_pct"]]):  # type: ignore[valid-type]
    kind: Literal["test_oscillator"]
    base: OscDesign = Field(default_factory=OscDesign)
    gain: Positive = 1.0

    PARAMETERS: ClassVar[dict[str, Any]] = OSC_PARAMETERS
    METRICS: ClassVar[dict[str, str]] = {"overshoot_pct": "peak overshoot, %"}
    EVALUATOR: ClassVar[Any] = overshoot_chunk

    def base_point(self) -> dict[str, float]:
        return {"zeta": float(self.base.zeta)}

    def evaluator_options(self) -> dict[str, Any]:
        return {"gain": float(self.gain)}


OSC_KIND = StudyKind("test_oscillator", OscStudy, run_sweep_study, report=__name__)


class OscResult(SweepStudyResult):
    pass


@register_writer(SweepStudyResult)  # the shared sweep writer is replaced for this test only
def _never(*args: Any, **kwargs: Any) -> None:  # pragma: no cover - restored below
    raise AssertionError


# restore the real sweep writer (importing it re-registers it), then register ours by kind
import designlab.report.sweep as _sweep_writer  # noqa: E402

register_writer(SweepStudyResult)(_sweep_writer.sweep_report)

OSC_YAML = """\
designlab: 1
kind: test_oscillator
name: osc
gain: 2
base: {zeta: 0.5}
sweep:
  method: list
  parameters:
    zeta: {values: [0.1, 0.5, 0.5, 2.0]}
"""


@pytest.fixture
def osc_kind():
    register_kind(OSC_KIND)
    yield OSC_KIND
    unregister_kind("test_oscillator")


def test_a_kind_defined_in_a_test_runs_end_to_end(osc_kind, tmp_path):
    assert "test_oscillator" in study_kinds()
    # the JSON Schema and the loader pick it up from the registry
    schema = study_json_schema()
    assert "test_oscillator" in schema["discriminator"]["mapping"]
    jsonschema.validate(yaml.safe_load(OSC_YAML), schema)
    study = parse_study(OSC_YAML)
    with open_store(tmp_path / "cache", study.name) as store:
        result = run_study(study, RunContext(store=store))
    f = result.to_frame()
    z = np.array([0.1, 0.5, 0.5])
    expected = 2 * 100 * np.exp(-np.pi * z / np.sqrt(1 - z**2))  # written here, independently
    np.testing.assert_allclose(f["overshoot_pct"].iloc[:3], expected, rtol=1e-12)
    # zeta = 2 has no overshoot: that point fails on its own, the rest of the chunk is kept
    assert f["status"].tolist() == ["ok", "ok", "ok", "error"]
    assert "zeta must be < 1" in f["error"].iloc[3]
    assert result.status == "partial" and any("failed" in w for w in result.warnings)
    assert result.stats["distinct"] == 3 and result.stats["points"] == 5  # base merged too
    # the report is written by the shared sweep writer, from the result alone
    out = write_report(result, tmp_path / "reports", index=False)
    got = pd.read_csv(out / "results.csv")
    np.testing.assert_allclose(got["overshoot_pct"].iloc[:3], expected, rtol=1e-6)
    # a second run reads every chunk from the store
    with open_store(tmp_path / "cache", study.name) as store:
        again = run_study(study, RunContext(store=store, resume=True))
    assert again.stats["computed"] == 0 and again.frame.equals(result.frame)


def test_registry_refuses_a_kind_whose_literal_differs():
    with pytest.raises(TypeError, match="must be Literal\\['other'\\]"):
        StudyKind("other", OscStudy, run_sweep_study, report=__name__)


# --- the JSON Schema, checked with the jsonschema package ----------------------------


@pytest.fixture(scope="module")
def schema() -> dict[str, Any]:
    s = study_json_schema()
    jsonschema.Draft202012Validator.check_schema(s)
    return s


@pytest.fixture(scope="module")
def validator(schema: dict[str, Any]) -> jsonschema.Draft202012Validator:
    """One validator of the checked schema (``jsonschema.validate`` checks the schema again at
    every call: 1.2 CPU s each, 6 CPU minutes over this module)."""
    return jsonschema.Draft202012Validator(schema)


def _yaml(path: Path) -> Any:
    from designlab.study.yamlio import load_yaml_with_lines

    return load_yaml_with_lines(path.read_text())[0]


@pytest.mark.parametrize("path", sorted((REPO / "studies").glob("*.yaml")), ids=lambda p: p.name)
def test_exported_schema_accepts_every_shipped_study(validator, path):
    validator.validate(_yaml(path))


@pytest.mark.parametrize(
    ("edit", "why"),
    [
        (lambda d: d["cases"][0].update(robot="MANIPULATOR_9"), "unknown preset"),
        (lambda d: d["cases"][0].update(impact_velocity=-1.0), "negative speed"),
        (lambda d: d["cases"][0].update(robot={"mass": -9.6, "stiffness": 1e4, "damping": 0}),
         "negative mass"),
        (lambda d: d["cases"][0].update(fom="FOAM_1"), "misspelt field"),
        (lambda d: d.update(kind="impact_case"), "unknown kind"),
    ],
)  # fmt: skip
def test_exported_schema_rejects_bad_impact_cases(validator, edit, why):
    data = _yaml(REPO / "studies" / "zeng_ch4_validation.yaml")
    edit(data)
    with pytest.raises(jsonschema.ValidationError):
        validator.validate(data)


def test_exported_schema_enforces_sweep_ranges(schema, validator):
    data = _yaml(REPO / "studies" / "impact_sensitivity.yaml")
    validator.validate(data)
    data["sweep"]["parameters"]["head.mass"] = {"low": -4.4, "high": 5.3}
    with pytest.raises(jsonschema.ValidationError):
        validator.validate(data)
    # against the kind's own schema the message names the value and the bound
    kind_schema = {"$ref": "#/$defs/ImpactSweepStudy", "$defs": schema["$defs"]}
    with pytest.raises(jsonschema.ValidationError, match=r"-4\.4 is less than or equal to .*0"):
        jsonschema.validate(data, kind_schema)


# --- cache keys follow the code of the evaluator's own package ------------------------


def test_store_keys_hash_only_the_evaluators_package(tmp_path, monkeypatch):
    from designlab.impact.evaluators import impact_metrics_chunk

    files = source_files("designlab.impact.evaluators")
    impact_dir = REPO / "designlab" / "impact"
    assert files and all(impact_dir in f.parents for f in files)
    assert impact_dir / "modal.py" in files and impact_dir / "evaluators.py" in files
    # a module outside designlab: its own file; editing it changes its keys, nothing else's
    pkg = tmp_path / "userpkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "ev.py").write_text("def ev(points, options):\n    return {'y': points['x']}\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    import importlib

    ev = importlib.import_module("userpkg.ev").ev
    pts = {"x": np.array([1.0, 2.0])}
    impact_before = code_version(impact_metrics_chunk)
    key_before = chunk_key(ev, {}, pts)
    (pkg / "ev.py").write_text("def ev(points, options):\n    return {'y': 2 * points['x']}\n")
    package_hash.cache_clear()
    assert chunk_key(ev, {}, pts) != key_before
    assert code_version(impact_metrics_chunk) == impact_before


def test_editing_a_domain_invalidates_only_its_points(tmp_path):
    """A copy of the package: edit impact/, and only impact keys change."""
    copy = tmp_path / "src"
    shutil.copytree(REPO / "designlab", copy / "designlab",
                    ignore=shutil.ignore_patterns("__pycache__"))  # fmt: skip
    probe = (
        "import numpy as np\n"
        "from designlab.analysis.keys import code_version\n"
        "from designlab.impact.evaluators import impact_metrics_chunk\n"
        "import designlab.analysis.sampling as s\n"
        "print(code_version(impact_metrics_chunk), code_version(s.GridPoints))\n"
    )

    def versions() -> list[str]:
        out = subprocess.run([sys.executable, "-c", probe], cwd=copy, capture_output=True,
                             text=True, check=True,
                             env={"PYTHONPATH": str(copy), "PATH": ""})  # fmt: skip
        return out.stdout.split()

    impact0, analysis0 = versions()
    with (copy / "designlab" / "impact" / "criteria.py").open("a") as fh:
        fh.write("\n# an edit\n")
    impact1, analysis1 = versions()
    assert impact1 != impact0 and analysis1 == analysis0


# --- layers, as import-linter contracts in pyproject.toml ------------------------------


def test_import_layers_hold():
    exe = Path(sys.executable).with_name("lint-imports")
    if not exe.exists():  # pragma: no cover - dev extra not installed
        pytest.skip("import-linter is not installed (pip install -e '.[dev]')")
    out = subprocess.run([str(exe)], cwd=REPO, capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "broken" not in out.stdout.lower().replace("0 broken", "")


# --- hostile input ----------------------------------------------------------------------


def test_alias_bomb_is_refused_quickly():
    import time

    lines = ["designlab: 1", "kind: impact_cases", "name: bomb", 'a0: &a0 ["x", "x", "x"]']
    for i in range(1, 30):
        prev = f"*a{i - 1}"
        lines.append(f"a{i}: &a{i} [{', '.join([prev] * 9)}]")
    t0 = time.perf_counter()
    from designlab.errors import StudyError

    with pytest.raises(StudyError, match=r"<bomb>:\d+: the document expands to more than"):
        parse_study("\n".join(lines) + "\n", file="<bomb>")
    assert time.perf_counter() - t0 < 30  # a generous bound: it must not hang


def test_recursive_alias_is_refused():
    from designlab.errors import StudyError

    with pytest.raises(StudyError, match="refers to itself"):
        parse_study("designlab: 1\nkind: impact_cases\nname: x\ncases: &c [*c]\n")


def test_huge_grid_is_refused_before_it_is_built():
    from designlab.errors import StudyError

    text = """\
designlab: 1
kind: impact_sweep
name: huge
base: {robot: MANIPULATOR_1, foam: FOAM_1, head: HEAD_MIN, impact_velocity: 1.25}
sweep:
  method: grid
  parameters:
    foam.stiffness: {low: 1e4, high: 6e4, num: 1000}
    foam.damping: {low: 0, high: 200, num: 1000}
    head.mass: {low: 4.4, high: 5.3, num: 1000}
"""
    with pytest.raises(StudyError, match="the grid has 1,000,000,000 points; at most 10,000,000"):
        parse_study(text)


def test_schema_json_is_plain_json():
    text = json.dumps(study_json_schema())
    assert "NaN" not in text and "Infinity" not in text


STUDIES = REPO / "studies"


def _integer_paths(node: Any, path: tuple = ()) -> list[tuple]:
    """Paths of the integer values (not booleans) of a parsed study."""
    if isinstance(node, dict):
        return [p for k, v in node.items() for p in _integer_paths(v, (*path, k))]
    if isinstance(node, list):
        return [p for i, v in enumerate(node) for p in _integer_paths(v, (*path, i))]
    return [path] if isinstance(node, int) and not isinstance(node, bool) else []


@pytest.mark.parametrize("study", sorted(STUDIES.glob("*.yaml")), ids=lambda p: p.stem)
def test_no_integer_field_takes_a_boolean(study):
    """YAML's ``true`` is not 1: every integer of every committed study refuses a boolean."""
    from designlab.errors import StudyError

    data = yaml.safe_load(study.read_text())
    paths = _integer_paths(data)
    for path in paths:
        bad = json.loads(json.dumps(data))
        node = bad
        for key in path[:-1]:
            node = node[key]
        node[path[-1]] = True
        try:
            parse_study(yaml.safe_dump(bad), file=study.name)
        except StudyError:
            pass
        else:
            raise AssertionError(f"{study.name}: {'.'.join(map(str, path))} = true accepted")


def test_reversed_gain_bounds_are_refused():
    from designlab.errors import StudyError

    text = (STUDIES / "navigation_gains.yaml").read_text().replace("b: [0.05, 3]", "b: [3, 0.05]")
    with pytest.raises(StudyError, match=r"bounds.b = \[3, 0.05\] is not allowed"):
        parse_study(text, file="navigation_gains.yaml")


def test_gain_bounds_beyond_the_largest_gain_are_refused():
    from designlab.errors import StudyError

    text = (STUDIES / "navigation_gains.yaml").read_text()
    text = text.replace("b: [0.05, 3]", "b: [0.05, 3e12]")
    with pytest.raises(StudyError, match=r"less than or equal to 1000000000"):
        parse_study(text, file="navigation_gains.yaml")


def _bool_fields(model: type, seen: set | None = None) -> list[tuple[str, Any]]:
    """(qualified name, FieldInfo) of every boolean field reachable from a study schema."""
    import typing

    from pydantic import BaseModel

    seen = set() if seen is None else seen
    if model in seen:
        return []
    seen.add(model)
    out = []
    for name, info in model.model_fields.items():
        todo = [info.annotation]
        while todo:
            t = todo.pop()
            if t is bool:
                out.append((f"{model.__name__}.{name}", info))
            elif isinstance(t, type) and issubclass(t, BaseModel):
                out += _bool_fields(t, seen)
            else:
                todo += [a for a in typing.get_args(t) if a is not type(None)]
    return out


def test_no_switch_takes_a_number_or_a_word():
    """``jit: 1`` or ``refine: "yes"`` is a typo, not true: every boolean field is strict."""
    from pydantic import TypeAdapter

    from designlab.study.registry import study_kinds

    fields = [f for kind in study_kinds().values() for f in _bool_fields(kind.schema)]
    names = {n for n, _ in fields}
    assert {
        "NavigationDesign.jit",
        "NavigationGainsStudy.jit",
        "NavigationGainsStudy.refine",
    } <= names
    for name, info in fields:
        adapter = TypeAdapter(typing_annotated(info))
        assert adapter.validate_python(True) is True, name
        for bad in (1, 0, "yes", "true", "on"):
            with pytest.raises(ValueError, match="valid boolean"):
                adapter.validate_python(bad)


def typing_annotated(info: Any) -> Any:
    """The field's type with its constraints, as pydantic validates it."""
    from typing import Annotated

    return Annotated[(info.annotation, *info.metadata)] if info.metadata else info.annotation


def test_jit_1_in_a_study_is_refused_with_the_line():
    from designlab.errors import StudyError

    text = (STUDIES / "navigation_gains.yaml").read_text() + "jit: 1\n"
    with pytest.raises(
        StudyError, match=r"navigation_gains.yaml:\d+: jit: Input should be a valid boolean"
    ):
        parse_study(text, file="navigation_gains.yaml")


def test_loading_a_study_imports_only_its_own_kind():
    """Running one study does not import the other domains' kinds (CLI start-up cost)."""
    import subprocess
    import sys

    code = (
        "import sys\n"
        "from designlab.study import parse_study\n"
        "s = parse_study('designlab: 1\\nkind: impact_sweep\\nname: x\\n"
        "base: {robot: MANIPULATOR_1, foam: FOAM_1, head: HEAD_MIN, impact_velocity: 1.0}\\n"
        "sweep: {method: grid, parameters: {head.mass: {low: 4.4, high: 5.3, num: 2}}}\\n')\n"
        "print(s.kind, 'designlab.study.kinds.navigation_crowds' in sys.modules,"
        " 'designlab.navigation' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["impact_sweep", "False", "False"]


def test_kind_of_after_the_lazy_path_still_lists_every_kind():
    from designlab.study.kinds import MODULES
    from designlab.study.registry import kind_of, study_kinds

    assert kind_of("impact_sweep").name == "impact_sweep"
    assert len(study_kinds()) >= len(MODULES)
