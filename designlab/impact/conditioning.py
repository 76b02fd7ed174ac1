"""How far apart the time scales of an impact design are: the conditioning of its arithmetic.

The impact models are linear ODEs whose exact solution is a sum of modes
``r_i exp(p_i t)`` plus the ramp's polynomial part (docs/impact.md, "Metrics"). When the
slowest mode is many orders of magnitude slower than the fastest (a manipulator of 1e13 kg
on a 4.4 kg head, a neck damping of 1e20 N s/m), the first lobe is a small difference of
huge slow-mode terms, nearly coincident slow poles cannot be told apart from the fast ones'
scale, and double precision no longer gives the declared accuracy. The ratio of the fastest
to the slowest pole modulus is the dimensionless measure of this; it is estimated here
without solving for the poles, from the characteristic polynomial's coefficients.

Every coefficient of the characteristic polynomial of these passive mass-spring-damper
networks is a sum of products of non-negative parameters, so it is computed to a few
rounding errors whatever the parameters. For a monic polynomial
``s^n + a_1 s^(n-1) + ... + a_n`` the largest root modulus lies within a factor 2 of
``max_k a_k^(1/k)`` (Fujiwara's bound and its converse) and the smallest, by the same
bound on the reversed polynomial, within a factor 2 of ``min_k (a_n / a_(n-k))^(1/k)``;
their ratio is :func:`time_scale_ratio`, within a factor 4 of the true ratio of the
fastest to the slowest time scale.

The bound :data:`~designlab.impact.parameters.TIME_SCALE_RATIO` is declared with the
other impact parameters; :func:`check_conditioning` refuses a design beyond it with the
row, the ratio, what is allowed and the parameter farthest from its typical range.

Examples
--------
>>> import numpy as np
>>> p = np.array([[9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 46, 3e3],
...               [3e13, 250, 20e3, 24.25e3, 71.9, 4.4, 46, 3e3]])
>>> [f"{r:.3g}" for r in time_scale_ratio(p)]
['3.03', '2.86e+06']
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from designlab.errors import InvalidParameterError
from designlab.params import Param, params_of

#: A fastest root at least this many times faster than the others is a separate time scale.
_SEPARATED = 10.0

__all__ = [
    "characteristic_polynomial",
    "check_conditioning",
    "check_eigen_route",
    "time_scale_ratio",
]


def _mul(a: NDArray, b: NDArray) -> NDArray:
    """Product of polynomials ``(N, i)`` and ``(N, j)`` (ascending powers) per row."""
    out = np.zeros((a.shape[0], a.shape[1] + b.shape[1] - 1))
    for i in range(a.shape[1]):
        out[:, i : i + b.shape[1]] += a[:, i : i + 1] * b
    return out


def _add(*polys: NDArray) -> NDArray:
    """Sum of polynomials (ascending powers) per row."""
    width = max(p.shape[1] for p in polys)
    out = np.zeros((polys[0].shape[0], width))
    for p in polys:
        out[:, : p.shape[1]] += p
    return out


def characteristic_polynomial(p: NDArray, constrained: bool = False) -> NDArray:
    """Coefficients (ascending powers, not normalised) of the models' characteristic polynomial.

    The network of Zeng 2011, Sec. 3.5: the manipulator M_r grounded through its joint
    impedance Z_j(s), the foam Z_c(s) = K_c + C_c s between it and the head M_h,
    grounded through the neck Z_h(s) = K_h + C_h s::

        (M_r s^2 + Z_j)(M_h s^2 + Z_h) + Z_c ((M_r + M_h) s^2 + Z_j + Z_h)

    (``M_r s^2 + Z_j + Z_c`` for the constrained impact). The reduced joint has
    Z_j = K_r + C_r s; the full series joint (3.4.6) the transmission and the controller in
    series, Z_j = N_j / D_j with N_j = (K_mech + C_mech s)(K_cont + C_cont s) and
    D_j = K_mech + K_cont + (C_mech + C_cont) s, and the polynomial is multiplied by D_j.
    Every coefficient is a sum of products of non-negative parameters.

    Parameters
    ----------
    p
        ``(N, 8)`` rows ordered as :data:`~designlab.impact.model.PARAM_NAMES` or ``(N, 10)``
        rows ordered as :data:`~designlab.impact.full_joint_model.FULL_PARAM_NAMES`.
    constrained
        The constrained impact (head against a wall).

    Returns
    -------
    numpy.ndarray
        ``(N, n + 1)``, the constant term first.

    Examples
    --------
    >>> import numpy as np
    >>> c = characteristic_polynomial(np.array([[9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 0, 4e3]]))
    >>> [f"{x:.4g}" for x in (c[0] / c[0, -1])[::-1]]       # 1, q1, q2, q3, q4 of (3.5.14)
    ['1', '49.87', '1.146e+04', '2.081e+05', '1.567e+07']
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    n = p.shape[0]
    col = {k: p[:, i : i + 1] for i, k in enumerate(("m_r", "c_j", "k_j", "k_c", "c_c", "m_h"))}
    zero = np.zeros((n, 1))
    z_c = np.hstack([col["k_c"], col["c_c"]])
    z_h = np.hstack([p[:, 7:8], p[:, 6:7]])
    if p.shape[1] == 10:  # full joint: Z_j = N_j / D_j
        n_j = _mul(np.hstack([col["k_j"], col["c_j"]]), np.hstack([p[:, 9:10], p[:, 8:9]]))
        d_j = np.hstack([col["k_j"] + p[:, 9:10], col["c_j"] + p[:, 8:9]])
    else:
        n_j = np.hstack([col["k_j"], col["c_j"]])
        d_j = np.ones((n, 1))
    robot = _add(_mul(np.hstack([zero, zero, col["m_r"]]), d_j), n_j)  # (M_r s^2 + Z_j) D_j
    with np.errstate(over="ignore", invalid="ignore"):
        if constrained:
            return _add(robot, _mul(z_c, d_j))
        head = _add(np.hstack([zero, zero, col["m_h"]]), z_h)
        masses = _mul(np.hstack([zero, zero, col["m_r"] + col["m_h"]]), d_j)
        return _add(_mul(robot, head), _mul(z_c, _add(masses, n_j, _mul(z_h, d_j))))


