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

__all__ = [
    "cell_keys",
    "decision_findings",
    "holm",
    "mcnemar",
    "minimum_detectable_difference",
    "time_limit_curve",
]


def cell_keys(runs: pd.DataFrame) -> list[str]:
    """The columns naming a cell of a study's runs: ``model`` (the pedestrian model, when the
    runs have it), ``scenario`` and ``density``.

    Parameters
    ----------
    runs
        A study's runs.

    Examples
    --------
    >>> cell_keys(pd.DataFrame(columns=["scenario", "density", "model", "seed"]))
    ['model', 'scenario', 'density']
    """
    return [k for k in ("model", "scenario", "density") if k in runs.columns or k != "model"]


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
    """Exact McNemar tests of ``outcome`` between every two methods, per cell
    (:func:`cell_keys`: pedestrian model, layout and density).

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
        The cell's keys, ``a``, ``b``, ``pairs`` (crowds both ran), ``a_rate``,
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
    keys = cell_keys(ok)
    for cell, g in ok.groupby(keys, sort=False):
        wide = g.pivot_table(index="seed", columns="method", values=outcome, aggfunc="first")
        methods = [m for m in dict.fromkeys(g["method"]) if m in wide.columns]
        for a, b in combinations(methods, 2):
            both = wide[[a, b]].dropna()
            x, y = both[a].to_numpy() > 0, both[b].to_numpy() > 0
            na, nb = int((x & ~y).sum()), int((~x & y).sum())
            p = binomtest(na, na + nb, 0.5).pvalue if na + nb else 1.0
            rows.append(dict(zip(keys, cell, strict=True)) | {"a": a, "b": b,
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
        The cell's keys (:func:`cell_keys`), ``method``, ``factor``, ``runs``, ``success_rate``,
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
    keys = [*cell_keys(ok), "method"]
    for key, g in ok.groupby(keys, sort=False):
        for k in ks:
            arrived = (g["success"] > 0) & (g["arrival_time_s"] <= k * g["free_run_s"])
            n, s = len(g), int(arrived.sum())
            lo, hi = wilson_interval(s, n, confidence)
            rows.append(dict(zip(keys, key, strict=True))
                        | {"factor": k, "runs": n, "success_rate": s / n if n else math.nan,
                           "success_low": lo, "success_high": hi})  # fmt: skip
    return pd.DataFrame(rows)


def holm(p_values: Any) -> np.ndarray:
    """Holm's step-down adjusted p-values (family-wise error over all the tests given).

    Parameters
    ----------
    p_values
        The raw p-values, in [0, 1].

    Examples
    --------
    >>> holm([0.01, 0.04, 0.03]).tolist()
    [0.03, 0.06, 0.06]
    """
    p = np.asarray(p_values, dtype=float).ravel()
    if p.size and not (np.all(p >= 0) and np.all(p <= 1)):
        raise InvalidParameterError("p_values", p.tolist(), "must be in [0, 1]")
    order = np.argsort(p, kind="stable")
    steps = (p.size - np.arange(p.size)) * p[order]
    adj = np.empty_like(p)
    adj[order] = np.minimum(np.maximum.accumulate(steps), 1.0)
    return adj


def _sentence(r: pd.Series, alpha: float) -> str:
    among = f" among {r['model']} pedestrians" if "model" in r else ""
    head = (f"- {r['scenario']} at {r['density']:g}/m^2{among}: {r['a']} arrived in "
            f"{r['a_rate']:.0%} of {int(r['pairs'])} paired crowds, {r['b']} in "
            f"{r['b_rate']:.0%}; ").replace("%", " %")  # fmt: skip
    tail = (f"({int(r['a_only'])} vs {int(r['b_only'])} discordant crowds, exact McNemar "
            f"p = {r['p_value']:.2g}, Holm-adjusted {r['p_holm']:.2g}).")  # fmt: skip
    if r["p_holm"] < alpha:
        more = r["a"] if r["a_only"] > r["b_only"] else r["b"]
        return f"{head}{more} more often {tail}"
    return f"{head}no difference shown {tail}"


def decision_findings(tests: pd.DataFrame, n: int, alpha: float = 0.05,
                      shown: int = 60) -> list[str]:  # fmt: skip
    """Sentences from :func:`mcnemar`'s table, each with its p-value and its Holm-adjusted
    p-value over the whole table (a difference is called at ``alpha`` after Holm); then the
    minimum detectable difference for ``n`` paired crowds per cell.

    Parameters
    ----------
    tests
        :func:`mcnemar`'s table.
    n
        Crowds per cell (the smallest, if cells differ).
    alpha
        The family-wise level a difference is called significant at.
    shown
        Sentences at most: the differences shown first (smallest p first), then the tests
        with the most discordant crowds; the rest are counted (every test is in the table).

    Examples
    --------
    >>> t = pd.DataFrame([{"scenario": "x", "density": 1.0, "a": "p", "b": "q", "pairs": 100,
    ...     "a_rate": 0.6, "b_rate": 0.3, "a_only": 35, "b_only": 5, "p_value": 1e-6}])
    >>> print(decision_findings(t, 100)[0][-86:])
    more often (35 vs 5 discordant crowds, exact McNemar p = 1e-06, Holm-adjusted 1e-06).
    """
    if tests.empty:
        return ["- No two methods met the same crowds: nothing to test."]
    t = tests.assign(p_holm=holm(tests["p_value"]), discordant=tests["a_only"] + tests["b_only"])
    called = t["p_holm"] < alpha
    order = t.assign(called=~called).sort_values(
        ["called", "p_value", "discordant"], ascending=[True, True, False], kind="stable"
    )
    out = [_sentence(r, alpha) for _, r in order.head(int(shown)).iterrows()]
    if len(order) > shown:
        out.append(f"- {len(order) - int(shown)} more tests not listed here, none of them a "
                   "difference shown" if int(called.sum()) <= shown else
                   f"- {len(order) - int(shown)} more tests not listed here")  # fmt: skip
    out.append(f"- {int(called.sum())} of {len(t)} pairwise tests show a difference at "
               f"family-wise level {alpha:g} (Holm over all of them).")  # fmt: skip
    mdd = minimum_detectable_difference(max(int(n), 1), alpha)
    size = f"below {mdd:.2f}" if mdd < 1 else "of any size"
    out.append(f"- With {n} crowds per cell, a difference of success rates {size} "
               f"(two-sided level {alpha:g}, 80 % power, worst case p = 1/2, independent-arm "
               "approximation) can go undetected.")  # fmt: skip
    return out
