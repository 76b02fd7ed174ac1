"""The coupled manipulator-foam-head impact model, written once in CasADi symbols.

Zeng 2011, Sec. 3.5 (time domain, Fig. 3.9) in the relative-coordinate form of
``impact.md`` Sec. 2.8. Every physical quantity is a symbol::

    p = [M_r, C_r, K_r, K_c, C_c, M_h, C_h, K_h]
    x = [delta_r, delta_r_dot, delta_h, delta_h_dot]      deflections from the prescribed motions
    u = [s_c, v_c, a_d]     closing displacement, closing speed (v_c = v_r - v_h, I5),
                            desired manipulator acceleration not compensated by feed-forward

    f_c   = K_c (delta_r - delta_h + s_c) + C_c (delta_r_dot - delta_h_dot + v_c)        (3.5.1)
    M_r delta_r_dd = -f_c - C_r delta_r_dot - K_r delta_r - M_r a_d                       (3.5.2)
    M_h delta_h_dd =  f_c - C_h delta_h_dot - K_h delta_h                                 (3.5.3)

The thesis's constant-velocity impact is the input ``u = v_c [t, 1, 0]``. The
constrained impact (head against a wall, K_h -> infinity, (3.6.1)/(3.9.4)) is
the same manipulator and foam with the head fixed.

From the symbolic state space the module derives, without a second copy of the
physics:

* ``casadi.Function`` objects for the state derivative and the outputs,
* the state-space matrices ``(A, B, C, D)`` by exact differentiation,
* the transfer-function coefficients of every input/output pair, by the
  Faddeev-LeVerrier recursion on the symbolic matrices (so the q_i of (3.5.14)
  come out as CasADi expressions of the physical parameters),
* python-control transfer functions F_c(s), A_h(s), eps(s) (3.5.11, 3.5.14,
  3.9.2) and their constrained forms (3.6.1, 3.9.4).

Examples
--------
>>> from designlab.impact.model import unconstrained_model
>>> m = unconstrained_model()
>>> m.param_names
('M_r', 'C_r', 'K_r', 'K_c', 'C_c', 'M_h', 'C_h', 'K_h')
>>> den = m.denominator([9.6, 250, 20e3, 24.25e3, 71.9, 4.4, 0.0, 4e3])
>>> [f"{c:.4g}" for c in den[0]]      # 1, q1, q2, q3, q4 of (3.5.14)
['1', '49.87', '1.146e+04', '2.081e+05', '1.567e+07']
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING, Any

import casadi as ca
import numpy as np
from numpy.typing import ArrayLike, NDArray

from designlab.errors import InvalidParameterError
from designlab.impact.parameters import check_closing_velocity
from designlab.sx import evaluate_batch

if TYPE_CHECKING:  # pragma: no cover
    import control

__all__ = [
    "INPUT_NAMES",
    "PARAM_NAMES",
    "LinearImpactModel",
    "constrained_model",
    "derive_model",
    "param_vector",
    "transfer_functions",
    "unconstrained_model",
]

PARAM_NAMES: tuple[str, ...] = ("M_r", "C_r", "K_r", "K_c", "C_c", "M_h", "C_h", "K_h")
"""The symbols of the model's parameter vector, in order (:func:`param_vector`)."""
INPUT_NAMES: tuple[str, ...] = ("s_c", "v_c", "a_d")