def time_scale_ratio(
    p: NDArray, constrained: bool = False, *, motor_node: bool = False
) -> NDArray[np.float64]:
    """Estimated ratio of the fastest to the slowest pole modulus of each design.

    From the coefficients of :func:`characteristic_polynomial` (monic, descending
    ``1, a_1, ..., a_n``): ``max_k a_k^(1/k) / min_k (a_n / a_(n-k))^(1/k)``, within a factor
    4 of the true ratio. For the full joint, the motor node's mode, when it is the fastest
    root (its modulus within a factor 2 of the node's own rate
    (K_mech + K_cont) / (C_mech + C_cont)) and more than 10 times faster than the others
    (a stiff transmission), is left out: it is a separate first-order transient, over
    before the first lobe's maxima, that the compiled kernel resolves exactly. A design
    with a pole at s = 0 (no restoring stiffness) gives 1: that case is refused elsewhere,
    by name. Coefficients beyond double precision give ``inf``. Reduced unconstrained
    designs take the compiled pass :func:`designlab.impact.kernel.time_scale_ratios` where
    the compiled kernels are available (the same estimate, to a few rounding errors).

    Parameters
    ----------
    p
        ``(N, 8)`` or ``(N, 10)`` parameter rows (see :func:`characteristic_polynomial`).
    constrained
        The constrained impact.
    motor_node
        Count the full joint's motor-node mode even when it is far the fastest (the time
        scales that an eigen-decomposition of the state matrix has to span).

    Returns
    -------
    numpy.ndarray
        ``(N,)`` ratios (>= 1).
    """
    from designlab.impact import kernel

    p = np.atleast_2d(np.asarray(p, dtype=float))
    if kernel.AVAILABLE and p.shape[1] == 8 and not constrained:
        return kernel.time_scale_ratios(p)  # the same estimate, compiled (the batch's hot path)
    c = characteristic_polynomial(p, constrained)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        logc = np.log(c)  # -inf for a zero coefficient
        deg = c.shape[1] - 1
        lead, const = logc[:, deg : deg + 1], logc[:, :1]
        k = np.arange(1, deg + 1, dtype=float)
        # a_k = c[deg - k] / c[deg]:  log rho_max = max_k log(a_k) / k
        log_a = logc[:, deg - 1 :: -1] - lead  # a_1 .. a_deg
        log_max = np.max(log_a / k, axis=1)
        if p.shape[1] == 10 and deg > 1 and not motor_node:
            # the full joint's massless motor node: a first-order mode that, for a stiff
            # transmission, is far faster than the rest and over long before the lobe's
            # maxima (designlab.impact.full_joint_model.grid_rate); it is a root of modulus
            # ~ a_1, and the remaining roots those of s^(n-1) + a_2/a_1 s^(n-2) + ...
            rest = np.max((log_a[:, 1:] - log_a[:, :1]) / k[:-1], axis=1)
            node = np.log((p[:, 2] + p[:, 9]) / (p[:, 1] + p[:, 8]))  # its own rate
            motor = np.abs(log_a[:, 0] - node) < math.log(2.0)  # the fastest root is the node's
            log_max = np.where(motor & (log_a[:, 0] - rest > math.log(_SEPARATED)), rest, log_max)
        # a_n / a_(n-k) = c[0] / c[k]:  log rho_min = min_k (log c_0 - log c_k) / k
        log_min = np.min((const - logc[:, 1:]) / k, axis=1)
        out = np.exp(log_max - log_min)
    finite = np.all(np.isfinite(c), axis=1)
    out = np.where(np.isfinite(const[:, 0]), out, 1.0)  # a pole at 0: refused elsewhere
    out = np.where(finite & (c[:, -1] > 0), out, np.inf)
    return np.where(np.isnan(out), np.inf, np.maximum(out, 1.0))


