"""Sensitivity tables: local elasticities, one-at-a-time percentages, Sobol indices.

Three views of how a metric depends on the design parameters, each a
:class:`SensitivityTable` (a long pandas frame with ranked CSV/Markdown
output in the manner of GPkit's sensitivity tables):

* :func:`elasticity_table` - local elasticities ``d ln(metric) / d ln(p)``
  at the base design (for smooth metrics; the impact metrics get them
  exactly by CasADi automatic differentiation). An elasticity of +0.5 means
  a 1 % larger parameter gives a 0.5 % larger metric.
* :func:`one_at_a_time_table` - the metric when each parameter alone is
  changed by a list of percentages, with the relative sensitivity
  ``S = (Δm / m0) / (Δp / p0)`` in % (Zeng 2011, App. C, eqs. C.3.1-C.3.4).
* :func:`sobol_table` - first-order and total Sobol indices from SALib
  (variance-based, global; for metrics that are not smooth or not monotone).

:func:`range_table` and :func:`tornado_figure` give the tornado plot: the
metric with each parameter at the low and the high end of its range.

Examples
--------
>>> t = elasticity_table({"a_h_max_g": {"M_r": 0.21, "K_c": 0.45, "v_c": 1.0}})
>>> print(t.to_markdown("a_h_max_g"))
| parameter   |   elasticity |
|:------------|-------------:|
| v_c         |         1    |
| K_c         |         0.45 |
| M_r         |         0.21 |
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from designlab.analysis.sampling import saltelli
from designlab.params import ARG

__all__ = [
    "MetricFunction",
    "SensitivityTable",
    "elasticities",
    "elasticity_table",
    "one_at_a_time",
    "one_at_a_time_table",
    "range_table",
    "sobol_indices",
    "sobol_table",
    "tornado_figure",
]


@dataclass(frozen=True)
class SensitivityTable:
    """A sensitivity table: one row per (metric, parameter[, perturbation]).

    Attributes
    ----------
    kind
        ``"elasticity"``, ``"one_at_a_time"``, ``"sobol"`` or ``"range"``.
    frame
        Long table with columns ``metric``, ``parameter`` and the values.
    rank_by
        The column whose absolute value orders the ranked tables.
    columns
        The value columns shown in Markdown.
    descriptions
        Parameter -> description (with unit), shown when given.
    """

    kind: str
    frame: pd.DataFrame
    rank_by: str
    columns: tuple[str, ...]
    descriptions: dict[str, str] = field(default_factory=dict)

    @property
    def metrics(self) -> list[str]:
        """Metrics in the table, in order."""
        return list(dict.fromkeys(self.frame["metric"]))

    def to_frame(self) -> pd.DataFrame:
        """The long table (a copy)."""
        return self.frame.copy()

    def ranked(self, metric: str) -> pd.DataFrame:
        """Rows of ``metric``, most influential parameter first (by ``|rank_by|``).

        Parameters
        ----------
        metric
            The metric whose table to rank.
        """
        rows = self.frame[self.frame["metric"] == metric].copy()
        order = rows[self.rank_by].abs().fillna(-1.0).sort_values(ascending=False, kind="stable")
        rows = rows.loc[order.index]
        cols = ["parameter", *self.columns]
        if self.descriptions:
            rows["description"] = [self.descriptions.get(p, "") for p in rows["parameter"]]
            cols.append("description")
        return rows[cols].reset_index(drop=True)

    def to_markdown(self, metric: str | None = None, floatfmt: str = ".4g") -> str:
        """Ranked Markdown table(s); one section per metric unless ``metric`` is given.

        Parameters
        ----------
        metric
            The metric whose table to show.
        floatfmt
            Number format of the values.
        """
        if metric is not None:
            return str(self.ranked(metric).to_markdown(index=False, floatfmt=floatfmt))
        parts = []
        for m in self.metrics:
            parts += [f"**{m}**", "", self.to_markdown(m, floatfmt), ""]
        return "\n".join(parts).rstrip()

    def to_csv(self) -> str:
        """The long table as CSV text (7 significant digits)."""
        return str(self.frame.to_csv(index=False, float_format="%.7g", lineterminator="\n"))


def elasticity_table(
    elasticities: Mapping[str, Mapping[str, float]],
    descriptions: Mapping[str, str] | None = None,
) -> SensitivityTable:
    """Local elasticities, ``{metric: {parameter: d ln m / d ln p}}``.

    Parameters
    ----------
    elasticities
        ``{metric: {parameter: d ln m / d ln p}}``.
    descriptions
        Parameter -> description (with unit), shown in the tables.
    """
    rows = [
        {"metric": m, "parameter": p, "elasticity": float(v)}
        for m, per in elasticities.items()
        for p, v in per.items()
    ]
    return SensitivityTable(
        "elasticity", pd.DataFrame(rows), "elasticity", ("elasticity",), dict(descriptions or {})
    )


def one_at_a_time_table(
    base: Mapping[str, float],
    rows: Sequence[tuple[str, float, float, Mapping[str, float]]],
    descriptions: Mapping[str, str] | None = None,
) -> SensitivityTable:
    """The Appendix-C table: metrics and relative sensitivities per perturbation.

    Parameters
    ----------
    base
        Metric values at the base design.
    rows
        ``(parameter, delta_pct, parameter_value, {metric: value})``: the
        metrics with one parameter changed by ``delta_pct`` % (NaN if the
        point failed).
    descriptions
        Parameter descriptions.

    Returns
    -------
    SensitivityTable
        Columns ``delta_pct``, ``value`` (the parameter), ``metric_value``,
        ``change_pct`` = 100 Δm/m0 and ``S_pct`` = 100 (Δm/m0)/(Δp/p0); the
        ranked view lists, per parameter, the largest ``|S_pct|``.

    Examples
    --------
    >>> t = one_at_a_time_table({"y": 2.0}, [("k", 10.0, 1.1, {"y": 2.1}),
    ...                                      ("k", -10.0, 0.9, {"y": 1.92})])
    >>> t.frame[["delta_pct", "change_pct", "S_pct"]].round(3).values.tolist()
    [[-10.0, -4.0, 40.0], [10.0, 5.0, 50.0]]
    >>> t.summary()[["parameter", "S_max_pct", "S_mean_pct"]].values.tolist()
    [['k', 50.0, 45.0]]
    """
    out = []
    for param, delta, value, metrics in rows:
        for m, y in metrics.items():
            y0 = base.get(m, np.nan)
            with np.errstate(divide="ignore", invalid="ignore"):
                change = 100.0 * (y - y0) / y0 if y0 else np.nan
            s = change / delta * 100.0 if delta else np.nan
            out.append(
                {
                    "metric": m,
                    "parameter": param,
                    "delta_pct": float(delta),
                    "value": float(value),
                    "metric_value": float(y),
                    "change_pct": float(change),
                    "S_pct": float(s),
                }
            )
    frame = pd.DataFrame(out)
    if len(frame):
        frame = frame.sort_values(["metric", "parameter", "delta_pct"], kind="stable")
        frame = frame.reset_index(drop=True)
    return _OATTable(
        "one_at_a_time",
        frame,
        "S_max_pct",
        ("S_max_pct", "S_mean_pct"),
        dict(descriptions or {}),
    )


@dataclass(frozen=True)
class _OATTable(SensitivityTable):
    """One-at-a-time table; ranked by the largest |S| over the perturbations."""

    def summary(self) -> pd.DataFrame:
        """Per metric and parameter: max and mean of ``|S_pct|`` (App. C.3 style)."""
        f = self.frame.assign(abs_S=self.frame["S_pct"].abs())
        g = f.groupby(["metric", "parameter"], sort=False)["abs_S"]
        return pd.DataFrame({"S_max_pct": g.max(), "S_mean_pct": g.mean()}).reset_index()

    def ranked(self, metric: str) -> pd.DataFrame:
        s = self.summary()
        rows = s[s["metric"] == metric]
        rows = rows.iloc[np.argsort(-rows["S_max_pct"].fillna(-1.0).to_numpy(), kind="stable")]
        cols = ["parameter", *self.columns]
        rows = rows.copy()
        if self.descriptions:
            rows["description"] = [self.descriptions.get(p, "") for p in rows["parameter"]]
            cols.append("description")
        return rows[cols].reset_index(drop=True)

    def percentage_table(self, metric: str) -> pd.DataFrame:
        """Wide App.-C form for one metric: rows Δ%, a value and S column per parameter."""
        f = self.frame[self.frame["metric"] == metric]
        wide = f.pivot_table(
            index="delta_pct", columns="parameter", values=["metric_value", "S_pct"], sort=False
        )
        wide.columns = [f"{p} {'S %' if v == 'S_pct' else metric}" for v, p in wide.columns]
        params = list(dict.fromkeys(f["parameter"]))
        cols = [c for p in params for c in (f"{p} {metric}", f"{p} S %") if c in wide.columns]
        return wide[cols].reset_index()


def sobol_table(
    names: Sequence[str],
    bounds: Sequence[tuple[float, float]],
    outputs: Mapping[str, ArrayLike],
    *,
    seed: int = ARG.seed.default,
    descriptions: Mapping[str, str] | None = None,
) -> SensitivityTable:
    """First-order (S1) and total (ST) Sobol indices with 95 % confidence half-widths.

    ``outputs[metric]`` are the model outputs at the points of
    :func:`designlab.analysis.sampling.saltelli` (same names, bounds and
    order). Points that failed (NaN) make the indices of that metric NaN.

    Parameters
    ----------
    names
        Parameter names, in the order of the sample.
    bounds
        ``(low, high)`` of each parameter.
    outputs
        Metric -> outputs at the points of :func:`designlab.analysis.sampling.saltelli`.
    seed
        Seed of the bootstrap confidence intervals.
    descriptions
        Parameter -> description (with unit).
    """
    from SALib.analyze import sobol

    problem = {"num_vars": len(names), "names": list(names), "bounds": [list(b) for b in bounds]}
    # SALib seeds its bootstrap only for a truthy seed (``if seed:``): seed 0 would leave the
    # intervals unseeded (different on every run), so 0 is passed as 2**32 (not a valid seed
    # of the sample, so no other seed maps to it).
    boot = seed if seed else 2**32
    rows = []
    for metric, y in outputs.items():
        y = np.asarray(y, dtype=float)
        if np.all(np.isfinite(y)) and np.ptp(y) > 0:
            res = sobol.analyze(problem, y, calc_second_order=False, seed=boot)
            vals = {k: res[k] for k in ("S1", "S1_conf", "ST", "ST_conf")}
        else:
            vals = {k: np.full(len(names), np.nan) for k in ("S1", "S1_conf", "ST", "ST_conf")}
        for j, name in enumerate(names):
            rows.append(
                {"metric": metric, "parameter": name} | {k: float(v[j]) for k, v in vals.items()}
            )
    return SensitivityTable(
        "sobol",
        pd.DataFrame(rows),
        "ST",
        ("S1", "S1_conf", "ST", "ST_conf"),
        dict(descriptions or {}),
    )


def range_table(
    base: Mapping[str, float],
    rows: Sequence[tuple[str, float, float, Mapping[str, float], Mapping[str, float]]],
    descriptions: Mapping[str, str] | None = None,
) -> SensitivityTable:
    """Metric at each parameter's low and high end (others at base): the tornado data.

    ``rows`` are ``(parameter, low, high, metrics_at_low, metrics_at_high)``;
    ``swing`` = metric(high) - metric(low), ranked by ``|swing|``.

    Parameters
    ----------
    base
        Metric values at the base design.
    rows
        ``(parameter, low, high, metrics_at_low, metrics_at_high)``.
    descriptions
        Parameter -> description (with unit).
    """
    out = []
    for param, lo, hi, at_lo, at_hi in rows:
        for m in at_lo:
            out.append(
                {
                    "metric": m,
                    "parameter": param,
                    "low": float(lo),
                    "high": float(hi),
                    "base_metric": float(base.get(m, np.nan)),
                    "metric_at_low": float(at_lo[m]),
                    "metric_at_high": float(at_hi[m]),
                    "swing": float(at_hi[m] - at_lo[m]),
                }
            )
    return SensitivityTable(
        "range",
        pd.DataFrame(out),
        "swing",
        ("low", "high", "metric_at_low", "metric_at_high", "swing"),
        dict(descriptions or {}),
    )


def tornado_figure(table: SensitivityTable, metric: str, *, title: str | None = None):  # type: ignore[no-untyped-def]
    """Tornado plot of a :func:`range_table`: bars from the base value to each end.

    Returns a :class:`matplotlib.figure.Figure` (not shown, not saved).

    Parameters
    ----------
    table
        A ``range`` table (:func:`range_table`).
    metric
        The metric to plot.
    title
        Figure title (default: the metric).
    """
    from matplotlib.figure import Figure

    rows = table.ranked(metric).iloc[::-1]
    full = table.frame[table.frame["metric"] == metric]
    base = float(full["base_metric"].iloc[0]) if len(full) else np.nan
    fig = Figure(figsize=(7.0, 0.45 * max(len(rows), 3) + 1.4))
    ax = fig.add_subplot()
    y = np.arange(len(rows))
    lo = rows["metric_at_low"].to_numpy() - base
    hi = rows["metric_at_high"].to_numpy() - base
    ax.barh(y, lo, left=base, color="#4c72b0", label="parameter at low end")
    ax.barh(y, hi, left=base, color="#dd8452", label="parameter at high end")
    ax.axvline(base, color="k", lw=0.8)
    labels = [
        f"{p}  [{a:.4g}, {b:.4g}]"
        for p, a, b in zip(rows["parameter"], rows["low"], rows["high"], strict=True)
    ]
    ax.set_yticks(y, labels)
    ax.set_ylabel("parameter")
    ax.set_xlabel(metric)
    ax.set_title(title or f"Tornado: {metric} (base {base:.4g})")
    ax.legend(loc="best", fontsize="small")
    fig.tight_layout()
    return fig


# --- the same tables for any callable metric --------------------------------------------

#: ``metric(points) -> {metric name: values}``: points are columns (name -> array), one
#: value per point; a failed point is NaN. Navigation gains, follower and PID gains and the
#: impact models all fit this shape.
MetricFunction = Callable[[dict[str, np.ndarray]], Mapping[str, ArrayLike]]


def _call(metric: MetricFunction, points: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    out = metric(points)
    n = len(next(iter(points.values())))
    res = {str(k): np.asarray(v, dtype=float).reshape(-1) for k, v in out.items()}
    for k, v in res.items():
        if v.shape != (n,):
            raise ValueError(f"metric {k!r} returned {v.shape[0]} values for {n} points")
    return res


def _replicate(base: Mapping[str, float], n: int) -> dict[str, np.ndarray]:
    return {k: np.full(n, float(v)) for k, v in base.items()}


def one_at_a_time(
    metric: MetricFunction,
    base: Mapping[str, float],
    parameters: Sequence[str],
    deltas_pct: Sequence[float] = (-50, -20, -10, -5, -2, 2, 5, 10, 20, 50),
    descriptions: Mapping[str, str] | None = None,
) -> SensitivityTable:
    """The Appendix-C table (Zeng 2011, eqs. C.3.1-C.3.4) of any vectorised metric.

    Each parameter alone is changed by each percentage; all the points are
    evaluated in one call of ``metric``.

    Parameters
    ----------
    metric
        ``metric(points) -> {name: values}`` (see :data:`MetricFunction`).
    base
        The base point (every parameter the metric needs).
    parameters
        Names in ``base`` to perturb.
    deltas_pct
        Perturbations, % of the base value (-100 sets the parameter to zero).
    descriptions
        Parameter -> description, shown in the tables.

    Examples
    --------
    >>> def power(p):
    ...     return {"y": p["a"] ** 2 * p["b"]}
    >>> t = one_at_a_time(power, {"a": 2.0, "b": 3.0}, ["a", "b"], [10])
    >>> t.frame.set_index("parameter")["S_pct"].round(1).to_dict()
    {'a': 210.0, 'b': 100.0}
    """
    names = list(parameters)
    unknown = [p for p in names if p not in base]
    if unknown:
        raise ValueError(f"parameters {unknown} are not in the base point {sorted(base)}")
    changes = [
        (p, float(d), float(base[p]) * (1 + float(d) / 100)) for p in names for d in deltas_pct
    ]
    pts = _replicate(base, len(changes) + 1)
    for i, (p, _, x) in enumerate(changes, start=1):
        pts[p][i] = x
    values = _call(metric, pts)
    at_base = {m: float(v[0]) for m, v in values.items()}
    rows = [(p, d, x, {m: float(v[i]) for m, v in values.items()})
            for i, (p, d, x) in enumerate(changes, start=1)]  # fmt: skip
    return one_at_a_time_table(at_base, rows, descriptions)


def elasticities(
    metric: MetricFunction,
    base: Mapping[str, float],
    parameters: Sequence[str],
    *,
    relative_step: float = 1e-4,
    descriptions: Mapping[str, str] | None = None,
) -> SensitivityTable:
    """Local elasticities ``d ln m / d ln p`` of any metric by central differences.

    For models with exact derivatives (the impact domain: CasADi AD) prefer
    those; this serves metrics without them (simulated navigation or
    follower runs, where the step must stay above the simulation's noise).

    Parameters
    ----------
    metric
        ``metric(points) -> {name: values}``.
    base
        The base point.
    parameters
        Names in ``base`` to differentiate against (their base values must be
        non-zero).
    relative_step
        Relative step of the central difference.
    descriptions
        Parameter -> description.

    Examples
    --------
    >>> t = elasticities(lambda p: {"y": p["a"] ** 2 * p["b"] ** -0.5}, {"a": 2.0, "b": 3.0},
    ...                  ["a", "b"])
    >>> t.frame.set_index("parameter")["elasticity"].round(6).to_dict()
    {'a': 2.0, 'b': -0.5}
    """
    if not relative_step > 0:
        raise ValueError(f"relative_step = {relative_step!r} must be > 0")
    names = list(parameters)
    pts = _replicate(base, 2 * len(names) + 1)
    for j, p in enumerate(names):
        if float(base[p]) == 0:
            raise ValueError(f"parameter {p!r} is 0 at the base: no elasticity")
        pts[p][1 + 2 * j] *= 1 + relative_step
        pts[p][2 + 2 * j] *= 1 - relative_step
    values = _call(metric, pts)
    out: dict[str, dict[str, float]] = {}
    for m, v in values.items():
        for j, p in enumerate(names):
            up, down, mid = v[1 + 2 * j], v[2 + 2 * j], v[0]
            with np.errstate(divide="ignore", invalid="ignore"):
                out.setdefault(m, {})[p] = float((up - down) / (2 * relative_step * mid))
    return elasticity_table(out, descriptions)


def sobol_indices(
    metric: MetricFunction,
    base: Mapping[str, float],
    bounds: Mapping[str, tuple[float, float]],
    samples: int = 256,
    *,
    seed: int = ARG.seed.default,
    descriptions: Mapping[str, str] | None = None,
) -> SensitivityTable:
    """First-order and total Sobol indices of any metric over a box (SALib).

    Parameters
    ----------
    metric
        ``metric(points) -> {name: values}``, called once on the whole sample.
    base
        Values of the parameters that are not varied.
    bounds
        Name -> (low, high) of the varied parameters (at least two).
    samples
        Base sample size N, a power of two; ``N (D + 2)`` evaluations.
    seed
        Seed of the sample and the bootstrap.
    descriptions
        Parameter -> description.

    Examples
    --------
    >>> box = {"a": (0, 1), "b": (0, 1)}
    >>> t = sobol_indices(lambda p: {"y": 10 * p["a"] + p["b"]}, {}, box, 512)
    >>> t.ranked("y")["parameter"].tolist()
    ['a', 'b']
    """
    if len(bounds) < 2:
        raise ValueError("Sobol indices need at least two varied parameters")
    sample = saltelli(bounds, samples, seed=seed)
    n = len(next(iter(sample.values())))
    pts = _replicate(base, n)
    pts.update(sample)
    values = _call(metric, pts)
    return sobol_table(list(bounds), list(bounds.values()), values, seed=seed,
                       descriptions=descriptions)  # fmt: skip
