"""Evaluate CasADi SX functions on numpy arrays, vectorised over a batch.

Models are written once in CasADi symbols. For sweeps over many designs, calling a
``casadi.Function`` per design (or through ``map``) costs microseconds per call;
replaying the function's SX instruction list with numpy on whole columns of designs
costs a few numpy operations per instruction for the whole batch. :func:`vectorize`
builds such an evaluator from any SX function, with the numpy forms of the one
operation table (:data:`designlab.sx.ops.OPS`); the physics stays in the CasADi
expression.

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
from typing import Any

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from designlab.sx.ops import NAMESPACE, OPS
from designlab.sx.program import Program, read_program

__all__ = ["evaluate_batch", "vectorize"]

Array = NDArray[np.float64]


@cache
def _numpy_callable(op: int) -> Callable[..., Any]:
    """The numpy form of ``op`` as a function of its operands."""
    form = OPS[op]
    names = ("a", "b")[: form.arity]
    src = f"lambda {', '.join(names)}: {form.numpy.format(*names)}"  # type: ignore[union-attr]
    fn: Callable[..., Any] = eval(src, dict(NAMESPACE))
    return fn


_IN, _OUT, _CONST, _OP = range(4)
_KIND = {ca.OP_INPUT: _IN, ca.OP_OUTPUT: _OUT, ca.OP_CONST: _CONST}


def _steps(prog: Program) -> list[tuple[int, Any, tuple[int, ...], tuple[int, ...]]]:
    """(kind, operation or constant, ins, outs) per instruction, resolved once."""
    steps = []
    for ins in prog.instructions:
        kind = _KIND.get(ins.op, _OP)
        what = _numpy_callable(ins.op) if kind == _OP else ins.const
        steps.append((kind, what, ins.ins, ins.outs))
    return steps


def _run(prog: Program, steps: list[Any], cols: list[Array], n: int) -> list[Array]:
    """Replay ``steps`` on the input columns; the outputs' nonzeros, ``(nnz, n)`` each."""
    work: list[Any] = [0.0] * prog.n_work
    results = [np.zeros((nz, n)) for nz in prog.nnz_out]
    for kind, what, i, o in steps:
        if kind == _OP:
            work[o[0]] = what(*[work[j] for j in i])
        elif kind == _IN:
            work[o[0]] = cols[i[0]][i[1]]
        elif kind == _OUT:
            results[o[0]][o[1]] = work[i[0]]
        else:
            work[o[0]] = what
    return results


def vectorize(f: ca.Function) -> Callable[..., list[Array]]:
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
        If ``f`` is not an SX function or uses an operation numpy cannot replay
        (:class:`~designlab.sx.UnsupportedOperation`).
    """
    prog = read_program(f, "numpy")
    steps = _steps(prog)
    n_in = f.n_in()
    sparsity = [f.sparsity_out(i) for i in range(f.n_out())]

    def evaluate(*args: NDArray) -> list[Array]:
        if len(args) != n_in:
            raise TypeError(f"{prog.name} takes {n_in} inputs, got {len(args)}")
        cols = [np.asarray(a, dtype=float) for a in args]
        cols = [c[:, None] if c.ndim == 1 else c for c in cols]
        n = max(c.shape[1] for c in cols)
        dense = []
        for res, sp in zip(_run(prog, steps, cols, n), sparsity, strict=True):
            if sp.is_dense():
                dense.append(res)
            else:
                full = np.zeros((sp.numel(), n))
                full[np.asarray(sp.find(), dtype=int)] = res
                dense.append(full)
        return dense

    return evaluate


@cache
def _vectorized(f: ca.Function) -> Callable[..., list[Array]]:
    return vectorize(f)


def evaluate_batch(f: ca.Function, p: NDArray[np.float64], *, direct_below: int = 9) -> list[Array]:
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
