"""Evaluate CasADi SX functions on numpy arrays, vectorised over a batch.

Models are written once in CasADi symbols. For sweeps over many designs,
calling a ``casadi.Function`` per design (or through ``map``) costs microseconds
per call; replaying the function's SX instruction list with numpy on whole
columns of designs costs a few numpy operations per instruction for the whole
batch. :func:`vectorize` builds such an evaluator from any SX function; the
physics stays in the CasADi expression.

Examples
--------
>>> import casadi as ca, numpy as np
>>> x = ca.SX.sym("x", 2)
>>> f = ca.Function("f", [x], [ca.vertcat(x[0] * x[1] + 3, ca.sin(x[0]) / x[1])])
>>> fv = vectorize(f)
>>> out = fv(np.array([[0.0, 1.0], [2.0, 4.0]]))      # rows: inputs, columns: designs
>>> np.round(out[0], 3)
array([[3.  , 7.  ],
       [0.  , 0.21]])
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cache

import casadi as ca
import numpy as np
from numpy.typing import NDArray

__all__ = ["evaluate_batch", "vectorize"]

_BINARY: dict[int, Callable[[NDArray, NDArray], NDArray]] = {
    ca.OP_ADD: np.add,
    ca.OP_SUB: np.subtract,
    ca.OP_MUL: np.multiply,
    ca.OP_DIV: np.divide,
    ca.OP_POW: np.power,
    ca.OP_CONSTPOW: np.power,
    ca.OP_FMIN: np.minimum,
    ca.OP_FMAX: np.maximum,
    ca.OP_LT: lambda a, b: (a < b).astype(float),
    ca.OP_LE: lambda a, b: (a <= b).astype(float),
    ca.OP_EQ: lambda a, b: (a == b).astype(float),
    ca.OP_NE: lambda a, b: (a != b).astype(float),
    ca.OP_AND: lambda a, b: ((a != 0) & (b != 0)).astype(float),
    ca.OP_OR: lambda a, b: ((a != 0) | (b != 0)).astype(float),
    ca.OP_IF_ELSE_ZERO: lambda a, b: np.where(a != 0, b, 0.0),
    ca.OP_ATAN2: np.arctan2,
    ca.OP_COPYSIGN: np.copysign,
}
_UNARY: dict[int, Callable[[NDArray], NDArray]] = {
    ca.OP_NEG: np.negative,
    ca.OP_SQ: np.square,
    ca.OP_TWICE: lambda a: 2.0 * a,
    ca.OP_INV: np.reciprocal,
    ca.OP_SQRT: np.sqrt,
    ca.OP_EXP: np.exp,
    ca.OP_LOG: np.log,
    ca.OP_SIN: np.sin,
    ca.OP_COS: np.cos,
    ca.OP_TAN: np.tan,
    ca.OP_ASIN: np.arcsin,
    ca.OP_ACOS: np.arccos,
    ca.OP_ATAN: np.arctan,
    ca.OP_SINH: np.sinh,
    ca.OP_COSH: np.cosh,
    ca.OP_TANH: np.tanh,
    ca.OP_FABS: np.abs,
    ca.OP_SIGN: np.sign,
    ca.OP_FLOOR: np.floor,
    ca.OP_CEIL: np.ceil,
    ca.OP_NOT: lambda a: (a == 0).astype(float),
    ca.OP_ASSIGN: lambda a: a,
}


def vectorize(f: ca.Function) -> Callable[..., list[NDArray[np.float64]]]:
    """Return a numpy evaluator of the SX function ``f`` for a batch of inputs.

    The evaluator takes one array per input of ``f``, each of shape
    ``(input.numel(), N)`` (or ``(input.numel(),)`` for a single design) and
    returns one array per output of shape ``(output.numel(), N)`` (dense,
    column-major like CasADi). Inputs with a single column broadcast.

    Parameters
    ----------
    f
        A CasADi SX function.

    Raises
    ------
    TypeError
        If ``f`` is not an SX function or uses an operation numpy cannot replay.
    """
    if not f.is_a("SXFunction"):
        raise TypeError(f"vectorize needs an SX function, got {f.class_name()}")
    program = []
    for k in range(f.n_instructions()):
        op = f.instruction_id(k)
        ins = list(f.instruction_input(k))
        outs = list(f.instruction_output(k))
        if op == ca.OP_CONST:
            program.append((op, ins, outs, f.instruction_constant(k)))
        elif op in (ca.OP_INPUT, ca.OP_OUTPUT) or op in _BINARY or op in _UNARY:
            program.append((op, ins, outs, None))
        else:
            raise TypeError(f"operation {op} of {f.name()} has no numpy replay")
    n_in = f.n_in()
    n_out = f.n_out()
    out_nnz = [f.sparsity_out(i).nnz() for i in range(n_out)]
    out_dense = [f.sparsity_out(i) for i in range(n_out)]
    sz_w = f.sz_w()

    def evaluate(*args: NDArray) -> list[NDArray[np.float64]]:
        if len(args) != n_in:
            raise TypeError(f"{f.name()} takes {n_in} inputs, got {len(args)}")
        cols = [np.asarray(a, dtype=float) for a in args]
        cols = [c[:, None] if c.ndim == 1 else c for c in cols]
        n = max(c.shape[1] for c in cols)
        work: list[NDArray | float] = [0.0] * sz_w
        results = [np.zeros((nz, n)) for nz in out_nnz]
        for op, ins, outs, const in program:
            if op == ca.OP_INPUT:
                work[outs[0]] = cols[ins[0]][ins[1]]
            elif op == ca.OP_OUTPUT:
                results[outs[0]][outs[1]] = work[ins[0]]
            elif op == ca.OP_CONST:
                work[outs[0]] = const
            elif op in _BINARY:
                work[outs[0]] = _BINARY[op](work[ins[0]], work[ins[1]])
            else:
                work[outs[0]] = _UNARY[op](work[ins[0]])
        dense = []
        for res, sp in zip(results, out_dense, strict=True):
            if sp.is_dense():
                dense.append(res)
            else:
                full = np.zeros((sp.numel(), n))
                full[np.asarray(sp.find(), dtype=int)] = res
                dense.append(full)
        return dense

    return evaluate


@cache
def _vectorized(f: ca.Function) -> Callable[..., list[NDArray[np.float64]]]:
    return vectorize(f)


def evaluate_batch(
    f: ca.Function, p: NDArray[np.float64], *, direct_below: int = 9
) -> list[NDArray[np.float64]]:
    """Evaluate a one-input CasADi function for each row of ``p``.

    Small batches call CasADi directly (no set-up cost); batches of
    ``direct_below`` rows or more replay the SX instruction list with numpy on
    the whole batch (:func:`vectorize`, built once per function and cached).

    Parameters
    ----------
    f
        A ``casadi.Function`` of one (vector) input built from SX symbols.
    p
        ``(N, n_in)`` inputs, one row per evaluation.
    direct_below
        Batches smaller than this are evaluated by calling ``f`` per row.

    Returns
    -------
    list of numpy.ndarray
        One array per output of ``f``, of shape ``(numel, N)`` (column-major
        flattening of each output, one column per row of ``p``).

    Examples
    --------
    >>> import casadi as ca, numpy as np
    >>> x = ca.SX.sym("x", 2)
    >>> f = ca.Function("f", [x], [x[0] * x[1], ca.vertcat(x[0], 2 * x[1])])
    >>> prod, pair = evaluate_batch(f, np.array([[1.0, 2.0], [3.0, 4.0]]))
    >>> prod.tolist(), pair.tolist()
    ([[2.0, 12.0]], [[1.0, 3.0], [4.0, 8.0]])
    >>> big = evaluate_batch(f, np.ones((20, 2)))[0]
    >>> big.shape
    (1, 20)
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if p.shape[0] >= direct_below:
        return _vectorized(f)(p.T)
    rows = [f(row) for row in p]
    rows = [r if isinstance(r, (list, tuple)) else [r] for r in rows]
    return [
        np.stack([np.asarray(r[k], dtype=float).ravel(order="F") for r in rows], axis=1)
        for k in range(f.n_out())
    ]