def check_conditioning(
    p: NDArray,
    names: tuple[str, ...],
    *,
    constrained: bool = False,
    label: str = "params",
    rows: NDArray | None = None,
    labels: Sequence[str | None] | None = None,
) -> None:
    """Refuse designs whose time scales span more than double precision serves.

    The error names, as the parameter, the input of the first such design that is farthest
    from its typical range, with its value; the other inputs, the ratio and the bound follow.

    Parameters
    ----------
    p
        ``(N, 8)`` or ``(N, 10)`` parameter rows, finite and in their declared ranges.
    names
        The names (symbols) of the columns.
    constrained
        The constrained impact.
    label
        The name of the batch (``"params"``: a column is named ``params[j].M_r``).
    rows
        The caller's row numbers of ``p`` (named in the error).
    labels
        The caller's names of the columns (``"robot.mass"``; ``None`` for a column the caller
        did not give, never blamed), instead of ``label[j].<name>``.

    Raises
    ------
    InvalidParameterError
        For the first design whose :func:`time_scale_ratio` exceeds
        :data:`~designlab.impact.parameters.TIME_SCALE_RATIO`.

    Examples
    --------
    >>> import numpy as np
    >>> from designlab.impact.model import PARAM_NAMES
    >>> check_conditioning(np.array([[3e13, 250, 2e4, 24.25e3, 71.9, 4.4, 46, 3e3]]),
    ...                    PARAM_NAMES)
    Traceback (most recent call last):
    ...
    designlab.errors.InvalidParameterError: params[0].M_r = 30000000000000.0 kg is not allowed: ...
    """
    from designlab.impact.parameters import TIME_SCALE_RATIO

    ratio = time_scale_ratio(p, constrained)
    bad = ~(ratio <= TIME_SCALE_RATIO.le)
    if not np.any(bad):
        return
    j = int(np.flatnonzero(bad)[0])
    row = j if rows is None else int(rows[j])
    if labels is None:
        labels = [f"{label}[{row}].{name}" for name in names]
    i = _most_extreme(p[j], names, labels)
    others = ", ".join(
        f"{k}={x:.4g}" for m, (k, x) in enumerate(zip(names, p[j], strict=True)) if m != i
    )
    spread = (
        f"its time scales span a ratio of {ratio[j]:.3g} (fastest to slowest mode, "
        f"{TIME_SCALE_RATIO.doc})"
        if np.isfinite(ratio[j])
        else "its model coefficients are beyond double precision"
    )
    decl = _declarations()[names[i]]
    scale = _typical().get(names[i])
    why = (
        f"; {names[i]} = {p[j, i]:.4g} {decl.unit} ({decl.doc}) is the input farthest from "
        f"its typical range "
        f"({scale.typical[0]:g}-{scale.typical[1]:g} {decl.unit})"
        if scale is not None and scale.typical is not None
        else ""
    )
    raise InvalidParameterError(
        str(labels[i]),
        float(p[j, i]),
        f"with the other inputs [{others}] {spread}; at most {TIME_SCALE_RATIO.le:g} is served "
        f'to the declared accuracy in double precision (docs/impact.md, "Limits"){why}',
        decl.unit,
    )


