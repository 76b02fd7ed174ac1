"""Published follower accuracy of Allan 2015 (Tables 3.2 and 3.3).

Normal path deviation of the robot from the leader, normalised by the wheel
track b = 0.28 m, for Pseudo-Joystick (PJ, "method A") and Follow the Leader
with Constant Distance (FTL-CD, "method B"): five healthy subjects on the
motion-capture slalom (Table 3.2, Sec. 3.3-3.4) and five home-oxygen-therapy
patients on the cone course (Table 3.3, Sec. 3.5). The "Average" rows are the
arithmetic means of the subject rows, also for the standard deviations.

Examples
--------
>>> t = allan_tables()
>>> float(t["table_3_2"].set_index("subject").loc["Average", "pj_mean_dev_over_b"])
0.423
>>> round(measured_ratio("table_3_3"), 2)
1.27
"""

from __future__ import annotations

from importlib import resources

import pandas as pd

from designlab.errors import InvalidParameterError

__all__ = ["TABLES", "allan_tables", "measured_ratio"]

#: Table name -> (CSV in designlab/data, caption).
TABLES = {
    "table_3_2": (
        "following_mocap_table3_2.csv",
        "Allan 2015 Table 3.2: motion capture, healthy leaders",
    ),
    "table_3_3": (
        "following_patients_table3_3.csv",
        "Allan 2015 Table 3.3: home oxygen therapy patients",
    ),
}


def allan_tables() -> dict[str, pd.DataFrame]:
    """Tables 3.2 and 3.3 as DataFrames (columns ``subject``, ``pj_mean_dev_over_b``, ...)."""
    out = {}
    for key, (name, _) in TABLES.items():
        with resources.files("designlab.data").joinpath(name).open("r") as fh:
            out[key] = pd.read_csv(fh, dtype={"subject": str})
    return out


def measured_ratio(table: str) -> float:
    """Average PJ deviation over average FTL-CD deviation of a table (1.53 and 1.27).

    Parameters
    ----------
    table
        ``"3.2"`` or ``"3.3"`` (Allan 2015 Tables 3.2 and 3.3).
    """
    if table not in TABLES:
        raise InvalidParameterError("table", table, f"one of {sorted(TABLES)}")
    avg = allan_tables()[table].set_index("subject").loc["Average"]
    return float(avg["pj_mean_dev_over_b"]) / float(avg["ftlcd_mean_dev_over_b"])
