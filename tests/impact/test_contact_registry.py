"""The impact contact models: one registry, one module each, no class tests in the engines."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import designlab as dl
from designlab.errors import InvalidParameterError
from designlab.impact.contact import CONTACTS, contact_of

ROOT = Path(dl.__file__).parent
#: the robot and contact (foam) classes a variant is chosen by
VARIANT_CLASSES = {
    "ContactDynamics", "LinkImpact", "FullJointContact", "FullJointLink", "SeriesJoint",
    "Foam", "HuntCrossleyFoam", "StressStrainFoam",
}  # fmt: skip


def _names(node: ast.AST) -> set[str]:
    if isinstance(node, ast.Tuple):
        return set().union(*(_names(e) for e in node.elts))
    if isinstance(node, ast.Name):
        return {node.id}
    if isinstance(node, ast.Attribute):
        return {node.attr}
    return set()


def positive_dispatches(path: Path) -> list[int]:
    """Lines of ``isinstance(x, <variant class>)`` not under ``not`` (a dispatch, not a check)."""
    tree = ast.parse(path.read_text())
    negated = {id(n.operand) for n in ast.walk(tree) if isinstance(n, ast.UnaryOp)
               and isinstance(n.op, ast.Not)}  # fmt: skip
    return [
        n.lineno
        for n in ast.walk(tree)
        if isinstance(n, ast.Call)
        and getattr(n.func, "id", None) == "isinstance"
        and len(n.args) == 2
        and _names(n.args[1]) & VARIANT_CLASSES
        and id(n) not in negated
    ]


def test_no_engine_dispatches_on_a_robot_or_contact_class() -> None:
    contact = ROOT / "impact" / "contact"
    found = {
        f"{p.relative_to(ROOT)}:{line}"
        for p in ROOT.rglob("*.py")
        if contact not in p.parents
        for line in positive_dispatches(p)
    }
    assert found == set(), "ask designlab.impact.contact.contact_of(robot, foam) instead"


def test_the_ast_count_sees_a_dispatch(tmp_path: Path) -> None:
    src = tmp_path / "engine.py"
    src.write_text(
        "if isinstance(robot, FullJointContact):\n    pass\n"
        "if not isinstance(foam, Foam):\n    raise ValueError\n"
    )
    assert positive_dispatches(src) == [1]


def test_each_pair_finds_its_model_and_a_wrong_pair_is_named() -> None:
    arm = dl.impact.FullJointContact.from_joint(0.059, 2e3, 2.0, 1.5e3, 30.0, lever_arm=0.2)
    hc = dl.impact.HuntCrossleyFoam(24.25e3, 71.9, densification_depth=0.02)
    assert contact_of(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1).name == "kelvin_voigt"
    assert contact_of(arm, dl.impact.FOAM_1).name == "series_joint"
    assert contact_of(dl.impact.MANIPULATOR_1, hc).name == "hunt_crossley"
    with pytest.raises(InvalidParameterError, match="must be one of \\['Foam'\\] with a Full"):
        contact_of(arm, hc)
    with pytest.raises(InvalidParameterError, match="robot = 'arm'"):
        contact_of("arm")


def test_rows_are_built_by_name_in_each_models_order() -> None:
    for model in CONTACTS:
        assert set(model.robot_columns) | {"K_c", "C_c", "M_h", "C_h", "K_h"} | set(
            model.foam_columns
        ) == set(model.columns)
    row = CONTACTS.get("kelvin_voigt").row(dl.impact.MANIPULATOR_1, dl.impact.FOAM_1, None)
    assert row.tolist() == [9.6, 250.0, 20e3, 24.25e3, 71.9, 1.0, 0.0, 0.0]


def test_the_registry_derives_choices_and_capabilities() -> None:
    assert CONTACTS.choices(linear=False) == ("hunt_crossley", "stress_strain")
    assert CONTACTS.choices(gradients=True) == ("kelvin_voigt",)
    assert CONTACTS.json_schema()["enum"] == [
        "kelvin_voigt", "series_joint", "hunt_crossley", "stress_strain"
    ]  # fmt: skip


def test_a_link_rows_scale_as_one_over_l_squared() -> None:
    link = dl.impact.LinkImpact(0.059, 1.5e3, 30.0, 1.0, 0.05, 0.3)
    rows = contact_of(link).robot_row(link, np.array([0.1, 0.2]))
    assert np.allclose(rows[:, 0], [5.9, 1.475]) and np.allclose(rows[:, 2], [1.5e5, 3.75e4])