def check_eigen_route(p: NDArray, rows: NDArray, constrained: bool = False) -> None:
    """Refuse full-joint designs the eigen-decomposition of the state matrix cannot serve.

    The compiled kernel evaluates a stiff transmission's motor-node mode exactly from the
    closed form; a design it does not certify (nearly repeated or ill-conditioned poles)
    is evaluated from the eigen-decomposition instead, whose slow eigenvalues carry an
    absolute error of about the rounding error times the fastest (the motor node's), so there
    the time scales counted with the motor node must not span more than
    :data:`~designlab.impact.parameters.TIME_SCALE_RATIO` either.

    Parameters
    ----------
    p
        ``(N, 10)`` full-joint rows evaluated by the eigen-decomposition.
    rows
        Their row numbers in the caller's batch (named in the error).
    constrained
        The constrained impact.
    """
    from designlab.impact.full_joint_model import FULL_PARAM_NAMES
    from designlab.impact.parameters import TIME_SCALE_RATIO

    ratio = time_scale_ratio(p, constrained, motor_node=True)
    bad = ~(ratio <= TIME_SCALE_RATIO.le)
    if not np.any(bad):
        return
    j = int(np.flatnonzero(bad)[0])
    shown = ", ".join(f"{k}={x:.4g}" for k, x in zip(FULL_PARAM_NAMES, p[j], strict=True))
    raise InvalidParameterError(
        f"params[{int(rows[j])}]",
        f"[{shown}]",
        "has poles the compiled kernel does not certify (nearly repeated or ill-conditioned), "
        f"and with its motor-node mode its time scales span a ratio of {ratio[j]:.3g}, beyond "
        f"the {TIME_SCALE_RATIO.le:g} the eigen-decomposition serves in double precision "
        '(docs/impact.md, "Limits"): a softer transmission (K_mech) or more damping at the '
        "motor node (C_mech + C_cont) is served",
    )


def _declarations() -> dict[str, Param]:
    """The declaration of each column, by column name (the full joint's effective values are
    declared on :class:`~designlab.impact.series_joint.FullJointContact` as ``C_mech/l^2``)."""
    from designlab.impact.parameters import ContactDynamics, Foam, HeadNeck
    from designlab.impact.series_joint import FullJointContact

    return {
        d.symbol.split("/")[0]: d
        for cls in (ContactDynamics, Foam, HeadNeck, FullJointContact)
        for d in params_of(cls).values()
        if d.symbol
    }


def _typical() -> dict[str, Param]:
    """The declarations with a typical range, by column name (the full joint's controller
    gains and transmission take the reduced joint's K_r and C_r as their scale)."""
    decls = {k: d for k, d in _declarations().items() if d.typical is not None}
    decls.update(C_mech=decls["C_r"], C_cont=decls["C_r"], K_cont=decls["K_r"])
    decls.update(K_mech=decls["K_r"])
    return decls


def _most_extreme(row: NDArray, names: tuple[str, ...], labels: Sequence[str | None]) -> int:
    """The column of ``row`` farthest (in decades) from its typical range, among those the
    caller gave (``labels[i]`` not ``None``) and > 0 (the first given one if none is)."""
    typical = _typical()
    best, pick = -1.0, next(i for i, lab in enumerate(labels) if lab is not None)
    for i, (name, x) in enumerate(zip(names, row, strict=True)):
        decl = typical.get(name)
        if labels[i] is None or decl is None or decl.typical is None or not x > 0:
            continue
        if decl.typical[0] <= 0:
            continue
        lo, hi = decl.typical
        decades = max(math.log10(lo / x), math.log10(x / hi), 0.0)
        if decades > best:
            best, pick = decades, i
    return pick
