"""The error-source section of the ``tether_comparison`` report (Allan 2015 Sec. 3.4).

Allan explains why people saw FTL-CD beat Pseudo-Joystick by less than the
simulation does by two error sources: wheel slip, which corrupts the dead
reckoning in which FTL and FTL-CD record the path, and the offset between the
tether tip and the waist marker the motion capture measured. The study's
``error_sources`` block runs each law with neither, each and both
(:func:`designlab.following.tether.simulate_with_errors`); this module states
what the table shows, computed from it.

Examples
--------
>>> import pandas as pd
>>> t = pd.DataFrame({"path": ["p"] * 4, "controller": ["PJ", "PJ", "CD", "CD"],
...                   "variant": ["none", "slip"] * 2, "npd_mean_m": [0.4, 0.4, 0.1, 0.2]})
>>> error_claims(t, reference="PJ")
['p: mean NPD PJ / CD 4.00 without errors, 2.00 with slip.']
"""

from __future__ import annotations

import pandas as pd

from designlab.report.builder import claims
from designlab.report.writers import markdown_table

__all__ = ["error_claims", "error_section"]

_WITH = {
    "none": "without errors",
    "slip": "with slip",
    "marker": "with the marker offset",
    "both": "with both",
}


def error_claims(table: pd.DataFrame, reference: str) -> list[str]:
    """Per path and law: the reference law's mean NPD over the law's, per variant.

    Parameters
    ----------
    table
        The study's error-source table (``path``, ``controller``, ``variant``, ``npd_mean_m``).
    reference
        The label of the law in the numerator (the thesis: Pseudo-Joystick).
    """
    out = []
    for path, rows in table.groupby("path", sort=False):
        npd = rows.set_index(["controller", "variant"])["npd_mean_m"]
        for law in dict.fromkeys(rows["controller"]):
            if law == reference:
                continue
            parts = [
                f"{npd[(reference, v)] / npd[(law, v)]:.2f} {_WITH.get(v, 'with ' + v)}"
                for v in dict.fromkeys(rows["variant"])
            ]
            out.append(f"{path}: mean NPD {reference} / {law} " + ", ".join(parts) + ".")
    return out


def error_section(table: pd.DataFrame | None, study: object) -> list[str]:
    """The markdown lines of the section (empty without a table).

    Parameters
    ----------
    table
        The error-source table, or None.
    study
        The comparison study (its ``error_sources`` and controllers).
    """
    if table is None or not len(table):
        return []
    e = study.error_sources  # type: ignore[attr-defined]
    s, m = e.slip, e.marker
    reference = study.controllers[0].title  # type: ignore[attr-defined]
    return [
        "## Error sources of Sec. 3.4: wheel slip and the marker offset",
        "",
        f"Each law at l_d = {e.desired_length:g} m with: no error; wheel slip (left "
        f"{s.left_slip:g}, right {s.right_slip:g}, noise {s.noise_std:g} per period, so the "
        "dead-reckoned pose in which FTL and FTL-CD record the path drifts from the true one); "
        f"the tether tip {m.forward:g} m ahead and {m.left:g} m left of the measured marker "
        "(the NPD is measured against the marker's path, as the motion capture did); both. "
        "The slip and offset values are the project's assumptions: the thesis names the "
        "sources without sizes (`docs/following.md`).",
        "",
        *claims(error_claims(table, reference)),
        markdown_table(table, floatfmt=".4g"),
        "",
    ]
