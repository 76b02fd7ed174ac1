"""Exact derivatives of the impact metrics by CasADi automatic differentiation.

The response at a time ``t`` of the constant-velocity impact is written in
CasADi symbols from the model's state space (:mod:`designlab.impact.model`)
through a symbolic matrix exponential (scaling and squaring of a Taylor
polynomial), so it can be differentiated with respect to every physical
parameter, the impact velocity and time.

The metrics are maxima over the first lobe. Their derivatives follow from the
envelope theorem at an interior maximum (``d/dp max_t y = dy/dp`` at the
maximising time) and from the implicit function theorem at the lobe end
(``dt_imp/dp = -(da_h/dp) / (da_h/dt)``), so :func:`metric_gradients` is exact
wherever the metric is differentiable.

Examples
--------
>>> import numpy as np
>>> from designlab.impact.derivatives import metric_gradients
>>> from designlab.impact.model import PARAM_NAMES
>>> g = metric_gradients([[9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 46.0, 3e3]], 1.25,
...                      columns=PARAM_NAMES)
>>> e = g.elasticities("peak_head_acceleration")   # d ln a_h,max / d ln p
>>> round(float(e["v_c"][0]), 6)                   # a_h,max is linear in v_c
1.0
>>> bool(e["K_c"][0] > 0 and e["M_r"][0] > 0)
True
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from typing import Any

import casadi as ca
import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from designlab.impact.metrics import ImpactMetrics, metrics_of_matrix
from designlab.impact.model import PARAM_NAMES, constrained_model, unconstrained_model
from designlab.results import Result
from designlab.validation import named_columns

__all__ = ["VARIABLE_NAMES", "MetricGradients", "metric_gradients", "response_function"]

#: Names of the differentiation variables: the model parameters and v_c.
VARIABLE_NAMES: tuple[str, ...] = (*PARAM_NAMES, "v_c")

_SQUARINGS = 18
_TAYLOR_ORDER = 12


def _expm_sx(m: ca.SX) -> ca.SX:
    """Matrix exponential of a small symbolic matrix by scaling and squaring.

    ``exp(M) = (T_k(M / 2^s))^(2^s)`` with a degree-12 Taylor polynomial ``T_k``
    and ``s = 18``: accurate to double precision for ``||M|| <~ 1e5``, which
    covers the impact model over its first lobes.
    """
    n = m.shape[0]
    eye = ca.SX.eye(n)
    x = m / float(2**_SQUARINGS)
    e = eye
    for k in range(_TAYLOR_ORDER, 0, -1):  # Horner: I + X/1 (I + X/2 (I + ...))
        e = eye + (x @ e) / float(k)
    for _ in range(_SQUARINGS):
        e = e @ e
    return e


@cache
def response_function(constrained: bool = False) -> ca.Function:
    """``casadi.Function`` ``(t, p, v_c) -> y``: outputs of the constant-velocity impact.

    ``y`` is ordered as the model's ``output_names`` (force, head_acceleration,
    compression, compression_rate, head_velocity, robot_deflection). Exact to
    double precision and differentiable in ``t``, ``p`` and ``v_c``.
    """
    model = constrained_model() if constrained else unconstrained_model()
    n = model.n_states
    p = ca.SX.sym("p", len(PARAM_NAMES))
    t = ca.SX.sym("t")
    v = ca.SX.sym("v_c")
    a, b, c, d = model.state_space(p)
    # augmented state z = [x, s_c, v_c]: s_c' = v_c, v_c' = 0, a_d = 0
    big = ca.SX.zeros(n + 2, n + 2)
    big[:n, :n] = a
    big[:n, n] = b[:, 0]
    big[:n, n + 1] = b[:, 1]
    big[n, n + 1] = 1.0
    z0 = ca.vertcat(ca.SX.zeros(n + 1), v)
    z = _expm_sx(big * t) @ z0
    u = ca.vertcat(z[n], z[n + 1], 0.0)
    y = c @ z[:n] + d @ u
    return ca.Function(f"impact_{model.name}_response", [t, p, v], [y], ["t", "p", "v_c"], ["y"])


@cache
def _jacobian_function(constrained: bool) -> ca.Function:
    """``(t, p, v) -> (y, dy/dt, dy/d[p, v])`` for all outputs."""
    f = response_function(constrained)
    t = ca.SX.sym("t")
    p = ca.SX.sym("p", len(PARAM_NAMES))
    v = ca.SX.sym("v")
    y = f(t, p, v)
    pv = ca.vertcat(p, v)
    jac_pv = ca.jacobian(y, pv)
    jac_t = ca.jacobian(y, t)
    # express the jacobian in terms of pv by substituting
    return ca.Function(
        "impact_response_jacobian",
        [t, p, v],
        [y, jac_t, jac_pv],
        ["t", "p", "v_c"],
        ["y", "dy_dt", "dy_dpv"],
    )


@dataclass(frozen=True)
class MetricGradients(Result):
    """Gradients of the first-lobe metrics with respect to :data:`VARIABLE_NAMES`.

    Attributes
    ----------
    metrics
        The :class:`~designlab.impact.metrics.ImpactMetrics` they belong to.
    gradients
        Per metric name (``peak_head_acceleration``, ``max_compression``,
        ``peak_force``, ``impact_duration``), an ``(N, len(variables))`` array of
        partial derivatives in SI units.
    variables
        The differentiation variables: the contact model's columns and v_c
        (:data:`VARIABLE_NAMES` for the linear reduced model).
    method
        ``"exact"`` (automatic differentiation of the closed form) or
        ``"finite_differences"`` (central differences of integrated metrics, a non-linear
        contact's: :mod:`designlab.impact.contact.integrated`).
    """

    metrics: ImpactMetrics
    gradients: dict[str, NDArray[np.float64]]
    variables: tuple[str, ...] = VARIABLE_NAMES
    method: str = "exact"

    @property
    def status(self) -> str:  # type: ignore[override]
        """The status of the metrics the gradients belong to."""
        return self.metrics.status

    @property
    def warnings(self) -> tuple[str, ...]:  # type: ignore[override]
        """The warnings of the metrics the gradients belong to (and how they were obtained)."""
        if self.method == "exact":
            return self.metrics.warnings
        note = (
            "gradients by central finite differences of the integrated metrics (relative "
            "step 1e-5): about 1e-6 relative, not exact"
        )
        return (*self.metrics.warnings, note)

    def elasticities(self, metric: str) -> dict[str, NDArray[np.float64]]:
        """``d ln(metric) / d ln(x)`` for every variable ``x`` (NaN where the metric is 0)."""
        g = self.gradients[metric]
        values = getattr(self.metrics, metric)
        x = np.column_stack([self.metrics.params, self.metrics.impact_velocity])
        with np.errstate(divide="ignore", invalid="ignore"):
            e = g * x / values[:, None]
        return {name: e[:, k] for k, name in enumerate(self.variables)}

    def to_frame(self) -> pd.DataFrame:
        """Long table: design, metric, variable, derivative and elasticity."""
        rows = []
        for metric, g in self.gradients.items():
            el = self.elasticities(metric)
            for k, name in enumerate(self.variables):
                for i in range(g.shape[0]):
                    rows.append((i, metric, name, g[i, k], el[name][i]))
        return pd.DataFrame(
            rows, columns=["design", "metric", "variable", "derivative", "elasticity"]
        )


_OUT = {"force": 0, "head_acceleration": 1, "compression": 2}


def metric_gradients(
    params: Mapping[str, ArrayLike] | pd.DataFrame | ArrayLike,
    impact_velocity: ArrayLike,
    *,
    columns: Sequence[str] | None = None,
    constrained: bool = False,
    metrics: ImpactMetrics | None = None,
) -> MetricGradients:
    """Gradients of a_h,max, eps_max, peak force and impact period.

    Exact (automatic differentiation) for a contact model with the ``gradients``
    capability (the linear reduced model); central finite differences of the integrated
    metrics for a non-linear one (``linear=False``: its columns given), stated in the
    result's ``method`` and warnings; any other model is refused, naming it.

    Parameters
    ----------
    params
        The model parameters by name (a mapping or a DataFrame with the keys
        :data:`~designlab.impact.model.PARAM_NAMES`, or a non-linear contact model's
        columns), or an array with ``columns``, as for
        :func:`~designlab.impact.metrics.impact_metrics`.
    impact_velocity
        v_c, m/s.
    columns
        Names of the columns of an array ``params`` (required for an array).
    constrained
        Constrained impact (head against a wall).
    metrics
        Already computed metrics for the same inputs (saves the evaluation).

    Returns
    -------
    MetricGradients
    """
    contact = _contact_of(params, columns, metrics)
    if contact is not None and not contact.gradients:
        return _other_gradients(contact, params, impact_velocity, columns, constrained)
    if metrics is None:
        matrix = named_columns("params", params, PARAM_NAMES, columns=columns)
        metrics = metrics_of_matrix(matrix, impact_velocity, constrained=constrained)
    m = metrics
    p = m.params
    v = m.impact_velocity
    n = p.shape[0]
    jf = _jacobian_function(constrained)
    fn = jf.map(n) if n > 1 else jf

    def at(times: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        tt = np.where(np.isfinite(times), times, 0.0)
        y, dyt, dyp = fn(tt[None, :], p.T, v[None, :])
        y = np.asarray(y).reshape(-1, n, order="F")
        dyt = np.asarray(dyt).reshape(-1, n, order="F")
        dyp = np.asarray(dyp).reshape(y.shape[0], len(VARIABLE_NAMES), n, order="F")
        return y, dyt, dyp

    n_v = len(VARIABLE_NAMES)
    grads: dict[str, NDArray] = {}
    t_imp = m.impact_duration
    if constrained:
        dtimp = np.zeros((n, n_v))
    else:
        _, dyt_i, dyp_i = at(t_imp)
        a = _OUT["head_acceleration"]
        with np.errstate(divide="ignore", invalid="ignore"):
            dtimp = -dyp_i[a].T / dyt_i[a][:, None]
    grads["impact_duration"] = dtimp
    for metric, out, t_arg in (
        ("peak_head_acceleration", "head_acceleration", m.time_of_peak_acceleration),
        ("max_compression", "compression", m.time_of_max_compression),
        ("peak_force", "force", m.time_of_peak_force),
    ):
        if constrained and out == "head_acceleration":
            grads[metric] = np.zeros((n, n_v))
            continue
        if not np.any(np.isfinite(t_arg)):
            grads[metric] = np.full((n, n_v), np.nan)
            continue
        _, dyt, dyp = at(t_arg)
        k = _OUT[out]
        g = dyp[k].T.copy()
        # maximum at the lobe end: the end moves with the parameters
        at_end = np.isclose(t_arg, t_imp, rtol=1e-9, atol=0.0)
        if np.any(at_end):
            g[at_end] += dyt[k][at_end, None] * dtimp[at_end]
        grads[metric] = g
    none = v <= 0
    for g in grads.values():
        g[none] = 0.0
    return MetricGradients(m, grads)


def _contact_of(
    params: object, columns: Sequence[str] | None, metrics: ImpactMetrics | None
) -> Any:
    """The contact model of the inputs (``None``: the linear reduced model's columns)."""
    from designlab.impact.contact import CONTACTS, contact_for_columns

    if metrics is not None:
        return CONTACTS.get(metrics.contact) if metrics.contact else None
    keys = columns if columns is not None else getattr(params, "keys", lambda: ())()
    model = contact_for_columns(keys)
    return None if model is None or set(model.columns) == set(PARAM_NAMES) else model


def _other_gradients(
    contact: Any, params: object, v: ArrayLike, columns: Sequence[str] | None, constrained: bool
) -> MetricGradients:
    """Finite differences of an integrated model's metrics; any other model refused."""
    from designlab.errors import InvalidParameterError
    from designlab.impact.contact import CONTACTS

    if contact.linear:
        exact = CONTACTS.choices(gradients=True)
        integrated = CONTACTS.choices(linear=False)
        raise InvalidParameterError(
            "params", f"the {contact.name} contact's columns", f"have no gradients: exact "
            f"gradients serve {list(exact)}, finite differences the integrated {list(integrated)}",
        )  # fmt: skip
    matrix = named_columns("params", params, contact.columns, columns=columns)
    m, grads = contact.finite_difference_gradients(matrix, v, constrained=constrained)
    return MetricGradients(m, grads, (*contact.columns, "v_c"), "finite_differences")
