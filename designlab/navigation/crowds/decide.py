"""What a crowd study decides (issue 35, item 6): exact McNemar tests between methods on
paired crowds, the minimum detectable difference, and the success rate against the time
limit, all from a study's runs frame.

* :func:`mcnemar` -- per layout and density, every pair of methods met the same crowds
  (seeds): of the crowds where exactly one of the two arrived, the exact two-sided binomial
  test of "each as likely" (McNemar's exact test: :func:`scipy.stats.binomtest` with p = 1/2
  on the discordant pairs).
* :func:`minimum_detectable_difference` -- the smallest difference of two success rates a
  two-sided test at level alpha detects with the power asked, for n runs per arm, at the
  worst case p = 1/2 (normal approximation): (z_{1-alpha/2} + z_power) sqrt(2 p (1-p) / n).
* :func:`time_limit_curve` -- the success rate if the time limit had been k times the free
  run time, for every k up to the study's own: a run arrived within k T_free with no earlier
  event (the runs record when they arrived, so one study at the longest limit gives every
  shorter one exactly).

Examples
--------
>>> round(minimum_detectable_difference(100), 3)
0.198
"""

from __future__ import annotations

import math
from itertools import combinations
from typing import Any

import numpy as np
import pandas as pd
from scipy.stats import binomtest, norm

from designlab.errors import InvalidParameterError
from designlab.navigation.crowds.metrics import wilson_interval
from designlab.params import ARG

__all__ = ["decision_findings", "mcnemar", "minimum_detectable_difference", "time_limit_curve"]


def minimum_detectable_difference(n: int, alpha: float = 0.05, power: float = 0.8) -> float:
    """The smallest difference of two success rates detectable with ``n`` runs per arm.

    Parameters
    ----------
    n
        Runs per arm (>= 1).
    alpha
        Two-sided level.
    power
        Power asked.
    """
    if not (isinstance(n, int | np.integer) and n >= 1):
        raise InvalidParameterError("n", n, "must be an integer >= 1")
    if not (0 < alpha < 1 and 0 < power < 1):
        raise InvalidParameterError("alpha, power", (alpha, power), "must be in (0, 1)")
    z = norm.ppf(1 - alpha / 2) + norm.ppf(power)
    return float(z * math.sqrt(2 * 0.25 / n))


def mcnemar(runs: pd.DataFrame, outcome: str = "success") -> pd.DataFrame:
    """Exact McNemar tests of ``outcome`` between every two methods, per layout and density.

    Parameters
    ----------
    runs
        A study's runs: ``scenario``, ``density``, ``seed``, ``method`` and ``outcome``'s
        0/1 column (runs that raised are left out, and their crowds with them).
    outcome
        The 0/1 column compared (``"success"``, ``"collided"``, ...).

    Returns
    -------
    DataFrame
        ``scenario``, ``density``, ``a``, ``b``, ``pairs`` (crowds both ran), ``a_rate``,
        ``b_rate``, ``a_only``, ``b_only`` (discordant pairs), ``p_value`` (exact,
        two-sided; 1 without discordant pairs).

    Examples
    --------
    >>> runs = pd.DataFrame({"scenario": "x", "density": 1.0, "seed": [0, 0, 1, 1, 2, 2],
    ...     "method": ["p", "q"] * 3, "success": [1, 0, 1, 0, 1, 1]})
    >>> r = mcnemar(runs).iloc[0]
    >>> int(r.a_only), int(r.b_only), float(r.p_value)
    (2, 0, 0.5)
    """
    need = {"scenario", "density", "seed", "method", outcome}
    if not isinstance(runs, pd.DataFrame) or not need <= set(runs.columns):
        raise InvalidParameterError("runs", type(runs).__name__, f"must have columns {need}")
    ok = runs[runs["status"].astype(str) != "error"] if "status" in runs else runs
    rows = []
    for (scen, dens), g in ok.groupby(["scenario", "density"], sort=False):
        wide = g.pivot_table(index="seed", columns="method", values=outcome, aggfunc="first")
        methods = [m for m in dict.fromkeys(g["method"]) if m in wide.columns]
        for a, b in combinations(methods, 2):
            both = wide[[a, b]].dropna()
            x, y = both[a].to_numpy() > 0, both[b].to_numpy() > 0
            na, nb = int((x & ~y).sum()), int((~x & y).sum())
            p = binomtest(na, na + nb, 0.5).pvalue if na + nb else 1.0
            rows.append({"scenario": scen, "density": dens, "a": a, "b": b,
                         "pairs": len(both), "a_rate": float(x.mean()) if len(both) else math.nan,
                         "b_rate": float(y.mean()) if len(both) else math.nan,
                         "a_only": na, "b_only": nb, "p_value": float(p)})  # fmt: skip
    return pd.DataFrame(rows)


