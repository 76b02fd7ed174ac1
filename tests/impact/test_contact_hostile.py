"""Hostile inputs to the contact registry and the Hunt-Crossley foam: refused by name.

Every public input of :class:`~designlab.impact.HuntCrossleyFoam` (its declared fields)
and of the registry's look-ups (:func:`~designlab.impact.contact.contact_of`,
``CONTACTS.get``, a contact model's ``metrics``) is given NaN, inf, a negative, a huge
value and a wrong type; each must raise a ``DesignlabError`` that is also a
``ValueError`` and names the parameter and the value (docs/developers.md). The hostile
YAML case (a Hunt-Crossley field on a study foam) is
``tests/study/hostile/foam_design_hunt_crossley_fields.yaml``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import designlab as dl
from designlab.errors import DesignlabError
from designlab.impact.contact import CONTACTS, contact_of

BASE = {"stiffness": 24.25e3, "damping": 71.9, "densification_depth": 0.02}
#: hostile values of a number (a wrong type included)
NUMBERS = [math.nan, math.inf, -math.inf, -1.0, 1e300, "0.02", None, [0.02]]
FIELDS = ("stiffness", "damping", "densification_depth", "stiffening", "damping_exponent",
          "thickness")  # fmt: skip


def _refused(excinfo: pytest.ExceptionInfo, name: str) -> None:
    assert isinstance(excinfo.value, DesignlabError) and isinstance(excinfo.value, ValueError)
    assert name in str(excinfo.value), str(excinfo.value)


@pytest.mark.parametrize("field", FIELDS)
@pytest.mark.parametrize("value", NUMBERS, ids=repr)
def test_every_foam_field_refuses_a_hostile_number_by_name(field: str, value: object) -> None:
    if field == "thickness" and value is None:
        pytest.skip("thickness=None is its documented default (scaled from x_d)")
    with pytest.raises(ValueError) as excinfo:
        dl.impact.HuntCrossleyFoam(**{**BASE, field: value})
    _refused(excinfo, field)


@pytest.mark.parametrize("value", [0.5, 0.999])
def test_a_damping_exponent_between_zero_and_one_is_refused(value: float) -> None:
    with pytest.raises(ValueError) as excinfo:
        dl.impact.HuntCrossleyFoam(**BASE, damping_exponent=value)
    _refused(excinfo, "damping_exponent")


def test_a_foam_thinner_than_its_densification_depth_is_refused() -> None:
    with pytest.raises(ValueError) as excinfo:
        dl.impact.HuntCrossleyFoam(**{**BASE, "densification_depth": 0.03}, thickness=0.0254)
    _refused(excinfo, "densification_depth")


@pytest.mark.parametrize("robot", [None, "MANIPULATOR_1", 9.6, math.nan, dl.impact.FOAM_1])
def test_contact_of_refuses_a_robot_that_is_not_one(robot: object) -> None:
    with pytest.raises(ValueError) as excinfo:
        contact_of(robot)
    _refused(excinfo, "robot")


@pytest.mark.parametrize("foam", [None, "FOAM_1", math.inf, dl.impact.HEAD_MIN, {"K_c": 1.0}])
def test_contact_of_refuses_a_foam_that_is_not_one(foam: object) -> None:
    with pytest.raises(ValueError) as excinfo:
        contact_of(dl.impact.MANIPULATOR_1, foam)
    _refused(excinfo, "foam")


@pytest.mark.parametrize("name", ["hunt-crossley", "", "KELVIN_VOIGT", None, 3])
def test_the_registry_refuses_an_unknown_name(name: object) -> None:
    with pytest.raises(ValueError) as excinfo:
        CONTACTS.get(name)  # type: ignore[arg-type]
    _refused(excinfo, "contact")


@pytest.mark.parametrize("bad", [math.nan, math.inf, -1.0, 1e300])
def test_the_general_path_refuses_a_hostile_row_or_velocity(bad: float) -> None:
    hc = CONTACTS.get("hunt_crossley")
    foam = dl.impact.HuntCrossleyFoam(**BASE)
    row = hc.row(dl.impact.MANIPULATOR_1, foam, dl.impact.HEAD_MIN)
    if bad != 1e300:  # a huge mass is a valid row; a huge velocity is not
        with pytest.raises(ValueError) as excinfo:
            hc.metrics(np.where(np.arange(row.size) == 0, bad, row), 1.25)
        _refused(excinfo, "M_r[0]" if bad == -1.0 else "params")
    if bad == -1.0:  # v_c <= 0 is no impact (docs/impact.md, "Impact velocity")
        m = hc.metrics(row, bad)
        assert m.peak_force[0] == 0.0 and str(m.design_status[0]) == "no_impact"
        return
    with pytest.raises(ValueError) as excinfo:
        hc.metrics(row, bad)
    _refused(excinfo, "velocity")


OUTSIDE = [("x_d", -0.02), ("x_d", 0.0), ("n_d", 11.0), ("p_c", -1.0), ("K_c", 0.0), ("M_h", -4.4)]


@pytest.mark.parametrize(("column", "value"), OUTSIDE)
def test_the_general_path_names_the_column_of_a_row_outside_its_declaration(
    column: str, value: float
) -> None:
    hc = CONTACTS.get("hunt_crossley")
    row = hc.row(dl.impact.MANIPULATOR_1, dl.impact.HuntCrossleyFoam(**BASE), dl.impact.HEAD_MIN)
    row[hc.columns.index(column)] = value
    with pytest.raises(ValueError) as excinfo:
        hc.metrics(row, 1.25)
    _refused(excinfo, f"{column}[0]")
