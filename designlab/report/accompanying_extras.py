"""The Sec. 6 section of the accompanying report: each option's effect, from its table.

Wu et al. 2021 (Sec. 5-6) name a sensor offset from the robot's centre, an
adaptive target distance and a motion filter without equations; the project's
models are in ``docs/accompanying.md``. :func:`extras_frame` tabulates the
runs of the study's ``extras`` block (each option alone, default PID) and
:func:`extras_claims` states what the table shows, computed from it.

Examples
--------
>>> import pandas as pd
>>> t = pd.DataFrame({"task": ["a", "a", "b", "b"], "option": ["none", "x", "none", "x"],
...                   "rms_error_mm": [10.0, 8.0, 10.0, 12.0],
...                   "yaw_command_roughness_rad_s2": [1.0, 1.0, 1.0, 1.0],
...                   "max_target_change_mm": [0.0] * 4})
>>> _rms_claim(t, "x", "option x")
'option x: RMS error -20.0 % on a, +20.0 % on b (lower on 1 of 2 tasks).'
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from designlab.following.accompanying import AccompanyResult
from designlab.report.builder import claims
from designlab.report.writers import markdown_table
from designlab.study.kinds.accompanying import AccompanyingResult

__all__ = ["extras_claims", "extras_frame", "extras_section", "yaw_command_roughness"]


def yaw_command_roughness(run: AccompanyResult) -> float:
    """RMS of the yaw-rate command's change per period over the period, rad/s^2.

    A smoothness measure of the command (what the motion filter is for): the
    pelvis sway at the step frequency shows as fast changes of omega_z.

    Parameters
    ----------
    run
        One accompanying run.
    """
    w = run.command[2]
    return float(np.sqrt(np.mean(np.diff(w) ** 2)) / run.sensor.period)


def extras_frame(result: AccompanyingResult) -> pd.DataFrame:
    """One row per (task, option): tracking error, path length, command roughness.

    Parameters
    ----------
    result
        An accompanying study result with its Sec. 6 runs.
    """
    rows = []
    for option, runs in result.extras.items():
        for task, r in runs.items():
            m = r.metrics
            rows.append(
                {
                    "task": task,
                    "option": option,
                    "rms_error_mm": 1e3 * m.rms_error,
                    "max_error_mm": 1e3 * m.max_error,
                    "settled_error_mm": 1e3 * m.settled_error,
                    "path_length_ratio": m.path_length_ratio,
                    "yaw_command_roughness_rad_s2": yaw_command_roughness(r),
                    "max_target_change_mm": 1e3 * float(np.max(np.abs(r.target_change))),
                    "status": str(r.status),
                }
            )
    return pd.DataFrame(rows)


def _relative(table: pd.DataFrame, option: str, column: str) -> pd.Series:
    base = table[table.option == "none"].set_index("task")[column]
    other = table[table.option == option].set_index("task")[column]
    return (other / base - 1.0).reindex(base.index)


def _rms_claim(table: pd.DataFrame, option: str, what: str) -> str:
    rel = _relative(table, option, "rms_error_mm")
    parts = ", ".join(f"{100 * v:+.1f} % on {task}" for task, v in rel.items())
    lower = int((rel < 0).sum())
    return f"{what}: RMS error {parts} (lower on {lower} of {len(rel)} tasks)."


def extras_claims(table: pd.DataFrame, offset: tuple[float, float]) -> list[str]:
    """Statements computed from :func:`extras_frame` (per task, never summarised away).

    Parameters
    ----------
    table
        :func:`extras_frame`.
    offset
        The sensor offset (a_x, a_y) of the mount runs, m.
    """
    out = [
        _rms_claim(
            table,
            "mount",
            f"Sensor {offset[1]:+.2f} m ahead, {offset[0]:+.2f} m right "
            "of the rotation centre, uncompensated",
        ),
    ]
    comp = _relative(table, "mount_compensated", "rms_error_mm").abs().max()
    out.append(
        "Compensated (the centre commanded so that the sensor point moves as the PID asks): "
        f"RMS error at most {100 * comp:.1f} % from the run with the sensor at the centre "
        "on every task."
    )
    out.append(_rms_claim(table, "adaptation", "Target-distance adaptation"))
    change = table[table.option == "adaptation"].set_index("task")["max_target_change_mm"]
    out.append(
        "Largest target-distance change: "
        + ", ".join(f"{v:.0f} mm on {t}" for t, v in change.items())
        + "."
    )
    out.append(_rms_claim(table, "motion_filter", "Motion filter"))
    rough = _relative(table, "motion_filter", "yaw_command_roughness_rad_s2")
    out.append(
        "Motion filter, yaw-rate command roughness: "
        + ", ".join(f"{100 * v:+.1f} % on {t}" for t, v in rough.items())
        + "."
    )
    return out


def extras_section(result: AccompanyingResult, table: pd.DataFrame) -> list[str]:
    """The markdown lines of the Sec. 6 section (empty without the study's ``extras``).

    Parameters
    ----------
    result
        An accompanying study result.
    table
        :func:`extras_frame` of it.
    """
    e = result.study.extras
    if e is None or not len(table):
        return []
    m, a, f = e.mount, e.adaptation, e.motion_filter
    return [
        "## Sec. 6 options: sensor offset, target-distance adaptation, motion filter",
        "",
        "Wu et al. 2021 (Sec. 5-6) name these without equations; the models are the "
        "project's (`docs/accompanying.md`). Each option runs alone with the default PID; "
        f"the user's pelvis sway here: {e.sway_lateral:g} m lateral, {e.sway_yaw:g} rad yaw. "
        f"Mount: sensor at ({m.offset_x:g}, {m.offset_y:g}) m (right, forward) from the "
        f"rotation centre. Adaptation: k_a = {a.gain:g} s, Delta_max = {a.max_change:g} m, "
        f"T_a = {a.time_constant:g} s. Motion filter: T_m = {f.time_constant:g} s. The errors "
        "are those of the sensor point against the fixed target (an adapted target moves "
        "away from it on purpose).",
        "",
        *claims(extras_claims(table, (m.offset_x, m.offset_y))),
        markdown_table(table, floatfmt=".4g"),
        "",
    ]