def _evaluate(f: ca.Function, p: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """Evaluate ``f`` for each row of ``p`` (:func:`designlab.sx.replay.evaluate_batch`)."""
    return evaluate_batch(f, p)


def _faddeev_leverrier(a: ca.SX) -> tuple[list[ca.SX], list[ca.SX]]:
    """Characteristic polynomial and adjugate of ``sI - A`` for a symbolic matrix.

    Returns ``(c, m)`` with ``det(sI - A) = sum_k c[k] s^(n-k)`` (``c[0] = 1``)
    and ``adj(sI - A) = sum_{k=1}^{n} m[k-1] s^(n-k)``.
    """
    n = a.shape[0]
    eye = ca.SX.eye(n)
    c: list[ca.SX] = [ca.SX(1.0)]
    mats: list[ca.SX] = []
    m_prev = ca.SX.zeros(n, n)
    for k in range(1, n + 1):
        m_k = a @ m_prev + c[k - 1] * eye
        mats.append(m_k)
        c.append(-ca.trace(a @ m_k) / k)
        m_prev = m_k
    return c, mats


@dataclass(frozen=True, eq=False)
class LinearImpactModel:
    """A linear time-invariant impact model held as CasADi functions.

    Attributes
    ----------
    name
        ``"unconstrained"`` or ``"constrained"``.
    ode
        ``casadi.Function`` ``(x, u, p) -> xdot``.
    outputs
        ``casadi.Function`` ``(x, u, p) -> y`` with ``y`` ordered as ``output_names``.
    state_space
        ``casadi.Function`` ``p -> (A, B, C, D)``.
    tf
        ``casadi.Function`` ``p -> (den, num_0, ..., num_{n_y-1})``: monic
        denominator coefficients (descending powers, length ``n+1``) and, per
        output, a ``(n_u, n+1)`` matrix of numerator coefficients, one row per input.
    ramp_tf
        ``casadi.Function`` ``p -> (den, num_0, ...)`` of the constant-velocity
        impact: ``Y(s) = v_c num(s) / (s^2 den(s))``, numerators of length ``n+2``.
    state_names
        Names of the states, in order.
    output_names
        Names of the outputs, in order.
    param_names
        Names of the parameters, in order (:data:`PARAM_NAMES`).
    input_names
        Names of the inputs, in order.
    """

    name: str
    ode: ca.Function
    outputs: ca.Function
    state_space: ca.Function
    tf: ca.Function
    ramp_tf: ca.Function
    state_names: tuple[str, ...]
    output_names: tuple[str, ...]
    param_names: tuple[str, ...] = PARAM_NAMES
    input_names: tuple[str, ...] = INPUT_NAMES

    @property
    def n_states(self) -> int:
        """Number of states."""
        return len(self.state_names)

    def tf_coefficients(
        self, params: ArrayLike
    ) -> tuple[NDArray[np.float64], dict[str, NDArray[np.float64]]]:
        """Evaluate the transfer-function coefficients for a batch of parameter sets.

        Parameters
        ----------
        params
            Array of shape ``(8,)`` or ``(N, 8)`` ordered as :data:`PARAM_NAMES`.

        Returns
        -------
        den
            ``(N, n+1)`` monic denominator coefficients (descending powers).
        num
            Per output name, ``(N, n_u, n+1)`` numerator coefficients.
        """
        p = np.atleast_2d(np.asarray(params, dtype=float))
        n_batch = p.shape[0]
        n = self.n_states
        res = _evaluate(self.tf, p)
        den = res[0].T
        num: dict[str, NDArray[np.float64]] = {}
        n_u = len(self.input_names)
        for k, name in enumerate(self.output_names):
            arr = res[k + 1].reshape(n_u, n + 1, n_batch, order="F")
            num[name] = np.moveaxis(arr, 2, 0)
        return den, num

    def ramp_coefficients(
        self, params: ArrayLike
    ) -> tuple[NDArray[np.float64], dict[str, NDArray[np.float64]]]:
        """Coefficients of the unit constant-velocity impact for a batch of designs.

        Returns ``den`` ``(N, n+1)`` and per output ``num`` ``(N, n+2)`` with
        ``Y(s) = v_c num(s) / (s^2 den(s))``. Evaluated with numpy on the whole
        batch from the SX expression (:func:`designlab.sx.replay.vectorize`).
        """
        p = np.atleast_2d(np.asarray(params, dtype=float))
        res = _evaluate(self.ramp_tf, p)
        den = res[0].T
        return den, {name: res[k + 1].T for k, name in enumerate(self.output_names)}

    def denominator(self, params: ArrayLike) -> NDArray[np.float64]:
        """Monic characteristic polynomial ``(N, n+1)`` for a batch of parameter sets."""
        return self.tf_coefficients(params)[0]

    def matrices(self, params: ArrayLike) -> tuple[NDArray[np.float64], ...]:
        """Numeric ``(A, B, C, D)`` for one parameter set."""
        res = self.state_space(np.asarray(params, dtype=float))
        return tuple(np.asarray(r, dtype=float) for r in res)

    def matrices_batch(self, params: ArrayLike) -> tuple[NDArray[np.float64], ...]:
        """Numeric ``(A, B, C, D)`` for a batch ``(N, n_p)``: arrays ``(N, rows, cols)``."""
        p = np.atleast_2d(np.asarray(params, dtype=float))
        res = _evaluate(self.state_space, p)
        n_x, n_u, n_y = self.n_states, len(self.input_names), len(self.output_names)
        shapes = ((n_x, n_x), (n_x, n_u), (n_y, n_x), (n_y, n_u))
        return tuple(
            np.moveaxis(r.reshape(*shape, p.shape[0], order="F"), 2, 0)
            for r, shape in zip(res, shapes, strict=True)
        )


#: Outputs of both models, in the order of ``y``.
OUTPUT_NAMES: tuple[str, ...] = (
    "force",
    "head_acceleration",
    "compression",
    "compression_rate",
    "head_velocity",
    "robot_deflection",
)


def _equations(constrained: bool) -> tuple[ca.SX, ca.SX, ca.SX, ca.SX, ca.SX, tuple[str, ...]]:
    """The model in symbols: ``(x, u, p, xdot, y, state_names)``, (3.5.1)-(3.5.3)."""
    p = ca.SX.sym("p", len(PARAM_NAMES))
    m_r, c_r, k_r, k_c, c_c, m_h, c_h, k_h = (p[i] for i in range(len(PARAM_NAMES)))
    u = ca.SX.sym("u", len(INPUT_NAMES))
    s_c, v_c, a_d = u[0], u[1], u[2]
    if constrained:
        x = ca.SX.sym("x", 2)
        d_r, d_r_dot = x[0], x[1]
        d_h = d_h_dot = ca.SX(0.0)
        state_names: tuple[str, ...] = ("delta_r", "delta_r_dot")
    else:
        x = ca.SX.sym("x", 4)
        d_r, d_r_dot, d_h, d_h_dot = x[0], x[1], x[2], x[3]
        state_names = ("delta_r", "delta_r_dot", "delta_h", "delta_h_dot")

    compression = d_r - d_h + s_c
    compression_rate = d_r_dot - d_h_dot + v_c
    f_c = k_c * compression + c_c * compression_rate  # (3.5.1)
    d_r_ddot = (-f_c - c_r * d_r_dot - k_r * d_r) / m_r - a_d  # (3.5.2)
    if constrained:
        a_h = ca.SX(0.0)
        xdot = ca.vertcat(d_r_dot, d_r_ddot)
    else:
        a_h = (f_c - c_h * d_h_dot - k_h * d_h) / m_h  # (3.5.3); torso acceleration is 0
        xdot = ca.vertcat(d_r_dot, d_r_ddot, d_h_dot, a_h)
    y = ca.vertcat(f_c, a_h, compression, compression_rate, d_h_dot, d_r)
    return x, u, p, xdot, y, state_names


def _tf_numerators(a_mat: ca.SX, b_mat: ca.SX, c_mat: ca.SX, d_mat: ca.SX) -> tuple[ca.SX, list]:
    """``den`` and one numerator matrix per output (rows: inputs; descending powers of s).

    G(s) = (C adj(sI-A) B + D det(sI-A)) / det(sI-A), by Faddeev-LeVerrier.
    """
    n = a_mat.shape[0]
    coeffs, adj = _faddeev_leverrier(a_mat)
    den = ca.vertcat(*coeffs)  # descending powers, length n+1
    nums = []
    for k in range(c_mat.shape[0]):
        rows = []
        for j in range(b_mat.shape[1]):
            poly = [d_mat[k, j] * coeffs[0]]
            for i in range(1, n + 1):
                poly.append(c_mat[k, :] @ adj[i - 1] @ b_mat[:, j] + d_mat[k, j] * coeffs[i])
            rows.append(ca.horzcat(*poly))
        nums.append(ca.simplify(ca.vertcat(*rows)))
    return den, nums


def _build(name: str, constrained: bool) -> LinearImpactModel:
    """Both numerical faces of one model: ODE, outputs, state space, transfer functions."""
    x, u, p, xdot, y, state_names = _equations(constrained)
    return derive_model(name, x, u, p, xdot, y, state_names, OUTPUT_NAMES)


def derive_model(
    name: str,
    x: ca.SX,
    u: ca.SX,
    p: ca.SX,
    xdot: ca.SX,
    y: ca.SX,
    state_names: tuple[str, ...],
    output_names: tuple[str, ...],
    param_names: tuple[str, ...] = PARAM_NAMES,
    input_names: tuple[str, ...] = INPUT_NAMES,
) -> LinearImpactModel:
    """Derive the functions, state space and transfer functions of a linear model.

    ``xdot = f(x, u, p)`` and ``y = g(x, u, p)`` must be linear in ``x`` and ``u``.
    The first two inputs must be the closing displacement and speed (``s_c``,
    ``v_c``) so that the constant-velocity impact is ``u = v_c [t, 1, 0, ...]``.
    Used for the reduced model here and the full series joint of
    :mod:`designlab.impact.full_joint`.

    Parameters
    ----------
    name
        Model name (``LinearImpactModel.name``; prefixes the CasADi functions).
    x, u, p
        Symbols of the states, the inputs and the parameters.
    xdot, y
        State derivatives and outputs, expressions in ``x``, ``u``, ``p``.
    state_names, output_names
        Names of the entries of ``x`` and ``y``.
    param_names, input_names
        Names of the entries of ``p`` and ``u``.

    Returns
    -------
    LinearImpactModel

    Examples
    --------
    >>> import casadi as ca
    >>> x, u, p = ca.SX.sym("x", 1), ca.SX.sym("u", 3), ca.SX.sym("p", 1)
    >>> m = derive_model("demo", x, u, p, -p[0] * x + u[1], x, ("x",), ("force",),
    ...                  param_names=("k",))
    >>> m.n_states, m.output_names
    (1, ('force',))
    """
    ode = ca.Function(f"impact_{name}_ode", [x, u, p], [xdot], ["x", "u", "p"], ["xdot"])
    outputs = ca.Function(f"impact_{name}_outputs", [x, u, p], [y], ["x", "u", "p"], ["y"])
    a_mat, b_mat = ca.jacobian(xdot, x), ca.jacobian(xdot, u)
    c_mat, d_mat = ca.jacobian(y, x), ca.jacobian(y, u)
    state_space = ca.Function(
        f"impact_{name}_ss", [p], [a_mat, b_mat, c_mat, d_mat], ["p"], ["A", "B", "C", "D"]
    )
    den, nums = _tf_numerators(a_mat, b_mat, c_mat, d_mat)
    num_names = [f"num_{o}" for o in output_names]
    tf = ca.Function(
        f"impact_{name}_tf", [p], [ca.simplify(den), *nums], ["p"], ["den", *num_names]
    )
    # Constant-velocity impact, u = v_c [1/s^2, 1/s, 0]: Y(s) = v_c (N_sc + s N_vc) / (s^2 den)
    ramps = [
        ca.simplify(ca.horzcat(ca.SX(0.0), nums[k][0, :]) + ca.horzcat(nums[k][1, :], ca.SX(0.0)))
        for k in range(len(output_names))
    ]
    ramp_tf = ca.Function(
        f"impact_{name}_ramp_tf", [p], [ca.simplify(den), *ramps], ["p"], ["den", *num_names]
    )
    return LinearImpactModel(
        name=name,
        ode=ode,
        outputs=outputs,
        state_space=state_space,
        tf=tf,
        ramp_tf=ramp_tf,
        state_names=state_names,
        output_names=output_names,
        param_names=param_names,
        input_names=input_names,
    )


@cache
def unconstrained_model() -> LinearImpactModel:
    """The coupled manipulator-foam-head model of Sec. 3.5 (built once, cached)."""
    return _build("unconstrained", constrained=False)


@cache
def constrained_model() -> LinearImpactModel:
    """The constrained impact (head against a wall, (3.6.1)/(3.9.4)), cached."""
    return _build("constrained", constrained=True)


def param_vector(robot: object, foam: object, head: object | None) -> NDArray[np.float64]:
    """Stack parameter objects into the model's parameter vector :data:`PARAM_NAMES`.

    ``head`` may be ``None`` for the constrained model (its entries are then 1, 0, 0).

    Parameters
    ----------
    robot
        Effective manipulator (mass, stiffness, damping).
    foam
        The foam (stiffness, damping).
    head
        The head-neck (``None``: a constrained head; its entries are NaN).
    """
    if head is None:
        hm, hc, hk = 1.0, 0.0, 0.0
    else:
        hm, hc, hk = head.mass, head.damping, head.stiffness  # type: ignore[attr-defined]
    return np.array(
        [
            robot.mass,  # type: ignore[attr-defined]
            robot.damping,  # type: ignore[attr-defined]
            robot.stiffness,  # type: ignore[attr-defined]
            foam.stiffness,  # type: ignore[attr-defined]
            foam.damping,  # type: ignore[attr-defined]
            hm,
            hc,
            hk,
        ],
        dtype=float,
    )


def printed_q2_correction(params: NDArray[np.float64]) -> NDArray[np.float64]:
    """The term C_r C_h/(M_r M_h) that the thesis's printed q2 omits (docs/impact.md, "q2").

    The *printed* denominator is the physical one minus this term on s^2.
    """
    p = np.atleast_2d(params)
    return p[:, 1] * p[:, 6] / (p[:, 0] * p[:, 5])


def transfer_functions(
    robot: object,
    foam: object,
    head: object | None = None,
    impact_velocity: float = 1.0,
    *,
    q2: str = "correct",
) -> dict[str, control.TransferFunction]:
    """Laplace-domain responses to the constant-velocity impact, as python-control TFs.

    Returns F_c(s) (3.5.11), A_h(s) (3.5.14) and eps(s) (3.9.2), each including
    the impact velocity, so that the time response is the impulse response.
    With ``head=None`` the constrained forms (3.6.1) and (3.9.4) are returned
    (and A_h = 0).

    Parameters
    ----------
    robot, foam, head
        :class:`ContactDynamics`, :class:`Foam`, :class:`HeadNeck` (or ``None``).
    impact_velocity
        v_c in m/s (at most the cap of
        :data:`~designlab.impact.parameters.IMPACT_VELOCITY`; v_c <= 0: no impact).
    q2
        ``"correct"`` (default, docs/impact.md, "q2") or ``"printed"`` to reproduce the
        thesis's q2 without the C_r C_h/(M_r M_h) term. The printed option
        changes the common denominator, so the force and eps change too,
        although Fig. 3.10 cites (3.5.11), whose form has no q2: that the
        thesis's force curves used the printed q2 is an inference from its
        Sec. 3.6 percentages, not something the text states.

    Examples
    --------
    >>> from designlab.impact import MANIPULATOR_1, FOAM_1, TEST_HEAD
    >>> tfs = transfer_functions(MANIPULATOR_1, FOAM_1, TEST_HEAD, 1.25)
    >>> sorted(tfs)
    ['compression', 'force', 'head_acceleration']
    >>> import numpy as np
    >>> float(np.real(tfs["force"](1e9) * 1e9))   # s F_c(s) -> f_c(0+) = C_c v_c
    89.875
    """
    import control

    v_c = check_closing_velocity(impact_velocity)
    if q2 not in ("correct", "printed"):
        raise InvalidParameterError("q2", q2, "must be 'correct' or 'printed'")
    model = constrained_model() if head is None else unconstrained_model()
    p = param_vector(robot, foam, head)
    den, num = model.tf_coefficients(p)
    den = den[0].copy()
    if q2 == "printed" and head is not None:
        den[2] -= printed_q2_correction(p)[0]
    out = {}
    s2den = np.polymul(den, [1.0, 0.0, 0.0])
    for name in ("force", "head_acceleration", "compression"):
        nm = num[name][0]
        # ramp input u = v_c [1/s^2, 1/s, 0]: N(s) = N_sc(s) + s N_vc(s)
        combined = np.polyadd(nm[0], np.polymul(nm[1], [1.0, 0.0])) * v_c
        out[name] = _cancel_ramp_poles(control, combined, s2den)
    return out


def _cancel_ramp_poles(control: Any, num: NDArray, s2den: NDArray) -> Any:
    """``num / s2den`` with the removable poles at s = 0 cancelled exactly.

    The ramp input puts a double pole at the origin (``s2den = s^2 den``);
    wherever the numerator has zeros at the origin (trailing zero
    coefficients, zero up to the round-off of the coefficient evaluation,
    1e-10 of the largest), the same powers of s are removed from both
    polynomials. No other pole-zero pair is touched (no numerical ``minreal``).
    """
    num = np.trim_zeros(np.asarray(num, dtype=float), "f")
    if num.size == 0 or not np.any(num):
        return control.tf([0.0], [1.0])
    scale = float(np.max(np.abs(num)))
    k = 0
    while k < 2 and num.size - k > 1 and abs(num[num.size - 1 - k]) <= 1e-10 * scale:
        k += 1
    return control.tf(num[: num.size - k], s2den[: s2den.size - k])