def time_limit_curve(
    runs: pd.DataFrame, factors: Any, confidence: float = ARG.confidence.default
) -> pd.DataFrame:
    """Success rates (with Wilson intervals) had the time limit been ``k`` x the free-run time.

    Parameters
    ----------
    runs
        A study's runs: ``scenario``, ``density``, ``method``, ``success``,
        ``arrival_time_s``, ``outcome_time_s``, ``free_run_s``, ``time_limit_s``.
    factors
        The factors k; each must keep k T_free within every run's own limit.
    confidence
        Of the intervals.

    Returns
    -------
    DataFrame
        ``scenario``, ``density``, ``method``, ``factor``, ``runs``, ``success_rate``,
        ``success_low``, ``success_high``.

    Examples
    --------
    >>> runs = pd.DataFrame({"scenario": "x", "density": 1.0, "method": "m",
    ...     "success": [1.0, 1.0, 0.0], "arrival_time_s": [10.0, 25.0, np.inf],
    ...     "outcome_time_s": [10.0, 25.0, 30.0], "free_run_s": 10.0, "time_limit_s": 30.0})
    >>> time_limit_curve(runs, [1.5, 3.0])["success_rate"].round(3).tolist()
    [0.333, 0.667]
    """
    ok = runs[runs["status"].astype(str) != "error"] if "status" in runs else runs
    ks = [float(k) for k in factors]
    limit = (ok["time_limit_s"] / ok["free_run_s"]).min() if len(ok) else math.inf
    if any(k <= 0 or k > limit + 1e-9 for k in ks):
        raise InvalidParameterError("factors", ks, f"must be in (0, {limit:.3g}] (the runs' limit)")
    rows = []
    for key, g in ok.groupby(["scenario", "density", "method"], sort=False):
        for k in ks:
            arrived = (g["success"] > 0) & (g["arrival_time_s"] <= k * g["free_run_s"])
            n, s = len(g), int(arrived.sum())
            lo, hi = wilson_interval(s, n, confidence)
            rows.append(dict(zip(("scenario", "density", "method"), key, strict=True))
                        | {"factor": k, "runs": n, "success_rate": s / n if n else math.nan,
                           "success_low": lo, "success_high": hi})  # fmt: skip
    return pd.DataFrame(rows)


def decision_findings(tests: pd.DataFrame, n: int, alpha: float = 0.05) -> list[str]:
    """Sentences from :func:`mcnemar`'s table, each with its p-value; then the minimum
    detectable difference for ``n`` paired crowds per cell.

    Parameters
    ----------
    tests
        :func:`mcnemar`'s table.
    n
        Crowds per cell.
    alpha
        The level a difference is called significant at (Holm's correction is not
        applied: every p-value is given).

    Examples
    --------
    >>> t = pd.DataFrame([{"scenario": "x", "density": 1.0, "a": "p", "b": "q", "pairs": 100,
    ...     "a_rate": 0.6, "b_rate": 0.3, "a_only": 35, "b_only": 5, "p_value": 1e-6}])
    >>> print(decision_findings(t, 100)[0][-64:])
    more often (35 vs 5 discordant crowds, exact McNemar p = 1e-06).
    """
    out = []
    for _, r in tests.iterrows():
        head = (f"- {r['scenario']} at {r['density']:g}/m^2: {r['a']} arrived in "
                f"{r['a_rate']:.0%} of {int(r['pairs'])} paired crowds, {r['b']} in "
                f"{r['b_rate']:.0%}; ").replace("%", " %")  # fmt: skip
        if r["p_value"] < alpha:
            more = r["a"] if r["a_only"] > r["b_only"] else r["b"]
            out.append(f"{head}{more} more often ({int(r['a_only'])} vs {int(r['b_only'])} "
                       f"discordant crowds, exact McNemar p = {r['p_value']:.2g}).")  # fmt: skip
        else:
            out.append(f"{head}no difference shown ({int(r['a_only'])} vs "
                       f"{int(r['b_only'])} discordant crowds, exact McNemar "
                       f"p = {r['p_value']:.2g}).")  # fmt: skip
    mdd = minimum_detectable_difference(max(int(n), 1), alpha)
    out.append(f"- With {n} crowds per cell, a difference of success rates below {mdd:.2f} "
               f"(two-sided level {alpha:g}, 80 % power, worst case p = 1/2) can go "
               "undetected.")  # fmt: skip
    return out
